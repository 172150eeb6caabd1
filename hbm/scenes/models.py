"""The damper models a scene can name: a name -> :class:`ModelSpec` mapping (scipy's ``METHODS`` habit).

A spec says which ``[damper]`` keys the model owns, what it needs from the rest of the scene (the
bar, the normal load), how it builds its contact element from a planned run, which microslip
topology it rests on, its amplitude unit and an example element for the property tests.  The
scene machinery reads only the spec, never the model's name, so adding a model is one call:

>>> from contact_models import Macroslip
>>> from hbm.scenes import Key, register_model, number, unregister_model
>>> spec = register_model(
...     "soft-jenkins", lambda run: Macroslip(stiffness=run.params["k_soft"], slip_force=1.0),
...     keys={"k_soft": Key(number(gt=0, unit="N/m"), 1.0e6, "spring of the soft Jenkins element (N/m)")},
...     doc="a Jenkins element of its own spring and a 1 N slider",
...     example=lambda: Macroslip(stiffness=1.0e6, slip_force=1.0))
>>> spec.keys["k_soft"].default
1000000.0
>>> unregister_model("soft-jenkins")

``docs/extending.md`` walks through it with the Iwan element.

Every element of ``contact_models`` is a model here, and all but three have an ``example`` that
the property suite of ``tests/test_element_registry_properties.py`` runs over.  The suite measures
its tolerances in units of the stuck stiffness (``k* a``), and an amplitude sweep tabulates
``F_s = f_s/(k* a)``; so its contract is an element with a stuck stiffness k* > 0:

- ``NumericalMicroslip``, the time-integrated discretised bar, is not a model: each of its
  evaluations integrates the bar to its periodic steady state (about a second even at 8 cells),
  so a scene's sweep (hundreds of evaluations) and the property suite would take hours; it is the
  reference the models are checked against (``docs/validation.md``), used directly.
- ``"cubic"`` (``CubicSpring``, f = k3 x^3) has no example: its stuck stiffness is 0 (nonlinear at
  every amplitude), so the suite's units and ``F_s`` would divide by zero.  ``contact_models``'
  tests check it against its closed forms.
- ``"gap"`` (``Gap``, f = k max(0, x - g)) has k* = 0 for an open gap (g >= 0) too; its example is
  a preloaded gap (g < 0: k* = k), on which the suite runs through both of its regimes (closed
  all period below |g|, opening above).
- ``"contact2d"`` (``Contact2D``) has its example (k* = kt for a preload n0 > 0); the suite sees
  its first harmonic with the normal DOF at rest (the Jenkins element at ``mu n0``).
- ``"contact3d"`` (``Contact3D``) has its example, seen the same way (one tangential direction moving,
  the normal at rest: the Jenkins element at ``mu n0``).
- ``"allmode2d"`` (``AllModeMicroslip2D``) has its example (8 cells, H = 11); the suite sees its
  first harmonic with the normal DOF at rest, which is ``AllModeMicroslip`` on the same cells and
  harmonics (its normal motion is checked in ``tests/test_allmode_normal.py``).

``Gap``, ``Contact2D`` and ``Contact3D`` declare ``linear_amplitude = 0`` (a mean displacement, or
normal motion, changes their contact state at any amplitude) although their first harmonic about a
zero mean is exactly k* a below |g| or mu n0/kt; the suite accepts that exactly linear start.

An amplitude sweep refuses an element whose k* is 0 (naming ``sweep.kind``); in a frequency sweep
and as a contact of a ``[structure]`` (``structure.contacts``, ``hbm.scenes.contacts``) every
model is usable.  ``"contact2d"`` and ``"allmode2d"`` act on two displacements (tangential, normal:
the element's ``components = 2``); the scene attaches the normal with ``structure.normal_dofs`` (or
an entry's ``normal_dofs``).  ``"contact3d"`` acts on three (two tangential, then the normal:
``components = 3``), its second tangential displacement attached with ``structure.second_dofs`` (or an
entry's ``second_dofs``).  ``"allmode2d"`` needs the bar and the load of ``[damper]``, so it is a
damper only, not an entry of ``[[structure.contacts]]``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any, Callable, Mapping, NamedTuple

from contact_models import (AllModeMicroslip, AllModeMicroslip2D, Bar, Contact2D, Contact3D, CubicSpring, Gap, Iwan,
                            Macroslip,
                            PointContact, QuadraticLoad, ThreeRegionMicroslip, TwoRegionMicroslip, UniformLoad)
from contact_models.allmode import CELLS, CELLS_2D, HARMONICS_2D, SAMPLES_PER_HARMONIC_2D

from .checks import OPTIONAL, Invalid, Key, SceneError, choice, integer, number, number_list, show

#: Harmonics inside AllModeMicroslip in scenes.  Scenes solve the single-harmonic balance, which
#: differences the element's omega-derivative; at the element's default H = 15 the default blade's
#: peak sits where the 13th harmonic meets a bar mode, and that balance stalls there
#: (docs/validation.md, "The default blade with the all-mode damper"); H = 11 traces it.
SCENE_HARMONICS = 11

#: The bar's keys in ``[damper]`` (E, rho, A, L, k, mu; beta for the strain-hardening spring).
BAR_KEYS = ("E", "rho", "A", "L", "k", "mu")

#: Keys of ``[damper]`` that every model shares: the bar (Eq. 1-2) and its strain-hardening spring.
BASE_DAMPER_KEYS: dict[str, Key] = {
    "E": Key(number(gt=0, unit="Pa"), OPTIONAL, "Young's modulus of the bar (Pa)"),
    "rho": Key(number(gt=0, unit="kg/m^3"), OPTIONAL, "density of the bar (kg/m^3)"),
    "A": Key(number(gt=0, unit="m^2"), OPTIONAL, "cross-section of the bar (m^2)"),
    "L": Key(number(gt=0, unit="m"), OPTIONAL, "length of the bar and the contact (m)"),
    "k": Key(number(gt=0, unit="N/m^2"), OPTIONAL, "shear-layer stiffness per length (N/m^2)"),
    "beta": Key(number(ge=0, unit="N/m"), OPTIONAL,
                "strain-hardening spring at x = 0 (N/m); needed while effects.strain_hardening = true"),
    "mu": Key(number(ge=0), OPTIONAL, "friction coefficient"),
}


class Built(NamedTuple):
    """What a spec's ``build`` may return instead of a bare element.

    Parameters
    ----------
    element : contact_models.ContactElement
        The run's contact element.
    label : str
        The run's name in the CSV, the summary and the figure.
    note : str, optional
        One line on how the element was made, shown in the effects' reasons (default ``""``).
    """

    element: Any
    label: str  #: the run's name in the CSV, the summary and the figure
    note: str = ""  #: one line on how the element was made (shown in the effects' reasons)


def needs_nothing(given: Mapping[str, Any]) -> set:
    """The default ``needs`` of a model: nothing from the rest of the scene."""
    return set()


@dataclass(frozen=True)
class ModelSpec:
    """Everything the scene machinery knows of a damper model.

    Attributes
    ----------
    name : str
        The value of ``damper.model``.
    build : callable
        ``build(run) -> element`` or :class:`Built`; ``run`` is the
        :class:`hbm.scenes.planning.RunContext` (``run.params`` holds this spec's keys, ``run.bar``,
        ``run.load``, ``run.N``, ``run.micro`` (the single-mode microslip element of the decided
        topology, for a spec with ``microslip``), ``run.inertia``, ``run.blade``, ``run.omega``).
    doc : str
        One line for ``python3 -m hbm models`` and the docs.
    keys : mapping
        ``[damper]`` keys the model owns: name -> :class:`hbm.scenes.Key`.
    needs : callable
        ``needs(given) -> set`` of ``"bar"``, ``"load"``: what the model needs, given the
        ``[damper]`` keys the scene sets (a key set to an invalid value is there as
        ``hbm.scenes.checks.GIVEN_INVALID``: given, its problem said once; read presence, not values).
    microslip : callable or None
        ``microslip(damper) -> "two-region" | "three-region" | "auto"``: the microslip element
        the model rests on (the topology effect decides it; ``run.micro`` is its element), or None.
    unit : callable or None
        ``unit(run) -> (metres, name)``: the amplitude unit of amplitude sweeps.  None: the
        element's ``reference_amplitude`` at the lowest frequency, named "reference amplitude".
    example : callable or None
        ``example() -> element``: a representative element, for the property tests.
    validate : callable or None
        ``validate(given) -> list of str``: rules between this model's keys (``given``: the
        ``[damper]`` keys the scene sets); each message starts with the key it is about.
    """

    name: str
    build: Callable[[Any], Any]
    doc: str = ""
    keys: Mapping[str, Key] = field(default_factory=dict)
    needs: Callable[[Mapping[str, Any]], set] = needs_nothing
    microslip: Callable[[Mapping[str, Any]], str | None] | None = None
    unit: Callable[[Any], tuple[float, str]] | None = None
    example: Callable[[], Any] | None = None
    validate: Callable[[Mapping[str, Any]], list] | None = None


_MODELS: dict[str, ModelSpec] = {}
#: The registered models, name -> ModelSpec (read-only view; register with :func:`register_model`).
MODELS: Mapping[str, ModelSpec] = MappingProxyType(_MODELS)


def register_model(name: str, build: Callable[[Any], Any], *, keys: Mapping[str, Key] | None = None,
                   needs: Callable[[Mapping[str, Any]], set] | set | tuple = (),
                   microslip: Callable[[Mapping[str, Any]], str | None] | None = None,
                   unit: Callable[[Any], tuple[float, str]] | None = None, doc: str = "",
                   example: Callable[[], Any] | None = None,
                   validate: Callable[[Mapping[str, Any]], list] | None = None,
                   replace: bool = False) -> ModelSpec:
    """Make ``damper.model = name`` build ``build(run)``; returns the :class:`ModelSpec`.

    ``needs`` is a set (``{"bar"}``, ``{"bar", "load"}``) or ``needs(given) -> set``.  A key name
    may be owned by several models only as the same :class:`Key` object.  ``replace=True``
    replaces a registered model of that name.  See :class:`ModelSpec` for the rest.

    Parameters
    ----------
    name : str
        The value of ``damper.model`` that selects the model (non-empty, no surrounding spaces).
    build : callable
        ``build(run) -> element`` or ``Built``; ``run`` is the ``RunContext`` of the run.
    keys : mapping or None, optional
        ``[damper]`` keys the model owns: name -> ``Key``; default none.
    needs : set, tuple or callable, optional
        ``"bar"`` and/or ``"load"``, or ``needs(given) -> set`` of them; default nothing.
    microslip : callable or None, optional
        ``microslip(damper) -> "two-region" | "three-region" | "auto"``, for a model resting on
        a microslip element; default None.
    unit : callable or None, optional
        ``unit(run) -> (metres, name)``, the amplitude unit of amplitude sweeps; default None
        (the element's reference amplitude).
    doc : str, optional
        One line for ``python3 -m hbm models`` and the docs.
    example : callable or None, optional
        ``example() -> element``, a representative element for the property tests.
    validate : callable or None, optional
        ``validate(given) -> list of str``, rules between the model's keys.
    replace : bool, optional
        Replace a model registered under ``name`` (default False).

    Returns
    -------
    ModelSpec
        The spec registered in ``MODELS``.

    Raises
    ------
    ValueError
        When ``name`` is empty or registered already (without ``replace``), ``build`` is not
        callable, a key is not a ``Key``, is one of the shared ``[damper]`` keys or belongs to
        another model with another meaning, or ``needs`` names something other than ``"bar"``
        and ``"load"``.

    Examples
    --------
    >>> from contact_models import Macroslip
    >>> from hbm.scenes import MODELS, register_model, unregister_model
    >>> _ = register_model("unit-jenkins", lambda run: Macroslip(stiffness=1.0, slip_force=1.0))
    >>> "unit-jenkins" in MODELS
    True
    >>> unregister_model("unit-jenkins")
    """
    if not isinstance(name, str) or not name or name != name.strip():
        raise ValueError(f"name must be a non-empty string without surrounding spaces, got name={name!r}")
    if name in _MODELS and not replace:
        raise ValueError(f"name={name!r} is registered already (pass replace=True to replace it)")
    if not callable(build):
        raise ValueError(f"build must be callable as build(run) -> element, got build={build!r}")
    keys = dict(keys or {})
    for key, spec in keys.items():
        if not isinstance(spec, Key):
            raise ValueError(f"keys[{key!r}] must be an hbm.scenes.Key, got {spec!r}")
        if key in BASE_DAMPER_KEYS or key == "load":
            raise ValueError(f"keys: {key!r} is a key of every damper ([damper].{key}); choose another name")
        for other in _MODELS.values():
            if other.name != name and key in other.keys and other.keys[key] is not spec:
                raise ValueError(f"keys: damper.{key} belongs to model {other.name!r} already with another "
                                 "meaning; choose another name (or share its Key object)")
    if not callable(needs):
        fixed = set(needs)
        bad = fixed - {"bar", "load"}
        if bad:
            raise ValueError(f"needs must name 'bar' and/or 'load', got needs={needs!r}")
        needs = lambda given, fixed=frozenset(fixed): set(fixed)  # noqa: E731
    spec = ModelSpec(name=name, build=build, doc=doc, keys=MappingProxyType(keys), needs=needs,
                     microslip=microslip, unit=unit, example=example, validate=validate)
    _MODELS[name] = spec
    return spec


def unregister_model(name: str) -> None:
    """Remove the model ``name`` registered with :func:`register_model`.

    Parameters
    ----------
    name : str
        The model's name (the value of ``damper.model``).

    Raises
    ------
    ValueError
        When no model of that name is registered.
    """
    if name not in _MODELS:
        raise ValueError(f"name={name!r} is not a registered model; registered: {', '.join(_MODELS)}")
    del _MODELS[name]


# ====================================================================== the built-in models
def _bar_a_min(run) -> tuple[float, str]:
    """``mu N/(k L)``: the paper's amplitude unit (a_min of the uniformly loaded bar)."""
    bar = run.bar
    return bar.mu * run.N / (bar.k * bar.L), "a_min"


def _example_bar():
    return Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)


