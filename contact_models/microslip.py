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

import numpy as np

from ._loading_path import (CSTEP, MAX_GROSS_DIP, MAX_ONSET_DIP, TABLE_POINTS, Regions,  # noqa: F401 (public here)
                            _ThreeRegionPiece, _TwoRegionPiece, load_curvature, region_solution)
from .bar import Bar, impedance_transmission
from .base import ContactElement, masing_loop
from .model_range import check_single_mode
from .numerics.checks import nonnegative

#: Gauss-Legendre nodes of the first rule; doubled until two rules agree to rtol.
GAUSS_START = 12
#: Largest Gauss-Legendre rule tried before giving up refining.
GAUSS_MAX = 384
#: A piece ending this close below a (relative) is integrated on geometrically graded cells.
GRADE_BELOW = 0.05
#: Number of geometric cells (ratio 1/4) used for a near-singular piece.
GRADE_CELLS = 14


_EPS = float(np.finfo(float).eps)
_TINY = float(np.finfo(float).tiny)


@lru_cache(maxsize=None)
def _gauss(n: int):
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1.0), 0.5 * w


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
        self._onsets: dict = {}
        self._check_topology()
        try:  # the static path (cached for later): a bar and load it cannot follow are refused here
            self._path(0.0)
        except FloatingPointError as exc:
            raise ValueError(f"bar, load: {exc} (bar={bar!r}, lambda L={bar.lam * bar.L:.4g}, "
                             f"load={self.load!r})") from None

    def _check_topology(self) -> None:
        """Refuse a load whose stick-slip topology the element does not describe (default: none)."""

    def __repr__(self):
        return f"{type(self).__name__}({self.bar!r}, {self.load!r})"

    # ------------------------------------------------------------ the path
    def _path(self, omega: float):
        """(a_min, pieces, a_gross, F_gross, K_slip, K_stuck) at omega, cached: the whole path."""
        return self._lazy_path(omega).full()

    def _lazy_path(self, omega: float) -> _Path:
        """The path at omega, cached, built as far as it has been needed (``_Path``)."""
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
        K = self._stuck_stiffness(omega)
        if bar.mu * self.load.N == 0.0:  # no friction: a linear spring of the slipping bar
            return _Path(K, [], done=(0.0, [], 0.0, 0.0,
                                      float(region_solution(bar, self.load, 0.0, None, omega).K_tip), K))
        return _Path(K, *self._first_pieces(omega))

    def _first_pieces(self, omega):
        """``(pieces, more)``: the path's first pieces and a callable building the rest (or None)."""
        return self._pieces(omega), None

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
    def _check_range(self, a, omega):
        """Warn (``ModelRangeWarning``) outside the single-mode range (``contact_models.model_range``)."""
        check_single_mode(self, a, omega, stacklevel=4)

    def _derivatives_one(self, a: float, w: float, rtol: float):
        """``(f_s, f_c, df_s/da, df_c/da)`` in floats for one amplitude at one frequency: the float
        path of the public methods (``ContactElement._scalar_call``) and of the solver's call."""
        K = self._stuck_answer(w, a)
        if K is not None:
            return K * a, 0.0, K, 0.0
        return _fourier_one(self._lazy_path(w).upto(a), a, rtol)

    def _stuck_answer(self, w: float, a_max: float):
        """The stuck stiffness when amplitudes up to ``a_max`` are stuck at ``w`` and that needs no
        loading path (none built yet), else None (the path answers; at a resonance of the stuck
        bar, K infinite, it reports it)."""
        if w not in self._paths and a_max <= self._onset(w)[1]:
            K = self._stuck_stiffness(w)
            if math.isfinite(K):
                return K
        return None

    def _stuck_stiffness(self, omega):
        # Bar.stuck_stiffness for one float omega without its array checks: the same operations.
        # Every path build and stuck answer passes here, through Bar.gamma2 (tests spy on it)
        bar = self.bar
        g2 = float(bar.gamma2(omega))
        with np.errstate(divide="ignore"):  # infinite at a resonance of the bar held at x = L
            return float(impedance_transmission(bar.beta, g2, bar.L, bar.EA, transmission=False)[0])

    def _slip_amplitude(self, omega):
        return self._path(omega)[0]  # builds (and so checks) the loading path

    def _linear_amplitude(self, omega):
        # the solver's question "is a stuck?" needs no loading path: the onset alone
        return self._onset(float(omega))[1]

    def _onset(self, omega: float):
        """``(x_star, a_min)``: where and at which tip amplitude slip starts at omega, cached.

        Needs no loading path (a stuck evaluation builds none): a_min is the loading curve's
        first point, the tip amplitude at which k u(x*) = mu q(x*) for the stuck bar.
        """
        hit = self._onsets.get(omega)
        if hit is None:
            hit = self._stuck_onset(omega) if self.bar.mu * self.load.N > 0.0 else (self.bar.L, 0.0)
            if len(self._onsets) > 256:
                self._onsets.clear()
            self._onsets[omega] = hit
        return hit

    def _stuck_onset(self, omega):
        """Two regions: slip starts at the excited end when k u(L) = mu q(L), at any frequency
        (the two-region solution at L1 = L: no slipping length, t1 = 1, x1 = mu q(L)/k)."""
        hit = self.__dict__.get("_end_onset")  # the same at every frequency: computed once
        if hit is None:
            L = self.bar.L
            hit = self._end_onset = (L, float(self.bar.mu * self.load.q(L) / self.bar.k))
        return hit

    def _hysteresis(self, a, omega, n):
        return masing_loop(lambda x: self.loading_curve(x, omega), a, n)

    def _fourier_derivatives(self, a, omega, rtol):
        if omega.size == 1 or (omega.size > 1 and np.all(omega == omega[0])):  # one frequency (the solver's call)
            w = float(omega[0])
            if a.size == 1:  # the solver's call: one amplitude, in floats
                return tuple(np.array([v]) for v in self._derivatives_one(float(a[0]), w, rtol))
            a_max = float(np.max(a))
            K = self._stuck_answer(w, a_max)
            if K is not None:  # stuck: no loading path needed
                return K * a, np.zeros_like(a), np.full_like(a, K), np.zeros_like(a)
            return _fourier_one_omega(self._lazy_path(w).upto(a_max), a, rtol)
        fs, fc, dfs, dfc = (np.empty_like(a) for _ in range(4))
        for w in np.unique(omega):
            sel = omega == w
            r = _fourier_one_omega(self._path(float(w)), a[sel], rtol)
            fs[sel], fc[sel], dfs[sel], dfc[sel] = r
        return fs, fc, dfs, dfc


