"""Stability of periodic solutions by Hill's method (``docs/multiharmonic.md``, "Stability").

A perturbation ``x(t) = exp(lambda t) p(t)`` of a periodic solution, ``p`` periodic with the
balance's H harmonics (coefficients ``P``, DOF-major layout ``[P0, Pc1, Ps1, ...]`` per DOF),
satisfies the quadratic eigenvalue problem::

    (lambda^2 D2 + lambda D1 + D0) P = 0,
    D2 = M (x) I,   D1 = C (x) I + 2 omega M (x) N,   D0 = K (x) I + omega C (x) N
         + omega^2 M (x) N^2 + dF/dX,

``N`` the derivative operator on the layout (``d/dtheta``: ``c_h' = h s_h``, ``s_h' = -h c_h``)
and ``dF/dX`` the contact forces' Jacobian of the balance (AFT).  ``D0`` is the balance's own
Jacobian in X, so a fold (a real exponent through 0) is exactly where that Jacobian is singular.
For rate-independent friction the perturbation force is taken from that Jacobian (the
linearisation about the periodic motion with the perturbation held periodic), the standard
choice of Hill's method for non-smooth forces (Krack & Gross 2019, ch. 5).

The QEP has ``2 n (2H+1)`` eigenvalues, in families ``lambda + i k omega`` (one Floquet
exponent each, defined modulo ``i omega``).  The ``2 n`` exponents are selected by the
symmetry of their eigenvectors (Lazarus & Thomas, "A harmonic-based method for computing the
stability of periodic solutions of dynamical systems", C. R. Mecanique 338 (2010) 510-517):
writing an eigenvector in complex exponentials ``p(t) = sum_k z_k exp(i k omega t)``, the
member of a family whose weights ``|z_k|^2`` are centred on ``k = 0`` is the one the truncation
represents best; the ``2 n`` eigenvalues with the smallest ``|sum_k k |z_k|^2| / sum_k |z_k|^2``
are kept, ties (to 0.01) going to the smaller ``|Im lambda|``.  (The imaginary-part criterion, "smallest |Im lambda|", fails when a mode's frequency
exceeds ``H omega``: its family's member in the strip ``|Im| <= omega/2`` is then missing from
the truncated problem and copies of other families are picked instead.)  The solution is stable
when every selected exponent has ``Re lambda <= STABILITY_TOL * omega``.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

#: A Floquet exponent with ``Re lambda > STABILITY_TOL * omega`` makes the solution unstable.
STABILITY_TOL = 1e-7
#: A stability change whose critical exponent has ``|Im lambda| > NS_IMAG_TOL * omega`` is a
#: Neimark-Sacker bifurcation (a complex pair crosses); otherwise a real exponent crosses (fold).
NS_IMAG_TOL = 1e-3
#: Couplings of dF between even and odd harmonics below ``PARITY_RTOL`` times its largest entry
#: are rounding (a solution with odd harmonics only): the eigenproblem is split by parity.
PARITY_RTOL = 1e-12


def derivative_operator(harmonics: int) -> NDArray[np.float64]:
    """``N`` (2H+1, 2H+1): coefficients of ``dx/dtheta`` from those of ``x`` (layout above)."""
    L = 2 * harmonics + 1
    N = np.zeros((L, L))
    for h in range(1, harmonics + 1):
        N[2 * h - 1, 2 * h] = h
        N[2 * h, 2 * h - 1] = -h
    return N


def hill_exponents(M: NDArray, C: NDArray, K: NDArray, omega: float, dF: NDArray,
                   harmonics: int) -> NDArray[np.complex128]:
    """The ``2 n`` Floquet exponents (1/s) of the periodic solution at ``omega`` (rad/s).

    Two exact shortcuts of the same eigenproblem (``docs/multiharmonic.md``, "Stability"): a
    ``dF`` that is a constant stiffness on every harmonic (``kron(K_c, I)``: every contact held
    in its linear range) makes the perturbation time-invariant, and the exponents are the
    eigenvalues of ``(M, C, K + K_c)``; a ``dF`` that couples no even harmonic to an odd one
    (a solution with odd harmonics only) splits the eigenproblem into its even and odd parts.

    Parameters
    ----------
    M, C, K : ndarray
        Dense n x n matrices of the model the exponents are computed on.
    omega : float
        Fundamental frequency of the solution (rad/s).
    dF : ndarray
        Jacobian (n(2H+1), n(2H+1)) of the nonlinear forces' harmonics in the displacement
        harmonics, DOF-major layout.
    harmonics : int
        H.

    Returns
    -------
    ndarray
        The 2n exponents with the most centred eigenvectors (module docstring), sorted by real
        part, largest first.

    Examples
    --------
    >>> import numpy as np
    >>> lam = hill_exponents(np.eye(1), 0.2 * np.eye(1), np.eye(1), 1.3, np.zeros((3, 3)), 1)
    >>> np.round(lam.real, 6).tolist()  # -c/(2m) for the linear oscillator, at any omega
    [-0.1, -0.1]
    """
    return HillProblem(M, C, K, harmonics).exponents(omega, dF)


class HillProblem:
    """Hill's eigenproblem of one model (M, C, K) at H harmonics, its omega-free parts formed once.

    ``HillProblem(M, C, K, H).exponents(omega, dF)`` is :func:`hill_exponents` (which see);
    a branch's points share one instance (``FrequencyResponse.stable``).

    Parameters
    ----------
    M, C, K : ndarray
        Dense n x n matrices of the model.
    harmonics : int
        H.
    coupling : tuple of three ndarray, optional
        ``(M_next, C_next, K_next)`` of one sector of a cyclic structure (:class:`hbm.CyclicStructure`),
        with ``angle``: the perturbation is of one travelling-wave family, harmonic h of the next sector
        that of this one turned by ``-h angle`` (``T``, :func:`hbm.balance.layout.next_sector_operator`)
        and times ``exp(-i mu)`` (:meth:`exponents`' ``family``), so each ``kron(A, I)`` becomes
        ``kron(A, I) + exp(-i mu) kron(A_next, T) + exp(i mu) kron(A_next^T, T^T)``
        (``docs/bladed_disks.md``).  Default none: the model is the whole structure.
    angle : float, optional
        ``phi = 2 pi EO / N`` (rad), with ``coupling``.
    """

    def __init__(self, M: NDArray, C: NDArray, K: NDArray, harmonics: int,
                 coupling: tuple[NDArray, NDArray, NDArray] | None = None, angle: float = 0.0) -> None:
        self.M, self.C, self.K = (np.asarray(A, dtype=float) for A in (M, C, K))
        self.n, self.H, self.L = self.M.shape[0], int(harmonics), 2 * int(harmonics) + 1
        self._Minv = np.linalg.inv(self.M)
        self._eye = np.eye(self.L)
        self._coupling = None  # a sector's: the own and the neighbours' parts of M, C, K on the real layout
        if coupling is not None:
            from .layout import next_sector_operator

            T = next_sector_operator(self.H, angle)
            self._coupling = tuple((np.kron(A, self._eye), np.kron(np.asarray(A1, dtype=float), T))
                                   for A, A1 in zip((self.M, self.C, self.K), coupling))
        parity = np.r_[0, np.repeat(np.arange(1, self.H + 1), 2)] % 2
        self._parts = (np.flatnonzero(parity == 0), np.flatnonzero(parity == 1))
        # the rows of every DOF's even and odd coefficients in the DOF-major layout
        self._rows = tuple(np.ravel(np.arange(self.n)[:, None] * self.L + part[None, :]) for part in self._parts)
        self._ops: dict = {}
        self._lwork: dict = {}
        # the last time-invariant case: its exponents do not depend on omega, and a branch's stuck
        # points share one contact stiffness (an equal Kc gives the same eigenproblem, bit for bit)
        self._invariant: tuple = (None, None)

    def exponents(self, omega: float, dF: NDArray, family: float = 0.0) -> NDArray[np.complex128]:
        """The ``2 n`` Floquet exponents (1/s) at ``omega`` for the contacts' Jacobian ``dF``; for a sector
        (``coupling``), those of the perturbations of the family ``mu = family`` (rad): the next sector's
        harmonic h is this one's times ``exp(-i (h phi + mu))``, ``mu = 2 pi m / N`` (``dF`` of that family,
        ``HarmonicBalance.perturbation_jacobian``)."""
        n, L, H = self.n, self.L, self.H
        Kc = dF[::L, ::L]
        blocks = dF.reshape(n, L, n, L)
        if self._coupling is None and np.array_equal(blocks, Kc[:, None, :, None] * self._eye[None, :, None, :]):
            # time-invariant (dF = kron(Kc, I)): the k = 0 member of each family
            key = Kc.tobytes()
            if self._invariant[0] != key:
                lam = _state_space_eigenvalues(self.M, self.C, self.K + Kc)
                self._invariant = (key, lam[np.argsort(-lam.real, kind="stable")])
            return self._invariant[1].copy()
        ie, io = self._rows
        scale = float(np.max(np.abs(dF))) if dF.size else 0.0
        cross = max(float(np.max(np.abs(dF[np.ix_(ie, io)]), initial=0.0)),
                    float(np.max(np.abs(dF[np.ix_(io, ie)]), initial=0.0)))
        parts = self._parts if H > 0 and cross <= PARITY_RTOL * scale else (np.arange(L),)
        lams, centres = [], []
        for part in parts:
            lam, centre = self._eig(omega, dF, part, family)
            lams.append(lam)
            centres.append(centre)
        lam, centre = np.concatenate(lams), np.concatenate(centres)
        # ties (equally centred members, e.g. a real exponent's symmetric +-1 content and a spurious
        # purely static member at H = 1) go to the smaller |Im lambda|
        lam = lam[np.lexsort((np.abs(lam.imag), np.round(centre, 2)))[:2 * n]]
        return lam[np.argsort(-lam.real, kind="stable")]

    def _operators(self, part: NDArray, family: float = 0.0) -> tuple:
        """The omega-free parts of ``-M^-1 D0`` and ``-M^-1 D1`` on the coefficients ``part`` (of the
        family ``family``, a sector's), and what :meth:`_eig` needs to weigh the eigenvectors' harmonics."""
        key = (tuple(part.tolist()), family)
        if key not in self._ops:
            n, L, p = self.n, self.L, part.size
            Nop = derivative_operator(self.H)[np.ix_(part, part)]
            I = np.eye(p)
            Minv = np.kron(self._Minv, I)
            idx = np.ravel(np.arange(n)[:, None] * L + part[None, :])
            # the part's cosine and sine rows of each harmonic h >= 1 (layout 2h - 1, 2h), and its h
            pos = {int(c): j for j, c in enumerate(part)}
            hs = [h for h in range(1, self.H + 1) if 2 * h - 1 in pos]
            rows = (np.array([pos[2 * h - 1] for h in hs], dtype=int), np.array([pos[2 * h] for h in hs], dtype=int))
            if self._coupling is None:
                self._ops[key] = (idx, Minv, Minv @ np.kron(self.K, I), Minv @ np.kron(self.C, Nop),
                                  Minv @ np.kron(self.M, Nop @ Nop), Minv @ np.kron(self.C, I),
                                  Minv @ np.kron(self.M, Nop), np.eye(idx.size), 0 in pos, rows,
                                  np.array(hs, dtype=float)[None, :, None])
            else:  # a sector: the operators block-diagonal in the harmonics, restricted to the part
                turn = np.exp(-1j * family) if family else 1.0
                Mo, Co, Ko = ((own + turn * nxt + np.conj(turn) * nxt.T)[np.ix_(idx, idx)]
                              for own, nxt in self._coupling)
                D = np.kron(np.eye(n), Nop)
                Minv = np.linalg.inv(Mo)
                self._ops[key] = (idx, Minv, Minv @ Ko, Minv @ Co @ D, Minv @ Mo @ D @ D, Minv @ Co, Minv @ Mo @ D,
                                  np.eye(idx.size), 0 in pos, rows, np.array(hs, dtype=float)[None, :, None])
        return self._ops[key]

    def _eig(self, omega: float, dF: NDArray, part: NDArray,
             family: float = 0.0) -> tuple[NDArray[np.complex128], NDArray[np.float64]]:
        """Eigenvalues of the QEP (module docstring) on the coefficients ``part`` of every DOF (the
        rest of the layout zero), and the centre of each displacement eigenvector (module docstring)."""
        from scipy.linalg.lapack import dgeev, dgeev_lwork  # lazily: import hbm stays light

        idx, Minv, MK, MCN, MMN2, MC, MMN, eye, static, (rc, rs), h = self._operators(part, family)
        size = idx.size
        if np.iscomplexobj(Minv) or np.iscomplexobj(dF):  # a sector's family mu != 0: a complex eigenproblem
            return self._eig_complex(omega, dF, idx, (Minv, MK, MCN, MMN2, MC, MMN, eye), static, (rc, rs), h)
        A = np.zeros((2 * size, 2 * size), order="F")  # LAPACK's order: no copy on the call
        A[:size, size:] = eye
        A[size:, :size] = -(MK + omega * MCN + omega * omega * MMN2 + Minv @ dF[np.ix_(idx, idx)])
        A[size:, size:] = -(MC + 2.0 * omega * MMN)
        # LAPACK's real eigensolver, right vectors only (scipy.linalg.eig's own call, without its
        # conversion of the velocity rows to complex): a conjugate pair is stored as
        # wi[j] > 0 at j, j + 1 with vectors vr[:, j] +- i vr[:, j + 1]
        if 2 * size not in self._lwork:  # the workspace scipy.linalg.eig asks for (the same blocking)
            self._lwork[2 * size] = int(dgeev_lwork(2 * size, compute_vl=0, compute_vr=1)[0])
        wr, wi, _, vr, info = dgeev(A, compute_vl=0, compute_vr=1, lwork=self._lwork[2 * size], overwrite_a=1)
        if info != 0:
            raise np.linalg.LinAlgError(f"Hill's eigenproblem at omega = {omega!r}: LAPACK dgeev info = {info}")
        # the eigenvector a + i b of each column (a pair's second column: its conjugate, the same
        # centre up to sign); with z_{+-h} = (c_h -+ i s_h) / 2 per DOF, |2 z_+h|^2 + |2 z_-h|^2 =
        # 2 (a_c^2 + a_s^2 + b_c^2 + b_s^2) and |2 z_+h|^2 - |2 z_-h|^2 = 4 (a_c b_s - a_s b_c)
        a = vr[:size].reshape(self.n, part.size, 2 * size)
        b = np.zeros_like(a)
        j = np.flatnonzero(wi > 0.0)
        b[:, :, j] = b[:, :, j + 1] = a[:, :, j + 1]
        a[:, :, j + 1] = a[:, :, j]
        ac, as_, bc, bs = a[:, rc], a[:, rs], b[:, rc], b[:, rs]
        total = 2.0 * np.sum(ac * ac + as_ * as_ + bc * bc + bs * bs, axis=(0, 1))
        if static:
            total += 4.0 * np.sum(a[:, 0] ** 2 + b[:, 0] ** 2, axis=0)
        centre = 4.0 * np.abs(np.sum(h * (ac * bs - as_ * bc), axis=(0, 1))) / np.maximum(total, 1e-300)
        return wr + 1j * wi, centre


    def _eig_complex(self, omega: float, dF: NDArray, idx: NDArray, ops: tuple, static: bool, rows: tuple,
                     h: NDArray) -> tuple[NDArray[np.complex128], NDArray[np.float64]]:
        """:meth:`_eig` of a complex QEP: the eigenvectors ``a + i b`` are complex, not in conjugate pairs."""
        from scipy.linalg import eig  # lazily: import hbm stays light

        Minv, MK, MCN, MMN2, MC, MMN, eye = ops
        size = idx.size
        A = np.zeros((2 * size, 2 * size), dtype=complex)
        A[:size, size:] = eye
        A[size:, :size] = -(MK + omega * MCN + omega * omega * MMN2 + Minv @ dF[np.ix_(idx, idx)])
        A[size:, size:] = -(MC + 2.0 * omega * MMN)
        lam, vr = eig(A, overwrite_a=True, check_finite=False)
        v = vr[:size].reshape(self.n, -1, 2 * size)
        a, b = v.real, v.imag
        rc, rs = rows
        ac, as_, bc, bs = a[:, rc], a[:, rs], b[:, rc], b[:, rs]
        total = 2.0 * np.sum(ac * ac + as_ * as_ + bc * bc + bs * bs, axis=(0, 1))
        if static:
            total += 4.0 * np.sum(a[:, 0] ** 2 + b[:, 0] ** 2, axis=0)
        centre = 4.0 * np.abs(np.sum(h * (ac * bs - as_ * bc), axis=(0, 1))) / np.maximum(total, 1e-300)
        return lam, centre


def band_modes(M: NDArray, K: NDArray, kept: int, band: float) -> list[int]:
    """Rows of a Craig-Bampton model (``kept`` physical DOFs, then its fixed-interface modes in
    ascending frequency) Hill's method keeps: the physical DOFs, every mode of frequency within
    ``band`` (rad/s) and the first mode above it.  A mode above the band has no member of its family
    of exponents in the strip the truncation resolves; it couples to the contacts quasi-statically,
    and the first one above carries most of that coupling (``docs/multiharmonic.md``, "Stability").

    Examples
    --------
    >>> import numpy as np
    >>> band_modes(np.eye(5), np.diag([9.0, 4.0, 1.0, 16.0, 100.0]), 2, 3.5)  # modes at 1, 4, 10 rad/s
    [0, 1, 2, 3]
    """
    omega = np.sqrt(np.diag(K)[kept:] / np.diag(M)[kept:])
    above = int(np.searchsorted(omega, band, side="right"))
    return list(range(kept + min(above + 1, omega.size)))


def _state_space_eigenvalues(M: NDArray, C: NDArray, K: NDArray) -> NDArray[np.complex128]:
    """The 2n eigenvalues of ``M x'' + C x' + K x = 0``."""
    from scipy.linalg import eigvals  # lazily: import hbm stays light

    n = M.shape[0]
    A = np.zeros((2 * n, 2 * n))
    A[:n, n:] = np.eye(n)
    A[n:, :n] = -np.linalg.solve(M, K)
    A[n:, n:] = -np.linalg.solve(M, C)
    return eigvals(A, overwrite_a=True, check_finite=False)


class StabilityChange(NamedTuple):
    """A change of stability along a branch, located between two points."""

    omega: float  #: rad/s
    amplitude: float  #: m, first harmonic of the response DOF
    kind: str  #: "fold" (a real exponent crosses 0) or "Neimark-Sacker" (a complex pair crosses)
    after: int  #: index of the point before the change


def stability_changes(omega: NDArray, amplitude: NDArray, exponents: NDArray, stable: NDArray,
                      fold_after: NDArray, folds: list[tuple[float, float]]) -> list[StabilityChange]:
    """Locate and classify each change of ``stable`` between neighbouring points.

    Location: the zero of the critical exponent's real part, linear between the two points (at
    a located fold when one lies between them).  Kind: "fold" when a fold lies between the
    points or the critical exponent is real, "Neimark-Sacker" when it is a complex pair.
    """
    out = []
    for i in np.flatnonzero(stable[1:] != stable[:-1]):
        lo, hi = exponents[i], exponents[i + 1]
        crit = hi[0] if not stable[i + 1] else lo[0]  # the exponent with the largest real part
        if i in set(np.asarray(fold_after).tolist()):
            j = list(np.asarray(fold_after)).index(i)
            w, a = folds[j] if j < len(folds) and np.all(np.isfinite(folds[j])) else (omega[i], amplitude[i])
            out.append(StabilityChange(float(w), float(a), "fold", int(i)))
            continue
        r0, r1 = lo[0].real, hi[0].real
        s = r0 / (r0 - r1) if r0 != r1 else 0.5
        s = min(max(s, 0.0), 1.0)
        w = omega[i] + s * (omega[i + 1] - omega[i])
        a = amplitude[i] + s * (amplitude[i + 1] - amplitude[i])
        kind = "Neimark-Sacker" if abs(crit.imag) > NS_IMAG_TOL * max(omega[i], 1e-300) else "fold"
        out.append(StabilityChange(float(w), float(a), kind, int(i)))
    return out


def single_harmonic_stability(blade: Any, element: Any, omega: NDArray, x_c: NDArray,
                               x_s: NDArray) -> NDArray[np.bool_]:
    """Hill's method at H = 1 for the points of a blade's single-harmonic FRF (``FrequencyResponse.stable``).

    The element's Jacobian is that of its describing function (``harmonic_force`` at H = 1); an
    element within its linear range is a spring ``k_s`` for a perturbation (static term included).
    """
    M, C, K = (np.array([[v]]) for v in (blade.mass, blade.damping, blade.stiffness))
    out = np.ones(len(omega), dtype=bool)
    for i, (w, xc, xs) in enumerate(zip(omega, x_c, x_s)):
        w = float(w)
        dF = np.zeros((3, 3))
        if element is not None:
            if float(np.hypot(xc, xs)) <= element.linear_amplitude(w):
                dF = float(element.linear_coefficients(w)[0]) * np.eye(3)
            else:
                dF = element.harmonic_force(np.array([0.0, xc, xs]), w)[1]
        lam = hill_exponents(M, C, K, w, dF, 1)
        out[i] = lam[0].real <= STABILITY_TOL * max(w, 1e-300)
    return out


__all__ = ["single_harmonic_stability", "hill_exponents", "HillProblem", "derivative_operator", "StabilityChange", "stability_changes", "STABILITY_TOL"]
