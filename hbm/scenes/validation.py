"""Reading and validating a scene: every problem of a file in one pass.

:func:`load_scene` reads the TOML file with ``tomllib``; :func:`scene_from_dict` checks it against
:func:`hbm.scenes.schema.schema`: unknown names (with the closest valid one), wrong types, values
out of range, missing keys and the rules between keys (which keys a model needs, mutually
exclusive keys).  A key whose value is invalid counts as given, so one pass reports every
problem once: fixing them all yields a valid scene, with no second round of new messages.
"""

from __future__ import annotations

import difflib
import tomllib
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

from ..balance import presets
from .._validation import MIN_RELATIVE_WIDTH
from ..frf import DEFAULT_TOL
from .checks import (GIVEN_INVALID, TOO_DEEP, Invalid, REQUIRED, OPTIONAL, SceneError, dot, number, number_list,
                     refuse_nesting, show)
from .contacts import check_entries, same_dof_problem
from .models import BAR_KEYS, MODELS
from .schema import REQUIRED_TABLES, SUBTABLES, schema
from .sampling import study_table


@dataclass(frozen=True)
class Scene:
    """A validated scene: each table as a dict with every default filled in.

    ``sweep["options"]`` holds exactly the accuracy keyword arguments of
    :func:`hbm.frequency_response` (``rtol``, ``max_step``, ``min_step``, ``max_steps``, and
    ``tol`` where ``sweep.tol`` is given; ``hbm.scenes.running.accuracy_options`` passes a
    ``sweep.accuracy`` preset by name instead); ``sweep["tol"]`` is the scene's target error in
    any case (given, else the preset's tolerance, else ``hbm.frf.DEFAULT_TOL``).  The balance's
    harmonics and samples are each run's (``RunPlan.harmonics``, ``RunPlan.n_t``).

    Parameters
    ----------
    path : Path
        The scene file (``"<scene>"`` for a scene made from a dict), named in messages.
    title : str
        The top-level ``title`` (``""`` when not given).
    blade : dict or None
        The ``[blade]`` table of a frequency sweep of the single-DOF blade, else None.
    damper : dict
        The ``[damper]`` table; ``damper["model"]`` is a tuple of model names (one run each).
    load : dict or None
        The ``[damper.load]`` table (``N`` a tuple of loads in N, one run each), or None.
    effects : dict
        The ``[effects]`` table, ``tolerance`` filled in (default ``sweep.tolerance``).
    sweep : dict
        The ``[sweep]`` table, ``omega`` in ``sweep["unit"]``, with ``options`` (see above).
    output : dict
        The ``[output]`` table: ``folder`` (default the file's name without ``.toml``) and
        ``formats``.
    structure : dict or None, optional
        The ``[structure]`` table of a structure from matrices (file paths resolved against the
        scene file's folder), or None.
    study : dict or None, optional
        The validated ``[study]`` table with its ``points``, or None.
    modes : dict or None, optional
        The ``[modes]`` table of a nonlinear mode (``sweep["kind"]`` is then ``"modes"``, or
        ``"optimum"`` with ``[optimum]``), or None.
    optimum : dict or None, optional
        The ``[optimum]`` table: ``parameter`` (the dotted key varied) and ``bounds``, or None.
    """

    path: Path
    title: str
    blade: dict | None
    damper: dict
    load: dict | None
    effects: dict
    sweep: dict
    output: dict
    structure: dict | None = None  #: [structure] of a frequency sweep of a structure from matrices (paths resolved)
    study: dict | None = None  #: the validated [study] table with its ``points`` (``hbm.scenes.sampling``)
    modes: dict | None = None  #: [modes] of a nonlinear mode (sweep kind "modes" or "optimum")
    optimum: dict | None = None  #: [optimum]: the damper key varied and its bounds (sweep kind "optimum")

    @property
    def name(self) -> str:
        """The file name without ``.toml``."""
        return self.path.stem

    def where(self, dotted: str) -> str:
        """``file: table.key`` for messages."""
        return f"{self.path}: {dotted}"


