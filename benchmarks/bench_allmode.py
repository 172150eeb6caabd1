"""What accuracy costs in ``AllModeMicroslip`` against ``NumericalMicroslip``.

Uniform load 100 N on the reference bar of the documentation, omega in {0.2, 0.5} omega_c, a in {1.5, 3, 10} a_min
(a_min of the 200-cell bar, the reference's).  Error: max |F_s - F_s,ref|, |F_c - F_c,ref| in
units of k* a against the stored converged time integration (``docs/data/allmode_reference.csv``:
NumericalMicroslip, 200 cells, 1024 steps per cycle, written by examples/validation_allmode.py).

Time per amplitude point (median of ``REPEATS`` round-robin runs, process CPU seconds):
- all-mode, *cold*: a new element per point (no warm start);
- all-mode, *sweep*: the six points in one ``fourier`` call per frequency (warm starts along a);
- numerical: ``simulate(a, omega)`` per point, timed once per point (it takes seconds).
The ratios are formed from times of this one run.  Run ``python benchmarks/bench_allmode.py``.

``python benchmarks/bench_allmode.py --frf [repeats] [--no-before]``: the default case's FRF
(``hbm.cli.cases``) with the single-mode damper, with ``AllModeMicroslip`` at fixed 16 cells, H = 7,
and choosing its rungs at the FRF's tol 1e-2 and 1e-3, each before (the element choosing per call:
``hbm.frf.RUNGS_ALONG_CURVE = False``) and after (rungs chosen along the curve), round-robin (one
run each per round), wall-clock medians of ``repeats`` (default 3), with the points, the peak, the
largest estimate and the AccuracyWarnings of the last round, and each time as a ratio to the
single-mode one of the same run.  ``--frf-study [tol]``: 50 all-mode FRFs (normal loads 40..300 N)
at ``tol`` (default 1e-2) on two processes.

``python benchmarks/bench_allmode.py --passes [repeats]``: where the all-mode FRF's time goes at tol 1e-3, pass by
pass (each continuation and each curve estimate timed), the first FRF in the process apart from the medians of the next
``repeats`` (docs/performance.md, "The all-mode FRF: where its time goes by pass").

``python benchmarks/bench_allmode.py --peak [repeats]``: the default case's FRF refined where it holds the peak
(``frequency_response(..., model="peak")``) against the single-mode FRF, and the whole job (``python3 -m hbm`` in a
new process) with ``--model given`` and by default, round-robin, wall and CPU medians (docs/performance.md, "The
all-mode FRF").  ``--peak-study``: 50 normal loads from 40 to 300 N on two processes, each the single-mode FRF
and the FRF refined where it holds the peak.

``python benchmarks/bench_allmode.py --estimates``: the error estimate (and the one the element
gave before: half-cells Richardson assuming order 2, and the H -> ceil(H/2) change) against the
converged references of ``tests/test_allmode_accuracy.py`` (copied below), and the element's own
choice at its default tol (docs/validation.md, "Accuracy to a tolerance").
"""

from __future__ import annotations

import csv
import os
import resource
import statistics
import subprocess
import tempfile
import warnings
import sys
import time
from pathlib import Path

import numpy as np

import math

from contact_models import (AccuracyWarning, AllModeMicroslip, Bar, FunctionLoad, NumericalMicroslip,
                            TwoRegionMicroslip, UniformLoad)

from common import REPEATS, ROOT, machine, machine_line, table

BAR = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
LOAD = UniformLoad(N=100.0)
FREQUENCIES = (0.2, 0.5)
RATIOS = (1.5, 3.0, 10.0)
REFERENCE = Path(__file__).resolve().parent.parent / "docs" / "data" / "allmode_reference.csv"
#: (label, cells, harmonics) of the all-mode settings and (label, cells, steps) of the numerical ones
ALLMODE = (("all-mode 20 cells, H 7", 20, 7), ("all-mode 40 cells, H 15 (default)", 40, 15),
           ("all-mode 80 cells, H 23", 80, 23))
NUMERICAL = (("numerical 50 cells, 256 steps", 50, 256), ("numerical 100 cells, 512 steps", 100, 512))


