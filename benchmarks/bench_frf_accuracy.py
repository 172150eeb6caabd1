"""What accuracy costs in ``hbm.frequency_response``: ``tol`` and the step controls of ``hbm.Steps``.

Cases:

- the default blade with the single-mode damper (``hbm.cli.cases.default_case()``: blade + two-region
  microslip bar, which has no time law, so H = 1 throughout);
- P1: m = k = 1, c = 0.004, F = 0.01 with a Jenkins element ``Macroslip(1, 0.02)`` to ground over
  0.6..1.8 rad/s, whose H the tolerance chooses along the curve.

Knobs, each swept with the others at their defaults: ``tol`` (the presets are tolerances: "fast"
1e-2, "default" 1e-3, "precise" 1e-5), and ``Steps.max_step``, ``Steps.min_step``,
``Steps.max_steps``, ``Steps.curve_tol``.

Per setting: ``frequency_response(...)`` + ``.peak()``, CPU and wall time (median of ``REPEATS``, all
settings of a case round-robin, so ratios are from the same run), points, the largest H, whether the
branch reached the end of the range, whether the call warned (``AccuracyWarning``), the peak's
estimate, and two errors:

- peak: max(|a_pk/a_ref - 1|, |w_pk/w_ref - 1|).  For P1 the reference is the true periodic peak by
  shooting (``tests/data/periodic_reference.json``), independent of the balance.  For the default
  blade it is the same model solved to ``tol = 1e-9`` with ``max_step = 0.005``: a convergence study
  of the given model (its distance from the bar with every mode, the estimate's model source, is the
  subject of "The physical curve" in ``docs/performance.md``);
- curve: the largest distance of a dense trace (``tol = 1e-6``, ``max_step = 0.005``) from the
  computed polyline, in the plane (omega / (w1 - w0), a / a_peak): how far the drawn curve is from the
  branch, as a fraction of the plot's width and height.

Run ``python benchmarks/bench_frf_accuracy.py``: prints the tables, writes
``docs/figures/accuracy_frf.png``.
"""

from __future__ import annotations

import json
import sys
import warnings

import numpy as np

from contact_models import AccuracyWarning, Macroslip
from hbm import Blade, Steps, frequency_response
from hbm.balance import presets
from hbm.cli.cases import default_case

from common import FIGURES, REPEATS, ROOT, interleaved, machine, machine_line, once, plot_curves, save_figure, sci, table

#: The references: the default blade's peak (its own model converged) and both curves.
PEAK_REFERENCE = {"tol": 1e-9, "steps": Steps(max_step=0.005)}
CURVE_REFERENCE = {"tol": 1e-6, "steps": Steps(max_step=0.005)}
STEP_DEFAULTS = Steps()
DEFAULTS = {"tol": presets.TOLERANCE["default"], "max_step": STEP_DEFAULTS.max_step,
            "min_step": STEP_DEFAULTS.min_step, "max_steps": STEP_DEFAULTS.max_steps,
            "curve_tol": STEP_DEFAULTS.curve_tol}
KNOBS = {
    "tol": (1e-2, 1e-3, 1e-4, 1e-5, 1e-6),
    "max_step": (0.3, 0.1, 0.03, 0.01),
    "min_step": (1e-12, 1e-9, 1e-5, 1e-2),
    "max_steps": (100, 150, 200, 250, 5000),
    "curve_tol": (None, 1e-3, 1e-5),
}
#: The preset names of the tolerances swept.
PRESET_OF = {v: k for k, v in presets.TOLERANCE.items()}
P1 = "P1 (Jenkins, c = 0.004, F_s = 0.02)"


