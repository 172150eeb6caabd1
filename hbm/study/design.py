"""Deprecated path of :mod:`hbm.designs`."""

from contact_models.numerics.compat import moved_module

moved_module(__name__, "hbm.designs")
