"""Contact elements for friction-damped structures: each gives f_s, f_c of its force.

See ``contact_models.base.ContactElement`` for the interface.
"""

from ._version import __version__
from .accuracy import AccuracyWarning
from .allmode import AllModeMicroslip, AllModeMicroslip2D
from .bar import Bar
from .centrifugal import CentrifugalLoad, RotatingPreload
from .base import ContactElement
from .contact2d import Contact2D
from .contact3d import Contact3D
from .iwan import Iwan
from .cubic import CubicSpring
from .gap import Gap
from .loads import FunctionLoad, QuadraticLoad, SampledLoad, UniformLoad
from .macroslip import Macroslip
from .model_range import ModelRangeWarning
from .microslip import ThreeRegionMicroslip, TwoRegionMicroslip
from .numerical import NumericalMicroslip
from .point_contact import PointContact
from .quasi_static import QuasiStatic

__all__ = ["__version__", "Bar", "CentrifugalLoad", "RotatingPreload", "ContactElement", "QuadraticLoad", "UniformLoad", "TwoRegionMicroslip",
           "ThreeRegionMicroslip", "Macroslip", "PointContact", "NumericalMicroslip", "QuasiStatic",
           "Iwan", "CubicSpring", "AllModeMicroslip", "FunctionLoad", "SampledLoad", "ModelRangeWarning",
           "AccuracyWarning", "Gap", "Contact2D", "AllModeMicroslip2D",
           "Contact3D"]
