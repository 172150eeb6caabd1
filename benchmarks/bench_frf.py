"""Benchmark of ``hbm.frequency_response``: the default case and a Jenkins damper.

Each case: ``frequency_response(...)`` then ``.peak()``, timed ``REPEATS`` times (wall clock
and process CPU time), median reported, with the point count, the counters and the peak's
relative error against an independent reference:

- default case (``python3 -m hbm``): the same FRF at rtol = 1e-9;
- blade + Macroslip(1, 1), m = k = 1, F = 0.5, zeta = 1e-2 and 1e-4: the quartic check (for
  each amplitude the balance is a quartic in omega; the peak is the largest amplitude at which
  it has a real root).

Run ``python benchmarks/bench_frf.py``; prints a Markdown table (docs/performance.md).
"""

from __future__ import annotations

import math
import platform
import statistics
import time

import numpy as np
from scipy.optimize import brentq

from hbm import Blade, frequency_response
from hbm.cli.cases import default_case

REPEATS = 5


def macroslip(stiffness, slip_force):
    try:
        from contact_models import Macroslip
    except ImportError:
        from contact_models.macroslip import Macroslip
    return Macroslip(stiffness=stiffness, slip_force=slip_force)


def jenkins_peak(blade, kd, slip, bracket):
    """Independent peak of blade + Jenkins: largest a with a real root of the quartic in omega."""
    m, c, k, F = blade.mass, blade.damping, blade.stiffness, blade.force

    def df(a):
        if a <= slip / kd:
            return kd, 0.0
        psi = math.acos(1 - 2 * slip / (kd * a))
        return kd * (psi - math.sin(2 * psi) / 2) / math.pi, 4 * slip * (1 - slip / (kd * a)) / (math.pi * a)

    def min_over_w(a):
        p, q = df(a)
        K = k + p
        roots = np.roots([4 * m * m, 0.0, 2 * (c * c - 2 * m * K), 2 * c * q])
        return min(((K - m * r.real**2) ** 2 + (c * r.real + q) ** 2, r.real)
                   for r in roots if abs(r.imag) <= 1e-9 * abs(r) and r.real > 0)

    a = brentq(lambda a: a * a * min_over_w(a)[0] - F * F, *bracket, xtol=1e-15, rtol=1e-15)
    return min_over_w(a)[1], a


def timed(run):
    walls, cpus = [], []
    for _ in range(REPEATS):
        t, p = time.perf_counter(), time.process_time()
        frf = run()
        pk = frf.peak()
        walls.append(time.perf_counter() - t)
        cpus.append(time.process_time() - p)
    return frf, pk, statistics.median(walls), statistics.median(cpus)


def main():
    rows = []
    case = default_case()
    run = lambda: frequency_response(case.blade, case.element, omega_range=case.omega_range)  # noqa: E731
    run()  # warm the imports
    frf, pk, wall, cpu = timed(run)
    ref = frequency_response(case.blade, case.element, omega_range=case.omega_range, rtol=1e-9).peak()
    rows.append(("default case (two-region microslip)", frf, pk, wall, cpu, ref))
    for zeta in (1e-2, 1e-4):
        blade = Blade.from_modal(frequency=1.0, damping_ratio=zeta, mass=1.0, force=0.5)
        el = macroslip(1.0, 1.0)
        run = lambda: frequency_response(blade, el, omega_range=(0.5, 2.0))  # noqa: E731
        frf, pk, wall, cpu = timed(run)
        w_ref, a_ref = jenkins_peak(blade, 1.0, 1.0, (0.9 * pk.amplitude, 1.1 * pk.amplitude))
        rows.append((f"Jenkins, zeta = {zeta:g}", frf, pk, wall, cpu, (w_ref, a_ref)))

    print(f"{platform.processor() or platform.machine()}, Python {platform.python_version()}, "
          f"numpy {np.__version__}; median of {REPEATS} runs (FRF + peak)\n")
    print("| case | points | wall (s) | CPU (s) | Newton its | element evals | stuck evals "
          "| peak amplitude rel. error | peak omega rel. error |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, frf, pk, wall, cpu, (w_ref, a_ref) in rows:
        print(f"| {name} | {len(frf)} | {wall:.3f} | {cpu:.3f} | {frf.nit} | {frf.nfev} | {frf.nstuck} "
              f"| {abs(pk.amplitude / a_ref - 1):.1e} | {abs(pk.omega / w_ref - 1):.1e} |")


if __name__ == "__main__":
    main()
