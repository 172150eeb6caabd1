"""Scenes with ``[modes]`` (a nonlinear mode) and ``[optimum]`` (the damper's optimum).

Each example scene is run as written and its outputs compared with the Python API called directly
on the same system (``hbm.nonlinear_modes``, ``hbm.damper_optimum``), the system built here from
the numbers of the scene file, not from the planner; bad keys are refused naming the key and value.
"""

from __future__ import annotations

import csv
import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from contact_models import Bar, Macroslip, TwoRegionMicroslip, UniformLoad
from hbm import Blade, Contact, Structure, damper_optimum, nonlinear_modes
from hbm.balance.presets import samples_for
from hbm.cli.main import main
from hbm.scenes import SceneError, load_scene, plan_scene, run_scene, scene_from_dict
from hbm.output import csv_lines

from conftest import scene_data  # a scene file's tables with changes

SCENES = Path(__file__).resolve().parent.parent / "examples" / "scenes"
CHAIN = SCENES / "nonlinear_modes_chain.toml"
OPTIMUM = SCENES / "damper_optimum.toml"
#: The chain of the scene: unit masses and springs ground-0-1-2, C = 0.004 K, forced at DOF 2.
K_CHAIN = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
#: The scene's continuation settings are the scene defaults (docs/scenes.md): rtol 1e-6, max_step 0.03.
RTOL, MAX_STEP, MAX_STEPS = 1e-6, 0.03, 5000
#: The default blade's optimal load by 50 FRFs and a cubic spline (docs/nonlinear_modes.md, independent of the modes).
SPLINE_OPTIMUM_N = 52.36370


def rows(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(csv_lines(fh)))


def column(table, name):
    return np.array([float(r[name]) for r in table])


def test_nonlinear_modes_chain_scene_is_the_api_mode(tmp_path):
    result = run_scene(load_scene(CHAIN), tmp_path / "out", progress=None)
    assert result.success and result.exit_code == 0
    s = Structure(np.eye(3), 0.004 * K_CHAIN, K_CHAIN, force=[0.0, 0.0, 0.01])
    api = nonlinear_modes(s, [Contact(Macroslip(stiffness=1.0, slip_force=0.02), dof=0)], mode=0,
                          amplitude_range=(1e-3, 10.0), harmonics=5, n_t=samples_for(5), rtol=RTOL,
                          max_step=MAX_STEP, max_steps=MAX_STEPS)
    table = rows(tmp_path / "out" / "modes.csv")
    assert len(table) == len(api) > 50
    np.testing.assert_allclose(column(table, "modal_amplitude"), api.amplitude, rtol=1e-12)
    np.testing.assert_allclose(column(table, "omega_rad_s"), api.omega, rtol=1e-12)
    np.testing.assert_allclose(column(table, "damping_ratio"), api.damping_ratio, rtol=1e-12)
    c = api.coefficients(2)  # the response DOF of the scene
    np.testing.assert_allclose(column(table, "response_amplitude_m"), np.hypot(c[:, 1], c[:, 2]), rtol=1e-12)
    # physics: stuck, the lowest eigenfrequency of K with the contact as a unit spring at DOF 0
    # (the damping C = 0.004 K is not proportional to the stuck stiffness: 1e-6)
    stuck = math.sqrt(np.linalg.eigvalsh(K_CHAIN + np.diag([1.0, 0.0, 0.0]))[0])
    assert column(table, "omega_rad_s")[0] == pytest.approx(stuck, rel=1e-6)
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["status"] == "success" and summary["kind"] == "modes"
    run = summary["runs"][0]
    assert run["mode"]["points"] == len(api) and run["mode"]["harmonics"] == 5 and run["mode"]["success"]
    assert run["mode"]["counters"]["nsteps"] == api.nsteps
    assert {e["effect"]: e["simulated"] for e in run["effects"]}["higher harmonics"] is True
    assert (tmp_path / "out" / "modes.png").stat().st_size > 10_000


def default_blade_api():
    """The blade and bar of damper_optimum.toml, from its numbers."""
    data = tomllib.loads(OPTIMUM.read_text())
    b, d = data["blade"], data["damper"]
    blade = Blade(mass=b["mass"], stiffness=b["stiffness"],
                  damping=2.0 * b["damping_ratio"] * math.sqrt(b["stiffness"] * b["mass"]), force=b["force"])
    bar = Bar(E=d["E"], rho=d["rho"], A=d["A"], L=d["L"], k=d["k"], beta=d["beta"], mu=d["mu"])
    return blade, bar, data


def test_damper_optimum_scene_is_the_api_optimum(tmp_path, capsys):
    code = main(["run", str(OPTIMUM), "--out", str(tmp_path / "out"), "--quiet"])
    printed = capsys.readouterr().out
    assert code == 0
    blade, bar, data = default_blade_api()
    api = damper_optimum(blade.as_structure(),
                         lambda p: [Contact(TwoRegionMicroslip(bar, UniformLoad(N=p)), dof=0)], (30.0, 90.0),
                         amplitude_range=tuple(data["modes"]["amplitude"]), harmonics=1, response_dof=0,
                         max_step=MAX_STEP, max_steps=MAX_STEPS)
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    opt = summary["runs"][0]["optimum"]
    assert opt["parameter"] == "damper.load.N"
    assert opt["value"] == pytest.approx(api.parameter, rel=1e-12)
    assert opt["peak"]["amplitude_m"] == pytest.approx(api.peak.amplitude, rel=1e-12)
    assert opt["peak"]["omega_rad_s"] == pytest.approx(api.peak.omega, rel=1e-12)
    table = rows(tmp_path / "out" / "optimum.csv")
    np.testing.assert_allclose(column(table, "parameter"), api.parameters, rtol=1e-12)
    np.testing.assert_allclose(column(table, "peak_amplitude_m"), api.peaks, rtol=1e-12)
    np.testing.assert_allclose(column(table, "peak_omega_rad_s"), api.peak_omega, rtol=1e-12)
    # against the FRFs' spline (another method): the same load to 2e-5
    assert opt["value"] == pytest.approx(SPLINE_OPTIMUM_N, rel=2e-5)
    assert f"optimum: damper.load.N = {api.parameter:.9g}" in printed
    assert (tmp_path / "out" / "optimum.png").exists()


