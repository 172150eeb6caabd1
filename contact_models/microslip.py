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
parameter, refined until two successive rules agree to ``rtol`` (``contact_models._path_integrals``:
the integrals of a path; this module builds the path and holds the elements).

Near a true resonance of the bar (stuck_stiffness infinite or the slip stiffness
singular) the returned values are those of the formulas, large and of either sign; the
elements do not hide resonances of the damper itself.
"""

from __future__ import annotations

import math

import numpy as np

from ._loading_path import (CSTEP, MAX_GROSS_DIP, MAX_ONSET_DIP, TABLE_POINTS, Regions,  # noqa: F401 (public here)
                            _ThreeRegionPiece, _TwoRegionPiece, load_curvature, region_solution)
from ._path_integrals import GAUSS_MAX, GAUSS_START, _fourier_one, _fourier_one_omega  # noqa: F401 (public here)
from .allmode import AllModeMicroslip
from .bar import Bar, impedance_transmission
from .base import ContactElement, masing_loop
from .loads import QuadraticLoad, UniformLoad
from .model_range import check_single_mode, single_mode_error
from .numerics.checks import count, finite_array, nonnegative
from .quasi_static import QuasiStatic
from .numerics.waves import check_phase


class _MicroslipBar(ContactElement):
    """Common machinery: the loading path, quadrature, Masing loop."""

    frequency_dependent = True

    def __init__(self, bar: Bar, load):
        if not isinstance(bar, Bar):
            raise ValueError(f"bar must be a contact_models.Bar, got bar={bar!r}")
        self.bar = bar
        if not isinstance(load, (UniformLoad, QuadraticLoad)):
            raise ValueError(f"load={load!r}: {type(self).__name__} solves the bar under a uniform or a quadratic "
                             f"normal load (Eq. 29) only; for any other distribution use "
                             f"contact_models.AllModeMicroslip (the bar with every mode, any load)")
        self.load = load.on(bar.L)
        if self.load.minimum() < 0.0:
            raise ValueError(f"load must be >= 0 everywhere, got load={load!r}")
        self._paths: dict = {}
        self._onsets: dict = {}
        self._check_topology()
        try:  # the static path (cached for later): a bar and load it cannot follow are refused here
            with np.errstate(over="ignore", invalid="ignore", divide="ignore"):  # (checked finite below)
                a_min, _, a_g, F_g, K_slip, K = self._path(0.0)
        except FloatingPointError as exc:
            raise ValueError(f"bar, load: {exc} (bar={bar!r}, lambda L={bar.lam * bar.L:.4g}, "
                             f"load={self.load!r})") from None
        with np.errstate(over="ignore", invalid="ignore"):
            span = (a_min, a_g, F_g, K * a_g, K_slip * a_g)
        if not all(math.isfinite(v) for v in span):  # k of 1e-300, a load of 1e300: past double precision
            raise ValueError(f"bar, load: the slip amplitudes and forces leave double precision (a_min = "
                             f"{a_min:.4g} m, gross slip at {a_g:.4g} m, k* a_gross = {K * a_g:.4g} N); mu q/k and "
                             f"k* mu q/k must stay well below 1e308 (bar={bar!r}, load={self.load!r})")

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
            check_phase(self.bar, key)
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
        x = finite_array("x", x)
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
        x = finite_array("x", x)
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
        theta = np.linspace(-0.5 * np.pi, 1.5 * np.pi, count("n", n, 2))
        x = a * np.sin(theta)
        up = theta <= 0.5 * np.pi
        s = np.where(up, 0.5 * (a + x), 0.5 * (a - x))
        L1, L2 = self.boundaries(s, omega)
        return theta, L1, L2

    # ------------------------------------------------------------ interface
    def _check_range(self, a, omega):
        """Warn (``ModelRangeWarning``) outside the single-mode range (``contact_models.model_range``)."""
        check_single_mode(self, a, omega, stacklevel=4)

    def _refined_model(self):
        """The all-mode bar of the same bar and load (every mode, the phase along the bar)."""
        return AllModeMicroslip(self.bar, self.load)

    def harmonics_law(self):
        """The quasi-static bar (``QuasiStatic``): its Masing loop carries this bar's higher force
        harmonics to order (omega/omega_c)^2, which this first-harmonic element does not give."""
        return QuasiStatic(self)

    def _model_error(self, a, omega):
        """The validity map's errors of F_s and F_c against the all-mode bar (``contact_models.model_range``)."""
        return single_mode_error(self, a, omega, "s"), single_mode_error(self, a, omega, "c")

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
            check_phase(self.bar, omega)  # once per frequency (cached): nothing on the hot path
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
    at every amplitude up to omega_1 (``model_range.single_mode_frequency_limit``; lower for stiffer
    shear layers, larger lambda L) and grows roughly like (omega/omega_c)^2 beyond, the single-mode
    solution being exact at omega = 0 (the values per bar: ``docs/validation.md``, "Where the
    single-mode model holds (the validity map)").  ``fourier`` and ``fourier_derivatives``
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

    Range (validity map, docs/validation.md, "Where the single-mode model holds (the validity
    map)"): as ``TwoRegionMicroslip``, mapped with the ratio-12 concave load: within 1 % at every
    amplitude up to omega_1 (``model_range.single_mode_frequency_limit``); warns
    (``ModelRangeWarning``) where the map's error exceeds 1 %.

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
