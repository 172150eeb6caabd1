"""Malformed scenes: exit code 2, a message naming the file and the key, and no output at all.

Each case edits the default scene's text (``examples/scenes/default_microslip_frf.toml``) and runs
``python3 -m hbm run`` in-process (one case also as a real subprocess).
"""

import re
import subprocess
import sys
from pathlib import Path

import pytest

from hbm.cli.main import main
from hbm.scenes import SceneError, all_keys, load_scene, schema
from hbm.scenes.validation import parse_override

SCENES = Path(__file__).resolve().parent.parent / "examples" / "scenes"
# the default scene with the elements' rtol given by the key of earlier releases (the cases below edit it)
DEFAULT = re.sub(r"(?m)^tol = 0\.15 .*$", "tolerance = 1e-6", (SCENES / "default_microslip_frf.toml").read_text())

UNIFORM = 'kind = "uniform"\nN = 100.0'

#: (id, old text, new text, substrings the message must hold)
CASES = [
    # unknown names, with the closest valid one suggested
    ("unknown key", "mass = ", "mas = ", ["blade.mas = 0.0877", "did you mean blade.mass?"]),
    ("unknown table", "[sweep]", "[sweeep]", ["[sweeep]", "did you mean sweep?"]),
    ("key in the wrong table", "[effects]", "[effects]\nbeta = 3.0", ["effects.beta", "damper.beta"]),
    ("unknown choice", 'model = "two-region"', 'model = "two_region"',
     ['damper.model = "two_region"', 'did you mean "two-region"?']),
    # wrong types
    ("string for a number", "force = 8.0", 'force = "eight"', ['blade.force = "eight"', "must be a number > 0"]),
    ("bool for a choice", 'inertia = "on"', "inertia = true", ["effects.inertia = true", '"on", "off", "auto"']),
    ("string for a bool", "strain_hardening = true", 'strain_hardening = "yes"',
     ["effects.strain_hardening", "true or false"]),
    ("scalar for a range", "omega = [0.24, 0.33]", "omega = 0.3", ["sweep.omega = 0.3", "list of 2"]),
    ("table expected", ('[damper.load]\nkind = "uniform"\nN = 100.0\n', "mu = 0.3\n"), ("", "mu = 0.3\nload = 100.0\n"),
     ["damper.load = 100.0", "must be a table"]),
    ("formats", 'formats = ["csv", "png", "json"]', 'formats = ["csv", "pdf"]', ["output.formats", '"png"']),
    ("not TOML", "force = 8.0", "force = = 8", ["not valid TOML"]),
    # missing values
    ("missing key", "force = 8.0", "", ["blade.force is missing"]),
    ("missing table", ("[sweep]\n", "omega = [0.24, 0.33]", 'unit = "omega_c"\n', "tolerance = 1e-6\n"),
     ("", "", "", ""), ["[sweep] is missing: required (at least sweep.omega)"]),
    ("missing bar parameter", "mu = 0.3\n", "", ["damper.mu is missing"]),
    ("missing beta with the spring on", "beta = 4.0e7\n", "", ["damper.beta is missing", "strain_hardening"]),
    ("neither damping nor ratio", "damping_ratio = 2.0e-3\n", "", ["blade.damping is missing", "damping_ratio"]),
    ("ratio without quadratic", UNIFORM, UNIFORM + "\nratio = 12.0", ["damper.load.ratio = 12.0", "quadratic"]),
    ("quadratic without ratio", UNIFORM, 'kind = "quadratic"\nN = 100.0', ["damper.load.ratio is missing"]),
    # values out of range, or conflicting
    ("negative mass", "mass = 0.0877", "mass = -0.0877", ["blade.mass = -0.0877", "> 0"]),
    ("negative load", "N = 100.0", "N = -1.0", ["damper.load.N = -1.0", ">= 0"]),
    ("tolerance too large", "tolerance = 1e-6", "tolerance = 0.5", ["sweep.tolerance = 0.5", "< 0.1"]),
    ("misspelt tol name", "tolerance = 1e-6", 'tol = "fats"',
     ['sweep.tol = "fats"', 'or one of "fast" (0.01), "default" (0.001), "precise" (1e-05)', 'did you mean "fast"?']),
    ("empty range", "omega = [0.24, 0.33]", "omega = [0.3, 0.3]", ["sweep.omega = [0.3, 0.3]", "different"]),
    # a range a few roundings wide: the run failed, naming frequency_response's omega_range, not the key
    ("range of rounding width", "omega = [0.24, 0.33]", "omega = [0.3, 0.30000000000000004]",
     ["sweep.omega = [0.3, 0.30000000000000004]", "at least 1e-12 of the larger apart"]),
    # the bar's phase without a digit where the inertia is decided: a ValueError naming no key
    ("frequency past the bar's phase", 'omega = [0.24, 0.33]', 'omega = [1e15, 1e16]',
     ["sweep.omega = [", "1e+16]: deciding the damper inertia there: omega=", "is too high for the bar"]),
    ("two ways to give stiffness", "stiffness = 1.0e8", "stiffness = 1.0e8\nfrequency = 3.0e4",
     ["blade.frequency = 30000.0", "together with blade.stiffness"]),
    ("tolerance and accuracy", "tolerance = 1e-6", 'tolerance = 1e-6\naccuracy = "precise"',
     ['sweep.accuracy = "precise"', "one of them"]),
    ("multi-harmonic", "harmonics = 1", "harmonics = 3",
     ["effects.harmonics = 3", "needs an element with a time-domain force law"]),
    ("negative q", UNIFORM, 'kind = "quadratic"\nq0 = 1000.0\nq2 = 2000.0', ["damper.load.q2 = 2000.0", "q0"]),
    ("macroslip key on a microslip model", "mu = 0.3", "mu = 0.3\nslip_force = 30.0",
     ["damper.slip_force = 30.0", "macroslip"]),
    # physically impossible for the model
    ("concave load on two regions", UNIFORM, 'kind = "quadratic"\nN = 100.0\nratio = 12.0',
     ['damper.model = "two-region"', "slip starts inside the bar", '"three-region" or "auto"']),
    ("convex load whose end slips", UNIFORM, 'kind = "quadratic"\nN = 100.0\nratio = 0.5',
     ["damper.load", "the end x = 0 starts slipping too"]),
]


