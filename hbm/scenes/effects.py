"""The physical effects of a scene: a sequence of small deciders, each returning its decision and why.

A scene simulates only the effects it calls for.  Each entry of :data:`EFFECTS` is an
:class:`EffectSpec`: its name, the ``[effects]`` key that sets it (if any) and a decider
``decide(run) -> Effect | None`` that looks at one planned run (an
:class:`hbm.scenes.planning.RunContext`) and returns what it decided and why: the
:class:`Effect`'s ``decided`` names the run settings it decides (switch the damper's inertia off,
pick the microslip topology, hold a damper stuck, take the all-mode bar, the balance's harmonics)
and the planner applies them; a decider changes nothing itself.  None means the effect does not
concern this run's model.  The deciders run in the order of :data:`EFFECTS`;
adding an effect is one :func:`register_effect` call (``docs/extending.md``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from contact_models import AllModeMicroslip, Bar, ThreeRegionMicroslip, TwoRegionMicroslip
from contact_models.microslip import region_solution
from contact_models.model_range import TOLERANCE, single_mode_frequency_limit
from contact_models.quasi_static import StuckContact

from ..balance.presets import samples_for
from ..balance.residual import MAX_BALANCE_HARMONICS, MAX_BALANCE_SAMPLES, linear_response
from .checks import Key, SceneError, boolean, choice, integer, Invalid, show
from .models import SCENE_HARMONICS, Built

#: Slip starts at the excited end when Bar.slip_onset's x* lies within this fraction of L of L.
ONSET_AT_END = 1e-9
#: Grid of the stuck-response check (points over the sweep) before the peak is refined.
STUCK_GRID = 4001
#: Frequencies at which the linear amplitude of a dynamic damper is sampled for the stuck check.
AMIN_SAMPLES = 65
#: The stuck response must stay below the linear amplitude by this relative margin to call the damper stuck.
STUCK_MARGIN = 1e-6
#: The whole curve takes the all-mode bar where the single-mode element is off by more than the scene's
#: tol over more than this share of the sweep (``phase_differences``)...
BULK = 0.5
#: ... read at this many frequencies over the sweep and amplitudes at each (``off_share``).
BULK_FREQUENCIES = 65
BULK_AMPLITUDES = 5


@dataclass
class Effect:
    """One physical effect of a run: simulated or not, and why.

    Parameters
    ----------
    name : str
        The effect's name (as registered with ``register_effect``).
    simulated : bool
        Whether the run simulates the effect.
    reason : str
        Why, in words (shown by ``python3 -m hbm run`` and written to ``summary.json``).
    decided : dict, optional
        The run settings decided, name -> value (``hbm.scenes.planning.DECISIONS``: ``"bar"``,
        ``"inertia"``, ``"topology"``, ``"element"``, ``"stuck"``, ``"model"``, ``"harmonics"``,
        ``"n_t"``); the planner applies them in order.  Default none.
    """

    name: str
    simulated: bool
    reason: str
    decided: dict = field(default_factory=dict)

    def as_dict(self) -> dict:
        return {"effect": self.name, "simulated": self.simulated, "reason": self.reason}


@dataclass(frozen=True)
class EffectSpec:
    """An effect: ``name``, the ``[effects]`` key that sets it (``key_name``, ``key``) and its decider.

    Parameters
    ----------
    name : str
        The effect's name.
    decide : callable
        ``decide(run) -> Effect or None``; ``run`` is the planned run's ``RunContext``, which the
        decider reads; what it decides for the run (its element, ``inertia``, ``topology``) it
        returns in ``Effect.decided``.  None: the effect does not apply to the run.
    key_name : str or None, optional
        The ``[effects]`` key that sets the effect, or None.
    key : Key or None, optional
        That key's check, default and doc (given with ``key_name``).
    """

    name: str
    decide: Callable[[Any], Effect | None]
    key_name: str | None = None
    key: Key | None = None


EFFECTS: list[EffectSpec] = []


def register_effect(name: str, decide: Callable[[Any], Effect | None], *, key_name: str | None = None,
                    key: Key | None = None, before: str | None = None) -> EffectSpec:
    """Add an effect decided by ``decide(run)``; ``key_name``/``key`` add ``effects.<key_name>``.

    The decider runs after the effects already registered, or just before the one named
    ``before``.  Returns the :class:`EffectSpec`.

    Parameters
    ----------
    name : str
        The effect's name (non-empty, not registered already).
    decide : callable
        ``decide(run) -> Effect or None``, called with each planned run's ``RunContext``.
    key_name : str or None, optional
        Name of the ``[effects]`` key that sets the effect; given with ``key``.  Default None.
    key : Key or None, optional
        The check, default and doc of ``effects.<key_name>``.  Default None.
    before : str or None, optional
        Name of a registered effect to decide just before; default None (after all of them).

    Returns
    -------
    EffectSpec
        The spec inserted into ``EFFECTS``.

    Raises
    ------
    ValueError
        When ``name`` is empty or registered already, ``decide`` is not callable, only one of
        ``key_name`` and ``key`` is given, ``key_name`` is another effect's key, or ``before``
        names no registered effect.

    Examples
    --------
    >>> from hbm.scenes import EFFECTS, Effect, register_effect, unregister_effect
    >>> spec = register_effect("note", lambda run: Effect("note", False, "a test effect"))
    >>> EFFECTS[-1].name
    'note'
    >>> unregister_effect("note")
    >>> any(e.name == "note" for e in EFFECTS)
    False
    """
    if not isinstance(name, str) or not name:
        raise ValueError(f"name must be a non-empty string, got name={name!r}")
    if any(e.name == name for e in EFFECTS):
        raise ValueError(f"name={name!r}: an effect of that name is registered already")
    if not callable(decide):
        raise ValueError(f"decide must be callable as decide(run) -> Effect | None, got decide={decide!r}")
    if (key_name is None) != (key is None):
        raise ValueError(f"key_name and key go together, got key_name={key_name!r}, key={key!r}")
    if key_name is not None and any(e.key_name == key_name for e in EFFECTS):
        raise ValueError(f"key_name={key_name!r}: effects.{key_name} is set by another effect already")
    spec = EffectSpec(name, decide, key_name, key)
    names = [e.name for e in EFFECTS]
    if before is not None and before not in names:
        raise ValueError(f"before={before!r} is not a registered effect; registered: {', '.join(names)}")
    EFFECTS.insert(names.index(before) if before is not None else len(EFFECTS), spec)
    return spec


def unregister_effect(name: str) -> None:
    """Remove the effect ``name``.

    Parameters
    ----------
    name : str
        The effect's name.

    Raises
    ------
    ValueError
        When no effect of that name is registered.
    """
    for i, e in enumerate(EFFECTS):
        if e.name == name:
            del EFFECTS[i]
            return
    raise ValueError(f"name={name!r} is not a registered effect")


# ====================================================================== the deciders
def strain_hardening(run: Any) -> Effect | None:
    """The spring beta at the bar's end x = 0: off sets beta = 0 in the bar of this run."""
    if run.bar is None:
        return None
    beta = run.bar.beta
    if not run.scene.effects["strain_hardening"]:
        b = run.bar
        return Effect("strain-hardening spring", False, "effects.strain_hardening = false: beta = 0" +
                      (f" (damper.beta = {beta:g} N/m left out)" if beta else ""),
                      decided={"bar": Bar(E=b.E, rho=b.rho, A=b.A, L=b.L, k=b.k, beta=0.0, mu=b.mu)})
    if beta == 0.0:
        return Effect("strain-hardening spring", False, "damper.beta = 0")
    return Effect("strain-hardening spring", True, f"beta = {beta:g} N/m")


