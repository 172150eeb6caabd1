"""Scenes: a study described once in a TOML file, validated, planned and run.

A scene names the blade, the damper (model, bar, normal load), the physical effects in play, the
sweep and the outputs (``docs/scenes.md`` documents every key).  Three steps, each usable alone:

- :func:`load_scene` reads the file with ``tomllib`` and validates it against :data:`SCHEMA`:
  unknown keys (with the closest valid name), wrong types, missing values, values out of range.
  Every problem is reported at once in a :class:`SceneError` naming the file, ``table.key``, the
  value and what is allowed.
- :func:`plan_scene` decides the effects and builds the contact elements.  An effect the scene
  leaves out is not computed: damper inertia off wraps the element in
  ``contact_models.QuasiStatic`` (omega = 0 in the damper); ``auto`` keeps it only if the stuck
  bar's dynamic stiffness at the top of the sweep differs from k* by more than the tolerance;
  model ``auto`` picks two or three regions from where slip starts (``Bar.slip_onset``); a
  damper whose stuck response never reaches its slip amplitude becomes a linear spring
  (``contact_models.quasi_static.StuckContact``).  Physically impossible scenes (a load that
  the chosen model cannot carry, a sweep outside the model's range) raise :class:`SceneError`.
- :func:`run_scene` computes every run and writes the outputs as it goes: each accepted point
  is appended to ``frf.partial.csv`` and flushed, which is renamed ``frf.csv`` when every run
  succeeded; ``summary.json`` (written last, atomically) lists each effect, simulated or not
  and why, the peaks, counters and timing.

Nothing here prints; ``python -m hbm run SCENE.toml`` (``hbm.__main__``) is the command line.
"""

from __future__ import annotations

import csv
import difflib
import json
import math
import time
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, NamedTuple

import numpy as np

from . import presets

#: Accuracy presets of ``[sweep] accuracy``: (tolerance, max_step), those of ``hbm.presets``.
ACCURACY_PRESETS = {name: (acc.rtol, acc.max_step)
                    for name, acc in ((n, presets.from_rtol(r)) for n, r in presets.NAMED.items())}
#: Slip starts at the excited end when Bar.slip_onset's x* lies within this fraction of L of L.
ONSET_AT_END = 1e-9
#: Grid of the stuck-response check (points over the sweep) before the peak is refined.
STUCK_GRID = 4001
#: Frequencies at which a_min(omega) of a dynamic bar is sampled for the stuck-response check.
AMIN_SAMPLES = 65
#: The stuck response must stay below a_min by this relative margin to call the damper stuck.
STUCK_MARGIN = 1e-6

MICROSLIP_MODELS = ("two-region", "three-region", "auto")
MODELS = MICROSLIP_MODELS + ("macroslip", "point-contact")


class SceneError(ValueError):
    """An invalid scene: ``problems`` lists every message (file, table.key, value, what is allowed)."""

    def __init__(self, problems):
        self.problems = list(problems)
        super().__init__("\n".join(self.problems))


# ====================================================================== schema
class _Invalid(Exception):
    """A value check failed; the argument says what is allowed."""


REQUIRED = object()  # marker: the key must be given (whatever else the scene says)
OPTIONAL = None  # the key may be left out; its meaning then depends on other keys (see doc)


class Key(NamedTuple):
    """One key of a table: ``check(value) -> converted`` (raises _Invalid), default, doc."""

    check: Callable
    default: object
    doc: str


