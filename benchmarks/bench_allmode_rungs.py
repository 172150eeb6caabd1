"""The all-mode FRF on rungs along the curve, against a converged reference at its own points.

``frequency_response(case.blade, AllModeMicroslip(bar, load, tol=tol), omega_range=case.omega_range,
tol=tol, harmonics=1)`` on the default case (``hbm.cli.cases.default_case()``): the bar's cells and
harmonics are chosen along the curve, and every point names its rung (``point_models``).  At the
curve's points nearest ``OMEGAS`` (the flanks, the peak and the notch where the 13th harmonic meets
the bar's second mode with its end held), at its first and last point where the bar slips, and at the
curve's largest point and its largest estimate, the point's amplitude is compared with the converged
H = 1 amplitude at the point's own frequency:
``hbm.reference.amplitude.amplitude_at`` (the amplitude equation, solved by its own Newton iteration,
not by the continuation) with the bar on ``REFERENCE`` = 1024 cells at H = 63.  The reference's doubt
is its larger change to 512 cells at H = 63 and to 1024 cells at H = 47.

The blade is held at H = 1 because the reference is the H = 1 amplitude equation; the curve's
``error_estimate`` also holds the blade's harmonics that H = 1 leaves out (the ``"harmonics"``
source), which the reference does not see, so the table gives the estimate and its part the
reference does see (``"model"``, the bar's cells and harmonics).  Two more columns split the error of a
slipping point: "off its rung", the point against the amplitude equation solved on the point's own rung
(at a sin(theta), as the reference and the estimate are), and "phase on its rung", how much that rung's
describing function changes between a sin(theta) and the point's own phase (``phase_change``).  Where the bar is stuck (the
amplitude at most ``linear_amplitude``) the element is linear and the comparison is of the two
solutions' Newton tolerances (the reference's is ``AMPLITUDE_RTOL`` = 1e-8): the table says "< 1e-8"
and gives no ratio there.

With ``--element``, the bar alone at points of the tol = 1e-2 curve (nearest ``ELEMENT_OMEGAS``), on
the point's own rung and on 128 cells at H = 31 (at the notch also on 64 and 256 cells at H = 31 and
64 cells at H = 15), driven by a sin(omega t): the relative error of (f_s, f_c) (the floor 0.01 k* a
of the element's estimate) against ``ELEMENT_REFERENCE`` = 2048 cells at H = 63 (doubt: the larger
change to 1024 cells at H = 63 and to 2048 cells at H = 47), the change of the same rung's cells to
H = 63, and the element's estimate (``model_error(a, omega, parts=True)``, the larger component) with
its cells and harmonics parts.

Run: ``PYTHONPATH=. OPENBLAS_NUM_THREADS=1 python3 benchmarks/bench_allmode_rungs.py [--tol 1e-3 1e-2]
[--element]`` (about 15 s of CPU per tolerance, 15 s for ``--element``).  Prints, per tolerance, the
curve's point count and its ``AccuracyWarning`` (if any) and the table of ``docs/validation.md``, "The
all-mode FRF on rungs along the curve, against a converged reference"; with ``--element`` the table of
the bar alone there.
"""

from __future__ import annotations

import argparse
import math
import re
import time
import warnings

import numpy as np

from contact_models import AccuracyWarning, AllModeMicroslip
from contact_models.allmode.accuracy import FLOOR
from hbm import frequency_response
from hbm.cli.cases import default_case
from hbm.reference.amplitude import AMPLITUDE_RTOL, amplitude_at

#: Frequencies (rad/s) whose nearest curve points are compared (those of the slow test of
#: ``tests/test_allmode_curve.py``).
OMEGAS = (33000.0, 36000.0, 38000.0, 38400.0, 38600.0, 38710.0, 38751.0, 38758.0, 38780.0, 38820.0, 38860.0,
          40000.0, 42000.0)
#: The reference rung (cells, bar harmonics) and the two coarser ones its doubt is read from.
REFERENCE = (1024, 63)
DOUBT = ((512, 63), (1024, 47))
#: ``--element``: frequencies (rad/s) of the tol = 1e-2 curve's points, from the flank to the notch
#: (38751 rad/s) and past the peak; the reference of the bar alone and the rungs its doubt is read from.
ELEMENT_OMEGAS = (38098.0, 38400.0, 38600.0, 38709.0, 38751.0, 38758.0, 38820.0, 39372.0)
NOTCH = 38751.0
ELEMENT_REFERENCE = (2048, 63)
ELEMENT_DOUBT = ((1024, 63), (2048, 47))


