"""The wrappers that switch an effect off state what it costs: ``QuasiStatic`` (no damper inertia) and
``StuckContact`` (no slip) give a model error against the physical contact, so a curve with them warns
where the effect left out matters, and ``model="auto"`` puts it back there.

The reference for the element's error is the bar of every mode (``AllModeMicroslip`` on 256 cells and
63 harmonics, whose own error is below 1e-4 here: docs/validation.md); the reference for the blade's
peak is ``tests/data/physical_peak_reference.json`` (the converged ladder of
``benchmarks/physical_peak_reference.py``).
"""

import json
import warnings
from pathlib import Path

import numpy as np
import pytest

from contact_models import AccuracyWarning, AllModeMicroslip, Macroslip, QuasiStatic, TwoRegionMicroslip, UniformLoad
from contact_models.quasi_static import StuckContact
from hbm import frequency_response
from hbm.cli.cases import default_case

from conftest import BAR

PEAK = json.loads((Path(__file__).parent / "data" / "physical_peak_reference.json").read_text())


@pytest.fixture(scope="module")
def bars():
    from contact_models import Bar

    bar = Bar(**BAR)
    load = UniformLoad(N=100.0)
    return bar, TwoRegionMicroslip(bar, load), AllModeMicroslip(bar, load, cells=256, harmonics=63)


@pytest.mark.parametrize("ratio", [0.02, 0.1, 0.29])
def test_the_quasi_static_bar_bounds_its_distance_from_the_bar_of_every_mode(bars, ratio):
    """Each component's stated error is at least its distance from the physical bar, and not more than four
    times it: the triangle inequality through the single-mode bar at omega, whose own error the map states."""
    bar, two, full = bars
    qs = QuasiStatic(two)
    w = ratio * bar.omega_c
    floor = 0.01 * two.stuck_stiffness(0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning)
        for x in (1.1, 2.0, 4.0):
            a = x * two.slip_amplitude()
            f = np.array(qs.fourier(a, w))
            ref = np.array(full.fourier(a, w))
            true = np.abs(f - ref) / np.maximum(np.abs(ref), floor * a)
            stated = np.array(qs.model_error(a, w, parts=True))
            assert np.all(stated >= true) and np.all(stated <= 4.0 * true + 1e-4), (x, stated, true)
    assert float(qs.model_error(2.0 * two.slip_amplitude(), 0.0)) == 0.0  # at omega = 0 it is the static bar


def test_below_slip_the_quasi_static_error_is_the_change_of_the_stuck_stiffness(bars):
    bar, two, _ = bars
    w = 0.29 * bar.omega_c
    ratio = abs(two.stuck_stiffness(w) / two.stuck_stiffness(0.0) - 1.0)
    e_s, e_c = QuasiStatic(two).model_error(0.5 * two.slip_amplitude(), w, parts=True)
    assert float(e_c) == 0.0 and float(e_s) == pytest.approx(ratio, rel=0.1) and ratio > 0.05


def test_an_element_without_inertia_loses_nothing_quasi_statically():
    jenkins = Macroslip(stiffness=1e6, slip_force=1.0)
    assert np.all(QuasiStatic(jenkins).model_error([1e-7, 1e-5], 3e4) == 0.0)
    assert QuasiStatic(jenkins).refined_model() is jenkins


def test_a_stuck_contact_states_the_slip_it_leaves_out(bars):
    bar, two, _ = bars
    st = StuckContact(two)
    w = 0.29 * bar.omega_c
    a_lin = two.linear_amplitude(w)
    e_s, e_c = st.model_error(np.array([0.5, 2.0]) * a_lin, w, parts=True)
    assert e_s[0] == e_c[0] == 0.0  # its exact answer while stuck
    fs, fc = two.fourier(2.0 * a_lin, w)
    assert e_c[1] >= 0.99 and e_s[1] >= abs(st.stuck_stiffness(w) * 2.0 * a_lin - fs) / abs(fs)


def test_a_blade_with_the_quasi_static_damper_warns_where_the_inertia_matters():
    """At 0.29 omega_c the inertia left out moves the resonance by 1 %: the peak is 3.1 % above the physical
    one, the curve warns, and the peak's estimate is not below half its true error."""
    case = default_case()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        frf = frequency_response(case.blade, QuasiStatic(case.element), case.omega_range, tol=1e-3)
    said = [str(w.message) for w in caught if issubclass(w.category, AccuracyWarning)
            and str(w.message).startswith("frequency_response")]
    peak = frf.peak()
    true = abs(peak.amplitude / PEAK["amplitude"] - 1.0)
    assert 0.025 < true < 0.035 and peak.estimate >= 0.5 * true and not peak.converged
    assert len(said) == 1 and "largest source: model" in said[0] and "model='auto'" in said[0]


def test_model_auto_puts_the_inertia_back_where_it_matters():
    case = default_case()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        frf = frequency_response(case.blade, QuasiStatic(case.element), case.omega_range, tol=1e-3, model="auto")
    assert not [w for w in caught if issubclass(w.category, AccuracyWarning) and "frequency_response" in str(w.message)]
    peak = frf.peak()
    assert abs(peak.amplitude / PEAK["amplitude"] - 1.0) <= 1e-3 and peak.estimate <= 1e-3
    assert frf.error_estimate.max() <= 1e-3


def test_the_wrapped_elements_extras_exist_only_where_it_has_them():
    """QuasiStatic(Jenkins).slip_stiffness() was an AttributeError raised inside, on the Jenkins element, and
    PointContact.fit took the wrapper for a microslip element (it has the three methods) until that call."""
    from contact_models import PointContact

    qs = QuasiStatic(Macroslip(stiffness=1e6, slip_force=1.0))
    assert not hasattr(qs, "slip_stiffness") and not hasattr(qs, "gross_slip_amplitude")
    assert hasattr(qs, "loading_curve") and qs.loading_curve([1e-6]).tolist() == [1.0]  # Jenkins has this one
    with pytest.raises(AttributeError, match=r"^QuasiStatic\(Macroslip\(.*\)\) has no slip_stiffness: the wrapped "
                                             r"Macroslip has none$"):
        qs.slip_stiffness()
    with pytest.raises(ValueError, match=r"^element must have stuck_stiffness, slip_stiffness and gross_slip_amplitude .*"
                                         r"without slip_stiffness, gross_slip_amplitude$"):
        PointContact.fit(qs)
    two = TwoRegionMicroslip(default_case().element.bar, UniformLoad(N=100.0))
    assert QuasiStatic(two).slip_stiffness(3e4) == two.slip_stiffness(0.0)
    assert QuasiStatic(two).gross_slip_amplitude() == two.gross_slip_amplitude(0.0)
