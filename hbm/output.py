"""The one CSV layout and the one FRF figure of the library.

Every FRF table (``FrequencyResponse.to_csv``, ``python3 -m hbm``, a scene's ``frf.csv``) has the
columns :data:`FRF_COLUMNS`, units in the names, with a scene's run columns :data:`RUN_COLUMNS`
in front, the column names followed by ``# key: value`` lines (case, model, tol, version) that
``numpy.loadtxt(..., skiprows=1)`` and ``pandas.read_csv(comment="#")`` skip (:func:`csv_lines`
for the ``csv`` module); rows are streamed and flushed as points arrive (:class:`CsvStream`).  Every FRF
figure is drawn by :func:`plot_frfs`, which stays readable for many curves: up to
:data:`LEGEND_LIMIT` curves get a legend, more are coloured by a swept parameter with a colour bar
and styled by model.  Floats are written with ``repr`` (round-trip exact).
"""

from __future__ import annotations

import csv
import math
import os
from pathlib import Path
from typing import Any, Iterable, Sequence

import numpy as np

from ._validation import count, omega_range_pair
from .balance.residual import linear_response

#: Columns of an FRF point: frequency, first-harmonic amplitude, phase lag, x_c, x_s and the
#: balance residual |R|/F of the point (dimensionless).
#: ``error_rel`` is the point's estimated relative error (``FrequencyResponse.error_estimate``;
#: ``nan`` while a scene streams the point, filled in when its run ends).
FRF_COLUMNS = ("omega_rad_s", "amplitude_m", "phase_rad", "x_c_m", "x_s_m", "residual_rel", "error_rel")
#: Column of a point's estimated relative error.
ERROR_COLUMN = FRF_COLUMNS[-1]
#: Column of the frequency in Hz, after ``omega_rad_s``, in a scene swept in Hz (``sweep.unit = "Hz"``).
HZ_COLUMN = "f_Hz"
#: Column of a point's stability by Hill's method (1 stable, 0 unstable; empty while not yet known)
#: in a multi-harmonic table.
STABLE_COLUMN = "stable"
#: Column of a point's number of harmonics, written last where it varies along the curve
#: (``hbm.frequency_response`` with ``tol`` chooses H along the curve).
H_COLUMN = "H"
#: Column of a point's model (its contacts' element class names, "+"-joined), written last where it
#: varies along the curve (``model="auto"``).
MODEL_COLUMN = "model"
#: Columns naming a scene's run in front of its rows.
RUN_COLUMNS = ("run", "model", "normal_load_N")
#: Columns of an amplitude sweep's table (F_s, F_c normalised by k* a).
TABLE_COLUMNS = ("omega_rad_s", "a_m", "a_over_unit", "f_s_N", "f_c_N", "F_s", "F_c")


class _Units(dict):
    """A figure's units by name; a name not among them is refused naming the parameter it came from."""

    def __init__(self, parameter: str, units: dict):
        super().__init__(units)
        self.parameter = parameter

    def __getitem__(self, name: object):
        try:
            return super().__getitem__(name)
        except TypeError:  # an unhashable name (a list): refused as an unknown one, not "unhashable type"
            return self.__missing__(name)

    def __missing__(self, name: object):
        raise ValueError(f"{self.parameter} must be one of {', '.join(map(repr, self))}, "
                         f"got {self.parameter}={name!r}")


#: Frequency units of a figure's axis: name -> (factor from rad/s, axis label).
OMEGA_UNITS = _Units("omega_unit", {"rad/s": (1.0, r"$\omega$ (rad/s)"),
                                    "Hz": (1.0 / (2.0 * math.pi), "frequency (Hz)")})
#: Amplitude units of a figure's axis: name -> (factor from m, axis label).
AMPLITUDE_UNITS = _Units("amplitude_unit", {"m": (1.0, "amplitude (m)"), "um": (1.0e6, "amplitude (\u00b5m)")})

