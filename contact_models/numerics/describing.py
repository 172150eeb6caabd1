"""The describing function as a stiffness: ``p = f_s/a``, ``q = f_c/a`` and their a-derivatives.

An element answers ``f_s, f_c`` (N) and ``df_s/da, df_c/da`` for ``x = a sin(theta)``; the
first-harmonic balance uses them as the complex stiffness ``p + i q`` (N/m) acting on the
DOF's coefficients (``docs/hbm.md``): ``F_c = p x_c + q x_s``, ``F_s = p x_s - q x_c``, with
``dp/da = (f_s' - p)/a`` and ``dq/da = (f_c' - q)/a``.  The element side (``harmonic_force`` at
H = 1) and the balance (``hbm.balance``) both take them from here.
"""

from __future__ import annotations

from typing import Callable

import numpy as np


def stiffness_terms(derivatives: Callable, a: float, omega: float, rtol: float) -> tuple[float, float, float, float]:
    """``(p, q, dp/da, dq/da)`` at amplitude ``a > 0`` from an element's ``fourier_derivatives_unchecked``.

    Examples
    --------
    >>> from contact_models import Macroslip
    >>> jen = Macroslip(stiffness=1.0, slip_force=0.5)
    >>> [round(v, 4) for v in stiffness_terms(jen.fourier_derivatives_unchecked, 1.0, 1.0, 1e-6)]
    [0.5, 0.3183, -0.6366, 0.0]
    """
    fs, fc, dfs, dfc = derivatives(np.array([a]), np.array([omega]), rtol)
    fs, fc, dfs, dfc = float(fs[0]), float(fc[0]), float(dfs[0]), float(dfc[0])
    p, q = fs / a, fc / a
    return p, q, (dfs - p) / a, (dfc - q) / a


def first_harmonic(pq: Callable, X: np.ndarray, omega: float, rtol: float, k_inf: float,
                   frequency_dependent: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """An element's harmonic force at H = 1 from its describing function: ``(F, dF/dX, dF/domega)``
    for ``X = [X0, Xc, Xs]``.

    ``pq(a, omega, rtol)`` gives ``(p, q, dp/da, dq/da)``; the static term is ``K_inf X0`` (a Masing
    element's slope past full slip); the omega-derivative of a frequency-dependent element is a
    forward difference of relative step sqrt(rtol).
    """
    X0, xc, xs = (float(v) for v in X)
    F = np.empty(3)
    J = np.zeros((3, 3))
    F[0], J[0, 0] = k_inf * X0, k_inf
    a = float(np.hypot(xc, xs))
    p, q, dp, dq = pq(a, omega, rtol)
    F[1], F[2] = p * xc + q * xs, p * xs - q * xc
    gc, gs = (xc / a, xs / a) if a > 0.0 else (0.0, 0.0)
    u, v = dp * xc + dq * xs, dp * xs - dq * xc
    J[1, 1:] = p + u * gc, q + u * gs
    J[2, 1:] = -q + v * gc, p + v * gs
    Fw = np.zeros(3)
    if frequency_dependent:
        h = np.sqrt(rtol) * max(omega, 1e-3)
        ph, qh, _, _ = pq(a, omega + h, rtol)
        Fw[1], Fw[2] = ((ph - p) * xc + (qh - q) * xs) / h, ((ph - p) * xs - (qh - q) * xc) / h
    return F, J, Fw


__all__ = ["stiffness_terms", "first_harmonic"]
