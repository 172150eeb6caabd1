"""The four-parameter Iwan element (Segalman 2005) against closed forms, limits and a
time-stepped discretisation into parallel Jenkins elements."""

import math

import numpy as np
import pytest

from contact_models import Iwan, Macroslip

F_S, K_T = 2.0, 3.0e6
CASES = [(-0.5, 0.1), (-0.8, 0.0), (0.0, 1.0)]  # (chi, beta)


@pytest.fixture(params=CASES, ids=[f"chi={c},beta={b}" for c, b in CASES])
def iwan(request):
    chi, beta = request.param
    return Iwan(slip_force=F_S, stiffness=K_T, chi=chi, beta=beta)


def test_parameters_reproduce_the_four_defining_integrals(iwan):
    """K_T = int rho, F_S = int phi rho, beta = S (chi+1)/(R phi_max^(chi+1)) (Segalman's definitions)."""
    chi, R, S, p = iwan.chi, iwan.R, iwan.S, iwan.phi_max
    assert R * p ** (chi + 1) / (chi + 1) + S == pytest.approx(K_T, rel=1e-14)
    assert R * p ** (chi + 2) / (chi + 2) + S * p == pytest.approx(F_S, rel=1e-14)
    assert S * (chi + 1) / (R * p ** (chi + 1)) == pytest.approx(iwan.beta, rel=1e-14, abs=1e-300)


def test_dissipation_is_segalmans_power_law_below_macroslip(iwan):
    """pi a f_c = 4 R a^(chi+3)/((chi+2)(chi+3)) for a <= phi_max, written here from the model."""
    chi, R = iwan.chi, iwan.R
    a = iwan.phi_max * np.array([1e-6, 1e-3, 0.1, 0.5, 0.99, 1.0])
    fc = iwan.fourier(a)[1]
    exact = 4 * R * a ** (chi + 3) / ((chi + 2) * (chi + 3))
    np.testing.assert_allclose(math.pi * a * fc, exact, rtol=1e-13)


def test_limits_small_and_large_amplitude(iwan):
    """f_s/a -> K_T as a -> 0, the softening falling like a^(chi+1) (the elements slipped at
    amplitude a have phi < a); f_c -> 4 F_S/pi and f_s/a -> 0 far past macroslip."""
    p = iwan.phi_max
    a = p * np.array([1e-6, 1e-9])
    soft = K_T - iwan.fourier(a)[0] / a
    assert np.all(soft > 0.0) and soft[1] < 0.02 * K_T
    assert soft[0] / soft[1] == pytest.approx(1e3 ** (iwan.chi + 1), rel=1e-6)
    fs, fc = iwan.fourier(np.array([1e-9 * p, 1e6 * p]))
    assert fc[1] == pytest.approx(4 * F_S / math.pi, rel=1e-5)
    assert fs[1] / (1e6 * p) < 1e-2 * K_T
    assert iwan.fourier(0.0) == (0.0, 0.0)


def test_huge_beta_is_the_jenkins_element():
    """beta -> infinity puts the whole density at phi_max = F_S/K_T: the Jenkins element."""
    iw, jen = Iwan(slip_force=F_S, stiffness=K_T, chi=-0.5, beta=1e12), Macroslip(stiffness=K_T, slip_force=F_S)
    a = F_S / K_T * np.array([0.3, 0.9, 1.5, 4.0, 100.0])
    np.testing.assert_allclose(iw.fourier(a), jen.fourier(a), rtol=1e-9, atol=1e-10 * F_S)


def jenkins_cells(iwan, cells):
    """Stiffness and slip force of ``cells`` Jenkins elements standing for the density.

    Cell [phi_i, phi_(i+1)] (graded towards 0 like i^3, where the density is singular) becomes one
    element with the cell's stiffness int rho and slip force int phi rho; the Dirac part at phi_max
    is one more element (stiffness S, slip force S phi_max).
    """
    chi, R = iwan.chi, iwan.R
    e = iwan.phi_max * np.linspace(0.0, 1.0, cells + 1) ** 3
    k = R * np.diff(e ** (chi + 1)) / (chi + 1)
    f = R * np.diff(e ** (chi + 2)) / (chi + 2)
    return np.append(k, iwan.S), np.append(f, iwan.S * iwan.phi_max)


