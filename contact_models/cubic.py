"""A cubic spring ``f = k3 x^3``: the Duffing nonlinearity, for checks of multi-harmonic balance.

Not a contact model: a smooth, non-hysteretic, rate-independent element with closed forms for
everything.  For ``x = a sin(theta)``, ``sin^3 = (3 sin(theta) - sin(3 theta))/4`` gives

    f_s = 3 k3 a^3 / 4,    f_c = 0,

and for any periodic displacement ``f = k3 x^3`` sample by sample (no memory), Jacobian
``diag(3 k3 x^2)``.  ``k3 < 0`` is a softening spring.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from .numerics.checks import finite, finite_array, positive
from .base import ContactElement


class CubicSpring(ContactElement):
    """Cubic spring ``f = k3 x^3`` (``k3`` in N/m^3, finite, nonzero).

    Parameters
    ----------
    k3 : float
        Cubic stiffness (N/m^3); negative for a softening spring.
    amplitude_unit : float
        The element's ``reference_amplitude`` (m): it has no slip amplitude. Default 1.

    Examples
    --------
    >>> from contact_models import CubicSpring
    >>> [float(v) for v in CubicSpring(k3=4.0).fourier(0.5)]  # 3 k3 a^3 / 4
    [0.375, 0.0]
    """

    frequency_dependent = False
    has_time_law = True

    def __init__(self, k3: float, *, amplitude_unit: float = 1.0) -> None:
        self.k3 = finite("k3", k3)
        if self.k3 == 0.0:
            raise ValueError(f"k3 must be nonzero, got k3={k3!r}")
        self.amplitude_unit = positive("amplitude_unit", amplitude_unit)

    def __repr__(self) -> str:
        return f"CubicSpring(k3={self.k3!r})"

    def _periodic_force(self, x, omega):
        f, d, _, _ = self._periodic_tangent(x, omega)
        return f, np.diag(d)

    def _periodic_tangent(self, x, omega):
        return self.k3 * x**3, 3.0 * self.k3 * x * x, np.empty(0, dtype=np.intp), np.empty((x.size, 0))

    def _fourier_derivatives(self, a, omega, rtol):
        zero = np.zeros_like(a)
        return 0.75 * self.k3 * a**3, zero, 2.25 * self.k3 * a * a, zero.copy()

    def _stuck_stiffness(self, omega):
        return 0.0

    def _slip_amplitude(self, omega):
        return 0.0

    def _linear_amplitude(self, omega):
        return 0.0

    def _reference_amplitude(self, omega):
        return self.amplitude_unit

    def _hysteresis(self, a, omega, n):
        x = a * np.sin(np.linspace(-0.5 * np.pi, 1.5 * np.pi, n))
        return x, self.k3 * x**3

    def harmonic_force_exact(self, X: NDArray) -> NDArray:
        """Exact harmonic coefficients of ``k3 x^3`` (cubic of a trigonometric polynomial of
        degree H has degree 3H: sampled at 6H + 2 points it is exact), truncated to H."""
        X = finite_array("X", X)
        if X.ndim != 1 or X.size < 3 or X.size % 2 == 0:
            raise ValueError(f"X must be of shape ('2H+1',) with 2H+1 odd >= 3, got X with shape {X.shape}")
        H = (X.size - 1) // 2
        return self.harmonic_force_unchecked(X, 0.0, 6 * H + 2)[0]


__all__ = ["CubicSpring"]
