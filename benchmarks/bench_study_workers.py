"""The design chart study (57 runs) on one process and on two worker processes: wall, CPU, tables.

``examples/scenes/design_chart_study.toml`` run ``--repeats`` times, interleaved: serially in this
process, then on a two-process pool (``executor="processes"``, ``workers=2``, the pool's start
included), each into a fresh folder.  Reported per setting: the median wall time, the median CPU
time of every process involved (this one plus its finished children, ``RUSAGE_CHILDREN``), the
speed-up serial / two workers from the two medians, whether every result table (all columns but
``time_s``) is identical to the first serial one, and the load average before and after.

The CPU time is the check on the pool's own cost: two workers doing the serial run's work spend
the same CPU, and their wall is half the serial one only when two cores are free for them.  So
that a speed-up measured on a shared machine can be read, each repeat also times the machine's
ceiling: two pure-Python loops of fixed work one after the other, then on two processes (the
speed-up any two-process code could have had at that moment).

Run: ``PYTHONPATH=. python3 benchmarks/bench_study_workers.py [--repeats 3] [--json OUT]``.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import tempfile
import time
from pathlib import Path

from hbm.study import Study, run_study

ROOT = Path(__file__).resolve().parent.parent
CHART = ROOT / "examples" / "scenes" / "design_chart_study.toml"
SETTINGS = {"serial": ("serial", {}), "2 workers": ("processes", {"workers": 2})}


def busy(n: int = 3_000_000) -> int:
    """Fixed pure-Python work (no BLAS, no I/O)."""
    s = 0
    for i in range(n):
        s += i
    return s


def ceiling() -> float:
    """Two loops of :func:`busy` one after the other, over the same two on two processes."""
    import multiprocessing

    t0 = time.perf_counter()
    busy(), busy()
    one = time.perf_counter() - t0
    with multiprocessing.get_context("fork").Pool(2) as pool:
        pool.map(busy, [1, 1])  # the pool started before the timing
        t0 = time.perf_counter()
        pool.map(busy, [3_000_000, 3_000_000], chunksize=1)
        two = time.perf_counter() - t0
    return one / two


def children_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--json", type=Path, default=None)
    args = ap.parse_args(argv)
    study = Study.from_scene(CHART)
    out = {"runs": len(study.points), "loadavg_start": list(os.getloadavg()), "wall": {}, "cpu": {}}
    tables = []
    out["ceiling"] = []
    for _ in range(args.repeats):
        out["ceiling"].append(ceiling())
        for name, (executor, kw) in SETTINGS.items():
            with tempfile.TemporaryDirectory() as tmp:
                t0, c0, k0 = time.perf_counter(), time.process_time(), children_cpu()
                result = run_study(study, tmp, executor=executor, formats=("csv",), **kw)
                wall = time.perf_counter() - t0
                cpu = time.process_time() - c0 + children_cpu() - k0
            if not result.success:
                raise RuntimeError(result.message)
            out["wall"].setdefault(name, []).append(wall)
            out["cpu"].setdefault(name, []).append(cpu)
            tables.append([{k: v for k, v in row.items() if k != "time_s"} for row in result.rows])
    out["loadavg_end"] = list(os.getloadavg())
    out["identical"] = all(t == tables[0] for t in tables)
    med = {k: statistics.median(v) for k, v in out["wall"].items()}
    cpu = {k: statistics.median(v) for k, v in out["cpu"].items()}
    out["speedup"] = med["serial"] / med["2 workers"]
    print("| setting | median wall | median CPU | walls |\n|---|---|---|---|")
    for name in SETTINGS:
        walls = " ".join(f"{w:.2f}" for w in out["wall"][name])
        print(f"| {name} | {med[name]:.2f} s | {cpu[name]:.2f} s | {walls} |")
    out["ceiling_median"] = statistics.median(out["ceiling"])
    print(f"\n{out['runs']} runs; speed-up serial / 2 workers {out['speedup']:.2f} (the machine's ceiling: "
          f"{out['ceiling_median']:.2f}); tables identical: "
          f"{out['identical']}; load average {out['loadavg_start'][0]:.1f} at the start, "
          f"{out['loadavg_end'][0]:.1f} at the end")
    if args.json:
        args.json.write_text(json.dumps(out, indent=1) + "\n")
    return out


if __name__ == "__main__":
    main()
