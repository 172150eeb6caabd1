"""The contact-element interface every model implements.

An element answers the first-harmonic question: for the steady displacement
``x = a sin(theta)``, ``theta = omega t`` at its attachment point, what are

    f_s = (1/pi) * integral_0^{2 pi} f(theta) sin(theta) dtheta   (in phase, "spring")
    f_c = (1/pi) * integral_0^{2 pi} f(theta) cos(theta) dtheta   (quadrature, "damping")

with ``f`` the force the element needs at that point.  ``pi * a * f_c`` is the
energy dissipated per cycle, so a passive element has ``f_c >= 0``.

Public methods validate and broadcast, then call the private ``_fourier`` and
friends on flat float arrays (the scipy ``OdeSolver.step``/``_step_impl`` split).

The contract: everything a solver or a scene reads of an element
------------------------------------------------------------------
A subclass implements ``_fourier_derivatives`` (or ``_fourier``), ``_stuck_stiffness``,
``_slip_amplitude`` and ``_hysteresis``, and may override the documented defaults below.
Nothing else of an element is read by ``hbm``:

===============================  ==========================================================
``frequency_dependent``          class attribute, default True.  False tells the solver that
                                 f_s, f_c do not depend on omega (no omega-derivative taken).
``fourier(a, omega)``            f_s, f_c (N); validated, broadcasting.
``fourier_derivatives(a, omega)``  f_s, f_c, df_s/da, df_c/da; validated, broadcasting.
``fourier_derivatives_unchecked``  the same on flat float64 arrays, no validation: the
                                 solver's fast path (its Newton loop calls it per point).
``stuck_stiffness(omega)``       dynamic stiffness while nothing slips (N/m); k* at 0.
``slip_amplitude(omega)``        a_min (m): the physical amplitude at which slip begins;
                                 0 for an element that slips at any amplitude (Iwan).
``linear_amplitude(omega)``      the amplitude (m) up to which the element is linear, so
                                 that ``f_s + i f_c = (k_s + i k_c) a`` with
                                 ``(k_s, k_c) = linear_coefficients(omega)``; the solver
                                 answers amplitudes up to it without calling ``fourier``.
                                 Default ``slip_amplitude(omega)``; 0 means "never linear".
``linear_coefficients(omega)``   ``(k_s, k_c)`` (N/m) of that linear range; default
                                 ``(stuck_stiffness(omega), 0)``.  An element with damping
                                 while stuck returns its k_c here.
``reference_amplitude(omega)``   an amplitude (m) at which the element is clearly
                                 nonlinear: the unit of amplitude sweeps and of property
                                 tests.  Default ``slip_amplitude(omega)``; an element with
                                 a_min = 0 must override it.
``hysteresis(a, omega)``         one closed loop (x, f) of the steady response.
===============================  ==========================================================
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from typing import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._validation import nonnegative, nonnegative_array, positive

#: Default relative tolerance of ``fourier`` on f_s and f_c.
DEFAULT_RTOL = 1e-6

#: Relative step of the central difference used by the default ``fourier_derivatives``.
FD_REL_STEP = 1e-6


class ContactElement(ABC):
    """Abstract contact element: f_s, f_c as functions of amplitude and frequency.

    For the steady displacement ``x = a sin(theta)``, ``theta = omega t``, at its attachment
    point, an element gives the first-harmonic coefficients of the force ``f`` it needs there,

    .. math::

        f_s = \\frac{1}{\\pi} \\int_0^{2\\pi} f \\sin\\theta \\, d\\theta, \\qquad
        f_c = \\frac{1}{\\pi} \\int_0^{2\\pi} f \\cos\\theta \\, d\\theta
        \\quad \\text{(N)},

    in phase ("spring") and in quadrature ("damping"); ``pi a f_c`` is the energy dissipated per
    cycle, so a passive element has ``f_c >= 0``.

    Notes
    -----
    A subclass implements ``_fourier_derivatives`` (or ``_fourier``), ``_stuck_stiffness``,
    ``_slip_amplitude`` and ``_hysteresis``; the public methods validate and broadcast, then
    call them on flat float arrays.  What a solver or a scene reads of an element (and nothing
    else): :attr:`frequency_dependent`, :meth:`fourier`, :meth:`fourier_derivatives`,
    :meth:`fourier_derivatives_unchecked`, :meth:`stuck_stiffness`, :meth:`slip_amplitude`,
    :meth:`linear_amplitude`, :meth:`linear_coefficients`, :meth:`reference_amplitude` and
    :meth:`hysteresis`; the module docstring of ``contact_models.base`` states each default.

    Examples
    --------
    >>> from contact_models import Macroslip
    >>> jen = Macroslip(stiffness=2.0, slip_force=1.0)
    >>> jen.linear_amplitude(), jen.linear_coefficients()
    (0.5, (2.0, 0.0))
    """

    #: True when f_s, f_c depend on omega; False lets the solver skip the omega-derivative.
    frequency_dependent: bool = True

    # ------------------------------------------------------------------ public
    def fourier(self, a: ArrayLike, omega: ArrayLike = 0.0, *,
                rtol: float = DEFAULT_RTOL) -> tuple[float | NDArray, float | NDArray]:
        """First-harmonic coefficients ``(f_s, f_c)`` in N for amplitude ``a`` (m) and ``omega`` (rad/s).

        ``a`` and ``omega`` broadcast against each other; both must be finite and >= 0.
        ``rtol`` is the relative accuracy asked of f_s and f_c.

        Parameters
        ----------
        a : array_like
            Amplitude of the displacement ``x = a sin(theta)`` (m), finite and >= 0.
        omega : array_like, optional
            Frequency (rad/s), finite and >= 0; broadcasts against ``a``.  Default 0.
        rtol : float, optional
            Relative accuracy asked of f_s and f_c, > 0.  Default 1e-6.

        Returns
        -------
        f_s, f_c : float or ndarray
            In-phase and quadrature coefficients (N), of the broadcast shape of ``a`` and
            ``omega`` (floats for scalar input).

        Raises
        ------
        ValueError
            If ``a`` or ``omega`` is negative or not finite, or ``rtol`` <= 0, naming it.

        Examples
        --------
        The Jenkins element against its closed form
        ``f_c = (4 F_s/pi)(1 - F_s/(k a))`` past slip:

        >>> import math
        >>> from contact_models import Macroslip
        >>> jen = Macroslip(stiffness=1.0e7, slip_force=10.0)
        >>> f_s, f_c = jen.fourier(2.0e-6)
        >>> round(float(f_c), 9) == round(4 * 10.0 / math.pi * (1 - 10.0 / (1.0e7 * 2.0e-6)), 9)
        True
        >>> jen.fourier([0.5e-6, 1.0e-6], 0.0)[1]          # stuck up to a_min = 1e-6 m: no dissipation
        array([0., 0.])
        """
        a_b, w_b, shape = self._prepare(a, omega)
        rtol = positive("rtol", rtol)
        fs, fc = self._fourier(a_b, w_b, rtol)
        return _shaped(fs, shape), _shaped(fc, shape)

    def fourier_derivatives(self, a: ArrayLike, omega: ArrayLike = 0.0, *,
                            rtol: float = DEFAULT_RTOL) -> tuple[float | NDArray, ...]:
        """``(f_s, f_c, df_s/da, df_c/da)``, broadcasting like :meth:`fourier`.

        Elements override ``_fourier_derivatives`` with analytic derivatives; the
        fallback (for elements that implement only ``_fourier``) is a central difference
        of relative step ``FD_REL_STEP`` in ``a``.
        """
        a_b, w_b, shape = self._prepare(a, omega)
        rtol = positive("rtol", rtol)
        out = self._fourier_derivatives(a_b, w_b, rtol)
        return tuple(_shaped(v, shape) for v in out)

    def fourier_derivatives_unchecked(self, a: NDArray, omega: NDArray, rtol: float) -> tuple[NDArray, ...]:
        """``(f_s, f_c, df_s/da, df_c/da)`` on flat float64 arrays ``a``, ``omega`` of one size.

        The solver's fast path: no validation and no broadcasting, so the caller guarantees
        finite ``a >= 0``, ``omega >= 0`` and ``rtol > 0``.  Returns four flat arrays.
        """
        return self._fourier_derivatives(a, omega, rtol)

    def linear_amplitude(self, omega: float = 0.0) -> float:
        """Amplitude (m) up to which ``f_s + i f_c = (k_s + i k_c) a`` (see ``linear_coefficients``).

        Default: ``slip_amplitude(omega)``.  0 for an element that is nonlinear at any amplitude.
        """
        return self._linear_amplitude(nonnegative("omega", omega))

    def linear_coefficients(self, omega: float = 0.0) -> tuple[float, float]:
        """``(k_s, k_c)`` (N/m): ``f_s = k_s a``, ``f_c = k_c a`` for ``a <= linear_amplitude(omega)``.

        Default: ``(stuck_stiffness(omega), 0.0)``.
        """
        return self._linear_coefficients(nonnegative("omega", omega))

    def reference_amplitude(self, omega: float = 0.0) -> float:
        """An amplitude (m) at which the element is clearly nonlinear (default ``slip_amplitude``).

        Amplitude sweeps are measured in it, and property tests sample amplitudes around it.
        """
        return self._reference_amplitude(nonnegative("omega", omega))

    def stuck_stiffness(self, omega: float = 0.0) -> float:
        """Dynamic stiffness (N/m) while nothing slips; ``k* = stuck_stiffness(0)``."""
        return self._stuck_stiffness(nonnegative("omega", omega))

    def slip_amplitude(self, omega: float = 0.0) -> float:
        """``a_min`` (m): the amplitude at which slip begins."""
        return self._slip_amplitude(nonnegative("omega", omega))

    def hysteresis(self, a: float, omega: float = 0.0, *, n: int = 401) -> tuple[NDArray, NDArray]:
        """One closed loop ``(x, f)`` of the steady response to ``x = a sin(theta)``.

        ``n`` points, theta from -pi/2 to 3 pi/2 (the loop starts and ends at x = -a).

        Parameters
        ----------
        a : float
            Amplitude (m), >= 0.
        omega : float, optional
            Frequency (rad/s), >= 0.  Default 0.
        n : int, optional
            Number of points, >= 5.  Default 401.

        Returns
        -------
        x, f : ndarray
            Displacement (m) and force (N) along the loop, ``n`` points each.

        Raises
        ------
        ValueError
            If ``a`` or ``omega`` is negative, or ``n`` is not an integer >= 5.

        Examples
        --------
        The loop's area is the energy dissipated per cycle, ``pi a f_c``:

        >>> import numpy as np
        >>> from contact_models import Macroslip
        >>> jen = Macroslip(stiffness=1.0e7, slip_force=10.0)
        >>> x, f = jen.hysteresis(2.0e-6, n=2001)
        >>> area = 0.5 * abs(np.dot(x[:-1], f[1:]) - np.dot(x[1:], f[:-1]))
        >>> round(float(area / (np.pi * 2.0e-6 * jen.fourier(2.0e-6)[1])), 4)
        1.0
        """
        a = nonnegative("a", a)
        omega = nonnegative("omega", omega)
        if int(n) != n or n < 5:
            raise ValueError(f"n must be an integer >= 5, got n={n!r}")
        return self._hysteresis(a, omega, int(n))

    # ----------------------------------------------------------------- private
    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        if (cls._fourier is ContactElement._fourier
                and cls._fourier_derivatives is ContactElement._fourier_derivatives):
            raise TypeError(f"{cls.__name__} must implement _fourier or _fourier_derivatives")

    def _fourier(self, a: np.ndarray, omega: np.ndarray, rtol: float):
        """Flat float arrays in, ``(f_s, f_c)`` flat arrays out.

        Elements with analytic derivatives implement only ``_fourier_derivatives``; the values
        are its first two outputs.  Elements without implement this instead.
        """
        return self._fourier_derivatives(a, omega, rtol)[:2]

    @abstractmethod
    def _stuck_stiffness(self, omega: float) -> float: ...

    @abstractmethod
    def _slip_amplitude(self, omega: float) -> float: ...

    @abstractmethod
    def _hysteresis(self, a: float, omega: float, n: int): ...

    def _linear_amplitude(self, omega: float) -> float:
        return float(self._slip_amplitude(omega))

    def _linear_coefficients(self, omega: float) -> tuple[float, float]:
        return float(self._stuck_stiffness(omega)), 0.0

    def _reference_amplitude(self, omega: float) -> float:
        return float(self._slip_amplitude(omega))

    def _fourier_derivatives(self, a, omega, rtol):
        fs, fc = self._fourier(a, omega, rtol)
        h = FD_REL_STEP * np.maximum(a, 1e-300)
        lo = np.maximum(a - h, 0.0)
        hi = a + h
        fs_hi, fc_hi = self._fourier(hi, omega, rtol)
        fs_lo, fc_lo = self._fourier(lo, omega, rtol)
        return fs, fc, (fs_hi - fs_lo) / (hi - lo), (fc_hi - fc_lo) / (hi - lo)

    @staticmethod
    def _prepare(a, omega):
        a = nonnegative_array("a", a)
        omega = nonnegative_array("omega", omega)
        a_b, w_b = np.broadcast_arrays(a, omega)
        shape = a_b.shape
        return a_b.ravel().astype(float), w_b.ravel().astype(float), shape


def masing_loop(loading: Callable[[NDArray], NDArray], a: float, n: int) -> tuple[NDArray, NDArray]:
    """Closed loop from a loading curve by the Masing rule.

    ``loading(x)`` is the virgin loading curve F(x) for x >= 0 (vectorised).  The
    branch from x = -a upwards is ``-F(a) + 2 F((a + x)/2)``, the branch down from
    x = +a is ``F(a) - 2 F((a - x)/2)``.  Returns ``(x, f)`` for theta from -pi/2
    to 3 pi/2 with ``x = a sin(theta)``.
    """
    theta = np.linspace(-0.5 * np.pi, 1.5 * np.pi, n)
    x = a * np.sin(theta)
    fa = float(np.asarray(loading(np.array([a])))[0])
    up = theta <= 0.5 * np.pi
    f = np.empty_like(x)
    f[up] = -fa + 2.0 * loading(0.5 * (a + x[up]))
    f[~up] = fa - 2.0 * loading(0.5 * (a - x[~up]))
    return x, f


def _shaped(v, shape):
    v = np.asarray(v, dtype=float).reshape(shape)
    return v[()] if v.ndim == 0 else v
