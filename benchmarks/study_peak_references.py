"""The 50-FRF study's peaks against references converged without the library's continuation or refinement.

The study (``docs/performance.md``; ``bench_allmode.py``, ``_frf_run``): the default case
(``hbm.cli.cases.default_case``) with ``AllModeMicroslip(bar, UniformLoad(N=N), tol=1e-3)`` as the damper at
50 normal loads ``np.linspace(40, 300, 50)``, each FRF traced at tol = 1e-3 with the rungs chosen along the
curve (``_frf_along``).  For each load this script records

* the study's peak, ``frf.peak()``: amplitude, omega and its stated ``estimate``, with the error sources,
  the bar's rung and the blade's H at the sampled maximum the estimate comes from;
* a reference peak.  The blade is balanced at fixed frequencies by the plain Newton iteration of
  ``benchmarks/physical_curve_reference.py`` (``fixed_frequency``, carried up a ladder of rungs by
  ``up_the_ladder``), not by the library's continuation, step control, harmonic or rung refinement or peak
  location.  The ladder is ``LADDER``: that script's (64, 31, 3) -> (128, 63, 15) -> (128, 127, 31) ->
  (256, 127, 31) -> (256, 127, 47) with (512, 127, 47) on top (cells, bar harmonics, blade harmonics; AFT
  on 16 samples per blade harmonic, the bar's own 8 per bar harmonic).  Each rung's Newton iteration
  starts from the rung below, the first from the single-mode FRF at that load (``tol=1e-4``) at the
  nearest frequency: a starting guess only.  The frequencies are ``COUNT`` samples ``STEP`` rad/s apart
  centred on the study's peak frequency (the only use of the study's answer), widened by ``STEP`` on the
  side of the largest sample until the largest is at least two samples from either end on each of the
  top three rungs.  The reference peak is the vertex of the parabola through the largest sample and its
  two neighbours on the top rung (as ``physical_peak_reference.py`` does).

Its doubt: ``ladder_doubt``, the larger relative change of the vertex from the two rungs below the top
(the cells 256 -> 512; the blade's harmonics 31 -> 47 with the cells 256 -> 512), and ``sampling_doubt``,
the change of the vertex to the parabola through the largest and the samples two steps either side (twice
the step: the vertex's own error at ``STEP`` is about a third of it where the curve is smooth).  ``true``
is ``|a_study / a_ref - 1|``; ``ratio`` is true / estimate.

Writes ``benchmarks/results/study_peak_references.json`` after every load (``--out``), one line per load
on stdout.  Run (one process; about 25 minutes of one core for the 50 loads, 15 to 50 s per load, about
4.5 s per reference frequency):

    PYTHONPATH=. OPENBLAS_NUM_THREADS=1 python3 benchmarks/study_peak_references.py [--every 2] [--loads 100 220.4]

``--step`` and ``--count`` set the reference's frequencies (finer steps beside a notch, where the sampling
doubt is largest: ``--step 1.5 --count 25`` takes about two minutes a load).

``--study-only`` computes the study's peaks again beside the stored references (a few minutes: after a change
of the library's estimate or refinement; the references do not depend on either).

``--table`` prints the Markdown table of ``docs/validation.md`` ("The 50-FRF study's peaks against
converged references") from the stored results without computing anything.
"""

from __future__ import annotations

import argparse
import json
import time
import warnings
from pathlib import Path

import numpy as np

import hbm
from contact_models import AllModeMicroslip, TwoRegionMicroslip, UniformLoad
from hbm.cli.cases import default_case

from bench_allmode import _frf_along
from common import machine, machine_line, table
from physical_curve_reference import LADDER as CURVE_LADDER
from physical_curve_reference import up_the_ladder
from physical_peak_reference import vertex

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "benchmarks" / "results" / "study_peak_references.json"
#: The study's loads (N) and tolerance, as ``bench_allmode.frf_study`` runs them.
LOADS = np.linspace(40.0, 300.0, 50)
TOL = 1e-3
#: (cells, bar harmonics, blade harmonics): the physical curve's ladder, one cell doubling on top.
LADDER = [*CURVE_LADDER, (512, 127, 47)]
#: The reference's frequencies: COUNT of them STEP rad/s apart, centred on the study's peak.
STEP, COUNT = 4.0, 9
#: At most this many samples added on one side to bring the largest inside.
MAX_WIDEN = 20


