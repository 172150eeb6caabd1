"""Parameter studies (hbm.study): the same table on every executor, crash safety and resume."""

import csv
import ctypes
import json
import math
import os
import signal
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import pytest

from contact_models import AccuracyWarning
from hbm.cli.main import main
from hbm.output import csv_lines
from hbm.scenes import SceneError
from hbm.study import (DASK_MISSING, Study, grid, lognormal, normal, read_records, run_study, samples, uniform)

from conftest import MACROSLIP_BLADE  # the blade and Jenkins damper these studies share
from test_cli import single_mode_scene

ROOT = Path(__file__).resolve().parent.parent
ENV = "FRICTIONDAMP_STUDY_TEST"  # the folder where flaky() logs its calls and finds its faults

SCENE = """title = "a small study"
""" + MACROSLIP_BLADE + """[effects]
inertia = "on"
[sweep]
omega = [0.24, 0.33]
unit = "omega_c"
tol = "fast"
max_step = 0.095
"""
STUDY = """[study]
n = 3
seed = 11
[study.grid]
"damper.model" = ["macroslip", "point-contact"]
[study.samples]
"damper.mu" = {distribution = "uniform", low = 0.2, high = 0.4}
"damper.load.N" = {distribution = "lognormal", median = 60.0, sigma = 0.5}
"""


def flaky(point):
    """A run of known result; it fails or kills its process when a marker file says so."""
    folder = Path(os.environ[ENV])
    x = point["x"]
    with open(folder / "calls.log", "a") as fh:
        fh.write(f"{x!r}\n")
    if (folder / f"raise-{x}").exists():
        raise RuntimeError(f"injected failure at x = {x}")
    if (folder / f"kill-{x}").exists():
        os._exit(3)  # the worker process dies without a word
    time.sleep(0.02)
    return {"peak_omega_rad_s": x, "peak_amplitude_m": math.sin(x) ** 2, "nfev": 10 * int(x),
            "curve": {"omega_rad_s": [0.0, x], "amplitude_m": [1.0, math.cos(x)]}}


def openblas_threads(point):
    """The threads of every OpenBLAS loaded in this process (its least), as a run's result."""
    with open("/proc/self/maps") as maps:
        paths = sorted({line.split()[-1] for line in maps if "openblas" in line.lower() and ".so" in line})
    counts = []
    for path in paths:
        lib = ctypes.CDLL(path)
        for fn in ("openblas_get_num_threads", "openblas_get_num_threads64_", "scipy_openblas_get_num_threads",
                   "scipy_openblas_get_num_threads64_"):
            if hasattr(lib, fn):
                counts.append(getattr(lib, fn)())
                break
    return {"peak_amplitude_m": float(max(counts)) if counts else None,
            "peak_omega_rad_s": float(os.environ.get("OPENBLAS_NUM_THREADS", "nan"))}


def loose(point):
    """A run that warns as a solve over its tolerance does: its estimate is x / 100."""
    if point["x"] > 1.0:
        warnings.warn(f"estimated error {point['x'] / 100.0:g} > tol 0.001", AccuracyWarning)
    return {"peak_amplitude_m": point["x"], "peak_error_rel": point["x"] / 100.0}


def calls(folder):
    path = Path(folder) / "calls.log"
    return [float(v) for v in path.read_text().split()] if path.exists() else []


def without_time(result):
    return [{k: v for k, v in row.items() if k != "time_s"} for row in result.rows]


