"""Harmonic balance of a blade with a friction damper, and pseudo-arclength continuation.

``Blade`` and ``frequency_response`` are the entry points; ``hbm.continuation`` is the generic
continuation core (it knows nothing of friction); ``hbm.residual`` states the balance.
"""

from .blade import Blade
from . import continuation
from .frf import FrequencyResponse, Peak, frequency_response
from .residual import HarmonicBalance

__all__ = ["Blade", "frequency_response", "FrequencyResponse", "Peak", "HarmonicBalance",
           "continuation"]
