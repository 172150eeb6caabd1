"""The bar, the loads and the fully stuck solution against independent answers."""

import math
import re

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.linalg import eigh

from contact_models import Bar, QuadraticLoad, UniformLoad
from conftest import BAR


def naive_stuck_stiffness(bar, omega):
    """Eq. 14 at L1 = L with plain complex arithmetic (fine for moderate gamma L)."""
    g = np.sqrt(complex(bar.k / bar.EA - bar.rho * omega**2 / bar.E))
    S, L, b = bar.EA, bar.L, bar.beta
    if g == 0:
        return S * b / (S + b * L)
    K = S * g * (S * g * np.sinh(g * L) + b * np.cosh(g * L)) / (S * g * np.cosh(g * L) + b * np.sinh(g * L))
    return K.real


@pytest.mark.parametrize("ratio", [0.0, 0.2, 0.5, 0.8, 1.01, 1.2, 2.0])
def test_stuck_stiffness_closed_form(bar, ratio):
    omega = ratio * bar.omega_c
    assert float(bar.stuck_stiffness(omega)) == pytest.approx(naive_stuck_stiffness(bar, omega), rel=1e-12)


def test_k_star_and_gamma_zero(bar):
    # k* = EA lam (EA lam tanh(lam L) + beta)/(EA lam + beta tanh(lam L)) = 4e7 for this bar
    assert bar.k_star == pytest.approx(4.0e7, rel=1e-14)
    w0 = math.sqrt(bar.k / (bar.rho * bar.A))  # gamma = 0 exactly
    K0 = float(bar.stuck_stiffness(w0))
    assert K0 == pytest.approx(bar.EA * bar.beta / (bar.EA + bar.beta * bar.L), rel=1e-12)
    side = bar.stuck_stiffness([w0 * (1 - 1e-9), w0 * (1 + 1e-9)])
    np.testing.assert_allclose(side, K0, rtol=1e-7)


def test_omega_c_against_finite_elements(bar):
    """First eigenvalue of a linear FE bar on the elastic foundation, beta at x=0, x=L free."""
    n = 1000
    h = bar.L / n
    S, k, m = bar.EA, bar.k, bar.rho * bar.A
    Ke = S / h * np.array([[1, -1], [-1, 1]]) + k * h / 6 * np.array([[2, 1], [1, 2]])
    Me = m * h / 6 * np.array([[2, 1], [1, 2]])
    K = np.zeros((n + 1, n + 1))
    M = np.zeros((n + 1, n + 1))
    for e in range(n):
        K[e:e + 2, e:e + 2] += Ke
        M[e:e + 2, e:e + 2] += Me
    K[0, 0] += bar.beta
    w2 = eigh(K, M, eigvals_only=True, subset_by_index=[0, 0])[0]
    assert bar.omega_c == pytest.approx(math.sqrt(w2), rel=1e-4)
    assert abs(float(bar.stuck_stiffness(bar.omega_c))) < 1e-9 * bar.k_star


def test_omega_c_without_beta():
    b = Bar(**{**BAR, "beta": 0.0})
    assert b.omega_c == pytest.approx(math.sqrt(b.k / (b.rho * b.A)), rel=1e-14)


def test_large_gamma_L_does_not_overflow():
    # lam L = 2e4: cosh would overflow; the stiffness tends to EA*gamma.
    b = Bar(**{**BAR, "k": 8.0e8 * 4e8})
    K = float(b.stuck_stiffness(0.0))
    assert np.isfinite(K)
    assert K == pytest.approx(b.EA * b.lam, rel=1e-12)
    shape = b.stuck_shape(np.linspace(0, b.L, 11), 0.0)
    assert np.all(np.isfinite(shape)) and shape[-1] == pytest.approx(1.0)
    np.testing.assert_allclose(shape[-2], math.exp(-b.lam * b.L / 10), rtol=1e-9)