def test_check_prints_the_effects_of_a_mode_scene(tmp_path, capsys):
    assert main(["run", str(CHAIN), "--check"]) == 0
    out = capsys.readouterr().out
    assert "1 run(s)" in out and "damper slip: simulated - a nonlinear mode" in out
    assert "higher harmonics: simulated - effects.harmonics = 5" in out


@pytest.mark.parametrize("path, changes, expected", [
    (CHAIN, {"modes.mode": -1}, "modes.mode = -1"),
    (CHAIN, {"modes.amplitude": [1.0, 0.1]}, "modes.amplitude = [1.0, 0.1]: must be [a0, a1] with a0 < a1"),
    (CHAIN, {"modes.amplitudes": [0.5, 20.0]}, "modes.amplitudes = [0.5, 20.0]: must lie within"),
    (CHAIN, {"modes.amplitude": None}, "modes.amplitude is missing"),
    (CHAIN, {"modes.harmonics": 3}, "modes.harmonics = 3: unknown key (it belongs in [effects]: effects.harmonics)"),
    (CHAIN, {"sweep.kind": "frequency"}, 'sweep.kind = "frequency": not allowed with [modes]'),
    (CHAIN, {"sweep.omega": [0.55, 0.4]}, "sweep.omega = [0.55, 0.4]: must be [w0, w1] with w0 < w1"),
    (CHAIN, {"sweep.min_step": 1e-6}, "sweep.min_step = 1e-06: not allowed with [modes]"),
    (OPTIMUM, {"optimum.parameter": "damper.normal_load"},
     'optimum.parameter = "damper.normal_load": must be a number key of [damper] or [damper.load]'),
    (OPTIMUM, {"optimum.parameter": "damper.model"}, 'optimum.parameter = "damper.model": must be a number key'),
    (OPTIMUM, {"optimum.bounds": [90.0, 30.0]}, "optimum.bounds = [90.0, 30.0]: must be [p0, p1] with p0 < p1"),
    (OPTIMUM, {"optimum.bounds": [-1.0, 90.0]}, "optimum.bounds = [-1.0, 90.0]: -1.0 is not a value of damper.load.N"),
    (OPTIMUM, {"optimum.bounds": None}, "optimum.bounds is missing"),
    (OPTIMUM, {"modes": None}, "[modes] is missing: required with [optimum]"),
    (OPTIMUM, {"modes.amplitudes": [1e-8]}, "modes.amplitudes = [1e-08]: not allowed with [optimum]"),
    (OPTIMUM, {"sweep.tolerance": 1e-8}, "sweep.tolerance = 1e-08: not allowed with [optimum]"),
    (OPTIMUM, {"sweep.tol": 1e-4}, "sweep.tol = 0.0001: not allowed with [optimum]"),
    (OPTIMUM, {"damper.load.N": [30.0, 60.0]}, 'optimum.parameter = "damper.load.N": must be a number key'),
])
def test_bad_mode_and_optimum_keys_are_refused_by_name(path, changes, expected):
    with pytest.raises(SceneError) as info:
        plan_scene(scene_from_dict(scene_data(path, **changes), path))
    assert expected in str(info.value), str(info.value)


def test_a_mode_the_system_has_not_is_refused_when_planned():
    scene = scene_from_dict(scene_data(CHAIN, **{"modes.mode": 3}), CHAIN)
    with pytest.raises(SceneError, match=r"modes\.mode = 3: the system has 3 DOFs, so 3 modes \(0 to 2\)"):
        plan_scene(scene)


def test_an_invalid_mode_scene_exits_2_and_writes_nothing(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text(OPTIMUM.read_text().replace('parameter = "damper.load.N"', 'parameter = "damper.normal_load"'))
    assert main(["run", str(bad), "--out", str(tmp_path / "o")]) == 2
    assert 'optimum.parameter = "damper.normal_load"' in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("changes, rtol", [({}, RTOL), ({"sweep.tol": 1e-6}, 1e-8), ({"sweep.tol": 0.01}, RTOL)])
def test_a_mode_scene_takes_its_elements_rtol_from_sweep_tol_as_frequency_response_does(tmp_path, monkeypatch,
                                                                                      changes, rtol):
    """sweep.tol caps the elements' rtol at tol/100 (at most 1e-6), the rule of frequency_response's tol."""
    import hbm.scenes.modal as modal

    seen = {}

    def spy(*args, **kwargs):
        seen.update(kwargs)
        raise RuntimeError("stop here")

    monkeypatch.setattr(modal, "nonlinear_modes", spy)
    result = run_scene(scene_from_dict(scene_data(CHAIN, **changes), CHAIN), tmp_path, progress=None)
    assert not result.success  # (the run stopped where the mode would be computed)
    assert seen["rtol"] == pytest.approx(rtol, rel=1e-15)