class _Path:
    """The loading path at one frequency, built only as far as the amplitudes asked need.

    The first pieces are built at once (a_min and the microslip up to their end ``s1``); the
    rest (for three regions the two-region continuation from L2 = L) and the sliding line past
    gross slip when an amplitude reaches past them, or the whole path is asked for (``full``):
    f_s, f_c at an amplitude a depend on the loading curve up to a only.
    """

    def __init__(self, K, pieces, more=None, *, done=None):
        self.K, self.pieces, self._more, self._full = K, pieces, more, done
        self.a_min = pieces[0].s0 if pieces else (done[0] if done else 0.0)

    def upto(self, a_max: float):
        """The path's tuple (as ``full``) for amplitudes up to ``a_max``: the pieces built so far
        when they reach past a_max (a_gross is then +inf, not reached), else the whole path."""
        if self._full is None and self._more is not None and a_max < self.pieces[-1].s1:
            return self.a_min, self.pieces, math.inf, math.nan, math.nan, self.K
        return self.full()

    def full(self):
        """``(a_min, pieces, a_gross, F_gross, K_slip, K_stuck)``, building what is missing."""
        if self._full is None:
            if self._more is not None:
                self.pieces = self.pieces + self._more()
                self._more = None
            last = self.pieces[-1]
            # the whole bar slips: F = F_fric + K_slip x, the region solution at L1 = 0
            F_fric, K_slip = last.sliding()
            a_g = last.s1
            # on the sliding line at a_g; differs from pieces[-1].F1 only after a gross-slip fold
            self._full = (self.a_min, self.pieces, a_g, F_fric + K_slip * a_g, K_slip, self.K)
        return self._full


