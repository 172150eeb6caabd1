"""Accuracy presets: ``frequency_response(..., accuracy=...)`` and ``hbm.balance.presets``.

On the default case the presets are ordered (precise < default < fast in the peak's error
against a tight reference), each within the bound documented in ``hbm.balance.presets`` and
docs/performance.md; one rtol sets all knobs consistently; bad values raise ValueError naming
``accuracy``.  About 5 s.
"""

import inspect
import math

import numpy as np
import pytest

import hbm
from hbm import Blade, frequency_response
from hbm.balance import presets
from hbm import frf as frf_module
from hbm.cli.cases import default_case

NAMES = ("fast", "default", "precise")


@pytest.fixture(scope="module")
def case():
    return default_case()


@pytest.fixture(scope="module")
def reference(case):
    """The peak at rtol = 1e-11 (its frequency is good to about 1e-10, its amplitude to 1e-15)."""
    frf = frequency_response(case.blade, case.element, omega_range=case.omega_range, rtol=1e-11)
    assert frf.success
    return frf.peak()


@pytest.fixture(scope="module")
def runs(case):
    out = {}
    for name in NAMES:
        frf = frequency_response(case.blade, case.element, omega_range=case.omega_range, accuracy=name)
        assert frf.success, frf.message
        out[name] = frf
    return out


def peak_error(frf, ref):
    pk = frf.peak()
    return max(abs(pk.amplitude / ref.amplitude - 1.0), abs(pk.omega / ref.omega - 1.0))


def test_presets_are_ordered_on_the_default_case(runs, reference):
    err = {name: peak_error(frf, reference) for name, frf in runs.items()}
    assert err["precise"] < err["default"] < err["fast"]
    # and the points: "fast" and "default" by max_step; "precise" by its curve tolerance (tests/test_steps.py)
    assert len(runs["fast"]) < len(runs["default"])


@pytest.mark.parametrize("name", NAMES)
def test_each_preset_within_its_documented_bound(runs, reference, name):
    assert peak_error(runs[name], reference) <= presets.PEAK_ERROR_BOUND[name]


def test_default_preset_is_frequency_responses_default(case, runs):
    steps = hbm.Steps()
    assert presets.resolve("default").options() == {"rtol": presets.DEFAULT_RTOL, "max_step": steps.max_step,
                                                   "min_step": steps.min_step, "max_steps": steps.max_steps}
    assert presets.resolve("default").curve_tol is steps.curve_tol is None
    plain = frequency_response(case.blade, case.element, omega_range=case.omega_range)
    np.testing.assert_array_equal(plain.omega, runs["default"].omega)
    np.testing.assert_array_equal(plain.amplitude, runs["default"].amplitude)


def test_one_rtol_sets_every_knob_consistently():
    # the names are rtol values on the same map
    for name, rtol in presets.NAMED.items():
        assert presets.resolve(rtol) == presets.resolve(name)
    levels = [presets.resolve(r) for r in (3e-2, 1e-3, 1e-5, 1e-7, 1e-9, 1e-12)]
    for coarse, fine in zip(levels, levels[1:]):
        assert fine.rtol < coarse.rtol
        assert fine.max_steps >= coarse.max_steps
        if coarse.curve_tol is None:  # at the default and coarser, max_step follows rtol
            assert fine.max_step <= coarse.max_step or fine.curve_tol is not None
        else:  # finer: the step by accuracy, a tighter curve tolerance, max_step only a safeguard
            assert fine.curve_tol < coarse.curve_tol and fine.max_step == presets.MAX_PRESET_STEP
    assert presets.resolve("precise").curve_tol == pytest.approx(1e-5)
    for s in levels:  # the step budget covers the same arclength as the default's
        assert s.max_steps * s.max_step >= presets.DEFAULT_MAX_STEPS * presets.DEFAULT_MAX_STEP * (1 - 1e-9)
        assert presets.MIN_PRESET_STEP <= s.max_step <= presets.MAX_PRESET_STEP


def test_float_accuracy_reaches_frequency_response():
    blade = Blade.from_modal(frequency=1.0, damping_ratio=1e-2, mass=1.0, force=0.5)
    from contact_models import Macroslip

    frf = frequency_response(blade, Macroslip(stiffness=1.0, slip_force=1.0), omega_range=(0.5, 2.0), accuracy=1e-4)
    assert frf.success
    assert frf.rtol == 1e-4
    assert frf.newton_tol == pytest.approx(frf_module.NEWTON_TOL_FACTOR * 1e-4)


@pytest.mark.parametrize("bad", ["medium", "", "FAST", "1e-6", 0, 0.0, -1e-6, 0.1, 1.0, math.nan, math.inf,
                                 True, [1e-6], {"rtol": 1e-6}])
def test_bad_accuracy_raises_naming_accuracy(bad):
    with pytest.raises(ValueError, match="accuracy"):
        presets.resolve(bad)
    blade = Blade.from_modal(frequency=1.0, damping_ratio=1e-2, mass=1.0, force=0.5)
    with pytest.raises(ValueError, match="accuracy"):
        frequency_response(blade, None, omega_range=(0.5, 2.0), accuracy=bad)


@pytest.mark.parametrize("knob, value", [("rtol", 1e-4), ("max_step", 0.1), ("min_step", 1e-6), ("max_steps", 100)])
def test_accuracy_with_an_explicit_knob_raises(knob, value):
    blade = Blade.from_modal(frequency=1.0, damping_ratio=1e-2, mass=1.0, force=0.5)
    with pytest.raises(ValueError, match=f"accuracy.*{knob}"):
        frequency_response(blade, None, omega_range=(0.5, 2.0), accuracy="fast", **{knob: value})
