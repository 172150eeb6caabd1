"""What accuracy costs in the multi-harmonic balance: peak error against the true periodic peak
versus time, for H in 1, 3, 5, 7, 11, 15, 21 and two sample counts.

Problems P1-P3 (m = k = 1, F = 0.01, Jenkins k = 1 to ground, omega 0.6..1.8; P1 c = 0.004,
F_s = 0.02; P2 c = 0.004, F_s = 0.005; P3 c = 0.0002, F_s = 0.02).  True peaks:
``tests/data/periodic_reference.json`` (``hbm.reference.shooting``).  Each configuration is timed
``--repeats`` times (median; the whole FRF with the refined peak, ``max_step`` 0.1, stability off
and, in a separate column, on); the load average is recorded.

Run: ``PYTHONPATH=. python3 benchmarks/bench_mhb_accuracy.py [--repeats 3] [--json OUT]``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import time
from pathlib import Path

import numpy as np

from contact_models import Macroslip
from contact_models.base import default_samples
from hbm import Contact, Structure, frequency_response

ROOT = Path(__file__).resolve().parent.parent
REF = json.loads((ROOT / "tests" / "data" / "periodic_reference.json").read_text())["jenkins"]
PROBLEMS = {"P1": (0.004, 0.02), "P2": (0.004, 0.005), "P3": (0.0002, 0.02)}
HARMONICS = (1, 3, 5, 7, 11, 15, 21)


def run(name: str, H: int, n_t: int, stability: bool) -> tuple[float, float, int]:
    c, fs = PROBLEMS[name]
    s = Structure(np.eye(1), np.array([[c]]), np.eye(1), force=[0.01])
    t0 = time.perf_counter()
    frf = frequency_response(s, [Contact(Macroslip(1.0, fs), dof=0)], omega_range=(0.6, 1.8), harmonics=H,
                             n_t=n_t, max_step=0.1, stability=stability)
    pk = frf.peak()
    return time.perf_counter() - t0, pk.amplitude, len(frf)


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--json", type=Path, default=None)
    args = ap.parse_args(argv)
    out = {"loadavg_start": list(os.getloadavg()), "rows": []}
    print("| problem | H | n_t | points | peak amplitude error | median time (s) | with stability (s) |")
    print("|---|---|---|---|---|---|---|")
    for name in PROBLEMS:
        true = REF[name]["peak_amplitude"]["amplitude"]
        for H in HARMONICS:
            for n_t in sorted({default_samples(H), 2048}):
                times = []
                for _ in range(args.repeats):
                    t, amp, pts = run(name, H, n_t, False)
                    times.append(t)
                t_stab = statistics.median(run(name, H, n_t, True)[0] for _ in range(args.repeats))
                row = dict(problem=name, H=H, n_t=n_t, points=pts, error=amp / true - 1.0,
                           seconds=statistics.median(times), seconds_stability=t_stab)
                out["rows"].append(row)
                print(f"| {name} | {H} | {n_t} | {pts} | {row['error']:+.1e} | {row['seconds']:.3f} | {t_stab:.3f} |",
                      flush=True)
    out["loadavg_end"] = list(os.getloadavg())
    print(f"\nload average {out['loadavg_start'][0]:.1f} at the start, {out['loadavg_end'][0]:.1f} at the end")
    if args.json:
        args.json.write_text(json.dumps(out, indent=1) + "\n")
    return out


if __name__ == "__main__":
    main()
