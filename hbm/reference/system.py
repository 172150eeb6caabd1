"""The input of the periodic reference: a structure and its contacts as the integrators' ``Model``.

``build_model(system, contacts)`` reads M, C, K and the force of a ``Structure``-like object (or
a ``Blade``-like one, or a tuple), each contact's DOFs and its element (a Jenkins element:
``stiffness`` and ``slip_force``; a cubic spring: ``k3``), checks them (``ValueError`` naming the
parameter and its value) and returns the ``Model`` of ``hbm.reference.piecewise`` that both
integrators of ``hbm.reference.shooting`` take.
"""

from __future__ import annotations

import math
from types import SimpleNamespace
from typing import Any, Iterable

import numpy as np
from numpy.typing import NDArray

from .piecewise import Model

__all__ = ["build_model"]


def _matrix(name: str, A: Any, n: int | None) -> NDArray[np.float64]:
    if hasattr(A, "toarray"):
        A = A.toarray()
    A = np.atleast_2d(np.asarray(A, dtype=float))
    if A.ndim != 2 or A.shape[0] != A.shape[1] or (n is not None and A.shape[0] != n):
        raise ValueError(f"{name} must be a square matrix of size {n or 'n'}, got shape {A.shape}")
    if not np.all(np.isfinite(A)):
        raise ValueError(f"{name} must be finite, got {name}={A!r}")
    return A


def _system(system: Any) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """(M, C, K, force) of a Structure-like object (M, C, K, force), a Blade-like one (mass,
    damping, stiffness, force) or a sequence (M, C, K, force)."""
    if getattr(system, "sector_angle", None) is not None:  # hbm.Structure's: None where it is the whole model
        raise ValueError("system must be the whole model: a cyclic structure is one sector of a disk, whose couplings "
                         "to its neighbours the time integration would leave out; give the whole disk, "
                         f"disk.full(contacts), got system={system!r}")
    if all(hasattr(system, a) for a in ("M", "C", "K", "force")):
        parts = (system.M, system.C, system.K, system.force)
    elif all(hasattr(system, a) for a in ("mass", "damping", "stiffness", "force")):
        parts = (system.mass, system.damping, system.stiffness, system.force)
    elif isinstance(system, (tuple, list)) and len(system) == 4:
        parts = tuple(system)
    else:
        raise ValueError("system must have attributes M, C, K, force (or mass, damping, stiffness, "
                         f"force) or be a tuple (M, C, K, force), got system={system!r}")
    M = _matrix("M", parts[0], None)
    n = M.shape[0]
    C, K = _matrix("C", parts[1], n), _matrix("K", parts[2], n)
    if np.iscomplexobj(parts[3]) and np.any(np.imag(parts[3])):
        raise ValueError("force must be real for the time-domain references (a phase per DOF is not integrated), "
                         f"got a complex force={parts[3]!r}")
    f = np.atleast_1d(np.asarray(parts[3], dtype=float)).ravel()
    if f.size != n or not np.all(np.isfinite(f)):
        raise ValueError(f"force must be a finite vector of length {n}, got force={parts[3]!r}")
    try:
        np.linalg.cholesky(0.5 * (M + M.T))
    except np.linalg.LinAlgError:
        raise ValueError(f"M must be positive definite, got M={M!r}") from None
    return M, C, K, f


def _contact_dofs(contact: Any, n: int) -> tuple[int, ...]:
    dofs = getattr(contact, "dofs", None)
    if dofs is None and hasattr(contact, "dof"):
        dofs = (contact.dof,)
    if dofs is None or not hasattr(contact, "element"):
        raise ValueError(f"contacts must hold objects with .element and .dofs (e.g. hbm.Contact), got {contact!r}")
    if getattr(contact, "next_sector", False):  # hbm.Contact's: a DOF of the next sector, which is not modelled
        raise ValueError("next_sector=True joins two sectors of a cyclic structure, which the time integration does "
                         f"not model: give the whole disk, disk.full(contacts), got next_sector=True in {contact!r}")
    dofs = tuple(np.atleast_1d(dofs)) if dofs is not None else ()
    if len(dofs) not in (1, 2) or any(isinstance(d, bool) or not isinstance(d, (int, np.integer))
                                      or not 0 <= d < n for d in dofs) or len(set(dofs)) != len(dofs):
        raise ValueError(f"contact dofs must be 1 or 2 distinct integers in [0, {n}), got dofs={dofs!r}")
    return tuple(int(d) for d in dofs)


def _contact_list(contacts: Any, n: int) -> list:
    """``contacts`` as a list, as ``hbm.frequency_response`` takes them: None, one contact (an object with
    ``.element``), a sequence of them, or a bare element on a one-DOF system; else a ValueError naming it."""
    if contacts is None:
        return []
    if hasattr(contacts, "element"):
        return [contacts]
    if callable(getattr(contacts, "fourier", None)):  # a bare contact element
        if n != 1:
            raise ValueError(f"a bare element attaches only to a one-DOF system; give hbm.Contact(element, dof=...) "
                             f"for a structure of {n} DOFs, got contacts={contacts!r}")
        return [SimpleNamespace(element=contacts, dofs=(0,))]
    if isinstance(contacts, (str, bytes, dict)) or not isinstance(contacts, Iterable):
        raise ValueError(f"contacts must be a sequence of hbm.Contact (or one, or a bare element on a one-DOF "
                         f"system), got contacts={contacts!r}")
    return list(contacts)


def build_model(system: Any, contacts: Iterable[Any]) -> Model:
    """The integrators' ``Model`` of ``system`` (M, C, K, force) with its Jenkins contacts and cubic
    springs; ``ValueError`` naming the offending input otherwise."""
    M, C, K, f = _system(system)
    n = M.shape[0]
    cols: dict[str, list] = {"B": [], "kt": [], "fs": [], "Bq": [], "k3": []}
    for contact in _contact_list(contacts, n):
        el = getattr(contact, "element", None)
        dofs = _contact_dofs(contact, n)
        b = np.zeros(n)
        b[dofs[0]] = 1.0
        if len(dofs) == 2:
            b[dofs[1]] = -1.0
        if el is not None and hasattr(el, "k3"):
            k3 = float(el.k3)
            if not math.isfinite(k3):
                raise ValueError(f"k3 must be finite, got k3={el.k3!r}")
            cols["Bq"].append(b)
            cols["k3"].append(k3)
        elif el is not None and hasattr(el, "stiffness") and hasattr(el, "slip_force"):
            kt, fs = float(el.stiffness), float(el.slip_force)
            if not (0.0 < kt < math.inf):
                raise ValueError(f"stiffness must be positive and finite (a rigid slider has no "
                                 f"unique state), got stiffness={el.stiffness!r}")
            if not (0.0 < fs < math.inf):
                raise ValueError(f"slip_force must be positive and finite, got slip_force={el.slip_force!r}")
            cols["B"].append(b)
            cols["kt"].append(kt)
            cols["fs"].append(fs)
        else:
            raise ValueError("contact element must be a Jenkins element (stiffness, slip_force) or "
                             f"a cubic spring (k3), got element={el!r}")

    def stack(key):
        return np.array(cols[key]).T.reshape(n, -1)
    return Model(M=M, C=C, K=K, force=f, B=stack("B"), kt=np.array(cols["kt"]), fs=np.array(cols["fs"]),
                 Bq=stack("Bq"), k3=np.array(cols["k3"]))