def _microslip_model(topology: str):
    """A spec's build and microslip functions for the bar with the given topology."""

    def build(run):
        label = run.topology if topology != "auto" else f"{run.topology} (auto)"
        return Built(run.micro, label)

    return build, (lambda damper: topology)


def _example_two():
    return TwoRegionMicroslip(_example_bar(), UniformLoad(N=100.0))


def _example_three():
    return ThreeRegionMicroslip(_example_bar(), QuadraticLoad.from_ratio(N=100.0, ratio=12.0))


FIT_TO = Key(choice("two-region", "three-region", "auto"), "auto",
             'point-contact only: the microslip model it is fitted to ("auto", "two-region", "three-region")')
FIT_OMEGA = Key(number(ge=0, unit="rad/s"), None,
                "point-contact only: frequency of the fit (rad/s); default the stuck resonance "
                "sqrt((k + k*)/m) of a blade's frequency sweep, the lower end of a structure's sweep, 0 for an "
                "amplitude sweep")


def _build_point_contact(run):


    if run.params.get("fit_omega") is not None:
        w_fit = run.params["fit_omega"]
    elif run.scene.structure is not None:
        w_fit = min(run.omega)  # a structure has no one stuck resonance: the sweep's lower end
    elif run.blade is not None:
        w_fit = math.sqrt((run.blade.stiffness + run.bar.k_star) / run.blade.mass)
    else:
        w_fit = 0.0
    w_fit = w_fit if run.inertia else 0.0
    try:
        element = PointContact.fit(run.micro, w_fit)
    except (ValueError, FloatingPointError) as exc:
        raise SceneError([f"{run.where('damper.fit_omega')} = {w_fit!r}: {exc}"]) from None
    return Built(element, f"point-contact (fitted to {run.topology} at {w_fit:.6g} rad/s)")


