"""Deprecated path of :mod:`hbm.scenes.sampling`."""

from contact_models.numerics.compat import moved_module

moved_module(__name__, "hbm.scenes.sampling")
