"""The microslip bar integrated in time: the paper's full numerical solution (Section 3.5, Eq. 30).

``NumericalMicroslip`` keeps every mode of the bar, so it is the independent check of the
single-mode analytic elements (``TwoRegionMicroslip``, ``ThreeRegionMicroslip``) and shows
where the neglected phase differences along the bar matter.

Model (Eq. 30 with the displacement input of Eq. 5).  Bar 0 <= x <= L, axial stiffness
S = EA, mass rho A per length, spring beta at x = 0 (S u_x(0) = beta u(0)), tip driven by
u(L, t) = a sin(omega t).  Shear layer: a Jenkins element at every point, stiffness k
(N/m^2) behind a slider of limit mu q(x) (N/m): tau = k (u - w), |tau| <= mu q.  Output:
the force the driver applies, f = S u_x(L).

Discretisation (method of lines, then time):

* linear finite elements on n equal cells, h = L/n, nodes x_i = i h;
* lumped (diagonal) mass rho A c_i, and the shear layer lumped at the nodes with trapezoid
  weights c_i (h inside, h/2 at both ends): node i carries a Jenkins element of stiffness
  k c_i and slip force mu q(x_i) c_i;
* the tip force is the reaction of the driven node, (S/h)(u_n - u_{n-1}) + tau_n + m_n u_n''
  (tau_n its Jenkins force, m_n its lumped mass), the consistent approximation of S u_x(L);
* time: implicit generalized-alpha (Chung & Hulbert 1993, J. Appl. Mech. 60) with spectral
  radius ``rho_inf`` at infinite frequency.  ``rho_inf = 1`` is exactly Newmark's average
  acceleration (trapezoidal rule, equilibrium at t_{n+1}); the default 0.9 keeps second order
  and, at the low modes that carry the response, practically no dissipation (O((omega dt)^3))
  but damps the spurious high modes of the mesh, which the friction never damps and which
  otherwise keep the undamped bar from ever becoming periodic (docs/validation.md);
* every step: exact return mapping of each nodal Jenkins element (backward Euler is exact
  for it) inside a semismooth Newton iteration with tangent k c_i on stuck nodes and 0 on
  slipping ones; the Jacobian is tridiagonal (``scipy.linalg.solve_banded``).  The step's
  system is piecewise linear, so the iteration stops when the stick/slip set it assumed is
  reproduced by its result (then solved exactly) or the residual is at rounding; after
  ``NEWTON_PLAIN`` iterations an Armijo line search on the step's convex potential guards
  against cycling;
* quasi-static mode (``quasi_static=True``, automatic at omega = 0): the same without mass,
  driven by the tip-displacement history.  The problem is rate independent and each
  monotone step is solved exactly, so the step count enters only the f_s, f_c quadrature.

Steady state.  Quasi-static runs load from rest to x = a (a quarter cycle), then cycle.
Dynamic runs start from rest with the amplitude raised by a quintic smooth step over
``ramp_cycles`` cycles.  The run stops at the first cycle whose force history differs from
the previous, uninterrupted cycle by less than ``steady_tol`` relative to its peak,

    max_theta |f_j(theta) - f_{j-1}(theta)| <= steady_tol * max_theta |f_j(theta)|,

or after ``max_cycles`` cycles (then ``converged`` is False and ``message`` says so, and ``fourier``
warns ``AccuracyWarning`` with the last change).  A dynamic run judges no cycle before a wave front
(speed sqrt(E/rho)) has crossed the bar and back (``first_judged_cycle``): until then the tip force
is the outgoing wave's and periodic whatever the rest of the bar does.  The
quasi-static bar follows the Masing rule and is periodic after the first reversal, so it stops
after 2 cycles.  The dynamic bar, with only friction to damp it, settles slowly; with
``shooting`` (default) some cycles also carry the exact derivative of the one-cycle map
(state u, v, acceleration and slider positions; the map is piecewise affine) and the
cycle-start state takes a Newton step, inside a trust region, to the periodic orbit.  The
criterion above is then checked on a following plain cycle, so it is always the judge.

f_s, f_c are the trapezoid-rule Fourier integrals (1/pi) int f sin(theta), (1/pi) int f
cos(theta) over the last cycle.  The stick/slip map: L1, L2 are the outer ends of the
nodes slipping in a step, located between nodes by extrapolating the stuck side's
utilisation tau/(mu q) (signed with the slip) linearly to 1.

Quasi-static runs of several amplitudes step in lockstep, their tridiagonal systems stacked
into one banded solve; dynamic runs go one (a, omega) pair at a time.

Code: the nodal data in ``numerics.fe_bar``, the integrator's coefficients in ``numerics.genalpha`` (shared
with ``hbm.reference.transient``), the step (return mapping, Newton, lockstep batch and its tangent) in
``_stepping``; here the element, its runs to the steady state (with the shooting) and the
result.  The names ``hbm.reference.transient`` uses are re-exported here.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .numerics.fe_bar import NodalData, _Discretisation
from .numerics.genalpha import GeneralizedAlpha
from .numerics.stepping import NEWTON_MAX, NEWTON_PLAIN, NEWTON_RTOL, _Batch, _unit_tangent, return_map, solve_step
from .loads import bound_load
from .numerics.checks import count as _count, finite, flag, nonnegative, relative
from .accuracy import AccuracyWarning
from .bar import Bar
from .base import ContactElement

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from .loads import QuadraticLoad, UniformLoad

__all__ = ["NumericalMicroslip", "SimulationResult", "NodalData", "GeneralizedAlpha", "return_map", "solve_step",
           "STEPS_QUASI_STATIC", "STEPS_DYNAMIC", "STEADY_TOL", "MAX_CYCLES_QUASI_STATIC", "MAX_CYCLES_DYNAMIC",
           "RHO_INF", "RAMP_CYCLES", "NEWTON_PLAIN", "NEWTON_MAX", "NEWTON_RTOL", "SHOOT_SKIP"]

#: Default steps per cycle, quasi-static and dynamic (multiples of 4: x = +-a are grid points).
STEPS_QUASI_STATIC = 512
STEPS_DYNAMIC = 512
#: Default relative cycle-to-cycle change of the force history accepted as steady.
STEADY_TOL = 1e-6
#: Default cycle budgets.
MAX_CYCLES_QUASI_STATIC = 8
MAX_CYCLES_DYNAMIC = 30
#: Default spectral radius at infinity of the generalized-alpha integrator (1: average acceleration).
RHO_INF = 0.9
#: Default cycles over which a dynamic run raises the amplitude from 0 to a.
RAMP_CYCLES = 2
#: The most cells the bar takes: a cycle's cost grows with cells times steps and its memory with
#: cells (10**9 cells grew by 400 MB/s until killed); raise it here to go further.
MAX_CELLS = 10_000
#: The relative error of the stuck stiffness (against the continuous bar's closed form, relative to
#: max(|K|, 0.01 k*)) above which ``fourier`` warns (``AccuracyWarning``) that the cells do not resolve omega.
WAVE_TOL = 1e-3
#: Shooting skips its Newton step when the one-cycle map moves the state by less than this
#: fraction of steady_tol (scaled, see ``_run_dynamic``).
SHOOT_SKIP = 1e-2


@dataclass
class SimulationResult:
    """Last (steady) cycle of a run, theta = omega t in [0, 2 pi) on ``steps_per_cycle`` points.

    ``L1``, ``L2``: the outer ends of the slipping zone in the step ending at theta (the left
    stuck region is [0, L1], the right one [L2, L]); both equal L while nothing slips.
    ``change`` is the last relative cycle-to-cycle change of f (``history``: per cycle, inf
    after a shooting jump); ``converged`` says whether it reached the tolerance; ``cycles``
    counts full cycles after the start (quasi-static: after the virgin quarter; dynamic: after
    the ramp); ``newton_iterations`` counts the step solves of the run (of the whole lockstep
    batch when several quasi-static amplitudes ran together).
    """

    a: float
    omega: float
    quasi_static: bool
    theta: np.ndarray
    x: np.ndarray
    f: np.ndarray
    L1: np.ndarray
    L2: np.ndarray
    f_s: float
    f_c: float
    cycles: int
    converged: bool
    change: float
    newton_iterations: int
    steps: int
    message: str = ""
    history: NDArray[np.float64] | None = field(default=None, repr=False)  # change per cycle

    @property
    def success(self) -> bool:
        return self.converged

    def loop(self, n: int | None = None) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Closed loop ``(x, f)`` from theta = -pi/2 to 3 pi/2 (x from -a back to -a)."""
        theta = np.linspace(-0.5 * np.pi, 1.5 * np.pi, n or self.theta.size + 1)
        return self.a * np.sin(theta), self.force_at(theta)

    def force_at(self, theta: ArrayLike) -> NDArray[np.float64]:
        """f at arbitrary theta (periodic linear interpolation of the steady cycle)."""
        th = np.mod(np.asarray(theta, dtype=float), 2.0 * np.pi)
        grid = np.append(self.theta, 2.0 * np.pi)
        return np.interp(th, grid, np.append(self.f, self.f[0]))

    def to_csv(self, path: str | Path) -> None:
        """Write theta, x, f, L1, L2 of the steady cycle."""
        data = np.column_stack([self.theta, self.x, self.f, self.L1, self.L2])
        np.savetxt(path, data, delimiter=",", header="theta,x,f,L1,L2", comments="")

    def plot(self, ax: Axes | None = None) -> Axes:
        """Hysteresis loop f against x."""
        import matplotlib.pyplot as plt  # lazily: heavy, and only plotting needs it

        ax = ax if ax is not None else plt.gca()
        x, f = self.loop()
        ax.plot(x, f)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("f (N)")
        return ax