def _example_point_contact():
    return PointContact.fit(_example_two())


STIFFNESS = Key(number(gt=0, unit="N/m"), None,
                "macroslip and iwan: stiffness of the element while stuck (N/m); default k* of the bar")
SLIP_FORCE = Key(number(gt=0, unit="N"), None,
                 "macroslip and iwan: force at which the whole element slips (N); default mu N")
CHI = Key(number(gt=-1), -0.5, "iwan only: exponent chi of the density of slip strengths (> -1; "
                               "dissipation per cycle ~ a^(chi + 3))")
IWAN_BETA = Key(number(ge=0), 0.1, "iwan only: beta, the share of the strongest elements (>= 0)")


SLIDER = Key(choice("centred", "from rest"), "centred",
             'macroslip only: the periodic state of a stuck slider, "centred" (w = (max x + min x)/2) or '
             '"from rest" (NLvib\'s: the slider from 0, marched two periods; Macroslip(slider=...))')


def _macroslip_own(params) -> bool:
    return params.get("stiffness") is not None and params.get("slip_force") is not None


def _macroslip_pair(given) -> list:
    """damper.stiffness and damper.slip_force go together."""
    if ("stiffness" in given) == ("slip_force" in given):
        return []
    have = "stiffness" if "stiffness" in given else "slip_force"
    other = "slip_force" if have == "stiffness" else "stiffness"
    return [f"damper.{other} is missing: required with damper.{have} (give both, or neither to take k* and "
            "mu N of the bar)"]