def rung(name: str) -> str:
    """``"AllModeMicroslip(cells=64, H=31)"`` as ``"64 cells, H = 31"``."""
    m = re.fullmatch(r"AllModeMicroslip\(cells=(\d+), H=(\d+)\)", name)
    return f"{m.group(1)} cells, H = {m.group(2)}" if m else name


def own_rung(name: str) -> tuple[int, int]:
    """``"AllModeMicroslip(cells=64, H=31)"`` as ``(64, 31)``."""
    m = re.fullmatch(r"AllModeMicroslip\(cells=(\d+), H=(\d+)\)", name)
    return int(m.group(1)), int(m.group(2))


def phase_change(el, x_c: float, x_s: float, omega: float) -> float:
    """|K(x_c, x_s) / K(a sin) - 1| of the bar ``el``: its describing function K = (F_c - i F_s) / (x_c - i x_s)
    driven at the curve point's phase against the same amplitude a = |(x_c, x_s)| as a sin(theta).  A bar
    solved exactly is invariant under a time shift (K the same); the nested solve samples the period at
    fixed points, so its K depends on where they fall in the cycle (docs/validation.md, "The phase of the
    nested solve's samples")."""

    def K(X):
        sol = el.solve(X, omega)
        if not sol.success:
            raise FloatingPointError(f"the bar did not converge at omega = {omega}, X = {X}")
        return complex(sol.F[1], -sol.F[2]) / complex(X[1], -X[2])

    return abs(K(np.array([0.0, x_c, x_s])) / K(np.array([0.0, 0.0, math.hypot(x_c, x_s)])) - 1.0)


def curve(case, tol: float):
    """The all-mode curve at ``tol`` and the messages of the ``AccuracyWarning``s it emitted."""
    bar, load = case.element.bar, case.element.load
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", AccuracyWarning)
        frf = frequency_response(case.blade, AllModeMicroslip(bar, load, tol=tol), omega_range=case.omega_range,
                                 tol=tol, harmonics=1)
    return frf, [str(w.message) for w in caught if issubclass(w.category, AccuracyWarning)]


def points(frf, linear) -> list[int]:
    """The indices of the curve's points nearest ``OMEGAS``, its first and last point where the bar slips
    (``linear``: the amplitude below which it is stuck, per frequency), its largest point and its largest
    estimate."""
    idx = {int(np.argmin(np.abs(frf.omega - w))) for w in OMEGAS}
    slips = np.flatnonzero(frf.amplitude > np.array([linear(float(w)) for w in frf.omega]))
    idx |= {int(slips[0]), int(slips[-1])}
    idx |= {int(np.argmax(frf.amplitude)), int(np.argmax(frf.error_estimate))}
    return sorted(idx)


