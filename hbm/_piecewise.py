"""Deprecated path of :mod:`hbm.reference.piecewise`."""

from contact_models.numerics.compat import moved_module

moved_module(__name__, "hbm.reference.piecewise")
