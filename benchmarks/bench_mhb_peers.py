"""Speed and accuracy of the multi-harmonic balance against pyHarm 1.2.2 on P1-P3 (docs/performance.md).

In one run: pyHarm (``benchmarks/peers/pyharm_p123.py``, executed by the python of a separate
virtual environment, default ``/work/venvs/pyharm``; never a dependency of this project) at
H = 7, nti = 512, ds_max = 0.005 from omega = 0.6 to 1.8, and our
``hbm.frequency_response(Structure, [Contact(Macroslip, dof=0)], harmonics=H, ...)`` on the same
problems, each timed ``--repeats`` times (medians).  Both peaks are compared with the true
periodic peaks of ``tests/data/periodic_reference.json`` (``benchmarks/periodic_reference.py``),
and the time ratio pyHarm / ours is formed from the two medians of this run.  The machine's load
average is recorded before and after.

Problems: m = k = 1, F = 0.01, Jenkins kt = 1 to ground; P1 c = 0.004, fs = 0.02; P2 c = 0.004,
fs = 0.005; P3 c = 0.0002, fs = 0.02.

Run: ``PYTHONPATH=. python3 benchmarks/bench_mhb_peers.py [--harmonics tol=1e-5,7] [--repeats 3]
[--pyharm-python PATH] [--skip-peer] [--no-stability] [--json OUT]``; ``--harmonics`` takes H
values (``harmonics=H`` at the default tol) and ``tol=X`` entries (the front door at ``tol=X``, its
H chosen along the curve).  Without ``hbm.Structure`` (the mhb work not
merged) only the peer's side is measured, and the table says so.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PEER = ROOT / "benchmarks" / "peers" / "pyharm_p123.py"
REFERENCE = ROOT / "tests" / "data" / "periodic_reference.json"
PYHARM_PYTHON = Path(os.environ.get("PYHARM_PYTHON", "/work/venvs/pyharm/bin/python"))
PROBLEMS = {"P1": (0.004, 0.02), "P2": (0.004, 0.005), "P3": (0.0002, 0.02)}


def run_peer(python: Path, repeats: int, timeout: float) -> dict:
    """The peer script's JSON, or {"error": why}."""
    if not python.exists():
        return {"error": f"no pyHarm venv python at {python} (create it: python3 -m venv /work/venvs/pyharm && "
                         "/work/venvs/pyharm/bin/pip install pyharm-os==1.2.2)"}
    cmd = [str(python), str(PEER), "--repeats", str(repeats)]
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}  # keep our package out of the venv
    try:  # in a scratch directory: pyHarm writes a .pyHarm/ state folder into its working directory
        with tempfile.TemporaryDirectory() as scratch:
            proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env, cwd=scratch)
    except subprocess.TimeoutExpired:
        return {"error": f"pyHarm did not finish in {timeout:.0f} s"}
    lines = [ln for ln in proc.stdout.splitlines() if ln.startswith("{")]
    if proc.returncode != 0 or not lines:
        return {"error": f"pyHarm exited with {proc.returncode}: {proc.stderr.strip().splitlines()[-1:]}"}
    return json.loads(lines[-1])


def ours_available() -> str | None:
    """None if hbm has the structure interface, else why not."""
    import hbm

    missing = [n for n in ("Structure", "Contact") if not hasattr(hbm, n)]
    if missing:
        return f"hbm has no {', '.join(missing)} yet (the mhb branch is not merged): our side not timed"
    return None


