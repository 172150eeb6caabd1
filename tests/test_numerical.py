"""NumericalMicroslip: the discretised bar of Eq. 30, integrated in time (docs/validation.md).

Order: closed forms of the discretised stuck bar, the quasi-static check against the analytic
elements, properties (f_c >= 0, energy = loop area, steady state), the dynamic element
at low frequency, derivatives of the shooting map against finite differences, convergence,
cost.  Long studies are marked slow (docs/validation.md has their numbers).
"""

import importlib
import math
import re
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from contact_models import QuadraticLoad, ThreeRegionMicroslip, TwoRegionMicroslip, UniformLoad
from contact_models import numerical as nm
from contact_models.numerical import NumericalMicroslip

# Amplitudes of the quasi-static check, in units of each element's own a_min.
RATIOS = (1.5, 3.0, 10.0, 30.0)


def _loads():
    return [(UniformLoad(N=100.0), TwoRegionMicroslip), (QuadraticLoad.from_ratio(N=100.0, ratio=12.0), ThreeRegionMicroslip)]


@pytest.fixture(scope="module", params=[0, 1], ids=["uniform", "concave12"])
def pair(request, bar):
    load, cls = _loads()[request.param]
    return cls(bar, load), load


# --------------------------------------------------------------- the discretised stuck bar
def test_stuck_stiffness_converges_to_closed_form(bar):
    """k* of the discretised bar -> S lam (S lam tanh(lam L) + beta)/(S lam + beta tanh(lam L)) at O(h^2)."""
    S, lam, L, beta = bar.EA, bar.lam, bar.L, bar.beta
    th = np.tanh(lam * L)
    k_star = S * lam * (S * lam * th + beta) / (S * lam + beta * th)
    assert k_star == pytest.approx(4.0e7, rel=1e-12)
    errs = []
    for n in (100, 200, 400):
        num = NumericalMicroslip(bar, UniformLoad(N=100.0), cells=n)
        errs.append(abs(num.stuck_stiffness(0.0) / k_star - 1.0))
    assert errs[-1] < 1e-6
    rates = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(np.abs(rates - 2.0) < 0.05)
    # and at a frequency, against the bar's dynamic stiffness (Eq. 1-2)
    num = NumericalMicroslip(bar, UniformLoad(N=100.0), cells=400)
    w = 0.3 * bar.omega_c
    assert num.stuck_stiffness(w) == pytest.approx(float(bar.stuck_stiffness(w)), rel=2e-6)


def test_omega_c_against_the_continuous_bar(bar):
    errs = [abs(NumericalMicroslip(bar, UniformLoad(N=100.0), cells=n).omega_c / bar.omega_c - 1.0) for n in (100, 200, 400)]
    assert errs[-1] < 1e-7
    assert np.all(np.abs(np.log2(np.array(errs[:-1]) / np.array(errs[1:])) - 2.0) < 0.05)
    # the discretised dynamic stiffness vanishes at the discretised omega_c
    num = NumericalMicroslip(bar, UniformLoad(N=100.0), cells=100)
    assert abs(num.stuck_stiffness(num.omega_c)) < 1e-6 * num.stuck_stiffness(0.0)


def test_slip_amplitude(bar, two, three):
    # uniform load: the tip node slips first, at exactly mu N / (k L)
    num = NumericalMicroslip(bar, UniformLoad(N=100.0), cells=200)
    assert num.slip_amplitude(0.0) == pytest.approx(bar.mu * 100.0 / (bar.k * bar.L), rel=1e-12)
    assert num.slip_amplitude(0.3 * bar.omega_c) == pytest.approx(two.slip_amplitude(0.3 * bar.omega_c), rel=1e-12)
    # concave load: an interior node, within O(h^2) of the analytic onset
    num = NumericalMicroslip(bar, QuadraticLoad.from_ratio(N=100.0, ratio=12.0), cells=400)
    assert num.slip_amplitude(0.0) == pytest.approx(three.slip_amplitude(0.0), rel=1e-4)


