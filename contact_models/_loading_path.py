"""The loading path of the microslip bar: its region solution and the pieces of its virgin
loading curve (``contact_models.microslip`` builds f_s, f_c on them).

``region_solution`` is the single-mode solution for given region boundaries (docs/theory.md,
sections 3 and 4); a piece (``_TwoRegionPiece``, ``_ThreeRegionPiece``) parametrises one
stretch of the loading curve by t in [0, 1], tabulates it once per frequency (folds, the
left-end check, the start of the inversion s(t) = a) and inverts it.
"""

from __future__ import annotations

import bisect
import cmath
import math
from functools import lru_cache
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike
from numpy.polynomial import chebyshev as cheb

from .numerics.roots import brentq
from .bar import Bar, impedance_transmission

#: Complex-step size for derivatives along the loading curve (relative to a unit parameter).
CSTEP = 1e-30
#: Largest relative dip of the loading curve below its onset value accepted as an onset fold.
MAX_ONSET_DIP = 1e-3
#: Largest relative overshoot of the loading curve before gross slip accepted as a gross-slip fold.
MAX_GROSS_DIP = 0.5
#: Points of the per-frequency table used to start the inversion s(t) = a.
TABLE_POINTS = 65

@lru_cache(maxsize=None)
def _table_nodes(n: int):
    """The per-frequency table's parameters t: Chebyshev-Lobatto points on [0, 1] (read-only)."""
    t = 0.5 * (1.0 - np.cos(np.linspace(0.0, np.pi, n)))
    t.flags.writeable = False
    return t


class Regions(NamedTuple):
    x1: np.ndarray
    x2: np.ndarray | None
    F_fric: np.ndarray
    K_tip: np.ndarray
    u1_fric: np.ndarray
    u1_unit: np.ndarray
    L1: Any = None  #: the stuck length the solution was taken at (as given)
    t0_fric: Any = None  #: u(0)/u(L1) of the friction part (static) and of the part
    t0_unit: Any = None  #: proportional to x, when asked for (``left=True``)


class Friction(NamedTuple):
    """The friction-driven part of the region solution (independent of theta and of omega): it
    depends on the region boundaries alone (``friction_part``)."""
    ell_m: Any  #: slipping length
    k0: Any  #: static stiffness of the stuck [0, L1]
    t0_fric: Any  #: u(0)/u(L1) of that static part (``left=True``), else None
    d0: Any  #: friction part of u(L1)
    F_fric: Any  #: EA u_x(L) of the friction part
    n1: Any  #: mu q(L1)/k - d0: the slip condition at L1 less its part proportional to x
    n2: Any  #: mu q(L2)/k - u_f(L2) for three regions (the same at L2), else None


def friction_part(bar: Bar, load: Any, L1: Any, L2: Any, *, left: bool = False, m: Any = np) -> Friction:
    """The friction-driven part of ``region_solution`` at the boundaries L1, L2 (L2 None: two
    regions): u'' = lam^2 u stuck, u'' = mu q/EA slipping, no inertia, so no omega.  ``m``: the
    functions' module (numpy, or cmath for one complex point)."""
    S, L, lam, mu, k, beta = bar.EA, bar.L, bar.lam, bar.mu, bar.k, bar.beta
    two = L2 is None
    ell_m = (L if two else L2) - L1  # slipping length
    # static stiffness of [0, L1] (and u(0)/u(L1) with left=True, for the left-end check)
    k0, t0_fric = impedance_transmission(beta, lam * lam, L1, S, transmission=left, m=m)
    # D2 = Q(L2) - Q(L1) - Q'(L1) ell_m and dQ = Q'(L2) - Q'(L1), Eq. 15, by Taylor at L1 (exact, no cancellation)
    e2 = ell_m * ell_m
    if not getattr(load, "q2", 0.0):  # a constant load: the Taylor series stops at q1
        q1 = float(load.q(0.0))
        D2 = mu / S * (q1 * e2 / 2)
        dQ = mu / S * (q1 * ell_m)
    else:
        q1, dq1, ddq = load.q(L1), load.dq(L1), load_curvature(load)
        D2 = mu / S * (q1 * e2 / 2 + dq1 * (e2 * ell_m) / 6 + ddq * (e2 * e2) / 24)
        dQ = mu / S * (q1 * ell_m + dq1 * e2 / 2 + ddq * (e2 * ell_m) / 6)
    if two:
        d0 = -D2 / (1.0 + k0 * ell_m / S)  # friction part of u(L1)
        return Friction(ell_m, k0, t0_fric, d0, S * dQ + k0 * d0, mu * q1 / k - d0, None)
    ell_2 = L - L2  # right stuck length
    e = m.exp(-lam * ell_2)
    sech2 = 2.0 * e / (1.0 + e * e)
    cR = m.tanh(lam * ell_2) / (S * lam)  # compliance u/(-EA u') of the right stuck part at L2
    d0 = -(D2 + cR * S * dQ) / (1.0 + k0 * (ell_m + cR * S) / S)
    uf2 = D2 + d0 * (1.0 + k0 * ell_m / S)  # friction part of u(L2)
    F_fric = (S * dQ + k0 * d0) * sech2  # EA u_x(L) of the friction part
    return Friction(ell_m, k0, t0_fric, d0, F_fric, mu * q1 / k - d0, mu * load.q(L2) / k - uf2)


