"""A normal preload that follows the rotation: ``CentrifugalLoad`` and the element that reads it.

Under engine-order excitation the drive frequency is ``omega = EO Omega`` (Omega the rotation
speed), so a damper pressed on its platforms by its own centrifugal force carries the preload

    N0(omega) = m_d r Omega^2 = m_d r (omega / EO)^2

(``m_d`` the damper's mass, ``r`` its radius): the preload grows along a frequency sweep.
:class:`CentrifugalLoad` is that law; :class:`RotatingPreload` makes any element whose preload is
one number (``Contact2D``'s ``n0``, a Jenkins slip force ``mu N``, a microslip bar's load ``N``)
an element whose preload is read at each frequency: ``RotatingPreload(lambda N: Contact2D(kt, kn,
mu, n0=N), CentrifugalLoad(mass, radius, engine_order))``.  Every hook answers with the element
built at ``N0(omega)``; the harmonic force's omega-derivative carries the load's, ``dF/dN dN/domega``
(a forward difference in N), which the continuation's tangent needs.
"""

from __future__ import annotations

import math
from typing import Any, Callable

import numpy as np
from numpy.typing import NDArray

from .numerics.checks import nonnegative, positive, shown
from .base import KIND_ATTRIBUTES, ContactElement

#: Relative step of the forward difference of the force in the preload.
LOAD_FD_STEP = 1e-6
#: Elements kept built, by preload (the balance asks at a handful of frequencies at a time).
KEEP_BUILT = 16
#: A zero preload (the disk at rest) is built as this fraction of a preload built before: an element
#: refuses a zero preload, and at rest only its stuck stiffness is asked for (the balance's scales).
ZERO_LOAD = 1e-9


class CentrifugalLoad:
    """``N0(omega) = mass radius (omega / engine_order)^2`` (N): the centrifugal preload of a damper of
    ``mass`` (kg) at ``radius`` (m) on a disk whose drive is engine order ``engine_order`` of the rotation.

    Parameters
    ----------
    mass : float
        The damper's mass (kg), > 0.
    radius : float
        Its radius (m), > 0.
    engine_order : int
        EO >= 1: ``omega = EO Omega``.

    Examples
    --------
    >>> load = CentrifugalLoad(mass=0.01, radius=0.3, engine_order=4)
    >>> round(load(4.0e3), 9), round(load.derivative(4.0e3), 12)   # m r (w/EO)^2, 2 m r w / EO^2
    (3000.0, 1.5)
    """

    def __init__(self, mass: float, radius: float, engine_order: int) -> None:
        self.mass = positive("mass", mass)
        self.radius = positive("radius", radius)
        if isinstance(engine_order, bool) or not isinstance(engine_order, (int, np.integer)) or engine_order < 1:
            raise ValueError(f"engine_order must be an integer >= 1 (omega = EO Omega), got engine_order={engine_order!r}")
        self.engine_order = int(engine_order)
        if not math.isfinite(self.mass * self.radius):
            raise ValueError(f"mass and radius must give a finite mass * radius, got mass={mass!r}, radius={radius!r}")

    def __call__(self, omega: float) -> float:
        """The preload (N) at the drive frequency ``omega`` (rad/s)."""
        what = "the preload mass radius (omega / engine_order)^2"
        try:
            value = self.mass * self.radius * (nonnegative("omega", omega) / self.engine_order) ** 2
        except OverflowError:  # float ** raises where * gives inf
            value = math.inf
        return self._finite(what, omega, value)

    def derivative(self, omega: float) -> float:
        """``dN0/domega`` (N s/rad)."""
        return self._finite("dN0/domega", omega,
                            2.0 * self.mass * self.radius * nonnegative("omega", omega) / self.engine_order**2)

    @staticmethod
    def _finite(what: str, omega: float, value: float) -> float:
        """``value``, or a ValueError naming ``omega`` where it left double precision (an inf preload
        would reach the element as a NaN force)."""
        if not math.isfinite(value):
            raise ValueError(f"omega={omega!r} is too large for this load: {what} is not finite in double precision")
        return value

    def speed(self, omega: float) -> float:
        """The rotation speed ``Omega = omega / EO`` (rad/s)."""
        return nonnegative("omega", omega) / self.engine_order

    def __repr__(self) -> str:
        return f"CentrifugalLoad(mass={self.mass!r}, radius={self.radius!r}, engine_order={self.engine_order})"


