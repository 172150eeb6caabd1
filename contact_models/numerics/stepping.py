"""One implicit step of the discretised microslip bar, and P bars stepped in lockstep.

Each step's system is piecewise linear: the exact return mapping of every nodal Jenkins element
(``return_map``; backward Euler is exact for it) inside a semismooth Newton iteration on the
tridiagonal system (``solve_step``, shared with ``hbm.reference.transient``).  ``_Batch`` integrates the
bar driven at its tip, with the generalized-alpha scheme of ``_genalpha`` (dynamic) or without
mass (quasi-static), and carries the exact derivative of a step for the shooting of
``NumericalMicroslip``.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from .fe_bar import _Discretisation
from .genalpha import GeneralizedAlpha

#: Plain semismooth Newton iterations before switching to the energy line search.
NEWTON_PLAIN = 8
#: Hard limit on Newton iterations per step.
NEWTON_MAX = 60
#: Residual accepted as converged, relative to the step's force scale.
NEWTON_RTOL = 1e-12


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
        self.scheme = GeneralizedAlpha.from_rho_inf(rho_inf)
        if quasi_static:
            self.dt = np.zeros(P)
            self.cm = np.zeros(P)
        else:
            self.dt = self.dtheta / self.omega
            self.cm = self.scheme.mass_coefficient(self.dt)
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
        d, n, ga = self.d, self.d.n, self.scheme
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
            pred = ga.predict(u0, self.v, self.acc, dt)  # u_{n+1} - beta dt^2 a_{n+1}
            rhs = self.cm[:, None] * d.m[None, :n] * pred[:, :n]
            if ga.alpha_f > 0.0:
                # alpha-weighted old terms: alpha_m M a_n + alpha_f (K u_n + tau_n), over (1 - alpha_f)
                g0 = self.internal_force(u0.T, self.z.T).T
                rhs -= ga.old_terms(d.m[:n], self.acc[:, :n], g0)
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
            acc_new = ga.acceleration(full, pred, dt)
            acc_new[:, -1] = acc_t
            self.v = ga.velocity(self.v, self.acc, acc_new, dt)
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
        d, n, ga = self.d, self.d.n, self.scheme
        dU, dV, dA, dZ = T
        dt, cm = float(self.dt[0]), float(self.cm[0])
        slip = self.slip[0]
        stuck = ~slip[:n]
        dpred = ga.predict(dU, dV, dA, dt)
        rhs = (cm * d.m[:n])[:, None] * dpred
        if ga.alpha_f > 0.0:
            dg = self.internal_force(np.vstack([dU, np.zeros((1, dU.shape[1]))]), dZ)
            rhs -= ga.old_terms(d.m[:n, None], dA, dg)
        rhs[stuck] += d.kc[:n][stuck, None] * dZ[:n][stuck]
        ab = self.ab.copy()
        ab[1] = self.base[0] + d.kc[:n] * stuck
        from scipy.linalg import solve_banded  # lazily: import contact_models stays light

        dU_new = solve_banded((1, 1), ab, rhs, overwrite_ab=True, overwrite_b=True, check_finite=False)
        dA_new = ga.acceleration(dU_new, dpred, dt)
        dV_new = ga.velocity(dV, dA, dA_new, dt)
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


def solve_step(ab: NDArray[np.float64], base: NDArray[np.float64], off: float, kc: NDArray[np.float64], p: NDArray[np.float64], z: NDArray[np.float64], rhs: NDArray[np.float64], u: NDArray[np.float64],
               scale: NDArray[np.float64]) -> tuple[NDArray[np.float64], int]:
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
        from scipy.linalg import solve_banded  # lazily: import contact_models stays light

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



def _unit_tangent(d: _Discretisation, zset):
    """Derivatives of the cycle-start state w.r.t. u, v, acc (free nodes) and the sliders ``zset``."""
    n = d.n
    iz = np.flatnonzero(zset)
    m = 3 * n + iz.size
    dZ = np.zeros((n + 1, m))
    dZ[iz, 3 * n + np.arange(iz.size)] = 1.0
    return np.eye(n, m), np.eye(n, m, n), np.eye(n, m, 2 * n), dZ


def return_map(u: NDArray[np.float64], z: NDArray[np.float64], kc: NDArray[np.float64], p: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Exact return mapping of Jenkins elements of stiffness ``kc`` and slip force ``p``, sliders
    at ``z`` before the step, ends at ``u``: (force, slipping mask).  The slider's new position is
    ``u - force / kc`` where the mask is set."""
    t = kc * (u - z)
    slip = np.abs(t) > p
    return np.clip(t, -p, p), slip
