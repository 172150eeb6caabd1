"""Where the elements of a ``[structure]`` scene act: the damper's DOFs and the structure's own contacts.

A ``[structure]`` attaches the run's damper (``[damper]``) at ``structure.contact_dofs`` and, for
an element of two components (tangential and normal, ``components = 2``: ``"contact2d"``, ``"allmode2d"``), its
normal at ``structure.normal_dofs``; for one of three (two tangential directions and the normal,
``components = 3``: ``"contact3d"``) also its second tangential direction at
``structure.second_dofs``.  It may hold further elements of the model registry
(``hbm.scenes.MODELS``), the same in every run, as an array of tables::

    [[structure.contacts]]
    model = "gap"            # any registered model complete in its own keys
    dofs = [2]               # [i]: DOF i to ground; [i, j]: on x_i - x_j (force +f on i, -f on j)
    gap_stiffness = 1.0      # the model's own keys, as in [damper] (python3 -m hbm keys)
    gap = 0.25

``normal_dofs`` attaches the normal of a two- or three-component entry, ``second_dofs`` the second
tangential direction of a three-component one.  In one sector of a cyclic structure
(``structure.sectors``) ``next_sector = true`` on an entry, or ``structure.next_sector = true`` for
the damper, joins the next sector to this one (``hbm.Contact(..., next_sector=True)``): every DOF
list is then a pair ``[p, q]``, x_p of the next sector minus x_q of this one, and may name one DOF
twice.  An entry is built from its model's
spec exactly as the damper is (``ModelSpec.build``), but from its own keys only: a model that
needs the bar or the normal load of ``[damper]`` (``ModelSpec.needs``) is refused there, and no
effect is decided for an entry (it is computed as written: no inertia decision, no stuck check).
Everything here reads the spec and the element's contract (``components``, ``has_time_law``), never
a model's name.
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass, field
from typing import Any

from ..structure import Contact
from .checks import GIVEN_INVALID, Invalid, OPTIONAL, REQUIRED, SceneError, boolean, choice, show
from .models import MODELS, Built

#: The keys of a ``[[structure.contacts]]`` entry besides its model's own.
ENTRY_KEYS = {"model": "the element: a registered model (python3 -m hbm models), complete in its own keys",
              "dofs": "[i] (DOF i to ground) or [i, j] (on x_i - x_j)",
              "second_dofs": "three-component models (contact3d) only, required for them: the second tangential "
                             "displacement, [k] or [k, l]",
              "normal_dofs": "two- and three-component models (contact2d, contact3d) only: the normal displacement, "
                             "[k] or [k, l]",
              "next_sector": "with structure.sectors only: true puts the entry between the next sector and this one, "
                             "dofs = [p, q] acting on x_p of the next sector minus x_q of this one (default false)"}


def dof_list(v: Any) -> tuple:
    """A list of one DOF index (to ground) or of two different ones (between them), as a tuple."""
    if (not isinstance(v, list) or len(v) not in (1, 2)  # the entries checked before set() hashes them (a list)
            or any(isinstance(x, bool) or not isinstance(x, int) or x < 0 for x in v) or len(set(v)) != len(v)):
        raise Invalid("must be a list of one DOF index (a contact to ground) or of two different ones "
                      "(a contact between them), each an integer >= 0")
    return tuple(v)


def dof_pair_list(v: Any) -> tuple:
    """As :func:`dof_list`, but a pair may name one DOF twice, ``[p, p]``: DOF p of the next sector and
    DOF p of this one, allowed only with ``next_sector = true`` (:func:`same_dof_problem` says so)."""
    if isinstance(v, list) and len(v) == 2 and v[0] == v[1]:
        return dof_list(v[:1]) * 2
    return dof_list(v)


def same_dof_problem(where: str, dofs: Any, next_sector: bool, next_key: str) -> str | None:
    """The message for a pair ``[p, p]`` without ``next_sector`` (None when there is nothing to say)."""
    if not isinstance(dofs, tuple) or len(dofs) != 2 or dofs[0] != dofs[1] or next_sector:
        return None
    return (f"{where} = {show(list(dofs))}: must be two different DOFs (one DOF twice, x_p of the next sector minus "
            f"x_p of this one, only with structure.sectors and {next_key} = true)")


def contact_tables(v: Any) -> tuple:
    """``structure.contacts``: a list of tables (``[[structure.contacts]]``); each entry is checked
    by :func:`check_entries`."""
    if not isinstance(v, list) or not v or not all(isinstance(e, dict) for e in v):
        raise Invalid("must be a non-empty list of tables ([[structure.contacts]] entries, each with model, dofs "
                      "and the model's keys)")
    return tuple(v)


def check_entries(entries: tuple, path: Any) -> tuple[list, list]:
    """Validate every ``[[structure.contacts]]`` entry: ``(entries, problems)``.

    Each entry comes back as a dict ``model``, ``dofs``, ``second_dofs`` and ``normal_dofs`` (or None) and ``params``
    (the model's keys, defaults filled in); each problem names ``structure.contacts[i].key``, the
    value and what is allowed.
    """
    out, problems = [], []
    for i, entry in enumerate(entries):
        at = f"structure.contacts[{i}]"
        name = entry.get("model")
        if name is None:
            problems.append(f"{path}: {at}.model is missing: required, {ENTRY_KEYS['model']}")
            continue
        try:
            spec = MODELS[choice(*MODELS)(name)]
        except Invalid as exc:
            problems.append(f"{path}: {at}.model = {show(name)}: {exc}")
            continue
        allowed = [*ENTRY_KEYS, *spec.keys]
        params, given, dofs = {}, {}, {}
        for key, value in entry.items():
            if key == "model":
                continue
            if key not in allowed:
                close = difflib.get_close_matches(key, allowed, n=1)
                hint = f" (did you mean {at}.{close[0]}?)" if close else ""
                problems.append(f"{path}: {at}.{key} = {show(value)}: unknown key{hint}; allowed with model = "
                                f"{show(name)}: {', '.join(allowed)}")
                continue
            try:
                if key == "next_sector":
                    dofs[key] = boolean(value)
                elif key in ENTRY_KEYS:
                    dofs[key] = dof_pair_list(value)
                else:
                    given[key] = GIVEN_INVALID  # given, even if invalid (the rules do not repeat its problem)
                    params[key] = given[key] = spec.keys[key].check(value)
            except Invalid as exc:
                problems.append(f"{path}: {at}.{key} = {show(value)}: {exc}")
        for key in ("dofs", "second_dofs", "normal_dofs"):
            same = same_dof_problem(f"{at}.{key}", dofs.get(key), dofs.get("next_sector", False), f"{at}.next_sector")
            if same is not None:
                problems.append(f"{path}: {same}")
        if "dofs" not in entry:
            problems.append(f"{path}: {at}.dofs is missing: required, {ENTRY_KEYS['dofs']}")
        for message in (spec.validate(given) if spec.validate is not None else []):
            problems.append(f"{path}: " + message.replace("damper.model", f"{at}.model").replace("damper.", f"{at}."))
        needs = spec.needs(given)
        if needs:
            problems.append(f"{path}: {at}.model = {show(name)}: as given it needs the {' and '.join(sorted(needs))} "
                            f"of [damper]; a contact of the structure is built from its own keys only (give the "
                            f"model's own parameters: {', '.join(spec.keys) or 'it has none'})")
        for key, k in spec.keys.items():
            if key not in params and k.default is not REQUIRED and k.default is not OPTIONAL:
                params[key] = k.default
        out.append({"model": name, "dofs": dofs.get("dofs"), "second_dofs": dofs.get("second_dofs"),
                    "normal_dofs": dofs.get("normal_dofs"), "next_sector": dofs.get("next_sector", False),
                    "params": params})
    return out, problems


@dataclass
class EntryRun:
    """What a model's ``build(run)`` reads, for a ``[[structure.contacts]]`` entry: its own keys
    (``params``), the scene, the structure and the sweep; no bar, no load, no decided effects."""

    scene: Any
    spec: Any
    index: int
    params: dict
    blade: Any
    omega: tuple
    bar: Any = None
    N: Any = None
    load: Any = None
    micro: Any = None
    inertia: Any = None
    topology: Any = None
    effects: list = field(default_factory=list)

    def where(self, dotted: str) -> str:
        return self.scene.where(dotted.replace("damper.", f"structure.contacts[{self.index}]."))


def attach(scene: Any, element: Any, dofs: tuple, normal_dofs: tuple | None, keys: tuple[str, str],
           label: str, second_dofs: tuple | None = None, second_key: str = "structure.second_dofs",
           next_sector: bool = False, next_key: str = "structure.next_sector") -> Contact:
    """``hbm.Contact`` of ``element`` at ``dofs`` (its normal at ``normal_dofs``, the second tangential
    direction of a three-component element at ``second_dofs``); ``keys`` and ``second_key`` are the
    scene keys that gave them (for messages), ``label`` the element's name in them; ``next_sector``
    (given by the scene key ``next_key``) joins DOF p of the next sector of a cyclic structure to DOF q
    of this one (``hbm.Contact(..., next_sector=True)``)."""
    c = getattr(element, "components", 1)
    if c >= 2 and normal_dofs is None:
        raise SceneError([f"{scene.where(keys[1])} is missing: the {label} element acts on "
                          f"{'a tangential' if c == 2 else 'two tangential displacements'} and a normal displacement; "
                          f"{keys[0]} gives the {'' if c == 2 else 'first '}tangential one, {keys[1]} = [k] "
                          "(to ground) or [k, l] (x_k - x_l) the normal one"])
    if c == 1 and normal_dofs is not None:
        raise SceneError([f"{scene.where(keys[1])} = {show(list(normal_dofs))}: not allowed: the {label} element "
                          "acts on one displacement (normal DOFs attach a two- or three-component element: contact2d, "
                          "contact3d, allmode2d)"])
    if c == 3 and second_dofs is None:
        raise SceneError([f"{scene.where(second_key)} is missing: the {label} element acts on two tangential "
                          f"displacements; {keys[0]} gives the first, {second_key} = [k] (to ground) or [k, l] "
                          "(x_k - x_l) the second"])
    if c != 3 and second_dofs is not None:
        raise SceneError([f"{scene.where(second_key)} = {show(list(second_dofs))}: not allowed: the {label} element "
                          "has one tangential direction (second tangential DOFs attach a three-component element: "
                          "contact3d)"])
    where = {"dof": dofs[0]} if len(dofs) == 1 else {"dofs": tuple(dofs)}
    for one, d in (("second_dof", second_dofs), ("normal_dof", normal_dofs)):
        if d is not None:
            where.update({one: d[0]} if len(d) == 1 else {one + "s": tuple(d)})
    if next_sector:
        for key, d in ((keys[0], dofs), (second_key, second_dofs), (keys[1], normal_dofs)):
            if d is not None and len(d) != 2:
                raise SceneError([f"{scene.where(key)} = {show(list(d))}: with {next_key} = true it must be a pair "
                                  "[p, q], x_p of the next sector minus x_q of this one"])
        where["next_sector"] = True
    try:
        return Contact(element, **where)
    except ValueError as exc:
        key, given = (keys[1], normal_dofs) if c >= 2 else (keys[0], dofs)
        if c == 3 and "second_dof(s)" in str(exc):
            key, given = second_key, second_dofs
        raise SceneError([f"{scene.where(key)} = {show(list(given))}: {exc}"]) from None


def damper_contact(scene: Any, element: Any, label: str = "damper") -> Contact:
    """The run's damper attached at ``structure.contact_dofs`` (``structure.normal_dofs``)."""
    st = scene.structure
    return attach(scene, element, tuple(st["contact_dofs"]), st.get("normal_dofs"),
                  ("structure.contact_dofs", "structure.normal_dofs"), label, st.get("second_dofs"),
                  "structure.second_dofs", bool(st.get("next_sector")), "structure.next_sector")


def structure_contacts(scene: Any, blade: Any, omega: tuple, harmonics: int) -> list:
    """The ``[[structure.contacts]]`` of ``scene`` as ``hbm.Contact`` objects, built from their
    specs; :class:`SceneError` naming the entry for an element that cannot be built or attached,
    or that has no time law where the balance needs one (``harmonics`` > 1)."""
    out, problems = [], []
    for i, e in enumerate(scene.structure.get("contacts") or ()):
        at = f"structure.contacts[{i}]"
        spec = MODELS[e["model"]]
        try:
            built = spec.build(EntryRun(scene, spec, i, dict(e["params"]), blade, omega))
            element = built.element if isinstance(built, Built) else built
            if harmonics > 1 and not element.has_time_law:
                raise SceneError([f"{scene.where(at + '.model')} = {show(e['model'])}: effects.harmonics = "
                                  f"{harmonics} needs an element with a time-domain law; "
                                  f"{type(element).__name__} has none"])
            out.append(attach(scene, element, e["dofs"], e["normal_dofs"], (at + ".dofs", at + ".normal_dofs"),
                              e["model"], e["second_dofs"], at + ".second_dofs", e.get("next_sector", False),
                              at + ".next_sector"))
        except ValueError as exc:  # SceneError is a ValueError: an element's constructor names its parameter
            problems.extend(exc.problems if isinstance(exc, SceneError) else [f"{scene.where(at)}: {exc}"])
    if problems:
        raise SceneError(problems)
    return out


def dof_problems(scene: Any, n: int) -> list:
    """Every DOF index of ``[structure]`` (the damper's, the contacts', the response's) beyond the
    structure's ``n`` DOFs, one message each."""
    st = scene.structure
    named = [("structure.contact_dofs", st["contact_dofs"]), ("structure.second_dofs", st.get("second_dofs")),
             ("structure.normal_dofs", st.get("normal_dofs")),
             ("structure.response_dof", None if st.get("response_dof") is None else (st["response_dof"],))]
    for i, e in enumerate(st.get("contacts") or ()):
        named += [(f"structure.contacts[{i}].{key}", e[key]) for key in ("dofs", "second_dofs", "normal_dofs")]
    out = []
    for key, dofs in named:
        shown = show(list(dofs)) if dofs is not None and not key.endswith("response_dof") else show(
            dofs[0] if dofs else None)
        for d in dofs or ():
            if d >= n:
                out.append(f"{scene.where(key)} = {shown}: DOF {d} is out of range for the structure's {n} DOFs "
                           f"(0 to {n - 1})")
    return out


__all__ = ["dof_list", "dof_pair_list", "same_dof_problem", "contact_tables", "check_entries", "attach",
           "damper_contact", "structure_contacts",
           "dof_problems", "ENTRY_KEYS", "EntryRun"]
