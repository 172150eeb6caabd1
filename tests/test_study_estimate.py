"""A study's records carry the peak's estimated error and the model of the peak (``peak_error_rel``,
``peak_model``), and ``sweep.tol`` reaches ``frequency_response`` from a scene."""

import csv
import json
import warnings
from pathlib import Path

import numpy as np
import pytest

from contact_models import AccuracyWarning
from hbm import frequency_response
from hbm.output import csv_lines
from hbm.cli.cases import default_case
from hbm.scenes import SceneError, run_scene, scene_from_dict
from hbm.scenes.reporting import peak_point
from hbm.study import RESULT_COLUMNS, Study, outcome, run_study

DEFAULT = Path(__file__).resolve().parent.parent / "examples" / "scenes" / "default_microslip_frf.toml"


def direct(tol):
    """The default scene's run with damper.model = "auto" as frequency_response gives it: the default
    case at the scene's H = 1 with model="peak" (the scene keeps the single-mode element there)."""
    case = default_case()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning)
        return frequency_response(case.blade, case.element, omega_range=case.omega_range, harmonics=1, tol=tol,
                                  model="peak")


def test_the_study_records_the_peak_s_estimate_and_model(tmp_path):
    """damper.model = "auto": at tol 1e-3 the peak solved with the bar of every mode (model="peak":
    the single-mode model part at the peak, 2 %, exceeds tol/2), at tol 0.1 the single-mode peak
    (2 % is below tol/2 = 5 %).  Each record holds the peak, its estimate and the model of the point
    the peak was located from, as frequency_response computes them for the same run."""
    scene = DEFAULT.read_text().replace('model = "two-region"', 'model = "auto"').replace(
        '[output]\nformats = ["csv", "png", "json"]', '[study.grid]\n"sweep.tol" = [1e-3, 0.1]\n')
    path = tmp_path / "s.toml"
    path.write_text(scene)
    result = run_study(Study.from_scene(path), tmp_path / "out", executor="serial", formats=("csv", "json"))
    assert result.success
    by_tol = {r["params"]["sweep.tol"]: r for r in result.records}
    fine, coarse = by_tol[1e-3], by_tol[0.1]

    spanned = {}  # per tol, the model source at the points the peak's estimate spans
    for rec, tol, model in ((fine, 1e-3, "AllModeMicroslip"), (coarse, 0.1, "TwoRegionMicroslip")):
        frf = direct(tol)
        pk = frf.peak()
        j = peak_point(frf)
        assert frf.point_models[j].split("(")[0] == model and rec["peak_model"] == model
        # the same run to the nested solves' Newton tolerance: they start from the states the process
        # kept, and the compiled kernels may load between the two runs (equal to rounding, not bitwise)
        assert rec["peak_omega_rad_s"] == pytest.approx(pk.omega, rel=1e-9)
        assert rec["peak_amplitude_m"] == pytest.approx(pk.amplitude, rel=1e-9)
        assert rec["peak_error_rel"] == pytest.approx(pk.estimate, rel=1e-6)  # (the nested solves start from states the process kept: 3e-10 apart)
        # the largest point estimate within two points of the sampled maximum (hbm.balance.errors.peak_estimate)
        i = int(np.argmax(frf.amplitude))
        assert rec["peak_error_rel"] == pytest.approx(float(np.max(frf.error_estimate[max(i - 2, 0):i + 3])), rel=1e-6)
        assert rec["peak_error_rel"] >= frf.error_estimate[j] * (1.0 - 1e-6)  # at least the point it was located from
        spanned[tol] = frf.error_sources["model"][max(i - 2, 0):i + 3]
    assert 0.0184 / 2.0 < coarse["peak_error_rel"] < 0.1  # mostly the single-mode model's part (docs/validation.md)
    # the model part is gone from it (below tol / 2 at every point it spans, against 1.8 % or more with the
    # single-mode bar); what is left is mostly the blade's harmonics the scene's H = 1 leaves out
    assert np.max(spanned[1e-3]) < 1e-3 / 2.0 and np.min(spanned[0.1]) > 0.0184 / 2.0
    assert fine["peak_error_rel"] < coarse["peak_error_rel"]
    assert fine["peak_amplitude_m"] / coarse["peak_amplitude_m"] - 1.0 > 0.01  # the bar of every mode peaks higher

    with (tmp_path / "out" / "study.csv").open() as fh:
        rows = list(csv.DictReader(csv_lines(fh)))
    assert {"peak_error_rel", "peak_model"} <= set(rows[0])
    assert {r["peak_model"] for r in rows} == {"AllModeMicroslip", "TwoRegionMicroslip"}
    assert sorted(float(r["peak_error_rel"]) for r in rows) == pytest.approx(
        sorted([fine["peak_error_rel"], coarse["peak_error_rel"]]), rel=1e-15)
    table = json.loads((tmp_path / "out" / "study.json").read_text())
    assert "peak_error_rel" in json.dumps(table) and "AllModeMicroslip" in json.dumps(table)