def _show(v) -> str:
    """A value as it would be written in TOML."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, float) and math.isinf(v):
        return "inf" if v > 0 else "-inf"
    if isinstance(v, float) and math.isnan(v):
        return "nan"
    if isinstance(v, list):
        return "[" + ", ".join(_show(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{k} = {_show(x)}" for k, x in v.items()) + "}"
    return repr(v)


def _number(*, gt=None, ge=None, lt=None, unit="", allow_inf=False):
    parts = [p for p in (f"> {gt:g}" if gt is not None else None, f">= {ge:g}" if ge is not None else None,
                         f"< {lt:g}" if lt is not None else None) if p]
    what = "a number" + (" " + " and ".join(parts) if parts else "") + (f" ({unit})" if unit else "")
    if allow_inf:
        what += " or inf"

    def check(v):
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise _Invalid(f"must be {what}")
        v = float(v)
        if math.isnan(v) or (math.isinf(v) and not (allow_inf and v > 0)):
            raise _Invalid(f"must be {what} (finite)" if not allow_inf else f"must be {what}")
        if ((gt is not None and not v > gt) or (ge is not None and not v >= ge)
                or (lt is not None and not v < lt)):
            raise _Invalid(f"must be {what}")
        return v

    check.what = what
    return check


def _integer(minimum):
    def check(v):
        if isinstance(v, bool) or not isinstance(v, int) or v < minimum:
            raise _Invalid(f"must be an integer >= {minimum}")
        return int(v)

    return check


def _boolean(v):
    if not isinstance(v, bool):
        raise _Invalid("must be true or false")
    return v


def _text(v):
    if not isinstance(v, str):
        raise _Invalid("must be a string")
    return v


def _choice(*names):
    allowed = ", ".join(json.dumps(n) for n in names)

    def check(v):
        if not isinstance(v, str) or v not in names:
            hint = ""
            if isinstance(v, str):
                close = difflib.get_close_matches(v, names, n=1)
                hint = f" (did you mean {json.dumps(close[0])}?)" if close else ""
            raise _Invalid(f"must be one of {allowed}{hint}")
        return v

    check.names = names
    return check


def _one_or_list(item, what):
    """A single value or a non-empty list of distinct values (a study over them); returns a tuple."""

    def check(v):
        values = v if isinstance(v, list) else [v]
        if not values:
            raise _Invalid(f"must be {what}, or a non-empty list of them")
        try:
            out = tuple(item(x) for x in values)
        except _Invalid as exc:
            raise _Invalid(f"{exc} (or a list of such values)") from None
        if len(set(out)) != len(out):
            raise _Invalid("must not repeat a value")
        return out

    return check


def _number_list(item, *, length=None, minimum=1):
    def check(v):
        if not isinstance(v, list) or (length is not None and len(v) != length) or len(v) < minimum:
            n = f"{length}" if length is not None else f"at least {minimum}"
            raise _Invalid(f"must be a list of {n} numbers, each {item.what}")
        try:
            return tuple(item(x) for x in v)
        except _Invalid as exc:
            raise _Invalid(f"must be a list of {len(v)} numbers, each {item.what}") from exc

    return check


def _harmonics(v):
    v = _integer(1)(v)
    if v != 1:
        raise _Invalid("must be 1: multi-harmonic balance is not available (the library solves the "
                       "single-harmonic balance)")
    return v


def _formats(v):
    names = ("csv", "png", "json")
    if not isinstance(v, list) or any(x not in names for x in v) or len(set(v)) != len(v):
        raise _Invalid('must be a list of distinct names out of "csv", "png", "json"')
    return tuple(v)


_pos = _number(gt=0)
_nonneg = _number(ge=0)

#: Every table and key of a scene: table -> {key: Key}.  ``""`` is the top level;
#: ``damper.load`` is a sub-table of ``damper``.  docs/scenes.md documents the same keys.
SCHEMA: dict[str, dict[str, Key]] = {
    "": {
        "title": Key(_text, "", "a one-line description, copied to the summary"),
    },
    "blade": {
        "mass": Key(_number(gt=0, unit="kg"), REQUIRED, "modal mass m (kg)"),
        "stiffness": Key(_number(ge=0, unit="N/m"), OPTIONAL,
                         "stiffness k (N/m); give this or `frequency`"),
        "frequency": Key(_number(gt=0, unit="rad/s"), OPTIONAL,
                         "natural frequency of the blade alone, sqrt(k/m) (rad/s); give this or `stiffness`"),
        "damping": Key(_number(ge=0, unit="N s/m"), OPTIONAL,
                       "viscous damping c (N s/m); give this or `damping_ratio`"),
        "damping_ratio": Key(_number(ge=0), OPTIONAL,
                             "viscous damping ratio zeta, c = 2 zeta sqrt(k m); give this or `damping`"),
        "force": Key(_number(gt=0, unit="N"), REQUIRED, "force amplitude F of F cos(omega t) (N)"),
    },
    "damper": {
        "model": Key(_one_or_list(_choice(*MODELS), "a model name"), ("auto",),
                     'contact model: "auto", "two-region", "three-region", "macroslip", "point-contact", '
                     "or a list of them (one run each)"),
        "E": Key(_number(gt=0, unit="Pa"), OPTIONAL, "Young's modulus of the bar (Pa)"),
        "rho": Key(_number(gt=0, unit="kg/m^3"), OPTIONAL, "density of the bar (kg/m^3)"),
        "A": Key(_number(gt=0, unit="m^2"), OPTIONAL, "cross-section of the bar (m^2)"),
        "L": Key(_number(gt=0, unit="m"), OPTIONAL, "length of the bar and the contact (m)"),
        "k": Key(_number(gt=0, unit="N/m^2"), OPTIONAL, "shear-layer stiffness per length (N/m^2)"),
        "beta": Key(_number(ge=0, unit="N/m"), OPTIONAL,
                    "strain-hardening spring at x = 0 (N/m); needed while effects.strain_hardening = true"),
        "mu": Key(_number(ge=0), OPTIONAL, "friction coefficient"),
        "stiffness": Key(_number(gt=0, unit="N/m"), OPTIONAL,
                         "macroslip only: spring of the Jenkins element (N/m); default k* of the bar"),
        "slip_force": Key(_number(gt=0, unit="N"), OPTIONAL,
                          "macroslip only: slip force of the Jenkins element (N); default mu N"),
        "fit_to": Key(_choice(*MICROSLIP_MODELS), "auto",
                      'point-contact only: the microslip model it is fitted to ("auto", "two-region", '
                      '"three-region")'),
        "fit_omega": Key(_number(ge=0, unit="rad/s"), OPTIONAL,
                         "point-contact only: frequency of the fit (rad/s); default the stuck resonance "
                         "sqrt((k + k*)/m) of a frequency sweep, 0 for an amplitude sweep"),
    },
    "damper.load": {
        "kind": Key(_choice("uniform", "quadratic"), "uniform",
                    '"uniform" (q = N/L) or "quadratic" (Eq. 29: q0 + q2 4x(x - L)/L^2)'),
        "N": Key(_one_or_list(_number(gt=0, unit="N"), "a number > 0 (N)"), OPTIONAL,
                 "total normal load (N), or a list of loads (one run each: a design chart)"),
        "ratio": Key(_number(gt=0, allow_inf=True), OPTIONAL,
                     "quadratic only: q0/(q0 - q2); > 1 concave (three regions), < 1 convex"),
        "q0": Key(_number(ge=0, unit="N/m"), OPTIONAL, "quadratic only, instead of N and ratio: q0 (N/m)"),
        "q2": Key(_number(unit="N/m"), OPTIONAL, "quadratic only, instead of N and ratio: q2 (N/m)"),
    },
    "effects": {
        "inertia": Key(_choice("on", "off", "auto"), "auto",
                       'damper inertia: "on", "off" (quasi-static damper, omega = 0 in it) or "auto"'),
        "strain_hardening": Key(_boolean, True, "the spring beta at x = 0: true, or false (beta = 0)"),
        "harmonics": Key(_harmonics, 1, "harmonics of the balance; only 1 is available"),
        "tolerance": Key(_number(gt=0, lt=1), OPTIONAL,
                         "relative change below which `auto` leaves an effect out; default sweep.tolerance"),
    },
    "sweep": {
        "kind": Key(_choice("frequency", "amplitude"), "frequency",
                    '"frequency" (an FRF of the blade) or "amplitude" (a table of F_s, F_c of the damper)'),
        "omega": Key(lambda v: v, REQUIRED,
                     "frequency: [w0, w1], the range traced from w0 to w1; amplitude: the list of "
                     "frequencies of the table"),
        "unit": Key(_choice("rad/s", "omega_c"), "rad/s",
                    '"rad/s", or "omega_c" (fractions of the bar\'s omega_c) for sweep.omega'),
        "tolerance": Key(_number(gt=0, lt=0.1), OPTIONAL, "relative accuracy (rtol); default 1e-6"),
        "accuracy": Key(_choice(*ACCURACY_PRESETS), OPTIONAL,
                        'a preset of hbm.presets instead of tolerance: "fast" (1e-3), "default" (1e-6), '
                        '"precise" (1e-9)'),
        "max_step": Key(_number(gt=0), OPTIONAL, "largest continuation step (scaled arclength); default 0.03"),
        "min_step": Key(_number(gt=0), 1e-9, "smallest continuation step"),
        "max_steps": Key(_integer(1), 5000, "step budget of the continuation"),
        "amplitude": Key(_number_list(_number(gt=0), length=2), OPTIONAL,
                         "amplitude sweep: [a0, a1], log-spaced (in sweep.amplitude_unit)"),
        "amplitude_unit": Key(_choice("a_min", "m"), "a_min",
                              'amplitude sweep: "a_min" (mu N/(k L), the paper\'s normalisation) or "m"'),
        "points": Key(_integer(2), 50, "amplitude sweep: amplitudes per frequency"),
    },
    "output": {
        "folder": Key(_text, OPTIONAL, "output folder; default the scene file's name without .toml"),
        "formats": Key(_formats, ("csv", "png", "json"), 'which outputs: any of "csv", "png", "json"'),
    },
}

#: Sub-tables (parent table -> child key).
SUBTABLES = {"damper": "load"}
#: Tables a scene must have, and what they hold at least.
REQUIRED_TABLES = {"damper": "the damper: model, bar parameters, [damper.load]",
                   "sweep": "at least sweep.omega"}


def all_keys():
    """Every ``table.key`` of the schema (top-level keys bare)."""
    for table, keys in SCHEMA.items():
        for key in keys:
            yield (f"{table}.{key}" if table else key)


# ====================================================================== loading
@dataclass(frozen=True)
class Scene:
    """A validated scene: each table as a dict with every default filled in."""

    path: Path
    title: str
    blade: dict | None
    damper: dict
    load: dict | None
    effects: dict
    sweep: dict
    output: dict

    @property
    def name(self) -> str:
        return self.path.stem

    def where(self, dotted: str) -> str:
        """``file: table.key`` for messages."""
        return f"{self.path}: {dotted}"


def load_scene(path, *, overrides=None) -> Scene:
    """Read and validate the scene file ``path``; ``overrides`` maps ``"table.key"`` to a value
    that replaces the file's (as ``python -m hbm run --set table.key=value``)."""
    path = Path(path)
    try:
        with path.open("rb") as fh:
            data = tomllib.load(fh)
    except FileNotFoundError:
        raise SceneError([f"{path}: no such file"]) from None
    except tomllib.TOMLDecodeError as exc:
        raise SceneError([f"{path}: not valid TOML: {exc}"]) from None
    return scene_from_dict(data, path, overrides=overrides)


