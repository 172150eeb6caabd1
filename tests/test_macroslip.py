"""Macroslip (Jenkins) element: describing function against time stepping, derivatives,
rigid Coulomb limit, loop energy, time-domain law, bad input."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from contact_models.macroslip import Macroslip, jenkins_fourier, z_minus_sin

K, F = 3.0e6, 2.0
Y = F / K  # slip amplitude
#: Steps per cycle of the time-stepped reference (the trapezoid rule's kink error is ~1e-8 here).
STEPS = 2**14


def stepped_fourier(element, a, n=STEPS):
    """f_s, f_c from the element's own force law stepped through x = a sin(theta) from rest.

    A quarter cycle from the relaxed state to x = a, then one full cycle [pi/2, 5 pi/2]
    integrated by the (periodic) trapezoid rule.
    """
    theta = 2.0 * np.pi * np.arange(n + n // 4 + 1) / n
    f = element.force_history(np.asarray(a, dtype=float)[:, None] * np.sin(theta))
    f, th = f[:, n // 4: n // 4 + n], theta[n // 4: n // 4 + n]
    return f @ np.sin(th) * 2.0 / n, f @ np.cos(th) * 2.0 / n


def piecewise_constant_fourier(element, a, n=4096):
    """As ``stepped_fourier`` for a force constant on each step (rigid slider): each step's
    integral of f sin / f cos is done exactly."""
    theta = 2.0 * np.pi * np.arange(n + n // 4 + 1) / n
    f = element.force_history(np.asarray(a, dtype=float)[:, None] * np.sin(theta))
    f, th = f[:, n // 4 + 1: n // 4 + n + 1], theta[n // 4: n // 4 + n + 1]
    fs = f @ (np.cos(th[:-1]) - np.cos(th[1:])) / np.pi
    fc = f @ (np.sin(th[1:]) - np.sin(th[:-1])) / np.pi
    return fs, fc


# ---------------------------------------------------------------- closed forms
def test_jenkins_formula_values():
    """The describing function as written in docs/point_contact.md (section 1), at a = 3 y."""
    el = Macroslip(stiffness=K, slip_force=F)
    a = 3.0 * Y
    psi = math.acos(1.0 - 2.0 * F / (K * a))
    fs, fc = el.fourier(a)
    assert fs == pytest.approx(K * a * (psi - math.sin(2 * psi) / 2) / math.pi, rel=1e-14)
    assert fc == pytest.approx(4.0 * F * (1.0 - F / (K * a)) / math.pi, rel=1e-14)


def test_stuck_below_slip_amplitude():
    el = Macroslip(K, F)
    a = np.array([0.0, 0.3 * Y, Y])
    fs, fc = el.fourier(a)
    np.testing.assert_allclose(fs, K * a, rtol=1e-15)
    assert np.all(fc == 0.0)
    assert el.stuck_stiffness() == K and el.slip_amplitude() == pytest.approx(Y, rel=1e-15)


@pytest.mark.parametrize("a_over_y", [0.5, 1.001, 1.01, 1.1, 3.0, 10.0, 30.0])
def test_fourier_matches_time_stepping(a_over_y):
    """Stuck, just-slipping and gross-slip amplitudes: closed form vs stepped force law, 1e-6."""
    el = Macroslip(K, F)
    a = np.array([a_over_y * Y])
    fs_ref, fc_ref = stepped_fourier(el, a)
    fs, fc = el.fourier(a)
    assert fs == pytest.approx(fs_ref, rel=1e-6)
    assert fc == pytest.approx(fc_ref, rel=1e-6, abs=1e-12 * K * a[0])


def test_rigid_coulomb_closed_form_and_time_stepping():
    el = Macroslip(stiffness=math.inf, slip_force=F)
    a = np.array([1e-9, 1e-6, 1.0])
    fs, fc = el.fourier(a)
    assert np.all(fs == 0.0)
    np.testing.assert_allclose(fc, 4.0 * F / np.pi, rtol=1e-15)
    fs_ref, fc_ref = piecewise_constant_fourier(el, a)
    np.testing.assert_allclose(fs_ref, 0.0, atol=1e-12 * F)
    np.testing.assert_allclose(fc, fc_ref, rtol=1e-6)
    assert el.fourier(0.0) == (0.0, 0.0)
    assert el.slip_amplitude() == 0.0 and el.stuck_stiffness() == math.inf


def test_stiff_jenkins_tends_to_rigid_coulomb():
    a = 1e-3
    fc_rigid = Macroslip(math.inf, F).fourier(a)[1]
    gaps = [abs(Macroslip(k, F).fourier(a)[1] - fc_rigid) / fc_rigid for k in (1e5, 1e7, 1e9)]
    assert gaps[0] > 10 * gaps[1] > 100 * gaps[2]  # f_c = 4F(1 - F/(k a))/pi: gap ~ 1/k


def test_large_amplitude_is_accurate():
    """f_s ~ (16/(3 pi)) k a (y/a)^{3/2} (1 + O(y/a)) without cancellation at y/a = 1e-12."""
    el = Macroslip(K, F)
    a = 1e12 * Y
    fs, _ = el.fourier(a)
    assert fs / (K * a * 1e-18) == pytest.approx(16.0 / (3.0 * np.pi), rel=1e-11)
    z = np.array([1e-3, 0.05, 0.3, 0.4999, 0.5001, 1.0])
    exact = np.array([math.fsum((-1) ** m * zz ** (2 * m + 3) / math.factorial(2 * m + 3) for m in range(15))
                      for zz in z])
    np.testing.assert_allclose(z_minus_sin(z), exact, rtol=1e-14)


# ---------------------------------------------------------------- derivatives and properties
@pytest.mark.parametrize("a_over_y", [0.5, 1.0001, 1.3, 4.0, 50.0, 1e4])
def test_derivatives_match_finite_differences(a_over_y):
    el = Macroslip(K, F)
    a = a_over_y * Y
    h = 1e-6 * a
    fs, fc, dfs, dfc = el.fourier_derivatives(a)
    fs_p, fc_p = el.fourier(a + h)
    fs_m, fc_m = el.fourier(a - h)
    assert (fs, fc) == (el.fourier(a)[0], el.fourier(a)[1])
    scale = K  # df/da is O(k) at worst
    assert dfs == pytest.approx((fs_p - fs_m) / (2 * h), rel=1e-6, abs=1e-8 * scale)
    assert dfc == pytest.approx((fc_p - fc_m) / (2 * h), rel=1e-6, abs=1e-8 * scale)


def test_derivatives_at_slip_onset():
    """df_s/da is continuous (= k); df_c/da jumps from 0 to 4 k/pi (f_c = 4 k y (1 - y/a)/pi)."""
    d_below = jenkins_fourier(K, Y, np.array([Y]))
    d_above = jenkins_fourier(K, Y, np.array([Y * (1 + 1e-10)]))
    assert d_below[2][0] == K and d_above[2][0] == pytest.approx(K, rel=1e-4)
    assert d_below[3][0] == 0.0 and d_above[3][0] == pytest.approx(4 * K / np.pi, rel=1e-9)


@given(st.floats(0.0, 1e3), st.floats(1e-3, 1e3), st.floats(1e-3, 1e9))
def test_fc_nonnegative_and_fs_between_zero_and_ka(a, slip_force, stiffness):
    fs, fc = Macroslip(stiffness, slip_force).fourier(a)
    assert fc >= 0.0
    assert -1e-12 * stiffness * a <= fs <= stiffness * a * (1 + 1e-14)


@pytest.mark.parametrize("a_over_y", [0.7, 2.0, 20.0])
def test_loop_area_is_pi_a_fc(a_over_y):
    el = Macroslip(K, F)
    a = a_over_y * Y
    x, f = el.hysteresis(a, n=20001)
    area = np.trapezoid(f, x)  # closed loop, clockwise in (x, f): the work done on the element
    assert area == pytest.approx(np.pi * a * el.fourier(a)[1], rel=1e-6, abs=1e-9 * F * a)


def test_broadcasting_and_omega_independence():
    el = Macroslip(K, F)
    a = np.linspace(0, 10 * Y, 5)[:, None]
    fs, fc = el.fourier(a, np.array([0.0, 1e3, 1e6]))
    assert fs.shape == (5, 3) and np.all(fs == fs[:, :1]) and np.all(fc == fc[:, :1])
    assert Macroslip.frequency_dependent is False


# ---------------------------------------------------------------- time domain
def test_force_history_state_is_carried():
    el = Macroslip(K, F)
    x = np.array([0.5 * Y, 2.0 * Y, 1.0 * Y, -3.0 * Y, -2.5 * Y])
    f = el.force_history(x)
    np.testing.assert_allclose(f, [0.5 * F, F, 0.0, -F, -0.5 * F], rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(el.slider_position(x[1], f[1]), Y, rtol=1e-12)  # slid by y
    # resume from a saved state = one uninterrupted history
    tail = el.force_history(x[3:], x0=x[2], f0=f[2])
    np.testing.assert_array_equal(tail, f[3:])
    # stateful step, vectorised over independent histories
    assert np.allclose(el.step(np.zeros(2), np.zeros(2), np.array([Y, -10 * Y])), [F, -F])


def test_rigid_force_history_holds_at_rest():
    el = Macroslip(math.inf, F)
    f = el.force_history(np.array([0.0, 1.0, 1.0, 0.5, 0.5]))
    np.testing.assert_array_equal(f, [0.0, F, F, -F, -F])


# ---------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(stiffness=-1.0, slip_force=1.0), "stiffness"),
        (dict(stiffness=0.0, slip_force=1.0), "stiffness"),
        (dict(stiffness=math.nan, slip_force=1.0), "stiffness"),
        (dict(stiffness=-math.inf, slip_force=1.0), "stiffness"),
        (dict(stiffness=1.0, slip_force=0.0), "slip_force"),
        (dict(stiffness=1.0, slip_force=math.nan), "slip_force"),
        (dict(stiffness=1.0, slip_force=math.inf), "slip_force"),
    ],
)
def test_bad_parameters_name_themselves(kwargs, name):
    with pytest.raises(ValueError, match=name):
        Macroslip(**kwargs)


def test_bad_arguments():
    el = Macroslip(K, F)
    with pytest.raises(ValueError, match="a"):
        el.fourier(np.array([1e-6, np.nan]))
    with pytest.raises(ValueError, match="omega"):
        el.fourier(1e-6, -1.0)
    with pytest.raises(ValueError, match="x"):
        el.force_history(np.array([0.0, np.inf]))


def test_the_loading_curve_refuses_a_non_finite_displacement_and_a_negative_omega():
    from contact_models import QuasiStatic

    jen = Macroslip(stiffness=1.0, slip_force=0.5)
    for el in (jen, QuasiStatic(jen)):
        with pytest.raises(ValueError, match=r"^x must be finite, got x=nan$"):
            el.loading_curve(math.nan)
        with pytest.raises(ValueError, match=r"^x must be a number or an array of numbers, got x='1'$"):
            el.loading_curve("1")
        with pytest.raises(ValueError, match=r"^omega must be >= 0, got omega=-1.0$"):
            el.loading_curve(0.5, -1.0)
