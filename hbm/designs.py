"""What a study computes: its points (a grid, random samples, or both) and the run of one point.

A point is a dict ``{name: value}``; for a scene study the names are scene keys in dotted form
(``"damper.mu"``, ``"damper.load.N"``).  Samples are drawn here, in the calling process, from one
``numpy.random.Generator(PCG64(seed))``, so that every executor is handed the same numbers.
"""

from __future__ import annotations

import hashlib
import json
import math
from collections.abc import Sequence as _Sequence
from dataclasses import dataclass
from typing import Any, Callable, Mapping, Sequence

import numpy as np

#: The most runs a study may make (points of :func:`grid`, :func:`samples`, :func:`combine` and
#: :class:`hbm.study.Study`); a larger one is refused before any point is made.
MAX_RUNS = 1_000_000


def _shown(value: Any) -> str:
    """``repr(value)``, cut to 120 characters for a message."""
    r = repr(value)
    return r if len(r) <= 120 else r[:117] + "..."


def mapping(name: str, value: Any, holds: str) -> Mapping:
    """``value`` if it is a mapping (a dict of ``holds``), else a ValueError naming ``name`` and the value."""
    if not isinstance(value, Mapping):
        raise ValueError(f"{name} must be a dict of {holds}, got {name}={_shown(value)}")
    return value


def point_list(name: str, value: Any) -> Sequence:
    """``value`` if it is a sequence of points (each a dict of parameter name to value), else a ValueError
    naming ``name``, the value or the first point that is not a dict."""
    if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, _Sequence):
        raise ValueError(f"{name} must be a sequence of points (dicts of parameter name to value, e.g. from "
                         f"grid or samples), got {name}={_shown(value)}")
    if not isinstance(value, Points):  # (Points of grid, samples or combine are dicts, each made when asked)
        for i, p in enumerate(value):
            mapping(f"{name}[{i}]", p, "parameter name to value")
    return value


def _too_many(count: int, what: str, scene: str = "") -> None:
    """Refuse ``count`` runs over :data:`MAX_RUNS`: ``what`` says what made them, ``scene`` the
    scene keys that did."""
    if count > MAX_RUNS:
        raise ValueError(f"{what} = {count} runs, more than a study may make (MAX_RUNS = {MAX_RUNS}"
                         + (f"; in a scene: {scene}" if scene else "") + ")")


class Points(_Sequence):
    """The points of a study, each made when it is asked for: what :func:`grid`, :func:`samples`
    and :func:`combine` return.

    A sequence of dicts (``len``, indexing, slicing, iteration) equal to the list of the same
    dicts; ``+`` and ``*`` give lists.  Only the drawn numbers are stored (``n`` floats per
    sampled parameter), so counting the runs of a large study, or making its first point,
    costs the same as for a small one.

    Examples
    --------
    >>> pts = grid({"a": [1, 2], "b": ["x", "y", "z"]})
    >>> len(pts), pts[4], pts[-1] == {"a": 2, "b": "z"}
    (6, {'a': 2, 'b': 'y'}, True)
    >>> pts[:2]
    [{'a': 1, 'b': 'x'}, {'a': 1, 'b': 'y'}]
    """

    __hash__ = None  # type: ignore[assignment]

    def __init__(self, length: int, make: Callable[[int], dict]) -> None:
        self._length = int(length)
        self._make = make

    def __len__(self) -> int:
        return self._length

    def __getitem__(self, index: Any) -> Any:
        if isinstance(index, slice):
            return [self._make(i) for i in range(*index.indices(self._length))]
        i = int(index)
        if i < 0:
            i += self._length
        if not 0 <= i < self._length:
            raise IndexError(f"point index out of range: {index} of {self._length} points")
        return self._make(i)

    def __iter__(self):
        return (self._make(i) for i in range(self._length))

    def __eq__(self, other: Any) -> bool:
        if not isinstance(other, _Sequence) or isinstance(other, (str, bytes)):
            return NotImplemented
        return len(self) == len(other) and all(a == b for a, b in zip(self, other))

    def __add__(self, other: Any) -> list:
        return list(self) + list(other)

    def __radd__(self, other: Any) -> list:
        return list(other) + list(self)

    def __mul__(self, times: int) -> list:
        return list(self) * times

    __rmul__ = __mul__

    def __repr__(self) -> str:
        return repr(list(self))


