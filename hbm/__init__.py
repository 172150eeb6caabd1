"""Harmonic balance of a blade with a friction damper, and pseudo-arclength continuation.

``Blade`` and ``frequency_response`` are the entry points; ``hbm.continuation`` is the generic
continuation core (it knows nothing of friction); ``hbm.residual`` states the balance.
``response_at`` solves the balance at one frequency; ``simulate_blade`` (``hbm.transient``)
integrates the blade with the discretised bar in time, the balance's independent check.
"""

from contact_models import __version__  # one version for both packages

from .blade import Blade
from . import continuation
from .frf import FrequencyResponse, Peak, Response, frequency_response, response_at
from .reference.transient import BladeSimulation, simulate_blade
from .residual import HarmonicBalance
from .reference.shooting import PeriodicPeak, PeriodicResponse, periodic_peak, periodic_response

__all__ = ["__version__", "Blade", "frequency_response", "FrequencyResponse", "Peak", "HarmonicBalance",
           "continuation", "response_at", "Response", "simulate_blade", "BladeSimulation"]
__all__ += ["periodic_response", "PeriodicResponse", "periodic_peak", "PeriodicPeak"]
from .structure import Contact, ReducedStructure, Structure
from .mhresult import MultiHarmonicResponse

__all__ += ["Structure", "ReducedStructure", "Contact", "MultiHarmonicResponse"]
