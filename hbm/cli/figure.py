"""The main job's figure ``frf.png``, drawn in a forked process while the parent solves the peak.

``python -m hbm`` spends about 0.3 s on the figure (matplotlib's import 0.2 s, the drawing and the
PNG 0.1 s) and, by default, most of its time on the all-mode peak (``hbm.allmode_peak``), which
runs on one core.  :class:`JobFigure` forks a child as soon as the single-mode curve is known: the
child imports matplotlib, draws the curve and the damper's linear reference and renders them
once (the fonts, the tick labels and the text layout are then cached), then waits for the peak
on a pipe; the parent sends it when solved, the child adds the all-mode markers and the legend,
writes the PNG and answers ``ok`` (or its traceback).  The parent waits for the child (no zombie)
and, where the child failed, says why in a ``RuntimeWarning`` and draws the figure itself, so a
genuine error in the drawing is raised in the parent as it would be without the child.

Where ``os.fork`` does not exist (Windows) or fails (a process limit), or with ``fork=False``, the
figure is drawn in the process, after the peak (the same functions, the same picture).  An
exception or a signal in
the parent between the fork and the end (Ctrl-C, SIGTERM) closes the pipe and ends and reaps
the child (:meth:`JobFigure.cancel`); the child ignores SIGINT (the parent reports it) and takes
the default action on SIGTERM.
"""

from __future__ import annotations

import os
import pickle
import signal
import sys
import traceback
import warnings
from pathlib import Path
from typing import Any

from ..allmode_peak import SCAN
from ..output import plot_frfs, plot_linear_reference

__all__ = ["JobFigure", "base_figure", "add_peak", "save_figure", "DPI", "SIZE"]

#: The figure's size (inches) and resolution (dots per inch).
SIZE = (6.4, 4.2)
DPI = 130


def base_figure(frf: Any, case: Any, *, render: bool = False, given: Any = None) -> tuple[Any, Any]:
    """The job's figure without the all-mode peak and without its legend.

    Parameters
    ----------
    frf : hbm.FrequencyResponse
        The job's curve: the physical one (``model="auto"``), or the single-mode one.
    case : hbm.cli.cases.Case
        The job's case: the damper stuck (linear) and a_min are drawn from its blade and element.
    render : bool, optional
        Draw it once on its Agg canvas (what the forked child does while it waits: the final
        draw then reuses the cached text and ticks).  Default False.
    given : hbm.FrequencyResponse, optional
        The single-mode curve, drawn beside ``frf`` for comparison where ``frf`` is the physical one.

    Returns
    -------
    tuple
        ``(fig, ax)``: a bare matplotlib Figure (no pyplot, no GUI backend) with an Agg canvas,
        :data:`SIZE` at :data:`DPI`, and its axes.
    """
    # heavy (0.2-0.5 s), lazily: only when the figure is drawn (and in the child, in parallel)
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    el = case.element
    fig = Figure(figsize=SIZE, dpi=DPI)
    FigureCanvasAgg(fig)
    ax = fig.subplots()
    plot_linear_reference(ax, case.blade, el, case.omega_range, a_min=el.slip_amplitude(0.0))
    if given is None:
        plot_frfs([(frf, "microslip damper (harmonic balance)", "microslip", None)], ax)
    else:
        ax.plot(given.omega, given.amplitude, "-", color="0.45", lw=0.9,
                label=f"single-mode bar (error to {100.0 * float(max(given.error_estimate)):.2g} %)")
        plot_frfs([(frf, f"bar with every mode (tol {frf.tol:g})", "microslip", None)], ax)
    if given is not None:
        _peak_inset(ax, frf, given)
    ax.set_title("Blade with a two-region microslip damper")
    # fixed margins: tight_layout would draw the figure once more to measure it
    fig.subplots_adjust(left=0.12, right=0.97, bottom=0.12, top=0.93)
    if render:
        fig.canvas.draw()
    return fig, ax


def _peak_inset(ax: Any, frf: Any, given: Any) -> None:
    """An inset of the peak (where the physical curve is above 80 % of its peak), linear axes: the
    single-mode curve's offset and the physical curve's error band, too small to see on the whole curve."""
    A = frf.amplitude
    near = A >= 0.8 * float(max(A))
    w0, w1 = float(min(frf.omega[near])), float(max(frf.omega[near]))
    inset = ax.inset_axes([0.07, 0.52, 0.36, 0.42])
    for f, style in ((given, dict(color="0.45", lw=0.9)), (frf, dict(color="C0", lw=1.2))):
        keep = (f.omega >= w0) & (f.omega <= w1)
        inset.plot(f.omega[keep], f.amplitude[keep], "-", **style)
    keep = (frf.omega >= w0) & (frf.omega <= w1)
    e = frf.error_estimate[keep]
    inset.fill_between(frf.omega[keep], A[keep] * (1.0 - e), A[keep] * (1.0 + e), color="C0", alpha=0.3, lw=0)
    inset.tick_params(labelsize=6)
    inset.set_title("near the peak", fontsize=7)


