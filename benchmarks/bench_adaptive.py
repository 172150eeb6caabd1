"""Harmonics and model chosen along the curve against H (or the model) chosen for the whole curve, in one run.

Three rounds, each timing in turn:

- the 3-DOF chain of ``benchmarks/bench_steps.py`` (``chain()``: omega 0.3..1.6 rad/s, the
  "precise" steps, ``tol=1e-5``, ``stability=False``, the refined peak): H along the curve (no
  ``harmonics``), and the whole curve at ``harmonics=31``, 15, 7 and 3;
- the Jenkins chain of ``docs/multiharmonic.md`` (omega 0.3..1.8 rad/s, default steps, ``tol=1e-3``):
  H along the curve, the whole curve at ``harmonics=15``, 7, 3 and 1;
- P1 (one DOF, ``tol=1e-5``): H along the curve.

"H along the curve" starts where the tolerance predicts (the sliders are closed forms:
``hbm.frf.start_harmonics``); "from 3" is the same call with its coarse trace at H = 3
(``hbm.frf.START_UNKNOWNS = 0``), the start of an element with sampled harmonics.

The whole-curve rule (H = 3, 7, 15, 31 in turn over the whole range until the estimate is below
half the tolerance everywhere) costs the sum of the whole-curve times up to the H it ends at.

Medians of the rounds; the peaks against the chain's true peak (``benchmarks/chain_peak_reference.py``:
0.5212270 rad/s, 0.1592898 m).  ``--blade``: once, the default blade of ``python3 -m hbm`` with
``model="auto"`` at ``tol=1e-2`` (the all-mode bar in a window near the peak) against the whole curve
with ``AllModeMicroslip`` (what ``model="auto"`` solved before) and the single-mode curve.

Run: ``PYTHONPATH=. python3 benchmarks/bench_adaptive.py [--rounds 3] [--blade]``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import time
import warnings
from pathlib import Path

import numpy as np




from contact_models import AllModeMicroslip, Macroslip  # noqa: E402
import hbm.frf  # noqa: E402
from hbm import Contact, Structure, frequency_response  # noqa: E402

PEAK = (0.5212270, 0.1592898)  # rad/s, m: benchmarks/chain_peak_reference.py
P1_PEAK = json.loads((Path(__file__).resolve().parent.parent / "tests" / "data" / "periodic_reference.json")
                     .read_text())["jenkins"]["P1"]["peak_amplitude"]["amplitude"]  # m, by shooting


def the_chain():
    K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    s = Structure(np.eye(3), 0.004 * K, K, force=[0.0, 0.0, 0.01])
    return s, [Contact(Macroslip(1.0, 0.02), dof=0), Contact(Macroslip(1.0, 0.05), dofs=(0, 1))]


def timed(from_three=False, one_dof=False, **kw):
    """One FRF of the chain (or of P1, ``one_dof``) and its peak, timed; ``from_three``: the coarse trace at
    H = 3 (``hbm.frf.START_UNKNOWNS = 0``) instead of the H the tolerance predicts for the closed-form sliders."""
    s, cs = the_chain()
    if one_dof:
        s, cs = Structure(np.eye(1), [[0.004]], np.eye(1), force=[0.01]), [Contact(Macroslip(1.0, 0.02), dof=0)]
    before = hbm.frf.START_UNKNOWNS
    hbm.frf.START_UNKNOWNS = 0 if from_three else before
    try:
        t0 = time.perf_counter()
        frf = frequency_response(s, cs, stability=False, **kw)
        pk = frf.peak()
        return time.perf_counter() - t0, frf, pk
    finally:
        hbm.frf.START_UNKNOWNS = before


CASES = {
    "precise, tol 1e-5: H along the curve": dict(omega_range=(0.3, 1.6), accuracy="precise", tol=1e-5),
    "precise, tol 1e-5: H along the curve from 3": dict(omega_range=(0.3, 1.6), accuracy="precise", tol=1e-5,
                                                       from_three=True),
    "precise, tol 1e-5: H = 31 everywhere": dict(omega_range=(0.3, 1.6), accuracy="precise", tol=1e-5, harmonics=31),
    "precise, tol 1e-5: H = 15 everywhere": dict(omega_range=(0.3, 1.6), accuracy="precise", tol=1e-5, harmonics=15),
    "precise, tol 1e-5: H = 7 everywhere": dict(omega_range=(0.3, 1.6), accuracy="precise", tol=1e-5, harmonics=7),
    "precise, tol 1e-5: H = 3 everywhere": dict(omega_range=(0.3, 1.6), accuracy="precise", tol=1e-5, harmonics=3),
    "Jenkins chain, tol 1e-3: H along the curve": dict(omega_range=(0.3, 1.8), tol=1e-3),
    "Jenkins chain, tol 1e-3: H along the curve from 3": dict(omega_range=(0.3, 1.8), tol=1e-3, from_three=True),
    "Jenkins chain, tol 1e-3: H = 15 everywhere": dict(omega_range=(0.3, 1.8), tol=1e-3, harmonics=15),
    "Jenkins chain, tol 1e-3: H = 7 everywhere": dict(omega_range=(0.3, 1.8), tol=1e-3, harmonics=7),
    "Jenkins chain, tol 1e-3: H = 3 everywhere": dict(omega_range=(0.3, 1.8), tol=1e-3, harmonics=3),
    "Jenkins chain, tol 1e-3: H = 1": dict(omega_range=(0.3, 1.8), tol=1e-3, harmonics=1),
    "P1, tol 1e-5: H along the curve": dict(omega_range=(0.6, 1.8), tol=1e-5, one_dof=True),
    "P1, tol 1e-5: H along the curve from 3": dict(omega_range=(0.6, 1.8), tol=1e-5, one_dof=True, from_three=True),
}


def blade():
    from hbm.cli.cases import default_case  # lazily: only --blade needs it

    case = default_case()
    rows = []
    for name, el, model in (("single-mode (given)", case.element, "given"),
                            ("model='auto': all-mode in a window", case.element, "auto"),
                            ("all-mode on the whole curve", AllModeMicroslip(case.element.bar, case.element.load),
                             "given")):
        t0 = time.perf_counter()
        frf = frequency_response(case.blade, el, omega_range=case.omega_range, tol=1e-2, model=model)
        pk = frf.peak()
        rows.append((name, time.perf_counter() - t0, len(frf), pk, float(np.max(frf.error_estimate)),
                     [(sg.start, sg.stop, sg.model) for sg in frf.segments]))
    for name, t, n, pk, e, seg in rows:
        print(f"| {name} | {t:.1f} | {n} | {pk.omega:.2f} | {pk.amplitude:.6e} | {e:.2g} | {seg} |")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--blade", action="store_true")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")  # the estimate's warnings are not what is timed
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                            cwd=Path(__file__).resolve().parent).stdout.strip()
    load0 = os.getloadavg()[0]
    times: dict = {k: [] for k in CASES}
    last: dict = {}
    timed(omega_range=(0.3, 1.6), harmonics=3)  # warm-up
    for _ in range(args.rounds):
        for name, kw in CASES.items():
            t, frf, pk = timed(**kw)
            times[name].append(t)
            last[name] = (frf, pk)
    print(f"commit {commit}; load average {load0:.1f} -> {os.getloadavg()[0]:.1f}; medians of {args.rounds}")
    print("| case | median (s) | points | H per point (points) | peak (rad/s) | peak error | estimate max |")
    print("|---|---|---|---|---|---|---|")
    for name in CASES:
        frf, pk = last[name]
        hs = ", ".join(f"{h}: {int(np.sum(frf.point_harmonics == h))}" for h in sorted(set(frf.point_harmonics)))
        print(f"| {name} | {statistics.median(times[name]):.2f} | {len(frf)} | {hs} | {pk.omega:.6f} | "
              f"{pk.amplitude / (P1_PEAK if name.startswith('P1') else PEAK[1]) - 1.0:+.1e} | "
              f"{float(np.max(frf.error_estimate)):.1e} |")
    for prefix, top in (("precise, tol 1e-5", 31), ("Jenkins chain, tol 1e-3", 15)):  # H for the whole curve:
        rule = sum(statistics.median(times[f"{prefix}: H = {h} everywhere"]) for h in (3, 7, 15, 31) if h <= top)
        print(f"{prefix}: the whole-curve rule (3, 7, ..., {top} in turn over the whole range) {rule:.2f} s; "
              f"H along the curve {statistics.median(times[prefix + ': H along the curve']):.2f} s")
    if args.blade:
        print("| blade, tol 1e-2 | seconds | points | peak (rad/s) | peak (m) | estimate max | segments |")
        print("|---|---|---|---|---|---|---|")
        blade()


if __name__ == "__main__":
    main()
