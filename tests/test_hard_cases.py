"""Every hard case of docs/theory.md (section 6), for every element and for the solver.

Each test asserts finite, continuous and accurate output against a limit or an independent
value, not only the absence of an exception.  Property tests over random parameters are in
tests/test_properties.py.
"""

import math

import numpy as np
import pytest

from contact_models import (Bar, ContactElement, Macroslip, PointContact, QuadraticLoad, ThreeRegionMicroslip,
                            TwoRegionMicroslip, UniformLoad)
from conftest import BAR
from hbm import Blade, frequency_response

A_MIN = 7.5e-7  # two-region a_min of the reference bar (docs/theory.md)


@pytest.fixture(scope="module")
def elements(bar, two, three):
    return {
        "two": two,
        "three": three,
        "convex": TwoRegionMicroslip(bar, QuadraticLoad.from_ratio(100.0, 0.85)),
        "macroslip": Macroslip(stiffness=4e7, slip_force=30.0),
        "point": PointContact.fit(two),
    }


NAMES = ["two", "three", "convex", "macroslip", "point"]
MICRO = ["two", "three", "convex"]


# ------------------------------------------------------------------ elements
@pytest.mark.parametrize("name", NAMES)
def test_omega_zero_limit_is_smooth(elements, name):
    """alpha -> 0 divides in Eq. 13; the entire segment functions make omega = 0 ordinary."""
    el = elements[name]
    a = np.array([0.5, 1.5, 3.0, 10.0, 30.0]) * A_MIN
    f0 = el.fourier(a, 0.0, rtol=1e-10)
    for eps in (1e-12, 1e-6, 1.0):
        f1 = el.fourier(a, eps, rtol=1e-10)
        np.testing.assert_allclose(f1[0], f0[0], rtol=1e-8)
        np.testing.assert_allclose(f1[1], f0[1], rtol=1e-8, atol=1e-12)


@pytest.mark.parametrize("name", MICRO)
def test_gamma_zero_and_imaginary(elements, bar, name):
    el = elements[name]
    w0 = math.sqrt(bar.k / (bar.rho * bar.A))  # gamma = 0 exactly
    a = np.array([1.5, 3.0, 10.0]) * A_MIN
    f = [el.fourier(a, w, rtol=1e-10) for w in (w0 * (1 - 1e-7), w0, w0 * (1 + 1e-7))]
    scale = bar.k_star * a.max()  # f_s crosses zero near here: compare on the force scale
    for fs, fc in f:
        assert np.all(np.isfinite(fs)) and np.all(np.isfinite(fc)) and np.all(fc >= 0)
    for (fs0, fc0), (fs1, fc1) in zip(f[:-1], f[1:]):
        np.testing.assert_allclose(fs1, fs0, rtol=0, atol=1e-6 * scale)
        np.testing.assert_allclose(fc1, fc0, rtol=0, atol=1e-6 * scale)
    fs, fc = el.fourier(a, 1.1 * w0)  # imaginary gamma, below omega_c
    assert np.all(np.isfinite(fs)) and np.all(fc >= 0)


@pytest.mark.parametrize("name", ["two", "three"])
def test_through_the_bar_resonance_omega_c(elements, bar, name):
    """At omega_c the stuck bar's stiffness vanishes; f_s stays finite and crosses zero smoothly."""
    el = elements[name]
    a = 0.5 * el.slip_amplitude(bar.omega_c)  # stuck: f_s = K*(omega) a
    w = bar.omega_c * np.array([0.999, 1.0, 1.001])
    fs, fc = el.fourier(a, w)
    np.testing.assert_allclose(fs, bar.stuck_stiffness(w) * a, rtol=1e-12, atol=1e-9 * bar.k_star * a)
    assert fs[0] > 0.0 > fs[2] and abs(fs[1]) < 1e-6 * bar.k_star * a
    slip = el.fourier(10 * A_MIN, w)
    assert np.all(np.isfinite(slip[0])) and np.all(slip[1] >= 0)
    assert np.all(np.abs(np.diff(slip[0])) < 0.01 * bar.k_star * 10 * A_MIN)


def test_large_gamma_L():
    b = Bar(**{**BAR, "k": 8.0e8 * 1e8})  # lam L = 1e4: cosh(lam L) overflows
    el = TwoRegionMicroslip(b, UniformLoad(100.0))
    am, ag = el.slip_amplitude(0.0), el.gross_slip_amplitude(0.0)
    a = np.array([0.5 * am, 1.5 * am, 3 * am, 1e4 * ag])
    fs, fc = el.fourier(a, 1e3)
    assert np.all(np.isfinite(fs)) and np.all(np.isfinite(fc)) and np.all(fc >= 0)
    assert fs[0] == pytest.approx(b.EA * b.lam * 0.5 * am, rel=1e-6)  # K* -> EA gamma
    # far past gross slip the bar slides: f_s -> K_slip a (series(beta, EA/L) at low omega)
    assert fs[-1] == pytest.approx(el.slip_stiffness(1e3) * a[-1], rel=1e-3)


