"""What accuracy costs in the analytic microslip elements.

Elements: ``TwoRegionMicroslip`` (uniform load, 100 N) and ``ThreeRegionMicroslip`` (concave
load ``QuadraticLoad.from_ratio(100, 12)``) on the reference bar (docs/theory.md).  Knobs:

- ``rtol`` of ``fourier`` (public; the quadrature refines its Gauss-Legendre rule until two
  successive rules agree to ``rtol / 10``);
- the module constants of ``contact_models.microslip`` behind it: ``GAUSS_START`` (the first
  rule, the loop resolution), ``GAUSS_MAX`` (the largest rule tried) and ``TABLE_POINTS`` (the
  per-frequency table that starts the inversion s(t) = a and finds the folds).

Error: the largest of |f_s - f_s,ref| and |f_c - f_c,ref| relative to |(f_s,ref, f_c,ref)|
over amplitudes from a_min to 3 a_gross (clustered at both ends of the microslip range) and
omega in {0.01, 0.1, 0.2, 0.3, 0.4, 0.5} omega_c; the reference is ``fourier(..., rtol=1e-13)``
with ``TABLE_POINTS = 257`` (``REFERENCE_CONSTANTS``).  Times (median of ``REPEATS``): one call with 1000 amplitudes
(0.5 a_min to 3 a_gross, geometric) and one scalar call at 0.3 omega_c, each at a new frequency
(a fresh element: the loading path is built in the call) and at a cached one; the settings
of one knob are timed round-robin.

Times are process CPU time (steady on a shared machine); the wall time of the main column is
given beside it.

Run ``python benchmarks/bench_element.py``: prints the tables, writes
``docs/figures/accuracy_element.png``.
"""

from __future__ import annotations

import contextlib
import sys

import numpy as np

import contact_models._path_integrals as quadrature
import contact_models.microslip as ms
from contact_models import Bar, QuadraticLoad, ThreeRegionMicroslip, TwoRegionMicroslip, UniformLoad

from common import FIGURES, REPEATS, interleaved, machine, machine_line, ms as fmt_ms, once, plot_curves, save_figure, sci, table

