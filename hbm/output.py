"""The one CSV layout and the one FRF figure of the library.

Every FRF table (``FrequencyResponse.to_csv``, ``python -m hbm``, a scene's ``frf.csv``) has the
columns :data:`FRF_COLUMNS`, units in the names, with a scene's run columns :data:`RUN_COLUMNS`
in front; rows are streamed and flushed as points arrive (:class:`CsvStream`).  Every FRF
figure is drawn by :func:`plot_frfs`, which stays readable for many curves: up to
:data:`LEGEND_LIMIT` curves get a legend, more are coloured by a swept parameter with a colour bar
and styled by model.  Floats are written with ``repr`` (round-trip exact).
"""

from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import Any, Iterable, Sequence

import numpy as np

#: Columns of an FRF point: frequency, first-harmonic amplitude, phase lag, x_c, x_s and the
#: balance residual |R|/F of the point (dimensionless).
FRF_COLUMNS = ("omega_rad_s", "amplitude_m", "phase_rad", "x_c_m", "x_s_m", "residual_rel")
#: Columns naming a scene's run in front of its rows.
RUN_COLUMNS = ("run", "model", "normal_load_N")
#: Columns of an amplitude sweep's table (F_s, F_c normalised by k* a).
TABLE_COLUMNS = ("omega_rad_s", "a_m", "a_over_unit", "f_s_N", "f_c_N", "F_s", "F_c")
#: At most this many curves get a legend; beyond, colour follows the swept parameter.
LEGEND_LIMIT = 8
#: Line styles by model, in order of first appearance.
STYLES = ("-", "--", "-.", ":")


def frf_row(omega: float, x_c: float, x_s: float, residual: float, *, amplitude: float | None = None,
            phase: float | None = None) -> list[str]:
    """The :data:`FRF_COLUMNS` values of one point, as text (amplitude and phase from x_c, x_s
    unless given)."""
    amplitude = math.hypot(x_c, x_s) if amplitude is None else amplitude
    phase = math.atan2(x_s, x_c) if phase is None else phase
    return [repr(float(v)) for v in (omega, amplitude, phase, x_c, x_s, residual)]


class CsvStream:
    """A CSV file written row by row and flushed after each, so an interrupted run keeps its rows.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "frf.csv"
    >>> with CsvStream(path, FRF_COLUMNS) as out:
    ...     out.write(frf_row(1.0, 3.0, 4.0, 1e-9))
    >>> path.read_text().splitlines()[1]
    '1.0,5.0,0.9272952180016122,3.0,4.0,1e-09'
    """

    def __init__(self, path: str | Path, columns: Sequence[str]) -> None:
        self.path = Path(path)
        self.columns = tuple(columns)
        self._fh = self.path.open("w", newline="")
        self._writer = csv.writer(self._fh)
        self.rows = 0
        self.write(self.columns, count=False)

    def write(self, row: Iterable[Any], *, count: bool = True) -> None:
        """Append one row and flush it."""
        self._writer.writerow(row)
        self._fh.flush()
        self.rows += count

    def close(self) -> None:
        self._fh.close()

    def __enter__(self) -> "CsvStream":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def write_frf_csv(path: str | Path, frf: Any) -> Path:
    """Write a :class:`hbm.FrequencyResponse` as :data:`FRF_COLUMNS`; returns the path."""
    with CsvStream(path, FRF_COLUMNS) as out:
        for w, xc, xs, r, a, ph in zip(frf.omega, frf.x_c, frf.x_s, frf.residual_norm, frf.amplitude, frf.phase):
            out.write(frf_row(w, xc, xs, r, amplitude=a, phase=ph))
    return Path(path)


def plot_frfs(curves: Iterable[tuple[Any, str | None, str | None, float | None]], ax: Any = None, *,
              parameter: str | None = None, log: bool = True) -> Any:
    """Amplitude against omega of several FRFs on ``ax`` (a new figure if None); returns ``ax``.

    ``curves`` is a sequence of ``(frf, label, model, value)``: ``model`` sets the line style,
    ``value`` (a number or None) the colour when there are more than :data:`LEGEND_LIMIT` curves,
    with a colour bar titled ``parameter``.  Each curve is drawn by ``FrequencyResponse.plot``,
    which marks its peak.
    """
    if ax is None:
        import matplotlib.pyplot as plt  # lazily: matplotlib only when a figure is drawn

        _, ax = plt.subplots(figsize=(6.4, 4.2))
    curves = list(curves)
    models = list(dict.fromkeys(c[2] for c in curves))
    values = [c[3] for c in curves if c[3] is not None]
    by_value = len(curves) > LEGEND_LIMIT and len(values) == len(curves) and len(set(values)) > 1
    if by_value:
        from matplotlib import cm, colormaps, colors  # lazily, as pyplot above

        norm = (colors.LogNorm if min(values) > 0 and max(values) / min(values) > 20 else colors.Normalize)(
            min(values), max(values))
        cmap = colormaps["viridis"]
    for i, (frf, label, model, value) in enumerate(curves):
        style = STYLES[models.index(model) % len(STYLES)]
        color = cmap(norm(value)) if by_value else f"C{i % 10}"
        frf.plot(ax, label=None if by_value else label, peak=bool(frf.success), ls=style, color=color,
                 lw=0.9 if by_value else 1.2)
    if log:
        ax.set_yscale("log")
    if by_value:
        bar = ax.figure.colorbar(cm.ScalarMappable(norm=norm, cmap=cmap), ax=ax)
        bar.set_label(parameter or "parameter")
        if len(models) > 1:
            from matplotlib.lines import Line2D  # lazily, as pyplot above

            ax.legend([Line2D([], [], ls=STYLES[i % len(STYLES)], color="0.3") for i in range(len(models))],
                      models, fontsize=7)
    elif curves and any(c[1] for c in curves):
        ax.legend(fontsize=7)
    return ax


def plot_branch(ax: Any, omega: Any, amplitude: Any, stable: Any = None, *, label: str | None = None,
                **kwargs: Any) -> tuple[Any, Any]:
    """Draw one branch on ``ax`` (a new figure if None): stable stretches solid, unstable
    stretches dashed in the same colour (``stable`` None: all solid).  Returns ``(ax, colour)``.

    A ``ls``/``linestyle`` given in ``kwargs`` styles the stable stretches (the model's style in
    :func:`plot_frfs`); unstable stretches are always dashed.
    """
    import matplotlib.pyplot as plt  # lazily: matplotlib only when a figure is drawn

    if ax is None:
        _, ax = plt.subplots(figsize=(6.4, 4.2))
    omega, amplitude = np.asarray(omega), np.asarray(amplitude)
    stable = np.ones(omega.size, dtype=bool) if stable is None else np.asarray(stable, dtype=bool)
    ls = kwargs.pop("ls", kwargs.pop("linestyle", "-"))
    cuts = np.flatnonzero(stable[1:] != stable[:-1]) + 1
    color = kwargs.pop("color", None)
    start = 0
    for end in list(cuts) + [omega.size]:
        seg = slice(start, min(end + 1, omega.size))  # overlap one point: no gaps
        line, = ax.plot(omega[seg], amplitude[seg], ls=ls if (stable[start] if omega.size else True) else "--",
                        color=color, label=label if start == 0 else None, **kwargs)
        color = line.get_color()  # one colour for the whole branch
        start = end
    ax.set_xlabel(r"$\omega$ (rad/s)")
    ax.set_ylabel("amplitude (m)")
    return ax, color
