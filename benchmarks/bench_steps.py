"""Step control by accuracy: ``accuracy="precise"`` on P1-P3 against pyHarm 1.2.2 at H = 7, in one run.

Three rounds; each round times ours on P1, P2, P3 (``frequency_response(Structure, [Contact(Macroslip)],
omega_range=(0.6, 1.8), accuracy="precise", stability=False)`` with the refined peak) and then the
peer once per problem (``benchmarks/peers/pyharm_p123.py --repeats 1`` in its own venv: H = 7,
nti = 512, ds_max = 0.005; its numba warm-up untimed), so that both are timed under the same load.
Medians of the three rounds, the ratio pyHarm / ours per problem; errors of both peaks against
``tests/data/periodic_reference.json``; the 3-DOF chain over 0.3..1.6 rad/s at the same preset;
the load average and the commit.

Run: ``PYTHONPATH=. python3 benchmarks/bench_steps.py [--rounds 3] [--skip-peer]``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_mhb_peers import PROBLEMS, PYHARM_PYTHON, REFERENCE, run_peer  # noqa: E402

from contact_models import Macroslip  # noqa: E402
from hbm import Contact, Structure, frequency_response  # noqa: E402


def ours(name: str):
    c, fs = PROBLEMS[name]
    s = Structure(np.eye(1), np.array([[c]]), np.eye(1), force=[0.01])
    t0 = time.perf_counter()
    frf = frequency_response(s, [Contact(Macroslip(1.0, fs), dof=0)], omega_range=(0.6, 1.8), accuracy="precise",
                             stability=False)
    pk = frf.peak()
    return time.perf_counter() - t0, pk, frf


def chain():
    K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    s = Structure(np.eye(3), 0.004 * K, K, force=[0.0, 0.0, 0.01])
    cs = [Contact(Macroslip(1.0, 0.02), dof=0), Contact(Macroslip(1.0, 0.05), dofs=(0, 1))]
    t0 = time.perf_counter()
    frf = frequency_response(s, cs, omega_range=(0.3, 1.6), accuracy="precise", stability=False)
    pk = frf.peak()
    return time.perf_counter() - t0, pk, frf


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--skip-peer", action="store_true")
    ap.add_argument("--pyharm-python", type=Path, default=PYHARM_PYTHON)
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")  # the error estimate's warning (the tol default) is not what is timed
    ref = json.loads(REFERENCE.read_text())["jenkins"]
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                            cwd=Path(__file__).resolve().parent).stdout.strip()
    out = {"commit": commit, "loadavg_start": list(os.getloadavg()), "ours": {}, "peer": {}, "chain": []}
    for name in PROBLEMS:
        ours(name)  # warm-up
    for _ in range(args.rounds):
        for name in PROBLEMS:
            wall, pk, frf = ours(name)
            d = out["ours"].setdefault(name, {"times": []})
            d["times"].append(wall)
            d.update(points=len(frf), peak_amplitude=pk.amplitude, coarse=frf.coarse.tolist())
        if not args.skip_peer:
            p = run_peer(args.pyharm_python, 1, 3600.0)
            for name, r in p.get("problems", {}).items():
                d = out["peer"].setdefault(name, {"times": []})
                d["times"].append(r["seconds_median"])
                d.update(points=r["points"], peak_amplitude=r["peak_amplitude"])
            if "error" in p:
                out["peer_error"] = p["error"]
        wall, pk, frf = chain()
        out["chain"].append({"seconds": wall, "points": len(frf), "peak_omega": pk.omega,
                             "peak_amplitude": pk.amplitude, "coarse": frf.coarse.tolist()})
    out["loadavg_end"] = list(os.getloadavg())
    print(f"commit {commit}; load average {out['loadavg_start'][0]:.1f} -> {out['loadavg_end'][0]:.1f}")
    print("| problem | ours: points | ours: median (s) | peak error | pyHarm H=7: points | median (s) | peak error "
          "| pyHarm/ours |\n|---|---|---|---|---|---|---|---|")
    for name in PROBLEMS:
        true = ref[name]["peak_amplitude"]["amplitude"]
        o, p = out["ours"][name], out["peer"].get(name)
        mo = statistics.median(o["times"])
        row = [name, o["points"], f"{mo:.3f}", f"{o['peak_amplitude'] / true - 1:+.1e}"]
        if p:
            mp = statistics.median(p["times"])
            row += [p["points"], f"{mp:.2f}", f"{p['peak_amplitude'] / true - 1:+.1e}", f"{mp / mo:.1f}"]
        else:
            row += ["-"] * 4
        print("| " + " | ".join(map(str, row)) + " |")
    ch = out["chain"]
    print(f"chain 0.3..1.6 rad/s, precise: {ch[0]['points']} points, median "
          f"{statistics.median(c['seconds'] for c in ch):.2f} s, peak {ch[0]['peak_omega']:.6f} rad/s "
          f"{ch[0]['peak_amplitude']:.6g} m, coarse {ch[0]['coarse']}")
    print(json.dumps(out))


if __name__ == "__main__":
    main()
