"""Shared helpers of the accuracy benchmarks: timing, the machine, Markdown tables, plots.

Timing: ``once(fn)`` measures one call's wall-clock and process-CPU time (the machine is
shared, so both are kept; CPU time is the steadier one); ``interleaved(tasks, repeats)`` runs
several settings round-robin (setting 1, 2, ..., then again) and keeps the medians, so that a
change of the machine's load hits all of them alike; ratios between settings are always formed
from times measured in the same run this way.
"""

from __future__ import annotations

import datetime
import io
import math
import os
import platform
import statistics
import subprocess
import tarfile
import tempfile
import time
from pathlib import Path

import numpy as np

#: Repetitions of every timed run (the median is reported); at least 5, for a stable median.
REPEATS = 5
#: Errors below this are drawn at this value on log axes (the rounding floor of doubles).
ERROR_FLOOR = 1e-16

ROOT = Path(__file__).resolve().parent.parent
FIGURES = ROOT / "docs" / "figures"


def checkout(commit: str) -> Path:
    """The tree of ``commit`` in a new temporary folder (``git archive``)."""
    data = subprocess.run(["git", "-C", str(ROOT), "archive", "--format=tar", commit], check=True,
                          capture_output=True).stdout
    folder = Path(tempfile.mkdtemp(prefix=f"frictiondamp-{commit}-"))
    with tarfile.open(fileobj=io.BytesIO(data)) as tar:
        tar.extractall(folder, filter="data")
    return folder


class Timing:
    """Median wall and CPU seconds of ``repeats`` runs, and the last run's return value."""

    def __init__(self, wall, cpu, value, repeats):
        self.wall, self.cpu, self.value, self.repeats = wall, cpu, value, repeats

    def __repr__(self):
        return f"Timing(wall={self.wall:.4g} s, cpu={self.cpu:.4g} s, repeats={self.repeats})"


def once(fn, setup=None):
    """``(wall, cpu, value)`` of one call ``fn(setup())`` (``fn()`` without setup); setup untimed."""
    state = setup() if setup is not None else None
    t, p = time.perf_counter(), time.process_time()
    value = fn(state) if setup is not None else fn()
    return time.perf_counter() - t, time.process_time() - p, value


def interleaved(tasks, repeats: int = REPEATS) -> list[Timing]:
    """Median timings of ``tasks`` (callables returning ``(wall, cpu, value)``, e.g. built on
    :func:`once`), run round-robin ``repeats`` times."""
    runs = [[] for _ in tasks]
    for _ in range(repeats):
        for i, task in enumerate(tasks):
            runs[i].append(task())
    return [Timing(statistics.median(r[0] for r in rs), statistics.median(r[1] for r in rs), rs[-1][2], repeats)
            for rs in runs]


def cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def machine() -> dict:
    """What the numbers were measured on, and when."""
    import scipy

    try:
        usable = len(os.sched_getaffinity(0))
    except AttributeError:
        usable = os.cpu_count()
    return {
        "date": datetime.datetime.now().strftime("%Y-%m-%d %H:%M"),
        "nproc": usable,
        "cpu": cpu_model(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "load": os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan"),
    }


def machine_line(info: dict) -> str:
    """The machine and versions a table was measured with (no date or load: the page states what is
    true of the code, and the load is reported per measurement where it matters)."""
    return (f"{info['nproc']} cores ({info['cpu']}), Python {info['python']}, "
            f"numpy {info['numpy']}, scipy {info['scipy']}")


def table(header, rows) -> str:
    """A Markdown table from a header list and rows of already formatted cells."""
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


def sci(x, digits=1) -> str:
    """1.2e-06 style; 0 and non-finite values spelled out."""
    if x is None:
        return "-"
    if x == 0.0:
        return "0"
    if not math.isfinite(x):
        return str(x)
    return f"{x:.{digits}e}"


def ms(seconds) -> str:
    """Seconds as ms with 3 significant digits (s above 10 s)."""
    if seconds >= 10.0:
        return f"{seconds:.1f} s"
    v = seconds * 1e3
    return f"{v:.3g} ms" if v < 100 else f"{v:.0f} ms"


def floor(err):
    return max(float(err), ERROR_FLOOR)


def plot_curves(ax, curves, *, xlabel, ylabel, title):
    """Log-log error against time, one curve per knob.

    ``curves``: list of dicts with ``label``, ``time`` (s), ``error``, ``values`` (knob values,
    annotated at the points) and ``default`` (index of the default setting or None).
    """
    for c in curves:
        t = np.asarray(c["time"], dtype=float)
        e = np.array([floor(v) for v in c["error"]])
        line, = ax.loglog(t, e, "o-", ms=3.5, lw=1.2, label=c["label"])
        for ti, ei, v in zip(t, e, c.get("values", [])):
            ax.annotate(v, (ti, ei), textcoords="offset points", xytext=(3, 3), fontsize=6,
                        color=line.get_color())
        d = c.get("default")
        if d is not None:
            ax.loglog([t[d]], [e[d]], "*", ms=13, mfc="none", mec=line.get_color(), mew=1.3)
    ax.plot([], [], "*", ms=10, mfc="none", mec="k", label="default setting")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=9)
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(fontsize=7)


def save_figure(fig, path):
    """Lay out, write (dpi 130) and close a benchmark figure; returns ``path``."""
    import matplotlib.pyplot as plt

    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path
