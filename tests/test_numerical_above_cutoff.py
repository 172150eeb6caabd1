"""The bars with every mode far above the cut-off (20-70 omega_c), against answers not built with them.

Independent answer below slip.  Stuck everywhere, the bar is linear: u(x, t) = a phi(x) sin(omega t) with
S phi'' - k phi + rho A omega^2 phi = 0 (S = EA), S phi'(0) = beta phi(0) and phi(L) = 1.  Above
omega^2 = k / (rho A) put g^2 = rho omega^2 / E - k / S > 0; then phi = (S g cos gx + beta sin gx) / (S g cos gL +
beta sin gL) and the end force S phi'(L) a gives

    K(omega) = S g (beta cos gL - S g sin gL) / (S g cos gL + beta sin gL),

so f_s = K a and f_c = 0 exactly, for a below the slip amplitude mu q(L) / (k |phi|max) (uniform load).
"""

import math
import re
import warnings

import numpy as np
import pytest

from contact_models import AccuracyWarning, AllModeMicroslip, AllModeMicroslip2D, Bar, NumericalMicroslip, UniformLoad

BAR = dict(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
LOAD = UniformLoad(N=100.0)


def exact_stuck_stiffness(omega):
    """K(omega) of the module docstring, written out from the bar's equation (omega^2 > k / (rho A))."""
    E, rho, A, L, k, beta = (BAR[n] for n in ("E", "rho", "A", "L", "k", "beta"))
    S = E * A
    g = math.sqrt(rho * omega**2 / E - k / S)
    return S * g * (beta * math.cos(g * L) - S * g * math.sin(g * L)) / (S * g * math.cos(g * L) + beta * math.sin(g * L))


def _accuracy_messages(record):
    return [str(w.message) for w in record if issubclass(w.category, AccuracyWarning)]


@pytest.mark.parametrize("omega", [3.0e6, 1.0e7])
def test_stuck_far_above_cutoff_is_the_continuous_bar_or_warns(omega):
    bar = Bar(**BAR)
    K = exact_stuck_stiffness(omega)
    assert math.isclose(K, -6.59616967930797e9 if omega == 3.0e6 else 4.77699637334e10, rel_tol=1e-9)  # (mpmath)
    a = 1e-9  # far below slip (about 1e-7 m here)
    fs, fc = AllModeMicroslip(bar, LOAD).fourier(a, omega)
    assert fs / a == pytest.approx(K, rel=1e-8) and fc == 0.0
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        fs, fc = NumericalMicroslip(bar, LOAD).fourier(a, omega)  # 200 lumped cells
    err = abs(fs / a - K) / max(abs(K), 0.01 * bar.k_star)
    assert err > 0.1  # the mesh's dispersion: 18 % at 3e6 rad/s, 96 % at 1e7 rad/s
    msgs = _accuracy_messages(rec)
    assert msgs, f"a wrong stuck stiffness ({err:.2g} off) came without a warning"
    stated = float(msgs[0].split("continuous bar's by ")[1].split(" ")[0])
    assert stated == pytest.approx(err, rel=1e-3)  # the error it states is the error it has


def test_fine_mesh_stuck_matches_without_warning():
    bar = Bar(**BAR)
    with warnings.catch_warnings():
        warnings.simplefilter("error", AccuracyWarning)
        fs, fc = NumericalMicroslip(bar, LOAD, cells=3200).fourier(1e-9, 3.0e6)
    assert fs / 1e-9 == pytest.approx(exact_stuck_stiffness(3.0e6), rel=1e-3) and fc == 0.0


def test_above_slip_time_domain_is_not_steady_before_the_wave_returns():
    """At 3e6 rad/s and a = 1e-6 m (7.5 slip amplitudes) the reference is the frequency-domain bar on a converged
    mesh: 640 -> 1280 cells and 7 -> 15 harmonics move (f_s, f_c) by less than 1e-5 of |F|.  A wave front needs
    9.5 cycles to cross the bar and come back; the time-domain bar's force is periodic before that (the outgoing
    wave's, f_c = rho c A a omega = 1189 N, f_s = 0) and must not be taken for the steady state."""
    bar = Bar(**BAR)
    w, a = 3.0e6, 1.0e-6
    F = {(n, h): np.array(AllModeMicroslip(bar, LOAD, cells=n, harmonics=h).fourier(a, w), dtype=float)
         for n, h in ((640, 7), (640, 15), (1280, 15))}
    ref = F[(1280, 15)]
    scale = float(np.hypot(*ref))
    assert max(float(np.max(np.abs(v - ref))) for v in F.values()) < 1e-5 * scale
    assert ref[0] == pytest.approx(-7223.06, rel=1e-4) and ref[1] == pytest.approx(122.99, rel=1e-3)
    el = NumericalMicroslip(bar, LOAD, cells=200, max_cycles=12)
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        fs, fc = el.fourier(a, w)
    unsteady = [m for m in _accuracy_messages(rec) if "not steady" in m]
    close = math.hypot(fs - ref[0], fc - ref[1]) < 0.3 * scale  # 200 cells carry 18 % in the stuck stiffness
    assert unsteady or close, f"f_s={fs:.4g}, f_c={fc:.4g} against {ref} without a 'not steady' warning"


@pytest.mark.parametrize("make", [lambda b: NumericalMicroslip(b, LOAD),
                                  lambda b: AllModeMicroslip2D(b, LOAD, kn=1e8)])
def test_absurd_frequency_is_refused_by_name(make):
    el = make(Bar(**BAR))
    with pytest.raises(ValueError, match=r"omega=1e\+160"):
        el.fourier(1e-6, 1e160)


def test_absurd_frequency_simulate_refused_by_name():
    with pytest.raises(ValueError, match=r"omega=1e\+160"):
        NumericalMicroslip(Bar(**BAR), LOAD).simulate(1e-6, 1e160)


@pytest.mark.parametrize("a", [1e-9, 1.5e-6])
@pytest.mark.parametrize("omega", [1e50, 1e160])
def test_single_mode_bar_refuses_a_frequency_whose_phase_has_no_digit(a, omega):
    """sqrt(rho/E) omega L is 9.9e45 rad at 1e50 rad/s: past 1/eps = 4.5e15 cos and sin of it are rounding noise.
    A ValueError names omega, and no numpy RuntimeWarning leaks (float scalar path and array path)."""
    from contact_models import ThreeRegionMicroslip, TwoRegionMicroslip

    bar = Bar(**BAR)
    for el in (TwoRegionMicroslip(bar, LOAD), ThreeRegionMicroslip(bar, LOAD)):
        for x in (a, np.array([a, 2 * a])):
            with warnings.catch_warnings():
                warnings.simplefilter("error", RuntimeWarning)
                with pytest.raises(ValueError, match=r"omega=1e\+(50|160) rad/s is too high for the bar"):
                    el.fourier(x, omega)
    limit = 1.0 / np.finfo(float).eps / (math.sqrt(BAR["rho"] / BAR["E"]) * BAR["L"])
    assert TwoRegionMicroslip(bar, LOAD).fourier(1e-9, 0.5 * limit)[1] == 0.0  # below it: answered (stuck)


@pytest.mark.parametrize("omega", [1e25, 1e155, 1e300])
def test_the_bar_refuses_a_frequency_whose_phase_has_no_digit_in_every_method(omega):
    """The bar's own frequency methods and the single-mode elements' stuck stiffness refuse omega by name where
    sqrt(rho/E) omega L exceeds 1/eps (at 1e25 rad/s they answered rounding noise, from about 1e154 with numpy's
    "overflow encountered in square"): the one guard is where every frequency of the bar passes, Bar.alpha2."""
    from contact_models import ThreeRegionMicroslip, TwoRegionMicroslip

    bar = Bar(**BAR)
    calls = [lambda: bar.stuck_stiffness(omega), lambda: bar.stuck_stiffness([0.0, omega]),
             lambda: bar.stuck_shape([0.01], omega), lambda: bar.slip_onset(LOAD, omega),
             lambda: bar.contact_force([0.01], omega, tip_displacement=1e-6), lambda: bar.gamma2(omega),
             lambda: bar.alpha2(np.array([omega]))]
    for cls in (TwoRegionMicroslip, ThreeRegionMicroslip):
        el = cls(bar, LOAD)
        calls += [lambda el=el: el.stuck_stiffness(omega), lambda el=el: el.linear_coefficients(omega)]
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        for call in calls:
            with pytest.raises(ValueError, match=rf"^omega={re.escape(repr(omega))} rad/s is too high for the bar: "):
                call()
    limit = 1.0 / np.finfo(float).eps / (math.sqrt(BAR["rho"] / BAR["E"]) * BAR["L"])
    assert math.isfinite(bar.stuck_stiffness(0.5 * limit)) and bar.alpha2(np.array([])).size == 0