@pytest.mark.parametrize("name", NAMES)
def test_at_and_just_above_a_min(elements, bar, name):
    el = elements[name]
    omega = 0.3 * bar.omega_c
    am = el.slip_amplitude(omega)
    K = el.stuck_stiffness(omega)
    fs, fc = el.fourier(np.array([am, am * (1 + 1e-9)]), omega)
    assert fs[0] == K * am and fc[0] == 0.0
    assert fs[1] == pytest.approx(K * am, rel=1e-8)
    jump, tangent = 0.0, K
    if hasattr(el, "_path"):  # an onset fold jumps (docs/theory.md, section 6)
        first = el._path(omega)[1][0]
        jump = 4 * abs(first.F0 - K * first.s0) / math.pi
        _, _, ds, dF = first.evaluate(np.array([0.0]))
        tangent = abs(float(dF[0] / ds[0])) if jump > 0 else K
    # df_c/da = -f_c/a + 4/(pi a) (F(a) - a F'(a)), F(a) ~ K a: the growth is at most (4/pi)(K + |F'|) da
    assert 0.0 <= fc[1] - jump <= 4 / math.pi * (K + tangent) * 1e-9 * am


@pytest.mark.parametrize("name", MICRO)
def test_boundaries_reach_both_ends(elements, bar, name):
    el = elements[name]
    am, ag = el.slip_amplitude(0.0), el.gross_slip_amplitude(0.0)
    L1, L2 = el.boundaries(np.array([ag * (1 - 1e-12), am * (1 + 1e-12)]))
    assert L1[0] < 1e-5 * bar.L and L2[0] == bar.L  # L1 -> 0 at gross slip
    if name == "three":
        assert abs(L1[1] - L2[1]) < 1e-4 * bar.L  # slip nucleates at x*: L1 = L2
    else:
        assert L1[1] > bar.L * (1 - 1e-4)  # L1 -> L at onset
    fs, fc = el.fourier(np.array([ag * (1 - 1e-12), ag * (1 + 1e-12)]), 0.0)
    assert np.all(np.isfinite(fs)) and np.all(np.abs(np.diff(fs)) < 1e-6 * bar.k_star * ag)


@pytest.mark.parametrize("name", NAMES)
def test_far_past_gross_slip(elements, name):
    """a = 1e4 x the gross-slip amplitude: the loop is a parallelogram."""
    el = elements[name]
    ag = el.gross_slip_amplitude(0.0) if hasattr(el, "gross_slip_amplitude") else el.slip_amplitude(0.0)
    a = 1e4 * ag
    fs, fc = el.fourier(a, 0.0)
    K_slip = el.slip_stiffness(0.0) if hasattr(el, "slip_stiffness") else 0.0
    F_int = float(el.loading_curve(2 * ag, 0.0)) - 2 * ag * K_slip  # force intercept of the sliding line
    # f_s/a -> K_slip (for the Jenkins element f_s ~ k a (y/a)^1.5 -> 0 relative to k a)
    assert fs == pytest.approx(K_slip * a, rel=1e-3, abs=1e-5 * el.stuck_stiffness(0.0) * a)
    assert fc == pytest.approx(4 * F_int / math.pi, rel=1e-3)


@pytest.mark.parametrize("ratio", [1e3, math.inf])
def test_normal_load_near_zero_somewhere(bar, ratio):
    el = ThreeRegionMicroslip(bar, QuadraticLoad.from_ratio(100.0, ratio))
    am = el.slip_amplitude(0.0)
    if ratio == math.inf:
        assert am < 1e-12 * A_MIN  # unloaded at mid-length: slips at once (0 up to where x* is solved)
    a = np.logspace(-2, 3, 50) * A_MIN
    for omega in (0.0, 0.2 * bar.omega_c):
        fs, fc = el.fourier(a, omega)
        assert np.all(np.isfinite(fs)) and np.all(fc >= 0.0)
        assert np.all(np.diff(fs / a) < 0)  # secant stiffness falls with amplitude
    # slip starts inside, near the lightly loaded middle
    L1, L2 = el.boundaries(max(1.001 * am, 1e-3 * A_MIN))
    assert 0.2 * bar.L < L1 < L2 < 0.8 * bar.L


