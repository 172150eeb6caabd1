"""Time laws of the elements for multi-harmonic balance.

Every Masing time law against direct time stepping (``step``/``force_history`` from rest,
several periods) for periodic signals with several reversals; the quasi-static bar against the
discretised quasi-static bar with return mapping (``NumericalMicroslip``, as in
tests/test_quasistatic_check.py); every Jacobian against central differences.
"""

import math

import numpy as np
import pytest

from contact_models import (CubicSpring, Macroslip, NumericalMicroslip, PointContact, QuasiStatic,
                            TwoRegionMicroslip, UniformLoad)
from contact_models.numerics.masing import aft_matrices, diagonal_product, to_harmonics, to_time

N_T = 64
THETA = 2.0 * np.pi * np.arange(N_T) / N_T


def signal(rng, H=5, mean=0.0, symmetric_extremes=False):
    """A periodic signal with several reversals (random harmonics up to H)."""
    X = rng.normal(size=2 * H + 1) * np.concatenate([[0.0], np.repeat(0.6 ** np.arange(H), 2)])
    x = aft_matrices(H, N_T)[1] @ X
    if symmetric_extremes:  # x_max = -x_min: the virgin start ends on the outer loop
        x = x - 0.5 * (x.max() + x.min())
    return x + mean


def reversals(x):
    d = np.sign(np.diff(np.append(x, x[0])))
    return int(np.sum(d != np.roll(d, 1)))


ELEMENTS = {
    "jenkins": Macroslip(stiffness=2.0, slip_force=0.3),
    "point": PointContact(k_s=5.0, beta_p=0.5, k_p=3.0, slip_force=0.4),
}


@pytest.mark.parametrize("name", sorted(ELEMENTS))
def test_masing_law_matches_time_stepping_over_many_reversals(name):
    el = ELEMENTS[name]
    rng = np.random.default_rng(3)
    checked = 0
    for _ in range(60):
        x = signal(rng, mean=rng.normal())
        if np.ptp(x) < 2.5 * el.slip_amplitude() or reversals(x) < 4:
            continue  # gross slip once per period makes the periodic state unique
        f, _ = el.periodic_force(x)
        f_step = el.force_history(np.tile(x, 4))[-N_T:]
        np.testing.assert_allclose(f, f_step, rtol=0, atol=1e-12)
        checked += 1
    assert checked >= 20


def test_stuck_jenkins_carries_no_mean_force():
    """Below slip the outer loop is centred on K_inf x_c = 0 (the stated convention)."""
    el = ELEMENTS["jenkins"]
    x = 0.05 * np.cos(THETA) + 0.02 * np.sin(3 * THETA) + 1.0
    f, _ = el.periodic_force(x)
    xc = 0.5 * (x.max() + x.min())
    np.testing.assert_allclose(f, 2.0 * (x - xc), atol=1e-14)


def test_quasi_static_bar_against_discretised_bar(bar):
    el = QuasiStatic(TwoRegionMicroslip(bar, UniformLoad(100.0)))
    num = NumericalMicroslip(bar, UniformLoad(100.0), cells=400, quasi_static=True)
    rng = np.random.default_rng(7)
    am = el.slip_amplitude()
    for ratio in (3.0, 12.0):  # microslip only; past gross slip
        x = signal(rng, symmetric_extremes=True)
        x *= ratio * am / (0.5 * np.ptp(x))
        assert reversals(x) >= 4
        f, _ = el.periodic_force(x)
        f_num = num.force_history(np.tile(x, 3))[-N_T:]
        assert np.max(np.abs(f - f_num)) < 5e-3 * np.ptp(f)


def _fd_jacobian(fun, x, h):
    J = np.empty((fun(x).size, x.size))
    for j in range(x.size):
        e = np.zeros_like(x)
        e[j] = h
        J[:, j] = (fun(x + e) - fun(x - e)) / (2 * h)
    return J


@pytest.mark.parametrize("name", ["jenkins", "point", "quasi_static", "cubic"])
def test_periodic_and_harmonic_jacobians_against_finite_differences(name, bar):
    el = {"quasi_static": lambda: QuasiStatic(TwoRegionMicroslip(bar, UniformLoad(100.0))),
          "cubic": lambda: CubicSpring(k3=0.7)}.get(name, lambda: ELEMENTS[name])()
    rng = np.random.default_rng(11)
    unit = el.reference_amplitude()
    x = signal(rng, mean=0.3) * 4.0 * unit
    h = 1e-7 * unit
    f, J = el.periodic_force(x)
    Jfd = _fd_jacobian(lambda y: el.periodic_force(y)[0], x, h)
    scale = np.max(np.abs(J))
    assert np.max(np.abs(J - Jfd)) < 1e-5 * scale
    H = 4
    X = np.linalg.lstsq(aft_matrices(H, N_T)[1], x, rcond=None)[0]
    F, dF, _ = el.harmonic_force(X, 1.0, n_t=N_T)
    dFfd = _fd_jacobian(lambda Y: el.harmonic_force(Y, 1.0, n_t=N_T)[0], X, h)
    assert np.max(np.abs(dF - dFfd)) < 1e-5 * np.max(np.abs(dF))