#: Axis names of the scene keys a scene or study varies: key -> (name, unit); SI units, "" for a
#: number without one.  A key not here is named by itself (:func:`key_label`).
KEY_LABELS = {
    "damper.load.N": ("normal load N", "N"),
    "damper.load.ratio": ("load ratio q0/(q0 - q2)", ""),
    "damper.mu": ("friction coefficient mu", ""),
    "damper.k": ("shear-layer stiffness k", "N/m^2"),
    "damper.beta": ("strain-hardening stiffness beta", "N/m"),
    "damper.E": ("Young's modulus E", "Pa"),
    "damper.rho": ("density rho", "kg/m^3"),
    "damper.A": ("cross-section A", "m^2"),
    "damper.L": ("bar length L", "m"),
    "damper.stiffness": ("damper stiffness", "N/m"),
    "damper.slip_force": ("slip force", "N"),
    "blade.mass": ("modal mass m", "kg"),
    "blade.stiffness": ("blade stiffness k", "N/m"),
    "blade.damping": ("viscous damping c", "N s/m"),
    "blade.damping_ratio": ("damping ratio zeta", ""),
    "blade.force": ("force amplitude F", "N"),
    "sweep.tol": ("target relative error tol", ""),
}


def key_label(key: str) -> str:
    """The axis label of a scene key: its name and SI unit from :data:`KEY_LABELS`, else the key.

    Examples
    --------
    >>> key_label("damper.load.N"), key_label("damper.mu"), key_label("effects.inertia")
    ('normal load N (N)', 'friction coefficient mu', 'effects.inertia')
    """
    if key not in KEY_LABELS:
        return key
    name, unit = KEY_LABELS[key]
    return f"{name} ({unit})" if unit else name


#: At most this many curves get a legend; beyond, colour follows the swept parameter.
LEGEND_LIMIT = 8
#: Line styles by model, in order of first appearance.
STYLES = ("-", "--", "-.", ":")


def harmonic_columns(harmonics: int) -> tuple[str, ...]:
    """The columns of the response DOF's harmonics at H = ``harmonics``: ``X0_m``, ``Xc1_m``,
    ``Xs1_m``, ..., ``XcH_m``, ``XsH_m`` (``x = X0 + sum_h Xc_h cos(h omega t) + Xs_h sin(h omega t)``,
    so ``c_h = Xc_h - i Xs_h`` of ``FrequencyResponse.coefficients``).

    Examples
    --------
    >>> harmonic_columns(2)
    ('X0_m', 'Xc1_m', 'Xs1_m', 'Xc2_m', 'Xs2_m')
    """
    return ("X0_m",) + tuple(f"X{cs}{h}_m" for h in range(1, harmonics + 1) for cs in "cs")


def frf_columns(harmonics: int = 1, *, hz: bool = False) -> tuple[str, ...]:
    """The columns of an FRF table: :data:`FRF_COLUMNS`, with ``f_Hz`` after ``omega_rad_s`` when
    ``hz``, and above one harmonic every harmonic of the response DOF (:func:`harmonic_columns`)
    and ``stable`` (0/1).  At H = 1 in rad/s exactly :data:`FRF_COLUMNS`.

    Examples
    --------
    >>> frf_columns() == FRF_COLUMNS
    True
    >>> frf_columns(2, hz=True)[:3], frf_columns(2)[-6:]
    (('omega_rad_s', 'f_Hz', 'amplitude_m'), ('X0_m', 'Xc1_m', 'Xs1_m', 'Xc2_m', 'Xs2_m', 'stable'))
    """
    cols = (FRF_COLUMNS[0], HZ_COLUMN) + FRF_COLUMNS[1:] if hz else FRF_COLUMNS
    return cols + (harmonic_columns(harmonics) + (STABLE_COLUMN,) if harmonics > 1 else ())


def with_hz(row: list[str], omega: float) -> list[str]:
    """``row`` (text, omega first) with ``f_Hz = omega / (2 pi)`` inserted after omega."""
    return row[:1] + [repr(float(omega) / (2.0 * math.pi))] + row[1:]


def harmonic_values(X: Any, harmonics: int) -> list[str]:
    """The :func:`harmonic_columns` values, as text, of one point's real layout ``X = (X0, Xc1, Xs1,
    ...)``; a layout with fewer harmonics (a run held linear, H = 1) is padded with exact zeros."""
    X = np.asarray(X, dtype=float)
    out = np.zeros(2 * harmonics + 1)
    out[:min(X.size, out.size)] = X[:out.size]
    return [repr(float(v)) for v in out]