class _Grid:  # the i-th combination, the last name fastest (as itertools.product)
    def __init__(self, names: list, values: list) -> None:
        self.names, self.values = names, values

    def __call__(self, i: int) -> dict:
        out = {}
        for name, vals in zip(reversed(self.names), reversed(self.values)):
            i, j = divmod(i, len(vals))
            out[name] = vals[j]
        return {name: out[name] for name in self.names}


class _Drawn:  # the i-th of the drawn values
    def __init__(self, drawn: dict) -> None:
        self.drawn = drawn

    def __call__(self, i: int) -> dict:
        return {name: float(v[i]) for name, v in self.drawn.items()}


class _Joined:  # every point of first with every point of second, second fastest
    def __init__(self, first: Sequence, second: Sequence) -> None:
        self.first, self.second = first, second

    def __call__(self, i: int) -> dict:
        a, b = divmod(i, len(self.second))
        return {**self.first[a], **self.second[b]}


def _finite(name: str, value: Any, *, positive: bool = False) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        v = math.nan
    if not math.isfinite(v) or (positive and v <= 0.0):
        raise ValueError(f"{name} must be a finite number{' > 0' if positive else ''}, got {name}={value!r}")
    return v


@dataclass(frozen=True)
class Distribution:
    """A distribution of one parameter: ``kind`` ("uniform", "normal", "lognormal") and its two
    numbers ``a``, ``b`` (see :func:`uniform`, :func:`normal`, :func:`lognormal`).

    Make one with ``uniform``, ``normal`` or ``lognormal``, which check the numbers; the
    constructor itself does not.

    Attributes
    ----------
    kind : {"uniform", "normal", "lognormal"}
        The family.
    a : float
        ``low`` (uniform), ``mean`` (normal) or ``median`` (lognormal), in the parameter's units.
    b : float
        ``high`` (uniform, the parameter's units), ``std`` (normal, the parameter's units) or
        ``sigma`` (lognormal: the standard deviation of ``log(x)``, dimensionless).

    Examples
    --------
    >>> d = normal(100.0, 5.0)
    >>> d.kind, d.a, d.b
    ('normal', 100.0, 5.0)
    """

    kind: str
    a: float
    b: float

    def draw(self, rng: np.random.Generator, n: int) -> np.ndarray:
        """``n`` values drawn with ``rng``."""
        if self.kind == "uniform":
            return rng.uniform(self.a, self.b, n)
        if self.kind == "normal":
            return rng.normal(self.a, self.b, n)
        return rng.lognormal(math.log(self.a), self.b, n)

    def as_dict(self) -> dict:
        names = {"uniform": ("low", "high"), "normal": ("mean", "std"), "lognormal": ("median", "sigma")}[self.kind]
        return {"distribution": self.kind, names[0]: self.a, names[1]: self.b}


def uniform(low: float, high: float) -> Distribution:
    """Uniform on ``[low, high)``.

    Parameters
    ----------
    low : float
        The smallest value, in the parameter's units.
    high : float
        The bound the values stay below, in the parameter's units.

    Returns
    -------
    Distribution
        ``Distribution("uniform", low, high)``.

    Raises
    ------
    ValueError
        Unless ``low < high``, both finite.

    Examples
    --------
    >>> uniform(0.2, 0.4).as_dict()
    {'distribution': 'uniform', 'low': 0.2, 'high': 0.4}
    """
    low, high = _finite("low", low), _finite("high", high)
    if not low < high:
        raise ValueError(f"uniform needs low < high, got low={low!r}, high={high!r}")
    return Distribution("uniform", low, high)


def normal(mean: float, std: float) -> Distribution:
    """Normal with ``mean`` and standard deviation ``std > 0``.

    Parameters
    ----------
    mean : float
        The mean, in the parameter's units.
    std : float
        The standard deviation (> 0), in the parameter's units.

    Returns
    -------
    Distribution
        ``Distribution("normal", mean, std)``.

    Raises
    ------
    ValueError
        If ``mean`` is not a finite number, or ``std`` is not a finite number > 0.

    Examples
    --------
    >>> normal(100.0, 5.0).as_dict()
    {'distribution': 'normal', 'mean': 100.0, 'std': 5.0}
    """
    return Distribution("normal", _finite("mean", mean), _finite("std", std, positive=True))


