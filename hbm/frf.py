"""``frequency_response``: the front of the harmonic balance (validate, pick, run, wrap).

``frequency_response(system, contacts, omega_range=(w0, w1))`` validates its options, builds the
one balance :class:`hbm.balance.HarmonicBalance` of the system (a blade is a one-DOF structure)
with its contacts, picks its scales and the stuck start at ``w0``, traces the branch from ``w0``
to ``w1`` through any folds with pseudo-arclength continuation (``hbm.continuation``) and wraps
it in one result type, :class:`hbm.FrequencyResponse`, whatever the number of DOFs and harmonics;
with ``tol`` it chooses H (and with ``model="auto"`` the model) along the curve (``hbm.adapt``).
The continuation measures arclength with every coefficient scaled by the current first-harmonic
amplitude and omega by the range width, so the number of points depends on the logarithm of the
resonant amplification, not on the amplification.  ``response_at`` solves a blade's balance at
one frequency by Brent's method, for elements without derivatives.
"""

from __future__ import annotations

import dataclasses
import difflib
import inspect
import math
import warnings
from typing import Any, Callable, NamedTuple

import numpy as np

from contact_models.accuracy import AccuracyWarning
from contact_models.numerics.roots import brentq  # scipy's algorithm without importing scipy.optimize

from . import adapt as along  # the module (hbm.adapt); frequency_response's adapt is a flag
from .continuation import Status
from .balance import errors
from ._threads import SMALL_SYSTEM, one_blas_thread
from ._validation import (MIN_RELATIVE_TOL, nonnegative, omega_range_pair, positive, relative_tolerance,
                          within_precision)
from .balance.presets import DEFAULT_RTOL, MAX_RTOL, TOLERANCE, Steps, apply, harmonic_knobs, samples_for
from .balance.residual import HarmonicBalance, as_contacts, as_structure, first_harmonic_only, samples_within_bound
from .blade import Blade
from .result import PEAK_XTOL_FACTOR, FrequencyResponse, Peak, Response

#: The target relative error of a solve that names none (``tol``).
DEFAULT_TOL = 1e-3
#: The named tolerances ``tol`` accepts: each is the number it names, and adapts as that number does.
PRESETS = dict(TOLERANCE)
#: With ``tol`` and no ``harmonics``, a structure's balance starts at this H over the whole range (a
#: blade at its own, 1; a balance with a first-harmonic element, one without a time law, at the only H it
#: takes, 1, where it stays); each window where the harmonics' estimate exceeds ``HARMONICS_SHARE * tol`` is
#: traced again at H -> 2H + 1, up to ``MAX_HARMONICS`` (``hbm.adapt``).
ADAPT_START = 3
HARMONICS_SHARE = 0.5
#: Where every element's force is in closed form (``exact_harmonics`` and not ``discretised``, with a time law:
#: no samples, no nested solve), a point costs about the same at any H while the balance is small, so a first trace at
#: ``ADAPT_START`` would be paid again wherever its windows are traced at a higher H.  The whole range then
#: starts at the H its tolerance predicts (``start_harmonics``): the rung where ``START_ESTIMATE``, the
#: harmonics source at H = 3 near a friction resonance, falls within ``HARMONICS_SHARE * tol`` by the decay
#: of ``hbm.adapt.next_harmonics`` (h^-4: 2e-3 at H = 7, 1e-4 at 15; the Jenkins problems and chains of
#: ``docs/multiharmonic.md`` read 1.5e-4 to 2.2e-3 at 7, 9e-6 to 9e-5 at 15), at most the rung at which
#: the balance has ``START_UNKNOWNS`` unknowns (a dense solve of that size costs about one closed-form
#: evaluation of the elements).  Where the prediction is short, the windows go up the ladder as from 3.
START_ESTIMATE = 0.06
START_UNKNOWNS = 200
#: With ``tol``, the elements' tolerance rtol is this share of it, at most ``DEFAULT_RTOL`` (the peak is
#: accepted within 10 rtol: ``hbm.balance.errors``).
RTOL_SHARE = 1e-2
MAX_HARMONICS = 31
#: Without ``tol`` (``tol=None``: no estimate, nothing chosen), a structure's H where none is given.
FIXED_HARMONICS = 7

#: ``model``, where the solve uses each element's refined model (``ContactElement.refined_model``):
#: "given" nowhere; "peak" in the windows of the curve that hold the peak (``hbm.adapt.peak_window``),
#: where the estimate's model source exceeds ``MODEL_SHARE * tol``; "auto" in every window where it does.
MODELS = ("given", "peak", "auto")
MODEL_SHARE = 0.5
#: With a tolerance, an element that chooses its discretisation at every call and offers a fixed
#: start rung (``ContactElement.start_rung``: ``AllModeMicroslip`` with cells and harmonics None) is
#: traced on that start rung and its windows on finer rungs (``hbm.adapt``, the model knob).
RUNGS_ALONG_CURVE = True

#: Newton tolerance on the scaled residual (``|R|/F`` for a one-DOF system at H = 1, ``|R|/x_ref``
#: otherwise) as a fraction of ``rtol``.
NEWTON_TOL_FACTOR = 5e-3