def parse_override(text: str):
    """``"table.key=value"`` -> ``("table.key", value)``, the value read as TOML (a bare word as a string)."""
    name, sep, raw = text.partition("=")
    name = name.strip()
    if not sep or not name:
        raise SceneError([f"--set {text!r}: must be table.key=value, e.g. sweep.max_step=0.1"])
    try:
        value = tomllib.loads(f"v = {raw.strip()}")["v"]
    except tomllib.TOMLDecodeError:
        value = raw.strip()
    return name, value


def scene_from_dict(data: dict, path="<scene>", *, overrides=None) -> Scene:
    """Validate the parsed TOML ``data`` (file name ``path`` for messages); see :func:`load_scene`."""
    path = Path(path)
    data = _copy(data)
    problems = []
    for dotted, value in (overrides or {}).items():
        *tables, key = dotted.split(".")
        node = data
        for t in tables:
            node = node.setdefault(t, {})
            if not isinstance(node, dict):
                break
        if isinstance(node, dict):
            node[key] = value
    tables, present = _check_keys(data, path, problems)
    if problems:
        raise SceneError(problems)
    scene = _semantics(tables, present, path, problems)
    if problems:
        raise SceneError(problems)
    return scene


def _copy(d):
    return {k: _copy(v) for k, v in d.items()} if isinstance(d, dict) else d


def _suggest(name, valid, table):
    """' (did you mean X?)' from the closest valid name here, or the same key in another table."""
    close = difflib.get_close_matches(name, list(valid), n=1, cutoff=0.6)
    if close:
        return f" (did you mean {_dot(table, close[0])}?)"
    elsewhere = [t for t, keys in SCHEMA.items() if name in keys and t != table]
    if elsewhere:
        return f" (it belongs in [{elsewhere[0]}]: {_dot(elsewhere[0], name)})"
    return ""


def _dot(table, key):
    return f"{table}.{key}" if table else key


def _check_keys(data, path, problems):
    """Unknown names, tables that are not tables, per-key types and ranges, required keys.

    Returns ``{table: {key: converted value}}`` (given keys only) and the set of tables present.
    """
    out = {t: {} for t in SCHEMA}
    present = {t for t in SCHEMA if t and isinstance(_table(data, t), dict)}
    top_tables = [t for t in SCHEMA if t and "." not in t]
    for key, value in data.items():
        if key in SCHEMA[""]:
            continue
        if key in top_tables:
            if not isinstance(value, dict):
                problems.append(f"{path}: {key} = {_show(value)}: must be a table ([{key}])")
            continue
        valid = list(SCHEMA[""]) + top_tables
        hint = _suggest(key, valid, "")
        shown = f"[{key}]" if isinstance(value, dict) else f"{key} = {_show(value)}"
        problems.append(f"{path}: {shown}: unknown top-level name{hint}; allowed: "
                        f"{', '.join(f'[{t}]' for t in top_tables)}, {', '.join(SCHEMA[''])}")
    for table, keys in SCHEMA.items():
        node = _table(data, table)
        if not isinstance(node, dict):
            continue
        sub = SUBTABLES.get(table)
        for key, value in node.items():
            if not table and key not in keys:
                continue  # the top level's tables and unknown names: handled above
            if key == sub:
                if not isinstance(value, dict):
                    problems.append(f"{path}: {table}.{key} = {_show(value)}: must be a table ([{table}.{key}])")
                continue
            if key not in keys:
                valid = list(keys) + ([sub] if sub else [])
                problems.append(f"{path}: {_dot(table, key)} = {_show(value)}: unknown key"
                                f"{_suggest(key, valid, table)}; allowed in [{table}]: {', '.join(valid)}")
                continue
            try:
                out[table][key] = keys[key].check(value)
            except _Invalid as exc:
                problems.append(f"{path}: {_dot(table, key)} = {_show(value)}: {exc}")
        for key, spec in keys.items():
            if spec.default is REQUIRED and key not in node and _table(data, table.split(".")[0]) is not None:
                problems.append(f"{path}: {_dot(table, key)} is missing: required, {spec.doc}")
    for table in REQUIRED_TABLES:
        if table not in data:
            problems.append(f"{path}: [{table}] is missing: required ({REQUIRED_TABLES[table]})")
    return out, present


def _table(data, dotted):
    node = data
    for part in dotted.split(".") if dotted else ():
        if not isinstance(node, dict):
            return None
        node = node.get(part)
    return node


def _with_defaults(table, given):
    out = {}
    for key, spec in SCHEMA[table].items():
        if key in given:
            out[key] = given[key]
        elif spec.default is not REQUIRED and spec.default is not OPTIONAL:
            out[key] = spec.default
    return out


