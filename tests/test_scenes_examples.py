"""Every scene in examples/scenes runs on a reduced setting (overrides, as ``--set``) and gives one
number checked here against the example script it mirrors or a stored value."""

import csv
import json
from pathlib import Path

import pytest

from contact_models import QuasiStatic, ThreeRegionMicroslip
from hbm.scenes import load_scene, plan_scene, run_scene
from hbm.output import csv_lines

SCENES = Path(__file__).resolve().parent.parent / "examples" / "scenes"
#: Default-case peak (python3 -m hbm; tests/test_hbm_examples.py).
DEFAULT_PEAK = 1.5119614110e-06


def run(name, tmp_path, **overrides):
    scene = load_scene(SCENES / f"{name}.toml", overrides=overrides)
    result = run_scene(scene, tmp_path)
    assert result.success, result.message
    assert (tmp_path / "summary.json").exists()
    return result


def peaks(result):
    return {(r.plan.model.split(" ")[0], r.plan.N): r.peak.amplitude for r in result.runs}


def test_every_example_scene_is_valid_and_tested():
    names = {p.stem for p in SCENES.glob("*.toml")}
    tested = {"default_microslip_frf", "microslip_vs_point_contact", "design_chart", "paper_fs_fc_two_region",
              "paper_fs_fc_three_region", "three_region_concave_frf", "quasi_static_low_frequency",
              "chain_3dof"}
    studies = {"design_chart_study", "monte_carlo"}  # tests/test_hbm_examples.py runs them
    modal = {"nonlinear_modes_chain", "damper_optimum"}  # tests/test_scenes_modes.py runs them
    # tests/test_scenes_normal.py and tests/test_scenes_allmode2d.py run them
    normal = {"nlvib_ex07", "contact_normal", "allmode_normal"}
    cyclic = {"bladed_disk"}  # tests/test_scenes_cyclic.py runs it
    assert names == tested | studies | modal | normal | cyclic
    for name in tested | modal | normal | cyclic:
        plan_scene(load_scene(SCENES / f"{name}.toml"))
    for name in studies:
        assert load_scene(SCENES / f"{name}.toml").study["points"]


def test_default_microslip_frf(tmp_path):
    result = run("default_microslip_frf", tmp_path, **{"sweep.max_step": 0.1})
    assert result.runs[0].peak.amplitude == pytest.approx(DEFAULT_PEAK, rel=1e-6)


def test_microslip_vs_point_contact(tmp_path):
    result = run("microslip_vs_point_contact", tmp_path, **{"damper.load.N": [100.0], "sweep.max_step": 0.1})
    p = peaks(result)
    assert p["two-region", 100.0] == pytest.approx(DEFAULT_PEAK, rel=1e-6)
    # examples/frf_microslip_vs_point_contact.py: ratio 0.72 at 100 N (the point contact peaks higher)
    assert p["two-region", 100.0] / p["point-contact", 100.0] == pytest.approx(0.72452, abs=1e-4)


def test_design_chart(tmp_path):
    result = run("design_chart", tmp_path, **{"damper.load.N": [100.0, 1000.0], "sweep.max_step": 0.1})
    p = peaks(result)
    assert p["two-region", 100.0] == pytest.approx(DEFAULT_PEAK, rel=1e-6)
    # examples/design_chart.py: at 1000 N microslip predicts about half the point contact's amplitude
    assert p["two-region", 1000.0] / p["point-contact", 1000.0] == pytest.approx(0.5057, abs=1e-3)
    assert p["macroslip", 100.0] < p["two-region", 100.0]  # the macroslip model dissipates most
    assert (tmp_path / "frf.png").stat().st_size > 10_000  # FRFs and the peak-against-load chart


@pytest.mark.parametrize("name, model, expected", [
    ("paper_fs_fc_two_region", "two-region (auto)", 0.8816531098),  # examples/fig09_two_region_fs.py
    ("paper_fs_fc_three_region", "three-region", 0.7814461547),  # examples/fig12_three_region_fs.py
])
def test_paper_fs_fc_tables(tmp_path, name, model, expected):
    result = run(name, tmp_path, **{"sweep.omega": [0.3], "sweep.amplitude": [1.5, 100.0], "sweep.points": 2})
    assert result.runs[0].plan.model == model
    rows = list(csv.DictReader(csv_lines((tmp_path / "coefficients.csv").open())))
    assert len(rows) == 2 and float(rows[0]["a_over_unit"]) == 1.5
    assert float(rows[0]["F_s"]) == pytest.approx(expected, rel=1e-8)  # F_s at 1.5 a_min, 0.3 omega_c


def test_three_region_concave_frf(tmp_path):
    result = run("three_region_concave_frf", tmp_path, **{"sweep.omega": [0.28, 0.295], "sweep.max_step": 0.1})
    r = result.runs[0]
    assert isinstance(r.plan.element, ThreeRegionMicroslip)  # auto: concave load, inertia kept
    # the full sweep [0.24, 0.33] omega_c at max_step 0.03 gives 1.76165346695e-06 m at 38216.9713 rad/s
    assert r.peak.amplitude == pytest.approx(1.76165346695e-06, rel=1e-8)
    assert r.peak.omega == pytest.approx(38216.9713, rel=1e-8)


def test_quasi_static_low_frequency(tmp_path):
    result = run("quasi_static_low_frequency", tmp_path, **{"sweep.max_step": 0.1})
    r = result.runs[0]
    assert isinstance(r.plan.element, QuasiStatic)
    summary = json.loads((tmp_path / "summary.json").read_text())["runs"][0]
    assert summary["effects"][1]["effect"] == "damper inertia" and summary["effects"][1]["simulated"] is False
    # stored: the quasi-static peak (the full model's is 2.1e-4 lower, tests/test_scenes.py)
    assert r.peak.amplitude == pytest.approx(1.5862416985e-06, rel=1e-8)


def test_chain_3dof_from_matrix_files(tmp_path):
    """The structure scene: five harmonics of the chain with its damper, as the API computes them."""
    import numpy as np

    from contact_models import Macroslip
    from hbm import Contact, Structure, frequency_response

    result = run("chain_3dof", tmp_path)
    assert result.success
    K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    scene = load_scene(SCENES / "chain_3dof.toml")
    api = frequency_response(Structure(np.eye(3), 0.004 * K, K, force=[0.0, 0.0, 0.01]),
                             [Contact(Macroslip(stiffness=1.0, slip_force=0.02), dof=0)], omega_range=(0.3, 0.8),
                             response_dof=2, **scene.sweep["options"], harmonics=5, n_t=512)
    assert result.runs[0].peak.amplitude == pytest.approx(api.peak().amplitude, rel=1e-12)
