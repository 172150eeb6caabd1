"""The true periodic steady response of a structure with Jenkins contacts, by time integration and
shooting: the independent reference the harmonic balance is checked against.

Model (n DOFs; SI units; ``t`` in s, ``omega`` in rad/s)::

    M x'' + C x' + K x + sum_c b_c f_c + sum_q b_q k3_q (b_q^T x)^3 = force cos(omega t),

``b = e_i`` for an element to ground at DOF i, ``b = e_i - e_j`` for one between DOFs i and j
(acting on ``u = x_i - x_j``, force +f on i, -f on j).  A Jenkins contact (``Macroslip``:
spring ``stiffness`` kt behind a Coulomb slider of force ``slip_force`` fs) has the force
``f = kt (u - z)``, ``|f| <= fs``, its slider z moving only while ``|f| = fs``.  A cubic spring
is any element with an attribute ``k3`` (N/m^3).

Method (``docs/shooting.md``):

1. Integrate one period T = 2 pi/omega from the state ``y0 = (x, v, z)`` at t = 0, either
   (a) event-driven (``integrator="events"``, the default): exact between stick/slip events by
   the matrix exponential of the mode's linear system (DOP853 at rtol 1e-12 where cubic springs
   make it nonlinear), events located by root finding; or (b) Newmark's average acceleration with
   ``steps`` fixed steps per period and the exact return mapping of the sliders
   (``integrator="newmark"``, second order; the cross-check of (a)).
2. Shooting: Newton on ``Phi_T(y0) - y0 = 0`` with the Jacobian by forward differences of the
   period map ``Phi_T`` (the sliders' states are part of y0).
3. Monodromy ``dPhi_T/dy0`` by central differences at the solution; its eigenvalues are the
   Floquet multipliers (a slider slipping at t = 0 gives a zero multiplier: its state is forgotten).

Accuracy (measured by ``benchmarks/periodic_reference.py``, ``tests/test_shooting.py``,
``docs/shooting.md``): the event-driven reference is exact to rounding between events; its first
harmonics agree with the exact linear response to 1e-12, do not change from 128 to 1024 grid
steps (1e-12), balance the energy per cycle to 1e-10, and Newmark converges to them at rate ~2
in the step (-2.8e-8, -9e-10, +5e-9 at 8192, 16384, 32768 steps per period on P1 at omega = 1.3).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validation import count, flag, positive, relative_tolerance, within_precision
from .newmark import NewmarkIntegrator
from .piecewise import EventIntegrator, Model
from .system import build_model

__all__ = ["PeriodicResponse", "PeriodicPeak", "periodic_response", "periodic_peak"]

#: Relative step of the forward differences of the shooting Jacobian.
NEWTON_FD = 1e-7
#: Relative step of the central differences of the monodromy matrix.
MONODROMY_FD = 1e-5
#: A chord iteration reducing the residual by less than this factor triggers a fresh Jacobian.
CHORD_RATE = 0.1
#: Newton iterations tried from the stuck guess before the transient is let settle.
FIRST_TRY = 12
#: Step halvings tried along one Newton direction.
HALVINGS = 12
#: Periods of transient integrated from the stuck guess before a second Newton attempt.
SETTLE = 60
#: Samples per period of the return map marched for ``_harmonic_guess``.
GUESS_SAMPLES = 256
#: Default grid steps per period of each integrator.
STEPS = {"events": 512, "newmark": 4096}


@dataclass
class PeriodicResponse:
    """One periodic steady response (see ``periodic_response``).

    Attributes
    ----------
    omega : float
        Forcing frequency (rad/s).
    t : ndarray, shape (steps,)
        Sample times t_k = 2 pi k / (steps omega) over one period.
    x, v : ndarray, shape (steps, n)
        Displacements and velocities of every DOF at ``t``.
    z, contact_force : ndarray, shape (steps, n_contacts)
        Slider positions and forces kt (u - z) of the Jenkins contacts at ``t``.
    harmonics : ndarray, shape (n, 2 H + 1)
        Real harmonic coefficients of every DOF, ``[X0, Xc1, Xs1, ..., XcH, XsH]``
        (``x = X0 + sum_h Xc_h cos(h omega t) + Xs_h sin(h omega t)``), from the samples by FFT.
    floquet : ndarray of complex, shape (2 n + n_contacts,)
        Floquet multipliers (eigenvalues of the monodromy matrix), by decreasing modulus; empty
        if not computed.
    monodromy : ndarray, shape (2 n + n_contacts, 2 n + n_contacts)
        The monodromy matrix (state order x, v, z), or an empty array.
    success : bool
    message : str
    iterations : int
        Newton iterations of the shooting.
    residual : float
        ``max |Phi_T(y0) - y0|`` over the state's scale at the solution.
    """

    omega: float
    t: NDArray[np.float64]
    x: NDArray[np.float64]
    v: NDArray[np.float64]
    z: NDArray[np.float64]
    contact_force: NDArray[np.float64]
    harmonics: NDArray[np.float64]
    floquet: NDArray[np.complex128]
    monodromy: NDArray[np.float64]
    success: bool
    message: str
    iterations: int
    residual: float
    state: NDArray[np.float64] = field(repr=False)
    _extreme: Any = field(default=None, repr=False)
    _extremes: dict = field(default_factory=dict, repr=False)

    def coefficients(self, dof: int) -> NDArray[np.complex128]:
        """Complex coefficients ``c_0 = X0, c_h = Xc_h - 1j Xs_h`` (h = 1..H) of DOF ``dof``, so
        that ``x = Re sum_h c_h exp(1j h omega t)``."""
        X = self.harmonics[_dof(dof, self.x.shape[1])]
        return np.concatenate([[X[0] + 0j], X[1::2] - 1j * X[2::2]])

    def amplitude(self, dof: int = 0) -> float:
        """First-harmonic amplitude ``sqrt(Xc1^2 + Xs1^2)`` of DOF ``dof``."""
        X = self.harmonics[_dof(dof, self.x.shape[1])]
        return float(math.hypot(X[1], X[2]))

    def max_abs(self, dof: int = 0) -> float:
        """``max_t |x_dof(t)|``: by root finding on the velocity with the event-driven flow
        (to rounding) for ``integrator="events"``; for Newmark the largest sample refined by the
        parabola through it and its two neighbours."""
        dof = _dof(dof, self.x.shape[1])
        if dof not in self._extremes:
            s = self.x[:, dof]
            k = int(np.argmax(np.abs(s)))
            if self._extreme is not None:
                value = self._extreme(k, dof)
            else:
                y0, y1, y2 = (abs(s[(k + i) % s.size]) for i in (-1, 0, 1))
                den = y0 - 2.0 * y1 + y2
                value = float(y1 - 0.125 * (y2 - y0) ** 2 / den) if den < 0.0 else float(y1)
            self._extremes[dof] = value
        return self._extremes[dof]

    @property
    def stable(self) -> bool:
        """All Floquet multipliers inside the unit circle (to 1e-6); False if not computed."""
        return bool(self.floquet.size and np.max(np.abs(self.floquet)) < 1.0 + 1e-6)


@dataclass
class PeriodicPeak:
    """The refined maximum of a periodic response measure over frequency (``periodic_peak``).

    Attributes
    ----------
    omega : float
        Frequency of the maximum (rad/s); on failure the best frequency solved, NaN when none was.
    value : float
        The measure there (m): first-harmonic amplitude or the largest displacement magnitude
        over the cycle; NaN when no response was solved.
    response : PeriodicResponse or None
        The periodic response at ``omega`` (None when no response was solved).
    evaluations : int
        Periodic responses computed during the search.
    success : bool
        Whether an interior maximum was found to ``xtol``.
    message : str
        ``"maximum found"``, or what went wrong.
    """

    omega: float
    value: float
    response: PeriodicResponse
    evaluations: int
    success: bool
    message: str


def _dof(dof: int, n: int) -> int:
    if isinstance(dof, bool) or not isinstance(dof, (int, np.integer)) or not 0 <= dof < n:
        raise ValueError(f"dof must be an integer in [0, {n}), got dof={dof!r}")
    return int(dof)


def _integrator(model: Model, omega: float, integrator: str, steps: int | None):
    if integrator not in STEPS:
        raise ValueError(f"integrator must be one of {sorted(STEPS)}, got integrator={integrator!r}")
    steps = STEPS[integrator] if steps is None else steps
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 8:
        raise ValueError(f"steps must be an integer >= 8, got steps={steps!r}")
    if integrator == "events":
        return EventIntegrator(model, omega, int(steps))
    return NewmarkIntegrator(model, omega, int(steps))


# ---------------------------------------------------------------- shooting
def _linear_guess(m: Model, omega: float) -> NDArray[np.float64]:
    """Start of the shooting: the response with every contact stuck, sliders at zero."""
    Kst = m.K + (m.B * m.kt) @ m.B.T
    X = np.linalg.solve(Kst - omega**2 * m.M + 1j * omega * m.C, m.force.astype(complex))
    return np.concatenate([X.real, (1j * omega * X).real, np.zeros(m.nc)])


def _harmonic_guess(m: Model, omega: float, X: NDArray[np.complex128]) -> NDArray[np.float64]:
    """Start of the shooting from first-harmonic coefficients ``x = Re(X exp(i omega t))``: the
    sliders' states at t = 0 by the return map marched over two periods of that motion."""
    if X.size != m.n or not np.all(np.isfinite(X)):
        raise ValueError(f"initial must hold {m.n} finite complex coefficients, got initial={X!r}")
    theta = np.linspace(0.0, 4.0 * np.pi, 2 * GUESS_SAMPLES + 1)
    u = np.real(np.outer(np.exp(1j * theta), X @ m.B))
    z = np.zeros(m.nc)
    for uk in u:
        f = np.clip(m.kt * (uk - z), -m.fs, m.fs)
        z = uk - f / m.kt
    return np.concatenate([X.real, -omega * X.imag, z])


