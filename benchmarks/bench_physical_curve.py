"""The default blade's resonance curve: what the physical answer costs against the single-mode one.

In one process, the median of ``--repeats`` runs of each (after one warm-up run of each, so the
compiled kernels, where the ``fast`` extra is installed, are loaded and numba's cache is warm):

* the single-mode curve (``model="given"``, tol = 1e-3);
* the curve refined where it holds the peak (``model="peak"``: the windows of the model source that
  hold the peak traced again with the bar of every mode, the single-mode bar elsewhere);
* the physical curve (``model="auto"``: the bar with every mode wherever the single-mode bar is off);
* the same with ``AllModeMicroslip`` given as the damper.

For each: the time, the points, the time per point, the largest estimated error and the largest
true error at the 16 frequencies of ``tests/data/physical_curve_reference.json`` (the curve read there
by the cubic through its four nearest points), and whether an ``AccuracyWarning`` was emitted.
Prints the table of ``docs/performance.md``, "The physical curve".

Run: ``PYTHONPATH=. python3 benchmarks/bench_physical_curve.py [--repeats N]``; with ``--points``, the
physical curve at each reference frequency instead (``docs/validation.md``, "The main job against the
converged bar").
"""

from __future__ import annotations

import argparse
import json
import statistics
import time
import warnings
from pathlib import Path

import numpy as np

import hbm
from contact_models import AccuracyWarning, AllModeMicroslip
from hbm.cli.cases import default_case

REFERENCE = Path(__file__).resolve().parent.parent / "tests" / "data" / "physical_curve_reference.json"


def true_error(frf, points) -> float:
    """The largest relative distance of ``frf`` (read by a local cubic) from the reference points."""
    w, A = frf.omega, frf.amplitude
    worst = 0.0
    for p in points:
        j = int(np.searchsorted(w, p["omega"]))
        idx = np.arange(max(0, j - 2), min(len(w), j + 2))
        a = float(np.polyfit(w[idx] - p["omega"], A[idx], len(idx) - 1)[-1])
        worst = max(worst, abs(a / p["amplitude"] - 1.0))
    return worst


def at(frf, values, omega: float) -> float:
    """``values`` of ``frf`` at ``omega`` by the cubic through its four points nearest it."""
    w = frf.omega
    j = int(np.searchsorted(w, omega))
    idx = np.arange(max(0, j - 2), min(len(w), j + 2))
    return float(np.polyfit(w[idx] - omega, values[idx], len(idx) - 1)[-1])


def point_table(points, blade, el, rng) -> None:
    """The physical curve (``model="auto"``) at each reference frequency: the table of
    ``docs/validation.md``, "The main job against the converged bar"."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning)
        frf = hbm.frequency_response(blade, el, rng, tol=1e-3, model="auto")
        single = hbm.frequency_response(blade, el, rng, tol=1e-3)
    print("| omega (rad/s) | reference (m) | its own error | true error | estimate | model, H | single-mode bar's error |")
    print("|---|---|---|---|---|---|---|")
    for p in points:
        w = p["omega"]
        true = abs(at(frf, frf.amplitude, w) / p["amplitude"] - 1.0)
        est = at(frf, frf.error_estimate, w)
        i = int(np.argmin(np.abs(frf.omega - w)))
        off = abs(at(single, single.amplitude, w) / p["amplitude"] - 1.0)
        print(f"| {w:.1f} | {p['amplitude']:.6e} | {p['spread']:.1e} | {true:.1e} | {est:.1e} | "
              f"{frf.point_models[i]}, {frf.point_harmonics[i]} | {off:.1e} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--points", action="store_true", help="the per-frequency table of docs/validation.md")
    args = parser.parse_args()
    points = json.loads(REFERENCE.read_text())["points"]
    case = default_case()
    blade, el, rng = case.blade, case.element, case.omega_range
    if args.points:
        point_table(points, blade, el, rng)
        return

    runs = {
        "single-mode curve (model='given')": lambda: (hbm.frequency_response(blade, el, rng, tol=1e-3), None),
        "curve refined where it holds the peak (model='peak')":
            lambda: (hbm.frequency_response(blade, el, rng, tol=1e-3, model="peak"), None),
        "physical curve (model='auto', the main job)":
            lambda: (hbm.frequency_response(blade, el, rng, tol=1e-3, model="auto"), None),
        "physical curve (AllModeMicroslip given)":
            lambda: (hbm.frequency_response(blade, AllModeMicroslip(el.bar, el.load), rng, tol=1e-3), None),
    }
    rows, base = [], None
    for name, run in runs.items():
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", AccuracyWarning)
            run()  # warm-up
            times = []
            for _ in range(args.repeats):
                t = time.perf_counter()
                frf, best = run()
                times.append(time.perf_counter() - t)
        warned = any(issubclass(w.category, AccuracyWarning) for w in caught)
        t = statistics.median(times)
        base = base or t
        est = float(np.max(frf.error_estimate))
        rows.append(f"| {name} | {t:.3g} | {t / base:.1f} | {len(frf)} | {1e3 * t / len(frf):.2g} | {est:.2g} | "
                    f"{true_error(frf, points):.2g} | {'yes' if warned else 'no'} |")
        print(rows[-1], flush=True)
    print()
    print("| run | time (s) | against the single-mode curve | points | ms per point | largest estimate "
          "| largest true error (16 frequencies) | AccuracyWarning |")
    print("|---|---|---|---|---|---|---|---|")
    print("\n".join(rows))


if __name__ == "__main__":
    main()
