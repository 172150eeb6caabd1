"""Two- and three-region microslip elements: limits, properties, hard cases, paper findings."""

import math
import re

import numpy as np
import pytest

from contact_models import Bar, QuadraticLoad, ThreeRegionMicroslip, TwoRegionMicroslip, UniformLoad
from conftest import BAR
from _static_bar import slip_zones, static_state

FREQS = [0.0, 0.01, 0.2, 0.3, 0.5]  # in omega_c


def loop_energy(el, a, omega, n=40001):
    """Closed-loop integral of f dx = int f(theta) a cos(theta) dtheta (periodic trapezoid)."""
    x, f = el.hysteresis(a, omega, n=n)
    theta = np.linspace(-0.5 * np.pi, 1.5 * np.pi, n)
    g = f * a * np.cos(theta)
    return np.sum(g[:-1]) * (theta[1] - theta[0])


@pytest.fixture(params=["two", "three"])
def element(request, two, three):
    return {"two": two, "three": three}[request.param]


@pytest.mark.parametrize("w", FREQS)
def test_stuck_below_a_min_exactly(element, bar, w):
    omega = w * bar.omega_c
    am = element.slip_amplitude(omega)
    a = np.array([0.0, 1e-3, 0.5, 0.999999, 1.0]) * am
    fs, fc = element.fourier(a, omega)
    assert np.array_equal(fs, element.stuck_stiffness(omega) * a)
    assert np.array_equal(fc, np.zeros_like(a))


@pytest.mark.parametrize("w", FREQS)
def test_fc_nonnegative_and_energy_is_loop_area(element, bar, w):
    omega = w * bar.omega_c
    am = element.slip_amplitude(omega)
    a = np.logspace(-1, 4, 400) * am
    fs, fc = element.fourier(a, omega)
    assert np.all(fc >= 0.0) and np.all(np.isfinite(fs))
    for r in (1.5, 3.0, 10.0):
        e = loop_energy(element, r * am, omega)
        fc1 = float(element.fourier(r * am, omega, rtol=1e-10)[1])
        assert math.pi * r * am * fc1 == pytest.approx(e, rel=1e-6)


@pytest.mark.parametrize("w", [0.0, 0.3])
def test_continuity_at_region_changes(element, bar, w):
    omega = w * bar.omega_c
    K = element.stuck_stiffness(omega)
    pieces = element._path(omega)[1]
    marks = [element.slip_amplitude(omega), element.gross_slip_amplitude(omega)]
    marks += [p.s1 for p in pieces[:-1]]  # three -> two regions
    # An interior onset under inertia can fold (docs/theory.md): the interface then snaps
    # from the stuck line to the branch past the fold, F jumps by dF = F(s0) - K s0 and
    # f_c by exactly 4|dF|/pi at a_min; nowhere else.
    dF = pieces[0].F0 - K * pieces[0].s0
    for i, m in enumerate(marks):
        lo = element.fourier(m * (1 - 1e-9), omega, rtol=1e-10)
        hi = element.fourier(m * (1 + 1e-9), omega, rtol=1e-10)
        scale = K * m
        assert abs(hi[0] - lo[0]) < 1e-7 * scale
        expected = 4 * abs(dF) / math.pi if i == 0 else 0.0
        assert abs(hi[1] - lo[1] - expected) < 1e-7 * scale
    assert abs(dF) < 1e-5 * K * marks[0]
    if element is not None and w == 0.0:
        assert dF == pytest.approx(0.0, abs=1e-12 * K * marks[0])


def test_three_region_has_the_three_to_two_change(three, bar):
    pieces = three._path(0.0)[1]
    assert len(pieces) == 2
    a_switch = pieces[0].s1
    L1, L2 = three.boundaries(np.array([0.999, 1.001]) * a_switch)
    assert L2[0] < bar.L and L2[1] == bar.L  # right stuck region has vanished
    assert 0.0 < L1[1] < L1[0] < bar.L


