"""Planning a scene: one run per model and load, its effects decided and its element built.

:func:`plan_scene` makes a :class:`RunContext` for every model at every normal load, passes it
through the deciders of :data:`hbm.scenes.effects.EFFECTS` in order, applies what each decided
(the deciders change nothing themselves), builds the element they decided and freezes it all into
a :class:`RunPlan`: the model, the element, the harmonics and samples of the balance.  Physically impossible scenes raise :class:`SceneError` naming the key, every
run's problems at once.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from contact_models import (Bar, CentrifugalLoad, ContactElement, QuadraticLoad, QuasiStatic, RotatingPreload,
                            ThreeRegionMicroslip, TwoRegionMicroslip, UniformLoad)
from contact_models.quasi_static import StuckContact

from ..blade import Blade
from .._validation import nonzero_force
from ..balance.residual import solved_as_one_dof, static_deflection
from ..cyclic import CyclicStructure
from ..structure import Structure
from .checks import SceneError, show
from .contacts import damper_contact, dof_problems, structure_contacts
from .effects import EFFECTS, ONSET_AT_END, Effect, linear_amplitude
from .matrices import read_matrix
from .models import BAR_KEYS, Built, MODELS, ModelSpec
from .validation import Scene


#: What a decider may decide for its run (``Effect.decided``), applied by the planner in order.
DECISIONS = ("bar", "inertia", "topology", "element", "stuck", "model", "harmonics", "n_t")


@dataclass
class RunContext:
    """One run while it is planned: what the deciders and the model's ``build`` read.

    The deciders do not change it: each returns an :class:`Effect` whose ``decided`` names the
    settings it decides (``hbm.scenes.planning.DECISIONS``), and the planner applies them with
    :meth:`apply`, in the order of ``EFFECTS``.  :attr:`element` is the element of the run as decided so far, made on
    first use from the model's spec (or the model a decider chose) and made again after a
    decision it depends on; without damper inertia a frequency-dependent element is wrapped in
    ``contact_models.QuasiStatic``.  The plan's element is the one left after the last decider,
    and only that one is checked along the sweep.

    Parameters
    ----------
    scene : Scene
        The validated scene.
    spec : ModelSpec
        The model of this run (``MODELS[name]``).
    index : int
        Position of the run in the plan, from 0 (the outputs number runs from 1).
    N : float or None
        Total normal load of this run (N), or None for a model that needs no load.
    bar : contact_models.Bar or None
        The bar of the scene's ``[damper]`` keys, or None (decided: ``"bar"``).
    blade : object
        The ``hbm.Blade`` (or ``hbm.Structure``) of a frequency sweep; None for an amplitude sweep.
    omega : tuple of float
        The sweep's range (frequency sweep) or frequencies (amplitude sweep), in rad/s.
    params : dict
        The ``[damper]`` keys this model owns, validated, defaults filled in.
    inertia : bool or None, optional
        Whether damper inertia is simulated (decided: ``"inertia"``).
    topology : str or None, optional
        ``"two-region"`` or ``"three-region"`` (decided: ``"topology"``).
    stuck : bool, optional
        The damper stays stuck: the element is wrapped in ``StuckContact`` (decided: ``"stuck"``).
    model : Built or None, optional
        A model a decider chose in place of the spec's build (decided: ``"model"``; the all-mode bar).
    harmonics, n_t : int or None, optional
        Harmonics and AFT samples of the balance; None: the single-harmonic balance of a blade
        (decided: ``"harmonics"``, ``"n_t"``).
    effects : list of Effect, optional
        The decisions made so far, in the order of ``EFFECTS``.
    """

    scene: Scene
    spec: ModelSpec
    index: int
    N: float | None
    bar: Any  #: the bar of the scene (``contact_models.Bar``) or None
    blade: Any  #: ``hbm.Blade`` of a frequency sweep, None for an amplitude sweep
    omega: tuple  #: the sweep's range (frequency) or frequencies (amplitude), rad/s
    params: dict  #: the [damper] keys of this model (validated, defaults filled in)
    inertia: bool | None = None  #: decided by the inertia decider
    topology: str | None = None  #: "two-region" or "three-region", decided by the topology decider
    stuck: bool = False  #: decided by the slip decider: the damper is a linear spring
    model: Built | None = None  #: a model chosen by a decider (the all-mode bar), else the spec's
    harmonics: int | None = None  #: harmonics of the balance (None: single-harmonic balance of a blade)
    n_t: int | None = None  #: AFT samples per period of the multi-harmonic balance
    effects: list = field(default_factory=list)
    _spec_built: Built | None = None  # caches, made again after the decisions they depend on
    _element: Any = None
    _micro: Any = None
    _load: Any = None

    def where(self, dotted: str) -> str:
        """``file: table.key`` for messages."""
        return self.scene.where(dotted)

    def apply(self, decided: dict) -> None:
        """Apply a decider's decisions (names of ``DECISIONS`` -> value), in order.

        ``"element"`` makes the given element the run's from here on (a decider that wraps
        :attr:`element`); ``"stuck"`` wraps the element as it is now in ``StuckContact``; the
        others set the field of that name, and the element is made again from them on next use."""
        for name, value in decided.items():
            if name not in DECISIONS:
                raise SceneError([f"{self.where('effects')}: a decider decided {name!r}, which is not one of "
                                  f"{', '.join(DECISIONS)}"])
            if name == "element":
                self._element = self._checked(value)
            elif name == "stuck":
                if value and not self.stuck:
                    self._element = StuckContact(self.element)
                self.stuck = bool(value)
            else:
                setattr(self, name, value)
                if name in ("bar", "topology"):
                    self._spec_built, self._micro, self._element = None, None, None
                elif name in ("model", "inertia"):
                    self._element = None

    @property
    def load(self) -> Any:
        """The normal load of this run (``contact_models`` load object), or None without [damper.load]."""
        if self._load is None and self.scene.load is not None:
            ld = self.scene.load
            if ld["kind"] in ("uniform", "centrifugal"):  # a centrifugal load: uniform, N of this run's omega
                self._load = UniformLoad(N=self.N)
            elif ld.get("q0") is not None:
                self._load = QuadraticLoad(q0=ld["q0"], q2=ld["q2"], L=self.scene.damper["L"])
            else:
                self._load = QuadraticLoad.from_ratio(N=self.N, ratio=ld["ratio"])
        return self._load

    @property
    def load_text(self) -> str:
        """The load in words, for the reasons."""
        load = self.load
        if self.scene.load["kind"] in ("uniform", "centrifugal"):
            return f"uniform load N = {load.N:g} N"
        r = load.ratio
        shape = "concave" if r > 1 else ("convex" if r < 1 else "uniform")
        return f"quadratic load N = {load.N:g} N, ratio q0/(q0 - q2) = {r:g} ({shape})"

    @property
    def micro_key(self) -> str:
        """The key that chose the microslip model: ``damper.fit_to`` or ``damper.model``."""
        return "damper.fit_to" if "fit_to" in self.spec.keys else "damper.model"

    @property
    def micro(self) -> Any:
        """The single-mode microslip element of the decided topology, for a model on the bar (made
        on first use; checked along the sweep only if the plan keeps it, :meth:`check_micro`)."""
        if self._micro is None:
            bar, load = self.bar, self.load
            cls = ThreeRegionMicroslip if self.topology == "three-region" else TwoRegionMicroslip
            try:
                self._micro = cls(bar, load)
            except ValueError as exc:
                static_interior = (bar.mu * load.on(bar.L).N > 0.0
                                   and bar.slip_onset(load, 0.0)[0] < bar.L * (1.0 - ONSET_AT_END))
                asked = self.spec.microslip(self.params)
                if cls is TwoRegionMicroslip and static_interior:  # the model asked for cannot follow this load
                    raise SceneError([f"{self.where(self.micro_key)} = {show(asked)} with the {self.load_text}: "
                                      f'{exc}; allowed here: "three-region" or "auto"']) from None
                # the bar and load themselves are outside what the microslip elements describe
                raise SceneError([f"{self.where('damper.load')}: {exc} (damper.model = {show(self.spec.name)}, "
                                  f"{self.load_text})"]) from None
        return self._micro

    def probe_frequencies(self) -> tuple:
        """The damper frequencies the element will see: 0 without inertia, the sweep's ends and
        middle for a frequency sweep, the table's frequencies for an amplitude sweep."""
        lo, hi = min(self.omega), max(self.omega)
        if not self.inertia:
            return (0.0,)
        if self.blade is not None:
            return (lo, 0.5 * (lo + hi), hi)
        return tuple(sorted(set(self.omega)))

    def check_micro(self) -> None:
        """The single-mode element's path must exist at every frequency it will see."""
        for w in self.probe_frequencies():
            try:
                self.micro.slip_amplitude(w)
                self.micro.gross_slip_amplitude(w)
            except (ValueError, FloatingPointError) as exc:
                key = "damper.load" if isinstance(exc, ValueError) else "sweep.omega"
                raise SceneError([f"{self.where(key)}: {exc} (damper.model = {show(self.spec.name)}, "
                                  f"{self.load_text})"]) from None

    def built(self) -> Built:
        """The run's model as decided so far: a decider's choice, else the spec's build."""
        if self.model is not None:
            return self.model
        if self._spec_built is None:
            out = self.spec.build(self)
            self._spec_built = out if isinstance(out, Built) else Built(out, self.spec.name)
        return self._spec_built

    def _checked(self, element: Any) -> Any:
        if not isinstance(element, ContactElement):
            raise SceneError([f"{self.where('damper.model')} = {show(self.spec.name)}: its build returned "
                              f"{element!r}, not a contact_models.ContactElement"])
        return element

    @property
    def element(self) -> Any:
        """The contact element of this run as decided so far (made on first use)."""
        if self._element is None:
            element = self._checked(self.built().element)
            if self.inertia is False and element.frequency_dependent:
                element = QuasiStatic(element)
            self._element = StuckContact(element) if self.stuck else element
        return self._element

    @property
    def label(self) -> str:
        return self.built().label

    @property
    def note(self) -> str:
        return self.built().note


