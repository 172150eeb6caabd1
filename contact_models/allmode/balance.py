"""Harmonic-balance pieces of the all-mode bar: the AFT matrices, the periodic Jenkins force of
many nodes at once with its exact Jacobian, and the block-tridiagonal (block Thomas) solver.

Layout (docs/extending.md, section 1, "Time laws"): a real vector ``[X0, Xc1, Xs1, ..., XcH, XsH]`` means
``x(t) = X0 + sum_h Xc_h cos(h theta) + Xs_h sin(h theta)``; samples at
``theta_k = 2 pi k / n_t``.
"""

from __future__ import annotations

import functools

import numpy as np
from numpy.typing import NDArray

from . import compiled
from .compiled import GEMM_SERIAL, rows_product  # noqa: F401  (this module's names too)


def aft_matrices(H: int, n_t: int) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """``(E, P, order)``: synthesis E (n_t, 2H+1) with ``x = E X``, analysis P (2H+1, n_t) with
    ``X = P x`` exact for trigonometric polynomials of degree <= H (needs n_t >= 2H + 2), and
    the harmonic number of every coefficient (0, 1, 1, 2, 2, ...)."""
    theta = 2.0 * np.pi * np.arange(n_t) / n_t
    order = np.concatenate([[0], np.repeat(np.arange(1, H + 1), 2)]).astype(float)
    E = np.empty((n_t, 2 * H + 1))
    E[:, 0] = 1.0
    ht = np.outer(theta, np.arange(1, H + 1))
    E[:, 1::2] = np.cos(ht)
    E[:, 2::2] = np.sin(ht)
    P = E.T * (2.0 / n_t)
    P[0] *= 0.5
    return E, P, order


def jenkins_periodic(u: NDArray[np.float64], kc: NDArray[np.float64], p: NDArray[np.float64], half: bool = False
                     ) -> tuple[NDArray[np.float64], NDArray[np.bool_], NDArray[np.intp], NDArray[np.bool_]]:
    """Steady periodic force of m Jenkins elements (stiffness ``kc``, slip force ``p``) for the
    sampled periodic displacements ``u`` (m, n_t).

    Exact return map marched over one period from the sample of each row's global maximum,
    where the force is ``min(p, kc (u_max - u_min)/2)``: if the element slips at all in the
    steady cycle it slips on the way up to the maximum, so the force there is ``p`` and one
    pass is periodic; if it never slips (``kc (u_max - u_min) <= 2 p``) the slider sits at the
    centre of the motion (the Masing convention, with an odd loop about the mean).

    ``half``: the rows are half-wave antisymmetric (``u(t + T/2) = -u(t)``, n_t even: the odd
    harmonics only), and so is the steady force, whose loop is odd: the map is marched over the
    half period from the maximum, and the other half is the first one negated (the force at the
    minimum is ``-p`` where the row slips, as it is ``p`` at the maximum).

    Returns ``(f, stuck, anchor, never)``: forces (m, n_t), the mask of samples at which the
    element sticks, the sample index at which the current stick phase began (the last slipping
    sample; its force is +-p), and the rows that never slip.  Then, exactly,
    ``df_k = kc (du_k - du_anchor)`` on stuck samples, 0 on slipping ones, and for never-slipping
    rows ``f = kc (u - (u_max + u_min)/2)``.
    """
    march = compiled.kernel("march")
    if march is not None:
        return march(np.ascontiguousarray(u, dtype=float), np.ascontiguousarray(kc, dtype=float),
                             np.ascontiguousarray(p, dtype=float), bool(half))
    m, n_t = u.shape
    rows = np.arange(m)
    kmax = np.argmax(u, axis=1)
    umax = u[rows, kmax]
    umin = np.min(u, axis=1)
    never = kc * (umax - umin) <= 2.0 * p
    # rolled so that each row starts at its maximum; time along axis 0 (contiguous steps)
    order = kmax[None, :] + np.arange(n_t)[:, None]
    order[order >= n_t] -= n_t
    ur = u[rows[None, :], order]
    steps = n_t // 2 if half else n_t  # marched samples
    dku = kc * np.diff(ur[:steps], axis=0)
    trial = np.empty((n_t, m))
    fk = np.where(never, 0.5 * kc * (umax - umin), p)
    trial[0] = fk
    lo = -p
    for j in range(1, steps):  # in place: no array is allocated per step
        t = trial[j]
        np.add(fk, dku[j - 1], out=t)
        np.maximum(t, lo, out=fk)
        np.minimum(fk, p, out=fk)
    if half:
        np.negative(trial[:steps], out=trial[steps:])
    fr = np.minimum(np.maximum(trial, lo), p)
    st = np.abs(trial) <= p
    st[0] = never
    if half:
        st[steps] = never
    # the stick phase at step j began at the last slipping step (step 0 slips unless `never`)
    last = np.where(st, 0, np.arange(n_t)[:, None])
    last = np.maximum.accumulate(last, axis=0)
    f = np.empty((m, n_t))
    stuck = np.empty((m, n_t), bool)
    anchor = np.empty((m, n_t), np.intp)
    f[rows[None, :], order] = fr
    stuck[rows[None, :], order] = st
    anchor[rows[None, :], order] = order[last, rows[None, :]]
    return f, stuck, anchor, never


