"""The library's warning category for answers that may be less accurate than asked.

:class:`AccuracyWarning` is emitted where an estimate of an answer's error exceeds the
tolerance asked for (``hbm.frequency_response(..., tol=...)``), and by elements evaluated
outside the range where their model holds (``ModelRangeWarning``, its subclass).  Filter or
escalate it like any warning.
"""

from __future__ import annotations

__all__ = ["AccuracyWarning"]


class AccuracyWarning(UserWarning):
    """An answer may be further from the true periodic response than the tolerance asked for.

    The message names the worst estimate, where it occurs and what would bring it within the
    tolerance.  ``contact_models.ModelRangeWarning`` is a subclass (a model outside its range).

    Examples
    --------
    >>> import warnings
    >>> from contact_models import AccuracyWarning, ModelRangeWarning
    >>> issubclass(ModelRangeWarning, AccuracyWarning), issubclass(AccuracyWarning, UserWarning)
    (True, True)
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("error", AccuracyWarning)
    ...     try:
    ...         warnings.warn("estimated error 2e-3 > tol 1e-3", AccuracyWarning)
    ...     except AccuracyWarning as exc:
    ...         print(exc)
    estimated error 2e-3 > tol 1e-3
    """
