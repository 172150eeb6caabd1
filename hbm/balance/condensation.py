"""Condensation of a structure onto the DOFs its contacts touch (and the response DOF).

With ``Z(s) = K + s C + s^2 M`` and the compliance ``G_h = [Z(i h omega)^-1]_aa`` at the
condensation DOFs ``a``, the linear DOFs are eliminated exactly, harmonic by harmonic: the
response at ``a`` is ``X = X_lin(omega) - G(omega) F``, ``F`` the contact forces' harmonics.
``G`` and its omega-derivative come from the state-space modes of (M, C, K), computed once
(:func:`hbm.structure.modal_compliance`), so an evaluation costs ``O(n_a^2 n H)`` whatever
the structure's size (``docs/multiharmonic.md`` derives every coefficient).
"""

from __future__ import annotations

import hashlib
import math
import weakref
from typing import Any, Sequence

import numpy as np
from numpy.typing import NDArray

from ..structure import Structure, modal_compliance
from .layout import to_complex

#: Largest ``n_a (n_a + 1) 2n`` for which the poles' residues at the condensation DOFs are kept
#: (16 bytes each): beyond it G is formed per harmonic instead.
RESIDUE_ENTRIES = 4_000_000


#: The state-space modes of each structure solved so far, with the fingerprint of its matrices:
#: the balances of one solve (the FRF's, and those of its error estimate at more harmonics and
#: samples) share one modal decomposition.
_MODES: "weakref.WeakKeyDictionary[Structure, tuple[bytes, tuple]]" = weakref.WeakKeyDictionary()


def _fingerprint(structure: Structure) -> bytes:
    """A digest of M, C, K as they are now (a matrix changed in place gives another)."""
    digest = hashlib.blake2b(digest_size=20)
    for A in (structure.M, structure.C, structure.K):
        parts = (A.data, A.indices, A.indptr) if hasattr(A, "indptr") else (np.ascontiguousarray(A),)
        digest.update(repr((A.shape, [np.asarray(a).dtype.str for a in parts])).encode())
        for a in parts:
            digest.update(np.ascontiguousarray(a).data)
    return digest.digest()


def structure_modes(structure: Structure) -> tuple[NDArray, NDArray, NDArray]:
    """:func:`hbm.structure.modal_compliance` of ``structure``, computed once while its matrices
    stay the same."""
    fp = _fingerprint(structure)
    known = _MODES.get(structure)
    if known is not None and known[0] == fp:
        return known[1]
    modes = modal_compliance(structure.M, structure.C, structure.K)
    _MODES[structure] = (fp, modes)
    return modes