def _trig_columns(E: NDArray[np.float64], P: NDArray[np.float64]) -> tuple[NDArray[np.intp], NDArray[np.bool_],
                                                                         NDArray[np.float64]]:
    """The harmonic h, whether a sine, and the analysis factor f (``P[a] = f E[:, a]^T``) of every
    column a of E, for columns of :func:`aft_matrices` (checked: ValueError otherwise)."""
    n_t = E.shape[0]
    spec = np.fft.rfft(E, axis=0)
    h = np.argmax(np.abs(spec), axis=0)
    sine = np.abs(spec[h, np.arange(E.shape[1])].imag) > np.abs(spec[h, np.arange(E.shape[1])].real)
    theta = 2.0 * np.pi * np.arange(n_t) / n_t
    model = np.where(sine, np.sin(np.outer(theta, h)), np.cos(np.outer(theta, h)))
    f = np.einsum("ak,ka->a", P, E) / np.einsum("ka,ka->a", E, E)
    if np.max(np.abs(model - E)) > 1e-12 or np.max(np.abs(P - f[:, None] * E.T)) > 1e-12 * np.max(np.abs(f)):
        raise ValueError("jacobian_prefix: E and P must be columns of aft_matrices (a sampled trigonometric basis)")
    return h, sine, f


def jacobian_prefix(E: NDArray[np.float64], P: NDArray[np.float64]) -> tuple:
    """What :func:`jenkins_jacobian` sums over the stuck runs, from the basis alone (a caller that
    evaluates many times keeps it: ``jenkins_harmonic``'s ``prefix``): ``(S, CP, I1, I2, coefs)``.

    ``Q[j] = sum_{k <= j} P[:, k] E[k]^T`` (s, s) is not stored: the entry (a, b) of
    ``P[:, k] E[k]^T`` is ``f_a phi_a(theta_k) phi_b(theta_k)`` (phi cos h theta, sin h theta or 1,
    f the analysis factor 2/n_t, 1/n_t for the mean), and by ``cos x cos y = (cos(x-y) + cos(x+y))/2``,
    ``sin x sin y = (cos(x-y) - cos(x+y))/2``, ``cos x sin y = (sin(x+y) - sin(x-y))/2`` and
    ``sin x cos y = (sin(x+y) + sin(x-y))/2`` it is a sum of two terms ``c g_n(theta_k)``, g_n the cosines
    and sines of the frequencies 0..2 h_max.  So ``Q[j]`` follows from ``S[j] = sum_{k <= j} g(theta_k)``
    (n_t, L): for a vector V of such sums, the matrix is ``W[I1] + W[I2]`` (flattened (s, s)) with
    ``W = (c V for c in coefs)`` flattened, ``coefs`` the distinct coefficients, ``I1``, ``I2`` (s*s,)
    indices into W (an index to a zero column for sin 0).  ``CP`` (n_t, s): the prefix sums of
    ``P[:, k]``.  The derivation: docs/theory.md, "The Jacobian by stick runs"."""
    n_t, s = E.shape
    h, sine, f = _trig_columns(E, P)
    nf = 2 * int(h.max()) + 1  # frequencies 0 .. 2 h_max
    theta = 2.0 * np.pi * np.arange(n_t) / n_t
    nt = np.outer(theta, np.arange(nf))
    g = np.concatenate([np.cos(nt), np.sin(nt), np.zeros((n_t, 1))], axis=1)  # columns: cos n, sin n, 0
    L = g.shape[1]
    ha, hb = h[:, None], h[None, :]
    sa, sb = sine[:, None], sine[None, :]
    # the two terms (frequency, sine?, sign) of phi_a phi_b = (t1 + t2)/2
    f1, f2 = ha - hb, ha + hb
    sin_term = sa ^ sb
    sign1 = np.where(sin_term, np.where(sa, 1.0, -1.0), 1.0)  # cos a sin b: -sin(a-b); sin a cos b: +sin(a-b)
    sign2 = np.where(sin_term, 1.0, np.where(sa, -1.0, 1.0))  # sin a sin b: -cos(a+b)
    sign1 = sign1 * np.where(sin_term & (f1 < 0), -1.0, 1.0)  # sin(-n) = -sin(n)
    f1 = np.abs(f1)

    def column(freq, is_sin):
        return np.where(is_sin, np.where(freq == 0, L - 1, nf + freq), freq)

    c1 = (0.5 * f[:, None] * sign1).ravel()
    c2 = (0.5 * f[:, None] * sign2 * np.ones_like(hb)).ravel()
    coefs, inv = np.unique(np.concatenate([c1, c2]), return_inverse=True)
    cols = np.concatenate([column(f1, sin_term).ravel(), column(f2, sin_term).ravel()])
    idx = inv * L + cols
    out = (np.cumsum(g, axis=0), np.cumsum(P.T, axis=0), idx[: s * s], idx[s * s:], coefs)
    for a in out:  # read-only, as every basis keeps them: one signature of the Jacobian kernel
        a.flags.writeable = False
    return out