#: (arcsin, sqrt, clip to [-1, 1]) for arrays and for one float amplitude.
_ARRAYS = (np.arcsin, np.sqrt, lambda u: np.minimum(np.maximum(u, -1.0), 1.0))
_FLOATS = (math.asin, math.sqrt, lambda u: min(max(u, -1.0), 1.0))


def _stretch(a, K, s1, s2, fns=_ARRAYS):
    """The integrals (J_s, J_c, J_d) of a straight stretch dF = K ds of the loading curve from
    s1 to s2 <= a, in closed form (s = a (1 + u)/2, u = sin th):

    J_s = K int sqrt(s (a - s)) ds = K a^2/8 [asin u + u sqrt(1 - u^2)],
    J_c = K int (a - 2 s) ds = K (a - s1 - s2)(s2 - s1),
    J_d = K int sqrt(s / (a - s)) / 2 ds = K a/4 [asin u - sqrt(1 - u^2)].

    ``fns``: ``_ARRAYS`` for arrays a, ``_FLOATS`` for one float a.
    """
    asin, sqrt, clip = fns
    u1 = clip(2.0 * s1 / a - 1.0)
    u2 = clip(2.0 * s2 / a - 1.0)
    as1, as2 = asin(u1), asin(u2)
    r1, r2 = sqrt(1.0 - u1 * u1), sqrt(1.0 - u2 * u2)
    Js = K * a * a / 8.0 * ((as2 - as1) + (u2 * r2 - u1 * r1))
    Jc = K * (a - s1 - s2) * (s2 - s1)
    Jd = K * a / 4.0 * ((as2 - as1) - (r2 - r1))
    return Js, Jc, Jd


def _fourier_one_omega(path, a, rtol):
    """f_s, f_c, df_s/da, df_c/da for amplitudes ``a`` at one frequency (see module docstring)."""
    a_min, pieces, a_g, F_g, K_slip, K = path
    a = np.asarray(a, dtype=float)
    slip = a > a_min
    if not np.any(slip):
        return K * a, np.zeros_like(a), np.full_like(a, K), np.zeros_like(a)
    every = bool(np.all(slip))
    A = a if every else a[slip]
    # Stieltjes integrals J_s = int sqrt(s(a-s)) dF, J_c = int (a - 2s) dF, Jd = int sqrt(s/(a-s))/2 dF;
    # first the stuck stretch [0, a_min] (A > a_min here)
    Js, Jc, Jd = _stretch(A, K, 0.0, a_min)
    gross = A > a_g
    any_gross = bool(np.any(gross))
    Fa = np.where(gross, F_g + K_slip * (A - a_g), 0.0) if any_gross else np.zeros_like(A)
    dFa = np.where(gross, K_slip, 0.0) if any_gross else np.zeros_like(A)
    # A skipped onset fold leaves F(s0) - K s0 as a jump of the loading curve: a point mass of dF.
    if pieces:
        s0, jump = pieces[0].s0, pieces[0].F0 - K * pieces[0].s0
        Js += jump * np.sqrt(s0 * np.maximum(A - s0, 0.0))
        Jc += jump * (A - 2.0 * s0)
        Jd += jump * 0.5 * np.sqrt(s0 / np.maximum(A - s0, _TINY))
    # Likewise a gross-slip fold: the curve snaps from the piece's end onto the sliding line at a_g.
    if any_gross and pieces:
        jump = F_g - pieces[-1].F1
        G = A[gross]
        Js[gross] += jump * np.sqrt(a_g * (G - a_g))
        Jc[gross] += jump * (G - 2.0 * a_g)
        Jd[gross] += jump * 0.5 * np.sqrt(a_g / (G - a_g))
    for p in pieces:
        act = A > p.s0
        if not np.any(act):
            continue
        all_act = bool(np.all(act))
        Aa = A if all_act else A[act]
        inside = Aa < p.s1
        if np.all(inside):
            t_end = p.invert(Aa)
        else:
            t_end = np.ones_like(Aa)
            if np.any(inside):
                t_end[inside] = p.invert(Aa[inside])
        (js, jc, jd), (Fe, dse, dFe) = _piece_integrals(p, Aa, t_end, inside, rtol)
        if all_act:
            Js += js
            Jc += jc
            Jd += jd
        else:
            Js[act] += js
            Jc[act] += jc
            Jd[act] += jd
        if all_act and np.all(inside):
            Fa, dFa = Fe, dFe / dse
        else:
            idx = np.flatnonzero(act)[inside]
            Fa[idx] = Fe[inside]
            dFa[idx] = dFe[inside] / dse[inside]
    if any_gross:
        G = A[gross]
        js, jc, jd = _stretch(G, K_slip, a_g, G)
        Js[gross] += js
        Jc[gross] += jc
        Jd[gross] += jd
    fs_s = 8.0 / (np.pi * A) * Js
    fc_s = 4.0 / (np.pi * A) * Jc
    # J_c cancels exactly on linear stretches; clear rounding-level negatives (|.| <= 64 eps K a).
    fc_s = np.where((fc_s < 0.0) & (fc_s > -64 * _EPS * abs(K) * A), 0.0, fc_s)
    dfs_s = -fs_s / A + 8.0 / (np.pi * A) * Jd
    dfc_s = -fc_s / A + 4.0 / (np.pi * A) * (Fa - A * dFa)
    if every:
        return fs_s, fc_s, dfs_s, dfc_s
    fs, fc, dfs, dfc = K * a, np.zeros_like(a), np.full_like(a, K), np.zeros_like(a)
    fs[slip], fc[slip], dfs[slip], dfc[slip] = fs_s, fc_s, dfs_s, dfc_s
    return fs, fc, dfs, dfc


