"""Deprecated path of :mod:`hbm.balance.residual`."""

from contact_models.numerics.compat import moved_module

moved_module(__name__, "hbm.balance.residual")