def jenkins_harmonic(U: NDArray[np.float64], kc: NDArray[np.float64], p: NDArray[np.float64],
                     E: NDArray[np.float64], P: NDArray[np.float64], *, jacobian: bool = True,
                     jacobian_basis: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None,
                     prefix: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None
                     ) -> tuple[NDArray[np.float64], NDArray[np.float64] | None, NDArray[np.bool_]]:
    """Harmonic coefficients T (m, 2H+1) of the periodic Jenkins forces of m nodes whose
    displacements have coefficients U (m, 2H+1), the exact Jacobians dT/dU (m, 2H+1, 2H+1) and
    the mask of samples at which each node slips (m, n_t): AFT, ``T = P f(E U)``.
    ``jacobian_basis=(E2, P2)``: the Jacobian on other coefficients (same samples; E2's first
    column the mean), e.g. the even block at an odd solution, without the full one.
    ``prefix``: ``jacobian_prefix`` of the Jacobian's basis (computed here when not given).

    The Jacobian of a node that slips somewhere: ``df_k = kc (du_k - du_a)`` on a stuck sample k
    whose stick phase began at the slipping sample a (its anchor), 0 on slipping samples, so
    ``dT/dU = kc sum_k stuck_k P[:, k] (E_k - E_a(k))^T``.  The stuck samples form runs
    (a, e] (circularly) with one anchor each, and a run's part is a difference of prefix
    sums, ``Q[e] - Q[a] - (CP[e] - CP[a]) E_a^T`` (plus the totals ``Q[-1]``, ``CP[-1]`` where
    the run wraps past the last sample), ``Q[j] = sum_{k <= j} P[:, k] E[k]^T``: O(runs s^2) per
    node instead of O(n_t s^2).  ``Q`` is kept as the prefix sums of the sampled cosines and sines
    of twice the basis's frequencies (``jacobian_prefix``): a node's runs are summed on those
    (O(runs H)) and expanded to (s, s) once."""
    u = rows_product(U, E.T)
    f, stuck, anchor, never = jenkins_periodic(u, kc, p)
    T = rows_product(f, P.T)
    if not jacobian:
        return T, None, ~stuck
    E, P = (E, P) if jacobian_basis is None else jacobian_basis
    return T, jenkins_jacobian((u, stuck, anchor, never), kc, E, P, prefix), ~stuck


