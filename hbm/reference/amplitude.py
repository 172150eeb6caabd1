"""The blade's amplitude at one frequency with the all-mode bar: the reference of the all-mode curve.

The blade (one DOF, mass m, stiffness k, damping c, force F cos(omega t)) at H = 1 with the damper's
first harmonic: for x = a sin(theta) the damper force is f_s sin(theta) + f_c cos(theta) + (higher
harmonics), so the balance of the sine and cosine parts gives the amplitude equation

    g(a) = P^2 + Q^2 - F^2 = 0,    P = (k - m omega^2) a + f_s(a, omega),   Q = c omega a + f_c(a, omega),

solved by Newton's method with dg/da = 2 P (k - m omega^2 + df_s/da) + 2 Q (c omega + df_c/da), the
derivatives exact (the nested balance's Jacobian, ``AllModeMicroslip.solve``), steps limited to
``MAX_STEP`` of a, to ``AMPLITUDE_RTOL``.  The sampled bar's f(a) is piecewise smooth, with a kink
wherever one more sample of a node starts to slip; on fine rungs (128 cells, H = 31) the kinks are so
dense that the local derivative is not the slope of g over a Newton step, so from the second iterate
on, where the secant through the last two iterates differs from the local dg/da by more than 25 % (and
has its sign), the secant's slope is taken; a bracketed root is closed by bisection.

No continuation, no estimate and no choice of rung: one fixed rung of the bar at one frequency, the
check the continuation's all-mode curve is measured against (``docs/validation.md``).
"""

from __future__ import annotations

import math
from typing import Any

__all__ = ["amplitude_at", "MAX_STEP", "AMPLITUDE_RTOL"]

AllModeMicroslip = Any  # contact_models.AllModeMicroslip on one rung

#: Newton steps on the amplitude are limited to this fraction of it; it is converged to AMPLITUDE_RTOL.
MAX_STEP = 0.02
AMPLITUDE_RTOL = 1e-8


def amplitude_at(blade: Any, element: AllModeMicroslip, omega: float, a0: float, max_iter: int = 60) -> float:
    """The blade's amplitude at one frequency with the damper at H = 1 (the amplitude equation).

    Parameters
    ----------
    blade : hbm.Blade
        The one-DOF blade (``mass``, ``stiffness``, ``damping``, ``force``).
    element : AllModeMicroslip
        The damper on one rung (``cells`` and ``harmonics`` given); anything with its ``solve(a,
        omega)`` returning ``success``, ``f_s``, ``f_c`` and ``dF_dX``.
    omega : float
        Frequency (rad/s).
    a0 : float
        Start amplitude (m), > 0.
    max_iter : int
        Newton iterations at most.

    Returns
    -------
    float
        The amplitude (m) solving g(a) = 0 (the module docstring), converged to ``AMPLITUDE_RTOL``
        (Newton's method, with the secant's slope where the local derivative misses the bar's kinks,
        safeguarded by bisection once a sign change of g is bracketed: the bar's f(a) has kinks where
        one more cell starts to slip, where plain Newton can cycle).

    Raises
    ------
    FloatingPointError
        Where the bar's balance or this iteration does not converge (numerical trouble, not bad input).
    """
    k_dyn = blade.stiffness - blade.mass * omega * omega
    cw = blade.damping * omega
    a, lo, hi = a0, None, None  # lo: g < 0 (below the root), hi: g > 0
    last = None  # (a, g) of the previous iterate: the secant's slope
    for _ in range(max_iter):
        sol = element.solve(a, omega)
        if not sol.success:
            raise FloatingPointError(f"the all-mode bar did not converge at omega = {omega:.6g} rad/s, a = {a:.4g} m")
        P = k_dyn * a + sol.f_s
        Q = cw * a + sol.f_c
        g = P * P + Q * Q - blade.force ** 2
        if g < 0.0:
            lo = a if lo is None else max(lo, a)
        else:
            hi = a if hi is None else min(hi, a)
        dg = 2.0 * P * (k_dyn + sol.dF_dX[2, 2]) + 2.0 * Q * (cw + sol.dF_dX[1, 2])
        if last is not None and last[0] != a:  # the secant: the local slope misses the kinks (docstring)
            secant = (g - last[1]) / (a - last[0])
            dg = secant if secant * dg > 0.0 and not 0.8 < secant / dg < 1.25 else dg
        last = (a, g)
        step = -g / dg if dg != 0.0 else math.nan
        step = max(-MAX_STEP * a, min(MAX_STEP * a, step)) if math.isfinite(step) else MAX_STEP * a
        new = a + step
        if lo is not None and hi is not None:
            if not min(lo, hi) < new < max(lo, hi):
                new = 0.5 * (lo + hi)
            if abs(hi - lo) <= AMPLITUDE_RTOL * a:
                return 0.5 * (lo + hi)
        if abs(new - a) <= AMPLITUDE_RTOL * a:
            return new
        a = new
    raise FloatingPointError(f"the amplitude equation did not converge at omega = {omega:.6g} rad/s in {max_iter} "
                             "iterations")