def _scale(m: Model, y: NDArray[np.float64], omega: float) -> NDArray[np.float64]:
    """Per-component scale of the state (x, v, z) for the differences and the convergence test."""
    n = m.n
    sx = max(float(np.max(np.abs(y[:n]))), float(np.max(np.abs(y[n:2 * n]))) / omega,
             float(np.max(m.fs / m.kt, initial=0.0)), 1e-300)
    return np.concatenate([np.full(n, sx), np.full(n, sx * omega), np.full(m.nc, sx)])


def _jacobian(phi, y, dy, central):
    d = y.size
    J = np.empty((d, d))
    base = None if central else phi(y)
    for j in range(d):
        e = np.zeros(d)
        e[j] = dy[j]
        J[:, j] = (phi(y + e) - phi(y - e)) / (2.0 * dy[j]) if central else (phi(y + e) - base) / dy[j]
    return J, base


def _shoot(m, omega, phi, y, J, tol, max_iter):
    """Newton (or chord Newton from ``J``) on Phi(y) - y with halving of the step.

    Returns (y, success, message, iterations, scaled residual)."""
    d = y.size
    py, it, res, it_fresh = None, 0, math.inf, -1
    try:
        for it in range(max_iter + 1):
            s = _scale(m, y, omega)
            if J is None:
                J, py = _jacobian(phi, y, NEWTON_FD * s, central=False)
                it_fresh = it
            elif py is None:
                py = phi(y)
            G = py - y
            res = float(np.max(np.abs(G) / s))
            if not math.isfinite(res):
                return y, False, f"non-finite state at Newton iteration {it}", it, res
            if res < tol:
                return y, True, f"converged in {it} Newton iterations", it, res
            if it == max_iter:
                break
            # least squares: a slider stuck all period is a neutral direction (multiplier 1)
            step = np.linalg.lstsq(J - np.eye(d), -G, rcond=1e-12)[0]
            t, fresh = 1.0, it_fresh == it
            for _ in range(HALVINGS):  # halve the step until the residual decreases
                trial = y + t * step
                p_trial = phi(trial)
                r_trial = float(np.max(np.abs(p_trial - trial) / _scale(m, trial, omega)))
                if r_trial < res:
                    break
                t *= 0.5
            else:
                if fresh:  # no decrease along a fresh Newton direction: rounding floor of the map
                    return y, False, (f"Newton stagnated at residual {res:.2e} > tol (the period map's "
                                      "rounding floor: loosen tol)"), it, res
            if r_trial > CHORD_RATE * res:
                J = None  # slow: a fresh Jacobian at the next iterate
            y, py = trial, p_trial
    except (FloatingPointError, np.linalg.LinAlgError) as exc:
        return y, False, f"shooting failed at Newton iteration {it}: {exc}", it, res
    return y, False, f"Newton did not converge in {max_iter} iterations (residual {res:.2e})", it, res