def region_solution(bar: Bar, load: Any, L1: ArrayLike, L2: ArrayLike | None, omega: float, *,
                    left: bool = False, friction: Friction | None = None) -> Regions:
    """Single-mode solution for stuck [0, L1], slipping [L1, L2], stuck [L2, L] while loading.

    Returns a ``Regions`` tuple: ``x1, x2`` the tip displacements at which the shear
    force at L1 resp. L2 equals mu q (Eq. 7, 21); the tip force is F = F_fric + K_tip x;
    u(L1) = u1_fric + u1_unit x.  ``L2=None`` is the two-region case (L2 = L; x2 None).  Accepts complex L1, L2
    (complex-step differentiation).  docs/theory.md, sections 3 and 4, derive every line.

    ``friction``: ``friction_part(bar, load, L1, L2, left=left)`` when the caller has it (it does
    not depend on omega: a per-frequency table at fixed boundaries keeps it); else computed here.
    """
    S, L, mu, k, beta = bar.EA, bar.L, bar.mu, bar.k, bar.beta
    two = L2 is None
    m = np  # the functions' module; cmath for one complex point (a complex step), 10 times faster
    if isinstance(L1, complex) or (np.ndim(L1) == 0 and np.iscomplexobj(L1)):  # (the first test is quick)
        m, L1 = cmath, complex(L1)
        L2 = None if two else complex(L2)
    # --- friction-driven part (independent of theta, no inertia)
    fr = friction_part(bar, load, L1, L2, left=left, m=m) if friction is None else friction
    ell_m, k0, d0 = fr.ell_m, fr.k0, fr.d0
    # --- part proportional to x = a sin(theta): u'' = gamma^2 u stuck, u'' = -alpha^2 u slipping
    w2 = float(omega) * float(omega)
    a2 = bar.rho * w2 / bar.E  # Bar.alpha2, Bar.gamma2 (Eq. 12) for one float omega
    g2 = bar.k / S - a2
    kap, t0_unit = impedance_transmission(beta, g2, L1, S, transmission=left, m=m)  # Eq. 14, beta'(L1)
    k_mid, t1 = impedance_transmission(kap, -a2, ell_m, S, m=m)  # t1 = u(L1)/u(L2)
    if two:
        # --- slip condition k u(L1) = mu q(L1), linear in x
        return Regions(fr.n1 / t1, None, fr.F_fric, k_mid, d0, t1, L1, fr.t0_fric, t0_unit)
    K_tip, t2 = impedance_transmission(k_mid, g2, L - L2, S, m=m)  # t2 = u(L2)/u(L)
    # --- slip conditions k u(L_i) = mu q(L_i), linear in x
    return Regions(fr.n1 / (t1 * t2), fr.n2 / t2, fr.F_fric, K_tip, d0, t1 * t2, L1, fr.t0_fric, t0_unit)


