"""Scenes (docs/scenes.md): effect selection changes what is computed, streaming, the command line.

Malformed scenes are in ``test_scenes_invalid.py``; the example scenes in ``test_scenes_examples.py``.
"""

import csv
import json
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from contact_models import (Bar, ContactElement, QuasiStatic, ThreeRegionMicroslip, TwoRegionMicroslip,
                            UniformLoad)
from contact_models.quasi_static import StuckContact
from hbm import Blade, Steps, frequency_response
from hbm.cli.main import main
from hbm.cli.progress import ProgressLine
from hbm.balance.residual import HarmonicBalance, linear_response
from hbm.scenes import EFFECTS, Progress, columns, load_scene, plan_scene, run_scene, scene_from_dict, summary_lines
from hbm.output import csv_lines

from conftest import BAR, scene_data

SCENES = Path(__file__).resolve().parent.parent / "examples" / "scenes"
ROOT = SCENES.parent.parent
DEFAULT = SCENES / "default_microslip_frf.toml"
LOW = SCENES / "quasi_static_low_frequency.toml"
#: Default-case peak (python3 -m hbm; tests/test_hbm_examples.py).
DEFAULT_PEAK = 1.5119614110e-06


def scene_dict(**changes):
    """The default scene as a dict, with ``{"table.key": value}`` changes (None deletes)."""
    return scene_data(DEFAULT, **changes)


def effect(run, name):
    return next(e for e in run.effects if e.name == name)


class AlphaSpy:
    """Records every omega at which the bar's dynamic coefficient alpha^2 = rho omega^2/E is evaluated
    (gamma^2, K*(omega) and every region solution go through it)."""

    def __init__(self, bar):
        self.omegas = []
        original = bar.alpha2

        def alpha2(omega):
            self.omegas.extend(np.atleast_1d(np.asarray(omega, dtype=float)).tolist())
            return original(omega)

        bar.alpha2 = alpha2


# ---------------------------------------------------------------------- QuasiStatic element
def test_quasi_static_element_evaluates_the_wrapped_element_at_omega_zero_only():
    bar = Bar(**BAR)
    spy = AlphaSpy(bar)
    qs = QuasiStatic(TwoRegionMicroslip(bar, UniformLoad(N=100.0)))
    ref = TwoRegionMicroslip(Bar(**BAR), UniformLoad(N=100.0))
    a = np.array([0.5, 1.5, 3.0]) * 7.5e-7
    for w in (0.0, 1e4, 4e4):
        assert np.array_equal(qs.fourier(a, w)[0], ref.fourier(a, 0.0)[0])
        assert np.array_equal(qs.fourier_derivatives(a, w)[3], ref.fourier_derivatives(a, 0.0)[3])
        assert qs.stuck_stiffness(w) == ref.stuck_stiffness(0.0)
        assert qs.slip_amplitude(w) == ref.slip_amplitude(0.0)
        assert np.array_equal(qs.hysteresis(a[1], w, n=41)[1], ref.hysteresis(a[1], 0.0, n=41)[1])
    assert qs.frequency_dependent is False and qs.calls > 0
    assert spy.omegas and set(spy.omegas) == {0.0}


def test_inertia_off_scene_gives_the_api_frf_and_traces_without_the_dynamic_path(tmp_path):
    """The trace evaluates the damper at omega = 0 only (one loading path); the estimate alone evaluates the
    dynamic bar, at the curve's own points, to state what the inertia left out costs."""
    scene = scene_from_dict(scene_dict(**{"effects.inertia": "off", "sweep.max_step": 0.1}), "off.toml")
    plan = plan_scene(scene)
    run = plan.runs[0]
    assert isinstance(run.element, QuasiStatic)
    assert not effect(run, "damper inertia").simulated
    spy = AlphaSpy(run.element.element.bar)  # from here on, every evaluation of the damper is recorded
    result = run_scene(scene, tmp_path, plan=plan)
    assert result.success
    points = set(result.runs[0].frf.omega.tolist())
    assert 0.0 in spy.omegas and set(spy.omegas) - {0.0} <= points  # dynamic only where the estimate reads
    assert set(run.element.element._paths) - {0.0} <= points  # the trace's one loading path, at omega = 0
    # the same FRF as the Python API with the quasi-static element
    api = frequency_response(plan.blade, QuasiStatic(TwoRegionMicroslip(Bar(**BAR), UniformLoad(N=100.0))),
                             omega_range=run.omega, harmonics=1, steps=Steps(max_step=0.1))
    frf = result.runs[0].frf
    assert np.array_equal(frf.omega, api.omega) and np.array_equal(frf.amplitude, api.amplitude)
    assert result.summary["runs"][0]["quasi_static_calls"] == run.element.calls > 0


