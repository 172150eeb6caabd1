"""Running a scene with ``[modes]`` or ``[optimum]``: the nonlinear mode, or the damper's optimum.

A ``[modes]`` scene computes, per run, the nonlinear mode of its system (the blade as a one-DOF
structure, ``hbm.Blade.as_structure``, or the ``[structure]`` with its contact) with the run's
planned element: ``hbm.nonlinear_modes`` (``docs/nonlinear_modes.md``).  An ``[optimum]`` scene
finds the value of one damper key that minimises the resonance peak: ``hbm.damper_optimum``, whose
elements at each parameter value come from the planner (``hbm.scenes.planning.plan_at``), so the
same deciders make them as made the plan.  The rows, the summary entries, the console lines and
the figure of both are here; ``hbm.scenes.running`` calls them.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from ..damper_optimum import damper_optimum
from ..frf import RTOL_SHARE
from ..modes import nonlinear_modes
from ..single_mode import forcing
from ..structure import Contact
from .contacts import damper_contact
from .planning import RunPlan, plan_at

#: The columns of ``modes.csv`` after the run's: per point of the mode.
MODE_COLUMNS = ("modal_amplitude", "omega_rad_s", "damping_ratio", "response_amplitude_m")
#: The columns of ``optimum.csv`` after the run's: per point of the peak followed in the parameter.
OPTIMUM_COLUMNS = ("parameter", "peak_amplitude_m", "peak_omega_rad_s")


def system_of(scene: Any, system: Any, element: Any, others: Any = ()) -> tuple[Any, list, int | None]:
    """``(structure, contacts, response_dof)`` of a run: the blade as a one-DOF structure with the
    element at DOF 0, or the ``[structure]`` with the element at ``structure.contact_dofs`` and
    ``others``, the structure's own contacts (``Plan.contacts``)."""
    if scene.structure is None:
        return system.as_structure(), [Contact(element, dof=0)], 0
    return system, [damper_contact(scene, element), *others], scene.structure.get("response_dof")


def elements_rtol(opts: dict) -> float:
    """The elements' rtol of a mode's scene: ``sweep.tolerance`` (or its default), capped at ``RTOL_SHARE`` of
    ``sweep.tol`` where given, as ``frequency_response`` caps it (its one accuracy key)."""
    return min(opts["rtol"], RTOL_SHARE * opts["tol"]) if "tol" in opts else opts["rtol"]


def run_modes(scene: Any, plan: Any, res: Any, emit: Any) -> None:
    """The nonlinear mode of one run (``hbm.nonlinear_modes``), one row per point."""
    p, m, opts = res.plan, scene.modes, scene.sweep["options"]
    structure, contacts, dof = system_of(scene, plan.blade, p.element, plan.contacts)
    modes = nonlinear_modes(structure, contacts, mode=m["mode"], amplitude_range=m.get("amplitude"),
                            amplitudes=m.get("amplitudes"), harmonics=p.harmonics or 1, n_t=p.n_t,
                            rtol=elements_rtol(opts), max_step=opts["max_step"], max_steps=opts["max_steps"])
    dof = forcing(modes.balance, None, dof)[1]
    span = np.log10([modes.amplitude.min(), modes.amplitude.max()]) if len(modes) else (0.0, 0.0)
    for a, w, D, r in zip(modes.amplitude, modes.omega, modes.damping_ratio, response_amplitude(modes, dof)):
        fraction = (math.log10(a) - span[0]) / (span[1] - span[0]) if span[1] > span[0] else 1.0
        emit([repr(float(v)) for v in (a, w, D, r)], float(w), fraction)
    res.modes, res.response_dof = modes, dof
    res.success, res.message = modes.success, modes.message


def response_amplitude(modes: Any, dof: int) -> np.ndarray:
    """The first-harmonic amplitude ``a |Psi_1[dof]|`` of ``dof`` at every point of the mode."""
    c = modes.coefficients(dof)
    return np.hypot(c[:, 1], c[:, 2])


def effect_flags(run: RunPlan) -> list:
    """``[(effect, simulated)]`` of a planned run: what must not change along the optimum's curve."""
    return [(e.name, e.simulated) for e in run.effects]


def run_optimum(scene: Any, plan: Any, res: Any, emit: Any) -> None:
    """The damper's optimum of one run (``hbm.damper_optimum``), one row per point of the peak curve."""
    p, opts = res.plan, scene.sweep["options"]
    name, bounds = scene.optimum["parameter"], scene.optimum["bounds"]
    structure, _, dof = system_of(scene, plan.blade, p.element, plan.contacts)
    planned = effect_flags(p)

    def contacts_of(value):
        at = plan_at(scene, plan.blade, p, float(value))
        if effect_flags(at) != planned:
            raise ValueError(f"{name} = {value:g}: the effects differ from those planned at the bounds "
                             f"({effect_flags(at)} against {planned})")
        return system_of(scene, plan.blade, at.element, plan.contacts)[1]

    opt = damper_optimum(structure, contacts_of, bounds, amplitude_range=scene.modes["amplitude"],
                         mode=scene.modes["mode"], harmonics=p.harmonics or 1, n_t=p.n_t, response_dof=dof,
                         max_step=opts["max_step"], max_steps=opts["max_steps"])
    for v, a, w in zip(opt.parameters, opt.peaks, opt.peak_omega):
        emit([repr(float(x)) for x in (v, a, w)], float(w), (float(v) - bounds[0]) / (bounds[1] - bounds[0]))
    res.optimum = opt
    res.success, res.message = opt.success, opt.message