def load_curvature(load: Any) -> float:
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
        tt = _table_nodes(self.table_points)
        s, F, ds, _, r = self._evaluate(tt, left=True, table=True)
        t0, t1 = 0.0, 1.0
        # the common case, a rising finite curve, in one test (NaN fails it, and with finite
        # ends a rising table is finite); else look for its folds
        rising = bool((s[1:] > s[:-1]).all()) and math.isfinite(s[0]) and math.isfinite(s[-1])
        if not rising:
            if not np.all(np.isfinite(s)):
                raise FloatingPointError(f"the loading curve is not finite at omega={omega!r} "
                                         "(at a resonance of the damper bar)")
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
                # started from the last frequency's t0 (kept on the element) when it lies in the bracket:
                # along a continuation it moves little, and the slopes here may not tell the curvature
                t0 = self._root_one(float(s[0]), *(float(v) for v in (tt[j - 1], tt[j], s[j - 1], s[j], ds[j - 1], ds[j])),
                                    start=getattr(element, "_last_onset_t0", None))
                element._last_onset_t0 = t0
            j = int(np.argmax(s))
            if j < self.table_points - 1:
                # Gross-slip fold: with little or no beta spring and inertia, s peaks just before
                # L1 = 0 (relative overshoot 4e-7 at 0.06 omega_c, 4e-4 at 0.3 omega_c for beta = 0).
                # Past the peak the last stuck zone cannot hold: gross slip starts at the peak.
                if not last:  # a piece handing on to another: a stuck zone at its end gave way
                    self._check_excited_end(tt, s)
                if not last or s[j] - s[-1] > MAX_GROSS_DIP * abs(s[j]):
                    raise FloatingPointError(
                        f"the loading curve folds back before gross slip at omega={omega!r} by "
                        f"{(s[j] - s[-1]) / abs(s[j]):.2g} (relative): outside the single-mode model's range")
                from scipy.optimize import minimize_scalar  # lazily: import contact_models stays light

                res = minimize_scalar(lambda t: -self._s(t), bounds=(tt[j - 1], tt[j + 1]), method="bounded",
                                      options={"xatol": 1e-14})
                t1 = float(res.x)
        if t1 != 1.0:  # a gross-slip fold (rare): the table anew on [t0, t1]
            self.t0, self.t1 = t0, t1
            s, F, ds, _, r = self._evaluate(tt, left=True)  # t1 depends on omega: no friction part to keep
        elif t0 != 0.0:  # an onset fold: the table's nodes past t0, and t0 itself, in the piece's t
            self.t0 = t0
            k = int(np.searchsorted(tt, t0, side="right"))
            k += bool(k < len(tt) - 1 and s[k] <= s[0])  # a node within rounding of t0
            tl, sl, Fl, dsl, dFl = self._last_root
            scale = 1.0 - t0  # d(raw t)/d(piece t)
            tt = np.concatenate(([0.0], (tt[k:] - t0) / scale))
            F = np.concatenate(([Fl + dFl * (t0 - tl)], F[k:]))  # F(t0) to O((t0 - tl)^2)
            s = np.concatenate(([s[0]], s[k:]))  # s(t0) = s(0): t0's definition
            ds = np.concatenate(([dsl], ds[k:])) * scale
            r = Regions(*(None if v is None else v[k:] for v in r))
            self._check_left_end(tt[1:], s[1:], r)
        if t0 == 0.0 or t1 != 1.0:
            self._check_left_end(tt, s, r)
        self.t_tab, self.s_tab, self.ds_tab = tt, s, ds
        # of the table's region solution only its last point is kept (``sliding``): a path holds
        # as few arrays as it needs (one is built per new frequency, and kept)
        self._table_end = (float(r.F_fric[-1].real), float(r.K_tip[-1].real))
        self.s0, self.s1 = float(s[0]), float(s[-1])
        self.F0, self.F1 = float(F[0]), float(F[-1])
        if not rising and np.any(np.diff(s) <= 0.0):
            # A fold inside the slip path: the tip displacement falls while the slip zone grows.
            # At omega = 0 the bar's own static curve cannot fold (docs/theory.md, section 6):
            # before the fold a second slip zone opens inside a stuck region, where mu q/(k u)
            # dips on its own (a load falling steeply away from where slip starts), and the
            # single-zone curve past that point is not the bar's.  At omega > 0 inertia adds
            # folds near a resonance of the damper bar.
            fall = np.max(np.maximum.accumulate(s) - s) / abs(s[-1])
            if omega == 0.0:
                raise FloatingPointError(
                    f"the loading curve folds back inside the slip path at omega={omega!r} (the tip displacement "
                    f"falls by {fall:.2g} relative while the slip zone grows): a second slip zone opens inside a "
                    "stuck region first, where mu q/(k u) dips on its own (the load falls too steeply along the "
                    "slip path); the two- and three-region models describe one slip zone")
            raise FloatingPointError(
                f"the loading curve folds back inside the slip path at omega={omega!r} (the tip displacement "
                f"falls by {fall:.2g} relative while the slip zone grows, so the slip front would jump; cause: "
                "the load, or inertia near a resonance of the damper bar): outside the single-mode model's range")

    def _s(self, t):
        return float(self.evaluate(np.array([t]))[0][0])

    def _check_left_end(self, t, s, regions=None):
        """The stuck region [0, L1] must stay stuck: k |u(0)| <= mu q(0) along the path.

        A lightly loaded left end (strongly convex loads) would start a second slip zone
        there, which neither the two- nor the three-region model describes.
        """
        bar, load = self.el.bar, self.el.load
        limit = bar.mu * float(load.q(0.0))
        k, slack, k_rounding = bar.k, limit * (1.0 + 1e-9), 1e-12 * bar.k

        def excess(t, s, r=None):  # (arrays: the real parts are views)
            if r is None:
                r = self._regions(t, left=True)
            fric = r.u1_fric.real * r.t0_fric.real  # the table's: complex step, real to O(h^2)
            unit = s * r.u1_unit.real * r.t0_unit.real
            rounding = k_rounding * (np.abs(fric) + np.abs(unit))  # at L1 = 0 they cancel to mu q / k
            return k * np.abs(fric + unit) - slack - rounding, r.L1.real

        over, L1 = excess(t, s, regions)
        if (over > 0.0).any():
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

    def _check_excited_end(self, t, s):
        """The stick condition at the excited end x = L along the table (t, s), for a piece
        with a stuck zone there; default: none (the stuck zone is at x = 0)."""

    def boundaries(self, t):
        """(L1, L2) at parameter t in [0, 1] (t = 0 at the piece's start)."""
        if self.t0 == 0.0 and self.t1 == 1.0:  # no fold: the piece's t is the raw one (0 + 1 t = t)
            return self._boundaries(t)
        return self._boundaries(self.t0 + (self.t1 - self.t0) * t)

    def evaluate(self, t):
        """s, F and their derivatives in t (complex step), for real array t."""
        return self._evaluate(t)[:4]

    def _evaluate(self, t, left=False, table=False):
        """``evaluate`` and the complex-step region solution it came from (whose real parts
        are the region solution at t, to O(CSTEP^2)).  ``table``: t are the per-frequency
        table's nodes (see ``_table_friction``)."""
        r = self._regions(np.asarray(t, dtype=float) + 1j * CSTEP, left, table)
        xc, Fc = r.x1, r.F_fric + r.K_tip * r.x1
        return xc.real, Fc.real, xc.imag / CSTEP, Fc.imag / CSTEP, r

    def _evaluate_one(self, t: float):
        """``evaluate`` at one float t, as floats (one complex point: cmath, no arrays)."""
        r = self._regions(complex(t, CSTEP))
        x, F = complex(r.x1), complex(r.F_fric + r.K_tip * r.x1)
        return x.real, F.real, x.imag / CSTEP, F.imag / CSTEP

    def _regions(self, t, left=False, table=False):
        L1, L2 = self.boundaries(t)
        friction = self._table_friction(L1, L2, left) if table else None
        return region_solution(self.el.bar, self.el.load, L1, L2, self.omega, left=left, friction=friction)

    def _table_key(self):
        """What fixes the table's region boundaries besides the piece's t0, t1 (None: they depend
        on omega, as the three-region piece's L1(L2) does)."""
        return None

    def _table_friction(self, L1, L2, left):
        """The friction part of the region solution at the table's boundaries L1, L2, or None.

        It does not depend on omega (``friction_part``), and a piece whose boundaries are fixed
        by ``_table_key`` and t0, t1 has the same table at every frequency: the element keeps it
        (a few entries), so a new frequency computes only the part proportional to x.
        """
        key = self._table_key()
        if key is None:
            return None
        key = (key, self.t0, self.t1, self.table_points, left)
        store = self.el.__dict__.setdefault("_friction_tables", {})
        hit = store.get(key)
        if hit is None:
            if len(store) >= 8:
                store.clear()
            hit = store[key] = friction_part(self.el.bar, self.el.load, L1, L2, left=left)
            for v in hit:  # shared by the tables of every frequency: read-only
                if isinstance(v, np.ndarray):
                    v.flags.writeable = False
        return hit

    def invert(self, a):
        """t with s(t) = a for s0 <= a <= s1 (vectorised safeguarded Newton)."""
        a = np.asarray(a, dtype=float)
        if a.size == 1:
            return np.full_like(a, self._invert_one(float(a.flat[0])))
        j = np.clip(np.searchsorted(self.s_tab, a), 1, len(self.s_tab) - 1)
        lo, hi = self.t_tab[j - 1], self.t_tab[j]
        slo, shi = self.s_tab[j - 1], self.s_tab[j]
        u = np.clip((a - slo) / (shi - slo), 0.0, 1.0)
        # start: cubic Hermite interpolation of the inverse t(s) between the two table points
        # (slopes 1/s'), error O(h^4); linear where a slope is not positive (at a fold)
        dlo, dhi = self.ds_tab[j - 1], self.ds_tab[j]
        with np.errstate(all="ignore"):
            H = shi - slo
            t = (lo + u * u * (3.0 - 2.0 * u) * (hi - lo)
                 + H * u * (1.0 - u) * ((1.0 - u) / dlo - u / dhi))
        linear = lo + (hi - lo) * u
        smooth = (dlo > 0.0) & (dhi > 0.0)
        t = np.where(smooth & (t >= lo) & (t <= hi), t, linear)
        # |s''| / (2 s') on the interval, from its end slopes: Newton's error after a step d is
        # about curv d^2, so a step with curv d^2 below rounding is the last
        with np.errstate(all="ignore"):
            curv = np.where(smooth, np.abs(dhi - dlo) / (2.0 * (hi - lo) * np.minimum(dlo, dhi)), np.inf)
        for _ in range(60):
            s, _, ds, _ = self.evaluate(t)
            r = s - a
            lo = np.where(r < 0, t, lo)
            hi = np.where(r > 0, t, hi)
            with np.errstate(all="ignore"):
                tn = t - r / ds
            bad = ~np.isfinite(tn) | (tn <= lo) | (tn >= hi)
            tn = np.where(bad, 0.5 * (lo + hi), tn)
            step = np.abs(tn - t)
            with np.errstate(invalid="ignore"):  # inf * 0: no curvature known and no step
                done = (step <= 4e-16 * np.maximum(1.0, np.abs(t))) | (~bad & (curv * step * step <= 1e-16))
            t = tn
            if np.all(done | (hi - lo <= 1e-16)):
                break
        return t

    def _invert_one(self, a: float) -> float:
        """``invert`` for one amplitude in floats (the solver's call, where numpy's per-call
        cost would exceed the arithmetic): the same start, steps and stopping rule."""
        # (bisect and six float reads of the arrays: cheaper than lists of the table, as a path
        # mostly serves one call, the continuation moving omega at each)
        t_tab, s_tab, ds_tab = self.t_tab, self.s_tab, self.ds_tab
        j = min(max(bisect.bisect_left(s_tab, a), 1), len(s_tab) - 1)
        return self._root_one(a, float(t_tab[j - 1]), float(t_tab[j]), float(s_tab[j - 1]), float(s_tab[j]),
                              float(ds_tab[j - 1]), float(ds_tab[j]))

    def _root_one(self, a, lo, hi, slo, shi, dlo, dhi, start=None):
        """t in [lo, hi] with s(t) = a, from the table's values s and slopes s' at lo and hi
        (s increasing there): Hermite start (or ``start`` if inside), safeguarded Newton, the
        stopping rule of ``invert``."""
        u = min(max((a - slo) / (shi - slo), 0.0), 1.0)
        t, curv = lo + (hi - lo) * u, math.inf
        if dlo > 0.0 and dhi > 0.0:
            th = lo + u * u * (3.0 - 2.0 * u) * (hi - lo) + (shi - slo) * u * (1.0 - u) * ((1.0 - u) / dlo - u / dhi)
            t = th if lo <= th <= hi else t
            curv = abs(dhi - dlo) / (2.0 * (hi - lo) * min(dlo, dhi))
        if start is not None and lo < start < hi:
            t = start
        prev = None
        for _ in range(60):
            s, F, ds, dF = self._evaluate_one(t)
            self._last_root = (t, s, F, ds, dF)  # the last evaluation (an onset fold's table starts with it)
            if prev is not None and ds > 0.0 and prev[1] > 0.0 and t != prev[0]:
                # |s''| / (2 s') from this slope and the last one (where the table's could not tell)
                curv = abs(ds - prev[1]) / (2.0 * abs(t - prev[0]) * min(ds, prev[1]))
            prev = (t, ds)
            r = s - a
            lo, hi = (t, hi) if r < 0.0 else ((lo, t) if r > 0.0 else (lo, hi))
            tn = t - r / ds if ds != 0.0 else math.nan
            bad = not lo < tn < hi
            tn = 0.5 * (lo + hi) if bad else tn
            step = abs(tn - t)
            done = step <= 4e-16 * max(1.0, abs(t)) or (not bad and curv * step * step <= 1e-16)
            t = tn
            if done or hi - lo <= 1e-16:
                break
        return t


