"""What a fixed rung of the all-mode bar returned, kept and read again: ``ForceMemo`` (the forces by their exact
end motion and frequency), ``truncated`` (a solution's force on the harmonics of the motion asked for) and
``EvenBlockLater`` (what an answer without dF/dX's even-even block needs to fill it later)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from .solve import AllModeSolution, FixedBar, even_part, pad_harmonics


def truncated(force: tuple, X: NDArray[np.float64], odd: bool) -> tuple:
    """``(F, dF/dX, dF/domega)`` of a solution (``force``, that triple, at least as long as X) on the
    harmonics of ``X`` (copies).  ``odd``: it was solved in the odd basis, its even block filled,
    for an ``X`` whose even coefficients are at most rounding (``solve.EVEN_ROUNDING``); the
    force is then the odd solution's plus its first-order even part ``dF/dX X_even`` (dF/dX is block
    diagonal in odd and even coefficients at an odd solution).  The remainder is of second order, or,
    where the even part moves a sample across a stick/slip change, at most about ``EVEN_ROUNDING`` of
    the force scale: below the nested Newton's tolerance."""
    F, J, dw = force
    m = X.size
    F, J = F[:m].copy(), J[:m, :m].copy()
    if odd:
        F += J @ even_part(X)
    return F, J, dw[:m].copy()


#: What a :class:`ForceMemo` keeps at most (bytes of its keys and values), the oldest dropped first.
MEMO_BYTES = 2 * 2**20


class ForceMemo:
    """The harmonic forces a fixed rung returned, by their exact end motion and frequency.

    A harmonic balance asks again for the force at motions it asked for before, to the bit: its
    error estimate evaluates every converged point again (the point's residual, and a Newton step
    at 2H + 1 harmonics from the point padded with zeros, whose end motion is the same on the bar's
    harmonics).  A solve there would start from another cached state and could differ from the
    first answer within Newton's tolerance; the memo returns the first answer, without a solve, so
    the estimate reads the same force the balance converged on."""

    def __init__(self, max_bytes: int = MEMO_BYTES) -> None:
        self.max_bytes = max_bytes
        self._kept: dict = {}  # key -> (F, dF/dX, dF/domega), in the order kept
        self._bytes = 0

    @staticmethod
    def key(X: NDArray[np.float64], omega: float, H: int, odd: bool, even_block: bool = True) -> tuple:
        """The key of the motion X (padded to the bar's H) at omega, solved in the odd basis or not, with
        the even-even block of dF/dX or without (``AllModeMicroslip._harmonic_force``'s ``even_block``)."""
        return H, odd, even_block, float(omega), pad_harmonics(np.asarray(X, dtype=float), H).tobytes()

    def get(self, key: tuple, m: int) -> tuple | None:
        """The kept triple of ``key`` if it holds at least m coefficients, else None; a key without the even
        block is also served by the triple kept with it."""
        hit = self._kept.get(key)
        if hit is None and not key[2]:
            hit = self._kept.get(key[:2] + (True,) + key[3:])
        return hit if hit is not None and hit[0].size >= m else None

    def put(self, key: tuple, force: tuple, m: int) -> None:
        """Keep ``force`` (F, dF/dX, dF/domega) on its first m coefficients under ``key``."""
        F, J, dw = force
        m = min(m, F.size)
        value = (F[:m].copy(), J[:m, :m].copy(), dw[:m].copy())
        old = self._kept.pop(key, None)
        if old is not None:
            self._bytes -= len(key[-1]) + sum(a.nbytes for a in old)
        self._kept[key] = value
        self._bytes += len(key[-1]) + sum(a.nbytes for a in value)
        while self._bytes > self.max_bytes and len(self._kept) > 1:
            k = next(iter(self._kept))
            self._bytes -= len(k[-1]) + sum(a.nbytes for a in self._kept.pop(k))


class EvenBlockLater:
    """The even-even block of an odd-basis answer's dF/dX, filled when asked
    (``ContactElement.harmonic_force_deferred``; ``AllModeMicroslip._harmonic_force_deferred``).

    A balance leaves the block out while it traces a half-wave symmetric curve (docs/multiharmonic.md,
    "Half-wave symmetry"), and Hill's method needs it at the curve's points.  At a point, the
    solution's dF/dX is block diagonal in (odd, even) coefficients, so the block is independent of
    the odd blocks the answer carries: it is the Schur complement of the even blocks at that same
    solution (``FixedBar.even_block``).  This keeps what that needs, the free nodes' odd
    coefficients and the end motion (``nbytes``), not the solution: ``whole(dF_dX)`` evaluates the
    bar's balance once at them and eliminates (``FixedBar.even_block_at``; the block the solve's own
    ``even_block`` gives, to the bit) instead of a new nested Newton solve, and returns ``dF_dX``
    (the answer's, on its m coefficients, ``truncated``) with the block's first rows and columns in."""

    __slots__ = ("bar", "U", "X", "omega", "nbytes")

    def __init__(self, bar: FixedBar, sol: AllModeSolution) -> None:
        self.bar, self.omega = bar, sol.omega
        self.U = sol.U[:-1, bar.basis(True).idx]  # (a copy: fancy indexing)
        self.X = sol.X.copy()
        self.nbytes = self.U.nbytes + self.X.nbytes

    def __call__(self, dF_dX: NDArray[np.float64]) -> NDArray[np.float64]:
        even, block = self.bar.even_block_at(self.U, self.X, self.omega)
        k = int(np.searchsorted(even, dF_dX.shape[0]))  # the even coefficients among the answer's m
        whole = np.array(dF_dX, dtype=float)
        whole[np.ix_(even[:k], even[:k])] = block[:k, :k]
        return whole
