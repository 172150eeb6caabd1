"""One discretisation of the all-mode bar with normal motion (``AllModeMicroslip2D``).

The bar of ``contact_models.allmode`` (n equal cells, lumped mass, node i a Jenkins element of
stiffness k c_i) whose nodal slip force follows a normal load that varies in time and may vanish:

    N_i(t) = max(0, q(x_i) c_i + kn c_i v_i(t)),    slip limit mu N_i(t),

with v_i(t) the normal displacement of node i (positive presses).  Each node is exactly the point
contact ``Contact2D`` (kt = k c_i, kn c_i, mu, n0 = q(x_i) c_i): its periodic return map on the
samples (``contact_models.contact2d.slip_origins``: stick while |T| < mu N_k, else T_k = mu N_k
sign, separation T = 0 while N = 0, the spring unloaded on re-contact) gives the force and, in
closed form, its derivatives in the node's displacement and in its limit samples.  The balance,
its Newton solve and the derivatives by the implicit function theorem are those of
``contact_models.allmode.solve.FixedBar``, in the full basis (a varying normal load breaks the
half-wave symmetry).  Derivation: ``docs/contacts_normal.md``, "The all-mode bar with normal motion".
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ..contact2d import slip_origins, stuck_midpoint
from .solve import AllModeSolution, FixedBar, _Basis, _Eval

if TYPE_CHECKING:
    from ..bar import Bar
    from ..loads import QuadraticLoad, UniformLoad

Array = NDArray[np.float64]


@dataclass
class NormalSolution(AllModeSolution):
    """``AllModeSolution`` of the bar with normal motion, and in addition: ``V`` (2H+1) the normal
    displacement's coefficients, ``FN`` (2H+1) the coefficients of the normal force sum_i s_i N_i(t)
    (N; the total normal reaction for uniform motion), ``dF_dV`` (2H+1, 2H+1) the tangential end
    force's derivative in V (None where the solve failed), ``dFN_dV`` (2H+1, 2H+1), and
    ``separated`` (n + 1, n_t): where each node is out of contact (N_i = 0) at theta_k = 2 pi k / n_t.
    ``slip`` includes separation."""

    V: Array | None = None
    FN: Array | None = None
    dF_dV: Array | None = None
    dFN_dV: Array | None = None
    separated: NDArray[np.bool_] | None = None


def node_map(u: Array, lim: Array, kt: float) -> tuple[Array, NDArray[np.bool_], tuple]:
    """The periodic force of one node (``Contact2D``'s return map) and its derivatives.

    ``u``, ``lim`` (n_t,): displacement and slip-limit samples; ``kt`` the stiffness.  Returns
    ``(T, slip, (r1, r2, w1, w2))``: the force samples, where the node slips, and two origins per
    sample with weights such that

        dT_k = kt (du_k - (du_r1 + du_r2)/2) + w1_k dlim_r1 + w2_k dlim_r2.

    A slipping node: r1 = r2 = r(k), the last slip at or before k (cyclically), w1 = w2 = s_r/2
    (T_k = kt (u_k - u_r) + s_r lim_r).  A node stuck all period at the midpoint of its admissible
    slider positions, w = ((u_i - lim_i/kt) + (u_j + lim_j/kt))/2 with i the argmax of u - lim/kt and
    j the argmin of u + lim/kt: r1 = i, r2 = j, w1 = 1/2, w2 = -1/2."""
    n = u.size
    found = slip_origins(u, lim, kt)
    if found is None:
        i, j, w = stuck_midpoint(u, lim, kt)
        return kt * (u - w), np.zeros(n, bool), (np.full(n, i), np.full(n, j), np.full(n, 0.5), np.full(n, -0.5))
    T, r, sgn = found
    return T, sgn != 0.0, (r, r, 0.5 * sgn[r], 0.5 * sgn[r])


class NormalBar(FixedBar):
    """``FixedBar`` whose nodes carry ``Contact2D`` under the normal loads of ``set_normal``:
    ``solve_normal(X, V, omega)`` with X, V of length 2 harmonics + 1."""

    lazy_jacobian = False  # its evaluations keep no return-map state: they carry their Jacobians

    def __init__(self, bar: Bar, load: UniformLoad | QuadraticLoad, kn: float, shape: tuple[float, float],
                 cells: int, harmonics: int, n_t: int) -> None:
        super().__init__(bar, load, cells, harmonics, n_t, "lumped")
        d = self.disc
        self.mu = bar.mu
        self.n0 = np.asarray(load.q(d.x), dtype=float) * d.c  # nodal preload q(x_i) c_i (N)
        self.knc = kn * d.c  # nodal normal stiffness kn c_i (N/m)
        self.s = shape[0] + (shape[1] - shape[0]) * d.x / bar.L  # v_i = s_i v
        self.lim = np.tile(d.p[:, None], (1, n_t))
        self.dlim = np.zeros((d.n + 1, n_t))
        self.V = np.zeros(2 * harmonics + 1)

    def set_normal(self, V: Array) -> None:
        """Nodal limits mu N_i(theta_k) and dlim/dv_i for the normal coefficients V (2H+1)."""
        v = self.basis(False).E @ V  # (n_t,)
        pre = self.n0[:, None] + self.knc[:, None] * self.s[:, None] * v[None, :]
        self.lim = self.mu * np.maximum(pre, 0.0)
        self.dlim = np.where(pre > 0.0, self.mu * self.knc[:, None], 0.0)  # d lim / d v_i
        self.V = np.array(V, dtype=float)

    def nodes(self, full: Array, b: _Basis, jacobian: bool) -> tuple:
        """Forces T (m, s), Jacobians dT/dU (m, s, s) (None without ``jacobian``), slip masks (m, n_t)
        and the origins and weights of ``node_map`` of every node of the coefficients ``full`` (m, s)."""
        u = full @ b.E.T
        m, s = full.shape
        kc = self.disc.kc
        T = np.empty((m, s))
        J = np.empty((m, s, s)) if jacobian else None
        slip = np.empty((m, u.shape[1]), bool)
        origins = []
        for i in range(m):
            f, slip[i], o = node_map(u[i], self.lim[i], float(kc[i]))
            T[i] = b.P @ f
            if jacobian:
                J[i] = kc[i] * (np.eye(s) - b.P @ (0.5 * (b.E[o[0]] + b.E[o[1]])))
            origins.append(o)
        return T, J, slip, origins

    def evaluate(self, U: Array, X: Array, omega: float, b: _Basis, jacobian: bool = True) -> _Eval:
        d = self.disc
        full = np.vstack([U, X[None, :]])
        T, J, slip, _ = self.nodes(full, b, jacobian)
        lin = d.kdiag[:, None] - omega**2 * d.m[:, None] * b.order[None, :] ** 2
        R = lin[:-1] * U + T[:-1]
        R[1:] += d.off * U[:-1]
        R[:-1] += d.off * U[1:]
        R[-1] += d.off * X
        return _Eval(U, R, float(np.max(np.abs(R))), T, J, slip, lin)

    def solve_normal(self, X: Array, V: Array, omega: float) -> NormalSolution:
        """Steady state for the end displacement X and the normal displacement V (both 2H+1) at omega."""
        self.set_normal(V)
        sol = self.solve(X, omega, False)
        return self.normal_parts(sol)

    def normal_parts(self, sol: AllModeSolution) -> NormalSolution:
        """Add the normal force, the derivatives in V (implicit function theorem) and the separation mask;
        ``sol`` is this bar's last solve (its factorisation of dR/dU is taken from the warm-start cache)."""
        d, b = self.disc, self.basis(False)
        out = NormalSolution(**sol.__dict__)
        out.V = self.V.copy()
        N = self.lim / self.mu  # (n+1, n_t)
        out.FN = b.P @ (self.s @ N)
        # dFN/dV = P diag(sum_i s_i^2 kn c_i [N_i > 0]) E
        out.dFN_dV = b.P @ (((self.s**2 * self.knc)[:, None] * (N > 0.0)).sum(axis=0)[:, None] * b.E)
        out.separated = N <= 0.0
        s = b.E.shape[1]
        if not sol.success:  # no converged state to differentiate: dF_dV stays None
            return out
        _, _, _, origins = self.nodes(sol.U, b, False)
        # dR_i/dV = s_i P (w1 dlim_r1 E_r1 + w2 dlim_r2 E_r2): the limits move with v_i = s_i v
        B = np.empty((d.n + 1, s, s))
        for i, (r1, r2, w1, w2) in enumerate(origins):
            dl = self.dlim[i]
            B[i] = self.s[i] * (b.P @ ((w1 * dl[r1])[:, None] * b.E[r1] + (w2 * dl[r2])[:, None] * b.E[r2]))
        fac = self._cache[False][3]  # the factorisation of dR/dU at sol, which its solve (the last) kept
        dU = -fac.solve(B[:-1])
        out.dF_dV = B[-1] + d.off * dU[-1]
        return out
