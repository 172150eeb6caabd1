"""The true periodic peak of the 3-DOF chain's response DOF (first-harmonic amplitude of DOF 2
over omega near its first resonance), by shooting on the event-driven exact integration
(``hbm.periodic_peak``, 1024 steps, 21 harmonics stored), for ``benchmarks/bench_steps.py``.

The chain is that of ``benchmarks/periodic_reference.py`` (M = I, K of unit springs
ground-1-2-3, C = 0.004 K, F = 0.01 at DOF 2, Jenkins kt = 1, fs = 0.02 DOF 0 to ground and
kt = 1, fs = 0.05 between DOFs 0 and 1).  The bracket is +-1.5 % around ``--omega`` (default
0.5212, the balance's peak); the start is the periodic response there from the stuck state.

Run: ``PYTHONPATH=. python3 benchmarks/chain_peak_reference.py [--omega 0.5212]``; prints JSON.
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

import hbm
from contact_models import Macroslip


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--omega", type=float, default=0.5212)
    args = ap.parse_args(argv)
    K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    system = (np.eye(3), 0.004 * K, K, np.array([0.0, 0.0, 0.01]))
    cs = [hbm.Contact(Macroslip(stiffness=1.0, slip_force=0.02), dof=0),
          hbm.Contact(Macroslip(stiffness=1.0, slip_force=0.05), dofs=(0, 1))]
    t0 = time.perf_counter()
    r0 = hbm.periodic_response(system, cs, omega=args.omega, steps=1024, harmonics=21)
    pk = hbm.periodic_peak(system, cs, bracket=(args.omega * 0.985, args.omega * 1.015), dof=2, initial=r0,
                           steps=1024, harmonics=21, xtol=1e-10)
    print(json.dumps({"omega": pk.omega, "amplitude": pk.value, "success": bool(pk.success),
                      "evaluations": pk.evaluations, "seconds": time.perf_counter() - t0}))


if __name__ == "__main__":
    main()
