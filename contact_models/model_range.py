"""Where the single-mode elements hold, and the warning they give outside it.

The single-mode dynamic elements (``TwoRegionMicroslip``, ``ThreeRegionMicroslip``) neglect the
phase differences along the bar.  Their error against the all-mode bar (``AllModeMicroslip``),

    e = max(|dF_s| / max(|F_s|, 0.01), |dF_c| / max(F_c, 0.01))      (F in units of k* a),

is tabulated over a grid (the validity map, ``examples/validity_map.py``, stored in
``MAP_FILE`` and shown in ``docs/validation.md``): lambda L in {0.3, 1, 3, 10} times beta L/EA in
{0.1, 1, 10}, the uniform load (two regions) and the concave load of ratio 12 (three regions),
omega/omega_c from 0.01 to 0.95 (14 values) and a/a_min(0) from 0.5 to 100 (10 values), with a
reference converged to well below the 1 % the warning is about (the map stores its error too).

The warning reads that map.  For an element it takes the map of its kind of load and
interpolates log10 e linearly in log(lambda L) and log(beta L/EA) (clamped to the map's ranges:
a bar outside them is taken at the nearest edge), then, at each call, in log(omega/omega_c) and
log(a/a_min(0)).  So at the map's own points it says what the map says, and between them what the
neighbouring points say.  Three rules complete it:

- a map point where the single-mode element refuses to evaluate (its loading curve folds there:
  the map's e is inf) carries no error value; the interpolation takes the neighbours it has (their
  weights renormalised), and where it has none the error is taken as infinite;
- below the element's slip onset at the frequency asked (map ratios <= a_min(omega)/a_min(0)) the
  map's points are stuck and exact; a slipping amplitude between them and the first slipping
  ratio takes that ratio's error (the error just past onset is like the first slipping point's);
- below omega/omega_c = 0.01 the error falls like (omega/omega_c)^2 (the single-mode solution is
  exact at omega = 0); above 0.95 and beyond a/a_min of 0.5 to 100 the map's edge is used.

Where the bar is stuck (a <= a_min(omega)) the elements are exact: e = 0.  The interpolation is
checked against random points off the grid (``docs/data/validity_check.csv``, ``docs/validation.md``,
"Where the single-mode model holds (the validity map)").

Separately, an element whose loading curve folds before gross slip snaps onto the sliding line
early (stiff shear layers, lambda L of 3 and more, with inertia); that snap is flagged when it
happens with more than ``SNAP_TOLERANCE`` L of the bar still stuck.

The check costs a few microseconds per scalar call (the element's slice of the map is
interpolated once and kept on it; the slip onset comes from the element's cache) and is not in
the solver's unchecked path (``fourier_derivatives_unchecked``).
"""

from __future__ import annotations

import bisect
import math
import warnings
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .accuracy import AccuracyWarning

__all__ = ["ModelRangeWarning", "TOLERANCE", "SNAP_TOLERANCE", "MAP_FILE", "validity_map",
           "single_mode_error", "single_mode_frequency_limit", "early_snap", "check_single_mode"]

#: The error (relative, with a floor of 0.01 k* a) beyond which the single-mode elements warn.
TOLERANCE = 0.01
#: An early gross-slip snap is flagged when the stuck length left at the snap exceeds this fraction of L.
SNAP_TOLERANCE = 0.01
#: The validity map (CSV): written by ``examples/validity_map.py``, read by the warning.
MAP_FILE = Path(__file__).resolve().parent / "data" / "validity_map.csv"
#: Smallest error kept in the logarithmic interpolation (the map's stuck points are rounding-level).
_ERROR_FLOOR = 1e-9


class ModelRangeWarning(AccuracyWarning):
    """A contact element is evaluated outside the range where its model is accurate.

    Raised (as a warning) by the single-mode elements ``TwoRegionMicroslip`` and
    ``ThreeRegionMicroslip`` where the validity map (``docs/validation.md``) says their F_s or
    F_c error against the all-mode bar exceeds 1 %, and where they snap onto gross slip early.
    Filter it like any warning, e.g. ``warnings.simplefilter("ignore", ModelRangeWarning)``, or
    turn it into an error with ``"error"``; use ``AllModeMicroslip`` there.

    It carries no attributes of its own: the message names the element class, the frequency
    (rad/s), the amplitude and the map's error there, or the early snap onto gross slip.

    Examples
    --------
    >>> import warnings
    >>> issubclass(ModelRangeWarning, AccuracyWarning)      # the library's accuracy category
    True
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("error", ModelRangeWarning)
    ...     try:
    ...         warnings.warn("outside the validity map", ModelRangeWarning)
    ...     except ModelRangeWarning as exc:
    ...         print(exc)
    outside the validity map
    """