def _build_macroslip(run):
    if _macroslip_own(run.params):
        return Built(Macroslip(stiffness=run.params["stiffness"], slip_force=run.params["slip_force"],
                               slider=run.params["slider"]), "macroslip", "damper.stiffness and damper.slip_force")
    return Built(Macroslip(stiffness=run.bar.k_star, slip_force=run.bar.mu * run.N, slider=run.params["slider"]),
                 "macroslip", "k* of the bar at omega = 0 and mu N")


def _macroslip_unit(run) -> tuple[float, str]:
    if run.bar is not None and run.N is not None:
        return _bar_a_min(run)
    return run.params["slip_force"] / run.params["stiffness"], "a_min"


def _example_macroslip():
    return Macroslip(stiffness=1.0e7, slip_force=30.0)


def _build_iwan(run):
    p = run.params
    if _macroslip_own(p):
        K, F, how = p["stiffness"], p["slip_force"], "damper.stiffness and damper.slip_force"
    else:
        K, F, how = run.bar.k_star, run.bar.mu * run.N, "k* of the bar at omega = 0 and mu N"
    return Built(Iwan(slip_force=F, stiffness=K, chi=p["chi"], beta=p["iwan_beta"]),
                 f"iwan (chi = {p['chi']:g}, beta = {p['iwan_beta']:g})", how)