def periodic_response(system: Any, contacts: Sequence[Any] = (), *, omega: float, harmonics: int = 21,
                      integrator: str = "events", steps: int | None = None,
                      initial: PeriodicResponse | ArrayLike | None = None, tol: float = 1e-11,
                      max_iter: int = 40, floquet: bool = True) -> PeriodicResponse:
    """The periodic steady response at the forcing frequency ``omega``, by shooting.

    Parameters
    ----------
    system : Structure, Blade or tuple
        Anything with attributes ``M, C, K, force`` (n x n arrays, dense or scipy.sparse, and the
        amplitudes of ``force cos(omega t)``), or ``mass, damping, stiffness, force`` (one DOF),
        or a tuple ``(M, C, K, force)``: the whole model (one sector of a ``CyclicStructure`` is refused:
        give ``disk.full(contacts)``).
    contacts : sequence of Contact
        Objects with ``.element`` and ``.dofs`` (1 or 2 DOFs; ``.dof`` also accepted), none to the next sector.  The element
        is a Jenkins element (``.stiffness`` finite, ``.slip_force``; e.g. ``Macroslip``) or a cubic
        spring (``.k3``).
    omega : float
        Forcing frequency (rad/s, > 0).
    harmonics : int, optional
        H of the returned coefficients (default 21); needs ``steps >= 2 H + 2``.
    integrator : {"events", "newmark"}, optional
        Event-driven exact integration (default) or Newmark with return mapping (the check).
    steps : int, optional
        Grid steps per period (samples of the output; Newmark's time step).  Default 512 for
        ``"events"``, 4096 for ``"newmark"``.
    initial : PeriodicResponse or array, optional
        Start of the Newton iteration: an earlier response (continuation), the state
        ``(x, v, z)`` at t = 0 (real, length 2 n + n_c), or complex first-harmonic coefficients
        of every DOF (length n, ``x = Re(X exp(i omega t))``; the sliders' states follow by the
        return map).  Default: the response with every contact stuck; if Newton fails from
        there, it is retried after 60 periods of transient.
    tol : float, optional
        Newton stops when ``max |Phi_T(y0) - y0|`` over the state's scale is below ``tol``, in (0, 1).
    max_iter : int, optional
        Newton iterations allowed, >= 1.
    floquet : bool, optional
        Compute the monodromy matrix and the Floquet multipliers (2 (2 n + n_c) more periods).

    Returns
    -------
    PeriodicResponse
        ``success`` False with a message if Newton did not converge (the last iterate is kept).

    Raises
    ------
    ValueError
        Naming the parameter and the value for malformed input.

    Notes
    -----
    The state ``y0 = (x(0), v(0), z(0))`` solves ``Phi_T(y0) = y0``; ``Phi_T`` is the exact
    period map (``integrator="events"``) or its Newmark approximation.  Newton uses forward
    differences of step ``1e-7`` times the state's scale, with step halving on the residual; the
    monodromy matrix uses central differences of step ``1e-5`` times the scale.

    Examples
    --------
    A linear oscillator (the slider never slips) against its exact amplitude
    ``F / |k + kt - m omega^2 + i c omega|``:

    >>> from contact_models import Macroslip
    >>> from hbm import Blade
    >>> class Ground:
    ...     element, dofs = Macroslip(stiffness=1.0, slip_force=1e3), (0,)
    >>> r = periodic_response(Blade(mass=1, stiffness=1, damping=0.1, force=0.01), [Ground()],
    ...                       omega=1.0, harmonics=3, steps=64)
    >>> round(r.amplitude(0), 10), round(abs(0.01 / complex(1.0, 0.1)), 10)
    (0.0099503719, 0.0099503719)
    """
    omega = positive("omega", omega)
    if isinstance(harmonics, bool) or not isinstance(harmonics, (int, np.integer)) or harmonics < 1:
        raise ValueError(f"harmonics must be an integer >= 1, got harmonics={harmonics!r}")
    tol, max_iter = relative_tolerance("tol", tol, 1.0), count("max_iter", max_iter, 1)
    floquet = flag("floquet", floquet)
    m = build_model(system, contacts)
    within_precision("omega", omega, omega, 1, m.M, m.C)  # the stuck start, the period map: omega^2 M
    I = _integrator(m, omega, integrator, steps)
    if I.steps < 2 * harmonics + 2:
        raise ValueError(f"steps must be >= 2 harmonics + 2 = {2 * harmonics + 2}, got steps={I.steps!r}")
    if initial is None:
        y = _linear_guess(m, omega)
    elif isinstance(initial, PeriodicResponse):
        y = initial.state.copy()
    elif np.iscomplexobj(initial):
        y = _harmonic_guess(m, omega, np.asarray(initial).ravel())
    else:
        try:
            y = np.asarray(initial, dtype=float).ravel().copy()
        except (TypeError, ValueError):
            y = np.empty(0)  # not numbers: refused below, naming initial
    d = 2 * m.n + m.nc
    if y.size != d or not np.all(np.isfinite(y)):
        raise ValueError(f"initial must be a finite state of length {d}, got initial={initial!r}")

    def phi(y):
        return I.period_map(y)[0]

    J0 = None
    if isinstance(initial, PeriodicResponse) and initial.monodromy.shape == (d, d):
        J0 = initial.monodromy  # chord Newton from a neighbour's monodromy (continuation)
    first = max_iter if initial is not None else min(max_iter, FIRST_TRY)
    y, success, message, it, res = _shoot(m, omega, phi, y, J0, tol, first)
    if not success and initial is None:  # from the stuck guess: let the transient settle, retry
        try:
            y = _linear_guess(m, omega)
            for _ in range(SETTLE):
                y = phi(y)
        except FloatingPointError:
            pass
        else:
            y, success, message, it2, res = _shoot(m, omega, phi, y, None, tol, max_iter)
            it += it2
            message += f" (after {SETTLE} periods of transient from the stuck guess)"
    try:
        _, samples = I.period_map(y, record=True)
    except FloatingPointError as exc:  # only after a failed shooting: keep the start's period
        message += f"; the last iterate cannot be integrated ({exc}), the samples are the stuck start's"
        y = _linear_guess(m, omega)
        _, samples = I.period_map(y, record=True)
    mono = np.empty((0, 0))
    mult = np.empty(0, dtype=complex)
    if floquet and success:
        mono, _ = _jacobian(phi, y, MONODROMY_FD * _scale(m, y, omega), central=True)
        mult = np.linalg.eigvals(mono)
        mult = mult[np.argsort(-np.abs(mult), kind="stable")]
    return _result(m, I, omega, harmonics, samples, y, mono, mult, success, message, it, res)


