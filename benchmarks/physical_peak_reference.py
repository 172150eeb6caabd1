"""Regenerate ``tests/data/physical_peak_reference.json``: the peak of the default blade's true periodic
response with the bar of every mode, the reference of ``model="peak"`` and of the main job's peak.

Each frequency is solved as in ``benchmarks/physical_curve_reference.py`` (a plain Newton iteration at
fixed omega carried up the ladder (64, 31, 3) -> ... -> (256, 127, 47), not the library's continuation
or refinement), at ``COUNT`` frequencies ``STEP`` apart around ``CENTRE``; the peak is the vertex of the
parabola through the largest and its two neighbours (the largest must be interior).  ``spread`` is the
vertex's relative change from the rung below.

Run: ``PYTHONPATH=. python3 benchmarks/physical_peak_reference.py [--out PATH]`` (about two minutes).
"""

from __future__ import annotations

import argparse
import json
import time
import warnings
from pathlib import Path

import numpy as np

import hbm
from hbm.cli.cases import default_case

from physical_curve_reference import LADDER, up_the_ladder

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "tests" / "data" / "physical_peak_reference.json"
#: The frequencies: COUNT of them STEP rad/s apart, centred on CENTRE (the converged curve's largest
#: sample of ``tests/data/physical_curve_reference.json`` is at 38732.5 rad/s).
CENTRE, STEP, COUNT = 38740.0, 5.0, 9


def vertex(w: np.ndarray, a: np.ndarray) -> tuple[float, float]:
    """The vertex (omega, amplitude) of the parabola through three points (w_i, a_i), fitted in
    omega - w_1 (frequencies some 4e4 rad/s, a few rad/s apart, are ill-conditioned raw)."""
    c2, c1, c0 = np.polyfit(w - w[1], a, 2)
    wv = -c1 / (2.0 * c2)
    return float(wv + w[1]), float(c0 + c1 * wv + c2 * wv * wv)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    case = default_case()
    blade, el = case.blade, case.element
    omegas = CENTRE + STEP * (np.arange(COUNT) - (COUNT - 1) / 2)
    single = hbm.frequency_response(blade, el, case.omega_range, harmonics=1, tol=1e-4)
    t0 = time.perf_counter()
    amps = np.zeros((COUNT, len(LADDER)))
    for k, w in enumerate(omegas):
        i = int(np.argmin(np.abs(single.omega - w)))
        amps[k] = up_the_ladder(blade, el, w, np.array([0.0, single.x_c[i], single.x_s[i]]))
        print(f"omega {w:.2f} amplitude {amps[k, -1]:.8e} ({time.perf_counter() - t0:.0f} s)", flush=True)
    peaks = []
    for r in (-2, -1):
        j = int(np.argmax(amps[:, r]))
        if not 0 < j < COUNT - 1:
            raise RuntimeError(f"the largest sample is at an end of the frequencies ({omegas[j]:.2f} rad/s)")
        peaks.append(vertex(omegas[j - 1:j + 2], amps[j - 1:j + 2, r]))
    (w_pk, a_pk), spread = peaks[1], abs(peaks[1][1] - peaks[0][1]) / peaks[1][1]
    data = {"generated_by": "benchmarks/physical_peak_reference.py", "case": case.description, "ladder": LADDER,
            "omega": w_pk, "amplitude": a_pk, "spread": spread,
            "samples": [{"omega": float(w), "ladder": list(map(float, a))} for w, a in zip(omegas, amps)],
            "seconds": round(time.perf_counter() - t0, 1)}
    args.out.write_text(json.dumps(data, indent=1) + "\n")
    print(f"peak {a_pk:.8e} m at {w_pk:.2f} rad/s (spread {spread:.1e}); wrote {args.out}")


if __name__ == "__main__":
    main()
