"""Regenerate ``tests/data/physical_curve_reference.json``: the default blade's true periodic response with
the bar of every mode at 16 frequencies across its resonance, the reference the main job's curve is
checked against.

The default case (``hbm.cli.cases.default_case``: the two-region bar under 100 N on the blade of
stiffness 1e8 N/m) with ``AllModeMicroslip(bar, load, cells, harmonics)`` as the damper, the blade
balanced with ``Hb`` harmonics (AFT on 16 Hb samples per harmonic).  Each frequency is solved by a
plain Newton iteration on the blade's harmonics at fixed omega (written here, not the library's
continuation or refinement), started from the single-mode balance's solution there and carried up a
ladder of resolutions, each rung from the last:

    (64, 31, 3) -> (128, 63, 15) -> (128, 127, 31) -> (256, 127, 31) -> (256, 127, 47)

(cells, bar harmonics, blade harmonics).  The blade's harmonics go to 31: where a high harmonic of
the drive meets a mode of the bar, the blade's own harmonic of that order moves the notch it makes
(near the peak the 13th meets the bar's second mode with its end held: between 9 and 13 blade
harmonics the amplitude at 38812 rad/s moves by 1.5 %; at 38593 rad/s one between 15 and 21 moves
it by 8e-4, at 38733 rad/s one between 21 and 31 by 1.5e-4).  The stored amplitude is the first
harmonic's modulus on the finest rung; ``spread`` is the larger of its relative distances to
(256, 127, 31) (the blade's harmonics) and to (128, 127, 31) (the cells too), an upper bound of the
reference's own error where the ladder converges (it is checked to be below 1e-4 of the amplitude:
ten times below the tolerance the curve is held to).

Run: ``PYTHONPATH=. python3 benchmarks/physical_curve_reference.py [--out PATH]`` (about five minutes
on one core).

``--beside-peak`` writes ``tests/data/physical_curve_beside_peak.json`` instead: the curve beside its
peak, where notches narrower than the curve's steps lie.  Two frequencies, one beside and one in the
narrow notch at 38718.6 rad/s, carried up ``NOTCH_LADDER``; and a grid of 0.5 rad/s over
38400..39100 rad/s on ``GRID_RUNG`` (the finest model the main job's curve takes there), each
frequency's Newton iteration started from the last.  Both start from the single-mode balance's first
harmonic (about one minute on one core).
"""

from __future__ import annotations

import argparse
import json
import time
import warnings
from pathlib import Path

import numpy as np

import hbm
from contact_models import AllModeMicroslip
from hbm.cli.cases import default_case

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "tests" / "data" / "physical_curve_reference.json"
BESIDE_PEAK = ROOT / "tests" / "data" / "physical_curve_beside_peak.json"
#: The ladder of (cells, bar harmonics, blade harmonics), the reference the last.
LADDER = [(64, 31, 3), (128, 63, 15), (128, 127, 31), (256, 127, 31), (256, 127, 47)]
#: Frequencies as fractions of the stuck resonance sqrt((k + k*)/m): across the microslip band
#: and both flanks, denser near the peak (about 0.972 of it).
FRACTIONS = [0.90, 0.94, 0.955, 0.96, 0.963, 0.966, 0.9685, 0.9695, 0.9705, 0.9715, 0.9725, 0.974,
             0.977, 0.982, 0.99, 1.02]
#: Beside the peak: the ladder of the notch's two frequencies and the rung of the 0.5 rad/s grid.
NOTCH_LADDER = [(64, 31, 3), (128, 63, 15), (128, 127, 31), (256, 127, 31)]
NOTCH_OMEGAS = [38710.0, 38718.6]
GRID_RUNG = (128, 31, 31)
GRID = (38400.0, 39100.0, 0.5)


def fixed_frequency(blade, element, Hb: int, omega: float, X0: np.ndarray) -> np.ndarray:
    """The blade's harmonics (2 Hb + 1,) at ``omega`` by Newton's method on the balance, from ``X0``."""
    hb = hbm.HarmonicBalance(blade, element, harmonics=Hb, n_t=16 * Hb)
    L = 2 * Hb + 1
    X = np.zeros(hb.na * L)
    X[:min(X0.size, L)] = X0[:L]
    for _ in range(60):
        R, J = hb.physical(np.concatenate([X, [omega]]))
        dX = np.linalg.solve(J[:, :-1], -R)
        X += dX
        if np.linalg.norm(dX) <= 1e-12 * np.linalg.norm(X):
            return X
    raise RuntimeError(f"Newton did not converge at omega = {omega!r} on {element!r}, Hb = {Hb}")