def validity_map(path: Path = MAP_FILE) -> dict[str, tuple]:
    """The validity map as grids: ``{load: (lambda_L, beta_L, w, ratio, e)}``.

    ``lambda_L``, ``beta_L`` (beta L/EA), ``w`` (omega/omega_c) and ``ratio`` (a/a_min(0)) are the
    sorted grid values (tuples); ``e`` is an array of shape ``(len(lambda_L), len(beta_L), len(w),
    len(ratio))`` of max(e_s, e_c), inf where the single-mode element refuses the point.  ``load``
    is ``"uniform"`` (the two-region element's map) or ``"concave12"`` (the three-region one's).
    Read once per process.

    Examples
    --------
    >>> from contact_models.model_range import validity_map
    >>> lam_L, beta_L, w, ratio, e = validity_map()["uniform"]
    >>> lam_L, beta_L, e.shape
    ((0.3, 1.0, 3.0, 10.0), (0.1, 1.0, 10.0), (4, 3, 14, 10))
    """
    return _read_map(path, "max")


@lru_cache(maxsize=None)
def _read_map(path: Path, component: str) -> dict[str, tuple]:
    """:func:`validity_map` of ``component``: "max" (max(e_s, e_c)), "s" (e_s) or "c" (e_c)."""
    with open(path) as fh:
        head = fh.readline().strip().split(",")
        cells = np.array(fh.read().strip().replace("\n", ",").split(",")).reshape(-1, len(head))
    num = cells[:, [head.index(k) for k in ("lamL", "betaL_EA", "w", "ratio", "e_s", "e_c")]].astype(float)
    load = cells[:, head.index("load")]
    out = {}
    for name in sorted(set(load.tolist())):
        sel = num[load == name]
        axes, index = zip(*(np.unique(sel[:, k], return_inverse=True) for k in range(4)))
        e = np.full(tuple(len(ax) for ax in axes), np.nan)
        e[index] = {"max": np.maximum(sel[:, 4], sel[:, 5]), "s": sel[:, 4], "c": sel[:, 5]}[component]
        if np.isnan(e).any() or len(sel) != e.size:
            raise ValueError(f"{path}: the map of load {name!r} is not a full grid")
        out[name] = (*(tuple(ax.tolist()) for ax in axes), e)
    return out


def _bracket(nodes: list[float], x: float) -> tuple[int, float]:
    """``(i, t)``: x between nodes[i] and nodes[i + 1] at fraction t in [0, 1] (clamped to the ends)."""
    i = min(max(bisect.bisect_right(nodes, x) - 1, 0), len(nodes) - 2)
    t = (x - nodes[i]) / (nodes[i + 1] - nodes[i])
    return i, min(max(t, 0.0), 1.0)


def _mix(u: float, v: float, t: float) -> float:
    """(1 - t) u + t v, or the one of u, v that is not NaN (a refused map point), NaN if neither is."""
    if u != u:
        return v
    if v != v:
        return u
    return (1.0 - t) * u + t * v


