"""Scenes with ``effects.harmonics = H``: the multi-harmonic balance where the
element has a time law (the quasi-static bar), refused by name where it has none."""

from pathlib import Path

import pytest

from hbm.scenes import load_scene, plan_scene, run_scene
from hbm.scenes.checks import SceneError

SCENE = Path(__file__).resolve().parent.parent / "examples" / "scenes" / "quasi_static_low_frequency.toml"


def test_two_harmonics_of_an_odd_law_give_the_single_harmonic_peak(tmp_path):
    """A Masing element under a symmetric response has no even harmonics: H = 2 reproduces H = 1
    (the exact describing function) up to the AFT's sampling error."""
    base = {"output.formats": ["json"], "sweep.max_step": 0.1}
    one = run_scene(load_scene(SCENE, overrides=base), tmp_path / "h1")
    two = run_scene(load_scene(SCENE, overrides={**base, "effects.harmonics": 2}), tmp_path / "h2")
    assert one.success and two.success
    effect = [e for e in two.runs[0].plan.effects if e.name == "higher harmonics"][0]
    assert effect.simulated and "n_t = 512" in effect.reason
    assert two.runs[0].peak.amplitude == pytest.approx(one.runs[0].peak.amplitude, rel=1e-5)


def test_harmonics_refused_for_an_element_without_a_time_law():
    scene = load_scene(SCENE, overrides={"effects.harmonics": 3, "effects.inertia": "on"})
    with pytest.raises(SceneError, match="harmonics = 3 needs an element with a time-domain force law"):
        plan_scene(scene)
