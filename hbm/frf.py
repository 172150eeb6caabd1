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

import math
import warnings
from typing import Any, Callable

import numpy as np

from contact_models.accuracy import AccuracyWarning
from contact_models.numerics.roots import brentq  # scipy's algorithm without importing scipy.optimize

from . import adapt as along  # the module (hbm.adapt); frequency_response's adapt is a flag
from .balance import errors
from ._validation import count, nonnegative, omega_range_pair, positive
from .balance.presets import (DEFAULT_MAX_STEP, DEFAULT_MAX_STEPS, DEFAULT_MIN_STEP, DEFAULT_RTOL, TOLERANCE, apply,
                              harmonic_knobs, samples_for)
from .balance.residual import HarmonicBalance, as_contacts, as_structure
from .blade import Blade
from .result import PEAK_XTOL_FACTOR, FrequencyResponse, Peak, Response

#: The target relative error of a solve that names none (``tol``): the warning's threshold.
DEFAULT_TOL = 1e-3
#: With ``tol`` given and no ``harmonics``, a structure's balance starts at this H over the whole
#: range; each window where the harmonics' estimate exceeds ``HARMONICS_SHARE * tol`` is traced again
#: at H -> 2H + 1, up to ``MAX_HARMONICS`` (``hbm.adapt``).
ADAPT_START = 3
HARMONICS_SHARE = 0.5
#: With ``tol`` given, the elements' tolerance rtol is at most this share of it (the peak is
#: accepted within 10 rtol: ``hbm.balance.errors``).
RTOL_SHARE = 1e-2
MAX_HARMONICS = 31

#: ``model``: "given" solves with the elements as given; "auto" traces again with each element's
#: refined model (``ContactElement.refined_model``) the windows where the model error exceeds
#: ``MODEL_SHARE * tol``.
MODELS = ("given", "auto")
MODEL_SHARE = 0.5
#: With a tolerance, an element that chooses its discretisation at every call and offers a fixed
#: ``start_rung(omega_range)`` (``AllModeMicroslip`` with cells and harmonics None) is traced on that
#: start rung and its windows on finer rungs (``hbm.adapt``, the model pass).  False: the element
#: as given, choosing per call (the path timed as "before" in docs/performance.md).
RUNGS_ALONG_CURVE = True

#: Newton tolerance on the scaled residual (``|R|/F`` for a one-DOF system at H = 1, ``|R|/x_ref``
#: otherwise) as a fraction of ``rtol``.
NEWTON_TOL_FACTOR = 5e-3