@pytest.mark.parametrize("w", [0.0, 0.3])
def test_analytic_derivatives(element, bar, w):
    omega = w * bar.omega_c
    am = 7.5e-7
    a = np.array([0.5, 1.2, 2.4, 5.0, 7.0, 40.0]) * am
    fs, fc, dfs, dfc = element.fourier_derivatives(a, omega, rtol=1e-11)
    h = 1e-6 * a
    p = element.fourier(a + h, omega, rtol=1e-12)
    m = element.fourier(a - h, omega, rtol=1e-12)
    np.testing.assert_allclose(dfs, (p[0] - m[0]) / (2 * h), rtol=1e-6)
    np.testing.assert_allclose(dfc, (p[1] - m[1]) / (2 * h), rtol=1e-6, atol=1e-6 * element.stuck_stiffness(omega))


def test_rtol_controls_accuracy(element, bar):
    omega = 0.3 * bar.omega_c
    a = np.array([1.3, 2.7, 6.0, 25.0]) * 7.5e-7
    ref = element.fourier(a, omega, rtol=1e-13)
    for rtol in (1e-3, 1e-6, 1e-9):
        got = element.fourier(a, omega, rtol=rtol)
        for g, r in zip(got, ref):
            assert np.all(np.abs(g - r) <= rtol * np.abs(r))


def test_gross_slip_limits(element, bar):
    for omega in (0.0, 0.3 * bar.omega_c):
        ag = element.gross_slip_amplitude(omega)
        a = 1e4 * ag
        fs, fc = element.fourier(a, omega)
        K_slip = element.slip_stiffness(omega)
        F_int = element.loading_curve(2 * ag, omega) - 2 * ag * K_slip  # loading-curve intercept past gross slip
        # the loop becomes a parallelogram: f_s -> K_slip a, f_c -> 4 F_int / pi
        assert fs / (K_slip * a) == pytest.approx(1.0, rel=1e-3)
        assert fc == pytest.approx(4 * F_int / math.pi, rel=1e-3)


def test_gross_slip_static_closed_form(two, bar):
    """omega = 0: slip stiffness is beta in series with the bar; past gross slip
    F = mu N + beta u(0) with x = u(0)(1 + beta L/EA) + mu N L/(2 EA)."""
    S, b, L, muN = bar.EA, bar.beta, bar.L, 30.0
    K_slip = 1.0 / (1.0 / b + L / S)
    assert two.slip_stiffness(0.0) == pytest.approx(K_slip, rel=1e-13)
    x = 10 * two.gross_slip_amplitude(0.0)
    u0 = (x - muN * L / (2 * S)) / (1 + b * L / S)
    assert two.loading_curve(x, 0.0) == pytest.approx(muN + b * u0, rel=1e-12)


def test_two_region_onset_and_stick_slip_history(two, bar):
    am = two.slip_amplitude(0.0)
    assert am == pytest.approx(bar.mu * 100.0 / (bar.k * bar.L), rel=1e-14)
    a = 2.0 * am  # below gross slip (2.5 a_min)
    theta, L1, L2 = two.stick_slip_history(a, 0.0, n=721)
    assert np.all(L2 == bar.L)
    # everything sticks at a reversal, then the slip front runs in from x = L to L1(a)
    assert L1[0] == bar.L and L1[361] == bar.L
    L1a = float(two.boundaries(a, 0.0)[0])
    assert L1[360] == pytest.approx(L1a, rel=1e-9) and L1[-1] == pytest.approx(L1a, rel=1e-9)
    assert np.all(np.diff(L1[:361]) <= 0) and np.all(np.diff(L1[361:]) <= 0)
    assert 0.0 < L1a < bar.L


def test_paper_findings(two, three, bar):
    # uniform load: slip starts at the excited end; concave ratio-12: inside, and earlier (Fig. 14)
    assert float(two.boundaries(1.0001 * two.slip_amplitude(0.0))[0]) > 0.99 * bar.L
    L1, L2 = three.boundaries(1.0001 * three.slip_amplitude(0.0))
    assert 0.2 * bar.L < L1 < L2 < 0.8 * bar.L
    assert three.slip_amplitude(0.0) < two.slip_amplitude(0.0)
    am = two.slip_amplitude(0.0)
    for el in (two, three):
        # Figs. 9-10, 12-13: just past slip F_s falls and F_c rises as omega goes 0.01 -> 0.5 omega_c
        a = 1.5 * am
        w = np.array([0.01, 0.2, 0.3, 0.5]) * bar.omega_c
        fs, fc = el.fourier(a, w)
        assert np.all(np.diff(fs) < 0.0) and np.all(np.diff(fc) > 0.0)
    # Fig. 14: the three-region interface damps below the two-region a_min
    assert float(three.fourier(0.8 * am, 0.3 * bar.omega_c)[1]) > 0.0
    assert float(two.fourier(0.8 * am, 0.3 * bar.omega_c)[1]) == 0.0


