"""The one-dimensional dynamic microslip bar (Cigeroglu, Lu & Menq 2006), as contact elements.

``TwoRegionMicroslip`` (Section 2.2, Eq. 3-15): stuck on [0, L1], slipping on [L1, L];
uniform and convex loads.  ``ThreeRegionMicroslip`` (Section 2.3, Eq. 16-28, Appendix A):
stuck, slipping on [L1, L2], stuck; concave loads.  When its right stuck region vanishes
(L2 = L) it continues as two regions up to gross slip (Fig. 7), and past gross slip the
bar slides as a whole.

Single-mode solution (the paper's approximation): on each region the displacement is a
friction-driven part independent of theta plus a part proportional to the tip motion
``x = a sin(theta)``; see ``docs/theory.md`` for every coefficient.  So each slip
condition (Eq. 7, 21) is linear in x, and the virgin loading curve F(x) is parametrised
by the region boundaries.  The closed loop follows by the Masing rule, and

    f_s = 8/(pi a) int_0^a sqrt(s (a - s)) dF(s),    f_c = 4/(pi a) int_0^a (a - 2 s) dF(s),

Stieltjes integrals along the loading curve (``docs/theory.md``, "From the loading curve
to f_s, f_c").  The stuck and gross-slip stretches are linear and integrate in closed
form; the microslip stretch is integrated by Gauss-Legendre quadrature in its boundary
parameter, refined until two successive rules agree to ``rtol``.

Near a true resonance of the bar (stuck_stiffness infinite or the slip stiffness
singular) the returned values are those of the formulas, large and of either sign; the
elements do not hide resonances of the damper itself.
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike
from numpy.polynomial import chebyshev as cheb
from scipy.optimize import brentq, minimize_scalar

from .bar import Bar, end_impedance, transmission
from .base import DEFAULT_RTOL, ContactElement, masing_loop
from .model_range import check_single_mode
from ._validation import nonnegative

#: Complex-step size for derivatives along the loading curve (relative to a unit parameter).
CSTEP = 1e-30
#: Gauss-Legendre nodes of the first rule; doubled until two rules agree to rtol.
GAUSS_START = 12
#: Largest Gauss-Legendre rule tried before giving up refining.
GAUSS_MAX = 384
#: A piece ending this close below a (relative) is integrated on geometrically graded cells.
GRADE_BELOW = 0.05
#: Number of geometric cells (ratio 1/4) used for a near-singular piece.
GRADE_CELLS = 14
#: Largest relative dip of the loading curve below its onset value accepted as an onset fold.
MAX_ONSET_DIP = 1e-3
#: Largest relative overshoot of the loading curve before gross slip accepted as a gross-slip fold.
MAX_GROSS_DIP = 0.5
#: Points of the per-frequency table used to start the inversion s(t) = a.
TABLE_POINTS = 65


@lru_cache(maxsize=None)
def _gauss(n: int):
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1.0), 0.5 * w


class Regions(NamedTuple):
    x1: np.ndarray
    x2: np.ndarray | None
    F_fric: np.ndarray
    K_tip: np.ndarray
    u1_fric: np.ndarray
    u1_unit: np.ndarray


def region_solution(bar: Bar, load, L1, L2, omega):
    """Single-mode solution for stuck [0, L1], slipping [L1, L2], stuck [L2, L] while loading.

    Returns a ``Regions`` tuple: ``x1, x2`` the tip displacements at which the shear
    force at L1 resp. L2 equals mu q (Eq. 7, 21); the tip force is F = F_fric + K_tip x;
    u(L1) = u1_fric + u1_unit x.  ``L2=None`` is the two-region case (L2 = L; x2 None).  Accepts complex L1, L2
    (complex-step differentiation).  docs/theory.md, sections 3 and 4, derive every line.
    """
    S, L, lam, mu, k = bar.EA, bar.L, bar.lam, bar.mu, bar.k
    two = L2 is None
    ell_m = (L if two else L2) - L1  # slipping length
    # --- friction-driven part (independent of theta, no inertia): u'' = lam^2 u stuck, u'' = mu q/EA slipping
    k0 = end_impedance(bar.beta, lam * lam, L1, S)  # static stiffness of [0, L1] seen from L1
    # D2 = Q(L2) - Q(L1) - Q'(L1) ell_m and dQ = Q'(L2) - Q'(L1), Eq. 15, by Taylor at L1 (exact, no cancellation)
    q1, dq1, ddq = load.q(L1), load.dq(L1), load_curvature(load)
    D2 = mu / S * (q1 * ell_m**2 / 2 + dq1 * ell_m**3 / 6 + ddq * ell_m**4 / 24)
    dQ = mu / S * (q1 * ell_m + dq1 * ell_m**2 / 2 + ddq * ell_m**3 / 6)
    # --- part proportional to x = a sin(theta): u'' = gamma^2 u stuck, u'' = -alpha^2 u slipping
    g2, a2 = bar.gamma2(omega), bar.alpha2(omega)
    kap = end_impedance(bar.beta, g2, L1, S)  # Eq. 14, beta'(L1)
    k_mid = end_impedance(kap, -a2, ell_m, S)
    t1 = transmission(kap, -a2, ell_m, S)  # u(L1)/u(L2)
    if two:
        d0 = -D2 / (1.0 + k0 * ell_m / S)  # friction part of u(L1)
        x1 = (mu * q1 / k - d0) / t1
        return Regions(x1, None, S * dQ + k0 * d0, k_mid, d0, t1)
    ell_2 = L - L2  # right stuck length
    e = np.exp(-lam * ell_2)
    sech2 = 2.0 * e / (1.0 + e * e)
    cR = np.tanh(lam * ell_2) / (S * lam)  # compliance u/(-EA u') of the right stuck part at L2
    d0 = -(D2 + cR * S * dQ) / (1.0 + k0 * (ell_m + cR * S) / S)
    uf2 = D2 + d0 * (1.0 + k0 * ell_m / S)  # friction part of u(L2)
    F_fric = (S * dQ + k0 * d0) * sech2  # EA u_x(L) of the friction part
    K_tip = end_impedance(k_mid, g2, ell_2, S)
    t2 = transmission(k_mid, g2, ell_2, S)  # u(L2)/u(L)
    # --- slip conditions k u(L_i) = mu q(L_i), linear in x
    x1 = (mu * q1 / k - d0) / (t1 * t2)
    x2 = (mu * load.q(L2) / k - uf2) / t2
    return Regions(x1, x2, F_fric, K_tip, d0, t1 * t2)


def load_curvature(load) -> float:
    """q'' (constant for the loads here)."""
    q2 = getattr(load, "q2", 0.0) or 0.0
    return 8.0 * q2 / load.L**2


class _Piece:
    """One stretch of the virgin loading curve, parameter t in [0, 1], s increasing with t.

    Subclasses give ``_boundaries(t)`` -> (L1, L2) (complex t allowed).
    """

    table_points = TABLE_POINTS

    def __init__(self, element, omega, *, last: bool = True):
        self.el = element
        self.omega = omega
        self.t0, self.t1 = 0.0, 1.0
        tt = 0.5 * (1.0 - np.cos(np.linspace(0.0, np.pi, self.table_points)))
        s = self.evaluate(tt)[0]
        if not np.all(np.isfinite(s)):
            raise FloatingPointError(f"the loading curve is not finite at omega={omega!r} "
                                     "(at a resonance of the damper bar)")
        t0, t1 = 0.0, 1.0
        i = int(np.argmin(s))
        if i > 0:
            # Onset fold: with inertia the single-mode curve can dip just after an interior
            # slip onset (relative depth ~1e-6 at 0.3 omega_c).  The interface stays stuck up
            # to the stuck onset s(0), then snaps to the rising branch where s = s(0) again.
            if s[0] - s[i] > MAX_ONSET_DIP * abs(s[0]) or s[-1] <= s[0]:
                raise FloatingPointError(
                    f"the loading curve folds back after slip onset at omega={omega!r} by "
                    f"{(s[0] - s[i]) / abs(s[0]):.2g} (relative): outside the single-mode model's range")
            j = i + int(np.argmax(s[i:] >= s[0]))
            t0 = self._rising_root(s[0], tt[i], tt[j])
        j = int(np.argmax(s))
        if j < self.table_points - 1:
            # Gross-slip fold: with little or no beta spring and inertia, s peaks just before
            # L1 = 0 (relative overshoot 4e-7 at 0.06 omega_c, 4e-4 at 0.3 omega_c for beta = 0).
            # Past the peak the last stuck zone cannot hold: gross slip starts at the peak.
            if not last or s[j] - s[-1] > MAX_GROSS_DIP * abs(s[j]):
                raise FloatingPointError(
                    f"the loading curve folds back before gross slip at omega={omega!r} by "
                    f"{(s[j] - s[-1]) / abs(s[j]):.2g} (relative): outside the single-mode model's range")
            res = minimize_scalar(lambda t: -self._s(t), bounds=(tt[j - 1], tt[j + 1]), method="bounded",
                                  options={"xatol": 1e-14})
            t1 = float(res.x)
        self.t0, self.t1 = t0, t1
        s, F = self.evaluate(tt)[:2]
        self._check_left_end(tt, s)
        self.t_tab, self.s_tab = tt, s
        self.s0, self.s1 = float(s[0]), float(s[-1])
        self.F0, self.F1 = float(F[0]), float(F[-1])
        if np.any(np.diff(s) <= 0.0):
            raise FloatingPointError(
                f"the loading curve is not monotone at omega={omega!r}: outside the single-mode model's range "
                "(near a resonance of the damper bar)")

    def _s(self, t):
        return float(self.evaluate(np.array([t]))[0][0])

    def _rising_root(self, target, lo, hi):
        """t in [lo, hi] with s(t) = target, s increasing there: Newton on s' (complex step), bisection guard."""
        t = 0.5 * (lo + hi)
        for _ in range(60):
            s, _, ds, _ = (float(v[0]) for v in self.evaluate(np.array([t])))
            if abs(s - target) <= 8 * np.finfo(float).eps * abs(target):  # s is known to rounding only
                return t
            if s < target:
                lo = t
            else:
                hi = t
            tn = t - (s - target) / ds if ds > 0.0 else 0.5 * (lo + hi)
            if not lo <= tn <= hi:
                tn = 0.5 * (lo + hi)
            if abs(tn - t) <= 1e-15 or hi - lo <= 1e-15:
                return tn
            t = tn
        return t

    def _check_left_end(self, t, s):
        """The stuck region [0, L1] must stay stuck: k |u(0)| <= mu q(0) along the path.

        A lightly loaded left end (strongly convex loads) would start a second slip zone
        there, which neither the two- nor the three-region model describes.
        """
        bar, load = self.el.bar, self.el.load
        limit = bar.mu * float(load.q(0.0))

        def excess(t, s):
            L1, L2 = self.boundaries(t)
            L1 = np.real(L1)
            r = region_solution(bar, load, L1, None if L2 is None else np.real(L2), self.omega)
            fric = r.u1_fric * transmission(bar.beta, bar.lam**2, L1, bar.EA)
            unit = s * r.u1_unit * transmission(bar.beta, bar.gamma2(self.omega), L1, bar.EA)
            rounding = 1e-12 * bar.k * (np.abs(fric) + np.abs(unit))  # at L1 = 0 they cancel to mu q / k
            return np.real(bar.k * np.abs(fric + unit) - limit * (1.0 + 1e-9) - rounding), L1

        over, L1 = excess(t, s)
        if np.any(over > 0.0):
            i = int(np.argmax(over > 0.0))
            if i > 0:  # locate the crossing between two table points
                tc = brentq(lambda u: float(excess(np.array([u]), self._s(u))[0][0]), t[i - 1], t[i], xtol=1e-14)
                xc, L1c = self._s(tc), float(excess(np.array([tc]), self._s(tc))[1][0])
            else:
                xc, L1c = s[0], L1[0]
            raise ValueError(
                f"load: the end x = 0 starts slipping too, at tip amplitude {xc:.4g} m (stuck length "
                f"L1 = {L1c / bar.L:.3f} L) at omega={self.omega!r}, before gross slip; the interface then "
                "has slip zones at both ends, which the two- and three-region models do not describe "
                f"(q(0) = {float(load.q(0.0)):.4g} N/m is too small)")

    def boundaries(self, t):
        """(L1, L2) at parameter t in [0, 1] (t = 0 at the piece's start)."""
        return self._boundaries(self.t0 + (self.t1 - self.t0) * t)

    def evaluate(self, t):
        """s, F and their derivatives in t (complex step), for real array t."""
        t = np.asarray(t, dtype=float)
        xc, Fc = self._xF(t + 1j * CSTEP)
        return xc.real, Fc.real, xc.imag / CSTEP, Fc.imag / CSTEP

    def _xF(self, t):
        L1, L2 = self.boundaries(t)
        r = region_solution(self.el.bar, self.el.load, L1, L2, self.omega)
        return r.x1, r.F_fric + r.K_tip * r.x1

    def invert(self, a):
        """t with s(t) = a for s0 <= a <= s1 (vectorised safeguarded Newton)."""
        a = np.asarray(a, dtype=float)
        j = np.clip(np.searchsorted(self.s_tab, a), 1, self.table_points - 1)
        lo, hi = self.t_tab[j - 1], self.t_tab[j]
        slo, shi = self.s_tab[j - 1], self.s_tab[j]
        t = lo + (hi - lo) * np.clip((a - slo) / (shi - slo), 0.0, 1.0)
        for _ in range(60):
            s, _, ds, _ = self.evaluate(t)
            r = s - a
            lo = np.where(r < 0, t, lo)
            hi = np.where(r > 0, t, hi)
            with np.errstate(all="ignore"):
                tn = t - r / ds
            bad = ~np.isfinite(tn) | (tn <= lo) | (tn >= hi)
            tn = np.where(bad, 0.5 * (lo + hi), tn)
            done = np.abs(tn - t) <= 4e-16 * np.maximum(1.0, np.abs(t))
            t = tn
            if np.all(done | (hi - lo <= 1e-16)):
                break
        return t


