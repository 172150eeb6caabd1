"""What accuracy costs in ``hbm.frequency_response``.

Cases:

- the default case (``hbm.cli.cases.default_case()``: blade + two-region microslip damper);
- a Jenkins blade: m = k = 1, zeta = 1e-4, F = 0.5, ``Macroslip(stiffness=1, slip_force=1)``
  over 0.5..2 rad/s (a sharp peak, amplification ~1e3).

Knobs, each swept with the others at their defaults: ``rtol`` (the element's tolerance and
the Newton tolerance of every point), ``max_step``, ``min_step``, ``max_steps``; then the
presets of ``hbm.balance.presets`` (``accuracy="fast"/"default"/"precise"`` and two rtol values).

Per setting: ``frequency_response(...)`` + ``.peak()``, CPU and wall time (median of
``REPEATS``, all settings of a case round-robin, so ratios are from the same run), points,
success, and two errors:

- peak: max(|a_pk/a_ref - 1|, |w_pk/w_ref - 1|), the reference being, for the default case,
  the same FRF at rtol = 1e-11, max_step = 0.005, and for Jenkins the independent quartic
  computation (``bench_frf.jenkins_peak``);
- curve: the largest distance of the reference branch (rtol = 1e-11, max_step = 0.005) from the
  computed polyline, in the plane (omega / (w1 - w0), a / a_peak): how far the drawn curve is
  from the true one, as a fraction of the plot's width and height.

Run ``python benchmarks/bench_frf_accuracy.py``: prints the tables, writes
``docs/figures/accuracy_frf.png``.
"""

from __future__ import annotations

import sys

import numpy as np

from hbm import Blade, frequency_response
from hbm.balance import presets
from hbm.cli.cases import default_case

from bench_frf import jenkins_peak, macroslip
from common import FIGURES, REPEATS, interleaved, machine, machine_line, once, plot_curves, save_figure, sci, table

#: The reference branch (peak of the default case, curve of both).
REFERENCE = {"rtol": 1e-11, "max_step": 0.005}
JENKINS_ZETA = 1e-4
DEFAULTS = {"rtol": 1e-6, "max_step": presets.DEFAULT_MAX_STEP, "min_step": presets.DEFAULT_MIN_STEP,
            "max_steps": presets.DEFAULT_MAX_STEPS}
KNOBS = {
    "rtol": (1e-2, 1e-3, 1e-4, 1e-6, 1e-8, 1e-10),
    "max_step": (0.3, 0.1, 0.03, 0.01),
    "min_step": (1e-12, 1e-9, 1e-5, 1e-2),
    "max_steps": (100, 150, 200, 250, 5000),
}
#: Presets measured: the names, and rtol values through accuracy=<float>.
PRESETS = ("fast", 1e-4, "default", 1e-8, "precise")


def cases():
    c = default_case()
    blade = Blade.from_modal(frequency=1.0, damping_ratio=JENKINS_ZETA, mass=1.0, force=0.5)
    jen = macroslip(1.0, 1.0)

    def jenkins_reference(frf):
        pk = frf.peak()
        return jenkins_peak(blade, 1.0, 1.0, (0.9 * pk.amplitude, 1.1 * pk.amplitude))

    return {
        "default case": (c.blade, c.element, c.omega_range, None),
        f"Jenkins, zeta = {JENKINS_ZETA:g}": (blade, jen, (0.5, 2.0), jenkins_reference),
    }


def settings():
    """(knob, value, keyword arguments) of every run; the all-default run once, as knob None."""
    out = [(None, None, {})]
    for knob, values in KNOBS.items():
        out += [(knob, v, {knob: v}) for v in values if v != DEFAULTS[knob]]
    out += [("accuracy", p, {"accuracy": p}) for p in PRESETS]
    return out


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
    for name, (blade, element, omega_range, independent) in cases().items():
        ref = frequency_response(blade, element, omega_range=omega_range, **REFERENCE)
        ref_pk = ref.peak()
        w_ref, a_ref = independent(ref) if independent is not None else (ref_pk.omega, ref_pk.amplitude)
        width = abs(omega_range[1] - omega_range[0])
        runs = settings()

        def task(kwargs):
            def run():
                def go():
                    f = frequency_response(blade, element, omega_range=omega_range, **kwargs)
                    f.peak()
                    return f
                return once(go)
            return run

        times = interleaved([task(kw) for _, _, kw in runs], repeats)
        rows = []
        for (knob, value, kwargs), t in zip(runs, times):
            f = t.value
            pk = f.peak()
            ea, ew = abs(pk.amplitude / a_ref - 1.0), abs(pk.omega / w_ref - 1.0)
            row = {"knob": knob, "value": value, "points": len(f), "success": bool(f.success),
                   "peak_amplitude_error": ea, "peak_omega_error": ew, "peak_error": max(ea, ew),
                   "curve_error": curve_error(f, ref, width, a_ref), "cpu": t.cpu, "wall": t.wall,
                   "nfev": f.nfev, "settings": {"rtol": f.rtol}}
            if knob == "accuracy":
                row["settings"] = presets.resolve(value).options()
            rows.append(row)
            log(f"  {name} {knob}={value}: {len(f)} points, peak error {max(ea, ew):.1e}, "
                f"curve {row['curve_error']:.1e}, CPU {t.cpu:.3f} s, wall {t.wall:.3f} s")
        out["cases"][name] = {"rows": rows, "reference": {"points": len(ref), "omega": w_ref, "amplitude": a_ref},
                              "independent": independent is not None}
    return out