def inertia(run: Any) -> Effect:
    """Damper inertia: from the stuck dynamic stiffness at the top of the sweep (``auto``).

    A model on the microslip bar decides from the bar before its element is built; any other
    model from its element's ``stuck_stiffness`` (a frequency-independent element is massless).
    Off, the element is wrapped in ``contact_models.QuasiStatic`` (omega = 0 in the damper).
    """
    tol = run.scene.effects["tolerance"]
    setting = run.scene.effects["inertia"]
    w_hi = max(run.omega)
    if run.spec.microslip is not None:
        bar = run.bar
        K0 = float(bar.stuck_stiffness(0.0))
        change = abs(float(bar.stuck_stiffness(w_hi)) / K0 - 1.0)
        at = (f"|K*(omega_max)/k* - 1| = {change:.3g} at omega_max = {w_hi:.6g} rad/s "
              f"({w_hi / bar.omega_c:.4g} omega_c)")
        slide = _sliding_change(bar, run.load, w_hi)
        info = "" if slide is None else f" (for information: the fully slipping bar's stiffness changes by {slide:.3g} there)"
    else:
        element = run.element
        if not element.frequency_dependent:
            note = f" ({run.note})" if run.note else ""
            return Effect("damper inertia", False, f"{run.label} element: massless, frequency independent{note}",
                          decided={"inertia": False})
        if getattr(element, "components", 1) != 1:
            return _two_component_inertia(run, setting)
        K0 = float(element.stuck_stiffness(0.0))
        change = abs(float(element.stuck_stiffness(w_hi)) / K0 - 1.0) if K0 else math.inf
        at = f"|K*(omega_max)/K*(0) - 1| = {change:.3g} at omega_max = {w_hi:.6g} rad/s"
        info = ""
    if setting == "auto":
        simulated = change > tol
        reason = f"auto: {at}, {'above' if simulated else 'not above'} effects.tolerance = {tol:g}"
    else:
        simulated = setting == "on"
        reason = f"effects.inertia = {show(setting)} ({at})"
    if not simulated:
        reason += ": quasi-static damper (omega = 0 in the damper)"
    reason += info
    if run.spec.name == "point-contact":
        reason += "; the point contact itself is massless: inertia enters through its fit"
    return Effect("damper inertia", simulated, reason, decided={"inertia": simulated})


