"""One sector of a tuned bladed disk under travelling-wave excitation: ``CyclicStructure``.

The whole disk of N identical sectors is block-circulant: sector j's DOFs couple to themselves by
the sector's M, C, K and to the next sector's (j + 1 mod N) by ``M_next``, ``C_next``, ``K_next``
(rows this sector, columns the next), to the previous one by their transposes.  An engine-order
excitation EO drives sector j with the sector's force lagging by ``2 pi EO j / N``; the steady
response of the tuned disk is a travelling wave with the same lag, so harmonic h of the next
sector is this sector's own times ``exp(-i h phi)``, ``phi = 2 pi EO / N``, and one sector's
balance with

    Z_h = K_h - (h omega)^2 M_h + i h omega C_h,
    A_h = A + A_next exp(-i h phi) + A_next^T exp(+i h phi)   (A = M, C, K)

carries the whole disk (``docs/bladed_disks.md`` derives it).  Harmonic h meets nodal diameter
``h EO mod N`` (the static term, h = 0, nodal diameter 0).  :meth:`CyclicStructure.full` builds the
whole disk as a plain :class:`hbm.Structure` with every contact, the independent check of the
reduction and the model of a mistuned disk.
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._validation import count, number_array, shown
from .structure import (NEGATIVE_EIGENVALUE_RTOL, Contact, Structure, _check_matrix, _dense, contact_within,
                        negative_eigenvalue)

#: The most sectors a cyclic structure takes: its constructor checks the disk's mass at every nodal diameter
#: and :meth:`CyclicStructure.full` builds N n DOFs, so the cost grows with N (a bladed disk has tens to a
#: few hundred sectors).
MAX_SECTORS = 1000


def _coupling(name: str, A: Any, n: int) -> NDArray[np.float64]:
    """A coupling matrix (n x n, real, finite; not symmetric in general), zero when None."""
    if A is None:
        return np.zeros((n, n))
    try:
        raw = np.asarray(A.toarray() if hasattr(A, "toarray") else A)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a square matrix of numbers, got {name}={A!r}") from None
    if np.iscomplexobj(raw):
        raise ValueError(f"{name} must be real, got a complex {name}")
    try:  # strings, booleans and None refused, as in M, C, K
        raw = number_array(name, raw)
    except ValueError:
        raise ValueError(f"{name} must be a square matrix of numbers, got {name}={shown(A)}") from None
    if raw.shape != (n, n):
        raise ValueError(f"{name} must be {n} x {n} like M, got {name} of shape {raw.shape}")
    if not np.all(np.isfinite(raw)):
        raise ValueError(f"{name} must be finite, got {name} with a non-finite entry")
    return raw


def _integer(name: str, value: Any) -> int:
    """``value`` as an int where it is an integer (not a bool), else a ValueError naming ``name``: a harmonic or
    nodal diameter of 2.5 or "1" has no meaning (``int()`` would take it as 2 or 1)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise ValueError(f"{name} must be an integer, got {name}={value!r}")
    return int(value)