def stable_value(stable: Any) -> str:
    """The ``stable`` cell: ``"1"``, ``"0"``, or ``""`` when not known (None)."""
    return "" if stable is None else str(int(bool(stable)))


def frf_row(omega: float, x_c: float, x_s: float, residual: float, *, amplitude: float | None = None,
            phase: float | None = None, error: float | None = None) -> list[str]:
    """The :data:`FRF_COLUMNS` values of one point, as text (amplitude and phase from x_c, x_s
    unless given; the error estimate ``nan`` unless given)."""
    amplitude = math.hypot(x_c, x_s) if amplitude is None else amplitude
    phase = math.atan2(x_s, x_c) if phase is None else phase
    return [repr(float(v)) for v in (omega, amplitude, phase, x_c, x_s, residual)] + [error_value(error)]


def error_value(error: float | None) -> str:
    """The ``error_rel`` cell: the estimate, or ``nan`` when there is none (yet): a row stays numeric."""
    return repr(float(error)) if error is not None else "nan"


#: The first character of a CSV's comment lines (what ``numpy.loadtxt``, ``numpy.genfromtxt`` and
#: ``pandas.read_csv(..., comment="#")`` skip; :func:`csv_lines` for the ``csv`` module).
COMMENT = "#"


def comment_lines(fields: Any) -> list[str]:
    """The ``# key: value`` lines of a CSV's header from ``fields`` (a mapping; None values left out,
    line breaks in a value made spaces, so every line stays one comment line).

    Examples
    --------
    >>> comment_lines({"case": "blade\\nand damper", "tol": 0.001, "model": None})
    ['# case: blade and damper', '# tol: 0.001']
    """
    return [f"{COMMENT} {k}: {' '.join(str(v).split())}" for k, v in dict(fields).items() if v is not None]


def csv_lines(lines: Iterable[str]) -> Iterable[str]:
    """The lines of a CSV without its ``#`` comment lines, for ``csv.reader`` / ``csv.DictReader``
    (an open file, or any iterable of lines).

    Examples
    --------
    >>> import csv
    >>> list(csv.reader(csv_lines(["# tol: 0.001", "a,b", "1,2"])))
    [['a', 'b'], ['1', '2']]
    """
    return (line for line in lines if not line.startswith(COMMENT))


def read_comments(path: str | Path) -> dict:
    """The ``# key: value`` lines of a CSV written here (:class:`CsvStream`), as a dict of strings.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "t.csv"
    >>> with CsvStream(path, ("a",), comments={"tol": 0.001}) as out:
    ...     out.write(["1.0"])
    >>> read_comments(path)
    {'tol': '0.001'}
    """
    out = {}
    with Path(path).open(newline="") as fh:
        next(fh, None)  # the column names
        for line in fh:
            if not line.startswith(COMMENT):
                break
            key, _, value = line[len(COMMENT):].strip().partition(": ")
            out[key] = value
    return out


class CsvStream:
    """A CSV file written row by row and flushed after each, so an interrupted run keeps its rows.

    ``comments`` (a mapping) is written as ``# key: value`` lines (:func:`comment_lines`) right
    after the column names: what the table is (case, model, tol, version).  There the usual
    readers skip them: ``numpy.loadtxt(path, delimiter=",", skiprows=1)`` (its ``skiprows`` counts
    comment lines too, so they follow the one line it skips), ``numpy.genfromtxt(path,
    delimiter=",", names=True)`` and ``pandas.read_csv(path, comment="#")``; for the ``csv``
    module, :func:`csv_lines`.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "frf.csv"
    >>> with CsvStream(path, FRF_COLUMNS, comments={"tol": 0.001}) as out:
    ...     out.write(frf_row(1.0, 3.0, 4.0, 1e-9))
    >>> path.read_text().splitlines()[1:]
    ['# tol: 0.001', '1.0,5.0,0.9272952180016122,3.0,4.0,1e-09,nan']
    >>> float(np.loadtxt(path, delimiter=",", skiprows=1)[1])   # the column names skipped, the comment too
    5.0
    """

    def __init__(self, path: str | Path, columns: Sequence[str], *, comments: Any = None) -> None:
        if not isinstance(path, (str, os.PathLike)):
            raise ValueError(f"path must be a file path (a str or pathlib.Path), got path={path!r}")
        self.path = Path(path)
        if "\0" in str(self.path):  # (the file system's "embedded null byte", naming nothing)
            raise ValueError(f"path must be a file path without a null character, got path={str(path)!r}")
        if self.path.is_dir():  # ("" is the current folder)
            raise ValueError(f"path must be a file path, not a folder, got path={str(path)!r}")
        if not self.path.parent.is_dir():  # before: a bare FileNotFoundError
            raise ValueError(f"path must be in an existing folder, got path={str(path)!r} (no folder "
                             f"{str(self.path.parent)!r}; create it first)")
        self.columns = tuple(columns)
        self._fh = self.path.open("w", newline="")
        self.comments = comment_lines(comments or {})
        self._writer = csv.writer(self._fh)
        self.rows = 0
        self._writer.writerow(self.columns)
        for line in self.comments:  # after the column names: loadtxt(skiprows=1), genfromtxt(names=True) read on
            self._fh.write(line + "\r\n")  # the csv module's line ending, as the rows
        self._fh.flush()

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