# ---------------------------------------------------------------------- inertia auto
def _solve_full(hb, y, fixed):
    """Newton on the full (dynamic) balance from y = (x_c, x_s, omega) with omega ("omega") or the
    amplitude ("amplitude") held; returns the solution or None."""
    y = np.array(y, dtype=float)
    a2 = y[0] ** 2 + y[1] ** 2
    for _ in range(30):
        R, J = hb.physical(y)
        if fixed == "omega":
            dy = np.append(np.linalg.solve(J[:, :2], -R), 0.0)
        else:
            A = np.vstack([J, [2 * y[0], 2 * y[1], 0.0]])
            dy = np.linalg.solve(A, -np.append(R, y[0] ** 2 + y[1] ** 2 - a2))
        y = y + dy
        if abs(dy[0]) + abs(dy[1]) <= 1e-13 * math.sqrt(a2) and abs(dy[2]) <= 1e-13 * y[2]:
            return y
    return None


def test_inertia_auto_drops_inertia_far_below_omega_c_and_the_frf_moves_less_than_the_tolerance(tmp_path):
    scene = load_scene(LOW)
    tol = scene.effects["tolerance"]
    plan = plan_scene(scene)
    run = plan.runs[0]
    inertia = effect(run, "damper inertia")
    assert not inertia.simulated and "0.000364" in inertia.reason and "0.001" in inertia.reason
    assert isinstance(run.element, QuasiStatic)
    qs = run_scene(scene, tmp_path, plan=plan).runs[0].frf
    full_el = TwoRegionMicroslip(Bar(**BAR), UniformLoad(N=100.0))
    full = frequency_response(plan.blade, full_el, omega_range=run.omega)
    # peak: measured 2.1e-4 in amplitude, 4.4e-5 in omega
    pq, pf = qs.peak(), full.peak()
    assert abs(pq.amplitude / pf.amplitude - 1) < tol and abs(pq.omega / pf.omega - 1) < tol
    # pointwise: each quasi-static point lies within tol (relative, in amplitude or in omega) of the
    # full FRF: d_a = amplitude change at equal omega, d_w = omega change at equal amplitude.
    hb = HarmonicBalance(plan.blade, full_el, rtol=1e-9)
    dist = []
    for y in zip(qs.x_c[::4], qs.x_s[::4], qs.omega[::4]):
        a = math.hypot(y[0], y[1])
        at_w = _solve_full(hb, y, "omega")
        at_a = _solve_full(hb, y, "amplitude")
        d_a = abs(math.hypot(at_w[0], at_w[1]) / a - 1) if at_w is not None else math.inf
        d_w = abs(at_a[2] / y[2] - 1) if at_a is not None else math.inf
        dist.append(min(d_a, d_w))
    assert max(dist) < tol  # measured 2.1e-4 (the peak); the flanks move by < 5e-5 in omega


def test_inertia_auto_keeps_inertia_near_0_3_omega_c():
    plan = plan_scene(scene_from_dict(scene_dict(**{"effects.inertia": "auto"}), "auto.toml"))
    run = plan.runs[0]
    inertia = effect(run, "damper inertia")
    assert inertia.simulated and "0.084" in inertia.reason
    assert isinstance(run.element, TwoRegionMicroslip)
    # even with a loose tolerance: 8.4 % is above 1e-2
    plan = plan_scene(scene_from_dict(scene_dict(**{"effects.inertia": "auto", "effects.tolerance": 1e-2}), "a.toml"))
    assert effect(plan.runs[0], "damper inertia").simulated