class _TwoRegionPiece(_Piece):
    """L1 from L1_start down to 0, L2 = L (t = 0 at L1_start)."""

    def __init__(self, element, omega, L1_start):
        self.L1_start = L1_start
        super().__init__(element, omega)

    def _boundaries(self, t):
        return self.L1_start * (1.0 - t), None


class _ThreeRegionPiece(_Piece):
    """L2 from the slip-onset point x* up to L, L1 = L1(L2) (a Chebyshev interpolant)."""

    #: a finer table: its onset dip (docs/theory.md, section 6) is shallow and short, and a
    #: 65-point table misses it at some frequencies (f_s, f_c then off by ~1e-9; 129: ~1e-11)
    table_points = 2 * TABLE_POINTS - 1

    def __init__(self, element, omega, x_star):
        self.x_star = x_star
        self.coef = self._fit_L1(element, omega, x_star)
        super().__init__(element, omega, last=False)

    def _boundaries(self, t):
        L = self.el.bar.L
        L2 = self.x_star + (L - self.x_star) * t
        L1 = cheb.chebval(2.0 * t - 1.0, self.coef)
        return L1, L2

    @staticmethod
    def _fit_L1(el, omega, x_star, tol=1e-13):
        """Chebyshev coefficients of L1(L2) on the three-region curve x1(L1, L2) = x2(L1, L2).

        The previous frequency's interpolant (kept on the element) starts the root solves,
        so consecutive frequencies of a continuation converge in a few Newton steps.
        """
        bar, load = el.bar, el.load
        L = bar.L
        previous = getattr(el, "_last_L1_fit", None)
        for deg in (24, 48, 96):
            u = np.cos(np.pi * (np.arange(deg + 1) + 0.5) / (deg + 1))  # Chebyshev points in (-1, 1)
            L2 = x_star + (L - x_star) * 0.5 * (u + 1.0)
            guess = None
            if previous is not None:
                xs_prev, coef_prev = previous
                t_prev = np.clip((L2 - xs_prev) / (L - xs_prev), 0.0, 1.0)
                guess = cheb.chebval(2.0 * t_prev - 1.0, coef_prev)
            L1 = _solve_L1(bar, load, L2, x_star, omega, guess)
            coef = cheb.chebfit(u, L1, deg)
            if np.max(np.abs(coef[-4:])) <= tol * L:
                break
        el._last_L1_fit = (x_star, coef)
        return coef


