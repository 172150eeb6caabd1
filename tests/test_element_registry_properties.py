"""Properties every registered element must have (scikit-fem's habit: one suite over all elements).

The elements are the ``example`` of every model in ``hbm.scenes.MODELS``: a model registered
later, by the library or a user, is tested here without editing this file.  Amplitudes are
sampled in units of the element's ``reference_amplitude``, which exists also when a_min = 0.
Each element is tested at omega = 0 and, if it is frequency dependent, at 0.2 omega_c of its bar.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hbm.scenes import MODELS

ELEMENTS = [(name, spec.example) for name, spec in MODELS.items() if spec.example is not None]
#: a / reference_amplitude from 0.01 to 1000 (log-uniform)
FACTORS = st.floats(-2.0, 3.0).map(lambda e: 10.0**e)


@pytest.fixture(scope="module", params=ELEMENTS, ids=[name for name, _ in ELEMENTS])
def element(request):
    return request.param[1]()


def frequencies(el):
    bar = getattr(el, "bar", None)
    return (0.0, 0.2 * bar.omega_c) if el.frequency_dependent and bar is not None else (0.0,)


def kinks(el, omega):
    """Amplitudes where the element changes regime (a_min, gross slip, linear range)."""
    out = [el.linear_amplitude(omega), el.slip_amplitude(omega)]
    gross = getattr(el, "gross_slip_amplitude", None)
    if gross is not None:
        out.append(gross(omega))
    return [a for a in out if a > 0.0 and math.isfinite(a)]


def away_from_kinks(el, omega, a, rel=1e-3):
    return all(abs(a / k - 1.0) > rel for k in kinks(el, omega))


def loop_coefficients(el, a, omega, n=4001):
    """f_s, f_c by quadrature of the element's own loop (theta uniform from -pi/2 to 3 pi/2)."""
    x, f = el.hysteresis(a, omega, n=n)
    theta = np.linspace(-0.5 * np.pi, 1.5 * np.pi, n)
    fs = np.trapezoid(f * np.sin(theta), theta) / np.pi
    fc = np.trapezoid(f * np.cos(theta), theta) / np.pi
    area = np.trapezoid(f, x)  # energy per cycle: the integral of f dx around the loop
    return fs, fc, area


@settings(max_examples=12, deadline=None)
@given(factor=FACTORS)
def test_dissipation_is_nonnegative_and_equals_the_loop_area(element, factor):
    for omega in frequencies(element):
        a = factor * element.reference_amplitude(omega)
        k = element.stuck_stiffness(0.0)
        fs, fc = element.fourier(a, omega)
        assert fc >= -1e-12 * k * a
        lfs, lfc, area = loop_coefficients(element, a, omega)
        # the loop's quadrature is second order at its kinks: 1e-4 of k* a at 4001 points
        assert abs(lfs - fs) <= 1e-4 * k * a and abs(lfc - fc) <= 1e-4 * k * a
        assert area == pytest.approx(math.pi * a * fc, abs=1e-4 * math.pi * k * a * a)


@settings(max_examples=12, deadline=None)
@given(factor=FACTORS)
def test_analytic_derivatives_match_central_differences(element, factor):
    for omega in frequencies(element):
        a = factor * element.reference_amplitude(omega)
        if not away_from_kinks(element, omega, a):
            continue
        k = element.stuck_stiffness(0.0)
        _, _, dfs, dfc = element.fourier_derivatives(a, omega, rtol=1e-10)
        h = 1e-5 * a
        fs_p, fc_p = element.fourier(a + h, omega, rtol=1e-10)
        fs_m, fc_m = element.fourier(a - h, omega, rtol=1e-10)
        assert dfs == pytest.approx((fs_p - fs_m) / (2 * h), abs=1e-5 * k)
        assert dfc == pytest.approx((fc_p - fc_m) / (2 * h), abs=1e-5 * k)


#: Largest jump of f_c at a regime change, in units of k* a: an element may snap across a fold of
#: its loading curve (the microslip bar's onset fold under inertia, docs/theory.md "Onset fold":
#: |dF| < 1e-5 k* a_min, so f_c jumps by at most 4/pi of that); f_s is continuous.
SNAP = 4.0 / math.pi * 1e-5


def test_continuous_across_regime_changes(element):
    for omega in frequencies(element):
        k = element.stuck_stiffness(0.0)
        for kink in kinks(element, omega):
            lo = element.fourier(kink * (1 - 1e-9), omega, rtol=1e-10)
            hi = element.fourier(kink * (1 + 1e-9), omega, rtol=1e-10)
            assert abs(hi[0] - lo[0]) <= 1e-6 * k * kink
            assert abs(hi[1] - lo[1]) <= SNAP * k * kink


def test_linear_range_and_stuck_limit(element):
    for omega in frequencies(element):
        k_s, k_c = element.linear_coefficients(omega)
        a_lin = element.linear_amplitude(omega)
        a_ref = element.reference_amplitude(omega)
        assert a_ref > 0.0 and math.isfinite(a_ref)
        if a_lin > 0.0:  # exactly linear below it, with the stuck stiffness
            a = np.array([0.1, 0.5, 0.999]) * a_lin
            fs, fc = element.fourier(a, omega)
            assert np.allclose(fs, k_s * a, rtol=1e-9) and np.allclose(fc, k_c * a, rtol=1e-9, atol=1e-12 * k_s * a_lin)
            assert k_s == pytest.approx(element.stuck_stiffness(omega), rel=1e-12)
        else:  # no linear range promised: f_s/a tends to the stuck stiffness as a -> 0, monotonically in the
            # error, or is exactly it there (Gap, Contact2D: linear_amplitude = 0 because a mean displacement or
            # normal motion changes the contact state at any amplitude, while the first harmonic about a zero
            # mean, the normal at rest, is k* a below |g| or mu n0/kt)
            K = element.stuck_stiffness(omega)
            errors = [abs(element.fourier(f * a_ref, omega)[0] / (f * a_ref) / K - 1.0) for f in (1e-2, 1e-4, 1e-6)]
            assert (errors[0] > errors[1] > errors[2] or max(errors) == 0.0) and errors[2] < 1e-2
