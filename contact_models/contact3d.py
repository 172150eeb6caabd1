"""A three-dimensional point contact: two tangential directions, a circular Coulomb limit, a normal load.

Three relative displacements at the contact point: the tangential pair ``u = (u1, u2)`` and the
normal ``v`` (``v > 0`` presses the surfaces together).  The normal force is the unilateral spring
of ``Contact2D``, ``N = max(0, n0 + kn v)``.  Tangentially an isotropic spring ``kt`` in series
with a two-dimensional Coulomb slider at ``w = (w1, w2)`` carries ``T = kt (u - w)`` with
``|T| <= mu N(t)``: the limit is a circle, so the slip direction turns with the path.  While
separated (``N = 0``) ``T = 0`` and the slider follows ``u``.  Derivations, conventions and
evidence: ``docs/contacts_normal.md``, "Three-dimensional contact".

**Time law** (``periodic_force``; ``x`` has shape (3, n_t): rows t1, t2, normal).  The radial
return map on the samples: with ``L_k = mu N_k``, the trial force ``T* = kt (u_k - w)`` sticks if
``|T*| < L_k``, else slips, ``T_k = L_k T*/|T*|``, ``w = u_k - T_k/kt``.  In the slider's plane
this is the projection of ``w`` onto the disc of radius ``r_k = L_k/kt`` about ``u_k``.

**Periodic state.** The slider positions for which nothing slips over the period are the
intersection of the discs ``|w - u_k| <= r_k``.  If it is not empty the element sticks all period
and takes its *clearance centre*, the point farthest inside every disc,
``argmin_w max_k (|u_k - w| - r_k)``: for a straight path it is the midpoint of ``Contact2D``, for
a constant load the centre of the smallest circle holding the path (a Masing centre in the plane).
Else the period map ``P`` (a composition of projections onto discs: nonexpansive, contracting
wherever slip happens) is iterated to its fixed point by Newton's method on ``w = P(w)`` with the
tangent ``dP/dw`` of the pass, falling back to a plain period where a Newton step does not reduce
the mismatch, until the slider repeats to ``STATE_RTOL`` of the contact's size.

**Jacobian.** The exact derivative of the sampled periodic map: the tangent of the return map is
propagated through one period and the periodic state's own dependence is the fixed point's,
``(I - dP/dw) dw_0 = (dP/dx) dx``.  ``Contact3D.harmonic_force`` propagates the inverse-FFT
columns instead of unit vectors, so the harmonic Jacobian costs O(n_t H), never a dense (3 n_t)^2.

**Reductions.** With one tangential row zero it is ``Contact2D`` (the same return map, centring and
slip origins); with the normal row at rest on a straight path, the Jenkins element
``Macroslip(kt, mu n0)``.  ``Contact3D.fourier`` is that Jenkins element (H = 1, normal at rest,
one direction); with normal motion or a turning path the balance answers through AFT.
"""

from __future__ import annotations

import math
from itertools import combinations

import numpy as np
from numpy.typing import NDArray

from .contact2d import PointContactLaw
from .numerics.masing import aft_matrices, to_harmonics, to_time

#: Periods of the period map tried before giving up on a fixed point.
MAX_PERIODS = 500
#: The periodic state is converged when the slider returns to within this fraction of the
#: contact's size (the largest slip radius mu N/kt or tangential excursion).
STATE_RTOL = 1e-13
#: Samples outside the current centre added to its basis at each repetition of the active-set loop.
VIOLATORS = 4
#: Slack, in units of the contact's size, within which a candidate centre covers a disc (rounding).
COVER_RTOL = 1e-14


