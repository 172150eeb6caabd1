"""Nothing stopped is hidden: a branch that ends early, a peak at an end of the range or on a
stopped stretch each give the call's ``AccuracyWarning`` saying what happened and where, and the
``Peak`` says whether it is an interior, converged maximum.

The expected values are closed forms (the bare blade's resonance) or facts of the set-up (the
range's end, the step budget), never the solver's own output.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from contact_models import Macroslip
from hbm import AccuracyWarning, Blade, Peak, Steps, frequency_response
from hbm.cli.cases import default_case

#: The bare blade of the closed-form tests: resonance at sqrt(k/m - c^2/(2 m^2)), amplitude F/(c sqrt(k/m - c^2/(4 m^2))).
BARE = Blade(mass=1.0, stiffness=1.0e4, damping=2.0, force=1.0)
BARE_OMEGA = math.sqrt(1.0e4 - 2.0)
BARE_AMPLITUDE = 1.0 / (2.0 * math.sqrt(1.0e4 - 1.0))


def solve(*args, **kwargs):
    """``(frf, [AccuracyWarning messages])``."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        frf = frequency_response(*args, **kwargs)
    return frf, [str(w.message) for w in caught if issubclass(w.category, AccuracyWarning)]


def test_an_interior_converged_peak_says_so_and_does_not_warn():
    frf, said = solve(BARE, omega_range=(90.0, 110.0))
    pk = frf.peak()
    assert isinstance(pk, Peak) and pk.interior and pk.converged and pk.message == ""
    assert abs(pk.omega / BARE_OMEGA - 1.0) < 1e-7 and abs(pk.amplitude / BARE_AMPLITUDE - 1.0) < 1e-7
    assert pk.estimate <= 1e-3
    w, a = pk  # still unpacks as the pair
    assert (w, a) == (pk.omega, pk.amplitude)
    assert said == []


def test_a_peak_outside_the_range_is_at_its_edge_and_warned():
    """The default blade (resonance near 3.4e4 rad/s) swept over 5000..7000 rad/s: its response grows
    all the way, so the largest response is at 7000 rad/s, the end of the range, not a resonance."""
    case = default_case()
    frf, said = solve(case.blade, case.element, omega_range=(5000.0, 7000.0))
    pk = frf.peak()
    assert frf.success
    assert pk.omega == 7000.0
    assert not pk.interior and not pk.converged
    assert "end of omega_range" in pk.message
    assert len(said) == 1 and "end of omega_range" in said[0] and "7000" in said[0]


def test_a_branch_that_stops_early_says_where_and_keeps_its_points():
    """A step budget of 20 on a Jenkins blade over 0.5..2: the branch stops well before 2 rad/s."""
    frf, said = solve(BARE, Macroslip(1.0e3, 1.0), omega_range=(50.0, 200.0), steps=Steps(max_steps=20))
    assert not frf.success and len(frf) == 21
    last = float(frf.omega[-1])
    assert last < 200.0
    assert len(said) == 1
    assert "the branch stopped at omega = " in said[0] and f"{last:.6g}" in said[0]
    assert "before the end of omega_range" in said[0]


def test_a_peak_where_the_branch_stopped_is_not_interior():
    """Stopped on the rising flank (the budget ends before the resonance at 100 rad/s): the largest
    response is the last point, where the response still rises."""
    frf, said = solve(BARE, omega_range=(50.0, 110.0), steps=Steps(max_steps=15))
    assert not frf.success and float(frf.omega[-1]) < 99.0
    pk = frf.peak()
    assert pk.omega == float(frf.omega[-1])
    assert not pk.interior and not pk.converged and "where the branch stopped" in pk.message
    assert len(said) == 1 and "where the branch stopped" in said[0]