#: The keywords of earlier releases, each with what replaces it (they warn ``DeprecationWarning``).
DEPRECATED = {
    "rtol": "tol (the elements' tolerance is tol/100, at most 1e-6)",
    "accuracy": "tol (a name: tol='fast', 'default' or 'precise')",
    "estimate_error": "tol=None (no estimate)",
    "max_step": "steps=hbm.Steps(max_step=...)",
    "min_step": "steps=hbm.Steps(min_step=...)",
    "max_steps": "steps=hbm.Steps(max_steps=...)",
    "curve_tol": "steps=hbm.Steps(curve_tol=...)",
    "locate_folds": "steps=hbm.Steps(locate_folds=...)",
    "on_point": "callback=f, called with an hbm.Point",
    "on_harmonics": "callback=f, called with an hbm.Point (its harmonics)",
}


class Point(NamedTuple):
    """One accepted point of a branch, as ``frequency_response``'s ``callback`` receives it.

    Attributes
    ----------
    omega : float
        Frequency (rad/s).
    x_c, x_s : float
        The response DOF's first harmonic (m), ``x ~ x_c cos(omega t) + x_s sin(omega t)``.
    residual : float
        The point's scaled residual.
    harmonics : ndarray
        The response DOF's harmonics (m), ``(X0, Xc1, Xs1, ..., XcH, XsH)``.
    """

    omega: float
    x_c: float
    x_s: float
    residual: float
    harmonics: Any


def start_harmonics(structure: Any, contacts: Any, response_dof: int | None, tol: float) -> int:
    """The H a structure's balance traces the whole range at first with ``tol`` and no ``harmonics``:
    1 where an element has no time law (a first-harmonic element: the balance takes no other H, and the
    driver raises it nowhere, ``hbm.adapt.knobs_of``); else ``ADAPT_START``, or where every element's force
    is in closed form the rung of the ladder 3 -> 7 -> 15 -> 31 that ``START_ESTIMATE`` predicts for ``tol``
    (``START_ESTIMATE`` above), at most ``START_UNKNOWNS`` unknowns of the balance.

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> from contact_models import Macroslip
    >>> from hbm import Contact, Structure
    >>> s = Structure(np.eye(1), [[0.004]], np.eye(1), force=[0.01])
    >>> [start_harmonics(s, [Contact(Macroslip(1.0, 0.02), dof=0)], None, t) for t in (0.2, 1e-2, 1e-3, 1e-5)]
    [3, 7, 15, 31]
    >>> start_harmonics(s, [Contact(Macroslip(math.inf, 0.005), dof=0)], None, 1e-3)  # the rigid slider
    1
    """
    attached = as_contacts(contacts, structure.n)
    if not all(c.element.has_time_law for c in attached):
        return 1
    closed = [c.element.exact_harmonics and not c.element.discretised for c in attached]
    if not attached or not all(closed):
        return ADAPT_START
    if START_ESTIMATE <= HARMONICS_SHARE * tol:
        return ADAPT_START
    H = along.next_harmonics(ADAPT_START, START_ESTIMATE / (HARMONICS_SHARE * tol), MAX_HARMONICS)
    dofs = balance_dofs(attached, response_dof)
    while H > ADAPT_START and dofs * (2 * H + 1) > START_UNKNOWNS:
        H = (H - 1) // 2
    return H


def may_climb(contacts: list, refined: bool) -> bool:
    """Whether a window of the curve can be traced at a higher H with ``contacts`` (``as_contacts``'s list): where
    every element has a time law, or where the model is refined along the curve (``refined``) every element
    without one has a refined model with one (``ContactElement.refined_model``: the single-mode bar's all-mode
    bar).  False with an element that keeps H = 1 everywhere (the rigid slider): the harmonics then have no knob.

    Examples
    --------
    >>> import math
    >>> from contact_models import Macroslip
    >>> from hbm import Contact
    >>> elastic, rigid = Contact(Macroslip(1.0, 0.02), dof=0), Contact(Macroslip(math.inf, 0.02), dof=0)
    >>> may_climb([elastic], False), may_climb([rigid], True)
    (True, False)
    """
    for c in contacts:
        if not c.element.has_time_law:
            better = c.element.refined_model() if refined else None
            if better is None or not better.has_time_law:
                return False
    return True


def balance_dofs(contacts: list, response_dof: int | None) -> int:
    """The DOFs a balance of ``contacts`` (``as_contacts``'s list) solves: every contact DOF and the response's
    (None counts as one more: the response DOF the balance picks)."""
    return len({d for c in contacts for d in c.all_dofs} | {response_dof})


