"""The progress line off a terminal: plain lines (no carriage return) every ``PLAIN_INTERVAL``
seconds when stderr is a pipe or a file, nothing under ``--quiet``."""

import io
import subprocess
import sys
import textwrap
from pathlib import Path

from hbm.cli import progress as progress_module
from hbm.cli.progress import PLAIN_INTERVAL, ProgressLine
from hbm.study import StudyProgress

from conftest import MACROSLIP_BLADE  # the blade and Jenkins damper these studies share

ROOT = Path(__file__).resolve().parent.parent

SCENE = """title = "a small study"
""" + MACROSLIP_BLADE + """[sweep]
omega = [0.24, 0.33]
unit = "omega_c"
tol = "fast"
max_step = 0.095
[study]
n = 3
seed = 11
[study.samples]
"damper.mu" = {distribution = "uniform", low = 0.2, high = 0.4}
"""


class Clock:
    def __init__(self):
        self.now = 100.0

    def __call__(self):
        return self.now


def _run(points, elapsed):
    return StudyProgress(points=points, runs=10, failed=0, reused=0, elapsed=elapsed)


def test_plain_progress_off_a_terminal_writes_whole_lines_every_plain_interval():
    assert 1.0 <= PLAIN_INTERVAL <= 10.0
    stream, clock = io.StringIO(), Clock()
    assert not stream.isatty()
    line = ProgressLine(stream, enabled=True, plain=True, clock=clock)
    line(_run(1, 0.5))
    assert stream.getvalue() == ""  # not yet PLAIN_INTERVAL s into the run
    clock.now += PLAIN_INTERVAL - 0.5  # PLAIN_INTERVAL s since the run started
    line(_run(2, PLAIN_INTERVAL))
    assert stream.getvalue() == _run(2, PLAIN_INTERVAL).line() + "\n"
    clock.now += PLAIN_INTERVAL / 2
    line(_run(3, 1.5 * PLAIN_INTERVAL))
    assert stream.getvalue().count("\n") == 1  # at most one line per interval
    clock.now += PLAIN_INTERVAL / 2
    line(_run(4, 2 * PLAIN_INTERVAL))
    text = stream.getvalue()
    assert text.count("\n") == 2 and "\r" not in text and text.endswith(_run(4, 2 * PLAIN_INTERVAL).line() + "\n")
    line.clear()  # nothing to erase off a terminal
    assert stream.getvalue() == text and line.points == 4


def test_plain_progress_is_silent_when_disabled_by_quiet():
    stream, clock = io.StringIO(), Clock()
    line = ProgressLine(stream, enabled=False, plain=True, clock=clock)
    for k in range(1, 5):
        clock.now += PLAIN_INTERVAL
        line(_run(k, k * PLAIN_INTERVAL))
    line.clear()
    assert stream.getvalue() == "" and line.points == 4


def _cli(tmp_path, *extra):
    """``python3 -m hbm run`` of a 3-run study, stderr a pipe, with PLAIN_INTERVAL = 0 (a line per run)."""
    path = tmp_path / "study.toml"
    path.write_text(SCENE)
    code = textwrap.dedent(f"""
        import sys
        import hbm.cli.progress
        hbm.cli.progress.PLAIN_INTERVAL = 0.0
        from hbm.cli.main import main
        sys.exit(main(sys.argv[1:]))
    """)
    return subprocess.run([sys.executable, "-c", code, "run", str(path), "--out", str(tmp_path / "out"),
                           "--executor", "serial", *extra], capture_output=True, text=True, timeout=300,
                          cwd=ROOT)


def test_cli_prints_plain_progress_lines_when_stderr_is_a_pipe(tmp_path):
    assert progress_module.PLAIN_INTERVAL == PLAIN_INTERVAL
    proc = _cli(tmp_path)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stderr.splitlines()
    assert "\r" not in proc.stderr
    assert [ln.split(",")[0] for ln in lines if ln.startswith("run ")] == ["run 1/3", "run 2/3", "run 3/3"]


def test_cli_prints_no_progress_under_quiet_when_stderr_is_a_pipe(tmp_path):
    proc = _cli(tmp_path, "--quiet")
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == ""


def test_ticking_draws_a_silent_computation_until_it_returns(monkeypatch):
    import threading
    import time

    from hbm.cli.progress import Elapsed, ticking

    monkeypatch.setattr(progress_module, "TICK", 0.02)
    monkeypatch.setattr(progress_module, "PLAIN_INTERVAL", 0.05)
    stream = io.StringIO()
    line = ProgressLine(stream, enabled=True, plain=True)

    def compute(state):
        for i in range(1, 4):
            state.points, state.omega = i, 100.0 * i
            time.sleep(0.1)
        return "answer"

    assert ticking(line, "the job", compute) == "answer"
    written = stream.getvalue()
    lines = written.splitlines()
    assert len(lines) >= 3 and "\r" not in written  # a plain line every PLAIN_INTERVAL s, off a terminal
    assert all(text.startswith("the job: ") and text.endswith(" s") for text in lines)
    assert lines[-1].startswith("the job: 3 points, omega = 300 rad/s")
    assert not any(t.name == "progress" for t in threading.enumerate())  # the timer ended with the computation
    time.sleep(0.1)
    assert stream.getvalue() == written  # and draws nothing after
    assert Elapsed("x", 0.4).line() == "x: 0 s"
