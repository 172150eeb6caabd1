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
from contact_models.allmode.solve import FixedBar

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
    ref = FixedBar(BAR, LOAD.on(BAR.L), CELLS, H, n_t, "lumped").solve(X, omega, False)  # the 2D bar is lumped
    el = AllModeMicroslip2D(BAR, LOAD, 0.0, CELLS, H, n_t=n_t)
    sol = el.solve(X, [1e-6, 2e-6, 0.0], omega)  # kn = 0: the normal motion does nothing
    for got, want in ((sol.F, ref.F), (sol.dF_dX, ref.dF_dX), (sol.dF_domega, ref.dF_domega)):
        assert np.max(np.abs(got - want)) <= 1e-12 * np.max(np.abs(want))
    assert np.max(np.abs(sol.dF_dV)) == 0.0
    fs, fc = el.fourier(A, omega)
    fs1, fc1 = AllModeMicroslip(BAR, LOAD, CELLS, H, n_t=n_t, linear="lumped").fourier(A, omega)
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


@pytest.mark.parametrize("case", CASES)
def test_jacobian_against_finite_differences(case):
    shape, V = CASES[case]
    H = 5
    el = AllModeMicroslip2D(BAR, LOAD, KN, 6, H, n_t=96, normal_shape=shape)
    X = np.zeros((2, 2 * H + 1))
    X[0, 1:4] = [0.3e-6, A, 0.2e-6]
    X[1, :3] = V
    X[1, 3] = 0.1e-6
    omega = 0.5 * BAR.omega_c
    F, J, Fw = el.harmonic_force(X, omega)
    L = 2 * H + 1
    num = np.empty_like(J)
    for j in range(2 * L):
        h = 1e-6 * (A if j < L else 1e-6)  # within one stick/slip/separation pattern
        Xp, Xm = X.copy(), X.copy()
        Xp.flat[j] += h
        Xm.flat[j] -= h
        num[:, j] = (el.harmonic_force(Xp, omega)[0] - el.harmonic_force(Xm, omega)[0]).ravel() / (2 * h)
    assert np.max(np.abs(J - num)) < 1e-5 * np.max(np.abs(J))
    dw = 1e-6 * omega
    numw = (el.harmonic_force(X, omega + dw)[0] - el.harmonic_force(X, omega - dw)[0]) / (2 * dw)
    assert np.max(np.abs(Fw - numw)) < 1e-5 * np.max(np.abs(Fw))
    # the time law's Jacobian is the same map through the samples
    x = np.vstack([np.cos(np.arange(24) * np.pi / 12) * A, 0.5e-6 * np.sin(np.arange(24) * np.pi / 12)])
    f, Jt = el.periodic_force(x, omega)
    k = 5
    e = np.zeros_like(x)
    e.flat[k] = 1e-6 * A
    numt = (el.periodic_force(x + e, omega)[0] - el.periodic_force(x - e, omega)[0]).ravel() / (2e-6 * A)
    assert np.max(np.abs(Jt[:, k] - numt)) < 1e-5 * np.max(np.abs(Jt))


def test_a_multi_dof_balance_converges_and_matches_the_time_integration():
    """Two DOFs: a mass (0.1 kg, 4e7 N/m) carrying the damper's tangential end and a stiff
    platform (1 kg, 1e10 N/m) pressing it (the damper's uniform normal motion), both forced.  The
    branch is traced with H = 3; its largest tangential response is then checked against the time
    integration of the element alone driven by that point's motion (tangential and normal)."""
    s = hbm.Structure(np.diag([0.1, 1.0]), np.diag([40.0, 2e3]), np.diag([4e7, 1e10]), force=[40.0, 3e3])
    el = AllModeMicroslip2D(BAR, LOAD, KN, CELLS, 15)
    res = hbm.frequency_response(s, hbm.Contact(el, dof=0, normal_dof=1), (1.8e4, 2.6e4), harmonics=3,
                                 response_dof=0, tol=None, stability=False,
                                 steps=hbm.Steps(max_steps=400))
    assert res.success and np.all(res.residual_norm < 1e-6)
    i = int(np.argmax(res.amplitude))
    omega = float(res.omega[i])

    def real(c):  # complex harmonics c_h = Xc_h - i Xs_h -> [X0, Xc1, Xs1, ...]
        return np.concatenate([[c[0].real], np.column_stack([c[1:].real, -c[1:].imag]).ravel()])

    X, V = real(res.coefficients(0)[i]), real(res.coefficients(1)[i])
    a = math.hypot(X[1], X[2])
    assert a > 10 * el.slip_amplitude(omega)  # well into microslip
    sol = el.solve(X, V, omega)
    scale = BAR.k_star * a
    ref, fine = march((1.0, 1.0), list(V), omega, 2000, X=list(X)), march((1.0, 1.0), list(V), omega, 4000, X=list(X))
    assert np.max(np.abs(fine - ref)) < 2e-4 * scale
    diff = np.abs(sol.F[:3] - fine) / scale
    print(f"balance point omega = {omega:.1f} rad/s, a = {a:.3g} m: |dF| / (k* a) = {diff.max():.1e}")
    assert np.max(diff) < 1e-3


@pytest.mark.parametrize("kwargs, name", [
    ({"kn": -1.0}, "kn"), ({"kn": math.inf}, "kn"), ({"cells": 1}, "cells"), ({"harmonics": 0}, "harmonics"),
    ({"n_t": 30}, "n_t"), ({"n_t": 4}, "n_t"), ({"n_t": 16.0}, "n_t"), ({"normal_shape": (1.0,)}, "normal_shape"),
    ({"normal_shape": (1.0, math.nan)}, "normal_shape"), ({"bar": "bar"}, "bar")])
def test_bad_input_is_refused(kwargs, name):
    args = {"bar": BAR, "load": LOAD, "kn": KN, "cells": 4, "harmonics": 3, **kwargs}
    with pytest.raises(ValueError, match=name):
        AllModeMicroslip2D(**args)


def test_bad_motion_is_refused():
    el = AllModeMicroslip2D(BAR, LOAD, KN, 4, 3)
    for a, v, name in ((-1.0, None, "a"), (A, [0.0, 1.0], "v"), (A, [0.0] * 9, "v"), (A, [math.nan, 0, 0], "v")):
        with pytest.raises(ValueError, match=name):
            el.solve(a, v, 1.0)
    with pytest.raises(ValueError, match="omega"):
        el.solve(A, None, -1.0)
    with pytest.raises(ValueError, match="x must be"):
        el.periodic_force(np.zeros(8), 1.0)
