"""Built-in cases: the main job of ``python3 -m hbm``.

The default case: the reference bar of the documentation (``Bar(E=2e11, rho=7850, A=1e-5, L=0.05, k=8e8, beta=4e7,
mu=0.3)``, omega_c = 1.332e5 rad/s) as a two-region microslip damper under a uniform normal
load of 100 N (k* = 4e7 N/m, a_min = 7.5e-7 m, gross slip at 1.78e-6 m near resonance), on a
blade of stiffness 1e8 N/m whose stuck resonance sqrt((k + k*)/m) is 0.3 omega_c (m = 0.0877 kg),
blade damping ratio 2e-3, force 8 N: at resonance the damper is in microslip (peak amplitude
about 2 a_min).  The sweep is 0.8 to 1.1 times the stuck resonance.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from contact_models import Bar, ContactElement, TwoRegionMicroslip, UniformLoad

from ..blade import Blade

__all__ = ["Case", "default_case", "DEFAULT_BLADE_STIFFNESS", "DEFAULT_DAMPING_RATIO", "DEFAULT_FORCE",
           "DEFAULT_RESONANCE", "DEFAULT_SWEEP"]

#: Blade stiffness (N/m), damping ratio and force amplitude (N) of the default case.
DEFAULT_BLADE_STIFFNESS = 1.0e8
DEFAULT_DAMPING_RATIO = 2.0e-3
DEFAULT_FORCE = 8.0
#: Stuck resonance as a fraction of the bar's omega_c, and the sweep around it.
DEFAULT_RESONANCE = 0.3
DEFAULT_SWEEP = (0.8, 1.1)


class Case(NamedTuple):
    """A job of the command line: the blade, its damper's element, the sweep (rad/s) and its description."""

    blade: Blade
    element: ContactElement
    omega_range: tuple[float, float]
    description: str


def default_case() -> Case:
    """Blade + two-region microslip damper (uniform load 100 N), stuck resonance at 0.3 omega_c."""
    bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    element = TwoRegionMicroslip(bar, UniformLoad(N=100.0))
    w_stuck = DEFAULT_RESONANCE * bar.omega_c
    k = DEFAULT_BLADE_STIFFNESS
    m = (k + element.stuck_stiffness(0.0)) / w_stuck**2
    blade = Blade.from_modal(frequency=math.sqrt(k / m), damping_ratio=DEFAULT_DAMPING_RATIO, mass=m,
                             force=DEFAULT_FORCE)
    w0, w1 = (f * w_stuck for f in DEFAULT_SWEEP)
    text = (f"blade k={k:.4g} N/m, m={m:.4g} kg, zeta={DEFAULT_DAMPING_RATIO:g}, F={DEFAULT_FORCE:g} N; "
            f"damper TwoRegionMicroslip(bar, UniformLoad(N=100)) (k*={element.stuck_stiffness(0.0):.4g} N/m, "
            f"a_min={element.slip_amplitude(0.0):.4g} m, omega_c={bar.omega_c:.6g} rad/s); "
            f"sweep {w0:.6g}..{w1:.6g} rad/s")
    return Case(blade, element, (w0, w1), text)