def test_grid_and_samples_are_the_documented_points():
    pts = grid({"a": [1, 2], "b": ["x", "y", "z"]})
    assert pts[0] == {"a": 1, "b": "x"} and pts[1] == {"a": 1, "b": "y"} and len(pts) == 6
    draws = samples(20000, {"u": uniform(2.0, 4.0), "n": normal(5.0, 0.5), "l": lognormal(100.0, 0.3)}, seed=3)
    u, n, ln = (np.array([p[k] for p in draws]) for k in ("u", "n", "l"))
    # moments against the distributions' closed forms (standard errors ~ 0.6 %, 0.4 %, 0.3 %)
    assert u.min() >= 2.0 and u.max() < 4.0 and u.mean() == pytest.approx(3.0, abs=0.01)
    assert u.std() == pytest.approx(2.0 / math.sqrt(12.0), rel=0.02)
    assert n.mean() == pytest.approx(5.0, abs=0.01) and n.std() == pytest.approx(0.5, rel=0.02)
    assert np.median(ln) == pytest.approx(100.0, rel=0.01)
    assert ln.mean() == pytest.approx(100.0 * math.exp(0.3 ** 2 / 2), rel=0.01)
    assert samples(4, {"u": uniform(0, 1)}, seed=3) == samples(4, {"u": uniform(0, 1)}, seed=3)
    assert samples(4, {"u": uniform(0, 1)}, seed=3) != samples(4, {"u": uniform(0, 1)}, seed=4)
    with pytest.raises(ValueError, match="low < high"):
        uniform(1.0, 1.0)
    with pytest.raises(ValueError, match="sigma"):
        lognormal(1.0, -0.1)
    with pytest.raises(ValueError, match="n=0"):
        samples(0, {"u": uniform(0, 1)}, seed=1)


def test_same_table_serially_in_processes_and_on_dask(tmp_path):
    """The small scene study (2 models x 3 samples of mu and N) gives the same table to the last bit
    serially, on two processes and on a two-worker Dask LocalCluster."""
    path = tmp_path / "s.toml"
    path.write_text(SCENE + STUDY)
    study = Study.from_scene(path)
    assert len(study.points) == 6 and study.parameters == ("damper.model", "damper.mu", "damper.load.N")
    results = {ex: run_study(study, tmp_path / ex, executor=ex, workers=2, formats=("csv", "json"))
               for ex in ("serial", "processes", "dask")}
    ref = without_time(results["serial"])
    assert all(r.success for r in results.values())
    peaks = [row["peak_amplitude_m"] for row in ref]
    assert all(p > 0 for p in peaks) and len(set(peaks)) == 6
    for ex in ("processes", "dask"):
        assert without_time(results[ex]) == ref, ex
        assert results[ex].records[0]["curve"] == results["serial"].records[0]["curve"]
    # the CSV holds the same numbers exactly (repr round-trips)
    rows = list(csv.DictReader(csv_lines((tmp_path / "dask" / "study.csv").read_text().splitlines())))
    assert [float(r["peak_amplitude_m"]) for r in rows] == peaks
    assert [r["damper.model"] for r in rows] == ["macroslip"] * 3 + ["point-contact"] * 3
    # the points are those the samples draw (seed 11), joined to each model
    drawn = samples(3, {"damper.mu": uniform(0.2, 0.4), "damper.load.N": lognormal(60.0, 0.5)}, seed=11)
    assert [{k: row[k] for k in ("damper.mu", "damper.load.N")} for row in ref] == drawn * 2


@pytest.mark.skipif(not Path("/proc/self/maps").exists(), reason="reads /proc/self/maps (Linux)")
def test_workers_run_blas_on_one_thread(tmp_path):
    """Two workers on two cores: each worker's OpenBLAS on one thread (oversubscription otherwise)."""
    result = run_study(Study(openblas_threads, grid({"i": [0, 1, 2, 3]})), tmp_path, executor="processes", workers=2,
                       formats=("csv",))
    assert result.success
    assert {r["peak_omega_rad_s"] for r in result.records} == {1.0}  # OPENBLAS_NUM_THREADS in the worker
    threads = {r["peak_amplitude_m"] for r in result.records}
    assert threads in ({1.0}, {None})  # None: no OpenBLAS in this numpy


