"""Deprecated: the multi-harmonic balance is the one balance of :mod:`hbm.balance`."""

from contact_models.numerics.compat import warn_moved

from .balance.condensation import Condensed
from .balance.layout import from_complex, to_complex
from .balance.residual import HarmonicBalance as MultiHarmonicBalance
from .frf import frequency_response as multiharmonic_response

warn_moved(__name__, "hbm.balance")

__all__ = ["MultiHarmonicBalance", "Condensed", "multiharmonic_response", "to_complex", "from_complex"]