def _change(f, prev):
    """Relative cycle-to-cycle change max|f_j - f_{j-1}| / max|f_j| per pair (inf without a previous cycle)."""
    if prev is None:
        return np.full(f.shape[0], np.inf)
    peak = np.max(np.abs(f), axis=1)
    return np.max(np.abs(f - prev), axis=1) / np.where(peak > 0, peak, 1.0)



def _fronts(slip, x, util):
    """Outer ends (L1, L2) of the slipping zone per pair, interpolated between nodes.

    ``util`` is tau/(mu q c) (+-1 on slipping nodes).  Taken with the sign of the slip at the
    front, the stuck-side utilisation is extrapolated linearly from the two stuck nodes next
    to the front to 1, and the result kept between the last stuck and the first slipping node.
    """
    P, n1 = slip.shape
    L = x[-1]
    any_slip = slip.any(axis=1)
    i1 = np.argmax(slip, axis=1)  # first slipping node
    i2 = n1 - 1 - np.argmax(slip[:, ::-1], axis=1)  # last slipping node
    rows = np.arange(P)
    L1 = np.full(P, L)
    L2 = np.full(P, L)
    # left front: between i1 - 1 (stuck) and i1
    j = np.clip(i1 - 1, 0, n1 - 1)
    jj = np.clip(i1 - 2, 0, n1 - 1)
    sgn = np.sign(util[rows, i1])
    r1, r0 = sgn * util[rows, j], sgn * util[rows, jj]
    h = x[1] - x[0]
    with np.errstate(all="ignore"):
        dx = np.where((i1 >= 2) & (r1 > r0), (1.0 - r1) / (r1 - r0) * h, 0.5 * h)
    left = np.where(i1 == 0, 0.0, x[j] + np.clip(dx, 0.0, h))
    L1 = np.where(any_slip, left, L)
    # right front: between i2 (slipping) and i2 + 1 (stuck)
    j = np.clip(i2 + 1, 0, n1 - 1)
    jj = np.clip(i2 + 2, 0, n1 - 1)
    sgn = np.sign(util[rows, i2])
    r1, r0 = sgn * util[rows, j], sgn * util[rows, jj]
    with np.errstate(all="ignore"):
        dx = np.where((i2 <= n1 - 3) & (r1 > r0), (1.0 - r1) / (r1 - r0) * h, 0.5 * h)
    right = np.where(i2 == n1 - 1, L, x[j] - np.clip(dx, 0.0, h))
    L2 = np.where(any_slip, right, L)
    return L1, L2


