"""The main job's figure ``frf.png``: the curve, the damper's linear reference and, beside a refined
curve (``--model auto`` or ``peak``), the single-mode one with an inset of the peak.

It is drawn after the curve is solved and written (the CSV first, so that a signal while drawing
keeps the curve); matplotlib is imported only here, when the figure is drawn (0.2 to 0.5 s).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ..output import plot_frfs, plot_linear_reference

__all__ = ["job_figure", "base_figure", "save_figure", "DPI", "SIZE"]

#: The figure's size (inches) and resolution (dots per inch).
SIZE = (6.4, 4.2)
DPI = 130


def base_figure(frf: Any, case: Any, *, given: Any = None) -> tuple[Any, Any]:
    """The job's figure without its legend.

    Parameters
    ----------
    frf : hbm.FrequencyResponse
        The job's curve: the one refined with the bar of every mode (``model="auto"`` or
        ``"peak"``; each point's model is ``frf.point_models``), or the single-mode one.
    case : hbm.cli.cases.Case
        The job's case: the damper stuck (linear) and a_min are drawn from its blade and element.
    given : hbm.FrequencyResponse, optional
        The single-mode curve, drawn beside ``frf`` for comparison where ``frf`` is refined.

    Returns
    -------
    tuple
        ``(fig, ax)``: a bare matplotlib Figure (no pyplot, no GUI backend) with an Agg canvas,
        :data:`SIZE` at :data:`DPI`, and its axes.
    """
    # heavy (0.2-0.5 s), lazily: only when the figure is drawn
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
                label=f"single-mode bar (estimated error up to {100.0 * float(max(given.error_estimate)):.2g} %)")
        plot_frfs([(frf, f"bar with every mode (tol {frf.tol:g})", "microslip", None)], ax)
    if given is not None:
        _peak_inset(ax, frf, given)
    ax.set_title("Blade with a two-region microslip damper")
    # fixed margins: tight_layout would draw the figure once more to measure it
    fig.subplots_adjust(left=0.12, right=0.97, bottom=0.12, top=0.93)
    return fig, ax


def _peak_inset(ax: Any, frf: Any, given: Any) -> None:
    """An inset of the peak (where the physical curve is above 80 % of its peak), linear axes in
    micrometres (no offset text): the single-mode curve's offset and the physical curve's error band,
    too small to see on the whole curve."""
    A = frf.amplitude
    near = A >= 0.8 * float(max(A))
    w0, w1 = float(min(frf.omega[near])), float(max(frf.omega[near]))
    inset = ax.inset_axes([0.07, 0.52, 0.36, 0.42])
    for f, style in ((given, dict(color="0.45", lw=0.9)), (frf, dict(color="C0", lw=1.2))):
        keep = (f.omega >= w0) & (f.omega <= w1)
        inset.plot(f.omega[keep], 1e6 * f.amplitude[keep], "-", **style)
    keep = (frf.omega >= w0) & (frf.omega <= w1)
    e = frf.error_estimate[keep]
    um = 1e6 * A[keep]
    inset.fill_between(frf.omega[keep], um * (1.0 - e), um * (1.0 + e), color="C0", alpha=0.3, lw=0)
    inset.tick_params(labelsize=6)
    inset.set_title("near the peak (µm, rad/s)", fontsize=7)


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


def job_figure(frf: Any, case: Any, path: Path, *, given: Any = None) -> Path:
    """Draw ``frf.png`` of the main job (:func:`base_figure` with its legend) and write it to ``path``.

    Parameters
    ----------
    frf : hbm.FrequencyResponse
        The job's curve.
    case : hbm.cli.cases.Case
        The job's case (blade, element, sweep).
    path : pathlib.Path
        Where the PNG goes.
    given : hbm.FrequencyResponse, optional
        The single-mode curve drawn beside a refined ``frf``.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    fig, ax = base_figure(frf, case, given=given)
    ax.legend(fontsize=7, loc="upper right")
    return save_figure(fig, Path(path))
