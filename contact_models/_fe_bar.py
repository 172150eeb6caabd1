"""Deprecated path of :mod:`contact_models.numerics.fe_bar`."""

from .numerics.compat import moved_module

moved_module(__name__, "contact_models.numerics.fe_bar")