def test_a_peak_on_a_stretch_that_stopped_later_is_interior_but_not_converged():
    """Past the resonance, stopped before the range's end: the maximum is inside the traced part, but
    the part not traced might hold a larger one, so the peak is not a converged answer for the range."""
    full = frequency_response(BARE, omega_range=(90.0, 200.0))
    after = int(np.searchsorted(full.omega, 104.0))  # steps to well past the resonance
    frf, said = solve(BARE, omega_range=(90.0, 200.0), steps=Steps(max_steps=after))
    assert not frf.success and 104.0 <= float(frf.omega[-1]) < 200.0
    pk = frf.peak()
    assert pk.interior and not pk.converged
    assert abs(pk.amplitude / BARE_AMPLITUDE - 1.0) < 1e-7  # it is the true peak here; the range says nothing more
    assert "largest on the traced part only" in pk.message
    assert len(said) == 1 and "largest on the traced part only" in said[0]


@pytest.mark.parametrize("name, number", [("fast", 1e-2), ("default", 1e-3), ("precise", 1e-5)])
def test_a_named_tolerance_is_its_number(name, number):
    a = frequency_response(BARE, omega_range=(90.0, 110.0), tol=name)
    b = frequency_response(BARE, omega_range=(90.0, 110.0), tol=number)
    assert a.tol == b.tol == number
    assert np.array_equal(a.amplitude, b.amplitude) and np.array_equal(a.error_estimate, b.error_estimate)


def test_the_old_keywords_warn_and_still_work():
    with pytest.warns(DeprecationWarning, match=r"max_steps=\.\.\.\) is deprecated: use steps=hbm.Steps"):
        old = frequency_response(BARE, omega_range=(90.0, 110.0), max_steps=15)
    new = frequency_response(BARE, omega_range=(90.0, 110.0), steps=Steps(max_steps=15))
    assert np.array_equal(old.amplitude, new.amplitude)
    seen = []
    with pytest.warns(DeprecationWarning, match="on_point"):
        frequency_response(BARE, omega_range=(90.0, 110.0), on_point=lambda w, xc, xs, r: seen.append(w))
    assert len(seen) > 10
    with pytest.raises(TypeError, match="unexpected keyword argument 'rtoll'"):
        frequency_response(BARE, omega_range=(90.0, 110.0), rtoll=1e-6)


def test_the_callback_gets_every_point_in_order():
    points = []
    frf = frequency_response(BARE, omega_range=(90.0, 110.0), callback=points.append)
    assert [p.omega for p in points] == list(frf.omega)
    assert [p.x_c for p in points] == list(frf.x_c) and len(points[0].harmonics) == 3


@pytest.mark.parametrize("bad, match", [(dict(tol="exact"), "tol must be a number in"), (dict(tol=2.0), "tol must be < 1"),
                                        (dict(model="physical"), "model must be one of"),
                                        (dict(steps={"max_step": 0.1}), "steps must be an hbm.Steps"),
                                        (dict(model="auto", tol=None), "needs a tol"),
                                        (dict(callback=3), "callback must be callable"),
                                        (dict(stability="yes"), r"^stability must be True or False, got stability='yes'$")])
def test_bad_options_are_named(bad, match):
    with pytest.raises(ValueError, match=match):
        frequency_response(BARE, omega_range=(90.0, 110.0), **bad)


@pytest.mark.parametrize("bad, match", [(dict(max_step=-1.0), r"^steps.max_step must be a positive number, got max_step=-1.0$"),
                                        (dict(max_step=math.nan), "steps.max_step must be a positive number"),
                                        (dict(max_steps=0), r"^steps.max_steps must be an integer >= 1, got max_steps=0$"),
                                        (dict(curve_tol=-1), "steps.curve_tol must be None or in"),
                                        (dict(locate_folds="no"),
                                         r"^steps.locate_folds must be True or False, got locate_folds='no'$"),
                                        (dict(max_step=1e-10), r"^steps.min_step must be <= max_step, got "
                                                               r"min_step=1e-09, max_step=1e-10$")])
def test_bad_step_controls_are_refused_where_they_are_made(bad, match):
    with pytest.raises(ValueError, match=match):
        Steps(**bad)
