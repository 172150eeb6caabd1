"""The damper bar of the paper (Fig. 1) and its fully stuck solution (Section 2.1).

A bar 0 <= x <= L of axial stiffness EA and mass rho A per length, a spring beta to
ground at x = 0 (strain hardening), lying on a shear layer of stiffness k per length
whose Coulomb limit is mu q(x).  The excited end x = L is driven harmonically.

Everything here is built from one segment solution.  On a segment of length ell
where u'' = s2 u (s2 = gamma^2 in a stuck region, Eq. 12; s2 = -alpha^2 in a slipping
one), the state propagates with

    C(ell) = cosh(sqrt(s2) ell),      Sn(ell) = sinh(sqrt(s2) ell) / sqrt(s2),

both entire in s2 (cos and sin(g ell)/g when s2 = -g^2 < 0, 1 and ell at s2 = 0), so no
case of gamma -> 0, imaginary gamma or alpha -> 0 divides by zero.  For s2 > 0 the pair is
carried scaled by 1/cosh, so large gamma L cannot overflow.  Lengths may be complex: the
microslip elements differentiate along the loading curve by complex step.
"""

from __future__ import annotations

import functools
import math
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .numerics.roots import brentq
from .loads import bound_load
from .numerics.checks import count, finite, finite_array, nonnegative, number_array, positive
from .numerics.waves import check_phase, max_omega

if TYPE_CHECKING:
    from .loads import QuadraticLoad, UniformLoad


def segment_cs(s2: ArrayLike, ell: ArrayLike) -> tuple[NDArray[Any] | float, NDArray[Any] | float,
                                                      NDArray[Any] | float]:
    """Scaled ``(C, Sn, scale)`` with C = scale*cosh(sqrt(s2) ell), Sn = scale*sinh(..)/sqrt(s2).

    ``scale`` = 1/cosh(sqrt(s2) ell) for s2 > 0 (so C = 1), and 1 otherwise.
    """
    ell = np.asarray(ell)
    if np.ndim(s2) == 0:  # one frequency: compute only the branch that applies
        return _segment(float(s2), ell, True)
    s2 = np.asarray(s2, dtype=float)
    pos = s2 > 0.0
    g = np.sqrt(np.abs(s2))
    with np.errstate(all="ignore"):
        # s2 > 0: hyperbolic, scaled by sech (tanh never overflows).
        z = g * ell
        th = np.tanh(z)
        e = np.exp(-z)
        sech = 2.0 * e / (1.0 + e * e)
        sn_pos = np.where(g > 0.0, th / np.where(g > 0.0, g, 1.0), ell)
        # s2 <= 0: trigonometric; sin(g ell)/g = ell sinc(g ell / pi) is exact at g = 0.
        c_neg = np.cos(z)
        sn_neg = ell * np.sinc(z / np.pi)
    C = np.where(pos, 1.0 + 0.0 * ell, c_neg)
    Sn = np.where(pos, sn_pos, sn_neg)
    scale = np.where(pos, sech, 1.0 + 0.0 * ell)
    return C, Sn, scale


def _segment(s2: float, ell, scaled: bool, m: Any = np):
    """``segment_cs`` for one float ``s2``: only the branch that applies; ``scale`` (the sech
    factor, needed by the transmission only) is computed when ``scaled``, else 1.

    For s2 < 0, Sn = sin(g ell)/g (g = sqrt(-s2) > 0): no division by ell, so ell = 0 is fine.
    ``m`` gives tanh, exp, cos, sin: numpy, or ``cmath`` for one complex ell (no array overhead).
    """
    if s2 > 0.0:
        g = math.sqrt(s2)
        z = g * ell
        if not scaled:
            return 1.0, m.tanh(z) / g, 1.0
        e = m.exp(-z)
        return 1.0, m.tanh(z) / g, 2.0 * e / (1.0 + e * e)
    if s2 < 0.0:
        g = math.sqrt(-s2)
        z = g * ell
        return m.cos(z), m.sin(z) / g, 1.0
    return 1.0, ell, 1.0