@pytest.mark.parametrize("N", [1e-9, 1e9])
def test_extreme_total_loads(bar, N):
    el = TwoRegionMicroslip(bar, UniformLoad(N))
    a = np.array([1e-9, 1e-7, 1e-6])
    fs, fc = el.fourier(a, 0.2 * bar.omega_c)
    if N < 1:  # slides freely: the slipping bar
        np.testing.assert_allclose(fs, el.slip_stiffness(0.2 * bar.omega_c) * a, rtol=1e-6)
        assert np.all(fc < 1e-8 * bar.k_star * a)
    else:  # stuck
        assert np.all(fs == bar.stuck_stiffness(0.2 * bar.omega_c) * a) and np.all(fc == 0)


def test_near_resonant_damper_bar(two, bar):
    """Near omega_c the element stays finite and its loop area is still pi a f_c."""
    omega = 0.95 * bar.omega_c
    a = 3 * A_MIN
    fs, fc = two.fourier(a, omega, rtol=1e-10)
    x, f = two.hysteresis(a, omega, n=40001)
    theta = np.linspace(-0.5 * np.pi, 1.5 * np.pi, 40001)
    area = np.sum((f * a * np.cos(theta))[:-1]) * (theta[1] - theta[0])
    assert np.isfinite(fs) and fc > 0 and math.pi * a * fc == pytest.approx(area, rel=1e-5)


# ------------------------------------------------------------------ solver
def jenkins_peak(blade, stiffness, slip_force):
    """Independent peak of blade + Jenkins: the largest a for which
    a^2 [(k - m w^2 + f_s/a)^2 + (c w + f_c/a)^2] = F^2 has a real root w."""
    from scipy.optimize import brentq

    m, c, k, F = blade.mass, blade.damping, blade.stiffness, blade.force

    def gap(a):  # min over w of the left side minus F^2
        y = slip_force / stiffness
        if a <= y:
            p, q = stiffness, 0.0
        else:
            psi = math.acos(1 - 2 * y / a)
            p = stiffness * (psi - math.sin(2 * psi) / 2) / math.pi
            q = 4 * slip_force * (1 - y / a) / (math.pi * a)
        # d/dw of (k + p - m w^2)^2 + (c w + q)^2 = 0: -4 m w (k + p - m w^2) + 2 c (c w + q) = 0
        roots = np.roots([4 * m * m, 0.0, -4 * m * (k + p) + 2 * c * c, 2 * c * q])
        ws = [r.real for r in roots if abs(r.imag) < 1e-9 * abs(r) and r.real > 0]
        return min(a * a * ((k + p - m * w * w) ** 2 + (c * w + q) ** 2) for w in ws) - F * F

    lo, hi = 1e-12, F / blade.damping  # gap(lo) < 0 < gap(hi)
    a = brentq(gap, lo, hi, xtol=1e-16, rtol=1e-14)
    return a


def test_sharp_resonance_damping_ratio_1e5():
    blade = Blade.from_modal(frequency=1000.0, damping_ratio=1e-5, mass=1.0, force=1.0)
    jen = Macroslip(stiffness=1e5, slip_force=0.5)
    frf = frequency_response(blade, jen, omega_range=(800.0, 1200.0))
    assert frf.success and np.all(frf.residual_norm <= 1e-8)
    assert frf.peak().amplitude == pytest.approx(jenkins_peak(blade, 1e5, 0.5), rel=1e-6)


class CubicSpring(ContactElement):
    """A hardening spring f = k3 x^3 (test double): f_s = 3/4 k3 a^3, f_c = 0."""

    frequency_dependent = False

    def __init__(self, k3):
        self.k3 = k3

    def _fourier_derivatives(self, a, omega, rtol):
        return 0.75 * self.k3 * a**3, 0.0 * a, 2.25 * self.k3 * a**2, 0.0 * a

    def _stuck_stiffness(self, omega):
        return 0.0

    def _slip_amplitude(self, omega):
        return 0.0

    def _hysteresis(self, a, omega, n):
        x = a * np.sin(np.linspace(-0.5 * np.pi, 1.5 * np.pi, n))
        return x, self.k3 * x**3


def test_folds_and_jumps():
    """A hardening element bends the peak over: two folds, found where d omega / d a = 0."""
    blade = Blade(mass=1.0, stiffness=1.0, damping=0.02, force=0.05)
    el = CubicSpring(k3=1.0)
    frf = frequency_response(blade, el, omega_range=(0.5, 2.5))
    assert frf.success and len(frf.folds_omega) == 2
    assert np.any(np.diff(frf.omega) < 0)  # the branch turns back
    a, w = frf.amplitude, frf.omega
    m, c, k, F = 1.0, 0.02, 1.0, 0.05
    G = a * a * ((k - m * w * w + 0.75 * a * a) ** 2 + (c * w) ** 2) - F * F
    assert np.max(np.abs(G)) < 1e-8 * F * F
    for wf, af in zip(frf.folds_omega, frf.folds_amplitude):
        # a turning point in omega: G = 0 and dG/da = 0 there (d omega/da = -G_a/G_w = 0)
        D = k - m * wf * wf + 0.75 * af * af
        P = D * D + (c * wf) ** 2
        dGda = 2 * af * P + 3 * af**3 * D
        assert abs(dGda) < 1e-5 * (2 * af * P + 3 * af**3 * abs(D))