def frequency_response(system: Any, contacts: Any = None, omega_range: tuple[float, float] | None = None, *,
                       tol: float | str | None = "default", harmonics: int | None = None, n_t: int | None = None,
                       model: str = "given", steps: Steps | None = None, callback: Callable[[Point], None] | None = None,
                       response_dof: int | None = None, stability: bool = True,
                       **deprecated: Any) -> FrequencyResponse:
    """FRF of ``system`` (a :class:`Blade` or a :class:`Structure`) with its ``contacts`` over
    ``omega_range = (w0, w1)`` rad/s, traced from ``w0`` to ``w1`` through any folds, to ``tol``.

    One balance for every system (``hbm.balance``): a blade is a one-DOF structure, a contact
    element given alone attaches to its DOF.  ``tol`` sets every accuracy knob the call does not
    fix itself: the harmonics H along the curve, the elements' tolerance (tol/100, at most 1e-6) and
    the Newton tolerance of every point (``NEWTON_TOL_FACTOR`` times that), and with ``model`` the
    model; every point carries its estimated error by source, and where the estimate exceeds
    ``tol``, where the branch stops before the end of the range, or where the peak is not an
    interior, converged maximum, one ``AccuracyWarning`` says so.

    Parameters
    ----------
    system : Blade or Structure
        The linear system: a blade (mass, stiffness, damping, force) or a structure (M, C, K, force).
    contacts : ContactElement, Contact, sequence of Contact, or None, optional
        The contacts: ``hbm.Contact(element, dof=i)`` or ``dofs=(i, j)``; a bare element (any
        ``contact_models`` element) on a one-DOF system is the damper at its DOF; None for none.
    omega_range : tuple of float
        ``(w0, w1)`` in rad/s, >= 0 and different; traced from w0 to w1 (either way).
    tol : float, {"fast", "default", "precise"} or None, optional
        The target relative error of the response amplitude against the true periodic response of
        the physical system (all harmonics, the physical contact), in [1e-10, 1) (``MIN_RELATIVE_TOL``,
        the bound of the command line and the scenes); a name stands for its
        number (``PRESETS``: "fast" 1e-2, "default" 1e-3, "precise" 1e-5) and adapts exactly as that
        number does.  Default "default" (``DEFAULT_TOL`` = 1e-3).  Without ``harmonics``, a
        structure's H is chosen along the curve (``hbm.adapt``): the whole range at 3 (a blade at
        1), then each window where the harmonics' estimate exceeds half of it traced again at
        2H + 1 (7, 15, 31), where every contact has a time law; with a contact that has none (a
        first-harmonic element, e.g. the rigid slider ``Macroslip(math.inf, ...)``) H is 1
        everywhere, and the warning says so where the harmonics' estimate exceeds ``tol`` or
        cannot be made.  None: no estimate and nothing
        chosen (H as given, else 1 for a blade and ``FIXED_HARMONICS`` for a structure).
    harmonics : int, optional
        The number of harmonics H, fixed.  Above 1 every contact needs a time law.
    n_t : int, optional
        AFT samples per period, >= 2H + 2.  Default ``hbm.balance.presets.samples_for(H)``.
    model : {"given", "peak", "auto"}, optional
        Where the solve uses each element's refined model (``ContactElement.refined_model``: the
        all-mode bar for a single-mode microslip bar): "given" (default) nowhere; "auto" in every
        window of the curve where the model source exceeds half the tolerance; "peak" in those of
        the windows that hold the peak (``hbm.adapt.peak_window``), each refined as "auto" refines
        it, and ``peak()`` is the refined model's maximum.  ``point_models`` names the model of
        every point.
    steps : Steps, optional
        The continuation's step controls (:class:`hbm.Steps`).  Default ``Steps()``.
    callback : callable, optional
        ``callback(point)`` with each accepted point (a :class:`hbm.Point`), in continuation order:
        as it is accepted, or where the balance may solve a window again (``tol`` without
        ``harmonics``, ``model="auto"``) once the run ends, the final points in order (their
        harmonics zero-padded to the largest H).  An exception it raises ends the run at that point
        (``success`` False, ``status`` ``hbm.Status.CALLBACK_RAISED``, the exception in
        ``message`` and the warning); the points computed are kept.
    response_dof : int, optional
        The DOF whose response is reported.  Default the forced DOF.
    stability : bool, optional
        Whether Hill's stability is available (computed on first use of ``stable``).  Default True.
    **deprecated
        The keywords of earlier releases (``DEPRECATED``: ``rtol``, ``accuracy``, ``estimate_error``,
        ``max_step``, ``min_step``, ``max_steps``, ``curve_tol``, ``locate_folds``, ``on_point``,
        ``on_harmonics``), still read for one release, each with a ``DeprecationWarning`` naming
        what replaces it.

    Returns
    -------
    FrequencyResponse
        The branch, with ``success`` and ``message``; a run that stops early keeps the points it
        computed.  A window whose refined trace fails keeps its coarse points; ``message`` and the
        warning say so.  An element that raises in the error estimate after the curve keeps it too: the
        estimate reads inf (unknown) there, ``message`` and the warning name the element, hook and omega.
        The peak is located (``peak()``).

    Raises
    ------
    ValueError
        If ``system`` is neither a Blade nor a Structure, a contact is not a contact element or
        ``hbm.Contact``, ``omega_range`` is missing or invalid, or an option is out of range; the
        message names it and its value.

    See Also
    --------
    response_at : a blade's balance at one frequency.
    simulate_blade : the blade and the discretised bar integrated in time, the independent check.

    Notes
    -----
    Single harmonic, one DOF: with ``x = x_c cos(omega t) + x_s sin(omega t)``,
    ``a = sqrt(x_c^2 + x_s^2)`` and the element's ``p = f_s/a``, ``q = f_c/a``,

    .. math::

        (k - m\\omega^2 + p + i(c\\omega + q))\\,(x_c - i x_s) = F,

    two real equations in ``y = (x_c, x_s, omega)``.  Any structure and H: the balance condensed
    to the contact DOFs, ``X - X_lin + G F(X) = 0`` (``hbm.balance.residual``).  ``docs/hbm.md``
    and ``docs/multiharmonic.md`` derive the Jacobians and the step control.

    Examples
    --------
    The bare blade against its closed form ``F/(c omega)`` at resonance:

    >>> from hbm import Blade, frequency_response
    >>> blade = Blade(mass=1.0, stiffness=1.0e4, damping=2.0, force=1.0)
    >>> frf = frequency_response(blade, omega_range=(90.0, 110.0))
    >>> pk = frf.peak()
    >>> import math
    >>> abs(pk.omega / math.sqrt(1.0e4 - 2.0) - 1.0) < 1e-7          # sqrt(k/m - c^2/(2 m^2))
    True
    >>> round(pk.amplitude / (1.0 / (2.0 * math.sqrt(1.0e4 - 1.0))), 6)  # F/(c sqrt(k/m - c^2/(4 m^2)))
    1.0
    >>> pk.interior, pk.converged
    (True, True)

    With the two-region microslip damper (the single-mode bar of ``python3 -m hbm``):

    >>> from contact_models import Bar, UniformLoad, TwoRegionMicroslip
    >>> bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    >>> two = TwoRegionMicroslip(bar, UniformLoad(N=100.0))
    >>> blade = Blade(mass=0.0877147, stiffness=1.0e8, damping=11.8467, force=8.0)
    >>> frf = frequency_response(blade, two, omega_range=(3.2e4, 4.4e4), tol=None)
    >>> frf.success, round(frf.peak().amplitude, 9)    # m
    (True, 1.512e-06)

    A structure with a Jenkins element at three harmonics:

    >>> import numpy as np
    >>> from contact_models import Macroslip
    >>> from hbm import Contact, Structure
    >>> s = Structure(np.eye(1), [[0.004]], np.eye(1), force=[0.01])
    >>> frf = frequency_response(s, [Contact(Macroslip(1.0, 0.02), dof=0)], omega_range=(0.6, 1.8), harmonics=3)
    >>> frf.success, frf.harmonics, frf.coefficients(0).shape[1]
    (True, 3, 4)
    """
    # ---- validate (the keywords of earlier releases first: they may set tol and the steps)
    explicit = tol != "default"  # a tol the caller gave (an earlier release's rtol keeps its value otherwise)
    tol, steps, callback, rtol, fixed = _deprecated(deprecated, tol, steps, callback)
    structure = as_structure(system)
    if structure.sector_angle is not None:  # what hbm.CyclicStructure.full() repeats on every sector by default
        structure.solved_contacts = as_contacts(contacts, structure.n)
    w0, w1 = omega_range_pair(omega_range)
    tolerance = tolerance_of(tol)
    _within_precision(structure, omega_range, max(w0, w1), harmonics, tolerance)
    if not isinstance(model, str) or model not in MODELS:  # (an array: numpy's ambiguous truth)
        raise ValueError(f"model must be one of {', '.join(map(repr, MODELS))}, got model={model!r}")
    if model != "given" and tolerance is None:
        raise ValueError(f"model={model!r} chooses the model by the error estimate: it needs a tol, got tol=None")
    if rtol is None:  # the elements' tolerance follows tol
        rtol = DEFAULT_RTOL if tolerance is None else min(DEFAULT_RTOL, RTOL_SHARE * tolerance)
    elif tolerance is not None and explicit:  # an earlier release's rtol, tightened by an explicit tol
        rtol = min(positive("rtol", rtol), RTOL_SHARE * tolerance)
    rtol = positive("rtol", rtol)
    if rtol >= 0.1:
        raise ValueError(f"rtol must be < 0.1, got rtol={rtol!r}")
    if steps is None:
        steps = Steps()
    if not isinstance(steps, Steps):
        raise ValueError(f"steps must be an hbm.Steps, got steps={steps!r}")
    step_controls = steps.checked()
    if callback is not None and not callable(callback):
        raise ValueError(f"callback must be callable, got callback={callback!r}")
    if not isinstance(stability, (bool, np.bool_)):
        raise ValueError(f"stability must be True or False, got stability={stability!r}")
    if response_dof is not None:  # checked here, before it is counted among the balance's DOFs (a list: unhashable)
        structure.response_dof(response_dof)
    # ---- pick: H and n_t (an explicit knob overrides only itself), the balance
    first_harmonic_only(as_contacts(contacts, structure.n), harmonics, tol_remedy=True)  # H > 1 without a time law
    adapt = harmonics is None and tolerance is not None
    if harmonics is None:
        harmonics = structure.default_harmonics if structure.default_harmonics is not None else (
            start_harmonics(structure, contacts, response_dof, tolerance) if adapt else fixed[0])
        if n_t is None and not adapt and structure.default_harmonics is None:
            n_t = fixed[1]
    n_t_given = samples_within_bound(n_t)
    rungs = False
    if tolerance is not None and RUNGS_ALONG_CURVE:
        contacts, rungs = _start_rungs(contacts, structure, (w0, w1))
    # H is raised along the curve where every element has a time law: a first-harmonic element keeps H = 1 (the only
    # H the balance takes with it) unless the model knob may put a refined model with one in its place
    climbs = adapt and may_climb(as_contacts(contacts, structure.n), model != "given" or rungs)
    again = climbs or model != "given" or rungs  # the balance may solve again: stream the final points at the end
    at_peak = model == "peak" and not rungs  # (an element already the complete model: its rungs everywhere)
    setup = along.Setup(system, w0, w1, rtol, NEWTON_TOL_FACTOR * rtol, step_controls, stability, tolerance,
                        lambda H: n_t_given if n_t_given is not None else _samples(H), response_dof)
    live = None if again or callback is None else (lambda problem: _reporter(callback, problem))
    notes: list[str] = []
    # the largest dense system of the call: the structure's, or the balance's at the most harmonics
    # it may use, 2H + 1 for the harmonics' estimate (SMALL_SYSTEM: on one BLAS thread up to that)
    h_most = MAX_HARMONICS if climbs else harmonics
    small = isinstance(h_most, (int, np.integer)) and not isinstance(h_most, bool)  # else the balance refuses it
    if small:
        if tolerance is not None:
            h_most = 2 * h_most + 1
        n_contact = balance_dofs(as_contacts(contacts, structure.n), response_dof)
        small = max(structure.n, n_contact * (2 * h_most + 1) + 1) <= SMALL_SYSTEM
    # one block: every other warning is said once, as Python says it
    with one_blas_thread(small), errors.collected() as said:
        frf = along.solve(setup, contacts, harmonics, live)
        if again:  # the model and H chosen along the curve (hbm.adapt)
            plan = along.Plan(MODEL_SHARE if model != "given" or rungs else None, HARMONICS_SHARE if climbs else None,
                              MAX_HARMONICS, rungs_only=model == "given" or (model == "peak" and rungs), at_peak=at_peak,
                              chosen=rungs)
            frf, notes = along.along(setup, frf, plan)
            if callback is not None:
                _stream(frf, callback)
        if len(frf):  # the peak located between points (the elements' warnings while locating join the call's)
            refined = None
            if at_peak and frf._segments_of is not None:  # the refined model's peak, in the peak's window
                refined = frf.point_models != frf._work[0].point_models[0]
            along.locate_peak(frf, (w0, w1), refined)
    heard = [m for f in dict.fromkeys(p[0] for p in (frf._segments_of or [(frf,)])) for m in f._heard]
    heard += said  # the elements' warnings outside a trace (while locating and refining the peak)
    frf.accuracy_warning = _warn_once(frf, tolerance, heard, notes, (w0, w1))
    return frf