def reference():
    with open(REFERENCE) as fh:
        return {(float(r["w"]), float(r["ratio"])): (float(r["Fs"]), float(r["Fc"]))
                for r in csv.DictReader(fh) if r["load"] == "uniform"}


def points():
    amin = NumericalMicroslip(BAR, LOAD, cells=200).slip_amplitude(0.0)
    return [(w, r, r * amin) for w in FREQUENCIES for r in RATIOS]


def run_allmode(cells, H, pts, cold):
    """(CPU seconds per point, values) for all points."""
    vals = {}
    t0 = time.process_time()
    if cold:
        for w, r, a in pts:
            el = AllModeMicroslip(BAR, LOAD, cells=cells, harmonics=H)
            vals[(w, r)] = el.fourier(a, w * BAR.omega_c)
    else:
        el = AllModeMicroslip(BAR, LOAD, cells=cells, harmonics=H)
        for w in FREQUENCIES:
            sel = [(ww, r, a) for ww, r, a in pts if ww == w]
            fs, fc = el.fourier(np.array([a for *_, a in sel]), w * BAR.omega_c)
            for (ww, r, a), s, c in zip(sel, fs, fc):
                vals[(w, r)] = (s, c)
    return (time.process_time() - t0) / len(pts), vals


def run_numerical(cells, steps, pts):
    vals, times = {}, []
    for w, r, a in pts:
        num = NumericalMicroslip(BAR, LOAD, cells=cells, steps_per_cycle=steps)
        t0 = time.process_time()
        res = num.simulate(a, w * BAR.omega_c)
        times.append(time.process_time() - t0)
        vals[(w, r)] = (res.f_s, res.f_c)
    return statistics.median(times), vals


def error(vals, ref, pts):
    return max(max(abs(vals[(w, r)][0] / (BAR.k_star * a) - ref[(w, r)][0]),
                   abs(vals[(w, r)][1] / (BAR.k_star * a) - ref[(w, r)][1])) for w, r, a in pts)


def main(repeats: int = REPEATS, numerical: bool = True):
    info = machine()
    ref = reference()
    pts = points()
    rows = []
    all_times = {}
    for label, cells, H in ALLMODE:
        cold = [run_allmode(cells, H, pts, True) for _ in range(repeats)]
        warm = [run_allmode(cells, H, pts, False) for _ in range(repeats)]
        t_cold = statistics.median(c[0] for c in cold)
        t_warm = statistics.median(c[0] for c in warm)
        all_times[label] = (t_cold, t_warm)
        rows.append([label, f"{error(cold[-1][1], ref, pts):.1e}", f"{1e3 * t_cold:.1f} ms", f"{1e3 * t_warm:.1f} ms"])
    num_times = {}
    if numerical:
        for label, cells, steps in NUMERICAL:
            t, vals = run_numerical(cells, steps, pts)
            num_times[label] = t
            rows.append([label, f"{error(vals, ref, pts):.1e}", f"{t:.2f} s (median of {len(pts)})", ""])
    print(machine_line(info))
    print(table(["setting", "max error (k* a)", "CPU per point (cold)", "CPU per point (sweep)"], rows))
    if num_times:
        for (la, (tc, tw)), (ln, tn) in zip(list(all_times.items())[:2], num_times.items()):
            print(f"\n{ln} / {la}: {tn / tc:.0f}x (cold), {tn / tw:.0f}x (sweep)")
    return rows, all_times, num_times


#: The converged references of tests/test_allmode_accuracy.py: (load, omega/omega_c, a, (f_s, f_c)).
SINE = FunctionLoad(lambda x: 2000.0 * (1.0 + 0.8 * np.sin(6.0 * np.pi * x / BAR.L)))
CASES = {"uniform 0.3 omega_c": (LOAD, 0.3, 1.5e-6, (48.04909825902723, 6.874552719918713)),
         "sine, 5 regions, 0.3 omega_c": (SINE, 0.3, 1.5 * 1.6298212423752916e-07,
                                          (9.019326918679495, 0.10307701386100945)),
         "uniform 10 omega_c": (LOAD, 10.0, 1.5e-6, (-462.45684743937454, 12.271992267837609)),
         "uniform 30 omega_c": (LOAD, 30.0, 1.5e-6, (8319.083, 69.9110))}