def _two_component_inertia(run: Any, setting: str) -> Effect:
    """A frequency-dependent element of two components keeps its inertia: the quasi-static wrapper
    (``QuasiStatic``) reads one displacement component; ``effects.inertia = "off"`` is refused."""
    why = (f"the {run.label} element acts on a tangential and a normal displacement, and the quasi-static "
           "damper (QuasiStatic) reads one")
    if setting == "off":
        raise SceneError([f"{run.where('effects.inertia')} = \"off\": not available with damper.model = "
                          f"{show(run.spec.name)}: {why}; use \"auto\" or \"on\" (its inertia is simulated)"])
    return Effect("damper inertia", True, f"effects.inertia = {show(setting)}: simulated ({why})",
                  decided={"inertia": True})


def topology(run: Any) -> Effect | None:
    """Two or three regions, from where slip starts on the bar (Section 2.1), at the damper
    frequencies the element will see (``run.probe_frequencies()``)."""
    if run.spec.microslip is None:
        return None
    asked = run.spec.microslip(run.params)
    bar, load = run.bar, run.load
    onsets = [(w, bar.slip_onset(load, w)[0] / bar.L) for w in run.probe_frequencies()]
    interior = [w for w, x in onsets if x < 1.0 - ONSET_AT_END]
    shown = {f"{x:.4g}" for _, x in onsets}
    if len(shown) == 1 and len(onsets) > 1:  # one onset at every frequency: said once
        ws = [f"{w:.6g}" for w, _ in onsets]
        where = f"x*/L = {shown.pop()} at {', '.join(ws[:-1])} and {ws[-1]} rad/s"
    else:
        where = ", ".join(f"x*/L = {x:.4g} at {w:.6g} rad/s" for w, x in onsets)
    if asked == "auto":
        name = "three-region" if interior else "two-region"
        why = (f"auto: slip starts inside the bar ({where}): three regions" if interior else
               f"auto: slip starts at the excited end ({where}): two regions")
    else:
        name = asked
        why = f"{run.micro_key} = {show(asked)} (slip starts at {where}; x*/L = 1 is the excited end)"
        if name == "three-region" and not interior:
            why += "; slip starts at the excited end, so the element follows its two-region path"
    return Effect("interior slip onset (three regions)", name == "three-region", f"{why}; {run.load_text}",
                  decided={"topology": name})