def _within_precision(structure: Any, omega_range: Any, w_top: float, harmonics: Any, tolerance: Any) -> None:
    """Refuse, naming ``omega_range``, a range whose top frequency at the highest harmonic the call may take (the
    given ``harmonics``; with a ``tol`` ``MAX_HARMONICS``; else the structure's own or ``FIXED_HARMONICS``) makes the
    structure's inertia or damping leave double precision (``hbm._validation.within_precision``): checked once
    here, not met as a non-finite residual."""
    if isinstance(harmonics, (int, np.integer)) and not isinstance(harmonics, bool) and harmonics >= 1:
        H = int(harmonics)
    else:  # (a harmonics that is no count is refused further on)
        H = MAX_HARMONICS if tolerance is not None else structure.default_harmonics or FIXED_HARMONICS
    within_precision("omega_range", omega_range, w_top, H, structure.M, structure.C)


def tolerance_of(tol: Any) -> float | None:
    """The target relative error ``tol`` stands for: a number in (0, 1), a name of ``PRESETS``, or None.

    Examples
    --------
    >>> tolerance_of("precise"), tolerance_of(1e-4), tolerance_of(None)
    (1e-05, 0.0001, None)
    """
    if tol is None:
        return None
    if isinstance(tol, str):
        if tol not in PRESETS:
            raise ValueError(f"tol must be a number in (0, 1) or one of {', '.join(map(repr, PRESETS))}, "
                             f"got tol={tol!r}")
        return PRESETS[tol]
    if isinstance(tol, (bytes, bool)):
        raise ValueError(f"tol must be a number in (0, 1), got tol={tol!r}")
    tol = positive("tol", tol)
    if tol >= 1.0:
        raise ValueError(f"tol must be < 1 (a relative error), got tol={tol!r}")
    if tol < MIN_RELATIVE_TOL:  # the command line's and the scenes' bound: no point would converge
        raise ValueError(f"tol must be >= {MIN_RELATIVE_TOL:g} (below it double precision cannot meet the Newton "
                         f"tolerance the balance derives from it), got tol={tol!r}")
    return tol


