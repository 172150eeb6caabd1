"""Input checks shared by ``hbm``: the library's one set (each failure a ValueError naming the
parameter and its value), re-exported so ``hbm`` modules import them from one place."""

import math
import warnings
from typing import Any

import numpy as np

from contact_models.numerics.checks import count, finite, flag, nonnegative, number_array, positive, relative, shown

number = finite

#: The smallest relative tolerance (``tol``, ``rtol``) the command line and scenes take: below it
#: double precision cannot meet the balance's Newton tolerance and no point converges.
MIN_RELATIVE_TOL = 1e-10


class InputError(ValueError):
    """Bad input, refused before anything is computed (the command line's exit code 2); a
    ``ValueError``.  ``hbm.scenes.SceneError`` is one."""


def relative_tolerance(name: str, value: object, upper: float) -> float:
    """``value`` as a float in (0, ``upper``): a relative tolerance, named in the ValueError."""
    v = positive(name, value)
    if v >= upper:
        raise ValueError(f"{name} must be < {upper:g}, got {name}={value!r}")
    return v


def nonzero_force(force: object) -> None:
    """Refuse an all-zero ``force`` (a structure's load vector): nothing excites the structure and the response
    is zero, whether or not a ``response_dof`` is given (the balance; a scene's ``--check``)."""
    if not np.any(force):
        raise ValueError(f"force must not be all zero (nothing excites the structure), got "
                         f"force={np.asarray(force, dtype=float).tolist()!r}")


#: The narrowest ``omega_range`` taken, relative to its upper end: double precision resolves omega to 2.2e-16 of
#: it, and a range a few roundings wide is no range to step along (at 5 roundings the trace stopped at once, its
#: corrector "moved 9.94e+11 steps from the predictor").
MIN_RELATIVE_WIDTH = 1e-12


def omega_range_pair(omega_range: object) -> tuple[float, float]:
    """``(w0, w1)`` from ``omega_range``: a pair of finite numbers >= 0 with w0 != w1, at least
    ``MIN_RELATIVE_WIDTH`` of the larger apart."""
    if omega_range is None:
        raise ValueError("omega_range must be given as (w0, w1), got omega_range=None")
    if isinstance(omega_range, (set, frozenset, dict)):  # no order: which end is w0 would be the hash's choice
        raise ValueError(f"omega_range must be a pair (w0, w1) in order (a tuple or a list), got "
                         f"omega_range={omega_range!r}")
    try:
        w0, w1 = omega_range  # type: ignore[misc]
    except (TypeError, ValueError):
        raise ValueError(f"omega_range must be a pair (w0, w1), got omega_range={omega_range!r}") from None
    w0 = nonnegative("omega_range[0]", w0)
    w1 = nonnegative("omega_range[1]", w1)
    if w0 == w1:
        raise ValueError(f"omega_range must have w0 != w1, got omega_range={omega_range!r}")
    if abs(w1 - w0) < MIN_RELATIVE_WIDTH * max(w0, w1):
        raise ValueError(f"omega_range must be at least {MIN_RELATIVE_WIDTH:g} of its upper end wide (double precision "
                         f"resolves omega to 2.2e-16 of it), got omega_range={omega_range!r}, "
                         f"{abs(w1 - w0) / max(w0, w1):.3g} of it")
    return w0, w1


#: The largest (H omega)^2 max|M| (and H omega max|C|) taken, N/m: a dynamic stiffness, and sums of such terms,
#: stay within double precision (above it a balance's residual overflowed to NaN: "SVD did not converge").
MAX_DYNAMIC_STIFFNESS = 1e300


def within_precision(name: str, value: object, omega: float, H: int, M: Any, C: Any) -> None:
    """Refuse, naming ``name=value``, a top frequency ``omega`` (rad/s) whose harmonic H makes the inertia
    (H omega)^2 max|M| or the damping H omega max|C| of a structure (dense or sparse M, C) leave double precision,
    stating the highest frequency taken."""
    m, c = (float(abs(A).max()) if A.shape[0] else 0.0 for A in (M, C))
    h = float(H) * omega
    with np.errstate(over="ignore"):
        if h * h * m <= MAX_DYNAMIC_STIFFNESS and h * c <= MAX_DYNAMIC_STIFFNESS:
            return
    top = min(math.sqrt(MAX_DYNAMIC_STIFFNESS / m) if m > 0.0 else math.inf,
              MAX_DYNAMIC_STIFFNESS / c if c > 0.0 else math.inf) / H
    raise ValueError(f"{name}={value!r} reaches too high for the structure: at harmonic {H} of omega={omega!r} rad/s "
                     f"its (H omega)^2 M or H omega C leaves double precision (above {MAX_DYNAMIC_STIFFNESS:.0e} N/m); "
                     f"{name} must stay below {top:.3g} rad/s at {H} harmonics")


#: The Newton tolerance of the modes' continuations (``nonlinear_modes``, ``damper_optimum``) by default.
NEWTON_TOL = 1e-10


def newton_tolerance(function: str, newton_tol: Any, tol: Any) -> Any:
    """``newton_tol``, or ``tol`` where only that earlier name is given (with a ``DeprecationWarning``: in
    ``frequency_response`` ``tol`` is the answer's target error, which ``function`` does not take); both
    given is a ValueError naming them."""
    if tol is None:
        return newton_tol
    if newton_tol != NEWTON_TOL:
        raise ValueError(f"give newton_tol (the Newton tolerance) alone, got newton_tol={newton_tol!r} and its "
                         f"earlier name tol={tol!r}")
    warnings.warn(f"{function}(tol=...) is deprecated: it is the Newton tolerance, now newton_tol= "
                  "(frequency_response's tol is the answer's target error, which this function does not take)",
                  DeprecationWarning, stacklevel=3)
    return tol


__all__ = ["count", "finite", "flag", "nonnegative", "nonzero_force", "number", "number_array", "positive", "relative",
           "shown", "omega_range_pair", "MIN_RELATIVE_WIDTH", "InputError", "relative_tolerance", "MIN_RELATIVE_TOL",
           "NEWTON_TOL",
           "newton_tolerance", "within_precision", "MAX_DYNAMIC_STIFFNESS"]