def _solve_L1(bar, load, L2, x_star, omega, guess=None):
    """Root L1 in [0, x*) of G = x1(L1, L2) - x2(L1, L2) for each L2 > x* (vectorised).

    G(0) > 0 > G(x*) brackets the physical root (L1 = L2 is the trivial one, outside the
    bracket, and divided out).  Newton with the complex-step derivative dG/dL1, bisection when a step leaves
    the bracket.
    """

    def G(L1):
        # divided by (L2 - L1) > 0: removes the trivial root, which otherwise makes the
        # physical one nearly double next to the nucleation point (slow Newton)
        z = L1 + 1j * CSTEP * bar.L
        r = region_solution(bar, load, z, L2, omega)
        with np.errstate(all="ignore"):
            g = (r.x1 - r.x2) / (L2 - z)
        return g.real, g.imag / (CSTEP * bar.L)

    at_start = (L2 - x_star) <= 1e-14 * bar.L  # nucleation limit: L1 -> x*
    lo = np.zeros_like(L2)
    hi = np.minimum(np.full_like(L2, x_star), L2)
    glo, _ = G(lo)
    ghi, _ = G(hi)
    if np.any(~at_start & ~((glo >= 0.0) & (ghi <= 0.0))):
        raise FloatingPointError("three-region curve: no stick-slip boundary L1 found (load or frequency "
                                 "outside the three-region model's range)")
    if guess is None:
        with np.errstate(all="ignore"):
            L1 = np.where(glo != ghi, (lo * ghi - hi * glo) / (ghi - glo), 0.5 * (lo + hi))
    else:
        L1 = np.asarray(guess, dtype=float).copy()
    L1 = np.where((L1 > lo) & (L1 < hi), L1, 0.5 * (lo + hi))
    done = at_start.copy()
    for _ in range(100):
        g, dg = G(L1)
        lo = np.where(g > 0.0, L1, lo)
        hi = np.where(g <= 0.0, L1, hi)
        with np.errstate(all="ignore"):
            new = L1 - g / dg
        # a converged point is itself a bracket end: accept steps onto the ends
        new = np.where(np.isfinite(new) & (new >= lo) & (new <= hi), new, 0.5 * (lo + hi))
        done |= (np.abs(new - L1) <= 1e-14 * bar.L) | (hi - lo <= 1e-14 * bar.L)  # interpolant needs 1e-13 L
        L1 = np.where(done, L1, new)
        if np.all(done):
            break
    return np.where(at_start, x_star, L1)