def load_scene(path: str | Path, *, overrides: Mapping[str, Any] | None = None) -> Scene:
    """Read and validate the scene file ``path``.

    ``overrides`` maps ``"table.key"`` to a value that replaces the file's (as
    ``python3 -m hbm run --set table.key=value``).  Raises :class:`SceneError` listing every problem.

    Parameters
    ----------
    path : str or Path
        The TOML scene file.
    overrides : mapping or None, optional
        ``"table.key"`` -> value, applied over the file's values before validation; default None.

    Returns
    -------
    Scene
        The validated scene, every default filled in.

    Raises
    ------
    SceneError
        When the file is missing or not TOML, or lists every problem of its content at once
        (unknown names, wrong types, values out of range, missing keys, rules between keys).

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> from hbm.scenes import load_scene
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = Path(folder) / "jenkins.toml"
    ...     _ = path.write_text('[damper]\\nmodel = "macroslip"\\nstiffness = 1e6\\nslip_force = 1.0\\n'
    ...                         '[sweep]\\nkind = "amplitude"\\nomega = [0.0]\\namplitude = [0.1, 10.0]\\n')
    ...     scene = load_scene(path, overrides={"sweep.points": 5})
    >>> scene.name, scene.sweep["points"], scene.output["folder"] == str(path.parent / "jenkins")
    ('jenkins', 5, True)
    """
    return scene_from_dict(read_toml(path), path, overrides=overrides)


def read_toml(path: str | Path) -> dict:
    """The parsed TOML file ``path``; :class:`SceneError` naming the file if it is missing, unreadable,
    not UTF-8 text or not TOML."""
    path = Path(path)
    try:
        with path.open("rb") as fh:
            data = tomllib.load(fh)
    except RecursionError:
        raise SceneError([f"{path}: not valid as a scene: {TOO_DEEP}"]) from None
    except FileNotFoundError:
        raise SceneError([f"{path}: no such file"]) from None
    except tomllib.TOMLDecodeError as exc:
        raise SceneError([f"{path}: not valid TOML: {exc}"]) from None
    except UnicodeDecodeError as exc:  # binary bytes: tomllib reads UTF-8 text only
        raise SceneError([f"{path}: not valid TOML: not UTF-8 text (byte {exc.object[exc.start:exc.start + 1]!r} "
                          f"at offset {exc.start}); a scene is a UTF-8 text file"]) from None
    except OSError as exc:
        raise SceneError([f"{path}: cannot be read: {exc.strerror or exc}"]) from None
    refuse_nesting(data, f"{path}: not valid as a scene")
    return data


def parse_override(text: str) -> tuple[str, Any]:
    """``"table.key=value"`` -> ``("table.key", value)``, the value read as TOML (a bare word as a string).

    Parameters
    ----------
    text : str
        One override as given to ``python3 -m hbm run --set``, e.g. ``"sweep.max_step=0.1"``.

    Returns
    -------
    tuple
        ``(name, value)``: the dotted name, stripped, and the value as TOML reads it (a number,
        a boolean, a list, ...), or the stripped text when it is not TOML.

    Raises
    ------
    SceneError
        When ``text`` has no ``=`` or no name before it.

    Examples
    --------
    >>> parse_override("sweep.max_step=0.1")
    ('sweep.max_step', 0.1)
    >>> parse_override("damper.model=macroslip")
    ('damper.model', 'macroslip')
    """
    name, sep, raw = text.partition("=")
    name = name.strip()
    if not sep or not name:
        raise SceneError([f"--set {text!r}: must be table.key=value, e.g. sweep.max_step=0.1"])
    try:
        value = tomllib.loads(f"v = {raw.strip()}")["v"]
    except tomllib.TOMLDecodeError:
        value = raw.strip()
    except RecursionError:
        raise SceneError([f"--set {name}: {TOO_DEEP}"]) from None
    refuse_nesting(value, f"--set {name}")
    return name, value


