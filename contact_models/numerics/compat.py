"""Old module paths kept importable: a moved module's old name answers with the new module."""

from __future__ import annotations

import importlib
import sys
import warnings


def moved_module(old: str, new: str) -> None:
    """Make module ``old`` an alias of module ``new`` and warn that it moved.

    Called from the body of the module left at the old path; afterwards ``import old`` and
    ``from old import name`` (private names too) give the new module's objects.

    Parameters
    ----------
    old, new : str
        Dotted module names.

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     moved_module("contact_models._example_old_path", "contact_models.numerics.roots")
    >>> caught[0].category.__name__, str(caught[0].message).split(";")[0]
    ('DeprecationWarning', 'contact_models._example_old_path moved to contact_models.numerics.roots')
    """
    warn_moved(old, new, stacklevel=4)
    sys.modules[old] = importlib.import_module(new)


def warn_moved(old: str, new: str, *, stacklevel: int = 3) -> None:
    """Warn (``DeprecationWarning``) that module ``old`` moved to ``new``; for a module left at the
    old path that re-exports the old names from their new homes."""
    warnings.warn(f"{old} moved to {new}; import it from there (this path will be removed)",
                  DeprecationWarning, stacklevel=stacklevel)