def _fourier_one(path, a: float, rtol):
    """``_fourier_one_omega`` for one float amplitude, term by term the same (numpy's cost per
    call on 1-element arrays would be most of the time): f_s, f_c, df_s/da, df_c/da."""
    a_min, pieces, a_g, F_g, K_slip, K = path
    if not a > a_min:
        return K * a, 0.0, K, 0.0
    Js, Jc, Jd = _stretch(a, K, 0.0, a_min, _FLOATS)
    Fa = dFa = 0.0
    if pieces:  # the onset fold's point mass (see _fourier_one_omega)
        s0, jump = pieces[0].s0, pieces[0].F0 - K * pieces[0].s0
        Js += jump * math.sqrt(s0 * max(a - s0, 0.0))
        Jc += jump * (a - 2.0 * s0)
        Jd += jump * 0.5 * math.sqrt(s0 / max(a - s0, _TINY))
    gross = a > a_g
    if gross and pieces:  # the gross-slip fold's
        jump = F_g - pieces[-1].F1
        Js += jump * math.sqrt(a_g * (a - a_g))
        Jc += jump * (a - 2.0 * a_g)
        Jd += jump * 0.5 * math.sqrt(a_g / (a - a_g))
    for p in pieces:
        if not a > p.s0:
            continue
        inside = a < p.s1
        t_end = p._invert_one(a) if inside else 1.0
        graded = not inside and (a - p.s1) < GRADE_BELOW * (p.s1 - p.s0)  # as _piece_integrals
        (js, jc, jd), (Fe, dse, dFe) = _converged_rules(p, a, t_end, graded, rtol)
        Js, Jc, Jd = Js + js, Jc + jc, Jd + jd
        if inside:
            Fa, dFa = Fe, dFe / dse
    if gross:
        Fa, dFa = F_g + K_slip * (a - a_g), K_slip
        js, jc, jd = _stretch(a, K_slip, a_g, a, _FLOATS)
        Js, Jc, Jd = Js + js, Jc + jc, Jd + jd
    fs = 8.0 / (math.pi * a) * Js
    fc = 4.0 / (math.pi * a) * Jc
    if -64 * _EPS * abs(K) * a < fc < 0.0:  # rounding-level negatives, as _fourier_one_omega
        fc = 0.0
    return fs, fc, -fs / a + 8.0 / (math.pi * a) * Jd, -fc / a + 4.0 / (math.pi * a) * (Fa - a * dFa)