def scene_from_dict(data: dict, path: str | Path = "<scene>", *, overrides: Mapping[str, Any] | None = None) -> Scene:
    """Validate the parsed TOML ``data`` (file name ``path`` for messages); see :func:`load_scene`.

    Parameters
    ----------
    data : dict
        The scene as ``tomllib`` parses it: table name -> dict of keys (``damper.load`` nested in
        ``damper``).  Not modified.
    path : str or Path, optional
        The name shown in messages and the default output folder's name (its stem); default
        ``"<scene>"``.
    overrides : mapping or None, optional
        ``"table.key"`` -> value, applied over ``data`` before validation; default None.

    Returns
    -------
    Scene
        The validated scene, with the defaults of the keys ``data`` leaves out.

    Raises
    ------
    SceneError
        Listing every problem of ``data`` at once (one message per key, naming ``path``).

    Examples
    --------
    >>> from hbm.scenes import scene_from_dict
    >>> scene = scene_from_dict({"damper": {"model": "macroslip", "stiffness": 1.0e6, "slip_force": 1.0},
    ...                          "sweep": {"kind": "amplitude", "omega": [0.0], "amplitude": [0.1, 10.0]}})
    >>> scene.damper["model"], scene.sweep["points"]
    (('macroslip',), 50)
    """
    path = Path(path)
    problems: list[str] = []
    data = apply_overrides(data, overrides or {}, problems=problems, path=path)
    tables = schema()
    values, given, present = _check_keys(tables, data, path, problems)
    scene = _Rules(tables, values, given, present, path, problems).scene()
    if problems:
        raise SceneError(list(dict.fromkeys(problems)))
    return scene


def apply_overrides(data: dict, overrides: Mapping[str, Any], *, problems: list | None = None,
                    path: str | Path = "<scene>") -> dict:
    """A copy of the parsed TOML ``data`` with each ``"table.key"`` of ``overrides`` set (tables
    created as needed).  A name below a key that holds a value, not a table (``blade.mass.x`` where
    ``blade.mass`` is a number), cannot be set: a ``SceneError`` naming it (appended to ``problems``
    where given, for validation to report with the rest), never an override dropped in silence.

    Examples
    --------
    >>> apply_overrides({"damper": {"mu": 0.3}}, {"damper.load.N": 50.0})
    {'damper': {'mu': 0.3, 'load': {'N': 50.0}}}
    """
    data = _copy(data)
    found: list[str] = []
    for dotted, value in overrides.items():
        *tables, key = dotted.split(".")
        node = data
        for i, t in enumerate(tables):
            inner = node.setdefault(t, {})
            if not isinstance(inner, dict):
                found.append(f"{path}: {dotted} = {show(value)}: cannot be set: {'.'.join(tables[:i + 1])} is "
                             f"{show(inner)}, not a table")
                break
            node = inner
        else:
            node[key] = value
    if found and problems is None:
        raise SceneError(found)
    if found:
        problems.extend(found)
    return data


def _copy(d):
    return {k: _copy(v) for k, v in d.items()} if isinstance(d, dict) else d


def _suggest(tables, name, valid, table):
    """' (did you mean X?)' from the closest valid name here, or the same key in another table."""
    close = difflib.get_close_matches(name, list(valid), n=1, cutoff=0.6)
    if close:
        return f" (did you mean {dot(table, close[0])}?)"
    elsewhere = [t for t, keys in tables.items() if name in keys and t != table]
    if elsewhere:
        return f" (it belongs in [{elsewhere[0]}]: {dot(elsewhere[0], name)})"
    return ""


def _node(data, dotted):
    node = data
    for part in dotted.split(".") if dotted else ():
        if not isinstance(node, dict):
            return None
        node = node.get(part)
    return node


