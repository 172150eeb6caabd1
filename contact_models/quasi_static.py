"""Wrappers that switch one physical effect of a contact element off.

``QuasiStatic(element)``: the element without damper inertia.  It answers every question at
omega = 0 whatever omega is asked: the quasi-static limit of the dynamic bar (Eq. 12 with
alpha = 0, gamma = lambda), which holds while the excitation frequency is far below the bar's
omega_c (``docs/scenes.md``, "Effects").  Its force is never evaluated at another frequency, so
a sweep computes no dynamic coefficient (alpha, gamma(omega), the dynamic stiffness K*(omega));
``calls`` counts the evaluations passed on.  Because the microslip elements cache their loading
path per frequency, a quasi-static sweep builds one path in all.  Only ``model_error`` (the error
estimate's model source) evaluates the wrapped element at omega: how far the quasi-static limit is
from it there.

``StuckContact(element)``: the element held stuck, a linear spring of the element's stuck
(dynamic) stiffness: ``f_s = K*(omega) a``, ``f_c = 0`` at every amplitude.  It is the
element's exact response while ``a <= slip_amplitude(omega)``; a scene uses it when the
sweep never reaches the slip amplitude (``docs/scenes.md``).

``QuasiStatic`` has a time law when the wrapped element has a loading curve (the microslip bars,
Jenkins, the point contact): the quasi-static bar obeys Masing's rules with memory, so its
force for any periodic displacement with several reversals follows from the loading curve at
omega = 0 (``periodic_force``, ``harmonic_force``; ``contact_models.numerics.masing``), checked
against the discretised quasi-static bar with return mapping (``tests/test_time_laws.py``).
The slope of the loading curve is the wrapped element's ``_loading_slope`` where it has one,
else a central difference of relative step ``SLOPE_FD_STEP`` (the microslip curves are smooth
between their region changes; about 1e-9 relative error).
"""

from __future__ import annotations

import functools
import math
import warnings

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .accuracy import AccuracyWarning
from .numerics.checks import finite_array, nonnegative
from .base import ContactElement

#: Relative step (of x + a_min) of the central difference giving a loading curve's slope.
SLOPE_FD_STEP = 1e-6


class _OfTheWrapped:
    """A method of ``QuasiStatic`` that exists where the wrapped element has the method of that name: on one
    without it (a Jenkins element has no ``slip_stiffness``) the attribute is absent, so ``hasattr`` and
    ``getattr(..., None)`` say so (``PointContact.fit`` then names the missing method) instead of a call
    failing inside on the wrapped element."""

    def __init__(self, method):
        self.method, self.__doc__ = method, method.__doc__

    def __set_name__(self, owner, name):
        self.name = name

    def __get__(self, obj, owner=None):
        if obj is None:
            return self.method
        if not callable(getattr(obj.element, self.name, None)):
            raise AttributeError(f"{obj!r} has no {self.name}: the wrapped {type(obj.element).__name__} has none",
                                 name=self.name, obj=obj)
        return self.method.__get__(obj, owner)


