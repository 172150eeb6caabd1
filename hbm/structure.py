"""Linear structures with contacts: ``Structure(M, C, K, force=f)`` and ``Contact``.

The equation of motion (``docs/multiharmonic.md``)::

    M x'' + C x' + K x + sum_contacts P_k f_k(x) = f cos(omega t)

with ``f_k`` the force of contact ``k`` for the displacement of its DOF (to ground) or the
relative displacement ``x_i - x_j`` (acting +f on i, -f on j).  Helpers build C from modal
damping ratios or Rayleigh coefficients, read M and K from ``.npz`` or Matrix Market files, and
reduce a large model by Craig-Bampton (:meth:`Structure.reduce`).

Why Craig-Bampton and not modal truncation with a static correction: the contact DOFs stay
physical DOFs of the reduced model (contacts attach to them unchanged, and several contacts or
relative contacts need no special treatment), the static response at every kept DOF is exact
(the constraint modes are the exact static shapes), and the error of the dynamic response falls
with the fixed-interface modes kept; the reduced M, C, K are symmetric and M stays positive
definite, so the reduced structure is again a ``Structure`` with every check and solver.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from contact_models import ContactElement

from ._validation import count, nonnegative, number_array, shown

#: An eigenvalue of (K, M) below ``-NEGATIVE_EIGENVALUE_RTOL`` times the largest one in magnitude
#: is negative (K indefinite: :meth:`Structure.natural_frequencies` raises); above it, rounding of
#: a zero (rigid-body) eigenvalue.
NEGATIVE_EIGENVALUE_RTOL = 1e-10
#: Relative asymmetry ``max|A - A^T| / max|A|`` above which a matrix is refused as not symmetric.
SYMMETRY_RTOL = 1e-10


def _dense(A: Any) -> NDArray[np.float64]:
    return np.asarray(A.toarray() if hasattr(A, "toarray") else A, dtype=float)


def _is_complex(A: Any) -> bool:
    return np.iscomplexobj(A.data if hasattr(A, "nnz") else A)


def _dense_complex(A: Any) -> NDArray[np.complex128]:
    return np.asarray(A.toarray() if hasattr(A, "toarray") else A, dtype=complex)


def _real(name: str, A: Any, what: str) -> Any:
    """``A`` itself, or the real part of a complex ``A`` whose imaginary parts are all zero; a
    ValueError naming ``name`` if one is not (casting to float would drop it with only numpy's
    ComplexWarning: a silently wrong structure)."""
    data = A.data if hasattr(A, "tocsr") and hasattr(A, "nnz") else A
    if not np.iscomplexobj(data):
        return A
    imag = np.abs(np.imag(data))
    if imag.size and float(np.max(imag)) != 0.0:
        raise ValueError(f"{name} must be real, got a complex {what} (max|Im {name}| = {float(np.max(imag)):.3g})")
    return A.real


def _check_matrix(name: str, A: Any, n: int | None) -> Any:
    """Validate one of M, C, K (dense or scipy.sparse): real, square, size n, finite, symmetric.  A sparse
    matrix or array of any format is converted to CSR first: the checks read its stored entries, which the
    other formats keep differently (DIA pads its diagonals, LIL holds lists) or not at all (DOK)."""
    sparse = hasattr(A, "tocsr") and hasattr(A, "nnz")
    if sparse:
        A = _real(name, A.tocsr(), "matrix")
    else:
        try:
            raw = np.asarray(A)
        except (TypeError, ValueError):
            raise ValueError(f"{name} must be a square matrix of numbers, got {name}={A!r}") from None
        raw = _real(name, raw, "matrix")
        try:  # strings, booleans and None refused: numpy would read "2" as 2.0 and True as 1.0
            A = number_array(name, A if isinstance(A, (list, tuple)) else raw)  # (a list: its booleans too)
        except ValueError:
            raise ValueError(f"{name} must be a square matrix of numbers, got {name}={shown(A)}") from None
    shape = A.shape
    if len(shape) != 2 or shape[0] != shape[1] or shape[0] < 1:
        raise ValueError(f"{name} must be a square matrix, got {name} of shape {shape}")
    if n is not None and shape[0] != n:
        raise ValueError(f"{name} must be {n} x {n} like M, got {name} of shape {shape}")
    data = A.data if sparse else A
    if not np.all(np.isfinite(data)):
        raise ValueError(f"{name} must be finite, got {name} with a non-finite entry")
    big = float(np.max(np.abs(data))) if data.size else 0.0
    asym = abs(A - A.T)
    asym = float(asym.max()) if sparse else float(np.max(asym))
    if asym > SYMMETRY_RTOL * big:
        raise ValueError(f"{name} must be symmetric, got {name} with max|{name} - {name}^T| = {asym:.3g} "
                         f"(max|{name}| = {big:.3g})")
    return A.astype(float) if sparse else A


def negative_eigenvalue(A: Any) -> tuple[float, float] | None:
    """``(smallest eigenvalue, largest in magnitude)`` of a symmetric or Hermitian ``A`` where it has a negative
    eigenvalue, below ``-NEGATIVE_EIGENVALUE_RTOL`` times the largest in magnitude (above it, the rounding of a
    zero: a free-free structure's rigid-body modes, an undamped DOF), else None.  Cholesky first: a positive
    definite matrix, the common case, needs no eigenvalues."""
    dense = np.asarray(A.toarray() if hasattr(A, "toarray") else A)
    dense = dense if np.iscomplexobj(dense) else dense.astype(float)  # (a disk's nodal matrices are complex)
    try:
        np.linalg.cholesky(dense)
        return None
    except np.linalg.LinAlgError:
        pass
    lam = np.linalg.eigvalsh(dense)
    scale = float(np.max(np.abs(lam))) if lam.size else 0.0
    return (float(lam[0]), scale) if lam.size and lam[0] < -NEGATIVE_EIGENVALUE_RTOL * scale else None


def _semidefinite(name: str, A: Any, what: str) -> None:
    """Refuse a symmetric ``A`` (one of C, K) that is not positive semi-definite (:func:`negative_eigenvalue`): a
    ValueError naming ``name`` and its smallest eigenvalue."""
    found = negative_eigenvalue(A)
    if found is not None:
        raise ValueError(f"{name} must be positive semi-definite ({what}), got {name} with a negative eigenvalue "
                         f"(smallest {found[0]:.6g}, largest in magnitude {found[1]:.6g})")


class Structure:
    """A linear structure ``M x'' + C x' + K x = force cos(omega t)`` with n DOFs.

    Parameters
    ----------
    M, C, K : array_like or scipy.sparse matrix
        Mass (kg), damping (N s/m) and stiffness (N/m) matrices, n x n, finite and symmetric;
        M positive definite, C and K positive semi-definite (no negative damping or stiffness; a
        zero eigenvalue within ``NEGATIVE_EIGENVALUE_RTOL`` of the largest, e.g. a free-free K, is taken).
    force : array_like
        Amplitudes (N) of the harmonic excitation ``force * cos(omega t)``, length n.  A complex
        entry ``f_i = |f_i| exp(i psi_i)`` is an amplitude with a phase: the force on DOF i is
        ``Re(f_i exp(i omega t)) = |f_i| cos(omega t + psi_i)`` (the library's complex convention,
        ``hbm.balance.layout``); a force whose imaginary parts are all zero is stored real.

    Raises
    ------
    ValueError
        Naming the matrix or vector and what is wrong with it.

    Notes
    -----
    Attributes ``M, C, K`` (as given, sparse converted to CSR), ``force`` and ``n``.

    Examples
    --------
    >>> import numpy as np
    >>> s = Structure(np.eye(2), 0.01 * np.eye(2), [[2.0, -1.0], [-1.0, 1.0]], force=[0.0, 1.0])
    >>> s.n, np.round(s.natural_frequencies(), 4).tolist()
    (2, [0.618, 1.618])
    """

    #: Harmonics of a solve that names none: None takes the accuracy preset's (``hbm.balance.presets``);
    #: a blade's structure says 1 (:meth:`hbm.Blade.as_structure`).
    default_harmonics: int | None = None
    #: ``phi = 2 pi EO / N`` of one sector of a cyclic structure (:class:`hbm.CyclicStructure`): harmonic h
    #: of the next sector is this one's times ``exp(-i h phi)``.  None: the structure is the whole model.
    sector_angle: float | None = None

    def harmonic_matrices(self, h: int) -> tuple[Any, Any, Any]:
        """``(M_h, C_h, K_h)``: the matrices of the balance at harmonic ``h``, whose dynamic stiffness is
        ``Z_h = K_h - (h omega)^2 M_h + i h omega C_h``; a structure's own M, C, K at every h (a cyclic
        sector's depend on h: :meth:`hbm.CyclicStructure.harmonic_matrices`)."""
        return self.M, self.C, self.K

    def __init__(self, M: ArrayLike, C: ArrayLike, K: ArrayLike, *, force: ArrayLike) -> None:
        self.M = _check_matrix("M", M, None)
        n = self.M.shape[0]
        self.C = _check_matrix("C", C, n)
        self.K = _check_matrix("K", K, n)
        try:
            np.linalg.cholesky(_dense(self.M))
        except np.linalg.LinAlgError:
            raise ValueError("M must be positive definite, got M with a non-positive eigenvalue "
                             f"(smallest {float(np.linalg.eigvalsh(_dense(self.M))[0]):.3g})") from None
        _semidefinite("C", self.C, "no negative damping")
        _semidefinite("K", self.K, "no negative stiffness: the structure would be statically unstable")
        try:
            f = np.asarray(force)
        except (TypeError, ValueError):
            raise ValueError(f"force must be a vector of {n} numbers, got force={shown(force)}") from None
        if np.iscomplexobj(f) and not np.any(np.imag(f)):
            f = f.real  # a complex force with every phase 0 is the real force, bit for bit
        try:  # as the matrices: no strings, booleans or None read as numbers
            f = (np.asarray(f, dtype=complex) if np.iscomplexobj(f)
                 else number_array("force", force if isinstance(force, (list, tuple)) else f))  # (a list: its booleans)
        except (TypeError, ValueError):
            raise ValueError(f"force must be a vector of {n} numbers, got force={shown(force)}") from None
        if f.ndim > 1 or (f.ndim == 0 and n != 1):  # a column or a table is not flattened (its layout is unknown)
            raise ValueError(f"force must be a one-dimensional vector of {n} number{'s' if n != 1 else ''}"
                             f"{' (or one number)' if n == 1 else ''}, got force of shape {f.shape}: "
                             f"force={shown(force)}")
        f = f.ravel()
        if f.size != n:
            raise ValueError(f"force must have length n = {n}, got force of length {f.size}")
        if not np.all(np.isfinite(f)):
            raise ValueError(f"force must be finite, got force={f!r}")
        self.force = f
        self.n = n

    def __repr__(self) -> str:
        return f"Structure(n={self.n}, forced DOFs {np.flatnonzero(self.force).tolist()})"

    # ------------------------------------------------------------ construction helpers
    @classmethod
    def with_rayleigh(cls, M: ArrayLike, K: ArrayLike, *, alpha: float, beta: float, force: ArrayLike) -> Structure:
        """Structure with Rayleigh damping ``C = alpha M + beta K`` (alpha in 1/s, beta in s).

        Examples
        --------
        >>> s = Structure.with_rayleigh([[1.0]], [[4.0]], alpha=0.1, beta=0.01, force=[1.0])
        >>> float(s.C[0, 0])
        0.14
        """
        a = nonnegative("alpha", alpha)
        b = nonnegative("beta", beta)
        M = _check_matrix("M", M, None)
        K = _check_matrix("K", K, M.shape[0])
        return cls(M, a * M + b * K, K, force=force)

    @classmethod
    def with_modal_damping(cls, M: ArrayLike, K: ArrayLike, *, ratios: float | Sequence[float],
                           force: ArrayLike) -> Structure:
        """Structure with modal damping ``C = M Phi diag(2 zeta_j omega_j) Phi^T M``.

        ``Phi`` are the mass-normalised modes of (K, M), ``omega_j`` their natural frequencies;
        ``ratios`` is one damping ratio for every mode or one per mode (n values, >= 0).  K must be positive
        semi-definite (a growing mode has no damping ratio: ValueError); rigid-body modes get no damping.

        Examples
        --------
        >>> s = Structure.with_modal_damping([[1.0]], [[4.0]], ratios=0.05, force=[1.0])
        >>> float(s.C[0, 0])  # 2 zeta omega m
        0.2
        """
        from scipy.linalg import eigh  # lazily: import hbm stays light

        M = _check_matrix("M", M, None)
        K = _check_matrix("K", K, M.shape[0])
        Md, Kd = _dense(M), _dense(K)
        n = Md.shape[0]
        bad = ValueError(f"ratios must be one number >= 0 or {n} of them, got ratios={ratios!r}")
        try:  # numbers only: numpy's "could not convert string to float" names no parameter
            z = number_array("ratios", ratios)
        except ValueError:
            raise bad from None
        z = np.broadcast_to(z, (n,)) if z.ndim == 0 else z
        if z.shape != (n,) or not np.all(np.isfinite(z)) or np.any(z < 0.0):
            raise bad
        try:
            lam, Phi = eigh(Kd, Md)
        except np.linalg.LinAlgError:
            raise ValueError("M must be positive definite, got M for which (K, M) has no eigen-decomposition") from None
        if lam[0] < -NEGATIVE_EIGENVALUE_RTOL * float(np.max(np.abs(lam))):  # eigh sorts ascending
            raise ValueError(f"K must be positive semi-definite for modal damping: (K, M) has omega^2 = {lam[0]:.6g}")
        w = np.sqrt(np.clip(lam, 0.0, None))
        MPhi = Md @ Phi
        return cls(M, (MPhi * (2.0 * z * w)) @ MPhi.T, K, force=force)

    @classmethod
    def from_files(cls, mass: str | Path, stiffness: str | Path, *, force: ArrayLike,
                   damping: str | Path | None = None, rayleigh: tuple[float, float] | None = None,
                   modal_damping: float | Sequence[float] | None = None) -> Structure:
        """Structure from matrix files: ``.mtx`` (Matrix Market, ``scipy.io.mmread``), ``.npz``
        (``scipy.sparse.save_npz`` or ``numpy.savez``; ``"file.npz:key"`` picks an array) or
        ``.npy``.  Damping: a ``damping`` file, ``rayleigh=(alpha, beta)`` or ``modal_damping``
        (ratios), exactly one.
        """
        _one_damping(damping, rayleigh, modal_damping)
        return cls.from_matrices(load_matrix(mass, name="mass"), load_matrix(stiffness, name="stiffness"), force=force,
                                 damping=None if damping is None else load_matrix(damping, name="damping"),
                                 rayleigh=rayleigh, modal_damping=modal_damping)

    @classmethod
    def from_matrices(cls, M: Any, K: Any, *, force: ArrayLike, damping: Any = None,
                      rayleigh: tuple[float, float] | None = None,
                      modal_damping: float | Sequence[float] | None = None) -> Structure:
        """Structure from M and K with a damping matrix ``damping``, ``rayleigh=(alpha, beta)`` or
        ``modal_damping`` (ratios), exactly one: what :meth:`from_files` builds once it has read
        the files.

        Examples
        --------
        >>> s = Structure.from_matrices([[1.0]], [[4.0]], force=[1.0], rayleigh=(0.1, 0.01))
        >>> float(s.C[0, 0])
        0.14
        """
        _one_damping(damping, rayleigh, modal_damping)
        if damping is not None:
            return cls(M, damping, K, force=force)
        if rayleigh is not None:
            try:
                alpha, beta = rayleigh
            except (TypeError, ValueError):
                raise ValueError(f"rayleigh must be a pair (alpha, beta), got rayleigh={rayleigh!r}") from None
            return cls.with_rayleigh(M, K, alpha=alpha, beta=beta, force=force)
        return cls.with_modal_damping(M, K, ratios=modal_damping, force=force)

    # ------------------------------------------------------------ properties
    def natural_frequencies(self) -> NDArray[np.float64]:
        """Undamped natural frequencies (rad/s) of (K, M), ascending (dense eigensolver).

        A rigid-body mode (K singular, eigenvalue zero within rounding, ``NEGATIVE_EIGENVALUE_RTOL``
        times the largest) has frequency 0.

        Raises
        ------
        ValueError
            When K has a negative eigenvalue (``K x = lambda M x`` with lambda < 0): the structure
            is statically unstable and that mode has no real natural frequency, so none is
            returned for it rather than a 0 that would look like a rigid-body mode.

        Examples
        --------
        >>> import numpy as np
        >>> Structure(np.eye(2), 0.0 * np.eye(2), [[1.0, -1.0], [-1.0, 1.0]], force=[1.0, 0.0]).natural_frequencies()
        array([0.        , 1.41421356])
        >>> try:
        ...     Structure(np.eye(1), np.zeros((1, 1)), [[-3.2]], force=[1.0])  # refused when built
        ... except ValueError as exc:
        ...     print(exc)
        K must be positive semi-definite (no negative stiffness: the structure would be statically unstable), got K with a negative eigenvalue (smallest -3.2, largest in magnitude 3.2)
        """
        from scipy.linalg import eigh  # lazily: import hbm stays light

        lam = eigh(_dense(self.K), _dense(self.M), eigvals_only=True)
        scale = float(np.max(np.abs(lam))) if lam.size else 0.0
        if lam.size and lam[0] < -NEGATIVE_EIGENVALUE_RTOL * scale:
            raise ValueError(f"K has a negative eigenvalue {float(lam[0]):.3g} (K x = lambda M x): the structure is "
                             "unstable; natural_frequencies needs K positive semi-definite")
        return np.sqrt(np.clip(lam, 0.0, None))

    def reduce(self, keep: Sequence[int], *, modes: int) -> ReducedStructure:
        """Craig-Bampton reduction to the DOFs ``keep`` plus ``modes`` fixed-interface modes.

        The reduced DOFs are ``keep`` (in that order, as physical DOFs: reduced DOF ``i`` is
        ``keep[i]``) followed by the modal coordinates.  ``x = T q`` with
        ``T = [[I, 0], [-K_ii^-1 K_ib, Phi_i]]`` (rows reordered to the original DOFs); the
        reduced matrices are ``T^T M T``, ``T^T C T``, ``T^T K T``, the force ``T^T f``.
        Exact statically at every kept DOF (module docstring says why this method).

        Examples
        --------
        >>> import numpy as np
        >>> n = 6
        >>> K = 2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
        >>> f = np.zeros(n); f[-1] = 1.0
        >>> r = Structure(np.eye(n), 0.01 * np.eye(n), K, force=f).reduce([0, n - 1], modes=4)
        >>> r.n, np.allclose(np.linalg.solve(r.K, r.force)[:2], np.linalg.solve(K, f)[[0, n - 1]])
        (6, True)
        """
        from scipy.linalg import eigh  # lazily: import hbm stays light

        if isinstance(keep, (str, bytes)) or not hasattr(keep, "__iter__"):
            raise ValueError(f"keep must be a sequence of DOF indices, got keep={keep!r}")
        keep = [self._dof("keep", d) for d in keep]
        if len(set(keep)) != len(keep) or not keep:
            raise ValueError(f"keep must be distinct DOFs, at least one, got keep={keep!r}")
        inner = np.setdiff1d(np.arange(self.n), keep)
        modes = count("modes", modes, 0)
        if modes > inner.size:
            raise ValueError(f"modes must be <= {inner.size} (the DOFs not kept), got modes={modes!r}")
        M, C, K = _dense(self.M), _dense(self.C), _dense(self.K)
        b = np.asarray(keep)
        Kii = K[np.ix_(inner, inner)]
        psi = -np.linalg.solve(Kii, K[np.ix_(inner, b)]) if inner.size else np.zeros((0, b.size))
        T = np.zeros((self.n, b.size + modes))
        T[b, np.arange(b.size)] = 1.0
        T[np.ix_(inner, np.arange(b.size))] = psi
        if modes:
            lam, Phi = eigh(Kii, M[np.ix_(inner, inner)], subset_by_index=(0, modes - 1))
            T[np.ix_(inner, b.size + np.arange(modes))] = Phi
        sym = lambda A: 0.5 * (A + A.T)  # noqa: E731 - remove rounding asymmetry of T^T A T
        return ReducedStructure(sym(T.T @ M @ T), sym(T.T @ C @ T), sym(T.T @ K @ T), force=T.T @ self.force,
                                T=T, kept=tuple(keep), full=self)

    def _dof(self, name: str, d: Any) -> int:
        if isinstance(d, bool) or not isinstance(d, (int, np.integer)) or not 0 <= int(d) < self.n:
            raise ValueError(f"{name} must be a DOF index in 0..{self.n - 1}, got {name}={d!r}")
        return int(d)

    @property
    def physical_dofs(self) -> int:
        """How many DOFs, from 0, are physical displacements (where a contact or a response may be): all
        of them; a reduced structure's kept DOFs only (:class:`ReducedStructure`)."""
        return self.n

    def response_dof(self, response_dof: Any = None, force: Any = None) -> int:
        """``response_dof`` checked as a physical DOF (:attr:`physical_dofs`), or by default the physical DOF
        of the largest ``|force|`` (the structure's own force if None)."""
        p = self.physical_dofs
        if response_dof is None:
            f = self.force if force is None else np.asarray(force)
            return int(np.argmax(np.abs(f[:p])))
        d = self._dof("response_dof", response_dof)
        if d >= p:
            raise ValueError(_modal_coordinate("response_dof", d, p))
        return d


def _one_damping(damping: Any, rayleigh: Any, modal_damping: Any) -> None:
    if sum(v is not None for v in (damping, rayleigh, modal_damping)) != 1:
        given = "a matrix" if damping is not None and not isinstance(damping, (str, Path)) else repr(damping)
        raise ValueError(f"give exactly one of damping, rayleigh and modal_damping, got damping={given}, "
                         f"rayleigh={rayleigh!r}, modal_damping={modal_damping!r}")


class ReducedStructure(Structure):
    """A :class:`Structure` from :meth:`Structure.reduce`: reduced DOF ``i < len(kept)`` is the
    original DOF ``kept[i]``; ``T`` maps reduced to original DOFs (``x = T q``); ``full`` is
    the structure it came from.

    Parameters
    ----------
    M, C, K : array_like
        The reduced mass (kg), damping (N s/m) and stiffness (N/m) matrices, r x r.
    force : array_like
        The reduced force amplitudes ``T^T f`` (N), length r.
    T : ndarray
        The transformation, n x r (n the original DOFs): ``x = T q``.
    kept : tuple of int
        The original DOFs kept as physical DOFs, in the order of the reduced DOFs.
    full : Structure
        The structure reduced.

    Attributes
    ----------
    T, kept, full
        As given.

    Raises
    ------
    ValueError
        As ``Structure`` for invalid matrices or force.

    Examples
    --------
    >>> import numpy as np
    >>> s = Structure(np.eye(3), 0.01 * np.eye(3), 2 * np.eye(3) - np.eye(3, k=1) - np.eye(3, k=-1),
    ...               force=[0.0, 0.0, 1.0])
    >>> r = s.reduce([2], modes=1)
    >>> r.n, r.kept, r.T.shape, r.dof(2)
    (2, (2,), (3, 2), 0)
    """

    def __init__(self, M: ArrayLike, C: ArrayLike, K: ArrayLike, *, force: ArrayLike, T: NDArray[np.float64],
                 kept: tuple[int, ...], full: Structure) -> None:
        super().__init__(M, C, K, force=force)
        if not isinstance(full, Structure):
            raise ValueError(f"full must be the hbm.Structure reduced, got full={full!r}")
        try:  # numbers only (a boolean matrix was taken as ones and zeros)
            T = number_array("T", T)
        except ValueError:
            raise ValueError(f"T must be a {full.n} x {self.n} matrix of numbers, got T={shown(T)}") from None
        if T.shape != (full.n, self.n) or not np.all(np.isfinite(T)):
            raise ValueError(f"T must be a finite {full.n} x {self.n} matrix (original x reduced DOFs), "
                             f"got T of shape {T.shape}")
        if isinstance(kept, (str, bytes)) or not hasattr(kept, "__iter__"):  # (a number was "not iterable")
            raise ValueError(f"kept must be a sequence of DOF indices of full, got kept={kept!r}")
        kept = tuple(full._dof("kept", d) for d in kept)
        if len(set(kept)) != len(kept) or len(kept) > self.n:
            raise ValueError(f"kept must be distinct DOFs of full, at most {self.n}, got kept={kept!r}")
        self.T = T
        self.kept = kept
        self.full = full

    @property
    def physical_dofs(self) -> int:
        """The kept DOFs: the reduced DOFs from ``len(kept)`` on are modal coordinates."""
        return len(self.kept)

    def dof(self, original: int) -> int:
        """The reduced DOF of the kept original DOF ``original``."""
        if isinstance(original, bool) or not isinstance(original, (int, np.integer)) or original not in self.kept:
            raise ValueError(f"original must be one of the kept DOFs {self.kept}, got original={original!r}")
        return self.kept.index(original)


class Contact:
    """A contact element attached at one DOF (to ground) or between two DOFs.

    Parameters
    ----------
    element : contact_models.ContactElement
        The element; its force depends on ``x_dof`` or on ``x_i - x_j``.
    dof : int, optional
        The DOF of a contact to ground.
    dofs : tuple of two ints, optional
        ``(i, j)`` for a contact between DOFs: force +f on i, -f on j. Exactly one of dof, dofs.
    second_dof : int, optional
        For a three-component element (``element.components == 3``, ``contact_models.Contact3D``):
        the DOF of the second tangential displacement to ground; ``dof``/``dofs`` then give the first.
    second_dofs : tuple of two ints, optional
        ``(k, l)``: the second tangential displacement ``x_k - x_l`` (force +T2 on k, -T2 on l).
        A three-component element needs exactly one of second_dof, second_dofs; any other element none.
    normal_dof : int, optional
        For a two- or three-component element (``contact_models.Contact2D``, ``Contact3D``): the DOF
        of the normal displacement to ground.
    normal_dofs : tuple of two ints, optional
        ``(k, l)``: the normal displacement ``x_k - x_l`` (normal force +N on k, -N on l).
        A two- or three-component element needs exactly one of normal_dof, normal_dofs; a
        one-component element none.
    next_sector : bool, default False
        For one sector of a cyclic structure (:class:`hbm.CyclicStructure`): the pair ``(p, q)``
        joins DOF p of the *next* sector to DOF q of this one (the relative displacement is
        ``x_p`` of the next sector minus ``x_q`` of this sector; force +f on the next sector's p,
        -f on this q), and so do ``second_dofs`` and ``normal_dofs``; p may equal q (the same DOF
        of two neighbours).  It needs ``dofs`` (and ``second_dofs``, ``normal_dofs`` for the other
        components); the balance of a structure that is not a sector refuses it
        (``docs/bladed_disks.md``).

    Attributes
    ----------
    element, dofs
        As given (``dofs`` a tuple of one or two DOFs: the (first) tangential attachment).
    second_dofs : tuple of int
        The second tangential attachment (one or two DOFs), empty unless the element has three components.
    normal_dofs : tuple of int
        The normal attachment (one or two DOFs), empty for a one-component element.
    components : tuple of tuple of int
        ``(dofs,)``, ``(dofs, normal_dofs)`` or ``(dofs, second_dofs, normal_dofs)``: the attachment
        of each component, in the element's order.
    next_sector : bool
        As given.

    Raises
    ------
    ValueError
        For an attachment the element's number of components does not take (or lacks), or DOFs
        shared between the attachments, naming the keywords and their values.

    Examples
    --------
    >>> from contact_models import Contact2D, Contact3D, Macroslip
    >>> Contact(Macroslip(stiffness=1.0, slip_force=0.05), dofs=(0, 1)).dofs
    (0, 1)
    >>> Contact(Contact2D(kt=1.0, kn=1.0, mu=0.5, n0=1.0), dof=0, normal_dof=1).components
    ((0,), (1,))
    >>> Contact(Contact3D(kt=1.0, kn=1.0, mu=0.5, n0=1.0), dof=0, second_dof=1, normal_dof=2).components
    ((0,), (1,), (2,))
    """

    def __init__(self, element: Any, *, dof: int | None = None, dofs: tuple[int, int] | None = None,
                 second_dof: int | None = None, second_dofs: tuple[int, int] | None = None,
                 normal_dof: int | None = None, normal_dofs: tuple[int, int] | None = None,
                 next_sector: bool = False) -> None:
        if not isinstance(element, ContactElement):
            raise ValueError(f"element must be a contact_models.ContactElement, got element={element!r}")
        if not isinstance(next_sector, (bool, np.bool_)):
            raise ValueError(f"next_sector must be True or False, got next_sector={next_sector!r}")
        self.next_sector = bool(next_sector)
        if self.next_sector and (dofs is None or normal_dof is not None or second_dof is not None):
            raise ValueError(f"next_sector=True joins a DOF of the next sector to one of this sector: it needs "
                             f"dofs=(p, q) (and second_dofs, normal_dofs for the other components), got dof={dof!r}, "
                             f"dofs={dofs!r}, second_dof={second_dof!r}, normal_dof={normal_dof!r}")
        self.element = element
        nxt = self.next_sector
        self.dofs = _attachment("dof", dof, "dofs", dofs, nxt)
        c = getattr(element, "components", 1)
        if c != 3 and (second_dof is not None or second_dofs is not None):
            raise ValueError(f"second_dof and second_dofs attach the second tangential direction of a three-component "
                             f"element (Contact3D); {type(element).__name__} has {c} component(s), got "
                             f"second_dof={second_dof!r}, second_dofs={second_dofs!r}")
        if c < 2 and (normal_dof is not None or normal_dofs is not None):
            raise ValueError(f"normal_dof and normal_dofs attach the normal of a two- or three-component element "
                             f"(Contact2D, Contact3D); {type(element).__name__} has one component, got "
                             f"normal_dof={normal_dof!r}, normal_dofs={normal_dofs!r}")
        self.second_dofs = _attachment("second_dof", second_dof, "second_dofs", second_dofs, nxt) if c == 3 else ()
        self.normal_dofs = _attachment("normal_dof", normal_dof, "normal_dofs", normal_dofs, nxt) if c >= 2 else ()
        # across sectors a pair's first DOF is the next sector's, its second this one's: they clash side by side
        shared = (lambda a, b: any(x == y for x, y in zip(a, b))) if nxt else (lambda a, b: bool(set(a) & set(b)))
        if shared(self.dofs, self.normal_dofs) or shared(self.second_dofs, self.normal_dofs):
            raise ValueError(f"normal_dof(s) must differ from the tangential dof(s), got dofs={self.dofs}, "
                             + (f"second_dofs={self.second_dofs}, " if self.second_dofs else "")
                             + f"normal_dofs={self.normal_dofs}")
        if shared(self.dofs, self.second_dofs):
            raise ValueError(f"second_dof(s) must differ from the first tangential dof(s), got dofs={self.dofs}, "
                             f"second_dofs={self.second_dofs}")
        self.components = tuple(d for d in (self.dofs, self.second_dofs, self.normal_dofs) if d)

    @property
    def all_dofs(self) -> tuple[int, ...]:
        """Every DOF the contact touches: the tangential ones (first, second), then the normal ones."""
        return self.dofs + self.second_dofs + self.normal_dofs

    def with_element(self, element: Any) -> "Contact":
        """The same attachment with another element (one with the same number of components)."""
        where = {}
        for one, two, d in (("dof", "dofs", self.dofs), ("second_dof", "second_dofs", self.second_dofs),
                            ("normal_dof", "normal_dofs", self.normal_dofs)):
            if d:
                where.update({one: d[0]} if len(d) == 1 else {two: d})
        return Contact(element, **where, next_sector=self.next_sector)

    def __repr__(self) -> str:
        where = f"dof={self.dofs[0]}" if len(self.dofs) == 1 else f"dofs={self.dofs}"
        for one, d in (("second_dof", self.second_dofs), ("normal_dof", self.normal_dofs)):
            if d:
                where += f", {one}={d[0]}" if len(d) == 1 else f", {one}s={d}"
        if self.next_sector:
            where += ", next_sector=True"
        return f"Contact({self.element!r}, {where})"


def contact_within(c: Contact, n: int, physical: int | None = None) -> Contact:
    """``c`` if every DOF it touches is one of a structure of ``n`` DOFs, else a ValueError naming the
    DOF and the contact (a DOF past n would index another sector's, or no, DOF); with ``physical``, one
    of the first ``physical`` (a reduced structure's kept DOFs, not its modal coordinates)."""
    for d in c.all_dofs:
        if d >= n:
            raise ValueError(f"dof must be a DOF index in 0..{n - 1}, got dof={d!r} in {c!r}")
        if physical is not None and d >= physical:
            raise ValueError(f"{_modal_coordinate('dof', d, physical)} in {c!r}")
    return c


def _modal_coordinate(name: str, d: int, physical: int) -> str:
    """The refusal of DOF ``d`` of a reduced structure whose first ``physical`` DOFs are its kept ones."""
    return (f"{name} must be a kept DOF of the reduced structure, in 0..{physical - 1} (its DOFs from {physical} on "
            f"are modal coordinates; reduced.dof(i) is original DOF i's), got {name}={d!r}")


def _attachment(one: str, d: Any, two: str, pair: Any, same: bool = False) -> tuple[int, ...]:
    """``(d,)`` or the pair ``(i, j)`` of DOF indices >= 0, distinct unless ``same`` (a pair across
    two sectors may name one DOF of each); exactly one of them given."""
    if (d is None) == (pair is None):
        raise ValueError(f"give exactly one of {one} and {two}, got {one}={d!r}, {two}={pair!r}")
    if d is not None:
        dd: tuple = (d,)
        name = one
    else:
        try:
            dd = tuple(pair)
        except TypeError:
            raise ValueError(f"{two} must be a pair (i, j), got {two}={pair!r}") from None
        name = two
        if len(dd) != 2:
            raise ValueError(f"{two} must be a pair (i, j), got {two}={pair!r}")
    for v in dd:
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 0:
            raise ValueError(f"{name} must hold DOF indices >= 0, got {name}={d if pair is None else pair!r}")
    if len(dd) == 2 and dd[0] == dd[1] and not same:
        raise ValueError(f"{two} must be two different DOFs, got {two}={pair!r}")
    return tuple(int(v) for v in dd)


def load_matrix(path: str | Path, *, name: str = "path") -> Any:
    """A matrix from ``.mtx`` (Matrix Market), ``.npz`` (``scipy.sparse.save_npz``, or
    ``numpy.savez`` with one array or ``"file.npz:key"``) or ``.npy``.

    ``name`` is the parameter (or scene key) that gave ``path``: every ValueError names it and the
    file, including a file the reader cannot parse (a corrupt file, pickled objects, which are never
    loaded).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> bad = pathlib.Path(tempfile.mkdtemp()) / "K.npy"
    >>> _ = bad.write_bytes(b"not a matrix")
    >>> try:
    ...     load_matrix(bad, name="stiffness")
    ... except ValueError as exc:
    ...     print(str(exc).split(" (")[0].replace(str(bad), "K.npy"))
    stiffness must name a matrix file that numpy can read, got stiffness='K.npy'
    """
    text = str(path)
    key = None
    if ".npz:" in text:
        text, key = text.split(".npz:", 1)
        text += ".npz"
    p = Path(text)
    if not p.is_file():
        raise ValueError(f"{name} must name an existing matrix file, got {name}={str(path)!r}")
    suffix = p.suffix.lower()
    if suffix not in (".mtx", ".npy", ".npz"):
        raise ValueError(f"{name} must end in .mtx, .npz or .npy, got {name}={str(path)!r}")
    try:
        return _read_matrix(p, suffix, key, name, path)
    except ValueError as exc:
        if str(exc).startswith(f"{name} "):
            raise
        reader = "scipy.io.mmread" if suffix == ".mtx" else "numpy"
        raise ValueError(f"{name} must name a matrix file that {reader} can read, got {name}={str(path)!r} "
                         f"({_reason(exc)})") from None
    except (OSError, EOFError, UnicodeError, TypeError, IndexError, KeyError) as exc:
        raise ValueError(f"{name} must name a matrix file that can be read, got {name}={str(path)!r} "
                         f"({type(exc).__name__}: {exc})") from None


def _reason(exc: Exception) -> str:
    text = str(exc)
    if "pickled" in text or "allow_pickle" in text:
        return "the file holds pickled Python objects, which are not loaded: not a numeric array"
    return text or type(exc).__name__


def _read_matrix(p: Path, suffix: str, key: str | None, name: str, path: Any) -> Any:
    if suffix == ".mtx":
        from scipy.io import mmread  # lazily: only for Matrix Market files

        return mmread(str(p))
    if suffix == ".npy":
        return np.load(p, allow_pickle=False)
    with np.load(p, allow_pickle=False) as z:
        names = list(z.keys())
        if key is None and {"format", "shape", "data"} <= set(names):
            from scipy.sparse import load_npz  # lazily: only for sparse .npz files

            return load_npz(p)
        if key is None:
            if len(names) != 1:
                raise ValueError(f"{name} must name one array as 'file.npz:key' (keys {names}), "
                                 f"got {name}={str(path)!r}")
            key = names[0]
        if key not in names:
            raise ValueError(f"{name} names key {key!r} not in {names}, got {name}={str(path)!r}")
        return z[key]


def modal_compliance(M: Any, C: Any, K: Any) -> tuple[NDArray[np.complex128], NDArray[np.complex128],
                                                       NDArray[np.complex128]]:
    """``(lam, V, B)``: the state-space modes of ``M x'' + C x' + K x``, so that for any s
    ``(K + s C + s^2 M)^-1 = V diag(1/(s - lam)) B`` (V: n x 2n, B: 2n x n).

    From the first-order form ``z' = A z``, ``A = [[0, I], [-M^-1 K, -M^-1 C]]``,
    ``A = W diag(lam) W^-1``: ``(s I - A)^-1 = W diag(1/(s - lam)) W^-1`` and
    ``Z(s)^-1 = [I 0] (s I - A)^-1 [0; M^-1]``.  Exact for any (non-defective) damping.
    Classical damping (``Phi^H C Phi`` diagonal for the mass-normalised undamped modes ``Phi``,
    Rayleigh and modal damping) takes the symmetric eigensolver instead: two poles per mode.
    Complex Hermitian M, C, K (a cyclic sector's nodal-diameter matrices,
    :meth:`hbm.CyclicStructure.harmonic_matrices`) take the same steps with ``Phi^H`` for ``Phi^T``.
    """
    Md, Cd, Kd = (_dense_complex(A) if _is_complex(A) else _dense(A) for A in (M, C, K))
    n = Md.shape[0]
    if n == 1:  # one DOF (a blade): its mode without scipy's eigensolvers
        w2, Phi = Kd[0] / Md[0, 0], np.array([[1.0 / math.sqrt(Md[0, 0])]])
    else:
        from scipy.linalg import eigh  # lazily: import hbm stays light

        w2, Phi = eigh(Kd, Md)
    # classical damping (C diagonal in the undamped modes): two poles per mode from eigh, with
    # 1/(s^2 + c s + w^2) = (1/(s - l+) - 1/(s - l-)) / (l+ - l-)
    PhiH = Phi.conj().T  # Phi^T of a real Phi, value for value
    c = PhiH @ Cd @ Phi
    cd = np.diag(c).real.copy()
    off = np.max(np.abs(c - np.diag(cd))) if n > 1 else 0.0
    disc = cd * cd - 4.0 * w2.astype(complex)
    if off <= 1e-12 * max(float(np.max(np.abs(cd))), 1e-300) and np.all(np.abs(disc) > 1e-12 * np.abs(w2) + 1e-300):
        root = np.sqrt(disc)
        lp, lm = 0.5 * (-cd + root), 0.5 * (-cd - root)
        inv = 1.0 / (lp - lm)
        V = np.hstack([Phi, Phi]).astype(complex)
        B = np.vstack([inv[:, None] * PhiH, -inv[:, None] * PhiH])
        return np.concatenate([lp, lm]), V, B
    from scipy.linalg import eig, lu_factor, lu_solve  # lazily: import hbm stays light

    MinvK = np.linalg.solve(Md, Kd)
    MinvC = np.linalg.solve(Md, Cd)
    A = np.zeros((2 * n, 2 * n), dtype=np.result_type(MinvK, MinvC))
    A[:n, n:] = np.eye(n)
    A[n:, :n] = -MinvK
    A[n:, n:] = -MinvC
    lam, W = eig(A)
    lu = lu_factor(W)
    rhs = np.zeros((2 * n, n), dtype=complex)
    rhs[n:] = np.linalg.inv(Md)
    B = lu_solve(lu, rhs)
    return lam, W[:n], B


__all__ = ["Structure", "ReducedStructure", "Contact", "load_matrix", "modal_compliance"]