def _check_keys(tables, data, path, problems):
    """Unknown names, tables that are not tables, per-key types and ranges, required keys.

    Returns ``{table: {key: converted value}}`` (valid keys only), ``{table: set of keys given}``
    (valid or not) and the set of tables present.
    """
    values = {t: {} for t in tables}
    given = {t: set() for t in tables}
    present = {t for t in tables if t and isinstance(_node(data, t), dict)}
    top_tables = [t for t in tables if t and "." not in t]
    for key, value in data.items():
        if key in tables[""]:
            continue
        if key in top_tables:
            if not isinstance(value, dict):
                problems.append(f"{path}: {key} = {show(value)}: must be a table ([{key}])")
            continue
        hint = _suggest(tables, key, list(tables[""]) + top_tables, "")
        shown = f"[{key}]" if isinstance(value, dict) else f"{key} = {show(value)}"
        problems.append(f"{path}: {shown}: unknown top-level name{hint}; allowed: "
                        f"{', '.join(f'[{t}]' for t in top_tables)}, {', '.join(tables[''])}")
    for table, keys in tables.items():
        node = _node(data, table)
        if not isinstance(node, dict):
            continue
        sub = SUBTABLES.get(table)
        for key, value in node.items():
            if not table and key not in keys:
                continue  # the top level's tables and unknown names: handled above
            if key == sub:
                if not isinstance(value, dict):
                    problems.append(f"{path}: {table}.{key} = {show(value)}: must be a table ([{table}.{key}])")
                continue
            if key not in keys:
                valid = list(keys) + ([sub] if sub else [])
                problems.append(f"{path}: {dot(table, key)} = {show(value)}: unknown key"
                                f"{_suggest(tables, key, valid, table)}; allowed in [{table}]: {', '.join(valid)}")
                continue
            given[table].add(key)
            try:
                values[table][key] = keys[key].check(value)
            except Invalid as exc:
                problems.append(f"{path}: {dot(table, key)} = {show(value)}: {exc}")
        for key, spec in keys.items():
            if spec.default is REQUIRED and key not in node and _node(data, table.split(".")[0]) is not None:
                problems.append(f"{path}: {dot(table, key)} is missing: required, {spec.doc}")
    for table in REQUIRED_TABLES:
        if table not in data:
            problems.append(f"{path}: [{table}] is missing: required ({REQUIRED_TABLES[table]})")
    return values, given, present


