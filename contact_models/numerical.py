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

or after ``max_cycles`` cycles (then ``converged`` is False and ``message`` says so).  The
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
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
from scipy.linalg import eigh_tridiagonal, solve_banded

from ._validation import nonnegative, positive
from .bar import Bar
from .base import ContactElement

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
#: Plain semismooth Newton iterations before switching to the energy line search.
NEWTON_PLAIN = 8
#: Hard limit on Newton iterations per step.
NEWTON_MAX = 60
#: Residual accepted as converged, relative to the step's force scale.
NEWTON_RTOL = 1e-12
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
    history: np.ndarray = field(default=None, repr=False)  # change per cycle

    @property
    def success(self) -> bool:
        return self.converged

    def loop(self, n: int | None = None):
        """Closed loop ``(x, f)`` from theta = -pi/2 to 3 pi/2 (x from -a back to -a)."""
        theta = np.linspace(-0.5 * np.pi, 1.5 * np.pi, n or self.theta.size + 1)
        return self.a * np.sin(theta), self.force_at(theta)

    def force_at(self, theta):
        """f at arbitrary theta (periodic linear interpolation of the steady cycle)."""
        th = np.mod(np.asarray(theta, dtype=float), 2.0 * np.pi)
        grid = np.append(self.theta, 2.0 * np.pi)
        return np.interp(th, grid, np.append(self.f, self.f[0]))

    def to_csv(self, path):
        """Write theta, x, f, L1, L2 of the steady cycle."""
        data = np.column_stack([self.theta, self.x, self.f, self.L1, self.L2])
        np.savetxt(path, data, delimiter=",", header="theta,x,f,L1,L2", comments="")

    def plot(self, ax=None):
        """Hysteresis loop f against x."""
        import matplotlib.pyplot as plt

        ax = ax if ax is not None else plt.gca()
        x, f = self.loop()
        ax.plot(x, f)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("f (N)")
        return ax


class NodalData(NamedTuple):
    """Nodal arrays of the discretised bar (n + 1 nodes, node n the driven end).

    ``mass``: lumped masses rho A c_i (kg); ``stiffness_diag``, ``stiffness_off``: the
    tridiagonal axial stiffness (N/m; the beta spring in entry 0, the driven node's diagonal
    S/h); ``shear_stiffness``, ``slip_force``: each node's Jenkins element k c_i (N/m) and
    mu q(x_i) c_i (N).
    """

    x: np.ndarray
    mass: np.ndarray
    stiffness_diag: np.ndarray
    stiffness_off: float
    shear_stiffness: np.ndarray
    slip_force: np.ndarray


class _Discretisation:
    """Nodal data of the finite-element bar (n cells, n + 1 nodes, node n driven)."""

    def __init__(self, bar: Bar, load, n: int):
        self.n = n
        self.h = bar.L / n
        self.x = np.linspace(0.0, bar.L, n + 1)
        c = np.full(n + 1, self.h)
        c[0] = c[-1] = 0.5 * self.h  # trapezoid weights
        self.c = c
        self.kc = bar.k * c  # nodal shear stiffness (N/m)
        self.p = bar.mu * np.asarray(load.q(self.x), dtype=float) * c  # nodal slip force (N)
        self.m = bar.rho * bar.A * c  # lumped mass (kg)
        self.off = -bar.EA / self.h  # off-diagonal of the stiffness matrix
        kd = np.full(n + 1, 2.0 * bar.EA / self.h)
        kd[0] = bar.EA / self.h + bar.beta
        kd[-1] = bar.EA / self.h
        self.kdiag = kd

    def stuck_solution(self, omega: float):
        """Free nodal displacements of the stuck bar for u_n = 1, and the tip reaction."""
        n = self.n
        d = self.kdiag + self.kc - omega**2 * self.m
        ab = np.zeros((3, n))
        ab[0, 1:] = self.off
        ab[1] = d[:n]
        ab[2, :-1] = self.off
        rhs = np.zeros(n)
        rhs[-1] = -self.off
        u = solve_banded((1, 1), ab, rhs)
        f = d[n] + self.off * u[-1]
        return np.append(u, 1.0), f