class _MicroslipBar(ContactElement):
    """Common machinery: the loading path, quadrature, Masing loop."""

    frequency_dependent = True

    def __init__(self, bar: Bar, load):
        if not isinstance(bar, Bar):
            raise ValueError(f"bar must be a contact_models.Bar, got bar={bar!r}")
        self.bar = bar
        self.load = load.on(bar.L)
        if self.load.minimum() < 0.0:
            raise ValueError(f"load must be >= 0 everywhere, got load={load!r}")
        self._paths: dict = {}

    def __repr__(self):
        return f"{type(self).__name__}({self.bar!r}, {self.load!r})"

    # ------------------------------------------------------------ the path
    def _path(self, omega: float):
        """(a_min, pieces, a_gross, F_gross, K_slip, K_stuck) at omega, cached."""
        key = float(omega)
        hit = self._paths.get(key)
        if hit is None:
            hit = self._build_path(key)
            if len(self._paths) > 256:
                self._paths.clear()
            self._paths[key] = hit
        return hit

    def _build_path(self, omega):
        bar = self.bar
        K = float(bar.stuck_stiffness(omega))
        sliding = region_solution(bar, self.load, 0.0, None, omega)  # the whole bar slips: F = F_int + K_slip x
        K_slip = float(sliding.K_tip)
        if bar.mu * self.load.N == 0.0:  # no friction: a linear spring of the slipping bar
            return 0.0, [], 0.0, 0.0, K_slip, K
        pieces = self._pieces(omega)
        a_min, a_g = pieces[0].s0, pieces[-1].s1
        # on the sliding line at a_g; differs from pieces[-1].F1 only after a gross-slip fold
        F_g = float(sliding.F_fric) + K_slip * a_g
        return a_min, pieces, a_g, F_g, K_slip, K

    # ------------------------------------------------------------ public extras
    def slip_stiffness(self, omega=0.0) -> float:
        """Slope of the loading curve past gross slip: the fully slipping bar's dynamic stiffness."""
        return self._path(nonnegative("omega", omega))[4]

    def gross_slip_amplitude(self, omega=0.0) -> float:
        """Amplitude at which the whole interface slips (L1 = 0)."""
        return self._path(nonnegative("omega", omega))[2]

    def loading_curve(self, x, omega=0.0):
        """Virgin loading force F(x) for tip displacement x >= 0 (Eq. 13 solved for theta)."""
        x = np.asarray(x, dtype=float)
        omega = nonnegative("omega", omega)
        a_min, pieces, a_g, F_g, K_slip, K = self._path(omega)
        F = np.where(x <= a_min, K * x, F_g + K_slip * (x - a_g))
        for p in pieces:
            inside = (x > p.s0) & (x < p.s1)
            if np.any(inside):
                F[inside] = p.evaluate(p.invert(x[inside]))[1]
        return F

    def boundaries(self, x, omega=0.0):
        """(L1, L2) on the virgin loading curve at tip displacement x (L1 = L2 = L while stuck
        for two regions; for three regions both equal the onset point x* while stuck)."""
        x = np.asarray(x, dtype=float)
        omega = nonnegative("omega", omega)
        a_min, pieces, a_g, *_ = self._path(omega)
        L = self.bar.L

        def at(p, t):
            b1, b2 = p.boundaries(t)
            return np.real(b1), (L if b2 is None else np.real(b2))

        start = at(pieces[0], 0.0) if pieces else (0.0, L)
        L1 = np.where(x <= a_min, start[0], 0.0)
        L2 = np.where(x <= a_min, start[1], L)
        for p in pieces:
            inside = (x > p.s0) & (x < p.s1)
            if np.any(inside):
                L1[inside], L2[inside] = at(p, p.invert(x[inside]))
        return L1, L2

    def stick_slip_history(self, a, omega=0.0, *, n: int = 361):
        """Steady-state boundaries over one cycle (Figs. 6, 7, 19): ``(theta, L1, L2)``.

        By the Masing rule the state at theta on the branch up from x = -a is the virgin
        state at (a + x)/2 (and (a - x)/2 on the way down); theta in [-pi/2, 3 pi/2].
        """
        a = nonnegative("a", a)
        theta = np.linspace(-0.5 * np.pi, 1.5 * np.pi, int(n))
        x = a * np.sin(theta)
        up = theta <= 0.5 * np.pi
        s = np.where(up, 0.5 * (a + x), 0.5 * (a - x))
        L1, L2 = self.boundaries(s, omega)
        return theta, L1, L2

    # ------------------------------------------------------------ interface
    def fourier(self, a: ArrayLike, omega: ArrayLike = 0.0, *, rtol: float = DEFAULT_RTOL) -> tuple[Any, Any]:
        """As ``ContactElement.fourier``; warns (``ModelRangeWarning``) outside the single-mode range
        (``contact_models.model_range``)."""
        out = super().fourier(a, omega, rtol=rtol)
        check_single_mode(self, a, omega)
        return out

    def fourier_derivatives(self, a: ArrayLike, omega: ArrayLike = 0.0, *,
                            rtol: float = DEFAULT_RTOL) -> tuple[Any, ...]:
        """As ``ContactElement.fourier_derivatives``; warns outside the single-mode range."""
        out = super().fourier_derivatives(a, omega, rtol=rtol)
        check_single_mode(self, a, omega)
        return out

    def _stuck_stiffness(self, omega):
        return float(self.bar.stuck_stiffness(omega))

    def _slip_amplitude(self, omega):
        return self._path(omega)[0]

    def _hysteresis(self, a, omega, n):
        return masing_loop(lambda x: self.loading_curve(x, omega), a, n)

    def _fourier_derivatives(self, a, omega, rtol):
        fs = np.empty_like(a)
        fc = np.empty_like(a)
        dfs = np.empty_like(a)
        dfc = np.empty_like(a)
        for w in np.unique(omega):
            sel = omega == w
            r = _fourier_one_omega(self._path(float(w)), a[sel], rtol)
            fs[sel], fc[sel], dfs[sel], dfc[sel] = r
        return fs, fc, dfs, dfc