def test_zero_normal_load_is_the_slipping_bar(bar):
    el = TwoRegionMicroslip(bar, UniformLoad(0.0))
    fs, fc = el.fourier([1e-9, 1e-6], 0.0)
    np.testing.assert_allclose(fs, el.slip_stiffness(0.0) * np.array([1e-9, 1e-6]), rtol=1e-14)
    assert np.all(fc == 0.0)


def test_vectorised_speed(two, bar):
    import time

    a = np.logspace(-1, 2, 1000) * 7.5e-7
    two.fourier(a, 0.3 * bar.omega_c)  # path cached after the first call
    t = time.perf_counter()
    two.fourier(a, 0.3 * bar.omega_c)
    assert time.perf_counter() - t < 0.5  # generous for a shared CI machine; docs/performance.md has medians


def test_bad_input(two):
    with pytest.raises(ValueError, match="a"):
        two.fourier(-1.0, 0.0)
    with pytest.raises(ValueError, match="omega"):
        two.fourier(1e-6, float("nan"))
    with pytest.raises(ValueError, match="rtol"):
        two.fourier(1e-6, 0.0, rtol=0.0)
    with pytest.raises(ValueError, match="ThreeRegion"):
        TwoRegionMicroslip(Bar(**BAR), QuadraticLoad.from_ratio(100.0, 12.0))


def test_convex_load_whose_left_end_slips_is_refused(bar):
    # ratio 0.5: at omega = 0 the stuck part is u(L1) exp(lam (x - L1)), so k u(0) exceeds mu q(0)
    # once L1 < 0.645 L: slip zones at both ends, which neither model describes.
    with pytest.raises(ValueError, match=r"x = 0 starts slipping .*L1 = 0\.64"):
        TwoRegionMicroslip(bar, QuadraticLoad.from_ratio(100.0, 0.5)).slip_amplitude(0.0)
    mild = TwoRegionMicroslip(bar, QuadraticLoad.from_ratio(100.0, 0.8))  # stays two-region to gross slip
    assert mild.slip_amplitude(0.0) == pytest.approx(bar.mu * mild.load.q(bar.L) / bar.k, rel=1e-14)


def test_static_fold_is_refused_up_front_with_a_true_message():
    """Hypothesis found this concave load (ratio 2.5) on a stiff layer (lambda L = 2.49).

    Slip starts at the tip, and the single-zone (two-region) curve folds back as the zone moves
    into the lighter middle.  The bar's own static curve does not: the static reference (any
    number of slip zones) opens a second zone inside the stuck region, at 0.848 L when
    x = 1.00075 mu q(L)/k, and its tip force keeps rising.  The element refuses the load when
    built, naming the bar, lambda L, the load and the second zone, without blaming a resonance.
    """
    bar = Bar(E=1e10, rho=1000, A=1e-4, L=0.1, k=6.2e8, beta=0, mu=1)
    load = QuadraticLoad(q0=16.67, q2=10, L=0.1)
    tip = bar.mu * load.q(bar.L) / bar.k
    x, _, _, slip = static_state(bar, load, 1.0005 * tip)
    assert len(slip_zones(x, slip)) == 1
    x, _, _, slip = static_state(bar, load, 1.001 * tip)
    inner, end = slip_zones(x, slip)
    assert 0.0 < inner[0] < inner[1] < end[0] < bar.L == end[1]
    forces = [static_state(bar, load, f * tip)[2] for f in (1.0005, 1.00075, 1.001, 1.002)]
    assert np.all(np.diff(forces) > 0.0)
    with pytest.raises(ValueError) as info:
        ThreeRegionMicroslip(bar, load)
    msg = str(info.value)
    assert msg.startswith("bar, load:") and "omega=0.0" in msg and "lambda L=2.49" in msg
    assert "q0=16.67" in msg and "resonance" not in msg and "a second slip zone opens inside a stuck region" in msg
    # the same bar with the uniform load is accepted, and so is the ratio-12 load on it
    assert ThreeRegionMicroslip(bar, QuadraticLoad.from_ratio(N=1.0, ratio=12.0)).slip_amplitude() > 0.0