def _semantics(t, present, path, problems) -> Scene:
    """Rules between keys: which keys a model needs, mutually exclusive keys, ranges."""
    where = lambda dotted: f"{path}: {dotted}"  # noqa: E731

    def need(table, key, why):
        problems.append(f"{where(_dot(table, key))} is missing: required {why}; {SCHEMA[table][key].doc}")

    def forbid(table, key, why):
        problems.append(f"{where(_dot(table, key))} = {_show(t[table][key])}: not allowed {why}")

    sweep = _with_defaults("sweep", t["sweep"])
    damper = _with_defaults("damper", t["damper"])
    effects = _with_defaults("effects", t["effects"])
    output = _with_defaults("output", t["output"])
    has_load = "damper.load" in present
    load = _with_defaults("damper.load", t["damper.load"])
    kind = sweep["kind"]
    models = damper["model"]

    # ---- [sweep]
    omega = t["sweep"].get("omega")
    if omega is not None:
        item = _number(ge=0)
        if kind == "frequency":
            try:
                pair = _number_list(item, length=2)(omega)
                if pair[0] == pair[1]:
                    raise _Invalid("must be a list of 2 different numbers [w0, w1] (w0 > w1 sweeps down)")
                sweep["omega"] = pair
            except _Invalid as exc:
                problems.append(f"{where('sweep.omega')} = {_show(omega)}: {exc} (sweep.kind = \"frequency\": "
                                "the range [w0, w1])")
        else:
            try:
                sweep["omega"] = _number_list(item, minimum=1)(omega)
            except _Invalid as exc:
                problems.append(f"{where('sweep.omega')} = {_show(omega)}: {exc} (sweep.kind = \"amplitude\": "
                                "the frequencies of the table)")
    if "tolerance" in t["sweep"] and "accuracy" in t["sweep"]:
        forbid("sweep", "accuracy", "together with sweep.tolerance: give one of them")
    preset = ACCURACY_PRESETS[sweep.get("accuracy") or "default"]
    sweep["tolerance"] = sweep.get("tolerance") or preset[0]
    sweep["max_step"] = sweep.get("max_step") or preset[1]
    if sweep["min_step"] > sweep["max_step"]:
        forbid("sweep", "min_step", f"above sweep.max_step = {sweep['max_step']!r}")
    if kind == "frequency":
        for key in ("amplitude", "amplitude_unit", "points"):
            if key in t["sweep"]:
                forbid("sweep", key, 'with sweep.kind = "frequency" (it belongs to an amplitude sweep)')
        if "blade" not in present:
            problems.append(f"{path}: [blade] is missing: required for sweep.kind = \"frequency\" "
                            "(mass, stiffness or frequency, damping or damping_ratio, force)")
    else:
        if "amplitude" not in t["sweep"]:
            need("sweep", "amplitude", 'with sweep.kind = "amplitude"')
        for key in ("max_step", "min_step", "max_steps", "accuracy"):
            if key in t["sweep"]:
                forbid("sweep", key, 'with sweep.kind = "amplitude" (continuation settings of a frequency sweep)')

    # ---- [blade]
    blade = None
    if "blade" in present and kind == "frequency":
        blade = dict(t["blade"])
        for a, b in (("stiffness", "frequency"), ("damping", "damping_ratio")):
            if a in blade and b in blade:
                forbid("blade", b, f"together with blade.{a}: give one of them")
            elif a not in blade and b not in blade:
                problems.append(f"{where('blade.' + a)} is missing: give blade.{a} or blade.{b}")

    # ---- [damper]
    bar_keys = ("E", "rho", "A", "L", "k", "mu")
    needs_bar = [m for m in models if m != "macroslip" or not {"stiffness", "slip_force"} <= set(t["damper"])]
    bar_complete = all(k in t["damper"] for k in bar_keys)
    if needs_bar:
        why = f"for damper.model = {_show(needs_bar[0])}"
        for key in bar_keys:
            if key not in t["damper"]:
                need("damper", key, why)
        if effects["strain_hardening"] and "beta" not in t["damper"]:
            need("damper", "beta", why + " while effects.strain_hardening = true (or set it false)")
    for key in ("stiffness", "slip_force"):
        if key in t["damper"] and "macroslip" not in models:
            forbid("damper", key, 'unless damper.model includes "macroslip"')
    if "macroslip" in models and ("stiffness" in t["damper"]) != ("slip_force" in t["damper"]):
        have = "stiffness" if "stiffness" in t["damper"] else "slip_force"
        other = "slip_force" if have == "stiffness" else "stiffness"
        need("damper", other, f"with damper.{have} (give both, or neither to take k* and mu N of the bar)")
    for key in ("fit_to", "fit_omega"):
        if key in t["damper"] and "point-contact" not in models:
            forbid("damper", key, 'unless damper.model includes "point-contact"')

    # ---- [damper.load]
    needs_load = [m for m in models if m != "macroslip" or "slip_force" not in t["damper"]]
    if needs_load and not has_load:
        problems.append(f"{path}: [damper.load] is missing: required for damper.model = {_show(needs_load[0])} "
                        "(kind, N, and ratio or q0 and q2 for a quadratic load)")
    elif has_load:
        given = t["damper.load"]
        if load["kind"] == "uniform":
            for key in ("ratio", "q0", "q2"):
                if key in given:
                    forbid("damper.load", key, 'with damper.load.kind = "uniform" (use kind = "quadratic")')
            if "N" not in given:
                need("damper.load", "N", 'with damper.load.kind = "uniform"')
        else:
            by_ratio = "N" in given or "ratio" in given
            by_q = "q0" in given or "q2" in given
            if by_ratio and by_q:
                problems.append(f"{where('damper.load')}: give N and ratio, or q0 and q2, not both")
            elif by_q:
                for key in ("q0", "q2"):
                    if key not in given:
                        need("damper.load", key, "with the other of q0, q2")
                if not problems and given["q2"] > given["q0"]:
                    problems.append(f"{where('damper.load.q2')} = {_show(given['q2'])}: must be <= damper.load.q0 "
                                    f"= {_show(given['q0'])} (the load q0 - q2 at mid-length must be >= 0)")
            else:
                for key in ("N", "ratio"):
                    if key not in given:
                        need("damper.load", key, 'with damper.load.kind = "quadratic" (or give q0 and q2)')
        if "N" not in given and load["kind"] == "quadratic" and "q0" in given and "q2" in given:
            L = t["damper"].get("L")
            load["N"] = ((given["q0"] - 2.0 * given["q2"] / 3.0) * L,) if L else None

    # ---- [effects]
    if effects.get("tolerance") is None:
        effects["tolerance"] = sweep["tolerance"]
    if sweep["unit"] == "omega_c" and not bar_complete and not needs_bar:
        forbid("sweep", "unit", "without a bar in [damper] (omega_c is the bar's: give E, rho, A, L, k, mu)")
    if output.get("folder") is None:
        output["folder"] = path.stem
    return Scene(path=path, title=t[""].get("title", ""), blade=blade, damper=damper,
                 load=load if has_load else None, effects=effects, sweep=sweep, output=output)