def test_failed_and_killed_runs_then_resume(tmp_path, monkeypatch):
    """A run that raises is recorded and the others go on; a killed worker process stops the pool
    and keeps every finished run; the rerun computes only what is missing (and the failed run)
    and ends with the table of an uninterrupted run."""
    monkeypatch.setenv(ENV, str(tmp_path))
    study = Study(flaky, grid({"x": [float(i) for i in range(10)]}))
    out = tmp_path / "out"
    (tmp_path / "raise-2.0").touch()
    first = run_study(study, out, executor="serial", formats=("csv",))
    assert calls(tmp_path) == [float(i) for i in range(10)]  # the failure stopped nothing
    assert not first.success and first.complete
    assert first.records[2]["message"] == "RuntimeError: injected failure at x = 2.0"
    assert sum(not r["success"] for r in first.records) == 1
    assert (out / "study.csv").exists()
    # the failure is gone; a worker process now dies at x = 6 (after 7 runs submitted)
    (tmp_path / "raise-2.0").unlink()
    (tmp_path / "kill-6.0").touch()
    (out / "runs.jsonl").write_text("".join(json.dumps(r) + "\n" for r in first.records[:5])
                                    + '{"run": 6, "id": "cut sh')  # a record cut short by a crash
    (tmp_path / "calls.log").unlink()
    second = run_study(study, out, executor="processes", workers=2, formats=("csv",))
    assert not second.complete and second.lost and "BrokenProcessPool" in second.lost[0][1]
    assert "run the study again" in second.message
    assert second.reused == 4  # runs 1, 2, 4, 5: the failed run 3 is retried
    assert not (out / "study.csv").exists() and (out / "study.partial.csv").exists()
    kept = read_records(out / "runs.jsonl")
    assert all(r["success"] for r in kept.values())
    partial = list(csv.DictReader(csv_lines((out / "study.partial.csv").read_text().splitlines())))
    assert sorted(int(r["run"]) for r in partial) == sorted(r["run"] for r in kept.values())
    assert not {0.0, 1.0, 3.0, 4.0} & set(calls(tmp_path)) and 2.0 in calls(tmp_path)  # 3 retried, no other
    # resume: only the runs without a record are computed
    (tmp_path / "kill-6.0").unlink()
    (tmp_path / "calls.log").unlink()
    third = run_study(study, out, executor="processes", workers=2, formats=("csv",))
    done = {r["params"]["x"] for r in kept.values()}
    assert sorted(calls(tmp_path)) == sorted(set(float(i) for i in range(10)) - done)
    assert third.success and third.reused == len(done)
    clean = run_study(study, tmp_path / "clean", executor="serial", formats=("csv",))
    assert without_time(third) == without_time(clean)
    assert [r["curve"] for r in third.records] == [r["curve"] for r in clean.records]
    assert len(read_records(out / "runs.jsonl")) == 10 and (out / "study.csv").exists()


def test_a_new_version_recomputes(tmp_path, monkeypatch):
    monkeypatch.setenv(ENV, str(tmp_path))
    study = Study(flaky, grid({"x": [1.0, 2.0]}))
    run_study(study, tmp_path / "o", executor="serial", formats=("csv",))
    assert run_study(study, tmp_path / "o", executor="serial", formats=("csv",)).reused == 2
    monkeypatch.setattr("contact_models.__version__", "999")
    assert run_study(study, tmp_path / "o", executor="serial", formats=("csv",)).reused == 0


def test_dask_missing_and_bad_arguments(tmp_path, monkeypatch):
    study = Study(flaky, grid({"x": [1.0]}))
    monkeypatch.setitem(sys.modules, "distributed", None)  # as if not installed
    with pytest.raises(ImportError, match=r'pip install "frictiondamp\[dask\]"'):
        run_study(study, tmp_path, executor="dask")
    assert "frictiondamp[dask]" in DASK_MISSING
    with pytest.raises(ValueError, match="executor="):
        run_study(study, tmp_path, executor="threads")
    with pytest.raises(ValueError, match="workers=0"):
        run_study(study, tmp_path, workers=0)
    with pytest.raises(ValueError, match="same parameters"):
        Study(flaky, [{"x": 1.0}, {"y": 2.0}])