# ---------------------------------------------------------------------- model auto
@pytest.mark.parametrize("load, expected", [
    ({"kind": "uniform", "N": 100.0}, TwoRegionMicroslip),
    ({"kind": "quadratic", "N": 100.0, "ratio": 0.9}, TwoRegionMicroslip),  # convex: hump-shaped
    ({"kind": "quadratic", "N": 100.0, "ratio": 12.0}, ThreeRegionMicroslip),  # concave
])
def test_model_auto_picks_the_topology_from_where_slip_starts(load, expected):
    data = scene_dict(**{"damper.model": "auto", "effects.phase_differences": "off"})  # the single-mode choice
    data["damper"]["load"] = load
    run = plan_scene(scene_from_dict(data, "auto.toml")).runs[0]
    assert type(run.element) is expected
    onset = effect(run, "interior slip onset (three regions)")
    assert onset.simulated is (expected is ThreeRegionMicroslip)
    assert ("slip starts inside the bar" if onset.simulated else "slip starts at the excited end") in onset.reason
    if onset.simulated:
        assert "x*/L = 0.511" in onset.reason


def test_model_auto_without_inertia_decides_at_omega_zero():
    data = scene_dict(**{"damper.model": "auto", "effects.inertia": "off"})
    data["damper"]["load"] = {"kind": "quadratic", "N": 100.0, "ratio": 12.0}
    run = plan_scene(scene_from_dict(data, "auto.toml")).runs[0]
    assert isinstance(run.element, QuasiStatic) and isinstance(run.element.element, ThreeRegionMicroslip)
    assert "at 0 rad/s" in effect(run, "interior slip onset (three regions)").reason


# ---------------------------------------------------------------------- other effects
def test_a_damper_that_never_reaches_its_slip_amplitude_is_a_linear_spring(tmp_path):
    # a_min = mu N/(k L) = 2.25e-5 m at N = 3000 N, above the stuck peak 1.71e-5 m
    scene = scene_from_dict(scene_dict(**{"damper.load.N": 3000.0, "sweep.max_step": 0.1}), "stuck.toml")
    plan = plan_scene(scene)
    run = plan.runs[0]
    slip = effect(run, "damper slip")
    assert not slip.simulated and "damper stayed stuck: linear spring" in slip.reason
    assert isinstance(run.element, StuckContact)
    micro = run.element.element
    paths_before = len(micro._paths)
    result = run_scene(scene, tmp_path, plan=plan)
    frf = result.runs[0].frf
    assert result.success and frf.nfev == 0 and len(micro._paths) == paths_before  # no loading path built
    # the same points as with the microslip element itself, and the linear closed form
    ref = frequency_response(plan.blade, TwoRegionMicroslip(Bar(**BAR), UniformLoad(N=3000.0)),
                             omega_range=run.omega, harmonics=1, steps=Steps(max_step=0.1))
    assert np.array_equal(frf.amplitude, ref.amplitude)
    exact = np.abs(linear_response(plan.blade, frf.omega, lambda w: Bar(**BAR).stuck_stiffness(w)))
    assert np.max(np.abs(frf.amplitude / exact - 1)) < 1e-8
    assert "linear spring" in json.loads((tmp_path / "summary.json").read_text())["runs"][0]["effects"][3]["reason"]


def test_strain_hardening_off_sets_beta_to_zero():
    run = plan_scene(scene_from_dict(scene_dict(**{"effects.strain_hardening": False}), "b.toml")).runs[0]
    assert run.element.bar.beta == 0.0
    sh = effect(run, "strain-hardening spring")
    assert not sh.simulated and "beta = 0" in sh.reason and "4e+07" in sh.reason
    # the key beta is then not needed
    plan_scene(scene_from_dict(scene_dict(**{"effects.strain_hardening": False, "damper.beta": None}), "b.toml"))


