"""Time-domain reference for a structure with one rigid Coulomb slider to ground (tests only).

Model (n DOFs, the slider at DOF ``d`` to ground, slip force ``fs``)::

    M x'' + C x' + K x + e_d f(t) = force cos(omega t),   |f| <= fs,

the slider stuck (``x_d' = 0``, ``f`` whatever holds it) or slipping (``f = fs sign(x_d')``).  Each phase
is a smooth ODE, integrated by ``scipy.integrate.solve_ivp`` (DOP853, rtol 1e-11) up to its event,
located by the integrator's root finding on its dense output:

- slipping -> the slider's velocity ``x_d'`` reaches 0; it then sticks if the force that holds it
  there, ``f_hold = (force cos(omega t) - C x' - K x)_d`` with ``x_d'' = 0`` (M diagonal), is at most
  ``fs`` in size, and otherwise slips on in the direction of ``f_hold``;
- stuck -> ``|f_hold|`` reaches ``fs``: it slips in the direction of ``f_hold``.

The periodic state is found by marching a transient from rest and then by shooting: Newton on the
period map of ``(x, x')`` at ``t = 0`` with forward differences (scipy.optimize.fsolve).  Output: the
first-harmonic amplitude of every DOF over the periodic cycle (by quadrature on a fine uniform grid of the
dense solution) and the fraction of the period the slider is stuck.

Nothing here uses the harmonic balance: it is the independent check of its rigid-slider answers.
"""

import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import fsolve

RTOL, ATOL = 1e-11, 1e-14


class RigidSlider:
    def __init__(self, M, C, K, force, dof, fs, omega):
        self.M, self.C, self.K = (np.asarray(A, dtype=float) for A in (M, C, K))
        assert np.allclose(self.M, np.diag(np.diag(self.M)))
        self.f = np.asarray(force, dtype=float)
        self.n, self.d, self.fs, self.w = self.M.shape[0], dof, float(fs), float(omega)
        self.T = 2.0 * math.pi / self.w
        self.minv = 1.0 / np.diag(self.M)

    def hold(self, t, y):
        """The force on the slider's DOF that keeps it from accelerating (its friction force if stuck)."""
        x, v = y[:self.n], y[self.n:]
        return float((self.f * math.cos(self.w * t) - self.C @ v - self.K @ x)[self.d])

    def rhs(self, mode):
        n, d = self.n, self.d

        def f(t, y):
            x, v = y[:n], y[n:]
            r = self.f * math.cos(self.w * t) - self.C @ v - self.K @ x
            r[d] -= mode * self.fs
            a = self.minv * r
            if mode == 0:
                a[d] = 0.0
            return np.concatenate([v, a])
        return f

    def events(self, mode):
        n, d = self.n, self.d
        if mode == 0:
            def ev(t, y):
                return abs(self.hold(t, y)) - self.fs
            ev.direction = 1.0
        else:
            def ev(t, y):
                return y[n + d]
            ev.direction = -mode  # the velocity falls to 0 from the slip direction
        ev.terminal = True
        return [ev]

    def mode_at(self, t, y, after_zero_velocity=True):
        h = self.hold(t, y)
        if abs(y[self.n + self.d]) > 0.0 and not after_zero_velocity:
            return int(np.sign(y[self.n + self.d]))
        return 0 if abs(h) <= self.fs * (1 + 1e-12) else int(np.sign(h))

    def march(self, y0, t0, t1, mode, dense=False):
        """(y(t1), mode at t1, [(t, y) pieces' dense solutions], stuck time)."""
        t, y, pieces, stuck = t0, np.array(y0, dtype=float), [], 0.0
        guard = 0
        while t < t1 - 1e-14 * self.T:
            guard += 1
            assert guard < 100000
            if mode == 0:
                y[self.n + self.d] = 0.0
            sol = solve_ivp(self.rhs(mode), (t, t1), y, method="DOP853", rtol=RTOL, atol=ATOL,
                            events=self.events(mode), dense_output=dense)
            if dense:
                pieces.append((sol.t[0], sol.t[-1], sol.sol, mode))
            if mode == 0:
                stuck += sol.t[-1] - t
            t, y = sol.t[-1], sol.y[:, -1].copy()
            if sol.status == 1:  # an event
                if mode != 0:
                    y[self.n + self.d] = 0.0
                    h = self.hold(t, y)
                    mode = 0 if abs(h) <= self.fs else int(np.sign(h))
                else:
                    mode = int(np.sign(self.hold(t, y)))
        return y, mode, pieces, stuck

    def periodic(self, periods=200):
        """The periodic state (y at t = 0, mode at t = 0) by a transient then shooting."""
        y, mode = np.zeros(2 * self.n), 0
        for _ in range(periods):
            y, mode, _, _ = self.march(y, 0.0, self.T, mode)
        def gap(z):
            zz = np.array(z)
            m = self.mode_at(0.0, zz, after_zero_velocity=False)
            if m == 0:
                zz[self.n + self.d] = 0.0
            return self.march(zz, 0.0, self.T, m)[0] - zz
        z = fsolve(gap, y, xtol=1e-13)
        return z, self.mode_at(0.0, z, after_zero_velocity=False), float(np.max(np.abs(gap(z))))

    def cycle(self, z, mode, samples=4096):
        """First-harmonic amplitudes of every DOF over the cycle from (z, mode), and the stuck fraction."""
        _, _, pieces, stuck = self.march(z, 0.0, self.T, mode, dense=True)
        t = np.arange(samples) * self.T / samples
        x = np.empty((samples, self.n))
        for ta, tb, s, _ in pieces:
            sel = (t >= ta) & (t <= tb)
            x[sel] = s(t[sel])[:self.n].T
        c = 2.0 / samples * np.cos(self.w * t) @ x
        s_ = 2.0 / samples * np.sin(self.w * t) @ x
        return np.hypot(c, s_), stuck / self.T


def reference(M, C, K, force, dof, fs, omega, periods=200):
    """(first-harmonic amplitudes per DOF, stuck fraction of the period, periodicity residual)."""
    r = RigidSlider(M, C, K, force, dof, fs, omega)
    z, mode, gap = r.periodic(periods)
    amp, stuck = r.cycle(z, mode)
    return amp, stuck, gap
