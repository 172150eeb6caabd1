"""The all-mode bar's exact segments against lumped masses: the force in the cells, far above the cut-off,
and the default all-mode FRF's time.

``python benchmarks/bench_allmode_linear.py``: (1) f_c (N) at three points of the default all-mode FRF at
100 N (the peak, the 13th harmonic's notch, below the peak) on 16 to 256 cells at H = 31 and 496 samples,
with ``linear="lumped"`` and ``linear="exact"``, and the limit in the cells (Richardson at order 2 from
the exact bar's 128 and 256 cells); (2) at 10 and 30 omega_c (the reference bar of
``tests/test_allmode_accuracy.py``, a = 1.5e-6 m) the error of both on 64 to 640 cells, H = 7, against the
converged references stored there, and what the element choosing its rungs (tol = 1e-3) gives.
``--frf [repeats]``: the default all-mode FRF at tol = 1e-3 (kernels as installed) with each, alternated,
medians of ``repeats`` (default 3) after one to warm up, and the single-mode FRF's for the ratio
(docs/validation.md and docs/performance.md, "The all-mode bar's exact segments").
"""

from __future__ import annotations

import statistics
import sys
import time
import warnings

import numpy as np

from common import machine, machine_line, table

POINTS = ((38827.4, 1.538e-6, "the peak"), (38752.0, 1.538e-6, "the notch"), (38446.6, 1.393e-6, "below the peak"))
CELLS = (16, 32, 64, 128, 256)
H, N_T = 31, 496
#: (omega / omega_c, reference (f_s, f_c)) of tests/test_allmode_accuracy.py's uniform load at a = 1.5e-6 m.
FAR = ((10.0, (-462.45684743937454, 12.271992267837609)), (30.0, (8319.083, 69.911)))


def forces():
    from hbm.cli.cases import default_case

    from contact_models import AllModeMicroslip

    case = default_case()
    bar, load = case.element.bar, case.element.load
    rows = []
    for omega, a, what in POINTS:
        fc = {lin: [AllModeMicroslip(bar, load, n, H, n_t=N_T, linear=lin).fourier(a, omega)[1] for n in CELLS]
              for lin in ("lumped", "exact")}
        limit = fc["exact"][-1] + (fc["exact"][-1] - fc["exact"][-2]) / 3.0
        for lin in ("lumped", "exact"):
            rows.append([f"{what}, {omega} rad/s", lin] + [f"{v:.5f} ({v - limit:+.1e})" for v in fc[lin]]
                        + [f"{limit:.5f}"])
    print(table(["point", "linear"] + [f"{n} cells" for n in CELLS] + ["limit"], rows))


def far_above():
    from contact_models import AccuracyWarning, AllModeMicroslip, Bar, UniformLoad

    bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    load, a = UniformLoad(N=100.0), 1.5e-6
    rows = []
    for w, ref in FAR:
        floor = 0.01 * bar.k_star * a
        scale = np.maximum(np.abs(ref), floor)
        for lin in ("lumped", "exact"):
            errs = []
            for n in (64, 128, 256, 640):
                try:
                    s = AllModeMicroslip(bar, load, n, 7, linear=lin).solve(a, w * bar.omega_c)
                    errs.append(f"{np.max(np.abs(np.array([s.f_s, s.f_c]) - ref) / scale):.1e}")
                except ValueError:
                    errs.append("too few cells")
            with warnings.catch_warnings(record=True) as heard:
                warnings.simplefilter("always", AccuracyWarning)
                s = AllModeMicroslip(bar, load, linear=lin).solve(a, w * bar.omega_c)
            true = np.max(np.abs(np.array([s.f_s, s.f_c]) - ref) / scale)
            chosen = (f"{s.cells} cells, H = {s.H}: estimate {s.relative_error:.1e}, off {true:.1e}"
                      + (", warns" if heard else ""))
            rows.append([f"{w:g} omega_c", lin] + errs + [chosen])
    print(table(["where", "linear", "64", "128", "256", "640", "chosen at tol = 1e-3"], rows))


def frf_times(repeats: int = 3):
    from hbm import frequency_response
    from hbm.cli.cases import default_case

    from contact_models import AllModeMicroslip

    case = default_case()
    bar, load = case.element.bar, case.element.load
    times: dict = {"single-mode": [], "lumped": [], "exact": []}
    last = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for k in range(repeats + 1):
            for lin in times:
                el = case.element if lin == "single-mode" else AllModeMicroslip(bar, load, linear=lin)
                t = time.perf_counter()
                frf = frequency_response(case.blade, el, omega_range=case.omega_range,
                                         **({} if lin == "single-mode" else {"tol": 1e-3}))
                if k:
                    times[lin].append(time.perf_counter() - t)
                last[lin] = frf
    base = statistics.median(times["single-mode"])
    rows = []
    for lin, ts in times.items():
        f, pk = last[lin], last[lin].peak()
        rows.append([lin, f"{statistics.median(ts):.3f} s", f"{statistics.median(ts) / base:.0f}x", str(len(f)),
                     f"{pk.amplitude:.6e} m at {pk.omega:.1f}", f"{float(np.max(f.error_estimate)):.1e}"])
    print(table(["damper", f"median of {repeats}", "/ single-mode", "points", "peak", "largest estimate"], rows))


if __name__ == "__main__":
    print(machine_line(machine()))
    if "--frf" in sys.argv:
        i = sys.argv.index("--frf")
        frf_times(int(sys.argv[i + 1]) if len(sys.argv) > i + 1 else 3)
    else:
        forces()
        far_above()