def _isq(a, s1, s2):
    """int_{s1}^{s2} sqrt(s (a - s)) ds, closed form (s = a (1 + sin th)/2)."""

    def prim(s):
        u = np.clip(2.0 * s / a - 1.0, -1.0, 1.0)
        return a * a / 8.0 * (np.arcsin(u) + u * np.sqrt(1.0 - u * u))

    return prim(s2) - prim(s1)


def _idsq(a, s1, s2):
    """int_{s1}^{s2} sqrt(s / (a - s)) / 2 ds, closed form (the a-derivative weight of f_s)."""

    def prim(s):
        u = np.clip(2.0 * s / a - 1.0, -1.0, 1.0)
        return a / 4.0 * (np.arcsin(u) - np.sqrt(1.0 - u * u))

    return prim(s2) - prim(s1)


def _fourier_one_omega(path, a, rtol):
    """f_s, f_c, df_s/da, df_c/da for amplitudes ``a`` at one frequency (see module docstring)."""
    a_min, pieces, a_g, F_g, K_slip, K = path
    a = np.asarray(a, dtype=float)
    fs = K * a
    fc = np.zeros_like(a)
    dfs = np.full_like(a, K)
    dfc = np.zeros_like(a)
    slip = a > a_min
    if not np.any(slip):
        return fs, fc, dfs, dfc
    A = a[slip]
    # Stieltjes integrals J_s = int sqrt(s(a-s)) dF, J_c = int (a - 2s) dF, Jd = int sqrt(s/(a-s))/2 dF
    m = np.minimum(A, a_min)
    Js = K * _isq(A, 0.0, m)
    Jc = K * (A * m - m * m)
    Jd = K * _idsq(A, 0.0, m)
    Fa = np.where(A > a_g, F_g + K_slip * (A - a_g), 0.0)
    dFa = np.where(A > a_g, K_slip, 0.0)
    # A skipped onset fold leaves F(s0) - K s0 as a jump of the loading curve: a point mass of dF.
    if pieces:
        s0, jump = pieces[0].s0, pieces[0].F0 - K * pieces[0].s0
        Js += jump * np.sqrt(s0 * np.maximum(A - s0, 0.0))
        Jc += jump * (A - 2.0 * s0)
        Jd += jump * 0.5 * np.sqrt(s0 / np.maximum(A - s0, np.finfo(float).tiny))
    # Likewise a gross-slip fold: the curve snaps from the piece's end onto the sliding line at a_g.
    gross = A > a_g
    if np.any(gross) and pieces:
        jump = F_g - pieces[-1].F1
        G = A[gross]
        Js[gross] += jump * np.sqrt(a_g * (G - a_g))
        Jc[gross] += jump * (G - 2.0 * a_g)
        Jd[gross] += jump * 0.5 * np.sqrt(a_g / (G - a_g))
    for p in pieces:
        act = A > p.s0
        if not np.any(act):
            continue
        Aa = A[act]
        inside = Aa < p.s1
        t_end = np.ones_like(Aa)
        if np.any(inside):
            t_end[inside] = p.invert(Aa[inside])
        js, jc, jd = _piece_integrals(p, Aa, t_end, inside, rtol)
        Js[act] += js
        Jc[act] += jc
        Jd[act] += jd
        if np.any(inside):
            _, Fi, dsi, dFi = p.evaluate(t_end[inside])
            idx = np.flatnonzero(act)[inside]
            Fa[idx] = Fi
            dFa[idx] = dFi / dsi
    if np.any(gross):
        G = A[gross]
        Js[gross] += K_slip * _isq(G, a_g, G)
        Jc[gross] += K_slip * (G * (G - a_g) - (G * G - a_g * a_g))
        Jd[gross] += K_slip * _idsq(G, a_g, G)
    fs_s = 8.0 / (np.pi * A) * Js
    fc_s = 4.0 / (np.pi * A) * Jc
    fs[slip] = fs_s
    # J_c cancels exactly on linear stretches; clear rounding-level negatives (|.| <= 64 eps K a).
    fc[slip] = np.where((fc_s < 0.0) & (fc_s > -64 * np.finfo(float).eps * abs(K) * A), 0.0, fc_s)
    dfs[slip] = -fs_s / A + 8.0 / (np.pi * A) * Jd
    dfc[slip] = -fc_s / A + 4.0 / (np.pi * A) * (Fa - A * dFa)
    return fs, fc, dfs, dfc


