"""Where the single-mode elements hold, and the warning they give outside it (issue 13).

The single-mode dynamic elements (``TwoRegionMicroslip``, ``ThreeRegionMicroslip``) neglect the
phase differences along the bar.  Measured against the all-mode bar (``AllModeMicroslip``) over
a/a_min in [0.5, 100], omega/omega_c in [0.01, 0.95] and bars with lambda L and beta L/EA by
decades (the validity map, ``docs/validation.md``), their error in F_s, F_c,

    e = max(|dF_s| / max(|F_s|, 0.01), |dF_c| / max(F_c, 0.01))      (F in units of k* a),

is zero while the bar is stuck (a <= a_min(omega): both are exact) and otherwise grows like the
square of the frequency at first (faster near and above the cut-off).  The closed-form bound,
fitted to the map's points at 0.1 to 0.3 omega_c (the largest e / (omega/omega_c)^2 there), is

    e <= C (omega / omega_c)^2,
    C = ERROR_COEFFICIENT[kind] * (1 + (lambda L)^2) * (1 + BETA_WEIGHT / max(beta L/EA, BETA_FLOOR)),

so the elements are within ``TOLERANCE`` (1 %) for omega <= omega_1 = omega_c sqrt(TOLERANCE / C)
(DESIGN.md bar: 0.10 omega_c for the two-region element, 0.082 omega_c for the three-region
one).  Over the map no point with e > 1 % lies below omega_1 (no missed warning); the bound
depends on frequency only, so above omega_1 it also warns at some amplitudes where the error
happens to be smaller (docs/validation.md counts them).  Measured for lambda L in [0.3, 10],
beta L/EA in [0.1, 10], the uniform and the ratio-12 concave loads; beta L/EA below 0.1 is
taken as 0.1.

The check costs about 0.1 ms per call (a tenth of a scalar ``fourier`` call; the element's
a_min(omega) and snap come from its cached loading path) and is not in the solver's unchecked
path.  Separately, an element whose loading curve folds before gross slip snaps onto the
sliding line early (stiff shear layers, lambda L of 3 and more, with inertia); that snap
is flagged when it happens with more than ``SNAP_TOLERANCE`` L of the bar still stuck.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["ModelRangeWarning", "TOLERANCE", "ERROR_COEFFICIENT", "BETA_WEIGHT", "BETA_FLOOR", "SNAP_TOLERANCE",
           "single_mode_error_bound", "single_mode_frequency_limit", "early_snap", "check_single_mode"]

#: The error (relative, with a floor of 0.01 k* a) beyond which the single-mode elements warn.
TOLERANCE = 0.01
#: C of the bound e <= C (omega/omega_c)^2 at lambda L -> 0 and stiff beta, per element (validity map).
ERROR_COEFFICIENT = {"two-region": 0.42, "three-region": 0.62}
#: Weight of the soft-beta growth of C: factor 1 + BETA_WEIGHT / max(beta L/EA, BETA_FLOOR).
BETA_WEIGHT = 0.2
#: beta L/EA below this (outside the map) is taken at it.
BETA_FLOOR = 0.1
#: An early gross-slip snap is flagged when the stuck length left at the snap exceeds this fraction of L.
SNAP_TOLERANCE = 0.01


class ModelRangeWarning(UserWarning):
    """A contact element is evaluated outside the range where its model is accurate.

    Raised (as a warning) by the single-mode elements ``TwoRegionMicroslip`` and
    ``ThreeRegionMicroslip`` where the validity map (``docs/validation.md``) says their F_s or
    F_c error against the all-mode bar may exceed 1 %, and where they snap onto gross slip early.
    Filter it like any warning, e.g. ``warnings.simplefilter("ignore", ModelRangeWarning)``, or
    turn it into an error with ``"error"``; use ``AllModeMicroslip`` there.

    It carries no attributes of its own: the message names the element class, the frequency
    (rad/s) and the error bound there, or the early snap onto gross slip.

    Examples
    --------
    >>> import warnings
    >>> issubclass(ModelRangeWarning, UserWarning)
    True
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("error", ModelRangeWarning)
    ...     try:
    ...         warnings.warn("outside the validity map", ModelRangeWarning)
    ...     except ModelRangeWarning as exc:
    ...         print(exc)
    outside the validity map
    """


def _kind(element: Any) -> str:
    return "three-region" if type(element).__name__ == "ThreeRegionMicroslip" else "two-region"


def _coefficient(element: Any) -> float:
    bar = element.bar
    lam_L = bar.lam * bar.L
    b = max(bar.beta * bar.L / bar.EA, BETA_FLOOR)
    return ERROR_COEFFICIENT[_kind(element)] * (1.0 + lam_L**2) * (1.0 + BETA_WEIGHT / b)


def single_mode_error_bound(element: Any, a: ArrayLike, omega: ArrayLike) -> np.ndarray:
    """The map's bound on the single-mode element's F_s, F_c error at (a, omega): 0 where the
    bar is stuck (a <= a_min(omega)), else C (omega/omega_c)^2 (module docstring).

    Examples
    --------
    >>> from contact_models import Bar, TwoRegionMicroslip, UniformLoad
    >>> from contact_models.model_range import single_mode_error_bound
    >>> bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    >>> two = TwoRegionMicroslip(bar, UniformLoad(N=100.0))
    >>> float(single_mode_error_bound(two, 0.5e-6, 0.3 * bar.omega_c))  # stuck: exact
    0.0
    """
    a_b, w_b = np.broadcast_arrays(np.asarray(a, dtype=float), np.asarray(omega, dtype=float))
    out = np.zeros(a_b.shape)
    C = _coefficient(element)
    wc = element.bar.omega_c
    for w in np.unique(w_b):
        sel = w_b == w
        a_min = element.linear_amplitude(float(w))  # the slip onset, without building the loading path
        out[sel] = np.where(a_b[sel] > a_min, C * (float(w) / wc) ** 2, 0.0)
    return out


def single_mode_frequency_limit(element: Any, tolerance: float = TOLERANCE) -> float:
    """omega_1 (rad/s): up to it the single-mode element's error stays within ``tolerance``.

    omega_1 = omega_c sqrt(tolerance / C), C of the module docstring.

    Examples
    --------
    >>> from contact_models import Bar, TwoRegionMicroslip, UniformLoad
    >>> from contact_models.model_range import single_mode_frequency_limit
    >>> bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    >>> round(single_mode_frequency_limit(TwoRegionMicroslip(bar, UniformLoad(N=100.0))) / bar.omega_c, 4)
    0.0996
    """
    return element.bar.omega_c * math.sqrt(tolerance / _coefficient(element))


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


def _range(element: Any) -> tuple[float, float, float]:
    """``(C, omega_c, omega_1)`` of the element, computed once and kept on it (the check runs at
    every public ``fourier`` call, so it must cost microseconds: ``Bar.omega_c`` is a root solve)."""
    cached = element.__dict__.get("_single_mode_range")
    if cached is None:
        C, wc = _coefficient(element), element.bar.omega_c
        cached = (C, wc, wc * math.sqrt(TOLERANCE / C))
        element.__dict__["_single_mode_range"] = cached
    return cached


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
    its error bound exceeds ``TOLERANCE`` or where it takes an early gross-slip snap.

    Cost: a few microseconds for a scalar call (C and omega_1 are computed once per element; the
    slip onset comes from the element's cache, the snap from its cached loading path).
    """
    C, wc, w1 = _range(element)
    if np.ndim(a) == 0 and np.ndim(omega) == 0:  # the common scalar call: no arrays
        pairs = [(float(omega), float(a))]
    else:
        a_b, w_b = np.broadcast_arrays(np.asarray(a, dtype=float), np.asarray(omega, dtype=float))
        pairs = [(float(w), float(np.max(a_b[w_b == w]))) for w in np.unique(w_b)]
    worst_w, snap_w, snap = None, None, 0.0
    for w, a_max in pairs:
        if a_max <= element._linear_amplitude(w):
            continue  # stuck at every amplitude asked: exact (and no path is built)
        if w > w1 and (worst_w is None or w > worst_w):
            worst_w = w
        if snap_w is None:
            snap = _snap(element, w, a_max)
            snap_w = w if snap > 0.0 else None
    parts = []
    if worst_w is not None:
        worst = C * (worst_w / wc) ** 2
        parts.append(f"at omega = {worst_w:.6g} rad/s ({worst_w / wc:.3g} omega_c) it is outside its single-mode "
                     f"range: F_s, F_c may be off by up to {worst:.1%} (validity map, docs/validation.md; within "
                     f"{TOLERANCE:.0%} up to {w1 / wc:.3g} omega_c)")
    if snap_w is not None:
        parts.append(f"at omega = {snap_w:.6g} rad/s its loading curve folds before gross slip and it snaps onto "
                     f"gross slip early, with {snap:.2f} L still stuck")
    if parts:
        warnings.warn(f"{type(element).__name__}: " + "; ".join(parts) + "; AllModeMicroslip resolves the phase "
                      "differences along the bar", ModelRangeWarning, stacklevel=stacklevel)
