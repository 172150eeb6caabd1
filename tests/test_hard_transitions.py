"""Branches that turn hard at a stick/slip topology change or a corner fold,
traced by the front door with default steps, against independent periodic responses.

References: ``tests/data/hard_transitions.json``, written by
``benchmarks/hard_transitions_reference.py`` (shooting on event-driven exact stick/slip
integration, ``hbm.reference.shooting``; for the gap, event-located DOP853 integration and
shooting).  No reference uses the harmonic balance; each case's parameters are stored with it.

Tolerance: every call asks ``tol=1e-3`` at ``harmonics=15``.  For the Jenkins chains with
internal resonances the balance's truncation at H = 15 is about 1e-5 at the peak (its error
estimate there is 2e-5), so the points are asserted to ``TOL`` = 1e-3, the call's own target.  The
stiff slider (100 times the structure's stiffness) makes the contact force's harmonics decay
slowly: at H = 15 the balance's own estimate reaches 1e-1 near the transition and the peak is
6e-3 low, so that case's peak is asserted to ``STIFF_TOL`` = 1e-2 and its points to ``TOL`` plus
the balance's own error estimate there (the truncation level it reports; measured differences
follow the estimate: 4.1e-2 against 9.0e-2 at omega = 0.55, 1.4e-2 against 1.5e-2 at 0.7).
The 2:1 internal resonance through a closing gap (``ir21_gap``) is asserted to ``TOL``: its
estimate is at most 4e-5 and the peak agrees with the shooting to 1.1e-5 in amplitude and 5.5e-5 in
frequency (both directions); the points differ by at most 2e-4, the call's tolerance and the
interpolation's chord (as large where the gap is open and the balance is exact).
"""

from __future__ import annotations

import json
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import hbm

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
build = __import__("hard_transitions_reference").build
DATA = json.loads((ROOT / "tests" / "data" / "hard_transitions.json").read_text())["cases"]

TOL = 1e-3
STIFF_TOL = 1e-2
#: A reference frequency farther than this from every branch point is not compared (linear
#: interpolation over a long chord measures the chord, not the balance).
CHORD_GAP = 1e-3
CASES = {name: (STIFF_TOL if name == "stiff" else TOL) for name in DATA}


def _trace(name, reverse):
    case = DATA[name]
    s, cs = build(case["parameters"])
    lo, hi = case["omega_range"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the stiff slider's AccuracyWarning at H = 15 is the point
        return hbm.frequency_response(s, cs, omega_range=(hi, lo) if reverse else (lo, hi), tol=1e-3,
                                      harmonics=15)


@pytest.fixture(scope="module", params=sorted(CASES))
def traced(request):
    name = request.param
    return name, _trace(name, False), _trace(name, True)


def _amplitude_at(frf, omega):
    """The branch's amplitude at ``omega`` by linear interpolation between the bracketing points
    (these stretches have no fold; the chord error at the default steps is below 1e-4)."""
    w, a = frf.omega, frf.amplitude
    order = np.argsort(w)
    return float(np.interp(omega, w[order], a[order]))


def test_both_directions_reach_the_end_with_default_steps(traced):
    name, up, down = traced
    lo, hi = DATA[name]["omega_range"]
    assert up.success, up.message
    assert down.success, down.message
    assert up.omega[-1] == pytest.approx(hi) and down.omega[-1] == pytest.approx(lo)


def test_amplitudes_match_the_periodic_reference(traced):
    name, up, down = traced
    case, tol = DATA[name], CASES[name]
    for frf in (up, down):
        assert len(frf.fold_after) == 0
        checked = 0
        for w, ref in zip(case["omega"], case["amplitude"]):
            i = int(np.argmin(np.abs(frf.omega - w)))
            if abs(frf.omega[i] - w) > CHORD_GAP:  # the interpolation would measure the chord
                continue
            bound = tol + (float(frf.error_estimate[i]) if name == "stiff" else 0.0)
            assert abs(_amplitude_at(frf, w) / ref - 1.0) <= bound, (name, w)
            checked += 1
        assert checked >= 3


def test_peak_matches_the_periodic_peak(traced):
    name, up, down = traced
    ref, tol = DATA[name]["peak"], CASES[name]
    for frf in (up, down):
        pk = frf.peak()
        assert pk.amplitude == pytest.approx(ref["amplitude"], rel=tol)
        assert pk.omega == pytest.approx(ref["omega"], rel=tol)