def _piece_integrals(p, a, t_end, exact_end, rtol):
    """Integrals of one piece from t = 0 to t_end for each amplitude, to relative ``rtol``.

    With t = t_end (1 - tau^2) the square-root end (s = a) becomes smooth in tau.  A piece
    that ends just below a (near-singular) is split into geometrically graded cells in tau.
    """
    near = ~exact_end & ((a - p.s1) < GRADE_BELOW * (p.s1 - p.s0))
    out = [np.zeros_like(a) for _ in range(3)]
    for mask, graded in ((~near, False), (near, True)):
        if not np.any(mask):
            continue
        aa, te = a[mask], t_end[mask]
        if graded:
            # cells [r^(j+1), r^j] in tau, the innermost [0, r^GRADE_CELLS]
            edges = np.concatenate(([0.0], 0.25 ** np.arange(GRADE_CELLS, -1, -1)))
        else:
            edges = np.array([0.0, 1.0])
        n = GAUSS_START
        prev = _graded_rule(p, aa, te, edges, n)
        while True:
            n *= 2
            cur = _graded_rule(p, aa, te, edges, n)
            scale = np.maximum(np.abs(cur[0]) + np.abs(cur[1]), 1e-300)
            err = np.maximum(np.abs(cur[0] - prev[0]), np.abs(cur[1] - prev[1])) / scale
            if np.all(err <= 0.1 * rtol) or n >= GAUSS_MAX:
                break
            prev = cur
        for k in range(3):
            out[k][mask] = cur[k]
    return out


