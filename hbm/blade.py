"""The blade: a single-degree-of-freedom oscillator ``m x'' + c x' + k x = F cos(omega t)``.

The damper's excited end moves with the blade, so the damper force ``f_d(x)`` adds to the
left-hand side (``hbm.balance``).  To the balance a blade is the one-DOF structure
:meth:`Blade.as_structure`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ._validation import nonnegative, positive
from .structure import Structure


@dataclass(frozen=True)
class Blade:
    """Blade of mass ``mass`` (kg), stiffness ``stiffness`` (N/m), viscous damping
    ``damping`` (N s/m), excited by ``force * cos(omega t)`` (force amplitude in N).

    The single-degree-of-freedom oscillator ``m x'' + c x' + k x + f_d(x) = F cos(omega t)``,
    ``f_d`` the force of the damper whose excited end moves with the blade.

    Parameters
    ----------
    mass : float
        Modal mass m (kg), > 0.
    stiffness : float
        Stiffness k (N/m), >= 0.
    damping : float
        Viscous damping c (N s/m), >= 0.
    force : float
        Force amplitude F (N), > 0.

    Raises
    ------
    ValueError
        If a parameter is out of its range or not finite, naming it and its value.

    See Also
    --------
    frequency_response : the FRF of the blade with a damper.

    Examples
    --------
    >>> from hbm import Blade
    >>> blade = Blade.from_modal(frequency=1000.0, damping_ratio=0.01, mass=2.0, force=1.0)
    >>> blade.stiffness, blade.damping                 # m w^2 (N/m), 2 zeta m w (N s/m)
    (2000000.0, 40.0)
    >>> blade.natural_frequency, round(blade.damping_ratio, 12)
    (1000.0, 0.01)
    """

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
        k, c = m * w * w, 2.0 * zeta * m * w
        if not (math.isfinite(k) and math.isfinite(c)):  # each finite, their product past the float range
            raise ValueError(f"frequency, damping_ratio and mass must give a finite stiffness m w^2 and damping "
                             f"2 zeta m w, got frequency={frequency!r}, damping_ratio={damping_ratio!r}, mass={mass!r}")
        return cls(mass=m, stiffness=k, damping=c, force=force)

    def as_structure(self) -> Structure:
        """The blade as a one-DOF :class:`hbm.Structure`, solved at one harmonic unless asked for more.

        Returns
        -------
        Structure
            ``M = [[mass]]``, ``C = [[damping]]``, ``K = [[stiffness]]``, ``force = [force]``, with
            ``default_harmonics = 1`` (the single-harmonic model of the paper).

        Examples
        --------
        >>> s = Blade(mass=2.0, stiffness=8.0, damping=0.1, force=1.0).as_structure()
        >>> s.n, s.K.tolist(), s.default_harmonics
        (1, [[8.0]], 1)
        """
        s = Structure([[self.mass]], [[self.damping]], [[self.stiffness]], force=[self.force])
        s.default_harmonics = 1
        return s

    @property
    def natural_frequency(self) -> float:
        """sqrt(k/m) in rad/s (the blade alone)."""
        return math.sqrt(self.stiffness / self.mass)

    @property
    def damping_ratio(self) -> float:
        """c / (2 sqrt(k m)) (the blade alone; inf for a blade without stiffness)."""
        km = self.stiffness * self.mass
        return self.damping / (2.0 * math.sqrt(km)) if km > 0.0 else math.inf
