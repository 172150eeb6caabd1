"""Faults of studies met by users, each run for real (processes, signals, sockets): a second study
into a busy folder, a killed parent, a damaged runs.jsonl, a huge study, a scheduler address that
is not Dask's, two quick Ctrl-C."""

import json
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from hbm.study import MAX_RUNS, Points, Study, grid, read_records, run_study, samples, uniform

ROOT = Path(__file__).resolve().parent.parent
ENV = {**os.environ, "PYTHONPATH": str(ROOT)}

#: A scene whose runs take some 25 ms each (macroslip, "fast"); the study samples mu.
SCENE = """title = "a fault study"
[blade]
mass = 0.08771473371579717
stiffness = 1.0e8
damping_ratio = 2.0e-3
force = 8.0
[damper]
model = "macroslip"
E = 2.0e11
rho = 7850.0
A = 1.0e-5
L = 0.05
k = 8.0e8
beta = 4.0e7
mu = 0.3
[damper.load]
kind = "uniform"
N = 100.0
[effects]
inertia = "on"
[sweep]
omega = [0.24, 0.33]
unit = "omega_c"
accuracy = "fast"
[study]
n = {n}
seed = 1
[study.samples]
"damper.mu" = {{distribution = "uniform", low = 0.2, high = 0.4}}
"""


def scene(tmp_path, n=2000, name="s.toml"):
    path = tmp_path / name
    path.write_text(SCENE.format(n=n))
    return path


def hbm_run(path, *args, **kw):
    """``python3 -m hbm run PATH ARGS`` in a new session (its own process group), pipes on."""
    return subprocess.Popen([sys.executable, "-m", "hbm", "run", str(path), "--quiet", *map(str, args)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=ENV,
                            start_new_session=True, **kw)


def finished_runs(folder):
    log = Path(folder) / "runs.jsonl"
    return log.read_bytes().count(b"\n") if log.exists() else 0


def wait_for_runs(proc, folder, count=1, timeout=60.0):
    t0 = time.monotonic()
    while finished_runs(folder) < count:
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() - t0 < timeout, "no run finished"
        time.sleep(0.01)


def running(pid):
    """Whether the process ``pid`` is running (a zombie, dead but not reaped, is not)."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except (FileNotFoundError, ProcessLookupError):
        return False
    return stat.rsplit(")", 1)[1].split()[0] not in ("Z", "X")


def descendants(pid):
    """The processes below ``pid`` (children, their children, ...), from /proc."""
    parents = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                stat = (entry / "stat").read_text()
            except OSError:
                continue
            parents[int(entry.name)] = int(stat.rsplit(")", 1)[1].split()[1])
    found, todo = [], [pid]
    while todo:
        p = todo.pop()
        kids = [c for c, pp in parents.items() if pp == p]
        found += kids
        todo += kids
    return found


def end(proc):
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()


needs_proc = pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs /proc (Linux)")


# 4. a study larger than MAX_RUNS; --check independent of the number of runs -------------------

def test_check_costs_the_same_for_any_number_of_runs_and_a_study_over_max_runs_is_refused(tmp_path):
    """--check of a study of MAX_RUNS runs takes the time of one of 10 runs (it made every point
    and validated its scene: over 2 minutes for 1e6); study.n = 1e11 is refused at once by its
    key and value (it was numpy's _ArrayMemoryError), nothing written."""
    times = {}
    for n in (10, MAX_RUNS):
        t0 = time.monotonic()
        done = subprocess.run([sys.executable, "-m", "hbm", "run", str(scene(tmp_path, n)), "--check"],
                              capture_output=True, text=True, env=ENV, timeout=60)
        times[n] = time.monotonic() - t0
        assert done.returncode == 0, done.stderr
        assert f"a study of {n} run(s) over damper.mu" in done.stdout and "effects of run 1:" in done.stdout
    assert times[MAX_RUNS] < times[10] + 1.0, times
    out = tmp_path / "out"
    for check in ((), ("--check",)):
        t0 = time.monotonic()
        done = subprocess.run([sys.executable, "-m", "hbm", "run", str(scene(tmp_path, 10 ** 11)), "--out", str(out),
                               *check], capture_output=True, text=True, env=ENV, timeout=60)
        assert time.monotonic() - t0 < 10.0
        assert done.returncode == 2 and "Traceback" not in done.stderr, done.stderr
        assert "study.n = 100000000000" in done.stderr and f"MAX_RUNS = {MAX_RUNS}" in done.stderr
        assert not out.exists()


def test_grid_samples_combine_and_study_refuse_more_than_max_runs_before_making_a_point():
    t0 = time.monotonic()
    with pytest.raises(ValueError, match=r"grid: a \(1001 values\) x b \(1000 values\) = 1001000 runs"):
        grid({"a": list(range(1001)), "b": list(range(1000))})
    with pytest.raises(ValueError, match="samples: n = 100000000000 runs"):
        samples(10 ** 11, {"u": uniform(0.0, 1.0)}, seed=1)
    pts = samples(MAX_RUNS, {"u": uniform(0.0, 1.0)}, seed=1)  # drawn, not made into dicts
    assert len(pts) == MAX_RUNS and pts[-1] == {"u": pts[MAX_RUNS - 1]["u"]}
    with pytest.raises(ValueError, match=f"points = {MAX_RUNS + 1} runs"):
        Study(lambda p: {}, Points(MAX_RUNS + 1, lambda i: {"u": 0.5}))
    assert time.monotonic() - t0 < 5.0
