"""The error estimate against the true error, on every reference it can be checked against.

For each case and tolerance: ``frequency_response(..., tol=tol)`` (H chosen by the balance where
the system has time laws), its estimate at the peak (``error_estimate`` at the sampled maximum)
and the true relative error of its refined peak amplitude against the reference, with the time:

- P1-P3 (one DOF, a Jenkins element to ground): the true periodic peaks by shooting
  (``tests/data/periodic_reference.json``, ``benchmarks/periodic_reference.py``);
- the 3-DOF chain at the frequencies of that file (amplitude of DOF 2 at fixed frequency);
- the default blade with its single-mode damper against the all-mode bar's FRF (the model
  source; computed here, about a minute).

Prints a Markdown table (``docs/validation.md``, "Error estimates").  Run:
``python3 benchmarks/bench_error_estimates.py [--no-allmode]``.
"""

from __future__ import annotations

import argparse
import json
import time
import warnings
from pathlib import Path

import numpy as np

from contact_models import AccuracyWarning, AllModeMicroslip, Macroslip
from hbm import Contact, Structure, continuation, frequency_response
from hbm.cli.cases import default_case

ROOT = Path(__file__).resolve().parent.parent
REFERENCE = ROOT / "tests" / "data" / "periodic_reference.json"
TOLS = (1e-2, 1e-3, 1e-5)


def estimate_at_peak(frf) -> float:
    return float(frf.error_estimate[int(np.argmax(frf.amplitude))])


def jenkins_rows(ref: dict) -> list[tuple]:
    rows = []
    for name, case in ref["jenkins"].items():
        p = case["parameters"]
        s = Structure([[p["mass"]]], [[p["damping"]]], [[p["stiffness"]]], force=[p["force"]])
        el = Macroslip(p["contact_stiffness"], p["slip_force"])
        w = case["peak_amplitude"]["omega"]
        true = case["peak_amplitude"]["amplitude"]
        for tol in TOLS:
            t = time.perf_counter()
            frf = frequency_response(s, [Contact(el, dof=0)], omega_range=(0.6 * w, 1.4 * w), tol=tol)
            dt = time.perf_counter() - t
            rows.append((name, tol, frf.harmonics, estimate_at_peak(frf), abs(frf.peak().amplitude / true - 1.0), dt))
    return rows


def chain_rows(ref: dict) -> list[tuple]:
    c = ref["chain"]
    K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    s = Structure(np.eye(3), 0.004 * K, K, force=[0.0, 0.0, 0.01])
    contacts = [Contact(Macroslip(1.0, 0.02), dof=0), Contact(Macroslip(1.0, 0.05), dofs=(0, 1))]
    rows = []
    for tol in TOLS:
        t = time.perf_counter()
        frf = frequency_response(s, contacts, omega_range=(0.3, 1.6), tol=tol)
        dt = time.perf_counter() - t
        worst_ratio, worst_true, worst_est = 0.0, 0.0, 0.0
        for point in c["points"]:
            w = point["omega"]
            X = np.array(point["harmonics"]["real"])[2]
            true_a = float(np.hypot(X[1], X[2]))
            j = np.flatnonzero((frf.omega[:-1] - w) * (frf.omega[1:] - w) <= 0.0)
            for k in j:
                f, i = frf._interval(int(k))  # the segment holding the interval (H chosen along the curve)
                pr = f._problem
                loc = continuation.locate(pr, f._run.y[i], f._run.y[i + 1],
                                          lambda y, tt, pr=pr: y[-1] * pr.omega_ref - w, tol=f.newton_tol, scale=f._scale,
                                          xtol=1e-13)
                if loc is None:
                    continue
                Xb, _ = pr.to_physical(loc.y)
                r = pr.dofs.index(2)
                err = abs(float(np.hypot(Xb[r, 1], Xb[r, 2])) / true_a - 1.0)
                est = float(np.interp(w, np.sort(frf.omega), frf.error_estimate[np.argsort(frf.omega)]))
                if err > worst_true:
                    worst_true, worst_est = err, est
                worst_ratio = max(worst_ratio, err / max(est, 1e-300))
        rows.append(("chain (8 frequencies)", tol, frf.harmonics, worst_est, worst_true, dt))
    return rows


def blade_rows() -> list[tuple]:
    case = default_case()
    bar, load = case.element.bar, case.element.load
    ref = frequency_response(case.blade, AllModeMicroslip(bar, load), omega_range=case.omega_range,
                             estimate_error=False).peak()
    t = time.perf_counter()
    frf = frequency_response(case.blade, case.element, omega_range=case.omega_range)
    dt = time.perf_counter() - t
    return [("default blade, single-mode", 1e-3, 1, estimate_at_peak(frf),
             abs(frf.peak().amplitude / ref.amplitude - 1.0), dt)]


def main(allmode: bool = True) -> list[tuple]:
    warnings.simplefilter("ignore", AccuracyWarning)
    ref = json.loads(REFERENCE.read_text())
    rows = jenkins_rows(ref) + chain_rows(ref) + (blade_rows() if allmode else [])
    print("| case | tol | H | estimate at the peak | true error | true/estimate | time (s) |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for name, tol, H, est, true, dt in rows:
        print(f"| {name} | {tol:g} | {H} | {est:.2e} | {true:.2e} | {true / max(est, 1e-300):.2f} | {dt:.2f} |")
    return rows


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--no-allmode", action="store_true", help="leave out the blade's all-mode reference")
    main(allmode=not parser.parse_args().no_allmode)
