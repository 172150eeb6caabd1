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


__all__ = ["stiffness_terms"]