#: The message of ``to_dataframe`` without pandas.
PANDAS_MISSING = ('to_dataframe needs pandas, which is not installed: pip install "frictiondamp[pandas]" '
                  '(or pip install pandas); to_csv writes the same table without it')


def pandas_module() -> Any:
    """``pandas``, imported when a table is asked for as a DataFrame; ``ImportError`` naming the
    ``pandas`` extra where it is not installed (the library itself needs only numpy, scipy and
    matplotlib)."""
    try:
        import pandas  # lazily: an optional extra
    except ImportError:
        raise ImportError(PANDAS_MISSING) from None
    return pandas


def frf_table(frf: Any) -> dict:
    """The columns of :func:`write_frf_csv` as arrays, ``{name: ndarray}`` in the CSV's order
    (numbers as floats, ``stable`` as bool, ``model`` as str): what ``to_dataframe`` holds."""
    H = int(frf.harmonics)
    table = {"omega_rad_s": np.asarray(frf.omega, dtype=float), "amplitude_m": np.asarray(frf.amplitude, dtype=float),
             "phase_rad": np.asarray(frf.phase, dtype=float), "x_c_m": np.asarray(frf.x_c, dtype=float),
             "x_s_m": np.asarray(frf.x_s, dtype=float), "residual_rel": np.asarray(frf.residual_norm, dtype=float),
             "error_rel": np.asarray(frf.error_estimate, dtype=float)}
    if H > 1:
        C = frf.coefficients(frf.response_dof)
        X = np.empty((len(C), 2 * H + 1))
        X[:, 0], X[:, 1::2], X[:, 2::2] = C[:, 0].real, C[:, 1:].real, -C[:, 1:].imag
        table.update(zip(harmonic_columns(H), X.T))
        table[STABLE_COLUMN] = np.asarray(frf.stable, dtype=bool)
    Hs, models = np.asarray(frf.point_harmonics), np.asarray(frf.point_models)
    if len(set(Hs.tolist())) > 1:
        table[H_COLUMN] = Hs.astype(int)
    if len(set(models.tolist())) > 1:
        table[MODEL_COLUMN] = models.astype(str)
    return table


def frf_comments(frf: Any, case: str | None = None) -> dict:
    """The header of an FRF's CSV: the library and its version, the ``case`` (if given), the model
    (the points' models, ``FrequencyResponse.point_models``), the tolerance (``tol``: the
    target of ``error_rel``; none without an estimate) and the harmonics."""
    from contact_models import __version__  # lazily: this module stays free of the packages' imports at load

    if case is not None and not isinstance(case, str):
        raise ValueError(f"case must be a str (what was solved, in words) or None, got case={case!r}")
    models = list(dict.fromkeys(str(m) for m in getattr(frf, "point_models", [])))
    tol = getattr(frf, "tol", None)
    return {"frictiondamp": __version__, "case": case, "model": ", ".join(models) or "none (linear)",
            "tol": "none (no error estimate)" if tol is None else f"{tol:g} (target relative error of amplitude_m; "
                                                                   "error_rel is each point's estimate)",
            "harmonics": int(frf.harmonics)}


