"""The finite-element microslip bar of ``NumericalMicroslip``: its nodal data.

Linear elements on n equal cells, h = L/n, nodes x_i = i h (node n the driven end); lumped
(diagonal) mass rho A c_i and the shear layer lumped at the nodes with trapezoid weights c_i
(h inside, h/2 at both ends): node i carries a Jenkins element of stiffness k c_i and slip
force mu q(x_i) c_i; the axial stiffness matrix is tridiagonal, with the beta spring in its
entry 0 (Eq. 30 by the method of lines).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple

import numpy as np
from numpy.typing import NDArray

from .waves import UnresolvedWave, cells_for_phase

if TYPE_CHECKING:
    from ..bar import Bar
    from ..loads import QuadraticLoad, UniformLoad


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

    def __init__(self, bar: Bar, load: UniformLoad | QuadraticLoad, n: int) -> None:
        self.n = n
        self.bar = bar
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

    def check_wave(self, omega: float) -> None:
        """UnresolvedWave (a ValueError) naming omega and the cells it needs where a cell carries more than
        ``waves.MAX_SEGMENT_PHASE`` of the wave at omega: the mesh cannot represent it at all (and omega**2
        past about 1e154 rad/s would overflow)."""
        need = cells_for_phase(self.bar, omega, 1)
        if need > self.n:
            raise UnresolvedWave(f"cells={self.n} are too few for omega={omega!r} rad/s: a cell is more than 0.9 of "
                                 f"half the wavelength of the stuck bar; it needs at least {need:.4g} cells")

    def stuck_error(self, omega: float, K: float | None = None) -> float:
        """Relative error of this mesh's stuck stiffness against the continuous bar's closed form
        (``Bar.stuck_stiffness``), relative to max(|K|, 0.01 k*) as in the validity map: the error of the
        linear part alone, which the mesh's dispersion sets (the lumped bar's wave number is off by about
        (g h)^2 / 24, so the error falls as cells^-2).  ``K``: this mesh's stiffness, if known."""
        K_h = self.stuck_solution(omega)[1] if K is None else K
        K = float(self.bar.stuck_stiffness(omega))
        if not np.isfinite(K):  # at a resonance of the bar held at x = L
            return float("inf")
        return abs(K_h - K) / max(abs(K), 0.01 * self.bar.k_star)

    def stuck_solution(self, omega: float) -> tuple[NDArray[np.float64], float]:
        """Free nodal displacements of the stuck bar for u_n = 1, and the tip reaction (UnresolvedWave where
        the cells cannot hold the wave at omega, ``check_wave``)."""
        self.check_wave(omega)
        n = self.n
        d = self.kdiag + self.kc - omega**2 * self.m
        ab = np.zeros((3, n))
        ab[0, 1:] = self.off
        ab[1] = d[:n]
        ab[2, :-1] = self.off
        rhs = np.zeros(n)
        rhs[-1] = -self.off
        from scipy.linalg import solve_banded  # lazily: import contact_models stays light

        u = solve_banded((1, 1), ab, rhs)
        f = d[n] + self.off * u[-1]
        return np.append(u, 1.0), f

    def slip_amplitude(self, omega: float) -> float:
        """Smallest tip amplitude at which a node's elastic force k c_i |u_i| of the stuck bar
        reaches its slip force mu q_i c_i (inf if none can)."""
        u, _ = self.stuck_solution(omega)
        with np.errstate(divide="ignore"):
            ratio = np.where(np.abs(u) > 0, self.p / (self.kc * np.abs(u)), np.inf)
        return float(np.min(ratio))
