"""Deprecated path of :mod:`contact_models.numerics.genalpha`."""

from .numerics.compat import moved_module

moved_module(__name__, "contact_models.numerics.genalpha")