class _Slice:
    """One element's map: log10 e on the (log w, log ratio) grid (NaN where refused), interpolated
    in the bar's log(lambda L), log(beta L/EA), and what the check needs of the element, computed once."""

    def __init__(self, element: Any, component: str = "max") -> None:
        bar = element.bar
        lam_L, beta_L, w, ratio, e = _read_map(MAP_FILE, component)[element._validity_load]
        log_e = np.full(e.shape, np.nan)
        np.log10(np.maximum(e, _ERROR_FLOOR), out=log_e, where=np.isfinite(e))
        i, t = _bracket([math.log(v) for v in lam_L], math.log(max(bar.lam * bar.L, lam_L[0])))
        j, u = _bracket([math.log(v) for v in beta_L], math.log(max(bar.beta * bar.L / bar.EA, beta_L[0])))
        num = den = 0.0
        for weight, corner in (((1.0 - t) * (1.0 - u), log_e[i, j]), (t * (1.0 - u), log_e[i + 1, j]),
                               ((1.0 - t) * u, log_e[i, j + 1]), (t * u, log_e[i + 1, j + 1])):
            if weight > 0.0:  # refused corners carry no error value: the others' weights are renormalised
                num = num + weight * np.nan_to_num(corner)
                den = den + weight * np.isfinite(corner)
        table = np.where(den > 0.0, num / np.where(den > 0.0, den, 1.0), np.nan)
        self.log_w = [math.log(v) for v in w]
        self.log_r = [math.log(v) for v in ratio]
        self.rows = table.tolist()  # [w][ratio] of log10 e, NaN where refused
        self.omega_c = bar.omega_c
        self.a_static = element.slip_amplitude(0.0)
        # no friction (mu N = 0): a linear spring the single-mode solution gives exactly, at any omega
        self.omega_1 = (math.inf if self.a_static == 0.0 else
                        self.omega_c * self._first_crossing(math.log10(TOLERANCE)))

    def error(self, w: float, r: float, r_onset: float) -> float:
        """The map's error at omega/omega_c = w > 0 and a/a_min(0) = r > r_onset, the slip onset's
        ratio a_min(omega)/a_min(0) (the ratio nodes at or below it take the first slipping node's
        value); inf where the map's neighbours are all refused."""
        j, u = _bracket(self.log_r, math.log(r))
        j0 = bisect.bisect_right(self.log_r, math.log(r_onset)) if r_onset > 0.0 else 0
        j0 = min(j0, len(self.log_r) - 1)
        lo, hi = max(j, j0), max(j + 1, j0)
        lw = math.log(w)
        if lw < self.log_w[0]:  # below the map: e falls like w^2 (exact at w = 0)
            row = self.rows[0]
            v = _mix(row[lo], row[hi], u) + 2.0 / math.log(10.0) * (lw - self.log_w[0])
        else:
            i, t = _bracket(self.log_w, lw)
            r0, r1 = self.rows[i], self.rows[i + 1]
            v = _mix(_mix(r0[lo], r1[lo], t), _mix(r0[hi], r1[hi], t), u)
        return 10.0 ** v if v == v else math.inf

    def _first_crossing(self, level: float) -> float:
        """The smallest w at which some ratio node's log10 e reaches ``level`` (a refused node: at
        once; inf if none does)."""
        best = math.inf
        for j in range(len(self.log_r)):
            col = [row[j] if row[j] == row[j] else math.inf for row in self.rows]
            if col[0] >= level:
                best = min(best, math.exp(self.log_w[0] + (level - col[0]) * math.log(10.0) / 2.0))
                continue
            for i in range(1, len(col)):
                if col[i] >= level:
                    t = (level - col[i - 1]) / (col[i] - col[i - 1])
                    best = min(best, math.exp(self.log_w[i - 1] + t * (self.log_w[i] - self.log_w[i - 1])))
                    break
        return best


def _slice(element: Any, component: str = "max") -> _Slice:
    """The element's ``_Slice`` of ``component`` ("max", "s", "c"), built on first use and kept on it."""
    key = "_single_mode_map" if component == "max" else f"_single_mode_map_{component}"
    s = element.__dict__.get(key)
    if s is None:
        s = element.__dict__[key] = _Slice(element, component)
    return s


def single_mode_error(element: Any, a: ArrayLike, omega: ArrayLike, component: str = "max") -> np.ndarray:
    """The validity map's error e of the single-mode ``element`` at (a, omega): 0 where the bar is
    stuck (a <= a_min(omega)), else the map interpolated (module docstring).

    Parameters
    ----------
    element : TwoRegionMicroslip or ThreeRegionMicroslip
        The single-mode element.
    a, omega : array_like
        Amplitudes (m) and frequencies (rad/s), >= 0; they broadcast.
    component : {"max", "s", "c"}, optional
        The error of F_s ("s"), of F_c ("c") or their larger ("max", the default), each relative to
        max(|F|, 0.01 k* a) of its own component.

    Returns
    -------
    ndarray
        The error as a fraction (0.01 is 1 %), of the broadcast shape.

    Examples
    --------
    >>> from contact_models import Bar, TwoRegionMicroslip, UniformLoad
    >>> from contact_models.model_range import single_mode_error
    >>> bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    >>> two = TwoRegionMicroslip(bar, UniformLoad(N=100.0))
    >>> float(single_mode_error(two, 0.5 * 7.5e-7, 0.3 * bar.omega_c))  # stuck: exact
    0.0
    >>> bool(single_mode_error(two, 2 * 7.5e-7, 0.05 * bar.omega_c) < 0.01)  # inside the range
    True
    """
    if component not in ("max", "s", "c"):
        raise ValueError(f'component must be "max", "s" or "c", got component={component!r}')
    a_b, w_b = np.broadcast_arrays(np.asarray(a, dtype=float), np.asarray(omega, dtype=float))
    out = np.zeros(a_b.shape)
    s = _slice(element, component)
    if s.a_static == 0.0:  # no friction (mu N = 0): the bar slides freely, a linear spring; exact
        return out
    for w in np.unique(w_b):
        a_lin = element.linear_amplitude(float(w))
        sel = (w_b == w) & (a_b > a_lin)
        if w > 0.0 and np.any(sel):
            w_n, r_on = float(w) / s.omega_c, a_lin / s.a_static
            out[sel] = [s.error(w_n, r, r_on) for r in (a_b[sel] / s.a_static).tolist()]
    return out