def frequency_response(system: Any, contacts: Any = None, omega_range: tuple[float, float] | None = None, *,
                       rtol: float = DEFAULT_RTOL, max_step: float = DEFAULT_MAX_STEP,
                       min_step: float = DEFAULT_MIN_STEP, max_steps: int = DEFAULT_MAX_STEPS,
                       locate_folds: bool = True, on_point: Callable[[float, float, float, float], None] | None = None,
                       accuracy: str | float | None = None, harmonics: int | None = None, n_t: int | None = None,
                       response_dof: int | None = None, stability: bool = True, tol: float | None = None,
                       estimate_error: bool = True, model: str = "given",
                       on_harmonics: Callable[[float, Any], None] | None = None,
                       curve_tol: float | None = None) -> FrequencyResponse:
    """FRF of ``system`` (a :class:`Blade` or a :class:`Structure`) with its ``contacts`` over
    ``omega_range = (w0, w1)`` rad/s, traced from ``w0`` to ``w1`` through any folds.

    One balance for every system (``hbm.balance``): a blade is a one-DOF structure, a contact
    element given alone attaches to its DOF.  The element is evaluated to ``rtol`` and every point
    solves the balance to ``NEWTON_TOL_FACTOR * rtol`` in its scaled residual.

    Parameters
    ----------
    system : Blade or Structure
        The linear system: a blade (mass, stiffness, damping, force) or a structure (M, C, K, force).
    contacts : ContactElement, Contact, sequence of Contact, or None, optional
        The contacts: ``hbm.Contact(element, dof=i)`` or ``dofs=(i, j)``; a bare element (any
        ``contact_models`` element) on a one-DOF system is the damper at its DOF; None for none.
    omega_range : tuple of float
        ``(w0, w1)`` in rad/s, >= 0 and different; traced from w0 to w1 (either way).
    rtol : float, optional
        Relative accuracy, in (0, 0.1).  Default 1e-6.
    max_step, min_step : float, optional
        Largest and smallest continuation step in scaled arclength.  Defaults 0.03, 1e-9.
    max_steps : int, optional
        Step budget.  Default 5000.
    curve_tol : float, optional
        Step control by accuracy: the steps are sized so that the curve between points (the cubic
        through the four nearest points, ``hbm.curve``) is within ``curve_tol`` of the branch
        (relative to the first-harmonic amplitude; omega to its reference), ``max_step`` then only a
        safeguard; after the run every interval whose neighbouring cubics disagree is checked at its
        mid-point against a converged solve and split there if off (those points are not streamed
        to ``on_point``).  Intervals still off (across corners of the branch) are listed in ``coarse``.
        Default None: the step is limited by ``max_step`` (the "precise" preset sets 1e-5).
    locate_folds : bool, optional
        Locate the turning points of the branch.  Default True.
    on_point : callable, optional
        ``on_point(omega, x_c, x_s, residual)`` with each accepted point (the response DOF's first
        harmonic, in m) and its scaled residual, as soon as it is accepted, in continuation order.
    accuracy : {"fast", "default", "precise"} or float, optional
        A preset of ``hbm.balance.presets`` instead of ``rtol`` and the step settings (not combined
        with them); for a structure it also sets H and n_t unless they are given.
    harmonics : int, optional
        The number of harmonics H.  Default: 1 for a blade, the accuracy preset's for a structure
        (``Structure.default_harmonics``).  Above 1 every contact needs a time law.
    n_t : int, optional
        AFT samples per period, >= 2H + 2.  Default ``hbm.balance.presets.samples_for(H, accuracy)``:
        the element's floor for H, and above H = 1 at least the accuracy preset's n_t.
    response_dof : int, optional
        The DOF whose response is reported.  Default the forced DOF.
    stability : bool, optional
        Whether Hill's stability is available (computed on first use of ``stable``).  Default True.
    tol : float, optional
        The target relative error of the response amplitude against the true periodic response
        of the physical system (all harmonics, the physical contact).  Given (and ``harmonics``
        not), a structure's H is chosen along the curve (``hbm.adapt``): the whole range at 3 (a
        blade at 1), then each window where the harmonics' estimate exceeds half of it traced again
        at 2H + 1 (7, 15, 31), in turn (``point_harmonics``, ``segments``).  Where the estimate (``error_estimate``) exceeds it, one ``AccuracyWarning`` names
        the worst point, its largest source and the fix.  The elements' own ``AccuracyWarning`` warnings
        during the solve (an element may warn at every evaluation) are merged into that one warning
        (their count and the worst), so a call warns at most once (``accuracy_warning``).  Default: with a
        named ``accuracy`` its tolerance (``hbm.balance.presets.TOLERANCE``: 1e-2, 1e-3, 1e-5), else
        ``DEFAULT_TOL`` (1e-3); for the estimate's target and the warning only.  With it, an element
        that chooses its discretisation at every call and offers ``start_rung`` (``AllModeMicroslip``
        with cells and harmonics None) is traced on that fixed start rung, and each window where the
        model source exceeds half the tolerance on the rung its estimate predicts (``hbm.adapt``;
        ``point_models`` names the rungs; ``RUNGS_ALONG_CURVE``).
    estimate_error : bool, optional
        Estimate the error of every point (``error_estimate``, ``error_sources``;
        ``hbm.balance.errors``).  Default True; False skips it (and the warning).
    model : {"given", "auto"}, optional
        "given" (default): the elements as given.  "auto": the windows of the curve where the
        estimate's model source exceeds half the tolerance are traced again with each element's
        refined model (``ContactElement.refined_model``: the all-mode bar for a single-mode
        microslip bar, on its fixed rungs; ``point_models``).
    on_harmonics : callable, optional
        ``on_harmonics(omega, X)`` with each accepted point, right after ``on_point``: ``X`` the
        response DOF's harmonics in m, ``(X0, Xc1, Xs1, ..., XcH, XsH)`` (``c_h = Xc_h - i Xs_h`` of
        ``FrequencyResponse.coefficients``), as it is accepted (a scene streams them to its CSV).  Where the balance may solve again
        (``model="auto"``, or ``tol`` without ``harmonics``), both callbacks get the final, spliced
        points once it ends, in order (``X`` zero-padded to the largest H).

    Returns
    -------
    FrequencyResponse
        The branch, with ``success`` and ``message``; a run that stops early keeps the points it
        computed.  A window whose refined trace fails keeps its coarse points; ``message`` and the
        warning say so.

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

    With the two-region microslip damper (the default case of ``python -m hbm``):

    >>> from contact_models import Bar, UniformLoad, TwoRegionMicroslip
    >>> bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    >>> two = TwoRegionMicroslip(bar, UniformLoad(N=100.0))
    >>> blade = Blade(mass=0.0877147, stiffness=1.0e8, damping=11.8467, force=8.0)
    >>> frf = frequency_response(blade, two, omega_range=(3.2e4, 4.4e4))
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
    # ---- validate
    structure = as_structure(system)
    w0, w1 = omega_range_pair(omega_range)
    preset = accuracy if accuracy is not None else "default"
    H_preset = harmonic_knobs(preset)[0]
    if accuracy is not None:
        rtol, max_step, min_step, max_steps, curve_tol = apply(accuracy, rtol=rtol, max_step=max_step,
                                                               min_step=min_step, max_steps=max_steps,
                                                               curve_tol=curve_tol)
    rtol = positive("rtol", rtol)
    if rtol >= 0.1:
        raise ValueError(f"rtol must be < 0.1, got rtol={rtol!r}")
    tolerance = _tolerance(tol, estimate_error, accuracy)
    if model not in MODELS:
        raise ValueError(f"model must be one of {', '.join(map(repr, MODELS))}, got model={model!r}")
    if model == "auto" and tolerance is None:
        raise ValueError("model='auto' chooses the model by its error estimate: it needs estimate_error=True")
    if tol is not None:  # the elements and the Newton points well inside the tolerance asked for
        rtol = min(rtol, RTOL_SHARE * tolerance)
    steps = dict(max_step=positive("max_step", max_step), min_step=positive("min_step", min_step),
                 max_steps=count("max_steps", max_steps), locate_folds=locate_folds,
                 curve_tol=None if curve_tol is None else positive("curve_tol", curve_tol))
    if steps["curve_tol"] is not None and steps["curve_tol"] >= 1.0:
        raise ValueError(f"curve_tol must be < 1 (a relative error), got curve_tol={curve_tol!r}")
    # ---- pick: H and n_t (an explicit knob overrides only itself), the balance
    adapt = harmonics is None and tol is not None
    if harmonics is None:
        harmonics = structure.default_harmonics if structure.default_harmonics is not None else H_preset
        if adapt and structure.default_harmonics is None:
            harmonics = ADAPT_START
    n_t_given = n_t
    rungs = False
    if tolerance is not None and RUNGS_ALONG_CURVE:
        contacts, rungs = _start_rungs(contacts, structure, (w0, w1))
    again = adapt or model == "auto" or rungs  # the balance may solve again: stream the final points at the end
    knobs = along.Knobs(system, w0, w1, rtol, NEWTON_TOL_FACTOR * rtol, steps, stability, tolerance,
                        lambda H: n_t_given if n_t_given is not None else _samples(H, preset), response_dof)
    live = None if again or (on_point is None and on_harmonics is None) else (
        lambda problem: _reporter(on_point, on_harmonics, problem))
    frf = along.solve(knobs, contacts, harmonics, live)
    notes: list[str] = []
    if again:  # the model and H chosen along the curve (hbm.adapt)
        plan = along.Plan(MODEL_SHARE if model == "auto" or rungs else None, HARMONICS_SHARE if adapt else None,
                          MAX_HARMONICS, rungs_only=model != "auto")
        frf, notes = along.along(knobs, frf, plan)
        if on_point is not None or on_harmonics is not None:
            _stream(frf, on_point, on_harmonics)
    heard = [m for f in dict.fromkeys(p[0] for p in (frf._pieces or [(frf,)])) for m in knobs.heard.get(id(f), [])]
    if tolerance is not None and len(frf) and float(np.max(frf.error_sources["peak"])) > tolerance:
        # the sampled maximum may fall short of the peak by more than tol: the peak located, its
        # source is then its own error (``FrequencyResponse.peak``)
        with errors.collected() as at_peak:
            frf.peak()
        heard += at_peak
    frf.accuracy_warning = _warn_once(frf, tolerance, heard, notes)
    return frf


def _start_rungs(contacts: Any, structure: Any, omega_range: tuple[float, float]) -> tuple[Any, bool]:
    """``(contacts, replaced)``: each element that offers a ``start_rung(omega_range)`` (a choosing
    ``AllModeMicroslip``) replaced by it; the contacts as given where none does."""
    listed = as_contacts(contacts, structure.n)
    out = []
    for c in listed:
        start = getattr(c.element, "start_rung", None)
        rung = start(omega_range) if callable(start) else None
        out.append(c if rung is None else c.with_element(rung))
    replaced = any(a is not b for a, b in zip(out, listed))
    return (out if replaced else contacts), replaced


def _tolerance(tol: Any, estimate_error: bool, accuracy: Any = None) -> float | None:
    """The target relative error: ``tol``, else the named preset's (``presets.TOLERANCE``), else
    ``DEFAULT_TOL``; None without an estimate."""
    if tol is None:
        preset = TOLERANCE.get(accuracy, DEFAULT_TOL) if isinstance(accuracy, str) else DEFAULT_TOL
        return preset if estimate_error else None
    if isinstance(tol, (str, bytes, bool)):
        raise ValueError(f"tol must be a number in (0, 1), got tol={tol!r}")
    tol = positive("tol", tol)
    if tol >= 1.0:
        raise ValueError(f"tol must be < 1 (a relative error), got tol={tol!r}")
    return tol


def _samples(H: Any, preset: Any) -> Any:
    """``samples_for(H, preset)`` for a valid H; an invalid H goes on to the balance's own check."""
    if isinstance(H, (int, np.integer)) and not isinstance(H, bool) and H >= 1:
        return samples_for(int(H), preset)
    return None