def add_peak(ax: Any, best: Any) -> None:
    """Add the all-mode peak and the legend to the axes of :func:`base_figure`.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes.
    best : hbm.allmode_peak.AllModePeak or None
        The peak: its scan (on ``hbm.allmode_peak.SCAN``) dashed and the refined peak as a dot,
        both labelled with their rungs.  None: the legend only.
    """
    if best is not None:
        ws, As = best.scan
        ax.plot(ws, As, "C3--", lw=1, label=f"all-mode bar near the peak ({SCAN[0]} cells, H = {SCAN[1]})")
        ax.plot([best.omega], [best.amplitude], "C3o", ms=4,
                label=f"all-mode peak ({best.cells} cells, H = {best.harmonics})")
    ax.legend(fontsize=7, loc="upper right")


def save_figure(fig: Any, path: Path) -> Path:
    """Write ``fig`` as PNG.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    path : pathlib.Path
        Where it goes.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    fig.savefig(path, dpi=DPI)
    return path


def _write_all(fd: int, data: bytes) -> None:
    view = memoryview(data)
    while view:
        view = view[os.write(fd, view):]


def _read_all(fd: int) -> bytes:
    chunks = []
    while True:
        chunk = os.read(fd, 65536)
        if not chunk:
            return b"".join(chunks)
        chunks.append(chunk)


class JobFigure:
    """``frf.png`` of the main job, drawn in a forked child while the peak is solved (module docstring).

    Parameters
    ----------
    frf : hbm.FrequencyResponse
        The single-mode curve.
    case : hbm.cli.cases.Case
        The job's case (blade, element, sweep).
    path : pathlib.Path
        Where the PNG goes.
    fork : bool, optional
        Draw in a forked child (where ``os.fork`` exists).  Default True; False draws in the process
        at :meth:`finish`.
    given : hbm.FrequencyResponse, optional
        The single-mode curve drawn beside a physical ``frf`` (:func:`base_figure`).
    """

    def __init__(self, frf: Any, case: Any, path: Path, *, fork: bool = True, given: Any = None) -> None:
        self.frf, self.case, self.path, self.given = frf, case, Path(path), given
        self.pid: int | None = None
        self._to_child = self._from_child = -1
        if fork and hasattr(os, "fork"):
            try:
                self._start()
            except OSError:  # no process to be had (a limit): drawn here at finish
                self.pid = None

    @property
    def forked(self) -> bool:
        """True while a child draws the figure."""
        return self.pid is not None

    def _start(self) -> None:
        r_in, w_in = os.pipe()
        r_out, w_out = os.pipe()
        for stream in (sys.stdout, sys.stderr):  # nothing buffered is written twice
            stream.flush()
        try:
            with warnings.catch_warnings():
                # Python >= 3.12 warns of fork in a process with threads: ours are BLAS's idle workers
                # (OpenBLAS resets them in the child), and the child only draws and exits
                warnings.simplefilter("ignore", DeprecationWarning)
                pid = os.fork()
        except OSError:
            for fd in (r_in, w_in, r_out, w_out):
                os.close(fd)
            raise
        if pid == 0:  # the child: never returns
            os.close(w_in)
            os.close(r_out)
            self._child(r_in, w_out)
        os.close(r_in)
        os.close(w_out)
        self.pid, self._to_child, self._from_child = pid, w_in, r_out

    def _child(self, r_in: int, w_out: int) -> None:
        code = 1
        try:
            signal.signal(signal.SIGINT, signal.SIG_IGN)
            signal.signal(signal.SIGTERM, signal.SIG_DFL)
            fig, ax = base_figure(self.frf, self.case, render=True, given=self.given)
            data = _read_all(r_in)
            if data:  # empty: the parent cancelled
                add_peak(ax, pickle.loads(data))
                save_figure(fig, self.path)
                os.write(w_out, b"ok")
                code = 0
        except BaseException:  # reported to the parent, which draws again and raises it there
            try:
                os.write(w_out, traceback.format_exc().encode()[:60000])
            except BaseException:
                pass
        finally:
            os._exit(code)

    def finish(self, best: Any) -> Path:
        """Write the figure with the peak and wait for the child.

        Parameters
        ----------
        best : hbm.allmode_peak.AllModePeak or None
            The all-mode peak, or None (the single-mode answer stands).

        Returns
        -------
        pathlib.Path
            The PNG written.

        Warns
        -----
        RuntimeWarning
            Where the child failed (its last traceback line); the figure is then drawn here,
            which raises a genuine error of the drawing.
        """
        if self.forked:
            try:
                try:
                    _write_all(self._to_child, pickle.dumps(best))
                except BrokenPipeError:  # the child is gone: its answer says why
                    pass
                os.close(self._to_child)
                self._to_child = -1
                answer = _read_all(self._from_child)
            finally:
                status = self._reap()
            if answer == b"ok" and status == 0:
                return self.path
            why = answer.decode(errors="replace").strip().splitlines()
            warnings.warn(f"the figure's process failed ({why[-1] if why else f'exit status {status}'}); "
                          "drawing it here", RuntimeWarning, stacklevel=2)
        fig, ax = base_figure(self.frf, self.case, given=self.given)
        add_peak(ax, best)
        return save_figure(fig, self.path)

    def cancel(self) -> None:
        """End and reap the child, if any (the parent failed or was interrupted)."""
        if self.forked:
            try:
                os.kill(self.pid, signal.SIGTERM)
            except ProcessLookupError:
                pass
            self._reap()

    def _reap(self) -> int:
        for fd in (self._to_child, self._from_child):
            if fd >= 0:
                os.close(fd)
        self._to_child = self._from_child = -1
        _, status = os.waitpid(self.pid, 0)
        self.pid = None
        return os.waitstatus_to_exitcode(status)