# --------------------------------------------------------------- quasi-static check
def test_quasi_static_agrees_with_analytic(pair):
    """The independent quasi-static check of the analytic elements: n = 400 cells,
    a/a_min in {1.5, 3, 10, 30}, target 0.5 %.

    At omega = 0 the single-mode solution is exact, so the difference is the discretisation
    error; it is below 1e-4 here (docs/validation.md)."""
    analytic, load = pair
    num = NumericalMicroslip(analytic.bar, load, cells=400)
    a = np.array(RATIOS) * analytic.slip_amplitude(0.0)
    t0 = time.perf_counter()
    fs, fc = num.fourier(a, 0.0)
    elapsed = time.perf_counter() - t0
    fs_a, fc_a = analytic.fourier(a, 0.0)
    assert np.max(np.abs(fs / fs_a - 1.0)) < 1e-4
    assert np.max(np.abs(fc / fc_a - 1.0)) < 1e-4
    assert elapsed < 10.0  # ~1 s on the CI machine


def test_quasi_static_loop_and_boundaries(pair, bar):
    """The steady loop and L1, L2 against the analytic Masing loop and boundaries (Fig. 6, 7, 19)."""
    analytic, load = pair
    num = NumericalMicroslip(bar, load, cells=400)
    for ratio in (1.5, 10.0):
        a = ratio * analytic.slip_amplitude(0.0)
        r = num.simulate(a, 0.0)
        assert r.converged and r.cycles == 2  # Masing: steady after the first reversal
        th = np.where(r.theta <= 1.5 * np.pi, r.theta, r.theta - 2.0 * np.pi)
        x = a * np.sin(th)
        s = np.where(th <= 0.5 * np.pi, 0.5 * (a + x), 0.5 * (a - x))
        F = analytic.loading_curve(s, 0.0)
        Fa = analytic.loading_curve(np.array([a]), 0.0)[0]
        f_masing = np.where(th <= 0.5 * np.pi, -Fa + 2.0 * F, Fa - 2.0 * F)
        assert np.max(np.abs(r.f - f_masing)) < 2e-4 * np.max(np.abs(f_masing))
        L1, L2 = analytic.boundaries(s, 0.0)
        slipping = s > analytic.slip_amplitude(0.0)
        assert np.max(np.abs(r.L1 - np.where(slipping, L1, bar.L))) < 0.005 * bar.L
        assert np.max(np.abs(r.L2 - np.where(slipping, L2, bar.L))) < 0.005 * bar.L


@pytest.mark.parametrize("ratio", [1e3, float("inf")])
def test_load_vanishing_mid_length(bar, ratio):
    """Hard case: q nearly or exactly 0 at mid-length (nodes with zero slip force always slip)."""
    load = QuadraticLoad.from_ratio(N=100.0, ratio=ratio)
    num = NumericalMicroslip(bar, load, cells=200)
    a = np.array([0.5, 2.0, 10.0]) * 7.5e-7
    fs, fc = num.fourier(a, 0.0)
    fs_a, fc_a = ThreeRegionMicroslip(bar, load).fourier(a, 0.0)
    assert np.all(np.isfinite(fs)) and np.all(fc > 0.0)
    assert np.max(np.abs(fs / fs_a - 1.0)) < 1e-4
    assert np.max(np.abs(fc / fc_a - 1.0)) < 2e-3
    r = NumericalMicroslip(bar, load, cells=30, steps_per_cycle=128).simulate(2 * 7.5e-7, 0.3 * bar.omega_c)
    assert r.converged and np.all(np.isfinite(r.L1)) and r.f_c > 0.0


def test_below_a_min_is_the_stuck_bar(bar, pair):
    analytic, load = pair
    num = NumericalMicroslip(bar, load, cells=100)
    for w in (0.0, 0.2 * bar.omega_c):
        a = 0.9 * num.slip_amplitude(w)
        fs, fc = num.fourier(a, w)
        assert fs == num.stuck_stiffness(w) * a and fc == 0.0
        x, f = num.hysteresis(a, w, n=21)
        assert np.allclose(f, num.stuck_stiffness(w) * x, rtol=0, atol=1e-12 * abs(fs))
    # the time integration itself: no slip, f exactly linear in x
    a = 0.9 * num.slip_amplitude(0.0)
    r = num.simulate(a, 0.0)
    assert np.all(r.L1 == bar.L)
    assert abs(r.f_c) < 1e-12 * r.f_s
    assert r.f_s == pytest.approx(num.stuck_stiffness(0.0) * a, rel=1e-10)
    assert num.fourier(0.0, 0.0) == (0.0, 0.0)