#: What brings each source of error down (the warning's advice).
REMEDY = {
    "harmonics": "more harmonics (give tol= and no harmonics= to let the balance choose, or raise harmonics=)",
    "first-harmonic": ("an element with a time-domain force law ({names} is a first-harmonic element: it has none, so "
                       "the balance keeps H = 1 with it; contact_models.AllModeMicroslip is the microslip bar with one)"),
    "sampling": "more AFT samples (raise n_t=)",
    "element": "a tighter element tolerance (lower rtol=)",
    "model": "contact_models.AllModeMicroslip (the bar with every mode) for this damper",
    "peak": "a tighter rtol=",
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
        first = [type(c.element).__name__ for c in site.contacts if not c.element.has_time_law]
        if first:  # no H above 1 for such an element: more harmonics is no advice
            return REMEDY["first-harmonic"].format(names=", ".join(dict.fromkeys(first)))
        return REMEDY[source]
    if source != "model":
        return REMEDY[source]
    site, _ = frf._site(i)
    top = [c.element for c in site.contacts if getattr(c.element, "refined_no_further", False)]
    if top:
        return TOP_RUNG_REMEDY.format(rung=f"{top[0].cells} cells, H = {top[0].harmonics}")
    if all(c.element.refined_model() is None or callable(getattr(c.element, "refined_rung", None))
           for c in frf.contacts):
        return REFINED_REMEDY
    return REMEDY[source]


def _warn_once(frf: FrequencyResponse, tolerance: float | None, heard: list[str], notes: list[str] = ()) -> str | None:
    """One ``AccuracyWarning`` per call: where the estimate exceeds the tolerance, the worst point,
    its largest source and what would fix it; with it, the number of warnings the elements gave
    during the solve (each evaluation may warn) and the worst of them.  Returns its message (None:
    no warning)."""
    parts = []
    if tolerance is not None and len(frf) and np.any(frf.error_estimate > tolerance):
        i = int(np.nanargmax(frf.error_estimate))
        source = max(frf.error_sources, key=lambda s: frf.error_sources[s][i])
        parts.append(f"estimated error {frf.error_estimate[i]:.2g} > tol {tolerance:g} at omega = {frf.omega[i]:.6g} "
                     f"rad/s, amplitude {frf.amplitude[i]:.4g} m (largest source: {source}, "
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
        Relative tolerance on the amplitude, passed to the element too.  Default 1e-8.

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
    >>> case = default_case()                          # the blade and damper of python -m hbm
    >>> r = response_at(case.blade, case.element, 38000.0, (1.0e-7, 1.0e-5))
    >>> round(r.amplitude, 10), round(r.phase, 3)      # m, rad
    (7.371e-07, 0.041)
    """
    if not isinstance(blade, Blade):
        raise ValueError(f"blade must be an hbm.Blade, got blade={blade!r}")
    if element is None or not callable(getattr(element, "fourier", None)):
        raise ValueError(f"element must be a contact element (with fourier(a, omega)), got element={element!r}")
    omega = nonnegative("omega", omega)
    rtol = positive("rtol", rtol)
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


def _stream(frf: FrequencyResponse, on_point: Callable | None, on_harmonics: Callable | None) -> None:
    """The final points to the callbacks, in order (``_reporter``'s arguments; the harmonics padded
    with zeros to the result's largest H)."""
    if frf._pieces is None:
        report = _reporter(on_point, on_harmonics, frf._problem)
        for u, rnorm in zip(frf._run.y, frf.residual_norm):
            report(u, rnorm)
        return
    for i, w in enumerate(frf.omega):
        if on_point is not None:
            on_point(float(w), float(frf.x_c[i]), float(frf.x_s[i]), float(frf.residual_norm[i]))
        if on_harmonics is not None:
            on_harmonics(float(w), frf._X[i, frf._r].copy())


def _reporter(on_point: Callable | None, on_harmonics: Callable | None, problem: HarmonicBalance) -> Callable:
    """``on_point(omega, x_c, x_s, residual)`` and ``on_harmonics(omega, X)`` for the continuation's
    ``on_point(u, rnorm)`` in scaled unknowns."""
    c, s = problem.response_components()
    x_ref, w_ref = problem.x_ref, problem.omega_ref
    r = problem.dofs.index(problem.response_dof)

    def report(u, rnorm):
        if on_point is not None:
            on_point(float(u[-1] * w_ref), float(u[c] * x_ref), float(u[s] * x_ref), float(rnorm))
        if on_harmonics is not None:
            X, w = problem.to_physical(u)
            on_harmonics(float(w), X[r].copy())

    return report


__all__ = ["frequency_response", "response_at", "FrequencyResponse", "Peak", "Response", "NEWTON_TOL_FACTOR",
           "PEAK_XTOL_FACTOR", "DEFAULT_RTOL", "DEFAULT_MAX_STEP", "DEFAULT_MIN_STEP", "DEFAULT_MAX_STEPS"]