class _TwoRegionPiece(_Piece):
    """L1 from L1_start down to 0, L2 = L (t = 0 at L1_start)."""

    def __init__(self, element, omega, L1_start):
        self.L1_start = L1_start
        super().__init__(element, omega)

    def _boundaries(self, t):
        return self.L1_start * (1.0 - t), None

    def _table_key(self):
        return ("two", self.L1_start)

    def sliding(self):
        """``(F_fric, K_slip)`` of the whole bar slipping (L1 = 0): the table's last point when
        the piece reaches L1 = 0, else a fresh region solution there."""
        if self.t1 == 1.0:
            return self._table_end
        r = region_solution(self.el.bar, self.el.load, 0.0, None, self.omega)
        return float(r.F_fric), float(r.K_tip)


class _ThreeRegionPiece(_Piece):
    """L2 from the slip-onset point x* up to L, L1 = L1(L2) (a Chebyshev interpolant)."""

    #: a finer table: its onset dip (docs/theory.md, section 6) is shallow and short, and a
    #: 65-point table misses it at some frequencies (f_s, f_c then off by ~1e-9; 129: ~1e-11)
    table_points = 2 * TABLE_POINTS - 1

    def __init__(self, element, omega, x_star):
        self.x_star = x_star
        self.coef = self._fit_L1(element, omega, x_star)
        self.dcoef = 2.0 * cheb.chebder(self.coef)  # d L1 / dt (x = 2 t - 1)
        super().__init__(element, omega, last=False)

    def _boundaries(self, t):
        L = self.el.bar.L
        L2 = self.x_star + (L - self.x_star) * t
        if np.iscomplexobj(t):  # complex step: L1(t + i h) = L1(t) + i h L1'(t) + O(h^2)
            L1, dL1 = _chebyshev_sum(2.0 * t.real - 1.0, self.coef, self.dcoef)
            return L1 + 1j * t.imag * dL1, L2
        return _chebyshev_sum(2.0 * np.asarray(t, dtype=float) - 1.0, self.coef)[0], L2

    def _check_excited_end(self, t, s):
        """The right stuck region [L2, L] must stay stuck at x = L: k x <= mu q(L) along the path.

        There u = x, and at L2 = L the slip condition there is k x = mu q(L) (Eq. 21), so the
        path ends exactly at that limit: a tip displacement above it before L2 = L is the
        loading curve folding back before its end.  The excited end then slips on its own, a
        second slip zone beside [L1, L2] (when slip starts inside, close to the end, and the
        load there is barely heavier than the onset needs), which the three-region model does
        not describe.  At omega = 0 the bar's true curve does not fold (docs/theory.md, section 6).
        """
        bar, L = self.el.bar, self.el.bar.L
        limit = bar.mu * float(self.el.load.q(L)) / bar.k
        over = s > limit
        if not over.any():  # a fold within rounding of the limit: the caller's message says how deep
            return
        i = int(np.argmax(over))
        tc = brentq(lambda u: self._s(u) - limit, t[i - 1], t[i], xtol=1e-14) if i > 0 else t[0]
        L1, L2 = (float(np.real(b)) for b in self.boundaries(tc))
        raise FloatingPointError(
            f"the excited end x = L starts slipping too, at tip amplitude {limit:.4g} m (k x = mu q(L)), while the "
            f"slip zone is [L1, L2] = [{L1 / L:.4f}, {L2 / L:.4f}] L (omega={self.omega!r}): the single slip zone's "
            f"loading curve rises {(s.max() - limit) / limit:.2g} (relative) above that and folds back before L2 = L; "
            "the interface has two slip zones there, which the three-region model does not describe")

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
            u, to_coef = _chebyshev_gauss(deg)
            L2 = x_star + (L - x_star) * 0.5 * (u + 1.0)
            guess = None
            if previous is not None:
                xs_prev, coef_prev = previous
                t_prev = np.clip((L2 - xs_prev) / (L - xs_prev), 0.0, 1.0)
                guess = _chebyshev_sum(2.0 * t_prev - 1.0, coef_prev)[0]
            L1 = _solve_L1(bar, load, L2, x_star, omega, guess)
            coef = to_coef @ L1  # the interpolant through the deg + 1 points (chebfit's, without a solve)
            if np.max(np.abs(coef[-4:])) <= tol * L:
                break
        el._last_L1_fit = (x_star, coef)
        return coef


