"""Point contact of Fig. 16: closed form against the layout's own time-stepped force law,
derivatives, the fit of Section 3.4 (conditions, independence of the fourth condition, the
slider = mu N impossibility), comparison with the microslip elements, bad input, examples."""

import math
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.integrate import quad

from contact_models import Bar, TwoRegionMicroslip, UniformLoad
from contact_models.macroslip import Macroslip
from contact_models.point_contact import PointContact

#: A layout of the size the fit gives for the reference bar (docs/theory.md).
LAYOUT = dict(k_s=1.0e8, beta_p=2.5e7, k_p=4.0e7, slip_force=46.0)
#: Steps per cycle of the time-stepped reference.
STEPS = 2**14
#: Amplitudes in units of the slip amplitude: stuck, just slipping, gross slip.
A_OVER_Y = (0.5, 1.001, 1.01, 1.1, 3.0, 10.0, 30.0)


def stepped_fourier(element, a, n=STEPS):
    """f_s, f_c from the element's force law stepped through x = a sin(theta) from rest: a quarter
    cycle to x = a, then one full cycle [pi/2, 5 pi/2] by the periodic trapezoid rule."""
    theta = 2.0 * np.pi * np.arange(n + n // 4 + 1) / n
    f = element.force_history(np.asarray(a, dtype=float)[:, None] * np.sin(theta))
    f, th = f[:, n // 4: n // 4 + n], theta[n // 4: n // 4 + n]
    return f @ np.sin(th) * 2.0 / n, f @ np.cos(th) * 2.0 / n


def bilinear_masing(K1, K2, a_g, a):
    """f_s, f_c of the Masing loop of the loading curve with slopes K1 (x < a_g), K2 (x > a_g),
    by quadrature of the Stieltjes forms f_s = 8/(pi a) int sqrt(s(a-s)) dF, f_c = 4/(pi a) int (a-2s) dF
    (s = a (1 - cos phi)/2 makes the first smooth)."""
    def dF(s):
        return K1 if s < a_g else K2

    phi_g = math.acos(1.0 - 2.0 * a_g / a) if a_g < a else math.pi
    fs_int = sum(quad(lambda p: math.sin(p) ** 2 * dF(a * (1 - math.cos(p)) / 2), lo, hi, epsabs=0, epsrel=1e-13)[0]
                 for lo, hi in ((0.0, phi_g), (phi_g, math.pi)) if hi > lo)
    fc_int = sum(quad(lambda s: (a - 2 * s) * dF(s), lo, hi, epsabs=1e-15 * K1 * a * a, epsrel=1e-13)[0]
                 for lo, hi in ((0.0, min(a, a_g)), (min(a, a_g), a)) if hi > lo)
    return 8.0 / (math.pi * a) * a * a / 4.0 * fs_int, 4.0 / (math.pi * a) * fc_int


class StandIn:
    """The microslip interface the fit reads, with the reference bar's two-region numbers at omega = 0."""

    bar = SimpleNamespace(mu=0.3, k=8.0e8, L=0.05)
    load = SimpleNamespace(N=100.0)

    def stuck_stiffness(self, omega=0.0):
        return 4.0e7

    def slip_stiffness(self, omega=0.0):
        return 2.0e7

    def gross_slip_amplitude(self, omega=0.0):
        return 1.875e-6

    def slip_amplitude(self, omega=0.0):
        return 7.5e-7


def conditions(pc, element, omega=0.0):
    """Relative misfit of conditions (1)-(3)."""
    return np.array([
        pc.stuck_stiffness() / element.stuck_stiffness(omega) - 1.0,
        pc.slip_stiffness() / element.slip_stiffness(omega) - 1.0,
        pc.gross_slip_amplitude() / element.gross_slip_amplitude(omega) - 1.0,
    ])


# ---------------------------------------------------------------- the layout and its closed form
@pytest.mark.parametrize("layout", [LAYOUT, dict(LAYOUT, k_s=math.inf), dict(LAYOUT, beta_p=0.0)],
                         ids=["layout", "rigid k_s", "no beta_p"])
def test_fourier_matches_time_stepping_of_the_layout(layout):
    """Closed form (Jenkins + K2 after eliminating the node) vs the layout's stepped law, 1e-6."""
    pc = PointContact(**layout)
    a = np.array(A_OVER_Y) * pc.slip_amplitude()
    fs_ref, fc_ref = stepped_fourier(pc, a)
    fs, fc = pc.fourier(a)
    np.testing.assert_allclose(fs, fs_ref, rtol=1e-6)
    np.testing.assert_allclose(fc, fc_ref, rtol=1e-6, atol=1e-12 * pc.stuck_stiffness() * a[0])
    assert np.all(fc[0] == 0.0) and fs[0] == pytest.approx(pc.stuck_stiffness() * a[0], rel=1e-15)


def test_series_parallel_constants():
    k_s, b, k_p, F = LAYOUT.values()
    pc = PointContact(**LAYOUT)
    assert pc.stuck_stiffness() == pytest.approx(1 / (1 / k_s + 1 / (b + k_p)), rel=1e-15)
    assert pc.slip_stiffness() == pytest.approx(1 / (1 / k_s + 1 / b), rel=1e-15)
    # the slider slips when k_p y = F with the node at y = k_s x/(k_s + b + k_p)
    assert pc.slip_amplitude() == pytest.approx(F * (k_s + b + k_p) / (k_s * k_p), rel=1e-15)
    assert pc.gross_slip_amplitude() == pc.slip_amplitude()


def test_loading_curve_is_the_layouts_virgin_response():
    pc = PointContact(**LAYOUT)
    x = np.linspace(0.0, 5.0 * pc.slip_amplitude(), 501)
    np.testing.assert_allclose(pc.force_history(x), pc.loading_curve(x), rtol=1e-13, atol=1e-12)


@given(st.lists(st.floats(-10.0, 10.0), min_size=1, max_size=30),
       st.floats(1e6, 1e9), st.floats(0.0, 1e9), st.floats(1e6, 1e9), st.floats(1e-2, 1e3))
def test_eliminating_the_node_gives_spring_plus_jenkins(xs, k_s, beta_p, k_p, slip_force):
    """For any history, f = K2 x + Jenkins(K1 - K2, slip force (K1 - K2) a_y) (docs, Section 2)."""
    pc = PointContact(k_s, beta_p, k_p, slip_force)
    x = np.array(xs) * pc.slip_amplitude()
    D = pc.stuck_stiffness() - pc.slip_stiffness()
    jenkins = Macroslip(D, D * pc.slip_amplitude())
    expected = pc.slip_stiffness() * x + jenkins.force_history(x)
    np.testing.assert_allclose(pc.force_history(x), expected, rtol=1e-9, atol=1e-9 * slip_force)


@given(st.floats(1e5, 1e10), st.floats(0.0, 1e10), st.floats(1e5, 1e10), st.floats(1e-3, 1e3))
def test_slider_force_lies_between_intercept_and_onset_force(k_s, beta_p, k_p, slip_force):
    """The inequality behind the positivity result: (K1 - K2) a_y <= slip_force <= K1 a_y,
    both equalities at beta_p = 0 only (docs, Section 3)."""
    pc = PointContact(k_s, beta_p, k_p, slip_force)
    K1, K2, a_y = pc.stuck_stiffness(), pc.slip_stiffness(), pc.slip_amplitude()
    D = k_s**2 * k_p / ((k_s + beta_p + k_p) * (k_s + beta_p))  # K1 - K2 without cancellation
    assert K1 - K2 == pytest.approx(D, rel=1e-15 * K1 / D + 1e-14)
    assert D * a_y == pytest.approx(slip_force * k_s / (k_s + beta_p), rel=1e-12)
    assert K1 * a_y == pytest.approx(slip_force * (beta_p + k_p) / k_p, rel=1e-12)
    if beta_p > 1e-6 * min(k_s, k_p):  # (not lost to rounding)
        assert D * a_y < slip_force < K1 * a_y


def test_force_history_resumes_from_state():
    pc = PointContact(**LAYOUT)
    y = pc.slip_amplitude()
    x = np.array([0.5, 2.0, 1.0, -3.0, -2.5, 4.0]) * y
    f = pc.force_history(x)
    np.testing.assert_array_equal(pc.force_history(x[3:], x0=x[2], f0=f[2]), f[3:])
    node, slider = pc.internal_state(x[1], f[1])
    assert LAYOUT["k_p"] * (node - slider) == pytest.approx(LAYOUT["slip_force"], rel=1e-12)  # slipping


@pytest.mark.parametrize("a_over_y", [0.5, 1.0001, 1.3, 4.0, 50.0, 1e4])
def test_derivatives_match_finite_differences(a_over_y):
    pc = PointContact(**LAYOUT)
    a = a_over_y * pc.slip_amplitude()
    h = 1e-6 * a
    _, _, dfs, dfc = pc.fourier_derivatives(a)
    fs_p, fc_p = pc.fourier(a + h)
    fs_m, fc_m = pc.fourier(a - h)
    K1 = pc.stuck_stiffness()
    assert dfs == pytest.approx((fs_p - fs_m) / (2 * h), rel=1e-6, abs=1e-8 * K1)
    assert dfc == pytest.approx((fc_p - fc_m) / (2 * h), rel=1e-6, abs=1e-8 * K1)


@pytest.mark.parametrize("a_over_y", [0.4, 2.0, 25.0])
def test_loop_is_bilinear_masing_and_area_is_pi_a_fc(a_over_y):
    pc = PointContact(**LAYOUT)
    a = a_over_y * pc.slip_amplitude()
    x, f = pc.hysteresis(a, n=20001)
    assert np.trapezoid(f, x) == pytest.approx(np.pi * a * pc.fourier(a)[1], rel=1e-6, abs=1e-12 * pc.slip_force * a)
    theta = np.linspace(-0.5 * np.pi, 1.5 * np.pi, 20001)  # the same loop from the layout, after one cycle
    f_steps = pc.force_history(np.concatenate([a * np.sin(theta), x]))[theta.size:]
    np.testing.assert_allclose(f, f_steps, rtol=1e-9, atol=1e-9 * pc.slip_force)


# ---------------------------------------------------------------- the fit (Section 3.4)
def test_fit_to_stand_in_reproduces_conditions_and_values():
    el = StandIn()
    pc = PointContact.fit(el)
    np.testing.assert_allclose(conditions(pc, el), 0.0, atol=1e-10)
    # fourth condition: k_p = k L; then c = k_s/(k_s + beta_p) solves 4 c^2 - 2 c - 1 = 0
    c = (1.0 + math.sqrt(5.0)) / 4.0
    assert pc.k_p == 4.0e7
    assert pc.beta_p == pytest.approx(2.0e7 / c, rel=1e-14)
    assert pc.k_s == pytest.approx(2.0e7 / (1.0 - c), rel=1e-12)
    assert pc.slip_force == pytest.approx(37.5 / c, rel=1e-14)  # 46.35 N, not mu N = 30 N


@pytest.mark.parametrize("name", ["two", "three"])
def test_fit_reproduces_conditions_for_microslip_elements(name, request):
    el = request.getfixturevalue(name)
    for omega in (0.0, 0.3 * el.bar.omega_c):
        pc = PointContact.fit(el, omega)
        np.testing.assert_allclose(conditions(pc, el, omega), 0.0, atol=1e-10)
        assert min(pc.k_s, pc.beta_p, pc.k_p, pc.slip_force) > 0.0


@pytest.mark.parametrize("name", ["two", "three"])
def test_fitted_fourier_is_bilinear_masing_whatever_the_fourth_condition(name, request):
    el = request.getfixturevalue(name)
    K1, K2, a_g = el.stuck_stiffness(), el.slip_stiffness(), el.gross_slip_amplitude()
    fits = [PointContact.fit(el), PointContact.fit(el, k_p=3.0 * (K1 - K2)),
            PointContact.fit(el, slip_force=0.9 * K1 * a_g), PointContact.fit(el, slip_force=1.01 * (K1 - K2) * a_g)]
    assert len({pc.k_s for pc in fits}) == len(fits)  # four different layouts ...
    a = np.array([0.3, 0.99, 1.0, 1.02, 2.0, 10.0, 100.0]) * a_g
    ref = np.array([bilinear_masing(K1, K2, a_g, ai) for ai in a]).T
    for pc in fits:  # ... one f_s, f_c
        fs, fc = pc.fourier(a)
        np.testing.assert_allclose(fs, ref[0], rtol=1e-10)
        np.testing.assert_allclose(fc, ref[1], rtol=1e-10, atol=1e-14 * K1 * a[0])
        np.testing.assert_allclose(np.array(pc.fourier(a)), np.array(fits[0].fourier(a)), rtol=1e-12,
                                   atol=1e-14 * K1 * a[-1])


@pytest.mark.parametrize("name", ["two", "three"])
def test_point_contact_stuck_while_microslip_dissipates(name, request):
    el = request.getfixturevalue(name)
    pc = PointContact.fit(el)
    a = np.geomspace(1.05 * el.slip_amplitude(), 0.99 * el.gross_slip_amplitude(), 12)
    assert np.all(pc.fourier(a)[1] == 0.0)
    assert np.all(pc.fourier(a)[0] == pc.stuck_stiffness() * a)
    assert np.all(el.fourier(a)[1] > 0.0)


@pytest.mark.parametrize("name", ["two", "three"])
def test_models_merge_past_gross_slip(name, request):
    el = request.getfixturevalue(name)
    pc = PointContact.fit(el)
    k_star = el.stuck_stiffness()
    a = np.array([3.0, 10.0, 30.0]) * el.gross_slip_amplitude()
    (ms, mc), (ps, pcc) = el.fourier(a), pc.fourier(a)
    gap_s, gap_c = np.abs(ms - ps) / (k_star * a), np.abs(mc - pcc) / (k_star * a)
    assert np.all(np.diff(gap_s) < 0.0) and np.all(np.diff(gap_c) < 0.0)
    assert gap_s[-1] < 0.1 * gap_s[0] and gap_c[-1] < 0.5 * gap_c[0]
    # past gross slip the loading curves are parallel (slope K2), offset by (K1 - K2) a_g - F_g0 > 0,
    # which the fit cannot remove (docs Section 4): 37.5 - 22.5 = 15 N for the uniform bar
    K1, K2, a_g = k_star, el.slip_stiffness(), el.gross_slip_amplitude()
    offset = pc.loading_curve(a) - el.loading_curve(a)
    F_g0 = el.loading_curve(np.array([a_g]))[0] - K2 * a_g
    np.testing.assert_allclose(offset, (K1 - K2) * a_g - F_g0, rtol=1e-9)
    if name == "two":
        assert offset[0] == pytest.approx(15.0, rel=1e-9)


# ---------------------------------------------------------------- slider = mu N
@pytest.mark.parametrize("name", ["two", "three"])
def test_slider_at_mu_N_has_no_positive_layout(name, request):
    el = request.getfixturevalue(name)
    mu_N = el.bar.mu * el.load.N
    K1, K2, a_g = el.stuck_stiffness(), el.slip_stiffness(), el.gross_slip_amplitude()
    assert (K1 - K2) * a_g > mu_N  # 37.5 N and 84.6 N against 30 N
    with pytest.raises(ValueError, match=r"condition \(3\), equal gross-slip amplitude.*slip_force >= \(K1 - K2\) a_g"):
        PointContact.fit(el, slip_force=mu_N)


@given(st.floats(0.1, 10.0), st.floats(0.1, 10.0), st.floats(0.1, 10.0), st.floats(0.01, 100.0))
def test_uniform_bar_never_admits_slider_at_mu_N(E_scale, k_scale, beta_scale, N):
    """(K1 - K2) a_g > mu N for uniform-load bars: the closed form of docs Section 4 and the element."""
    bar = Bar(E=2e11 * E_scale, rho=7850.0, A=1e-5, L=0.05, k=8e8 * k_scale, beta=4e7 * beta_scale, mu=0.3)
    el = TwoRegionMicroslip(bar, UniformLoad(N=N))
    s, b, Lam = bar.EA / bar.L, bar.beta, bar.lam * bar.L
    K1 = s * Lam * (Lam * math.tanh(Lam) + b / s) / (Lam + b / s * math.tanh(Lam))
    K2 = b * s / (b + s)
    a_g = bar.mu * N * ((1 + b / s) / (bar.k * bar.L) + 1 / (2 * s))
    assert el.stuck_stiffness() == pytest.approx(K1, rel=1e-12)
    assert el.slip_stiffness() == pytest.approx(K2, rel=1e-12)
    assert el.gross_slip_amplitude() == pytest.approx(a_g, rel=1e-9)
    assert (K1 - K2) * a_g > bar.mu * N
    with pytest.raises(ValueError, match=r"condition \(3\)"):
        PointContact.fit(el, slip_force=bar.mu * N)
    PointContact.fit(el)  # the default fourth condition always has a positive layout at omega = 0


def test_fit_boundary_is_a_rigid_series_spring():
    """slip_force = (K1 - K2) a_g, or k_p = K1 - K2, is the limit k_s = inf: spring K2 parallel
    to a Jenkins element (K1 - K2, (K1 - K2) a_g)."""
    K1, K2, a_g = 4e7, 2e7, 1.875e-6
    for pc in (PointContact.from_bilinear(K1, K2, a_g, slip_force=(K1 - K2) * a_g),
               PointContact.from_bilinear(K1, K2, a_g, k_p=K1 - K2)):
        assert pc.k_s == math.inf
        assert (pc.beta_p, pc.k_p) == pytest.approx((K2, K1 - K2), rel=1e-15)
        assert pc.slip_force == pytest.approx(37.5, rel=1e-15)
        np.testing.assert_allclose([pc.stuck_stiffness(), pc.slip_stiffness(), pc.slip_amplitude()],
                                   [K1, K2, a_g], rtol=1e-15)


@given(st.floats(1e5, 1e10), st.floats(1e4, 1e10), st.floats(1e5, 1e10), st.floats(1e-3, 1e3))
def test_from_bilinear_inverts_the_layout(k_s, beta_p, k_p, slip_force):
    pc = PointContact(k_s, beta_p, k_p, slip_force)
    target = (pc.stuck_stiffness(), pc.slip_stiffness(), pc.slip_amplitude())
    for again in (PointContact.from_bilinear(*target, slip_force=slip_force),
                  PointContact.from_bilinear(*target, k_p=k_p)):
        np.testing.assert_allclose([again.k_s, again.beta_p, again.k_p, again.slip_force],
                                   [k_s, beta_p, k_p, slip_force], rtol=1e-6)
        np.testing.assert_allclose(
            [again.stuck_stiffness(), again.slip_stiffness(), again.slip_amplitude()], target, rtol=1e-10)


# ---------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    "change, name",
    [
        (dict(k_s=-1.0), "k_s"), (dict(k_s=math.nan), "k_s"), (dict(k_s=0.0), "k_s"),
        (dict(beta_p=-1.0), "beta_p"), (dict(beta_p=math.nan), "beta_p"), (dict(beta_p=math.inf), "beta_p"),
        (dict(k_p=-1.0), "k_p"), (dict(k_p=0.0), "k_p"), (dict(k_p=math.nan), "k_p"),
        (dict(slip_force=0.0), "slip_force"), (dict(slip_force=-1.0), "slip_force"),
        (dict(slip_force=math.nan), "slip_force"),
    ],
)
def test_bad_parameters_name_themselves(change, name):
    with pytest.raises(ValueError, match=name):
        PointContact(**dict(LAYOUT, **change))


@pytest.mark.parametrize(
    "args, kwargs, match",
    [
        ((4e7, -1.0, 1e-6), dict(k_p=1e8), r"condition \(2\)"),
        ((4e7, 4e7, 1e-6), dict(k_p=1e8), r"condition \(1\)"),
        ((4e7, 2e7, 0.0), dict(k_p=1e8), r"condition \(3\)"),
        ((4e7, 2e7, 1e-6), dict(k_p=1.5e7), r"condition \(1\).*k_p >= K1 - K2"),
        ((4e7, 2e7, 1e-6), dict(slip_force=45.0), r"condition \(3\).*slip_force < K1 a_g"),
        ((4e7, 2e7, 1e-6), dict(slip_force=19.0), r"condition \(3\).*slip_force >= \(K1 - K2\) a_g"),
        ((4e7, 2e7, 1e-6), dict(), "exactly one of k_p and slip_force"),
        ((4e7, 2e7, 1e-6), dict(k_p=1e8, slip_force=30.0), "exactly one of k_p and slip_force"),
        ((math.nan, 2e7, 1e-6), dict(k_p=1e8), "stuck_stiffness"),
        ((4e7, 2e7, 1e-6), dict(k_p=math.nan), "k_p"),
        ((4e7, 2e7, 1e-6), dict(slip_force=-1.0), "slip_force"),
    ],
)
def test_fit_failures_name_the_condition(args, kwargs, match):
    with pytest.raises(ValueError, match=match):
        PointContact.from_bilinear(*args, **kwargs)


def test_fit_above_the_bars_slip_stiffness_zero_fails_on_condition_2(two):
    with pytest.raises(ValueError, match=r"condition \(2\)"):
        PointContact.fit(two, 0.9 * two.bar.omega_c)  # the sliding bar's dynamic stiffness is < 0 there
    with pytest.raises(ValueError, match="omega"):
        PointContact.fit(two, -1.0)


# ---------------------------------------------------------------- examples
@pytest.fixture
def examples(monkeypatch):
    import importlib
    from pathlib import Path

    monkeypatch.syspath_prepend(str(Path(__file__).resolve().parent.parent / "examples"))
    return importlib.import_module


def test_example_fig17_18(examples, tmp_path):
    out = examples("fig17_18_point_contact").main(outdir=tmp_path, small=True)
    assert all((tmp_path / f"fig{n}.png").exists() for n in (17, 18))
    assert out["a_g_over_a_min"] == pytest.approx(2.5, rel=1e-12)
    assert out["point_Fc_below_a_g"] == 0.0
    assert out["point_contact"].slip_force == pytest.approx(37.5 * 4 / (1 + math.sqrt(5)), rel=1e-12)
    gaps = out["gaps"]
    assert gaps[3.0][0] > gaps[10.0][0] > gaps[30.0][0] and gaps[3.0][1] > gaps[10.0][1] > gaps[30.0][1]


def test_example_three_region(examples, tmp_path):
    out = examples("point_contact_three_region").main(outdir=tmp_path, small=True)
    assert (tmp_path / "point_contact_three_region.png").exists()
    assert out["a_g_over_a_min2"] == pytest.approx(5.642857142857143, rel=1e-9)
    assert out["gaps"][30.0][1] < out["gaps"][3.0][1]


def test_the_loading_curve_refuses_a_non_finite_displacement_and_a_negative_omega():
    pc = PointContact(k_s=1.0, beta_p=1.0, k_p=1.0, slip_force=1.0)
    with pytest.raises(ValueError, match=r"^x must be finite, got x=nan$"):
        pc.loading_curve(math.nan)
    with pytest.raises(ValueError, match=r"^omega must be >= 0, got omega=-1.0$"):
        pc.loading_curve(0.5, -1.0)