class CyclicStructure(Structure):
    """One sector of a tuned cyclic structure (a bladed disk) under engine-order excitation.

    Parameters
    ----------
    M, C, K : array_like or scipy.sparse matrix
        The sector's own mass (kg), damping (N s/m) and stiffness (N/m), n x n, symmetric (the
        diagonal blocks of the whole disk).
    sectors : int
        N, the number of sectors, 2..``MAX_SECTORS``.
    engine_order : int
        EO, any integer: it is reduced mod N (EO and EO + N drive every sector with the same
        phase); a negative EO is a backward travelling wave.  Stored reduced, in 0..N-1.
    force : array_like
        The force amplitudes on sector 0 (N), length n, real or complex (a phase per DOF,
        :class:`hbm.Structure`); sector j's is ``force exp(-i 2 pi EO j / N)``.
    M_next, C_next, K_next : array_like, optional
        n x n, real: the coupling of this sector's DOFs (rows) to the next sector's (columns).
        Default zero.

    Attributes
    ----------
    sectors, engine_order : int
        N and EO (reduced mod N).
    M_next, C_next, K_next : ndarray
        The couplings (dense).
    sector_angle : float
        ``phi = 2 pi EO / N``.

    Raises
    ------
    ValueError
        Naming the parameter: sectors not an integer in 2..``MAX_SECTORS``, engine_order not an integer, a matrix
        of another size, or a disk whose mass is not positive definite, or damping or stiffness not positive
        semi-definite, at some nodal diameter.

    Notes
    -----
    The balance of one sector carries the whole disk only while every sector moves alike (a tuned
    disk, travelling-wave excitation); a mistuned disk needs :meth:`full` with its sectors made
    different.  Hill's stability of the sector's solutions covers the perturbations of the same
    travelling-wave family (``docs/bladed_disks.md``).

    Examples
    --------
    Two masses per sector in a ring: the sector's nodal-diameter frequencies are those of the whole
    disk.

    >>> import numpy as np
    >>> K = np.array([[3.0, -1.0], [-1.0, 1.0]]); K1 = np.array([[-1.0, 0.0], [0.0, 0.0]])
    >>> disk = CyclicStructure(np.eye(2), 0.01 * np.eye(2), K, sectors=6, engine_order=2, force=[0.0, 1.0],
    ...                        K_next=K1)
    >>> full, _ = disk.full()
    >>> w_full = np.sort(full.natural_frequencies())
    >>> w_nd = np.sort(np.concatenate([disk.natural_frequencies(k) for k in range(6)]))
    >>> bool(np.allclose(w_full, w_nd))
    True
    """

    def __init__(self, M: ArrayLike, C: ArrayLike, K: ArrayLike, *, sectors: int, engine_order: int,
                 force: ArrayLike, M_next: ArrayLike | None = None, C_next: ArrayLike | None = None,
                 K_next: ArrayLike | None = None) -> None:
        if isinstance(sectors, bool) or not isinstance(sectors, (int, np.integer)) or sectors < 2:
            raise ValueError(f"sectors must be an integer >= 2, got sectors={sectors!r}")
        count("sectors", sectors, 2, MAX_SECTORS, "hbm.cyclic.MAX_SECTORS")
        if isinstance(engine_order, bool) or not isinstance(engine_order, (int, np.integer)):
            raise ValueError(f"engine_order must be an integer (reduced mod sectors), got engine_order={engine_order!r}")
        super().__init__(M, C, K, force=force)
        n = self.n
        self.sectors = int(sectors)
        self.engine_order = int(engine_order) % self.sectors
        self.M_next = _coupling("M_next", M_next, n)
        self.C_next = _coupling("C_next", C_next, n)
        self.K_next = _coupling("K_next", K_next, n)
        self.sector_angle = 2.0 * math.pi * self.engine_order / self.sectors
        #: The contacts of the last ``hbm.frequency_response`` of this sector (what :meth:`full` repeats by default).
        self.solved_contacts: list[Contact] = []
        self._check_disk()

    def _check_disk(self) -> None:
        """Refuse a disk whose mass is not positive definite, or damping or stiffness not positive semi-definite
        (as :class:`hbm.Structure` refuses them): the disk's matrices are block-circulant, so their eigenvalues
        are those of every nodal diameter's (:meth:`nodal_matrices`); a coupling of zero leaves the sector's own,
        already checked."""
        for k in range(self.sectors):
            Mk, Ck, Kk = self.nodal_matrices(k)
            try:
                np.linalg.cholesky(Mk)
            except np.linalg.LinAlgError:
                raise ValueError(f"M, M_next must give a positive definite disk mass, got one not positive definite "
                                 f"at nodal diameter {k}") from None
            for name, A1, Ak, what in (("C", self.C_next, Ck, "damping (no negative damping)"),
                                       ("K", self.K_next, Kk, "stiffness (no negative stiffness: the disk would be "
                                                              "statically unstable)")):
                found = negative_eigenvalue(Ak) if np.any(A1) else None
                if found is not None:
                    raise ValueError(f"{name}, {name}_next must give a positive semi-definite disk {what}, got one "
                                     f"with a negative eigenvalue at nodal diameter {k} (smallest {found[0]:.6g}, "
                                     f"largest in magnitude {found[1]:.6g})")

    def __repr__(self) -> str:
        return (f"CyclicStructure(n={self.n} per sector, sectors={self.sectors}, engine_order={self.engine_order}, "
                f"forced DOFs {np.flatnonzero(self.force).tolist()})")

    # ------------------------------------------------------------ nodal diameters
    def nodal_diameter(self, h: int) -> int:
        """The nodal diameter ``h EO mod N`` harmonic ``h`` (an integer) of the travelling wave meets (0..N-1)."""
        return (_integer("h", h) * self.engine_order) % self.sectors

    def nodal_matrices(self, k: int) -> tuple[NDArray, NDArray, NDArray]:
        """``(M_k, C_k, K_k)``, complex Hermitian n x n: ``A + A_next exp(-i 2 pi k / N) + A_next^T exp(+i 2 pi k / N)``,
        the sector's matrices for a motion whose next sector is its own times ``exp(-i 2 pi k / N)``
        (nodal diameter k, an integer taken mod N)."""
        e = np.exp(-2j * math.pi * (_integer("k", k) % self.sectors) / self.sectors)
        return tuple(_dense(A) + A1 * e + A1.T * np.conj(e)
                     for A, A1 in ((self.M, self.M_next), (self.C, self.C_next), (self.K, self.K_next)))

    def harmonic_matrices(self, h: int) -> tuple[NDArray, NDArray, NDArray]:
        """``(M_h, C_h, K_h)`` of harmonic ``h``: :meth:`nodal_matrices` of its nodal diameter
        ``h EO mod N`` (module docstring)."""
        return self.nodal_matrices(self.nodal_diameter(h))

    def natural_frequencies(self, nodal_diameter: int | None = None) -> NDArray[np.float64]:
        """Undamped natural frequencies (rad/s) of the disk's modes of one nodal diameter (default
        EO's, the one harmonic 1 meets), ascending: the eigenvalues of ``(K_k, M_k)``.  One below
        ``-NEGATIVE_EIGENVALUE_RTOL`` times the largest in magnitude is negative (ValueError), as for a structure;
        above it, the rounding of a zero (the disk's rigid rotation), frequency 0."""
        from scipy.linalg import eigh  # lazily: import hbm stays light

        k = self.engine_order if nodal_diameter is None else _integer("nodal_diameter", nodal_diameter)
        Mk, _, Kk = self.nodal_matrices(k)
        lam = eigh(Kk, Mk, eigvals_only=True)
        if lam.size and lam[0] < -NEGATIVE_EIGENVALUE_RTOL * float(np.max(np.abs(lam))):
            raise ValueError(f"K has a negative eigenvalue {float(lam[0]):.3g} at nodal diameter {k}: the disk is unstable")
        return np.sqrt(np.clip(lam, 0.0, None))

    def reduce(self, keep: Sequence[int], *, modes: int) -> Any:
        """Not available for a sector: a Craig-Bampton model of a sector must keep the DOFs its
        couplings touch; reduce the sector's model before building the disk."""
        raise ValueError("reduce is not available for a CyclicStructure (the couplings to the neighbours need the "
                         f"interface DOFs kept); reduce the sector before building it, got keep={keep!r}")

    # ------------------------------------------------------------ the whole disk
    def full(self, contacts: Sequence[Contact] | None = None) -> tuple[Structure, list[Contact]]:
        """The whole disk as a :class:`hbm.Structure` and its contacts.

        DOF d of sector j is ``j n + d``.  The matrices are block-circulant and sparse (CSR): the
        sector's own on the diagonal blocks, ``A_next`` in block (j, j + 1 mod N) and its transpose in
        (j + 1, j).  The force of sector j is ``force exp(-i 2 pi EO j / N)`` (complex, real for EO 0).
        Every contact is repeated on every sector: one within the sector joins ``j n + p`` and
        ``j n + q``, a ``next_sector`` one ``(j + 1 mod N) n + p`` and ``j n + q`` (its other pairs alike).

        Parameters
        ----------
        contacts : sequence of hbm.Contact, optional
            The sector's contacts.  Default: those of the last ``hbm.frequency_response`` of this
            sector (none before the first).

        Returns
        -------
        (Structure, list of Contact)
        """
        from scipy import sparse  # lazily: import hbm stays light

        N, n = self.sectors, self.n
        blocks = []
        for A, A1 in ((self.M, self.M_next), (self.C, self.C_next), (self.K, self.K_next)):
            own = sparse.kron(sparse.identity(N), sparse.csr_matrix(_dense(A)))
            shift = sparse.diags([np.ones(N - 1), np.ones(1)], [1, -(N - 1)], shape=(N, N))  # (j, j + 1 mod N)
            nxt = sparse.kron(shift, sparse.csr_matrix(A1))
            blocks.append((own + nxt + nxt.T).tocsr())
        phase = np.exp(-2j * math.pi * self.engine_order * np.arange(N) / N)
        f = (phase[:, None] * self.force[None, :]).ravel()
        full = Structure(*blocks, force=f)
        out: list[Contact] = []
        from .balance.residual import as_contacts  # (the balance imports this module's neighbours)

        # one Contact or a sequence of them, as frequency_response takes them (a number was "not iterable")
        for c in self.solved_contacts if contacts is None else as_contacts(contacts, n):
            contact_within(c, n)  # a DOF past the sector's would land on the next sector's
            for j in range(N):
                out.append(self._placed(c, j))
        return full, out

    def _placed(self, c: Contact, j: int) -> Contact:
        """Sector j's copy of the sector's contact ``c`` on the whole disk's DOFs."""
        N, n = self.sectors, self.n
        here, there = j * n, ((j + 1) % N) * n

        def pair(ix: tuple[int, ...]) -> tuple[int, ...]:
            if len(ix) == 1:
                return (here + ix[0],)
            return ((there if c.next_sector else here) + ix[0], here + ix[1])

        kw: dict[str, Any] = {}
        d = pair(c.dofs)
        kw["dof" if len(d) == 1 else "dofs"] = d[0] if len(d) == 1 else d
        for one, two, ix in (("second_dof", "second_dofs", c.second_dofs), ("normal_dof", "normal_dofs", c.normal_dofs)):
            if ix:
                d = pair(ix)
                kw[one if len(d) == 1 else two] = d[0] if len(d) == 1 else d
        return Contact(c.element, **kw)


__all__ = ["CyclicStructure"]