def test_a_runner_s_dict_may_give_the_peak_s_estimate_and_model():
    rec = outcome({"peak_amplitude_m": 1e-6, "peak_error_rel": 2.5e-4, "peak_model": "Macroslip"})
    assert rec["peak_error_rel"] == 2.5e-4 and rec["peak_model"] == "Macroslip"
    rec = outcome({"peak_amplitude_m": 1e-6, "peak_error_rel": float("nan")})
    assert rec["peak_error_rel"] is None and rec["peak_model"] is None
    assert RESULT_COLUMNS.index("peak_error_rel") == RESULT_COLUMNS.index("peak_amplitude_m") + 1


def scene_with(**sweep):
    data = {"blade": {"mass": 1.0, "stiffness": 1.0e4, "damping": 2.0, "force": 1.0},
            "damper": {"model": "macroslip", "stiffness": 1.0e3, "slip_force": 0.5},
            "sweep": {"omega": [80.0, 120.0], **sweep}, "output": {"formats": ["json"]}}
    return scene_from_dict(data, "s.toml")


@pytest.mark.parametrize("sweep, tolerance, rtol", [
    ({}, 1e-3, 1e-6),                                    # frequency_response's default tol
    ({"tol": 2e-2}, 2e-2, 1e-6),                         # given: passed as tol
    ({"tol": 1e-5, "tolerance": 1e-4}, 1e-5, 1e-7),      # tol caps the elements' rtol at tol/100
    ({"accuracy": "fast"}, 1e-2, 1e-3),                  # a preset's tolerance
    ({"accuracy": "precise", "tol": 1e-4}, 1e-4, 1e-9),  # tol given with a preset
])
def test_sweep_tol_reaches_frequency_response(tmp_path, sweep, tolerance, rtol):
    result = run_scene(scene_with(**sweep), tmp_path)
    frf = result.runs[0].frf
    assert frf.tolerance == tolerance and frf.rtol == pytest.approx(rtol, rel=1e-12)
    assert result.summary["tol"] == tolerance
    run = result.summary["runs"][0]
    assert run["error"]["tolerance"] == tolerance and run["peak"]["tol"] == tolerance
    assert run["peak"]["model"] == "Macroslip"
    i = int(np.argmax(frf.amplitude))
    assert run["peak"]["error_rel"] == frf.peak().estimate == np.max(frf.error_estimate[max(i - 2, 0):i + 3])
    assert run["peak"]["largest_source"] == max(frf.error_sources, key=lambda k: frf.error_sources[k][i])


@pytest.mark.parametrize("value", [0.0, 1.0, -1e-3, "1e-3", True])
def test_sweep_tol_is_validated(value):
    with pytest.raises(SceneError, match=r"sweep\.tol"):
        scene_with(tol=value)
