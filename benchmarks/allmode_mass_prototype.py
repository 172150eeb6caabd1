"""A prototype, not library code: the all-mode bar with the averaged mass matrix, against the lumped one.

The library's all-mode bar with ``linear="lumped"`` (``contact_models.allmode.solve.FixedBar``) has the
lumped mass of linear elements, whose mode frequencies are low by (k h)^2 / 24 to leading order; the
consistent mass's are high by as much, so their average, M = (M_lumped + M_consistent) / 2 (diagonal
5 rho A h / 6, 5 rho A h / 12 at the ends; off-diagonal rho A h / 12), places the modes to fourth order.
The off-diagonal mass makes the coupling of neighbouring nodes depend on the harmonic, c_j = -EA/h -
omega^2 j^2 rho A h / 12, which ``FixedBar`` takes as it takes its exact segments' (its ``linear`` part,
overridden here).  The bar the library now uses by default, exact between its nodes, is compared in
``bench_allmode_linear.py``.

``python benchmarks/allmode_mass_prototype.py``: the default case's bar and load; (1) the second mode of
the bar stuck and free (no shear layer), over the drive frequency at the notch, lumped and averaged,
on 16 to 512 cells; (2) f_s and f_c at three points of the default all-mode FRF (the peak, the 13th
harmonic's notch beside it, and a point below the peak) on 16 to 256 cells at H = 31 and 496 samples,
lumped (the library's ``linear="lumped"``: checked against ``AllModeMicroslip`` to 1e-9 relative) and averaged
(docs/performance.md, "The all-mode FRF: one nested solve on the finest rung").
"""

from __future__ import annotations

import numpy as np

from contact_models import AllModeMicroslip
from contact_models.allmode.solve import FixedBar
from contact_models.allmode.segments import LinearPart

#: (omega rad/s, a m, what) of the default all-mode FRF at 100 N (rounded).
POINTS = ((38827.4, 1.538e-6, "the peak"), (38752.0, 1.538e-6, "the notch"), (38446.6, 1.393e-6, "below the peak"))
CELLS = (16, 32, 64, 128, 256)
H, N_T = 31, 496


class MassBar(FixedBar):
    """The bar with the mass (1 - alpha) M_lumped + alpha M_consistent: ``FixedBar`` on its linear part
    (diagonal K_ii - Omega^2 m_i, coupling -EA/h - Omega^2 m_off per harmonic); ``force(a, omega)``."""

    def __init__(self, bar, load, cells, harmonics, n_t, alpha):
        super().__init__(bar, load, cells, harmonics, n_t, "lumped")
        d, rho_a = self.disc, bar.rho * bar.A
        consistent = np.full(d.n + 1, 2.0 * rho_a * d.h / 3.0)
        consistent[0] = consistent[-1] = rho_a * d.h / 3.0
        self.mass = (1.0 - alpha) * d.m + alpha * consistent
        self.mass_off = alpha * rho_a * d.h / 6.0

    def linear(self, omega, order, key):
        d, w2 = self.disc, np.asarray(order, dtype=float) ** 2
        return LinearPart(d.kdiag[:, None] - omega**2 * self.mass[:, None] * w2, d.off - omega**2 * self.mass_off * w2,
                          -2.0 * omega * self.mass[:, None] * w2, -2.0 * omega * self.mass_off * w2)

    def force(self, a, omega):
        """(f_s, f_c) for the end motion a sin(omega t)."""
        X = np.zeros(2 * self.H + 1)
        X[2] = a
        sol = self.solve(X, omega, odd=True)
        if not sol.success:
            raise FloatingPointError(f"no convergence at a={a}, omega={omega}: {sol.message}")
        return sol.f_s, sol.f_c


def second_mode(bar, cells, alpha, stuck):
    """The second mode (rad/s) of the bar with its driven end held, stuck (the shear layer's springs) or not."""
    from scipy.linalg import eigh

    from contact_models.numerics.fe_bar import _Discretisation
    from contact_models import UniformLoad

    d = _Discretisation(bar, UniformLoad(N=1.0).on(bar.L), cells)
    n, rho_a = cells, bar.rho * bar.A
    K = np.diag(d.kdiag[:n] + (d.kc[:n] if stuck else 0.0)) + d.off * (np.eye(n, k=1) + np.eye(n, k=-1))
    consistent = np.diag(np.r_[rho_a * d.h / 3.0, np.full(n - 1, 2.0 * rho_a * d.h / 3.0)])
    consistent += rho_a * d.h / 6.0 * (np.eye(n, k=1) + np.eye(n, k=-1))
    M = (1.0 - alpha) * np.diag(d.m[:n]) + alpha * consistent
    return float(np.sqrt(eigh(K, M, eigvals_only=True, subset_by_index=[1, 1])[0]))


def main():
    from hbm.cli.cases import default_case

    case = default_case()
    bar, load = case.element.bar, case.element.load.on(case.element.bar.L)
    w = POINTS[1][0]
    print(f"(1) the bar's second mode over {w} rad/s (the first is below the drive), lumped / averaged mass:")
    for stuck in (True, False):
        row = [f"{n}: {second_mode(bar, n, 0.0, stuck) / w:.4f} / {second_mode(bar, n, 0.5, stuck) / w:.4f}"
               for n in (16, 32, 64, 128, 512)]
        print(f"  {'stuck' if stuck else 'free '}  " + ", ".join(row))
    print(f"(2) f_s, f_c (N) at H = {H}, {N_T} samples:")
    for omega, a, what in POINTS:
        lib = AllModeMicroslip(case.element.bar, case.element.load, CELLS[2], H, n_t=N_T, linear="lumped")
        F = lib.harmonic_force(np.array([0.0, 0.0, a]), omega)[0]
        check = MassBar(case.element.bar, load, CELLS[2], H, N_T, 0.0).force(a, omega)
        assert abs(check[0] - F[2]) <= 1e-9 * abs(F[2]) and abs(check[1] - F[1]) <= 1e-9 * abs(F[2]), (check, F)
        print(f"  {what}, omega = {omega} rad/s, a = {a} m:")
        for alpha, name in ((0.0, "lumped"), (0.5, "averaged")):
            vals = [MassBar(case.element.bar, load, n, H, N_T, alpha).force(a, omega) for n in CELLS]
            print(f"    {name:8s} " + "  ".join(f"{n}: {s:.6f} {c:.6f}" for n, (s, c) in zip(CELLS, vals)))


if __name__ == "__main__":
    main()