def test_summary_lists_every_effect_with_a_reason(tmp_path):
    scene = scene_from_dict(scene_dict(**{"sweep.max_step": 0.1}), tmp_path / "s.toml")
    result = run_scene(scene, tmp_path / "out")
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["status"] == "success"
    run = summary["runs"][0]
    names = [e["effect"] for e in run["effects"]]
    assert names == [e.name for e in EFFECTS]  # every registered effect, in order, decided for the bar
    assert {"strain-hardening spring", "damper inertia", "interior slip onset (three regions)", "damper slip",
            "higher harmonics"} <= set(names)
    assert all(isinstance(e["simulated"], bool) and e["reason"] for e in run["effects"])
    assert run["peak"]["amplitude_m"] == pytest.approx(DEFAULT_PEAK, rel=1e-6)
    assert run["counters"]["nsteps"] == run["points"] - 1 and run["time_s"] > 0
    text = "\n".join(summary_lines(result))
    assert "damper inertia: simulated" in text and "higher harmonics: not simulated" in text


# ---------------------------------------------------------------------- streaming
class Cubic(ContactElement):
    """A hardening spring f = k a sin + 3/4 k3 a^3 (Duffing): its FRF folds twice."""

    frequency_dependent = False

    def _fourier_derivatives(self, a, omega, rtol):
        z = np.zeros_like(a)
        return 0.1 * a + 0.75 * a**3, z, 0.1 + 2.25 * a**2, z.copy()

    def _stuck_stiffness(self, omega):
        return 0.1

    def _slip_amplitude(self, omega):
        return 0.0

    def _hysteresis(self, a, omega, n):  # elastic: the loop closes on the curve f = 0.1 x + x^3
        x = a * np.sin(np.linspace(-0.5 * np.pi, 1.5 * np.pi, n))
        return x, 0.1 * x + x**3


@pytest.mark.parametrize("case", ["default", "folds"])
def test_on_point_streams_exactly_the_points_of_the_result(case):
    if case == "default":
        blade = Blade(mass=0.08771473371579717, stiffness=1e8, damping=11.846669318642919, force=8.0)
        el, rng = TwoRegionMicroslip(Bar(**BAR), UniformLoad(N=100.0)), (3.2e4, 4.4e4)
    else:
        blade, el, rng = Blade(mass=1.0, stiffness=1.0, damping=0.02, force=0.05), Cubic(), (0.5, 3.0)
    seen = []
    frf = frequency_response(blade, el, omega_range=rng, steps=Steps(max_step=0.1),
                             callback=lambda p: seen.append((p.omega, p.x_c, p.x_s, p.residual)))
    if case == "folds":
        assert len(frf.folds_omega) == 2
    frf.peak()  # after the run: no more calls
    seen = np.array(seen)
    assert len(seen) == len(frf)
    assert np.array_equal(seen[:, 0], frf.omega) and np.array_equal(seen[:, 1], frf.x_c)
    assert np.array_equal(seen[:, 2], frf.x_s) and np.array_equal(seen[:, 3], frf.residual_norm)


def test_csv_is_renamed_complete_only_after_success(tmp_path):
    scene = scene_from_dict(scene_dict(**{"sweep.max_step": 0.1}), "s.toml")
    rows_during = []

    def progress(p):
        rows_during.append(sum(1 for _ in csv_lines((tmp_path / "frf.partial.csv").open())) - 1)
        assert not (tmp_path / "frf.csv").exists() and not (tmp_path / "summary.json").exists()

    result = run_scene(scene, tmp_path, progress=progress)
    assert rows_during == list(range(1, len(rows_during) + 1))  # every point on disk as it comes
    assert not (tmp_path / "frf.partial.csv").exists()
    rows = list(csv.DictReader(csv_lines((tmp_path / "frf.csv").open())))
    assert len(rows) == result.points == len(result.runs[0].frf)
    assert float(rows[-1]["omega_rad_s"]) == result.runs[0].frf.omega[-1]