def test_invalid_study_tables_name_the_key(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(SCENE + '[study]\nn = 3\n[study.grid]\n"damper.muu" = [0.1]\n[study.samples]\n'
                    '"damper.k" = {distribution = "normal", mean = 1.0}\n')
    with pytest.raises(SceneError) as err:
        Study.from_scene(path)
    text = str(err.value)
    assert '"damper.muu" is not a scene key' in text and "takes exactly mean, std" in text
    path.write_text(SCENE + '[study.grid]\n"damper.mu" = [-0.1, 0.2]\n')
    with pytest.raises(SceneError, match=r"run 1 \(damper.mu = -0.1\).*damper.mu = -0.1"):
        Study.from_scene(path)
    path.write_text(SCENE.replace('model = "macroslip"', 'model = ["macroslip", "two-region"]')
                    + '[study.grid]\n"damper.mu" = [0.2]\n')
    with pytest.raises(SceneError, match="one computation"):
        Study.from_scene(path)


@pytest.mark.parametrize("sig, executor, code, said", [
    (signal.SIGTERM, "serial", 143, "terminated (SIGTERM)"),
    (signal.SIGINT, "processes", 130, "interrupted"),
])
def test_cli_study_signal_keeps_finished_runs_and_resumes(tmp_path, sig, executor, code, said):
    """SIGTERM ends a study with the message of Ctrl-C (exit 143, Ctrl-C 130), the worker processes
    stopped; the rerun computes only the rest."""
    scene = tmp_path / "chart.toml"
    loads = ", ".join(repr(float(v)) for v in np.geomspace(20.0, 400.0, 6))
    scene.write_text(SCENE.replace('model = "macroslip"', 'model = "two-region"')
                     .replace('tol = "fast"\nmax_step = 0.095', 'tol = "default"')
                     + f'[study]\nexecutor = "{executor}"\nworkers = 2\n[study.grid]\n"damper.load.N" = [{loads}]\n')
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "hbm", "run", str(scene), "--out", str(out), "--quiet"]
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env, text=True)
    log = out / "runs.jsonl"
    try:
        t0 = time.monotonic()
        while time.monotonic() - t0 < 60 and not (log.exists() and log.read_text().count("\n") >= 2):
            assert proc.poll() is None, proc.stderr.read()
            time.sleep(0.02)
        proc.send_signal(sig)
        _, err = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == code, err
    kept = read_records(log)
    assert 2 <= len(kept) < 6 and f"{said}: kept {len(kept)} finished runs" in err
    assert len(list(csv.reader(csv_lines((out / "study.partial.csv").read_text().splitlines())))) == len(kept) + 1
    if sig == signal.SIGINT:
        return
    done = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=120)
    assert done.returncode == 0, done.stderr
    assert f"{6 - len(kept)} computed now, {len(kept)} found in the folder" in done.stdout
    assert len(list(csv.reader(csv_lines((out / "study.csv").read_text().splitlines())))) == 7