@dataclass
class RunPlan:
    """One computation of a scene: a model at a normal load.

    Parameters
    ----------
    index : int
        Position of the run in the plan, from 0 (the outputs number runs from 1).
    model : str
        The run's label (``"auto"`` resolved, e.g. ``"two-region (auto)"``).
    N : float or None
        Total normal load (N), or None for a model that needs no load.
    element : contact_models.ContactElement
        The contact element the run computes with.
    effects : list of Effect
        Every effect decided for the run: simulated or not, and why.
    omega : tuple of float
        The sweep's range (frequency sweep) or frequencies (amplitude sweep), in rad/s.
    a_ref : float or None, optional
        Amplitude unit of an amplitude sweep (m); None for a frequency sweep.
    a_min : float or None, optional
        The element's linear amplitude at the sweep's lowest frequency (m).
    unit_name : str, optional
        Name of the amplitude unit (default ``"a_min"``).
    harmonics : int or None, optional
        Harmonics H of the balance; None: the single-harmonic balance of a blade (default).
    n_t : int or None, optional
        AFT samples per period of the multi-harmonic balance; None: its default.
    name : str, optional
        The ``damper.model`` name the run was planned from (``MODELS`` key).
    """

    index: int
    model: str  #: the run's label ("auto" resolved: "two-region (auto)")
    N: float | None
    element: Any
    effects: list
    omega: tuple  #: the sweep's range (frequency) or frequencies (amplitude), rad/s
    a_ref: float | None = None  #: amplitude unit of an amplitude sweep (m)
    a_min: float | None = None  #: the damper's linear amplitude at the sweep's lowest frequency (m)
    unit_name: str = "a_min"  #: name of the amplitude unit
    harmonics: int | None = None  #: harmonics of the balance (None: the single-harmonic balance of a blade)
    n_t: int | None = None  #: AFT samples per period (None: the balance's default)
    name: str = ""  #: the damper.model name of the run (a key of MODELS)

    @property
    def label(self) -> str:
        return self.model + (f", N = {self.N:g} N" if self.N is not None else "")


