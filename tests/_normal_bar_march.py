"""Time-domain reference for the all-mode bar with normal motion (tests only).

The same discretised bar as ``contact_models.AllModeMicroslip2D`` (``numerics.fe_bar``: lumped
mass m_i, tridiagonal stiffness K, node i a Jenkins element k c_i under the limit
mu max(0, q(x_i) c_i + kn c_i v_i(t)), node n driven) integrated by the explicit central
difference rule with step dt = T/steps:

    u_{k+1} = 2 u_k - u_{k-1} - dt^2 M^-1 (K u_k + tau_k),

tau_k the return map of each node at sample k (stick while |k c (u_k - w)| < lim_k, else
tau_k = lim_k sign, w = u_k - tau_k/(k c); lim_k = 0 is separation).  The periodic state is found
by shooting: a few periods marched from rest, then Newton on the period map z -> Phi(z) (z: the
free nodes' u_0, u_{-1} and every slider w), whose Jacobian is taken by forward differences
(the map is piecewise affine, so the differences are exact within one stick/slip pattern) and
solved in least squares.  Output: the end force samples and their Fourier coefficients.
"""

import math

import numpy as np

from contact_models.numerics.fe_bar import _Discretisation


class Marcher:
    """The bar on ``cells`` cells driven by the end motion X (coefficients, layout [X0, Xc1, Xs1,
    ...]) with normal motion V (same layout, v_i = s_i v), at omega, ``steps`` per period (or, below
    1, the step as that fraction of the explicit rule's critical step 2/omega_max)."""

    def __init__(self, bar, load, kn, shape, cells, X, V, omega, steps):
        d = self.d = _Discretisation(bar, load.on(bar.L), cells)
        self.n = cells
        self.T = 2.0 * math.pi / omega
        K = np.diag(d.kdiag) + d.off * (np.eye(cells + 1, k=1) + np.eye(cells + 1, k=-1))
        self.K = K
        lam = np.linalg.eigvalsh(np.diag(d.m ** -0.5) @ (K + np.diag(d.kc)) @ np.diag(d.m ** -0.5))
        self.dt_critical = 2.0 / math.sqrt(lam.max())
        if steps < 1:  # given as a fraction of the critical step
            steps = 4 * math.ceil(self.T / (steps * self.dt_critical) / 4)
        self.dt = self.T / steps
        self.steps = steps
        if self.dt > 0.95 * self.dt_critical:
            raise ValueError(f"steps={steps} too few for the explicit rule (dt/dt_crit = {self.dt / self.dt_critical:.3g})")
        theta = 2.0 * math.pi * np.arange(steps + 1) / steps
        H = (len(X) - 1) // 2
        h = np.arange(1, H + 1)
        c, s = np.cos(np.outer(theta, h)), np.sin(np.outer(theta, h))
        X, V = np.asarray(X, float), np.asarray(V, float)
        self.x = X[0] + c @ X[1::2] + s @ X[2::2]
        self.xdd = -omega**2 * (c @ (h**2 * X[1::2]) + s @ (h**2 * X[2::2]))
        HV = (len(V) - 1) // 2
        hv = np.arange(1, HV + 1)
        v = V[0] + np.cos(np.outer(theta, hv)) @ V[1::2] + np.sin(np.outer(theta, hv)) @ V[2::2]
        sx = shape[0] + (shape[1] - shape[0]) * d.x / bar.L
        pre = np.asarray(load.on(bar.L).q(d.x), float)[None, :] * d.c + kn * d.c * sx * v[:, None]
        self.N = np.maximum(pre, 0.0)  # (steps + 1, n + 1)
        self.lim = bar.mu * self.N
        self.s = sx

    def period(self, z, record=False):
        """March one period from the states z (3n + 1, B): returns the end states (and the end force)."""
        n, d, dt = self.n, self.d, self.dt
        u, up, w = z[:n].copy(), z[n:2 * n].copy(), z[2 * n:].copy()
        kc = d.kc[:, None]
        f_end = np.empty((self.steps, z.shape[1])) if record else None
        a = dt**2 / d.m[:n, None]
        for k in range(self.steps):
            full = np.vstack([u, np.full((1, z.shape[1]), self.x[k])])
            lim = self.lim[k][:, None]
            tau = np.clip(kc * (full - w), -lim, lim)
            w = full - tau / kc
            Ku = self.K @ full
            if record:
                f_end[k] = Ku[n] + tau[n] + d.m[n] * self.xdd[k]
            u, up = 2.0 * u - up - a * (Ku[:n] + tau[:n]), u
        return np.vstack([u, up, w]), f_end

    def periodic(self, warm=8, tol=1e-12, max_iter=20):
        """Shoot to the periodic state; returns (end force samples, residual of the period map)."""
        n = self.n
        z = np.zeros((3 * n + 1, 1))
        for _ in range(warm):
            z, _ = self.period(z)
        scale = max(float(np.max(np.abs(self.x))), 1e-300)
        eps = 1e-7 * scale
        for _ in range(max_iter):
            Z = np.hstack([z, z + eps * np.eye(3 * n + 1)])
            P, _ = self.period(Z)
            r = P[:, :1] - z
            if np.max(np.abs(r)) <= tol * scale:
                break
            J = (P[:, 1:] - P[:, :1]) / eps - np.eye(3 * n + 1)
            z = z - np.linalg.lstsq(J, r, rcond=1e-13)[0]
        _, f = self.period(z, record=True)
        P, _ = self.period(z)
        return f[:, 0], float(np.max(np.abs(P - z))) / scale

    def coefficients(self, f, H=1):
        """[F0, Fc1, Fs1, ..., FcH, FsH] of the samples f of one period (trapezoid = plain mean)."""
        theta = 2.0 * math.pi * np.arange(self.steps) / self.steps
        out = [f.mean()]
        for h in range(1, H + 1):
            out += [2.0 * np.mean(f * np.cos(h * theta)), 2.0 * np.mean(f * np.sin(h * theta))]
        return np.array(out)
