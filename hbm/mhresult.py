"""Deprecated: one result type, :class:`hbm.FrequencyResponse` (``hbm.result``), for every solve."""

from contact_models.numerics.compat import warn_moved

from .result import FrequencyResponse as MultiHarmonicResponse

warn_moved(__name__, "hbm.result")

__all__ = ["MultiHarmonicResponse"]
