"""The all-mode dynamic microslip bar in the frequency domain (the paper's future work).

``AllModeMicroslip`` is the bar of Eq. 30 with every mode: the same finite-element bar as
``NumericalMicroslip`` (``numerics.fe_bar``: n equal cells, lumped mass rho A c_i, a Jenkins element of
stiffness k c_i and slip force mu q(x_i) c_i at node i, the beta spring at node 0, node n
driven), but solved for its steady periodic state directly, by multi-harmonic balance with
alternating frequency-time (AFT) at the nodes, instead of integrated in time.  It resolves the
phase differences along the bar that the single-mode elements (``TwoRegionMicroslip``,
``ThreeRegionMicroslip``) neglect, works for any normal load (any number of stick and slip
regions) and any frequency, including above the cut-off sqrt(k/(rho A)).

Model.  Free nodes i = 0..n-1 with harmonic coefficients U_i (layout ``[U0, Uc1, Us1, ...]``,
H harmonics), driven node U_n = X (the end displacement, ``a sin(theta)`` for ``fourier``):

    R_i = (K_ii - (h omega)^2 m_i) U_i + K_off (U_{i-1} + U_{i+1}) + T_i(U_i) = 0,

with (h omega)^2 acting per harmonic h, K the tridiagonal axial stiffness (beta in K_00) and
T_i = P tau_i(E U_i) the harmonic coefficients of node i's periodic Jenkins force (exact
return map marched from the sample of the global maximum, ``_hbal.jenkins_periodic``).  The
end force ``EA u_x(L)`` is the driven node's reaction,

    F = K_nn X + K_off U_{n-1} + T_n(X) - (h omega)^2 m_n X.

Solution.  Newton's method on R (piecewise linear in U for a fixed stick/slip pattern, so it
ends exactly once the pattern settles) with an Armijo backtracking line search; the Jacobian
is block tridiagonal (diagonal blocks (2H+1)^2 from AFT, off-diagonal K_off I) and is solved
by block Thomas elimination in O(n H^3).  The derivatives of F follow from the implicit
function theorem at the converged Jacobian: only node n-1 couples to X, so
``dF/dX = K_nn - (h omega)^2 m_n + dT_n/dX - K_off^2 C_{n-1}^{-1}`` with C_{n-1} the last
pivot block of the elimination, and ``dF/domega = -2 omega h^2 m_n X + K_off dU_{n-1}/domega``
with ``J dU/domega = 2 omega h^2 m U``.  The last solution is cached and warm-starts the next
call (along amplitude and frequency); a failed Newton run falls back to continuation in the
amplitude from the exactly linear (stuck) state.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .numerics.fe_bar import _Discretisation
from ._hbal import BlockTridiagonal, aft_matrices, jenkins_harmonic, jenkins_periodic
from .numerics.checks import count, nonnegative, positive
from .bar import Bar
from .base import DEFAULT_RTOL, ContactElement

if TYPE_CHECKING:
    from .loads import QuadraticLoad, UniformLoad

__all__ = ["AllModeMicroslip", "AllModeSolution", "CELLS", "HARMONICS", "SAMPLES_PER_HARMONIC", "NEWTON_TOL",
           "NEWTON_MAX_ITER"]

#: Default number of cells.
CELLS = 40
#: Default number of harmonics H.
HARMONICS = 15
#: Default time samples per harmonic (n_t = SAMPLES_PER_HARMONIC * H, rounded up to a multiple of 4).
SAMPLES_PER_HARMONIC = 8
#: Newton stops when the residual is below this fraction of the bar's force scale.
NEWTON_TOL = 1e-11
#: Newton iteration limit (per solve, before the continuation fallback).
NEWTON_MAX_ITER = 40


@dataclass
class AllModeSolution:
    """Steady periodic state of the all-mode bar for one end displacement and frequency.

    ``X``: the end displacement's coefficients (2H+1, layout ``[X0, Xc1, Xs1, ...]``), ``omega``
    (rad/s), ``F``: the end force's coefficients (N), ``U``: every node's coefficients
    (n + 1, 2H+1; row n is X), ``dF_dX`` (2H+1, 2H+1) and ``dF_domega`` (2H+1) by the implicit
    function theorem, ``slip`` (n + 1, n_t): where each node slips at theta_k = 2 pi k/n_t.
    ``decay``: max(|F_H|, |F_{H-1}|) / |F_1|, the size of the last harmonics kept relative to
    the first (a truncation indicator; two because even harmonics vanish for a symmetric drive); ``error``: the error estimate of (F_s, F_c) in N from
    ``AllModeMicroslip.solve`` with ``estimate_error=True`` (None otherwise) and
    ``error_parts`` its parts (``"cells"``: Richardson estimate from the half-cells solution,
    ``"harmonics"``: change from H to ceil(H/2) harmonics).
    """

    X: NDArray[np.float64]
    omega: float
    F: NDArray[np.float64]
    U: NDArray[np.float64]
    dF_dX: NDArray[np.float64]
    dF_domega: NDArray[np.float64]
    slip: NDArray[np.bool_]
    success: bool
    message: str
    iterations: int
    decay: float
    error: float | None = None
    error_parts: dict = field(default_factory=dict)

    @property
    def f_s(self) -> float:
        """First-harmonic sine coefficient of the end force (N)."""
        return float(self.F[2])

    @property
    def f_c(self) -> float:
        """First-harmonic cosine coefficient of the end force (N)."""
        return float(self.F[1])

    @property
    def harmonics(self) -> NDArray[np.complex128]:
        """Complex coefficients c_h = F_c,h - i F_s,h of the end force, h = 0..H."""
        return np.concatenate([[self.F[0]], self.F[1::2] - 1j * self.F[2::2]])


class _Basis(NamedTuple):
    """The harmonic coefficients solved for: ``idx`` into the full layout, AFT matrices on them."""

    H: int
    odd: bool
    idx: NDArray[np.intp]
    E: NDArray[np.float64]
    P: NDArray[np.float64]
    order: NDArray[np.float64]

    @property
    def key(self):
        return (self.H, self.odd)


class _Eval(NamedTuple):
    """One evaluation of the bar's balance at U."""

    U: NDArray[np.float64]
    R: NDArray[np.float64]
    res: float
    T: NDArray[np.float64]
    J: NDArray[np.float64]
    slip: NDArray[np.bool_]
    lin: NDArray[np.float64]


