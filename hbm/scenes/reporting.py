"""Reporting a scene: the per-run summary, ``summary.json``, the figure and the text of the command line.

Nothing here prints: the functions return dicts and lines, and ``hbm.cli`` prints them.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from contact_models import QuasiStatic
from contact_models.quasi_static import StuckContact

from ..blade import Blade
from ..output import AMPLITUDE_UNITS, LEGEND_LIMIT, key_label, plot_frfs, plot_linear_reference
from .effects import linear_amplitude
from .modal import modal_lines
from .planning import Plan


def run_summary(res: Any, *, hz: bool = False) -> dict:
    """The summary.json entry of one :class:`hbm.scenes.running.RunResult`; ``hz``: the scene's
    frequencies are in Hz, and its peak says ``frequency_Hz`` beside ``omega_rad_s``."""
    p = res.plan
    out = {"run": res.number, "model": p.model, "normal_load_N": p.N, "element": repr(p.element),
           "success": res.success, "message": res.message, "points": res.points, "time_s": res.seconds}
    el = p.element
    inner = el.element if isinstance(el, StuckContact) else el
    if res.frf is not None:
        frf = res.frf
        out["counters"] = {"nsteps": frf.nsteps, "nit": frf.nit, "nfev": frf.nfev, "nstuck": frf.nstuck}
        if frf.tol is not None and len(frf):
            out["error"] = error_summary(frf)
        if res.peak is not None:
            a_min = p.a_min
            out["peak"] = {"omega_rad_s": res.peak.omega, "amplitude_m": res.peak.amplitude,
                           "amplitude_over_a_min": res.peak.amplitude / a_min if a_min else None}
            if frf.tol is not None and len(frf):
                out["peak"].update(peak_accuracy(frf))
            if hz:
                out["peak"] = {"frequency_Hz": res.peak.omega / (2.0 * math.pi), **out["peak"]}
            slip = next((e for e in p.effects if e.name == "damper slip"), None)
            if slip is not None and slip.simulated and "computed:" not in slip.reason:
                smallest = min(linear_amplitude(el, w) for w in thin(frf.omega))
                if smallest > 0.0:
                    top = float(np.max(frf.amplitude)) / smallest
                    slip.reason += (f"; computed: the largest amplitude is {top:.4g} a_min" if top >= 1.0 else
                                    f"; computed: every amplitude stayed below a_min (largest {top:.4g} a_min)")
    if res.table is not None:
        out["omega_rad_s"] = list(map(float, res.table["omega"]))
        if hz:
            out["frequency_Hz"] = [float(w) / (2.0 * math.pi) for w in res.table["omega"]]
        out["amplitude_unit"] = {"name": p.unit_name, "m": p.a_ref}
    out["effects"] = [e.as_dict() for e in p.effects]
    if isinstance(inner, QuasiStatic):
        out["quasi_static_calls"] = inner.calls  # every one at omega = 0
    return out


def error_summary(frf: Any) -> dict:
    """The estimated error of a run (``FrequencyResponse.error_estimate``): the tolerance, the
    largest estimate and where, the estimate at the sampled peak and its sources there, and
    whether it exceeds the tolerance, and the one ``AccuracyWarning`` the run printed (None if none)."""
    i, j = int(np.nanargmax(frf.error_estimate)), int(np.argmax(frf.amplitude))
    return {"tolerance": frf.tol, "largest": float(frf.error_estimate[i]),
            "largest_at_omega_rad_s": float(frf.omega[i]), "at_peak": float(frf.error_estimate[j]),
            "sources_at_peak": {k: float(v[j]) for k, v in frf.error_sources.items()},
            "above_tolerance": bool(frf.error_estimate[i] > frf.tol),
            "warning": frf.accuracy_warning}


def peak_accuracy(frf: Any) -> dict:
    """The peak's estimated error: ``error_rel`` (relative, the located peak's ``estimate``),
    ``largest_source`` (the largest part of the estimate at the peak's point, ``peak_point``), ``tol``,
    ``model`` (the model of that point, ``FrequencyResponse.point_models``: the bar with every mode
    where ``model="peak"`` refined the peak, e.g. ``"AllModeMicroslip(cells=64, H=31)"``) and
    ``harmonics`` (its H).  The peak is located between the neighbours of that point and carries the
    largest point estimate within two points of it (``hbm.adapt.locate_peak``,
    ``hbm.balance.errors.peak_estimate``)."""
    j = peak_point(frf)
    source = max(frf.error_sources, key=lambda k: frf.error_sources[k][j])
    est = frf.peak().estimate  # (None: nothing estimated at the peak, written as null)
    return {"error_rel": None if est is None else float(est), "largest_source": source, "tol": frf.tol,
            "model": str(frf.point_models[j]), "harmonics": int(frf.point_harmonics[j])}


def peak_point(frf: Any) -> int:
    """The index of the sampled point the peak of ``frf`` was located from: its largest point, or
    where some points were solved with another model than the whole range's first trace (``model="peak"``:
    the refined model in the peak's window), the largest of those, as ``frequency_response`` seeks it
    (``hbm.adapt.locate_peak``'s ``among``): the refined model's maximum is the peak there, whatever the
    coarse points outside read."""
    refined = frf.point_models != frf._work[0].point_models[0]  # the first trace: the contacts as given
    a = frf.amplitude
    return int(np.argmax(np.where(refined, a, -np.inf) if np.any(refined) else a))


def thin(omega: Any, n: int = 33) -> np.ndarray:
    """A few frequencies of the branch (the linear amplitude varies slowly with omega)."""
    omega = np.asarray(omega)
    return omega[np.unique(np.linspace(0, len(omega) - 1, min(n, len(omega))).astype(int))]


def jsonable(v: Any) -> Any:
    """``v`` with numpy scalars as Python numbers and non-finite floats as strings."""
    if isinstance(v, dict):
        return {k: jsonable(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [jsonable(x) for x in v]
    if isinstance(v, (np.floating, float)):
        v = float(v)
        return v if math.isfinite(v) else str(v)
    if isinstance(v, np.integer):
        return int(v)
    return v


def _model_of(label: str) -> str:
    return label.split(" (")[0]


def figure(scene: Any, results: list, path: str | Path, *, blade: Any = None) -> Path:
    """The scene's figure: FRFs (and peaks against the load for several loads), or F_s, F_c tables.

    Frequencies in Hz when the scene gives them in Hz, else rad/s; amplitudes in metres, as the CSV
    and ``python3 -m hbm``'s figure give them (one convention: SI); for a ``blade`` (``Plan.blade``) with up to
    ``hbm.output.LEGEND_LIMIT`` runs, each run's stuck (linear) response and its a_min line, as
    ``python3 -m hbm`` draws them.
    """
    import matplotlib  # heavy (0.1-0.5 s), lazily: only when the figure is drawn

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # heavy, lazily (above)

    title = scene.title or scene.name
    omega_unit = "Hz" if scene.sweep["unit"] == "Hz" else "rad/s"
    if scene.sweep["kind"] == "frequency":
        loads = sorted({r.plan.N for r in results if r.plan.N is not None})
        chart = len(loads) > 1
        fig, axes = plt.subplots(1, 2 if chart else 1, figsize=(11.0 if chart else 6.4, 4.4), squeeze=False)
        amplitude_unit = "m"
        curves = [(r.frf, r.plan.label, _model_of(r.plan.model), r.plan.N) for r in results]
        if len(curves) <= LEGEND_LIMIT:
            _linear_references(axes[0][0], blade, results, omega_unit, amplitude_unit)
        plot_frfs(curves, axes[0][0], parameter=key_label("damper.load.N"), omega_unit=omega_unit,
                  amplitude_unit=amplitude_unit)
        if chart:
            bx = axes[0][1]
            scale, label = AMPLITUDE_UNITS[amplitude_unit]
            for m in dict.fromkeys(_model_of(r.plan.model) for r in results):
                rs = [r for r in results if _model_of(r.plan.model) == m and r.plan.N is not None]
                bx.loglog([r.plan.N for r in rs], [r.peak.amplitude * scale for r in rs], "o-", ms=3, label=m)
            bx.set_xlabel(key_label("damper.load.N"))
            bx.set_ylabel("resonant " + label)
            bx.legend(fontsize=8)
    else:
        fig, axes = plt.subplots(1, 2, figsize=(11.0, 4.4), squeeze=False)
        for r in results:
            over = r.table["a"] / r.plan.a_ref
            for w, Fs, Fc in zip(r.table["omega"], r.table["F_s"], r.table["F_c"]):
                lab = (f"{r.plan.label}, {w / (2.0 * math.pi):.4g} Hz" if omega_unit == "Hz" else
                       f"{r.plan.label}, {w:.4g} rad/s")
                axes[0][0].semilogx(over, Fs, label=lab)
                axes[0][1].semilogx(over, Fc, label=lab)
        unit = "a (m)" if scene.sweep["amplitude_unit"] == "m" else f"a / {results[0].plan.unit_name}"
        for ax, name in zip(axes[0], ("F_s", "F_c")):
            ax.set_xlabel(unit)
            ax.set_ylabel(f"${name}$ = f/(k* a)")
            ax.grid(True, which="both", alpha=0.3)
        axes[0][1].legend(fontsize=6)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return Path(path)


def _linear_references(ax: Any, blade: Any, results: list, omega_unit: str, amplitude_unit: str) -> None:
    """The stuck (linear) response and the a_min line of each run of a blade with its damper
    (``hbm.output.plot_linear_reference``, as ``python3 -m hbm`` draws them), each distinct curve
    and level once, a_min in the run's colour when there are several runs; none for a structure
    from matrices (its stuck response is not a blade's)."""
    drawn_stuck, drawn_levels = [], []
    if not isinstance(blade, Blade):
        return
    for i, r in enumerate(results):
        if r.frf is None:
            continue
        element = r.plan.element
        inner = element.element if isinstance(element, StuckContact) else element
        key = (repr(inner), tuple(r.plan.omega))
        a_min = r.plan.a_min if r.plan.a_min not in drawn_levels else None
        if key in drawn_stuck and a_min is None:
            continue
        try:
            with np.errstate(all="ignore"):
                plot_linear_reference(ax, blade, element, r.plan.omega, a_min=a_min, omega_unit=omega_unit,
                                      amplitude_unit=amplitude_unit, label=not drawn_stuck,
                                      stiffness=_stuck_stiffness(element),
                                      a_min_color="C3" if len(results) == 1 else f"C{i % 10}")
        except (ArithmeticError, ValueError, NotImplementedError):
            continue  # an element without a stuck stiffness: no reference to draw
        drawn_stuck.append(key)
        drawn_levels.append(r.plan.a_min)


def _stuck_stiffness(element: Any) -> Any:
    """``omega -> K*(omega)`` of a run's element for the figure, without touching the counter of a
    quasi-static damper (``QuasiStatic.calls`` reports the run's evaluations in summary.json):
    a damper held stuck has its element's stiffness, a quasi-static one its element's at omega = 0."""
    if isinstance(element, StuckContact):
        element = element.element
    if isinstance(element, QuasiStatic):
        k = float(element.element.stuck_stiffness(0.0))
        return lambda om: np.full(np.shape(om), k)
    return lambda om: np.array([element.stuck_stiffness(x) for x in om])


def effect_lines(plan: Plan) -> list:
    """Per effect: simulated or not, in which runs, and why (the first run's reason when the runs'
    reasons differ; every run's is in summary.json).

    Parameters
    ----------
    plan : Plan
        The scene's plan (``plan_scene``), its effects decided.

    Returns
    -------
    list of str
        One line per effect and decision, ``"  name: simulated - reason"`` or
        ``"  name: not simulated [runs 1-3] - reason"`` when the runs' decisions differ.

    Examples
    --------
    >>> from hbm.scenes import effect_lines, plan_scene, scene_from_dict
    >>> scene = scene_from_dict({"damper": {"model": "macroslip", "stiffness": 1.0e6, "slip_force": 1.0},
    ...                          "sweep": {"kind": "amplitude", "omega": [0.0], "amplitude": [0.1, 10.0]}})
    >>> len(effect_lines(plan_scene(scene)))
    3
    """
    n = len(plan.runs)
    groups = {}
    for r in plan.runs:
        for e in r.effects:
            groups.setdefault(e.name, {}).setdefault(e.simulated, []).append((r.index + 1, e.reason))
    lines = []
    for name, by_sim in groups.items():
        for sim, items in by_sim.items():
            reasons = list(dict.fromkeys(reason for _, reason in items))
            which = "" if len(items) == n else f" [runs {_ranges([i for i, _ in items])}]"
            text = reasons[0] if len(reasons) == 1 else (
                f"{reasons[0]} (run {items[0][0]}; {len(reasons) - 1} other reason{'s' if len(reasons) > 2 else ''}: "
                "see summary.json)")
            lines.append(f"  {name}: {'simulated' if sim else 'not simulated'}{which} - {text}")
    return lines


def _estimate_text(pk: dict) -> str:
    """``; estimated error 1.2 % (tol 0.001, largest source: harmonics; model: AllModeMicroslip(cells=64, H=31),
    balance at H = 1)``: the model of the peak's point and the harmonics its balance was solved with."""
    model = pk["model"] + (f", balance at H = {pk['harmonics']}" if "harmonics" in pk else "")
    return (f"; estimated error {100.0 * pk['error_rel']:.2g} % (tol {pk['tol']:g}, largest source: "
            f"{pk['largest_source']}; model: {model})")


def _ranges(numbers) -> str:
    """[1, 2, 3, 6] -> '1-3, 6'."""
    out, start = [], None
    for k, i in enumerate(numbers):
        if start is None:
            start = i
        if k + 1 == len(numbers) or numbers[k + 1] != i + 1:
            out.append(f"{start}" if start == i else f"{start}-{i}")
            start = None
    return ", ".join(out)


def summary_lines(result: Any) -> list:
    """The end-of-run summary of a :class:`hbm.scenes.running.SceneResult` as lines of text.

    Parameters
    ----------
    result : SceneResult
        What ``run_scene`` returned.

    Returns
    -------
    list of str
        The scene, every effect (``effect_lines``), each run's points, time, counters and peak
        (omega in rad/s, and the frequency in Hz first when the scene is swept in Hz; amplitude in m), the files written and, after a failure, what failed
        and which points were kept.  The command line prints them; nothing here prints.
    """
    lines = []
    scene = result.plan.scene
    lines.append(f"scene: {scene.path}" + (f" ({scene.title})" if scene.title else ""))
    lines.append("effects:")
    lines += effect_lines(result.plan)
    for r in result.runs:
        s = r.summary
        head = f"run {r.number}: {r.plan.label}: {s['points']} points in {s['time_s']:.2f} s"
        if "counters" in s:
            c = s["counters"]
            head += f" ({c['nsteps']} steps, {c['nit']} Newton iterations, {c['nfev']} element evaluations)"
        lines.append(head + ("" if r.success else f": FAILED: {r.message}"))
        lines += modal_lines(r)
        if "peak" in s:
            pk = s["peak"]
            where = (f"f = {pk['frequency_Hz']:.9g} Hz (omega = {pk['omega_rad_s']:.9g} rad/s)" if "frequency_Hz" in pk
                     else f"omega = {pk['omega_rad_s']:.9g} rad/s")
            lines.append(f"  peak: {where}, amplitude = {pk['amplitude_m']:.9g} m"
                         + (f" (= {pk['amplitude_over_a_min']:.4g} a_min)" if pk["amplitude_over_a_min"] else "")
                         + (_estimate_text(pk) if "error_rel" in pk else ""))
    for path in result.files.values():
        lines.append(f"wrote {Path(path).resolve()}" + ("  (partial: failed run)" if path.name.endswith(".partial.csv")
                                                       else ""))
    if not result.success:
        lines.append(f"failed: {result.message}")
        lines.append(f"kept: {result.points} finished points" +
                     (f" in {Path(result.files['csv']).resolve()}" if "csv" in result.files else ""))
    return lines