def impedance_transmission(k_left: ArrayLike, s2: float, ell: ArrayLike, EA: float, *,
                           transmission: bool = True, m: Any = np) -> tuple[Any, Any]:
    """``(end_impedance(...), transmission(...))`` of one segment for one float ``s2``, sharing
    the segment functions and the denominator (the microslip elements' inner loop).

    ``transmission=False`` skips the transmission (returned as None) and its sech factor;
    ``m``: the functions' module (``numpy``, or ``cmath`` for one complex ``ell``).
    """
    C, Sn, scale = _segment(s2, ell, transmission, m)
    den = EA * C + k_left * Sn
    imp = EA * (EA * s2 * Sn + k_left * C) / den
    return imp, (EA * scale / den if transmission else None)


def end_impedance(k_left: ArrayLike, s2: ArrayLike, ell: ArrayLike, EA: float) -> NDArray[Any] | float:
    """Dynamic stiffness EA u'(ell)/u(ell) of a segment with EA u'(0) = k_left u(0).

    With k_left = beta and s2 = gamma^2 this is Eq. 14's beta'.
    """
    C, Sn, _ = segment_cs(s2, ell)
    return EA * (EA * s2 * Sn + k_left * C) / (EA * C + k_left * Sn)


def transmission(k_left: ArrayLike, s2: ArrayLike, ell: ArrayLike, EA: float) -> NDArray[Any] | float:
    """u(0)/u(ell) for the same segment: the share of the end motion reaching its start."""
    C, Sn, scale = segment_cs(s2, ell)
    return EA * scale / (EA * C + k_left * Sn)