def _piece_integrals(p, a, t_end, exact_end, rtol):
    """Integrals of one piece from t = 0 to t_end for each amplitude, to relative ``rtol``,
    and ``(F, s', F')`` at t_end (the end node of the first evaluation).

    With t = t_end (1 - tau^2) the square-root end (s = a) becomes smooth in tau.  A piece
    that ends just below a (near-singular) is split into geometrically graded cells in tau.
    The first two rules (``GAUSS_START`` and twice as many nodes) and the end node share one
    evaluation of the loading curve.
    """
    near = ~exact_end & ((a - p.s1) < GRADE_BELOW * (p.s1 - p.s0))
    if not np.any(near):
        return _converged_rules(p, a, t_end, False, rtol)
    out = [np.zeros_like(a) for _ in range(3)]
    end = [np.zeros_like(a) for _ in range(3)]
    for mask, graded in ((~near, False), (near, True)):
        if np.any(mask):
            cur, at_end = _converged_rules(p, a[mask], t_end[mask], graded, rtol)
            for k in range(3):
                out[k][mask] = cur[k]
                end[k][mask] = at_end[k]
    return out, end


def _converged_rules(p, a, t_end, graded, rtol):
    """The piece's integrals by rules of doubling size until two agree to ``rtol / 10``, and the
    curve's ``(F, s', F')`` at t_end.  ``a``, ``t_end``: arrays, or floats for one amplitude (the
    solver's call; everything is then a float)."""
    n = 2 * GAUSS_START
    (prev, cur), at_end = _graded_rules(p, a, t_end, graded, (GAUSS_START, n), with_end=True)
    while True:
        if isinstance(a, float):  # one amplitude: the same test in floats
            agree = (max(abs(cur[0] - prev[0]), abs(cur[1] - prev[1])) / max(abs(cur[0]) + abs(cur[1]), 1e-300)
                     <= 0.1 * rtol)
        else:
            scale = np.maximum(np.abs(cur[0]) + np.abs(cur[1]), 1e-300)
            err = np.maximum(np.abs(cur[0] - prev[0]), np.abs(cur[1] - prev[1])) / scale
            agree = bool(np.all(err <= 0.1 * rtol))
        if agree or n >= GAUSS_MAX:
            return cur, at_end
        n *= 2
        prev, ((cur,), _) = cur, _graded_rules(p, a, t_end, graded, (n,))


@lru_cache(maxsize=64)
def _rule_nodes(graded: bool, ns: tuple, with_end: bool):
    """Nodes tau in [0, 1] of the Gauss-Legendre rules of sizes ``ns`` (one after the other, and
    tau = 0 last when ``with_end``) on one cell or on the graded cells, ``1 - tau^2`` at them, and
    each rule's weights."""
    if graded:
        # cells [r^(j+1), r^j] in tau, the innermost [0, r^GRADE_CELLS]
        edges = np.concatenate(([0.0], 0.25 ** np.arange(GRADE_CELLS, -1, -1)))
    else:
        edges = np.array([0.0, 1.0])
    lo, hi = edges[:-1], edges[1:]
    taus, wts = [], []
    for n in ns:
        x, w = _gauss(n)
        taus.append((lo[:, None] + (hi - lo)[:, None] * x[None, :]).ravel())  # nodes in (0, 1)
        wts.append(((hi - lo)[:, None] * w[None, :]).ravel())
    tau = np.concatenate(taus + ([np.zeros(1)] if with_end else []))
    shrink = 1.0 - tau * tau  # t = t_end (1 - tau^2)
    for v in [tau, shrink] + wts:
        v.flags.writeable = False
    return tau, shrink, tuple(wts)