_T_CACHE: dict = {}


@lru_cache(maxsize=None)
def _chebyshev_gauss(deg: int):
    """The deg + 1 Chebyshev points u_j = cos(theta_j), theta_j = pi (j + 1/2)/(deg + 1), in (-1, 1),
    and the matrix taking values there to the interpolant's coefficients (discrete orthogonality
    of T_k at these points: c_k = (2 - [k = 0])/(deg + 1) sum_j f_j cos(k theta_j))."""
    n = deg + 1
    theta = np.pi * (np.arange(n) + 0.5) / n
    M = np.cos(np.arange(n)[:, None] * theta[None, :]) * (2.0 / n)
    M[0] *= 0.5
    u = np.cos(theta)
    u.flags.writeable = False
    M.flags.writeable = False
    return u, M


def _chebyshev_sum(x, *coefs):
    """``sum_k c_k T_k(x)`` for each coefficient vector, x real in [-1, 1] (any shape), with
    T_k(x) = cos(k arccos x): one matrix of T_k shared by the sums (``chebval``'s Clenshaw
    recurrence costs a numpy call per degree).  The matrix of a long x (the per-frequency table,
    the same nodes at every frequency) is kept for the next call."""
    x = np.asarray(x, dtype=float)
    key = (x.tobytes(), len(coefs[0])) if x.size >= 64 else None
    T = _T_CACHE.get(key) if key is not None else None
    if T is None:
        theta = np.arccos(np.clip(x.ravel(), -1.0, 1.0))
        T = np.cos(theta[:, None] * np.arange(len(coefs[0]))[None, :])
        if key is not None:
            if len(_T_CACHE) >= 16:
                _T_CACHE.clear()
            _T_CACHE[key] = T
    return tuple((T[:, :len(c)] @ c).reshape(x.shape) for c in coefs)


