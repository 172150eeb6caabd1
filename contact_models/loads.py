"""Normal load distributions q(x) (N/m) along the contact, 0 <= x <= L.

A load may be created without the bar's length (``UniformLoad(N)``,
``QuadraticLoad.from_ratio(N, ratio)``); the element binds it to its bar with
:meth:`on`.  Besides q, a load gives the running integrals used in Eq. 15,

    I1(x) = int_0^x q,      I2(x) = int_0^x I1,

so that Q'(x) = mu I1(x)/(EA) and Q(x) = mu I2(x)/(EA) exactly, in closed form.
All functions accept complex x (the microslip elements differentiate by complex step).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any, Self

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .numerics.checks import finite, nonnegative, number_array, positive, shown


def bound_load(load: Any, L: float) -> "_Load":
    """``load.on(L)``: a normal load of this module bound to a contact of length ``L`` (m), >= 0 along it;
    else a ValueError naming ``load`` (a number or None given for it, a load negative somewhere)."""
    if not isinstance(load, _Load):
        raise ValueError(f"load must be a normal load (UniformLoad, QuadraticLoad, FunctionLoad or SampledLoad), "
                         f"got load={load!r}")
    bound = load.on(L)
    if bound.minimum() < 0.0:
        raise ValueError(f"load must be >= 0 everywhere, got load={load!r}")
    return bound


class _Load:
    N: float
    L: float | None

    def on(self, L: float) -> Self:
        """This load on a contact of length ``L`` (checks an explicit length agrees)."""
        L = positive("L", L)
        if self.L is not None and not math.isclose(self.L, L, rel_tol=1e-12):
            raise ValueError(f"load length L={self.L!r} differs from the bar's length L={L!r}")
        return replace(self, L=L)

    def _length(self) -> float:
        if self.L is None:
            raise ValueError(f"{type(self).__name__} has no length yet: use load.on(L) or give L")
        return self.L

    def minimum(self) -> float:
        """Smallest value of q over [0, L]."""
        x = np.linspace(0.0, self._length(), 2001)
        return float(np.min(self.q(x)))


@dataclass(frozen=True)
class UniformLoad(_Load):
    """Constant normal load q = N/L (the paper's two-region case, Section 3).

    Parameters
    ----------
    N : float
        Total normal load (N), >= 0.
    L : float or None, optional
        Contact length (m), > 0.  Default None: the element binds the load to its bar's length
        with :meth:`on`.

    Raises
    ------
    ValueError
        If ``N`` < 0 or ``L`` <= 0 (or either is not finite), naming the parameter and value.

    See Also
    --------
    QuadraticLoad : Eq. 29, the paper's non-uniform loads.

    Notes
    -----
    Besides ``q(x)`` (N/m), a load gives the running integrals of Eq. 15 in closed form,
    ``I1(x) = int_0^x q`` (N) and ``I2(x) = int_0^x I1`` (N m), so that ``Q'(x) = mu I1/(EA)``
    and ``Q(x) = mu I2/(EA)``.

    Examples
    --------
    >>> from contact_models import UniformLoad
    >>> load = UniformLoad(N=100.0).on(0.05)
    >>> float(load.q(0.02)), float(load.I1(0.05)), float(load.I2(0.05))   # N/m, N, N m
    (2000.0, 100.0, 2.5)
    """

    N: float
    L: float | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "N", nonnegative("N", self.N))
        if self.L is not None:
            object.__setattr__(self, "L", positive("L", self.L))

    def q(self, x: ArrayLike) -> NDArray[Any]:
        return self.N / self._length() + 0.0 * np.asarray(x)

    def dq(self, x: ArrayLike) -> NDArray[Any]:
        return 0.0 * np.asarray(x)

    def I1(self, x: ArrayLike) -> NDArray[Any]:
        return self.N / self._length() * np.asarray(x)

    def I2(self, x: ArrayLike) -> NDArray[Any]:
        x = np.asarray(x)
        return 0.5 * self.N / self._length() * x * x


@dataclass(frozen=True)
class QuadraticLoad(_Load):
    """Eq. 29: q(x) = q0 + q2 * 4 x (x - L) / L^2, total N = (q0 - 2 q2/3) L.

    q2 > 0: concave (largest at the ends, q0 - q2 in the middle; three regions);
    q2 < 0: convex, hump-shaped (two regions).  q must be >= 0 everywhere.
    ``from_ratio(N, ratio)`` without L keeps (q0 L, q2 L) until :meth:`on` gives L.

    Parameters
    ----------
    q0 : float
        Load per length at the ends x = 0 and x = L (N/m), >= 0.
    q2 : float
        Depth of the parabola (N/m): the load at mid-length is ``q0 - q2`` >= 0.
    L : float or None, optional
        Contact length (m).  Default None: bound to the bar's length by :meth:`on`.

    Raises
    ------
    ValueError
        If ``q0`` < 0, ``q2`` is not finite, ``q2 > q0`` (negative load at mid-length), or
        ``L`` <= 0; the message names the parameter and its value.

    See Also
    --------
    UniformLoad

    Notes
    -----
    The paper's Section 3.3 sets the shape by ``ratio = q0/(q0 - q2)`` (:meth:`from_ratio`):
    ratio > 1 is concave (slip starts inside the bar: :class:`ThreeRegionMicroslip`), ratio < 1
    convex.  With N the total load, ``q0 L = 3 N/(1 + 2/ratio)``.

    References
    ----------
    .. [1] Cigeroglu, Lu & Menq (2006), Eq. 29 and Section 3.3.

    Examples
    --------
    The paper's concave load, ratio 12, 100 N on a 0.05 m contact:

    >>> from contact_models import QuadraticLoad
    >>> load = QuadraticLoad.from_ratio(N=100.0, ratio=12.0).on(0.05)
    >>> round(load.q0, 3), round(load.q2, 3)            # N/m
    (5142.857, 4714.286)
    >>> round(float(load.q(0.025)), 3), round(float(load.I1(0.05)), 9)   # N/m at mid-length, N in all
    (428.571, 100.0)
    """

    q0: float | None
    q2: float | None
    L: float | None = None
    _per_length: tuple | None = field(default=None, repr=False, compare=False)

    def __post_init__(self) -> None:
        if self._per_length is not None:  # from_ratio without a length
            return
        q0 = nonnegative("q0", self.q0)
        q2 = finite("q2", self.q2)
        if q0 - q2 < 0.0:
            raise ValueError(
                "q2 must not exceed q0 (the load q0 - q2 at mid-length would be negative), "
                f"got q0={q0!r}, q2={q2!r}"
            )
        object.__setattr__(self, "q0", q0)
        object.__setattr__(self, "q2", q2)
        if self.L is not None:
            object.__setattr__(self, "L", positive("L", self.L))

    @classmethod
    def from_ratio(cls, N: float, ratio: float, L: float | None = None) -> "QuadraticLoad":
        """Load with q0/(q0 - q2) = ``ratio`` and total ``N``; ``ratio=inf`` unloads mid-length."""
        N = nonnegative("N", N)
        try:
            if isinstance(ratio, (bool, str, bytes)):  # float("12") would read a string: a number only
                raise TypeError
            r = float(ratio)
        except (TypeError, ValueError):
            raise ValueError(f"ratio must be a number, got ratio={ratio!r}") from None
        if not r > 0.0:
            raise ValueError(f"ratio must be > 0 (q0/(q0 - q2) with q >= 0), got ratio={ratio!r}")
        # q0 - q2 = q0/r and N = (q0 - 2 q2/3) L  =>  q0 L = 3 N / (1 + 2/r).
        frac = 0.0 if math.isinf(r) else 1.0 / r  # (q0 - q2)/q0
        q0L = 3.0 * N / (1.0 + 2.0 * frac)
        q2L = q0L * (1.0 - frac)
        if L is None:
            return cls(q0=None, q2=None, L=None, _per_length=(q0L, q2L))
        L = positive("L", L)
        return cls(q0=q0L / L, q2=q2L / L, L=L)

    def on(self, L: float) -> "QuadraticLoad":
        if self._per_length is None:
            return super().on(L)
        L = positive("L", L)
        q0L, q2L = self._per_length
        return QuadraticLoad(q0=q0L / L, q2=q2L / L, L=L)

    @property
    def N(self) -> float:
        if self._per_length is not None:
            q0L, q2L = self._per_length
            return q0L - 2.0 * q2L / 3.0
        return (self.q0 - 2.0 * self.q2 / 3.0) * self._length()

    @property
    def ratio(self) -> float:
        q0, q2 = self._per_length if self._per_length is not None else (self.q0, self.q2)
        return math.inf if q0 == q2 else q0 / (q0 - q2)

    def q(self, x: ArrayLike) -> NDArray[Any]:
        # q0 + q2 4x(x-L)/L^2 written as (q0 - q2) + q2 (2x/L - 1)^2: never below q0 - q2 by rounding
        L = self._length()
        u = 2.0 * np.asarray(x) / L - 1.0
        return (self.q0 - self.q2) + self.q2 * u * u

    def dq(self, x: ArrayLike) -> NDArray[Any]:
        L = self._length()
        return self.q2 * 4.0 * (2.0 * np.asarray(x) - L) / L**2

    def I1(self, x: ArrayLike) -> NDArray[Any]:
        L = self._length()
        x = np.asarray(x)
        return self.q0 * x + 4.0 * self.q2 / L**2 * (x**3 / 3.0 - L * x**2 / 2.0)

    def I2(self, x: ArrayLike) -> NDArray[Any]:
        L = self._length()
        x = np.asarray(x)
        return self.q0 * x**2 / 2.0 + 4.0 * self.q2 / L**2 * (x**4 / 12.0 - L * x**3 / 6.0)


@dataclass(frozen=True)
class FunctionLoad(_Load):
    """A user's normal load q(x) (N/m) given as a function of x (m), e.g. one with several
    minima that gives four or more stick and slip regions.

    Parameters
    ----------
    func : callable
        ``func(x) -> q`` for an array ``x`` in [0, L], vectorised, finite and >= 0.
    L : float, optional
        Contact length (m); set by ``on`` from the bar otherwise.

    Notes
    -----
    Only ``q`` is defined (the all-mode and numerical bars need nothing else; the single-mode
    elements need ``I1``, ``I2`` and refuse this load).  ``N`` is the integral of q over
    [0, L] (Gauss-Legendre, 200 points).

    Examples
    --------
    >>> import numpy as np
    >>> from contact_models import FunctionLoad
    >>> load = FunctionLoad(lambda x: 2000.0 * (1.0 + 0.5 * np.cos(2 * np.pi * x / 0.05)), L=0.05)
    >>> round(load.N, 6)
    100.0
    """

    func: Any
    L: float | None = None

    def __post_init__(self) -> None:
        if not callable(self.func):
            raise ValueError(f"func must be callable, got func={self.func!r}")
        if self.L is not None:
            object.__setattr__(self, "L", positive("L", self.L))
            self._check()

    def _check(self) -> None:
        x = np.linspace(0.0, self._length(), 2001)
        q = self._values(x)
        if q.shape != x.shape or not np.all(np.isfinite(q)):
            raise ValueError(f"func must return finite values of the shape of x, got func={self.func!r}")
        if np.any(q < 0.0):
            i = int(np.argmin(q))
            raise ValueError(f"func must return values >= 0 (a normal load), got func={self.func!r} with "
                             f"q({float(x[i])!r}) = {float(q[i])!r}")

    def q(self, x: ArrayLike) -> NDArray[Any]:
        x = np.asarray(x, dtype=float)
        return self._values(x) + 0.0 * x

    def _values(self, x: NDArray) -> NDArray[np.float64]:
        """``func(x)`` as real numbers: a string, a boolean or a complex value (whose imaginary part a float
        conversion would drop with a ComplexWarning) is refused naming ``func``."""
        out = self.func(x)
        try:
            return number_array("func(x)", out)
        except ValueError:
            raise ValueError(f"func must return real numbers (N/m), got func={self.func!r} returning "
                             f"{shown(out)}") from None

    @property
    def N(self) -> float:
        L = self._length()
        t, w = np.polynomial.legendre.leggauss(200)
        return float(0.5 * L * np.sum(w * self.q(0.5 * L * (t + 1.0))))


@dataclass(frozen=True)
class SampledLoad(_Load):
    """A user's normal load given as samples ``values`` (N/m) at positions ``x`` (m), linearly
    interpolated; ``x`` increasing from 0 to L.

    Parameters
    ----------
    x : array_like
        Sample positions (m), strictly increasing, x[0] = 0, x[-1] = L.
    values : array_like
        q at the samples (N/m), finite and >= 0.
    L : float, optional
        Contact length (m); default x[-1] (must equal it).

    Raises
    ------
    ValueError
        Naming ``x``, ``values`` or ``L`` and what they got.

    Notes
    -----
    ``N`` is the trapezoid integral of the samples (exact for the interpolant).  Only ``q`` is
    defined, as for ``FunctionLoad``.

    Examples
    --------
    >>> from contact_models import SampledLoad
    >>> load = SampledLoad(x=[0.0, 0.025, 0.05], values=[3000.0, 1000.0, 3000.0])
    >>> round(load.N, 6), float(load.q(0.0125))
    (100.0, 2000.0)
    """

    x: Any
    values: Any
    L: float | None = None

    def __post_init__(self) -> None:
        try:  # numbers only: a string ("0.05") or a boolean, which a float conversion would read, is refused
            x = np.array(number_array("x", self.x))
            v = np.array(number_array("values", self.values))
        except ValueError:
            raise ValueError(f"x and values must be arrays of numbers, got x={self.x!r}, values={self.values!r}") from None
        if x.ndim != 1 or x.size < 2 or v.shape != x.shape:
            raise ValueError(f"x and values must be 1-d of one length >= 2, got x={self.x!r}, values={self.values!r}")
        if not np.all(np.isfinite(x)) or np.any(np.diff(x) <= 0) or x[0] != 0.0:
            raise ValueError(f"x must be finite, increasing and start at 0, got x={self.x!r}")
        if not np.all(np.isfinite(v)):
            raise ValueError(f"values must be finite, got values={self.values!r}")
        if np.any(v < 0):
            raise ValueError(f"values must be >= 0, got values={self.values!r}")
        L = float(x[-1]) if self.L is None else positive("L", self.L)
        if not math.isclose(L, float(x[-1]), rel_tol=1e-12):
            raise ValueError(f"the samples must end at x = L, got x[-1]={x[-1]!r}, L={self.L!r}")
        x.flags.writeable = False
        v.flags.writeable = False
        object.__setattr__(self, "x", x)
        object.__setattr__(self, "values", v)
        object.__setattr__(self, "L", L)

    def q(self, x: ArrayLike) -> NDArray[Any]:
        return np.interp(np.asarray(x, dtype=float), self.x, self.values)

    @property
    def N(self) -> float:
        return float(np.trapezoid(self.values, self.x))
