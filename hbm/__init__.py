"""One harmonic balance for friction-damped structures, with continuation, references and scenes.

A blade with a damper is the one-DOF case of a structure with contacts; ``frequency_response``
traces the FRF of either (``hbm.frf``, front of the balance in ``hbm.balance``) and returns one
result type, :class:`FrequencyResponse`.  ``hbm.continuation`` is the generic continuation core
(it knows nothing of friction).  ``response_at`` solves a blade's balance at one frequency;
``simulate_blade`` (``hbm.reference``) integrates the blade with the discretised bar in time and ``periodic_response``
finds the true periodic response by shooting, the balance's independent checks.
``nonlinear_modes`` traces a structure's nonlinear modes (extended periodic motion concept),
``forced_response`` the forced response from one mode, ``damper_optimum`` the damper parameter
that minimises the resonance peak (``docs/nonlinear_modes.md``).  Scenes
(``hbm.scenes``), studies (``hbm.study``) and the command line build on these.
"""

from contact_models import __version__  # one version for both packages
from contact_models.accuracy import AccuracyWarning  # the library's one accuracy category

from . import continuation
from .continuation import Status
from .balance import HarmonicBalance
from .blade import Blade
from .frf import Point, frequency_response, response_at
from .balance.presets import Steps
from .modes import NonlinearModes, nonlinear_modes
from .single_mode import ModalFRF, forced_response
from .damper_optimum import DamperOptimum, damper_optimum
from .result import FrequencyResponse, Peak, Response, Segment
from .reference.shooting import PeriodicPeak, PeriodicResponse, periodic_peak, periodic_response
from .structure import Contact, ReducedStructure, Structure
from .cyclic import CyclicStructure
from .reference.transient import BladeSimulation, simulate_blade

#: The result of a structure's solve is the one result type (this name is kept for old code).
MultiHarmonicResponse = FrequencyResponse

__all__ = ["__version__", "Blade", "frequency_response", "FrequencyResponse", "Peak", "Point", "Steps", "HarmonicBalance",
           "continuation", "response_at", "Response", "simulate_blade", "BladeSimulation"]
__all__ += ["periodic_response", "PeriodicResponse", "periodic_peak", "PeriodicPeak"]
__all__ += ["Structure", "ReducedStructure", "CyclicStructure", "Contact", "MultiHarmonicResponse", "AccuracyWarning"]
__all__ += ["nonlinear_modes", "NonlinearModes", "forced_response", "ModalFRF", "damper_optimum", "DamperOptimum"]
__all__ += ["Segment", "Status"]
