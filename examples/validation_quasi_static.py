"""Validation: the quasi-static bar against the analytic elements
==============================================================

The independent check of the quasi-static bar: the discretised bar against the analytic elements.

At omega = 0 the single-mode solution of the paper is exact (no inertia, no phase), so the
difference between ``NumericalMicroslip`` (n cells, Jenkins element per node, exact return
mapping, quasi-static stepping) and ``TwoRegionMicroslip`` / ``ThreeRegionMicroslip`` is the
discretisation error of the numerical bar plus the analytic elements' rtol (1e-6).  Writes
``validation_quasi_static.png`` (the relative differences of F_s and F_c against a/a_min) and
prints the table, aligned as text (``--markdown``: as the Markdown table of
docs/validation.md)::

    python3 examples/validation_quasi_static.py            # n = 400, the table of docs/validation.md
    python3 examples/validation_quasi_static.py --cells 100
"""

from __future__ import annotations

import argparse
import time

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.ticker import NullFormatter

from validation_common import BAR, FIGURES, LOADS, RATIOS, analytic, markdown_table, text_table

from contact_models import NumericalMicroslip


def main(cells: int = 400, ratios=RATIOS, steps_per_cycle: int = 1024, small: bool = False):
    """Rows (load, a/a_min, F_s, F_c analytic and numerical, relative differences, seconds).

    Amplitudes are multiples of each element's own a_min and, for the concave load, also of
    the uniform load's a_min (the paper's Figs. 14, 15 normalisation).  ``small``: 100 cells."""
    if small:
        cells = 100
    k_star = BAR.k_star
    rows = []
    a_min_uniform = analytic("uniform").slip_amplitude(0.0)
    for name, (load, _) in LOADS.items():
        el = analytic(name)
        num = NumericalMicroslip(BAR, load, cells=cells, steps_per_cycle=steps_per_cycle)
        bases = [("own", el.slip_amplitude(0.0))]
        if name != "uniform":
            bases.append(("uniform", a_min_uniform))
        for base, a_min in bases:
            a = np.array(ratios) * a_min
            t0 = time.perf_counter()
            fs, fc = num.fourier(a, 0.0)
            seconds = time.perf_counter() - t0
            fs_a, fc_a = el.fourier(a, 0.0)
            for i, r in enumerate(ratios):
                rows.append(dict(load=name, a_min=base, ratio=r, Fs=fs_a[i] / (k_star * a[i]),
                                 Fs_num=fs[i] / (k_star * a[i]), Fc=fc_a[i] / (k_star * a[i]),
                                 Fc_num=fc[i] / (k_star * a[i]), dFs=fs[i] / fs_a[i] - 1.0,
                                 dFc=fc[i] / fc_a[i] - 1.0, seconds=seconds / len(ratios)))
    return rows


def table(rows, markdown: bool = True) -> str:
    """The rows as the Markdown table of docs/validation.md, or (``markdown=False``) as aligned text."""
    header = ["load", "a/a_min", "F_s analytic", "F_s numerical", "rel. diff", "F_c analytic", "F_c numerical", "rel. diff"]
    body = [[r["load"] + ("" if r["a_min"] == "own" else " (a_min uniform)"), f"{r['ratio']:g}", f"{r['Fs']:.6f}",
             f"{r['Fs_num']:.6f}", f"{r['dFs']:+.1e}", f"{r['Fc']:.6f}", f"{r['Fc_num']:.6f}", f"{r['dFc']:+.1e}"]
            for r in rows]
    return markdown_table(header, body) if markdown else text_table(header, body)


#: Resolution of the saved PNG.
DPI = 150


def figure(rows, outdir: Path = FIGURES) -> Path:
    """|F(numerical)/F(analytic) - 1| of F_s and F_c against a/a_min, one line per load (and per
    a_min of the concave load); writes ``outdir/validation_quasi_static.png``, returns its path."""
    fig, axes = plt.subplots(1, 2, figsize=(9.0, 3.8), sharey=True, layout="constrained")
    groups = {}
    for r in rows:
        groups.setdefault(r["load"] + ("" if r["a_min"] == "own" else " (a_min of uniform)"), []).append(r)
    for ax, key, label in ((axes[0], "dFs", "F_s"), (axes[1], "dFc", "F_c")):
        for (name, sel), marker in zip(groups.items(), "osD^"):
            ax.loglog([r["ratio"] for r in sel], [max(abs(r[key]), 1e-12) for r in sel], marker=marker, label=name)
        ratios = sorted({r["ratio"] for r in rows})
        ax.set_xticks(ratios, [f"{x:g}" for x in ratios])
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.set_xlabel("a / a_min")
        ax.set_title(f"{label}: numerical against analytic")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("relative difference")
    axes[1].legend(fontsize=8)
    fig.suptitle("Quasi-static bar (omega = 0): the discretised bar against the analytic elements")
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    path = outdir / "validation_quasi_static.png"
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return path


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=(__doc__ or "").partition("\n")[0])
    parser.add_argument("--cells", type=int, default=400)
    parser.add_argument("--markdown", action="store_true", help="print the table as Markdown")
    args = parser.parse_args()
    t0 = time.perf_counter()
    rows = main(cells=args.cells)
    figure(rows)
    print(table(rows, markdown=args.markdown))
    worst = max(max(abs(r["dFs"]), abs(r["dFc"])) for r in rows)
    print(f"\nlargest relative difference {worst:.1e}; {time.perf_counter() - t0:.1f} s in all")