class _Batch:
    """P bars of the same discretisation integrated in lockstep over theta.

    State per pair: nodal u, slider positions z (post-step, tau = k c (u - z) exactly), and
    for the dynamic mode v and the acceleration.  Free unknowns are nodes 0 .. n-1; node n
    follows the drive.
    """

    def __init__(self, disc: _Discretisation, a, omega, quasi_static: bool, steps: int, ramp_cycles: float,
                 rho_inf: float = 1.0):
        self.d = disc
        self.a = np.asarray(a, dtype=float)
        self.omega = np.asarray(omega, dtype=float)
        self.qs = quasi_static
        self.steps = steps
        self.dtheta = 2.0 * np.pi / steps
        self.ramp = 0.0 if quasi_static else float(ramp_cycles) * 2.0 * np.pi
        P, n1 = self.a.size, disc.n + 1
        self.u = np.zeros((P, n1))
        self.z = np.zeros((P, n1))
        self.u_prev = np.zeros((P, n1))
        self.v = np.zeros((P, n1))
        self.acc = np.zeros((P, n1))
        self.slip = np.zeros((P, n1), bool)  # nodes that slipped in the last step
        self.count = 0  # steps taken; theta = count * dtheta
        self.newton = 0
        # generalized-alpha (Chung & Hulbert 1993).  rho_inf = 1 is Newmark average acceleration,
        # written with equilibrium at t_{n+1} (alpha_m = alpha_f = 0) so that its spurious root is
        # 0 rather than -1 (the alpha = 1/2 form carries an undamped equilibrium error).
        if rho_inf >= 1.0:
            self.am = self.af = 0.0
        else:
            self.am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0)
            self.af = rho_inf / (rho_inf + 1.0)
        self.gamma = 0.5 - self.am + self.af
        self.beta = 0.25 * (1.0 - self.am + self.af) ** 2
        if quasi_static:
            self.dt = np.zeros(P)
            self.cm = np.zeros(P)
        else:
            self.dt = self.dtheta / self.omega
            # a_{n+1} = (u_{n+1} - pred) / (beta dt^2); the step equation divided by 1 - alpha_f
            self.cm = (1.0 - self.am) / ((1.0 - self.af) * self.beta * self.dt**2)
        self._build_band()

    def _build_band(self):
        P, n = self.a.size, self.d.n
        ab = np.zeros((3, P * n))
        off = np.full(P * n, self.d.off)
        off[n - 1 :: n] = 0.0  # no coupling across blocks
        ab[0, 1:] = off[:-1]
        ab[2, :-1] = off[:-1]
        self.ab = ab
        self.base = self.d.kdiag[None, :n] + self.cm[:, None] * self.d.m[None, :n]

    def keep(self, idx):
        """Drop all pairs but ``idx``."""
        for name in ("a", "omega", "u", "z", "u_prev", "v", "acc", "slip", "cm", "dt"):
            setattr(self, name, getattr(self, name)[idx])
        self._build_band()

    # ---------------------------------------------------------------- drive
    def drive(self, theta):
        """Tip displacement, velocity and acceleration at theta (quintic amplitude ramp if dynamic)."""
        s, c = math.sin(theta), math.cos(theta)
        if self.ramp > 0.0 and theta < self.ramp:
            r_ = theta / self.ramp
            r = r_**3 * (10.0 - 15.0 * r_ + 6.0 * r_**2)
            dr = 30.0 * r_**2 * (1.0 - r_) ** 2 / self.ramp
            ddr = 60.0 * r_ * (1.0 - r_) * (1.0 - 2.0 * r_) / self.ramp**2
        else:
            r, dr, ddr = 1.0, 0.0, 0.0
        x = self.a * r * s
        vel = self.a * self.omega * (dr * s + r * c)
        # d2/dtheta2 of r sin = r'' sin + 2 r' cos - r sin, times omega^2
        acc = self.a * self.omega**2 * (ddr * s + 2.0 * dr * c - r * s)
        return x, vel, acc

    def set_state(self, u, v, acc, z):
        """Put the free nodes at (u, v, acc) and the sliders at z at the current theta (dynamic)."""
        n = self.d.n
        ut, vt, at = self.drive(self.count * self.dtheta)
        self.u = np.concatenate([u, ut[:, None]], axis=1)
        self.v = np.concatenate([v, vt[:, None]], axis=1)
        self.acc = np.concatenate([acc, at[:, None]], axis=1)
        self.z = z

    def internal_force(self, u, z):
        """K u + k c (u - z) on the free nodes (tau = k c (u - z) holds exactly after a step);
        ``u`` over all nodes, or a tangent (n + 1, m) with zero tip row."""
        d, n = self.d, self.d.n
        g = d.kdiag[:n, None] * u[:n] + d.kc[:n, None] * (u[:n] - z[:n])
        g[1:] += d.off * u[: n - 1]
        g += d.off * u[1:]
        return g

    # ---------------------------------------------------------------- step
    def step(self, ut=None):
        """Advance every pair by one theta step (or to the tip displacements ``ut``, quasi-static).

        Returns the tip force per pair; the slip mask of the step is left in ``self.slip``."""
        d, n = self.d, self.d.n
        self.count += 1
        if ut is None:
            ut, _, acc_t = self.drive(self.count * self.dtheta)
        u0 = self.u
        if self.qs:
            # linear extrapolation of the free nodes as the Newton start
            guess = 2.0 * u0[:, :n] - self.u_prev[:, :n]
            rhs = np.zeros_like(guess)
        else:
            dt = self.dt[:, None]
            pred = u0 + dt * self.v + (0.5 - self.beta) * dt * dt * self.acc  # u_{n+1} - beta dt^2 a_{n+1}
            rhs = self.cm[:, None] * d.m[None, :n] * pred[:, :n]
            if self.af > 0.0:
                # alpha-weighted old terms: alpha_m M a_n + alpha_f (K u_n + tau_n), over (1 - alpha_f)
                g0 = self.internal_force(u0.T, self.z.T).T
                rhs -= (self.am * d.m[:n] * self.acc[:, :n] + self.af * g0) / (1.0 - self.af)
            guess = u0[:, :n] + dt * self.v[:, :n] + 0.5 * dt * dt * self.acc[:, :n]
        rhs[:, -1] -= d.off * ut  # coupling of node n-1 to the driven node (old one in g0)
        u = self._solve(guess, rhs, ut)
        # commit: return mapping on every node (tip node explicit)
        full = np.concatenate([u, ut[:, None]], axis=1)
        tau, slip = return_map(full, self.z, d.kc, d.p)
        self.z = np.where(slip, full - tau / d.kc, self.z)
        self.slip = slip
        if self.qs:
            acc_new = np.zeros_like(full)
        else:
            dt = self.dt[:, None]
            acc_new = (full - pred) / (self.beta * dt * dt)
            acc_new[:, -1] = acc_t
            self.v = self.v + dt * ((1.0 - self.gamma) * self.acc + self.gamma * acc_new)
        self.acc = acc_new
        self.u_prev, self.u = self.u, full
        # tip reaction: (S/h)(u_n - u_{n-1}) + tau_n + m_n u_n''
        return -d.off * (ut - u[:, -1]) + tau[:, -1] + d.m[-1] * acc_new[:, -1]

    def tangent_step(self, T):
        """Carry the derivatives ``T = (dU, dV, dA, dZ)`` of the state through the last step.

        One pair (dynamic).  Each array has one column per direction; dU, dV, dA over the free
        nodes, dZ over all nodes.  The step is piecewise linear, so with the step's stick/slip
        set this is its exact derivative: J dU' = cm M dpred - old terms + k c [stuck] dZ,
        slipping sliders follow their node, stuck ones keep dZ; Newmark updates dV, dA.
        """
        d, n = self.d, self.d.n
        dU, dV, dA, dZ = T
        dt, cm = float(self.dt[0]), float(self.cm[0])
        slip = self.slip[0]
        stuck = ~slip[:n]
        dpred = dU + dt * dV + ((0.5 - self.beta) * dt * dt) * dA
        rhs = (cm * d.m[:n])[:, None] * dpred
        if self.af > 0.0:
            dg = self.internal_force(np.vstack([dU, np.zeros((1, dU.shape[1]))]), dZ)
            rhs -= (self.am * d.m[:n, None] * dA + self.af * dg) / (1.0 - self.af)
        rhs[stuck] += d.kc[:n][stuck, None] * dZ[:n][stuck]
        ab = self.ab.copy()
        ab[1] = self.base[0] + d.kc[:n] * stuck
        dU_new = solve_banded((1, 1), ab, rhs, overwrite_ab=True, overwrite_b=True, check_finite=False)
        dA_new = (dU_new - dpred) / (self.beta * dt * dt)
        dV_new = dV + dt * ((1.0 - self.gamma) * dA + self.gamma * dA_new)
        dZ[:n][slip[:n]] = dU_new[slip[:n]]  # in place: dZ belongs to the caller's tangent
        if slip[n]:
            dZ[n] = 0.0  # the tip slider follows the prescribed tip
        return dU_new, dV_new, dA_new, dZ

    def _solve(self, u, rhs, ut):
        """The step's system on the free nodes, all pairs at once (``solve_step``)."""
        d, n = self.d, self.d.n
        scale = NEWTON_RTOL * (np.abs(ut) * (abs(d.off) + d.kc[-1]) + np.max(d.p) + 1e-300)[:, None]
        try:
            u, iterations = solve_step(self.ab, self.base, d.off, d.kc[:n], d.p[:n], self.z[:, :n], rhs, u, scale)
        except FloatingPointError as exc:
            raise FloatingPointError(f"NumericalMicroslip: {exc}") from None
        self.newton += iterations
        return u