def write_frf_csv(path: str | Path, frf: Any, *, case: str | None = None) -> Path:
    """Write a :class:`hbm.FrequencyResponse` as :func:`frf_columns` (:data:`FRF_COLUMNS` at one
    harmonic; above one, also every harmonic of the response DOF, from
    ``frf.coefficients(frf.response_dof)``, zero above a point's own H, and its stability), then
    :data:`H_COLUMN` and :data:`MODEL_COLUMN` where the point's H and model vary along the curve
    (``frf.point_harmonics``, ``frf.point_models``), under the ``#`` header of :func:`frf_comments`
    (``case`` a description of what was solved); returns the path."""
    H = int(frf.harmonics)
    n = len(frf.omega)
    Hs, models = (np.asarray(getattr(frf, name, np.full(n, v))) for name, v in (("point_harmonics", H),
                                                                                 ("point_models", "")))
    extra = ((H_COLUMN,) if len(set(Hs.tolist())) > 1 else ()) + ((MODEL_COLUMN,) if len(set(models.tolist())) > 1
                                                                  else ())
    tail = [[str(int(h))] * (H_COLUMN in extra) + [str(m)] * (MODEL_COLUMN in extra) for h, m in zip(Hs, models)]
    with CsvStream(path, frf_columns(H) + extra, comments=frf_comments(frf, case)) as out:
        if H == 1:
            for w, xc, xs, r, a, ph, e, t in zip(frf.omega, frf.x_c, frf.x_s, frf.residual_norm, frf.amplitude,
                                                 frf.phase, frf.error_estimate, tail):
                out.write(frf_row(w, xc, xs, r, amplitude=a, phase=ph, error=e) + t)
        else:
            C = frf.coefficients(frf.response_dof)
            X = np.empty((len(C), 2 * H + 1))
            X[:, 0], X[:, 1::2], X[:, 2::2] = C[:, 0].real, C[:, 1:].real, -C[:, 1:].imag
            for w, xc, xs, r, a, ph, x, st, e, t in zip(frf.omega, frf.x_c, frf.x_s, frf.residual_norm, frf.amplitude,
                                                        frf.phase, X, frf.stable, frf.error_estimate, tail):
                out.write(frf_row(w, xc, xs, r, amplitude=a, phase=ph, error=e) + harmonic_values(x, H)
                          + [stable_value(st)] + t)
    return Path(path)


def _axes(ax: Any) -> Any:
    """``ax``, or a new figure's axes where it is None; anything that cannot draw is refused by name."""
    if ax is None:
        import matplotlib.pyplot as plt  # lazily: matplotlib only when a figure is drawn

        return plt.subplots(figsize=(6.4, 4.2))[1]
    if not callable(getattr(ax, "plot", None)):
        raise ValueError(f"ax must be a matplotlib Axes or None, got ax={ax!r}")
    return ax


