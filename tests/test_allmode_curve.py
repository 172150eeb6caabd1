"""The all-mode bar's cells and harmonics chosen along the curve (``AllModeMicroslip.start_rung``,
``refined_rung``; ``hbm.adapt``'s model pass), against an independent converged reference."""

from __future__ import annotations

import csv
import re
import warnings

import numpy as np
import pytest

from contact_models import AccuracyWarning, AllModeMicroslip, TwoRegionMicroslip
from contact_models.allmode.accuracy import start_cells
from contact_models.allmode.rungs import (CURVE_MAX_CELLS, PROBES, START_CELLS, START_HARMONICS, next_rung,
                                          probed_rung)
from hbm import frequency_response
from hbm.reference.amplitude import amplitude_at
from hbm.cli.cases import default_case
from hbm.output import csv_lines, write_frf_csv

CASE = default_case()
BAR, LOAD = CASE.element.bar, CASE.element.load
LADDER = (7, 15, 31)
START = f"AllModeMicroslip(cells={START_CELLS}, H={START_HARMONICS})"


# ------------------------------------------------------------------ the rule
def test_next_rung_refines_the_part_that_misses_its_share():
    # cells alone: the harmonics part (1e-4) within half the target 1.1e-3: 1e-2 (16/n')^2 <= 1e-3 -> n' = 64
    assert next_rung(16, 7, 1e-2, 1e-4, 10.0, max_cells=640, ladder=LADDER) == (64, 7)
    # harmonics alone: 4e-3 (7/H')^4 <= 4.1e-4 (target 5e-4 less the cells part 9e-5): 15 gives 1.9e-4
    assert next_rung(16, 7, 9e-5, 4e-3, 8.18, max_cells=640, ladder=LADDER) == (16, 15)
    # both miss half: each within half (5e-4): 32 cells (2.5e-4), H = 15 (1.9e-4)
    assert next_rung(16, 7, 1e-3, 4e-3, 5.0, max_cells=640, ladder=LADDER) == (32, 15)
    # a factor at most 1 still refines the larger part one step
    assert next_rung(32, 15, 1e-3, 1e-5, 0.5, max_cells=640, ladder=LADDER) == (64, 15)
    # the top of each: cells capped, harmonics at the last rung; None at the top of both
    assert next_rung(64, 7, 1.0, 0.0, 1e6, max_cells=128, ladder=LADDER) == (128, 7)
    assert next_rung(16, 7, 0.0, 1.0, 1e6, max_cells=128, ladder=LADDER) == (16, 31)
    assert next_rung(128, 31, 1.0, 1.0, 10.0, max_cells=128, ladder=LADDER) is None
    # an estimate that failed (inf) goes to the top of its part
    assert next_rung(16, 7, np.inf, 1e-4, 2.0, max_cells=128, ladder=LADDER) == (128, 7)
    # the wavelength of the highest harmonic asks for more cells at H' (cells_for)
    assert next_rung(16, 7, 0.0, 1.0, 1e6, max_cells=640, ladder=LADDER, cells_for=lambda h: 2 * h) == (64, 31)


def test_start_rung_and_refined_rung_of_the_element():
    el = AllModeMicroslip(BAR, LOAD)
    start = el.start_rung(CASE.omega_range)
    assert (start.cells, start.harmonics, start.tol) == (32, 7, el.tol)
    assert start.model_name == "AllModeMicroslip(cells=32, H=7)" and el.model_name == "AllModeMicroslip"
    assert AllModeMicroslip(BAR, LOAD, cells=16).start_rung(CASE.omega_range) is None  # cells given: per call
    assert start.refined_rung() is None  # nothing estimated yet
    a, w = 7.7e-7, 38065.5  # near the slip onset: the cells part dominates
    e_s, e_c = start.model_error(a, w, parts=True)
    sol = AllModeMicroslip(BAR, LOAD, 32, 7).solve(a, w, estimate_error=True)
    assert float(max(e_s, e_c)) == pytest.approx(sol.relative_error, rel=1e-9)  # its components' larger
    rung = start.refined_rung(10.0)
    (_, _, rel_c, rel_h), = start._seen
    # the predicted rung is tried at that point first, and the next predicted from there while its
    # estimate misses the target: 128 cells, the most along a curve, whose estimate misses the target
    # (1.6e-3 against 6.1e-4) with the harmonics part within its share, so no rung follows; each rung's
    # estimate covers its error against 512 cells (5.3e-3 under 6.1e-3 on 32 cells, 8.0e-4 under 1.6e-3 on 128)
    target = (rel_c + rel_h) / 10.0
    tried = [next_rung(32, 7, rel_c, rel_h, 10.0, max_cells=CURVE_MAX_CELLS, ladder=LADDER)]
    assert tried == [(128, 7)]
    probe = AllModeMicroslip(BAR, LOAD, *tried[-1])
    probe.model_error(a, w)
    (_, _, rc, rh), = probe._seen
    assert rc + rh > target and next_rung(*tried[-1], rc, rh, (rc + rh) / target, max_cells=CURVE_MAX_CELLS,
                                          ladder=LADDER) is None
    assert (rung.cells, rung.harmonics) == tried[-1]
    ref = AllModeMicroslip(BAR, LOAD, 512, 15).solve(a, w).F[1:3]
    for (n, H), est in (((32, 7), rel_c + rel_h), ((128, 7), rc + rh)):
        F = AllModeMicroslip(BAR, LOAD, n, H).solve(a, w).F[1:3]
        true = np.max(np.abs(F - ref) / np.maximum(np.abs(ref), 0.01 * BAR.k_star * a))
        assert 0.5 * est <= true <= est
    assert rung.tol == el.tol and rung._seen[0][:2] == (w, a)  # traced from where it was tried


