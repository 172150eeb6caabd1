"""The command line beyond running scenes: --version, --help, new, models, keys, the Hz unit."""

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

import hbm
from hbm.cli.main import build_parser, in_scene_terms, main, program_name
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
    assert program_name("/x/hbm/__main__.py") == "python3 -m hbm"


def test_help_from_a_real_process_names_python_dash_m_hbm():
    proc = subprocess.run([sys.executable, "-m", "hbm", "--help"], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0 and proc.stdout.startswith("usage: python3 -m hbm")


def test_new_writes_a_template_that_runs_as_written(tmp_path, capsys):
    path = tmp_path / "study.toml"
    assert main(["new", str(path)]) == 0
    text = path.read_text()
    for key in all_keys():  # every key of the schema is in the template, set or commented
        assert f"{key.split('.')[-1]} = " in text, key
    scene = load_scene(path)
    # tol states the single-mode bar's error (tests/test_quiet_defaults.py)
    assert scene.sweep["options"] == {"rtol": 1e-6, "max_step": 0.03, "min_step": 1e-9, "max_steps": 5000,
                                      "tol": 0.15}
    # as written it is the default case; a coarser step only makes it quick here
    result = run_scene(load_scene(path, overrides={"sweep.max_step": 0.1}), tmp_path / "out")
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


# ----------------------------------------------------------------------------- exit codes, no tracebacks
def test_unreachable_tol_is_bad_input_exit_2_naming_the_option_and_its_range(capsys):
    with pytest.raises(SystemExit) as stop:
        main(["default", "--tol", "1e-300"])
    assert stop.value.code == 2
    assert "argument --tol: must be a number in [1e-10, 1)" in capsys.readouterr().err
    with pytest.raises(SystemExit) as stop:
        main(["--rtol", "0.5"])
    assert stop.value.code == 2


def test_run_answers_tol_in_one_line_pointing_to_sweep_tol(capsys):
    # before: "error: unrecognized arguments: --tol 1e-3", nothing about where a scene's tol is set
    for argv, value in ((["run", str(DEFAULT), "--tol", "1e-3"], "1e-3"), (["run", str(DEFAULT), "--tol=fast"], "fast"),
                        (["run", str(DEFAULT), "--tol"], "VALUE")):
        with pytest.raises(SystemExit) as stop:
            main(argv)
        err = capsys.readouterr().err
        assert stop.value.code == 2 and "Traceback" not in err and "unrecognized" not in err
        assert err.strip().splitlines()[-1].endswith(
            f" run: error: --tol does not apply to run: a scene's target error is its sweep.tol: give --set "
            f"sweep.tol={value}")
    with pytest.raises(SystemExit) as stop:  # given before run: the same pointer
        main(["--tol", "1e-3", "run", str(DEFAULT)])
    err = capsys.readouterr().err
    assert stop.value.code == 2 and err.strip().splitlines()[-1].endswith(
        "error: --tol does not apply to run (only to the main job); a scene's target error is its sweep.tol: "
        "give --set sweep.tol=VALUE")


def test_the_help_of_run_points_its_rtol_to_sweep_tol_not_to_a_tol_it_lacks(capsys):
    # before: "--rtol ... deprecated: the elements' relative accuracy, which --tol now sets"; run has no --tol
    with pytest.raises(SystemExit) as stop:
        main(["run", "--help"])
    out = " ".join(capsys.readouterr().out.split())
    assert stop.value.code == 0
    assert "which --tol now sets" not in out and "[--tol" not in out
    assert ("--rtol RTOL deprecated: the elements' relative accuracy; it overrides sweep.tolerance; use --set "
            "sweep.tol=VALUE instead, the target relative error, which sets it (tol/100, at most 1e-6)") in out


def test_a_failure_inside_the_computation_exits_1_not_2(tmp_path, capsys, monkeypatch):
    import hbm.cli.main as cli

    def broken(*args, **kwargs):
        raise ValueError("the frequency response has no points")

    monkeypatch.setattr(cli, "frequency_response", broken)
    assert main(["--out", str(tmp_path)]) == 1
    err = capsys.readouterr().err
    assert err.startswith("error: the computation failed: the frequency response has no points")
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err


@pytest.mark.parametrize("signal_, code, word", [("KeyboardInterrupt", 130, "interrupted"),
                                                 ("Terminated", 143, "terminated (SIGTERM)")])
def test_a_signal_during_the_default_job_exits_130_or_143_with_one_kept_line(tmp_path, capsys, monkeypatch,
                                                                             signal_, code, word):
    import hbm.cli.main as cli
    import hbm.cli.progress as progress

    stop = KeyboardInterrupt if signal_ == "KeyboardInterrupt" else cli.Terminated

    def interrupted(*args, **kwargs):
        raise stop()

    monkeypatch.setattr(cli, "job_figure", interrupted)  # the curve is computed and written: it is kept
    monkeypatch.setattr(progress, "PLAIN_INTERVAL", float("inf"))  # stderr a pipe: no progress line however long
    assert main(["--model", "given", "--out", str(tmp_path)]) == code
    err = capsys.readouterr().err.strip()
    assert err == f"{word}: kept files: {(tmp_path / 'frf.csv').resolve()}"
    assert (tmp_path / "frf.csv").exists()


def test_default_job_output_places_that_cannot_take_the_files_exit_2_before_computing(tmp_path, capsys):
    (tmp_path / "file").write_text("x")
    assert main(["--out", str(tmp_path / "file")]) == 2
    assert "is a file, not a folder" in capsys.readouterr().err
    (tmp_path / "out" / "frf.csv").mkdir(parents=True)
    assert main(["--out", str(tmp_path / "out")]) == 2
    assert "frf.csv is a folder where the output file frf.csv goes" in capsys.readouterr().err
    assert not (tmp_path / "out" / "frf.png").exists()
    # a folder to be made under a file, or where nothing can be written
    assert main(["--out", str(tmp_path / "file" / "sub")]) == 2
    assert f"{tmp_path / 'file'} is a file, so the folder cannot be made there" in capsys.readouterr().err
    if Path("/proc/self").is_dir():
        assert main(["--out", "/proc/frictiondamp-out"]) == 2
        assert "--out = /proc/frictiondamp-out: nothing can be written in /proc" in capsys.readouterr().err


def test_run_refuses_an_output_folder_that_is_a_file(tmp_path, capsys):
    (tmp_path / "file").write_text("x")
    assert main(["run", str(DEFAULT), "--out", str(tmp_path / "file")]) == 2
    assert "is a file, not a folder" in capsys.readouterr().err


def test_an_output_folder_whose_name_is_too_long_exits_2_before_computing(tmp_path, capsys):
    """A folder name of 300 characters passed the checks, the scene was computed, and writing failed after it:
    "error: cannot write: [Errno 36] File name too long", exit 1, nothing kept.  Now refused before computing."""
    long = tmp_path / ("a" * 300)
    for argv in (["run", str(DEFAULT), "--out", str(long)], ["--out", str(long)]):
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert f"--out = {long}: " in err and "cannot be a file name here (File name too long)" in err
        assert "nothing computed, nothing written" in err
    assert list(tmp_path.iterdir()) == []


def test_new_into_a_missing_folder_or_onto_a_folder_exits_2_with_one_line(tmp_path, capsys):
    assert main(["new", str(tmp_path / "missing" / "s.toml")]) == 2
    err = capsys.readouterr().err
    assert "does not exist; create it first" in err and len(err.strip().splitlines()) == 1
    assert main(["new", str(tmp_path)]) == 2
    assert "is a folder; new writes a scene file" in capsys.readouterr().err


def test_listing_into_a_closed_pipe_or_a_full_device_prints_no_traceback():
    proc = subprocess.run(f"{sys.executable} -m hbm keys | head -1", shell=True, capture_output=True, text=True,
                          timeout=60, cwd=ROOT)
    assert proc.stdout.strip() == "(top level)" and proc.stderr == ""
    if Path("/dev/full").exists():
        with open("/dev/full", "w") as full:
            proc = subprocess.run([sys.executable, "-m", "hbm", "keys"], stdout=full, stderr=subprocess.PIPE,
                                  text=True, timeout=60, cwd=ROOT)
        assert proc.returncode == 1
        assert proc.stderr.strip() == "error: cannot write: [Errno 28] No space left on device"


def test_a_warning_is_one_plain_line_without_a_file_path(tmp_path):
    # a real process: Python's own display of warnings (here its format), not pytest's capture
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.run([sys.executable, "-m", "hbm", "--model", "given", "--out", str(tmp_path)], cwd=tmp_path,
                          capture_output=True, text=True, timeout=120, env=env)
    assert proc.returncode == 0
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr  # the single-mode bar is off the physical one on the flank: said once
    assert lines[0].startswith("warning: frequency_response: estimated error ")
    assert lines[0].endswith(" (AccuracyWarning)") and ".py:" not in lines[0]


def single_mode_scene(folder):
    """The default scene with the single-mode bar at tol 1e-2: its model error on the flank (0.1) warns."""
    text = re.sub(r'(?m)^model = .*$', 'model = "two-region"', DEFAULT.read_text())
    path = folder / "single_mode.toml"
    path.write_text(re.sub(r"(?m)^(tolerance|tol|accuracy) = .*$", "", text).replace("[sweep]", "[sweep]\ntol = 1e-2"))
    return path


def test_a_scene_says_its_warning_once_after_the_summary(tmp_path, capsys):
    assert main(["run", str(single_mode_scene(tmp_path)), "--out", str(tmp_path / "out")]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert lines[-1].startswith("warning: frequency_response: estimated error ")
    assert lines[-1].endswith(" (AccuracyWarning)")
    assert sum(line.startswith("warning:") for line in lines) == 1
    # its advice in the scene's own keys: the bar with every mode is effects.phase_differences, the target sweep.tol
    assert "model='auto'" in lines[-1]
    assert "(in a scene: model='auto' is effects.phase_differences = \"on\"" in lines[-1]


def test_scene_terms_name_the_keys_of_the_arguments_the_advice_gives_and_leave_other_text_alone():
    said = in_scene_terms("use more harmonics (leave harmonics= out) or a smaller tol=")
    assert said.endswith("(in a scene: harmonics= is effects.harmonics, which a scene fixes (default 1; above 1 only "
                         "for a damper with a time-domain law); tol= is sweep.tol)")
    assert in_scene_terms("the branch stopped at omega = 3.9e4 rad/s") == "the branch stopped at omega = 3.9e4 rad/s"


@pytest.mark.parametrize("argv", [["--harmonics", "3"], ["run", "--harmonics", "3", "scene.toml"]])
def test_an_option_no_command_takes_is_named_not_the_value_after_it(argv, capsys):
    with pytest.raises(SystemExit) as stop:
        main(argv)
    assert stop.value.code == 2
    assert capsys.readouterr().err.strip().endswith("error: unrecognized option: --harmonics")