BAR = dict(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
#: Frequencies of the error set, as fractions of omega_c.
FREQUENCIES = (0.01, 0.1, 0.2, 0.3, 0.4, 0.5)
#: Frequency of the timed calls, as a fraction of omega_c.
TIMED_FREQUENCY = 0.3
REFERENCE_RTOL = 1e-13
#: The reference also uses a finer table: with 65 points the three-region element misses the
#: shallow onset folds at 0.1-0.2 omega_c (an error of ~1e-9 just above a_min, see the tables).
REFERENCE_CONSTANTS = {"TABLE_POINTS": 257}
#: The swept values of each knob (the library's default is marked in the output).
KNOBS = {
    "rtol": (1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12),
    "GAUSS_START": (2, 4, 8, 12, 16),
    "TABLE_POINTS": (17, 33, 65, 129, 257),
    "GAUSS_MAX": (24, 96, 384),
}
DEFAULTS = {"rtol": 1e-6, "GAUSS_START": ms.GAUSS_START, "TABLE_POINTS": ms.TABLE_POINTS,
            "GAUSS_MAX": ms.GAUSS_MAX}
#: rtol used while sweeping a module constant (GAUSS_MAX only matters when rules keep refining).
KNOB_RTOL = {"rtol": None, "GAUSS_START": 1e-6, "TABLE_POINTS": 1e-6, "GAUSS_MAX": 1e-13}


def elements():
    bar = Bar(**BAR)
    return {
        "TwoRegionMicroslip (uniform)": lambda: TwoRegionMicroslip(bar, UniformLoad(N=100.0)),
        "ThreeRegionMicroslip (concave 12)": lambda: ThreeRegionMicroslip(bar, QuadraticLoad.from_ratio(N=100.0, ratio=12.0)),
    }


@contextlib.contextmanager
def constants(**values):
    """Set module constants of ``contact_models.microslip`` for the duration of the block, in the
    module that reads them (the quadrature's live in ``contact_models._path_integrals``)."""
    owner = {k: quadrature if hasattr(quadrature, k) else ms for k in values}
    old = {k: getattr(owner[k], k) for k in values}
    try:
        for k, v in values.items():
            setattr(owner[k], k, v)
        yield
    finally:
        for k, v in old.items():
            setattr(owner[k], k, v)


def amplitudes(el, omega):
    """Amplitudes of the error set: just above a_min, across microslip, around gross slip, beyond."""
    a0, ag = el.slip_amplitude(omega), el.gross_slip_amplitude(omega)
    eps = np.geomspace(1e-8, 1e-1, 8)
    return np.concatenate([a0 * (1 + eps), np.geomspace(a0, ag, 42)[1:-1], ag * (1 - eps), ag * (1 + eps),
                           [2 * ag, 3 * ag]])


def error_set(make, omega_c):
    el = make()
    return [(w * omega_c, amplitudes(el, w * omega_c)) for w in FREQUENCIES]


def max_error(make, points, refs, rtol):
    """Largest relative error over the set, and where: (error, omega/omega_c, a/a_min(omega))."""
    el = make()
    worst = (0.0, float("nan"), float("nan"))
    for (w, a), (fs0, fc0) in zip(points, refs):
        fs, fc = el.fourier(a, w, rtol=rtol)
        e = np.maximum(np.abs(fs - fs0), np.abs(fc - fc0)) / np.hypot(fs0, fc0)
        i = int(np.argmax(e))
        if e[i] > worst[0]:
            worst = (float(e[i]), w / el.bar.omega_c, float(a[i] / el.slip_amplitude(w)))
    return worst


def measure(repeats: int = REPEATS, log=print):
    out = {"machine": machine(), "repeats": repeats, "elements": {}}
    for name, make in elements().items():
        el = make()
        omega_c = el.bar.omega_c
        points = error_set(make, omega_c)
        with constants(**REFERENCE_CONSTANTS):
            ref_el = make()
            refs = [ref_el.fourier(a, w, rtol=REFERENCE_RTOL) for w, a in points]
        w = TIMED_FREQUENCY * omega_c
        a_min, a_g = el.slip_amplitude(w), el.gross_slip_amplitude(w)
        a1000 = np.geomspace(0.5 * a_min, 3.0 * a_g, 1000)
        a1 = 2.0 * a_min

        def warm():
            e = make()
            e.fourier(a1, w)
            return e

        def task(a, rtol, patch, setup):
            def run():
                with constants(**patch):
                    return once(lambda e: e.fourier(a, w, rtol=rtol), setup)
            return run

        knobs = {}
        for knob, values in KNOBS.items():
            settings = []
            for v in values:
                rtol = v if knob == "rtol" else KNOB_RTOL[knob]
                patch = {} if knob == "rtol" else {knob: v}
                with constants(**patch):
                    err, w_worst, a_worst = max_error(make, points, refs, rtol)
                settings.append((v, rtol, patch, (err, w_worst, a_worst)))
            tasks = [task(a, rtol, patch, setup) for v, rtol, patch, err in settings
                     for a, setup in ((a1000, make), (a1000, warm), (a1, make), (a1, warm))]
            times = interleaved(tasks, repeats)
            rows = []
            for k, (v, rtol, patch, (err, w_worst, a_worst)) in enumerate(settings):
                t_vc, t_vw, t_sc, t_sw = times[4 * k:4 * k + 4]
                rows.append({"value": v, "default": v == DEFAULTS[knob], "rtol": rtol, "error": err,
                             "worst_omega": w_worst, "worst_a": a_worst,
                             "vec_cold": t_vc.cpu, "vec_warm": t_vw.cpu, "scalar_cold": t_sc.cpu,
                             "scalar_warm": t_sw.cpu, "vec_cold_wall": t_vc.wall})
                log(f"  {name} {knob}={v:g}: error {err:.2e}, CPU 1000 a {t_vc.cpu * 1e3:.1f} ms (new omega), "
                    f"{t_vw.cpu * 1e3:.1f} ms (cached), scalar {t_sc.cpu * 1e3:.2f} / {t_sw.cpu * 1e3:.2f} ms")
            knobs[knob] = rows
        out["elements"][name] = {"knobs": knobs, "npoints": int(sum(a.size for _, a in points))}
    return out


def _where(r):
    """Where the largest error sits; not meaningful at the rounding level."""
    if r["error"] < 1e-13:
        return "(rounding)"
    return f"{r['worst_omega']:.2g}, {r['worst_a']:.10g}"


def tables(res) -> str:
    parts = []
    for name, data in res["elements"].items():
        rows = []
        for knob, kr in data["knobs"].items():
            base = next(r for r in kr if r["default"])
            for r in kr:
                v = f"{r['value']:g}" + (" (default)" if r["default"] else "")
                note = "" if knob == "rtol" else f" (rtol {r['rtol']:g})"
                rows.append([f"`{knob}`{note}", v, sci(r["error"]), _where(r), fmt_ms(r["vec_cold"]), fmt_ms(r["vec_cold_wall"]),
                             fmt_ms(r["vec_warm"]), fmt_ms(r["scalar_cold"]), fmt_ms(r["scalar_warm"]),
                             f"{r['vec_cold'] / base['vec_cold']:.2f}"])
        parts.append(f"**{name}** ({data['npoints']} (a, omega) points in the error set)\n\n" + table(
            ["knob", "value", "max rel. error", "where (omega/omega_c, a/a_min)", "1000 a, new omega: CPU", "(wall)", "1000 a, cached omega",
             "scalar, new omega", "scalar, cached omega", "CPU / default (1000 a, new omega)"], rows))
    return "\n\n".join(parts)


def plot(res, path=None):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    path = path or FIGURES / "accuracy_element.png"
    names = list(res["elements"])
    fig, axes = plt.subplots(1, len(names), figsize=(6.2 * len(names), 4.6))
    for ax, name in zip(np.atleast_1d(axes), names):
        curves = []
        for knob, kr in res["elements"][name]["knobs"].items():
            d = next((i for i, r in enumerate(kr) if r["default"]), None)
            label = knob if knob == "rtol" else f"{knob} (rtol {KNOB_RTOL[knob]:g})"
            curves.append({"label": label, "time": [r["vec_cold"] for r in kr], "error": [r["error"] for r in kr],
                           "values": [f"{r['value']:g}" for r in kr], "default": d})
        plot_curves(ax, curves, xlabel="CPU time of one call, 1000 amplitudes at a new omega (s, median)",
                    ylabel="max relative error of f_s, f_c", title=name)
        top = max(r["error"] for kr in res["elements"][name]["knobs"].values() for r in kr)
        ax.set_ylim(1e-16, max(1e-5, 10 * top))
        ax.axhspan(1e-16, 1e-14, color="0.9", zorder=0)
        ax.text(0.02, 0.02, "rounding level", transform=ax.transAxes, fontsize=7, color="0.4")
    fig.suptitle(f"Analytic elements: error vs time (errors below 1e-16 drawn at 1e-16); {res['machine']['date']}",
                 fontsize=9)
    return save_figure(fig, path)


def main(argv=None):
    res = measure(log=lambda s: print(s, file=sys.stderr))
    print(machine_line(res["machine"]) + f"; median of {res['repeats']} runs\n")
    print(tables(res))
    print(f"\nfigure: {plot(res)}")


if __name__ == "__main__":
    main()
