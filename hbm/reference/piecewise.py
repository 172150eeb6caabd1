"""The event-driven stick/slip integrator behind ``hbm.reference.shooting`` (the reference's integrator (a)).

Model (n DOFs, ``nc`` Jenkins contacts, ``nq`` cubic springs)::

    M x'' + C x' + K x + B f(t) + Bq k3 (Bq^T x)^3 = force cos(omega t),
    f_c = kt_c (u_c - z_c),  u = B^T x,  |f_c| <= fs_c,

``B`` (n, nc) holds one column per contact: ``e_i`` (to ground at DOF i) or ``e_i - e_j``
(between DOFs i and j, acting on ``x_i - x_j``); ``Bq`` likewise for the cubic springs.  A
contact is either stuck (``z_c' = 0``) or slipping (``z_c' = u_c'``, force ``sigma fs_c``).
Either way the equations are linear in the augmented state

    y = [x (n), v (n), z (nc), cos(omega t), sin(omega t)],   y' = A(mode) y - cubic terms,

the forcing being carried by the rotation ``(c, s)' = omega (-s, c)``.  Without cubic springs
the flow of one mode over a time ``tau`` is exactly ``expm(A tau)``; with them each mode's segment
is integrated by DOP853 at rtol 1e-12.  Mode changes (events) are located by root finding on
the exact (or dense) solution: stick -> slip where ``sigma f_c = fs_c``, slip -> stick where the
relative velocity ``sigma u_c'`` reaches zero.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

#: Relative tolerance on |f| = fs deciding that a contact starts a step on its slip limit.
ON_LIMIT = 1e-12
#: A stuck contact slips once |f| exceeds fs (1 + STICK_MARGIN): a contact that has just stuck on
#: its limit is not found slipping again at once by rounding.
STICK_MARGIN = 1e-13
#: Maximum mode changes inside one grid step (a guard against chattering at a grazing event).
EVENTS_PER_STEP = 64
#: Largest condition number of a mode's eigenvectors for which fractions of a step are taken by
#: eigen-decomposition (else ``expm``; e.g. a structure free while its contact slips).
EIG_COND = 1e6
#: Tolerances of the DOP853 path (cubic springs).
IVP_RTOL = 1e-12


@dataclass
class Model:
    """Dense matrices of the structure, its contacts and cubic springs (see the module)."""

    M: NDArray[np.float64]
    C: NDArray[np.float64]
    K: NDArray[np.float64]
    force: NDArray[np.float64]
    B: NDArray[np.float64]
    kt: NDArray[np.float64]
    fs: NDArray[np.float64]
    Bq: NDArray[np.float64]
    k3: NDArray[np.float64]
    Minv: NDArray[np.float64] = field(init=False)

    def __post_init__(self) -> None:
        self.Minv = np.linalg.inv(self.M)

    @property
    def n(self) -> int:
        return self.M.shape[0]

    @property
    def nc(self) -> int:
        return self.kt.size

    @property
    def nonlinear(self) -> bool:
        return self.k3.size > 0

    def contact_force(self, x: NDArray[np.float64], z: NDArray[np.float64]) -> NDArray[np.float64]:
        """Slider forces kt (B^T x - z), unclipped; x, z may carry leading sample axes."""
        return self.kt * (x @ self.B - z)

    def cubic_force(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """Nodal forces of the cubic springs, Bq k3 (Bq^T x)^3."""
        return (self.k3 * (x @ self.Bq) ** 3) @ self.Bq.T


class EventIntegrator:
    """Exact (``expm``) or DOP853 flow of the piecewise linear model, with located events.

    ``omega`` fixes the forcing; ``steps`` grid steps per period ``T = 2 pi/omega`` are the
    sample times of the output and the stride of the event search.
    """

    def __init__(self, model: Model, omega: float, steps: int, *, method: str = "expm") -> None:
        self.m = model
        self.omega = float(omega)
        self.period = 2.0 * np.pi / self.omega
        self.steps = int(steps)
        self.h = self.period / self.steps
        self.method = "ivp" if model.nonlinear else method
        n, nc = model.n, model.nc
        self.dim = 2 * n + nc + 2
        A = np.zeros((self.dim, self.dim))
        A[:n, n:2 * n] = np.eye(n)
        A[n:2 * n, :n] = -model.Minv @ (model.K + (model.B * model.kt) @ model.B.T)
        A[n:2 * n, n:2 * n] = -model.Minv @ model.C
        A[n:2 * n, 2 * n:2 * n + nc] = model.Minv @ (model.B * model.kt)
        A[n:2 * n, -2] = model.Minv @ model.force
        A[-2, -1], A[-1, -2] = -self.omega, self.omega
        self._A0 = A
        self._A: dict[tuple[bool, ...], NDArray[np.float64]] = {}
        self._step: dict[tuple[bool, ...], NDArray[np.float64]] = {}
        self._eigs: dict = {}
        self.events = 0

    # ------------------------------------------------------------ modes
    def A(self, slip: tuple[bool, ...]) -> NDArray[np.float64]:
        """The mode's matrix: row z_c' = B_c^T v for the slipping contacts."""
        if slip not in self._A:
            A = self._A0.copy()
            n = self.m.n
            for c, s in enumerate(slip):
                if s:
                    A[2 * n + c, n:2 * n] = self.m.B[:, c]
            self._A[slip] = A
        return self._A[slip]

    def flow(self, slip: tuple[bool, ...], y: NDArray[np.float64], tau: float) -> NDArray[np.float64]:
        """State after ``tau`` in mode ``slip`` (no event handling)."""
        from scipy.linalg import expm  # scipy submodule, lazily: import hbm stays light

        if self.method == "expm":
            if tau == self.h:
                if slip not in self._step:
                    self._step[slip] = expm(self.A(slip) * self.h)
                return self._step[slip] @ y
            eig = self._eig(slip)
            if eig is None:
                return expm(self.A(slip) * tau) @ y
            lam, V, Vinv = eig
            return (V @ (np.exp(lam * tau) * (Vinv @ y))).real
        return self._ivp(slip, y, tau, dense=False)

    def _eig(self, slip):
        """Eigen-decomposition of the mode's matrix for the flow over fractions of a step, or
        None where the eigenvectors are ill-conditioned (then ``expm``)."""
        if slip not in self._eigs:
            lam, V = np.linalg.eig(self.A(slip))
            ok = np.linalg.cond(V) < EIG_COND
            self._eigs[slip] = (lam, V, np.linalg.inv(V)) if ok else None
        return self._eigs[slip]

    def _rhs(self, slip):
        A, m, n = self.A(slip), self.m, self.m.n

        def f(t, y):
            dy = A @ y
            if m.nonlinear:
                dy[n:2 * n] -= m.Minv @ m.cubic_force(y[:n])
            return dy
        return f

    def _ivp(self, slip, y, tau, dense):
        from scipy.integrate import solve_ivp  # heavy (0.1-0.5 s), lazily: only with cubic springs

        scale = max(float(np.max(np.abs(y[:-2]))), 1e-300)
        sol = solve_ivp(self._rhs(slip), (0.0, tau), y, method="DOP853", rtol=IVP_RTOL,
                        atol=IVP_RTOL * 1e-2 * scale, dense_output=dense)
        if not sol.success:
            raise FloatingPointError(f"DOP853 failed: {sol.message}")
        return sol.sol if dense else sol.y[:, -1]

    # ------------------------------------------------------------ contact logic
    def _u(self, y):
        n = self.m.n
        return y[:n] @ self.m.B, y[n:2 * n] @ self.m.B

    def classify(self, y: NDArray[np.float64]) -> tuple[tuple[bool, ...], NDArray[np.float64]]:
        """Mode of the state ``y`` and ``y`` with each slider return-mapped onto its limit.

        A contact at (or beyond) its limit slips if its relative velocity loads it further,
        else it sticks."""
        m, n = self.m, self.m.n
        y = y.copy()
        u, du = self._u(y)
        f = m.kt * (u - y[2 * n:2 * n + m.nc])
        slip = []
        for c in range(m.nc):
            sig = 1.0 if f[c] >= 0.0 else -1.0
            if abs(f[c]) >= m.fs[c] * (1.0 - ON_LIMIT):
                y[2 * n + c] = u[c] - sig * m.fs[c] / m.kt[c]
                slip.append(bool(sig * du[c] > 0.0))
            else:
                slip.append(False)
        return tuple(slip), y

    def _event_values(self, slip, sig, y):
        """Per contact: <= 0 while the present mode holds, crossing to > 0 at its event."""
        m, n = self.m, self.m.n
        u, du = self._u(y)
        f = m.kt * (u - y[2 * n:2 * n + m.nc])
        return np.where(slip, -sig * du, np.abs(f) - m.fs * (1.0 + STICK_MARGIN))

    # ------------------------------------------------------------ integration
    def period_map(self, y0: NDArray[np.float64], *,
                   record: bool = False) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
        """Integrate one period from ``y0`` = (x, v, z) at t = 0.

        Returns the end state (x, v, z) and, with ``record``, the states (x, v, z) at the
        grid times t_k = k h (k = 0 .. steps - 1) as an array (steps, 2 n + nc)."""
        y = np.concatenate([y0, [1.0, 0.0]])
        slip, y = self.classify(y)
        out = np.empty((self.steps, self.dim - 2)) if record else None
        for k in range(self.steps):
            if record:
                out[k] = y[:-2]
            y, slip = self._advance(y, slip, k)
        return y[:-2], out

    def _signs(self, y):
        return np.where(self.m.contact_force(y[:self.m.n], y[2 * self.m.n:2 * self.m.n + self.m.nc]) >= 0.0, 1.0, -1.0)

    def _advance(self, y, slip, k, length=None):
        """One grid step h from t_k (or ``length``), switching mode at every event inside it."""
        from scipy.optimize import brentq  # heavy (0.1-0.5 s), lazily: import hbm stays light

        left = self.h if length is None else length
        for _ in range(EVENTS_PER_STEP):
            sig = self._signs(y)
            slip_arr = np.array(slip, dtype=bool)
            if self.method == "expm" and left == self.h:
                y1 = self.flow(slip, y, left)
                g1 = self._event_values(slip_arr, sig, y1)
                if not np.any(g1 > 0.0):
                    return y1, slip
                path = lambda tau: self.flow(slip, y, tau)  # noqa: E731
            elif self.method == "expm":
                path = lambda tau: self.flow(slip, y, tau)  # noqa: E731
                y1 = path(left)
                g1 = self._event_values(slip_arr, sig, y1)
                if not np.any(g1 > 0.0):
                    return y1, slip
            else:
                sol = self._ivp(slip, y, left, dense=True)
                y1 = sol(left)
                g1 = self._event_values(slip_arr, sig, y1)
                if not np.any(g1 > 0.0):
                    return y1, slip
                path = sol
            # earliest crossing among the contacts whose event function ended positive
            t_ev, c_ev = left, -1
            for c in np.flatnonzero(g1 > 0.0):
                gc = lambda tau, c=c: self._event_values(slip_arr, sig, path(tau))[c]  # noqa: E731
                if gc(0.0) >= 0.0:
                    tau = 0.0
                else:
                    tau = brentq(gc, 0.0, left, xtol=1e-15 * self.h, rtol=1e-15)
                if tau < t_ev or c_ev < 0:
                    t_ev, c_ev = tau, c
            y = path(t_ev) if t_ev > 0.0 else y.copy()
            left -= t_ev
            self.events += 1
            slip = list(slip)
            if slip[c_ev]:
                slip[c_ev] = False  # slip -> stick at zero relative velocity
            else:
                slip[c_ev] = True  # stick -> slip: put the slider exactly on its limit
                n = self.m.n
                u, _ = self._u(y)
                s = 1.0 if u[c_ev] - y[2 * n + c_ev] >= 0.0 else -1.0
                y[2 * n + c_ev] = u[c_ev] - s * self.m.fs[c_ev] / self.m.kt[c_ev]
            slip = tuple(slip)
            if left <= 0.0:
                return y, slip
        raise FloatingPointError(f"more than {EVENTS_PER_STEP} stick/slip events in grid step {k}")


    def extreme(self, start: NDArray[np.float64], dof: int) -> float:
        """``|x_dof|`` at the zero of ``v_dof`` within two grid steps of the sample ``start``
        (augmented state at t_{k-1}, the sample before the largest ``|x_dof|``), located by
        root finding on the event-resolved flow; the larger end value if ``v_dof`` keeps its sign."""
        from scipy.optimize import brentq  # heavy (0.1-0.5 s), lazily: import hbm stays light

        n = self.m.n
        slip0, y0 = self.classify(start)

        def at(tau):
            return y0 if tau <= 0.0 else self._advance(y0, slip0, -1, length=tau)[0]

        ends = (at(0.0), at(2.0 * self.h))
        if ends[0][n + dof] * ends[1][n + dof] > 0.0:
            return float(max(abs(e[dof]) for e in ends))
        tau = brentq(lambda t: at(t)[n + dof], 0.0, 2.0 * self.h, xtol=1e-14 * self.h, rtol=1e-15)
        return float(abs(at(tau)[dof]))