def test_cli_scene_sigterm_says_what_was_kept(tmp_path):
    """A plain scene: SIGTERM keeps the partial CSV and says so, as Ctrl-C does (exit 143)."""
    scene = tmp_path / "long.toml"
    scene.write_text(SCENE.replace('tol = "fast"\nmax_step = 0.095', "max_step = 0.0005"))
    out = tmp_path / "out"
    proc = subprocess.Popen([sys.executable, "-m", "hbm", "run", str(scene), "--out", str(out), "--quiet"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env={**os.environ, "PYTHONPATH": str(ROOT)})
    partial = out / "frf.partial.csv"
    try:
        t0 = time.monotonic()
        while time.monotonic() - t0 < 60 and not (partial.exists() and partial.read_text().count("\n") > 20):
            assert proc.poll() is None, proc.stderr.read()
            time.sleep(0.02)
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 143
    rows = len(list(csv_lines(partial.read_text().splitlines()))) - 1  # not the names nor the "#" lines
    assert f"terminated (SIGTERM): kept {rows} finished points; files: {partial}" in err


def test_cli_refuses_workers_without_a_study(tmp_path, capsys):
    scene = tmp_path / "plain.toml"
    scene.write_text(SCENE)
    assert main(["run", str(scene), "--workers", "2"]) == 2
    assert "need a [study] table" in capsys.readouterr().err


@pytest.mark.parametrize("workers", ["0", "-3", "x", "1.5"])
def test_cli_refuses_workers_that_are_no_count_by_name_even_with_check(tmp_path, capsys, workers):
    """--workers 0 passed --check (exit code 0) and failed a run as a computation; "x" named argparse's int."""
    scene = tmp_path / "plain.toml"
    scene.write_text(SCENE)
    with pytest.raises(SystemExit) as stop:
        main(["run", str(scene), "--check", "--workers", workers])
    assert stop.value.code == 2
    assert f"argument --workers: must be an integer >= 1 (processes), got --workers {workers}" in capsys.readouterr().err


@pytest.mark.parametrize("module", ["hbm.study", "hbm.designs", "hbm.study.figures", "hbm.study.runs",
                                    "hbm.study.store", "hbm.scenes.validation"])
def test_docstring_examples(module, tmp_path, monkeypatch):
    import doctest
    import importlib

    monkeypatch.chdir(tmp_path)
    result = doctest.testmod(importlib.import_module(module))
    assert result.attempted > 0 and result.failed == 0


def test_amplitude_sweep_study_records_the_largest_F_c(tmp_path):
    """Each run of an amplitude-sweep scene is a table of F_s, F_c; its "peak" is the largest F_c,
    checked against the element evaluated directly."""
    from contact_models import Bar, TwoRegionMicroslip, UniformLoad

    path = tmp_path / "amp.toml"
    path.write_text(SCENE.split("[blade]")[0] + SCENE.split("force = 8.0\n")[1].split("[sweep]")[0]
                    .replace('"macroslip"', '"two-region"')
                    + '[sweep]\nkind = "amplitude"\nomega = [0.3]\nunit = "omega_c"\namplitude = [0.5, 50.0]\n'
                      'points = 40\n[study.grid]\n"damper.load.N" = [50.0, 200.0]\n')
    result = run_study(Study.from_scene(path), tmp_path / "out", executor="serial", formats=("csv",))
    assert result.success
    for rec in result.records:
        N = rec["params"]["damper.load.N"]
        el = TwoRegionMicroslip(Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3),
                                UniformLoad(N=N))
        w = 0.3 * el.bar.omega_c
        a = np.geomspace(0.5, 50.0, 40) * 0.3 * N / (8.0e8 * 0.05)  # in a_min = mu N / (k L)
        fs, fc = el.fourier(a, w)
        Fc = fc / (el.stuck_stiffness(0.0) * a)
        i = int(np.argmax(Fc))
        assert rec["peak_omega_rad_s"] == w and rec["peak_amplitude_m"] == pytest.approx(a[i], rel=1e-12)
        assert max(rec["curve"]["F_c"][0]) == pytest.approx(Fc[i], rel=1e-6)


def test_progress_line_counts_runs_with_an_eta():
    import io

    from hbm.cli.progress import ProgressLine
    from hbm.study import StudyProgress

    p = StudyProgress(points=3, runs=10, failed=1, reused=1, elapsed=6.0)
    assert p.eta == pytest.approx(6.0 * 7 / 2)  # 2 runs computed in 6 s, 7 to go
    assert p.line() == "run 3/10 (1 failed, 1 reused), 6.0 s, about 21 s left"
    assert StudyProgress(points=4, runs=10, failed=0, reused=4, elapsed=0.5).eta is None  # nothing computed yet
    term = io.StringIO()
    line = ProgressLine(term, enabled=True)
    line(p)
    assert term.getvalue() == "\r" + p.line() and line.points == 3


