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
from ._validation import count, nonnegative, omega_range_pair, positive
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
    """The largest first-harmonic amplitude on the branch and its frequency.

    Attributes
    ----------
    omega : float
        Frequency (rad/s).
    amplitude : float
        First-harmonic amplitude (m).
    """

    omega: float
    amplitude: float


class Response(NamedTuple):
    """The single-harmonic response at one frequency (``response_at``).

    Attributes
    ----------
    omega : float
        Excitation frequency (rad/s).
    x_c, x_s : float
        Cosine and sine coefficients of the displacement (m):
        ``x = x_c cos(omega t) + x_s sin(omega t)``.
    amplitude : float
        First-harmonic amplitude ``hypot(x_c, x_s)`` (m).
    phase : float
        Lag of the displacement behind the force (rad), ``x = amplitude cos(omega t - phase)``.
    """

    omega: float
    x_c: float
    x_s: float
    amplitude: float
    phase: float  #: lag of the displacement behind the force, x = a cos(omega t - phase)


class FrequencyResponse:
    """The FRF: arrays along the branch, in continuation order, and how the run went.

    ``omega`` (rad/s), ``amplitude`` (m, first harmonic), ``phase`` (rad, lag of the displacement
    behind the force, ``x = a cos(omega t - phase)``), ``x_c``, ``x_s``, ``residual_norm``
    (``|R|/F`` at each point, R = (R_c, R_s)), ``folds_omega``/``folds_amplitude`` (located turning points),
    ``success``, ``status``, ``message``, counters ``nsteps`` (accepted steps), ``nit`` (Newton
    iterations), ``nfev`` (element evaluations), ``nstuck`` (evaluations answered by the
    stuck stiffness); the counters include the work of :meth:`peak` once it has been called.

    Made by :func:`frequency_response`, not by hand.

    Attributes
    ----------
    omega, amplitude, phase, x_c, x_s, residual_norm : ndarray
        One value per point along the branch (rad/s, m, rad, m, m, dimensionless).
    folds_omega, folds_amplitude : ndarray
        The located turning points of the branch (rad/s, m).
    success : bool
        Whether the branch reached the end of ``omega_range``.
    status, message
        How the continuation ended, as a code and in words; on failure the points computed
        before are kept.
    nsteps, nit, nfev, nstuck : int
        Accepted steps, Newton iterations, element evaluations, stuck evaluations.

    Examples
    --------
    >>> from hbm import Blade, frequency_response
    >>> frf = frequency_response(Blade(mass=1.0, stiffness=1.0e4, damping=2.0, force=1.0),
    ...                          omega_range=(90.0, 110.0))
    >>> frf.success, len(frf.omega) == len(frf.amplitude) > 100
    (True, True)
    >>> float(frf.residual_norm.max()) < 1e-6              # |R|/F at every point
    True
    >>> round(float(frf.amplitude.max()), 6)           # largest sampled point, m (peak() refines it)
    0.005
    """

    def __init__(self, problem: HarmonicBalance, run: cont.ContinuationResult, *, rtol: float, tol: float,
                 scale: Callable[[np.ndarray], np.ndarray]) -> None:
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
        self._take_run(run)

    def _take_run(self, run: cont.ContinuationResult) -> None:
        """Status, message (with where a failed branch stops), counters; the peak not yet located."""
        w = self.omega
        self.status = run.status
        self.message = run.message
        if not run.success and len(w):
            self.message += f"; the branch stops at omega = {w[-1]:.9g} rad/s, amplitude {self.amplitude[-1]:.6g} m"
        self.nsteps = run.nsteps
        self._nit0 = run.nit
        self._peak = None
        self._peak_nit = 0
        self.peak_refined = False  #: whether peak() located the maximum between samples
        self._stable = None

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
    #: Indices in the unknowns of the response's (x_c, x_s) (``peak`` maximises their norm).
    _peak_components = (0, 1)

    def _peak_point(self, y: np.ndarray) -> tuple[float, float]:
        """``(omega, amplitude)`` of the scaled point ``y``."""
        xc, xs, w = self._problem.to_physical(y)
        return float(w), float(math.hypot(xc, xs))

    def peak(self) -> Peak:
        """``(omega, amplitude)`` of the largest response, located on the branch.

        Between the neighbours of the largest sampled point the branch is parametrised by its
        chord and the zero of ``d(a^2)/ds = 2 (x_c t_c + x_s t_s)`` (``t`` the tangent, with a
        fresh omega-derivative) is found by Brent's method; every trial point is a converged
        Newton point.  A maximum at an end of the branch is returned as sampled.

        Returns
        -------
        Peak
            ``(omega, amplitude)`` in rad/s and m; cached after the first call.

        Raises
        ------
        ValueError
            If the response has no points.

        Examples
        --------
        The default case of ``python -m hbm``: the damper is in microslip at resonance, the
        peak at about twice its slip amplitude a_min = 7.5e-7 m.

        >>> from hbm import frequency_response
        >>> from hbm.cli.cases import default_case
        >>> case = default_case()
        >>> frf = frequency_response(case.blade, case.element, omega_range=case.omega_range)
        >>> pk = frf.peak()
        >>> round(pk.omega, -1), round(pk.amplitude / 7.5e-7, 2)     # rad/s, a/a_min
        (38770.0, 2.02)
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

            c, s_ = self._peak_components  # the scaled (x_c, x_s) of the response in y

            def slope(u, t):  # proportional to d(a^2)/ds along the branch
                return u[c] * t[c] + u[s_] * t[s_]

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
                w, a = self._peak_point(loc.y)
                if a >= best.amplitude * (1.0 - 10.0 * self.rtol):
                    best = Peak(float(w), a)
                    self.peak_refined = True
        self._peak = best
        return best

    # ------------------------------------------------------------------ output
    def to_csv(self, path: str | Path) -> Path:
        """Write the points as ``hbm.output.FRF_COLUMNS`` (omega, amplitude, phase, x_c, x_s,
        residual, units in the header); returns the path.

        Parameters
        ----------
        path : str or Path
            The CSV file to write.

        Returns
        -------
        Path
            The file written.

        Examples
        --------
        >>> import tempfile, pathlib
        >>> from hbm import Blade, frequency_response
        >>> frf = frequency_response(Blade(mass=1.0, stiffness=1.0e4, damping=2.0, force=1.0),
        ...                          omega_range=(90.0, 110.0))
        >>> path = frf.to_csv(pathlib.Path(tempfile.mkdtemp()) / "frf.csv")
        >>> lines = path.read_text().splitlines()
        >>> lines[0].split(",")[:2], len(lines) == len(frf.omega) + 1
        (['omega_rad_s', 'amplitude_m'], True)
        >>> float(lines[1].split(",")[0]), float(lines[-1].split(",")[0])   # omega_range, rad/s
        (90.0, 110.0)
        """
        return write_frf_csv(path, self)

    def plot(self, ax: Any = None, *, label: str | None = None, peak: bool = True, **kwargs: Any) -> Any:
        """Amplitude against omega on ``ax`` (a new figure if None): stable stretches solid, unstable
        dashed (:attr:`stable`); marks the peak. Returns ax.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Where to draw; default a new figure.
        label : str, optional
            Legend label of the curve.
        peak : bool, optional
            Mark the peak (:meth:`peak`) with a dot.  Default True.
        **kwargs
            Passed to ``ax.plot`` (colour, line style).

        Returns
        -------
        matplotlib.axes.Axes
            The axes drawn on.

        Examples
        --------
        >>> import matplotlib
        >>> matplotlib.use("Agg")
        >>> from hbm import Blade, frequency_response
        >>> frf = frequency_response(Blade(mass=1.0, stiffness=1.0e4, damping=2.0, force=1.0),
        ...                          omega_range=(90.0, 110.0))
        >>> ax = frf.plot(label="bare blade")
        >>> ax.get_ylabel(), len(ax.lines)                 # the curve and its peak
        ('amplitude (m)', 2)
        """
        from .output import plot_branch

        # a single DOF at H = 1 with a passive element loses stability only at folds (the sum of
        # its two exponents is minus its damping): stability is computed only on a folded branch
        folded = self._stable is not None or len(getattr(self._run, "fold_after", ())) > 0
        ax, color = plot_branch(ax, self.omega, self.amplitude, self.stable if folded else None, label=label,
                                **kwargs)
        if peak and len(self):
            pk = self.peak()
            ax.plot([pk.omega], [pk.amplitude], "o", color=color, ms=4)
        return ax

    @property
    def stable(self) -> np.ndarray:
        """Stability of every point (bool), by Hill's method at H = 1 (``hbm.stability``), computed on
        first use; unstable stretches are drawn dashed by :meth:`plot`."""
        if self._stable is None:
            from .stability import single_harmonic_stability

            self._stable = single_harmonic_stability(self.blade, self.element, self.omega, self.x_c, self.x_s)
        return self._stable


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
    ``on_point(omega, x_c, x_s, residual)``: called with each accepted point and its ``|R|/F`` as soon
    as it is accepted, in continuation order (the same points as the result's), so a caller can
    stream them.
    ``accuracy``: "fast", "default", "precise" or an rtol; sets rtol, max_step, min_step and
    max_steps together (``hbm.presets``; not combined with them).

    Parameters
    ----------
    blade : Blade
        The blade (mass, stiffness, damping, force).
    element : ContactElement or None, optional
        The damper at the blade's tip (any ``contact_models`` element); None for the bare blade.
    omega_range : tuple of float
        ``(w0, w1)`` in rad/s, >= 0 and different; traced from w0 to w1 (either way).
    rtol : float, optional
        Relative accuracy, in (0, 0.1).  Default 1e-6.
    max_step, min_step : float, optional
        Largest and smallest continuation step in scaled arclength.  Defaults 0.03, 1e-9.
    max_steps : int, optional
        Step budget.  Default 5000.
    locate_folds : bool, optional
        Locate the turning points of the branch.  Default True.
    on_point : callable, optional
        ``on_point(omega, x_c, x_s, residual)`` for each accepted point, as it is accepted.
    accuracy : {"fast", "default", "precise"} or float, optional
        A preset of ``hbm.presets`` instead of ``rtol`` and the step settings.
    harmonics, n_t, response_dof, stability : optional
        The multi-harmonic balance's options (see below): the number of harmonics H (default the
        accuracy preset's), the AFT samples per period, the DOF whose response is reported (default
        the forced DOF) and whether Hill's stability is computed at every point (default True).

    Returns
    -------
    FrequencyResponse
        The branch, with ``success`` and ``message``; a run that stops early keeps the points it
        computed.  For the multi-harmonic balance an ``hbm.mhresult.MultiHarmonicResponse``.

    Raises
    ------
    ValueError
        If ``blade`` is not a :class:`Blade`, ``element`` has no ``fourier``, ``omega_range`` is
        missing or invalid, or an option is out of range; the message names it and its value.

    See Also
    --------
    response_at : the balance at one frequency.
    simulate_blade : the blade and the discretised bar integrated in time, the independent check.

    Notes
    -----
    With an ``hbm.Structure`` first and a sequence of ``hbm.Contact`` second (or a ``Blade``
    with ``harmonics``/``n_t``/``response_dof`` given) this is the multi-harmonic balance
    (``hbm.multiharmonic``): ``harmonics`` H (default: the accuracy preset's), ``n_t`` AFT
    samples per period, ``response_dof`` (default the forced DOF), ``stability`` (Hill's method
    at every point); it returns an ``hbm.mhresult.MultiHarmonicResponse``.

    Single-harmonic balance: with ``x = x_c cos(omega t) + x_s sin(omega t)``,
    ``a = sqrt(x_c^2 + x_s^2)`` and the element's ``p = f_s/a``, ``q = f_c/a``,

    .. math::

        (k - m\\omega^2 + p + i(c\\omega + q))\\,(x_c - i x_s) = F,

    two real equations in ``y = (x_c, x_s, omega)``, traced by pseudo-arclength continuation
    through folds; each point solves it to ``|R|/F <= NEWTON_TOL_FACTOR * rtol``.
    ``docs/hbm.md`` derives the Jacobian and the step control.

    Examples
    --------
    The bare blade against its closed form ``F/(c omega)`` at resonance:

    >>> from hbm import Blade, frequency_response
    >>> blade = Blade(mass=1.0, stiffness=1.0e4, damping=2.0, force=1.0)
    >>> frf = frequency_response(blade, omega_range=(90.0, 110.0))
    >>> pk = frf.peak()
    >>> import math
    >>> abs(pk.omega / math.sqrt(1.0e4 - 2.0) - 1.0) < 1e-7          # sqrt(k/m - c^2/(2 m^2))
    True
    >>> round(pk.amplitude / (1.0 / (2.0 * math.sqrt(1.0e4 - 1.0))), 6)  # F/(c sqrt(k/m - c^2/(4 m^2)))
    1.0

    With the two-region microslip damper (the default case of ``python -m hbm``):

    >>> from contact_models import Bar, UniformLoad, TwoRegionMicroslip
    >>> from hbm import Blade, frequency_response
    >>> bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    >>> two = TwoRegionMicroslip(bar, UniformLoad(N=100.0))
    >>> blade = Blade(mass=0.0877147, stiffness=1.0e8, damping=11.8467, force=8.0)
    >>> frf = frequency_response(blade, two, omega_range=(3.2e4, 4.4e4))
    >>> frf.success, round(frf.peak().amplitude, 9)    # m
    (True, 1.512e-06)
    """
    if not isinstance(blade, Blade) or harmonics is not None or n_t is not None or response_dof is not None:
        from .mhdispatch import structure_response

        return structure_response(blade, element, omega_range, rtol=rtol, max_step=max_step, min_step=min_step,
                                  max_steps=max_steps, locate_folds=locate_folds, on_point=on_point,
                                  accuracy=accuracy, harmonics=harmonics, n_t=n_t, response_dof=response_dof,
                                  stability=stability)
    if not isinstance(blade, Blade):
        raise ValueError(f"blade must be an hbm.Blade, got blade={blade!r}")
    w0, w1 = omega_range_pair(omega_range)
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

    Parameters
    ----------
    blade : Blade
        The blade.
    element : ContactElement
        The damper.
    omega : float
        Frequency (rad/s), >= 0.
    amplitude_bracket : tuple of float
        ``(a_lo, a_hi)`` (m), 0 < a_lo < a_hi, bracketing one solution.
    rtol : float, optional
        Relative tolerance on the amplitude, passed to the element too.  Default 1e-8.

    Returns
    -------
    Response
        ``(omega, x_c, x_s, amplitude, phase)`` in rad/s, m, m, m, rad.

    Raises
    ------
    ValueError
        If an argument is invalid, or the bracket does not change sign (no solution, or an
        even number of them, in it); the message gives the values at its ends.

    See Also
    --------
    frequency_response

    Examples
    --------
    >>> from hbm import response_at
    >>> from hbm.cli.cases import default_case
    >>> case = default_case()                          # the blade and damper of python -m hbm
    >>> r = response_at(case.blade, case.element, 38000.0, (1.0e-7, 1.0e-5))
    >>> round(r.amplitude, 10), round(r.phase, 3)      # m, rad
    (7.371e-07, 0.041)
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