class QuasiStatic(ContactElement):
    """``element`` evaluated at omega = 0 for every omega (no damper inertia).

    ``calls`` counts the evaluations of the wrapped element (all at omega = 0).

    Parameters
    ----------
    element : ContactElement
        The element to evaluate quasi-statically.

    Raises
    ------
    ValueError
        If ``element`` is not a :class:`ContactElement`.

    Notes
    -----
    A scene whose damper inertia is off wraps its element in this: ``frequency_dependent`` is
    False, so the balance takes no omega-derivative, and no dynamic coefficient of the bar
    (alpha, gamma(omega), K*(omega)) is ever evaluated.  Valid while the stuck bar's
    ``|K*(omega)/k* - 1|`` is small over the sweep (``docs/scenes.md``, effects).

    Examples
    --------
    >>> from contact_models import Bar, UniformLoad, TwoRegionMicroslip, QuasiStatic
    >>> bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    >>> two = TwoRegionMicroslip(bar, UniformLoad(N=100.0))
    >>> qs = QuasiStatic(two)
    >>> qs.fourier(1.5e-6, 0.3 * bar.omega_c) == two.fourier(1.5e-6, 0.0)
    True
    >>> qs.frequency_dependent, qs.calls
    (False, 1)
    """

    frequency_dependent = False

    def __init__(self, element: ContactElement) -> None:
        if not isinstance(element, ContactElement):
            raise ValueError(f"element must be a contact_models.ContactElement, got element={element!r}")
        self.element = element
        self.calls = 0

    def __repr__(self) -> str:
        return f"QuasiStatic({self.element!r})"

    @functools.cached_property
    def has_time_law(self) -> bool:
        """True when the wrapped element's virgin loading curve at omega = 0 is a time law by Masing's rules with
        memory: it has a loading curve (a wrapped ``QuasiStatic`` has one only where its own element has) and a
        finite stuck stiffness (the rigid slider's curve is a step).  Read once: every evaluation at H = 1 asks it
        (``exact_describing_function``)."""
        el = self.element
        return callable(getattr(el, "loading_curve", None)) and math.isfinite(float(el.stuck_stiffness(0.0)))

    def _loading_slope(self, x, omega):
        el = self.element
        if type(el)._loading_slope is not ContactElement._loading_slope:
            return el._loading_slope(x, 0.0)
        x = np.asarray(x, dtype=float)
        h = SLOPE_FD_STEP * (np.abs(x) + float(el.slip_amplitude(0.0)))
        self.calls += 1
        F = el.loading_curve(np.concatenate([x + h, x - h]), 0.0)
        return (F[:x.size] - F[x.size:]) / (2.0 * h)

    def _masing_centre_stiffness(self, omega):
        return self.element._masing_centre_stiffness(0.0)

    # ------------------------------------------------------------ extras of the wrapped element (where it has them)
    @_OfTheWrapped
    def slip_stiffness(self, omega: float = 0.0) -> float:
        """The wrapped element's fully slipping stiffness at omega = 0."""
        self._check(omega)
        self.calls += 1
        return self.element.slip_stiffness(0.0)

    @_OfTheWrapped
    def gross_slip_amplitude(self, omega: float = 0.0) -> float:
        """The wrapped element's gross-slip amplitude at omega = 0."""
        self._check(omega)
        self.calls += 1
        return self.element.gross_slip_amplitude(0.0)

    @_OfTheWrapped
    def loading_curve(self, x: ArrayLike, omega: float = 0.0) -> NDArray[np.float64]:
        """The wrapped element's virgin loading curve at omega = 0."""
        x = finite_array("x", x)
        self._check(omega)
        self.calls += 1
        return self.element.loading_curve(x, 0.0)

    # ------------------------------------------------------------ interface
    def _stuck_stiffness(self, omega):
        self.calls += 1
        return float(self.element.stuck_stiffness(0.0))

    def _slip_amplitude(self, omega):
        self.calls += 1
        return float(self.element.slip_amplitude(0.0))

    def _hysteresis(self, a, omega, n):
        self.calls += 1
        return self.element.hysteresis(a, 0.0, n=n)

    def _linear_amplitude(self, omega):
        self.calls += 1
        return float(self.element.linear_amplitude(0.0))

    def _linear_coefficients(self, omega):
        self.calls += 1
        return self.element.linear_coefficients(0.0)

    def _reference_amplitude(self, omega):
        self.calls += 1
        return float(self.element.reference_amplitude(0.0))

    def _fourier(self, a, omega, rtol):
        self.calls += 1
        return self.element._fourier(a, np.zeros_like(omega), rtol)

    def _model_error(self, a, omega):
        """``(e_s, e_c)`` against the physical contact, through the wrapped element (``_through``): the inertia
        left out, ``|F(a, 0) - F(a, omega)|``, plus the wrapped element's own model error at omega.  Below slip
        this is ``|K*(omega)/k* - 1|``, the criterion of a scene's inertia effect."""
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", AccuracyWarning)
            return _through(self.element, a, omega, self.element.fourier(a, 0.0))

    def _fourier_derivatives(self, a, omega, rtol):
        self.calls += 1
        return self.element.fourier_derivatives_unchecked(a, np.zeros_like(omega), rtol)

    def _refined_model(self):
        """What the quasi-static limit stands for, its inertia on: the wrapped element's refined model where it
        has one (a single-mode bar's: the bar with every mode, which has a time law as this one does), else the
        wrapped element; ``model="auto"`` takes it where this one is off."""
        return self.element.refined_model() or self.element

    @staticmethod
    def _check(omega):
        nonnegative("omega", omega)


