"""``model="peak"``: the refinement driver in the windows that hold the peak (``hbm.adapt.peak_window``),
checked against the converged physical peak of ``benchmarks/physical_peak_reference.py``."""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest

from contact_models import AccuracyWarning
from hbm import frequency_response
from hbm.adapt import peak_window
from hbm.cli.cases import default_case

REFERENCE = json.loads((Path(__file__).parent / "data" / "physical_peak_reference.json").read_text())


def test_the_peak_window_holds_every_point_the_refined_peak_can_be_at():
    # the refined response is within 2e of the given one: its maximum is where a (1 + 2e) >= a_i (1 - 2e_i)
    a = np.array([1.0, 2.0, 3.0, 3.9, 4.0, 3.95, 3.0, 2.0])
    e = np.full(8, 0.01)
    frf = type("Curve", (), {"__len__": lambda self: len(a), "amplitude": a, "error_sources": {"model": e}})()
    # a_i (1 - 0.02) = 3.92: points 3 (3.9 * 1.02 = 3.978), 4 and 5 qualify; one more on each side
    assert peak_window(frf, 0.005) == (2, 6)
    assert peak_window(frf, 0.01) is None  # the model source at the peak within its share: nothing to refine
    e[4] = 0.2  # a large model error at the maximum widens the window to where the response can reach it
    assert peak_window(frf, 0.005) == (1, 7)  # a_i (1 - 0.4) = 2.4: points 2 to 6 qualify


@pytest.fixture(scope="module")
def peak_run():
    case = default_case()
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always", AccuracyWarning)
        frf = frequency_response(case.blade, case.element, omega_range=case.omega_range, tol=1e-3, model="peak")
    return case, frf, [str(w.message) for w in said if issubclass(w.category, AccuracyWarning)]


@pytest.mark.slow  # the same solve as tests/test_cli_peak.py's job, which checks the peak in the default run
def test_the_peak_is_the_physical_one_within_tol_and_its_estimate(peak_run):
    _, frf, _ = peak_run
    pk = frf.peak()
    true = abs(pk.amplitude / REFERENCE["amplitude"] - 1.0)
    assert REFERENCE["spread"] < 1e-4
    assert pk.interior and pk.converged and pk.estimate <= 1e-3
    assert true <= 1e-3 and true <= 2.0 * pk.estimate  # within tol, the estimate not under-read by 2x
    assert pk.omega == pytest.approx(REFERENCE["omega"], rel=2e-4)
    i = int(np.argmin(np.abs(frf.omega - pk.omega)))
    assert str(frf.point_models[i]).startswith("AllModeMicroslip")


@pytest.mark.slow
def test_away_from_the_peak_the_curve_keeps_the_given_model_and_says_its_error(peak_run):
    _, frf, said = peak_run
    given = frf.point_models == "TwoRegionMicroslip"
    assert given[0] and given[-1] and not given.all()
    if frf.error_estimate[given].max() > 1e-3:  # the single-mode bar's own error on the flanks: warned
        assert len(said) == 1 and "largest source: model" in said[0]
    else:
        assert not said


def test_where_the_peak_needs_no_refined_model_the_curve_is_the_given_one():
    # at tol = 0.15 the single-mode bar's model source at the peak (about 2 %) is within half of tol
    case = default_case()
    kw = dict(omega_range=case.omega_range, tol=0.15, harmonics=1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning)
        peak = frequency_response(case.blade, case.element, model="peak", **kw)
        given = frequency_response(case.blade, case.element, model="given", **kw)
    assert set(peak.point_models.tolist()) == {"TwoRegionMicroslip"}
    np.testing.assert_array_equal(peak.amplitude, given.amplitude)
    assert peak.peak() == given.peak()