class Condensed:
    """The structure's compliance at a set of DOFs for harmonics 0..H (state-space modes).

    Parameters
    ----------
    structure : hbm.Structure
        The linear structure.
    dofs : sequence of int
        The condensation DOFs ``a``.
    harmonics : int
        The highest harmonic H.
    """

    def __init__(self, structure: Structure, dofs: Sequence[int], harmonics: int) -> None:
        self.lam, V, B = structure_modes(structure)
        self.V, self.B = V, B
        self.dofs = np.asarray(dofs, dtype=int)
        self.Va = V[self.dofs]  # (n_a, 2n)
        self.Ba = B[:, self.dofs]  # (2n, n_a)
        self.bf = B @ structure.force  # (2n,)
        self.h = np.arange(harmonics + 1)
        self._ih = (1j * self.h[:, None], -1j * self.h[:, None])  # i h and -i h, (H+1, 1)
        na = self.dofs.size
        # the residues of every pole at the pairs (a, b), once: G_h(omega) is then one matrix
        # product over the poles, (n_a^2, 2n) @ (2n, H+1), with the forcing's row appended
        self._residues: NDArray | None = None
        if na * (na + 1) * self.lam.size <= RESIDUE_ENTRIES:
            self._residues = np.vstack([(self.Va[:, None, :] * self.Ba.T[None, :, :]).reshape(na * na, -1),
                                        self.Va * self.bf[None, :]])
        self._cache: tuple | None = None
        self._real_cache: tuple | None = None
        self._layout: tuple | None = None

    def at(self, omega: float) -> tuple[NDArray, NDArray, NDArray, NDArray]:
        """``(G, dG/domega, x_lin, dx_lin/domega)``: G (H+1, n_a, n_a) complex, x_lin (n_a,) complex."""
        if self._cache is not None and self._cache[0] == omega:
            return self._cache[1]
        S, dS = self._poles(omega)
        na, n1 = self.dofs.size, self.h.size
        if self._residues is not None:
            both = self._residues @ np.concatenate((S, dS)).T  # (n_a^2 + n_a, 2 (H+1))
            G = both[:na * na, :n1].T.reshape(n1, na, na)
            dG = both[:na * na, n1:].T.reshape(n1, na, na)
            xl, dxl = both[na * na:, 1], both[na * na:, n1 + 1]
        else:  # many condensation DOFs: per harmonic, (n_a, 2n) @ (2n, n_a)
            G = np.matmul(self.Va[None, :, :] * S[:, None, :], self.Ba)
            dG = np.matmul(self.Va[None, :, :] * dS[:, None, :], self.Ba)
            xl = self.Va @ (S[1] * self.bf)
            dxl = self.Va @ (dS[1] * self.bf)
        G = np.ascontiguousarray(G)
        dG = np.ascontiguousarray(dG)
        G[0] = G[0].real
        out = (G, dG, xl, dxl)
        self._cache = (omega, out)
        return out

    def _poles(self, omega: float) -> tuple[NDArray, NDArray]:
        """``1/(i h omega - lambda_j)`` (H+1, 2n) and its omega-derivative.

        ``h omega`` exactly on an undamped pole (a natural frequency of the structure without damping) has
        no finite compliance: a ``ZeroDivisionError`` saying so (a failed step to a continuation), not
        numpy's warnings and an inf/NaN compliance."""
        ih, mih = self._ih
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            S = 1.0 / (ih * omega - self.lam[None, :])
            dS = mih * S * S
        if not (np.isfinite(S).all() and np.isfinite(dS).all()):
            h = int(np.flatnonzero(~np.isfinite(S).all(axis=1) | ~np.isfinite(dS).all(axis=1))[0])
            raise ZeroDivisionError(f"omega={omega!r} puts harmonic {h} on a natural frequency of the undamped "
                                    "structure: its compliance is infinite there")
        return S, dS

    def real_at(self, omega: float) -> tuple[NDArray, NDArray, NDArray, NDArray, NDArray, NDArray]:
        """For one condensation DOF: ``G`` and ``dG/domega`` as the multipliers ``(a, b)`` of the real
        layout, ``G F = a F + b F_swapped`` (``a = [g_0, g_r1, g_r1, ...]``, ``b = [0, g_i1, -g_i1, ...]``,
        ``F_swapped`` with each harmonic's cos and sin exchanged), then ``x_lin`` and ``dx_lin/domega``."""
        if self._real_cache is not None and self._real_cache[0] == omega:
            return self._real_cache[1]
        n1 = self.h.size
        if self._residues is None:
            G, dG, xl, dxl = self.at(omega)
            gdg, xl, dxl = np.concatenate((G[:, 0, 0], dG[:, 0, 0])), xl[0], dxl[0]
        else:  # at's product, without its (H+1, 1, 1) copies
            both = self._residues @ np.concatenate(self._poles(omega)).T  # (2, 2 (H+1))
            gdg, xl, dxl = both[0], both[1, 1], both[1, n1 + 1]
        L = 2 * n1 - 1
        if self._layout is None:  # in [g, dg]: h of each real coefficient [0, 1, 1, 2, 2, ...], twice; the signs of b
            at = (np.arange(L) + 1) // 2
            sign = np.array([0.0] + [1.0, -1.0] * self.h[-1])
            self._layout = (np.concatenate((at, at + n1)), np.concatenate((sign, sign)))
        at, sign = self._layout
        re, im = gdg.real[at], gdg.imag[at] * sign  # sign[0] = 0: Im g_0 out
        res = (re[:L], im[:L], re[L:], im[L:], xl, dxl)
        self._real_cache = (omega, res)
        return res

    def response(self, omega: float, F: NDArray) -> NDArray[np.complex128]:
        """Complex harmonics (n, H+1) of every DOF for contact-force harmonics F (n_a, 2H+1)."""
        S = 1.0 / (1j * self.h[:, None] * omega - self.lam[None, :])
        c = to_complex(F)  # (n_a, H+1)
        Xall = -np.einsum("nj,hj,ja,ah->nh", self.V, S, self.Ba, c)
        Xall[:, 1] += self.V @ (S[1] * self.bf)
        Xall[:, 0] = Xall[:, 0].real
        return Xall