def jenkins_state(U: NDArray[np.float64], kc: NDArray[np.float64], p: NDArray[np.float64],
                  E: NDArray[np.float64], P: NDArray[np.float64], half: bool = False
                  ) -> tuple[NDArray[np.float64], NDArray[np.bool_], tuple]:
    """``jenkins_harmonic`` without the Jacobian: ``(T, slip, state)``, ``state`` what
    :func:`jenkins_jacobian` needs to add it later without marching the return map again.
    ``half``: the basis holds odd harmonics only (:func:`jenkins_periodic`; the products on half the samples,
    :func:`half_products`)."""
    if not half:
        u = rows_product(U, E.T)
        f, stuck, anchor, never = jenkins_periodic(u, kc, p)
        return rows_product(f, P.T), ~stuck, (u, stuck, anchor, never)
    EhT, Ph2T = half_products(E, P)
    uh = rows_product(U, EhT)
    u = np.concatenate((uh, -uh), axis=1)
    f, stuck, anchor, never = jenkins_periodic(u, kc, p, True)
    return rows_product(np.ascontiguousarray(f[:, :EhT.shape[1]]), Ph2T), ~stuck, (u, stuck, anchor, never)


def kernel_constants(E: NDArray[np.float64], P: NDArray[np.float64]) -> tuple:
    """``(E contiguous, P 1 rounded, the mean of E)``: what the Jacobian kernel takes besides the prefix (kept per
    basis)."""
    return _derived(E, P)[2:5]