# ====================================================================== planning
@dataclass
class Effect:
    """One physical effect of a run: simulated or not, and why."""

    name: str
    simulated: bool
    reason: str

    def as_dict(self):
        return {"effect": self.name, "simulated": self.simulated, "reason": self.reason}


@dataclass
class RunPlan:
    """One computation of a scene: a model at a normal load."""

    index: int
    model: str  #: the model asked for ("auto" resolved: "two-region (auto)")
    N: float | None
    element: object
    effects: list
    omega: tuple  #: the sweep's range (frequency) or frequencies (amplitude), rad/s
    a_ref: float | None = None  #: amplitude unit of an amplitude sweep (m)
    a_min: float | None = None  #: the damper's slip amplitude at the sweep's lowest frequency (m)

    @property
    def label(self) -> str:
        return self.model + (f", N = {self.N:g} N" if self.N is not None else "")


@dataclass
class Plan:
    scene: Scene
    blade: object
    runs: list


def plan_scene(scene: Scene) -> Plan:
    """Decide every effect and build the element of each run; raises SceneError for physically
    impossible scenes (the message names the key)."""
    from contact_models import Bar

    from .blade import Blade

    problems = []
    blade = None
    if scene.sweep["kind"] == "frequency":
        b = scene.blade
        try:
            if "frequency" in b:
                w = b["frequency"]
                stiffness = b["mass"] * w * w
            else:
                stiffness = b["stiffness"]
            damping = b.get("damping")
            if damping is None:
                damping = 2.0 * b["damping_ratio"] * math.sqrt(stiffness * b["mass"])
            blade = Blade(mass=b["mass"], stiffness=stiffness, damping=damping, force=b["force"])
        except ValueError as exc:
            raise SceneError([scene.where(f"[blade]: {exc}")]) from None

    d = scene.damper
    bar_given = bar = None
    if all(k in d for k in ("E", "rho", "A", "L", "k", "mu")):
        beta = d.get("beta", 0.0)
        bar_given = Bar(E=d["E"], rho=d["rho"], A=d["A"], L=d["L"], k=d["k"], beta=beta, mu=d["mu"])
        bar = bar_given if scene.effects["strain_hardening"] else Bar(
            E=d["E"], rho=d["rho"], A=d["A"], L=d["L"], k=d["k"], beta=0.0, mu=d["mu"])
    unit = bar_given.omega_c if scene.sweep["unit"] == "omega_c" else 1.0
    omega = tuple(unit * w for w in scene.sweep["omega"])
    loads = scene.load.get("N") or (None,) if scene.load is not None else (None,)
    runs = []
    for model in d["model"]:
        for N in (loads if model != "macroslip" or "slip_force" not in d else (None,)):
            try:
                runs.append(_plan_run(scene, len(runs), model, N, bar, bar_given, blade, omega))
            except SceneError as exc:
                problems.extend(exc.problems)
    if problems:
        raise SceneError(list(dict.fromkeys(problems)))
    return Plan(scene, blade, runs)


def _make_load(scene, N):
    from contact_models import QuadraticLoad, UniformLoad

    ld = scene.load
    if ld["kind"] == "uniform":
        return UniformLoad(N=N)
    if ld.get("q0") is not None:
        return QuadraticLoad(q0=ld["q0"], q2=ld["q2"], L=scene.damper["L"])
    return QuadraticLoad.from_ratio(N=N, ratio=ld["ratio"])


def _load_text(scene, load):
    if scene.load["kind"] == "uniform":
        return f"uniform load N = {load.N:g} N"
    r = load.ratio
    shape = "concave" if r > 1 else ("convex" if r < 1 else "uniform")
    return f"quadratic load N = {load.N:g} N, ratio q0/(q0 - q2) = {r:g} ({shape})"