def _solve_L1(bar, load, L2, x_star, omega, guess=None):
    """Root L1 in [0, x*) of G = x1(L1, L2) - x2(L1, L2) for each L2 > x* (vectorised).

    G(0) > 0 > G(x*) brackets the physical root (L1 = L2 is the trivial one, outside the
    bracket, and divided out).  Newton with the complex-step derivative dG/dL1, bisection when a step leaves
    the bracket.
    """

    def G(L1, L2=L2):
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
    n = L2.size
    if guess is None:
        g3, _ = G(np.concatenate([lo, hi]), np.concatenate([L2, L2]))
        glo, ghi = g3[:n], g3[n:]
        with np.errstate(all="ignore"):
            L1 = np.where(glo != ghi, (lo * ghi - hi * glo) / (ghi - glo), 0.5 * (lo + hi))
        L1 = np.where((L1 > lo) & (L1 < hi), L1, 0.5 * (lo + hi))
        first = None
    else:  # the bracket's ends and the first Newton point in one evaluation
        L1 = np.asarray(guess, dtype=float)
        L1 = np.where((L1 > lo) & (L1 < hi), L1, 0.5 * (lo + hi))
        g3, dg3 = G(np.concatenate([lo, hi, L1]), np.concatenate([L2, L2, L2]))
        glo, ghi, first = g3[:n], g3[n:2 * n], (g3[2 * n:], dg3[2 * n:])
    if np.any(~at_start & ~((glo >= 0.0) & (ghi <= 0.0))):
        raise FloatingPointError("three-region curve: no stick-slip boundary L1 found (load or frequency "
                                 "outside the three-region model's range)")
    done = at_start.copy()
    for _ in range(100):
        g, dg = G(L1) if first is None else first
        first = None
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
