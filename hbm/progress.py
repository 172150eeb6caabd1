"""Deprecated path of :mod:`hbm.cli.progress`."""

from contact_models.numerics.compat import moved_module

moved_module(__name__, "hbm.cli.progress")
