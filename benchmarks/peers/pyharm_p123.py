"""pyHarm 1.2.2 on the Jenkins problems P1-P3 of docs/performance.md (runs INSIDE the pyHarm venv).

Problem: ``m x'' + c x' + k x + f_J = F cos(omega t)``, m = k = 1, F = 0.01, one Jenkins element
(pyHarm ``Jenkins``: spring k = 1 behind a slider of force mu N0; mu = 1, N0 = slip force) from
the DOF to the ground; P1 c = 0.004, fs = 0.02; P2 c = 0.004, fs = 0.005; P3 c = 0.0002,
fs = 0.02.  pyHarm's own arc-length continuation (``frf`` study: tangent predictor, arc-length
corrector, scipy root solver, its default acceptance step sizer) from omega = 0.6 to 1.8 rad/s,
``nh = 7`` harmonics (with the static term), ``nti = 512``, ``ds_max = 0.005``.

Prints one JSON object: per problem the median wall time of ``repeats`` runs (the model is
built, and numba compiled, once before timing; each timed run builds a fresh ``Maestro`` and
calls ``operate()``), the number of accepted points, and the peak of the first-harmonic
amplitude over the accepted points, refined by the parabola through the largest point and its
two neighbours (in the continuation order), and the same peak refined by an untimed second
continuation over +-0.3 % of it with ds_max / 50.

Run: ``/work/venvs/pyharm/bin/python benchmarks/peers/pyharm_p123.py [--repeats 3] [--nh 7]``.
"""

import argparse
import json
import logging
import os
import statistics
import time

import numpy as np

PROBLEMS = {"P1": (0.004, 0.02), "P2": (0.004, 0.005), "P3": (0.0002, 0.02)}


def data(c, fs, nh, nti, ds_max, window=(0.6, 1.8)):
    return {
        "analysis": {"frf": {"study": "frf", "puls_inf": window[0], "puls_sup": window[1], "ds0": ds_max, "ds_min": 1e-8,
                             "ds_max": ds_max, "sign_ds": 1, "verbose": False, "predictor": "tangent",
                             "corrector": "arc_length", "stopper": "bounds"}},
        "system": {"type": "Base", "nh": nh, "nti": nti},
        "substructures": {"blade": {"matrix": {"M": np.array([[1.0]]), "C": np.array([[c]]), "K": np.array([[1.0]]),
                                               "G": np.array([[0.0]])}, "ndofs": 1}},
        "connectors": {
            "loading": {"type": "CosinusForcing", "connect": {"blade": [0]}, "dirs": [0], "amp": 0.01},
            "jenkins": {"type": "Jenkins", "connect": {"blade": [0]}, "dirs": [0], "mu": 1.0, "N0": fs, "k": 1.0},
        },
    }


def run(c, fs, nh, nti, ds_max, window=(0.6, 1.8)):
    from pyHarm.Maestro import Maestro

    M = Maestro(data(c, fs, nh, nti, ds_max, window))
    idx = np.sort(np.asarray(M.getIndex("blade", 0, 0)))
    t0 = time.perf_counter()
    M.operate()
    wall = time.perf_counter() - t0
    sols = [s for s in M.nls["frf"].SolList if s.flag_accepted]
    om = np.array([s.x[-1] for s in sols])
    # per DOF the harmonic coefficients are [a0, a1, b1, a2, b2, ...] (pyHarm's compute_DFT)
    amp = np.array([np.hypot(s.x[idx[1]], s.x[idx[2]]) for s in sols])
    return wall, om, amp


def peak(om, amp):
    k = int(np.argmax(amp))
    if 0 < k < amp.size - 1:
        w, a = om[k - 1:k + 2], amp[k - 1:k + 2]
        c2, c1, c0 = np.polyfit(w - w[1], a, 2)
        if c2 < 0:
            dw = -0.5 * c1 / c2
            return float(w[1] + dw), float(c0 + c1 * dw + c2 * dw * dw)
    return float(om[k]), float(amp[k])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--nh", type=int, default=7)
    ap.add_argument("--nti", type=int, default=512)
    ap.add_argument("--ds-max", type=float, default=0.005)
    ap.add_argument("--problems", default="P1,P2,P3")
    args = ap.parse_args()
    logging.disable(logging.CRITICAL)
    import pyHarm

    out = {"peer": "pyHarm", "version": getattr(pyHarm, "__version__", "?"), "nh": args.nh, "nti": args.nti,
           "ds_max": args.ds_max, "repeats": args.repeats, "loadavg_start": list(os.getloadavg()), "problems": {}}
    for name in args.problems.split(","):
        c, fs = PROBLEMS[name]
        t0 = time.perf_counter()
        run(c, fs, args.nh, args.nti, args.ds_max)  # warm-up: numba compilation, caches
        warm = time.perf_counter() - t0
        walls = []
        for _ in range(args.repeats):
            wall, om, amp = run(c, fs, args.nh, args.nti, args.ds_max)
            walls.append(wall)
        w, a = peak(om, amp)
        # untimed refinement: pyHarm's own continuation again, over +-0.3 % of the peak with a
        # step 50 times finer, so that the parabola through the three largest points carries
        # the balance's error at this H, not the spacing of the timed run's points
        _, om_f, amp_f = run(c, fs, args.nh, args.nti, args.ds_max / 50, (w * 0.997, w * 1.003))
        wf, af = peak(om_f, amp_f)
        out["problems"][name] = {"refined_peak_omega": wf, "refined_peak_amplitude": af,
                                 "seconds_median": statistics.median(walls), "seconds": walls,
                                 "warmup_seconds": warm, "points": int(om.size), "omega_end": float(om[-1]),
                                 "peak_omega": w, "peak_amplitude": a, "peak_amplitude_max_point": float(amp.max())}
    out["loadavg_end"] = list(os.getloadavg())
    print(json.dumps(out))


if __name__ == "__main__":
    main()
