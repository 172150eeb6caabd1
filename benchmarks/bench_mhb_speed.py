"""Speed of the multi-harmonic balance at the H that reaches 1e-5 against pyHarm 1.2.2 at H = 7
on P1-P3 (docs/performance.md), in one run.

Ours: ``frequency_response(Structure, [Contact(Macroslip)], harmonics=15, n_t=2048,
max_step=0.1, stability=False)`` with the refined peak (the "precise" preset's H and n_t),
timed ``--repeats`` times before and after the peer (medians of both passes).  The peer:
``benchmarks/peers/pyharm_p123.py`` in its own venv, through ``bench_mhb_peers.run_peer`` (the
ref branch's driver).  Errors against ``tests/data/periodic_reference.json``; load average
before and after.

Run: ``PYTHONPATH=. python3 benchmarks/bench_mhb_speed.py [--repeats 3]``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_mhb_peers import PROBLEMS, PYHARM_PYTHON, REFERENCE, run_peer  # noqa: E402

from contact_models import Macroslip  # noqa: E402
from hbm import Contact, Structure, frequency_response  # noqa: E402
from hbm.balance.presets import harmonic_knobs  # noqa: E402


def ours(name: str) -> tuple[float, float]:
    c, fs = PROBLEMS[name]
    H, n_t = harmonic_knobs("precise")
    s = Structure(np.eye(1), np.array([[c]]), np.eye(1), force=[0.01])
    t0 = time.perf_counter()
    frf = frequency_response(s, [Contact(Macroslip(1.0, fs), dof=0)], omega_range=(0.6, 1.8), harmonics=H,
                             n_t=n_t, max_step=0.1, stability=False)
    return time.perf_counter() - t0, frf.peak().amplitude


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args(argv)
    ref = json.loads(REFERENCE.read_text())["jenkins"]
    load0 = os.getloadavg()
    runs = {name: [] for name in PROBLEMS}
    for name in PROBLEMS:
        ours(name)  # warm-up
        runs[name] += [ours(name) for _ in range(args.repeats)]
    peer = run_peer(PYHARM_PYTHON, args.repeats, 3600.0)
    for name in PROBLEMS:
        runs[name] += [ours(name) for _ in range(args.repeats)]
    print("| problem | ours (H = 15, n_t = 2048) | error | pyHarm H = 7 | error | pyHarm/ours |\n|---|---|---|---|---|---|")
    for name in PROBLEMS:
        true = ref[name]["peak_amplitude"]["amplitude"]
        t = statistics.median(r[0] for r in runs[name])
        p = peer.get("problems", {}).get(name)
        peer_cols = (f"{p['seconds_median']:.2f} s | {p['peak_amplitude'] / true - 1:+.1e} | "
                     f"{p['seconds_median'] / t:.1f}") if p else f"- | - | {peer.get('error', '-')}"
        print(f"| {name} | {t:.3f} s | {runs[name][0][1] / true - 1:+.1e} | {peer_cols} |")
    print(f"\nload average {load0[0]:.1f} before, {os.getloadavg()[0]:.1f} after")


if __name__ == "__main__":
    main()
