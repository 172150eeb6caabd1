"""The all-mode bar's Jacobian around a nested Newton step: the block-tridiagonal matrix with the linear part on
its diagonal blocks (``with_diagonal``) factorised with its couplings divided out (``Coupled``), the nodes that never
slip at its start (``stuck_prefix``), and the residual's rate in omega (``residual_rate``)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from .balance import BANDED_MAX_BLOCK, BlockTridiagonal, factorise
from .compiled import kernel

Array = NDArray[np.float64]


def with_diagonal(J: NDArray[np.float64], diag: NDArray[np.float64]) -> NDArray[np.float64]:
    """The blocks ``J`` (n, s, s) with ``diag`` (n, s) added to their diagonals, in a new array (a third of
    the time of ``J + diag[:, :, None] * I``, which forms the (n, s, s) product first)."""
    out = np.array(J, dtype=float)
    n, s = diag.shape
    out.reshape(n, s * s)[:, :: s + 1] += diag
    return out


class Coupled:
    """A factorisation of the bar's block-tridiagonal Jacobian A (diagonal blocks, coupling diag(c) of
    neighbouring nodes): held as the factorisation ``fac`` of A itself where c is one number (the lumped
    bar), else of diag(c)^-1 A, whose coupling is the identity that ``balance.factorise`` takes (each block
    row divided by c: diagonal blocks stay diagonal, so the nodes that never slip stay cheap)."""

    def __init__(self, blocks: Array, c: Array, diagonal: int, row0: bool) -> None:
        self.scaled = bool(np.any(c != c[0]))
        self.c = c
        if self.scaled:
            self.fac = factorise(blocks / c[None, :, None], 1.0, diagonal, row0)
        else:
            self.fac = factorise(blocks, float(c[0]), diagonal, row0)

    @classmethod
    def of(cls, J: Array, lin: Array, c: Array, diagonal: int, row0: bool) -> Coupled:
        """``Coupled(with_diagonal(J[:-1], lin[:-1]), c, diagonal, row0)``: in one compiled call where the blocks are
        eliminated one by one (more than ``BANDED_MAX_BLOCK`` coefficients a node), the same numbers."""
        fused = kernel("coupled_factor")
        if fused is None or J.shape[1] <= BANDED_MAX_BLOCK:
            return cls(with_diagonal(J[:-1], lin[:-1]), c, diagonal, row0)
        k = min(int(diagonal), J.shape[0] - 1)
        inv_d, inv_v, inv, bad = fused(J, lin, c, k, bool(row0), bool(np.any(c != c[0])))
        return cls.from_factors(inv_d, inv_v, inv, bad, c, row0)

    @classmethod
    def from_factors(cls, inv_d: Array, inv_v: Array, inv: Array, bad: int, c: Array, row0: bool) -> Coupled:
        """The factorisation from the compiled block elimination's arrays (``compiled.coupled_factor``);
        ``LinAlgError`` where it met a singular block (``bad`` >= 0)."""
        if bad >= 0:
            raise np.linalg.LinAlgError(f"singular block {bad} in the block elimination")
        out = cls.__new__(cls)
        out.scaled, out.c = bool(np.any(c != c[0])), c
        out.fac = BlockTridiagonal.from_factors(inv_d, inv_v, inv, 1.0 if out.scaled else float(c[0]), row0)
        return out

    def solve(self, r: Array) -> Array:
        """A^-1 r for r of shape (n, s) or (n, s, q)."""
        if not self.scaled:
            return self.fac.solve(r)
        return self.fac.solve(r / self.c.reshape((-1,) + (1,) * (r.ndim - 2)))

    def coupled_last_inverse(self) -> Array:
        """diag(c) (A^-1)_{n-1,n-1} diag(c): the Schur complement's correction at the driven node."""
        if not self.scaled:
            return self.c[0] ** 2 * self.fac.last_inverse()
        return self.c[:, None] * self.fac.last_inverse()  # (A^-1)_ll = (C^-1 A)^-1_ll C^-1


def residual_rate(dlin: Array, dc: Array, U: Array, X: Array) -> Array:
    """dR/domega (n, s) of the free nodes at the state U (n, s) for the end motion X: the linear part's
    derivatives ``dlin`` (n + 1, s) and ``dc`` (s,) of ``segments.LinearPart`` (the forces do not
    depend on omega)."""
    rate = dlin[:-1] * U
    if np.any(dc):
        rate[1:] += dc * U[:-1]
        rate[:-1] += dc * U[1:]
        rate[-1] += dc * X
    return rate


def stuck_prefix(state: tuple | None) -> int:
    """How many of the bar's first nodes never slip in the return map's ``state`` (0 without one):
    their Jacobian blocks are ``kc I`` plus the diagonal linear part in the odd basis, and that but
    for the first row (the mean's) in a basis with the mean (``factorise``'s ``row0``)."""
    if state is None:
        return 0
    never = state[3][:-1]
    return int(never.size if never.all() else np.argmin(never))