class _Rules:
    """Rules between keys, on the valid values; a key given with an invalid value counts as given."""

    def __init__(self, tables, values, given, present, path, problems):
        self.tables, self.t, self.given, self.present = tables, values, given, present
        self.path, self.problems = path, problems

    def where(self, dotted):
        return f"{self.path}: {dotted}"

    def has(self, table, key):
        return key in self.given[table]

    def given_values(self, table):
        """The valid values of ``table`` and ``GIVEN_INVALID`` for each key given with an invalid value: what a
        model's ``needs`` sees (a key whose value is refused is still given: its problem is said once)."""
        return {**dict.fromkeys(self.given[table], GIVEN_INVALID), **self.t[table]}

    def need(self, table, key, why):
        if not self.has(table, key):
            self.problems.append(f"{self.where(dot(table, key))} is missing: required {why}; "
                                 f"{self.tables[table][key].doc}")

    def forbid(self, table, key, why):
        raw = self.t[table].get(key, "(invalid)")
        self.problems.append(f"{self.where(dot(table, key))} = {show(raw)}: not allowed {why}")

    def defaults(self, table):
        out = {}
        for key, spec in self.tables[table].items():
            if key in self.t[table]:
                out[key] = self.t[table][key]
            elif spec.default is not REQUIRED and spec.default is not OPTIONAL:
                out[key] = spec.default
        return out

    # ------------------------------------------------------------------
    def scene(self) -> Scene:
        sweep = self.defaults("sweep")
        damper = self.defaults("damper")
        effects = self.defaults("effects")
        output = self.defaults("output")
        load = self.defaults("damper.load")
        modes, optimum = self._modal(sweep, load)
        self._sweep(sweep)
        blade = self._blade(sweep["kind"])
        structure = self._structure(sweep["kind"])
        specs = [MODELS[m] for m in damper["model"]]
        needs = set().union(*(s.needs(self.given_values("damper")) for s in specs)) if specs else set()
        self._damper(specs, needs, effects)
        has_load = "damper.load" in self.present
        self._load(needs, has_load, load, damper["model"])
        if effects.get("tolerance") is None:
            effects["tolerance"] = sweep["options"]["rtol"]
        bar_complete = all(self.has("damper", k) for k in BAR_KEYS)
        if sweep["unit"] == "omega_c" and not bar_complete and "bar" not in needs:
            self.forbid("sweep", "unit", "without a bar in [damper] (omega_c is the bar's: give E, rho, A, L, k, mu)")
        # beside the scene file, as its matrix files are read (the command line's --out writes elsewhere)
        output["folder"] = str(self.path.parent / (output.get("folder") or self.path.stem))
        study = study_table(self) if "study" in self.tables else None
        if study is not None and modes is not None:
            self.problems.append(f"{self.path}: [study] with [{'optimum' if optimum else 'modes'}]: a study runs "
                                 "frequency or amplitude sweeps only")
        return Scene(path=self.path, title=self.t[""].get("title", ""), blade=blade, damper=damper,
                     load=load if has_load else None, effects=effects, sweep=sweep, output=output, study=study,
                     structure=structure, modes=modes, optimum=optimum)

    def _modal(self, sweep, load):
        """[modes] and [optimum]: the scene's kind becomes "modes" or "optimum" (``sweep["kind"]``)."""
        if "modes" not in self.present and "optimum" not in self.present:
            return None, None
        kind = "optimum" if "optimum" in self.present else "modes"
        if self.has("sweep", "kind"):
            self.forbid("sweep", "kind", f"with [{kind}]: the scene computes "
                        f"{'the damper optimum' if kind == 'optimum' else 'a nonlinear mode'}; leave sweep.kind out")
        sweep["kind"] = kind
        if "modes" not in self.present:
            self.problems.append(f"{self.path}: [modes] is missing: required with [optimum] (modes.amplitude: the "
                                 "modal amplitudes of the mode at optimum.bounds[0], holding its peak)")
            return None, None
        modes = self.defaults("modes")
        rng, at = modes.get("amplitude"), modes.get("amplitudes")
        if rng is not None and not rng[0] < rng[1]:
            self.problems.append(f"{self.where('modes.amplitude')} = {show(list(rng))}: must be [a0, a1] with a0 < a1")
        elif rng is not None and at is not None and not rng[0] <= min(at) <= max(at) <= rng[1]:
            self.problems.append(f"{self.where('modes.amplitudes')} = {show(list(at))}: must lie within "
                                 f"modes.amplitude = {show(list(rng))}")
        if kind == "optimum":
            self.need("modes", "amplitude", "with [optimum] (the mode at optimum.bounds[0] is traced over it)")
            if self.has("modes", "amplitudes"):
                self.problems.append(f"{self.where('modes.amplitudes')} = {show(list(at or ()) or '(invalid)')}: not "
                                     "allowed with [optimum] (the optimum follows the peak, not given amplitudes)")
        elif not self.has("modes", "amplitude") and not self.has("modes", "amplitudes"):
            self.problems.append(f"{self.where('modes.amplitude')} is missing: give modes.amplitude = [a0, a1] or "
                                 "modes.amplitudes = [...]")
        return modes, (self._optimum(load) if kind == "optimum" else None)

    def _optimum(self, load):
        """[optimum]: the parameter is a number key of [damper] or [damper.load] the scene gives."""
        opt = self.defaults("optimum")
        name, bounds = opt.get("parameter"), opt.get("bounds")
        table, _, key = (name or "").rpartition(".")
        one = lambda k, v: isinstance(v, float) or (k == "N" and isinstance(v, tuple) and len(v) == 1)  # noqa: E731
        scalar = table in ("damper", "damper.load") and one(key, self.t[table].get(key))
        if name is not None and not scalar:
            keys = [dot(t, k) for t in ("damper", "damper.load") for k, v in self.t[t].items() if one(k, v)]
            self.problems.append(f"{self.where('optimum.parameter')} = {show(name)}: must be a number key of "
                                 f"[damper] or [damper.load] that the scene gives (one value); here: "
                                 f"{', '.join(keys) or 'none'}")
        if bounds is not None:
            if not bounds[0] < bounds[1]:
                self.problems.append(f"{self.where('optimum.bounds')} = {show(list(bounds))}: must be [p0, p1] "
                                     "with p0 < p1")
            elif scalar:
                for b in bounds:
                    try:
                        self.tables[table][key].check(b)
                    except Invalid as exc:
                        self.problems.append(f"{self.where('optimum.bounds')} = {show(list(bounds))}: {b!r} is not "
                                             f"a value of {name}: {exc}")
        return opt

    def _sweep(self, sweep):
        kind = sweep["kind"]
        omega = self.t["sweep"].get("omega")
        if omega is not None:
            item = number(ge=0)
            try:
                if kind == "frequency":
                    pair = number_list(item, length=2)(omega)
                    if pair[0] == pair[1]:
                        raise Invalid("must be a list of 2 different numbers [w0, w1] (w0 > w1 sweeps down)")
                    if abs(pair[1] - pair[0]) < MIN_RELATIVE_WIDTH * max(pair):  # as frequency_response refuses it
                        raise Invalid(f"must be [w0, w1] at least {MIN_RELATIVE_WIDTH:g} of the larger apart (double "
                                      f"precision resolves omega to 2.2e-16 of it)")
                    sweep["omega"] = pair
                elif kind in ("modes", "optimum"):
                    pair = number_list(item, length=2)(omega)
                    if not pair[0] < pair[1]:
                        raise Invalid("must be [w0, w1] with w0 < w1: the frequencies the mode spans")
                    sweep["omega"] = pair
                else:
                    sweep["omega"] = number_list(item, minimum=1)(omega)
            except Invalid as exc:
                what = {"frequency": "the range [w0, w1])", "amplitude": "the frequencies of the table)"}.get(
                    kind, "the frequencies the mode spans, on which the effects are decided)")
                self.problems.append(f"{self.where('sweep.omega')} = {show(omega)}: {exc} "
                                     f"(sweep.kind = \"{kind}\": {what}")
        knobs = ("tolerance", "max_step", "min_step", "max_steps")
        if self.has("sweep", "tolerance"):  # read for one release: it is not the accuracy, sweep.tol is
            warnings.warn(f"{self.where('sweep.tolerance')} is deprecated: it sets the elements' relative accuracy "
                          "(rtol), not the target error of the response; give sweep.tol, the one accuracy key (it "
                          "sets rtol = tol/100, at most 1e-6)", FutureWarning, stacklevel=2)
        if self.has("sweep", "accuracy"):  # read for one release: sweep.tol takes the same names
            name = self.t["sweep"].get("accuracy")  # None: not a preset name, already reported with the names
            if name is not None:
                warnings.warn(f"{self.where('sweep.accuracy')} is deprecated: it is a preset of an earlier release "
                              "(the tolerance of its name with that release's element rtol and steps); give "
                              f"sweep.tol = {show(name)}, which adapts as a number does", FutureWarning, stacklevel=2)
            for key in knobs:
                if self.has("sweep", key):
                    self.forbid("sweep", "accuracy", f"together with sweep.{key}, which it sets: give one of "
                                                     "them (as frequency_response's accuracy=)")
            options = presets.resolve(sweep.get("accuracy", "default")).options()
        else:
            options = presets.resolve("default").options()
            for key, name in zip(knobs, ("rtol", "max_step", "min_step", "max_steps")):
                if key in self.t["sweep"]:
                    options[name] = self.t["sweep"][key]
            if options["min_step"] > options["max_step"]:
                self.forbid("sweep", "min_step", f"above sweep.max_step = {options['max_step']!r}")
        sweep["options"] = options
        sweep["tolerance"] = options["rtol"]
        if sweep.get("tol") is not None:  # given: frequency_response's tol (else its default, or the preset's)
            options["tol"] = sweep["tol"]
        else:
            sweep["tol"] = presets.TOLERANCE[sweep["accuracy"]] if sweep.get("accuracy") else DEFAULT_TOL
        if kind in ("modes", "optimum"):
            for key in ("min_step", "accuracy") + (("tolerance", "tol") if kind == "optimum" else ()):
                if self.has("sweep", key):
                    self.forbid("sweep", key, f"with [{kind}] (not a setting of the mode's continuation"
                                              f"{'; the optimum takes the elements default tolerance' if key in ('tolerance', 'tol') else ''})")
        if kind != "amplitude":
            for key in ("amplitude", "amplitude_unit", "points"):
                if self.has("sweep", key):
                    self.forbid("sweep", key, f'with sweep.kind = "{kind}" (it belongs to an amplitude sweep)')
            if "blade" not in self.present and "structure" not in self.present:
                self.problems.append(f"{self.path}: [blade] is missing: required for sweep.kind = \"frequency\" "
                                     "(mass, stiffness or frequency, damping or damping_ratio, force), or "
                                     "[structure] (matrices from files)")
            elif "blade" in self.present and "structure" in self.present:
                self.problems.append(f"{self.path}: [blade] and [structure] together: give one of them")
        else:
            self.need("sweep", "amplitude", 'with sweep.kind = "amplitude"')
            for key in ("max_step", "min_step", "max_steps", "accuracy"):
                if self.has("sweep", key):
                    self.forbid("sweep", key, 'with sweep.kind = "amplitude" (continuation settings of a '
                                              'frequency sweep)')

    def _blade(self, kind):
        if "blade" not in self.present or kind == "amplitude":
            return None
        blade = dict(self.t["blade"])
        for a, b in (("stiffness", "frequency"), ("damping", "damping_ratio")):
            if self.has("blade", a) and self.has("blade", b):
                self.forbid("blade", b, f"together with blade.{a}: give one of them")
            elif not self.has("blade", a) and not self.has("blade", b):
                self.problems.append(f"{self.where('blade.' + a)} is missing: give blade.{a} or blade.{b}")
        return blade

    def _structure(self, kind):
        """[structure]: exactly one damping, the files relative to the scene file."""
        if "structure" not in self.present:
            return None
        if kind == "amplitude":
            self.problems.append(f"{self.path}: [structure] belongs to a frequency sweep (sweep.kind = \"frequency\") "
                                 "or a nonlinear mode ([modes])")
            return None
        st = self.defaults("structure")
        given = [k for k in ("damping", "rayleigh", "modal_damping") if self.has("structure", k)]
        if len(given) != 1:
            self.problems.append(f"{self.where('structure.damping')}: give exactly one of structure.damping, "
                                 f"structure.rayleigh, structure.modal_damping (got {', '.join(given) or 'none'})")
        self._cyclic(st)
        for key in ("mass", "stiffness", "damping", "next_mass", "next_stiffness", "next_damping"):
            if isinstance(st.get(key), str):
                st[key] = str(self.path.parent / st[key])
        if st.get("contacts") is not None:  # [[structure.contacts]]: each entry's model and keys
            st["contacts"], problems = check_entries(st["contacts"], self.path)
            self.problems.extend(problems)
            if not self.has("structure", "sectors"):
                for i, e in enumerate(st["contacts"]):
                    if e.get("next_sector"):
                        self.problems.append(f"{self.where(f'structure.contacts[{i}].next_sector')} = true: not "
                                             "allowed unless structure.sectors is given (a contact to the next "
                                             "sector belongs to a cyclic structure)")
        return st

    def _cyclic(self, st):
        """The keys of one sector of a cyclic structure (``structure.sectors``): engine_order required
        with it, the couplings and next_sector refused without it, [modes] and [optimum] (nonlinear
        modes, which one sector does not provide) and modal damping refused with it
        (a disk's modes differ per nodal diameter: give structure.damping or structure.rayleigh), the
        damping coupling only beside a damping file."""
        cyclic = self.has("structure", "sectors")
        own = ("engine_order", "next_mass", "next_stiffness", "next_damping", "next_sector")
        if cyclic:
            self.need("structure", "engine_order", "with structure.sectors")
            for table in ("modes", "optimum"):
                if table in self.present:
                    self.forbid("structure", "sectors", f"with [{table}]: the nonlinear modes of one sector of a "
                                "cyclic structure are not provided (give the whole disk's matrices as a plain "
                                "[structure], or a frequency sweep)")
            if self.has("structure", "modal_damping"):
                self.forbid("structure", "modal_damping", "with structure.sectors (the disk's modes differ per "
                            "nodal diameter): give structure.damping and structure.next_damping, or "
                            "structure.rayleigh")
            if self.has("structure", "next_damping") and not self.has("structure", "damping"):
                self.forbid("structure", "next_damping", "unless structure.damping is given (with structure.rayleigh "
                            "C_next = alpha M_next + beta K_next)")
        else:
            for key in own:
                if self.has("structure", key):
                    self.forbid("structure", key, "unless structure.sectors is given (it belongs to one sector of a "
                                "cyclic structure)")
        for key in ("contact_dofs", "second_dofs", "normal_dofs"):
            same = same_dof_problem(self.where(f"structure.{key}"), st.get(key), bool(st.get("next_sector")) and cyclic,
                                    "structure.next_sector")
            if same is not None:
                self.problems.append(same)

    def _damper(self, specs, needs, effects):
        if "bar" in needs:
            first = next(s.name for s in specs if "bar" in s.needs(self.given_values("damper")))
            why = f"for damper.model = {show(first)}"
            for key in BAR_KEYS:
                self.need("damper", key, why)
            if effects["strain_hardening"]:
                self.need("damper", "beta", why + " while effects.strain_hardening = true (or set it false)")
        names = [s.name for s in specs]
        for key in sorted(self.given["damper"]):
            owners = [m.name for m in MODELS.values() if key in m.keys]
            if owners and not any(o in names for o in owners):
                self.forbid("damper", key, f"unless damper.model includes {' or '.join(map(show, owners))}")
        for spec in specs:
            if spec.validate is not None:
                own = {k: v for k, v in self.t["damper"].items() if k in spec.keys}
                own.update({k: None for k in self.given["damper"] if k in spec.keys and k not in own})
                for message in spec.validate(own):
                    self.problems.append(self.where(message))

    def _load(self, needs, has_load, load, models):
        if "load" in needs and not has_load:
            first = next(m for m in models if "load" in MODELS[m].needs(self.given_values("damper")))
            self.problems.append(f"{self.path}: [damper.load] is missing: required for damper.model = {show(first)} "
                                 "(kind, N, and ratio or q0 and q2 for a quadratic load)")
            return
        if not has_load:
            return
        t = self.t["damper.load"]
        if load["kind"] == "centrifugal":
            for key in ("N", "ratio", "q0", "q2"):
                if self.has("damper.load", key):
                    self.forbid("damper.load", key, 'with damper.load.kind = "centrifugal" (its load follows omega)')
            for key in ("mass", "radius", "engine_order"):
                self.need("damper.load", key, 'with damper.load.kind = "centrifugal"')
            return
        for key in ("mass", "radius", "engine_order"):
            if self.has("damper.load", key):
                self.forbid("damper.load", key, 'except with damper.load.kind = "centrifugal"')
        if load["kind"] == "uniform":
            for key in ("ratio", "q0", "q2"):
                if self.has("damper.load", key):
                    self.forbid("damper.load", key, 'with damper.load.kind = "uniform" (use kind = "quadratic")')
            self.need("damper.load", "N", 'with damper.load.kind = "uniform"')
            return
        by_ratio = self.has("damper.load", "N") or self.has("damper.load", "ratio")
        by_q = self.has("damper.load", "q0") or self.has("damper.load", "q2")
        if by_ratio and by_q:
            self.problems.append(f"{self.where('damper.load')}: give N and ratio, or q0 and q2, not both")
        elif by_q:
            for key in ("q0", "q2"):
                self.need("damper.load", key, "with the other of q0, q2")
            if "q0" in t and "q2" in t:
                if t["q2"] > t["q0"]:
                    self.problems.append(f"{self.where('damper.load.q2')} = {show(t['q2'])}: must be <= "
                                         f"damper.load.q0 = {show(t['q0'])} (the load q0 - q2 at mid-length must "
                                         "be >= 0)")
                L = self.t["damper"].get("L")
                load["N"] = ((t["q0"] - 2.0 * t["q2"] / 3.0) * L,) if L else None
        else:
            for key in ("N", "ratio"):
                self.need("damper.load", key, 'with damper.load.kind = "quadratic" (or give q0 and q2)')