def test_a_probed_rung_is_followed_by_the_next_while_its_estimate_misses_the_target():
    class Rung:  # an element whose estimate at a point is given per rung
        def __init__(self, n, h):
            self.rung, self._seen = (n, h), []

        def model_error(self, a, w):
            self._seen.append((w, a, *estimates[self.rung]))

    estimates = {(64, 15): (3e-3, 1e-4), (128, 15): (8e-4, 1e-4), (256, 15): (2e-4, 1e-4)}
    built = []

    def build(n, h):
        built.append((n, h))
        return Rung(n, h)

    def predict(el, rel_c, rel_h, excess):
        return 2 * el.rung[0], el.rung[1]

    assert probed_rung((64, 15), (38000.0, 1e-6), 1e-3, build, predict).rung == (128, 15)
    assert built == [(64, 15), (128, 15)]  # 64 cells missed 1e-3 (3.1e-3), 128 met it (9e-4)
    built.clear()
    # PROBES = 3 rungs tried, all short of 1e-4: the one predicted after the third is traced untried
    assert probed_rung((64, 15), (38000.0, 1e-6), 1e-4, build, predict).rung == (512, 15)
    assert built == [(64, 15), (128, 15), (256, 15), (512, 15)] and PROBES == 3


def test_the_top_rung_is_where_a_curve_refines_no_further():
    tops = {(n, h): AllModeMicroslip(BAR, LOAD, n, h).at_top_rung for n in (64, CURVE_MAX_CELLS, 256) for h in (15, 31)}
    assert tops == {(64, 15): False, (64, 31): False, (CURVE_MAX_CELLS, 15): False, (CURVE_MAX_CELLS, 31): True,
                    (256, 15): False, (256, 31): True}
    assert not AllModeMicroslip(BAR, LOAD).at_top_rung and not AllModeMicroslip(BAR, LOAD, cells=256).at_top_rung
    top = AllModeMicroslip(BAR, LOAD, CURVE_MAX_CELLS, 31)
    top.model_error(1.2e-6, 38500.0)  # estimated, and still no rung after it
    assert top._seen and top.refined_rung(10.0) is None


# ------------------------------------------------------------------ the FRF on rungs
@pytest.fixture(scope="module")
def curve():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", AccuracyWarning)
        frf = frequency_response(CASE.blade, AllModeMicroslip(BAR, LOAD, tol=1e-2), omega_range=CASE.omega_range,
                                 tol=1e-2, harmonics=1)
    return frf, [w for w in caught if issubclass(w.category, AccuracyWarning)]


