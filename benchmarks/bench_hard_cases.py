"""The hard cases of ``tests/test_hard_cases_tol.py`` with their slow references: estimate against true error.

For each case: ``frequency_response`` at its tolerance, the estimate at the point compared (the
peak, or the reference's frequency), the true relative error of the amplitude there against an
independent reference, and whether the call warned (``AccuracyWarning``, one per call):

- the 3-DOF chain's window at omega = 0.62 (3 omega on the third mode): the true periodic
  response by shooting (``tests/data/periodic_reference.json``);
- the single-mode bars (stiff shear layer, near and above the cut-off): the all-mode bar
  (``AllModeMicroslip``, its cells and harmonics chosen to 1e-5, or to 1e-4 for the stiff layer)
  at the same frequency by ``response_at`` (both single-harmonic balances: the model's error);
- the many-region load on the all-mode bar: the same bar with 320 cells and 31 harmonics.

Prints a Markdown table (``docs/validation.md``, "Hard cases").  Run:
``python3 benchmarks/bench_hard_cases.py [--slow]`` (``--slow`` adds the many-region load with
chosen cells, about 10 minutes; the rest takes about 5).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT / "tests"), str(ROOT)]  # this tree's packages; the cases are the tests' own

from contact_models import AccuracyWarning, AllModeMicroslip, Bar, TwoRegionMicroslip, UniformLoad  # noqa: E402
from hbm import frequency_response, response_at  # noqa: E402
from hbm.cli.cases import default_case  # noqa: E402
from test_hard_cases_tol import BAR, CHAIN_062, WAVY, at_omega, blade_at, chain  # noqa: E402


def run(*args, **kwargs):
    """``(frf, warned, seconds)``."""
    t = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", AccuracyWarning)
        frf = frequency_response(*args, **kwargs)
    return frf, any(issubclass(w.category, AccuracyWarning) for w in caught), time.perf_counter() - t


def at_peak(frf, blade, reference) -> tuple[float, float]:
    """(estimate at the sampled maximum, true error of the refined peak's amplitude against
    ``reference`` solved at the peak's frequency)."""
    i = int(np.argmax(frf.amplitude))
    pk = frf.peak()
    ref = response_at(blade, reference, pk.omega, (0.5 * pk.amplitude, 2.0 * pk.amplitude), rtol=1e-8)
    return float(frf.error_estimate[i]), abs(pk.amplitude / ref.amplitude - 1.0)


def chain_rows() -> list[tuple]:
    s, cs = chain()
    rows = []
    for H, window in ((None, (0.615, 0.625)), (7, (0.618, 0.622)), (15, (0.618, 0.622))):
        frf, warned, dt = run(s, cs, omega_range=window, tol=1e-5, harmonics=H, response_dof=2, stability=False)
        est = float(np.interp(0.62, np.sort(frf.omega), frf.error_estimate[np.argsort(frf.omega)]))
        name = f"chain, omega = 0.62 (3:1 superharmonic), H {'chosen' if H is None else 'given'} = {frf.harmonics}"
        rows.append((name, 1e-5, est, abs(at_omega(frf, 0.62) / CHAIN_062 - 1.0), warned, dt))
    return rows


def single_mode_rows() -> list[tuple]:
    case = default_case()
    rows = []
    stiff = Bar(**{**BAR, "k": 100.0 * BAR["k"]})
    el = TwoRegionMicroslip(stiff, UniformLoad(N=100.0))
    w_s = math.sqrt((case.blade.stiffness + el.stuck_stiffness(0.0)) / case.blade.mass)
    frf, warned, dt = run(case.blade, el, omega_range=(0.8 * w_s, 1.1 * w_s))
    rows.append(("stiff shear layer (k x 100, lambda L = 10), default blade", 1e-3,
                 *at_peak(frf, case.blade, AllModeMicroslip(stiff, UniformLoad(N=100.0), tol=1e-4)), warned, dt))
    bar = Bar(**BAR)
    for name, resonance, force, window in (
            ("single-mode, slipping near cut-off (0.85-0.99 omega_c)", 0.95, 40.0, (0.85, 0.99)),
            ("single-mode, stuck above cut-off (1.17-1.43 omega_c)", 1.3, 8.0, (1.17, 1.43))):
        blade = blade_at(resonance * bar.omega_c, force)
        frf, warned, dt = run(blade, TwoRegionMicroslip(bar, UniformLoad(N=100.0)),
                              omega_range=tuple(f * bar.omega_c for f in window))
        rows.append((name, 1e-3, *at_peak(frf, blade, AllModeMicroslip(bar, UniformLoad(N=100.0), tol=1e-5)),
                     warned, dt))
    return rows


def many_region_rows(slow: bool) -> list[tuple]:
    case = default_case()
    fine = AllModeMicroslip(Bar(**BAR), WAVY, cells=320, harmonics=31)
    rows = []
    for name, el in (("many-region load, all-mode bar, 8 cells H = 7 fixed",
                      AllModeMicroslip(Bar(**BAR), WAVY, cells=8, harmonics=7)),
                     ("many-region load, all-mode bar, cells and H chosen", AllModeMicroslip(Bar(**BAR), WAVY))):
        if "chosen" in name and not slow:
            continue
        frf, warned, dt = run(case.blade, el, omega_range=(37500.0, 39000.0))
        rows.append((name, 1e-3, *at_peak(frf, case.blade, fine), warned, dt))
    return rows


def main(slow: bool = False) -> list[tuple]:
    print("| case | tol | estimate | true error | true/estimate | warned | time (s) |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    rows = []
    for part in (chain_rows, single_mode_rows, lambda: many_region_rows(slow)):
        for name, tol, est, true, warned, dt in part():
            rows.append((name, tol, est, true, warned, dt))
            print(f"| {name} | {tol:g} | {est:.2e} | {true:.2e} | {true / max(est, 1e-300):.2f} | "
                  f"{'yes' if warned else 'no'} | {dt:.1f} |", flush=True)
    return rows


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--slow", action="store_true", help="add the many-region load with chosen cells")
    main(slow=parser.parse_args().slow)
