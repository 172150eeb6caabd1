"""The four-parameter Iwan element (Segalman 2005): a continuum of Jenkins elements in parallel.

D. J. Segalman, "A four-parameter Iwan model for lap-type joints", J. Appl. Mech. 72 (2005)
752-760.  Not a model of the paper (Cigeroglu, Lu & Menq 2006), which cites Iwan-type models
among the microslip models of its introduction; it is the library's example of an element that
slips at every amplitude (``docs/extending.md`` builds it step by step).

Model
-----
Jenkins elements of unit stiffness, each a spring behind a slider that slips when the spring
stretches by ``phi``, are put in parallel with the density

    rho(phi) = R phi**chi   for 0 < phi < phi_max,    plus   S delta(phi - phi_max),

so that the force is ``f = integral rho(phi) (u - x(phi)) dphi`` (``x(phi)`` the sliders).  The
four parameters are the joint's macroslip force ``slip_force`` F_S, its stiffness at small
amplitude ``stiffness`` K_T, the exponent ``chi`` > -1 (lap joints: -1 < chi <= 0; the
dissipation per cycle grows like a**(chi + 3) below macroslip) and ``beta`` >= 0, the ratio of
S to the continuous part's stiffness.  From ``K_T = R phi_max**(chi+1)/(chi+1) + S``,
``F_S = R phi_max**(chi+2)/(chi+2) + S phi_max`` and ``beta = S (chi+1)/(R phi_max**(chi+1))``,
with ``c = (chi+1)/(chi+2)``::

    phi_max = F_S (1 + beta) / (K_T (beta + c))
    R = F_S (chi + 1) / (phi_max**(chi+2) (beta + c))
    S = F_S beta / (phi_max (beta + c))

Virgin loading curve (elements with phi < u have slipped and carry phi, the others u)::

    F(u) = K_T u - R u**(chi+2) / ((chi+1)(chi+2))    for 0 <= u < phi_max,    F_S beyond,
    F'(u) = K_T - R u**(chi+1)/(chi+1)                 (S at phi_max-, 0 beyond).

Fourier coefficients
--------------------
Parallel Jenkins elements obey Masing's rules exactly, so the steady loop for ``x = a sin(theta)``
is the Masing loop of F, and (the Stieltjes form of ``docs/theory.md``), with ``m = min(a, phi_max)``::

    f_s = 8/(pi a) J_s,   J_s = integral_0^m sqrt(s (a - s)) F'(s) ds
    f_c = 4/(pi a) J_c,   J_c = integral_0^m (a - 2 s) F'(s) ds

In closed form, with the incomplete Beta function ``B(x; p, q) = integral_0^x t**(p-1) (1-t)**(q-1) dt``
(``scipy.special.betainc`` times ``beta``) and ``x = m/a``::

    J_s = K_T a**2 B(x; 3/2, 3/2) - R/(chi+1) a**(chi+3) B(x; chi+5/2, 3/2)
    J_c = K_T (a m - m**2) - R/(chi+1) (a m**(chi+2)/(chi+2) - 2 m**(chi+3)/(chi+3))

Below macroslip (a <= phi_max) ``J_c = R a**(chi+3)/((chi+2)(chi+3))``: the dissipation per cycle is
``pi a f_c = 4 R a**(chi+3)/((chi+2)(chi+3))`` (Segalman's power law).  The a-derivatives::

    df_s/da = -f_s/a + 8/(pi a) J_d,   J_d = K_T a/2 B(x; 3/2, 1/2) - R/(chi+1) a**(chi+2)/2 B(x; chi+5/2, 1/2)
    df_c/da = -f_c/a + 4/(pi a) (F(m) - a F'(a) [a < phi_max])

Contract (``contact_models.base``): ``slip_amplitude = 0`` (some element slips at any amplitude),
``linear_amplitude = 0`` (never linear), ``reference_amplitude = phi_max`` (macroslip), stuck
stiffness K_T at every frequency; the force law is rate independent.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .numerics.checks import derived, finite, nonnegative, nonnegative_array, positive
from .base import ContactElement, masing_loop


def _beta_inc(x: NDArray, p: float, q: float) -> NDArray:
    """Incomplete Beta function ``integral_0^x t**(p-1) (1-t)**(q-1) dt`` for x in [0, 1]."""
    from scipy.special import beta, betainc  # imported where used: keeps `import contact_models` light

    return beta(p, q) * betainc(p, q, x)


#: Below this ratio x = phi_max / a the incomplete Beta function is its series' first term, x**p / p (the
#: next is x times smaller): a huge amplitude's x**p underflows, and the scaled forms below divide by a power of x.
_SERIES_X = 1e-50


def _beta_scaled(x: NDArray, p: float, q: float, k: float) -> NDArray:
    """``_beta_inc(x, p, q) / x**k`` (k <= p) for x in (0, 1], without underflow or 0/0 where x is tiny (a huge
    amplitude past macroslip): there it is x**(p - k) / p to double precision."""
    small = x < _SERIES_X
    xs = np.where(small, 1.0, x)  # (no division by an underflowed power)
    return np.where(small, x ** (p - k) / p, _beta_inc(xs, p, q) / xs**k)


class Iwan(ContactElement):
    """Segalman's four-parameter Iwan element: parallel Jenkins elements with a power-law density.

    Parameters
    ----------
    slip_force : float
        F_S (N): the force at which every element slips (macroslip), > 0.
    stiffness : float
        K_T (N/m): the stiffness at vanishing amplitude, > 0.
    chi : float
        Exponent of the density of slip strengths, > -1; the dissipation per cycle below
        macroslip is proportional to ``a**(chi + 3)``.  Lap joints: -1 < chi <= 0.
    beta : float
        S relative to the continuous part's stiffness, >= 0 (0: no slider at phi_max; the
        loading curve then reaches F_S with zero slope).

    Attributes
    ----------
    phi_max : float
        Slip displacement of the strongest element (m): the macroslip amplitude.
    R, S : float
        The density's coefficient (N/m**(chi+2)) and the stiffness of the elements at phi_max (N/m).

    Raises
    ------
    ValueError
        A parameter outside its range, named with the value it got.

    Notes
    -----
    The module docstring gives the loading curve and the closed-form f_s, f_c and derivatives
    (incomplete Beta functions).  Frequency independent.

    References
    ----------
    D. J. Segalman, J. Appl. Mech. 72 (2005) 752-760.

    Examples
    --------
    >>> from contact_models import Iwan
    >>> el = Iwan(slip_force=1.0, stiffness=1.0e6, chi=-0.5, beta=0.1)
    >>> round(el.phi_max * 1e6, 6)      # macroslip amplitude, micrometres
    2.538462
    >>> a = 0.5 * el.phi_max
    >>> fs, fc = el.fourier(a)
    >>> bool(abs(fc - 4 * el.R * a**1.5 / (3.75 * math.pi)) < 1e-12 * el.stiffness * a)
    True
    """

    frequency_dependent = False
    has_time_law = True  #: Masing's rules with memory hold exactly: the multi-harmonic balance uses them

    def __init__(self, slip_force: float, stiffness: float, chi: float, beta: float) -> None:
        self.slip_force = positive("slip_force", slip_force)
        self.stiffness = positive("stiffness", stiffness)
        chi = finite("chi", chi)
        if chi <= -1.0:
            raise ValueError(f"chi must be > -1 (the density phi**chi must be integrable), got chi={chi!r}")
        self.chi = chi
        self.beta = nonnegative("beta", beta)
        if not math.isfinite(self.beta):
            raise ValueError(f"beta must be finite, got beta={beta!r}")
        c = (chi + 1.0) / (chi + 2.0)

        def constants():
            phi_max = self.slip_force * (1.0 + self.beta) / (self.stiffness * (self.beta + c))
            R = self.slip_force * (chi + 1.0) / (phi_max ** (chi + 2.0) * (self.beta + c))
            return {"phi_max": phi_max, "R": R, "S": self.slip_force * self.beta / (phi_max * (self.beta + c)),
                    "R phi_max**(chi+1)": R * phi_max ** (chi + 1.0)}

        params = {"slip_force": slip_force, "stiffness": stiffness, "chi": chi, "beta": beta}
        k = derived("Iwan", params, constants, positive_names=("phi_max", "R", "R phi_max**(chi+1)"))
        self.phi_max, self.R, self.S = k["phi_max"], k["R"], k["S"]

    def __repr__(self) -> str:
        return (f"Iwan(slip_force={self.slip_force!r}, stiffness={self.stiffness!r}, chi={self.chi!r}, "
                f"beta={self.beta!r})")

    # ------------------------------------------------------------ the loading curve
    def loading_curve(self, x: ArrayLike, omega: float = 0.0) -> NDArray[np.float64]:
        """Virgin loading force ``F(x)`` (N) for x >= 0: ``K_T x - R x**(chi+2)/((chi+1)(chi+2))``, F_S past phi_max."""
        x = nonnegative_array("x", x)  # x < 0: x**(chi+2) is NaN for a non-integer chi
        nonnegative("omega", omega)
        u = np.minimum(x, self.phi_max)
        p = self.chi + 2.0
        F = self.stiffness * u - self.R * u**p / ((p - 1.0) * p)
        return np.where(x >= self.phi_max, self.slip_force, F)

    def _loading_slope(self, x: NDArray, omega: float = 0.0) -> NDArray[np.float64]:
        """``dF/dx``: ``K_T - R x**(chi+1)/(chi+1)`` below phi_max, 0 from phi_max on."""
        x = np.asarray(x, dtype=float)
        u = np.minimum(x, self.phi_max)
        q = self.chi + 1.0
        return np.where(x >= self.phi_max, 0.0, self.stiffness - self.R * u**q / q)

    def gross_slip_amplitude(self, omega: float = 0.0) -> float:
        """``phi_max`` (m): from this amplitude on every element slips (macroslip)."""
        nonnegative("omega", omega)
        return self.phi_max

    # ------------------------------------------------------------ the contract
    def _stuck_stiffness(self, omega):
        return self.stiffness

    def _slip_amplitude(self, omega):
        return 0.0

    def _linear_amplitude(self, omega):
        return 0.0

    def _reference_amplitude(self, omega):
        return self.phi_max

    def _hysteresis(self, a, omega, n):
        return masing_loop(self.loading_curve, a, n)

    def _fourier_derivatives(self, a, omega, rtol):
        # f_s, f_c and their slopes as 8 J_s/(pi a), 4 J_c/(pi a) ... with the division by a done first, in powers
        # of m = min(a, phi_max) and x = m/a <= 1: nothing overflows at a huge amplitude (a**2 did from 1e154 m,
        # giving NaN) nor underflows at a tiny one (a**2 at 1e-300 m gave f_s = 0 for K_T a)
        a = np.asarray(a, dtype=float)
        K, R, chi = self.stiffness, self.R, self.chi
        pos = a > 0.0
        A = np.where(pos, a, 1.0)  # a = 0: the limits below, no division by zero
        m = np.minimum(A, self.phi_max)
        x = np.where(A <= self.phi_max, 1.0, m / A)
        q = R / (chi + 1.0)
        mp = m ** (chi + 1.0)
        fs = 8.0 / math.pi * m * (K * _beta_scaled(x, 1.5, 1.5, 1.0)
                                  - q * mp * _beta_scaled(x, chi + 2.5, 1.5, chi + 2.0))
        Jd_a = 0.5 * (K * _beta_inc(x, 1.5, 0.5) - q * mp * _beta_scaled(x, chi + 2.5, 0.5, chi + 1.0))  # J_d / a
        below = A <= self.phi_max
        # below macroslip K_T (a m - m^2) vanishes: J_c in the form without cancellation
        Jc_a = np.where(below, R * A ** (chi + 2.0) / ((chi + 2.0) * (chi + 3.0)),
                        K * m * (1.0 - x) - q * mp * m * (1.0 / (chi + 2.0) - 2.0 * x / (chi + 3.0)))  # J_c / a
        fc = 4.0 / math.pi * Jc_a
        dfs = -fs / A + 8.0 / math.pi * Jd_a
        # -f_c/a + 4 (F(m)/a - F'(a))/pi cancels: below macroslip to 4 R a^(chi+1)/((chi+3) pi) (it lost every digit
        # at a tiny a), from it on to 4 x^2 (K_T - 2 q m^(chi+1)/(chi+3))/pi (1e-8 of it at a = 1e8 phi_max): taken so
        dfc = 4.0 / math.pi * np.where(A < self.phi_max, R * mp / (chi + 3.0), x * x * (K - 2.0 * q * mp / (chi + 3.0)))
        # a = 0: f_s = f_c = 0, df_s/da = K_T, df_c/da = 0 (f_c ~ a**(chi+2), chi > -1)
        return (np.where(pos, fs, 0.0), np.where(pos, fc, 0.0), np.where(pos, dfs, K), np.where(pos, dfc, 0.0))


__all__ = ["Iwan"]