def test_the_curve_is_traced_on_rungs_named_per_point(curve, tmp_path):
    frf, heard = curve
    assert frf.success and len(frf.segments) > 1 and len(heard) <= 1
    names = set(frf.point_models.tolist())
    assert START in names and all(n.startswith("AllModeMicroslip(cells=") for n in names)
    assert frf.point_models[0] == START  # away from the peak
    assert {sg.model for sg in frf.segments} == names
    # where the top rungs leave the estimate above tol (today near the peak, where the 13th harmonic
    # meets a mode of the bar) the one warning says so, with its largest source
    if float(frf.error_estimate.max()) > 1e-2:
        source = max(frf.error_sources, key=lambda k: frf.error_sources[k][int(np.argmax(frf.error_estimate))])
        assert len(heard) == 1 and frf.accuracy_warning == str(heard[0].message)
        assert f"largest source: {source}" in frf.accuracy_warning
        model = str(frf.point_models[int(np.argmax(frf.error_estimate))])
        if source == "harmonics":  # the blade's harmonics that harmonics=1 leaves out (the 13th meets a mode
            assert "more harmonics" in frf.accuracy_warning  # of the bar): the advice is more of them
        else:
            # there the bar is on the last rung a curve refines it to (H = 31, the top of the ladder; its
            # harmonics part, pessimistic there, dominates): the advice is the element alone, not a smaller
            # tol= or cells left to be chosen (they are)
            n = int(re.search(r"cells=(\d+), H=31\)", model).group(1))
            assert n > 0 and source == "model" and f"last rung it is refined to there ({model})" in frf.accuracy_warning
            assert "left to be chosen" not in frf.accuracy_warning
    rows = list(csv.DictReader(csv_lines(open(write_frf_csv(tmp_path / "frf.csv", frf)))))
    assert [r["model"] for r in rows] == frf.point_models.tolist()


@pytest.mark.slow
def test_the_curve_is_within_its_estimate_of_a_converged_reference(curve):
    """At FRF points from the flanks to the peak and across the 13th harmonic's notch (38751 rad/s):
    the reference converged in cells and in harmonics (1024 cells, H = 63, the amplitude equation of
    ``hbm.reference.amplitude``; its doubt the larger change from 512 cells and from H = 47) within the
    point's estimate (docs/validation.md, printed by ``benchmarks/bench_allmode_rungs.py --tol 1e-2``: true /
    estimate 0.01 to 0.47 at the slipping points among these)."""
    frf, _ = curve
    refs = {k: AllModeMicroslip(BAR, LOAD, *k) for k in ((512, 63), (1024, 47), (1024, 63))}
    for w in (33000.0, 36000.0, 38000.0, 38400.0, 38600.0, 38710.0, 38751.0, 38758.0, 38780.0, 38820.0, 38860.0,
              40000.0, 42000.0):
        i = int(np.argmin(abs(frf.omega - w)))
        wi, a = float(frf.omega[i]), float(frf.amplitude[i])
        r = {k: amplitude_at(CASE.blade, el, wi, a) for k, el in refs.items()}
        ref = r[1024, 63]
        doubt = max(abs(r[512, 63] / ref - 1.0), abs(r[1024, 47] / ref - 1.0))
        assert abs(a / ref - 1.0) <= frf.error_estimate[i] + doubt, (wi, a, r, frf.error_estimate[i])


def test_model_auto_from_the_single_mode_element_refines_on_rungs():
    frf = frequency_response(CASE.blade, TwoRegionMicroslip(BAR, LOAD), omega_range=CASE.omega_range, tol=1e-2,
                             model="auto", harmonics=1)
    names = set(frf.point_models.tolist())
    assert "TwoRegionMicroslip" in names and any(n.startswith("AllModeMicroslip(cells=") for n in names)
    assert "AllModeMicroslip" not in names  # never the element choosing per call


def test_the_element_alone_keeps_its_choice_per_call():
    el = AllModeMicroslip(BAR, LOAD)
    sol = el.solve(1.5e-6, 38800.0)
    assert sol.relative_error <= el.tol and el.cells is None and el.harmonics is None


def test_a_window_where_both_knobs_ask_is_traced_once_at_both_next_settings():
    """At 200 N and 100 N, tol = 1e-3, the start rung's window around the peak needs both more blade
    harmonics (H = 1 -> 3) and a finer rung: the driver asks every knob that asks there for its next setting
    and traces the window once at all of them (``hbm.adapt.refine``), never at H = 3 on the start rung
    (which the rung knob would then trace again).  No window is given up; at 100 N the curve ends within tol,
    at 200 N within it or warned that the bar is on its finest rung along a curve there (near 38915 rad/s,
    where the 13th harmonic meets a mode of the bar, 128 cells read 1.1e-3 at H = 15)."""

    def frf(N):
        return frequency_response(CASE.blade, AllModeMicroslip(BAR, type(LOAD)(N=N), tol=1e-3),
                                  omega_range=CASE.omega_range, tol=1e-3)

    def traced(f):
        return [(g.harmonics, str(g.point_models[0])) for g in f._work]

    cheap = f"AllModeMicroslip(cells={START_CELLS}, H=31)"  # the start rung in a balance of H = 3 (adapt.balanced)
    for N in (200.0, 100.0):
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always", AccuracyWarning)
            f = frf(N)
        first, *windows = traced(f)
        assert first[0] == 1 and windows and (3, cheap) not in windows
        assert windows[0][0] == 3 and windows[0][1] != first[1]  # both knobs turned at once
        assert f.success and "failed" not in f.message
        within = float(f.error_estimate.max()) <= 1e-3
        assert within == (not said) and (within or (N == 200.0 and "last rung it is refined to" in str(said[0].message)))


