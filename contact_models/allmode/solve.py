"""One discretisation of the all-mode bar solved by multi-harmonic balance (``AllModeMicroslip``).

``FixedBar(bar, load, cells, harmonics, n_t)`` is the bar on ``cells`` equal cells with ``harmonics``
harmonics and ``n_t`` AFT samples: the balance, its Newton solve with warm starts, the continuation
fallback and the derivatives by the implicit function theorem (the model and the solution are in
``contact_models.allmode``'s docstring).  ``AllModeMicroslip`` holds one ``FixedBar`` per level of
its ladder of cells and harmonics and chooses among them (``contact_models.allmode.accuracy``).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Callable, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..numerics.checks import nonnegative
from ..numerics.fe_bar import _Discretisation
from .balance import (BANDED_MAX_BLOCK, aft_matrices, half_products, jacobian_prefix, jenkins_harmonic, jenkins_jacobian,
                      jenkins_periodic, jenkins_state, kernel_constants, same_jacobian, scalar_tridiagonal)
from .compiled import kernel, numpy_clock, numpy_spent
from .coupled import Coupled, residual_rate, stuck_prefix, with_diagonal
from .segments import Segments

if TYPE_CHECKING:
    from ..bar import Bar
    from ..loads import QuadraticLoad, UniformLoad

Array = NDArray[np.float64]

#: Newton stops when the residual is below this fraction of the bar's force scale.
NEWTON_TOL = 1e-11
#: Newton iteration limit (per solve, before the continuation fallback).
NEWTON_MAX_ITER = 40
#: A cached solution moved along its tangent to the new end motion and frequency
#: (``FixedBar.tangent_guess``) whose residual is below this fraction of the force scale starts
#: Newton without the linear state being evaluated too: where the bar slips the linear state is
#: far from the solution, so a tangent start this close is the better start and evaluating the
#: linear state as well would only cost a residual (docs/theory.md, "The all-mode bar in the
#: frequency domain", "Error estimate").
START_CLOSE = 1e-6
#: A start whose residual is below this fraction of the force scale is the solution to rounding and
#: is kept without a Newton step (the tangent start where no sample changes between stick and slip,
#: the linear state of a stuck bar); any other takes at least one step, so that a start just inside
#: ``NEWTON_TOL`` is not kept as it is (its error would show in finite differences of the force).
START_EXACT = 1e-13


@dataclass
class AllModeSolution:
    """Steady periodic state of the all-mode bar for one end displacement and frequency.

    ``X``: the end displacement's coefficients (2H+1, layout ``[X0, Xc1, Xs1, ...]``), ``omega``
    (rad/s), ``F``: the end force's coefficients (N), ``U``: every node's coefficients
    (n + 1, 2H+1; row n is X), ``dF_dX`` (2H+1, 2H+1) and ``dF_domega`` (2H+1) by the implicit
    function theorem, ``slip`` (n + 1, n_t): where each node slips at theta_k = 2 pi k/n_t.
    ``decay``: max(|F_H|, |F_{H-1}|) / |F_1|, the size of the last harmonics kept relative to
    the first (a truncation indicator; two because even harmonics vanish for a symmetric drive).
    ``cells``, ``H``: the discretisation this solution is on.  ``error``: the estimate of the
    error of (F_s, F_c) in N (the larger component of the sum of its parts), ``relative_error``:
    the same relative to max(|F|, 0.01 k* a) component by component (as ``tol``), and
    ``error_parts``: ``"cells"`` (Richardson in cells with the observed order; below 128 cells
    against the rung above, ``accuracy.cells_error``) and
    ``"harmonics"`` (the same in H), in N; None and empty when not estimated.  ``error_components``:
    the sum of the parts on (F_c, F_s) in N (the components of ``error``).
    """

    X: NDArray[np.float64]
    omega: float
    F: NDArray[np.float64]
    U: NDArray[np.float64]
    dF_dX: NDArray[np.float64] | None
    dF_domega: NDArray[np.float64] | None
    slip: NDArray[np.bool_]
    success: bool
    message: str
    iterations: int
    decay: float
    cells: int = 0
    H: int = 0
    error: float | None = None
    relative_error: float | None = None
    error_parts: dict = field(default_factory=dict)
    error_components: NDArray[np.float64] | None = None

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
    """The harmonic coefficients solved for: ``idx`` into the full layout, AFT matrices on them and
    their ``jacobian_prefix`` (kept: it depends on the basis only)."""

    H: int
    odd: bool
    idx: NDArray[np.intp]
    E: NDArray[np.float64]
    P: NDArray[np.float64]
    order: NDArray[np.float64]
    prefix: tuple
    flat: NDArray[np.intp]  #: the (idx, idx) block's entries in the flattened full-layout matrix, row by row


class _Eval(NamedTuple):
    """One evaluation of the bar's balance at U (``J`` None until asked for: ``state`` the return
    map's result it is computed from, ``FixedBar.with_jacobian``; None where a subclass's node law
    keeps none, which then evaluates again)."""

    U: NDArray[np.float64]
    R: NDArray[np.float64]
    res: float
    T: NDArray[np.float64]
    J: NDArray[np.float64] | None
    slip: NDArray[np.bool_]
    lin: NDArray[np.float64]
    state: tuple | None = None


@functools.lru_cache(maxsize=32)
def shared_basis(H: int, n_t: int, odd: bool) -> _Basis:
    """The :class:`_Basis` of H harmonics (odd ones only if ``odd``) on n_t samples, built once per
    process for every bar of that H and n_t (its arrays are read-only)."""
    E, P, order = aft_matrices(H, n_t)
    idx = np.flatnonzero(order % 2 == 1) if odd else np.arange(order.size)
    Eb, Pb = E[:, idx], P[idx]
    flat = (idx[:, None] * order.size + idx[None, :]).ravel()
    basis = _Basis(H, odd, idx, Eb, Pb, order[idx], jacobian_prefix(Eb, Pb), flat)
    for a in (idx, Eb, Pb, basis.order, *basis.prefix, flat):
        a.flags.writeable = False
    return basis


def aft_products(b: _Basis) -> tuple[Array, Array]:
    """The synthesis and analysis the compiled residual takes for the basis ``b``: on half the samples in the odd
    basis (``balance.half_products``), else E^T and P^T."""
    return half_products(b.E, b.P) if b.odd else (b.E.T, b.P.T)


def scaled_samples(n_t: int, harmonics: int, H: int) -> int:
    """The samples of a bar of H harmonics where ``n_t`` was given for ``harmonics``: n_t itself at that
    H, else n_t scaled with H (a multiple of 4, at least 2H + 2)."""
    if H == harmonics:
        return n_t
    return max(4 * math.ceil((2 * H + 2) / 4), 4 * math.ceil(n_t * H / harmonics / 4))


#: The largest bar an element is built on, in entries of its block-tridiagonal balance: cells times
#: max((2H + 1)^2, n_t), the memory of one solve growing with it (2**28 entries take a few GB).
MAX_MESH = 2**28


def checked_mesh(cells: int, harmonics: int, n_t: int, given: str) -> None:
    """Refuse a bar of ``cells`` cells, ``harmonics`` H and ``n_t`` samples above ``MAX_MESH`` (the most an
    element may climb to where it chooses them), naming what was ``given`` and the bound: a request that
    would exhaust the memory of the process is refused when the element is built, never killed later."""
    size = cells * max((2 * harmonics + 1) ** 2, n_t)
    if size > MAX_MESH:
        raise ValueError(f"{given}: a bar of {cells} cells at H = {harmonics} with {n_t} samples has "
                         f"cells * max((2H + 1)^2, n_t) = {size:.3g} entries, more than {MAX_MESH:.3g} (the bound "
                         "is contact_models.allmode.solve.MAX_MESH: raise it to go further); give fewer cells or "
                         "harmonics")


def checked_samples(n_t: int | None, harmonics: int | None, default: Callable[[int], int]) -> int | None:
    """An element's ``n_t``: as given (a multiple of 4, at least 2 ``harmonics`` + 2), ``default(harmonics)`` where
    only ``harmonics`` is given, None where neither is; ValueError naming ``n_t`` otherwise."""
    if n_t is not None and harmonics is None:
        raise ValueError(f"n_t is tied to H where harmonics are chosen: give harmonics with it, got n_t={n_t!r}")
    if harmonics is not None and n_t is None:
        return default(harmonics)
    if n_t is not None and (isinstance(n_t, bool) or int(n_t) != n_t or n_t % 4 or n_t < 2 * harmonics + 2):
        raise ValueError(f"n_t must be a multiple of 4 and >= 2 harmonics + 2 = {2 * harmonics + 2}, got n_t={n_t!r}")
    return None if n_t is None else int(n_t)


def end_vector(a: float | ArrayLike, H: int) -> NDArray[np.float64]:
    """An element's end motion: coefficients [0, 0, a] for an amplitude ``a`` (``a sin``), or ``a`` as given (odd
    length at most 2H + 1, finite); ValueError naming ``a`` otherwise."""
    arr = np.asarray(a, dtype=float)
    if arr.ndim == 0:
        return np.array([0.0, 0.0, nonnegative("a", float(arr))])
    if arr.ndim != 1 or arr.size % 2 == 0 or arr.size > 2 * H + 1 or not np.all(np.isfinite(arr)):
        raise ValueError(f"a must be an amplitude or a finite coefficient vector of odd length <= {2 * H + 1}, "
                         f"got a={a!r}")
    return arr.copy()


def pad_harmonics(X: NDArray[np.float64], H: int) -> NDArray[np.float64]:
    """The coefficients ``X`` (layout [X0, Xc1, Xs1, ...]) on H harmonics: zeros added, or cut."""
    if X.size >= 2 * H + 1:
        return X[: 2 * H + 1]
    out = np.zeros(2 * H + 1)  # (np.pad costs ten times as much on these short vectors)
    out[: X.size] = X
    return out


def transferred(U: NDArray[np.float64], cells: int, H: int) -> NDArray[np.float64]:
    """Nodal coefficients ``U`` (n + 1 nodes, full layout) of one rung moved to another of ``cells`` cells and
    H harmonics: linear in x between the nodes, harmonics cut or zeros added.  Newton's start on a rung an
    estimate reads at the same motion and frequency (``FixedBar.solve``'s ``guess``)."""
    n = U.shape[0] - 1
    pos = np.arange(cells + 1) * (n / cells)
    i = np.minimum(pos.astype(np.intp), n - 1)
    w = (pos - i)[:, None]
    k = min(U.shape[1], 2 * H + 1)
    out = np.zeros((cells + 1, 2 * H + 1))
    out[:, :k] = (1.0 - w) * U[i, :k] + w * U[i + 1, :k]
    return out


#: Even coefficients of an end motion at most this fraction of its largest coefficient are rounding:
#: a balance that carries harmonics 0..H (H > 1) of a half-wave symmetric response returns its even
#: coefficients at rounding of the first harmonic (its linear solves mix them), never exactly 0.
#: Solved in the full basis, such a motion costs the bar about twice the AFT and eight times the
#: block elimination of the odd basis (63 against 32 coefficients a node at H = 31).
EVEN_ROUNDING = 1e-12


def even_part(X: NDArray[np.float64]) -> NDArray[np.float64]:
    """``X`` (layout [X0, Xc1, Xs1, ...]) with its odd-harmonic coefficients set to 0."""
    Xe = np.zeros_like(X)
    Xe[0::4], Xe[3::4] = X[0::4], X[3::4]
    return Xe


def is_odd(X: NDArray[np.float64], rtol: float = 0.0) -> bool:
    """True when the coefficients ``X`` hold odd harmonics only (h = 0, 2, 4, ... sit at 0, 3, 4, 7, 8,
    ...): every even coefficient at most ``rtol`` times the largest coefficient (``rtol=0``: exactly 0)."""
    even = np.abs(even_part(X))
    return not np.any(even > rtol * float(np.max(np.abs(X), initial=0.0)))


class FixedBar:
    """The bar on ``cells`` cells with ``harmonics`` harmonics and ``n_t`` samples (inputs checked by
    the caller); ``solve(X, omega, odd)`` with X of length 2 harmonics + 1."""

    #: Evaluations keep the return map's state and get their Jacobians only when used (a subclass
    #: whose ``evaluate`` keeps no state sets it False: its evaluations then carry their Jacobians).
    lazy_jacobian = True

    def __init__(self, bar: Bar, load: UniformLoad | QuadraticLoad, cells: int, harmonics: int, n_t: int,
                 linear: str = "exact") -> None:
        self.cells, self.H, self.n_t = cells, harmonics, n_t
        self.bar, self.linear_kind = bar, linear
        self.disc = _Discretisation(bar, load, cells)
        self._linear: dict = {}  # (omega, basis key) -> LinearPart, the last few
        self._segments: dict = {}  # basis key -> segments.Segments
        d = self.disc
        self._scale = (abs(d.off) + float(np.max(d.kc)), float(np.max(d.p)))
        self._aft: dict = {}
        self._cache: dict = {}  # odd -> (X, omega, U, J's factorisation) of the last converged solve
        self._even: tuple | None = None  # the even coefficients: (idx, E, P, jacobian_prefix)
        self._last: tuple = (None, None)  # (the last solution in the odd basis, its return map's state)

    def basis(self, odd: bool) -> _Basis:
        """Harmonics 0..H, or only the odd ones: a drive with only odd harmonics (``a sin``) has a
        half-wave symmetric steady state (u(t + T/2) = -u(t) at every node: the equations are odd
        and invariant under the half-period shift), so the even coefficients vanish."""
        if odd not in self._aft:
            self._aft[odd] = shared_basis(self.H, self.n_t, odd)
        return self._aft[odd]

    def linear(self, omega: float, order: Array, key: object) -> tuple:
        """The bar's linear part (``segments.LinearPart``: lin, c, dlin, dc) at omega on the orders
        ``order`` (one basis, named by ``key``), kept for the last few frequencies."""
        k = (float(omega), key)
        part = self._linear.get(k)
        if part is None:
            if len(self._linear) >= 8:
                self._linear.clear()
            segments = self._segments.get(key)
            if segments is None:
                segments = self._segments[key] = Segments(self.bar, self.disc, order, self.linear_kind)
            part = self._linear[k] = segments.at(omega)
        return part

    def scale(self, X: Array) -> float:
        """The force scale of the end motion X (N): Newton's tolerance is ``NEWTON_TOL`` of it."""
        stiff, slip = self._scale
        return stiff * max(float(np.max(np.abs(X))), 1e-300) + slip

    def evaluate(self, U: Array, X: Array, omega: float, b: _Basis, jacobian: bool = True) -> _Eval:
        """Residual R (n, s) at U (n, s) with the Jenkins forces and Jacobians of all n + 1 nodes
        (None without ``jacobian``), the slip masks and the linear part (X, U in the basis b of s
        coefficients)."""
        d = self.disc
        lin, c = self.linear(omega, b.order, b.odd)[:2]  # (n+1, s), (s,)
        fused = kernel("residual")
        if fused is not None:  # the same operations in one compiled call
            ET, PT = aft_products(b)
            R, res, T, *state = fused(np.ascontiguousarray(U), X, lin, c, d.kc, d.p, ET, PT, b.odd)
            ev = _Eval(U, R, res, T, None, ~state[1], lin, tuple(state))
            return self.with_jacobian(ev, X, omega, b) if jacobian else ev
        full = np.vstack([U, X[None, :]])
        T, slip, state = jenkins_state(full, d.kc, d.p, b.E, b.P, b.odd)
        R = lin[:-1] * U + T[:-1]
        R[1:] += c * U[:-1]
        R[:-1] += c * U[1:]
        R[-1] += c * X
        ev = _Eval(U, R, float(np.max(np.abs(R))), T, None, slip, lin, state)
        return self.with_jacobian(ev, X, omega, b) if jacobian else ev

    def with_jacobian(self, ev: _Eval, X: Array, omega: float, b: _Basis, like: _Eval | None = None) -> _Eval:
        """``ev`` (at X, omega) with its Jacobians: from the return map's state it kept (no second
        march), or evaluated again where it kept none.  ``like``: an evaluation in the same basis
        with its Jacobians; where its stick/slip pattern (``jacobian_pattern``) is ``ev``'s, its
        Jacobians are ``ev``'s (the forces are piecewise linear) and are taken as they are."""
        if ev.J is not None:
            return ev
        if ev.state is None:
            return self.evaluate(ev.U, X, omega, b)
        if like is not None and like.J is not None and like.state is not None:
            if same_jacobian(like.state, ev.state):
                return ev._replace(J=like.J)
        return ev._replace(J=jenkins_jacobian(ev.state, self.disc.kc, b.E, b.P, b.prefix))

    def linear_guess(self, X: Array, omega: float, b: _Basis) -> Array:
        """All nodes stuck (Jenkins as springs k c_i at every harmonic): the exact state below slip."""
        d = self.disc
        lin, c = self.linear(omega, b.order, b.odd)[:2]
        diag = lin[:-1] + d.kc[:-1, None]
        if not np.any(c != c[0]):  # the lumped bar: one coupling
            return scalar_tridiagonal(diag, float(c[0]), -c[0] * X)  # per coefficient, all at once
        return scalar_tridiagonal(diag / c, 1.0, -X)  # each row divided by its coefficient's coupling

    def tangent_guess(self, X: Array, omega: float, b: _Basis) -> Array:
        """The cached solution U_c (at X_c, omega_c) moved along its tangent to (X, omega):
        U_c + (dU/dX) (X - X_c) + (dU/domega) (omega - omega_c), both derivatives from the cached
        factorisation of its Jacobian J (one block solve): J dU = -(omega - omega_c) dR/domega - e_(n-1) c
        (X - X_c), dR/domega = dlin U_c + dc (U_c's neighbours, X_c at the last node).  Exact while the
        samples' stick/slip pattern stays that of U_c (the forces are linear in U for a fixed pattern) and
        to first order in the frequency, so a continuation's next call often needs no Newton step."""
        Xc, wc, Uc, fac = self._cache[b.odd]
        _, c, dlin, dc = self.linear(wc, b.order, b.odd)
        rhs = (wc - omega) * residual_rate(dlin, dc, Uc, Xc)
        rhs[-1] -= c * (X - Xc)
        return Uc + fac.solve(rhs)

    def start(self, X: Array, omega: float, b: _Basis, guess: Array | None = None) -> _Eval:
        """The better (smaller residual) of the linear state and the cached solution moved along its
        tangent to (X, omega) (``tangent_guess``; compared on residuals alone; the Jacobian is
        evaluated for the one kept); the cached one alone where its residual is below
        ``START_CLOSE`` of the force scale.  With a ``guess`` (free nodes in the basis b), the better of
        it and the cached one, the cached one alone within ``START_CLOSE`` (the linear state is not tried)."""
        if guess is not None:  # (the cached one first: where it is within START_CLOSE, the guess is not evaluated)
            cached = None
            if b.odd in self._cache:
                cached = self.evaluate(self.tangent_guess(X, omega, b), X, omega, b, not self.lazy_jacobian)
                if cached.res <= START_CLOSE * self.scale(X):
                    return self.with_jacobian(cached, X, omega, b)
            ev = self.evaluate(guess, X, omega, b, not self.lazy_jacobian)
            return self.with_jacobian(cached if cached is not None and cached.res < ev.res else ev, X, omega, b)
        if b.odd in self._cache:
            cached = self.evaluate(self.tangent_guess(X, omega, b), X, omega, b, not self.lazy_jacobian)
            if cached.res <= START_CLOSE * self.scale(X):  # Newton's start: the linear state cannot do better
                return self.with_jacobian(cached, X, omega, b)
            ev = self.evaluate(self.linear_guess(X, omega, b), X, omega, b, not self.lazy_jacobian)
            return self.with_jacobian(cached if cached.res < ev.res else ev, X, omega, b)
        return self.evaluate(self.linear_guess(X, omega, b), X, omega, b)

    def newton(self, ev: _Eval, X: Array, omega: float, b: _Basis, max_iter: int = NEWTON_MAX_ITER,
               derivatives: bool = True) -> tuple:
        """Damped Newton from the evaluation ``ev``: (last evaluation, its factorisation, converged,
        iterations).  Armijo backtracking on max|R|; accepted trials are reused.  At least one step
        unless the start's residual is of rounding size (``START_EXACT``).  Without ``derivatives`` the
        last evaluation is not factorised (nor its Jacobian evaluated) where no step follows it: the
        factorisation returned is the last one made (None if none was)."""
        scale = self.scale(X)
        tol = NEWTON_TOL * scale
        fused = kernel("newton")
        if fused is not None and ev.J is not None and ev.state is not None and ev.U.shape[1] > BANDED_MAX_BLOCK:
            return self.compiled_newton(fused, ev, X, omega, b, max_iter, derivatives, scale)
        fac, J, prev = None, None, None
        for it in range(max_iter + 1):
            done = ev.res <= (tol if it else START_EXACT * scale) or it == max_iter or not np.isfinite(ev.res)
            if done and not derivatives:
                break
            if ev.J is None:  # an accepted trial: its Jacobian, or its predecessor's for the same pattern
                ev = self.with_jacobian(ev, X, omega, b, like=prev)
            if ev.J is not J:  # the same Jacobian (an unchanged stick/slip pattern) keeps its factorisation
                J = ev.J
                c = self.linear(omega, b.order, b.odd)[1]
                fac = Coupled.of(J, ev.lin, c, stuck_prefix(ev.state), not b.odd)
            if done:
                break
            dU = -fac.solve(ev.R)
            t = 1.0
            for _ in range(30):  # the Jacobian only for the trial accepted
                trial = self.evaluate(ev.U + t * dU, X, omega, b, not self.lazy_jacobian)
                if trial.res <= (1.0 - 1e-4 * t) * ev.res:
                    break
                t *= 0.5
            prev, ev = ev, trial
        return ev, fac, ev.res <= tol, it

    def compiled_newton(self, fused: object, ev: _Eval, X: Array, omega: float, b: _Basis, max_iter: int,
                        derivatives: bool, scale: float) -> tuple:
        """``newton`` in one compiled call (``compiled.newton``: the same steps and numbers) where the blocks
        are eliminated one by one and the start's Jacobian is known."""
        d = self.disc
        c = self.linear(omega, b.order, b.odd)[1]
        ET, PT = aft_products(b)
        E, P1, mean = kernel_constants(b.E, b.P)
        U, R, res, T, u, st, an, nv, J, has_J, inv_d, inv_v, inv, has_fac, bad, it, ok = fused(
            np.ascontiguousarray(ev.U), ev.R, ev.res, ev.T, *ev.state, ev.J, X, ev.lin, c, d.kc, d.p, ET, PT, b.odd,
            E, P1, mean, *b.prefix, NEWTON_TOL * scale, START_EXACT * scale, max_iter, not b.odd, derivatives)
        fac = Coupled.from_factors(inv_d, inv_v, inv, bad, c, not b.odd) if has_fac else None
        return _Eval(U, R, res, T, J if has_J else None, ~st, ev.lin, (u, st, an, nv)), fac, bool(ok), int(it)

    def solve(self, X: Array, omega: float, odd: bool = False, guess: Array | None = None,
              derivatives: bool = True) -> AllModeSolution:
        """Steady state for the full-layout X (2H+1) at omega, in the odd basis if asked; ``guess``: nodal
        coefficients (cells + 1 nodes, full layout, ``transferred``) to start Newton from.  Without
        ``derivatives`` the solution's ``dF_dX`` and ``dF_domega`` are None (an estimate's rungs read the force
        alone) and its last state is not factorised."""
        since = numpy_clock()  # its time counts towards loading the compiled kernels while they are not
        b = self.basis(odd)
        Xb = X[b.idx]
        start = self.start(Xb, omega, b, None if guess is None else np.ascontiguousarray(guess[:-1, b.idx]))
        ev, fac, ok, iters = self.newton(start, Xb, omega, b, derivatives=derivatives)
        if not ok:  # (the fallback's solution is factorised)
            ev, fac, ok, extra = self.continuation(Xb, omega, b)
            iters += extra
            derivatives = True
        sol = self.finish(ev, fac, X, Xb, omega, b, ok, iters, derivatives)
        if since is not None:
            numpy_spent(since)
        return sol

    def continuation(self, X: Array, omega: float, b: _Basis) -> tuple:
        """Scale the end motion from the linear (stuck) state up to X, halving steps on failure."""
        size = float(np.max(np.abs(X)))
        s = min(1.0, 0.5 * self.disc.slip_amplitude(omega) / size) if size > 0 else 1.0
        ev = self.evaluate(self.linear_guess(s * X, omega, b), s * X, omega, b)
        ds, total, fac, ok = s, 0, None, True
        while s < 1.0:
            s_new = min(1.0, s + ds)
            start = self.evaluate(ev.U * (s_new / s), s_new * X, omega, b)
            ev_t, fac_t, ok_t, it = self.newton(start, s_new * X, omega, b, max_iter=15)
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
            ev, fac, ok, it = self.newton(ev, X, omega, b)
            total += it
        return ev, fac, ok and s >= 1.0, total

    def finish(self, ev: _Eval, fac: object, X: Array, Xb: Array, omega: float, b: _Basis, ok: bool,
               iters: int, derivatives: bool = True) -> AllModeSolution:
        d = self.disc
        U, T, J, lin = ev.U, ev.T, ev.J, ev.lin
        _, c, dlin, dc = self.linear(omega, b.order, b.odd)
        full = 2 * b.H + 1
        Fb = lin[-1] * Xb + c * U[-1] + T[-1]
        if derivatives:
            dF_dXb = J[-1] - fac.coupled_last_inverse()
            dF_dXb.flat[:: dF_dXb.shape[0] + 1] += lin[-1]
            dU_dw = fac.solve(-residual_rate(dlin, dc, U, Xb))
            dF_dwb = dlin[-1] * Xb + dc * U[-1] + c * dU_dw[-1]
        else:
            dF_dXb = dF_dwb = None
        if b.odd:  # onto the full layout (the even coefficients 0; their block is ``even_block``'s)
            F = np.zeros(full)
            F[b.idx] = Fb
            dF_dX = dF_dw = None
            if derivatives:
                dF_dX = np.zeros((full, full))
                dF_dX.flat[b.flat] = dF_dXb
                dF_dw = np.zeros(full)
                dF_dw[b.idx] = dF_dwb
        else:
            F, dF_dX, dF_dw = Fb, dF_dXb, dF_dwb
        Ufull = np.empty((d.n + 1, full))
        if b.odd:
            Ufull[:-1] = 0.0
            Ufull[:-1, b.idx] = U
        else:
            Ufull[:-1] = U
        Ufull[-1] = X
        F1 = math.hypot(F[1], F[2])
        FH = max(math.hypot(F[-2], F[-1]), math.hypot(F[-4], F[-3]) if b.H >= 2 else 0.0)
        decay = FH / F1 if F1 > 0 else 0.0
        ok = bool(ok and np.isfinite(Fb).all() and (not derivatives or np.isfinite(dF_dXb).all()))
        if ok and fac is not None:  # (without derivatives, the last factorisation made: a start's guess only)
            self._cache[b.odd] = (Xb.copy(), omega, U.copy(), fac)
        msg = "converged" if ok else f"Newton did not converge (residual {ev.res:.3g} N)"
        sol = AllModeSolution(X=X.copy(), omega=omega, F=F, U=Ufull, dF_dX=dF_dX, dF_domega=dF_dw,
                              slip=ev.slip, success=ok, message=msg, iterations=iters, decay=decay,
                              cells=self.cells, H=self.H)
        if b.odd and derivatives:
            self._last = (sol, ev.state)
        return sol

    def end_force(self, sol: AllModeSolution, theta: Array, x: Array) -> Array:
        """The end force (N) in time at the angles ``theta`` (a closed cycle, last = first + 2 pi) for the
        end motion ``x`` there (``sol.X`` in time): the linear part D_n X + c U_{n-1} from the harmonics,
        the tip Jenkins marched on x."""
        d, H = self.disc, sol.H
        b = self.basis(False)
        lin, c = self.linear(sol.omega, b.order, False)[:2]
        Ef = np.ones((theta.size, 2 * H + 1))
        hth = np.outer(theta, np.arange(1, H + 1))
        Ef[:, 1::2], Ef[:, 2::2] = np.cos(hth), np.sin(hth)
        tau, *_ = jenkins_periodic(x[None, :-1], d.kc[-1:], d.p[-1:])
        tau = np.append(tau[0], tau[0, 0])
        return Ef @ ((lin[-1] + d.kc[-1]) * sol.X + c * sol.U[-2]) - d.kc[-1] * x + tau

    def even_block(self, sol: AllModeSolution) -> None:
        """Fill the even-even block of ``sol.dF_dX`` for a half-wave symmetric solution solved in
        the odd basis.  There the Jacobian commutes with the half-period shift, so it is block
        diagonal in (odd, even) coefficients: F_even = 0, dF_even/dX_odd = dF_odd/dX_even = 0,
        dF_even/domega = 0, and dF_even/dX_even is the Schur complement of the even blocks of the
        full-basis Jacobian at the solution (one evaluation and one block elimination).  The even
        basis and its prefix sums are kept; the return map's state is the one the odd solve kept
        where ``sol`` is the last solution of this bar (the same samples: no second march)."""
        last, state = self._last
        even, block = self._even_elimination(sol.U, sol.omega, state if last is sol else None)
        sol.dF_dX[np.ix_(even, even)] = block

    def even_block_at(self, U: Array, X: Array, omega: float) -> tuple[NDArray[np.intp], Array]:
        """``(even, block)``: the indices of the even coefficients in the full layout and the block
        ``even_block`` fills there, from what is left of an odd-basis solution without the solution:
        its free nodes' odd coefficients ``U`` (n, s; ``sol.U[:-1, basis(True).idx]``) and its end
        motion ``X`` (full layout) at ``omega``.  The balance is evaluated once at U (its return map's
        state, the one the solve converged on), then the block eliminated as in ``even_block``: no
        Newton step, so a caller that kept U (``memo.EvenBlockLater``) fills the block of an answer
        given without it for the cost of one evaluation and one elimination."""
        b = self.basis(True)
        state = self.evaluate(U, X[b.idx], omega, b, jacobian=False).state
        full = None
        if state is None:  # (an evaluation that keeps no state: the full basis's march on the whole U)
            full = np.zeros((U.shape[0] + 1, X.size))
            full[:-1, b.idx], full[-1] = U, X
        return self._even_elimination(full, omega, state)

    def _even_elimination(self, U: Array | None, omega: float, state: tuple | None) -> tuple[NDArray[np.intp], Array]:
        """``(even, dF_even/dX_even)`` at the odd solution whose return map's ``state`` (odd basis) is
        given, else at its nodes' coefficients ``U`` (n + 1, full layout), marched again."""
        d = self.disc
        b = self.basis(False)
        if self._even is None:
            even = np.flatnonzero(b.order % 2 == 0)
            Ee, Pe = b.E[:, even], b.P[even]
            self._even = (even, Ee, Pe, jacobian_prefix(Ee, Pe))
        even, Ee, Pe, prefix = self._even
        if state is not None:
            Je = jenkins_jacobian(state, d.kc, Ee, Pe, prefix)
        else:
            _, Je, _ = jenkins_harmonic(U, d.kc, d.p, b.E, b.P, jacobian_basis=(Ee, Pe), prefix=prefix)
        lin, c = self.linear(omega, b.order[even], "even")[:2]
        fac = Coupled(with_diagonal(Je[:-1], lin[:-1]), c, stuck_prefix(state), True)
        return even, np.diag(lin[-1]) + Je[-1] - fac.coupled_last_inverse()