def _deprecated(given: dict, tol: Any, steps: Any, callback: Any) -> tuple[Any, Any, Any, float | None, tuple]:
    """``(tol, steps, callback, rtol, fixed)`` with the keywords of earlier releases read into them, each
    with a ``DeprecationWarning`` naming what replaces it (``DEPRECATED``); ``fixed``: a structure's H and
    n_t where nothing is chosen (``FIXED_HARMONICS``, or an earlier release's preset's).  An unknown
    keyword raises ``TypeError`` as Python would, naming the keyword it is closest to."""
    unknown = [k for k in given if k not in DEPRECATED]
    if unknown:
        names = [*inspect.signature(frequency_response).parameters, *DEPRECATED]
        near = difflib.get_close_matches(unknown[0], [n for n in names if n != "deprecated"], n=1)
        raise TypeError(f"frequency_response() got an unexpected keyword argument {unknown[0]!r}"
                        + (f" (did you mean {near[0]}?)" if near else ""))
    for k in given:
        warnings.warn(f"frequency_response({k}=...) is deprecated: use {DEPRECATED[k]}", DeprecationWarning,
                      stacklevel=3)
    rtol = given.get("rtol")
    fields = {k: given[k] for k in ("max_step", "min_step", "max_steps", "curve_tol", "locate_folds") if k in given}
    accuracy = given.get("accuracy")
    fixed: tuple = (FIXED_HARMONICS, None)
    if accuracy is not None:  # an earlier release's preset: its rtol, steps, H and n_t as they were, its tolerance
        base = Steps()
        knobs = apply(accuracy, rtol=DEFAULT_RTOL if rtol is None else rtol,
                      **{k: fields.get(k, getattr(base, k)) for k in ("max_step", "min_step", "max_steps", "curve_tol")})
        rtol = knobs[0]
        fields.update(zip(("max_step", "min_step", "max_steps", "curve_tol"), knobs[1:]))
        if isinstance(accuracy, str) and tol == "default":  # a tol given beside it wins, as it did
            tol = accuracy
        fixed = harmonic_knobs(accuracy)
    if given.get("estimate_error") is False:
        tol = None
    if fields:
        steps = dataclasses.replace(steps if isinstance(steps, Steps) else Steps(), **fields)
    on_point, on_harmonics = given.get("on_point"), given.get("on_harmonics")
    if on_point is not None or on_harmonics is not None:
        for name, f in (("on_point", on_point), ("on_harmonics", on_harmonics)):
            if f is not None and not callable(f):
                raise ValueError(f"{name} must be callable, got {name}={f!r}")
        first = callback

        def callback(p: Point) -> None:
            if first is not None:
                first(p)
            if on_point is not None:
                on_point(p.omega, p.x_c, p.x_s, p.residual)
            if on_harmonics is not None:
                on_harmonics(p.omega, p.harmonics)
    return tol, steps, callback, rtol, fixed