@dataclass
class Plan:
    """The runs of a scene, with its blade (None for an amplitude sweep).

    Parameters
    ----------
    scene : Scene
        The validated scene.
    blade : object
        The ``hbm.Blade`` (or ``hbm.Structure`` of ``[structure]``) of a frequency sweep; None
        for an amplitude sweep.
    runs : list of RunPlan
        One per model and normal load, models in the order of ``damper.model``.
    contacts : list of hbm.Contact, optional
        The structure's own elements (``[[structure.contacts]]``), the same in every run; empty
        for a blade.
    """

    scene: Scene
    blade: Any
    runs: list
    contacts: list = field(default_factory=list)  #: the structure's own contacts (hbm.Contact), every run


def plan_scene(scene: Scene) -> Plan:
    """Decide every effect and build the element of each run.

    Raises :class:`SceneError` for physically impossible scenes (the message names the key).

    Parameters
    ----------
    scene : Scene
        A validated scene (``load_scene``, ``scene_from_dict``).

    Returns
    -------
    Plan
        One run per model of ``damper.model`` and, for a model that needs a load, per load of
        ``damper.load.N``; each with its element built and its effects decided.

    Raises
    ------
    SceneError
        For physically impossible scenes (a blade or structure that cannot be built, an amplitude
        unit the model does not have, a build that does not return a contact element), listing
        every run's problems at once.

    Examples
    --------
    >>> from hbm.scenes import plan_scene, scene_from_dict
    >>> scene = scene_from_dict({"damper": {"model": "macroslip", "stiffness": 1.0e6, "slip_force": 1.0},
    ...                          "sweep": {"kind": "amplitude", "omega": [0.0], "amplitude": [0.1, 10.0]}})
    >>> plan = plan_scene(scene)
    >>> len(plan.runs), plan.runs[0].label, plan.runs[0].a_ref
    (1, 'macroslip', 1e-06)
    """
    problems = []
    blade = _blade(scene)
    d = scene.damper
    bar = _bar(d)
    unit = {"rad/s": 1.0, "Hz": 2.0 * math.pi, "omega_c": bar.omega_c if bar is not None else math.nan}
    omega = tuple(unit[scene.sweep["unit"]] * w for w in scene.sweep["omega"])
    loads = (scene.load.get("N") or (None,)) if scene.load is not None else (None,)
    centrifugal = scene.load is not None and scene.load["kind"] == "centrifugal"
    if centrifugal:  # one run per model, planned at the load of the sweep's middle frequency, then at each omega's
        if scene.optimum is not None:
            problems.append(f"{scene.where('damper.load.kind')} = \"centrifugal\": not allowed with [optimum] "
                            "(its load follows omega; vary a [damper] key with a uniform load)")
        loads = (_centrifugal(scene)(0.5 * (min(omega) + max(omega))),)
    runs = []
    for model in d["model"]:
        for N in (loads if "load" in _needs(scene, model) else (None,)):
            try:
                runs.append(_plan_run(scene, model, len(runs), N, bar, blade, omega))
                if centrifugal and N is not None:
                    runs[-1] = _following(scene, runs[-1], bar, blade, omega)
            except SceneError as exc:
                problems.extend(exc.problems)
                continue
            if isinstance(blade, Blade) and getattr(runs[-1].element, "components", 1) != 1:
                problems.append(f"{scene.where('damper.model')} = {show(model)}: the element acts on a tangential "
                                "and a normal displacement; a [blade] has one DOF: use a [structure] with "
                                "structure.contact_dofs and structure.normal_dofs"
                                + (" (and structure.second_dofs)" if runs[-1].element.components == 3 else ""))
    if scene.modes is not None and scene.modes["mode"] >= getattr(blade, "n", 1):
        n = getattr(blade, "n", 1)
        problems.append(f"{scene.where('modes.mode')} = {scene.modes['mode']}: the system has {n} DOF"
                        f"{'s' if n > 1 else ''}, so {n} modes (0 to {n - 1})")
    if scene.optimum is not None and not problems:
        runs = _at_bounds(scene, blade, runs, problems)
    contacts = []
    if isinstance(blade, Structure) and not problems:
        try:
            contacts = structure_contacts(scene, blade, omega, max((r.harmonics or 1) for r in runs))
            problems += _static_compliance(scene, blade, runs, contacts)
        except SceneError as exc:
            problems.extend(exc.problems)
    if problems:
        raise SceneError(list(dict.fromkeys(problems)))
    return Plan(scene, blade, runs, contacts)