def _plan_run(scene, index, model, N, bar, bar_given, blade, omega) -> RunPlan:
    from contact_models import Macroslip, PointContact, QuasiStatic, ThreeRegionMicroslip, TwoRegionMicroslip
    from contact_models.quasi_static import StuckContact

    eff = scene.effects
    tol = eff["tolerance"]
    freq = scene.sweep["kind"] == "frequency"
    w_lo, w_hi = min(omega), max(omega)
    effects = []
    src = scene.where("damper.model") + f" = {_show(model)}"

    # ---- strain-hardening spring
    if bar is not None:
        beta = scene.damper.get("beta", 0.0)
        if not eff["strain_hardening"]:
            effects.append(Effect("strain-hardening spring", False,
                                  "effects.strain_hardening = false: beta = 0" +
                                  (f" (damper.beta = {beta:g} N/m left out)" if beta else "")))
        elif beta == 0.0:
            effects.append(Effect("strain-hardening spring", False, "damper.beta = 0"))
        else:
            effects.append(Effect("strain-hardening spring", True, f"beta = {beta:g} N/m"))

    # ---- damper inertia: from the stuck bar's dynamic stiffness at the top of the sweep
    uses_bar = model != "macroslip"
    if not uses_bar:
        how = ("damper.stiffness and damper.slip_force" if "slip_force" in scene.damper
               else "k* of the bar at omega = 0 and mu N")
        inertia = False
        effects.append(Effect("damper inertia", False,
                              f"macroslip (Jenkins) element: massless, frequency independent ({how})"))
    else:
        K0 = float(bar.stuck_stiffness(0.0))
        change = abs(float(bar.stuck_stiffness(w_hi)) / K0 - 1.0)
        at = f"|K*(omega_max)/k* - 1| = {change:.3g} at omega_max = {w_hi:.6g} rad/s ({w_hi / bar.omega_c:.4g} omega_c)"
        slide = _sliding_change(bar, _make_load(scene, N), w_hi)
        info = ("" if slide is None else
                f" (for information: the fully slipping bar's stiffness changes by {slide:.3g} there)")
        setting = eff["inertia"]
        if setting == "auto":
            inertia = change > tol
            verdict = "above" if inertia else "not above"
            reason = f"auto: {at}, {verdict} the tolerance {tol:g}"
        else:
            inertia = setting == "on"
            reason = f"effects.inertia = {_show(setting)} ({at})"
        if not inertia:
            reason += ": quasi-static damper (omega = 0 in the damper)"
        reason += info
        if model == "point-contact":
            reason += "; the point contact itself is massless: inertia enters through its fit"
        effects.append(Effect("damper inertia", inertia, reason))

    # ---- the microslip element and its topology
    micro_model = scene.damper["fit_to"] if model == "point-contact" else model
    micro = load = None
    if uses_bar:
        load = _make_load(scene, N)
        if freq:
            probe = (w_lo, 0.5 * (w_lo + w_hi), w_hi) if inertia else (0.0,)
        else:
            probe = tuple(sorted(set(omega))) if inertia else (0.0,)
        onsets = [(w, bar.slip_onset(load, w)[0] / bar.L) for w in probe]
        interior = [w for w, x in onsets if x < 1.0 - ONSET_AT_END]
        where_ = ", ".join(f"x*/L = {x:.4g} at {w:.6g} rad/s" for w, x in onsets)
        lt = _load_text(scene, load)
        if micro_model == "auto":
            name = "three-region" if interior else "two-region"
            why = (f"auto: slip starts inside the bar ({where_}): three regions" if interior else
                   f"auto: slip starts at the excited end ({where_}): two regions")
        else:
            name = micro_model
            why = f"{'damper.fit_to' if model == 'point-contact' else 'damper.model'} = {_show(micro_model)} ({where_})"
            if name == "three-region" and not interior:
                why += "; slip starts at the excited end, so the element follows its two-region path"
        cls = ThreeRegionMicroslip if name == "three-region" else TwoRegionMicroslip
        try:
            micro = cls(bar, load)
        except ValueError as exc:
            key = "damper.fit_to" if model == "point-contact" else "damper.model"
            raise SceneError([f"{scene.where(key)} = {_show(micro_model)} with the {lt}: {exc}; "
                              'allowed here: "three-region" or "auto"']) from None
        effects.append(Effect("interior slip onset (three regions)", name == "three-region", f"{why}; {lt}"))
        # the damper frequencies the element will see: its path must exist there
        for w in probe:
            try:
                micro.slip_amplitude(w)
                micro.gross_slip_amplitude(w)
            except (ValueError, FloatingPointError) as exc:
                key = "damper.load" if isinstance(exc, ValueError) else "sweep.omega"
                raise SceneError([f"{scene.where(key)}: {exc} (damper.model = {_show(model)}, {lt})"]) from None

    if model in MICROSLIP_MODELS:
        element = micro if inertia else QuasiStatic(micro)
        label = f"{micro_model if micro_model != 'auto' else name}" + (" (auto)" if micro_model == "auto" else "")
    elif model == "point-contact":
        if "fit_omega" in scene.damper:
            w_fit = scene.damper["fit_omega"]
        elif freq:
            w_fit = math.sqrt((blade.stiffness + bar.k_star) / blade.mass)
        else:
            w_fit = 0.0
        w_fit = w_fit if inertia else 0.0
        try:
            element = PointContact.fit(micro, w_fit)
        except (ValueError, FloatingPointError) as exc:
            raise SceneError([f"{scene.where('damper.fit_omega')} = {w_fit!r}: {exc}"]) from None
        label = f"point-contact (fitted to {name} at {w_fit:.6g} rad/s)"
    else:
        if "slip_force" in scene.damper:
            element = Macroslip(stiffness=scene.damper["stiffness"], slip_force=scene.damper["slip_force"])
        else:
            element = Macroslip(stiffness=bar.k_star, slip_force=bar.mu * N)
        label = "macroslip"

    # ---- amplitude unit of an amplitude sweep
    a_ref = None
    if not freq:
        if scene.sweep["amplitude_unit"] == "m":
            a_ref = 1.0
        elif uses_bar or "slip_force" not in scene.damper:
            a_ref = bar.mu * N / (bar.k * bar.L)
        else:
            a_ref = scene.damper["slip_force"] / scene.damper["stiffness"]

    # ---- slip: a damper whose stuck response never reaches a_min is a linear spring
    a_min = _a_min(element, w_lo)
    if freq:
        peak_stuck, min_amin = _stuck_peak(blade, element, omega)
        ratio = peak_stuck / min_amin
        if ratio < 1.0 - STUCK_MARGIN:
            element = StuckContact(element)
            effects.append(Effect("damper slip", False,
                                  f"damper stayed stuck: linear spring (the stuck response peaks at "
                                  f"{peak_stuck:.4g} m = {ratio:.4g} of the smallest slip amplitude {min_amin:.4g} m "
                                  "in the sweep)"))
        else:
            effects.append(Effect("damper slip", True,
                                  f"the stuck response reaches {ratio:.4g} times the slip amplitude "
                                  f"({peak_stuck:.4g} m against {min_amin:.4g} m)"))
    else:
        effects.append(Effect("damper slip", True, "amplitude sweep: the amplitudes are given"))
    effects.append(Effect("higher harmonics", False,
                          "effects.harmonics = 1: single-harmonic balance (first-harmonic f_s, f_c)"))
    return RunPlan(index=index, model=label, N=N if (uses_bar or "slip_force" not in scene.damper) else None,
                   element=element, effects=effects, omega=omega, a_ref=a_ref, a_min=a_min)


def _sliding_change(bar, load, omega):
    """|K_slip(omega)/K_slip(0) - 1| of the bar sliding as a whole (the slope of the loading curve
    past gross slip, which F_s tends to at large amplitude), or None where it is not defined."""
    from contact_models.microslip import region_solution

    try:
        with np.errstate(all="ignore"):
            k0 = float(region_solution(bar, load.on(bar.L), 0.0, None, 0.0).K_tip)
            kw = float(region_solution(bar, load.on(bar.L), 0.0, None, omega).K_tip)
        v = abs(kw / k0 - 1.0)
    except (ArithmeticError, ValueError):
        return None
    return v if math.isfinite(v) else None


def _a_min(element, omega):
    """Slip amplitude at ``omega``; for a dynamic bar from Bar.slip_onset (no loading path built)."""
    from contact_models import QuasiStatic

    if isinstance(element, QuasiStatic):
        return float(element.slip_amplitude(0.0))
    bar, load = getattr(element, "bar", None), getattr(element, "load", None)
    if bar is not None and load is not None and getattr(element, "frequency_dependent", False):
        return float(bar.slip_onset(load, omega)[1])
    return float(element.slip_amplitude(omega))


def _stuck_peak(blade, element, omega):
    """(largest amplitude of the blade with the damper stuck over the range, smallest a_min there)."""
    from scipy.optimize import minimize_scalar

    from .residual import linear_response

    w0, w1 = min(omega), max(omega)
    bar = getattr(element, "bar", None)
    if not getattr(element, "frequency_dependent", True):
        k0 = float(element.stuck_stiffness(0.0))
        K = lambda om: np.full_like(om, k0)  # noqa: E731
    elif bar is not None:
        K = bar.stuck_stiffness  # vectorised
    else:
        K = lambda om: np.array([float(element.stuck_stiffness(x)) for x in om])  # noqa: E731

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
    amins = [_a_min(element, w) for w in np.linspace(w0, w1, AMIN_SAMPLES)]
    return best, min(amins)


# ====================================================================== running
@dataclass
class Progress:
    """Passed to the ``progress`` callback of :func:`run_scene` after each point."""

    run: int  #: 0-based index of the run
    runs: int
    label: str
    omega: float
    fraction: float  #: how far along the run's sweep (0..1)
    points: int  #: points written so far (all runs)
    elapsed: float  #: seconds since the scene started


