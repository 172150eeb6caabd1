"""Deprecated: :func:`hbm.frequency_response` (``hbm.frf``) solves every system."""

from contact_models.numerics.compat import warn_moved

from .frf import frequency_response as structure_response

warn_moved(__name__, "hbm.frf")