def slip(run: Any) -> Effect:
    """A damper whose stuck (linear) response never reaches its linear amplitude is a linear spring."""

    if run.blade is None:
        return Effect("damper slip", True, "amplitude sweep: the amplitudes are given")
    if run.scene.modes is not None:
        return Effect("damper slip", True, "a nonlinear mode: its modal amplitudes are given (modes.amplitude), "
                                           "from the stuck mode into slip")
    if run.scene.structure is not None:
        return Effect("damper slip", True, "a structure from [structure]: the stuck check is made for a blade only; "
                                           "the balance answers amplitudes within the damper's linear range from "
                                           "its linear coefficients")
    peak, smallest = stuck_peak(run.blade, run.element, run.omega)
    if smallest == 0.0:
        return Effect("damper slip", True, "the element is nonlinear at every amplitude (linear_amplitude = 0)")
    ratio = peak / smallest
    if ratio < 1.0 - STUCK_MARGIN:
        return Effect("damper slip", False,
                      f"damper stayed stuck: linear spring (the stuck response peaks at {peak:.4g} m = "
                      f"{ratio:.4g} of the smallest slip amplitude {smallest:.4g} m in the sweep)",
                      decided={"stuck": True})
    return Effect("damper slip", True, f"the stuck response reaches {ratio:.4g} times the slip amplitude "
                                       f"({peak:.4g} m against {smallest:.4g} m)")


def phase_differences(run: Any) -> Effect | None:
    """Phase differences along the bar: the all-mode bar (``AllModeMicroslip``) for the whole curve
    where the single-mode element is off by more than the scene's ``sweep.tol`` over the bulk of the
    sweep, the single-mode one where it holds there (it is far cheaper).

    The single-mode element's amplitude-aware model error (``ContactElement.model_error``, the
    validity map) is read at ``BULK_FREQUENCIES`` frequencies over the sweep (:func:`off_share`);
    the whole curve takes the all-mode bar when it exceeds ``sweep.tol`` over more than ``BULK`` of
    them.  Otherwise a ``damper.model = "auto"`` frequency sweep of a blade at H = 1 keeps the
    single-mode element and solves with ``model="peak"`` (``hbm.scenes.running.peak_refined``): where
    the estimate's model part at the curve's largest point exceeds half of tol, the windows of the
    curve that hold the peak are traced again with the bar of every mode, and the peak is that
    model's maximum.

    ``effects.phase_differences``: "auto" (default) decides for ``damper.model = "auto"`` and
    reports, without switching, for an explicitly chosen "two-region" or "three-region"; "on"
    takes the all-mode bar for any of the three; "off" never does.  The point contact and other
    models are not concerned.  Runs after "damper slip": a damper that stays stuck needs no
    all-mode bar (the single-mode stuck stiffness is exact).
    """
    if run.spec.microslip is None or run.spec.name not in ("auto", "two-region", "three-region"):
        return None

    setting = run.scene.effects["phase_differences"]
    name = "phase differences along the bar"
    if not run.inertia:
        return Effect(name, False, "no damper inertia: the quasi-static bar is in phase along its length")
    if run.stuck:
        return Effect(name, False, "the damper stays stuck: the single-mode stuck stiffness is exact")
    micro, tol = run.micro, run.scene.sweep["tol"]
    if micro.bar.mu * micro.load.N == 0.0:
        return Effect(name, False, "no friction (mu N = 0): the bar slides freely, a linear spring the "
                                   "single-mode solution gives exactly")
    share, worst, how = off_share(run, micro, tol)
    wc = micro.bar.omega_c
    at = (f"the single-mode element is off by more than tol = {tol:g} over {share:.0%} of the sweep "
          f"(its model error of F_s, F_c up to {worst:.2g}, {how}; the response's estimate is in the "
          f"summary; within {TOLERANCE:.0%} at every amplitude up to "
          f"{single_mode_frequency_limit(micro) / wc:.3g} omega_c, the sweep reaches {max(run.omega) / wc:.3g} omega_c)")
    bulk = share > BULK
    if setting == "on" or (setting == "auto" and bulk and run.spec.name == "auto"):
        element = AllModeMicroslip(micro.bar, micro.load, harmonics=SCENE_HARMONICS)
        model = Built(element, "all-mode" if setting == "on" else "all-mode (auto)", run.note)
        why = 'effects.phase_differences = "on"' if setting == "on" else f"auto: more than {BULK:.0%}"
        cells = f"{element.cells} cells" if element.cells is not None else "cells chosen by its tolerance"
        return Effect(name, True, f"{why}: {at}; AllModeMicroslip for the whole curve (all modes, {cells}, "
                                  f"H = {element.harmonics})", decided={"model": model})
    if setting == "off":
        return Effect(name, False, f'effects.phase_differences = "off": {at}')
    if run.spec.name != "auto":
        return Effect(name, False, f"auto: {at}, but damper.model = {show(run.spec.name)} asks for the single-mode "
                                   'element (damper.model = "auto" or effects.phase_differences = "on" takes '
                                   "the all-mode bar)")
    peak = ("; the peak is the all-mode bar's where the estimate's model part there exceeds tol/2 "
            '(frequency_response(..., model="peak"))' if run.blade is not None and run.scene.structure is None
            and run.scene.sweep["kind"] == "frequency" and run.scene.effects["harmonics"] == 1 else "")
    return Effect(name, False, f"auto: not more than {BULK:.0%}: {at}: single-mode element{peak}")


