"""The fixed-step integrator behind ``hbm.reference.shooting`` (the reference's integrator (b)).

Newmark's average acceleration (``GeneralizedAlpha.from_rho_inf(1)`` of ``contact_models``,
equilibrium at t_{n+1}) for the model of ``hbm.reference.piecewise``; each step's equation

    M a_{n+1} + C v_{n+1} + K x_{n+1} + B f(B^T x_{n+1}; z_n) + Bq k3 (Bq^T x_{n+1})^3
        = force cos(omega t_{n+1})

is solved by semismooth Newton with the exact return mapping of the sliders
(``contact_models.numerics.stepping.return_map``: backward Euler is exact for a rate-independent
slider).  Second order in the step where the motion is smooth; each stick/slip event inside a
step adds a local error of the same order, so the scheme stays second order over a period.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from contact_models.numerics.genalpha import GeneralizedAlpha
from contact_models.numerics.stepping import return_map

from .piecewise import Model

#: Newton iterations per step before giving up.
NEWTON_MAX = 50
#: Step residual accepted, relative to the force scale.
NEWTON_RTOL = 1e-14


class NewmarkIntegrator:
    """``steps`` Newmark steps per period of the forcing ``omega`` (same interface as
    ``EventIntegrator``)."""

    def __init__(self, model: Model, omega: float, steps: int) -> None:
        self.m = model
        self.omega = float(omega)
        self.period = 2.0 * np.pi / self.omega
        self.steps = int(steps)
        self.h = self.period / self.steps
        self.ga = GeneralizedAlpha.from_rho_inf(1.0)
        cm = self.ga.mass_coefficient(self.h)
        self.cd = self.ga.damping_coefficient(self.h)
        self.cm = cm
        self.lhs = cm * model.M + self.cd * model.C + model.K
        self.events = 0

    def _forces(self, x, z):
        """Internal (non-inertial, non-damping) forces and the slider forces and slip mask."""
        m = self.m
        tau, slip = return_map(x @ m.B, z, m.kt, m.fs)
        g = m.K @ x + m.B @ tau
        if m.nonlinear:
            g = g + m.cubic_force(x)
        return g, tau, slip

    def _acceleration(self, t, x, v, z):
        g, _, _ = self._forces(x, z)
        return self.m.Minv @ (self.m.force * np.cos(self.omega * t) - self.m.C @ v - g)

    def _step(self, t1, x, v, a, z):
        m, ga, h = self.m, self.ga, self.h
        pred = ga.predict(x, v, a, h)
        vpred = ga.velocity_predictor(v, a, h)
        rhs = m.force * np.cos(self.omega * t1) + m.M @ (self.cm * pred) - m.C @ (vpred - self.cd * pred)
        x1 = pred.copy()
        assumed = None
        for _ in range(NEWTON_MAX):
            u = x1 @ m.B
            tau, slip = return_map(u, z, m.kt, m.fs)
            R = self.lhs @ x1 + m.B @ tau - rhs
            J = self.lhs + (m.B * (m.kt * ~slip)) @ m.B.T
            if m.nonlinear:
                uq = x1 @ m.Bq
                R = R + (m.k3 * uq**3) @ m.Bq.T
                J = J + (m.Bq * (3.0 * m.k3 * uq**2)) @ m.Bq.T
                small = np.max(np.abs(R)) <= NEWTON_RTOL * (np.max(np.abs(self.lhs @ x1)) + np.max(np.abs(rhs)))
            else:  # piecewise linear: exact once the slip set it was solved with is reproduced
                small = assumed is not None and np.array_equal(slip, assumed)
            if small:
                break
            assumed = slip
            x1 = x1 - np.linalg.solve(J, R)
        else:
            raise FloatingPointError("Newmark step: Newton did not converge")
        tau, slip = return_map(x1 @ m.B, z, m.kt, m.fs)
        z1 = np.where(slip, x1 @ m.B - tau / m.kt, z)
        a1 = ga.acceleration(x1, pred, h)
        v1 = ga.velocity(v, a, a1, h)
        return x1, v1, a1, z1

    def period_map(self, y0: NDArray[np.float64], *,
                   record: bool = False) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
        """One period from (x, v, z) at t = 0 (sliders return-mapped first); see
        ``EventIntegrator.period_map``."""
        m, n = self.m, self.m.n
        x, v, z = y0[:n].copy(), y0[n:2 * n].copy(), y0[2 * n:].copy()
        tau, slip = return_map(x @ m.B, z, m.kt, m.fs)
        z = np.where(slip, x @ m.B - tau / m.kt, z)
        a = self._acceleration(0.0, x, v, z)
        out = np.empty((self.steps, 2 * n + m.nc)) if record else None
        for k in range(self.steps):
            if record:
                out[k] = np.concatenate([x, v, z])
            x, v, a, z = self._step((k + 1) * self.h, x, v, a, z)
        return np.concatenate([x, v, z]), out
