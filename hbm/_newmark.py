"""Deprecated path of :mod:`hbm.reference.newmark`."""

from contact_models.numerics.compat import moved_module

moved_module(__name__, "hbm.reference.newmark")