def up_the_ladder(blade, el, omega: float, X0: np.ndarray, ladder=LADDER) -> list[float]:
    """The first-harmonic amplitude (m) of the blade with ``AllModeMicroslip(el.bar, el.load, cells, harmonics)``
    at ``omega`` on each rung of ``ladder`` (cells, bar harmonics, blade harmonics) in turn, each rung's Newton
    iteration (``fixed_frequency``) started from the last rung's solution, the first from ``X0``."""
    X, amps = X0, []
    for n, H, Hb in ladder:
        X = fixed_frequency(blade, AllModeMicroslip(el.bar, el.load, cells=n, harmonics=H), Hb, float(omega), X)
        amps.append(float(np.hypot(X[1], X[2])))
    return amps


def beside_peak(case) -> dict:
    """The notch's two frequencies up ``NOTCH_LADDER`` and the grid on ``GRID_RUNG`` (module docstring)."""
    blade, el = case.blade, case.element
    single = hbm.frequency_response(blade, el, case.omega_range, harmonics=1, tol=1e-4)

    def start(w):
        i = int(np.argmin(np.abs(single.omega - w)))
        return np.array([0.0, single.x_c[i], single.x_s[i]])

    t0 = time.perf_counter()
    notch = [{"omega": w, "ladder": up_the_ladder(blade, el, w, start(w), NOTCH_LADDER)} for w in NOTCH_OMEGAS]
    for p in notch:
        print(f"omega {p['omega']:.1f} ladder {p['ladder']} ({time.perf_counter() - t0:.0f} s)", flush=True)
    n, H, Hb = GRID_RUNG
    fine = AllModeMicroslip(el.bar, el.load, cells=n, harmonics=H)
    lo, hi, step = GRID
    omegas = np.arange(lo, hi + 1e-9, step)
    X, amps = start(lo), []
    for w in omegas:
        X = fixed_frequency(blade, fine, Hb, float(w), X)
        amps.append(float(np.hypot(X[1], X[2])))
    print(f"grid of {omegas.size} frequencies ({time.perf_counter() - t0:.0f} s)", flush=True)
    return {"generated_by": "benchmarks/physical_curve_reference.py --beside-peak", "case": case.description,
            "notch_ladder": NOTCH_LADDER, "notch": notch, "grid_rung": GRID_RUNG,
            "grid_omega": [float(w) for w in omegas], "grid_amplitude": amps,
            "seconds": round(time.perf_counter() - t0, 1)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=None)
    parser.add_argument("--beside-peak", action="store_true", help="write the reference beside the peak instead")
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    case = default_case()
    if args.beside_peak:
        out = args.out or BESIDE_PEAK
        out.write_text(json.dumps(beside_peak(case), indent=1) + "\n")
        print(f"wrote {out}")
        return
    args.out = args.out or OUT
    blade, el = case.blade, case.element
    w_stuck = float(np.sqrt((blade.stiffness + el.stuck_stiffness(0.0)) / blade.mass))
    omegas = [f * w_stuck for f in FRACTIONS]
    single = hbm.frequency_response(blade, el, case.omega_range, harmonics=1, tol=1e-4)
    points = []
    t0 = time.perf_counter()
    for w in omegas:
        i = int(np.argmin(np.abs(single.omega - w)))
        amps = up_the_ladder(blade, el, w, np.array([0.0, single.x_c[i], single.x_s[i]]))
        spread = max(abs(amps[-1] - amps[-2]), abs(amps[-1] - amps[-3])) / amps[-1]
        points.append({"omega": w, "amplitude": amps[-1], "spread": spread, "ladder": amps})
        print(f"omega {w:.2f} amplitude {amps[-1]:.8e} spread {spread:.1e} ({time.perf_counter() - t0:.0f} s)",
              flush=True)
    data = {"generated_by": "benchmarks/physical_curve_reference.py", "case": case.description,
            "ladder": LADDER, "fractions_of_stuck_resonance": FRACTIONS, "points": points,
            "seconds": round(time.perf_counter() - t0, 1)}
    args.out.write_text(json.dumps(data, indent=1) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