def test_killed_run_leaves_a_parseable_csv_of_finished_points(tmp_path):
    out = tmp_path / "out"
    # a long sweep: about 8000 points at this step
    cmd = [sys.executable, "-m", "hbm", "run", str(DEFAULT), "--out", str(out), "--quiet",
           "--set", "sweep.max_step=0.0005", "--set", "output.formats=['csv', 'json']"]
    proc = subprocess.Popen(cmd, cwd=tmp_path, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            env={**os.environ, "PYTHONPATH": str(ROOT)})
    partial = out / "frf.partial.csv"
    try:
        t0 = time.monotonic()
        while time.monotonic() - t0 < 60:
            if partial.exists() and sum(1 for _ in partial.open()) > 40:
                break
            assert proc.poll() is None, proc.stderr.read().decode()
            time.sleep(0.05)
        proc.send_signal(signal.SIGKILL)
        proc.wait(10)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == -signal.SIGKILL
    rows = list(csv.reader(csv_lines(partial.open())))
    assert tuple(rows[0]) == columns(load_scene(DEFAULT)) and len(rows) > 40
    data = np.array([[float(v) for v in r[3:]] for r in rows[1:]])  # every row complete and numeric
    assert all(len(r) == len(rows[0]) for r in rows)
    omega, amp = data[:, 0], data[:, 1]
    assert omega[0] == pytest.approx(0.24 * Bar(**BAR).omega_c, rel=1e-12) and np.all(np.diff(omega) > 0)
    assert np.all(amp > 0)
    assert not (out / "frf.csv").exists() and not (out / "summary.json").exists()  # nothing looks complete


def test_failed_run_exits_1_and_keeps_what_was_computed(tmp_path, capsys):
    scene = tmp_path / "short.toml"
    scene.write_text(DEFAULT.read_text().replace("tol = 0.15 ", "max_steps = 5\ntol = 0.15 "))
    assert main(["run", str(scene), "--out", str(tmp_path / "out"), "--quiet"]) == 1
    out = capsys.readouterr().out
    assert "FAILED" in out and "kept: 6 finished points" in out and "frf.partial.csv" in out
    rows = list(csv.reader(csv_lines((tmp_path / "out" / "frf.partial.csv").open())))
    assert len(rows) == 7
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["status"] == "failed" and "max_steps" in summary["message"]
    assert not (tmp_path / "out" / "frf.csv").exists() and not (tmp_path / "out" / "frf.png").exists()


# ---------------------------------------------------------------------- command line
def test_cli_run_writes_csv_png_json_and_prints_the_summary(tmp_path, capsys):
    assert main(["run", str(DEFAULT), "--out", str(tmp_path), "--set", "sweep.max_step=0.1"]) == 0
    cap = capsys.readouterr()
    assert cap.err == ""  # not a terminal: no progress line
    assert "peak: omega = 38768.306" in cap.out and "damper inertia: simulated" in cap.out
    assert {p.name for p in tmp_path.iterdir()} == {"frf.csv", "frf.png", "summary.json"}
    assert json.loads((tmp_path / "summary.json").read_text())["runs"][0]["peak"]["amplitude_m"] == \
        pytest.approx(DEFAULT_PEAK, rel=1e-6)


def test_cli_check_computes_nothing(tmp_path, capsys):
    assert main(["run", str(DEFAULT), "--check", "--out", str(tmp_path / "o")]) == 0
    assert "is valid" in capsys.readouterr().out and not (tmp_path / "o").exists()


def test_cli_default_job_still_runs_without_arguments(tmp_path, monkeypatch, capsys):
    import hbm.cli.main as cli

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(cli, "DEFAULT_MODEL", "given")  # the path without arguments; the model: test_physical_curve
    assert main([]) == 0
    assert (tmp_path / "frf.csv").exists() and "peak: omega" in capsys.readouterr().out


class FakeTerminal:
    def __init__(self):
        self.text = ""

    def write(self, s):
        self.text += s

    def flush(self):
        pass


def test_progress_line_appears_after_a_second_on_a_terminal_only():
    def p(elapsed, points=3):
        return Progress(1, 2, "two-region", 3.5e4, 0.25, points, elapsed)  # runs numbered from 1

    term = FakeTerminal()
    line = ProgressLine(term, enabled=True)
    line(p(0.5))
    assert term.text == ""  # short sweeps: nothing
    line(p(1.5, 7))
    assert term.text.startswith("\r") and "run 1/2 two-region" in term.text and "(25 %), 7 points" in term.text
    # 1/8 of the scene done in 1.5 s: 7/8 left take 10.5 s
    assert "about 10 s left" in term.text  # 10.5 s, rounded half to even
    line.clear()
    assert term.text.endswith("\r")
    quiet = FakeTerminal()
    line = ProgressLine(quiet, enabled=False)
    line(p(5.0, 9))
    assert quiet.text == "" and line.points == 9
