"""Planning decides, then builds: the deciders return their decisions (``Effect.decided``), the
planner applies them, and only the element the plan keeps is built and checked along the sweep."""

from dataclasses import fields, replace
from pathlib import Path

import pytest

from contact_models import AllModeMicroslip
from contact_models.quasi_static import StuckContact
from hbm.cli.main import main
from hbm.scenes import EFFECTS, load_scene, plan_scene, run_scene

SCENE = Path(__file__).resolve().parents[1] / "examples" / "scenes" / "default_microslip_frf.toml"
ALL_MODE = {"damper.model": "auto", "effects.phase_differences": "on"}


def test_the_all_mode_bar_is_built_without_the_single_mode_path_it_replaces(capsys):
    """Above omega_c the single-mode element has no path; with phase differences on, the plan takes
    the all-mode bar and does not ask the single-mode element for one."""
    scene = load_scene(SCENE, overrides={**ALL_MODE, "sweep.omega": [2.0, 3.0], "blade.mass": 0.001})
    run = plan_scene(scene).runs[0]
    assert isinstance(run.element, AllModeMicroslip) and run.model == "all-mode"
    assert main(["run", str(SCENE), "--check", "--set", 'damper.model="auto"', "--set",
                 'effects.phase_differences="on"', "--set", "sweep.omega=[2.0, 3.0]", "--set", "blade.mass=0.001"]) == 0
    assert "AllModeMicroslip" in capsys.readouterr().out


def test_a_damper_held_stuck_needs_no_single_mode_path(tmp_path):
    scene = load_scene(SCENE, overrides={**ALL_MODE, "damper.k": 1.0e12, "output.formats": ["csv"]})
    result = run_scene(scene, tmp_path)
    assert result.success, result.message
    assert isinstance(result.runs[0].plan.element, StuckContact)
    assert not next(e for e in result.runs[0].plan.effects if e.name == "damper slip").simulated


def test_deciders_change_nothing_and_the_plan_carries_the_balance(monkeypatch):
    def watched(spec):
        def decide(run):
            before = {f.name: getattr(run, f.name) for f in fields(run) if not f.name.startswith("_")}
            effects = list(run.effects)
            decision = spec.decide(run)
            after = {f.name: getattr(run, f.name) for f in fields(run) if not f.name.startswith("_")}
            assert all(after[k] is v for k, v in before.items() if k != "effects"), spec.name
            assert run.effects == effects, spec.name
            return decision
        return replace(spec, decide=decide)

    monkeypatch.setattr("hbm.scenes.planning.EFFECTS", [watched(s) for s in EFFECTS])
    single = plan_scene(load_scene(SCENE)).runs[0]
    assert (single.harmonics, single.n_t) == (1, None)  # the single-harmonic balance of a blade, as the scene asks
    scene = load_scene(SCENE, overrides={"effects.harmonics": 2, "effects.inertia": "off"})
    options = dict(scene.sweep["options"])
    multi = plan_scene(scene).runs[0]
    assert (multi.harmonics, multi.n_t) == (2, 512)
    assert {k: scene.sweep["options"][k] for k in options} == options  # the accuracy options untouched