# ---------------------------------------------------------------------- the stuck period: clearance centre
def clearance_centre(u: NDArray, r: NDArray) -> tuple[NDArray, tuple[int, ...], float]:
    """``(w, basis, F)``: the minimiser ``w`` of ``F(w) = max_k (|u_k - w| - r_k)`` over the samples
    ``u`` (2, n) with radii ``r`` (n,), the samples active there (one to three) and the minimum ``F``.

    ``F <= 0`` is a nonempty intersection of the discs, ``w`` its point of largest clearance ``-F``.
    The minimiser is unique (the norm is strictly convex off lines through ``u_k``), so it is a
    continuous function of ``u`` and ``r``.  Active-set iteration: solve exactly on a small set of
    samples (every basis of one, two or three, the smallest covering candidate), add the samples the
    answer leaves outside, repeat with the basis and those.  ``F`` grows strictly at each repetition
    (the old centre misses a sample of the new set), so no basis returns and it ends.
    """
    scale = max(float(np.max(np.ptp(u, axis=1))), float(np.max(r)), np.finfo(float).tiny)
    eps = COVER_RTOL * scale
    picks = [np.argmax(u[0] - r), np.argmin(u[0] + r), np.argmax(u[1] - r), np.argmin(u[1] + r), np.argmin(r)]
    S = list(dict.fromkeys(int(i) for i in picks))
    for _ in range(4 * r.size + 4):
        w, F, B = _small_centre(u[:, S], r[S], eps)
        g = np.hypot(u[0] - w[0], u[1] - w[1]) - r
        out = np.flatnonzero(g > F + eps)
        basis = tuple(S[b] for b in B)
        if out.size == 0:
            return w, basis, F
        S = list(basis) + [int(i) for i in out[np.argsort(g[out])[-VIOLATORS:]]]
    raise RuntimeError(f"no clearance centre of the {r.size} samples")


def _small_centre(P: NDArray, r: NDArray, eps: float) -> tuple[NDArray, float, tuple[int, ...]]:
    """:func:`clearance_centre` on a few samples by enumeration: the candidates of every basis
    (a sample itself; the point between two on their segment with equal excess; the point of equal
    excess to three, a quadratic), the covering one of least ``F``, a smaller basis on a tie."""
    m = r.size
    cands: list[tuple[float, int, NDArray, tuple[int, ...]]] = [(-r[i], 1, P[:, i], (i,)) for i in range(m)]
    for i, j in combinations(range(m), 2):
        d = math.hypot(P[0, j] - P[0, i], P[1, j] - P[1, i])
        if d > abs(r[i] - r[j]):
            t = 0.5 * (d + r[i] - r[j])
            cands.append((t - r[i], 2, P[:, i] + (t / d) * (P[:, j] - P[:, i]), (i, j)))
    for tri in combinations(range(m), 3):
        cands += [(F, 3, w, tri) for F, w in _three_centres(P[:, tri], r[list(tri)], eps)]
    best = None
    for F, size, w, basis in cands:
        if (best is None or (F, size) < best[:2]) and np.all(np.hypot(P[0] - w[0], P[1] - w[1]) - r <= F + eps):
            best = (F, size, w, basis)
    if best is None:  # the optimum's own basis is a candidate: only rounding beyond eps gets here
        raise RuntimeError(f"no covering centre of {m} samples within {eps:.3g}")
    return np.array(best[2], dtype=float), float(best[0]), best[3]


def _three_centres(P: NDArray, r: NDArray, eps: float) -> list[tuple[float, NDArray]]:
    """Points ``w`` with ``|P_k - w| - r_k = F`` for the three samples (columns of ``P``): with the
    origin at the first, ``2 (P_k - P_0).w = |P_k - P_0|^2 - r_k^2 + r_0^2 - 2 (r_k - r_0) F``
    (k = 1, 2) gives ``w = p + q F``, and ``|w| = F + r_0`` a quadratic in ``F``."""
    Q = P[:, 1:] - P[:, :1]
    M = 2.0 * Q.T
    det = M[0, 0] * M[1, 1] - M[0, 1] * M[1, 0]
    if abs(det) <= 1e-12 * float(np.sum(M * M)):
        return []  # collinear: no point of equal excess off the line
    alpha = np.sum(Q * Q, axis=0) - r[1:] ** 2 + r[0] ** 2
    beta = -2.0 * (r[1:] - r[0])
    p, q = np.linalg.solve(M, alpha), np.linalg.solve(M, beta)
    a, b, c = q @ q - 1.0, 2.0 * (p @ q - r[0]), p @ p - r[0] ** 2
    if abs(a) <= 1e-14:
        roots = [-c / b] if b != 0.0 else []
    else:
        disc = b * b - 4.0 * a * c
        if disc < 0.0:
            return []
        s = math.sqrt(disc)
        roots = [(-b - s) / (2.0 * a), (-b + s) / (2.0 * a)]
    return [(F, P[:, 0] + p + q * F) for F in roots if min(F + r[0], F + r[1], F + r[2]) >= -eps]