def _start_rungs(contacts: Any, structure: Any, omega_range: tuple[float, float]) -> tuple[Any, bool]:
    """``(contacts, replaced)``: each element that has a start rung for ``omega_range``
    (``ContactElement.start_rung``: a choosing ``AllModeMicroslip``) replaced by it; the contacts as
    given where none has."""
    listed = as_contacts(contacts, structure.n)
    out = []
    for c in listed:
        rung = c.element.start_rung(omega_range)
        out.append(c if rung is None else c.with_element(rung))
    replaced = any(a is not b for a, b in zip(out, listed))
    return (out if replaced else contacts), replaced


def _samples(H: Any) -> Any:
    """``samples_for(H)`` for a valid H; an invalid H goes on to the balance's own check."""
    if isinstance(H, (int, np.integer)) and not isinstance(H, bool) and H >= 1:
        return samples_for(int(H))
    return None


#: What brings each source of error down (the warning's advice).
REMEDY = {
    "harmonics": "more harmonics (leave harmonics= out to let the balance choose them to tol, or raise harmonics=)",
    "first-harmonic": ("an element with a time-domain force law in its place ({names} is a first-harmonic element: "
                       "{elements} has no time-domain force law, so the balance cannot raise H above 1 with it, and "
                       "harmonics=1 is its describing-function answer{refined})"),
    "sampling": "more AFT samples (raise n_t=)",
    "element": "a smaller tol= (the elements are evaluated to tol/100, at most 1e-6)",
    "model": "model='auto' (each element's refined model where the estimate asks for it: for a single-mode "
             "microslip bar, the bar with every mode, contact_models.AllModeMicroslip)",
    "peak": "a smaller tol=",
}
#: The model source's advice where every element already is the complete model (no refined model).
REFINED_REMEDY = ("a finer discretisation of the element (AllModeMicroslip: cells and harmonics left to be chosen, "
                  "or a smaller tol=)")
#: The model source's advice where the point's all-mode bar is on its finest rung along a curve.
TOP_RUNG_REMEDY = ("the element alone at that point (AllModeMicroslip with tol=, cells up to 640): along the curve "
                   "the all-mode bar is on the last rung it is refined to there ({rung}), where its estimate can be "
                   "pessimistic if a harmonic of the drive meets a mode of the bar")


def _remedy(frf: FrequencyResponse, source: str, i: int) -> str:
    """What brings ``source`` down at point ``i``; for the model source, the refined model only where
    one exists, and the element alone where a curve refines the point's all-mode rung no further; for the
    harmonics source, a time law where an element has none (the balance cannot raise H with it)."""
    if source == "harmonics":
        site, _ = frf._site(i)
        first = [c.element for c in site.contacts if not c.element.has_time_law]
        if first:  # no H above 1 for such an element: more harmonics is no advice
            refined = [(type(e).__name__, type(m).__name__) for e in first for m in [e.refined_model()]
                       if m is not None and m.has_time_law]  # the element's refined model, where it has a time law
            return REMEDY["first-harmonic"].format(
                names=", ".join(dict.fromkeys(type(e).__name__ for e in first)),
                elements=", ".join(dict.fromkeys(repr(e) for e in first)),
                refined="".join(dict.fromkeys(f"; {name}'s refined model, contact_models.{m}, has one"
                                              for name, m in refined)))
        return REMEDY[source]
    if source != "model":
        return REMEDY[source]
    site, _ = frf._site(i)
    top = [c.element for c in site.contacts if c.element.refined_no_further]
    if top:
        return TOP_RUNG_REMEDY.format(rung=top[0].model_name)
    if all(c.element.discretised or c.element.refined_model() is None for c in frf.contacts):
        return REFINED_REMEDY
    return REMEDY[source]


