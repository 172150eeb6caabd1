"""Deprecated path of :mod:`hbm.reference.transient`."""

from contact_models.numerics.compat import moved_module

moved_module(__name__, "hbm.reference.transient")
