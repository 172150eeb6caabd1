"""The ``[study]`` table of a scene: a grid over, or random samples of, any other scene key.

``[study.grid]`` maps dotted scene keys to lists of values (every combination is one run);
``[study.samples]`` maps dotted scene keys to distributions, drawn ``study.n`` times with
``study.seed``; given both, every grid point is combined with every sample.  Each run is the
scene with its point's keys set (``hbm.study``, ``docs/studies.md``).

A study varies the other keys of the scene, which the schema (``hbm.scenes.schema``) lists; the
schema holds this table too, so it passes those keys in (:func:`study_keys`) rather than this
module asking the schema for them.
"""

from __future__ import annotations

from typing import Any, Collection

from ..designs import DISTRIBUTIONS, combine, grid, repeated, samples
from .checks import OPTIONAL, Invalid, Key, choice, integer, number, show, text

#: Executors of a study (``hbm.study.EXECUTORS``).
STUDY_EXECUTORS = ("processes", "serial", "dask")
#: Tables a study may not vary.
_FIXED_TABLES = ("study", "output")


def _scene_key(name: Any, known: Collection[str]) -> str:
    if not isinstance(name, str) or name.split(".")[0] in _FIXED_TABLES or name not in known:
        raise Invalid(f"{show(name)} is not a scene key a study can vary (python3 -m hbm keys lists them; "
                      "write it in quotes with its table: \"damper.mu\")")
    return name


def _grid(v: Any, known: Collection[str]) -> dict:
    if not isinstance(v, dict) or not v:
        raise Invalid('must be a table of "table.key" = [values], e.g. "damper.load.N" = [10.0, 100.0]')
    out = {}
    for name, values in v.items():
        _scene_key(name, known)
        if not isinstance(values, list) or not values:
            raise Invalid(f"{show(name)} = {show(values)}: must be a non-empty list of values")
        twice = repeated(values)
        if twice is not None:
            raise Invalid(f"{show(name)} = {show(values)}: must not repeat a value (one run per value; "
                          f"{show(twice[0])} and {show(twice[1])} are the same value)")
        out[name] = values
    return out


def _samples(v: Any, known: Collection[str]) -> dict:
    if not isinstance(v, dict) or not v:
        raise Invalid('must be a table of "table.key" = {distribution = "uniform", low = ..., high = ...}')
    out = {}
    for name, spec in v.items():
        _scene_key(name, known)
        forms = "; ".join(f'{{distribution = "{k}", {a} = ..., {b} = ...}}' for k, (_, (a, b)) in DISTRIBUTIONS.items())
        if not isinstance(spec, dict) or spec.get("distribution") not in DISTRIBUTIONS:
            raise Invalid(f"{show(name)} = {show(spec)}: must be one of {forms}")
        make, params = DISTRIBUTIONS[spec["distribution"]]
        if set(spec) != {"distribution", *params}:
            raise Invalid(f"{show(name)} = {show(spec)}: a {spec['distribution']} distribution takes exactly "
                          f"{', '.join(params)}")
        try:
            out[name] = make(*(spec[p] for p in params))
        except ValueError as exc:
            raise Invalid(f"{show(name)} = {show(spec)}: {exc}") from None
    return out


def study_keys(known: Collection[str]) -> dict[str, Key]:
    """The keys of ``[study]``; ``study.grid`` and ``study.samples`` may vary the scene keys ``known``
    (dotted, ``table.key``) outside the tables ``study`` and ``output``."""
    known = frozenset(known)
    return {
        "grid": Key(lambda v: _grid(v, known), OPTIONAL, 'table of "table.key" = [values]: one run per combination'),
        "samples": Key(lambda v: _samples(v, known), OPTIONAL,
                       'table of "table.key" = {distribution = "uniform" (low, high), "normal" (mean, std) or '
                       '"lognormal" (median, sigma)}: study.n random runs'),
        "n": Key(integer(1), OPTIONAL, "number of samples; required with study.samples"),
        "seed": Key(integer(0), 0, "seed of the samples (numpy.random.default_rng)"),
        "executor": Key(choice(*STUDY_EXECUTORS), "processes",
                        '"processes" (every local core), "serial" or "dask" (a Dask cluster)'),
        "workers": Key(integer(1), OPTIONAL, "processes or LocalCluster workers; default every core"),
        "scheduler": Key(text, OPTIONAL, 'address of a running Dask scheduler, e.g. "tcp://10.0.0.5:8786" '
                                         '(implies executor = "dask"); default a LocalCluster'),
        "time_limit": Key(number(gt=0, unit="s"), OPTIONAL,
                          "seconds each run may take (a run over it fails, naming the limit; a worker that does "
                          "not stop is killed); default no limit; --time-limit overrides it"),
    }


def study_table(rules: Any) -> dict | None:
    """The validated ``[study]`` of a scene (``rules``: the validator), with its ``points``; None
    without a ``[study]`` table.  Problems are appended to ``rules.problems``."""
    if "study" not in rules.present:
        return None
    study = rules.defaults("study")
    has = lambda key: rules.has("study", key)  # noqa: E731
    if not has("grid") and not has("samples"):
        rules.problems.append(f"{rules.where('[study]')}: give study.grid or study.samples (or both)")
    if has("samples"):
        rules.need("study", "n", "with study.samples")
    elif has("n"):
        rules.forbid("study", "n", "without study.samples")
    both = set(study.get("grid") or ()) & set(study.get("samples") or ())
    if both:
        rules.problems.append(f"{rules.where('[study]')}: {', '.join(sorted(both))} in both study.grid and "
                              "study.samples: give each key once")
    if has("scheduler") and has("executor") and study["executor"] != "dask":
        rules.forbid("study", "scheduler", f"with study.executor = {show(study['executor'])} (a scheduler is Dask's)")
    if rules.problems:
        return study
    points = [{}]
    if study.get("grid"):
        points = grid(study["grid"])
    if study.get("samples"):
        points = combine(points, samples(study["n"], study["samples"], seed=study["seed"]))
    study["points"] = points
    return study


__all__ = ["study_keys", "STUDY_EXECUTORS", "study_table"]
