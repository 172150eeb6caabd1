"""The command line beyond running scenes: --version, --help, new, models, keys, the Hz unit."""

import subprocess
import sys
from pathlib import Path

import pytest

import hbm
from hbm.cli.main import build_parser, main, program_name
from hbm.scenes import MODELS, all_keys, load_scene, plan_scene, run_scene, scene_from_dict

ROOT = Path(__file__).resolve().parent.parent
DEFAULT = ROOT / "examples" / "scenes" / "default_microslip_frf.toml"


def test_version_is_the_package_version(capsys):
    with pytest.raises(SystemExit) as stop:
        main(["--version"])
    assert stop.value.code == 0
    assert capsys.readouterr().out.strip().endswith(" " + hbm.__version__)


def test_help_is_plain_text_with_examples_and_the_typed_program_name():
    text = build_parser("frictiondamp").format_help()
    assert "``" not in text and ":func:" not in text
    assert "examples:" in text and "frictiondamp run study.toml" in text
    assert program_name("/usr/bin/frictiondamp") == "frictiondamp"
    assert program_name("/x/hbm/__main__.py") == "python -m hbm"


def test_help_from_a_real_process_names_python_dash_m_hbm():
    proc = subprocess.run([sys.executable, "-m", "hbm", "--help"], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0 and proc.stdout.startswith("usage: python -m hbm")


def test_new_writes_a_template_that_runs_as_written(tmp_path, capsys):
    path = tmp_path / "study.toml"
    assert main(["new", str(path)]) == 0
    text = path.read_text()
    for key in all_keys():  # every key of the schema is in the template, set or commented
        assert f"{key.split('.')[-1]} = " in text, key
    scene = load_scene(path)
    assert scene.sweep["options"] == {"rtol": 1e-6, "max_step": 0.03, "min_step": 1e-9, "max_steps": 5000}
    # as written it is the default case; a coarser step only makes it quick here
    result = run_scene(load_scene(path, overrides={"sweep.accuracy": "fast"}), tmp_path / "out")
    assert result.success and result.runs[0].peak.amplitude == pytest.approx(1.5119614110e-06, rel=1e-4)
    assert main(["new", str(path)]) == 2  # no silent overwrite
    assert "exists" in capsys.readouterr().err


def test_models_and_keys_list_the_registries(capsys):
    assert main(["models"]) == 0
    out = capsys.readouterr().out
    assert all(name in out for name in MODELS)
    assert main(["keys"]) == 0
    out = capsys.readouterr().out
    assert all(f"{k}:" in out for k in all_keys())


def test_hz_sweep_unit_is_two_pi_rad_per_second():
    import tomllib

    data = tomllib.loads(DEFAULT.read_text())
    data["sweep"].update(unit="Hz", omega=[5000.0, 6500.0])
    plan = plan_scene(scene_from_dict(data, "hz.toml"))
    assert plan.runs[0].omega == pytest.approx((2 * 3.141592653589793 * 5000.0, 2 * 3.141592653589793 * 6500.0),
                                               rel=1e-15)
