"""Large structures: a 1000-DOF chain with 10 friction contacts at H = 7, and Hill's stability on
the 200-DOF blade against the FRF without it.

    python3 benchmarks/bench_large.py                  # this tree, medians of 3
    python3 benchmarks/bench_large.py --tree DIR       # the same runs on another checkout (DIR on sys.path first)

1. The chain (:func:`chain`): 1000 unit cells (mass 1 g, spring 4e6 N/m; the first mass tied to
   ground, the last forced by 1 N cos(omega t)), modal damping 1 % on every mode; 10 Macroslip
   contacts (stiffness 2e3 N/m, slip force 0.05 N) from DOFs 99, 199, ..., 999 to ground.  The FRF
   at H = 7 (n_t = 128, the default) over a window around the first natural frequency omega_1
   (99.30 rad/s): +-5 % (the resonance: 2.5 half-power bandwidths each side) and +-20 %, with the
   default accuracy and step settings, ``stability=False``.  Timed: ``frequency_response`` (the
   structure is built beforehand); its modal decomposition (once) is included.
2. The 200-DOF blade of ``examples/blade_200dof.py`` (H = 7, n_t = 256, rtol 1e-9, max_step
   0.03 over 0.8 .. 2 omega_1): the FRF, then ``frf.stable`` (Hill's method on every point).

Wall and CPU time (this process) are reported, medians of ``--repeats``, with the load average
(1 min) before and after: the machine may be shared, and the CPU time is the steadier.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def chain(n: int = 1000, contacts: int = 10):
    """``(structure, contacts, omega_1)`` of the chain of the module docstring."""
    import numpy as np

    from contact_models import Macroslip
    from hbm import Contact, Structure

    m, k = 1e-3, 4e6
    K = np.zeros((n, n))
    i = np.arange(n)
    K[i, i] = 2.0 * k
    K[i[:-1], i[1:]] = -k
    K[i[1:], i[:-1]] = -k
    K[-1, -1] = k
    force = np.zeros(n)
    force[-1] = 1.0
    s = Structure.with_modal_damping(m * np.eye(n), K, ratios=0.01, force=force)
    dofs = np.linspace(n // contacts - 1, n - 1, contacts).astype(int)
    cs = [Contact(Macroslip(stiffness=2e3, slip_force=0.05), dof=int(d)) for d in dofs]
    return s, cs, float(s.natural_frequencies()[0])


def timed(fn):
    """(wall s, CPU s, load before, load after, value) of ``fn()``; every structure's modal
    decomposition is forgotten first (a solve keeps it while the matrices stay the same)."""
    try:
        from hbm.balance.condensation import _MODES
    except ImportError:  # a checkout without the cache
        _MODES = {}
    _MODES.clear()
    l0 = os.getloadavg()[0]
    t0, c0 = time.perf_counter(), time.process_time()
    out = fn()
    return time.perf_counter() - t0, time.process_time() - c0, l0, os.getloadavg()[0], out


def run_chain(repeats: int) -> list[str]:
    from hbm import frequency_response

    t0 = time.perf_counter()
    s, cs, w1 = chain()
    build = time.perf_counter() - t0
    lines = [f"chain: {s.n} DOFs, {len(cs)} contacts, omega_1 = {w1:.4f} rad/s; structure built in {build:.2f} s",
             "| window | points | nfev | peak (m) | wall (median) | CPU (median) | each repeat: wall / CPU (s) | load |",
             "|---|---|---|---|---|---|---|---|"]
    for lo, hi in ((0.95, 1.05), (0.8, 1.2)):
        runs = [timed(lambda: frequency_response(s, cs, omega_range=(lo * w1, hi * w1), harmonics=7,
                                                 stability=False)) for _ in range(repeats)]
        frf = runs[-1][4]
        walls, cpus = [r[0] for r in runs], [r[1] for r in runs]
        lines.append(f"| {lo:g} .. {hi:g} omega_1 | {len(frf)} | {frf.nfev} | {frf.peak().amplitude:.9e} | "
                     f"{statistics.median(walls):.2f} s | {statistics.median(cpus):.2f} s | "
                     + ", ".join(f"{w:.2f} / {c:.2f}" for w, c in zip(walls, cpus))
                     + f" | {runs[0][2]:.1f} / {runs[-1][3]:.1f} |")
    return lines


def run_blade(repeats: int) -> list[str]:
    sys.path.insert(0, str(HERE.parent / "examples"))
    from blade_200dof import blade

    from hbm import frequency_response

    s, cs, tip = blade(100)
    w1 = float(s.natural_frequencies()[0])
    rows = []
    for _ in range(repeats):
        f = timed(lambda: frequency_response(s, cs, omega_range=(0.8 * w1, 2.0 * w1), harmonics=7, n_t=256,
                                             response_dof=tip, rtol=1e-9, max_step=0.03))
        h = timed(lambda: f[4].stable)
        rows.append((f[0], f[1], h[0], h[1], f[2], h[3], len(f[4]), int(f[4].stable.sum())))
    med = lambda j: statistics.median(r[j] for r in rows)  # noqa: E731
    return [f"blade: {s.n} DOFs, {rows[0][6]} points ({rows[0][7]} stable)",
            "| FRF wall | FRF CPU | Hill wall | Hill CPU | (FRF + Hill) / FRF, wall | CPU | each repeat: FRF / Hill wall (s) | load |",
            "|---|---|---|---|---|---|---|---|",
            f"| {med(0):.2f} s | {med(1):.2f} s | {med(2):.2f} s | {med(3):.2f} s | "
            f"{statistics.median((r[0] + r[2]) / r[0] for r in rows):.2f} | "
            f"{statistics.median((r[1] + r[3]) / r[1] for r in rows):.2f} | "
            + ", ".join(f"{r[0]:.2f} / {r[2]:.2f}" for r in rows) + f" | {rows[0][4]:.1f} / {rows[-1][5]:.1f} |"]


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--tree", default=str(HERE.parent), help="the checkout whose hbm is timed")
    ap.add_argument("--only", choices=("chain", "blade"), default=None)
    args = ap.parse_args(argv)
    sys.path.insert(0, str(Path(args.tree).resolve()))
    import hbm

    print(f"hbm from {Path(hbm.__file__).parent}; OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}")
    if args.only in (None, "chain"):
        print("\n".join(run_chain(args.repeats)))
    if args.only in (None, "blade"):
        print("\n".join(run_blade(args.repeats)))


if __name__ == "__main__":
    main()
