"""What accuracy costs in ``NumericalMicroslip``, against the analytic element.

The numerical bar (``contact_models.numerical``) integrated in time, uniform load 100 N on the
reference bar (docs/theory.md); knobs ``cells`` (n), ``steps_per_cycle`` and ``steady_tol``, each swept with the
others fixed.  Error: max over a in {1.5, 3, 10} a_min of max(|F_s - F_s,ref|, |F_c - F_c,ref|)
in units of k* a, against ``TwoRegionMicroslip`` (rtol 1e-13):

- dynamic, omega = 0.01 omega_c, where the single-mode analytic solution and the full one agree
  to about 1e-5 of k* a (``docs/validation.md``): below that the error is the model difference;
- quasi-static (omega = 0), where the analytic solution is exact.

Time: per f_s/f_c pair, ``simulate(3 a_min, omega)`` (median of ``REPEATS``, all settings and the
analytic element's scalar call round-robin, so the ratios come from the same run).  A setting
whose first run takes longer than ``SLOW_RUN`` seconds is timed once only (marked).

Run ``python benchmarks/bench_numerical.py``: prints the tables, writes
``docs/figures/accuracy_numerical.png``.
"""

from __future__ import annotations

import statistics
import sys

import numpy as np

from contact_models import Bar, TwoRegionMicroslip, UniformLoad
from contact_models import numerical as nm
from contact_models.numerical import NumericalMicroslip

from common import FIGURES, REPEATS, machine, machine_line, once, plot_curves, save_figure, sci, table