def _step_residual(base, off, kc, p, z, u, rhs):
    R = base * u - rhs
    R[:, 1:] += off * u[:, :-1]
    R[:, :-1] += off * u[:, 1:]
    tau, slip = return_map(u, z, kc, p)
    return R + tau, ~slip


def _step_energy(base, off, kc, p, z, u, rhs):
    """The convex potential whose gradient is the step's residual (for the line search)."""
    E = 0.5 * np.sum(base * u * u, axis=1) + off * np.sum(u[:, :-1] * u[:, 1:], axis=1) - np.sum(rhs * u, axis=1)
    e = u - z
    lim = p / kc
    quad = 0.5 * kc * e * e
    lin = p * np.abs(e) - 0.5 * p * lim
    return E + np.sum(np.where(np.abs(e) <= lim, quad, lin), axis=1)


def solve_step(ab, base, off, kc, p, z, rhs, u, scale):
    """One implicit step's piecewise linear system for P independent chains of m nodes,
    ``base * u + off * (neighbours) + tau(u) = rhs`` row by row, tau the Jenkins forces of
    stiffness ``kc``, slip force ``p`` and sliders ``z`` (return mapping), by semismooth Newton
    from ``u`` (P, m).

    The system is piecewise linear, so a pair stops when the stick/slip set it assumed is
    reproduced (then solved exactly) or its residual is below ``scale`` (P, 1); after
    ``NEWTON_PLAIN`` iterations an Armijo line search on the step's convex potential guards
    against cycling.  ``ab`` is the (3, P m) banded work matrix with the off-diagonals set
    (zero between chains); its diagonal is overwritten.  Returns (u, Newton iterations).
    """
    P, m = u.shape
    args = (base, off, kc, p, z)
    R, stuck = _step_residual(*args, u, rhs)
    assumed = None
    for it in range(NEWTON_MAX):
        small = np.all(np.abs(R) <= scale, axis=1)
        same = np.all(stuck == assumed, axis=1) if assumed is not None else np.zeros(P, bool)
        if np.all(small | same):
            return u, it
        ab[1] = (base + kc * stuck).ravel()
        delta = solve_banded((1, 1), ab, -R.ravel(), overwrite_b=True, check_finite=False).reshape(P, m)
        assumed = stuck
        if it >= NEWTON_PLAIN:  # guarded: Armijo backtracking on the convex potential, per pair
            E0 = _step_energy(*args, u, rhs)
            slope = np.sum(R * delta, axis=1)
            t = np.ones(P)
            for _ in range(40):
                bad = _step_energy(*args, u + t[:, None] * delta, rhs) > E0 + 1e-4 * t * slope
                if not np.any(bad):
                    break
                t = np.where(bad, 0.5 * t, t)
            delta = t[:, None] * delta
        u = u + delta
        R, stuck = _step_residual(*args, u, rhs)
    raise FloatingPointError("Newton did not converge in a step")


