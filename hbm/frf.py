"""Frequency response of the blade with a damper: continuation of the single-harmonic balance.

``frequency_response(blade, element, omega_range=(w0, w1))`` traces the branch of
``hbm.residual.HarmonicBalance`` from ``w0`` to ``w1`` with ``hbm.continuation`` and returns a
:class:`FrequencyResponse`.  The continuation measures arclength in
``(x_c/a, x_s/a, omega/|w1 - w0|)`` at each point (``a`` the current amplitude), so the number
of points depends on the logarithm of the resonant amplification, not on the amplification.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, NamedTuple

import numpy as np

from . import continuation as cont  # the module (hbm.continuation)
from ._validation import count, nonnegative, positive
from .blade import Blade
from .output import write_frf_csv
from .presets import DEFAULT_MAX_STEP, DEFAULT_MAX_STEPS, DEFAULT_MIN_STEP, DEFAULT_RTOL, apply
from .residual import HarmonicBalance

if TYPE_CHECKING:
    from contact_models import ContactElement

#: Newton tolerance on |R|/F (Euclidean, R = (R_c, R_s)) as a fraction of ``rtol``.
NEWTON_TOL_FACTOR = 5e-3
#: The peak is located to this fraction of its bracket times sqrt(rtol) in arclength; the
#: amplitude error is quadratic in that distance.
PEAK_XTOL_FACTOR = 1e-3


class Peak(NamedTuple):
    """The largest first-harmonic amplitude on the branch and its frequency."""

    omega: float
    amplitude: float


class Response(NamedTuple):
    """The single-harmonic response at one frequency (``response_at``)."""

    omega: float
    x_c: float
    x_s: float
    amplitude: float
    phase: float  #: lag of the displacement behind the force, x = a cos(omega t - phase)


class FrequencyResponse:
    """The FRF: arrays along the branch, in continuation order, and how the run went.

    ``omega`` (rad/s), ``amplitude`` (m, first harmonic), ``phase`` (rad, lag of the displacement
    behind the force, ``x = a cos(omega t - phase)``), ``x_c``, ``x_s``, ``residual_norm``
    (|R|/F at each point, R = (R_c, R_s)), ``folds_omega``/``folds_amplitude`` (located turning points),
    ``success``, ``status``, ``message``, counters ``nsteps`` (accepted steps), ``nit`` (Newton
    iterations), ``nfev`` (element evaluations), ``nstuck`` (evaluations answered by the
    stuck stiffness); the counters include the work of :meth:`peak` once it has been called.
    """

    def __init__(self, problem: HarmonicBalance, run: cont.ContinuationResult, *, rtol: float, tol: float,
                 scale: Callable[[np.ndarray], np.ndarray]):
        self._problem = problem
        self._run = run
        self._scale = scale
        self.rtol = rtol
        self.tol = tol
        self.blade = problem.blade
        self.element = problem.element
        xc, xs, w = problem.to_physical(run.y) if len(run.y) else (np.empty(0),) * 3
        self.x_c, self.x_s, self.omega = xc, xs, w
        self.amplitude = np.hypot(xc, xs)
        self.phase = np.arctan2(xs, xc)
        self.residual_norm = run.residual_norm
        fx, fs_, fw = problem.to_physical(run.folds) if len(run.folds) else (np.empty(0),) * 3
        self.folds_omega = fw
        self.folds_amplitude = np.hypot(fx, fs_)
        self.status = run.status
        self.message = run.message
        if not run.success and len(w):
            self.message += f"; the branch stops at omega = {w[-1]:.9g} rad/s, amplitude {self.amplitude[-1]:.6g} m"
        self.nsteps = run.nsteps
        self._nit0 = run.nit
        self._peak = None
        self._peak_nit = 0
        self.peak_refined = False  #: whether peak() located the maximum between samples

    # ------------------------------------------------------------------ counters
    @property
    def success(self) -> bool:
        return self._run.success

    @property
    def nit(self) -> int:
        return self._nit0 + self._peak_nit

    @property
    def nfev(self) -> int:
        return self._problem.nfev

    @property
    def nstuck(self) -> int:
        return self._problem.nstuck

    def __len__(self):
        return len(self.omega)

    def __repr__(self):
        return (f"FrequencyResponse({len(self)} points, omega {self.omega[0]:.6g}..{self.omega[-1]:.6g} rad/s, "
                f"success={self.success}, message={self.message!r})" if len(self) else
                f"FrequencyResponse(0 points, success=False, message={self.message!r})")

    # ------------------------------------------------------------------ peak
    def peak(self) -> Peak:
        """``(omega, amplitude)`` of the largest response, located on the branch.

        Between the neighbours of the largest sampled point the branch is parametrised by its
        chord and the zero of ``d(a^2)/ds = 2 (x_c t_c + x_s t_s)`` (``t`` the tangent, with a
        fresh omega-derivative) is found by Brent's method; every trial point is a converged
        Newton point.  A maximum at an end of the branch is returned as sampled.
        """
        if self._peak is not None:
            return self._peak
        if len(self) == 0:
            raise ValueError("the frequency response has no points")
        i = int(np.argmax(self.amplitude))
        best = Peak(float(self.omega[i]), float(self.amplitude[i]))
        if 0 < i < len(self) - 1:
            pr = self._problem
            pr.fresh_omega_derivative = True
            counter = cont._Count()
            y = self._run.y

            def slope(u, t):  # proportional to d(a^2)/ds along the branch
                return u[0] * t[0] + u[1] * t[1]

            try:
                xtol = PEAK_XTOL_FACTOR * math.sqrt(self.rtol)
                loc = None
                for ja, jb in ((i - 1, i + 1), (i - 1, i), (i, i + 1)):
                    loc = cont.locate(pr, y[ja], y[jb], slope, tol=self.tol, scale=self._scale,
                                      xtol=xtol, count=counter)
                    if loc is not None:
                        break
            finally:
                pr.fresh_omega_derivative = False
                self._peak_nit += counter.nit
            if loc is not None:
                xc, xs, w = pr.to_physical(loc.y)
                a = float(math.hypot(xc, xs))
                if a >= best.amplitude * (1.0 - 10.0 * self.rtol):
                    best = Peak(float(w), a)
                    self.peak_refined = True
        self._peak = best
        return best

    # ------------------------------------------------------------------ output
    def to_csv(self, path: str | Path) -> Path:
        """Write the points as ``hbm.output.FRF_COLUMNS`` (omega, amplitude, phase, x_c, x_s,
        residual, units in the header); returns the path."""
        return write_frf_csv(path, self)

    def plot(self, ax: Any = None, *, label: str | None = None, peak: bool = True, **kwargs: Any) -> Any:
        """Amplitude against omega on ``ax`` (a new figure if None); marks the peak. Returns ax."""
        import matplotlib.pyplot as plt  # only when plotting

        if ax is None:
            _, ax = plt.subplots(figsize=(6.4, 4.2))
        line, = ax.plot(self.omega, self.amplitude, label=label, **kwargs)
        if peak and len(self):
            pk = self.peak()
            ax.plot([pk.omega], [pk.amplitude], "o", color=line.get_color(), ms=4)
        ax.set_xlabel(r"$\omega$ (rad/s)")
        ax.set_ylabel("amplitude (m)")
        return ax


def frequency_response(blade: Blade, element: ContactElement | None = None,
                       omega_range: tuple[float, float] | None = None, *, rtol: float = DEFAULT_RTOL,
                       max_step: float = DEFAULT_MAX_STEP, min_step: float = DEFAULT_MIN_STEP,
                       max_steps: int = DEFAULT_MAX_STEPS, locate_folds: bool = True,
                       on_point: Callable[[float, float, float, float], None] | None = None,
                       accuracy: str | float | None = None, harmonics: int | None = None,
                       n_t: int | None = None, response_dof: int | None = None,
                       stability: bool = True) -> FrequencyResponse:
    """FRF of ``blade`` with the contact element ``element`` (None: the bare blade) over
    ``omega_range = (w0, w1)`` rad/s, traced from ``w0`` to ``w1`` through any folds.

    ``rtol``: relative accuracy; the element is evaluated to ``rtol`` and every point solves
    the balance to ``|R|/F <= NEWTON_TOL_FACTOR * rtol``.  ``max_step``/``min_step``: step
    limits in scaled arclength (module docstring); ``max_steps``: step budget.
    ``on_point(omega, x_c, x_s, residual)``: called with each accepted point and its |R|/F as soon
    as it is accepted, in continuation order (the same points as the result's), so a caller can
    stream them.
    ``accuracy``: "fast", "default", "precise" or an rtol; sets rtol, max_step, min_step and
    max_steps together (``hbm.presets``; not combined with them).

    With an ``hbm.Structure`` first and a sequence of ``hbm.Contact`` second (or a ``Blade``
    with ``harmonics``/``n_t``/``response_dof`` given) this is the multi-harmonic balance
    (``hbm.multiharmonic``): ``harmonics`` H (default: the accuracy preset's), ``n_t`` AFT
    samples per period, ``response_dof`` (default the forced DOF), ``stability`` (Hill's method
    at every point); it returns an ``hbm.mhresult.MultiHarmonicResponse``.
    """
    if not isinstance(blade, Blade) or harmonics is not None or n_t is not None or response_dof is not None:
        from .mhdispatch import structure_response

        return structure_response(blade, element, omega_range, rtol=rtol, max_step=max_step, min_step=min_step,
                                  max_steps=max_steps, locate_folds=locate_folds, on_point=on_point,
                                  accuracy=accuracy, harmonics=harmonics, n_t=n_t, response_dof=response_dof,
                                  stability=stability)
    if not isinstance(blade, Blade):
        raise ValueError(f"blade must be an hbm.Blade, got blade={blade!r}")
    if omega_range is None:
        raise ValueError("omega_range must be given as (w0, w1), got omega_range=None")
    try:
        w0, w1 = omega_range
    except (TypeError, ValueError):
        raise ValueError(f"omega_range must be a pair (w0, w1), got omega_range={omega_range!r}") from None
    w0 = nonnegative("omega_range[0]", w0)
    w1 = nonnegative("omega_range[1]", w1)
    if w0 == w1:
        raise ValueError(f"omega_range must have w0 != w1, got omega_range={omega_range!r}")
    if accuracy is not None:
        rtol, max_step, min_step, max_steps = apply(accuracy, rtol=rtol, max_step=max_step,
                                                    min_step=min_step, max_steps=max_steps)
    rtol = positive("rtol", rtol)
    if rtol >= 0.1:
        raise ValueError(f"rtol must be < 0.1, got rtol={rtol!r}")
    max_step = positive("max_step", max_step)
    min_step = positive("min_step", min_step)
    max_steps = count("max_steps", max_steps)
    if element is not None and not callable(getattr(element, "fourier", None)):
        raise ValueError(f"element must be a contact element (with fourier(a, omega)), got element={element!r}")

    # ---- scales: x by the static deflection, omega by the range width
    k0 = blade.stiffness + _finite_or_zero(element.stuck_stiffness(0.0) if element is not None else 0.0)
    k_ref = k0 if k0 > 0.0 else blade.mass * max(w0, w1) ** 2
    x_ref = blade.force / k_ref
    w_ref = abs(w1 - w0)
    problem = HarmonicBalance(blade, element, rtol=rtol, x_ref=x_ref, omega_ref=w_ref)

    # ---- start: the stuck (linear) solution at w0, corrected by the continuation
    kd = _finite_or_zero(element.stuck_stiffness(w0)) if element is not None else 0.0
    z = blade.force / (blade.stiffness + kd - blade.mass * w0 * w0 + 1j * blade.damping * w0)
    u0 = np.array([z.real / x_ref, -z.imag / x_ref, w0 / w_ref])
    tol = NEWTON_TOL_FACTOR * rtol

    def scale(u):
        a = max(math.hypot(u[0], u[1]), 1e-300)
        return np.array([a, a, 1.0])

    run = cont.continuation(problem, u0, parameter=2, bounds=(min(w0, w1) / w_ref, max(w0, w1) / w_ref),
                            direction=1 if w1 > w0 else -1, max_step=max_step, min_step=min_step,
                            max_steps=max_steps, tol=tol, scale=scale, locate_folds=locate_folds,
                            fold_xtol=PEAK_XTOL_FACTOR * math.sqrt(rtol),
                            on_point=None if on_point is None else _physical(on_point, problem))
    return FrequencyResponse(problem, run, rtol=rtol, tol=tol, scale=scale)


def response_at(blade: Blade, element: ContactElement, omega: float,
                amplitude_bracket: tuple[float, float], *, rtol: float = 1e-8) -> Response:
    """The single-harmonic balance at one frequency ``omega``, for one amplitude in
    ``amplitude_bracket = (a_lo, a_hi)`` (m).

    The balance's modulus gives one equation in the amplitude a,
    ``|(k - m omega^2 + i c omega) a + f_s(a) + i f_c(a)| = F``, solved by Brent's method in the
    bracket (it must change sign there: near a fold there are several solutions, and the bracket
    picks one); its argument gives the phase.  ``rtol`` is passed to the element and is the
    relative tolerance on a.  For any contact element, including ``NumericalMicroslip``, whose
    f_s, f_c carry no derivatives: the check of a time integration at a few frequencies
    (``docs/validation.md``), where a continuation would cost too much.
    """
    from scipy.optimize import brentq

    if not isinstance(blade, Blade):
        raise ValueError(f"blade must be an hbm.Blade, got blade={blade!r}")
    if element is None or not callable(getattr(element, "fourier", None)):
        raise ValueError(f"element must be a contact element (with fourier(a, omega)), got element={element!r}")
    omega = nonnegative("omega", omega)
    rtol = positive("rtol", rtol)
    try:
        lo, hi = (positive("amplitude_bracket", v) for v in amplitude_bracket)
    except (TypeError, ValueError):
        raise ValueError(f"amplitude_bracket must be a pair 0 < a_lo < a_hi, got "
                         f"amplitude_bracket={amplitude_bracket!r}") from None
    if not lo < hi:
        raise ValueError(f"amplitude_bracket must have a_lo < a_hi, got amplitude_bracket={amplitude_bracket!r}")
    lin = complex(blade.stiffness - blade.mass * omega * omega, blade.damping * omega)

    def force(a):
        fs, fc = element.fourier(a, omega, rtol=rtol)
        return lin * a + complex(float(fs), float(fc))

    g_lo, g_hi = abs(force(lo)) - blade.force, abs(force(hi)) - blade.force
    if g_lo * g_hi > 0.0:
        raise ValueError(f"amplitude_bracket={amplitude_bracket!r} does not bracket a solution at omega={omega!r}: "
                         f"|balance force| - F is {g_lo:.4g} N and {g_hi:.4g} N at its ends")
    a = brentq(lambda a: abs(force(a)) - blade.force, lo, hi, xtol=1e-300,
               rtol=max(rtol, 4.0 * np.finfo(float).eps))  # brentq's floor
    z = blade.force * a / force(a)  # x_c - i x_s = F / (k - m w^2 + p + i (c w + q))
    return Response(omega=omega, x_c=z.real, x_s=-z.imag, amplitude=math.hypot(z.real, z.imag),
                    phase=math.atan2(-z.imag, z.real))


def _physical(on_point, problem):
    """``on_point(omega, x_c, x_s, residual)`` for the continuation's ``on_point(y, rnorm)`` in scaled unknowns."""

    def report(y, rnorm):
        xc, xs, w = problem.to_physical(y)
        on_point(float(w), float(xc), float(xs), float(rnorm))

    return report


def _finite_or_zero(k) -> float:
    """A stuck stiffness for scales and the first guess (a rigid stuck contact gives none: 0)."""
    k = float(k)
    return k if math.isfinite(k) else 0.0