def _result(m, I, omega, H, samples, y, mono, mult, success, message, it, res) -> PeriodicResponse:
    n, N = m.n, I.steps
    x, v, z = samples[:, :n], samples[:, n:2 * n], samples[:, 2 * n:]
    spec = np.fft.rfft(x, axis=0) / N
    X = np.empty((n, 2 * H + 1))
    X[:, 0] = spec[0].real
    X[:, 1::2] = 2.0 * spec[1:H + 1].real.T
    X[:, 2::2] = -2.0 * spec[1:H + 1].imag.T
    return PeriodicResponse(omega=omega, t=np.arange(N) * I.h, x=x, v=v, z=z,
                            contact_force=np.clip(m.contact_force(x, z), -m.fs, m.fs), harmonics=X,
                            floquet=mult, monodromy=mono, success=success, message=message,
                            iterations=it, residual=res, state=y, _extreme=_extreme_finder(I, samples))


def _extreme_finder(I, samples):
    """``(k, dof) -> max |x_dof|`` near sample k, exact for the event-driven integrator."""
    if not isinstance(I, EventIntegrator):
        return None
    N = I.steps

    def find(k, dof):
        j = (k - 1) % N
        start = np.concatenate([samples[j], [math.cos(I.omega * j * I.h), math.sin(I.omega * j * I.h)]])
        return I.extreme(start, dof)
    return find