def plot_frfs(curves: Iterable[tuple[Any, str | None, str | None, float | None]], ax: Any = None, *,
              parameter: str | None = None, log: bool = True, omega_unit: str = "rad/s",
              amplitude_unit: str = "m") -> Any:
    """Amplitude against omega of several FRFs on ``ax`` (a new figure if None); returns ``ax``.

    ``curves`` is a sequence of ``(frf, label, model, value)``: ``model`` sets the line style,
    ``value`` (a number or None) the colour when there are more than :data:`LEGEND_LIMIT` curves,
    with a colour bar titled ``parameter``.  Each curve is drawn by ``FrequencyResponse.plot``,
    which marks its peak and shades its estimated error (up to :data:`LEGEND_LIMIT` curves; more
    would hide each other under their bands); ``omega_unit`` (:data:`OMEGA_UNITS`) and
    ``amplitude_unit`` (:data:`AMPLITUDE_UNITS`) set the axes' units.  ``parameter`` is the colour
    bar's title (:func:`key_label` of a scene key).
    """
    ax = _axes(ax)
    OMEGA_UNITS[omega_unit], AMPLITUDE_UNITS[amplitude_unit]  # (refused here, before any curve is drawn)
    curves = list(curves)
    # units passed on only when asked: a curve may be any object with plot(ax, label=, peak=, **style)
    units = {k: v for k, v in (("omega_unit", omega_unit), ("amplitude_unit", amplitude_unit))
             if v != {"omega_unit": "rad/s", "amplitude_unit": "m"}[k]}
    models = list(dict.fromkeys(c[2] for c in curves))
    values = [c[3] for c in curves if c[3] is not None]
    by_value = len(curves) > LEGEND_LIMIT and len(values) == len(curves) and len(set(values)) > 1
    if by_value:
        from matplotlib import cm, colormaps, colors  # lazily, as pyplot above

        norm = (colors.LogNorm if min(values) > 0 and max(values) / min(values) > 20 else colors.Normalize)(
            min(values), max(values))
        cmap = colormaps["viridis"]
    before = len(ax.patches)
    for i, (frf, label, model, value) in enumerate(curves):
        style = STYLES[models.index(model) % len(STYLES)]
        color = cmap(norm(value)) if by_value else f"C{i % 10}"
        frf.plot(ax, label=None if by_value else label, peak=bool(frf.success), ls=style, color=color,
                 lw=0.9 if by_value else 1.2, **units, **({"error_band": False} if by_value else {}))
    bands = ax.patches[before:]
    if bands:  # one legend entry says what the shading is
        bands[0].set_label(BAND_LABEL)
    if log:
        ax.set_yscale("log")
    if by_value:
        bar = ax.figure.colorbar(cm.ScalarMappable(norm=norm, cmap=cmap), ax=ax)
        bar.set_label(parameter or "parameter")
        if len(models) > 1:
            from matplotlib.lines import Line2D  # lazily, as pyplot above

            ax.legend([Line2D([], [], ls=STYLES[i % len(STYLES)], color="0.3") for i in range(len(models))],
                      models, fontsize=7)
    elif curves and any(c[1] for c in curves) or any(line.get_label()[:1] not in ("_", "") for line in ax.lines):
        ax.legend(fontsize=7)
    return ax


#: The a_min line is drawn where it lies within this factor of the stuck response's range (else left out).
LEVEL_RANGE = 1e10


def plot_linear_reference(ax: Any, blade: Any, element: Any, omega_range: tuple[float, float], *,
                          a_min: float | None = None, omega_unit: str = "rad/s", amplitude_unit: str = "m",
                          points: int = 600, label: bool = True, stiffness: Any = None,
                          a_min_color: Any = "C3") -> Any:
    """Draw on ``ax`` what the damper's linear range says of a blade's FRF: the response with the
    damper stuck (a linear spring of stiffness ``element.stuck_stiffness(omega)``), dashed grey,
    and the amplitude ``a_min`` at which slip begins, a dotted horizontal line (left out when
    ``a_min`` is None, 0 or not finite, or more than ``LEVEL_RANGE`` from the stuck response).  The one
    drawing of both for ``python3 -m hbm``'s figure and a scene's; returns ``ax``.  ``label`` False draws
    them without legend entries (a second
    run's references); ``stiffness(omega array) -> array`` replaces ``element.stuck_stiffness``
    (a scene's quasi-static damper, whose own evaluations are counted as the run's); ``a_min_color``
    colours the a_min line (a scene of several runs: the run's colour).  ``omega_range`` is checked as
    :func:`hbm.frequency_response`'s (finite, >= 0, w0 != w1: NaN or inf refused by name), ``points`` >= 2."""

    w_scale = OMEGA_UNITS[omega_unit][0]
    a_scale = AMPLITUDE_UNITS[amplitude_unit][0]
    w = np.linspace(*omega_range_pair(omega_range), count("points", points, 2))
    if stiffness is None:
        stiffness = lambda om: np.array([element.stuck_stiffness(x) for x in om])  # noqa: E731
    stuck = np.abs(linear_response(blade, w, stiffness))
    shown = np.all(np.isfinite(stuck))
    if shown:
        ax.plot(w * w_scale, stuck * a_scale, "--", color="0.6", lw=1,
                label="damper stuck (linear)" if label else None)
    positive = stuck[stuck > 0.0] if shown else stuck[:0]
    if positive.size and a_min is not None and not (float(np.min(positive)) / LEVEL_RANGE <= a_min
                                                    <= float(np.max(positive)) * LEVEL_RANGE):
        a_min = None  # decades away from the response: a line there squashes the curve (and past about 1e280
        # matplotlib's logarithmic ticks overflow: "cannot convert float infinity to integer")
    if a_min is not None and math.isfinite(a_min) and a_min > 0.0:
        ax.axhline(a_min * a_scale, color=a_min_color, lw=0.8, ls=":", label=r"$a_{min}$ (slip begins)" if label else None)
    return ax