def off_share(run: Any, micro: Any, tol: float) -> tuple[float, float, str]:
    """``(share, worst, how)``: the share of the sweep where the single-mode ``micro`` is off by more
    than ``tol`` (``micro.model_error``), its largest error there, and how the amplitudes were taken.

    A frequency sweep of a blade: at ``BULK_FREQUENCIES`` frequencies, the largest error between the
    slip amplitude a_min(omega) and the stuck response (the blade with the damper's stuck stiffness),
    between which the response lies where the damper slips (0 where the stuck response stays below
    a_min: the damper is stuck there, the element exact).  An amplitude sweep: the table's own points.
    Otherwise (a structure, a nonlinear mode: the amplitudes are not known before the solve): every
    amplitude of the validity map (0.5 to 100 a_min(0)) at each frequency."""
    if run.blade is not None and run.scene.structure is None and run.scene.sweep["kind"] == "frequency":
        w = np.linspace(min(run.omega), max(run.omega), BULK_FREQUENCIES)
        top = np.abs(linear_response(run.blade, w, micro.bar.stuck_stiffness))
        low = np.array([micro.linear_amplitude(float(x)) for x in w])
        e = [float(np.max(micro.model_error(np.geomspace(lo, hi, BULK_AMPLITUDES), x))) if hi > lo else 0.0
             for x, lo, hi in zip(w, low, top)]
        return float(np.mean(np.array(e) > tol)), max(e), "between a_min and the stuck response"
    if run.blade is None:  # an amplitude sweep: its table's points
        sweep = run.scene.sweep
        a_ref = 1.0 if sweep["amplitude_unit"] == "m" else float(micro.slip_amplitude(0.0))
        a = np.geomspace(*sweep["amplitude"], sweep["points"]) * a_ref
        e = np.array([micro.model_error(a, float(x)) for x in run.omega])
        return float(np.mean(e > tol)), float(np.max(e)), "at the table's amplitudes"
    w = np.linspace(min(run.omega), max(run.omega), BULK_FREQUENCIES)
    a = np.geomspace(0.5, 100.0, BULK_AMPLITUDES) * float(micro.slip_amplitude(0.0))
    e = [float(np.max(micro.model_error(a, float(x)))) for x in w]
    return float(np.mean(np.array(e) > tol)), max(e), "at every amplitude of the validity map"