class RotatingPreload(ContactElement):
    """An element whose normal preload follows the drive frequency: ``build(load(omega))`` at each omega.

    Parameters
    ----------
    build : callable
        ``build(N) -> ContactElement``: the element at preload N (N); every element it builds must
        have the same kind (components, time law).
    load : CentrifugalLoad or callable
        ``load(omega) -> N`` (N), >= 0; a :class:`CentrifugalLoad` also gives its derivative.
    omega_ref : float, optional
        A frequency (rad/s) where ``load`` is positive, for the element's kind.  Default: the omega
        where a :class:`CentrifugalLoad` is 1 N, else 1.

    Notes
    -----
    Every hook (``fourier``, ``harmonic_force``, ``stuck_stiffness``, ``slip_amplitude``,
    ``linear_coefficients``, ``hysteresis``, ``model_error``) answers with ``build(load(omega))``, so the
    element is exactly the given one at each frequency; ``harmonic_force``'s omega-derivative adds
    ``dF/dN dN/domega`` (forward difference of relative step ``LOAD_FD_STEP`` in N).  The describing
    function's omega-derivative is the balance's own forward difference (``frequency_dependent``).

    Examples
    --------
    >>> from contact_models import Contact2D
    >>> load = CentrifugalLoad(mass=0.01, radius=0.3, engine_order=4)
    >>> el = RotatingPreload(lambda N: Contact2D(kt=1e7, kn=1e7, mu=0.3, n0=N), load)
    >>> el.at(4.0e3).n0                     # the preload at omega = 4000 rad/s
    3000.0
    """

    frequency_dependent = True

    def __init__(self, build: Callable[[float], ContactElement], load: Any, *, omega_ref: float | None = None) -> None:
        if not callable(build):
            raise ValueError(f"build must be a callable N -> contact element, got build={build!r}")
        if not callable(load):
            raise ValueError(f"load must be a callable omega -> N (a CentrifugalLoad), got load={load!r}")
        self.build, self.load = build, load
        if omega_ref is None:
            omega_ref = (load.engine_order / math.sqrt(load.mass * load.radius)
                         if isinstance(load, CentrifugalLoad) else 1.0)
        self.omega_ref = positive("omega_ref", omega_ref)
        self._built: dict[float, ContactElement] = {}
        proto = self.at(self.omega_ref)
        for name in KIND_ATTRIBUTES:  # the kind of every element built (the same for every preload)
            setattr(self, name, getattr(proto, name))
        self._exact_df = proto.exact_describing_function

    def __repr__(self) -> str:
        return f"RotatingPreload({type(self.at(self.omega_ref)).__name__}, {self.load!r})"

    @property
    def exact_describing_function(self) -> bool:
        """As the elements it builds."""
        return self._exact_df

    def at(self, omega: float) -> ContactElement:
        """The element at the preload of ``omega`` (rad/s)."""
        return self._at_load(self._preload(nonnegative("omega", omega)))

    def _preload(self, omega: float) -> float:
        """``load(omega)`` as a float: a real number, else a ValueError naming ``load`` and what it returned (a
        string, None or an array failed in ``float()``; a boolean was taken as 1 N)."""
        N = self.load(omega)
        if not isinstance(N, (bool, np.bool_, str, bytes)) and np.ndim(N) == 0 and not np.iscomplexobj(N):
            try:
                return float(N)
            except (TypeError, ValueError):
                pass
        raise ValueError(f"load must return a preload (N), a real number, got load({omega!r}) = {shown(N)}")

    def _at_load(self, N: float) -> ContactElement:
        if N == 0.0 and self._built:  # at rest (omega = 0, the balance's static scale): the smallest preload
            N = ZERO_LOAD * max(self._built)  # the elements refuse a zero one
        el = self._built.get(N)
        if el is None:
            if not (math.isfinite(N) and N >= 0.0):
                raise ValueError(f"load must give a preload >= 0, got N={N!r}")
            el = self.build(N)
            if not isinstance(el, ContactElement):
                raise ValueError(f"build must return a contact element, got {el!r} for N={N!r}")
            if len(self._built) >= KEEP_BUILT:
                self._built.pop(next(iter(self._built)))
            self._built[N] = el
        return el

    def _dload(self, omega: float) -> float:
        d = getattr(self.load, "derivative", None)
        if callable(d):
            return float(d(omega))
        h = 1e-6 * max(omega, self.omega_ref)
        return (self._preload(omega + h) - self._preload(max(omega - h, 0.0))) / (omega + h - max(omega - h, 0.0))

    # ------------------------------------------------------------------ hooks: the element at N0(omega)
    def _fourier_derivatives(self, a: NDArray, omega: NDArray, rtol: float):
        out = [np.empty(a.size) for _ in range(4)]
        for w in np.unique(omega):
            m = omega == w
            for o, v in zip(out, self.at(float(w)).fourier_derivatives_unchecked(a[m], omega[m], rtol)):
                o[m] = v
        return tuple(out)

    def _harmonic_force(self, X: NDArray, omega: float, n_t: int, rtol: float, **kw: Any):
        N = self._preload(omega)
        F, J, Fw = self._at_load(N).harmonic_force_unchecked(X, omega, n_t, rtol, **kw)
        dN = self._dload(omega)
        if dN != 0.0:  # it enters the Jacobian's omega column (the tangent), never the residual
            h = LOAD_FD_STEP * max(N, 1.0)
            F_hi = self._at_load(N + h).harmonic_force_unchecked(X, omega, n_t, rtol, **kw)[0]
            Fw = Fw + (F_hi - F) / h * dN
        return F, J, Fw

    def _periodic_force(self, x: NDArray, omega: float):
        return self.at(omega).periodic_force(x, omega)

    def _model_error(self, a: np.ndarray, omega: np.ndarray):
        if type(self.at(self.omega_ref))._model_error is ContactElement._model_error:  # exact for what it models
            return np.zeros(a.size), np.zeros(a.size)
        parts = [self.at(float(w)).model_error(a[omega == w], omega[omega == w], parts=True) for w in np.unique(omega)]
        e_s, e_c = np.empty(a.size), np.empty(a.size)
        for w, (s, c) in zip(np.unique(omega), parts):
            e_s[omega == w], e_c[omega == w] = s, c
        return e_s, e_c

    def _stuck_stiffness(self, omega: float) -> float:
        return self.at(omega).stuck_stiffness(omega)

    def _slip_amplitude(self, omega: float) -> float:
        return self.at(omega).slip_amplitude(omega)

    def _linear_amplitude(self, omega: float) -> float:
        return self.at(omega).linear_amplitude(omega)

    def _linear_coefficients(self, omega: float) -> tuple[float, float]:
        return self.at(omega).linear_coefficients(omega)

    def _reference_amplitude(self, omega: float) -> float:
        return self.at(omega).reference_amplitude(omega)

    def _hysteresis(self, a: float, omega: float, n: int):
        return self.at(omega).hysteresis(a, omega, n=n)


__all__ = ["CentrifugalLoad", "RotatingPreload"]
