"""Deprecated path of :mod:`contact_models.numerics.checks`."""

from .numerics.compat import moved_module

moved_module(__name__, "contact_models.numerics.checks")