BAR = dict(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
RATIOS = (1.5, 3.0, 10.0)
TIMED_RATIO = 3.0
DYNAMIC_FREQUENCY = 0.01  # of omega_c
#: The element's defaults (read from its module; the values of 2026-11-21 if it renames them).
STEPS_DYNAMIC = getattr(nm, "STEPS_DYNAMIC", 512)
STEPS_QUASI_STATIC = getattr(nm, "STEPS_QUASI_STATIC", 512)
STEADY_TOL = getattr(nm, "STEADY_TOL", 1e-6)
#: A first run slower than this (s) is not repeated.
SLOW_RUN = 15.0
#: Dynamic sweeps: (knob, values, fixed settings).  The library's defaults (200 cells, 512 steps)
#: cost 6-7 s per pair at 0.01 omega_c here, too slow to repeat five times within the runner's
#: budget; the sweeps run at coarser fixed settings.
DYNAMIC = (
    ("cells", (25, 50, 100, 200), {"steps_per_cycle": 128}),
    ("steps_per_cycle", tuple(sorted({64, 128, 256, STEPS_DYNAMIC})), {"cells": 50}),
    ("steady_tol", (1e-2, 1e-4, 1e-6), {"cells": 50, "steps_per_cycle": 128}),
)
QUASI_STATIC = (
    ("cells", (25, 50, 100, 200, 400), {}),
    ("steps_per_cycle", tuple(sorted({64, 128, STEPS_QUASI_STATIC, 1024})), {"cells": 100}),
)
DEFAULTS = {"cells": 200, "steps_per_cycle": None, "steady_tol": STEADY_TOL}


def _configs():
    """Unique (mode, settings) pairs and, per sweep, the list of their keys."""
    configs, sweeps = {}, []
    for mode, table_ in (("dynamic", DYNAMIC), ("quasi-static", QUASI_STATIC)):
        for knob, values, fixed in table_:
            keys = []
            for v in values:
                s = dict(fixed, **{knob: v})
                key = (mode, tuple(sorted(s.items())))
                configs[key] = s
                keys.append(key)
            sweeps.append((mode, knob, values, fixed, keys))
    return configs, sweeps


def measure(repeats: int = REPEATS, log=print):
    bar = Bar(**BAR)
    load = UniformLoad(N=100.0)
    analytic = TwoRegionMicroslip(bar, load)
    k_star = analytic.stuck_stiffness(0.0)
    omegas = {"dynamic": DYNAMIC_FREQUENCY * bar.omega_c, "quasi-static": 0.0}
    configs, sweeps = _configs()
    results = {}
    for key, s in configs.items():
        mode = key[0]
        w = omegas[mode]
        a_min = analytic.slip_amplitude(w)
        a = np.array(RATIOS) * a_min
        fs0, fc0 = analytic.fourier(a, w, rtol=1e-13)
        kw = {k: v for k, v in s.items() if k != "steady_tol"}
        tol = s.get("steady_tol")
        try:
            el = NumericalMicroslip(bar, load, quasi_static=(mode == "quasi-static"), **kw)
            runs = {}
            for r, ai in zip(RATIOS, a):
                runs[r] = once(lambda: el.simulate(ai, w, steady_tol=tol))
            err = max(max(abs(runs[r][2].f_s - f0), abs(runs[r][2].f_c - c0)) / (k_star * ai)
                      for r, ai, f0, c0 in zip(RATIOS, a, fs0, fc0))
            first = runs[TIMED_RATIO]
            res = {"settings": s, "error": float(err), "cpu": [first[1]], "wall": [first[0]],
                   "cycles": max(runs[r][2].cycles for r in RATIOS),
                   "converged": all(runs[r][2].converged for r in RATIOS), "el": el, "a": TIMED_RATIO * a_min,
                   "omega": w, "failed": None}
        except Exception as exc:  # the numerical element is still being finished: report, go on
            res = {"settings": s, "error": float("nan"), "cpu": [], "wall": [], "cycles": 0, "converged": False,
                   "el": None, "failed": f"{type(exc).__name__}: {exc}"}
        results[key] = res
        log(f"  {mode} {s}: error {res['error']:.2e}, first run CPU {res['cpu'][0] if res['cpu'] else float('nan'):.2f} s"
            + (f" FAILED {res['failed']}" if res["failed"] else ""))

    # ---- repeats, round-robin, with the analytic element's scalar call (new and cached omega)
    def analytic_new(w):
        return once(lambda e: e.fourier(TIMED_RATIO * analytic.slip_amplitude(w), w), lambda: TwoRegionMicroslip(bar, load))

    cached = TwoRegionMicroslip(bar, load)
    an = {m: {"new": [], "cached": []} for m in omegas}
    repeat_keys = [k for k, r in results.items() if r["el"] is not None and r["cpu"][0] <= SLOW_RUN]
    for rnd in range(repeats):
        for key in repeat_keys if rnd > 0 else ():  # round 0: the first runs above
            r = results[key]
            wall, cpu, _ = once(lambda: r["el"].simulate(r["a"], r["omega"], steady_tol=r["settings"].get("steady_tol")))
            r["wall"].append(wall)
            r["cpu"].append(cpu)
        for m, w in omegas.items():
            an[m]["new"].append(analytic_new(w)[1])
            cached.fourier(TIMED_RATIO * analytic.slip_amplitude(w), w)
            an[m]["cached"].append(once(lambda: cached.fourier(TIMED_RATIO * analytic.slip_amplitude(w), w))[1])
    out = {"machine": machine(), "repeats": repeats, "sweeps": [], "analytic": {}}
    for m in omegas:
        out["analytic"][m] = {k: statistics.median(v) for k, v in an[m].items()}
    for mode, knob, values, fixed, keys in sweeps:
        rows = []
        for v, key in zip(values, keys):
            r = results[key]
            rows.append({"value": v, "error": r["error"], "cpu": statistics.median(r["cpu"]) if r["cpu"] else float("nan"),
                         "wall": statistics.median(r["wall"]) if r["wall"] else float("nan"), "runs": len(r["cpu"]),
                         "cycles": r["cycles"], "converged": r["converged"], "failed": r["failed"]})
        out["sweeps"].append({"mode": mode, "knob": knob, "fixed": fixed, "rows": rows})
    return out


def _fixed(fixed):
    return ", ".join(f"{k} = {v:g}" for k, v in fixed.items()) or "defaults"


def _value(knob, v, mode):
    default = DEFAULTS[knob]
    if knob == "steps_per_cycle":
        default = STEPS_QUASI_STATIC if mode == "quasi-static" else STEPS_DYNAMIC
    return f"{v:g}" + (" (default)" if v == default else "")


def tables(res) -> str:
    rows = []
    for sw in res["sweeps"]:
        t_an = res["analytic"][sw["mode"]]["new"]
        for r in sw["rows"]:
            if r["failed"]:
                rows.append([sw["mode"], f"`{sw['knob']}` ({_fixed(sw['fixed'])})", _value(sw["knob"], r["value"], sw["mode"]),
                             "failed: " + r["failed"][:80], "", "", "", "", ""])
                continue
            rows.append([sw["mode"], f"`{sw['knob']}` ({_fixed(sw['fixed'])})", _value(sw["knob"], r["value"], sw["mode"]),
                         sci(r["error"]), f"{r['cpu']:.3f}", f"{r['wall']:.3f}",
                         f"{r['runs']}", f"{r['cycles']}" + ("" if r["converged"] else " (not steady)"),
                         f"{r['cpu'] / t_an:.0f}"])
    an = res["analytic"]
    head = ("Analytic `TwoRegionMicroslip.fourier`, one scalar call (CPU, median of "
            f"{res['repeats']}): {an['dynamic']['new'] * 1e3:.2f} ms at a new frequency (0.01 omega_c, "
            f"path built), {an['dynamic']['cached'] * 1e3:.2f} ms at a cached one; "
            f"{an['quasi-static']['new'] * 1e3:.2f} / {an['quasi-static']['cached'] * 1e3:.2f} ms at omega = 0.")
    return head + "\n\n" + table(["mode", "knob (fixed)", "value", "max error (k* a)", "CPU per pair (s)", "wall (s)",
                                  "runs", "cycles (max)", "CPU / analytic (new omega)"], rows)


def matched(res, levels=(1e-4, 1e-5)) -> str:
    """The cheapest numerical setting within each error level, against the analytic element."""
    lines = []
    for mode in ("dynamic", "quasi-static"):
        rows = [(sw["knob"], sw["fixed"], r) for sw in res["sweeps"] if sw["mode"] == mode for r in sw["rows"]
                if not r["failed"]]
        t_an = res["analytic"][mode]["new"]
        for level in levels:
            ok = [x for x in rows if x[2]["error"] <= level]
            if not ok:
                lines.append(f"- {mode}, error <= {level:g} k* a: no setting of these sweeps reaches it")
                continue
            knob, fixed, r = min(ok, key=lambda x: x[2]["cpu"])
            lines.append(f"- {mode}, error <= {level:g} k* a: the cheapest measured setting is {knob} = {r['value']:g} "
                         f"({_fixed(fixed)}; error {r['error']:.1e}), {r['cpu']:.3f} s per pair: **{r['cpu'] / t_an:.0f} "
                         f"times** the analytic element's {t_an * 1e3:.2f} ms")
    return "\n".join(lines)


def plot(res, path=None):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    path = path or FIGURES / "accuracy_numerical.png"
    fig, axes = plt.subplots(1, 2, figsize=(12.4, 4.8))
    for ax, mode in zip(axes, ("dynamic", "quasi-static")):
        curves = []
        for sw in res["sweeps"]:
            if sw["mode"] != mode:
                continue
            rows = [r for r in sw["rows"] if not r["failed"]]
            d = next((i for i, r in enumerate(rows) if "(default)" in _value(sw["knob"], r["value"], mode)), None)
            curves.append({"label": f"{sw['knob']} ({_fixed(sw['fixed'])})", "time": [r["cpu"] for r in rows],
                           "error": [r["error"] for r in rows], "values": [f"{r['value']:g}" for r in rows],
                           "default": d})
        plot_curves(ax, curves, xlabel="CPU time per f_s/f_c pair (s, median)", ylabel="max error of F_s, F_c (k* a)",
                    title=f"NumericalMicroslip, {mode}" + (" at 0.01 omega_c" if mode == "dynamic" else " (omega = 0)"))
        t_an = res["analytic"][mode]["new"]
        ax.axvline(t_an, color="k", ls="--", lw=0.8)
        ax.annotate("analytic element", (t_an, ax.get_ylim()[0]), textcoords="offset points",
                    xytext=(3, 10), fontsize=7)
        ax.set_xlim(left=t_an / 2)
    fig.suptitle(f"Numerical bar: error vs time per pair; dashed: the analytic element's time; {res['machine']['date']}",
                 fontsize=9)
    return save_figure(fig, path)


def main(argv=None):
    res = measure(log=lambda s: print(s, file=sys.stderr))
    print(machine_line(res["machine"]) + f"; median of {res['repeats']} runs\n")
    print(tables(res))
    print()
    print(matched(res))
    print(f"\nfigure: {plot(res)}")


if __name__ == "__main__":
    main()