def centre_tangent(u: NDArray, r: NDArray, w: NDArray, basis: tuple[int, ...]) -> tuple[NDArray, NDArray]:
    """``(W, omega)``: ``dw = sum_b W[b] du_b + omega[b] dr_b`` over the active samples ``basis`` of the
    clearance centre ``w`` (``W`` (len, 2, 2), ``omega`` (len, 2)), the derivative of the active
    conditions ``|u_b - w| - r_b = F``.

    One sample: ``w = u_b``.  Two: ``w = u_i + t e``, ``t = (d + r_i - r_j)/2``, ``e = (u_j - u_i)/d``,
    so ``dw/du_j = I/2 + (r_i - r_j)/(2 d) (I - e e^T)``, ``dw/du_i = I - dw/du_j``, ``dw/dr_i = e/2 = -dw/dr_j``.
    Three: ``n_b^T (du_b - dw) - dr_b - dF = 0`` with ``n_b = (u_b - w)/|u_b - w|``, a 3 x 3 solve.
    """
    I2 = np.eye(2)
    if len(basis) == 1:
        return I2[None].copy(), np.zeros((1, 2))
    if len(basis) == 2:
        i, j = basis
        delta = u[:, j] - u[:, i]
        d = math.hypot(*delta)
        e = delta / d
        Wj = 0.5 * I2 + (r[i] - r[j]) / (2.0 * d) * (I2 - np.outer(e, e))
        return np.stack([I2 - Wj, Wj]), np.stack([0.5 * e, -0.5 * e])
    nb = (u[:, basis] - w[:, None]) / np.hypot(*(u[:, basis] - w[:, None]))  # (2, 3)
    A = np.hstack([nb.T, np.ones((3, 1))])
    Ainv = np.linalg.inv(A)[:2]  # d(w) rows of [dw; dF] = A^-1 (n_b^T du_b - dr_b)
    return np.einsum("ib,jb->bij", Ainv, nb), -Ainv.T


# ---------------------------------------------------------------------- the slipping period: the period map
def period_pass(u0: list, u1: list, lim: list, kt: float,
                w: tuple[float, float]) -> tuple[list, list, tuple[float, float], NDArray, list]:
    """One period of the radial return map from the slider at ``w``: ``(T0, T1, w_end, A, slips)``.

    ``A = dw_end/dw`` (2 x 2) is the product of the slip samples' ``s (I - c c^T)`` (``c`` the slip
    direction, ``s = L/|T*|``); ``slips`` lists ``(k, s, c0, c1)`` for each slip sample.
    """
    n = len(u0)
    w0, w1 = w
    T0, T1 = [0.0] * n, [0.0] * n
    a00, a01, a10, a11 = 1.0, 0.0, 0.0, 1.0
    slips = []
    for k in range(n):
        t0, t1 = kt * (u0[k] - w0), kt * (u1[k] - w1)
        m, L = math.hypot(t0, t1), lim[k]
        if m < L:  # stick
            T0[k], T1[k] = t0, t1
            continue
        s, c0, c1 = (L / m, t0 / m, t1 / m) if m > 0.0 else (0.0, 0.0, 0.0)
        T0[k], T1[k] = L * c0, L * c1
        w0, w1 = u0[k] - T0[k] / kt, u1[k] - T1[k] / kt
        q00, q01, q11 = s * (1.0 - c0 * c0), -s * c0 * c1, s * (1.0 - c1 * c1)  # Q = s (I - c c^T)
        a00, a01, a10, a11 = (q00 * a00 + q01 * a10, q00 * a01 + q01 * a11,
                              q01 * a00 + q11 * a10, q01 * a01 + q11 * a11)
        slips.append((k, s, c0, c1))
    return T0, T1, (w0, w1), np.array([[a00, a01], [a10, a11]]), slips