def cases():
    """name -> (system, element, omega_range, true peak (omega, a) or None)."""
    c = default_case()
    ref = json.loads((ROOT / "tests" / "data" / "periodic_reference.json").read_text())["jenkins"]["P1"]
    p, pk = ref["parameters"], ref["peak_amplitude"]
    blade = Blade(mass=p["mass"], stiffness=p["stiffness"], damping=p["damping"], force=p["force"])
    return {
        "default blade, single-mode damper": (c.blade, c.element, c.omega_range, None),
        P1: (blade, Macroslip(p["contact_stiffness"], p["slip_force"]), (0.6, 1.8), (pk["omega"], pk["amplitude"])),
    }


def settings():
    """(knob, value, keyword arguments) of every run; the all-default run once, as knob None."""
    out = [(None, None, {})]
    for knob, values in KNOBS.items():
        for v in values:
            if v == DEFAULTS[knob]:
                continue
            out.append((knob, v, {"tol": v} if knob == "tol" else {"steps": Steps(**{knob: v})}))
    return out


def solved(system, element, omega_range, kwargs):
    """The FRF, its peak and whether the call warned."""
    with warnings.catch_warnings(record=True) as heard:
        warnings.simplefilter("always", AccuracyWarning)
        f = frequency_response(system, element, omega_range, stability=False, **kwargs)
        pk = f.peak()
    return f, pk, any(issubclass(w.category, AccuracyWarning) for w in heard)


def curve_error(frf, ref, width, a_peak):
    """Largest distance of the reference points from the polyline of ``frf`` (scaled plane)."""
    if len(frf) < 2:
        return np.inf
    P = np.column_stack([ref.omega / width, ref.amplitude / a_peak])
    Q = np.column_stack([frf.omega / width, frf.amplitude / a_peak])
    A, D = Q[:-1], np.diff(Q, axis=0)
    dd = np.maximum(np.sum(D * D, axis=1), 1e-300)
    best = np.full(len(P), np.inf)
    for i in range(0, len(P), 256):
        p = P[i:i + 256, None, :]
        t = np.clip(np.sum((p - A) * D, axis=2) / dd, 0.0, 1.0)
        d = np.hypot(*np.moveaxis(p - (A + t[..., None] * D), 2, 0))
        best[i:i + 256] = np.min(d, axis=1)
    return float(np.max(best))


def measure(repeats: int = REPEATS, log=print):
    out = {"machine": machine(), "repeats": repeats, "cases": {}}
    for name, (system, element, omega_range, true_peak) in cases().items():
        dense, _, _ = solved(system, element, omega_range, CURVE_REFERENCE)
        if true_peak is None:
            _, pk, _ = solved(system, element, omega_range, PEAK_REFERENCE)
            true_peak = (pk.omega, pk.amplitude)
        w_ref, a_ref = true_peak
        width = abs(omega_range[1] - omega_range[0])
        runs = settings()

        def task(kwargs):
            return lambda: once(lambda: solved(system, element, omega_range, kwargs))

        times = interleaved([task(kw) for _, _, kw in runs], repeats)
        rows = []
        for (knob, value, _), t in zip(runs, times):
            f, pk, warned = t.value
            ea, ew = abs(pk.amplitude / a_ref - 1.0), abs(pk.omega / w_ref - 1.0)
            rows.append({"knob": knob, "value": value, "points": len(f), "success": bool(f.success),
                         "harmonics": int(np.max(f.point_harmonics)), "warned": warned,
                         "peak_estimate": float(pk.estimate), "estimate_max": float(np.nanmax(f.error_estimate)),
                         "peak_amplitude_error": ea, "peak_omega_error": ew,
                         "peak_error": max(ea, ew), "curve_error": curve_error(f, dense, width, a_ref),
                         "cpu": t.cpu, "wall": t.wall})
            log(f"  {name} {knob}={value}: {len(f)} points, peak error {max(ea, ew):.1e}, estimate "
                f"{pk.estimate:.1e}, curve {rows[-1]['curve_error']:.1e}, CPU {t.cpu:.3f} s, wall {t.wall:.3f} s")
        out["cases"][name] = {"rows": rows, "independent": name == P1,
                              "reference": {"points": len(dense), "omega": w_ref, "amplitude": a_ref}}
    return out