def test_aft_is_the_real_fft_of_the_force():
    E, Einv = aft_matrices(3, 16)
    np.testing.assert_allclose(E @ Einv, np.eye(7), atol=1e-14)
    f = np.cos(THETA) ** 5 + np.sin(2 * THETA)
    np.testing.assert_allclose(to_harmonics(f, 3), aft_matrices(3, N_T)[0] @ f, atol=1e-14)
    # cos^5 = (10 cos + 5 cos 3 + cos 5)/16
    np.testing.assert_allclose(to_harmonics(f, 5), [0, 10 / 16, 0, 0, 1, 5 / 16, 0, 0, 0, 1 / 16, 0], atol=1e-14)


def test_cubic_spring_closed_forms():
    el = CubicSpring(k3=2.0)
    a = 0.7
    F, J, _ = el.harmonic_force([0.0, 0.0, a, 0.0, 0.0, 0.0, 0.0], 1.0, n_t=32)
    # sin^3 = (3 sin - sin 3)/4
    np.testing.assert_allclose(F, [0, 0, 0.75 * 2 * a**3, 0, 0, 0, -0.25 * 2 * a**3], atol=1e-14)
    fs, fc = el.fourier(a)
    assert fs == pytest.approx(0.75 * 2 * a**3, rel=1e-15) and fc == 0.0


def test_masing_h1_is_the_describing_function_and_aft_converges_to_it():
    el = ELEMENTS["jenkins"]
    X = np.array([0.0, 0.3, 0.4])
    F1, J1, _ = el.harmonic_force(X, 1.0)
    fs, fc = el.fourier(0.5)
    # x = 0.5 sin(theta + psi): F = (f_s Xc + f_c Xs)/a cos + (f_s Xs - f_c Xc)/a sin
    np.testing.assert_allclose(F1, [0.0, (fs * 0.3 + fc * 0.4) / 0.5, (fs * 0.4 - fc * 0.3) / 0.5], rtol=1e-14)
    X3 = np.concatenate([X, np.zeros(4)])
    F3, _, _ = el.harmonic_force(X3, 1.0, n_t=4096)
    np.testing.assert_allclose(F3[:3], F1, atol=2e-6)


@pytest.mark.parametrize("element, name", [(Macroslip(stiffness=math.inf, slip_force=1.0), "Macroslip"),
                                           (None, "TwoRegionMicroslip")])
def test_first_harmonic_elements_refuse_more_harmonics_by_name(element, name, two):
    element = element or two
    F, J, _ = element.harmonic_force([0.0, 1e-3, 0.0], 1.0)  # H = 1 works
    assert np.all(np.isfinite(F))
    with pytest.raises(ValueError, match=name):
        element.harmonic_force(np.zeros(5), 1.0)
    with pytest.raises(ValueError, match=name):
        element.periodic_force(np.zeros(8))


def test_bad_samples_refused():
    el = ELEMENTS["jenkins"]
    with pytest.raises(ValueError, match="n_t"):
        el.harmonic_force(np.zeros(7), 1.0, n_t=7)
    with pytest.raises(ValueError, match="X"):
        el.harmonic_force(np.zeros(4), 1.0)
    with pytest.raises(ValueError, match="x"):
        el.periodic_force([0.0, np.nan, 1.0])


@pytest.mark.parametrize("H, n_t", [(1, 4), (3, 8), (7, 64), (21, 1024)])
def test_fast_transforms_equal_the_dense_matrices(H, n_t):
    rng = np.random.default_rng(H)
    E, Einv = aft_matrices(H, n_t)
    d = rng.normal(size=n_t)
    np.testing.assert_allclose(diagonal_product(d, H), (E * d) @ Einv, rtol=0, atol=1e-13)
    X = rng.normal(size=2 * H + 1)
    np.testing.assert_allclose(to_time(X, n_t), Einv @ X, rtol=0, atol=1e-13)


def test_the_cubic_springs_exact_harmonics_name_a_bad_X():
    from contact_models import CubicSpring

    el = CubicSpring(k3=1.0)
    with pytest.raises(ValueError, match=r"^X must be finite, got X with an entry nan$"):
        el.harmonic_force_exact([0.0, math.nan, 1.0])
    with pytest.raises(ValueError, match=r"^X must be of shape \('2H\+1',\) with 2H\+1 odd >= 3, got X with shape \(2,\)$"):
        el.harmonic_force_exact([0.0, 1.0])