class Bar:
    """The paper's damper bar (Fig. 1) and its fully stuck solution (Section 2.1).

    A bar 0 <= x <= L of axial stiffness EA and mass rho A per length on a shear layer of
    stiffness k per length, whose Coulomb limit is mu q(x); a spring beta ties x = 0 to ground
    (strain hardening); the excited end x = L is driven.  The contact elements
    (:class:`TwoRegionMicroslip`, :class:`ThreeRegionMicroslip`, :class:`NumericalMicroslip`)
    take a bar and a normal load.

    Parameters
    ----------
    E : float
        Young's modulus (Pa), > 0.
    rho : float
        Density (kg/m^3), > 0.
    A : float
        Cross-section (m^2), > 0.
    L : float
        Length of the bar and of the contact (m), > 0.
    k : float
        Shear-layer stiffness per unit length (N/m^2), > 0.
    beta : float
        Strain-hardening spring at x = 0 (N/m), >= 0.
    mu : float
        Friction coefficient, >= 0.

    Raises
    ------
    ValueError
        If a parameter is not finite or out of its range; the message names it and its value.

    See Also
    --------
    UniformLoad, QuadraticLoad : the normal load q(x) along the contact.

    Notes
    -----
    Eq. 12 defines ``lambda^2 = k/(EA)``, ``alpha^2 = rho omega^2/E`` and
    ``gamma^2 = lambda^2 - alpha^2`` (:meth:`alpha2`, :meth:`gamma2`).  :attr:`omega_c` is the
    first natural frequency of the stuck bar with x = L free (rad/s), :attr:`k_star` the static
    stuck stiffness ``k* = stuck_stiffness(0)`` (N/m); ``docs/theory.md`` derives both.

    References
    ----------
    .. [1] E. Cigeroglu, W. Lu, C.-H. Menq, "One-dimensional dynamic microslip friction model",
       J. Sound Vib. 292 (2006), Section 2.1, Eqs. 1-2 and 12.

    Examples
    --------
    The bar of the paper's figures: lambda L = 1 and beta = EA lambda, so k* = EA lambda.

    >>> from contact_models import Bar
    >>> bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    >>> bar.lam * bar.L, bar.k_star                     # -, N/m
    (1.0, 40000000.0)
    >>> round(bar.omega_c, 1)                           # rad/s
    133170.0
    >>> abs(float(bar.stuck_stiffness(bar.omega_c))) < 1e-6 * bar.k_star
    True
    """

    def __init__(self, E: float, rho: float, A: float, L: float, k: float, beta: float, mu: float) -> None:
        self.E = positive("E", E)
        self.rho = positive("rho", rho)
        self.A = positive("A", A)
        self.L = positive("L", L)
        self.k = positive("k", k)
        self.beta = nonnegative("beta", beta)
        self.mu = nonnegative("mu", mu)

    def __repr__(self) -> str:
        return (f"Bar(E={self.E!r}, rho={self.rho!r}, A={self.A!r}, L={self.L!r}, "
                f"k={self.k!r}, beta={self.beta!r}, mu={self.mu!r})")

    # ------------------------------------------------------------ constants
    @property
    def EA(self) -> float:
        return self.E * self.A

    @property
    def lam(self) -> float:
        """lambda = sqrt(k/EA) (Eq. 12)."""
        return math.sqrt(self.k / self.EA)

    def alpha2(self, omega: ArrayLike) -> NDArray[np.float64] | float:
        """alpha^2 = rho omega^2 / E (Eq. 12).  Every frequency of the stuck bar passes here, so here the bar
        refuses, naming omega, a frequency whose phase sqrt(rho/E) omega L leaves cos and sin no digit
        (``numerics.waves.check_phase``): its stiffness there would be rounding noise, and omega**2 overflows."""
        w = np.asarray(omega, dtype=float)
        top = float(w) if w.ndim == 0 else float(np.max(w, initial=0.0))
        if top > self._max_omega:  # (one comparison on the float path; NaN passes to the formula)
            check_phase(self, top)
        return self.rho * w**2 / self.E

    @functools.cached_property
    def _max_omega(self) -> float:
        """The highest omega ``check_phase`` takes for this bar (rad/s), computed once."""
        return max_omega(self)

    def gamma2(self, omega: ArrayLike) -> NDArray[np.float64] | float:
        """gamma^2 = k/EA - rho omega^2/E (Eq. 12); negative above sqrt(k/(rho A))."""
        return self.k / self.EA - self.alpha2(omega)

    # ------------------------------------------------------------ stuck bar
    def stuck_stiffness(self, omega: ArrayLike = 0.0) -> NDArray[np.float64] | float:
        """Dynamic stiffness EA u_x(L)/u(L) of the fully stuck bar (Eq. 1-2; Eq. 14 at L1 = L).

        Broadcasts over ``omega``; infinite values mark resonances of the bar held at x = L.
        """
        omega = number_array("omega", omega)
        if np.any(~np.isfinite(omega) | (omega < 0)):
            raise ValueError(f"omega must be finite and >= 0, got omega={omega!r}")
        with np.errstate(divide="ignore"):
            K = end_impedance(self.beta, self.gamma2(omega), self.L, self.EA)
        return K[()] if K.ndim == 0 else K

    @property
    def k_star(self) -> float:
        """k* = stuck_stiffness(0)."""
        return float(self.stuck_stiffness(0.0))

    @property
    def omega_c(self) -> float:
        """First natural frequency (rad/s) of the fully stuck bar with x = L free.

        It solves stuck_stiffness(omega) = 0, i.e. with gamma = i g:
        tan(g L) = beta / (EA g); beta = 0 gives g = 0, omega_c = sqrt(k/(rho A)).
        """
        EA, L = self.EA, self.L
        if self.beta == 0.0:
            g = 0.0
        else:
            b = self.beta * L / EA
            y = brentq(lambda y: y * math.sin(y) - b * math.cos(y), 0.0, 0.5 * math.pi, xtol=1e-15, rtol=1e-15)
            g = y / L
        return math.sqrt(self.E / self.rho * (g * g + self.k / EA))

    def stuck_shape(self, x: ArrayLike, omega: float = 0.0) -> NDArray[np.float64]:
        """u(x)/u(L) of the fully stuck bar at frequency omega (the mode-like shape of Fig. 2), 0 <= x <= L."""
        x = finite_array("x", x)
        if np.any((x < 0.0) | (x > self.L)):
            raise ValueError(f"x must lie on the bar, 0 <= x <= L={self.L!r}, got x with an entry "
                             f"{float(x[(x < 0.0) | (x > self.L)].flat[0]) if x.ndim else float(x)!r}")
        omega = nonnegative("omega", omega)
        s2 = float(self.gamma2(omega))
        # u(x) = u(0) (C(x) + beta Sn(x)/EA): ratio of scaled values at x and L.
        Cx, Sx, scx = segment_cs(s2, x)
        CL, SL, scL = segment_cs(s2, self.L)
        b = self.beta / self.EA
        if s2 > 0.0:
            # scale cancels up to exp(g (x - L)) (cosh ratio), kept finite.
            g = math.sqrt(s2)
            ratio = np.exp(g * (x - self.L)) * (1.0 + np.exp(-2 * g * x)) / (1.0 + math.exp(-2 * g * self.L))
            return ratio * (Cx + b * Sx) / (CL + b * SL)
        return (Cx + b * Sx) / (CL + b * SL)

    def contact_force(self, x: ArrayLike, omega: float = 0.0, *, tip_displacement: float | None = None,
                      tip_force: float | None = None) -> NDArray[np.float64]:
        """Contact elastic force k u(x) (N/m) of the stuck bar (Figs. 2, 3) for a tip
        displacement or a tip force (give one)."""
        if (tip_displacement is None) == (tip_force is None):
            raise ValueError("give exactly one of tip_displacement and tip_force")
        if tip_force is not None:
            K = float(self.stuck_stiffness(omega))
            tip_displacement = finite("tip_force", tip_force) / K
        else:
            tip_displacement = finite("tip_displacement", tip_displacement)
        return self.k * tip_displacement * self.stuck_shape(x, omega)

    def slip_onset(self, load: UniformLoad | QuadraticLoad, omega: float = 0.0, *,
                   grid: int = 801) -> tuple[float, float]:
        """``(x_star, a_min)``: where and at which tip amplitude the stuck bar first slips.

        Slip starts where ``k |u(x)| = mu q(x)`` first holds as the amplitude grows, i.e. at the
        minimum over x of ``mu q(x) / (k |u(x)/u(L)|)`` (Section 2.1, Fig. 3).
        """
        load = bound_load(load, self.L)
        omega = nonnegative("omega", omega)
        grid = count("grid", grid, 2)
        xs = np.linspace(0.0, self.L, grid)

        def ratio(x):
            phi = np.abs(self.stuck_shape(x, omega))
            with np.errstate(divide="ignore"):
                return np.where(phi > 0.0, self.mu * load.q(x) / (self.k * np.maximum(phi, 1e-300)), np.inf)

        r = np.maximum(ratio(xs), 0.0)
        i = int(np.argmin(r))
        if i == grid - 1:
            return self.L, float(r[-1])
        # Interior minimum: d/dx log(q/phi) = q'/q - phi'/phi = 0, with phi'/phi from the
        # scaled segment functions (d C/dx = s2 Sn, d Sn/dx = C), solved to rounding.
        s2 = float(self.gamma2(omega))
        b = self.beta / self.EA

        def dlog(x):
            C, Sn, _ = segment_cs(s2, x)
            return float(load.dq(x) / load.q(x) - (s2 * Sn + b * C) / (C + b * Sn))

        lo, hi = xs[max(i - 1, 0)], xs[min(i + 1, grid - 1)]
        if i == 0 or not dlog(lo) < 0.0 < dlog(hi):
            return float(xs[i]), float(r[i])
        x_star = brentq(dlog, lo, hi, xtol=1e-15 * self.L, rtol=1e-15)
        return x_star, max(float(ratio(np.array(x_star))), 0.0)  # q(x*) = 0 may round below 0