#: The legend entry of the estimated error's shading (once per figure, :func:`plot_frfs`).
BAND_LABEL = "estimated error (shaded)"
#: The most of the band's relative half-width drawn below the curve: its lower edge stays above zero
#: (a logarithmic axis draws it).
BAND_FLOOR = 0.99


def plot_error_band(ax: Any, omega: Any, amplitude: Any, error: Any, *, color: Any = None, omega_unit: str = "rad/s",
                    amplitude_unit: str = "m", alpha: float = 0.2) -> Any:
    """Shade ``amplitude * (1 +- error)`` along a branch on ``ax`` (``error`` relative, per point; NaN
    is no width), as a ribbon: the upper edge in continuation order, the lower edge back, so the band
    follows a folded branch.  The lower edge's relative distance is capped at :data:`BAND_FLOOR`.
    Returns the patch (no legend entry).

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> _, ax = plt.subplots()
    >>> band = plot_error_band(ax, [1.0, 2.0, 3.0], [1.0, 2.0, 1.0], [0.1, 0.5, float("nan")])
    >>> band.get_xy()[:6, 1].round(6).tolist()          # up: 1.1, 3.0, 1.0; back: 1.0, 1.0, 0.9
    [1.1, 3.0, 1.0, 1.0, 1.0, 0.9]
    """
    w_scale, a_scale = OMEGA_UNITS[omega_unit][0], AMPLITUDE_UNITS[amplitude_unit][0]
    w = np.asarray(omega, dtype=float) * w_scale
    a = np.asarray(amplitude, dtype=float) * a_scale
    e = np.nan_to_num(np.asarray(error, dtype=float), nan=0.0, posinf=0.0)
    upper, lower = a * (1.0 + e), a * (1.0 - np.minimum(e, BAND_FLOOR))
    band, = ax.fill(np.concatenate([w, w[::-1]]), np.concatenate([upper, lower[::-1]]), color=color, alpha=alpha,
                    lw=0, label="_nolegend_")
    return band


def line_options(kwargs: dict) -> None:
    """Refuse a keyword that is not a property of a matplotlib line (``Line2D.set_<name>``, aliases such as
    ``ls`` and ``lw`` included): a TypeError naming it, before anything is drawn, not matplotlib's
    AttributeError from inside ``ax.plot``."""
    from matplotlib.lines import Line2D  # lazily, as pyplot in _axes

    for key, value in kwargs.items():
        if not callable(getattr(Line2D, f"set_{key}", None)):
            raise TypeError(f"plot() got an unexpected keyword argument {key!r}: not a property of a matplotlib line "
                            f"(matplotlib.lines.Line2D), got {key}={value!r}")


def plot_branch(ax: Any, omega: Any, amplitude: Any, stable: Any = None, *, label: str | None = None,
                omega_unit: str = "rad/s", amplitude_unit: str = "m", **kwargs: Any) -> tuple[Any, Any]:
    """Draw one branch on ``ax`` (a new figure if None): stable stretches solid, unstable
    stretches dashed in the same colour (``stable`` None: all solid).  Returns ``(ax, colour)``.
    ``omega`` (rad/s) and ``amplitude`` (m) are drawn in ``omega_unit`` (:data:`OMEGA_UNITS`) and
    ``amplitude_unit`` (:data:`AMPLITUDE_UNITS`).

    A ``ls``/``linestyle`` given in ``kwargs`` styles the stable stretches (the model's style in
    :func:`plot_frfs`); unstable stretches are always dashed.
    """
    (w_scale, w_label), (a_scale, a_label) = OMEGA_UNITS[omega_unit], AMPLITUDE_UNITS[amplitude_unit]
    line_options(kwargs)
    ax = _axes(ax)
    omega, amplitude = np.asarray(omega) * w_scale, np.asarray(amplitude) * a_scale
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
    ax.set_xlabel(w_label)
    ax.set_ylabel(a_label)
    return ax, color