def lognormal(median: float, sigma: float) -> Distribution:
    """Lognormal: ``log(x)`` is normal with mean ``log(median)`` and standard deviation ``sigma``.

    Parameters
    ----------
    median : float
        The median (> 0), in the parameter's units.
    sigma : float
        The standard deviation of ``log(x)`` (> 0, dimensionless).

    Returns
    -------
    Distribution
        ``Distribution("lognormal", median, sigma)``.

    Raises
    ------
    ValueError
        If ``median`` or ``sigma`` is not a finite number > 0.

    Notes
    -----
    The median is ``median``, the mean ``median exp(sigma^2/2)``; every value is > 0, so it suits
    loads, stiffnesses and friction coefficients.

    Examples
    --------
    >>> lognormal(100.0, 0.3).as_dict()
    {'distribution': 'lognormal', 'median': 100.0, 'sigma': 0.3}
    """
    return Distribution("lognormal", _finite("median", median, positive=True),
                        _finite("sigma", sigma, positive=True))


#: Distribution constructors by name (the ``distribution`` key of a scene's ``[study.samples]``).
DISTRIBUTIONS: dict[str, tuple[Callable[..., Distribution], tuple[str, str]]] = {
    "uniform": (uniform, ("low", "high")),
    "normal": (normal, ("mean", "std")),
    "lognormal": (lognormal, ("median", "sigma")),
}


def grid(axes: Mapping[str, Sequence[Any]]) -> list[dict]:
    """Every combination of the values of ``axes`` (``{name: values}``), the last name fastest.

    Parameters
    ----------
    axes : mapping of str to sequence
        The values of each parameter, by name (a scene key in dotted form for a scene study).  A
        list, tuple or array gives several values; anything else is one value.  NumPy scalars are
        turned into Python numbers.

    Returns
    -------
    Points
        ``prod(len(values))`` points ``{name: value}`` (a sequence of dict, each made when asked
        for), names in the order of ``axes``; the first name varies slowest.

    Raises
    ------
    ValueError
        If ``axes`` is empty, a name has no values, or the points are more than :data:`MAX_RUNS`.

    Examples
    --------
    >>> grid({"damper.model": ["two-region", "macroslip"], "damper.load.N": [10.0, 100.0]})[1]
    {'damper.model': 'two-region', 'damper.load.N': 100.0}
    >>> len(grid({"a": [1, 2, 3], "b": [4, 5]}))
    6
    """
    if not mapping("axes", axes, "parameter name to its values"):
        raise ValueError("grid needs at least one parameter, got axes={}")
    values = []
    for name, vals in axes.items():
        vals = list(vals) if isinstance(vals, (list, tuple, np.ndarray)) else [vals]
        if not vals:
            raise ValueError(f"grid: parameter {name!r} has no values, got {name}={vals!r}")
        vals = [v.item() if isinstance(v, np.generic) else v for v in vals]
        twice = repeated(vals)
        if twice is not None:
            raise ValueError(f"grid: parameter {name!r} must not repeat a value (one run per value), got "
                             f"{name}={vals!r}: {twice[0]!r} and {twice[1]!r} are the same value")
        values.append(vals)
    count = math.prod(len(v) for v in values)
    _too_many(count, "grid: " + " x ".join(f"{name} ({len(v)} values)" for name, v in zip(axes, values)),
              "study.grid")
    return Points(count, _Grid(list(axes), values))


def repeated(values: Sequence[Any]) -> tuple | None:
    """The first two of ``values`` that are equal (``10`` and ``10.0`` are; ``1`` and ``True`` are not),
    or None: a grid computing one point twice, under one id or two."""
    seen: dict = {}
    unhashable: list = []
    for v in values:
        key = (type(v) is bool, v)
        try:
            if key in seen:
                return seen[key], v
            seen[key] = v
        except TypeError:  # a list or a table: compared one by one
            for u in unhashable:
                if u == v:
                    return u, v
            unhashable.append(v)
    return None