def harmonics_key(v: Any) -> int:
    """``effects.harmonics``: H in 1..``MAX_BALANCE_HARMONICS`` (the balance's bound, so that ``--check``
    refuses what the run would); above 1 every element of the scene needs a time law."""
    return _bounded(integer(1)(v), 1, MAX_BALANCE_HARMONICS, "MAX_BALANCE_HARMONICS")


def samples_key(v: Any) -> int:
    """``effects.samples``: n_t in 3..``MAX_BALANCE_SAMPLES`` (the balance's bound); its lower bound
    2 H + 2 is checked with H (:func:`harmonics`)."""
    return _bounded(integer(3)(v), 3, MAX_BALANCE_SAMPLES, "MAX_BALANCE_SAMPLES")


def _bounded(v: int, lo: int, hi: int, bound: str) -> int:
    if v > hi:
        raise Invalid(f"must be an integer in {lo}..{hi} (the bound is hbm.balance.residual.{bound})")
    return v


def harmonics(run: Any) -> Effect:
    """Higher harmonics of the balance: H = 1 the single-harmonic balance; H > 1 the multi-harmonic
    balance with AFT (``hbm.balance``) for a frequency sweep, where the element (after the
    inertia decider: ``QuasiStatic`` without damper inertia) must own a time-domain law."""
    H = run.scene.effects["harmonics"]
    samples = run.scene.effects.get("samples")
    multi = run.blade is not None and (H > 1 or run.scene.structure is not None)
    if samples is not None and not multi:
        raise SceneError([f"{run.where('effects.samples')} = {samples}: not used here: only a multi-harmonic "
                          "balance samples the period (a [structure], or effects.harmonics > 1 in a frequency "
                          "sweep); leave it out"])
    if samples is not None and samples < 2 * H + 2:  # the balance's aliasing bound (hbm.balance.residual)
        raise SceneError([f"{run.where('effects.samples')} = {samples}: must be at least 2 H + 2 = {2 * H + 2} "
                          f"samples per period for effects.harmonics = {H}"])
    if H == 1:  # a structure's balance is the multi-harmonic one at H = 1; a blade's the single-harmonic one
        # the scene asks for H = 1: the balance keeps it (frequency_response would otherwise choose H to tol)
        decided = {"harmonics": 1, **({"n_t": samples} if samples and run.scene.structure is not None else {})}
        return Effect("higher harmonics", False,
                      "effects.harmonics = 1: single-harmonic balance (first-harmonic f_s, f_c" +
                      (f"; AFT with n_t = {samples} samples where an element needs its time law)" if samples else ")"),
                      decided=decided)
    if run.blade is None:
        return Effect("higher harmonics", False, f"effects.harmonics = {H}: an amplitude sweep tabulates the "
                                                 "first-harmonic f_s, f_c of the element; no balance is solved")
    element = run.element
    if isinstance(element, StuckContact):
        return Effect("higher harmonics", False, f"effects.harmonics = {H}: the damper stays stuck (a linear "
                                                 "spring), so the response has no higher harmonics")
    if not element.has_time_law:
        raise SceneError([f"{run.where('effects.harmonics')} = {H}: harmonics = {H} needs an element with a "
                          f"time-domain force law, but the {run.label} element {type(element).__name__} has none "
                          "(with damper inertia the single-mode bar is a first-harmonic element); use "
                          "harmonics = 1" + (", damper.model = \"all-mode\" (the bar with every mode has one)"
                                             if run.spec.microslip is not None else "")
                          + " or effects.inertia = \"off\""])

    n_t = samples or harmonic_samples(H)
    return Effect("higher harmonics", True, f"effects.harmonics = {H}: multi-harmonic balance with AFT, "
                                            f"n_t = {n_t} samples per period "
                                            f"({type(element).__name__} has a time-domain law)",
                  decided={"harmonics": H, "n_t": n_t})