def table(case, tol: float) -> None:
    """The curve at ``tol`` against the converged H = 1 amplitude at its points (module docstring)."""
    bar, load = case.element.bar, case.element.load
    t0 = time.process_time()
    frf, heard = curve(case, tol)
    worst, top = int(np.argmax(frf.error_estimate)), int(np.argmax(frf.amplitude))
    print(f"tol = {tol:g}: {len(frf.omega)} points, {time.process_time() - t0:.1f} s CPU; largest estimate "
          f"{float(frf.error_estimate[worst]):.1e} at {float(frf.omega[worst]):.1f} rad/s; largest point "
          f"{float(frf.amplitude[top]):.6e} m at {float(frf.omega[top]):.1f} rad/s")
    print("AccuracyWarning: " + (" | ".join(heard) if heard else "none"))
    refs = {k: AllModeMicroslip(bar, load, *k) for k in (REFERENCE, *DOUBT)}
    model = frf.error_sources["model"]
    linear = AllModeMicroslip(bar, load).linear_amplitude
    print()
    print("| omega (rad/s) | rung | true | doubt of the reference | off its rung | phase on its rung | estimate "
          "| model part | true / estimate | true / model part |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    ratios, t0 = [], time.process_time()
    for i in points(frf, linear):
        w, a = float(frf.omega[i]), float(frf.amplitude[i])
        r = {k: amplitude_at(case.blade, el, w, a) for k, el in refs.items()}
        ref = r[REFERENCE]
        doubt = max(abs(r[k] / ref - 1.0) for k in DOUBT)
        true = abs(a / ref - 1.0)
        est, mod = float(frf.error_estimate[i]), float(model[i])
        name = rung(str(frf.point_models[i]))
        if a <= linear(w):  # stuck: no ratio (module docstring)
            small = "< " + f"{AMPLITUDE_RTOL:.0e}".replace("e-0", "e-") if max(true, doubt) < AMPLITUDE_RTOL else None
            print(f"| {w:.1f} | {name} (stuck) | {small or f'{true:.1e}'} | {small or f'{doubt:.1e}'} | - | - | "
                  f"{est:.1e} | {mod:.1e} | - | - |", flush=True)
            continue
        own = AllModeMicroslip(bar, load, *own_rung(str(frf.point_models[i])))
        off = abs(a / amplitude_at(case.blade, own, w, a) - 1.0)
        phase = phase_change(own, float(np.ravel(frf.x_c)[i]), float(np.ravel(frf.x_s)[i]), w)
        ratios.append((true / est, true / mod))
        print(f"| {w:.1f} | {name} | {true:.1e} | {doubt:.1e} | {off:.1e} | {phase:.1e} | {est:.1e} | {mod:.1e} | "
              f"{true / est:.2f} | {true / mod:.2f} |", flush=True)
    r_est, r_mod = np.array(ratios).T
    print(f"\nslipping points: true / estimate {r_est.min():.2f} to {r_est.max():.2f}, true / model part "
          f"{r_mod.min():.2f} to {r_mod.max():.2f}; the references {time.process_time() - t0:.0f} s CPU\n")


def element_table(case) -> None:
    """The bar alone at points of the tol = 1e-2 curve (module docstring, ``--element``)."""
    bar, load = case.element.bar, case.element.load
    frf, _ = curve(case, 1e-2)
    t0 = time.process_time()

    def force(n, H, a, w):
        sol = AllModeMicroslip(bar, load, n, H).solve(a, w)
        if not sol.success:
            raise FloatingPointError(f"{n} cells, H = {H} did not converge at omega = {w}, a = {a}")
        return sol.F[1:3]

    def rel(F, ref, a):
        return float(np.max(np.abs(F - ref) / np.maximum(np.abs(ref), FLOOR * bar.k_star * a)))

    print("| omega (rad/s) | a (m) | rung | true | doubt of the reference | true, harmonics | cells part "
          "| harmonics part | estimate | true / estimate |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for w0 in ELEMENT_OMEGAS:
        i = int(np.argmin(np.abs(frf.omega - w0)))
        w, a = float(frf.omega[i]), float(frf.amplitude[i])
        ref = force(*ELEMENT_REFERENCE, a, w)
        doubt = max(rel(force(*k, a, w), ref, a) for k in ELEMENT_DOUBT)
        own = re.fullmatch(r"AllModeMicroslip\(cells=(\d+), H=(\d+)\)", str(frf.point_models[i]))
        rungs = [(int(own.group(1)), int(own.group(2)))] if own else []
        rungs += [(128, 31)] + ([(64, 31), (256, 31), (64, 15)] if w0 == NOTCH else [])
        for n, H in dict.fromkeys(rungs):
            el = AllModeMicroslip(bar, load, n, H)
            F = force(n, H, a, w)
            est = float(max(el.model_error(a, w, parts=True)))
            (_, _, rel_c, rel_h), = el._seen  # the cells and harmonics parts of this estimate
            true = rel(F, ref, a)
            print(f"| {w:.1f} | {a:.3e} | {n} cells, H = {H}{' (the point)' if own and (n, H) == rungs[0] else ''} "
                  f"| {true:.1e} | {doubt:.1e} | {rel(F, force(n, 63, a, w), a):.1e} | {rel_c:.1e} | {rel_h:.1e} "
                  f"| {est:.1e} | {true / est:.2f} |", flush=True)
    print(f"\n{time.process_time() - t0:.0f} s CPU\n")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tol", type=float, nargs="+", default=[1e-3])
    parser.add_argument("--element", action="store_true", help="the bar alone at points of the tol = 1e-2 curve")
    args = parser.parse_args()
    case = default_case()
    if args.element:
        element_table(case)
        return
    for tol in args.tol:
        table(case, tol)


if __name__ == "__main__":
    main()