def study_peak(case, N: float) -> dict:
    """The study's FRF at load ``N`` as ``bench_allmode._frf_run`` computes it, and its peak."""
    t0 = time.process_time()
    frf = _frf_along(case, AllModeMicroslip(case.element.bar, UniformLoad(N=N), tol=TOL), TOL, True)
    cpu = time.process_time() - t0
    pk = frf.peak()
    i = int(np.argmax(frf.amplitude))
    seg = next(s for s in frf.segments if s.start <= i < s.stop)
    return {"omega": pk.omega, "amplitude": pk.amplitude, "estimate": pk.estimate, "converged": pk.converged,
            "interior": pk.interior, "message": pk.message, "points": len(frf),
            "sources": {k: float(v[i]) for k, v in frf.error_sources.items()},
            "model": str(frf.point_models[i]), "blade_harmonics": int(seg.harmonics), "cpu_s": round(cpu, 2)}


def reference_peak(case, N: float, centre: float, step: float = STEP, count: int = COUNT) -> dict:
    """The reference peak at load ``N`` from fixed-frequency balances around ``centre`` (rad/s)."""
    t0 = time.process_time()
    blade, el = case.blade, TwoRegionMicroslip(case.element.bar, UniformLoad(N=N))
    single = hbm.frequency_response(blade, el, case.omega_range, harmonics=1, tol=1e-4)

    def solve(w: float) -> list[float]:
        i = int(np.argmin(np.abs(single.omega - w)))
        return up_the_ladder(blade, el, w, np.array([0.0, single.x_c[i], single.x_s[i]]), ladder=LADDER)

    omegas = list(centre + step * (np.arange(count) - (count - 1) / 2))
    amps = [solve(w) for w in omegas]
    widened = 0
    while True:
        A = np.array(amps)
        js = [int(np.argmax(A[:, r])) for r in (-3, -2, -1)]
        if all(2 <= j <= len(omegas) - 3 for j in js):
            break
        if widened >= MAX_WIDEN:
            raise RuntimeError(f"N = {N}: the largest sample stays at an end of {omegas[0]:.1f}..{omegas[-1]:.1f}")
        widened += 1
        if min(js) < 2:
            omegas.insert(0, omegas[0] - step)
            amps.insert(0, solve(omegas[0]))
        else:
            omegas.append(omegas[-1] + step)
            amps.append(solve(omegas[-1]))
    w = np.array(omegas)
    peaks = []
    for r in range(len(LADDER)):
        j = int(np.argmax(A[:, r]))
        peaks.append(vertex(w[j - 1:j + 2], A[j - 1:j + 2, r]) if 0 < j < len(w) - 1 else (float(w[j]), float(A[j, r])))
    (w_pk, a_pk) = peaks[-1]
    j = js[-1]
    w2, a2 = vertex(w[j - 2:j + 3:2], A[j - 2:j + 3:2, -1])
    ladder_doubt = max(abs(peaks[-2][1] - a_pk), abs(peaks[-3][1] - a_pk)) / a_pk
    return {"omega": w_pk, "amplitude": a_pk, "ladder_doubt": ladder_doubt, "sampling_doubt": abs(a2 - a_pk) / a_pk,
            "omega_2step": w2, "rung_peaks": [{"rung": list(rung), "omega": p[0], "amplitude": p[1]}
                                              for rung, p in zip(LADDER, peaks)],
            "samples": [{"omega": float(x), "ladder": list(map(float, a))} for x, a in zip(w, A)],
            "widened": widened, "cpu_s": round(time.process_time() - t0, 2)}


def rows(results: list[dict]) -> list[list[str]]:
    """The table's rows, one per load."""
    out = []
    for r in results:
        s, ref = r["study"], r["reference"]
        true = abs(s["amplitude"] / ref["amplitude"] - 1.0)
        big = max(s["sources"], key=s["sources"].get)
        rung = s["model"].replace("AllModeMicroslip(cells=", "").replace(", H=", " cells, H = ").rstrip(")")
        out.append([f"{r['N']:.1f}", f"{s['amplitude']:.6e} at {s['omega']:.1f}",
                    f"{ref['amplitude']:.6e} at {ref['omega']:.1f}", f"{ref['ladder_doubt']:.1e}",
                    f"{ref['sampling_doubt']:.1e}", f"{true:.1e}", f"{s['estimate']:.1e}",
                    f"**{true / s['estimate']:.2f}**" if true > s["estimate"] else f"{true / s['estimate']:.2f}",
                    f"{rung}; {s['blade_harmonics']}", big + ("" if s["converged"] else " (not located)")])
    return out


