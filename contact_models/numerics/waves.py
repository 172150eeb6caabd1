"""How many cells a bar needs for the wavelength of a frequency: the guard both bars with every mode share.

A cell of the bar at the frequency Omega = H omega carries the phase sqrt(q) h, q = (rho A Omega^2 - k) / EA
(the wave number of the bar on its stuck shear layer, real above sqrt(k / (rho A))).  An exact segment
resonates with both ends held where that phase reaches pi, and a lumped finite element stops carrying the
wave (the stop band of its dispersion) already at phase 2.  A mesh whose cells carry more than
``MAX_SEGMENT_PHASE`` cannot represent the wave at all: it is refused by name (:class:`UnresolvedWave`).
"""

from __future__ import annotations

import math
from typing import Protocol


class _Bar(Protocol):
    """What the guards read of a ``contact_models.Bar`` (a protocol: the bar itself imports this module)."""

    E: float
    rho: float
    A: float
    L: float
    k: float

    @property
    def EA(self) -> float: ...

#: The largest phase sqrt(z) of a segment accepted (a fraction of pi: a cell at most 0.9 of half the
#: wavelength of the highest harmonic).
MAX_SEGMENT_PHASE = 0.9 * math.pi


class UnresolvedWave(ValueError):
    """Cells longer than ``MAX_SEGMENT_PHASE`` / pi of the highest harmonic's half wavelength (a rung of
    the all-mode element's estimate that is so is left out, ``allmode.accuracy.cells_error``)."""


def cells_for_phase(bar: _Bar, omega: float, H: int) -> int:
    """The fewest cells whose segments stay below ``MAX_SEGMENT_PHASE`` at harmonic H of omega."""
    try:
        q = (bar.rho * bar.A * (H * omega) ** 2 - bar.k) / bar.EA
    except OverflowError:  # (H omega)^2 beyond double precision (omega above about 1e154 rad/s)
        q = math.inf
    cells = math.sqrt(max(q, 0.0)) * bar.L / MAX_SEGMENT_PHASE
    return max(1, int(math.floor(min(cells, 2.0**62))) + 1)


#: The largest phase sqrt(rho / E) omega L of the whole bar (rad) at which its cos and sin still carry a digit:
#: past 1/eps the spacing of doubles there exceeds 2 pi.
MAX_BAR_PHASE = 1.0 / 2.220446049250313e-16


def max_omega(bar: _Bar) -> float:
    """The highest frequency (rad/s) whose phase sqrt(rho / E) omega L is within ``MAX_BAR_PHASE``."""
    return MAX_BAR_PHASE / (math.sqrt(bar.rho / bar.E) * bar.L)


def check_phase(bar: _Bar, omega: float) -> None:
    """ValueError naming omega where the bar's phase sqrt(rho / E) omega L exceeds ``MAX_BAR_PHASE``: its
    cos and sin are then rounding noise, so no answer at omega means anything (and omega**2 may overflow)."""
    phase = math.sqrt(bar.rho / bar.E) * omega * bar.L
    if not phase <= MAX_BAR_PHASE:
        raise ValueError(f"omega={omega!r} rad/s is too high for the bar: its phase sqrt(rho/E) omega L = {phase:.3g} "
                         f"rad exceeds 1/eps = {MAX_BAR_PHASE:.3g}, where cos and sin carry no digit; omega must be "
                         f"below {max_omega(bar):.3g} rad/s")
