"""Deprecated path of :mod:`hbm.reference.shooting`."""

from contact_models.numerics.compat import moved_module

moved_module(__name__, "hbm.reference.shooting")