@pytest.mark.parametrize("old, new, expected", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_malformed_scene_exits_2_names_the_key_and_writes_nothing(tmp_path, capsys, old, new, expected):
    text = DEFAULT
    for o, n in zip(*((old, new) if isinstance(old, tuple) else ((old,), (new,)))):
        assert text.count(o) >= 1, o
        text = text.replace(o, n, 1)
    scene = tmp_path / "bad_scene.toml"
    scene.write_text(text)
    out = tmp_path / "out"
    assert main(["run", str(scene), "--out", str(out)]) == 2
    cap = capsys.readouterr()
    assert cap.out == ""
    assert "bad_scene.toml" in cap.err
    for text in expected:
        assert text in cap.err
    assert not out.exists()  # nothing written, not even the folder


def test_at_least_fifteen_malformed_cases():
    assert len(CASES) >= 15


def test_every_problem_is_reported_at_once(tmp_path):
    scene = tmp_path / "s.toml"
    scene.write_text(DEFAULT.replace("mass = ", "mas = ").replace("harmonics = 1", "harmonics = 2")
                     .replace("force = 8.0", "force = -8.0"))
    with pytest.raises(SceneError) as err:
        load_scene(scene)
    keys = " ".join(err.value.problems)
    assert len(err.value.problems) >= 3 and "blade.mas " in keys and "blade.force" in keys


def test_key_errors_and_rules_between_keys_come_in_one_pass(tmp_path):
    """A bad value and a broken rule between keys are reported together, and a key given with a bad
    value is not also reported missing: correcting what is reported gives a valid scene."""
    bad = (DEFAULT.replace("force = 8.0", "force = -8.0").replace("tolerance = 1e-6", 'tolerance = 1e-6\naccuracy = "fast"')
           .replace("mu = 0.3", 'mu = "high"').replace('kind = "uniform"', 'kind = "quadratic"'))
    scene = tmp_path / "s.toml"
    scene.write_text(bad)
    with pytest.raises(SceneError) as err:
        load_scene(scene)
    problems = err.value.problems
    assert any("blade.force = -8.0" in p for p in problems)  # a value
    assert any('sweep.accuracy = "fast"' in p and "sweep.tolerance" in p for p in problems)  # a rule
    assert any("damper.load.ratio is missing" in p for p in problems)  # a rule on another table
    assert not any("damper.mu is missing" in p for p in problems)  # given, though invalid
    assert len(problems) == 4, problems
    fixed = (bad.replace("force = -8.0", "force = 8.0").replace('\naccuracy = "fast"', "")
             .replace('mu = "high"', "mu = 0.3").replace("N = 100.0", "N = 100.0\nratio = 12.0"))
    scene.write_text(fixed)
    load_scene(scene)  # no second round of problems


def test_bad_override_on_the_command_line_exits_2(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text(DEFAULT)
    assert main(["run", str(scene), "--out", str(tmp_path / "o"), "--set", "sweep.max_step=-1"]) == 2
    assert "sweep.max_step = -1" in capsys.readouterr().err and not (tmp_path / "o").exists()


@pytest.mark.parametrize("override, message", [
    # before: the override was dropped in silence (the run went on with blade.mass as in the file, exit code 0)
    ("blade.mass.x=3", "blade.mass.x = 3: cannot be set: blade.mass is 0.08771473371579717, not a table"),
    ("sweep.omega.lo=1", "sweep.omega.lo = 1: cannot be set: sweep.omega is [0.24, 0.33], not a table"),
])
def test_an_override_below_a_value_that_is_no_table_exits_2_naming_it(tmp_path, capsys, override, message):
    scene = tmp_path / "s.toml"
    scene.write_text(DEFAULT)
    assert main(["run", str(scene), "--out", str(tmp_path / "o"), "--check", "--set", override]) == 2
    err = capsys.readouterr().err
    assert f"{scene}: {message}" in err and "Traceback" not in err and not (tmp_path / "o").exists()
    with pytest.raises(SceneError, match=re.escape(message)):
        load_scene(scene, overrides=dict([parse_override(override)]))


def test_invalid_scene_exit_code_from_a_real_process(tmp_path):
    scene = tmp_path / "bad.toml"
    scene.write_text(DEFAULT.replace("harmonics = 1", "harmonics = 5"))
    proc = subprocess.run([sys.executable, "-m", "hbm", "run", str(scene), "--out", str(tmp_path / "o")],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2
    assert "effects.harmonics = 5" in proc.stderr and not (tmp_path / "o").exists()


def test_docs_list_every_key():
    doc = (Path(__file__).resolve().parent.parent / "docs" / "scenes.md").read_text()
    missing = [k for k in all_keys() if f"`{k}`" not in doc]
    assert not missing, missing
    assert set(schema()) == {"", "blade", "structure", "damper", "damper.load", "effects", "sweep", "modes", "optimum", "output",
                            "study"}


@pytest.mark.parametrize("values", ["[10.0, 10.0]", "[10, 10.0]", "[10.0, 20.0, 10]"])
def test_a_study_grid_repeating_a_value_is_refused_like_a_repeated_model(tmp_path, capsys, values):
    path = tmp_path / "grid.toml"
    path.write_text(DEFAULT + f'\n[study.grid]\n"damper.load.N" = {values}\n')
    assert main(["run", str(path), "--check"]) == 2
    err = capsys.readouterr().err
    assert f'"damper.load.N" = {values}: must not repeat a value (one run per value;' in err and "study.grid" in err
    assert not (tmp_path / "grid").exists()


def test_the_grid_function_refuses_a_repeated_value():
    from hbm.study import grid

    with pytest.raises(ValueError, match=r"^grid: parameter 'x' must not repeat a value .* 10 and 10.0 are the same"):
        grid({"x": [10, 10.0]})


@pytest.mark.parametrize("folder", ["/tmp/elsewhere", "../outside", "a/../../b", ""])
def test_output_folder_outside_the_scene_folder_is_refused(tmp_path, capsys, folder):
    path = tmp_path / "scenes" / "s.toml"
    path.parent.mkdir()
    path.write_text(DEFAULT + f'folder = "{folder}"\n')
    assert main(["run", str(path), "--check"]) == 2
    err = capsys.readouterr().err
    assert "output.folder" in err and ("inside the scene's folder" in err or "folder name" in err)


def test_output_folder_is_resolved_beside_the_scene_file_and_out_writes_anywhere(tmp_path, monkeypatch):
    path = tmp_path / "scenes" / "s.toml"
    path.parent.mkdir()
    path.write_text(DEFAULT.replace("tolerance = 1e-6", "tolerance = 1e-3") + 'folder = "results"\n')
    elsewhere = tmp_path / "cwd"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    assert load_scene(path).output["folder"] == str(path.parent / "results")
    assert main(["run", str(path), "--quiet", "--set", 'effects.phase_differences="off"']) == 0
    assert (path.parent / "results" / "frf.csv").exists() and not list(elsewhere.iterdir())
    assert main(["run", str(path), "--quiet", "--set", 'effects.phase_differences="off"',
                 "--out", str(tmp_path / "free")]) == 0
    assert (tmp_path / "free" / "frf.csv").exists()


def test_sweep_tolerance_warns_as_deprecated_naming_sweep_tol(tmp_path):
    path = tmp_path / "old.toml"
    path.write_text(DEFAULT)  # the default scene with sweep.tolerance = 1e-6 (above)
    with pytest.warns(FutureWarning, match=r"sweep.tolerance is deprecated: .*give sweep.tol"):
        scene = load_scene(path)
    assert scene.sweep["options"]["rtol"] == 1e-6  # still read, for one release
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error", FutureWarning)
        for shipped in sorted(SCENES.glob("*.toml")):  # nothing shipped uses it
            load_scene(shipped)


def test_sweep_tol_takes_the_names_of_frequency_response_tol(tmp_path):
    """sweep.tol = "precise" is sweep.tol = 1e-5, as frequency_response(tol="precise") is tol=1e-5."""
    named, number = tmp_path / "named.toml", tmp_path / "number.toml"
    named.write_text(DEFAULT.replace("tolerance = 1e-6", 'tol = "precise"'))
    number.write_text(DEFAULT.replace("tolerance = 1e-6", "tol = 1e-5"))
    a, b = load_scene(named), load_scene(number)
    assert a.sweep["tol"] == b.sweep["tol"] == 1e-5
    assert a.sweep["options"] == b.sweep["options"] and a.sweep["options"]["tol"] == 1e-5


def test_sweep_accuracy_warns_once_as_deprecated_naming_sweep_tol(tmp_path, capsys):
    """The preset key of an earlier release still reads as it did, with one warning in the scene's terms
    (not a second one from frequency_response's own deprecated keyword)."""
    import warnings

    path = tmp_path / "old.toml"
    path.write_text(DEFAULT.replace("tolerance = 1e-6", 'accuracy = "fast"'))
    with pytest.warns(FutureWarning, match=r'sweep.accuracy is deprecated: .*give sweep.tol = "fast"'):
        scene = load_scene(path)
    assert scene.sweep["options"]["rtol"] == 1e-3 and scene.sweep["tol"] == 1e-2  # the preset, for one release
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        assert main(["run", str(path), "--quiet", "--out", str(tmp_path / "out")]) == 0
    said = [str(w.message) for w in seen] + capsys.readouterr().err.splitlines()
    assert sum("deprecated" in m for m in said) == 1, said


@pytest.mark.parametrize("value, shown", [("5", "sweep.accuracy = 5"), ('"fast-ish"', 'sweep.accuracy = "fast-ish"')])
def test_a_sweep_accuracy_that_is_no_preset_is_a_scene_error_naming_the_key_value_and_presets(tmp_path, value, shown):
    """The deprecated key's value is checked like any choice: a SceneError naming it and the preset names,
    not a KeyError of the rule that reads the (refused) value."""
    path = tmp_path / "acc.toml"
    path.write_text(DEFAULT.replace("tolerance = 1e-6", f"accuracy = {value}"))
    with pytest.raises(SceneError) as err:
        load_scene(path)
    assert err.value.problems == [f'{path}: {shown}: must be one of "fast", "default", "precise"'
                                  + (' (did you mean "fast"?)' if "fast" in value else "")]


def test_a_sweep_accuracy_that_is_no_preset_exits_2_with_the_scene_message_from_a_real_process(tmp_path):
    scene = tmp_path / "acc.toml"
    scene.write_text(DEFAULT.replace("tolerance = 1e-6", "accuracy = 5"))
    proc = subprocess.run([sys.executable, "-m", "hbm", "run", str(scene), "--out", str(tmp_path / "o")],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2 and proc.stdout == ""
    assert proc.stderr.splitlines() == ["error: invalid scene (nothing computed, nothing written):",
                                        f'{scene}: sweep.accuracy = 5: must be one of "fast", "default", "precise"']
    assert not (tmp_path / "o").exists()


@pytest.mark.filterwarnings("ignore:.*sweep.tolerance is deprecated:FutureWarning")
def test_a_sweep_accuracy_that_is_no_preset_beside_a_step_knob_reports_both(tmp_path):
    """A key given with a refused value still counts as given: the rule against giving it with the knob
    it sets is said too, so fixing what is reported gives a valid scene."""
    path = tmp_path / "acc.toml"
    path.write_text(DEFAULT.replace("tolerance = 1e-6", "tolerance = 1e-6\naccuracy = 5"))
    with pytest.raises(SceneError) as err:
        load_scene(path)
    problems = err.value.problems
    assert any("sweep.accuracy = 5: must be one of" in p for p in problems)
    assert any("sweep.accuracy = \"(invalid)\": not allowed together with sweep.tolerance" in p for p in problems), problems