def _example_iwan():
    return Iwan(slip_force=30.0, stiffness=1.0e7, chi=-0.5, beta=0.1)


CELLS_KEY = Key(integer(2), OPTIONAL, f"all-mode and allmode2d: finite cells along the bar; default {CELLS} "
                                      f"(all-mode, AllModeMicroslip) or {CELLS_2D} (allmode2d, AllModeMicroslip2D)")


def _build_all_mode(run):
    cells = run.params.get("cells") or CELLS
    element = AllModeMicroslip(run.bar, run.load, cells=cells, harmonics=SCENE_HARMONICS)
    return Built(element, "all-mode", f"{element.cells} cells, H = {element.harmonics}")


def _example_all_mode():
    return AllModeMicroslip(_example_bar(), UniformLoad(N=100.0), cells=8, harmonics=SCENE_HARMONICS)


# ---- elements of a structure's contacts: unilateral spring, 2D point contact, cubic spring
def _nonzero(v):
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v == 0.0:
        raise Invalid("must be a nonzero finite number (N/m^3; < 0 softening)")
    return float(v)


_nonzero.what = "a nonzero finite number (N/m^3)"

GAP_STIFFNESS = Key(number(gt=0, unit="N/m"), None,
                    "gap only, required: stiffness k of the unilateral spring f = k max(0, x - gap) (N/m)")
GAP = Key(number(unit="m"), None, "gap only, required: the gap g (m), the displacement at which the contact "
                                  "closes; < 0 a preloaded contact (force -k g at x = 0)")
KT = Key(number(gt=0, unit="N/m"), None, "contact2d and contact3d, required: tangential contact stiffness kt (N/m)")
KN = Key(number(ge=0, unit="N/m for contact2d and contact3d, N/m^2 for allmode2d"), None,
         "contact2d, contact3d and allmode2d, required: normal contact stiffness kn, v > 0 pressing; contact2d's and "
         "contact3d's (N/m): the normal load N = max(0, n0 + kn v); allmode2d's per unit length (N/m^2): the load "
         "q(x) + kn s(x) v")
N0 = Key(number(unit="N"), None, "contact2d and contact3d, required: normal preload n0 (N) at zero normal "
                                 "displacement (<= 0: open at rest)")
FRICTION = Key(number(gt=0), None, "contact2d and contact3d, required: friction coefficient mu of the point contact, "
                                   "|T| <= mu N (contact3d: the magnitude of its two tangential components)")
