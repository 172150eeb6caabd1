"""The blade: a single-degree-of-freedom oscillator ``m x'' + c x' + k x = F cos(omega t)``.

The damper's excited end moves with the blade, so the damper force ``f_d(x)`` adds to the
left-hand side (``hbm.residual``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ._validation import nonnegative, positive


@dataclass(frozen=True)
class Blade:
    """Blade of mass ``mass`` (kg), stiffness ``stiffness`` (N/m), viscous damping
    ``damping`` (N s/m), excited by ``force * cos(omega t)`` (force amplitude in N)."""

    mass: float
    stiffness: float
    damping: float
    force: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", positive("mass", self.mass))
        object.__setattr__(self, "stiffness", nonnegative("stiffness", self.stiffness))
        object.__setattr__(self, "damping", nonnegative("damping", self.damping))
        object.__setattr__(self, "force", positive("force", self.force))

    @classmethod
    def from_modal(cls, *, frequency: float, damping_ratio: float, mass: float, force: float) -> Blade:
        """Blade from its own natural frequency ``frequency`` (rad/s, without the damper),
        viscous ``damping_ratio`` (c = 2 zeta m omega_n), ``mass`` (kg) and ``force`` (N)."""
        w = positive("frequency", frequency)
        zeta = nonnegative("damping_ratio", damping_ratio)
        m = positive("mass", mass)
        return cls(mass=m, stiffness=m * w * w, damping=2.0 * zeta * m * w, force=force)

    @property
    def natural_frequency(self) -> float:
        """sqrt(k/m) in rad/s (the blade alone)."""
        return math.sqrt(self.stiffness / self.mass)

    @property
    def damping_ratio(self) -> float:
        """c / (2 sqrt(k m)) (the blade alone; inf for a blade without stiffness)."""
        km = self.stiffness * self.mass
        return self.damping / (2.0 * math.sqrt(km)) if km > 0.0 else math.inf