def _centrifugal(scene: Scene) -> CentrifugalLoad:
    """The ``[damper.load]`` of kind "centrifugal" as its load law."""
    ld = scene.load
    return CentrifugalLoad(mass=ld["mass"], radius=ld["radius"], engine_order=ld["engine_order"])


def _following(scene: Scene, run: RunPlan, bar: Any, blade: Any, omega: tuple) -> RunPlan:
    """``run`` (planned at one load) with the element whose load follows the drive frequency: at each
    omega the run planned again at ``N0(omega)`` (the same deciders), ``contact_models.RotatingPreload``."""
    load = _centrifugal(scene)

    def build(N: float) -> ContactElement:
        return _plan_run(scene, run.name, run.index, N, bar, blade, omega).element

    element = RotatingPreload(build, load, omega_ref=0.5 * (min(omega) + max(omega)) or 1.0)
    ld = scene.load
    return replace(run, element=element, N=None,
                   model=f"{run.model}, centrifugal load {ld['mass']:g} kg at {ld['radius']:g} m, EO {ld['engine_order']}")


def _bar(d: dict) -> Any:
    """The bar of the ``[damper]`` keys, or None when they do not make one."""
    if not all(k in d for k in BAR_KEYS):
        return None
    return Bar(E=d["E"], rho=d["rho"], A=d["A"], L=d["L"], k=d["k"], beta=d.get("beta", 0.0), mu=d["mu"])