#: The state-space modes of each nodal diameter of each cyclic sector solved so far, with the fingerprint
#: of its matrices (the couplings included).
_ND_MODES: "weakref.WeakKeyDictionary[Structure, tuple[bytes, dict]]" = weakref.WeakKeyDictionary()


def nodal_modes(structure: Structure, k: int) -> tuple[NDArray, NDArray, NDArray]:
    """:func:`hbm.structure.modal_compliance` of a cyclic sector's nodal diameter ``k``
    (``structure.nodal_matrices(k)``), computed once while its matrices stay the same."""
    digest = hashlib.blake2b(_fingerprint(structure), digest_size=20)
    for A in (structure.M_next, structure.C_next, structure.K_next):
        digest.update(np.ascontiguousarray(A).data)
    fp = digest.digest()
    known = _ND_MODES.get(structure)
    if known is None or known[0] != fp:
        known = _ND_MODES[structure] = (fp, {})
    if k not in known[1]:
        known[1][k] = modal_compliance(*structure.nodal_matrices(k))
    return known[1][k]


class CyclicCondensed(Condensed):
    """:class:`Condensed` of one sector of a cyclic structure (``structure.sector_angle`` set): harmonic
    h's compliance ``G_h = [Z_h^-1]_aa`` from the state-space modes of its nodal diameter's complex
    Hermitian matrices (:meth:`hbm.CyclicStructure.harmonic_matrices`), one decomposition per nodal
    diameter; the forcing at harmonic 1 (``docs/bladed_disks.md``).  The same interface: :meth:`at`,
    :meth:`real_at` (through :meth:`at`) and :meth:`response`.

    Parameters
    ----------
    structure : hbm.CyclicStructure
        The sector.
    dofs : sequence of int
        The condensation DOFs ``a``.
    harmonics : int
        The highest harmonic H.
    """

    def __init__(self, structure: Structure, dofs: Sequence[int], harmonics: int) -> None:
        self.dofs = np.asarray(dofs, dtype=int)
        self.h = np.arange(harmonics + 1)
        self._ih = (1j * self.h[:, None], -1j * self.h[:, None])
        nd = [structure.nodal_diameter(h) for h in range(max(harmonics, 1) + 1)]
        # one modal decomposition per nodal diameter (kept for the structure's other balances), and the
        # harmonics that meet it
        modes = {k: nodal_modes(structure, k) for k in dict.fromkeys(nd)}
        self._groups = []
        for k, (lam, V, B) in modes.items():
            hs = np.flatnonzero(np.asarray(nd[:self.h.size]) == k)
            if hs.size:
                self._groups.append((hs, lam, V, B, V[self.dofs], B[:, self.dofs]))
        lam, V, B = modes[nd[1]]
        self._forced = (lam, V, V[self.dofs], B @ structure.force)
        self._residues = None  # real_at goes through at
        self._cache = self._real_cache = self._layout = None

    def at(self, omega: float) -> tuple[NDArray, NDArray, NDArray, NDArray]:
        """``(G, dG/domega, x_lin, dx_lin/domega)`` as :meth:`Condensed.at`, harmonic by harmonic."""
        if self._cache is not None and self._cache[0] == omega:
            return self._cache[1]
        na, n1 = self.dofs.size, self.h.size
        G = np.empty((n1, na, na), dtype=complex)
        dG = np.empty((n1, na, na), dtype=complex)
        for hs, lam, _, _, Va, Ba in self._groups:
            ih = 1j * hs[:, None]
            S = 1.0 / (ih * omega - lam[None, :])
            G[hs] = np.matmul(Va[None, :, :] * S[:, None, :], Ba)
            dG[hs] = np.matmul(Va[None, :, :] * (-ih * S * S)[:, None, :], Ba)
        lam, _, Va, bf = self._forced
        S1 = 1.0 / (1j * omega - lam)
        xl, dxl = Va @ (S1 * bf), Va @ (-1j * S1 * S1 * bf)
        G[0] = G[0].real  # nodal diameter 0: real matrices
        out = (G, dG, xl, dxl)
        self._cache = (omega, out)
        return out

    def response(self, omega: float, F: NDArray) -> NDArray[np.complex128]:
        """Complex harmonics (n, H+1) of every DOF of the sector for contact-force harmonics F (n_a, 2H+1)."""
        c = to_complex(F)  # (n_a, H+1)
        lam, V, _, bf = self._forced
        Xall = np.zeros((V.shape[0], self.h.size), dtype=complex)
        for hs, lam_k, Vk, Bk, _, Ba in self._groups:
            S = 1.0 / (1j * hs[:, None] * omega - lam_k[None, :])
            Xall[:, hs] = -np.einsum("nj,hj,ja,ah->nh", Vk, S, Ba, c[:, hs])
        Xall[:, 1] += V @ (bf / (1j * omega - lam))
        Xall[:, 0] = Xall[:, 0].real
        return Xall