def test_quasi_static_rate_independent(bar):
    """Quasi-static steps are solved exactly; the step count only enters the Fourier quadrature."""
    load = UniformLoad(N=100.0)
    a = 3.0 * 7.5e-7
    coarse = NumericalMicroslip(bar, load, cells=100, steps_per_cycle=256).simulate(a)
    fine = NumericalMicroslip(bar, load, cells=100, steps_per_cycle=2048).simulate(a)
    assert fine.force_at(coarse.theta) == pytest.approx(coarse.f, abs=1e-9 * np.max(np.abs(coarse.f)))
    assert coarse.f_s == pytest.approx(fine.f_s, rel=1e-4)
    assert coarse.f_c == pytest.approx(fine.f_c, rel=1e-3)


def test_force_history_is_the_same_bar(bar):
    load = QuadraticLoad.from_ratio(N=100.0, ratio=12.0)
    num = NumericalMicroslip(bar, load, cells=100, steps_per_cycle=256)
    a = 5.0 * num.slip_amplitude(0.0)
    r = num.simulate(a)
    k = np.arange(1, 256 // 4 + 3 * 256 + 1)  # virgin quarter + 3 cycles
    f = num.force_history(a * np.sin(k * 2.0 * np.pi / 256))
    assert f[-256:] == pytest.approx(r.f[k[-256:] % 256], abs=1e-9 * np.max(np.abs(r.f)))


# --------------------------------------------------------------- properties
@pytest.mark.parametrize("w_ratio", [0.0, 0.3])
def test_fc_nonnegative_and_energy_is_loop_area(pair, bar, w_ratio):
    """f_c > 0 past a_min, and pi a f_c (trapezoid rule in theta) equals the area of the loop
    (polygon through 4097 points of the linearly interpolated steady cycle) to 1e-4; the
    difference is the O(dtheta^2 / 12) error of the linear interpolation."""
    analytic, load = pair
    w = w_ratio * bar.omega_c
    if w == 0.0:
        num = NumericalMicroslip(bar, load, cells=200)
    else:
        num = NumericalMicroslip(bar, load, cells=30, steps_per_cycle=256)
    for ratio in (1.2, 4.0, 40.0):
        a = ratio * num.slip_amplitude(w)
        r = num.simulate(a, w)
        assert r.converged
        assert r.f_c > 0.0
        x, f = r.loop(4097)
        area = 0.5 * np.sum((f[1:] + f[:-1]) * np.diff(x))  # counter-clockwise in (x, f)
        assert np.pi * a * r.f_c == pytest.approx(area, rel=1e-4)
    if w == 0.0:  # the public loop is the same steady cycle
        xh, fh = num.hysteresis(a, w, n=4097)
        assert np.array_equal(xh, x) and np.array_equal(fh, f)


def test_steady_state_criterion(bar):
    load = UniformLoad(N=100.0)
    num = NumericalMicroslip(bar, load, cells=40, steps_per_cycle=256, steady_tol=1e-8)
    r = num.simulate(4.0 * 7.5e-7, 0.2 * bar.omega_c)
    assert r.success and r.change <= 1e-8 and r.history[-1] == r.change
    assert r.cycles <= 10
    # without shooting the undamped bar settles slowly: not steady in a few cycles, and says so
    plain = NumericalMicroslip(bar, load, cells=40, steps_per_cycle=256, shooting=False, max_cycles=4)
    p = plain.simulate(4.0 * 7.5e-7, 0.2 * bar.omega_c)
    assert not p.converged and p.change > 1e-8 and "not steady" in p.message
    # but it heads for the same orbit
    assert p.f_s == pytest.approx(r.f_s, rel=2e-2) and p.f_c == pytest.approx(r.f_c, rel=5e-2)
    # a fine mesh far below omega_c (the bar's own modes carry v and acceleration): still a few cycles
    fine = NumericalMicroslip(bar, load, cells=200, steps_per_cycle=128).simulate(3.0 * 7.5e-7, 0.01 * bar.omega_c)
    assert fine.converged and fine.cycles <= 6


# --------------------------------------------------------------- dynamic element
def test_low_frequency_dynamic_agrees_with_analytic(pair, bar):
    """At omega = 0.01 omega_c, F_s and F_c within 1 %, L1 within 2 % of L (coarse CI setting)."""
    analytic, load = pair
    w = 0.01 * bar.omega_c
    num = NumericalMicroslip(bar, load, cells=50, steps_per_cycle=256)
    a = np.array(RATIOS) * analytic.slip_amplitude(w)
    runs = [num.simulate(ai, w) for ai in a]
    fs, fc = np.array([r.f_s for r in runs]), np.array([r.f_c for r in runs])
    fs_a, fc_a = analytic.fourier(a, w)
    assert np.max(np.abs(fs / fs_a - 1.0)) < 0.01
    assert np.max(np.abs(fc / fc_a - 1.0)) < 0.01
    r = runs[1]  # a = 3 a_min
    th = np.where(r.theta <= 1.5 * np.pi, r.theta, r.theta - 2.0 * np.pi)
    x = r.a * np.sin(th)
    s = np.where(th <= 0.5 * np.pi, 0.5 * (r.a + x), 0.5 * (r.a - x))
    L1, L2 = analytic.boundaries(s, w)
    # compare where the analytic slip zone is longer than two cells (at nucleation the
    # numerical zone is still empty while the analytic one has zero length)
    zone = (s > analytic.slip_amplitude(w)) & (L2 - L1 > 2.0 * bar.L / num.cells)
    assert np.count_nonzero(zone) > 50
    assert np.max(np.abs(r.L1 - L1)[zone]) < 0.02 * bar.L
    assert np.max(np.abs(r.L2 - L2)[zone]) < 0.02 * bar.L


def test_dynamic_below_and_at_frequency_zero(bar):
    num = NumericalMicroslip(bar, UniformLoad(N=100.0), cells=40, steps_per_cycle=128, quasi_static=False)
    with pytest.raises(ValueError, match="omega"):
        num.simulate(1e-6, 0.0)
    with pytest.raises(ValueError, match="omega"):
        num.fourier(1e-6, 0.0)
    # quasi_static=True at a frequency: the inertia is dropped
    qs = NumericalMicroslip(bar, UniformLoad(N=100.0), cells=40, steps_per_cycle=128, quasi_static=True)
    assert qs.fourier(3e-6, 0.3 * bar.omega_c) == qs.fourier(3e-6, 0.0)


def test_shooting_derivative_against_finite_differences(bar):
    """The carried derivative of the (piecewise affine) step map equals a finite difference."""
    load = QuadraticLoad.from_ratio(N=100.0, ratio=12.0)
    num = NumericalMicroslip(bar, load, cells=20, steps_per_cycle=64)
    d, n = num._disc, num._disc.n
    for rho_inf in (1.0, 0.9):
        b = nm._Batch(d, np.array([4e-6]), np.array([0.3 * bar.omega_c]), False, 64, 1.0, rho_inf)
        for _ in range(80):  # into the ramp, with slip
            b.step()
        s0 = (b.u[:, :n].copy(), b.v[:, :n].copy(), b.acc[:, :n].copy(), b.z.copy(), b.count)
        zset = np.ones(n + 1, bool)
        T = nm._unit_tangent(d, zset)
        for _ in range(16):
            b.step()
            T = b.tangent_step(T)
        s1 = np.concatenate([b.u[0, :n], b.v[0, :n], b.acc[0, :n], b.z[0]])
        rng = np.random.default_rng(3)
        direction = rng.standard_normal(T[0].shape[1])
        scale = np.concatenate([np.full(n, 4e-6), np.full(n, 4e-6 * 4e4), np.full(n, 4e-6 * 1.6e9), np.full(n + 1, 4e-6)])
        direction *= scale * 1e-9
        b.count = s0[4]
        b.set_state(s0[0] + direction[:n], s0[1] + direction[n:2 * n], s0[2] + direction[2 * n:3 * n],
                    s0[3] + direction[3 * n:])
        for _ in range(16):
            b.step()
        s2 = np.concatenate([b.u[0, :n], b.v[0, :n], b.acc[0, :n], b.z[0]])
        predicted = np.concatenate([T[0] @ direction, T[1] @ direction, T[2] @ direction, T[3] @ direction])
        assert np.allclose((s2 - s1) / scale, predicted / scale, rtol=0, atol=1e-6 * np.max(np.abs(predicted / scale)))


def test_halving_cell_and_step_within_error_bars(bar):
    """Halving h and dt changes F_s, F_c by less than the stated error bars (coarse CI setting).

    docs/validation.md states, for cells=50, steps_per_cycle=256 at up to 0.5 omega_c, error
    bars of 2e-3 on F_s and F_c (relative to k* a); here one point at 0.3 omega_c."""
    load = UniformLoad(N=100.0)
    w = 0.3 * bar.omega_c
    a = 3.0 * 7.5e-7
    k_star = bar.k_star
    coarse = NumericalMicroslip(bar, load, cells=50, steps_per_cycle=256).simulate(a, w)
    fine = NumericalMicroslip(bar, load, cells=100, steps_per_cycle=512).simulate(a, w)
    assert coarse.converged and fine.converged
    assert abs(coarse.f_s - fine.f_s) / (k_star * a) < 2e-3
    assert abs(coarse.f_c - fine.f_c) / (k_star * a) < 2e-3


# --------------------------------------------------------------- interface, validation, cost
def test_broadcasting_and_result_object(bar, tmp_path):
    num = NumericalMicroslip(bar, UniformLoad(N=100.0), cells=40, steps_per_cycle=128)
    a = np.array([[0.0, 1e-6], [2e-6, 5e-7]])
    fs, fc = num.fourier(a, 0.0)
    assert fs.shape == (2, 2) and np.all(fc >= 0.0)
    fs2, fc2 = num.fourier(a.ravel(), 0.0)
    assert np.array_equal(fs.ravel(), fs2)
    r = num.simulate(2e-6)
    r.to_csv(tmp_path / "loop.csv")
    data = np.loadtxt(tmp_path / "loop.csv", delimiter=",", skiprows=1)
    assert data.shape == (128, 5)
    assert r.x == pytest.approx(2e-6 * np.sin(r.theta))


@pytest.mark.parametrize("kwargs, name", [
    (dict(cells=1), "cells"), (dict(cells=2.5), "cells"), (dict(steps_per_cycle=30), "steps_per_cycle"),
    (dict(quasi_static="yes"), "quasi_static"), (dict(steady_tol=0.0), "steady_tol"),
    (dict(max_cycles=1), "max_cycles"), (dict(rho_inf=1.5), "rho_inf"), (dict(shooting=None), "shooting"),
])
def test_bad_options(bar, kwargs, name):
    with pytest.raises(ValueError, match=name):
        NumericalMicroslip(bar, UniformLoad(N=100.0), **kwargs)


@pytest.mark.parametrize("name", ["quasi_static", "shooting"])
def test_a_flag_given_an_array_or_a_number_is_refused_by_name(bar, name):
    """An array failed in ``in (True, False)`` with numpy's "truth value of an array is ambiguous", naming
    nothing; 0 was taken as False."""
    for value in (np.ones((2, 2)), 0):
        with pytest.raises(ValueError, match=rf"^{name} must be .*True or False, got {name}="):
            NumericalMicroslip(bar, UniformLoad(N=100.0), **{name: value})


def test_bad_inputs(bar):
    num = NumericalMicroslip(bar, UniformLoad(N=100.0), cells=20)
    with pytest.raises(ValueError, match="a"):
        num.fourier(-1e-6, 0.0)
    with pytest.raises(ValueError, match="bar"):
        NumericalMicroslip("bar", UniformLoad(N=100.0))
    with pytest.raises(ValueError, match="x"):
        num.force_history(np.array([0.0, np.nan]))


# --------------------------------------------------------------- long studies
@pytest.mark.slow
@pytest.mark.parametrize("w_ratio", [0.2, 0.3, 0.5])
def test_dynamic_convergence_study(pair, bar, w_ratio):
    """The coarse setting's error bar (2e-3 k* a for cells=50, 256 steps) at every amplitude and
    at 0.2, 0.3 and 0.5 omega_c; docs/validation.md has the finer study (4.7e-5 at 200 cells)."""
    analytic, load = pair
    w = w_ratio * bar.omega_c
    a = np.array(RATIOS) * analytic.slip_amplitude(0.0)
    coarse = NumericalMicroslip(bar, load, cells=50, steps_per_cycle=256).fourier(a, w)
    fine = NumericalMicroslip(bar, load, cells=100, steps_per_cycle=512).fourier(a, w)
    for c, f in zip(coarse, fine):
        assert np.max(np.abs(c - f) / (bar.k_star * a)) < 2e-3


@pytest.mark.slow
def test_quasi_static_convergence_rate(pair, bar):
    """Errors against the exact (analytic, omega = 0) values fall with n; n = 1600 below 1e-5."""
    analytic, load = pair
    a = np.array(RATIOS) * analytic.slip_amplitude(0.0)
    fs_a, fc_a = analytic.fourier(a, 0.0)
    errs = []
    for n in (100, 400, 1600):
        fs, fc = NumericalMicroslip(bar, load, cells=n, steps_per_cycle=4096).fourier(a, 0.0)
        errs.append(max(np.max(np.abs(fs / fs_a - 1)), np.max(np.abs(fc / fc_a - 1))))
    assert errs[2] < errs[1] < errs[0]
    assert errs[2] < 1e-5


# --------------------------------------------------------------- the validation examples
EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _example(name):
    if str(EXAMPLES) not in sys.path:
        sys.path.insert(0, str(EXAMPLES))
    return importlib.import_module(name)


def test_example_quasi_static():
    rows = _example("validation_quasi_static").main(small=True)
    assert len(rows) == 12
    assert max(max(abs(r["dFs"]), abs(r["dFc"])) for r in rows) < 2e-3  # 100 cells (7e-4); 4e-5 at 400
    first = rows[0]
    assert (first["load"], first["ratio"]) == ("uniform", 1.5)
    assert first["Fs_num"] == pytest.approx(0.956790, abs=2e-6)


def test_example_fig19(tmp_path):
    out = _example("validation_fig19").main(outdir=tmp_path, small=True)
    assert Path(out["path"]).stat().st_size > 10_000
    assert out["uniform@0.01"]["L1"] < 0.02 and out["concave12@0.01"]["L2"] < 0.02
    # at 0.5 omega_c the full solution slips deeper than the single-mode one
    assert out["uniform@0.5"]["min_L1_numerical"] < out["uniform@0.5"]["min_L1_analytic"] - 0.02


@pytest.mark.slow
def test_example_dynamic(tmp_path):
    out = _example("validation_dynamic").main(outdir=tmp_path, small=True)
    rows = out["rows"]
    assert Path(out["path"]).stat().st_size > 10_000
    low = [r for r in rows if r["w"] == 0.01]
    assert max(max(abs(r["dFs"]), abs(r["dFc"])) for r in low) < 0.01
    assert max(max(r["Fs_err"], r["Fc_err"]) for r in rows) < 2e-3


@pytest.mark.slow
def test_example_convergence(tmp_path):
    out = _example("validation_convergence").main(small=True, outdir=tmp_path)
    e = out["qs_cells_uniform"].max(axis=1)
    assert e[-1] < e[0] / 8  # n: 50 -> 200, second order


def test_the_constructor_names_a_bad_integrator_setting():
    from contact_models import Bar
    from conftest import BAR

    bar, load = Bar(**BAR), UniformLoad(N=100.0)
    bad = [("steps_per_cycle", math.nan, r"steps_per_cycle must be a multiple of 4 and >= 8, got steps_per_cycle=nan"),
           ("steps_per_cycle", "8", r"steps_per_cycle must be a multiple of 4 and >= 8, got steps_per_cycle='8'"),
           ("max_cycles", math.nan, r"max_cycles must be an integer >= 2, got max_cycles=nan"),
           ("rho_inf", "0.5", r"rho_inf must be a number, got rho_inf='0.5'"),
           ("rho_inf", True, r"rho_inf must be a number, got rho_inf=True"),
           ("rho_inf", None, r"rho_inf must be a number, got rho_inf=None"),
           ("steady_tol", 2.0, r"steady_tol must be in \(0, 1\) \(a relative accuracy\), got steady_tol=2.0")]
    for name, value, message in bad:
        with pytest.raises(ValueError, match=f"^{message}$"):
            NumericalMicroslip(bar, load, 10, **{name: value})
    with pytest.raises(ValueError, match=r"^load must be a normal load \(UniformLoad, QuadraticLoad, FunctionLoad or "
                                         r"SampledLoad\), got load='x'$"):
        NumericalMicroslip(bar, "x", 10)


def test_simulate_and_natural_frequencies_name_a_bad_tolerance_or_count():
    from contact_models import Bar
    from conftest import BAR

    el = NumericalMicroslip(Bar(**BAR), UniformLoad(N=100.0), 10)
    for tol in (-1.0, 0.0, 1.0):
        with pytest.raises(ValueError,
                           match=rf"^steady_tol must be in \(0, 1\) \(a relative accuracy\), got steady_tol={tol!r}$"):
            el.simulate(1e-6, steady_tol=tol)
    for count in (0, 12, "2", 2.5):
        with pytest.raises(ValueError, match=rf"^count must be an integer in 1\.\.11 \(the nodes of cells=10\), "
                                             rf"got count={re.escape(repr(count))}$"):
            el.natural_frequencies(count)