def _change(f, prev):
    """Relative cycle-to-cycle change max|f_j - f_{j-1}| / max|f_j| per pair (inf without a previous cycle)."""
    if prev is None:
        return np.full(f.shape[0], np.inf)
    peak = np.max(np.abs(f), axis=1)
    return np.max(np.abs(f - prev), axis=1) / np.where(peak > 0, peak, 1.0)


def _unit_tangent(d: _Discretisation, zset):
    """Derivatives of the cycle-start state w.r.t. u, v, acc (free nodes) and the sliders ``zset``."""
    n = d.n
    iz = np.flatnonzero(zset)
    m = 3 * n + iz.size
    dZ = np.zeros((n + 1, m))
    dZ[iz, 3 * n + np.arange(iz.size)] = 1.0
    return np.eye(n, m), np.eye(n, m, n), np.eye(n, m, 2 * n), dZ


def return_map(u, z, kc, p):
    """Exact return mapping of Jenkins elements of stiffness ``kc`` and slip force ``p``, sliders
    at ``z`` before the step, ends at ``u``: (force, slipping mask).  The slider's new position is
    ``u - force / kc`` where the mask is set."""
    t = kc * (u - z)
    slip = np.abs(t) > p
    return np.clip(t, -p, p), slip


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
    """

    def __init__(self, bar: Bar, load, cells: int = 200, *, steps_per_cycle: int | None = None,
                 quasi_static: bool | None = None, steady_tol: float = STEADY_TOL,
                 max_cycles: int | None = None, ramp_cycles: float = RAMP_CYCLES, shooting: bool = True,
                 rho_inf: float = RHO_INF):
        if not isinstance(bar, Bar):
            raise ValueError(f"bar must be a contact_models.Bar, got bar={bar!r}")
        if isinstance(cells, bool) or int(cells) != cells or cells < 2:
            raise ValueError(f"cells must be an integer >= 2, got cells={cells!r}")
        if steps_per_cycle is not None and (isinstance(steps_per_cycle, bool) or int(steps_per_cycle) != steps_per_cycle
                                            or steps_per_cycle < 8 or steps_per_cycle % 4):
            raise ValueError(f"steps_per_cycle must be a multiple of 4 and >= 8, got steps_per_cycle={steps_per_cycle!r}")
        if quasi_static not in (None, True, False):
            raise ValueError(f"quasi_static must be None, True or False, got quasi_static={quasi_static!r}")
        if max_cycles is not None and (isinstance(max_cycles, bool) or int(max_cycles) != max_cycles or max_cycles < 2):
            raise ValueError(f"max_cycles must be an integer >= 2, got max_cycles={max_cycles!r}")
        self.bar = bar
        self.load = load.on(bar.L)
        if self.load.minimum() < 0.0:
            raise ValueError(f"load must be >= 0 everywhere, got load={load!r}")
        self.cells = int(cells)
        self.steps_per_cycle = None if steps_per_cycle is None else int(steps_per_cycle)
        self.quasi_static = quasi_static
        self.steady_tol = positive("steady_tol", steady_tol)
        self.max_cycles = None if max_cycles is None else int(max_cycles)
        self.ramp_cycles = nonnegative("ramp_cycles", ramp_cycles)
        if shooting not in (True, False):
            raise ValueError(f"shooting must be True or False, got shooting={shooting!r}")
        self.shooting = bool(shooting)
        self.rho_inf = float(rho_inf)
        if not 0.0 <= self.rho_inf <= 1.0:
            raise ValueError(f"rho_inf must be in [0, 1], got rho_inf={rho_inf!r}")
        self._disc = _Discretisation(bar, self.load, self.cells)

    def __repr__(self):
        return f"NumericalMicroslip({self.bar!r}, {self.load!r}, cells={self.cells})"

    # ------------------------------------------------------------ extras
    @property
    def nodes(self) -> np.ndarray:
        """Node positions x_i (m)."""
        return self._disc.x.copy()

    def natural_frequencies(self, count: int = 1) -> np.ndarray:
        """Lowest ``count`` natural frequencies (rad/s) of the discretised stuck bar, tip free."""
        d = self._disc
        s = 1.0 / np.sqrt(d.m)
        diag = (d.kdiag + d.kc) * s * s
        off = d.off * s[:-1] * s[1:]
        w2 = eigh_tridiagonal(diag, off, eigvals_only=True, select="i", select_range=(0, count - 1))
        return np.sqrt(w2)

    def nodal_data(self) -> NodalData:
        """Copies of the discretisation's nodal arrays, for integrators that couple the bar to
        other degrees of freedom (``hbm.transient``)."""
        d = self._disc
        return NodalData(x=d.x.copy(), mass=d.m.copy(), stiffness_diag=d.kdiag.copy(),
                         stiffness_off=float(d.off), shear_stiffness=d.kc.copy(), slip_force=d.p.copy())

    @property
    def omega_c(self) -> float:
        """First natural frequency of the discretised stuck bar with x = L free."""
        return float(self.natural_frequencies(1)[0])

    def stuck_shape(self, omega=0.0) -> np.ndarray:
        """Nodal u(x_i)/u(L) of the discretised stuck bar at frequency omega."""
        return self._disc.stuck_solution(nonnegative("omega", omega))[0]

    def _check_mode(self, omega: float) -> bool:
        """True for a quasi-static run at omega; a dynamic run needs omega > 0."""
        qs = omega == 0.0 if self.quasi_static is None else self.quasi_static
        if not qs and omega == 0.0:
            raise ValueError("omega must be > 0 for a dynamic run (quasi_static=False), got omega=0.0")
        return qs

    def simulate(self, a, omega=0.0, *, steady_tol: float | None = None) -> SimulationResult:
        """Integrate from rest to the periodic steady state for ``x = a sin(omega t)``."""
        a = nonnegative("a", a)
        omega = nonnegative("omega", omega)
        qs = self._check_mode(omega)
        return self._run(np.array([a]), np.array([omega]), qs, steady_tol or self.steady_tol)[0]

    def force_history(self, x) -> np.ndarray:
        """Quasi-static tip force for a tip-displacement history ``x`` (from rest, x[0] first)."""
        x = np.asarray(x, dtype=float)
        if x.ndim != 1 or not np.all(np.isfinite(x)):
            raise ValueError(f"x must be a finite 1-d array, got x with shape {x.shape}")
        batch = _Batch(self._disc, np.ones(1), np.zeros(1), True, 4, 0.0)
        return np.array([batch.step(np.array([xi]))[0] for xi in x])

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
            if change <= tol:
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
        return self._result(batch, 0, f[0], L1[0], L2[0], cycle + 1, change <= tol, history)

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
        d = self._disc
        u, _ = d.stuck_solution(omega)
        with np.errstate(divide="ignore"):
            ratio = np.where(np.abs(u) > 0, d.p / (d.kc * np.abs(u)), np.inf)
        return float(np.min(ratio))

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
        for qs, idx in run.items():
            if idx:
                idx = np.array(idx)
                for i, r in zip(idx, self._run(a[idx], omega[idx], qs, min(self.steady_tol, rtol))):
                    fs[i], fc[i] = r.f_s, r.f_c
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
