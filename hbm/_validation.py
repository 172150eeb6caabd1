"""Input checks shared by ``hbm``: the library's one set (each failure a ValueError naming the
parameter and its value), re-exported so ``hbm`` modules import them from one place."""

from contact_models._validation import count, finite, nonnegative, positive

number = finite

__all__ = ["count", "finite", "nonnegative", "number", "positive"]