def test_excited_end_that_slips_too_is_refused_naming_the_second_slip_zone():
    """Hypothesis found this ratio-2 load on a stiff layer (lambda L = 2.07, beta = 0).

    Slip starts inside, at x* = 0.943 L, only just before the excited end would (a_min is 6e-5
    below mu q(L)/k).  The slip zone [L1, L2] grows, but the tip reaches k x = mu q(L) before the
    zone reaches x = L: the end then slips on its own, a second slip zone, which the three-region
    model does not describe.  The static reference (any number of slip zones) shows the two
    zones; the element refuses the load when built, naming the end, the amplitude and the zone.
    """
    bar = Bar(E=1e10, rho=1e3, A=1e-4, L=0.1, k=4.2745e8, beta=0.0, mu=1.0)
    load = QuadraticLoad(q0=15.0, q2=7.5, L=0.1)
    tip = bar.mu * load.q(bar.L) / bar.k  # k u(L) = mu q(L): the end's own slip limit
    x, _, _, slip = static_state(bar, load, tip * (1.0 - 1e-9))
    (zone,) = slip_zones(x, slip)  # one interior zone up to that amplitude
    x, _, _, slip = static_state(bar, load, tip * (1.0 + 2e-6))
    inner, end = slip_zones(x, slip)  # just past it: the end slips too, apart from the inner zone
    assert inner[1] < end[0] < bar.L == end[1]
    # the static curve itself does not fold: the tip force rises through the second zone's opening
    forces = [static_state(bar, load, tip * f)[2] for f in (1.0 - 1e-5, 1.0, 1.0 + 1e-5, 1.0 + 1e-4)]
    assert np.all(np.diff(forces) > 0.0)
    with pytest.raises(ValueError) as info:
        ThreeRegionMicroslip(bar, load)
    msg = str(info.value)
    found = re.search(r"x = L starts slipping too, at tip amplitude (\S+) m .*\[L1, L2\] = \[(\S+), (\S+)\] L "
                      r"\(omega=0\.0\)", msg)
    assert found and msg.startswith("bar, load:") and "lambda L=2.067" in msg and "resonance" not in msg
    assert float(found[1]) == pytest.approx(tip, rel=5e-4)  # printed to 4 digits
    # printed to 4 decimals of L; the reference's cells are 5e-6 L
    assert float(found[2]) * bar.L == pytest.approx(zone[0], abs=1e-4 * bar.L)
    assert float(found[3]) * bar.L == pytest.approx(zone[1], abs=1e-4 * bar.L)
    # a little more E (lambda L = 2.047): the inner zone reaches the end first, and the load is accepted
    softer = Bar(E=1.02e10, rho=1e3, A=1e-4, L=0.1, k=4.2745e8, beta=0.0, mu=1.0)
    assert ThreeRegionMicroslip(softer, load).gross_slip_amplitude() > tip


def test_the_loading_curve_and_its_boundaries_refuse_a_displacement_that_is_not_a_finite_number(two):
    for method in (two.loading_curve, two.boundaries):
        with pytest.raises(ValueError, match=r"^x must be finite, got x=nan$"):
            method(math.nan)
        with pytest.raises(ValueError, match=r"^x must be finite, got x with an entry inf$"):
            method([0.0, math.inf])
        with pytest.raises(ValueError, match=r"^x must be a number or an array of numbers, got x='a'$"):
            method("a")


@pytest.mark.parametrize("n", [math.nan, None, "361", 1])
def test_stick_slip_history_names_a_bad_number_of_points(two, n):
    with pytest.raises(ValueError, match=rf"^n must be an integer >= 2, got n={n!r}$"):
        two.stick_slip_history(3e-6, n=n)