def modal_summary(res: Any, scene: Any) -> dict:
    """The summary.json entries of a mode's run (``"mode"``) or an optimum's run (``"optimum"``)."""
    if getattr(res, "modes", None) is not None:
        m = res.modes
        out = {"points": len(m), "mode": scene.modes["mode"], "harmonics": m.harmonics, "n_t": m.n_t,
               "response_dof": res.response_dof,
               "counters": {"nsteps": m.nsteps, "nrejected": m.nrejected, "nit": m.nit, "nfev": m.nfev},
               "success": m.success, "message": m.message}
        if len(m):
            out.update(modal_amplitude=[float(m.amplitude.min()), float(m.amplitude.max())],
                       omega_rad_s=[float(m.omega.min()), float(m.omega.max())],
                       damping_ratio=[float(m.damping_ratio.min()), float(m.damping_ratio.max())])
        return {"mode": out}
    if getattr(res, "optimum", None) is not None:
        o = res.optimum
        return {"optimum": {"parameter": scene.optimum["parameter"], "value": o.parameter,
                            "bounds": list(scene.optimum["bounds"]),
                            "peak": {"omega_rad_s": o.peak.omega, "amplitude_m": o.peak.amplitude},
                            "points": int(len(o.parameters)), "counters": {"nsteps": o.nsteps, "nfev": o.nfev},
                            "success": o.success, "message": o.message}}
    return {}


def modal_lines(res: Any) -> list:
    """The console lines of a mode's or an optimum's run (after its head line)."""
    s = res.summary
    if "mode" in s and "omega_rad_s" in s["mode"]:
        m = s["mode"]
        return [f"  mode {m['mode']}: {m['points']} points, modal amplitude {m['modal_amplitude'][0]:.4g} .. "
                f"{m['modal_amplitude'][1]:.4g}, omega {m['omega_rad_s'][0]:.9g} .. {m['omega_rad_s'][1]:.9g} rad/s, "
                f"damping ratio {m['damping_ratio'][0]:.4g} .. {m['damping_ratio'][1]:.4g}"]
    if "optimum" in s:
        o = s["optimum"]
        return [f"  optimum: {o['parameter']} = {o['value']:.9g} in [{o['bounds'][0]:g}, {o['bounds'][1]:g}]: "
                f"peak amplitude = {o['peak']['amplitude_m']:.9g} m at omega = {o['peak']['omega_rad_s']:.9g} rad/s"]
    return []


def modal_figure(scene: Any, results: list, path: str | Path) -> Path:
    """A mode's figure (frequency and damping ratio against the modal amplitude, log amplitude axis)
    or an optimum's (the peak amplitude against the parameter, the optimum marked)."""
    import matplotlib  # heavy (0.1-0.5 s), lazily: only when the figure is drawn

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # heavy, lazily (above)

    if scene.modes is not None and scene.optimum is None:
        fig, (ax, bx) = plt.subplots(2, 1, figsize=(7.2, 5.6), sharex=True)
        for r in results:
            if r.modes is not None and len(r.modes):
                ax.semilogx(r.modes.amplitude, r.modes.omega, label=r.plan.label)
                bx.semilogx(r.modes.amplitude, 100.0 * r.modes.damping_ratio, label=r.plan.label)
        ax.set_ylabel(r"$\omega$ (rad/s)")
        bx.set_ylabel("modal damping ratio D (%)")
        bx.set_xlabel("modal amplitude a")
        axes = (ax, bx)
    else:
        fig, ax = plt.subplots(figsize=(6.4, 4.4))
        for r in results:
            o = r.optimum
            if o is not None:
                line, = ax.plot(o.parameters, o.peaks, label=r.plan.label)
                ax.plot(o.parameter, o.peak.amplitude, "*", ms=12, color=line.get_color(),
                        label=f"optimum {o.parameter:.6g}")
        ax.set_xlabel(scene.optimum["parameter"])
        ax.set_ylabel("resonant amplitude (m)")
        axes = (ax,)
    for a in axes:
        a.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle(scene.title or scene.name, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return Path(path)


__all__ = ["MODE_COLUMNS", "OPTIMUM_COLUMNS", "run_modes", "run_optimum", "modal_summary", "modal_lines",
           "modal_figure", "system_of", "response_amplitude"]