def _needs(scene: Scene, model: str) -> set:
    spec = MODELS[model]
    return spec.needs({k: v for k, v in scene.damper.items() if k in spec.keys})


def _plan_run(scene: Scene, model: str, index: int, N: Any, bar: Any, blade: Any, omega: tuple) -> RunPlan:
    """One run of ``model`` at the load ``N``: its effects decided and its element built."""
    spec = MODELS[model]
    ctx = RunContext(scene, spec, index, N, bar, blade, omega, {k: scene.damper.get(k) for k in spec.keys})
    return replace(_decide(ctx, "load" in _needs(scene, model)), name=model)


def scene_at(scene: Scene, parameter: str, value: float) -> Scene:
    """A new scene with the number key ``parameter`` (``damper.X`` or ``damper.load.X``) set to
    ``value``; ``scene`` itself is not changed."""
    table, _, key = parameter.rpartition(".")
    if table == "damper.load":
        load = dict(scene.load)
        load[key] = (value,) if key == "N" else value
        if load.get("q0") is not None:
            load["N"] = ((load["q0"] - 2.0 * load["q2"] / 3.0) * scene.damper["L"],)
        return replace(scene, load=load)
    damper = dict(scene.damper)
    damper[key] = value
    load = scene.load
    if key == "L" and load is not None and load.get("q0") is not None:
        load = dict(load, N=((load["q0"] - 2.0 * load["q2"] / 3.0) * value,))
    return replace(scene, damper=damper, load=load)


def plan_at(scene: Scene, blade: Any, run: RunPlan, value: float) -> RunPlan:
    """The run ``run`` of an ``[optimum]`` scene planned again with its parameter
    (``optimum.parameter``) at ``value``: the same deciders on :func:`scene_at`'s scene, the same
    frequencies (``run.omega``).  The optimum's elements along its curve come from here."""
    parameter = scene.optimum["parameter"]
    at = scene_at(scene, parameter, value)
    N = at.load["N"][0] if parameter.startswith("damper.load.") else run.N
    out = _plan_run(at, run.name, run.index, N, _bar(at.damper), blade, run.omega)
    return replace(out, N=None) if parameter == "damper.load.N" else out


