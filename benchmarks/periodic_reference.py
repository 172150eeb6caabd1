"""Regenerate ``tests/data/periodic_reference.json``: the true periodic responses (shooting on
the event-driven exact integration, ``hbm.periodic_response``) that the multi-harmonic balance
is checked against.

Contents (every problem's parameters are stored beside its numbers):

* ``jenkins``: P1-P3 (m = k = 1, F = 0.01, one Jenkins kt = 1 to ground; P1 c = 0.004,
  fs = 0.02; P2 c = 0.004, fs = 0.005; P3 c = 0.0002, fs = 0.02): the peak of the first-harmonic
  amplitude of x over omega (frequency, amplitude, every harmonic there, Floquet multipliers),
  the peak of max_t |x|, the single-harmonic balance's peak and its relative errors.
* ``chain``: the 3-DOF chain (M = I, K of unit springs ground-1-2-3, C = 0.004 K, F = 0.01 at
  DOF 2, Jenkins kt = 1, fs = 0.02 from DOF 0 to ground and kt = 1, fs = 0.05 between DOFs 0
  and 1) at 8 frequencies through its first two resonances: harmonics 0..21 of every DOF and
  the Floquet multipliers; each point reached by sweeping up and by sweeping down (the two agree:
  one periodic response there).
* ``duffing``: m = k = 1, c = 0.02, k3 = 0.1, F = 0.05 at omega = 1.08 and 1.12, where three
  periodic responses coexist: each one's harmonics and Floquet multipliers.
* ``accuracy``: the event-driven reference at 1024 against 4096 samples, and the Newmark
  integrator's convergence to it at the P1 peak (``--newmark`` adds the finest steps; slow).

Run: ``PYTHONPATH=. python3 benchmarks/periodic_reference.py [--newmark] [--out PATH]``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import time
from pathlib import Path
from types import SimpleNamespace

import numpy as np

import hbm
from contact_models import Macroslip

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "tests" / "data" / "periodic_reference.json"

#: Harmonics stored, and samples per period of the reference (aliasing of c_1 < 1e-13).
H = 21
STEPS = 1024
#: The Jenkins problems P1-P3 (parameters in the module docstring).
JENKINS = {"P1": dict(damping=0.004, slip_force=0.02), "P2": dict(damping=0.004, slip_force=0.005),
           "P3": dict(damping=0.0002, slip_force=0.02)}
CHAIN_OMEGA = [0.40, 0.47, 0.52, 0.56, 0.62, 1.00, 1.36, 1.38]
DUFFING = dict(mass=1.0, stiffness=1.0, damping=0.02, k3=0.1, force=0.05, omega=[1.08, 1.12])


def contact(element, *dofs):
    """A duck-typed contact (``hbm.Contact`` once it exists has the same two attributes)."""
    return SimpleNamespace(element=element, dofs=tuple(dofs))


def jenkins(name):
    p = JENKINS[name]
    blade = hbm.Blade(mass=1.0, stiffness=1.0, damping=p["damping"], force=0.01)
    return blade, Macroslip(stiffness=1.0, slip_force=p["slip_force"])


def describing_guess(blade, element, omega, amplitude):
    """First-harmonic complex amplitude X (x = Re X e^{i omega t}) of the single-harmonic balance
    at (omega, amplitude): X = F / (k - m omega^2 + i c omega + (f_s + i f_c)/a)."""
    fs, fc = (float(np.ravel(v)[0]) for v in element.fourier(np.array([amplitude]), omega))
    keq = complex(fs, fc) / amplitude
    return np.array([blade.force / (blade.stiffness - blade.mass * omega**2 + 1j * blade.damping * omega + keq)])


def harmonics_json(r):
    return {"real": r.harmonics.tolist(), "layout": "[X0, Xc1, Xs1, ..., XcH, XsH] per DOF"}


def floquet_json(r):
    return {"abs": np.abs(r.floquet).tolist(), "real": r.floquet.real.tolist(), "imag": r.floquet.imag.tolist()}


def jenkins_peaks(name):
    blade, el = jenkins(name)
    cs = [contact(el, 0)]
    t0 = time.perf_counter()
    hb = hbm.frequency_response(blade, el, omega_range=(0.6, 1.8)).peak()
    r0 = hbm.periodic_response(blade, cs, omega=hb.omega, initial=describing_guess(blade, el, hb.omega, hb.amplitude),
                               steps=STEPS, harmonics=H)
    assert r0.success, r0.message
    bracket = (hb.omega * 0.985, hb.omega * 1.015)
    pa = hbm.periodic_peak(blade, cs, bracket=bracket, initial=r0, steps=STEPS, harmonics=H, xtol=1e-11)
    pm = hbm.periodic_peak(blade, cs, bracket=bracket, initial=pa.response, measure="max", steps=STEPS,
                           harmonics=H, xtol=1e-11)
    at = hbm.periodic_response(blade, cs, omega=pa.omega, initial=pa.response, steps=STEPS, harmonics=H)
    # independent check of the frequency: vertex of the parabola through the amplitudes at
    # omega* + j delta, j = -2..2 (delta = 2e-5 omega*: the cubic term shifts the vertex by
    # ~ (A'''/A'') delta^2 ~ 1e-8, the amplitudes' noise by less)
    delta = 2e-5 * pa.omega
    ws = pa.omega + delta * np.arange(-2, 3)
    amps = [hbm.periodic_response(blade, cs, omega=w, initial=at, steps=STEPS, harmonics=1, floquet=False).amplitude(0)
            for w in ws]
    c2, c1, _ = np.polyfit((ws - pa.omega) / delta, amps, 2)
    vertex = pa.omega - 0.5 * c1 / c2 * delta
    fine = hbm.periodic_response(blade, cs, omega=pa.omega, initial=at, steps=4 * STEPS, harmonics=H, floquet=False)
    return {
        "parameters": dict(mass=1.0, stiffness=1.0, force=0.01, contact_stiffness=1.0, **JENKINS[name]),
        "peak_amplitude": {"omega": pa.omega, "amplitude": pa.value, "success": pa.success,
                           "evaluations": pa.evaluations, "max_abs_there": at.max_abs(0)},
        "peak_max_abs": {"omega": pm.omega, "max_abs": pm.value, "success": pm.success},
        "at_peak": {"harmonics": harmonics_json(at), "floquet": floquet_json(at), "stable": at.stable},
        "single_harmonic": {"omega": hb.omega, "amplitude": hb.amplitude,
                            "omega_error": hb.omega / pa.omega - 1.0, "amplitude_error": hb.amplitude / pa.value - 1.0},
        "check_parabola_vertex_omega": vertex / pa.omega - 1.0,
        "check_samples_4096_vs_1024": {"amplitude": fine.amplitude(0) / at.amplitude(0) - 1.0,
                                       "max_abs": fine.max_abs(0) / at.max_abs(0) - 1.0},
        "seconds": time.perf_counter() - t0,
    }


def chain_system():
    K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    M, C, f = np.eye(3), 0.004 * K, np.array([0.0, 0.0, 0.01])
    cs = [contact(Macroslip(stiffness=1.0, slip_force=0.02), 0), contact(Macroslip(stiffness=1.0, slip_force=0.05), 0, 1)]
    return (M, C, K, f), cs


def never_slipping(r):
    """Indices of the contacts whose slider does not move over the period."""
    return [int(c) for c in np.flatnonzero(np.ptp(r.z, axis=0) == 0.0)]


def sweep(system, cs, omegas):
    out, prev = {}, None
    for w in omegas:
        r = hbm.periodic_response(system, cs, omega=w, initial=prev, steps=STEPS, harmonics=H)
        if not r.success:  # far from the neighbour: start afresh from the stuck response
            r = hbm.periodic_response(system, cs, omega=w, steps=STEPS, harmonics=H)
        out[w], prev = r, r
    return out


def chain():
    system, cs = chain_system()
    up = sweep(system, cs, CHAIN_OMEGA)
    down = sweep(system, cs, CHAIN_OMEGA[::-1])
    points = []
    for w in CHAIN_OMEGA:
        r, d = up[w], down[w]
        points.append({"omega": w, "success": r.success, "harmonics": harmonics_json(r), "floquet": floquet_json(r),
                       "stable": r.stable, "amplitude": [r.amplitude(i) for i in range(3)],
                       "max_abs": [r.max_abs(i) for i in range(3)],
                       "never_slipping_contacts": never_slipping(r),
                       # h >= 1 only: see "static_offset" below
                       "up_down_difference": float(np.max(np.abs(r.harmonics[:, 1:] - d.harmonics[:, 1:]))
                                                   / np.max(np.abs(r.harmonics[:, 1:])))})
    M, C, K, f = system
    return {"parameters": {"M": M.tolist(), "C": C.tolist(), "K": K.tolist(), "force": f.tolist(),
                           "damping": "C = 0.004 K (stiffness proportional)",
                           "contacts": [{"dofs": [0], "stiffness": 1.0, "slip_force": 0.02},
                                        {"dofs": [0, 1], "stiffness": 1.0, "slip_force": 0.05}]},
            "static_offset": "Where a contact sticks all period (never_slipping_contacts, a Floquet multiplier 1), "
                             "its slider's position is not fixed by periodicity: a family of periodic responses "
                             "differs by a static offset, so X0 depends on the start (the history); harmonics h >= 1 "
                             "are unique (up_down_difference). Compare X0 only where no contact sticks all period.",
            "points": points}


class CubicSpring:
    """Stand-in for the cubic spring ``f = k3 x^3`` (only ``k3`` is read by the shooting)."""

    def __init__(self, k3):
        self.k3 = k3


def duffing():
    p = DUFFING
    system = (np.array([[p["mass"]]]), np.array([[p["damping"]]]), np.array([[p["stiffness"]]]), np.array([p["force"]]))
    cs = [contact(CubicSpring(p["k3"]), 0)]
    out = []
    for w in p["omega"]:
        # the single-harmonic amplitudes: ((k - m w^2 + 3/4 k3 A^2)^2 + (c w)^2) A^2 = F^2
        d, a = p["stiffness"] - p["mass"] * w * w, 0.75 * p["k3"]
        roots = np.roots([a * a, 2 * a * d, d * d + (p["damping"] * w) ** 2, -p["force"] ** 2])
        amps = np.sqrt(np.sort(roots[np.abs(roots.imag) < 1e-12].real))
        branches = []
        for A in amps:
            X = p["force"] / (d + a * A * A + 1j * p["damping"] * w)
            r = hbm.periodic_response(system, cs, omega=w, initial=np.array([X]), steps=STEPS, harmonics=H)
            branches.append({"single_harmonic_amplitude": float(A), "success": r.success, "amplitude": r.amplitude(0),
                             "max_abs": r.max_abs(0), "harmonics": harmonics_json(r), "floquet": floquet_json(r),
                             "stable": r.stable})
        out.append({"omega": w, "branches": branches})
    return {"parameters": {k: v for k, v in p.items() if k != "omega"}, "points": out}


def newmark_convergence(steps_list):
    blade, el = jenkins("P1")
    cs = [contact(el, 0)]
    w = 1.3
    ref = hbm.periodic_response(blade, cs, omega=w, steps=STEPS, harmonics=H)
    rows = []
    for N in steps_list:
        t0 = time.perf_counter()
        r = hbm.periodic_response(blade, cs, omega=w, integrator="newmark", steps=N, initial=ref, harmonics=H,
                                  floquet=False, tol=1e-10 if N <= 8192 else 1e-9)  # rounding floor grows with N
        rows.append({"steps": N, "success": r.success, "amplitude_error": r.amplitude(0) / ref.amplitude(0) - 1.0,
                     "seconds": time.perf_counter() - t0})
    e = np.array([abs(r["amplitude_error"]) for r in rows])
    n = np.array(steps_list, dtype=float)
    rate = float(-np.polyfit(np.log(n), np.log(e), 1)[0]) if len(rows) > 1 else math.nan
    return {"problem": "P1", "omega": w, "reference_amplitude": ref.amplitude(0), "rows": rows, "fitted_rate": rate}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=OUT)
    ap.add_argument("--newmark", action="store_true", help="Newmark to 32768 steps per period (slow)")
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    data = {"generated_by": "benchmarks/periodic_reference.py", "steps": STEPS, "harmonics": H,
            "loadavg_start": list(os.getloadavg())}
    data["jenkins"] = {name: jenkins_peaks(name) for name in JENKINS}
    print(json.dumps({k: {"peak": v["peak_amplitude"], "max": v["peak_max_abs"], "hb": v["single_harmonic"]}
                      for k, v in data["jenkins"].items()}, indent=1))
    data["chain"] = chain()
    data["duffing"] = duffing()
    steps = [1024, 2048, 4096, 8192] + ([16384, 32768] if args.newmark else [])
    data["accuracy"] = {"newmark": newmark_convergence(steps)}
    data["seconds"] = time.perf_counter() - t0
    data["loadavg_end"] = list(os.getloadavg())
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(data, indent=1) + "\n")
    print(f"wrote {args.out} in {data['seconds']:.0f} s")


if __name__ == "__main__":
    main()
