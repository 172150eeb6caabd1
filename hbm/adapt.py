"""The one refinement driver: windows of a branch traced again at the next setting of every knob that asks.

``hbm.frequency_response`` with ``tol`` traces the whole range once at a start setting (H and the
elements as given, or an element's start rung), then refines it (``refine``).  Each source of the
estimate has a knob (``Knob``): the harmonics source the balance's H (``next_harmonics``: H -> 2H + 1,
or further where the estimate's decay asks), the model source each element's own refinement, asked
through the element contract (``refined_contacts``: a rung's next rung, ``refined_rung``, or the
refined model on its start rung).  A knob asks at a point where its source exceeds its share of
``tol`` or, where the whole estimate exceeds ``tol``, what the other sources leave of it (``asks``).
The **windows** are the runs of points where any knob asks, widened to the nearest estimate nodes
(``hbm.balance.errors.nodes``) outside them (``windows``; by point index, so folds are fine).  Each
window is traced again once, at the next setting of every knob that asks there, from its first point
lifted to the new setting (zero-padded harmonics, corrected by Newton at its frequency) to where the
branch passes the window's last point: the first accepted point beyond the hyperplane through the
coarse end point normal to the coarse tangent, moved onto that hyperplane (``window``,
``hbm.continuation.locate``).  The refined window is refined the same way in turn, until no knob
asks or every ladder that asks has ended.  A window whose refined trace fails keeps the coarse
points, and says so.  ``model="peak"`` turns the model knob only in the windows that hold the peak
(``peak_window``).  The segments are spliced into one :class:`hbm.FrequencyResponse`
(``FrequencyResponse.spliced``); ``locate_peak`` locates its peak.  ``docs/multiharmonic.md``
("Harmonics along the curve") gives the rules.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any, Callable

import numpy as np

from . import continuation as cont  # the module (hbm.continuation)
from . import curve
from ._steps import RESIDUAL_RAISED_AT_ONCE
from .balance import errors
from .balance.residual import HarmonicBalance
from .balance.start import equivalent_start, force_homotopy, stuck_reason
from .result import PEAK_XTOL_FACTOR, FrequencyResponse, Peak, model_label


#: A window's refined trace ends at its first point beyond the hyperplane through the coarse end
#: point within this many coarse chords of that point (or two of the longest steps).
RADIUS_CHORDS = 3.0
#: The point beyond is moved onto the hyperplane to this fraction of its last step.
CUT_XTOL = 0.02
#: A window's next H is predicted from its largest harmonics estimate ``e`` at H as the smallest H' of
#: the ladder (2H + 1, 2(2H + 1) + 1, ...) with ``e (H/H')^DECAY_ORDER`` below the share of tol, so that
#: a window is traced again once rather than once per rung.  A friction contact's force harmonics fall
#: like h^-2 (a kink per stick/slip switch), the response's two orders faster at a well-separated
#: resonance; where the decay is slower the refined window's own estimate asks for the next rung.
DECAY_ORDER = 4.0
#: Newton updates at most at each stage of a window's start solved again after its lifted start failed (``staged``).
STAGED_MAX_ITER = 40
#: Where the whole estimate is above tol, a knob also asks where its source exceeds what the other sources
#: leave of tol, where that is at least this share of it (``asks``).
LEFT_FLOOR = 0.1
#: The peak's window (``peak_window``) takes the model source as a bound of the model's error within this
#: factor (the estimate is held to under-read by at most 2x: ``docs/error_estimates.md``).
ESTIMATE_SLACK = 2.0


@dataclasses.dataclass
class Setup:
    """What every trace of one ``frequency_response`` call shares."""

    system: Any
    w0: float
    w1: float
    rtol: float
    newton_tol: float  #: Newton tolerance on the scaled residual
    steps: dict  #: the continuation's step settings (``max_step``, ``curve_tol``, ...)
    stability: bool
    tolerance: float | None
    samples: Callable[[int], Any]  #: n_t for an H
    response_dof: Any

    def balance(self, contacts: Any, H: int) -> HarmonicBalance:
        """The balance of ``contacts`` at ``H`` harmonics that every trace of this call solves."""
        return HarmonicBalance(self.system, contacts, harmonics=H, n_t=self.samples(H),
                               response_dof=self.response_dof, rtol=self.rtol)


#: Where a branch that stopped early is asked why (``stuck_reason``): this far beyond its last point, relative.
BEYOND_END = 1e-3


def solve(setup: Setup, contacts: Any, H: int, reporter: Callable | None = None) -> FrequencyResponse:
    """The whole range traced with ``contacts`` at ``H`` harmonics (the stuck start at w0);
    ``reporter(problem)`` makes the continuation's ``on_point`` once the problem's scales are set."""
    problem = setup.balance(contacts, H)
    problem.keep_jacobians = setup.stability  # for Hill's method at the points (FrequencyResponse.stable)
    with errors.collected() as now:
        out = trace(problem, setup, reporter=reporter)
    out._heard = list(now)
    return out


def trace(problem: HarmonicBalance, setup: Setup, *, reporter: Callable | None = None, start: Any = None,
          direction: int | None = None, stop: Callable | None = None,
          cut: Callable | None = None) -> FrequencyResponse:
    """Scales, the start (the stuck one at w0, else a homotopy in the force; or ``start``, scaled
    unknowns, in ``direction``), the continuation to w1 or to ``stop``, ``cut(run, scale)`` of the
    run, the check of its intervals (``curve_tol``), the result."""
    w0, w1, steps = setup.w0, setup.w1, setup.steps
    problem.set_scales(w0, w1)
    tol, scale, w_ref = setup.newton_tol, problem.arclength_scale(), problem.omega_ref
    components = (*problem.response_components(), -1)
    report = reporter(problem) if reporter is not None else None

    def run_from(u_start):
        return cont.continuation(problem, u_start, parameter=problem.unknowns - 1,
                                 bounds=(min(w0, w1) / w_ref, max(w0, w1) / w_ref),
                                 direction=direction or (1 if w1 > w0 else -1), tol=tol, scale=scale,
                                 fold_xtol=PEAK_XTOL_FACTOR * math.sqrt(setup.rtol), on_point=report,
                                 curve_components=components, stop=stop, from_bound=start is None, **steps)

    try:
        u0 = problem.stuck_start(w0) if start is None else start(problem)
    except ZeroDivisionError as exc:  # w0 on an undamped natural frequency: no finite response to start from
        raise ValueError(f"omega_range must not start on a natural frequency of the undamped structure, got "
                         f"omega_range[0]={w0!r} ({exc})") from None
    run = run_from(u0)
    if run.status == cont.Status.START_FAILED and start is None:
        u_h = force_homotopy(problem, w0, tol, scale)
        if u_h is not None:
            run = run_from(u_h)
    if run.status == cont.Status.START_FAILED and start is None:  # the describing functions' equivalent system
        u_e = equivalent_start(problem, w0)
        if u_e is not None:
            run = run_from(u_e)
    if run.status == cont.Status.START_FAILED and start is None:  # say why, where a contact sticks there
        why = stuck_reason(problem, w0)
        if why is not None:
            run = dataclasses.replace(run, message=f"{run.message}: {why}")
    elif run.status == cont.Status.STEP_TOO_SMALL and len(run.y):  # stopped where such a contact stops slipping?
        w_end = float(run.y[-1, -1]) * w_ref
        why = stuck_reason(problem, w_end * (1.0 + BEYOND_END * (direction or (1 if w1 > w0 else -1))))
        if why is not None:
            run = dataclasses.replace(run, message=f"{run.message}; just beyond its last point, {why}")
    elif run.status == cont.Status.TURNED_BACK:  # back on the bound it started from: the range was not traced
        far = float((max if w1 > w0 else min)(run.y[:, -1])) * w_ref
        run = dataclasses.replace(run, message=(
            f"{cont.MESSAGES[cont.Status.TURNED_BACK]}: it turned at omega = {far:.6g} rad/s and came back to "
            f"w0 = {w0:.6g} rad/s before reaching w1 = {w1:.6g} rad/s: the branch through w0 leaves the range there "
            "(a fold whose other branch lies beyond w0: start the range outside the folds; or a response below what "
            "the balance resolves, an omega_range too wide to trace)"))
    if cut is not None:
        run = cut(run, scale)
    if steps["curve_tol"] is not None and len(run.y) > 1:  # every interval checked, split where off
        run = curve.refine(problem, run, scale, components, steps["curve_tol"], tol, parameter=problem.unknowns - 1)
    out = FrequencyResponse(problem, run, rtol=setup.rtol, newton_tol=tol, scale=scale, stability=setup.stability,
                            tol=setup.tolerance)
    if setup.tolerance is not None:
        out._estimated(estimated(problem, out, setup.rtol), errors.nodes(out.amplitude))
    return out


def estimated(problem: HarmonicBalance, out: FrequencyResponse, rtol: float) -> dict:
    """``errors.estimate`` of the points of ``out``; where an element's hook raises during it (a user's force
    function), the traced points are kept as they are during the trace: every source reads inf (unknown, as a
    source with no bound) at every point, and ``out._estimate_failed`` says what raised, naming the element, the
    hook and the omega (the call's warning says it).  ``RESIDUAL_RAISED_AT_ONCE`` (a defect of the element's
    code, a warning the caller made an error) propagates at once, as during the trace."""
    try:
        return errors.estimate(problem, out._X, out.omega, rtol, out._newton_steps)
    except RESIDUAL_RAISED_AT_ONCE:
        raise
    except Exception as exc:  # noqa: BLE001 - an element's hook of the caller's: the curve stays
        out._estimate_failed = cont.described(exc)
        out.message += f"; the error estimate raised an exception ({out._estimate_failed}), it is unknown (inf)"
        return {s: np.full(len(out), math.inf) for s in errors.SOURCES}


# ------------------------------------------------------------------ windows
def windows(source: np.ndarray, nodes: np.ndarray, threshold: float, lo: int, hi: int) -> list[tuple[int, int]]:
    """``[(i0, i1), ...]``: the runs of ``lo <= i < hi`` where ``source`` exceeds ``threshold``,
    each widened to the nearest estimate ``nodes`` on each side (else ``lo``, ``hi - 1``), merged
    where they meet; ``i0``, ``i1`` inclusive.

    Examples
    --------
    >>> import numpy as np
    >>> e = np.array([0.1, 0.2, 0.9, 0.8, 0.1, 0.1, 0.1, 0.7, 0.1, 0.1])
    >>> windows(e, np.array([0, 4, 6, 9]), 0.5, 0, 10)
    [(0, 4), (6, 9)]
    """
    above = np.flatnonzero(source[lo:hi] > threshold) + lo
    out: list[tuple[int, int]] = []
    if not len(above):
        return out
    breaks = np.flatnonzero(np.diff(above) > 1)
    for a, b in zip(np.r_[above[0], above[breaks + 1]], np.r_[above[breaks], above[-1]]):
        before, after = nodes[(nodes < a) & (nodes >= lo)], nodes[(nodes > b) & (nodes < hi)]
        i0, i1 = (int(before[-1]) if len(before) else lo), (int(after[0]) if len(after) else hi - 1)
        if out and i0 <= out[-1][1]:
            out[-1] = (out[-1][0], max(out[-1][1], i1))
        else:
            out.append((i0, i1))
    return out


def lift(problem: HarmonicBalance, X: np.ndarray, w: float) -> np.ndarray:
    """The scaled unknowns of ``problem`` for the physical point ``X`` (n_a, 2H'+1) at ``w``: harmonics
    above the problem's H cut, missing ones zero (the same condensation DOFs)."""
    xr, wr = problem.x_ref, problem.omega_ref
    if problem.one_dof:
        return np.array([X[0, 1] / xr, X[0, 2] / xr, w / wr])
    Xp = np.zeros((problem.na, problem.L))
    k = min(problem.L, X.shape[1])
    Xp[:, :k] = X[:, :k]
    return np.append(Xp.ravel() / xr, w / wr)


def window(setup: Setup, frf: FrequencyResponse, i0: int, i1: int, contacts: Any,
           H: int) -> tuple[FrequencyResponse, str | None]:
    """Points ``i0..i1`` of ``frf`` traced again with ``contacts`` at ``H``: the result, and why it
    failed (None: it did not)."""
    problem = setup.balance(contacts, H)
    problem.keep_jacobians = setup.stability  # for Hill's method at the points (FrequencyResponse.stable)
    coarse, run = frf._problem, frf._run
    y_end, t_end = run.y[i1], run.tangent[i1]
    s_end = frf._scale(y_end)
    # the window reaches the end of the range (not the end of a window's own trace): the bound ends it
    last = i1 == len(frf) - 1 and min(abs(float(frf.omega[-1]) - w) for w in (setup.w0, setup.w1)) <= 1e-9 * max(
        abs(setup.w0), abs(setup.w1))

    def back(u):  # the refined point in the coarse run's coordinates scaled at its end point
        X, w = problem.to_physical(u)
        return (lift(coarse, X, float(w)) - y_end) / s_end

    # a crossing counts near the end point only (a bent branch may cross the hyperplane elsewhere):
    # within RADIUS_CHORDS of its coarse chords, or two of the longest steps (a step lands that close)
    chords = [float(np.linalg.norm((run.y[j] - y_end) / s_end)) for j in (i1 - 1, i1 + 1) if 0 <= j < len(run.y)]
    radius = max(RADIUS_CHORDS * max(chords, default=0.0), 2.0 * setup.steps["max_step"])

    crossed: list = []

    def beyond(u):
        d = back(u)
        if float(t_end @ d) >= 0.0 and float(np.linalg.norm(d)) <= radius:
            crossed.append(True)
        return bool(crossed)

    def cut(r, scale):  # the point beyond, moved onto the hyperplane
        if last or len(r.y) < 2 or not crossed:
            return r
        loc = cont.locate(problem, r.y[-2], r.y[-1], lambda u, t: float(t_end @ back(u)), tol=setup.newton_tol,
                          scale=scale, xtol=CUT_XTOL)
        if loc is None:
            return r
        s = scale(loc.y)
        t = loc.tangent / s
        y, tg = r.y.copy(), r.tangent.copy()
        y[-1], tg[-1] = loc.y, t / np.linalg.norm(t)
        rn = r.residual_norm.copy()
        rn[-1] = loc.residual_norm
        steps = None if r.newton_step is None else r.newton_step.copy()
        if steps is not None:
            steps[-1] = np.nan  # (the located point's residual is not kept)
        return dataclasses.replace(r, y=y, tangent=tg, residual_norm=rn, nfev=r.nfev + loc.nfev, newton_step=steps)

    X0, w_start = frf._X[i0], float(frf.omega[i0])
    t0 = float(run.tangent[i0][-1])
    direction = (1 if t0 > 0.0 else -1) if t0 != 0.0 else (1 if setup.w1 > setup.w0 else -1)
    def traced_from(X):
        return trace(problem, setup, start=lambda pr: lift(pr, X, w_start), direction=direction,
                     stop=None if last else beyond, cut=cut)

    with errors.collected() as now:
        out = traced_from(X0)
        if out._run.status == cont.Status.START_FAILED and H > frf.harmonics:
            X1 = staged(setup, contacts, X0, w_start, frf.harmonics, H)
            if X1 is not None:
                out = traced_from(X1)
    out._heard = list(now)
    if not out.success:
        return out, out._run.message
    if not last and not crossed:
        return out, "the refined branch did not pass the window's last point"
    return out, None


def staged(setup: Setup, contacts: Any, X: np.ndarray, w: float, H0: int, H: int) -> np.ndarray | None:
    """The point ``X`` (solved at ``H0`` harmonics, physical) solved again at ``w`` at each H of the ladder
    ``2 H0 + 1, ...`` up to ``H`` in turn, each lifted from the last, by Newton's method with a backtracking
    line search on |R| (``STAGED_MAX_ITER`` updates at most): a window's start where plain Newton from the
    lift straight to ``H`` fails, as it can where the stick/slip pattern of a nested element changes under
    the full steps (Newton then stops contracting); the line search keeps |R| falling.  None where a
    stage fails."""
    h = min(2 * H0 + 1, H)
    while True:
        problem = setup.balance(contacts, h)
        problem.set_scales(setup.w0, setup.w1)
        u = damped_newton(problem, lift(problem, X, w), setup.newton_tol)
        if u is None:
            return None
        X = problem.to_physical(u)[0]
        if h >= H:
            return X
        h = min(2 * h + 1, H)


def damped_newton(problem: HarmonicBalance, u: np.ndarray, tol: float,
                  max_iter: int = STAGED_MAX_ITER) -> np.ndarray | None:
    """``problem``'s scaled unknowns ``u`` corrected at their frequency until |R| <= tol: Newton's steps
    shortened by halving until |R| falls (Armijo), at most ``max_iter``; None where it does not get there."""
    try:
        R, J = problem(u)
        r = float(np.linalg.norm(R))
        for _ in range(max_iter):
            if r <= tol:
                return u
            du, t = np.linalg.solve(J[:, :-1], -R), 1.0
            while t >= 1e-6:
                v = u.copy()
                v[:-1] += t * du
                R_v, J_v = problem(v)
                r_v = float(np.linalg.norm(R_v))
                if r_v <= (1.0 - 1e-4 * t) * r:
                    break
                t *= 0.5
            else:
                return None
            u, R, J, r = v, R_v, J_v, r_v
    except (ArithmeticError, np.linalg.LinAlgError):
        return None
    return u if r <= tol else None


def next_harmonics(H: int, excess: float, top: int) -> int:
    """The H a window is traced again at: the smallest of ``2H + 1``, ``2(2H + 1) + 1``, ... (at most
    ``top``) at which an estimate ``excess`` times its share at H falls within it, falling like
    ``H^-DECAY_ORDER``.

    Examples
    --------
    >>> next_harmonics(3, 1.5, 31), next_harmonics(3, 100.0, 31), next_harmonics(3, 1e4, 31)
    (7, 15, 31)
    """
    nxt = 2 * H + 1
    while nxt < top and excess * (H / nxt) ** DECAY_ORDER > 1.0:
        nxt = 2 * nxt + 1
    return min(nxt, top)


def refined_contacts(contacts: list, excess: float = 1.0, span: tuple[float, float] | None = None,
                     omega_range: tuple[float, float] | None = None, rungs_only: bool = False) -> list | None:
    """The contacts with each element that has one replaced by its refinement; None if none has.

    An element that is one rung of a discretisation (``ContactElement.refined_rung``, e.g. a fixed
    ``AllModeMicroslip``) gets the next rung predicted for the window ``span = (lo, hi)`` rad/s whose
    estimate must fall by the factor ``excess``; any other element its refined model
    (``ContactElement.refined_model``), on that model's start rung where it has one
    (``ContactElement.start_rung``; refined in turn along the curve).  ``rungs_only``: only rungs are refined (a choosing
    element given by the caller, traced on its rungs; the other elements as given)."""
    out, changed = [], False
    for c in contacts:
        better = c.element.refined_rung(excess, span)  # a rung of a discretisation: its next rung
        if better is None and not rungs_only:  # else the more complete model, on its start rung
            better = c.element.refined_model()
            if better is not None and omega_range is not None:
                better = better.start_rung(omega_range) or better
        changed |= better is not None
        el = better if better is not None else c.element
        out.append(c.with_element(el))
    return out if changed else None


def balanced(contacts: list, H: int, keep: frozenset = frozenset()) -> list:
    """The contacts for a balance of H harmonics: each element replaced by ``for_balance(H)`` (a rung of a
    nested balance, e.g. a fixed ``AllModeMicroslip``, takes the top of its own harmonic ladder).  A rung's
    estimate is made for the drive ``a sin`` (``model_error``) and sees neither the harmonics the balance
    adds to the drive nor its phase; its own harmonics well above them keep it valid (``docs/theory.md``,
    "Rungs in a balance of more harmonics").  At H = 1 the drive is ``a sin``: the contacts as they are.  The elements
    ``keep`` names (by ``id``: the caller's own) are not the curve's choice and keep their harmonics."""
    if H <= 1:
        return contacts
    return [c if id(c.element) in keep else c.with_element(c.element.for_balance(H)) for c in contacts]


# ------------------------------------------------------------------ the driver
@dataclasses.dataclass
class Plan:
    """What is chosen along the curve: the share of ``tol`` each knob's source may take before a window is
    traced again at the knob's next setting (None: the knob stays as given)."""

    model_share: float | None
    harmonics_share: float | None
    max_harmonics: int
    rungs_only: bool = False  #: the model knob refines only the rungs of a discretisation (``refined_contacts``)
    at_peak: bool = False  #: the model knob turns in the windows that hold the peak only (``peak_window``)
    chosen: bool = False  #: the first trace's elements are the curve's choice (start rungs), not the caller's


@dataclasses.dataclass(frozen=True)
class Knob:
    """One accuracy knob: the estimate's ``source`` it brings down, the ``share`` of tol that source may take,
    and ``next(f, excess, span)``, its next setting for a window of ``f`` (rad/s ``span``) whose source must
    fall by the factor ``excess``: ``{"contacts": ...}`` or ``{"H": ...}``, None where its ladder ends."""

    source: str
    share: float
    next: Callable[[FrequencyResponse, float, tuple[float, float]], dict | None]


def knobs_of(plan: Plan, setup: Setup) -> list[Knob]:
    """The setup ``plan`` turns: the model (each element's next rung or refined model, ``refined_contacts``)
    and the balance's harmonics (``next_harmonics``; only where every contact has a time law: a
    first-harmonic element keeps H = 1, and the warning says why)."""
    out = []
    if plan.model_share is not None:
        def next_model(f, excess, span):
            better = refined_contacts(f.contacts, excess, span, (setup.w0, setup.w1), plan.rungs_only)
            return None if better is None else {"contacts": better}
        out.append(Knob("model", plan.model_share, next_model))
    if plan.harmonics_share is not None:
        def next_h(f, excess, span):
            if f.harmonics >= plan.max_harmonics or not all(c.element.has_time_law for c in f.contacts):
                return None
            return {"H": next_harmonics(f.harmonics, excess, plan.max_harmonics)}
        out.append(Knob("harmonics", plan.harmonics_share, next_h))
    return out


def asks(f: FrequencyResponse, knob: Knob, tol: float) -> np.ndarray:
    """Per point of ``f``, ``knob``'s source over its threshold (above 1: the knob asks to turn there).  The
    threshold is the knob's share of ``tol``; where the whole estimate exceeds ``tol``, it is what the other
    sources leave of ``tol`` if that is smaller, and at least ``LEFT_FLOOR * tol`` (below that, turning this
    knob alone cannot bring the sum within tol: the warning names the source that is left)."""
    if knob.source not in f.error_sources:
        return np.zeros(len(f))
    part, total = f.error_sources[knob.source], f.error_estimate
    limit = np.full(len(f), knob.share * tol)
    left = tol - (total - part)
    closing = (total > tol) & (left >= LEFT_FLOOR * tol) & (left < limit)
    limit[closing] = left[closing]
    return part / limit


def along(setup: Setup, frf: FrequencyResponse, plan: Plan) -> tuple[FrequencyResponse, list[str]]:
    """``frf`` (the whole range at the start setting) refined by the one driver (``refine``): one result
    and the notes of the windows whose refined trace failed (their coarse points kept)."""
    work, notes, full = [frf], [], {id(frf)}
    keep = frozenset() if plan.chosen else frozenset(id(c.element) for c in frf.contacts)
    segments_of = refine(setup, knobs_of(plan, setup), frf, plan.at_peak, keep, work, notes, full)
    note = "".join(f"; {n}" for n in notes)
    if len(segments_of) == 1 and segments_of[0][1] == 0 and segments_of[0][2] == len(segments_of[0][0]) and not notes:
        return segments_of[0][0], notes  # one setting everywhere: that solve's own result, as it was
    return FrequencyResponse.spliced(segments_of, work, note), notes


def refine(setup: Setup, turn: list[Knob], f: FrequencyResponse, at_peak: bool, keep: frozenset, work: list,
           notes: list, full: set) -> list[tuple[FrequencyResponse, int, int]]:
    """``f`` as segments ``(result, lo, hi)``: the windows where any knob asks (``asks``: its source above
    its share of tol, or above what the others leave of it where the sum exceeds tol; ``windows``) traced
    again once, at the next setting of every knob that asks there (each asked with its own excess over the
    window), and refined the same way in turn, until no knob asks or every ladder that asks has ended.
    ``at_peak``: the model knob asks only in its windows that meet the peak's window (``peak_window``).
    ``keep``: the caller's own elements, which keep their harmonics at any H (``balanced``)."""
    tol = setup.tolerance
    if not len(f) or not turn:
        return [(f, 0, len(f))]
    if f._estimate_failed is not None:  # its estimate raised (unknown everywhere): nothing to refine by
        return [(f, 0, len(f))]
    ratio = {k.source: asks(f, k, tol) for k in turn}
    if at_peak and "model" in ratio:
        ratio["model"] = _near_peak(f, ratio["model"])
    out, at = [], 0
    for i0, i1 in windows(np.max(np.array(list(ratio.values())), axis=0), f._nodes, 1.0, 0, len(f)):
        i0 = max(i0, at)  # the window before, widened to the node this one starts at, holds that point
        if i1 <= i0:  # a run of one point (between two others' windows) is not traced alone
            continue
        span = (float(np.min(f.omega[i0:i1 + 1])), float(np.max(f.omega[i0:i1 + 1])))
        setting: dict = {}
        for k in turn:
            excess = float(np.max(ratio[k.source][i0:i1 + 1]))
            if excess > 1.0:
                setting.update(k.next(f, excess, span) or {})
        if not setting:  # every ladder that asks here has ended: the window is kept
            continue
        H = setting.get("H", f.harmonics)
        contacts = balanced(setting.get("contacts", f.contacts), H, keep)
        i0, i1 = _widened(f, f.amplitude[i0:i1 + 1], i0, i1, at) or (i0, i1)  # f's own peak at an end: wider at once
        g = _retrace(setup, f, i0, i1, contacts, H, work, notes, full)
        wider = None if g is None else _widened(f, g.amplitude, i0, i1, at)
        if wider is not None:  # the refined peak at an end of the window: traced again to the next node beyond
            h = _retrace(setup, f, *wider, contacts, H, work, notes, full)
            if h is not None:
                g, (i0, i1) = h, wider
        if g is None:
            continue
        if at < i0:
            out.append((f, at, i0))
        out += refine(setup, turn, g, False, keep, work, notes, full)
        at = i1 + 1
    if at < len(f):
        out.append((f, at, len(f)))
    return out


def _widened(f: FrequencyResponse, amplitude: np.ndarray, i0: int, i1: int, at: int) -> tuple[int, int] | None:
    """The window ``i0..i1`` of ``f`` widened to the next estimate node beyond the end of the window where
    ``amplitude`` (the response along it: ``f``'s own, or its refined trace's) is largest, where that is the
    curve's peak (at least the largest of ``f`` outside the window): the peak then lies at or beyond the
    window's end, where it cannot be located between points of one balance.  Asked first of ``f`` (a
    window whose coarse peak is at its end is traced wide at once) and then of the refined trace (whose
    peak may have moved there).  None where the peak is inside, or the window already reaches the end of
    ``f`` (or, at its start, the last window kept, ``at``)."""
    j = int(np.argmax(amplitude))
    outside = np.r_[f.amplitude[:i0], f.amplitude[i1 + 1:]]
    if 0 < j < len(amplitude) - 1 or (len(outside) and amplitude[j] < np.max(outside)):
        return None
    nodes = np.asarray(f._nodes)
    if j == len(amplitude) - 1 and i1 < len(f) - 1:
        after = nodes[nodes > i1]
        return i0, int(after[0]) if len(after) else len(f) - 1
    if j == 0 and i0 > at:
        before = nodes[(nodes < i0) & (nodes >= at)]
        return int(before[-1]) if len(before) else at, i1
    return None


def _retrace(setup: Setup, f: FrequencyResponse, i0: int, i1: int, contacts: list, H: int, work: list,
             notes: list, full: set) -> FrequencyResponse | None:
    """The window ``i0..i1`` of ``f`` traced again with ``contacts`` at ``H``; None where the trace failed (the
    note says so, and the coarse points stay).  A whole-range window is solved again from the stuck start,
    as a solve without windows."""
    whole = id(f) in full and (i0, i1) == (0, len(f) - 1)
    if whole:
        g = solve(setup, contacts, H)
        why = None if len(g) else g.message
    else:
        g, why = window(setup, f, i0, i1, contacts, H)
    work.append(g)  # its work is counted, kept or not
    if why is not None:
        notes.append(f"the window omega = {f.omega[i0]:.6g}..{f.omega[i1]:.6g} rad/s traced again with H = "
                     f"{H}, {model_label(contacts)} failed ({why}): its points at H = {f.harmonics} are kept")
        return None
    if whole:
        full.add(id(g))
    return g


def peak_window(f: FrequencyResponse, threshold: float) -> tuple[int, int] | None:
    """The points ``(i0, i1)`` of ``f`` that hold the refined model's peak, where the model source at the
    sampled maximum ``i`` exceeds ``threshold`` (None: the peak stands as it is).

    With the model source ``e`` read as a bound of the given model's error within ``ESTIMATE_SLACK``
    (``s``), the refined response is at least ``a_i (1 - s e_i)`` at ``omega_i`` and at most
    ``a_j (1 + s e_j)`` at point ``j``, so its maximum lies where ``a_j (1 + s e_j) >= a_i (1 - s e_i)``:
    the contiguous run of such points around ``i``, one more on each side so that the window brackets it.
    """
    if not len(f) or "model" not in f.error_sources:
        return None
    e, a = f.error_sources["model"], f.amplitude
    i = int(np.argmax(a))
    if not e[i] > threshold:
        return None
    inside = a * (1.0 + ESTIMATE_SLACK * e) >= a[i] * (1.0 - ESTIMATE_SLACK * e[i])
    i0, i1 = i, i
    while i0 > 0 and inside[i0 - 1]:
        i0 -= 1
    while i1 < len(f) - 1 and inside[i1 + 1]:
        i1 += 1
    return max(i0 - 1, 0), min(i1 + 1, len(f) - 1)


def _near_peak(f: FrequencyResponse, ratio: np.ndarray) -> np.ndarray:
    """The model knob's ``ratio`` kept in its windows that meet the peak's window (``peak_window``), zero
    elsewhere: with ``model="peak"`` the refined model answers where the peak may lie, each window whole."""
    out = np.zeros_like(ratio)
    near = peak_window(f, 0.0) if ratio[int(np.argmax(f.amplitude))] > 1.0 else None  # the model asks at the peak
    if near is None:
        return out
    for i0, i1 in windows(ratio, f._nodes, 1.0, 0, len(f)):
        if i1 >= near[0] and i0 <= near[1]:
            out[i0:i1 + 1] = ratio[i0:i1 + 1]
    return out


# ------------------------------------------------------------------ the peak
def locate_peak(frf: FrequencyResponse, omega_range: tuple[float, float], among: np.ndarray | None = None) -> Peak:
    """The peak of ``frf`` located on the branch, stored in it (``FrequencyResponse.peak`` returns it).

    Between the neighbours of the largest sampled point the branch is parametrised by its chord and
    the zero of ``d(a^2)/ds = 2 (x_c t_c + x_s t_s)`` (``t`` the tangent, with a fresh
    omega-derivative) is found by Brent's method (``hbm.continuation.locate``), or the next candidate of
    ``_locate_on`` where that one lies below the sampled maximum; every trial point is
    a converged Newton point, so the located peak carries the Newton tolerance alone as its peak
    source.  A maximum at an end of the branch is kept as sampled and is not interior: at an end of
    ``omega_range`` the resonance may lie outside the range, and where a branch stopped early the
    response may still rise beyond.  The peak's estimate is the largest point estimate within two points of
    the sampled maximum (``hbm.balance.errors.peak_estimate``).  ``among``: the points the peak is sought
    among (a mask; the refined model's points for ``model="peak"``), else all.  The elements' warnings while locating join the call's.
    Where an element's hook raises while locating (a user's force function), the traced points stay as they are
    and the largest sampled point is the peak, not converged, its message naming the exception, the element,
    the hook and where it was asked (the call's warning says it); ``RESIDUAL_RAISED_AT_ONCE`` propagates."""
    if len(frf) == 0:
        raise ValueError("the frequency response has no points")
    n = len(frf)
    i = int(np.argmax(frf.amplitude if among is None or not np.any(among) else np.where(among, frf.amplitude, -np.inf)))
    w, a = float(frf.omega[i]), float(frf.amplitude[i])
    reasons = []
    located, raised = False, None
    site, j = frf._site(i)  # located with the balance of the segment holding the maximum
    if len(site) > 1 and (0 < j < len(site) - 1 or 0 < i < n - 1):  # (at a window's end: its last interval)
        loc, nit, raised = _locate_on(site, j, frf._r, a * (1.0 - errors.PEAK_ACCEPT * frf.rtol))
        frf._peak_nit += nit
        if loc is not None:
            (w, a), located = loc, True
            frf.peak_refined = True
            frf._located_peak_source(i)
    lo, hi = min(omega_range), max(omega_range)
    at_edge = i in (0, n - 1) and min(abs(w - lo), abs(w - hi)) <= 1e-9 * max(abs(lo), abs(hi))
    at_stop = not frf.success and i == n - 1
    if at_edge:
        reasons.append(f"the largest response is at the end of omega_range, omega = {w:.6g} rad/s: the resonance "
                       f"may lie outside the range")
    elif at_stop:
        reasons.append(f"the largest response is where the branch stopped, omega = {w:.6g} rad/s: it may rise "
                       f"beyond")
    elif not frf.success:
        reasons.append(f"the branch stopped at omega = {float(frf.omega[-1]):.6g} rad/s before the end of the range: "
                       f"the peak found is the largest on the traced part only")
    elif raised is not None:
        reasons.append(f"the maximum could not be located between points: locating it near omega = {w:.6g} rad/s "
                       f"raised an exception ({raised}); the largest sampled point is given")
    elif not located:
        reasons.append("the maximum could not be located between points (the largest sampled point is given)")
    estimate = errors.peak_estimate(frf.error_estimate, i)
    if math.isnan(estimate):  # nothing estimated there (tol=None): the Peak says None
        estimate = None
        if frf.tol is not None:
            reasons.append(f"its error was not estimated, so it is not known to be within tol {frf.tol:g}")
    elif frf.tol is not None and math.isinf(estimate):  # a source with no bound there (the call's warning says which)
        reasons.append(f"its error cannot be estimated (a source of it has no bound there), so it is not known "
                       f"to be within tol {frf.tol:g}")
    elif frf.tol is not None and estimate > frf.tol:
        reasons.append(f"its estimated error {estimate:.2g} exceeds tol {frf.tol:g}")
    interior = not (at_edge or at_stop)
    frf._peak = Peak(w, a, interior=interior, converged=not reasons, estimate=estimate, message="; ".join(reasons))
    return frf._peak


#: The stretch between the sampled maximum's neighbours, where locating the peak on their chords failed, is
#: traced again at steps this many times shorter than the chord (``_retraced``).
REFINE_STEPS = 16
#: Retraces in turn, each between the neighbours of the last one's largest point (a corner sharp enough to defeat
#: the chords of one retrace is 16 times shorter on the next).
REFINE_LEVELS = 2


def _retraced(f: FrequencyResponse, y: np.ndarray, i: int, counter: Any) -> np.ndarray | None:
    """The branch of ``f`` between the neighbours of point ``i`` of its points ``y`` (scaled unknowns) traced
    again by the continuation, from point ``i - 1`` to the frequency of point ``i + 1`` at steps of
    ``1 / REFINE_STEPS`` of their chord (one row per point); None where the neighbours do not bracket ``i`` in
    the frequency (a fold) or the trace does not reach point ``i + 1``'s frequency."""
    if not 0 < i < len(y) - 1:
        return None
    pr, p = f._problem, f._problem.unknowns - 1
    ya, yb = y[i - 1], y[i + 1]
    if not (ya[p] - y[i][p]) * (yb[p] - y[i][p]) < 0.0:
        return None
    length = float(np.linalg.norm((yb - ya) / f._scale(ya)))
    if not length > 0.0:
        return None
    run = cont.continuation(pr, ya, parameter=p, bounds=(min(ya[p], yb[p]), max(ya[p], yb[p])),
                            direction=1 if yb[p] > ya[p] else -1, tol=f.newton_tol, scale=f._scale,
                            step=length / REFINE_STEPS, max_step=length / REFINE_STEPS,
                            min_step=length * 1e-6, max_steps=20 * REFINE_STEPS, locate_folds=False, from_bound=True)
    counter.nfev += run.nfev
    counter.nit += run.nit
    if not run.success or len(run.y) < 3:
        return None
    return np.asarray(run.y)


def _locate_on(f: FrequencyResponse, i: int, r: int, floor: float
               ) -> tuple[tuple[float, float] | None, int, str | None]:
    """``(omega, amplitude)`` of the peak near point ``i`` of the single-balance result ``f`` (``r`` the response
    DOF's index): the first candidate whose amplitude is at least ``floor`` (below it, a candidate is no better
    than the sampled maximum), the Newton updates spent, and what an element's hook raised meanwhile
    (``hbm.continuation.described``; None where nothing did: ``RESIDUAL_RAISED_AT_ONCE`` propagates).

    The candidates, in order: the zero of d(a^2)/ds bracketed between the neighbours, then between point ``i``
    and either neighbour, then the largest a^2 between the neighbours (``hbm.continuation.maximise``: structure
    finer than the points), then the same three on the stretch between the neighbours traced again by the
    continuation at ``REFINE_STEPS`` times finer steps (``_retraced``), and so on ``REFINE_LEVELS`` times.
    Each is tried in turn: a ripple of the branch between points (a sampled time law at H > 1) can put one
    bracket's zero below the sampled maximum while another candidate holds the peak; and where a contact
    starts to slip at the maximum the branch has a corner between the points, where Newton from the chord's
    points (far off a branch that bends sharply in the higher harmonics) fails, while the points of a finer
    trace lie close enough to their chords."""
    pr = f._problem
    pr.fresh_omega_derivative = True
    counter = cont._Count()
    y = f._run.y
    c, s_ = pr.response_components()
    opts = dict(tol=f.newton_tol, scale=f._scale, xtol=PEAK_XTOL_FACTOR * math.sqrt(f.rtol), count=counter)

    def slope(u, t):  # proportional to d(a^2)/ds along the branch
        return u[c] * t[c] + u[s_] * t[s_]

    def on(y, i):
        for ja, jb in ((i - 1, i + 1), (i - 1, i), (i, i + 1)):
            if ja >= 0 and jb < len(y):
                yield cont.locate(pr, y[ja], y[jb], slope, **opts)
        if 0 < i < len(y) - 1:
            yield cont.maximise(pr, y[i - 1], y[i + 1], lambda u: u[c] * u[c] + u[s_] * u[s_], **opts)

    def candidates():
        yc, ic = y, i
        yield from on(yc, ic)
        for _ in range(REFINE_LEVELS):
            yc = _retraced(f, yc, ic, counter)
            if yc is None:
                return
            ic = int(np.argmax(yc[:, c] ** 2 + yc[:, s_] ** 2))
            yield from on(yc, ic)

    try:
        for loc in candidates():
            if loc is not None:
                X, w = pr.to_physical(loc.y)
                a = float(math.hypot(X[r, 1], X[r, 2]))
                if a >= floor:
                    return (float(w), a), counter.nit, None
        return None, counter.nit, None
    except RESIDUAL_RAISED_AT_ONCE:
        raise
    except Exception as exc:  # noqa: BLE001 - an element's hook of the caller's: the traced peak stays
        return None, counter.nit, cont.described(exc)
    finally:
        pr.fresh_omega_derivative = False