@dataclass
class RunResult:
    plan: RunPlan
    success: bool = False
    message: str = ""
    frf: object = None
    table: dict | None = None
    points: int = 0
    seconds: float = 0.0
    peak: object = None
    summary: dict = field(default_factory=dict)


@dataclass
class SceneResult:
    """What :func:`run_scene` did: ``success``, ``message``, per-run results, files, summary."""

    plan: Plan
    runs: list
    success: bool
    message: str
    files: dict  #: kind ("csv", "png", "json") -> Path written
    summary: dict
    points: int  #: rows written to the CSV

    @property
    def exit_code(self) -> int:
        return 0 if self.success else 1


FRF_COLUMNS = ("run", "model", "normal_load_N", "omega_rad_s", "amplitude_m", "phase_rad", "x_c_m", "x_s_m")
TABLE_COLUMNS = ("run", "model", "normal_load_N", "omega_rad_s", "a_m", "a_over_unit", "f_s_N", "f_c_N",
                 "F_s", "F_c")


def output_names(scene: Scene) -> dict:
    """File names of a scene's outputs: ``{"csv", "partial", "png", "json"}``."""
    stem = "frf" if scene.sweep["kind"] == "frequency" else "coefficients"
    return {"csv": f"{stem}.csv", "partial": f"{stem}.partial.csv", "png": f"{stem}.png", "json": "summary.json"}


def run_scene(scene: Scene, out=None, *, plan: Plan | None = None, progress=None) -> SceneResult:
    """Run every computation of ``scene``, writing its outputs to ``out`` (default
    ``scene.output["folder"]``) as they are computed; see the module docstring.

    ``progress(Progress)`` is called after each point.  A run that fails (the continuation stops
    short, or the element raises) is recorded and the next run goes on; the result's
    ``success`` is False and the CSV keeps its ``.partial.csv`` name.
    """
    plan = plan if plan is not None else plan_scene(scene)
    folder = Path(out if out is not None else scene.output["folder"])
    formats = scene.output["formats"]
    names = output_names(scene)
    folder.mkdir(parents=True, exist_ok=True)
    for key in ("csv", "partial", "png", "json"):  # stale outputs of an earlier run of this scene
        (folder / names[key]).unlink(missing_ok=True)
    t_start = time.perf_counter()
    files = {}
    results = [RunResult(p) for p in plan.runs]
    written = 0
    fh = None
    writer = None
    partial = folder / names["partial"]
    freq = scene.sweep["kind"] == "frequency"
    try:
        if "csv" in formats:
            fh = partial.open("w", newline="")
            writer = csv.writer(fh)
            writer.writerow(FRF_COLUMNS if freq else TABLE_COLUMNS)
            fh.flush()
        for res in results:
            p = res.plan

            def emit(row, omega, fraction, p=p):
                nonlocal written
                if writer is not None:
                    writer.writerow(row)
                    fh.flush()
                written += 1
                if progress is not None:
                    progress(Progress(p.index, len(results), p.label, omega, fraction, written,
                                      time.perf_counter() - t_start))

            t0 = time.perf_counter()
            try:
                (_run_frequency if freq else _run_amplitude)(scene, plan, res, emit)
            except (ArithmeticError, ValueError, RuntimeError, np.linalg.LinAlgError) as exc:
                res.success = False
                res.message = f"{type(exc).__name__}: {exc}"
            res.seconds = time.perf_counter() - t0
            res.summary = _run_summary(res)
    finally:
        if fh is not None:
            fh.close()
    success = all(r.success for r in results)
    failed = [r for r in results if not r.success]
    if "csv" in formats:
        if success:
            files["csv"] = partial.replace(folder / names["csv"])
        else:
            files["csv"] = partial
    if success and "png" in formats:
        files["png"] = _figure(scene, plan, results, folder / names["png"])
    message = ("every run succeeded" if success else
               "; ".join(f"run {r.plan.index} ({r.plan.label}) failed: {r.message}" for r in failed))
    summary = {
        "scene": str(scene.path),
        "title": scene.title,
        "status": "success" if success else "failed",
        "message": message,
        "kind": scene.sweep["kind"],
        "settings": {k: v for k, v in scene.sweep.items() if v is not None},
        "effects_tolerance": scene.effects["tolerance"],
        "runs": [r.summary for r in results],
        "points_written": written,
        "elapsed_s": time.perf_counter() - t_start,
        "outputs": {k: str(v) for k, v in files.items()},
    }
    if "json" in formats:
        files["json"] = folder / names["json"]
        summary["outputs"]["json"] = str(files["json"])
        tmp = folder / (names["json"] + ".tmp")
        tmp.write_text(json.dumps(_jsonable(summary), indent=2) + "\n")
        tmp.replace(files["json"])
    return SceneResult(plan, results, success, message, files, summary, written)


def _run_frequency(scene, plan, res, emit):
    from .frf import frequency_response

    p = res.plan
    w0, w1 = p.omega
    sw = scene.sweep
    label = p.model
    N = "" if p.N is None else repr(float(p.N))

    def on_point(omega, xc, xs):
        a = math.hypot(xc, xs)
        row = [p.index, label, N] + [repr(float(v)) for v in (omega, a, math.atan2(xs, xc), xc, xs)]
        emit(row, omega, (omega - w0) / (w1 - w0))
        res.points += 1

    frf = frequency_response(plan.blade, p.element, omega_range=(w0, w1), rtol=sw["tolerance"],
                             max_step=sw["max_step"], min_step=sw["min_step"], max_steps=sw["max_steps"],
                             on_point=on_point)
    res.frf = frf
    res.success = frf.success
    res.message = frf.message
    if len(frf):
        res.peak = frf.peak()


def _run_amplitude(scene, plan, res, emit):
    p = res.plan
    a0, a1 = scene.sweep["amplitude"]
    over = np.geomspace(a0, a1, scene.sweep["points"])
    a = over * p.a_ref
    el = p.element
    k_star = float(el.stuck_stiffness(0.0))
    N = "" if p.N is None else repr(float(p.N))
    table = {"omega": [], "a": a, "F_s": [], "F_c": []}
    for j, w in enumerate(p.omega):
        fs, fc = el.fourier(a, w, rtol=scene.sweep["tolerance"])
        Fs, Fc = fs / (k_star * a), fc / (k_star * a)
        for i in range(len(a)):
            emit([p.index, p.model, N] + [repr(float(v)) for v in (w, a[i], over[i], fs[i], fc[i], Fs[i], Fc[i])],
                 w, (j + (i + 1) / len(a)) / len(p.omega))
            res.points += 1
        table["omega"].append(w)
        table["F_s"].append(Fs)
        table["F_c"].append(Fc)
    res.table = table
    res.success = True
    res.message = "table complete"