K3 = Key(_nonzero, None, "cubic only, required: coefficient k3 of f = k3 x^3 (N/m^3; < 0 softening)")


def _required(model: str, *keys: str):
    """A spec's ``validate``: every key of ``keys`` must be given with ``damper.model = model``."""

    def validate(given) -> list:
        return [f"damper.{key} is missing: required with damper.model = {show(model)}" for key in keys
                if key not in given]

    return validate


def _build_gap(run):
    p = run.params
    return Built(Gap(stiffness=p["gap_stiffness"], gap=p["gap"]), "gap",
                 f"k = {p['gap_stiffness']:g} N/m, gap {p['gap']:g} m")


def _build_contact2d(run):
    p = run.params
    return Built(Contact2D(kt=p["kt"], kn=p["kn"], mu=p["friction"], n0=p["n0"]), "contact2d",
                 f"kt = {p['kt']:g} N/m, kn = {p['kn']:g} N/m, mu = {p['friction']:g}, n0 = {p['n0']:g} N")


def _build_contact3d(run):
    p = run.params
    return Built(Contact3D(kt=p["kt"], kn=p["kn"], mu=p["friction"], n0=p["n0"]), "contact3d",
                 f"kt = {p['kt']:g} N/m, kn = {p['kn']:g} N/m, mu = {p['friction']:g}, n0 = {p['n0']:g} N")


def _build_cubic(run):
    return Built(CubicSpring(k3=run.params["k3"]), "cubic", f"k3 = {run.params['k3']:g} N/m^3")


def _example_gap():
    return Gap(stiffness=1.0e6, gap=-1.0e-5)


def _example_contact2d():
    return Contact2D(kt=1.0e6, kn=5.0e5, mu=0.3, n0=100.0)


def _example_contact3d():
    return Contact3D(kt=1.0e6, kn=5.0e5, mu=0.3, n0=100.0)


# ---- the all-mode bar with normal motion (two components: tangential end, normal displacement)
NORMAL_SHAPE = Key(number_list(number(), length=2), (1.0, 1.0),
                   "allmode2d only: [s_0, s_L], the normal displacement along the bar v(x, t) = (s_0 + (s_L - s_0) "
                   "x/L) v(t) of the normal DOF's v(t); [1, 1] uniform, another pair a rocking damper")
BAR_HARMONICS = Key(integer(1), OPTIONAL, f"allmode2d only: harmonics of the bar's nodal motion (AllModeMicroslip2D's "
                                          f"harmonics); default {HARMONICS_2D}; the bar is solved with the larger of "
                                          "this and effects.harmonics")
BAR_SAMPLES = Key(integer(4), OPTIONAL, "allmode2d only: time samples per period of the bar's nodes "
                                        "(AllModeMicroslip2D's n_t), a multiple of 4 and >= 2 damper.bar_harmonics + 2; "
                                        f"default {SAMPLES_PER_HARMONIC_2D} damper.bar_harmonics rounded up to a "
                                        "multiple of 4")


def _validate_all_mode_2d(given) -> list:
    """kn is required; damper.bar_samples must suit damper.bar_harmonics (the element's rule on n_t)."""
    out = _required("allmode2d", "kn")(given)
    n_t, H = given.get("bar_samples"), given.get("bar_harmonics") or HARMONICS_2D
    if n_t is not None and (n_t % 4 or n_t < 2 * H + 2):
        out.append(f"damper.bar_samples = {n_t}: must be a multiple of 4 and at least 2 damper.bar_harmonics + 2 "
                   f"= {2 * H + 2} (damper.bar_harmonics = {H})")
    return out


def _build_all_mode_2d(run):
    p = run.params
    try:
        element = AllModeMicroslip2D(run.bar, run.load, kn=p["kn"], cells=p.get("cells") or CELLS_2D,
                                     harmonics=p.get("bar_harmonics") or HARMONICS_2D, n_t=p.get("bar_samples"),
                                     normal_shape=tuple(p["normal_shape"]))
    except ValueError as exc:
        raise SceneError([f"{run.where('damper.model')} = \"allmode2d\": {exc}"]) from None
    s0, sL = element.normal_shape
    return Built(element, "allmode2d", f"{element.cells} cells, H = {element.harmonics}, n_t = {element.n_t}, "
                                       f"kn = {element.kn:g} N/m^2, normal shape [{s0:g}, {sL:g}]")