def periodic_slip(u: NDArray, lim: NDArray, kt: float, start: NDArray) -> tuple[NDArray, list]:
    """The periodic state of a period that slips: ``(T (2, n), slips)`` of the pass from the fixed
    point of ``P`` (Newton on ``w = P(w)`` with ``A = dP/dw``; a plain period where Newton does
    not reduce ``|P(w) - w|``, which a plain period never increases: ``P`` is nonexpansive)."""
    u0, u1, L = u[0].tolist(), u[1].tolist(), lim.tolist()
    size = max(float(np.max(lim)) / kt, float(np.max(np.ptp(u, axis=1))), np.finfo(float).tiny)
    w = (float(start[0]), float(start[1]))
    out = period_pass(u0, u1, L, kt, w)
    for _ in range(MAX_PERIODS):
        res = np.subtract(out[2], w)
        if math.hypot(*res) <= STATE_RTOL * size:
            return np.array([out[0], out[1]]), out[4]
        try:
            cand = tuple(np.add(w, np.linalg.solve(np.eye(2) - out[3], res)).tolist())
            trial = period_pass(u0, u1, L, kt, cand)
            if math.hypot(*np.subtract(trial[2], cand)) < math.hypot(*res):
                w, out = cand, trial
                continue
        except np.linalg.LinAlgError:
            pass
        w = out[2]
        out = period_pass(u0, u1, L, kt, w)
    raise RuntimeError(f"no periodic state of the return map after {MAX_PERIODS} periods")


def slip_tangent(R: NDArray, n: int, kt: float, dlim: NDArray, slips: list) -> NDArray:
    """``dT @ R`` (2 n, m) of the periodic slipping state for input directions ``R`` (3 n, m).

    Per sample, with ``z_k`` the slider's tangent before it: stick ``dT = kt (du - z)``, ``z`` kept;
    slip ``dT = kt Q (du - z) + c dL``, ``z <- (I - Q) du - c dL/kt + Q z`` (``Q = s (I - c c^T)``).
    Periodicity: ``z_0 = z_n = Phi z_0 + zhat_n`` with ``Phi`` the product of the ``Q``, so
    ``z_0 = (I - Phi)^-1 zhat_n`` and ``z_k = zhat_k + Phi_k z_0`` (the fixed point's derivative).
    """
    m = R.shape[1]
    Ru = np.stack([R[:n], R[n:2 * n]], axis=1)  # (n, 2, m): du_k
    dL = dlim[:, None] * R[2 * n:]  # (n, m)
    ks = np.array([k for k, *_ in slips], dtype=int)
    s = np.array([sl[1] for sl in slips])
    c = np.array([[sl[2], sl[3]] for sl in slips]).reshape(-1, 2)
    Q = s[:, None, None] * (np.eye(2) - c[:, :, None] * c[:, None, :])  # (ns, 2, 2)
    G = Ru[ks] - np.einsum("qij,qjm->qim", Q, Ru[ks]) - c[:, :, None] * dL[ks][:, None, :] / kt
    Z = np.zeros((ks.size + 1, 2, m))
    Phi = np.zeros((ks.size + 1, 2, 2))
    Phi[0] = np.eye(2)
    for q in range(ks.size):  # z after each slip sample
        Z[q + 1] = Q[q] @ Z[q] + G[q]
        Phi[q + 1] = Q[q] @ Phi[q]
    z0 = np.linalg.solve(np.eye(2) - Phi[-1], Z[-1])
    before = np.searchsorted(ks, np.arange(n), side="left")  # slips before sample k
    z = Z[before] + np.einsum("kij,jm->kim", Phi[before], z0)  # (n, 2, m)
    dT = kt * (Ru - z)
    dT[ks] = np.einsum("qij,qjm->qim", Q, dT[ks]) + c[:, :, None] * dL[ks][:, None, :]
    return np.concatenate([dT[:, 0], dT[:, 1]])