def _at_bounds(scene: Scene, blade: Any, runs: list, problems: list) -> list:
    """The runs of an ``[optimum]`` scene planned at both bounds: their effects must agree (one
    plan holds over the bounds); each run is kept as planned at the first bound."""
    out = []
    bounds = scene.optimum["bounds"]
    for run in runs:
        try:
            ends = [plan_at(scene, blade, run, p) for p in bounds]
        except SceneError as exc:
            problems.extend(exc.problems)
            continue
        flags = [[(e.name, e.simulated) for e in r.effects] for r in ends]
        if flags[0] != flags[1]:
            differ = [f"{a[0]}: {'simulated' if a[1] else 'not simulated'} at {bounds[0]:g}, "
                      f"{'simulated' if b[1] else 'not simulated'} at {bounds[1]:g}"
                      for a, b in zip(*flags) if a != b]
            problems.append(f"{scene.where('optimum.bounds')} = {show(list(bounds))}: the effects differ between "
                            f"the bounds ({'; '.join(differ)}): narrow the bounds so that one plan holds over them")
        out.append(ends[0])
    return out


def _static_compliance(scene, structure, runs, contacts):
    """The balance of a structure condenses with K^-1 (every run but a one-DOF single-harmonic
    one): a singular K is refused here, as the run would refuse it, so that ``--check`` says so and
    a run creates no folder for it.  Each run's damper is attached here too (``structure.normal_dofs``
    checked against its element)."""
    attached = [damper_contact(scene, run.element, run.model) for run in runs]
    for run, contact in zip(runs, attached):
        if not solved_as_one_dof(structure, [contact, *contacts], run.harmonics or 1):
            try:
                static_deflection(structure)
            except ValueError as exc:
                return [scene.where(f"structure.stiffness: {exc}")]
            return []
    return []


def _blade(scene):
    if scene.sweep["kind"] == "amplitude":
        return None
    if scene.structure is not None:
        return _structure(scene)
    b = scene.blade
    try:
        stiffness = b["mass"] * b["frequency"] ** 2 if "frequency" in b else b["stiffness"]
        damping = b.get("damping")
        if damping is None:
            damping = 2.0 * b["damping_ratio"] * math.sqrt(stiffness * b["mass"])
        return Blade(mass=b["mass"], stiffness=stiffness, damping=damping, force=b["force"])
    except ValueError as exc:
        raise SceneError([scene.where(f"[blade]: {exc}")]) from None


#: The [structure] key that gives each matrix of ``hbm.Structure`` (its messages name the matrix).
_MATRIX_KEYS = {"M": "structure.mass", "K": "structure.stiffness", "C": "structure.damping",
                "force": "structure.force", "M_next": "structure.next_mass", "K_next": "structure.next_stiffness",
                "C_next": "structure.next_damping", "sectors": "structure.sectors",
                "engine_order": "structure.engine_order", "M, M_next": "structure.next_mass"}


def _structure(scene):
    """The ``hbm.Structure`` of ``[structure]``, its DOF indices checked against its size; a file
    that cannot be read, or a matrix the structure refuses, is named by its key."""
    st = scene.structure
    matrices, problems = {}, []
    for key in ("mass", "stiffness", "damping", "next_mass", "next_stiffness", "next_damping"):
        if st.get(key) is not None:
            try:
                matrices[key] = read_matrix(st[key], f"structure.{key}")
            except ValueError as exc:
                problems.append(scene.where(f"[structure]: {exc}"))
    if problems:
        raise SceneError(problems)
    damping = {"damping": matrices.get("damping"), "modal_damping": st.get("modal_damping"),
               "rayleigh": tuple(st["rayleigh"]) if st.get("rayleigh") is not None else None}
    try:
        s = Structure.from_matrices(matrices["mass"], matrices["stiffness"], force=list(st["force"]),
                                    **{k: v for k, v in damping.items() if v is not None})
        if st.get("sectors") is not None:
            s = _sector(st, s, matrices)
        nonzero_force(s.force)  # (a zero force passes the structure: the balance refuses it, and so does --check)
    except ValueError as exc:
        text = str(exc)
        key = next((k for m, k in _MATRIX_KEYS.items() if text.startswith(f"{m} ")), "[structure]")
        raise SceneError([scene.where(f"{key}: {text}")]) from None
    bad = dof_problems(scene, s.n)
    if bad:
        raise SceneError(bad)
    return s