class StuckContact(ContactElement):
    """``element`` held stuck: a linear spring of stiffness ``element.stuck_stiffness(omega)``.

    ``slip_amplitude`` is infinite (it never slips); ``f_c = 0``.
    """

    def __init__(self, element: ContactElement) -> None:
        if not isinstance(element, ContactElement):
            raise ValueError(f"element must be a contact_models.ContactElement, got element={element!r}")
        self.element = element
        self.frequency_dependent = bool(getattr(element, "frequency_dependent", True))

    def __repr__(self) -> str:
        return f"StuckContact({self.element!r})"

    def _stuck_stiffness(self, omega):
        return float(self.element.stuck_stiffness(omega))

    def _slip_amplitude(self, omega):
        return math.inf

    def _reference_amplitude(self, omega):
        return float(self.element.reference_amplitude(omega))

    def _hysteresis(self, a, omega, n):
        theta = np.linspace(-0.5 * np.pi, 1.5 * np.pi, n)
        x = a * np.sin(theta)
        return x, self._stuck_stiffness(omega) * x

    def _fourier_derivatives(self, a, omega, rtol):
        K = np.array([self._stuck_stiffness(float(w)) for w in omega]) if omega.size else np.empty(0)
        zero = np.zeros_like(a)
        return K * a, zero, K, zero.copy()

    def _model_error(self, a, omega):
        """``(e_s, e_c)`` against the physical contact, through the wrapped element (``_through``): 0 up to its
        linear amplitude, where the stuck spring is its exact answer (a scene holds a damper stuck only where
        the sweep stays there, and then evaluates nothing more); above, the slip the spring leaves out."""
        el = self.element
        e_s, e_c = np.zeros(a.shape), np.zeros(a.shape)
        slips = np.array([ai > el.linear_amplitude(float(wi)) for ai, wi in zip(a, omega)], dtype=bool)
        if slips.any():
            a_s, w_s = a[slips], omega[slips]
            K = np.array([self._stuck_stiffness(float(w)) for w in w_s])
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", AccuracyWarning)
                e_s[slips], e_c[slips] = _through(el, a_s, w_s, (K * a_s, np.zeros(a_s.shape)))
        return e_s, e_c


def _through(el: ContactElement, a: NDArray, omega: NDArray, f: tuple) -> tuple[NDArray, NDArray]:
    """``(e_s, e_c)`` of a wrapper whose answer is ``f = (f_s, f_c)`` against the physical contact the wrapped
    ``el`` stands for, by the triangle inequality: ``|f - F_el(a, omega)| / scale + el.model_error``, each
    relative to ``max(|F_el|, 0.01 k* a)`` of its component (``ContactElement.model_error``).  Where ``el`` has
    no finite answer at omega (a resonance of the stuck bar) the error is unknown: inf."""
    fs, fc = el.fourier(a, omega)
    e_s, e_c = el.model_error(a, omega, parts=True)
    floor = 0.01 * float(el.stuck_stiffness(0.0)) * a
    out = []
    with np.errstate(invalid="ignore", divide="ignore"):
        for g, F, e in ((f[0], fs, e_s), (f[1], fc, e_c)):
            scale = np.maximum(np.abs(F), floor)
            rel = np.where(a > 0.0, np.abs(g - F) / np.where(scale > 0.0, scale, 1.0), 0.0) + e
            out.append(np.where(np.isfinite(rel), rel, math.inf))
    return out[0], out[1]


__all__ = ["QuasiStatic", "StuckContact"]
