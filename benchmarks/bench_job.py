"""The main job's time, ``python3 -m hbm``, against the code of an earlier commit.

    python3 benchmarks/bench_job.py [--base COMMIT] [--rounds 5] [--profile]

The base commit's tree is checked out with ``git archive`` into a temporary folder; the two
trees' jobs run alternately (base, this tree, base, ...) as new processes, each in its own
output folder, and the medians of wall-clock time (``time.perf_counter`` around the child) and of
the child's CPU time (user + system, ``resource.getrusage(RUSAGE_CHILDREN)``, so BLAS threads and an
earlier tree's forked figure process are counted) are printed as one Markdown row per tree, with the load
average before and after.  Both trees' last lines (the peak) are printed too.

``--profile`` adds where the job's time goes, tree by tree: one run in a process that times its
phases (the interpreter's start, importing ``hbm.cli.main``, ``frequency_response``, the figure, the
CSV; in a tree that still solved the all-mode peak after the curve, that solve), medians over the
rounds.  In a tree that drew the figure in a forked process while the peak was solved, the figure's
row is the wait for that process.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))
from common import checkout  # noqa: E402  (the benchmarks' shared helpers)

#: Run in a child with the tree first on sys.path: the job with its phases timed.
PHASES = r"""
import sys, time, json, io, contextlib
t0 = time.perf_counter()
sys.path.insert(0, sys.argv[1])
import hbm.cli.main as m
t1 = time.perf_counter()
out = {"import hbm.cli.main": t1 - t0}
def timed(owner, name, key):
    f = getattr(owner, name)
    def g(*a, **k):
        t = time.perf_counter()
        try:
            return f(*a, **k)
        finally:
            out[key] = out.get(key, 0.0) + time.perf_counter() - t
    setattr(owner, name, g)
timed(m, "frequency_response", "frequency_response (the curve, and the single-mode one beside it)")
for name in ("physical_peak", "refine_peak"):  # an earlier tree's all-mode peak, solved after the curve
    if hasattr(m, name):
        timed(m, name, "all-mode peak (an earlier tree's own solve)")
if hasattr(m, "job_figure"):
    timed(m, "job_figure", "figure")
elif hasattr(m, "_figure"):
    timed(m, "_figure", "figure")
else:
    import hbm.cli.figure as fg
    timed(fg.JobFigure, "finish", "figure")
from hbm.result import FrequencyResponse
timed(FrequencyResponse, "to_csv", "frf.csv")
with contextlib.redirect_stdout(io.StringIO()):
    m.main(["--out", sys.argv[2]])
out["job (main)"] = time.perf_counter() - t1
print(json.dumps(out))
"""


def job(tree: Path, out: Path) -> tuple[float, float, str]:
    """One ``python3 -m hbm --out out`` in ``tree``: (wall s, child CPU s, its last line)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    run = subprocess.run([sys.executable, "-m", "hbm", "--out", str(out)], cwd=tree, capture_output=True, text=True)
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if run.returncode:
        raise RuntimeError(f"the job in {tree} failed:\n{run.stderr[-3000:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, run.stdout.strip().splitlines()[-1]


def phases(tree: Path, out: Path) -> dict:
    start = time.perf_counter()
    subprocess.run([sys.executable, "-c", "pass"], check=True)
    interpreter = time.perf_counter() - start
    run = subprocess.run([sys.executable, "-c", PHASES, str(tree), str(out)], cwd=tempfile.gettempdir(),
                         capture_output=True, text=True)
    if run.returncode:
        raise RuntimeError(f"the phases in {tree} failed:\n{run.stderr[-3000:]}")
    return {"interpreter start (python3 -c pass)": interpreter} | json.loads(run.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--base", default="30383f8", help="the commit compared against")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--profile", action="store_true")
    args = ap.parse_args()
    trees = {args.base: checkout(args.base), "this tree": ROOT}
    outs = {name: Path(tempfile.mkdtemp(prefix="job-")) for name in trees}
    load0 = os.getloadavg()[0]
    times: dict = {name: [] for name in trees}
    last: dict = {}
    for _ in range(args.rounds):
        for name, tree in trees.items():
            wall, cpu, last[name] = job(tree, outs[name])
            times[name].append((wall, cpu))
    load1 = os.getloadavg()[0]
    print(f"load average {load0:.2f} at the start, {load1:.2f} at the end; {args.rounds} rounds")
    print("| code | wall, median | CPU, median | walls | CPUs |\n|---|---|---|---|---|")
    for name, ts in times.items():
        walls, cpus = [t[0] for t in ts], [t[1] for t in ts]
        print(f"| {name} | {statistics.median(walls):.2f} s | {statistics.median(cpus):.2f} s | "
              f"{' '.join(f'{w:.2f}' for w in walls)} | {' '.join(f'{c:.2f}' for c in cpus)} |")
    for name, line in last.items():
        print(f"{name}: {line}")
    if args.profile:
        rows: dict = {}
        for _ in range(args.rounds):
            for name, tree in trees.items():
                for key, value in phases(tree, outs[name]).items():
                    rows.setdefault(key, {}).setdefault(name, []).append(value)
        print("\n| phase | " + " | ".join(trees) + " |\n|---|" + "---|" * len(trees))
        for key, by in rows.items():
            print(f"| {key} | " + " | ".join(f"{statistics.median(by[n]):.3f} s" if n in by else "-" for n in trees)
                  + " |")


if __name__ == "__main__":
    main()
