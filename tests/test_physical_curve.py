"""The main job's curve is the physical one: within tol = 1e-3 of the blade with the bar of every mode.

The reference (``tests/data/physical_curve_reference.json``, from ``benchmarks/physical_curve_reference.py``)
is the default blade with ``AllModeMicroslip`` on 256 cells and 127 harmonics, the blade balanced with 47
harmonics, solved at 16 fixed frequencies by a plain Newton iteration written in that script (not the
library's continuation or refinement), each frequency carried up a ladder of resolutions; its own error
(the larger change from the rungs below in cells and in harmonics) is below 1e-4 everywhere. Beside the
peak the same script (``--beside-peak``) solves the narrow notch and a 0.5 rad/s grid
(``tests/data/physical_curve_beside_peak.json``).
"""

import contextlib
import csv
import io
import json
import warnings
from pathlib import Path

import numpy as np
import pytest

from contact_models import AccuracyWarning
from hbm.cli.main import main

REFERENCE = json.loads((Path(__file__).parent / "data" / "physical_curve_reference.json").read_text())
#: Beside the peak (``benchmarks/physical_curve_reference.py --beside-peak``): the narrow notch's two
#: frequencies up a ladder, and a 0.5 rad/s grid on the finest model the job's curve takes there.
BESIDE_PEAK = json.loads((Path(__file__).parent / "data" / "physical_curve_beside_peak.json").read_text())
TOL = 1e-3


def at(omega, w, values):
    """``values`` at ``omega`` by the cubic through the four points of the curve ``w`` nearest it."""
    j = int(np.searchsorted(w, omega))
    idx = np.arange(max(0, j - 2), min(len(w), j + 2))
    return float(np.polyfit(w[idx] - omega, values[idx], len(idx) - 1)[-1])


@pytest.fixture(scope="module")
def job(tmp_path_factory):
    """The main job as a user runs it (``python3 -m hbm``): its CSV, its warnings."""
    out = tmp_path_factory.mktemp("job")
    printed = io.StringIO()
    with warnings.catch_warnings(record=True) as caught, contextlib.redirect_stdout(printed):
        warnings.simplefilter("always")
        assert main(["--out", str(out)]) == 0
    assert (out / "frf.png").stat().st_size > 10000
    with open(out / "frf.csv", newline="") as fh:
        rows = [r for r in csv.reader(line for line in fh if not line.startswith("#"))]
    head, body = rows[0], rows[1:]
    table = {name: [r[i] for r in body] for i, name in enumerate(head)}
    return table, [w for w in caught if issubclass(w.category, AccuracyWarning)], printed.getvalue()


def test_the_reference_is_converged():
    assert len(REFERENCE["points"]) == 16
    assert max(p["spread"] for p in REFERENCE["points"]) < 1e-4


def test_the_main_job_is_within_tol_of_the_physical_curve_and_says_so(job):
    table, accuracy_warnings, printed = job
    w = np.array(table["omega_rad_s"], dtype=float)
    A = np.array(table["amplitude_m"], dtype=float)
    est = np.array(table["error_rel"], dtype=float)
    assert np.all(np.diff(w) > 0.0) and not accuracy_warnings
    assert float(np.max(est)) <= TOL
    true = []
    for p in REFERENCE["points"]:
        e = abs(at(p["omega"], w, A) / p["amplitude"] - 1.0)
        true.append(e)
        assert e <= TOL, f"omega = {p['omega']:.1f}: {e:.2e} off the physical curve"
    # the reading between points has an error of its own, which no point's estimate states (at 38593 rad/s a
    # harmonic of the blade bends the curve between points 13.5 rad/s apart: 4.5e-4 off, within tol); the
    # estimate's 2x promise at the points is checked at their own frequencies (the slow test below)
    last = printed.strip().splitlines()[-1]  # the job's last line: the peak and the whole curve's estimate
    assert last.startswith("peak 387") and "largest estimated error" in last and f"within tol = {TOL:g}" in last
    stated = float(last.split("largest estimated error ")[1].split(" %")[0]) / 100.0
    assert stated == pytest.approx(float(np.max(est)), rel=0.05)


def test_the_csv_says_which_model_and_harmonics_answered(job):
    table, _, _ = job
    models, H = table["model"], np.array(table["H"], dtype=int)
    w = np.array(table["omega_rad_s"], dtype=float)
    A = np.array(table["amplitude_m"], dtype=float)
    peak = int(np.argmax(A))
    assert models[peak].startswith("AllModeMicroslip(") and H[peak] >= 3
    assert models[0] == "TwoRegionMicroslip" and H[0] == 1  # far below the resonance the single-mode bar is within
    assert set(models) >= {"TwoRegionMicroslip"} and len(w) == len(models)



