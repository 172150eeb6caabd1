"""P1-P3 at ``accuracy="precise"`` (the call of ``bench_steps.py``) in two source trees, alternating, with a fingerprint of the bits.

Each round runs every tree in its own process (``cwd`` = the tree, so that its ``hbm`` and
``contact_models`` are imported): per problem a warm-up, then the best of ``--repeats`` timed
solves (the response and its refined peak).  Prints, per problem, the median over the rounds of
each tree, the ratio new/old, and per tree a SHA-256 prefix of the points' omega, amplitude and
residual norms with the peak (repr, all digits), so that "the same answers" is checked bit for bit::

    OPENBLAS_NUM_THREADS=1 python3 benchmarks/bench_steps_trees.py OLD_TREE NEW_TREE [--rounds 5]

(``docs/performance.md``, "Step control by accuracy").
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys

CHILD = r'''
import hashlib, json, sys, time, warnings
import numpy as np
sys.path.insert(0, ".")
from contact_models import Macroslip
from hbm import Contact, Structure, frequency_response
warnings.simplefilter("ignore")
PROBLEMS = {"P1": (0.004, 0.02), "P2": (0.004, 0.005), "P3": (0.0002, 0.02)}

def run(c, fs):
    s = Structure(np.eye(1), np.array([[c]]), np.eye(1), force=[0.01])
    frf = frequency_response(s, [Contact(Macroslip(1.0, fs), dof=0)], omega_range=(0.6, 1.8),
                             accuracy="precise", stability=False)
    return frf, frf.peak()

out = {}
for name, (c, fs) in PROBLEMS.items():
    frf, pk = run(c, fs)
    times = []
    for _ in range(int(sys.argv[1])):
        t0 = time.perf_counter()
        run(c, fs)
        times.append(time.perf_counter() - t0)
    h = hashlib.sha256()
    for a in (frf.omega, frf.amplitude, frf.residual_norm):
        h.update(np.ascontiguousarray(a, dtype=float).tobytes())
    out[name] = {"best": min(times), "points": len(frf), "peak": repr((pk.omega, pk.amplitude)),
                 "sha": h.hexdigest()[:16]}
print(json.dumps(out))
'''


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args(argv)
    trees = {"old": args.old, "new": args.new}
    env = dict(os.environ, OPENBLAS_NUM_THREADS=os.environ.get("OPENBLAS_NUM_THREADS", "1"))
    env.pop("PYTHONPATH", None)
    res = {k: [] for k in trees}
    print(f"load average at the start: {os.getloadavg()[0]:.2f}")
    for _ in range(args.rounds):
        for k, tree in trees.items():
            p = subprocess.run([sys.executable, "-c", CHILD, str(args.repeats)], cwd=tree, env=env,
                               capture_output=True, text=True, check=True)
            res[k].append(json.loads(p.stdout.strip().splitlines()[-1]))
    print(f"load average at the end: {os.getloadavg()[0]:.2f}")
    for name in res["old"][0]:
        t = {k: statistics.median(r[name]["best"] for r in res[k]) for k in trees}
        print(f"{name}: old {t['old'] * 1e3:.1f} ms, new {t['new'] * 1e3:.1f} ms, new/old {t['new'] / t['old']:.3f}")
        for k in trees:
            r = res[k][0][name]
            print(f"    {k}: {r['points']} points, sha256 {r['sha']}, peak {r['peak']}")


if __name__ == "__main__":
    main()