def half_products(E: NDArray[np.float64], P: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``(E_h^T, 2 P_h^T)``: the synthesis and analysis of a basis of odd harmonics on the first half of its n_t
    samples (``E_h = E[:n_t/2]``, ``P_h = P[:, :n_t/2]``; contiguous, kept per basis).  Such a motion is half-wave
    antisymmetric, u(theta + pi) = -u(theta), and so is the Jenkins force of ``jenkins_periodic(..., half=True)``: the
    samples u = U E^T are those of the first half and their negatives, and the coefficients P f of the force are
    twice the first half's sum, 2 P_h f_h.  Half the work of the two products, exactly (the second half's samples
    of E and P are the first half's negatives but for rounding)."""
    d = _derived(E, P)
    return d[5], d[6]


def jacobian_pattern(state: tuple) -> tuple:
    """What :func:`jenkins_jacobian` of ``state`` depends on besides the basis and kc: the rows that
    never slip, the stuck masks and anchors of the others, and the samples of the maximum and the
    minimum of the never-slipping rows (with the rows that do not move).  The force is piecewise
    linear in the displacements, so two states of equal patterns (:func:`same_pattern`) have equal
    Jacobians, bit for bit."""
    u, stuck, anchor, never = state
    iv = np.flatnonzero(never)
    kmax = np.argmax(u[iv], axis=1)
    kmin = np.argmin(u[iv], axis=1)
    rows = ~never
    return never, stuck[rows], anchor[rows], kmax, kmin, u[iv, kmax] == u[iv, kmin]


def same_pattern(p: tuple, q: tuple) -> bool:
    """True when the :func:`jacobian_pattern` ``p`` and ``q`` are equal (then so are the Jacobians)."""
    return all(np.array_equal(x, y) for x, y in zip(p, q))


def same_jacobian(a: tuple, b: tuple) -> bool:
    """True when the return map's states ``a`` and ``b`` (:func:`jenkins_state`) have equal patterns
    (:func:`same_pattern` of their :func:`jacobian_pattern`): then their Jacobians are equal, bit for bit."""
    same = compiled.kernel("same_pattern")
    if same is not None:
        return bool(same(*a, *b))
    return same_pattern(jacobian_pattern(a), jacobian_pattern(b))


#: What ``jenkins_jacobian``'s kernel takes besides the prefix, and ``half_products``, by basis: ``(id(E), id(P)) ->
#: (E, P, E contiguous, P 1, the mean of E, E_h^T, 2 P_h^T)``, for bases that are not changed in place (E and P are
#: kept, so that their ids are not reused while kept).
_DERIVED: dict = {}


def _derived(E: NDArray[np.float64], P: NDArray[np.float64]) -> tuple:
    hit = _DERIVED.get((id(E), id(P)))
    if hit is None or hit[0] is not E or hit[1] is not P:
        if len(_DERIVED) >= 64:
            _DERIVED.clear()
        Ec, h = np.ascontiguousarray(E), E.shape[0] // 2
        hit = _DERIVED[(id(E), id(P))] = (E, P, Ec, np.rint(P.sum(axis=1)), Ec.mean(axis=0),
                                          np.ascontiguousarray(E[:h].T), np.ascontiguousarray((2.0 * P[:, :h]).T))
    return hit


def jenkins_jacobian(state: tuple, kc: NDArray[np.float64], E: NDArray[np.float64], P: NDArray[np.float64],
                     prefix: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None) -> NDArray[np.float64]:
    """The Jacobians dT/dU (m, s, s) on the basis (E, P) from the ``state`` of :func:`jenkins_state`
    (the derivation in :func:`jenkins_harmonic`)."""
    u, stuck, anchor, never = state
    jacobians = compiled.kernel("jacobians")
    if jacobians is not None:
        S, CP, I1, I2, coefs = jacobian_prefix(E, P) if prefix is None else prefix
        E, P1, mean = kernel_constants(E, P)
        return jacobians(u, stuck, anchor, never, np.ascontiguousarray(kc, dtype=float), E, P1, mean, S, CP,
                         I1, I2, coefs)
    m, nh = u.shape[0], E.shape[1]
    if not np.any(never):
        J = _slip_jacobians(stuck, anchor, E, P, prefix)
        J *= kc[:, None, None]
    else:
        J = np.empty((m, nh, nh))
        slips = np.flatnonzero(~never)
        if slips.size:
            Js = _slip_jacobians(stuck[slips], anchor[slips], E, P, prefix)
            Js *= kc[slips, None, None]
            J[slips] = Js
        # f = kc (u - c), c = (u_max + u_min)/2: dT/dU = kc (I - (P 1) dc/dU), P 1 the coefficients of
        # a constant (e0 in a basis with the mean, 0 in the odd basis: rounded to those integers, so that
        # in the odd basis the block is kc I exactly), dc/dU = (E_max + E_min)/2.
        # A constant row (no motion: max and min not unique) has no derivative of c; its one-sided
        # derivative (max du + min du)/2 is the mean of du for every constant and every half-wave
        # symmetric du, so the mean (E averaged over the samples) is taken there.
        iv = np.flatnonzero(never)
        kmax = np.argmax(u[iv], axis=1)
        kmin = np.argmin(u[iv], axis=1)
        dc = 0.5 * (E[kmax] + E[kmin])
        dc[u[iv, kmax] == u[iv, kmin]] = E.mean(axis=0)
        J[iv] = kc[iv, None, None] * (np.eye(nh) - np.rint(P.sum(axis=1))[None, :, None] * dc[:, None, :])
    return J


def _slip_jacobians(st: NDArray[np.bool_], anchor: NDArray[np.intp], E: NDArray[np.float64], P: NDArray[np.float64],
                    prefix: tuple | None) -> NDArray[np.float64]:
    """``sum_runs Q[e] - Q[a] + wrap Q[-1] - (CP[e] - CP[a] + wrap CP[-1]) E_a^T`` of every node
    (m, s, s), the Jacobians divided by kc of m nodes that slip, from their stuck masks ``st`` and
    ``anchor`` (m, n_t).

    The sums of ``Q`` are summed as the vectors ``S`` of :func:`jacobian_prefix` (L numbers a run,
    not s^2) and expanded to (s, s) once per node; every node's runs are padded to the largest
    number K of runs of a node with empty runs (e = a = 0: their terms are exactly 0), and the
    rank-K part ``sum_runs C E_a^T`` is one stacked product (m, s, K) @ (m, K, s)."""
    S, CP, I1, I2, coefs = jacobian_prefix(E, P) if prefix is None else prefix
    m, nh = st.shape[0], E.shape[1]
    r, e = np.nonzero(st & ~np.roll(st, -1, axis=1))  # the last stuck sample of every run, by node
    a = anchor[r, e]
    counts = np.bincount(r, minlength=m)
    K = max(1, int(counts.max()))
    slot = np.arange(r.size) - np.concatenate([[0], np.cumsum(counts)[:-1]])[r]  # run number within its node
    ep = np.zeros((K, m), np.intp)
    ap = np.zeros((K, m), np.intp)
    ep[slot, r] = e
    ap[slot, r] = a
    wrap = ep < ap
    C = CP[ep] - CP[ap]  # (K, m, s)
    C += wrap[:, :, None] * CP[-1]
    V = (S[ep] - S[ap]).sum(axis=0)  # (m, L)
    V += wrap.sum(axis=0)[:, None] * S[-1]
    W = (V[:, None, :] * coefs[None, :, None]).reshape(m, -1)
    J = np.take(W, I1, axis=1).reshape(m, nh, nh)
    work = np.take(W, I2, axis=1).reshape(m, nh, nh)
    J += work
    J -= np.matmul(C.transpose(1, 2, 0), E[ap].transpose(1, 0, 2), out=work)
    return J


def scalar_tridiagonal(diag: NDArray[np.float64], off: float, last: NDArray[np.float64]) -> NDArray[np.float64]:
    """Solve the tridiagonal systems with diagonal ``diag[:, j]`` (n, s), every off-diagonal ``off``
    and right-hand side zero but ``last`` (s) in the last row, for every column j at once (Thomas)."""
    thomas = compiled.kernel("thomas")
    if thomas is not None:
        return thomas(np.ascontiguousarray(diag, dtype=float), float(off), np.asarray(last, dtype=float))
    n = diag.shape[0]
    cp = np.empty_like(diag)
    y = np.zeros_like(diag)
    cp[0] = diag[0]
    y[-1] = last
    for i in range(1, n):
        w = off / cp[i - 1]
        cp[i] = diag[i] - w * off
        y[i] -= w * y[i - 1]
    U = np.empty_like(y)
    U[-1] = y[-1] / cp[-1]
    for i in range(n - 2, -1, -1):
        U[i] = (y[i] - off * U[i + 1]) / cp[i]
    return U


@functools.lru_cache(maxsize=None)
def _getri_lwork(s: int) -> int:
    """LAPACK's optimal workspace of ``dgetri`` for s x s (its blocked code; numba's inverse asks the same)."""
    from scipy.linalg import lapack  # lazily: import contact_models stays light

    return max(1, int(lapack.dgetri_lwork(s)[0]))


class BlockTridiagonal:
    """Factorisation of the block-tridiagonal matrix with diagonal blocks ``B`` (n, s, s) and
    every off-diagonal block ``c I`` (the axial coupling of neighbouring nodes), by block
    Thomas elimination: ``C_0 = B_0``, ``C_i = B_i - c^2 C_{i-1}^{-1}``; O(n s^3) work.

    ``diagonal``: the first blocks that the caller knows to be diagonal (the bar's nodes that never
    slip, in the odd basis: ``kc I`` plus the linear part), or, with ``row0``, diagonal but for their
    first row (those nodes in a basis whose first coefficient is the mean: ``kc (I - e0 dc^T)``).
    There every ``C_i`` keeps that form, ``diag(d) + e0 w^T`` (w_0 = 0), and so does its inverse,
    ``diag(1/d) + e0 v^T`` with ``v_j = -w_j / (d_j d_0)``: O(s) a node instead of O(s^3).  Without
    ``row0`` this is ``1 / C_i`` elementwise, what LAPACK's inverse gives on a diagonal matrix, bit
    for bit."""

    def __init__(self, B: NDArray[np.float64], c: float, diagonal: int = 0, row0: bool = False) -> None:
        from scipy.linalg import lapack  # lazily: import contact_models stays light

        n, s, _ = B.shape
        self.c, self.row0 = c, bool(row0)
        self.k = k = min(int(diagonal), n)
        block_factor = compiled.kernel("block_factor")
        if block_factor is not None:
            self.inv_d, self.inv_v, self.inv, bad = block_factor(np.ascontiguousarray(B, dtype=float),
                                                                 float(c), k, self.row0)
            if bad >= 0:
                raise np.linalg.LinAlgError(f"singular block {bad} in the block elimination")
            return
        self.inv_d = inv_d = np.empty((k, s))  # the inverses of the first C_i: their diagonals
        self.inv_v = inv_v = np.zeros((k, s))  # and the rest of their first rows (row0)
        self.inv = np.empty((n - k, s, s))  # the inverses of the others, from C_k on
        c2 = c * c
        d = np.diagonal(B[:k], axis1=1, axis2=2)
        for i in range(k):
            di = d[i] - c2 * inv_d[i - 1] if i else d[0]
            if not np.all(di):
                raise np.linalg.LinAlgError(f"singular block {i} in the block elimination")
            np.divide(1.0, di, out=inv_d[i])
            if self.row0:
                wi = B[i, 0, 1:] - c2 * inv_v[i - 1, 1:] if i else B[0, 0, 1:]
                inv_v[i, 1:] = -wi * inv_d[i, 1:] * inv_d[i, 0]
        getrf, getri = lapack.dgetrf, lapack.dgetri
        lwork = _getri_lwork(s)
        for i in range(k, n):
            if i == 0:
                Ci = B[0]
            elif i == k:
                Ci = B[i].copy()
                Ci[np.diag_indices(s)] -= c2 * inv_d[-1]
                if self.row0:
                    Ci[0, 1:] -= c2 * inv_v[-1, 1:]
            else:
                Ci = B[i] - c2 * self.inv[i - 1 - k]
            # LAPACK's dgetrf and dgetri (the inverse from the LU factors, with the optimal workspace), as the
            # compiled kernel's numpy.linalg.inv does, without numpy's per-call overhead
            lu, piv, info = getrf(Ci)
            if info == 0:
                self.inv[i - k], info = getri(lu, piv, lwork=lwork)
            if info > 0:
                raise np.linalg.LinAlgError(f"singular block {i} in the block elimination")

    @classmethod
    def from_factors(cls, inv_d: NDArray[np.float64], inv_v: NDArray[np.float64], inv: NDArray[np.float64], c: float,
                     row0: bool) -> BlockTridiagonal:
        """The factorisation from the arrays ``block_factor`` returns (``compiled.coupled_factor``)."""
        out = cls.__new__(cls)
        out.c, out.row0, out.k = c, bool(row0), inv_d.shape[0]
        out.inv_d, out.inv_v, out.inv = inv_d, inv_v, inv
        return out

    def last_inverse(self) -> NDArray[np.float64]:
        """C_{n-1}^{-1}, the last diagonal block of the inverse."""
        if self.inv.shape[0]:
            return self.inv[-1]
        out = np.diag(self.inv_d[-1])
        out[0, 1:] += self.inv_v[-1, 1:]
        return out

    def _first(self, i: int, z: NDArray[np.float64]) -> NDArray[np.float64]:
        """``C_i^{-1} z`` for one of the first k pivots (z of shape (s,) or (s, q))."""
        out = (self.inv_d[i] if z.ndim == 1 else self.inv_d[i][:, None]) * z
        if self.row0:
            out[0] += self.inv_v[i, 1:] @ z[1:]
        return out

    def solve(self, r: NDArray[np.float64]) -> NDArray[np.float64]:
        """Solve for ``r`` of shape (n, s) or (n, s, q) (q right-hand sides)."""
        c, k, inv = self.c, self.k, self.inv
        block_solve = compiled.kernel("block_solve")
        if block_solve is not None:
            return block_solve(self.inv_d, self.inv_v, inv, float(c), np.array(r, dtype=float), self.row0)
        n = k + inv.shape[0]
        y = np.array(r, dtype=float, copy=True)
        for i in range(1, n):
            y[i] -= c * (self._first(i - 1, y[i - 1]) if i <= k else inv[i - 1 - k] @ y[i - 1])
        x = np.empty_like(y)
        x[n - 1] = self._first(n - 1, y[n - 1]) if n == k else inv[-1] @ y[n - 1]
        for i in range(n - 2, -1, -1):
            z = y[i] - c * x[i + 1]
            x[i] = self._first(i, z) if i < k else inv[i - k] @ z
        return x


class BandedBlockTridiagonal:
    """The same matrix as ``BlockTridiagonal`` factorised as one band matrix (half-bandwidth s) by
    LAPACK's banded LU with partial pivoting (``dgbtrf``): one call instead of n inversions in a
    Python loop.  ``solve`` as there; ``last_inverse()`` is the last diagonal block of the inverse,
    which is C_{n-1}^{-1}, the last pivot block's inverse of the block elimination."""

    def __init__(self, B: NDArray[np.float64], c: float) -> None:
        from scipy.linalg import lapack  # lazily: import contact_models stays light

        n, s, _ = B.shape
        self.n, self.s = n, s
        N, k = n * s, s
        ab = np.zeros((3 * k + 1, N))
        # band row of A[i, j] is 2k + i - j: block b's entry (i, j) is ab[2k + i - j, b s + j], one strided
        # view of ab (steps s along b, N along i, 1 - N along j from ab[2k, 0]), filled by one copy
        it = ab.itemsize
        np.lib.stride_tricks.as_strided(ab[2 * k:], shape=(n, s, s), strides=(s * it, N * it, (1 - N) * it))[...] = B
        ab[k, s:] = c  # upper block diagonal c I: A[i, i + s]
        ab[3 * k, : N - s] = c  # lower: A[i + s, i]
        self._lu, self._piv, info = lapack.dgbtrf(ab, k, k)
        self._trs = lapack.dgbtrs
        self._last = None
        if info > 0:
            self._lu[:] = np.nan  # singular: solutions come out nan and the caller's checks catch it

    def solve(self, r: NDArray[np.float64]) -> NDArray[np.float64]:
        """Solve for ``r`` of shape (n, s) or (n, s, q) (q right-hand sides)."""
        shape = r.shape
        x, _ = self._trs(self._lu, self.s, self.s, np.reshape(r, (self.n * self.s, -1)), self._piv)
        return x.reshape(shape)

    def last_inverse(self) -> NDArray[np.float64]:
        """C_{n-1}^{-1}: the solve of ``e_(n-1) I`` on the factors' last two blocks alone, O(s^3) instead of
        O(n s^3).  LAPACK's forward sweep does nothing before them (the right-hand side is 0 there and its row
        swaps reach at most s rows down), and the back substitution's last block reads only the last block of
        U: the full solve's last block, to rounding (the band solver's blocking differs)."""
        if self._last is None:
            s = self.s
            a = max(0, (self.n - 2) * s)  # the first row of the last two blocks
            e = np.zeros((self.n * s - a, s))
            e[-s:] = np.eye(s)
            x, _ = self._trs(self._lu[:, a:], s, s, e, self._piv[a:] - a)
            self._last = x[-s:]
        return self._last


#: Up to this block size the banded LU is the faster factorisation; above it LAPACK's band kernels lose
#: to n small block inversions (docs/performance.md, "The all-mode FRF", "Banded LU").
BANDED_MAX_BLOCK = 20


def factorise(B: NDArray[np.float64], c: float, diagonal: int = 0, row0: bool = False
              ) -> BlockTridiagonal | BandedBlockTridiagonal:
    """The faster factorisation of the block-tridiagonal matrix (blocks ``B``, coupling ``c I``;
    ``diagonal``, ``row0``: its first blocks known to be diagonal, or diagonal but for their first
    row, see :class:`BlockTridiagonal`)."""
    if B.shape[1] <= BANDED_MAX_BLOCK:
        return BandedBlockTridiagonal(B, c)
    return BlockTridiagonal(B, c, diagonal, row0)