def test_damper_shifts_the_peak_by_40_percent():
    """A stuck damper of 0.96 k: the resonance moves from w_n to 1.4 w_n; closed form."""
    zeta = 1e-3
    blade = Blade.from_modal(frequency=100.0, damping_ratio=zeta, mass=1.0, force=1.0)
    kd = 0.96 * blade.stiffness
    jen = Macroslip(stiffness=kd, slip_force=1e6)  # never slips
    frf = frequency_response(blade, jen, omega_range=(50.0, 200.0))
    K, c, m = blade.stiffness + kd, blade.damping, blade.mass
    wn = math.sqrt(K / m)
    z = c / (2 * math.sqrt(K * m))
    w_peak = wn * math.sqrt(1 - 2 * z * z)
    a_peak = blade.force / abs(K - m * w_peak**2 + 1j * c * w_peak)
    assert wn / 100.0 == pytest.approx(1.4, rel=1e-12)
    assert frf.peak().omega == pytest.approx(w_peak, rel=1e-6)
    assert frf.peak().amplitude == pytest.approx(a_peak, rel=1e-6)
    assert frf.nfev == 0  # stuck throughout: the element's Fourier routine was never called


@pytest.mark.parametrize("N", [1e-6, 1e6])
def test_frf_with_near_zero_and_huge_normal_load(bar, N):
    """N -> 0: the damper is the freely sliding bar; N huge: it is stuck. Both linear, closed form."""
    el = TwoRegionMicroslip(bar, UniformLoad(N))
    w_c = 0.3 * bar.omega_c
    blade = Blade.from_modal(frequency=w_c, damping_ratio=2e-3, mass=0.05, force=1.0)
    frf = frequency_response(blade, el, omega_range=(0.8 * w_c, 1.6 * w_c))
    assert frf.success
    w = frf.omega
    if N > 1:
        Kd = bar.stuck_stiffness(w)
    else:
        Kd = np.array([el.slip_stiffness(x) for x in w])
    exact = blade.force / np.abs(blade.stiffness + Kd - blade.mass * w**2 + 1j * blade.damping * w)
    np.testing.assert_allclose(frf.amplitude, exact, rtol=1e-6 if N < 1 else 1e-8)


def test_frequency_range_from_zero(two):
    blade = Blade.from_modal(frequency=3e4, damping_ratio=2e-3, mass=0.1, force=4.0)
    frf = frequency_response(blade, two, omega_range=(0.0, 5e4))
    assert frf.success and frf.omega[0] == 0.0
    assert frf.amplitude[0] == pytest.approx(blade.force / (blade.stiffness + two.stuck_stiffness(0.0)), rel=1e-10)
    assert frf.omega[-1] == pytest.approx(5e4) and np.all(np.isfinite(frf.amplitude))


def test_frequency_range_across_omega_c(two, bar):
    """Past omega_c of the damper bar the single-mode model leaves its range; the run says so,
    keeps every point it computed, and those points are accurate."""
    blade = Blade.from_modal(frequency=1.0e5, damping_ratio=2e-3, mass=0.01, force=1.0)
    frf = frequency_response(blade, two, omega_range=(0.7 * bar.omega_c, 1.3 * bar.omega_c))
    assert np.max(frf.omega) > bar.omega_c  # the branch gets through omega_c itself
    if not frf.success:
        assert "single-mode" in frf.message and "stops at omega" in frf.message
    assert np.all(frf.residual_norm <= 1e-8) and np.all(np.isfinite(frf.amplitude))


def test_a_force_of_1e200_is_traced_without_overflow_to_the_linear_peak():
    """At F = 1e200 N the slider's 0.02 N is nothing: the curve is the linear blade's, whose peak is
    F/(c sqrt(k/m - c^2/(4 m^2))) (m = k = 1, c = 0.004); the estimate's amplitude projections are
    formed scale-free (no overflow warning leaves the library)."""
    import warnings

    from contact_models import Macroslip
    from hbm import Contact

    c, F = 0.004, 1e200
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        frf = frequency_response(Blade(mass=1.0, stiffness=1.0, damping=c, force=F),
                                 [Contact(Macroslip(1.0, 0.02), dof=0)], omega_range=(0.6, 1.8))
    pk = frf.peak()
    assert frf.success and pk.converged and np.all(np.isfinite(frf.error_estimate))
    assert abs(pk.amplitude / (F / (c * math.sqrt(1.0 - c * c / 4.0))) - 1.0) < 1e-7
    assert abs(pk.omega / math.sqrt(1.0 - c * c / 2.0) - 1.0) < 1e-7
