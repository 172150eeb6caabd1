"""What a fixed rung of the all-mode bar returned, kept and read again: ``ForceMemo`` (the forces by their exact
end motion and frequency) and ``truncated`` (a solution's force on the harmonics of the motion asked for)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from .solve import even_part, pad_harmonics


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
