"""The all-mode bar with normal motion (``AllModeMicroslip2D``) against an independent time
integration of the same discretised bar (``tests/_normal_bar_march.py``: explicit central
difference, shooting to the periodic state), its limits (kn = 0 is ``AllModeMicroslip``; one
quasi-static cell is ``Contact2D``), its Jacobians, and a multi-DOF balance with it."""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

import hbm
from contact_models import AllModeMicroslip, AllModeMicroslip2D, Bar, Contact2D, UniformLoad
from contact_models._allmode_solve import FixedBar

sys.path.insert(0, str(Path(__file__).parent))
from _normal_bar_march import Marcher  # noqa: E402

BAR = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
LOAD = UniformLoad(N=100.0)  # q = 2000 N/m
KN = 2.0e9  # N/m^2: kn v = q at v = 1 um
A = 3 * 7.5e-7  # tangential amplitude, 3 times the slip onset of the quasi-static bar
CELLS = 10
#: (normal shape, coefficients of v): N_i = q c_i (1 + s_i v / 1 um), never 0 in the first case;
#: in the second (a rocking damper, v_0 = 0.2 v, v_L = 1.8 v) the far half separates over part
#: of the cycle.
CASES = {"no separation": ((1.0, 1.0), [0.0, 0.5e-6, 0.3e-6]),
         "partial separation": ((0.2, 1.8), [0.0, 0.6e-6, 0.6e-6])}
#: (omega / omega_c, march steps per period N; the reference is checked against 2N)
FREQUENCIES = [(0.05, 4000), (0.5, 2000), (1.5, 4000)]


def march(shape, V, omega, steps, X=(0.0, 0.0, A), kn=KN, load=LOAD, cells=CELLS):
    m = Marcher(BAR, load, kn, shape, cells, list(X), V, omega, steps)
    f, res = m.periodic()
    assert res < 1e-10
    return m.coefficients(f, 1)


@pytest.mark.parametrize("case", CASES)
@pytest.mark.parametrize("ratio, steps", FREQUENCIES)
def test_against_the_time_integration(case, ratio, steps):
    shape, V = CASES[case]
    omega = ratio * BAR.omega_c
    el = AllModeMicroslip2D(BAR, LOAD, KN, CELLS, 15, normal_shape=shape)
    sol = el.solve(A, V, omega)
    assert sol.success
    assert np.all(sol.slip.any(axis=1))  # every node slips or separates: the periodic state is unique
    sep = sol.separated.mean()
    assert (sep == 0.0) if case == "no separation" else (0.03 < sep < 0.3)
    scale = BAR.k_star * A
    ref, fine = march(shape, V, omega, steps), march(shape, V, omega, 2 * steps)
    assert np.max(np.abs(fine - ref)) < 2e-4 * scale  # the reference's own step error
    diff = np.abs(sol.F[:3] - fine) / scale
    print(f"{case}, {ratio} omega_c: |dF0|, |dFc1|, |dFs1| / (k* a) = {diff[0]:.1e} {diff[1]:.1e} {diff[2]:.1e}")
    assert np.max(diff) < 1e-3
    # the normal force sum_i s_i N_i: its mean and first harmonic where nothing separates
    if case == "no separation":
        assert np.allclose(sol.FN[:3], LOAD.N * np.array([1.0, V[1] / 1e-6, V[2] / 1e-6]), rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("ratio", [0.0, 0.05, 0.5, 1.5])
def test_kn_zero_is_the_all_mode_bar(ratio):
    H, n_t = 7, 64
    omega = ratio * BAR.omega_c
    X = np.zeros(2 * H + 1)
    X[1:4] = [0.4e-6, A, 1e-7]
    ref = FixedBar(BAR, LOAD.on(BAR.L), CELLS, H, n_t).solve(X, omega, False)
    el = AllModeMicroslip2D(BAR, LOAD, 0.0, CELLS, H, n_t=n_t)
    sol = el.solve(X, [1e-6, 2e-6, 0.0], omega)  # kn = 0: the normal motion does nothing
    for got, want in ((sol.F, ref.F), (sol.dF_dX, ref.dF_dX), (sol.dF_domega, ref.dF_domega)):
        assert np.max(np.abs(got - want)) <= 1e-12 * np.max(np.abs(want))
    assert np.max(np.abs(sol.dF_dV)) == 0.0
    fs, fc = el.fourier(A, omega)
    fs1, fc1 = AllModeMicroslip(BAR, LOAD, CELLS, H, n_t=n_t).fourier(A, omega)
    assert abs(fs - fs1) <= 1e-12 * abs(fs1) and abs(fc - fc1) <= 1e-12 * abs(fs1)


def test_one_quasi_static_cell_approaches_contact2d():
    """A quasi-static bar much stiffer axially than its shear layer (EA/L = 1e4 k L): every node
    moves with the end, and the bar is the point contact of stiffness k L, normal stiffness kn L,
    preload q L = N (uniform normal motion), to O(k L^2/EA)."""
    bar = Bar(E=2.0e15, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=0.0, mu=0.3)
    H, n_t = 7, 128
    el = AllModeMicroslip2D(bar, LOAD, KN, cells=2, harmonics=H, n_t=n_t)
    pc = Contact2D(kt=bar.k * bar.L, kn=KN * bar.L, mu=bar.mu, n0=LOAD.N)
    X = np.zeros((2, 2 * H + 1))
    X[0, 2], X[1, 1], X[1, 2] = 2.0 * A, 0.7e-6, 0.4e-6
    F, J, _ = el.harmonic_force(X, 1e-3 * bar.omega_c)
    F2, J2, _ = pc.harmonic_force(X, 1e-3 * bar.omega_c, n_t=n_t)
    scale = bar.k * bar.L * 2.0 * A
    assert np.max(np.abs(F[0] - F2[0])) < 1e-3 * scale
    assert np.max(np.abs(F[1] - F2[1])) < 1e-9 * LOAD.N