class Contact3D(PointContactLaw):
    """Point contact: two tangential directions, a circular Coulomb limit ``mu N``, ``N = max(0, n0 + kn v)``.

    Parameters
    ----------
    kt : float
        Tangential contact stiffness (N/m), the same in both directions, > 0 and finite.
    kn : float
        Normal contact stiffness (N/m), >= 0 and finite (0: the load stays ``n0``).
    mu : float
        Friction coefficient, > 0 and finite.
    n0 : float
        Normal preload (N) at zero normal displacement, finite; <= 0 is a contact open at rest.

    Raises
    ------
    ValueError
        For a parameter out of range, naming it and its value, or parameters whose slip force ``mu n0``,
        slip amplitude ``mu n0 / kt`` or their normal slopes overflow double precision.

    Notes
    -----
    ``components = 3``: :meth:`periodic_force` takes ``x`` of shape (3, n_t) (tangential rows t1, t2,
    then the normal row) and returns the forces (3, n_t) with the Jacobian (3 n_t, 3 n_t);
    :meth:`harmonic_force` takes ``X`` (3, 2H+1).  ``hbm.Contact(el, dof=t1, second_dof=t2,
    normal_dof=n)`` attaches it.  :meth:`fourier` is the Jenkins element at the load ``n0``.

    Examples
    --------
    >>> import numpy as np
    >>> from contact_models import Contact3D
    >>> c = Contact3D(kt=1.0, kn=2.0, mu=0.5, n0=1.0)
    >>> theta = np.arange(8) * np.pi / 4
    >>> f, J = c.periodic_force(np.vstack([np.cos(theta), np.zeros(8), np.zeros(8)]))  # Macroslip(1, 0.5)
    >>> np.round(f[0], 3).tolist()
    [0.5, 0.207, -0.5, -0.5, -0.5, -0.207, 0.5, 0.5]
    >>> f, J = c.periodic_force(np.vstack([np.cos(theta), np.sin(theta), np.zeros(8)]))  # a circle
    >>> np.round(np.hypot(f[0], f[1]), 3).tolist()  # slips all period at |T| = mu n0
    [0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5]
    """

    has_time_law = True
    components = 3

    def _periodic_force(self, x, omega):
        f, tangent = self._periodic_state(x)
        return f, tangent(np.eye(x.size))

    def _harmonic_force(self, X, omega, n_t, rtol):
        """AFT with the tangent propagated along the inverse-FFT columns: ``dF/dX = E (J E^-1)``
        blockwise, ``J E^-1`` from :func:`slip_tangent` (or the stuck centre) with ``R = E^-1``."""
        L = X.shape[1]
        Einv = aft_matrices((L - 1) // 2, n_t)[1]
        x = np.stack([to_time(row, n_t) for row in X])
        f, tangent = self._periodic_state(x)
        R = np.zeros((3 * n_t, 3 * L))
        for a in range(3):
            R[a * n_t:(a + 1) * n_t, a * L:(a + 1) * L] = Einv
        JR = tangent(R).reshape(3, n_t, 3 * L)
        J = to_harmonics(JR.transpose(0, 2, 1), (L - 1) // 2).transpose(0, 2, 1).reshape(3 * L, 3 * L)  # E JR (FFT)
        return to_harmonics(f, (L - 1) // 2), J, np.zeros_like(X)

    def _periodic_state(self, x):
        """Forces (3, n) of the periodic state and ``tangent(R)``: the Jacobian times ``R`` (3 n, m)."""
        u, v = x[:2], x[2]
        n, kt = v.size, self.kt
        p = self.n0 + self.kn * v
        N = np.maximum(p, 0.0)
        dN = np.where(p > 0.0, self.kn, 0.0)
        lim, dlim = self.mu * N, self.mu * dN
        r = lim / kt
        lo, hi = np.max(u - r, axis=1), np.min(u + r, axis=1)  # the discs' shadows on each axis
        start = 0.5 * (lo + hi)
        if np.all(lo <= hi):  # the discs may meet: the clearance centre decides
            w, basis, F = clearance_centre(u, r)
            if F <= 0.0:
                return np.vstack([kt * (u - w[:, None]), N]), self._stuck_tangent(u, r, w, basis, dlim, dN)
            start = w
        T, slips = periodic_slip(u, lim, kt, start)

        def tangent(R):
            return np.concatenate([slip_tangent(R, n, kt, dlim, slips), dN[:, None] * R[2 * n:]])

        return np.vstack([T, N]), tangent

    def _stuck_tangent(self, u, r, w, basis, dlim, dN):
        """``tangent(R)`` of a period stuck at the clearance centre: ``dT_k = kt (du_k - dw)``."""
        n, kt = dN.size, self.kt
        W, om = centre_tangent(u, r, w, basis)

        def tangent(R):
            dw = sum(W[i] @ R[[b, n + b]] + np.outer(om[i], R[2 * n + b]) * (dlim[b] / kt)
                     for i, b in enumerate(basis))
            return np.concatenate([kt * (R[:n] - dw[0]), kt * (R[n:2 * n] - dw[1]), dN[:, None] * R[2 * n:]])

        return tangent


__all__ = ["Contact3D", "clearance_centre", "centre_tangent", "period_pass", "periodic_slip", "slip_tangent"]