def _run_summary(res: RunResult) -> dict:
    from contact_models import QuasiStatic
    from contact_models.quasi_static import StuckContact

    p = res.plan
    out = {"index": p.index, "model": p.model, "normal_load_N": p.N, "element": repr(p.element),
           "success": res.success, "message": res.message, "points": res.points, "time_s": res.seconds}
    el = p.element
    inner = el.element if isinstance(el, StuckContact) else el
    if res.frf is not None:
        frf = res.frf
        out["counters"] = {"nsteps": frf.nsteps, "nit": frf.nit, "nfev": frf.nfev, "nstuck": frf.nstuck}
        if res.peak is not None:
            a_min = p.a_min
            out["peak"] = {"omega_rad_s": res.peak.omega, "amplitude_m": res.peak.amplitude,
                           "amplitude_over_a_min": res.peak.amplitude / a_min if a_min else None}
            slip = next(e for e in p.effects if e.name == "damper slip")
            if slip.simulated and "computed:" not in slip.reason:
                top = float(np.max(frf.amplitude)) / min(_a_min(el, w) for w in _thin(frf.omega))
                slip.reason += (f"; computed: the largest amplitude is {top:.4g} a_min" if top >= 1.0 else
                                f"; computed: every amplitude stayed below a_min (largest {top:.4g} a_min)")
    if res.table is not None:
        out["omega_rad_s"] = list(map(float, res.table["omega"]))
    out["effects"] = [e.as_dict() for e in p.effects]
    if isinstance(inner, QuasiStatic):
        out["quasi_static_calls"] = inner.calls  # every one at omega = 0
    return out


def _thin(omega, n=33):
    """A few frequencies of the branch (a_min varies slowly with omega)."""
    omega = np.asarray(omega)
    return omega[np.unique(np.linspace(0, len(omega) - 1, min(n, len(omega))).astype(int))]


def _jsonable(v):
    if isinstance(v, dict):
        return {k: _jsonable(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_jsonable(x) for x in v]
    if isinstance(v, (np.floating, float)):
        v = float(v)
        return v if math.isfinite(v) else str(v)
    if isinstance(v, np.integer):
        return int(v)
    return v


def _figure(scene, plan, results, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    title = scene.title or scene.name
    if scene.sweep["kind"] == "frequency":
        loads = sorted({r.plan.N for r in results if r.plan.N is not None})
        chart = len(loads) > 1
        fig, axes = plt.subplots(1, 2 if chart else 1, figsize=(11.0 if chart else 6.4, 4.4), squeeze=False)
        ax = axes[0][0]
        for r in results:
            ax.plot(r.frf.omega, r.frf.amplitude, lw=0.8 if chart else 1.2, label=r.plan.label)
        ax.set_yscale("log")
        ax.set_xlabel(r"$\omega$ (rad/s)")
        ax.set_ylabel("amplitude (m)")
        if len(results) <= 8:
            ax.legend(fontsize=7)
        if chart:
            bx = axes[0][1]
            models = list(dict.fromkeys(r.plan.model.split(" (")[0] for r in results))
            for m in models:
                rs = [r for r in results if r.plan.model.split(" (")[0] == m and r.plan.N is not None]
                bx.loglog([r.plan.N for r in rs], [r.peak.amplitude for r in rs], "o-", ms=3, label=m)
            bx.set_xlabel("normal load N (N)")
            bx.set_ylabel("resonant amplitude (m)")
            bx.legend(fontsize=8)
    else:
        fig, axes = plt.subplots(1, 2, figsize=(11.0, 4.4), squeeze=False)
        for r in results:
            over = r.table["a"] / r.plan.a_ref
            for w, Fs, Fc in zip(r.table["omega"], r.table["F_s"], r.table["F_c"]):
                lab = f"{r.plan.label}, {w:.4g} rad/s"
                axes[0][0].semilogx(over, Fs, label=lab)
                axes[0][1].semilogx(over, Fc, label=lab)
        unit = "a/a_min" if scene.sweep["amplitude_unit"] == "a_min" else "a (m)"
        for ax, name in zip(axes[0], ("F_s", "F_c")):
            ax.set_xlabel(unit)
            ax.set_ylabel(f"${name}$ = f/(k* a)")
            ax.grid(True, which="both", alpha=0.3)
        axes[0][1].legend(fontsize=6)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


# ====================================================================== text for the command line
def effect_lines(plan: Plan) -> list:
    """Per effect: simulated or not, in which runs, and why (the first run's reason when the runs'
    reasons differ; every run's is in summary.json)."""
    n = len(plan.runs)
    groups = {}
    for r in plan.runs:
        for e in r.effects:
            groups.setdefault(e.name, {}).setdefault(e.simulated, []).append((r.index, e.reason))
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


def _ranges(indices) -> str:
    """[0, 1, 2, 5] -> '0-2, 5'."""
    out, start = [], None
    for k, i in enumerate(indices):
        if start is None:
            start = i
        if k + 1 == len(indices) or indices[k + 1] != i + 1:
            out.append(f"{start}" if start == i else f"{start}-{i}")
            start = None
    return ", ".join(out)


def summary_lines(result: SceneResult) -> list:
    """The end-of-run summary as lines of text."""
    lines = []
    scene = result.plan.scene
    lines.append(f"scene: {scene.path}" + (f" ({scene.title})" if scene.title else ""))
    lines.append("effects:")
    lines += effect_lines(result.plan)
    for r in result.runs:
        s = r.summary
        head = f"run {r.plan.index}: {r.plan.label}: {s['points']} points in {s['time_s']:.2f} s"
        if "counters" in s:
            c = s["counters"]
            head += f" ({c['nsteps']} steps, {c['nit']} Newton iterations, {c['nfev']} element evaluations)"
        lines.append(head + ("" if r.success else f": FAILED: {r.message}"))
        if "peak" in s:
            pk = s["peak"]
            lines.append(f"  peak: omega = {pk['omega_rad_s']:.9g} rad/s, amplitude = {pk['amplitude_m']:.9g} m"
                         + (f" (= {pk['amplitude_over_a_min']:.4g} a_min)" if pk["amplitude_over_a_min"] else ""))
    for kind, path in result.files.items():
        lines.append(f"wrote {Path(path).resolve()}" + ("  (partial: failed run)" if path.name.endswith(".partial.csv")
                                                       else ""))
    if not result.success:
        lines.append(f"failed: {result.message}")
        lines.append(f"kept: {result.points} finished points" +
                     (f" in {Path(result.files['csv']).resolve()}" if "csv" in result.files else ""))
    return lines