def rows_for(rows, knob):
    """The knob's rows, the all-default run in its place, in the order of ``KNOBS[knob]``; and that run."""
    base = next(r for r in rows if r["knob"] is None)
    sel = {r["value"]: r for r in rows if r["knob"] == knob}
    sel[DEFAULTS[knob]] = dict(base, value=DEFAULTS[knob])
    return [dict(sel[v], knob=knob) for v in KNOBS[knob]], base


def shown(knob, v):
    """A knob's value as the tables print it: the default and the preset names said."""
    text = "None" if v is None else f"{v:g}"
    if knob == "tol" and v in PRESET_OF:
        return text + f' ("{PRESET_OF[v]}")'  # "default" says it
    return text + (" (default)" if v == DEFAULTS[knob] else "")


def tables(res) -> str:
    parts = []
    for name, data in res["cases"].items():
        rows = []
        for knob in KNOBS:
            kr, base = rows_for(data["rows"], knob)
            for r in kr:
                rows.append([f"`{knob}`", shown(knob, r["value"]), r["points"], r["harmonics"],
                             "yes" if r["success"] else "**no**", sci(r["peak_amplitude_error"]),
                             sci(r["peak_omega_error"]), sci(r["peak_estimate"]), "yes" if r["warned"] else "no",
                             sci(r["curve_error"]), f"{r['cpu']:.3f}", f"{r['wall']:.3f}",
                             f"{r['cpu'] / base['cpu']:.2f}"])
        ref = data["reference"]
        how = ("the true periodic peak by shooting" if data["independent"] else
               f"the same model at tol = {PEAK_REFERENCE['tol']:g}, max_step = {PEAK_REFERENCE['steps'].max_step:g}")
        parts.append(f"**{name}** (peak reference: {how}, omega = {ref['omega']:.10g}, a = {ref['amplitude']:.10g}; "
                     f"curve reference: {ref['points']} points)\n\n" + table(
                         ["knob", "value", "points", "largest H", "reached w1", "peak a error", "peak omega error",
                          "peak estimate", "warned", "curve error", "CPU (s)", "wall (s)", "CPU / default"], rows))
    return "\n\n".join(parts)


def plot(res, path=None):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    path = path or FIGURES / "accuracy_frf.png"
    names = list(res["cases"])
    fig, axes = plt.subplots(2, len(names), figsize=(6.2 * len(names), 9.0), squeeze=False)
    for j, name in enumerate(names):
        rows = res["cases"][name]["rows"]
        for i, (metric, label) in enumerate((("peak_error", "peak error (max of amplitude, omega; relative)"),
                                             ("curve_error", "curve error (fraction of plot width/height)"))):
            curves = []
            for knob in KNOBS:
                kr, _ = rows_for(rows, knob)
                ok = [r for r in kr if np.isfinite(r[metric])]
                d = next((k for k, r in enumerate(ok) if r["value"] == DEFAULTS[knob]), None)
                curves.append({"label": knob if knob == "tol" else f"Steps.{knob}",
                               "time": [r["cpu"] for r in ok], "error": [r[metric] for r in ok],
                               "values": ["None" if r["value"] is None else f"{r['value']:g}" for r in ok],
                               "default": d})
            plot_curves(axes[i, j], curves, xlabel="CPU time of FRF + peak (s, median)", ylabel=label, title=name)
    fig.suptitle(f"frequency_response: error vs time, one curve per knob (others at defaults); {res['machine']['date']}",
                 fontsize=9)
    return save_figure(fig, path)


def main(argv=None):
    res = measure(log=lambda s: print(s, file=sys.stderr))
    print(machine_line(res["machine"]) + f"; median of {res['repeats']} runs\n")
    print(tables(res))
    print(f"\nfigure: {plot(res)}")


if __name__ == "__main__":
    main()