def condensed(structure: Structure, dofs: Sequence[int], harmonics: int) -> Condensed:
    """The condensation of ``structure`` at ``dofs``: :class:`Condensed`, or :class:`CyclicCondensed` for
    one sector of a cyclic structure (``structure.sector_angle`` set)."""
    if structure.sector_angle is None:
        return Condensed(structure, dofs, harmonics)
    return CyclicCondensed(structure, dofs, harmonics)


def stuck_matrix(contacts: Sequence[Any], dofs: Sequence[int], omega: float,
                 angle: float = 0.0, stiffness: Sequence[complex] | None = None) -> NDArray[np.complex128]:
    """Complex stiffness (n_a, n_a) of the contacts held in their linear range at omega (rigid: 0), for a
    motion whose next sector is this one's times ``exp(-i angle)`` (a ``next_sector`` contact's p; 0:
    the static term, or a structure that is not a sector); ``stiffness``: each contact's complex
    stiffness instead (an equivalent linear system, ``hbm.balance.start``)."""
    pos = {d: i for i, d in enumerate(dofs)}
    Kc = np.zeros((len(dofs), len(dofs)), dtype=complex)
    turn = complex(math.cos(angle), -math.sin(angle))
    for e, c in enumerate(contacts):
        ks, kc = c.element.linear_coefficients(omega) if stiffness is None else (stiffness[e].real, stiffness[e].imag)
        k = complex(ks, kc) if math.isfinite(ks) and math.isfinite(kc) else 0.0
        ix = [pos[d] for d in c.dofs]
        if c.next_sector:  # relative motion turn c_p - c_q; force conj(turn) f on p, -f on q
            sg = [turn, -1.0]
            for i, si in zip(ix, sg):
                for j, sj in zip(ix, sg):
                    Kc[i, j] += np.conj(si) * sj * k
            continue
        sg = [1.0, -1.0][:len(ix)]
        for i, si in zip(ix, sg):
            for j, sj in zip(ix, sg):
                Kc[i, j] += si * sj * k
    return Kc


__all__ = ["Condensed", "CyclicCondensed", "condensed", "nodal_modes", "stuck_matrix", "structure_modes"]