def test_stuck_shape_and_contact_force(bar):
    x = np.linspace(0, bar.L, 7)
    # omega = 0: u(x)/u(L) = (cosh(lam x) + beta/(EA lam) sinh(lam x)) / (same at L)
    lam, b = bar.lam, bar.beta / (bar.EA * bar.lam)
    exact = (np.cosh(lam * x) + b * np.sinh(lam * x)) / (np.cosh(lam * bar.L) + b * np.sinh(lam * bar.L))
    np.testing.assert_allclose(bar.stuck_shape(x, 0.0), exact, rtol=1e-13)
    f = bar.contact_force(x, 0.0, tip_force=30.0)
    np.testing.assert_allclose(f, bar.k * 30.0 / bar.k_star * exact, rtol=1e-13)


def test_slip_onset(bar):
    xs, am = bar.slip_onset(UniformLoad(100.0), 0.0)
    assert xs == bar.L and am == pytest.approx(0.3 * 100 / (8e8 * 0.05), rel=1e-14)
    conc = QuadraticLoad.from_ratio(100.0, 12.0)
    xs, am_c = bar.slip_onset(conc, 0.0)
    assert 0.2 * bar.L < xs < 0.8 * bar.L  # slip starts inside (Fig. 3)
    assert am_c < am  # and at a smaller amplitude (Fig. 14)
    # at the onset point the stuck contact force equals the friction limit
    q = conc.on(bar.L).q(xs)
    assert bar.k * am_c * bar.stuck_shape(xs, 0.0) == pytest.approx(bar.mu * q, rel=1e-12)
    # the convex (hump) load slips at the excited end
    assert bar.slip_onset(QuadraticLoad.from_ratio(100.0, 0.5), 0.0)[0] == bar.L


@pytest.mark.parametrize("load", [UniformLoad(100.0), QuadraticLoad.from_ratio(100.0, 12.0),
                                  QuadraticLoad.from_ratio(100.0, 0.5), QuadraticLoad.from_ratio(100.0, 1e3)])
def test_load_integrals(load):
    ld = load.on(0.05)
    assert ld.N == pytest.approx(100.0, rel=1e-13)
    assert quad(ld.q, 0, 0.05, epsabs=0)[0] == pytest.approx(100.0, rel=1e-12)
    for x in (0.0, 0.013, 0.05):
        assert ld.I1(x) == pytest.approx(quad(ld.q, 0, x, epsabs=0)[0], rel=1e-12, abs=1e-300)
        assert ld.I2(x) == pytest.approx(quad(ld.I1, 0, x, epsabs=0)[0], rel=1e-12, abs=1e-300)
        assert ld.dq(x) == pytest.approx((ld.q(x + 1e-7) - ld.q(x - 1e-7)) / 2e-7, rel=1e-6, abs=1e-3)
    assert ld.minimum() >= 0.0


def test_quadratic_load_ratio_definition():
    ld = QuadraticLoad.from_ratio(100.0, 12.0, L=0.05)
    assert ld.q0 / (ld.q0 - ld.q2) == pytest.approx(12.0, rel=1e-13)
    assert ld.q(0.0) == pytest.approx(ld.q0) and ld.q(0.025) == pytest.approx(ld.q0 - ld.q2)
    assert QuadraticLoad.from_ratio(100.0, math.inf, L=0.05).q(0.025) == pytest.approx(0.0, abs=1e-9)


@pytest.mark.parametrize("name,value", [("E", 0.0), ("rho", -1.0), ("A", float("nan")), ("L", -0.05),
                                        ("k", 0.0), ("beta", -1.0), ("mu", -0.1), ("E", "steel")])
def test_bar_rejects_bad_parameters(name, value):
    with pytest.raises(ValueError, match=name):
        Bar(**{**BAR, name: value})


def test_loads_reject_bad_parameters():
    with pytest.raises(ValueError, match="N"):
        UniformLoad(-1.0)
    with pytest.raises(ValueError, match="q2"):
        QuadraticLoad(q0=1.0, q2=2.0, L=0.05)  # negative at mid-length
    with pytest.raises(ValueError, match="q0"):
        QuadraticLoad(q0=-1.0, q2=-2.0, L=0.05)
    with pytest.raises(ValueError, match="ratio"):
        QuadraticLoad.from_ratio(100.0, -3.0)
    with pytest.raises(ValueError, match="length"):
        QuadraticLoad(q0=1.0, q2=0.5, L=0.04).on(0.05)