def _graded_rule(p, a, t_end, edges, n):
    x, w = _gauss(n)
    lo, hi = edges[:-1], edges[1:]
    tau = (lo[:, None] + (hi - lo)[:, None] * x[None, :]).ravel()  # nodes in (0, 1)
    wt = ((hi - lo)[:, None] * w[None, :]).ravel()
    tt = t_end[:, None] * (1.0 - tau[None, :] ** 2)
    s, _, _, dF = p.evaluate(tt)
    jac = 2.0 * t_end[:, None] * tau[None, :]  # |dt/dtau|
    A = a[:, None]
    gap = np.maximum(A - s, 0.0)
    sq = np.sqrt(np.maximum(s, 0.0))
    dFw = dF * jac * wt[None, :]
    Js = np.sum(sq * np.sqrt(gap) * dFw, axis=1)
    Jc = np.sum((A - 2.0 * s) * dFw, axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        Jd = np.sum(np.where(gap > 0.0, 0.5 * sq / np.sqrt(gap), 0.0) * dFw, axis=1)
    return Js, Jc, Jd


class TwoRegionMicroslip(_MicroslipBar):
    """Two-region microslip bar (Section 2.2): slip starts at the excited end and the stuck
    region [0, L1] shrinks to gross slip.  For uniform and convex loads (Eq. 3-15).

    ``TwoRegionMicroslip(bar, UniformLoad(N=100.0))``; a_min = mu q(L)/k.

    Range (validity map, docs/validation.md): exact while stuck and at omega -> 0; otherwise its
    F_s, F_c error against the all-mode bar stays within 1 % up to
    omega_1 = omega_c sqrt(0.01/C), C = 0.42 (1 + (lambda L)^2)(1 + 0.2 EA/(beta L)) (0.10 omega_c
    for the DESIGN.md bar), and grows like (omega/omega_c)^2 beyond (2.4 % at 0.2, 21 % at 0.5
    omega_c there).  ``fourier`` and ``fourier_derivatives`` warn (``ModelRangeWarning``) beyond
    omega_1 and at an early gross-slip snap; ``AllModeMicroslip`` holds everywhere.
    """

    def __init__(self, bar: Bar, load):
        super().__init__(bar, load)
        x_star = bar.slip_onset(self.load, 0.0)[0] if bar.mu * self.load.N > 0.0 else bar.L
        if x_star < bar.L * (1.0 - 1e-9):
            raise ValueError(
                f"load: slip starts inside the bar (x = {x_star:.4g} of L = {bar.L:.4g}) at low frequency, "
                "so the interface has three regions; use ThreeRegionMicroslip"
            )

    def _pieces(self, omega):
        return [_TwoRegionPiece(self, omega, self.bar.L)]


class ThreeRegionMicroslip(_MicroslipBar):
    """Three-region microslip bar (Section 2.3): slip starts inside at x*, the slip region
    [L1, L2] grows both ways; when L2 reaches L the bar continues as two regions to gross
    slip (Fig. 7).  For concave loads, e.g. ``QuadraticLoad.from_ratio(N, 12)``.

    With a load that slips first at the excited end it reduces to the two-region path.

    Range (validity map, docs/validation.md): as ``TwoRegionMicroslip`` with C = 0.62 (1 + (lambda
    L)^2)(1 + 0.2 EA/(beta L)) (ratio-12 concave load; 0.082 omega_c for the DESIGN.md bar, 5.3 %
    error at 0.2 omega_c); warns (``ModelRangeWarning``) beyond it.
    """

    def _pieces(self, omega):
        L = self.bar.L
        x_star, _ = self.bar.slip_onset(self.load, omega)
        if x_star >= L * (1.0 - 1e-9):
            return [_TwoRegionPiece(self, omega, L)]
        three = _ThreeRegionPiece(self, omega, x_star)
        if three.t1 != 1.0:
            raise FloatingPointError(f"three-region curve ends before L2 = L at omega={omega!r}")
        L1_end = float(np.real(three.boundaries(1.0)[0]))
        two = _TwoRegionPiece(self, omega, L1_end)
        return [three, two]