def single_mode_frequency_limit(element: Any) -> float:
    """omega_1 (rad/s): the lowest frequency at which the map's error of ``element`` exceeds
    ``TOLERANCE`` at some amplitude (between map frequencies: where its interpolation crosses).

    Below omega_1 the single-mode element is within 1 % at every amplitude; above it, at some.

    Examples
    --------
    >>> from contact_models import Bar, TwoRegionMicroslip, UniformLoad
    >>> from contact_models.model_range import single_mode_frequency_limit
    >>> bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    >>> w1 = single_mode_frequency_limit(TwoRegionMicroslip(bar, UniformLoad(N=100.0))) / bar.omega_c
    >>> bool(0.1 < w1 < 0.2)
    True
    """
    return _slice(element).omega_1


def early_snap(element: Any, omega: float) -> float:
    """The stuck length L1/L left where the element's loading curve folds and it snaps onto
    gross slip (0 when it reaches L1 = 0 without a fold)."""
    try:
        piece = element._path(float(omega))[1][-1]
    except (AttributeError, IndexError, TypeError):
        return 0.0
    if getattr(piece, "t1", 1.0) >= 1.0:
        return 0.0
    return float(np.real(piece.boundaries(1.0)[0])) / element.bar.L


def _snap(element: Any, w: float, a_max: float) -> float:
    """The stuck length L1/L left at an early gross-slip snap that amplitudes up to ``a_max`` reach
    at ``w``, else 0; builds no path the amplitudes did not need."""
    lazy = getattr(element, "_lazy_path", None)
    if lazy is not None and lazy(w)._full is None:
        return 0.0  # the amplitudes stayed on the microslip pieces: gross slip, and its snap, not reached
    snap = early_snap(element, w)
    return snap if snap > SNAP_TOLERANCE and a_max > element.gross_slip_amplitude(w) else 0.0


def check_single_mode(element: Any, a: ArrayLike, omega: ArrayLike, *, stacklevel: int = 3) -> None:
    """Warn (``ModelRangeWarning``, once per call) if the single-mode ``element`` is evaluated where
    the validity map's error exceeds ``TOLERANCE`` or where it takes an early gross-slip snap.

    Cost: a few microseconds for a scalar call (the element's slice of the map is computed once;
    the slip onset comes from the element's cache, the snap from its cached loading path).
    """
    s = _slice(element)
    if s.a_static == 0.0:  # no friction (mu N = 0): the bar slides freely, a linear spring; exact
        return
    if np.ndim(a) == 0 and np.ndim(omega) == 0:  # the common scalar call: no arrays
        items = [(float(omega), float(a), None)]
    else:
        a_b, w_b = np.broadcast_arrays(np.asarray(a, dtype=float), np.asarray(omega, dtype=float))
        items = [(float(w), float(amps.max()), amps) for w in np.unique(w_b) for amps in (a_b[w_b == w],)]
    worst, snap_w, snap = None, None, 0.0
    for w, a_max, amps in items:
        a_lin = element._linear_amplitude(w)
        if a_max <= a_lin or w <= 0.0:
            continue  # stuck at every amplitude asked, or quasi-static: exact (and no path is built)
        if w > s.omega_1:  # below omega_1 the map is within the tolerance at every amplitude
            w_n, r_on = w / s.omega_c, a_lin / s.a_static
            slipping = [a_max] if amps is None else amps[amps > a_lin].tolist()
            e, a_e = max((s.error(w_n, a_i / s.a_static, r_on), a_i) for a_i in slipping)
            if e > TOLERANCE and (worst is None or e > worst[0]):
                worst = (e, w, a_e)
        if snap_w is None:
            snap = _snap(element, w, a_max)
            snap_w = w if snap > 0.0 else None
    parts = []
    if worst is not None:
        e, w, a_e = worst
        off = (f"F_s, F_c are off by about {e:.1%} there" if math.isfinite(e) else
               "the single-mode model breaks down at the map's neighbouring points")
        parts.append(f"at omega = {w:.6g} rad/s ({w / s.omega_c:.3g} omega_c) and a = {a_e:.4g} m "
                     f"({a_e / s.a_static:.3g} a_min) it is outside its single-mode range: {off} (validity map, "
                     f"docs/validation.md; within {TOLERANCE:.0%} at every amplitude up to "
                     f"{s.omega_1 / s.omega_c:.3g} omega_c)")
    if snap_w is not None:
        parts.append(f"at omega = {snap_w:.6g} rad/s its loading curve folds before gross slip and it snaps onto "
                     f"gross slip early, with {snap:.2f} L still stuck")
    if parts:
        warnings.warn(f"{type(element).__name__}: " + "; ".join(parts) + "; AllModeMicroslip resolves the phase "
                      "differences along the bar", ModelRangeWarning, stacklevel=stacklevel)