# ---------------------------------------------------------------- peak
def _measure(r: PeriodicResponse, dof: int, measure: str) -> float:
    return r.amplitude(dof) if measure == "amplitude" else r.max_abs(dof)


def periodic_peak(system: Any, contacts: Sequence[Any] = (), *, bracket: tuple[float, float], dof: int = 0,
                  measure: str = "amplitude", initial: PeriodicResponse | None = None, xtol: float = 1e-9,
                  **options: Any) -> PeriodicPeak:
    """The frequency in ``bracket`` where the periodic response's ``measure`` of DOF ``dof`` is
    largest (Brent's bounded search, each point warm-started from the nearest one solved).

    Parameters
    ----------
    system, contacts
        As for ``periodic_response``.
    bracket : (float, float)
        Frequencies (rad/s) enclosing one maximum of the measure on one branch.
    dof : int, optional
        The DOF whose response is maximised (default 0).
    measure : {"amplitude", "max"}, optional
        First-harmonic amplitude (default) or ``max_t |x_dof|``.
    initial : PeriodicResponse, optional
        A response near the bracket to start from (selects the branch where several coexist).
    xtol : float, optional
        Absolute tolerance on the frequency (rad/s), > 0 and below a twentieth of the bracket's width
        (a maximum is interior 10 xtol inside the bracket); default 1e-9.
    **options
        Passed to ``periodic_response`` (e.g. ``steps``, ``harmonics``); ``floquet`` is False.

    Returns
    -------
    PeriodicPeak
        ``omega``, ``value`` (the measure there), the ``response`` and the number of responses
        computed.

    Raises
    ------
    ValueError
        For a bracket that is not two increasing positive frequencies, an xtol it cannot hold or an
        unknown measure.

    Notes
    -----
    Near a maximum the measure is quadratic in omega, so a noise e on it limits the frequency to
    about sqrt(e / |A''|); the event-driven responses carry e ~ 1e-13 relative.

    Examples
    --------
    >>> from contact_models import Macroslip
    >>> from hbm import Blade
    >>> class Ground:
    ...     element, dofs = Macroslip(stiffness=1.0, slip_force=1e3), (0,)
    >>> p = periodic_peak(Blade(mass=1, stiffness=1, damping=0.1, force=0.01), [Ground()],
    ...                   bracket=(1.3, 1.5), steps=64, harmonics=1)
    >>> round(p.omega, 6), round(math.sqrt(2 - 0.1**2 / 2), 6)
    (1.412445, 1.412445)
    """
    from scipy.optimize import minimize_scalar  # heavy (0.1-0.5 s), lazily: import hbm stays light

    try:
        lo, hi = (positive("bracket", b) for b in bracket)
    except (TypeError, ValueError):
        lo = hi = math.nan
    if not (0.0 < lo < hi < math.inf):
        raise ValueError(f"bracket must be two increasing positive frequencies, got bracket={bracket!r}")
    if measure not in ("amplitude", "max"):
        raise ValueError(f"measure must be 'amplitude' or 'max', got measure={measure!r}")
    xtol = positive("xtol", xtol)
    if not xtol < (hi - lo) / 20.0:
        raise ValueError(f"xtol must be < (bracket[1] - bracket[0]) / 20 = {(hi - lo) / 20.0:g} (an absolute "
                         f"tolerance in rad/s; a maximum is interior 10 xtol inside the bracket), got xtol={xtol!r} "
                         f"with bracket={bracket!r}")
    if initial is not None and not isinstance(initial, PeriodicResponse):
        raise ValueError(f"initial must be a PeriodicResponse (from periodic_response) or None, got initial={initial!r}")
    options = {**options, "floquet": False}
    solved: dict[float, PeriodicResponse] = {}
    if initial is not None:
        solved[initial.omega] = initial

    def value(w):
        start = solved[min(solved, key=lambda s: abs(s - w))] if solved else None
        r = periodic_response(system, contacts, omega=w, initial=start, **options)
        if not r.success:
            raise FloatingPointError(f"no periodic response at omega={w!r}: {r.message}")
        solved[w] = r
        return -_measure(r, dof, measure)

    try:
        opt = minimize_scalar(value, bounds=(lo, hi), method="bounded", options={"xatol": xtol, "maxiter": 200})
    except FloatingPointError as exc:
        if not solved:
            return PeriodicPeak(math.nan, math.nan, None, 0, False, str(exc))
        best = max(solved, key=lambda w: _measure(solved[w], dof, measure))
        return PeriodicPeak(best, _measure(solved[best], dof, measure), solved[best], len(solved), False, str(exc))
    w = float(opt.x)
    r = solved[w] if w in solved else periodic_response(system, contacts, omega=w, **options)
    ok = bool(opt.success) and lo + 10 * xtol < w < hi - 10 * xtol
    msg = "maximum found" if ok else f"no interior maximum in the bracket ({opt.message})"
    return PeriodicPeak(w, -float(opt.fun), r, len(solved), ok, msg)