def stepped_fourier(iwan, a, cells, steps=2**13):
    """f_s, f_c of the parallel Jenkins elements stepped (exact return map) through a sin(theta).

    From rest: a quarter cycle up to x = a, then one cycle integrated by the periodic trapezoid rule.
    """
    k, fmax = jenkins_cells(iwan, cells)
    theta = 2 * np.pi * np.arange(steps + steps // 4 + 1) / steps
    x = a * np.sin(theta)
    fj = np.zeros_like(k)
    f = np.empty_like(x)
    for i in range(1, len(x)):
        fj = np.clip(fj + k * (x[i] - x[i - 1]), -fmax, fmax)
        f[i] = fj.sum()
    f, th = f[steps // 4: steps // 4 + steps], theta[steps // 4: steps // 4 + steps]
    return f @ np.sin(th) * 2 / steps, f @ np.cos(th) * 2 / steps


@pytest.mark.parametrize("ratio", [0.3, 1.0, 3.0])
def test_closed_form_against_time_stepped_parallel_jenkins(ratio):
    """Second-order convergence in the number of cells to the closed form (chi = -0.5, beta = 0.1)."""
    iwan = Iwan(slip_force=F_S, stiffness=K_T, chi=-0.5, beta=0.1)
    a = ratio * iwan.phi_max
    exact = np.array(iwan.fourier(a))
    errors = [np.max(np.abs(np.array(stepped_fourier(iwan, a, n)) - exact)) / (K_T * a) for n in (50, 100)]
    assert errors[1] < 3e-5
    assert errors[0] / errors[1] > 3.0  # second order: 4 expected


def test_loop_and_virgin_curve(iwan):
    """The loop is the Masing loop of the loading curve, which is continuous at phi_max and flat past it."""
    p = iwan.phi_max
    assert iwan.loading_curve(p * (1 - 1e-12)) == pytest.approx(F_S, rel=1e-10)
    assert iwan.loading_curve(2 * p) == F_S
    x, f = iwan.hysteresis(2 * p, n=401)
    assert x[0] == pytest.approx(-2 * p) and f[0] == pytest.approx(-F_S) and f[200] == pytest.approx(F_S)
    slope = iwan._loading_slope(np.array([0.0, 0.5 * p, 2 * p]))
    h = 1e-7 * p
    assert slope[1] == pytest.approx((iwan.loading_curve(0.5 * p + h) - iwan.loading_curve(0.5 * p - h)) / (2 * h),
                                     rel=1e-6)
    assert slope[0] == K_T and slope[2] == 0.0


def test_contract_values(iwan):
    assert iwan.slip_amplitude() == 0.0 and iwan.linear_amplitude() == 0.0
    assert iwan.reference_amplitude() == iwan.phi_max == iwan.gross_slip_amplitude()
    assert iwan.stuck_stiffness(123.0) == K_T and not iwan.frequency_dependent


@pytest.mark.parametrize("kwargs, name", [
    (dict(slip_force=0.0), "slip_force"), (dict(stiffness=-1.0), "stiffness"), (dict(chi=-1.0), "chi"),
    (dict(chi=math.nan), "chi"), (dict(beta=-0.1), "beta"), (dict(beta=math.inf), "beta")])
def test_bad_parameters_are_refused_by_name(kwargs, name):
    args = dict(slip_force=F_S, stiffness=K_T, chi=-0.5, beta=0.1) | kwargs
    with pytest.raises(ValueError, match=f"{name}="):
        Iwan(**args)


def test_periodic_force_with_inner_loops_against_stepped_parallel_jenkins():
    """The multi-harmonic time law (Masing with memory, from the loading curve and its slope) for a
    displacement with inner loops, against the discretised element stepped from rest for three
    periods (its last period); and its Jacobian against central differences."""
    iwan = Iwan(slip_force=F_S, stiffness=K_T, chi=-0.5, beta=0.1)
    th = 2 * np.pi * np.arange(256) / 256
    x = iwan.phi_max * (0.8 * np.sin(th) + 0.3 * np.sin(3 * th + 0.4))  # four reversals a period
    f, J = iwan.periodic_force(x)
    k, fmax = jenkins_cells(iwan, 400)
    fj, prev, hist = np.zeros_like(k), 0.0, []
    for xi in np.concatenate([x, x, x]):
        fj = np.clip(fj + k * (xi - prev), -fmax, fmax)
        prev = xi
        hist.append(fj.sum())
    assert np.max(np.abs(np.array(hist[-256:]) - f)) < 2e-5 * F_S  # 400 cells: second order in cells
    h = 1e-7 * iwan.phi_max
    for j in (3, 100, 200):
        dx = np.zeros_like(x)
        dx[j] = h
        fd = (iwan.periodic_force(x + dx)[0] - iwan.periodic_force(x - dx)[0]) / (2 * h)
        assert np.allclose(J[:, j], fd, rtol=1e-5, atol=1e-6 * K_T)


class _SampledJenkins(Macroslip):
    """The Jenkins element through the same AFT as the Iwan element (not its closed form)."""

    exact_harmonics = False


def test_multi_harmonic_frf_with_huge_beta_is_the_jenkins_frf():
    """Through the multi-harmonic balance (H = 7) the Iwan element with beta -> inf gives the
    Jenkins element's FRF (problem P1 of docs/performance.md), both sampled alike (n_t = 512)."""
    from hbm import Contact, Structure, frequency_response

    s = Structure(np.eye(1), np.array([[0.004]]), np.eye(1), force=[0.01])
    peaks = [frequency_response(s, [Contact(el, dof=0)], omega_range=(0.6, 1.8), harmonics=7, n_t=512,
                                stability=False).peak()
             for el in (Iwan(slip_force=0.02, stiffness=1.0, chi=-0.5, beta=1e9), _SampledJenkins(1.0, 0.02))]
    assert peaks[0].amplitude == pytest.approx(peaks[1].amplitude, rel=1e-7)
    assert peaks[0].omega == pytest.approx(peaks[1].omega, rel=1e-7)


def test_the_loading_curve_refuses_a_negative_or_non_finite_displacement_and_a_negative_omega():
    iwan = Iwan(slip_force=1.0, stiffness=1.0, chi=-0.5, beta=0.0)  # x < 0: x**1.5 would be NaN
    with pytest.raises(ValueError, match=r"^x must be finite and >= 0, got x=-1.0$"):
        iwan.loading_curve(-1.0)
    with pytest.raises(ValueError, match=r"^x must be finite and >= 0, got x=nan$"):
        iwan.loading_curve([0.5, math.nan])
    with pytest.raises(ValueError, match=r"^omega must be >= 0, got omega=-1.0$"):
        iwan.loading_curve(0.5, -1.0)


@pytest.mark.parametrize("a", [1e160, 1e300, 1e308])
def test_a_huge_amplitude_gives_macroslip_not_nan(iwan, a):
    """Far past macroslip f_c is 4 F_S/pi and f_s, the slopes vanish: a**2 overflowed from about 1e154 m, and f_s
    was NaN (an ElementOutputError; before the output checks the NaN itself)."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        fs, fc, dfs, dfc = iwan.fourier_derivatives(a)
        fa, fca = iwan.fourier(np.array([a]))
    assert fc == pytest.approx(4.0 * F_S / math.pi, rel=1e-12) and fca[0] == fc
    assert 0.0 <= fs < 1e-50 * F_S and fa[0] == fs
    assert all(math.isfinite(v) and abs(v) < 1e-100 for v in (dfs, dfc))


@pytest.mark.parametrize("a", [1e-300, 1e-250])
def test_a_tiny_amplitude_keeps_the_stuck_stiffness(iwan, a):
    """f_s = K_T a to first order (a**2 underflowed at 1e-300 m: f_s was 0)."""
    fs, fc, dfs, dfc = iwan.fourier_derivatives(a)
    assert fs == pytest.approx(K_T * a, rel=1e-9) and dfs == pytest.approx(K_T, rel=1e-9)
    assert 0.0 <= fc <= 1e-9 * fs and dfc >= 0.0


def test_slopes_past_macroslip_without_cancellation(iwan):
    """df_c/da past macroslip is 4 x^2 (K_T - 2 R phi^(chi+1)/((chi+1)(chi+3)))/pi, x = phi_max/a, to rounding (it
    came from -f_c/a + 4 F_S/(pi a), which lost 1e-8 of it at a = 1e8 phi_max), and meets a difference quotient."""
    chi, R, p = iwan.chi, iwan.R, iwan.phi_max
    for ratio in (2.0, 1e4, 1e8):
        a = ratio * p
        x = p / a
        dfc = iwan.fourier_derivatives(a)[3]
        assert dfc == pytest.approx(4 / math.pi * x * x * (K_T - 2 * R * p ** (chi + 1) / ((chi + 1) * (chi + 3))),
                                    rel=1e-13)
    a, h = 3.0 * p, 1e-6 * p
    fd = (iwan.fourier(a + h)[1] - iwan.fourier(a - h)[1]) / (2 * h)
    assert iwan.fourier_derivatives(a)[3] == pytest.approx(fd, rel=1e-6)