class AllModeMicroslip(ContactElement):
    """Microslip bar of Eq. 30 with every mode, solved in the frequency domain.

    Parameters
    ----------
    bar : Bar
        The damper bar.
    load : UniformLoad, QuadraticLoad, FunctionLoad or SampledLoad
        Normal load q(x) >= 0 (any shape: any number of stick and slip regions).
    cells : int, optional
        Linear finite elements along the bar (default ``CELLS`` = 40); error O(cells^-2).
    harmonics : int, optional
        Harmonics H kept in every node's motion (default ``HARMONICS`` = 15).
    n_t : int, optional
        Time samples per period of the AFT, a multiple of 4 and >= 2H + 2 (default
        ``SAMPLES_PER_HARMONIC * H`` rounded up to a multiple of 4).

    Notes
    -----
    The model and the solution are in the module docstring and ``docs/theory.md`` (section
    "The all-mode bar").  Accuracy against converged time integration and the cost of each
    knob: ``docs/validation.md`` and ``docs/performance.md``.  The steady state of a node that
    never slips is taken with its slider at the centre of its motion (the Masing convention;
    the symmetric state for the drive ``a sin(theta)``).
    ``fourier``'s ``rtol`` is not used: Newton converges to rounding (relative residual 1e-11),
    and the accuracy is set by ``cells``, ``harmonics`` and ``n_t`` (``solve(...,
    estimate_error=True)`` estimates it).  ``fourier`` raises FloatingPointError where the
    balance does not converge; ``solve`` reports it in ``success`` and ``message``.

    Raises
    ------
    ValueError
        ``bar`` not a ``Bar``; ``cells``, ``harmonics`` or ``n_t`` out of range; a load below 0.

    Examples
    --------
    >>> from contact_models import AllModeMicroslip, Bar, UniformLoad
    >>> bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    >>> el = AllModeMicroslip(bar, UniformLoad(N=100.0), cells=20, harmonics=7)
    >>> fs, fc = el.fourier(3 * 7.5e-7, 0.0)
    >>> round(float(fs) / (bar.k_star * 3 * 7.5e-7), 2), round(float(fc) / (bar.k_star * 3 * 7.5e-7), 2)
    (0.75, 0.15)
    """

    #: It owns a force law for any periodic end motion (a nested harmonic balance), so the
    #: multi-harmonic solver may use it at H > 1 (it implements the hook ``_harmonic_force``).
    has_time_law = True

    def __init__(self, bar: Bar, load: UniformLoad | QuadraticLoad, cells: int = CELLS, *,
                 harmonics: int = HARMONICS, n_t: int | None = None) -> None:
        if not isinstance(bar, Bar):
            raise ValueError(f"bar must be a contact_models.Bar, got bar={bar!r}")
        self.cells = count("cells", cells, 2)
        self.harmonics = count("harmonics", harmonics, 1)
        if n_t is None:
            n_t = 4 * math.ceil(SAMPLES_PER_HARMONIC * self.harmonics / 4)
        if isinstance(n_t, bool) or int(n_t) != n_t or n_t % 4 or n_t < 2 * self.harmonics + 2:
            raise ValueError(f"n_t must be a multiple of 4 and >= 2 harmonics + 2 = {2 * self.harmonics + 2}, "
                             f"got n_t={n_t!r}")
        self.n_t = int(n_t)
        self.bar = bar
        self.load = load.on(bar.L)
        if self.load.minimum() < 0.0:
            raise ValueError(f"load must be >= 0 everywhere, got load={load!r}")
        self._disc = _Discretisation(bar, self.load, self.cells)
        self._aft: dict = {}
        self._cache: dict = {}  # (H, odd) -> (X, omega, U) of the last converged solve

    def __repr__(self) -> str:
        return (f"AllModeMicroslip({self.bar!r}, {self.load!r}, cells={self.cells}, "
                f"harmonics={self.harmonics}, n_t={self.n_t})")

    # ------------------------------------------------------------ extras
    @property
    def nodes(self) -> NDArray[np.float64]:
        """Node positions x_i (m)."""
        return self._disc.x.copy()

    def solve(self, a: float | ArrayLike, omega: float = 0.0, *, estimate_error: bool = False) -> AllModeSolution:
        """Steady periodic state of the bar for a driven-end displacement.

        Parameters
        ----------
        a : float or array_like
            An amplitude (m) for ``a sin(theta)``, or end-displacement coefficients (m) of length
            2H'+1, layout ``[X0, Xc1, Xs1, ...]``, H' <= ``harmonics``.
        omega : float
            Frequency (rad/s), >= 0.
        estimate_error : bool
            Also solve with half the cells and with ceil(H/2) harmonics and fill ``error`` (N, on
            (f_s, f_c): the larger of the two parts) and ``error_parts``.  Default False.

        Returns
        -------
        AllModeSolution
            End force harmonics, nodal coefficients, derivatives, slip map, ``success``, ``message``.

        Raises
        ------
        ValueError
            ``a`` or ``omega`` negative, not finite, or ``a`` of a bad length.

        Examples
        --------
        >>> from contact_models import AllModeMicroslip, Bar, UniformLoad
        >>> bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
        >>> sol = AllModeMicroslip(bar, UniformLoad(N=100.0), cells=20, harmonics=7).solve(
        ...     3 * 7.5e-7, 0.5 * bar.omega_c, estimate_error=True)
        >>> sol.success, round(sol.f_c / (bar.k_star * 3 * 7.5e-7), 3), sol.error < 1e-3 * bar.k_star * 3 * 7.5e-7
        (True, 0.19, True)
        """
        omega = nonnegative("omega", omega)
        X = self._end_vector(a)
        sol = self._solve(X, omega, self.harmonics, odd=self._is_odd(X))
        if estimate_error and sol.success:
            sol.error_parts = self._error_parts(X, omega, sol)
            sol.error = max(sol.error_parts.values())
        return sol

    def _harmonic_force(self, X: NDArray[np.float64], omega: float, n_t: int, rtol: float
                        ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """End force coefficients ``F`` (2H+1), ``dF/dX`` (2H+1, 2H+1) and ``dF/domega`` (2H+1)
        for the end displacement coefficients ``X`` (length 2H+1, H >= 1) at ``omega`` (rad/s),
        checked by ``harmonic_force`` (or trusted by ``harmonic_force_unchecked``).

        The multi-harmonic hook (docs/extending.md, section 1, "Time laws") with a nested solve:
        the bar is solved with ``max(H, harmonics)`` harmonics (its internal motion needs its own
        resolution) and its own sample count (``n_t`` and ``rtol`` of the caller are accepted and
        not used: the nested AFT samples every node, and Newton converges to rounding); the result
        is truncated to H.  Derivatives by the implicit function theorem (exact for the discrete
        model).  Raises FloatingPointError when the nested solve fails (the solver's continuation
        then shortens its step).
        """
        H = (X.size - 1) // 2
        Hi = max(H, self.harmonics)
        Xp = np.pad(X, (0, 2 * (Hi - H)))
        odd = self._is_odd(Xp)
        sol = self._solve(Xp, float(omega), Hi, odd=odd)
        if not sol.success:  # numerical trouble, not bad input: a continuation shrinks its step on it
            raise FloatingPointError(f"AllModeMicroslip: {sol.message} (omega={omega!r}, X={X!r})")
        if odd:
            self._even_block(sol, Hi)
        m = 2 * H + 1
        return sol.F[:m].copy(), sol.dF_dX[:m, :m].copy(), sol.dF_domega[:m].copy()

    def _even_block(self, sol: AllModeSolution, H: int) -> None:
        """Fill the even-even block of ``sol.dF_dX`` for a half-wave symmetric solution solved in
        the odd basis.  There the Jacobian commutes with the half-period shift, so it is block
        diagonal in (odd, even) coefficients: F_even = 0, dF_even/dX_odd = dF_odd/dX_even = 0,
        dF_even/domega = 0, and dF_even/dX_even is the Schur complement of the even blocks of the
        full-basis Jacobian at the solution (one evaluation and one block elimination)."""
        d = self._disc
        b = self._basis(H, False)
        even = np.flatnonzero(b.order % 2 == 0)
        _, J, _ = jenkins_harmonic(sol.U, d.kc, d.p, b.E, b.P)
        Je = J[:, even][:, :, even]
        lin = d.kdiag[:, None] - sol.omega**2 * d.m[:, None] * b.order[None, even] ** 2
        fac = BlockTridiagonal(Je[:-1] + lin[:-1, :, None] * np.eye(even.size)[None], d.off)
        sol.dF_dX[np.ix_(even, even)] = np.diag(lin[-1]) + Je[-1] - d.off**2 * fac.inv[-1]

    def _periodic_force(self, x, omega):
        """The time law the multi-harmonic contract asks for (``periodic_force``): the steady end
        force for the sampled periodic end displacement ``x`` (n samples over one period), through
        the harmonics the samples carry (H = (n - 2) // 2): f = E F(P x), df/dx = E (dF/dX) P."""
        n = x.size
        H = max(1, (n - 2) // 2)
        E, P, _ = aft_matrices(H, n)
        F, J, _ = self._harmonic_force(P @ x, float(omega), n, DEFAULT_RTOL)
        return E @ F, E @ J @ P

    def stick_slip_map(self, a: float, omega: float = 0.0) -> tuple[NDArray[np.float64], NDArray[np.float64],
                                                                        NDArray[np.bool_]]:
        """``(theta, x, slip)``: where the bar slips over one cycle of ``a sin(theta)`` (``a`` in m,
        ``omega`` in rad/s): ``slip[i, k]`` is True when node ``x[i]`` (m) slips at
        ``theta[k] = 2 pi k / n_t`` (the return map clipped there).  Draws like the paper's
        Figs. 6-7 for any number of stick and slip regions (docs/validation.md, wavy load)."""
        sol = self.solve(a, omega)
        return 2.0 * np.pi * np.arange(self.n_t) / self.n_t, self.nodes, sol.slip

    # ------------------------------------------------------------ the solve
    def _basis(self, H: int, odd: bool) -> _Basis:
        """Harmonics 0..H, or only the odd ones: a drive with only odd harmonics (``a sin``) has a
        half-wave symmetric steady state (u(t + T/2) = -u(t) at every node: the equations are odd
        and invariant under the half-period shift), so the even coefficients vanish."""
        key = (H, odd)
        if key not in self._aft:
            n_t = self.n_t if H == self.harmonics else max(
                4 * math.ceil((2 * H + 2) / 4), 4 * math.ceil(self.n_t * H / self.harmonics / 4))
            E, P, order = aft_matrices(H, n_t)
            idx = np.flatnonzero(order % 2 == 1) if odd else np.arange(order.size)
            self._aft[key] = _Basis(H, odd, idx, E[:, idx], P[idx], order[idx])
        return self._aft[key]

    def _end_vector(self, a) -> NDArray[np.float64]:
        arr = np.asarray(a, dtype=float)
        if arr.ndim == 0:
            X = np.zeros(2 * self.harmonics + 1)
            X[2] = nonnegative("a", float(arr))
            return X
        if arr.ndim != 1 or arr.size % 2 == 0 or arr.size > 2 * self.harmonics + 1 or not np.all(np.isfinite(arr)):
            raise ValueError(f"a must be an amplitude or a finite coefficient vector of odd length <= "
                             f"{2 * self.harmonics + 1}, got a={a!r}")
        return np.pad(arr, (0, 2 * self.harmonics + 1 - arr.size))

    def _scale(self, X):
        d = self._disc
        return (abs(d.off) + float(np.max(d.kc))) * max(float(np.max(np.abs(X))), 1e-300) + float(np.max(d.p))

    def _evaluate(self, U, X, omega, b):
        """Residual R (n, s) at U (n, s) with the Jenkins forces and Jacobians of all n + 1 nodes,
        the slip masks and the linear part (X, U in the basis b of s coefficients)."""
        d = self._disc
        full = np.vstack([U, X[None, :]])
        T, J, slip = jenkins_harmonic(full, d.kc, d.p, b.E, b.P)
        lin = d.kdiag[:, None] - omega**2 * d.m[:, None] * b.order[None, :] ** 2  # (n+1, s)
        R = lin[:-1] * U + T[:-1]
        R[1:] += d.off * U[:-1]
        R[:-1] += d.off * U[1:]
        R[-1] += d.off * X
        return _Eval(U, R, float(np.max(np.abs(R))), T, J, slip, lin)

    def _linear_guess(self, X, omega, b):
        """All nodes stuck (Jenkins as springs k c_i at every harmonic): the exact state below slip."""
        d = self._disc
        diag = d.kdiag[:-1, None] + d.kc[:-1, None] - omega**2 * d.m[:-1, None] * b.order[None, :] ** 2
        off, n = d.off, d.n
        # per coefficient a tridiagonal solve, all at once (scalar Thomas)
        cp = np.empty_like(diag)
        y = np.zeros_like(diag)
        cp[0] = diag[0]
        y[-1] = -off * X
        for i in range(1, n):
            w = off / cp[i - 1]
            cp[i] = diag[i] - w * off
            y[i] -= w * y[i - 1]
        U = np.empty_like(y)
        U[-1] = y[-1] / cp[-1]
        for i in range(n - 2, -1, -1):
            U[i] = (y[i] - off * U[i + 1]) / cp[i]
        return U

    def _start(self, X, omega, b):
        """The better (smaller residual) of the linear state and the cached solution scaled to X."""
        best = self._evaluate(self._linear_guess(X, omega, b), X, omega, b)
        if b.key in self._cache:
            Xc, _, Uc = self._cache[b.key]
            s = float(np.linalg.norm(X)) / max(float(np.linalg.norm(Xc)), 1e-300)
            ev = self._evaluate(Uc * s, X, omega, b)
            if ev.res < best.res:
                best = ev
        return best

    def _newton(self, ev, X, omega, b, max_iter=NEWTON_MAX_ITER):
        """Damped Newton from the evaluation ``ev``: (last evaluation, its factorisation, converged,
        iterations).  Armijo backtracking on max|R|; accepted trials are reused."""
        tol = NEWTON_TOL * self._scale(X)
        for it in range(max_iter + 1):
            B = ev.J[:-1] + ev.lin[:-1, :, None] * np.eye(ev.lin.shape[1])[None]
            fac = BlockTridiagonal(B, self._disc.off)
            if ev.res <= tol or it == max_iter or not np.isfinite(ev.res):
                break
            dU = -fac.solve(ev.R)
            t = 1.0
            for _ in range(30):
                trial = self._evaluate(ev.U + t * dU, X, omega, b)
                if trial.res <= (1.0 - 1e-4 * t) * ev.res:
                    break
                t *= 0.5
            ev = trial
        return ev, fac, ev.res <= tol, it

    def _solve(self, X, omega, H, odd=False) -> AllModeSolution:
        """Steady state for the full-layout X (2H+1) at omega, in the odd basis if asked."""
        b = self._basis(H, odd)
        Xb = X[b.idx]
        ev, fac, ok, iters = self._newton(self._start(Xb, omega, b), Xb, omega, b)
        if not ok:
            ev, fac, ok, extra = self._continuation(Xb, omega, b)
            iters += extra
        return self._finish(ev, fac, X, Xb, omega, b, ok, iters)

    def _continuation(self, X, omega, b):
        """Scale the end motion from the linear (stuck) state up to X, halving steps on failure."""
        size = float(np.max(np.abs(X)))
        s = min(1.0, 0.5 * self._disc.slip_amplitude(omega) / size) if size > 0 else 1.0
        ev = self._evaluate(self._linear_guess(s * X, omega, b), s * X, omega, b)
        ds, total, fac, ok = s, 0, None, True
        while s < 1.0:
            s_new = min(1.0, s + ds)
            start = self._evaluate(ev.U * (s_new / s), s_new * X, omega, b)
            ev_t, fac_t, ok_t, it = self._newton(start, s_new * X, omega, b, max_iter=15)
            total += it
            if ok_t:
                ev, fac, s = ev_t, fac_t, s_new
                ds *= 1.5
            else:
                ds *= 0.5
                if ds < 1e-6:
                    ok = False
                    break
        if fac is None:
            ev, fac, ok, it = self._newton(ev, X, omega, b)
            total += it
        return ev, fac, ok and s >= 1.0, total

    def _finish(self, ev, fac, X, Xb, omega, b, ok, iters) -> AllModeSolution:
        d = self._disc
        U, T, J, lin = ev.U, ev.T, ev.J, ev.lin
        full = 2 * b.H + 1
        Fb = lin[-1] * Xb + d.off * U[-1] + T[-1]
        dF_dXb = np.diag(lin[-1]) + J[-1] - d.off**2 * fac.inv[-1]
        dU_dw = fac.solve(2.0 * omega * d.m[:-1, None] * b.order[None, :] ** 2 * U)
        dF_dwb = -2.0 * omega * d.m[-1] * b.order**2 * Xb + d.off * dU_dw[-1]
        F = np.zeros(full)
        F[b.idx] = Fb
        dF_dX = np.zeros((full, full))
        dF_dX[np.ix_(b.idx, b.idx)] = dF_dXb
        dF_dw = np.zeros(full)
        dF_dw[b.idx] = dF_dwb
        Ufull = np.zeros((d.n + 1, full))
        Ufull[:-1, b.idx] = U
        Ufull[-1] = X
        F1 = math.hypot(F[1], F[2])
        FH = max(math.hypot(F[-2], F[-1]), math.hypot(F[-4], F[-3]) if b.H >= 2 else 0.0)
        decay = FH / F1 if F1 > 0 else 0.0
        ok = bool(ok and np.all(np.isfinite(F)) and np.all(np.isfinite(dF_dX)))
        if ok:
            self._cache[b.key] = (Xb.copy(), omega, U.copy())
        msg = "converged" if ok else f"Newton did not converge (residual {ev.res:.3g} N)"
        return AllModeSolution(X=X.copy(), omega=omega, F=F, U=Ufull, dF_dX=dF_dX, dF_domega=dF_dw,
                               slip=ev.slip, success=ok, message=msg, iterations=iters, decay=decay)

    @staticmethod
    def _is_odd(X):
        return not np.any(X[0::4]) and not np.any(X[3::4])  # h = 0, 2, 4, ... sit at 0, 3, 4, 7, 8, ...

    def _error_parts(self, X, omega, sol):
        parts = {}
        if self.cells >= 4:
            coarse = AllModeMicroslip(self.bar, self.load, self.cells // 2, harmonics=self.harmonics, n_t=self.n_t)
            c = coarse._solve(X, omega, self.harmonics, odd=self._is_odd(X))
            parts["cells"] = float(np.max(np.abs(c.F[1:3] - sol.F[1:3]))) / 3.0
        Hh = max(1, math.ceil(self.harmonics / 2))
        if Hh < self.harmonics:
            h = self._solve(X[: 2 * Hh + 1], omega, Hh, odd=self._is_odd(X))
            parts["harmonics"] = float(np.max(np.abs(h.F[1:3] - sol.F[1:3])))
        return parts

    # ------------------------------------------------------------ interface
    def _stuck_stiffness(self, omega):
        return float(self._disc.stuck_solution(omega)[1])

    def _slip_amplitude(self, omega):
        return self._disc.slip_amplitude(omega)

    def _fourier_derivatives(self, a, omega, rtol):
        fs, fc, dfs, dfc = (np.zeros_like(a) for _ in range(4))
        for w in np.unique(omega):
            sel = np.flatnonzero(omega == w)
            sel = sel[np.argsort(a[sel])]
            a_lin = self._slip_amplitude(float(w))
            K = self._stuck_stiffness(float(w))
            for i in sel:
                if a[i] <= a_lin:
                    fs[i], dfs[i] = K * a[i], K
                    continue
                X = np.zeros(2 * self.harmonics + 1)
                X[2] = a[i]
                sol = self._solve(X, float(w), self.harmonics, odd=True)
                if not sol.success:
                    raise FloatingPointError(f"AllModeMicroslip: {sol.message} at a={a[i]!r}, omega={w!r}")
                fs[i], fc[i] = sol.f_s, sol.f_c
                dfs[i], dfc[i] = sol.dF_dX[2, 2], sol.dF_dX[1, 2]
        return fs, fc, dfs, dfc

    def _hysteresis(self, a, omega, n):
        theta = np.linspace(-0.5 * np.pi, 1.5 * np.pi, n)
        x = a * np.sin(theta)
        if a <= self._slip_amplitude(omega):
            return x, self._stuck_stiffness(omega) * x
        sol = self.solve(a, omega)
        d, H = self._disc, self.harmonics
        # end force in time: axial term from node n-1's series, tip Jenkins marched on x itself
        Ef = np.ones((n, 2 * H + 1))
        hth = np.outer(theta, np.arange(1, H + 1))
        Ef[:, 1::2], Ef[:, 2::2] = np.cos(hth), np.sin(hth)
        u_prev = Ef @ sol.U[-2]
        tau, *_ = jenkins_periodic(x[None, :-1], d.kc[-1:], d.p[-1:])
        tau = np.append(tau[0], tau[0, 0])
        f = -d.off * (x - u_prev) + tau - d.m[-1] * omega**2 * x
        return x, f