@pytest.mark.parametrize("ratio", ["12", True, b"12"])
def test_from_ratio_refuses_a_ratio_that_is_not_a_number(ratio):
    with pytest.raises(ValueError, match=rf"^ratio must be a number, got ratio={re.escape(repr(ratio))}$"):
        QuadraticLoad.from_ratio(100.0, ratio)


def test_a_function_load_negative_somewhere_is_refused_when_it_has_a_length():
    from contact_models import FunctionLoad

    with pytest.raises(ValueError, match=r"^func must return values >= 0 \(a normal load\), got func=.* with "
                                         r"q\(0\.025\) = -1\.0$"):
        FunctionLoad(lambda x: np.abs(x - 0.025) * 1e3 - 1.0, L=0.05)
    with pytest.raises(ValueError, match=r"^func must return values >= 0"):  # bound by the element's bar
        FunctionLoad(lambda x: -1.0 + 0.0 * x).on(0.05)


@pytest.mark.parametrize("returned, shown", [
    # before: numpy's "could not convert string to float: 'a'", a complex q taken as its real part with a
    # ComplexWarning, and True taken as a load of 1 N/m
    (lambda x: "a", "'a'"), (lambda x: (2000.0 + 1.0j) + 0.0 * x, "array([2000.+1.j"), (lambda x: x >= 0.0, "array([ True"),
])
def test_a_function_load_returning_no_real_numbers_is_refused_naming_func(returned, shown):
    from contact_models import AllModeMicroslip, FunctionLoad

    message = rf"^func must return real numbers \(N/m\), got func=.* returning {re.escape(shown)}"
    with pytest.raises(ValueError, match=message):
        FunctionLoad(returned, L=0.05)
    with pytest.raises(ValueError, match=message):  # bound by the element's bar
        AllModeMicroslip(Bar(**BAR), FunctionLoad(returned), cells=20, harmonics=1)


@pytest.mark.parametrize("kw", [dict(x=["0", "0.05"], values=[1.0, 1.0]), dict(x=[0.0, 0.05], values=["1", "1"]),
                                dict(x=[0.0, 0.05], values=[True, 1.0])])
def test_a_sampled_load_of_strings_or_booleans_is_refused_naming_x_and_values(kw):
    """Strings were read as numbers and True as 1 N/m (numpy's float conversion)."""
    from contact_models import SampledLoad

    with pytest.raises(ValueError, match=rf"^x and values must be arrays of numbers, got x={re.escape(repr(kw['x']))}, "
                                         rf"values={re.escape(repr(kw['values']))}$"):
        SampledLoad(**kw)


@pytest.mark.parametrize("load", ["x", None, 100.0])
def test_slip_onset_names_a_load_that_is_not_a_load(load):
    with pytest.raises(ValueError, match=r"^load must be a normal load \(UniformLoad, QuadraticLoad, FunctionLoad or "
                                         rf"SampledLoad\), got load={re.escape(repr(load))}$"):
        Bar(**BAR).slip_onset(load)


@pytest.mark.parametrize("grid", [1, 2.5, "801", None])
def test_slip_onset_names_a_bad_grid(grid):
    with pytest.raises(ValueError, match=rf"^grid must be an integer >= 2, got grid={re.escape(repr(grid))}$"):
        Bar(**BAR).slip_onset(UniformLoad(N=100.0), grid=grid)


def test_the_stuck_bar_names_a_frequency_position_or_tip_value_that_is_not_a_finite_number():
    bar = Bar(**BAR)
    with pytest.raises(ValueError, match=r"^omega must be a number or an array of numbers, got omega='x'$"):
        bar.stuck_stiffness("x")
    with pytest.raises(ValueError, match=r"^x must be finite, got x=nan$"):
        bar.stuck_shape(math.nan)
    with pytest.raises(ValueError, match=r"^x must lie on the bar, 0 <= x <= L=0\.05, got x with an entry -1\.0$"):
        bar.stuck_shape([0.0, -1.0])
    with pytest.raises(ValueError, match=r"^tip_displacement must be a number, got tip_displacement='a'$"):
        bar.contact_force(0.01, tip_displacement="a")
    with pytest.raises(ValueError, match=r"^tip_force must be finite, got tip_force=nan$"):
        bar.contact_force(0.01, tip_force=math.nan)