def test_harmonics_of_raises_a_rung_to_the_top_harmonics_on_its_cells():
    start = AllModeMicroslip(BAR, LOAD, 32, 7)
    raised = start.harmonics_of(AllModeMicroslip(BAR, LOAD, 64, 31))
    assert (raised.cells, raised.harmonics, raised.tol, raised.linear) == (32, 31, start.tol, start.linear)
    assert start.harmonics_of(AllModeMicroslip(BAR, LOAD, 64, 15)) is None  # not the top harmonics
    assert AllModeMicroslip(BAR, LOAD, 32, 31).harmonics_of(AllModeMicroslip(BAR, LOAD, 64, 31)) is None
    assert AllModeMicroslip(BAR, LOAD).harmonics_of(AllModeMicroslip(BAR, LOAD, 64, 31)) is None  # choosing
    # too few cells for the 31st harmonic's wavelength at the points estimated (18 at 43946 rad/s): doubled
    few = AllModeMicroslip(BAR, LOAD, 4, 7)
    few.model_error(1.5e-6, 43946.0)
    assert start_cells(BAR, 43946.0, 31) == 18 and few.harmonics_of(AllModeMicroslip(BAR, LOAD, 64, 31)).cells == 32


def test_the_estimate_is_computed_either_side_of_the_onset_of_slip():
    """The model source has a kink at the onset of slip: below it the stuck stiffness's error, growing
    towards the resonance; above it the slipping bar's.  The points either side of the onset are nodes
    of the estimate (``hbm.balance.errors.onsets``), not interpolated: on 16 cells the last stuck point
    before the resonance (38021 rad/s) was given 5.9e-4 interpolated between a stuck and a slipping node,
    while it is 1.2e-3 off a converged reference (the stuck stiffness's 3.6e-4, through the balance)."""
    from hbm.balance import errors

    el = AllModeMicroslip(BAR, LOAD, 16, 15)
    frf = frequency_response(CASE.blade, el, omega_range=(37000.0, 38300.0), harmonics=1, tol=1e-2)
    stuck = frf.amplitude <= np.array([el.linear_amplitude(float(w)) for w in frf.omega])
    i = int(np.flatnonzero(stuck[:-1] & ~stuck[1:])[0])  # the last stuck point
    X = frf._X
    assert set(errors.onsets(frf._problem, X, frf.omega, errors.nodes(frf.amplitude))) >= {i, i + 1}
    alone = errors.estimate(frf._problem, X[i:i + 1], frf.omega[i:i + 1], frf.rtol)["model"][0]
    assert frf.error_sources["model"][i] == pytest.approx(alone, rel=1e-12)
    ref = amplitude_at(CASE.blade, AllModeMicroslip(BAR, LOAD, 512, 63), float(frf.omega[i]), float(frf.amplitude[i]))
    assert abs(frf.amplitude[i] / ref - 1.0) <= frf.error_estimate[i]


def test_the_40_N_curve_reaches_its_H_31_windows_and_ends_within_tol():
    """At 40 N and tol = 1e-3 windows below and beside the peak go to H = 31 (two rungs above H = 7 read
    the harmonics the bar's modes meet there); every window's start converges (from the lifted point, or
    in stages where that fails: ``hbm.adapt.staged``), nothing is given up, and the curve ends within tol."""
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always", AccuracyWarning)
        frf = frequency_response(CASE.blade, AllModeMicroslip(BAR, type(LOAD)(N=40.0)), omega_range=CASE.omega_range,
                                 tol=1e-3)
    assert frf.success and "failed" not in frf.message and not said
    assert any(sg.harmonics == 31 for sg in frf.segments)
    assert float(frf.error_estimate.max()) <= 1e-3


def test_an_element_given_fixed_keeps_its_harmonics_in_every_window():
    """Rungs chosen along a curve get the top harmonics in a balance of H > 1 (``hbm.adapt.balanced``); an element
    given with its cells and harmonics is not a choice of the curve's and keeps them in the windows at H = 3
    and 7 (its estimate says what that costs)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning)
        frf = frequency_response(CASE.blade, AllModeMicroslip(BAR, LOAD, 16, 3), omega_range=(38000.0, 39500.0),
                                 tol=1e-3)
    assert max(sg.harmonics for sg in frf.segments) >= 3
    assert set(frf.point_models.tolist()) == {"AllModeMicroslip(cells=16, H=3)"}