HEADER = ["N", "study peak (m at rad/s)", "reference (m at rad/s)", "ladder doubt", "sampling doubt", "true",
          "estimate", "true / estimate", "bar's rung; blade H", "largest source"]


def study_only(case, out: Path, loads: list[float]) -> None:
    """The study's peaks at ``loads`` computed again into the stored results at ``out``, beside their stored
    references.  A reference was sampled about the study's peak as it then was: a new peak must lie inside the
    reference's sampled frequencies, else this stops and says to compute the reference again."""
    data = json.loads(out.read_text())
    for N in loads:
        entry = min(data["loads"], key=lambda e: abs(e["N"] - N))
        if abs(entry["N"] - N) > 1e-9 * N:
            raise SystemExit(f"N = {N}: no stored reference; run without --study-only")
        s = study_peak(case, entry["N"])
        w = [x["omega"] for x in entry["reference"]["samples"]]
        if not min(w) < s["omega"] < max(w):
            raise SystemExit(f"N = {N}: the study's peak at {s['omega']:.1f} rad/s is outside the reference's "
                             f"samples {min(w):.1f}..{max(w):.1f}; run without --study-only")
        entry["study"] = s
        out.write_text(json.dumps(data, indent=1) + "\n")
        ref = entry["reference"]
        true = abs(s["amplitude"] / ref["amplitude"] - 1.0)
        print(f"N {N:6.1f}  study {s['amplitude']:.7e} at {s['omega']:.2f} est {s['estimate']:.1e}  "
              f"ref {ref['amplitude']:.7e}  true {true:.1e} ratio {true / s['estimate']:.2f}", flush=True)
    print(f"wrote {out}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=OUT)
    parser.add_argument("--every", type=int, default=1, help="take every n-th of the 50 loads")
    parser.add_argument("--loads", type=float, nargs="*", help="these loads (N) instead")
    parser.add_argument("--step", type=float, default=STEP, help="the reference's frequency step (rad/s)")
    parser.add_argument("--count", type=int, default=COUNT, help="the reference's frequencies before widening")
    parser.add_argument("--table", action="store_true", help="print the table from the stored results")
    parser.add_argument("--study-only", action="store_true",
                        help="recompute the study's peaks only, keeping the stored references (they do not depend "
                             "on the library's estimate or refinement)")
    args = parser.parse_args()
    if args.table:
        data = json.loads(args.out.read_text())
        print(table(HEADER, rows(data["loads"])))
        return
    warnings.simplefilter("ignore")
    case = default_case()
    loads = args.loads if args.loads else [float(N) for N in LOADS[::args.every]]
    if args.study_only:
        study_only(case, args.out, loads)
        return
    info = machine()
    data = {"generated_by": "benchmarks/study_peak_references.py", "case": case.description, "tol": TOL,
            "ladder": LADDER, "step": args.step, "count": args.count, "machine": machine_line(info), "loads": []}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    for N in loads:
        s = study_peak(case, N)
        ref = reference_peak(case, N, s["omega"], args.step, args.count)
        data["loads"].append({"N": N, "study": s, "reference": ref})
        data["seconds"] = round(time.perf_counter() - t0, 1)
        args.out.write_text(json.dumps(data, indent=1) + "\n")
        true = abs(s["amplitude"] / ref["amplitude"] - 1.0)
        print(f"N {N:6.1f}  study {s['amplitude']:.7e} at {s['omega']:.2f} est {s['estimate']:.1e}  "
              f"ref {ref['amplitude']:.7e} at {ref['omega']:.2f} doubt {ref['ladder_doubt']:.1e} "
              f"sampling {ref['sampling_doubt']:.1e}  true {true:.1e} ratio {true / s['estimate']:.2f}  "
              f"[{s['model']}, Hb {s['blade_harmonics']}; {s['cpu_s']:.0f} + {ref['cpu_s']:.0f} s CPU, "
              f"{time.perf_counter() - t0:.0f} s]", flush=True)
    print(f"wrote {args.out} ({data['seconds']:.0f} s)")


if __name__ == "__main__":
    main()