@pytest.mark.slow
def test_a_running_cluster_by_its_address(tmp_path):
    """scheduler=ADDRESS uses a running Dask cluster (here a LocalCluster started by the test)."""
    from distributed import LocalCluster

    path = tmp_path / "s.toml"
    path.write_text(SCENE + STUDY)
    study = Study.from_scene(path)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster:
        remote = run_study(study, tmp_path / "remote", scheduler=cluster.scheduler_address, formats=("csv",))
    assert remote.summary["executor"] == "dask" and remote.summary["scheduler"] == cluster.scheduler_address
    serial = run_study(study, tmp_path / "serial", executor="serial", formats=("csv",))
    assert remote.success and without_time(remote) == without_time(serial)


def test_docs_list_the_study_keys_as_the_schema_has_them():
    """The [study] tables of docs/studies.md and docs/scenes.md are the schema's rows (generated)."""
    from hbm.scenes import REQUIRED, schema
    from hbm.scenes.checks import show

    for key, spec in schema()["study"].items():
        default = "required" if spec.default is REQUIRED else "-" if spec.default is None else f"`{show(spec.default)}`"
        row = f"| `study.{key}` | {default} | {spec.doc} |"
        for doc in ("studies.md", "scenes.md"):
            assert row in (ROOT / "docs" / doc).read_text(), (doc, row)


def test_runs_warnings_are_recorded_and_said_once_naming_the_worst(tmp_path, capfd):
    study = Study(loose, grid({"x": [0.5, 2.0, 3.0, 1.5]}))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = run_study(study, tmp_path, executor="processes", workers=2, formats=("csv", "json"))
    said = [str(w.message) for w in caught if issubclass(w.category, AccuracyWarning)]
    assert len(said) == 1  # one for the study, not one per run
    assert said[0].startswith("run_study: 3 of 4 runs warned")
    assert "the worst, run 3 (x = 3.0), peak_error_rel 0.03: estimated error 0.03 > tol 0.001" in said[0]
    assert "AccuracyWarning" not in capfd.readouterr().err  # the workers showed nothing
    assert [r["warning"] for r in result.records] == [None, "estimated error 0.02 > tol 0.001",
                                                      "estimated error 0.03 > tol 0.001",
                                                      "estimated error 0.015 > tol 0.001"]
    assert result.records[2]["message"] == "estimated error 0.03 > tol 0.001"  # the table says it too
    summary = json.loads((tmp_path / "study.json").read_text())
    assert summary["warned"] == 3 and summary["worst_warning"]["run"] == 3
    with warnings.catch_warnings(record=True) as caught:  # a resume reuses the records and says the same
        warnings.simplefilter("always")
        again = run_study(study, tmp_path, executor="serial", formats=("csv",))
    assert again.reused == 4 and [str(w.message) for w in caught] == said


def test_cli_study_prints_one_warning_line_after_its_summary(tmp_path, capsys):
    path = single_mode_scene(tmp_path)  # tol 1e-2: the single-mode bar's model error (0.1) is over it
    path.write_text(path.read_text() + '[study]\nexecutor = "serial"\n[study.grid]\n"damper.load.N" = [60.0, 120.0]\n')
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 0
    out, err = capsys.readouterr()
    lines = out.strip().splitlines()
    warned = [line for line in lines if line.startswith("warning:")]
    assert len(warned) == 1 and warned[0] == lines[-1]
    assert warned[0].startswith("warning: run_study: 2 of 2 runs warned") and warned[0].endswith("(AccuracyWarning)")
    assert "Warning:" not in err and ".py:" not in err