def _graded_rules(p, a, t_end, graded, ns, *, with_end=False):
    """``([(J_s, J_c, J_d) for each rule of n in ns], (F, s', F') at t_end or None)``: one
    evaluation of the loading curve at the nodes of all the rules (and at tau = 0).

    ``a``, ``t_end``: arrays (one row of nodes per amplitude), or floats for one amplitude (one
    row, 1-D, and float results).
    """
    tau, shrink, wts = _rule_nodes(graded, ns, with_end)
    one = isinstance(a, float)
    te, A = (t_end, a) if one else (t_end[:, None], a[:, None])
    s, F, ds, dF = p.evaluate(te * shrink)
    gap = np.maximum(A - s, 0.0)
    sq = np.sqrt(np.maximum(s, 0.0))
    dFj = dF * ((2.0 * te) * tau)  # dF/dt |dt/dtau|
    rg = np.sqrt(gap)
    g_s = sq * rg * dFj
    g_c = (A - 2.0 * s) * dFj
    g_d = 0.5 * sq / np.where(gap > 0.0, rg, np.inf) * dFj  # 0 at the end s = a (gap = 0)
    rules, i = [], 0
    for wt in wts:
        cols = slice(i, i + wt.size)
        rule = (g_s[..., cols] @ wt, g_c[..., cols] @ wt, g_d[..., cols] @ wt)
        rules.append(tuple(map(float, rule)) if one else rule)
        i += wt.size
    if not with_end:
        return rules, None
    return rules, ((float(F[-1]), float(ds[-1]), float(dF[-1])) if one else (F[:, -1], ds[:, -1], dF[:, -1]))