def _sector(st: dict, s: Structure, matrices: dict) -> CyclicStructure:
    """One sector of the cyclic structure of ``[structure]`` (``structure.sectors``): the sector's M, C, K
    of the plain structure ``s`` built from the same keys, and the couplings to the next sector read
    from ``structure.next_*`` (zero when not given).  With ``structure.rayleigh`` the coupling's damping
    is ``alpha M_next + beta K_next``, the off-diagonal blocks of ``alpha M + beta K`` of the whole disk."""
    n = s.n
    nxt = {}
    for key, name in (("next_mass", "M_next"), ("next_stiffness", "K_next"), ("next_damping", "C_next")):
        A = matrices.get(key)
        nxt[name] = None if A is None else (A.toarray() if hasattr(A, "toarray") else np.asarray(A))
    if st.get("rayleigh") is not None:
        alpha, beta = st["rayleigh"]
        zero = np.zeros((n, n))
        M1 = zero if nxt["M_next"] is None else nxt["M_next"]
        K1 = zero if nxt["K_next"] is None else nxt["K_next"]
        if M1.shape == K1.shape:  # (another shape is refused, naming the matrix, by CyclicStructure)
            nxt["C_next"] = alpha * M1 + beta * K1
    return CyclicStructure(s.M, s.C, s.K, sectors=st["sectors"], engine_order=st["engine_order"],
                           force=list(st["force"]), **nxt)


def _decide(ctx: RunContext, with_load: bool) -> RunPlan:
    """Pass the run through the deciders, apply each decision, then make the plan's element."""
    for effect in EFFECTS:
        try:
            decision = effect.decide(ctx)
        except SceneError:
            raise
        except ValueError as exc:  # a library check on the values it was decided at: said with the scene's keys
            raise SceneError([f"{ctx.where('sweep.omega')} = {show(list(ctx.scene.sweep['omega']))}: deciding the "
                              f"{effect.name} there: {exc}"]) from None
        if decision is not None:
            if not isinstance(decision, Effect):
                raise SceneError([f"effect {effect.name!r}: its decider returned {decision!r}, not an Effect"])
            ctx.effects.append(decision)
            ctx.apply(decision.decided)
    element = ctx.element
    if ctx.spec.microslip is not None and ctx.model is None and not ctx.stuck:
        ctx.check_micro()  # the plan keeps the single-mode element along its path (held stuck it needs none)
    inner = element.element if isinstance(element, StuckContact) else element
    a_ref, unit_name = None, "a_min"
    if ctx.blade is None:
        a_ref, unit_name = _amplitude_unit(ctx)
    return RunPlan(index=ctx.index, model=ctx.label, N=ctx.N if with_load else None, element=element,
                   effects=ctx.effects, omega=ctx.omega, a_ref=a_ref,
                   a_min=linear_amplitude(inner, min(ctx.omega)), unit_name=unit_name,
                   harmonics=ctx.harmonics, n_t=ctx.n_t)


def _amplitude_unit(ctx: RunContext) -> tuple[float, str]:
    """(metres, name) of the amplitude unit of an amplitude sweep."""
    asked = ctx.scene.sweep["amplitude_unit"]
    if asked == "m":
        return 1.0, "m"
    if not float(ctx.element.stuck_stiffness(min(ctx.omega))) > 0.0:
        raise SceneError([f"{ctx.where('sweep.kind')} = \"amplitude\": damper.model = {show(ctx.spec.name)} has "
                          "no stuck stiffness (k* = 0: it is not linear at small amplitudes), so the table's "
                          "F_s = f_s/(k* a) is undefined; use a frequency sweep (a [structure] or [blade])"])
    if ctx.spec.unit is not None:
        value, name = ctx.spec.unit(ctx)
    else:
        value, name = float(ctx.element.reference_amplitude(min(ctx.omega))), "reference amplitude"
    if asked == "a_min" and name != "a_min":
        raise SceneError([f"{ctx.where('sweep.amplitude_unit')} = \"a_min\": damper.model = {show(ctx.spec.name)} "
                          f"has no slip amplitude as its unit (its unit is the {name}); use \"model\" or \"m\""])
    if not (value > 0.0 and math.isfinite(value)):
        raise SceneError([f"{ctx.where('sweep.amplitude_unit')}: the {name} of damper.model = "
                          f"{show(ctx.spec.name)} is {value!r}; use \"m\""])
    return value, name
