"""The blade and the discretised microslip bar integrated together in time.

The independent check of the harmonic-balance FRF: no harmonic truncation, no single-mode
assumption on the damper.  ``simulate_blade(blade, damper, omega)`` integrates

    m x'' + c x' + k x + f_d = F cos(omega t),

with ``f_d`` the force of a ``contact_models.NumericalMicroslip`` bar whose driven end x = L
moves with the blade (u(L, t) = x(t)), from rest to the periodic steady state, and returns the
last cycle with the first-harmonic coefficients ``x_c``, ``x_s`` in the layout of ``hbm``
(x ~ x_c cos(omega t) + x_s sin(omega t)).

Model.  The bar's finite-element nodes 0 .. n (``NumericalMicroslip.nodal_data``) plus the
blade lumped onto node n: node n carries mass m_n + m, stiffness S/h + k, the blade's dashpot
c and the force F cos(omega t); every node carries its Jenkins element.  Node n's equation is
the blade's, with f_d = (S/h)(u_n - u_{n-1}) + tau_n + m_n u_n'' (the driven-end reaction of
``NumericalMicroslip``).  All n + 1 nodes are free.

Time: the generalized-alpha scheme of ``NumericalMicroslip`` (``GeneralizedAlpha``, spectral radius
``damper.rho_inf``), with the damping term C v at the alpha_f point, and each step's piecewise
linear system A u + tau(u) = r (A = K + c_m M + c_c C, tridiagonal) solved exactly by
semismooth Newton with the exact return mapping of every Jenkins element, guarded by an Armijo
line search on its convex potential.  The force is raised from 0 by a quintic smooth step over
``ramp_cycles`` cycles.

Steady state: the run stops at the first cycle whose blade displacement differs from the
previous cycle's by at most ``steady_tol`` times its peak,

    max_theta |x_j(theta) - x_{j-1}(theta)| <= steady_tol * max_theta |x_j(theta)|,

or after ``max_cycles`` (``converged`` False, ``message`` says so).  The blade's transient
decays geometrically by a factor r per cycle; with r estimated from the last two changes the
distance of the last cycle from the periodic orbit is about change r / (1 - r), reported as
``distance``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from contact_models.numerical import NEWTON_RTOL, GeneralizedAlpha, NumericalMicroslip, return_map, solve_step

from .._validation import count, positive, relative, within_precision
from ..blade import Blade

#: Default theta steps per cycle (a multiple of 4), steady tolerance, cycle budget and ramp.
STEPS = 256
STEADY_TOL = 1e-6
MAX_CYCLES = 1000
RAMP_CYCLES = 2


@dataclass
class BladeSimulation:
    """Last (steady) cycle of a blade + bar run, theta = omega t in [0, 2 pi) on ``steps`` points.

    ``x``: blade displacement (m); ``f``: damper force on the blade (N); ``x_c``, ``x_s``: first
    harmonic of x in cos/sin(omega t); ``amplitude = hypot(x_c, x_s)`` (the FRF's quantity);
    ``cycles``: cycles after the ramp; ``change``: the last relative cycle-to-cycle change of x
    (``history`` per cycle); ``distance``: the estimated relative distance of the last cycle
    from the periodic orbit (``change r / (1 - r)``, r the last ratio of changes; inf when r
    >= 1).

    Attributes
    ----------
    omega : float
        Excitation frequency (rad/s).
    theta : ndarray
        Phase ``omega t`` of each sample of the last cycle (rad), ``steps`` values in [0, 2 pi).
    x : ndarray
        Blade displacement at ``theta`` (m).
    f : ndarray
        Damper force on the blade at ``theta`` (N).
    x_c, x_s : float
        First harmonic of ``x`` (m): ``x_c cos(omega t) + x_s sin(omega t)``.
    cycles : int
        Cycles computed after the ramp.
    converged : bool
        Whether the cycle-to-cycle change fell to the tolerance (also ``success``).
    change : float
        The last relative cycle-to-cycle change of ``x`` (inf before two cycles).
    distance : float
        Estimated relative distance of the last cycle from the periodic orbit (inf when the
        changes do not shrink).
    newton_iterations : int
        Newton iterations of the time integration, in total.
    steps : int
        Time steps per cycle.
    message : str
        ``"steady"``, or why not.
    history : ndarray or None
        The relative change of each cycle from the one before.
    """

    omega: float
    theta: np.ndarray
    x: np.ndarray
    f: np.ndarray
    x_c: float
    x_s: float
    cycles: int
    converged: bool
    change: float
    distance: float
    newton_iterations: int
    steps: int
    message: str = ""
    history: NDArray[np.float64] | None = field(default=None, repr=False)

    @property
    def amplitude(self) -> float:
        return math.hypot(self.x_c, self.x_s)

    @property
    def phase(self) -> float:
        """phi with x ~ a cos(omega t - phi) (hbm's convention)."""
        return math.atan2(self.x_s, self.x_c)

    @property
    def success(self) -> bool:
        return self.converged

    def harmonic(self, h: int) -> float:
        """Amplitude of the h-th harmonic of x (h >= 1)."""
        h = count("h", h, 1)
        return 2.0 / self.steps * float(abs(np.sum(self.x * np.exp(-1j * h * self.theta))))

    def to_csv(self, path: str | Path) -> None:
        """Write theta, x, f of the steady cycle."""
        np.savetxt(path, np.column_stack([self.theta, self.x, self.f]), delimiter=",", header="theta,x,f",
                   comments="")


def simulate_blade(blade: Blade, damper: NumericalMicroslip, omega: float, *, steps_per_cycle: int = STEPS,
                   steady_tol: float = STEADY_TOL, max_cycles: int = MAX_CYCLES,
                   ramp_cycles: int = RAMP_CYCLES) -> BladeSimulation:
    """Integrate blade + discretised bar at ``omega`` (rad/s) from rest to the steady state.

    ``damper`` is a ``NumericalMicroslip`` (its ``cells`` and ``rho_inf`` are used; its own
    run settings are not).  See the module docstring for the scheme and the criterion.

    Parameters
    ----------
    blade : Blade
        The blade; its force ``F cos(omega t)`` drives the system.
    damper : contact_models.NumericalMicroslip
        The discretised bar, whose driven end x = L moves with the blade.
    omega : float
        Excitation frequency (rad/s), > 0.
    steps_per_cycle : int, optional
        Time steps per cycle, a multiple of 4, >= 8.  Default 256.
    steady_tol : float, optional
        The run stops at the first cycle whose blade displacement differs from the previous
        cycle's by at most ``steady_tol`` times its peak, in (0, 1).  Default 1e-6.
    max_cycles : int, optional
        Cycle budget after the ramp (``BladeSimulation.cycles``), >= 2.  Default 1000.
    ramp_cycles : int, optional
        Cycles over which the force is raised from 0 (a quintic smooth step), 0 to ``max_cycles``:
        the ramp is not in the budget, so a longer one would bound the run by nothing.  Default 2.

    Returns
    -------
    BladeSimulation
        The last cycle: ``x``, ``f``, its first harmonic ``x_c``, ``x_s`` and ``amplitude``,
        ``converged`` and ``message``; a run out of cycles keeps its last cycle.

    Raises
    ------
    ValueError
        If ``blade`` or ``damper`` has the wrong type or an option is out of range, naming it.

    See Also
    --------
    response_at : the harmonic balance at the same frequency, which this run checks.

    Notes
    -----
    ``m x'' + c x' + k x + f_d = F cos(omega t)`` with the bar of Eq. 30 (every mode) as
    ``f_d``, integrated from rest by generalized-alpha with the exact return map of every
    Jenkins element of the bar; no harmonic truncation, no single-mode assumption.
    ``docs/validation.md`` compares it with the FRF near resonance.

    Examples
    --------
    Below slip (a well-damped blade, 30000 rad/s) the run agrees with the harmonic balance of
    the single-mode element to the discretisation error of a 20-cell bar:

    >>> from contact_models import Bar, UniformLoad, NumericalMicroslip, TwoRegionMicroslip
    >>> from hbm import Blade, response_at, simulate_blade
    >>> bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    >>> blade = Blade.from_modal(frequency=33765.0, damping_ratio=0.05, mass=0.0877, force=8.0)
    >>> run = simulate_blade(blade, NumericalMicroslip(bar, UniformLoad(N=100.0), cells=20),
    ...                      30000.0, steps_per_cycle=64)
    >>> hb = response_at(blade, TwoRegionMicroslip(bar, UniformLoad(N=100.0)), 30000.0, (1e-9, 1e-5))
    >>> run.converged, round(run.amplitude / hb.amplitude, 2)
    (True, 1.0)
    """
    if not isinstance(blade, Blade):
        raise ValueError(f"blade must be an hbm.Blade, got blade={blade!r}")
    if not isinstance(damper, NumericalMicroslip):
        raise ValueError("damper must be a contact_models.NumericalMicroslip (an element with a state to "
                         f"integrate), got damper={damper!r}")
    omega = positive("omega", omega)
    within_precision("omega", omega, omega, 1, np.array([[blade.mass]]), np.array([[blade.damping]]))
    damper.stuck_stiffness(omega)  # refuses an omega whose wave the bar's cells cannot hold (UnresolvedWave)
    try:
        steps = count("steps_per_cycle", steps_per_cycle, 8)
    except ValueError:
        steps = 1  # (not an integer >= 8: the one message below)
    if steps % 4:
        raise ValueError(f"steps_per_cycle must be a multiple of 4 and >= 8, got steps_per_cycle={steps_per_cycle!r}")
    steady_tol = relative("steady_tol", steady_tol)  # as NumericalMicroslip's own steady_tol
    max_cycles, ramp_cycles = count("max_cycles", max_cycles, 2), count("ramp_cycles", ramp_cycles, 0)
    if ramp_cycles > max_cycles:
        raise ValueError(f"ramp_cycles must be <= max_cycles (the ramp runs before the cycle budget, which counts "
                         f"the cycles after it), got ramp_cycles={ramp_cycles!r}, max_cycles={max_cycles!r}")
    run = _Coupled(blade, damper, omega, steps, ramp_cycles)
    return run.to_steady_state(steady_tol, max_cycles)


class _Coupled:
    """State and step of the blade + bar system (nodes 0 .. n free, the blade on node n)."""

    def __init__(self, blade: Blade, damper: NumericalMicroslip, omega: float, steps: int, ramp_cycles: int):
        d = damper.nodal_data()
        n1 = d.x.size
        self.omega = omega
        self.steps = steps
        self.ramp = 2.0 * math.pi * ramp_cycles
        self.force = blade.force
        self.m_tip = float(d.mass[-1])  # the bar's own lumped mass at the driven node
        self.off = d.stiffness_off
        self.kdiag = d.stiffness_diag.copy()
        self.kdiag[-1] += blade.stiffness
        self.mass = d.mass.copy()
        self.mass[-1] += blade.mass
        self.damping = np.zeros(n1)
        self.damping[-1] = blade.damping
        self.kc, self.p = d.shear_stiffness, d.slip_force
        self.scheme = GeneralizedAlpha.from_rho_inf(damper.rho_inf)
        self.dtheta = 2.0 * math.pi / steps
        self.dt = self.dtheta / omega
        self.cm = self.scheme.mass_coefficient(self.dt)
        self.cc = self.scheme.damping_coefficient(self.dt)
        self.A = self.kdiag + self.cm * self.mass + self.cc * self.damping  # diagonal of the step matrix
        self.ab = np.zeros((3, n1))
        self.ab[0, 1:] = self.off
        self.ab[2, :-1] = self.off
        self.u = np.zeros(n1)
        self.v = np.zeros(n1)
        self.acc = np.zeros(n1)
        self.z = np.zeros(n1)
        self.tau = np.zeros(n1)
        self.count = 0
        self.newton = 0
        # at rest at t = 0 under the force's initial value (0 with a ramp): M a_0 = F_0 e_n
        self.f_old = self.load(0.0)
        self.acc[-1] = self.f_old / self.mass[-1]
        self.tol_force = NEWTON_RTOL * (self.force + float(np.max(self.p)))

    def load(self, theta: float) -> float:
        if self.ramp > 0.0 and theta < self.ramp:
            r = theta / self.ramp
            return self.force * r**3 * (10.0 - 15.0 * r + 6.0 * r * r) * math.cos(theta)
        return self.force * math.cos(theta)

    def _matvec(self, u):
        g = self.kdiag * u
        g[1:] += self.off * u[:-1]
        g[:-1] += self.off * u[1:]
        return g

    def step(self) -> tuple[float, float]:
        """One theta step; returns (blade displacement, damper force on the blade)."""
        self.count += 1
        dt, ga = self.dt, self.scheme
        f_new = self.load(self.count * self.dtheta)
        pred = ga.predict(self.u, self.v, self.acc, dt)
        vpred = ga.velocity_predictor(self.v, self.acc, dt)  # C v_{n+1} = C (vpred + cc (u_{n+1} - pred))
        rhs = self.cm * self.mass * pred + self.damping * (self.cc * pred - vpred)
        if ga.alpha_f > 0.0:
            rhs -= ga.old_terms(self.mass, self.acc, self.damping * self.v + self._matvec(self.u) + self.tau)
        rhs[-1] += f_new + ga.alpha_f / (1.0 - ga.alpha_f) * self.f_old
        self.f_old = f_new
        u = self._solve(pred, rhs)  # the predictor as the Newton start
        tau, slip = return_map(u, self.z, self.kc, self.p)
        self.z = np.where(slip, u - tau / self.kc, self.z)
        acc = ga.acceleration(u, pred, dt)
        self.v = ga.velocity(self.v, self.acc, acc, dt)
        self.acc, self.u, self.tau = acc, u, tau
        fd = -self.off * (u[-1] - u[-2]) + tau[-1] + self.m_tip * acc[-1]
        return u[-1], fd

    def _solve(self, u, rhs):
        """The step's system over all n + 1 nodes (``contact_models.numerical.solve_step``)."""
        scale = np.array([[self.tol_force + NEWTON_RTOL * float(np.max(np.abs(rhs)))]])
        try:
            u, iterations = solve_step(self.ab, self.A[None], self.off, self.kc, self.p, self.z[None], rhs[None],
                                       u[None], scale)
        except FloatingPointError as exc:
            raise FloatingPointError(f"simulate_blade: {exc} at omega={self.omega!r}") from None
        self.newton += iterations
        return u[0]

    def cycle(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        x = np.empty(self.steps)
        f = np.empty(self.steps)
        for k in range(self.steps):
            x[k], f[k] = self.step()
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(f))):
            raise FloatingPointError(f"simulate_blade: non-finite state at omega={self.omega!r}")
        return x, f

    def to_steady_state(self, tol: float, max_cycles: int) -> BladeSimulation:
        for _ in range(int(round(self.ramp / (2.0 * math.pi)))):
            self.cycle()
        history: list = []
        prev = None
        for cycle in range(max_cycles):
            x, f = self.cycle()
            if prev is not None:
                history.append(float(np.max(np.abs(x - prev)) / max(np.max(np.abs(x)), 1e-300)))
                if history[-1] <= tol:
                    break
            prev = x
        converged = bool(history) and history[-1] <= tol
        change = history[-1] if history else math.inf
        r = history[-1] / history[-2] if len(history) >= 2 and history[-2] > 0 else math.inf
        distance = change * r / (1.0 - r) if r < 1.0 else math.inf
        # the cycle's samples sit at theta = (k + 1) dtheta: roll onto theta = 2 pi k / steps
        x, f = np.roll(x, 1), np.roll(f, 1)
        theta = np.arange(self.steps) * self.dtheta
        xc = 2.0 / self.steps * float(np.sum(x * np.cos(theta)))
        xs = 2.0 / self.steps * float(np.sum(x * np.sin(theta)))
        msg = "steady" if converged else f"not steady after {cycle + 1} cycles: change {change:.3g} > tolerance"
        return BladeSimulation(omega=self.omega, theta=theta, x=x, f=f, x_c=xc, x_s=xs, cycles=cycle + 1,
                               converged=converged, change=change, distance=distance,
                               newton_iterations=self.newton, steps=self.steps, message=msg,
                               history=np.array(history))