class TwoRegionMicroslip(_MicroslipBar):
    """Two-region microslip bar (Section 2.2): slip starts at the excited end and the stuck
    region [0, L1] shrinks to gross slip.  For uniform and convex loads (Eq. 3-15).

    ``TwoRegionMicroslip(bar, UniformLoad(N=100.0))``; a_min = mu q(L)/k.

    Parameters
    ----------
    bar : Bar
        The damper bar.
    load : UniformLoad or QuadraticLoad
        Normal load along the contact; bound to ``bar.L``.  It must slip first at the excited
        end x = L (uniform, convex).

    Raises
    ------
    ValueError
        If slip starts inside the bar at low frequency (a concave load: use
        :class:`ThreeRegionMicroslip`), or if the load's lightly loaded end x = 0 would slip
        before gross slip; the message says which.

    See Also
    --------
    ThreeRegionMicroslip : slip starting inside the bar (concave loads).
    NumericalMicroslip : the same bar with every mode, integrated in time.
    PointContact.fit : the equivalent single-slider contact.

    Notes
    -----
    The single-mode solution of the paper: the virgin loading curve F(x) is parametrised by the
    stuck length L1, from L1 = L (slip onset at ``a_min = mu q(L)/k``, for a uniform load
    ``mu N/(k L)``) down to L1 = 0 (gross slip at :meth:`gross_slip_amplitude`); past it the
    bar slides as a whole with stiffness :meth:`slip_stiffness`.  The Masing rule closes the
    loop, and f_s, f_c are its Fourier integrals, evaluated to ``rtol``.  ``docs/theory.md``
    gives every coefficient (Eqs. 10-15) and where the printed paper differs.

    Range (validity map, docs/validation.md, over lambda L, beta L/EA, omega and a): exact while
    stuck and at omega -> 0; otherwise its F_s, F_c error against the all-mode bar is within 1 %
    at every amplitude up to omega_1 (``model_range.single_mode_frequency_limit``: 0.124 omega_c
    for the DESIGN.md bar, 0.1 to 0.22 omega_c for lambda L <= 1, 0.02 to 0.08 omega_c for
    lambda L = 3) and grows roughly like (omega/omega_c)^2 beyond (at the worst amplitude 2.7 % at
    0.2 and 21 % at 0.5 omega_c for the DESIGN.md bar).  ``fourier`` and ``fourier_derivatives``
    warn (``ModelRangeWarning``) at the points where the map's error exceeds 1 % and at an early
    gross-slip snap; ``AllModeMicroslip`` holds everywhere.

    References
    ----------
    .. [1] Cigeroglu, Lu & Menq (2006), Section 2.2, Eqs. 3-15; Figs. 6, 8-10.

    Examples
    --------
    >>> from contact_models import Bar, UniformLoad, TwoRegionMicroslip
    >>> bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    >>> two = TwoRegionMicroslip(bar, UniformLoad(N=100.0))
    >>> a_min = two.slip_amplitude()                   # mu N/(k L), m
    >>> a_min, round(two.gross_slip_amplitude() / a_min, 6), two.slip_stiffness() / bar.k_star
    (7.5e-07, 2.5, 0.5)
    >>> f_s, f_c = two.fourier(2 * a_min, 0.3 * bar.omega_c)
    >>> round(float(f_s), 3), round(float(f_c), 3)      # N
    (47.653, 7.221)
    """

    #: The validity map's load for this element (``contact_models.model_range``).
    _validity_load = "uniform"

    def _check_topology(self) -> None:
        bar = self.bar
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

    Parameters
    ----------
    bar : Bar
        The damper bar.
    load : UniformLoad or QuadraticLoad
        Normal load along the contact; bound to ``bar.L``.

    Raises
    ------
    ValueError
        If the load's lightly loaded end x = 0 would slip before gross slip (the model's
        topology cannot follow it); the message says where.

    See Also
    --------
    TwoRegionMicroslip, QuadraticLoad.from_ratio

    Notes
    -----
    Slip starts at the minimum x* of ``mu q(x)/(k |u(x)/u(L)|)`` (:meth:`Bar.slip_onset`), at
    the amplitude ``a_min``; the slip region [L1, L2] grows both ways (Eqs. 16-28 and
    Appendix A), the right stuck region vanishes first, and the interface then continues as two
    regions to gross slip.  ``docs/theory.md``, section 4, has every coefficient.

    Range (validity map, docs/validation.md): as ``TwoRegionMicroslip``, measured with the ratio-12
    concave load: within 1 % at every amplitude up to 0.078 omega_c for the DESIGN.md bar (6.4 % at
    0.2 omega_c at the worst amplitude); warns (``ModelRangeWarning``) where the map's error
    exceeds 1 %.

    References
    ----------
    .. [1] Cigeroglu, Lu & Menq (2006), Section 2.3, Eqs. 16-28, Appendix A; Figs. 7, 11-15.

    Examples
    --------
    The concave ratio-12 load slips first at x* = 0.5114 L, at 0.3513 of the uniform load's
    a_min:

    >>> from contact_models import Bar, QuadraticLoad, ThreeRegionMicroslip
    >>> bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    >>> three = ThreeRegionMicroslip(bar, QuadraticLoad.from_ratio(N=100.0, ratio=12.0))
    >>> round(three.slip_amplitude() / 7.5e-07, 4)
    0.3513
    >>> f_s, f_c = three.fourier(2.25e-6, 0.3 * bar.omega_c)
    >>> round(float(f_s), 3), round(float(f_c), 3)      # N
    (57.478, 10.511)
    """

    #: The validity map's load for this element (``contact_models.model_range``).
    _validity_load = "concave12"

    def _stuck_onset(self, omega):
        x_star, a_min = self.bar.slip_onset(self.load, omega)
        if x_star >= self.bar.L * (1.0 - 1e-9):  # slip starts at the excited end: two regions
            return super()._stuck_onset(omega)
        return x_star, a_min

    def _pieces(self, omega):
        first, more = self._first_pieces(omega)
        return first + (more() if more is not None else [])

    def _first_pieces(self, omega):
        L = self.bar.L
        x_star, _ = self._onset(omega)
        if x_star >= L * (1.0 - 1e-9):
            return [_TwoRegionPiece(self, omega, L)], None
        three = _ThreeRegionPiece(self, omega, x_star)
        if three.t1 != 1.0:
            raise FloatingPointError(f"three-region curve ends before L2 = L at omega={omega!r}")

        def more():  # the two-region continuation, from L2 = L to gross slip
            return [_TwoRegionPiece(self, omega, float(np.real(three.boundaries(1.0)[0])))]

        return [three], more