def _warn_once(frf: FrequencyResponse, tolerance: float | None, heard: list[str], notes: list[str],
               omega_range: tuple[float, float]) -> str | None:
    """One ``AccuracyWarning`` per call, saying what the caller must know before using the answer: a
    branch that stopped before the end of ``omega_range`` (where and why); a peak that is not an
    interior, converged maximum (``Peak.message``); the worst point whose estimate exceeds the
    tolerance, its largest source and what would fix it; the elements' own warnings during the
    solve (their count and the worst); windows whose refined trace failed.  Returns its message
    (None: no warning)."""
    parts = []
    if len(frf) == 0:
        parts.append(f"no point was computed: {frf.message}")
    elif not frf._work[0]._run.success:
        w0, w1 = omega_range
        parts.append(f"the branch stopped at omega = {float(frf.omega[-1]):.6g} rad/s, before the end of omega_range "
                     f"({w0:.6g}, {w1:.6g}) ({frf._work[0]._run.message}); the points before are kept")
    elif not frf.success:  # the whole curve traced, the callback failed while it was streamed
        parts.append(frf.message)
    pk = frf._peak
    why = [] if pk is None else [r for r in pk.message.split("; ") if r and "estimated error" not in r]
    if why:  # (an estimate above tol at the peak is said with the curve's below)
        parts.append(f"the peak at omega = {pk.omega:.6g} rad/s, amplitude {pk.amplitude:.4g} m is not a converged "
                     f"interior maximum: {'; '.join(why)}")
    failed = list(dict.fromkeys(f._estimate_failed for f in frf._work if f._estimate_failed))
    if failed and len(frf):  # an element raised in the estimate: it is unknown there, the points kept
        w = frf.omega[np.isinf(frf.error_estimate)]
        parts.append(f"the error estimate raised an exception ({'; '.join(failed)}): it is unknown (inf) at "
                     f"{len(w)} of {len(frf)} points" + (f" (omega = {float(np.min(w)):.6g} to "
                                                         f"{float(np.max(w)):.6g} rad/s)" if len(w) else "")
                     + "; the points are kept")
    elif tolerance is not None and len(frf) and np.any(frf.error_estimate > tolerance):
        i = int(np.nanargmax(frf.error_estimate))
        source = max(frf.error_sources, key=lambda s: frf.error_sources[s][i])
        unknown = np.isinf(frf.error_sources[source])
        if unknown[i]:  # no bound: say where, not "estimated error inf"
            w = frf.omega[unknown]
            parts.append(f"the {source} source of the error cannot be estimated at {int(np.sum(unknown))} of "
                         f"{len(frf)} points (omega = {float(np.min(w)):.6g} to {float(np.max(w)):.6g} rad/s, H = "
                         f"{frf.point_harmonics[i]}): its estimate is inf there, no bound could be computed; for an "
                         f"estimate and a closer answer use {_remedy(frf, source, i)}")
        else:
            parts.append(f"estimated error {frf.error_estimate[i]:.2g} > tol {tolerance:g} at omega = "
                         f"{frf.omega[i]:.6g} rad/s, amplitude {frf.amplitude[i]:.4g} m (largest source: {source}, "
                         f"{frf.error_sources[source][i]:.2g}; H = {frf.point_harmonics[i]}); for a closer answer use "
                         f"{_remedy(frf, source, i)}")
    elif heard and tolerance is not None and len(frf):
        parts.append(f"the response's estimated error (at most {float(np.nanmax(frf.error_estimate)):.2g}, "
                     f"tol {tolerance:g}) carries the elements' own estimates through the balance")
    if heard:
        parts.append(errors.heard_line(heard, "during the solve"))
    parts += list(notes)  # windows whose refined trace failed: numerical trouble, said
    if not parts:
        return None
    message = "frequency_response: " + "; ".join(parts)
    warnings.warn(message, AccuracyWarning, stacklevel=3)
    return message