def run_ours(name: str, H: str, stability: bool = True):
    """One timed FRF; ``H`` an integer (``harmonics=H``) or ``tol=X`` (the front door at that tol)."""
    import numpy as np

    import hbm
    from contact_models import Macroslip

    c, fs = PROBLEMS[name]
    s = hbm.Structure(np.eye(1), np.array([[c]]), np.eye(1), force=np.array([0.01]))
    knob = {"harmonics": int(H)} if H.isdigit() else {"tol": float(H.removeprefix("tol="))}
    t0 = time.perf_counter()
    frf = hbm.frequency_response(s, [hbm.Contact(Macroslip(stiffness=1.0, slip_force=fs), dof=0)],
                                 omega_range=(0.6, 1.8), stability=stability, **knob)
    pk = frf.peak()
    return time.perf_counter() - t0, pk, frf


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--harmonics", default="tol=1e-5,7",
                    help="comma-separated H values or tol=X entries (the front door at that tol)")
    ap.add_argument("--no-stability", action="store_true", help="time our FRF without Hill's method")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--pyharm-python", type=Path, default=PYHARM_PYTHON)
    ap.add_argument("--skip-peer", action="store_true")
    ap.add_argument("--timeout", type=float, default=3600.0)
    ap.add_argument("--json", type=Path, default=None)
    args = ap.parse_args(argv)
    ref = json.loads(REFERENCE.read_text())["jenkins"]
    out = {"loadavg_start": list(os.getloadavg()), "repeats": args.repeats}

    # ours first, then the peer, then ours again: the medians of both passes bracket the peer's
    why = ours_available()
    hs = args.harmonics.split(",")
    stab = not args.no_stability
    out["our_stability"] = stab
    ours: dict = {}
    if why is None:
        for name in PROBLEMS:
            for H in hs:
                run_ours(name, H, stab)  # warm-up
    for rnd in range(2 if not args.skip_peer else 1):
        if why is None:
            for _ in range(args.repeats):
                for name in PROBLEMS:
                    for H in hs:
                        wall, pk, frf = run_ours(name, H, stab)
                        d = ours.setdefault(f"{name} H={H}", {"times": [], "problem": name, "H": H})
                        d["times"].append(wall)
                        d["peak_omega"], d["peak_amplitude"] = float(pk.omega), float(pk.amplitude)
                        d["points"] = int(len(frf.omega))
        if rnd == 0 and not args.skip_peer:
            out["pyharm"] = run_peer(args.pyharm_python, args.repeats, args.timeout)
    out["loadavg_end"] = list(os.getloadavg())
    out["ours"] = ours if why is None else {"error": why}

    rows = []
    peer = out.get("pyharm", {}).get("problems", {})
    for name in PROBLEMS:
        true = ref[name]["peak_amplitude"]
        p = peer.get(name)
        if p:
            rows.append([name, "pyHarm H=7", f"{p['seconds_median']:.2f} s", p["points"],
                         f"{p['peak_omega'] / true['omega'] - 1:+.1e}", f"{p['peak_amplitude'] / true['amplitude'] - 1:+.1e}", ""])
            if "refined_peak_omega" in p:
                rows.append([name, "pyHarm H=7, peak refined (untimed)", "-", "-",
                             f"{p['refined_peak_omega'] / true['omega'] - 1:+.1e}",
                             f"{p['refined_peak_amplitude'] / true['amplitude'] - 1:+.1e}", ""])
        for key, d in ours.items():
            if d["problem"] != name:
                continue
            med = statistics.median(d["times"])
            d["seconds_median"] = med
            ratio = f"{p['seconds_median'] / med:.1f}" if p else "-"
            d["omega_error"] = d["peak_omega"] / true["omega"] - 1
            d["amplitude_error"] = d["peak_amplitude"] / true["amplitude"] - 1
            rows.append([name, f"hbm {d['H']}" if d["H"].startswith("tol") else f"hbm H={d['H']}", f"{med:.3f} s", d["points"], f"{d['omega_error']:+.1e}",
                         f"{d['amplitude_error']:+.1e}", ratio])
    head = ["problem", "solver", "median time", "points", "peak omega err", "peak amplitude err", "pyHarm/ours"]
    print("| " + " | ".join(head) + " |\n|" + "---|" * len(head))
    for r in rows:
        print("| " + " | ".join(str(c) for c in r) + " |")
    if why:
        print(f"\n{why}")
    if "error" in out.get("pyharm", {}):
        print(f"\npyHarm: {out['pyharm']['error']}")
    print(f"\nload average {out['loadavg_start'][0]:.1f} at the start, {out['loadavg_end'][0]:.1f} at the end; "
          f"python {sys.version.split()[0]}")
    if args.json:
        args.json.write_text(json.dumps(out, indent=1) + "\n")


if __name__ == "__main__":
    main()
