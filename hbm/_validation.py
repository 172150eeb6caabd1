"""Input checks shared by ``hbm``: each failure is a ValueError naming the parameter and its value."""

from __future__ import annotations

import math


def number(name: str, value) -> float:
    """``value`` as a finite float, else ValueError."""
    if isinstance(value, bool):
        raise ValueError(f"{name} must be a number, got {name}={value!r}")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {name}={value!r}") from None
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite, got {name}={value!r}")
    return v


def positive(name: str, value) -> float:
    """``value`` as a float if finite and > 0, else ValueError."""
    v = number(name, value)
    if not v > 0.0:
        raise ValueError(f"{name} must be positive, got {name}={value!r}")
    return v


def nonnegative(name: str, value) -> float:
    """``value`` as a float if finite and >= 0, else ValueError."""
    v = number(name, value)
    if not v >= 0.0:
        raise ValueError(f"{name} must be >= 0, got {name}={value!r}")
    return v


def count(name: str, value, minimum: int = 1) -> int:
    """``value`` as an int >= ``minimum``, else ValueError."""
    ok = not isinstance(value, bool)
    try:
        ok = ok and float(value) == int(value) and int(value) >= minimum
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok:
        raise ValueError(f"{name} must be an integer >= {minimum}, got {name}={value!r}")
    return int(value)