def harmonic_samples(H: int) -> int:
    """The AFT samples per period of a scene's balance at ``H`` harmonics: what
    ``frequency_response`` takes for H (``hbm.balance.presets.samples_for``)."""
    return samples_for(H)


# ====================================================================== helpers
def _sliding_change(bar, load, omega):
    """|K_slip(omega)/K_slip(0) - 1| of the bar sliding as a whole (the slope of the loading curve
    past gross slip, which F_s tends to at large amplitude), or None where it is not defined."""

    try:
        with np.errstate(all="ignore"):
            k0 = float(region_solution(bar, load.on(bar.L), 0.0, None, 0.0).K_tip)
            kw = float(region_solution(bar, load.on(bar.L), 0.0, None, omega).K_tip)
        v = abs(kw / k0 - 1.0)
    except (ArithmeticError, ValueError):
        return None
    return v if math.isfinite(v) else None


def linear_amplitude(element: Any, omega: float) -> float:
    """The element's linear amplitude at ``omega``; for a dynamic bar from ``Bar.slip_onset``
    (no loading path built)."""
    bar, load = getattr(element, "bar", None), getattr(element, "load", None)
    if bar is not None and load is not None and element.frequency_dependent:
        return float(bar.slip_onset(load, omega)[1])
    return float(element.linear_amplitude(omega))


def stuck_peak(blade: Any, element: Any, omega: tuple) -> tuple[float, float]:
    """(largest amplitude of the blade with the damper linear over the range, smallest linear
    amplitude there)."""
    from scipy.optimize import minimize_scalar  # heavy (0.1-0.5 s), lazily: import hbm stays light

    w0, w1 = min(omega), max(omega)
    lins = [linear_amplitude(element, w) for w in np.linspace(w0, w1, AMIN_SAMPLES)]
    smallest = min(lins)
    if smallest == 0.0:
        return math.nan, 0.0
    bar = getattr(element, "bar", None)
    if not element.frequency_dependent:
        ks, kc = element.linear_coefficients(0.0)
        K = lambda om: np.full_like(om, ks + 1j * kc, dtype=complex)  # noqa: E731
    elif bar is not None:
        K = bar.stuck_stiffness  # vectorised
    else:
        K = lambda om: np.array([complex(*element.linear_coefficients(x)) for x in om])  # noqa: E731

    def amp(w):
        w = np.atleast_1d(np.asarray(w, dtype=float))
        return np.abs(linear_response(blade, w, K))

    grid = np.linspace(w0, w1, STUCK_GRID)
    a = amp(grid)
    i = int(np.argmax(a))
    best = float(a[i])
    if 0 < i < STUCK_GRID - 1 and np.isfinite(best):
        res = minimize_scalar(lambda w: -float(amp(w)[0]), bounds=(grid[i - 1], grid[i + 1]), method="bounded",
                              options={"xatol": 1e-12 * w1})
        best = max(best, -float(res.fun))
    if not np.isfinite(best):
        best = math.inf
    return best, smallest


register_effect("strain-hardening spring", strain_hardening, key_name="strain_hardening",
                key=Key(boolean, True, "the spring beta at x = 0: true, or false (beta = 0)"))
register_effect("damper inertia", inertia, key_name="inertia",
                key=Key(choice("on", "off", "auto"), "auto",
                        'damper inertia: "on", "off" (quasi-static damper, omega = 0 in it) or "auto"'))
register_effect("interior slip onset (three regions)", topology)
register_effect("damper slip", slip)
register_effect("phase differences along the bar", phase_differences, key_name="phase_differences",
                key=Key(choice("auto", "on", "off"), "auto",
                        'the all-mode bar (AllModeMicroslip): "auto" (for damper.model = "auto": the whole curve '
                        'where the single-mode element is off by more than sweep.tol over most of the sweep; else '
                        'the peak\'s window where needed), "on" or "off"'))
register_effect("higher harmonics", harmonics, key_name="harmonics",
                key=Key(harmonics_key, 1, "harmonics of the balance (H >= 1; above 1 the element needs a "
                                                "time-domain law: multi-harmonic balance with AFT)"))