def test_the_main_job_s_curve_goes_down_into_the_narrow_notch_beside_its_peak(job):
    """Where the 13th harmonic of the drive meets the bar's second mode with its end held, the physical curve
    dips by 0.3 % within about 5 rad/s (38718.6 rad/s), narrower than the curve's steps on either side; a
    trace that steps over it is within tol at every point it keeps and 2e-3 off between them. The curve
    read there (the cubic through its four nearest points) against the reference solved at that frequency
    (``BESIDE_PEAK``: the reference script's plain Newton up its ladder to 256 cells, 127 bar harmonics and
    31 blade harmonics), its own change from the rung below added."""
    table, _, _ = job
    w = np.array(table["omega_rad_s"], dtype=float)
    A = np.array(table["amplitude_m"], dtype=float)
    ref = {}
    for p in BESIDE_PEAK["notch"]:
        amps = p["ladder"]
        read = at(p["omega"], w, A)
        doubt = abs(amps[-1] - amps[-2]) / amps[-1]
        assert doubt < 1e-4 and abs(read / amps[-1] - 1.0) <= TOL - doubt, f"omega = {p['omega']}: {read:.6e}, {amps}"
        ref[p["omega"]] = amps[-1]
    assert ref[38718.6] < (1.0 - 2.0 * TOL) * ref[38710.0]  # the notch is deeper than tol: missing it is an error


def test_the_main_job_s_curve_between_its_points_beside_the_peak(job):
    """Read between its points (the cubic through the four nearest), on a grid of 0.5 rad/s over 38400..39100
    rad/s where the curve's windows are traced on the bar of every mode: within tol of the finest model the
    curve takes there (128 cells, 31 bar harmonics, the blade at 31 harmonics) solved at each frequency by
    the reference script's plain Newton, each from the last (``BESIDE_PEAK``). The notches are narrower than
    the curve's steps beside them; the worst reading is 9.2e-4 off, at 38598.5 rad/s (docs/validation.md)."""
    table, _, _ = job
    w = np.array(table["omega_rad_s"], dtype=float)
    A = np.array(table["amplitude_m"], dtype=float)
    assert BESIDE_PEAK["grid_rung"] == [128, 31, 31] and len(BESIDE_PEAK["grid_omega"]) == 1401
    off = [(abs(at(omega, w, A) / ref - 1.0), omega)
           for omega, ref in zip(BESIDE_PEAK["grid_omega"], BESIDE_PEAK["grid_amplitude"])]
    worst = max(off)
    assert worst[0] <= TOL, f"read at omega = {worst[1]}: {worst[0]:.2e} off"


@pytest.mark.slow
def test_the_main_job_s_points_across_the_notches_are_within_twice_their_estimate(job):
    """At the job's points nearest four reference frequencies across the resonance (the notches where a
    harmonic of the drive meets a mode of the bar, and the peak), the reference solved at the point's own
    frequency (``benchmarks/physical_curve_reference.py``'s plain Newton up its ladder to 256 cells, 127 bar
    harmonics and 31 blade harmonics, from the point's first harmonic): the point within tol and within
    twice its estimate, the reference's own change from the rung below added."""
    import sys
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "benchmarks"))
    from physical_curve_reference import up_the_ladder

    from hbm.cli.cases import default_case

    table, _, _ = job
    case = default_case()
    w = np.array(table["omega_rad_s"], dtype=float)
    A = np.array(table["amplitude_m"], dtype=float)
    est = np.array(table["error_rel"], dtype=float)
    xc, xs = (np.array(table[k], dtype=float) for k in ("x_c_m", "x_s_m"))
    for target in (38592.7, 38732.5, 38812.4, 38912.3):
        i = int(np.argmin(np.abs(w - target)))
        amps = up_the_ladder(case.blade, case.element, w[i], np.array([0.0, xc[i], xs[i]]),
                             [(64, 31, 3), (128, 63, 15), (128, 127, 31), (256, 127, 31)])
        doubt = abs(amps[-1] - amps[-2]) / amps[-1]
        e = abs(A[i] / amps[-1] - 1.0)
        assert doubt < 1e-4 and e <= TOL and e <= 2.0 * est[i] + doubt + 1e-6, f"omega = {w[i]:.1f}: {e:.2e}, {est[i]:.2e}"