def _example_all_mode_2d():
    return AllModeMicroslip2D(_example_bar(), UniformLoad(N=100.0), kn=2.0e9, cells=8, harmonics=SCENE_HARMONICS)


def _register_contacts():
    register_model("gap", _build_gap, keys={"gap_stiffness": GAP_STIFFNESS, "gap": GAP},
                   doc="a unilateral spring behind a gap, f = k max(0, x - g) (Gap)", example=_example_gap,
                   validate=_required("gap", "gap_stiffness", "gap"))
    register_model("contact2d", _build_contact2d, keys={"kt": KT, "kn": KN, "friction": FRICTION, "n0": N0},
                   doc="a point contact: Jenkins friction under the normal load max(0, n0 + kn v), separation "
                       "(Contact2D; tangential and normal DOFs)", example=_example_contact2d,
                   validate=_required("contact2d", "kt", "kn", "friction", "n0"))
    register_model("contact3d", _build_contact3d, keys={"kt": KT, "kn": KN, "friction": FRICTION, "n0": N0},
                   doc="a point contact with two tangential directions: a circular Coulomb limit mu max(0, n0 + kn v), "
                       "separation (Contact3D; two tangential DOFs and a normal one)", example=_example_contact3d,
                   validate=_required("contact3d", "kt", "kn", "friction", "n0"))
    register_model("cubic", _build_cubic, keys={"k3": K3}, doc="a cubic spring f = k3 x^3 (CubicSpring)",
                   validate=_required("cubic", "k3"))
    register_model("allmode2d", _build_all_mode_2d,
                   keys={"kn": KN, "normal_shape": NORMAL_SHAPE, "cells": CELLS_KEY, "bar_harmonics": BAR_HARMONICS,
                         "bar_samples": BAR_SAMPLES}, needs={"bar", "load"}, unit=_bar_a_min,
                   doc="the all-mode bar whose normal load follows a normal motion, with separation "
                       "(AllModeMicroslip2D; tangential and normal DOFs)", example=_example_all_mode_2d,
                   validate=_validate_all_mode_2d)


def _register_builtins():
    bar_and_load = {"bar", "load"}
    for name, doc, example in (
            ("auto", "the microslip bar, two or three regions from where slip starts (Section 2.1)", None),
            ("two-region", "the dynamic microslip bar, slip from the excited end (Eqs. 5-15)", _example_two),
            ("three-region", "the dynamic microslip bar, slip starting inside it (Eqs. 16-28)", _example_three)):
        build, micro = _microslip_model(name)
        register_model(name, build, needs=bar_and_load, microslip=micro, unit=_bar_a_min, doc=doc,
                       example=example)
    register_model("point-contact", _build_point_contact, keys={"fit_to": FIT_TO, "fit_omega": FIT_OMEGA},
                   needs=bar_and_load, microslip=lambda damper: damper.get("fit_to") or "auto", unit=_bar_a_min,
                   doc="the point contact fitted to the microslip bar (Fig. 16)", example=_example_point_contact)
    register_model("macroslip", _build_macroslip, keys={"stiffness": STIFFNESS, "slip_force": SLIP_FORCE, "slider": SLIDER},
                   needs=lambda given: set() if _macroslip_own(given) else {"bar", "load"},
                   unit=_macroslip_unit, doc="the Jenkins element: a spring behind a Coulomb slider",
                   example=_example_macroslip, validate=_macroslip_pair)
    register_model("iwan", _build_iwan,
                   keys={"stiffness": STIFFNESS, "slip_force": SLIP_FORCE, "chi": CHI, "iwan_beta": IWAN_BETA},
                   needs=lambda given: set() if _macroslip_own(given) else {"bar", "load"},
                   doc="Segalman's four-parameter Iwan element: parallel Jenkins elements, slip at any amplitude",
                   example=_example_iwan, validate=_macroslip_pair)
    register_model("all-mode", _build_all_mode, keys={"cells": CELLS_KEY}, needs=bar_and_load, unit=_bar_a_min,
                   doc="the microslip bar with every mode (AllModeMicroslip: phase differences along it)",
                   example=_example_all_mode)


_register_builtins()
_register_contacts()
