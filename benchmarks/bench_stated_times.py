"""The times ``python3 -m hbm --help`` states: the main job and each ``--model``, measured.

    python3 benchmarks/bench_stated_times.py [--rounds 3]

Each variant (``--model auto``, the default; ``peak``; ``given``) runs as a new process with this
tree first on ``PYTHONPATH``, in its own output folder, ``--rounds`` times interleaved (peak,
peak, given, auto, ...); printed per variant, as one Markdown row: the median wall-clock time
(``time.perf_counter`` around the child), the median CPU time of the child (user + system,
``resource.getrusage(RUSAGE_CHILDREN)``), and the job's last
line (its peak).  The machine's load average before and after is printed too: on a loaded
machine the wall time grows with the load and the CPU time is the steadier number.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
#: The variants timed: --model values (the default first).
MODELS = ("auto", "peak", "given")


def run(model: str, out: Path) -> tuple[float, float, str]:
    """One job: ``(wall s, CPU s of the child, its last line)``."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "hbm", "--model", model, "--out", str(out)], env=env, cwd=out,
                          capture_output=True, text=True, check=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, proc.stdout.strip().splitlines()[-1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    load0 = os.getloadavg()
    times: dict = {m: [] for m in MODELS}
    last: dict = {}
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(args.rounds):
            for m in MODELS:
                out = Path(tmp) / f"{m}-{r}"
                out.mkdir()
                wall, cpu, last[m] = run(m, out)
                times[m].append((wall, cpu))
    load1 = os.getloadavg()
    print(f"load average before {load0[0]:.1f}, after {load1[0]:.1f}; {args.rounds} rounds, {os.cpu_count()} cores")
    print("| --model | wall, median (s) | CPU, median (s) | last line |")
    print("|---|---|---|---|")
    for m in MODELS:
        wall = statistics.median(t[0] for t in times[m])
        cpu = statistics.median(t[1] for t in times[m])
        print(f"| {m} | {wall:.2f} | {cpu:.2f} | {last[m][:90]} |")


if __name__ == "__main__":
    main()