def samples(n: int, distributions: Mapping[str, Distribution], *, seed: int) -> list[dict]:
    """``n`` random points: parameter ``name`` drawn from ``distributions[name]``.

    One generator ``numpy.random.default_rng(seed)`` draws all ``n`` values of each parameter in
    the order of ``distributions``, so the points depend only on ``n``, ``seed`` and that order.

    Parameters
    ----------
    n : int
        The number of points (>= 1).
    distributions : mapping of str to Distribution
        The distribution of each parameter, by name; the order sets the order of drawing.
    seed : int
        The seed of the generator (>= 0), keyword-only; the same seed gives the same points.

    Returns
    -------
    Points
        ``n`` points ``{name: float}`` (a sequence of dict, each made when asked for; the values
        are drawn here).

    Raises
    ------
    ValueError
        For ``n < 1`` or ``n`` more than :data:`MAX_RUNS` (nothing is drawn), a negative or
        non-integer ``seed``, empty ``distributions``, or a value that is not a
        :class:`Distribution`.

    Examples
    --------
    >>> pts = samples(3, {"damper.mu": uniform(0.2, 0.4)}, seed=1)
    >>> [round(p["damper.mu"], 4) for p in pts]
    [0.3024, 0.3901, 0.2288]
    """
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"samples needs an integer n >= 1, got n={n!r}")
    _too_many(int(n), "samples: n", f"study.n = {int(n)}")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"samples needs an integer seed >= 0, got seed={seed!r}")
    if not mapping("distributions", distributions, "parameter name to a Distribution"):
        raise ValueError("samples needs at least one distribution, got distributions={}")
    rng = np.random.default_rng(int(seed))
    drawn = {}
    for name, dist in distributions.items():
        if not isinstance(dist, Distribution):
            raise ValueError(f"samples: {name} must be a Distribution (uniform, normal, lognormal), got {dist!r}")
        drawn[name] = dist.draw(rng, int(n))
    return Points(int(n), _Drawn(drawn))


def combine(first: Sequence[dict], second: Sequence[dict]) -> list[dict]:
    """Every point of ``first`` joined with every point of ``second`` (e.g. each model of a grid
    with every sample); ``second`` varies fastest.

    Parameters
    ----------
    first : sequence of dict
        The outer points (e.g. from ``grid``).
    second : sequence of dict
        The inner points (e.g. from ``samples``); where both name a parameter, ``second``'s value
        is kept.

    Returns
    -------
    Points
        ``len(first) * len(second)`` points (a sequence of dict, each made when asked for).

    Raises
    ------
    ValueError
        If they are more than :data:`MAX_RUNS`.

    Examples
    --------
    >>> combine([{"a": 1}, {"a": 2}], [{"b": 3}])
    [{'a': 1, 'b': 3}, {'a': 2, 'b': 3}]
    """
    first, second = point_list("first", first), point_list("second", second)
    _too_many(len(first) * len(second), f"combine: {len(first)} x {len(second)} points",
              f"the points of study.grid x study.n = {len(second)}")
    return Points(len(first) * len(second), _Joined(first, second))


def run_id(identity: Any, version: str) -> str:
    """The hash naming a run: SHA-256 of its inputs ``identity`` (JSON, keys sorted, floats
    exact) and the library ``version``, 20 hex digits.

    Parameters
    ----------
    identity : object
        The run's inputs, JSON-serialisable (anything else is written as its ``repr``).
    version : str
        The library version (``contact_models.__version__``): a new version gives new ids.

    Returns
    -------
    str
        The first 20 hex digits of the SHA-256 digest.

    Examples
    --------
    >>> a = run_id({"damper.mu": 0.3}, "0.1.0")
    >>> len(a), a == run_id({"damper.mu": 0.3}, "0.1.0"), a == run_id({"damper.mu": 0.3}, "0.2.0")
    (20, True, False)
    """
    text = json.dumps({"inputs": identity, "version": version}, sort_keys=True, default=repr)
    return hashlib.sha256(text.encode()).hexdigest()[:20]


__all__ = ["MAX_RUNS", "Points", "Distribution", "uniform", "normal", "lognormal", "DISTRIBUTIONS", "grid",
           "samples", "combine", "run_id"]