def estimate_rows():
    """Rows (case, cells, H, estimate, true, ratio, old estimate, old ratio) and the default choices."""
    rows, auto = [], []
    for name, (load, w, a, ref) in CASES.items():
        floor, omega = 0.01 * BAR.k_star * a, w * BAR.omega_c
        ref_v = np.array(ref[::-1])  # (f_c, f_s), the layout's order

        def rel(F):
            return float(np.max(F / np.maximum(np.abs(ref_v), floor)))

        def F(c, h):
            return AllModeMicroslip(BAR, load, c, h).solve(a, omega).F[1:3]

        grid = [(n, H) for H in ((7, 15) if w < 1 else (7,)) for n in ((16, 32, 64, 128) if w < 30 else (64, 128, 256))]
        for n, H in grid:
            try:
                sol = AllModeMicroslip(BAR, load, n, H).solve(a, omega, estimate_error=True)
            except ValueError:  # exact cells longer than 0.9 of half the highest harmonic's wavelength
                rows.append([name, str(n), str(H), "too few cells", "", "", "", ""])
                continue
            f = sol.F[1:3]
            true = rel(np.abs(f - ref_v))
            try:
                old = float(np.max(np.maximum(np.abs(f - F(n // 2, H)) / 3, np.abs(f - F(n, math.ceil(H / 2))))
                                   / np.maximum(np.abs(f), floor)))
            except ValueError:  # its half cells too few for the exact segments
                old = math.nan
            rows.append([name, str(n), str(H), f"{sol.relative_error:.2e}", f"{true:.2e}",
                         f"{sol.relative_error / true:.2f}", f"{old:.2e}", f"{old / true:.2f}"])
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", AccuracyWarning)
            sol = AllModeMicroslip(BAR, load).solve(a, omega)
        auto.append([name, f"{sol.cells}, {sol.H}", f"{sol.relative_error:.2e}", f"{rel(np.abs(sol.F[1:3] - ref_v)):.2e}",
                     "yes" if caught else "no"])
    print(table(["case", "cells", "H", "estimate", "true error", "ratio", "old estimate", "old ratio"], rows))
    print()
    print(table(["case", "chosen cells, H", "estimate", "true error", "warns"], auto))
    return rows, auto


def _frf_along(case, el, tol, along):
    """The default case's FRF with ``el`` at ``tol``: rungs chosen along the curve (``along``) or the
    element choosing per call (``hbm.frf.RUNGS_ALONG_CURVE = False``, the path before)."""
    from hbm import frequency_response  # lazily: the element benchmark above needs no solver
    from hbm import frf as frf_module

    frf_module.RUNGS_ALONG_CURVE = along
    try:
        return frequency_response(case.blade, el, omega_range=case.omega_range, tol=tol)
    finally:
        frf_module.RUNGS_ALONG_CURVE = True


def frf_rows(repeats: int = 3, before: bool = True):
    """The default FRF with each damper, round-robin; rows of (label, median s, ratio, points, peak,
    estimate, warnings).  The all-mode bar choosing its rungs: at the FRF's tol 1e-2 and 1e-3 (the
    element's tol the same), before (per call) and after (along the curve); ``before=False`` skips
    the per-call tol = 1e-3 run (tens of seconds)."""
    from hbm.cli.cases import default_case

    case = default_case()
    bar, load = case.element.bar, case.element.load
    dampers = [("single-mode TwoRegionMicroslip", lambda: case.element, 1e-3, True),
               ("all-mode 16 cells, H = 7 (fixed)", lambda: AllModeMicroslip(bar, load, 16, 7), 1e-3, True),
               ("all-mode tol = 1e-2, before (per call)", lambda: AllModeMicroslip(bar, load, tol=1e-2), 1e-2, False),
               ("all-mode tol = 1e-2, after (along the curve)", lambda: AllModeMicroslip(bar, load, tol=1e-2), 1e-2,
                True),
               ("all-mode tol = 1e-3, before (per call)", lambda: AllModeMicroslip(bar, load), 1e-3, False),
               ("all-mode tol = 1e-3, after (along the curve)", lambda: AllModeMicroslip(bar, load), 1e-3, True)]
    if not before:
        dampers = [d for d in dampers if not d[0].startswith("all-mode tol = 1e-3, before")]
    times = {label: [] for label, *_ in dampers}
    last = {}
    for _ in range(repeats):
        for label, make, tol, along in dampers:
            el = make()  # a new element each run: no warm start carried between runs
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always", AccuracyWarning)
                t = time.perf_counter()
                frf = _frf_along(case, el, tol, along)
                times[label].append(time.perf_counter() - t)
            pk = frf.peak()
            n_warn = sum(issubclass(w.category, AccuracyWarning) for w in caught)
            last[label] = (len(frf), f"{pk.amplitude:.6e} m at {pk.omega:.2f} rad/s",
                           f"{float(np.max(frf.error_estimate)):.1e}", n_warn)
    base = statistics.median(times[dampers[0][0]])
    rows = [[label, f"{statistics.median(ts):.2f} s", f"{statistics.median(ts) / base:.0f}x", str(last[label][0]),
             last[label][1], last[label][2], str(last[label][3])] for label, ts in times.items()]
    print(machine_line(machine()))
    print(table(["damper", f"wall, median of {repeats}", "/ single-mode", "points", "peak", "largest estimate",
                 "AccuracyWarnings"], rows))
    return rows


def pass_rows(repeats: int = 3, tol: float = 1e-3):
    """Where the all-mode FRF's time goes: the default case at ``tol`` (the element's tol the same)
    ``repeats + 1`` times in this process, each continuation (``hbm.continuation.continuation``, the
    whole range and each window traced again) and each curve estimate (``hbm.balance.errors.estimate``)
    timed by wrapping it; the first FRF (loading: numba's cached kernels, first calls) apart, then
    the medians of the others, pass by pass, with the single-mode FRF's median for the ratio."""
    from hbm import continuation as cont_module
    from hbm import frequency_response
    from hbm.balance import errors
    from hbm.cli.cases import default_case

    case = default_case()
    bar, load = case.element.bar, case.element.load
    log: list = []

    def timed(kind, fn, what):
        def wrapper(*args, **kwargs):
            t = time.perf_counter()
            out = fn(*args, **kwargs)
            log.append((kind, *what(args, out), time.perf_counter() - t))
            return out
        return wrapper

    def rung(problem):
        return "; ".join(getattr(c.element, "model_name", type(c.element).__name__) for c in problem.contacts)

    def traced(args, out):
        om = args[0].to_physical(out.y)[1] if len(out.y) else np.zeros(1)
        return args[0].H, rung(args[0]), len(out.y), out.nfev, f"{om.min():.0f}..{om.max():.0f}"

    saved = cont_module.continuation, errors.estimate
    cont_module.continuation = timed("trace", saved[0], traced)
    errors.estimate = timed("estimate", saved[1], lambda args, out: (args[0].H, rung(args[0]), len(args[2]), 0, ""))
    runs, single = [], []
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            for _ in range(repeats + 1):
                log.clear()
                t = time.perf_counter()
                frf = frequency_response(case.blade, AllModeMicroslip(bar, load, tol=tol), case.omega_range, tol=tol)
                runs.append((time.perf_counter() - t, list(log), len(frf)))
                t = time.perf_counter()
                frequency_response(case.blade, case.element, omega_range=case.omega_range)
                single.append(time.perf_counter() - t)
    finally:
        cont_module.continuation, errors.estimate = saved
    if any(len(r[1]) != len(runs[-1][1]) for r in runs):  # the rows pair the passes of the runs in order
        raise RuntimeError(f"the FRFs took different passes: {[len(r[1]) for r in runs]} traces and estimates")
    base = statistics.median(single[1:])
    print(machine_line(machine()))
    print(f"all-mode FRF at tol = {tol:g}: first in the process {runs[0][0]:.2f} s, then median of {repeats} "
          f"{statistics.median(r[0] for r in runs[1:]):.2f} s ({statistics.median(r[0] for r in runs[1:]) / base:.0f}x "
          f"the single-mode FRF, {base:.3f} s); {runs[-1][2]} points")
    rows = []
    for j, entry in enumerate(runs[-1][1]):
        warm = statistics.median(r[1][j][-1] for r in runs[1:])
        rows.append([entry[0], str(entry[1]), entry[2], str(entry[3]), str(entry[4] or ""), entry[5],
                     f"{runs[0][1][j][-1]:.3f} s", f"{warm:.3f} s"])
    rest = [r[0] - sum(e[-1] for e in r[1]) for r in runs]
    rows.append(["the rest (rungs probed, splice)", "", "", "", "", "", f"{rest[0]:.3f} s",
                 f"{statistics.median(rest[1:]):.3f} s"])
    print(table(["what", "balance H", "rung", "points", "evaluations", "omega (rad/s)", "first FRF",
                 f"median of {repeats}"], rows))
    return rows


def _frf_run(args):
    """One run of the all-mode FRF study: the default case with normal load N at ``tol``, rungs along
    the curve; (N, peak amplitude, largest estimate, CPU s)."""
    from hbm.cli.cases import default_case

    N, tol = args
    warnings.simplefilter("ignore")
    case = default_case()
    t0 = time.process_time()
    frf = _frf_along(case, AllModeMicroslip(case.element.bar, UniformLoad(N=N), tol=tol), tol, True)
    return N, frf.peak().amplitude, float(np.max(frf.error_estimate)), time.process_time() - t0


def frf_study(tol: float = 1e-2, runs: int = 50):
    """``runs`` all-mode FRFs (normal loads 40..300 N) at ``tol`` on two processes: wall and CPU."""
    from multiprocessing import Pool  # lazily: only this study runs processes

    info = machine()
    t = time.perf_counter()
    with Pool(2) as pool:
        rows = pool.map(_frf_run, [(N, tol) for N in np.linspace(40.0, 300.0, runs)], chunksize=1)
    wall = time.perf_counter() - t
    cpu = sum(r[3] for r in rows)
    print(machine_line(info))
    print(f"{runs} all-mode FRFs at tol {tol:g}: {wall:.1f} s wall on 2 processes, {cpu:.1f} s CPU in all "
          f"({cpu / runs:.2f} s per run, slowest {max(r[3] for r in rows):.2f} s), {sum(r[2] > tol for r in rows)} "
          f"above tol; load average {os.getloadavg()[0]:.1f} at the end")
    return rows


def _child_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def _at_peak(frf) -> tuple[float, float, float, str]:
    """``(omega, amplitude, estimate, model)`` of the peak of ``frf``: the model of the point nearest it."""
    pk = frf.peak()
    i = int(np.argmin(np.abs(frf.omega / pk.omega - 1.0) + np.abs(frf.amplitude / pk.amplitude - 1.0)))
    return pk.omega, pk.amplitude, pk.estimate, str(frf.point_models[i])


def peak_rows(repeats: int = 3):
    """The default case's FRF refined where it holds the peak (``model="peak"``) against the single-mode
    FRF, and the whole job each way (a new process: import, solve, CSV, figure), round-robin; wall and CPU
    medians, ratios of this run."""
    from hbm import frequency_response  # lazily: the element benchmark above needs no solver
    from hbm.cli.cases import default_case

    case = default_case()
    el = case.element
    out = Path(tempfile.mkdtemp())
    job = [sys.executable, "-m", "hbm", "--out", str(out)]
    state = {}

    def single():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            state["frf"] = frequency_response(case.blade, el, omega_range=case.omega_range)

    def peak():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            state["peak"] = frequency_response(case.blade, el, omega_range=case.omega_range, model="peak")

    def run(args):
        return lambda: subprocess.run(job + args, check=True, capture_output=True, cwd=ROOT)

    tasks = (("single-mode FRF (frequency_response)", single, False),
             ("FRF refined at the peak (model='peak')", peak, False),
             ("job: python3 -m hbm --model given", run(["--model", "given"]), True),
             ("job: python3 -m hbm (auto, the default)", run([]), True))
    times = {label: ([], []) for label, *_ in tasks}
    for _ in range(repeats):
        for label, fn, child in tasks:
            c0, t0 = (_child_cpu() if child else time.process_time()), time.perf_counter()
            fn()
            times[label][0].append(time.perf_counter() - t0)
            times[label][1].append((_child_cpu() if child else time.process_time()) - c0)
    base = [statistics.median(v) for v in times[tasks[0][0]]]
    rows = [[label, f"{statistics.median(w):.2f} s", f"{statistics.median(c):.2f} s",
             f"{statistics.median(w) / base[0]:.1f}x", f"{statistics.median(c) / base[1]:.1f}x"]
            for label, (w, c) in times.items()]
    omega, amplitude, estimate, model = _at_peak(state["peak"])
    print(machine_line(machine()))
    print(table(["what", f"wall, median of {repeats}", "CPU", "wall / single-mode FRF", "CPU / single-mode FRF"],
                rows))
    print(f"peak {amplitude:.7e} m at {omega:.2f} rad/s, estimate {estimate:.2e} ({model})")
    return rows


def _peak_run(N):
    """One run of the peak study: the single-mode FRF with load N and the FRF refined where it holds the
    peak; (N, single peak, the refined FRF's (omega, amplitude, estimate, model at the peak), CPU)."""
    from hbm import frequency_response  # lazily: the element benchmark above needs no solver
    from hbm.cli.cases import default_case

    warnings.simplefilter("ignore")
    case = default_case()
    el = TwoRegionMicroslip(case.element.bar, UniformLoad(N=N))
    t0 = time.process_time()
    frf = frequency_response(case.blade, el, omega_range=case.omega_range)
    pk = frf.peak()
    best = _at_peak(frequency_response(case.blade, el, omega_range=case.omega_range, model="peak"))
    return N, (pk.omega, pk.amplitude), best, time.process_time() - t0


def peak_study(runs: int = 50):
    """The default case with ``runs`` normal loads from 40 to 300 N on two processes: each run the
    single-mode FRF and the FRF refined where it holds the peak (``_peak_run``); wall, CPU, and the runs
    whose peak's estimate is above tol."""
    from multiprocessing import Pool  # lazily: only this study runs processes

    info = machine()
    t = time.perf_counter()
    with Pool(2) as pool:
        rows = pool.map(_peak_run, np.linspace(40.0, 300.0, runs), chunksize=1)
    wall = time.perf_counter() - t
    cpu = sum(r[3] for r in rows)
    print(machine_line(info))
    print(f"{runs} runs: {wall:.1f} s wall on 2 processes, {cpu:.1f} s CPU in all ({cpu / runs:.2f} s per run), "
          f"load average {os.getloadavg()[0]:.1f} at the end")
    for N, single, best, c in rows:
        if not best[2] <= 1e-3:
            print(f"N = {N:.1f}: single-mode {single}, refined at the peak {best}, CPU {c:.2f} s")
    return rows


if __name__ == "__main__":
    if "--frf-study" in sys.argv:
        rest = [a for a in sys.argv[1:] if a != "--frf-study"]
        frf_study(float(rest[0]) if rest else 1e-2)
        sys.exit()
    if "--peak-study" in sys.argv:
        peak_study()
        sys.exit()
    if "--peak" in sys.argv:
        rest = [a for a in sys.argv[1:] if a != "--peak"]
        peak_rows(int(rest[0]) if rest else 3)
        sys.exit()
    if "--passes" in sys.argv:
        rest = [a for a in sys.argv[1:] if a != "--passes"]
        pass_rows(int(rest[0]) if rest else 3)
        sys.exit()
    if "--estimates" in sys.argv:
        estimate_rows()
    elif "--frf" in sys.argv:
        rest = [a for a in sys.argv[1:] if a != "--frf"]
        frf_rows(int(rest[0]) if rest else 3, before="--no-before" not in sys.argv)
    else:
        main(numerical="--no-numerical" not in sys.argv)
