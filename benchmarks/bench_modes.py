"""Evidence of ``docs/nonlinear_modes.md``: the forced response from one nonlinear mode against the
full FRF, and the damper's optimum from the modes against a sweep of 50 FRFs.

1. Single nonlinear mode theory (``hbm.single_mode.forced_response``) against
   ``hbm.frequency_response``: peak frequency and amplitude, for the default blade (H = 1) and the
   3-DOF chain of ``docs/multiharmonic.md`` (H = 1 and H = 7, n_t = 512).
2. The default blade's normal load N in [30, 90] N that minimises the peak: ``hbm.damper_optimum``
   (one run) against 50 FRFs at N equally spaced over the range, whose peaks are interpolated by a
   cubic spline and the spline minimised.  Both timed in this run, interleaved, median of 3.

Run: ``python3 -m benchmarks.bench_modes`` (from the repository root; about a minute).
"""

from __future__ import annotations

import statistics
import time

import numpy as np

from contact_models import Macroslip, TwoRegionMicroslip, UniformLoad
from hbm import Contact, Structure, frequency_response, nonlinear_modes
from hbm.cli.cases import default_case
from hbm.damper_optimum import damper_optimum
from hbm.single_mode import forced_response

BOUNDS = (30.0, 90.0)
SWEEP = 50
REPEATS = 3


def chain() -> tuple[Structure, list[Contact]]:
    """The 3-DOF chain of ``docs/multiharmonic.md``."""
    K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    s = Structure(np.eye(3), 0.004 * K, K, force=[0.0, 0.0, 0.01])
    return s, [Contact(Macroslip(stiffness=1.0, slip_force=0.02), dof=0),
               Contact(Macroslip(stiffness=1.0, slip_force=0.05), dofs=(0, 1))]


def snmt_rows() -> list[tuple]:
    """(case, H, peak frequency difference, peak amplitude difference), relative to the FRF."""
    case = default_case()
    sm = np.sqrt(case.blade.mass)
    rows = []
    m = nonlinear_modes(case.blade.as_structure(), [Contact(case.element, dof=0)],
                        amplitude_range=(1e-8 * sm, 1e-5 * sm), harmonics=1)
    fr = forced_response(m).peak
    pk = frequency_response(case.blade, case.element, omega_range=case.omega_range).peak()
    rows.append(("default blade", 1, fr.omega / pk.omega - 1.0, fr.amplitude / pk.amplitude - 1.0))
    s, contacts = chain()
    for H, nt in ((1, 64), (7, 512)):
        fr = forced_response(nonlinear_modes(s, contacts, amplitude_range=(1e-3, 10.0), harmonics=H, n_t=nt)).peak
        pk = frequency_response(s, contacts, omega_range=(0.3, 0.9), harmonics=H, n_t=nt, response_dof=2).peak()
        rows.append(("3-DOF chain", H, fr.omega / pk.omega - 1.0, fr.amplitude / pk.amplitude - 1.0))
    return rows


def by_modes():
    case = default_case()
    bar, sm = case.element.bar, np.sqrt(case.blade.mass)
    return damper_optimum(case.blade.as_structure(),
                          lambda N: [Contact(TwoRegionMicroslip(bar, UniformLoad(N=N)), dof=0)], BOUNDS,
                          amplitude_range=(1e-8 * sm, 1e-5 * sm))


def by_sweep() -> tuple[float, float, np.ndarray, np.ndarray]:
    """``(N*, peak*, N, peaks)`` from 50 FRFs and the minimum of the cubic spline through their peaks."""
    from scipy.interpolate import CubicSpline  # the benchmark's own interpolation, not the library's

    case = default_case()
    loads = np.linspace(*BOUNDS, SWEEP)
    peaks = np.array([frequency_response(case.blade, TwoRegionMicroslip(case.element.bar, UniformLoad(N=N)),
                                         omega_range=case.omega_range).peak().amplitude for N in loads])
    spline = CubicSpline(loads, peaks)
    cands = spline.derivative().roots(extrapolate=False)
    cands = np.concatenate([cands, BOUNDS])
    best = cands[np.argmin(spline(cands))]
    return float(best), float(spline(best)), loads, peaks


def main(repeats: int = REPEATS) -> None:
    print("| case | H | peak frequency, relative difference | peak amplitude, relative difference |")
    print("|---|---|---|---|")
    for name, H, dw, da in snmt_rows():
        print(f"| {name} | {H} | {dw:+.2e} | {da:+.2e} |")
    t_modes, t_sweep = [], []
    for _ in range(repeats):
        t = time.perf_counter()
        opt = by_modes()
        t_modes.append(time.perf_counter() - t)
        t = time.perf_counter()
        n_s, p_s, _, _ = by_sweep()
        t_sweep.append(time.perf_counter() - t)
    tm, ts = statistics.median(t_modes), statistics.median(t_sweep)
    print()
    print("| method | optimum N (N) | peak (m) | time (s, median of 3) |")
    print("|---|---|---|---|")
    print(f"| damper_optimum (modes, one run) | {opt.parameter:.6f} | {opt.peak.amplitude:.8e} | {tm:.2f} |")
    print(f"| 50 FRFs + cubic spline | {n_s:.6f} | {p_s:.8e} | {ts:.2f} |")
    print(f"\noptimum relative difference {opt.parameter / n_s - 1.0:+.2e}, peak {opt.peak.amplitude / p_s - 1.0:+.2e}, "
          f"speed-up {ts / tm:.1f}")


if __name__ == "__main__":
    main()