def _is_count(v: object) -> bool:
    """Whether ``v`` is an integer (or an integral float), not a bool or a string."""
    try:
        _count("v", v, -2**62)
    except ValueError:
        return False
    return True


def _multiple_of_4(v: object) -> bool:
    """Whether ``v`` is an integer >= 8 that 4 divides (``steps_per_cycle``)."""
    return _is_count(v) and v >= 8 and int(v) % 4 == 0


class NumericalMicroslip(ContactElement):
    """Microslip bar of Eq. 30 discretised in space (``cells`` linear elements) and time.

    ``NumericalMicroslip(bar, UniformLoad(N=100.0), cells=200)``.  Keyword options:
    ``steps_per_cycle`` (theta steps per cycle, a multiple of 4; default 512 quasi-static and
    dynamic), ``quasi_static`` (None: quasi-static exactly when omega == 0),
    ``steady_tol`` (relative cycle-to-cycle change of the force history, default 1e-6),
    ``max_cycles`` (default 8 quasi-static, 30 dynamic), ``ramp_cycles`` (dynamic start-up,
    default 2), ``shooting`` (Newton on the one-cycle map, default True), ``rho_inf``
    (generalized-alpha spectral radius, default 0.9; 1 is Newmark average acceleration).
    Also: ``simulate(a, omega)`` (the run as a ``SimulationResult``), ``force_history(x)``
    (quasi-static force for a displacement history), ``natural_frequencies``, ``omega_c``.
    See the module docstring for the scheme.  ``fourier``'s ``rtol`` can only tighten the
    steady-state tolerance; the accuracy is set by the discretisation (``docs/validation.md``
    gives its error: about 1e-5 k* a at the defaults).

    Parameters
    ----------
    bar : Bar
        The damper bar.
    load : UniformLoad or QuadraticLoad
        Normal load, >= 0 everywhere; bound to ``bar.L``.
    cells : int, optional
        Linear elements along the bar, >= 2.  Default 200.
    steps_per_cycle : int, optional
        Time steps per cycle, a multiple of 4, >= 8.  Default 512.
    quasi_static : bool or None, optional
        Drop inertia; None (default): exactly when omega == 0.
    steady_tol : float, optional
        Relative cycle-to-cycle change of the force history that counts as steady.
        Default 1e-6.
    max_cycles : int, optional
        Cycles before giving up, >= 2.  Default 8 quasi-static, 30 dynamic.
    ramp_cycles : float, optional
        Cycles of dynamic start-up ramp, >= 0 and at most the dynamic budget ``max_cycles``.  Default 2.
    shooting : bool, optional
        Newton on the one-cycle map to reach the steady state.  Default True.
    rho_inf : float, optional
        Spectral radius at infinity of the generalized-alpha scheme, in [0, 1].  Default 0.9.

    Raises
    ------
    ValueError
        If an option is out of its range or the load is negative somewhere, naming it.

    See Also
    --------
    TwoRegionMicroslip, ThreeRegionMicroslip : the single-mode analytic elements it checks.
    hbm.simulate_blade : the blade integrated in time with this bar.

    Notes
    -----
    Eq. 30 with every mode: the bar in ``cells`` linear elements with lumped masses, a Jenkins
    element (stiffness k per length, slider mu q per length) at every node, integrated over
    cycles of ``x = a sin(theta)`` with an exact return map per node until the force history
    is steady; f_s, f_c are the Fourier integrals of the last cycle.

    References
    ----------
    .. [1] Cigeroglu, Lu & Menq (2006), Eq. 30 and Section 3.5 (Fig. 19).

    Examples
    --------
    At omega = 0 the single-mode solution is exact, so the discretised bar converges to it:

    >>> from contact_models import Bar, UniformLoad, NumericalMicroslip, TwoRegionMicroslip
    >>> bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    >>> num = NumericalMicroslip(bar, UniformLoad(N=100.0), cells=40)
    >>> f_s, f_c = num.fourier(1.5e-6)
    >>> g_s, g_c = TwoRegionMicroslip(bar, UniformLoad(N=100.0)).fourier(1.5e-6)
    >>> round(float(f_s), 2), round(float(g_s), 2)       # N
    (52.78, 52.78)
    >>> float(abs(f_c - g_c)) / (bar.k_star * 1.5e-6) < 1e-4     # error measured in k* a
    True
    """

    def __init__(self, bar: Bar, load: UniformLoad | QuadraticLoad, cells: int = 200, *,
                 steps_per_cycle: int | None = None, quasi_static: bool | None = None,
                 steady_tol: float = STEADY_TOL, max_cycles: int | None = None,
                 ramp_cycles: float = RAMP_CYCLES, shooting: bool = True, rho_inf: float = RHO_INF) -> None:
        if not isinstance(bar, Bar):
            raise ValueError(f"bar must be a contact_models.Bar, got bar={bar!r}")
        cells = _count("cells", cells, 2, MAX_CELLS, "contact_models.numerical.MAX_CELLS")
        if steps_per_cycle is not None and not _multiple_of_4(steps_per_cycle):
            raise ValueError(f"steps_per_cycle must be a multiple of 4 and >= 8, got steps_per_cycle={steps_per_cycle!r}")
        if not (quasi_static is None or quasi_static is True or quasi_static is False or isinstance(quasi_static, np.bool_)):
            raise ValueError(f"quasi_static must be None, True or False, got quasi_static={quasi_static!r}")
        if max_cycles is not None:
            _count("max_cycles", max_cycles, 2)
        self.bar = bar
        self.load = bound_load(load, bar.L)
        self.cells = int(cells)
        self.steps_per_cycle = None if steps_per_cycle is None else int(steps_per_cycle)
        self.quasi_static = None if quasi_static is None else bool(quasi_static)
        self.steady_tol = relative("steady_tol", steady_tol)
        self.max_cycles = None if max_cycles is None else int(max_cycles)
        self.ramp_cycles = nonnegative("ramp_cycles", ramp_cycles)
        budget = MAX_CYCLES_DYNAMIC if self.max_cycles is None else self.max_cycles
        if self.ramp_cycles > budget:  # the ramp runs before the budget, which counts the cycles after it
            raise ValueError(f"ramp_cycles must be <= max_cycles (the dynamic run's budget of cycles after the ramp, "
                             f"default {MAX_CYCLES_DYNAMIC}), got ramp_cycles={ramp_cycles!r}, max_cycles={max_cycles!r}")
        self.shooting = flag("shooting", shooting)  # (an array's "in (True, False)" was numpy's ambiguous truth)
        self.rho_inf = finite("rho_inf", rho_inf)
        if not 0.0 <= self.rho_inf <= 1.0:
            raise ValueError(f"rho_inf must be in [0, 1], got rho_inf={rho_inf!r}")
        self._disc = _Discretisation(bar, self.load, self.cells)

    def __repr__(self) -> str:
        return f"NumericalMicroslip({self.bar!r}, {self.load!r}, cells={self.cells})"

    # ------------------------------------------------------------ extras
    @property
    def nodes(self) -> NDArray[np.float64]:
        """Node positions x_i (m)."""
        return self._disc.x.copy()

    def natural_frequencies(self, count: int = 1) -> NDArray[np.float64]:
        """Lowest ``count`` natural frequencies (rad/s) of the discretised stuck bar, tip free."""
        d = self._disc
        if not (_is_count(count) and 1 <= count <= d.m.size):
            raise ValueError(f"count must be an integer in 1..{d.m.size} (the nodes of cells={self.cells}), "
                             f"got count={count!r}")
        s = 1.0 / np.sqrt(d.m)
        diag = (d.kdiag + d.kc) * s * s
        off = d.off * s[:-1] * s[1:]
        from scipy.linalg import eigh_tridiagonal  # lazily: import contact_models stays light

        w2 = eigh_tridiagonal(diag, off, eigvals_only=True, select="i", select_range=(0, count - 1))
        return np.sqrt(w2)

    def nodal_data(self) -> NodalData:
        """Copies of the discretisation's nodal arrays, for integrators that couple the bar to
        other degrees of freedom (``hbm.reference.transient``)."""
        d = self._disc
        return NodalData(x=d.x.copy(), mass=d.m.copy(), stiffness_diag=d.kdiag.copy(),
                         stiffness_off=float(d.off), shear_stiffness=d.kc.copy(), slip_force=d.p.copy())

    @property
    def omega_c(self) -> float:
        """First natural frequency of the discretised stuck bar with x = L free."""
        return float(self.natural_frequencies(1)[0])

    def stuck_shape(self, omega: float = 0.0) -> NDArray[np.float64]:
        """Nodal u(x_i)/u(L) of the discretised stuck bar at frequency omega."""
        return self._disc.stuck_solution(nonnegative("omega", omega))[0]

    def _check_mode(self, omega: float) -> bool:
        """True for a quasi-static run at omega; a dynamic run needs omega > 0."""
        qs = omega == 0.0 if self.quasi_static is None else self.quasi_static
        if not qs and omega == 0.0:
            raise ValueError("omega must be > 0 for a dynamic run (quasi_static=False), got omega=0.0")
        return qs

    def simulate(self, a: float, omega: float = 0.0, *, steady_tol: float | None = None) -> SimulationResult:
        """Integrate from rest to the periodic steady state for ``x = a sin(omega t)``."""
        a = nonnegative("a", a)
        omega = nonnegative("omega", omega)
        qs = self._check_mode(omega)
        if not qs:
            self._disc.check_wave(omega)
        tol = self.steady_tol if steady_tol is None else relative("steady_tol", steady_tol)
        return self._run(np.array([a]), np.array([omega]), qs, tol)[0]

    def force_history(self, x: ArrayLike) -> NDArray[np.float64]:
        """Quasi-static tip force for a tip-displacement history ``x`` (from rest, x[0] first)."""
        x = np.asarray(x, dtype=float)
        if x.ndim != 1 or not np.all(np.isfinite(x)):
            raise ValueError(f"x must be a finite 1-d array, got x with shape {x.shape}")
        batch = _Batch(self._disc, np.ones(1), np.zeros(1), True, 4, 0.0)
        return np.array([batch.step(np.array([xi]))[0] for xi in x])

    def first_judged_cycle(self, omega: float) -> int:
        """The first cycle after the ramp (0-based) a dynamic run at omega may call steady: the one whose
        previous cycle starts after a wave front from the start of the run has travelled to x = 0 and back,
        2 L / c with c = sqrt(E / rho) (no signal is faster in the bar).  Before that the tip force is the
        outgoing wave's alone (about rho c A times the tip velocity far above the cut-off), periodic cycle to
        cycle whatever the rest of the bar does."""
        trip = 2.0 * self.bar.L * omega / (2.0 * math.pi * math.sqrt(self.bar.E / self.bar.rho))  # in cycles
        return max(0, int(math.ceil(trip)) - int(math.ceil(self.ramp_cycles)) + 1)

    def _resolution_warnings(self, omegas) -> None:
        """One AccuracyWarning for the dynamic frequencies of a call where the mesh's stuck stiffness is further
        than ``WAVE_TOL`` from the continuous bar's (``numerics.fe_bar``'s ``stuck_error``): the cells do not
        resolve the wave there, and the answer carries at least that error."""
        errs = [(self._disc.stuck_error(w), w) for w in omegas if w > 0.0]
        worst = max(errs, default=(0.0, 0.0))
        if worst[0] > WAVE_TOL:
            rel, w = worst
            need = min(MAX_CELLS, int(math.ceil(self.cells * math.sqrt(rel / WAVE_TOL))) if math.isfinite(rel) else MAX_CELLS)
            warnings.warn(f"NumericalMicroslip: cells={self.cells} do not resolve the wave at omega={w:.6g} rad/s: "
                          f"the stuck bar's stiffness is off the continuous bar's by {rel:.3g} (relative to "
                          f"max(|K|, 0.01 k*)), and the answer by at least as much; the error falls as cells^-2, so "
                          f"about {need} cells bring it below {WAVE_TOL:g}", AccuracyWarning, stacklevel=4)

    # ------------------------------------------------------------ the run
    def _settings(self, qs: bool):
        steps = self.steps_per_cycle or (STEPS_QUASI_STATIC if qs else STEPS_DYNAMIC)
        max_cycles = self.max_cycles or (MAX_CYCLES_QUASI_STATIC if qs else MAX_CYCLES_DYNAMIC)
        return steps, max_cycles

    def _run(self, a, omega, qs: bool, tol: float):
        if qs:
            return self._run_quasi_static(a, tol)
        return [self._run_dynamic(float(ai), float(wi), tol) for ai, wi in zip(a, omega)]

    def _cycle(self, batch, steps, tangent=None):
        """One cycle: tip force, L1, L2 per pair and step, the nodes of pair 0 that slipped
        at some step, and the carried tangent (dynamic, one pair)."""
        d = self._disc
        P = batch.a.size
        f = np.empty((P, steps))
        slip = np.empty((steps, P, d.n + 1), bool)
        util = np.empty((steps, P, d.n + 1))
        for k in range(steps):
            f[:, k] = batch.step()
            if tangent is not None:
                tangent = batch.tangent_step(tangent)
            slip[k] = batch.slip
            util[k] = batch.u - batch.z
        ever = np.any(slip[:, 0], axis=0)
        # stick/slip map: signed utilisation tau/(mu q c) (+-1 on slipping nodes)
        with np.errstate(divide="ignore", invalid="ignore"):
            util = np.where(d.p > 0, np.clip(d.kc * util / d.p, -1.0, 1.0), np.sign(util))
        L1, L2 = _fronts(slip.reshape(-1, d.n + 1), d.x, util.reshape(-1, d.n + 1))
        L1, L2 = L1.reshape(steps, P).T, L2.reshape(steps, P).T
        return f, L1, L2, ever, tangent

    def _run_quasi_static(self, a, tol):
        """All amplitudes in lockstep: load 0 -> a (a quarter cycle), then cycle from x = a."""
        steps, max_cycles = self._settings(True)
        batch = _Batch(self._disc, a, np.zeros_like(a), True, steps, 0.0)
        results: list = [None] * a.size
        history = [[] for _ in range(a.size)]
        active = np.arange(a.size)
        for _ in range(steps // 4):
            batch.step()
        prev = None
        for cycle in range(max_cycles):
            f, L1, L2, _, _ = self._cycle(batch, steps)
            change = _change(f, prev)
            done = change <= tol
            last = cycle == max_cycles - 1
            for j, p in enumerate(active):
                history[p].append(change[j])
                if done[j] or last:
                    results[p] = self._result(batch, j, f[j], L1[j], L2[j], cycle + 1, bool(done[j]), history[p])
            keep = np.flatnonzero(~done)
            if last or keep.size == 0:
                break
            if keep.size < active.size:
                batch.keep(keep)
                active, f = active[keep], f[keep]
            prev = f
        return results

    def _run_dynamic(self, a, omega, tol):
        """Ramp, then cycles.  With ``shooting``, a cycle may also carry the derivative of the
        one-cycle map s -> Phi(s) (state s = u, v, z at the cycle start; the map is piecewise
        affine, so the carried derivative is exact) and the cycle-start state then takes a
        Newton step towards the periodic orbit Phi(s) = s, inside a trust region on the scaled
        residual max|Phi(s) - s| (u, z scaled by a, v and acceleration by a w, a w^2 with w the
        larger of omega and omega_c).  Steadiness is judged only
        between consecutive, uninterrupted cycles (the stated criterion)."""
        steps, max_cycles = self._settings(False)
        d, n = self._disc, self._disc.n
        batch = _Batch(d, np.array([a]), np.array([omega]), False, steps, self.ramp_cycles, self.rho_inf)
        for _ in range(int(math.ceil(self.ramp_cycles)) * steps):
            batch.step()
        # scales of the state: a, and for v and acceleration the faster of the drive and the
        # bar's first mode (at low omega the bar's own modes carry the velocity and acceleration)
        w_ref = max(omega, self.omega_c)
        scale = np.concatenate([np.full(n, a), np.full(n, a * w_ref), np.full(n, a * w_ref**2), np.full(n + 1, a)])

        def state():
            return np.concatenate([batch.u[0, :n], batch.v[0, :n], batch.acc[0, :n], batch.z[0]])

        def jump(s):
            batch.set_state(s[None, :n], s[None, n:2 * n], s[None, 2 * n:3 * n], s[None, 3 * n:])

        # the tip cannot hear the far end before a wave front (speed c = sqrt(E/rho)) has gone there and back:
        # until then consecutive cycles of the tip force agree while the bar is far from steady, so no cycle
        # starting before that is judged steady (far above the cut-off this is many cycles)
        judge_from = self.first_judged_cycle(omega)
        history: list = []
        prev = None  # force of the previous cycle if the run continued from it uninterrupted
        zset = None  # sliders carried as unknowns (those that slipped in an earlier cycle)
        newton = self.shooting
        base = None  # last accepted shooting point: (s0, scaled residual, Newton step)
        radius = np.inf  # trust radius on the scaled step
        for cycle in range(max_cycles):
            s0 = state()
            tangent = _unit_tangent(d, zset) if newton and zset is not None else None
            f, L1, L2, ever, T = self._cycle(batch, steps, tangent)
            change = float(_change(f, prev)[0])
            history.append(change)
            if change <= tol and cycle >= judge_from:
                break
            prev = f
            if T is None:  # a plain cycle
                zset = ever if zset is None else zset | ever
                newton = self.shooting
                continue
            s1 = state()
            rn = float(np.max(np.abs(s1 - s0) / scale))
            if base is not None and rn > (1.0 - 1e-4) * base[1]:
                # the trial did not reduce the residual: shrink the region, retry from the base;
                # at a base already periodic to within tol, go back to it and check plainly
                s_b, rn_b, step_b = base
                if rn_b <= tol:
                    jump(s_b)
                    newton, base = False, None
                else:
                    radius = 0.25 * min(radius, float(np.max(np.abs(step_b) / scale)))
                    jump(s_b + step_b * min(1.0, radius / float(np.max(np.abs(step_b) / scale))))
                prev = None
                continue
            if rn <= SHOOT_SKIP * tol:
                newton, base = False, None  # periodic to well below tol: a plain cycle checks it
                continue
            if np.any(ever & ~zset):  # a slider outside the unknowns moved: widen, go on from here
                zset = zset | ever
                base = None
                continue
            # Newton step on Phi(s) - s over u, v and the sliders that moved in the cycle
            cols = np.concatenate([np.arange(3 * n), 3 * n + np.flatnonzero(ever[zset])])
            rows = np.concatenate([np.arange(3 * n), 3 * n + np.flatnonzero(ever)])
            sc = scale[rows]
            J = np.vstack([T[0], T[1], T[2], T[3][ever]])[:, cols] * (1.0 / sc)[:, None] * sc[None, :]
            J -= np.eye(rows.size)
            r = (s1 - s0)[rows] / sc
            try:
                delta = np.linalg.solve(J, -r)
            except np.linalg.LinAlgError:
                delta = np.linalg.lstsq(J, -r, rcond=None)[0]
            step = np.zeros_like(s0)
            step[rows] = delta * sc
            if base is not None:
                radius = max(radius, 2.0 * float(np.max(np.abs(base[2]) / scale)))
            base = (s0, rn, step)
            norm = float(np.max(np.abs(delta)))
            jump(s0 + step * min(1.0, radius / norm if norm > 0 else 1.0))
            prev = None
        return self._result(batch, 0, f[0], L1[0], L2[0], cycle + 1, change <= tol and cycle >= judge_from, history)

    def _result(self, batch, j, f, L1, L2, cycles, converged, history):
        a, omega = float(batch.a[j]), float(batch.omega[j])
        steps = f.size
        # samples sit at theta_k = theta_start + (k + 1) dtheta: roll onto theta = 2 pi k / steps
        shift = (batch.count - steps + 1) % steps  # the cycle's first sample is at this grid index
        f, L1, L2 = (np.roll(v, shift) for v in (f, L1, L2))
        theta = np.arange(steps) * batch.dtheta
        fs = 2.0 / steps * float(np.sum(f * np.sin(theta)))
        fc = 2.0 / steps * float(np.sum(f * np.cos(theta)))
        change = float(history[-1])
        msg = "steady" if converged else f"not steady after {cycles} cycles: change {change:.3g} > tolerance"
        return SimulationResult(a=a, omega=omega, quasi_static=batch.qs, theta=theta, x=a * np.sin(theta), f=f,
                                L1=L1, L2=L2, f_s=fs, f_c=fc, cycles=cycles, converged=converged,
                                change=change, newton_iterations=batch.newton, steps=steps,
                                message=msg, history=np.array(history))

    # ------------------------------------------------------------ interface
    def _stuck_stiffness(self, omega):
        return float(self._disc.stuck_solution(omega)[1])

    def _slip_amplitude(self, omega):
        """Smallest tip amplitude at which a node's elastic force k c_i |u_i| reaches mu q_i c_i."""
        return self._disc.slip_amplitude(omega)

    def _fourier(self, a, omega, rtol):
        fs = np.empty_like(a)
        fc = np.zeros_like(a)
        run = {True: [], False: []}
        for w in np.unique(omega):
            qs = self._check_mode(float(w))
            w_eff = 0.0 if qs else float(w)  # the quasi-static bar has no inertia at any omega
            sel = np.flatnonzero(omega == w)
            stuck = a[sel] <= self._slip_amplitude(w_eff)
            fs[sel[stuck]] = self._stuck_stiffness(w_eff) * a[sel[stuck]]  # the exact linear steady state
            run[qs].extend(sel[~stuck])
        self._resolution_warnings([float(w) for w in np.unique(omega) if not self._check_mode(float(w))])
        unsteady = []
        for qs, idx in run.items():
            if idx:
                idx = np.array(idx)
                for i, r in zip(idx, self._run(a[idx], omega[idx], qs, min(self.steady_tol, rtol))):
                    fs[i], fc[i] = r.f_s, r.f_c
                    if not r.converged:
                        unsteady.append(r)
        if unsteady:  # the last cycle is not the steady state: its change is the error it states
            def last(r):  # the last change between uninterrupted cycles (a shooting jump's is inf)
                h = np.asarray(r.history, dtype=float)
                h = h[np.isfinite(h)]
                return float(h[-1]) if h.size else math.inf

            r = max(unsteady, key=last)
            change = (f"the last two uninterrupted cycles' forces differed by {last(r):.3g} of the peak"
                      if math.isfinite(last(r)) else "no two uninterrupted cycles were compared")
            first = self.first_judged_cycle(r.omega)
            if r.cycles <= first:
                change = (f"a wave front needs {first} cycles after the ramp to cross the bar and back, and no cycle "
                          f"before that can be judged steady")
            warnings.warn(f"NumericalMicroslip: not steady at omega={r.omega:.6g} rad/s, a={r.a:.4g} m after "
                          f"{r.cycles} cycles (max_cycles): {change} (steady_tol {self.steady_tol:g}); "
                          f"{len(unsteady)} point(s) of this call; raise max_cycles", AccuracyWarning, stacklevel=3)
        return fs, fc

    def _hysteresis(self, a, omega, n):
        theta = np.linspace(-0.5 * np.pi, 1.5 * np.pi, n)
        x = a * np.sin(theta)
        qs = self._check_mode(omega)
        w_eff = 0.0 if qs else omega
        if a <= self._slip_amplitude(w_eff):
            return x, self._stuck_stiffness(w_eff) * x
        r = self._run(np.array([a]), np.array([omega]), qs, self.steady_tol)[0]
        return x, r.force_at(theta)
