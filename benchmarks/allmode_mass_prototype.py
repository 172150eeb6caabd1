"""A prototype, not library code: the all-mode bar with the averaged mass matrix, against the lumped one.

The library's all-mode bar (``contact_models._allmode_solve.FixedBar``) has the lumped mass of linear
elements, whose mode frequencies are low by (k h)^2 / 24 to leading order; the consistent mass's are
high by as much, so their average, M = (M_lumped + M_consistent) / 2 (diagonal 5 rho A h / 6, 5 rho A h
/ 12 at the ends; off-diagonal rho A h / 12), places the modes to fourth order.  The off-diagonal mass
makes the coupling of neighbouring nodes depend on the harmonic, c_j = -EA/h - omega^2 j^2 rho A h / 12;
each block row divided by diag(c_j) has the unit coupling that ``factorise`` takes.  Only the force is
computed here (no derivatives: the prototype answers how fast the force converges in the cells).

``python benchmarks/allmode_mass_prototype.py``: the default case's bar and load; (1) the second mode of
the bar stuck and free (no shear layer), over the drive frequency at the notch, lumped and averaged,
on 16 to 512 cells; (2) f_s and f_c at three points of the default all-mode FRF (the peak, the 13th
harmonic's notch beside it, and a point below the peak) on 16 to 256 cells at H = 31 and 496 samples,
lumped (which is the library's bar: checked against ``AllModeMicroslip`` to 1e-9 relative) and averaged
(docs/performance.md, "The all-mode FRF: one nested solve on the finest rung").
"""

from __future__ import annotations

import numpy as np

from contact_models import AllModeMicroslip
from contact_models._allmode_solve import FixedBar, _Eval, with_diagonal
from contact_models._hbal import factorise, jenkins_state

#: (omega rad/s, a m, what) of the default all-mode FRF at 100 N (rounded).
POINTS = ((38827.4, 1.538e-6, "the peak"), (38752.0, 1.538e-6, "the notch"), (38446.6, 1.393e-6, "below the peak"))
CELLS = (16, 32, 64, 128, 256)
H, N_T = 31, 496


class MassBar(FixedBar):
    """The bar with the mass (1 - alpha) M_lumped + alpha M_consistent; ``force(X, omega)`` only."""

    lazy_jacobian = False

    def __init__(self, bar, load, cells, harmonics, n_t, alpha):
        super().__init__(bar, load, cells, harmonics, n_t)
        d, rho_a = self.disc, bar.rho * bar.A
        consistent = np.full(d.n + 1, 2.0 * rho_a * d.h / 3.0)
        consistent[0] = consistent[-1] = rho_a * d.h / 3.0
        self.mass = (1.0 - alpha) * d.m + alpha * consistent
        self.mass_off = alpha * rho_a * d.h / 6.0

    def coupling(self, omega, b):
        return self.disc.off - omega**2 * self.mass_off * b.order**2

    def evaluate(self, U, X, omega, b, jacobian=True):
        d = self.disc
        T, slip, state = jenkins_state(np.vstack([U, X[None, :]]), d.kc, d.p, b.E, b.P, b.odd)
        lin = d.kdiag[:, None] - omega**2 * self.mass[:, None] * b.order[None, :] ** 2
        c = self.coupling(omega, b)
        R = lin[:-1] * U + T[:-1]
        R[1:] += c * U[:-1]
        R[:-1] += c * U[1:]
        R[-1] += c * X
        ev = _Eval(U, R, float(np.max(np.abs(R))), T, None, slip, lin, state)
        return self.with_jacobian(ev, X, omega, b) if jacobian else ev

    def linear_guess(self, X, omega, b):
        d, c = self.disc, self.coupling(omega, b)
        diag = d.kdiag[:-1, None] + d.kc[:-1, None] - omega**2 * self.mass[:-1, None] * b.order[None, :] ** 2
        n = diag.shape[0]
        U = np.empty_like(diag)
        for j in range(diag.shape[1]):
            A = np.diag(diag[:, j]) + c[j] * (np.eye(n, k=1) + np.eye(n, k=-1))
            rhs = np.zeros(n)
            rhs[-1] = -c[j] * X[j]
            U[:, j] = np.linalg.solve(A, rhs)
        return U

    def newton(self, ev, X, omega, b, max_iter=40):
        tol = 1e-11 * self.scale(X)
        c = self.coupling(omega, b)
        fac = None
        for it in range(max_iter + 1):
            fac = factorise(with_diagonal(ev.J[:-1], ev.lin[:-1]) / c[None, :, None], 1.0, 0, not b.odd)
            if ev.res <= tol or it == max_iter:
                break
            dU = -fac.solve(ev.R / c[None, :])
            t = 1.0
            for _ in range(30):
                trial = self.evaluate(ev.U + t * dU, X, omega, b)
                if trial.res <= (1.0 - 1e-4 * t) * ev.res:
                    break
                t *= 0.5
            ev = trial
        return ev, fac, ev.res <= tol, it

    def force(self, a, omega):
        """(f_s, f_c) for the end motion a sin(omega t)."""
        b = self.basis(True)
        X = np.zeros(2 * self.H + 1)
        X[2] = a
        Xb = X[b.idx]
        ev, _, ok, _ = self.newton(self.evaluate(self.linear_guess(Xb, omega, b), Xb, omega, b), Xb, omega, b)
        if not ok:
            ev, _, ok, _ = self.continuation(Xb, omega, b)
        if not ok:
            raise FloatingPointError(f"no convergence at a={a}, omega={omega}")
        F = ev.lin[-1] * Xb + self.coupling(omega, b) * ev.U[-1] + ev.T[-1]
        return float(F[1]), float(F[0])  # the odd basis holds c1, s1, c3, s3, ...


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
        lib = AllModeMicroslip(case.element.bar, case.element.load, CELLS[2], H, n_t=N_T)
        F = lib.harmonic_force(np.array([0.0, 0.0, a]), omega)[0]
        check = MassBar(case.element.bar, load, CELLS[2], H, N_T, 0.0).force(a, omega)
        assert abs(check[0] - F[2]) <= 1e-9 * abs(F[2]) and abs(check[1] - F[1]) <= 1e-9 * abs(F[2]), (check, F)
        print(f"  {what}, omega = {omega} rad/s, a = {a} m:")
        for alpha, name in ((0.0, "lumped"), (0.5, "averaged")):
            vals = [MassBar(case.element.bar, load, n, H, N_T, alpha).force(a, omega) for n in CELLS]
            print(f"    {name:8s} " + "  ".join(f"{n}: {s:.6f} {c:.6f}" for n, (s, c) in zip(CELLS, vals)))


if __name__ == "__main__":
    main()