def response_at(blade: Blade, element: ContactElement, omega: float,
                amplitude_bracket: tuple[float, float], *, rtol: float = 1e-8) -> Response:
    """The single-harmonic balance at one frequency ``omega``, for one amplitude in
    ``amplitude_bracket = (a_lo, a_hi)`` (m).

    The balance's modulus gives one equation in the amplitude a,
    ``|(k - m omega^2 + i c omega) a + f_s(a) + i f_c(a)| = F``, solved by Brent's method in the
    bracket (it must change sign there: near a fold there are several solutions, and the bracket
    picks one); its argument gives the phase.  ``rtol`` is passed to the element and is the
    relative tolerance on a.  For any contact element, including ``NumericalMicroslip``, whose
    f_s, f_c carry no derivatives: the check of a time integration at a few frequencies
    (``docs/validation.md``), where a continuation would cost too much.

    Parameters
    ----------
    blade : Blade
        The blade.
    element : ContactElement
        The damper.
    omega : float
        Frequency (rad/s), >= 0.
    amplitude_bracket : tuple of float
        ``(a_lo, a_hi)`` (m), 0 < a_lo < a_hi, bracketing one solution.
    rtol : float, optional
        Relative tolerance on the amplitude, passed to the element too, in (0, 0.1).  Default 1e-8.

    Returns
    -------
    Response
        ``(omega, x_c, x_s, amplitude, phase)`` in rad/s, m, m, m, rad.

    Raises
    ------
    ValueError
        If an argument is invalid, or the bracket does not change sign (no solution, or an
        even number of them, in it); the message gives the values at its ends.

    See Also
    --------
    frequency_response

    Examples
    --------
    >>> from hbm import response_at
    >>> from hbm.cli.cases import default_case
    >>> case = default_case()                          # the blade and damper of python3 -m hbm
    >>> r = response_at(case.blade, case.element, 38000.0, (1.0e-7, 1.0e-5))
    >>> round(r.amplitude, 10), round(r.phase, 3)      # m, rad
    (7.371e-07, 0.041)
    """
    if not isinstance(blade, Blade):
        raise ValueError(f"blade must be an hbm.Blade, got blade={blade!r}")
    if element is None or not callable(getattr(element, "fourier", None)):
        raise ValueError(f"element must be a contact element (with fourier(a, omega)), got element={element!r}")
    omega = nonnegative("omega", omega)
    within_precision("omega", omega, omega, 1, np.array([[blade.mass]]), np.array([[blade.damping]]))
    rtol = relative_tolerance("rtol", rtol, MAX_RTOL)
    try:
        lo, hi = (positive("amplitude_bracket", v) for v in amplitude_bracket)
    except (TypeError, ValueError):
        raise ValueError(f"amplitude_bracket must be a pair 0 < a_lo < a_hi, got "
                         f"amplitude_bracket={amplitude_bracket!r}") from None
    if not lo < hi:
        raise ValueError(f"amplitude_bracket must have a_lo < a_hi, got amplitude_bracket={amplitude_bracket!r}")
    lin = complex(blade.stiffness - blade.mass * omega * omega, blade.damping * omega)

    def force(a):
        fs, fc = element.fourier(a, omega, rtol=rtol)
        return lin * a + complex(float(fs), float(fc))

    g_lo, g_hi = abs(force(lo)) - blade.force, abs(force(hi)) - blade.force
    if g_lo * g_hi > 0.0:
        raise ValueError(f"amplitude_bracket={amplitude_bracket!r} does not bracket a solution at omega={omega!r}: "
                         f"|balance force| - F is {g_lo:.4g} N and {g_hi:.4g} N at its ends")
    a = brentq(lambda a: abs(force(a)) - blade.force, lo, hi, xtol=1e-300,
               rtol=max(rtol, 4.0 * np.finfo(float).eps))  # brentq's floor
    z = blade.force * a / force(a)  # x_c - i x_s = F / (k - m w^2 + p + i (c w + q))
    return Response(omega=omega, x_c=z.real, x_s=-z.imag, amplitude=math.hypot(z.real, z.imag),
                    phase=math.atan2(-z.imag, z.real))


def _stream(frf: FrequencyResponse, callback: Callable[[Point], None]) -> None:
    """The final points to ``callback``, in order (their harmonics padded with zeros to the result's
    largest H).  An exception the callback raises ends the stream and the result's success
    (``Status.CALLBACK_RAISED``, the message says at which point and what it raised): every point stays."""
    report = _reporter(callback, frf._problem) if frf._segments_of is None else None
    for i, w in enumerate(frf.omega):
        try:
            if report is not None:
                report(frf._run.y[i], frf.residual_norm[i])
            else:
                callback(Point(float(w), float(frf.x_c[i]), float(frf.x_s[i]), float(frf.residual_norm[i]),
                               frf._X[i, frf._r].copy()))
        except Exception as exc:  # noqa: BLE001 - the caller's code: any Exception is said, nothing computed is lost
            frf.status = Status.CALLBACK_RAISED
            frf.message = (f"the callback raised an exception ({type(exc).__name__}: {exc}) at omega = {float(w):.9g} "
                           f"rad/s, point {i + 1} of {len(frf)} of the final curve as it was streamed to it, which "
                           f"ends the stream; every point was computed and is kept (the trace: {frf.message})")
            return


def _reporter(callback: Callable[[Point], None], problem: HarmonicBalance) -> Callable:
    """``callback(Point)`` for the continuation's ``on_point(u, rnorm)`` in scaled unknowns."""
    c, s = problem.response_components()
    x_ref, w_ref = problem.x_ref, problem.omega_ref
    r = problem.dofs.index(problem.response_dof)

    def report(u, rnorm):
        X, w = problem.to_physical(u)
        callback(Point(float(u[-1] * w_ref), float(u[c] * x_ref), float(u[s] * x_ref), float(rnorm), X[r].copy()))

    return report


__all__ = ["frequency_response", "response_at", "tolerance_of", "FrequencyResponse", "Peak", "Point",
           "Response", "Steps", "NEWTON_TOL_FACTOR", "PEAK_XTOL_FACTOR", "DEFAULT_RTOL", "DEFAULT_TOL", "MODELS", "PRESETS"]