def _rows_for(rows, knob):
    """The knob's rows plus the all-default run, in the order of KNOBS[knob]."""
    base = next(r for r in rows if r["knob"] is None)
    if knob == "accuracy":
        return [r for r in rows if r["knob"] == "accuracy"], base
    sel = {r["value"]: r for r in rows if r["knob"] == knob}
    sel[DEFAULTS[knob]] = dict(base, value=DEFAULTS[knob])
    return [dict(sel[v], knob=knob) for v in KNOBS[knob]], base


def _value(knob, v):
    if knob == "accuracy":
        return repr(v) if isinstance(v, str) else f"{v:g}"
    return f"{v:g}" + (" (default)" if v == DEFAULTS[knob] else "")


def tables(res) -> str:
    parts = []
    for name, data in res["cases"].items():
        rows = []
        for knob in list(KNOBS):
            kr, base = _rows_for(data["rows"], knob)
            for r in kr:
                rows.append([f"`{knob}`", _value(knob, r["value"]), r["points"], "yes" if r["success"] else "**no**",
                             sci(r["peak_amplitude_error"]), sci(r["peak_omega_error"]), sci(r["curve_error"]),
                             f"{r['cpu']:.3f}", f"{r['wall']:.3f}", f"{r['cpu'] / base['cpu']:.2f}"])
        ref = data["reference"]
        how = ("the independent quartic computation" if data["independent"] else
               f"the FRF at rtol = {REFERENCE['rtol']:g}, max_step = {REFERENCE['max_step']:g}")
        parts.append(f"**{name}** (peak reference: {how}, omega = {ref['omega']:.10g}, a = {ref['amplitude']:.10g}; "
                     f"curve reference: {ref['points']} points)\n\n" + table(
                         ["knob", "value", "points", "reached w1", "peak a error", "peak omega error", "curve error",
                          "CPU (s)", "wall (s)", "CPU / default"], rows))
    return "\n\n".join(parts)


def preset_table(res) -> str:
    """The presets on each case: settings, errors, time."""
    rows = []
    for name, data in res["cases"].items():
        kr, base = _rows_for(data["rows"], "accuracy")
        for r in kr:
            s = r["settings"]
            rows.append([name, f"`accuracy={_value('accuracy', r['value'])}`", f"{s['rtol']:g}", f"{s['max_step']:.3g}",
                         s["max_steps"], r["points"], sci(r["peak_error"]), sci(r["curve_error"]), f"{r['cpu']:.3f}",
                         f"{r['cpu'] / base['cpu']:.2f}"])
    return table(["case", "preset", "rtol", "max_step", "max_steps", "points", "peak error", "curve error", "CPU (s)",
                  "CPU / default"], rows)


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
            for knob in list(KNOBS) + ["accuracy"]:
                kr, _ = _rows_for(rows, knob)
                ok = [r for r in kr if np.isfinite(r[metric])]
                d = next((k for k, r in enumerate(ok) if knob != "accuracy" and r["value"] == DEFAULTS[knob]), None)
                if knob == "accuracy":
                    d = next((k for k, r in enumerate(ok) if r["value"] == "default"), None)
                curves.append({"label": "presets (accuracy=)" if knob == "accuracy" else knob,
                               "time": [r["cpu"] for r in ok], "error": [r[metric] for r in ok],
                               "values": [_value(knob, r["value"]).replace(" (default)", "") for r in ok], "default": d})
            plot_curves(axes[i, j], curves, xlabel="CPU time of FRF + peak (s, median)", ylabel=label, title=name)
    fig.suptitle(f"frequency_response: error vs time, one curve per knob (others at defaults); {res['machine']['date']}",
                 fontsize=9)
    return save_figure(fig, path)


def main(argv=None):
    res = measure(log=lambda s: print(s, file=sys.stderr))
    print(machine_line(res["machine"]) + f"; median of {res['repeats']} runs\n")
    print(tables(res))
    print("\nPresets:\n")
    print(preset_table(res))
    print(f"\nfigure: {plot(res)}")


if __name__ == "__main__":
    main()
