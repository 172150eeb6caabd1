"""The generalized-alpha time integrator's coefficients and update formulas, in one place.

Chung & Hulbert 1993 (J. Appl. Mech. 60, 371-375), for M a + g(u, v) = F with equilibrium
at the alpha points,

    (1 - alpha_m) M a_{n+1} + alpha_m M a_n + (1 - alpha_f) g_{n+1} + alpha_f g_n
        = (1 - alpha_f) F_{n+1} + alpha_f F_n,

and Newmark's updates with gamma, beta.  Parameters from the spectral radius at infinite
frequency rho_inf in [0, 1]:

    alpha_m = (2 rho_inf - 1) / (rho_inf + 1),  alpha_f = rho_inf / (rho_inf + 1),
    gamma = 1/2 - alpha_m + alpha_f,  beta = (1 - alpha_m + alpha_f)^2 / 4.

``rho_inf = 1`` is Newmark's average acceleration written with equilibrium at t_{n+1}
(alpha_m = alpha_f = 0), so that its spurious root is 0 rather than -1 (the alpha = 1/2 form
carries an undamped equilibrium error).  Used by ``NumericalMicroslip`` (the bar alone) and
``hbm.reference.transient`` (the blade with the bar).

Predictor-corrector form of one step of length dt:

    u~ = u_n + dt v_n + (1/2 - beta) dt^2 a_n          (``predict``)
    a_{n+1} = (u_{n+1} - u~) / (beta dt^2)              (``acceleration``)
    v_{n+1} = v_n + dt ((1 - gamma) a_n + gamma a_{n+1})  (``velocity``)

so the step equation, divided by (1 - alpha_f), is linear in u_{n+1} with the mass matrix
weighted by ``mass_coefficient(dt)`` and the damping matrix by ``damping_coefficient(dt)``;
``old_terms`` gives the alpha-weighted terms of step n moved to its right-hand side.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

#: Scalars or float arrays (broadcasting); the formulas are applied element by element.
Values = float | NDArray[np.float64]


@dataclass(frozen=True)
class GeneralizedAlpha:
    """Coefficients ``alpha_m``, ``alpha_f``, ``gamma``, ``beta`` of the scheme (see the module)."""

    alpha_m: float
    alpha_f: float
    gamma: float
    beta: float

    @classmethod
    def from_rho_inf(cls, rho_inf: float) -> GeneralizedAlpha:
        """The second-order scheme with spectral radius ``rho_inf`` at infinite frequency
        (Chung & Hulbert 1993); 1 is Newmark's average acceleration."""
        if not 0.0 <= rho_inf <= 1.0:
            raise ValueError(f"rho_inf must be in [0, 1], got rho_inf={rho_inf!r}")
        if rho_inf >= 1.0:
            am = af = 0.0
        else:
            am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0)
            af = rho_inf / (rho_inf + 1.0)
        return cls(alpha_m=am, alpha_f=af, gamma=0.5 - am + af, beta=0.25 * (1.0 - am + af) ** 2)

    def mass_coefficient(self, dt: Values) -> Values:
        """Weight of M u_{n+1} in the step equation divided by (1 - alpha_f) (dt > 0)."""
        return (1.0 - self.alpha_m) / ((1.0 - self.alpha_f) * self.beta * dt**2)

    def damping_coefficient(self, dt: Values) -> Values:
        """Weight of C u_{n+1} in the step equation divided by (1 - alpha_f)."""
        return self.gamma / (self.beta * dt)

    def old_terms(self, mass: Values, acc: Values, forces: Values) -> Values:
        """``(alpha_m M a_n + alpha_f g_n) / (1 - alpha_f)``, M diagonal (``mass``), g_n the
        internal and damping forces of step n; subtracted from the step's right-hand side."""
        return (self.alpha_m * mass * acc + self.alpha_f * forces) / (1.0 - self.alpha_f)

    def predict(self, u: Values, v: Values, acc: Values, dt: Values) -> Values:
        """The displacement predictor u~ = u_n + dt v_n + (1/2 - beta) dt^2 a_n."""
        return u + dt * v + (0.5 - self.beta) * dt * dt * acc

    def acceleration(self, u_new: Values, u_pred: Values, dt: Values) -> Values:
        """a_{n+1} = (u_{n+1} - u~) / (beta dt^2)."""
        return (u_new - u_pred) / (self.beta * dt * dt)

    def velocity(self, v: Values, acc: Values, acc_new: Values, dt: Values) -> Values:
        """v_{n+1} = v_n + dt ((1 - gamma) a_n + gamma a_{n+1})."""
        return v + dt * ((1.0 - self.gamma) * acc + self.gamma * acc_new)

    def velocity_predictor(self, v: Values, acc: Values, dt: Values) -> Values:
        """v~ = v_n + (1 - gamma) dt a_n, so that v_{n+1} = v~ + gamma dt a_{n+1} (the damping
        term of the step equation)."""
        return v + dt * (1.0 - self.gamma) * acc
