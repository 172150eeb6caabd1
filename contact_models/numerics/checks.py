"""Shared input checks: every failure is a ValueError naming the parameter and its value."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray


def positive(name: str, value: object) -> float:
    """Return ``value`` as float if it is finite and > 0, else raise ValueError."""
    v = _scalar(name, value)
    if not v > 0.0:
        raise ValueError(f"{name} must be positive, got {name}={value!r}")
    return v


def nonnegative(name: str, value: object) -> float:
    """Return ``value`` as float if it is finite and >= 0, else raise ValueError."""
    v = _scalar(name, value)
    if not v >= 0.0:
        raise ValueError(f"{name} must be >= 0, got {name}={value!r}")
    return v


def finite(name: str, value: object) -> float:
    """Return ``value`` as a finite float, else raise ValueError."""
    return _scalar(name, value)


def count(name: str, value: object, minimum: int = 1) -> int:
    """Return ``value`` as an int >= ``minimum``, else raise ValueError.

    A number only: an integer, or a float with an integral value; booleans and strings (``"3"``,
    which ``int()`` would read) are refused.
    """
    ok = not isinstance(value, (bool, str, bytes))
    try:
        ok = ok and float(value) == int(value) and int(value) >= minimum
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok:
        raise ValueError(f"{name} must be an integer >= {minimum}, got {name}={value!r}")
    return int(value)


def derived(owner: str, params: dict, compute, *, positive_names: tuple = ()) -> dict:
    """``compute()``: the quantities an element derives from its parameters (a dict), each finite
    (and > 0 for ``positive_names``); else a ValueError naming the parameters, the quantity and its
    value (parameters near the float limits, e.g. a stiffness of 1e-300 beside one of 1e300)."""
    shown = ", ".join(f"{k}={v!r}" for k, v in params.items())
    try:
        with np.errstate(all="raise"):
            out = compute()
    except (ZeroDivisionError, OverflowError, FloatingPointError) as exc:
        raise ValueError(f"{owner}({shown}): the parameters are too far apart for double precision (deriving the "
                         f"element's constants: {exc}); keep their ratios within about 1e150") from None
    for name, v in out.items():
        v = float(v)
        if not math.isfinite(v) or (name in positive_names and not v > 0.0):
            raise ValueError(f"{owner}({shown}): the parameters give {name} = {v!r}, which must be finite"
                             f"{' and > 0' if name in positive_names else ''}; keep their ratios within about 1e150")
    return out


def nonnegative_array(name: str, value: ArrayLike) -> NDArray[np.float64]:
    """Return ``value`` as a float array whose entries are finite and >= 0."""
    if type(value) is float and 0.0 <= value < math.inf:  # the common scalar, without numpy's checks
        return np.array(value)
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number or an array of numbers, got {name}={value!r}") from None
    bad = ~np.isfinite(arr) | (arr < 0.0)
    if np.any(bad):
        first = arr[bad].flat[0] if arr.ndim else float(arr)
        raise ValueError(f"{name} must be finite and >= 0, got {name}={first!r}")
    return arr


def _scalar(name: str, value: object) -> float:
    if isinstance(value, (bool, str, bytes)):  # float("2e11") would read a string: a number only, as count
        raise ValueError(f"{name} must be a number, got {name}={value!r}")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {name}={value!r}") from None
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite, got {name}={value!r}")
    return v
