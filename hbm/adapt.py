"""Harmonics and model chosen along the curve: windows of a branch traced again, spliced into one result.

``hbm.frequency_response`` with ``tol`` traces the whole range once at a start setting (H and the
elements as given), then finds the **windows**: the contiguous runs of points of the branch (by point
index, so folds are fine) where one source of its error estimate exceeds a share of ``tol`` (the
harmonics source, or the model source for ``model="auto"``), widened to the nearest estimate nodes
(``hbm.balance.errors.nodes``) below the share on each side.  Each window is traced again with
``H -> 2H + 1`` (or each element's refined model: for a fixed rung of a discretised element such as
``AllModeMicroslip``, the next rung its estimate predicts for the window, ``refined_contacts``),
starting from the window's first point lifted to the new setting (zero-padded harmonics, corrected
by Newton at its frequency) and ending where
the branch passes the window's last point: at the first accepted point beyond the hyperplane
through the coarse end point normal to the coarse tangent, moved onto that hyperplane
(``hbm.continuation.locate``).  The refined window is searched again with its own estimate, up to
``MAX_HARMONICS``.  A window whose refined trace fails keeps the coarse points, and says so.  The
segments are spliced into one :class:`hbm.FrequencyResponse` (``FrequencyResponse.spliced``);
``docs/multiharmonic.md`` ("Harmonics along the curve") gives the rules.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any, Callable

import numpy as np

from . import continuation as cont  # the module (hbm.continuation)
from . import curve
from .balance import errors
from .balance.residual import HarmonicBalance
from .balance.start import force_homotopy
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
#: After the passes, a source is refined where the whole estimate is above tol down to what the other
#: sources leave of tol, where that is at least this share of it (``_left_for``).
LEFT_FLOOR = 0.1
#: Along a discretised element's rungs, a harmonics window whose points the model pass would trace again
#: (the model source's windows above its share) for at least this fraction, on the finest rung predicted,
#: is traced once, at its new H on that rung, instead of at its new H on the cheap rung first (``rungs_too``).
COMBINE_SHARE = 0.5
#: The peak's window (``peak_window``) takes the model source as a bound of the model's error within this
#: factor (the estimate is held to under-read by at most 2x: ``docs/error_estimates.md``).
ESTIMATE_SLACK = 2.0


@dataclasses.dataclass
class Knobs:
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


def solve(knobs: Knobs, contacts: Any, H: int, reporter: Callable | None = None) -> FrequencyResponse:
    """The whole range traced with ``contacts`` at ``H`` harmonics (the stuck start at w0);
    ``reporter(problem)`` makes the continuation's ``on_point`` once the problem's scales are set."""
    problem = knobs.balance(contacts, H)
    problem.keep_jacobians = knobs.stability  # for Hill's method at the points (FrequencyResponse.stable)
    with errors.collected() as now:
        out = trace(problem, knobs, reporter=reporter)
    out._heard = list(now)
    return out


def trace(problem: HarmonicBalance, knobs: Knobs, *, reporter: Callable | None = None, start: Any = None,
          direction: int | None = None, stop: Callable | None = None,
          cut: Callable | None = None) -> FrequencyResponse:
    """Scales, the start (the stuck one at w0, else a homotopy in the force; or ``start``, scaled
    unknowns, in ``direction``), the continuation to w1 or to ``stop``, ``cut(run, scale)`` of the
    run, the check of its intervals (``curve_tol``), the result."""
    w0, w1, steps = knobs.w0, knobs.w1, knobs.steps
    problem.set_scales(w0, w1)
    tol, scale, w_ref = knobs.newton_tol, problem.arclength_scale(), problem.omega_ref
    components = (*problem.response_components(), -1)
    report = reporter(problem) if reporter is not None else None

    def run_from(u_start):
        return cont.continuation(problem, u_start, parameter=problem.unknowns - 1,
                                 bounds=(min(w0, w1) / w_ref, max(w0, w1) / w_ref),
                                 direction=direction or (1 if w1 > w0 else -1), tol=tol, scale=scale,
                                 fold_xtol=PEAK_XTOL_FACTOR * math.sqrt(knobs.rtol), on_point=report,
                                 curve_components=components, stop=stop, **steps)

    run = run_from(problem.stuck_start(w0) if start is None else start(problem))
    if run.status == cont.Status.START_FAILED and start is None:
        u_h = force_homotopy(problem, w0, tol, scale)
        if u_h is not None:
            run = run_from(u_h)
    if cut is not None:
        run = cut(run, scale)
    if steps["curve_tol"] is not None and len(run.y) > 1:  # every interval checked, split where off
        run = curve.refine(problem, run, scale, components, steps["curve_tol"], tol, parameter=problem.unknowns - 1)
    out = FrequencyResponse(problem, run, rtol=knobs.rtol, newton_tol=tol, scale=scale, stability=knobs.stability,
                            tol=knobs.tolerance)
    if knobs.tolerance is not None:
        out._estimated(errors.estimate(problem, out._X, out.omega, knobs.rtol), errors.nodes(out.amplitude))
    return out


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


def window(knobs: Knobs, frf: FrequencyResponse, i0: int, i1: int, contacts: Any,
           H: int) -> tuple[FrequencyResponse, str | None]:
    """Points ``i0..i1`` of ``frf`` traced again with ``contacts`` at ``H``: the result, and why it
    failed (None: it did not)."""
    problem = knobs.balance(contacts, H)
    problem.keep_jacobians = knobs.stability  # for Hill's method at the points (FrequencyResponse.stable)
    coarse, run = frf._problem, frf._run
    y_end, t_end = run.y[i1], run.tangent[i1]
    s_end = frf._scale(y_end)
    # the window reaches the end of the range (not the end of a window's own trace): the bound ends it
    last = i1 == len(frf) - 1 and min(abs(float(frf.omega[-1]) - w) for w in (knobs.w0, knobs.w1)) <= 1e-9 * max(
        abs(knobs.w0), abs(knobs.w1))

    def back(u):  # the refined point in the coarse run's coordinates scaled at its end point
        X, w = problem.to_physical(u)
        return (lift(coarse, X, float(w)) - y_end) / s_end

    # a crossing counts near the end point only (a bent branch may cross the hyperplane elsewhere):
    # within RADIUS_CHORDS of its coarse chords, or two of the longest steps (a step lands that close)
    chords = [float(np.linalg.norm((run.y[j] - y_end) / s_end)) for j in (i1 - 1, i1 + 1) if 0 <= j < len(run.y)]
    radius = max(RADIUS_CHORDS * max(chords, default=0.0), 2.0 * knobs.steps["max_step"])

    crossed: list = []

    def beyond(u):
        d = back(u)
        if float(t_end @ d) >= 0.0 and float(np.linalg.norm(d)) <= radius:
            crossed.append(True)
        return bool(crossed)

    def cut(r, scale):  # the point beyond, moved onto the hyperplane
        if last or len(r.y) < 2 or not crossed:
            return r
        loc = cont.locate(problem, r.y[-2], r.y[-1], lambda u, t: float(t_end @ back(u)), tol=knobs.newton_tol,
                          scale=scale, xtol=CUT_XTOL)
        if loc is None:
            return r
        s = scale(loc.y)
        t = loc.tangent / s
        y, tg = r.y.copy(), r.tangent.copy()
        y[-1], tg[-1] = loc.y, t / np.linalg.norm(t)
        rn = r.residual_norm.copy()
        rn[-1] = loc.residual_norm
        return dataclasses.replace(r, y=y, tangent=tg, residual_norm=rn, nfev=r.nfev + loc.nfev)

    X0, w_start = frf._X[i0], float(frf.omega[i0])
    t0 = float(run.tangent[i0][-1])
    direction = (1 if t0 > 0.0 else -1) if t0 != 0.0 else (1 if knobs.w1 > knobs.w0 else -1)
    def traced_from(X):
        return trace(problem, knobs, start=lambda pr: lift(pr, X, w_start), direction=direction,
                     stop=None if last else beyond, cut=cut)

    with errors.collected() as now:
        out = traced_from(X0)
        if out._run.status == cont.Status.START_FAILED and H > frf.harmonics:
            X1 = staged(knobs, contacts, X0, w_start, frf.harmonics, H)
            if X1 is not None:
                out = traced_from(X1)
    out._heard = list(now)
    if not out.success:
        return out, out._run.message
    if not last and not crossed:
        return out, "the refined branch did not pass the window's last point"
    return out, None


def staged(knobs: Knobs, contacts: Any, X: np.ndarray, w: float, H0: int, H: int) -> np.ndarray | None:
    """The point ``X`` (solved at ``H0`` harmonics, physical) solved again at ``w`` at each H of the ladder
    ``2 H0 + 1, ...`` up to ``H`` in turn, each lifted from the last, by Newton's method with a backtracking
    line search on |R| (``STAGED_MAX_ITER`` updates at most): a window's start where plain Newton from the
    lift straight to ``H`` fails, as it can where the stick/slip pattern of a nested element changes under
    the full steps (Newton then stops contracting); the line search keeps |R| falling.  None where a
    stage fails."""
    h = min(2 * H0 + 1, H)
    while True:
        problem = knobs.balance(contacts, h)
        problem.set_scales(knobs.w0, knobs.w1)
        u = damped_newton(problem, lift(problem, X, w), knobs.newton_tol)
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


def balanced(contacts: list, H: int) -> list:
    """The contacts for a balance of H harmonics: each element replaced by ``for_balance(H)`` (a rung of a
    nested balance, e.g. a fixed ``AllModeMicroslip``, keeps two rungs of its own harmonics above the
    balance's).  A rung's estimate is made for the drive ``a sin`` (``model_error``) and cannot see the
    harmonics the balance adds to the drive; its own harmonics well above them keep it valid
    (``docs/validation.md``).  At H = 1 the drive is ``a sin``: the contacts as they are."""
    if H <= 1:
        return contacts
    return [c.with_element(c.element.for_balance(H)) for c in contacts]


def rungs_too(f: FrequencyResponse, i0: int, i1: int, threshold: float, span: tuple[float, float],
              knobs: Knobs) -> list | None:
    """The contacts to trace a harmonics window ``i0..i1`` of ``f`` on at its new H, if the model pass would
    trace most of that window again anyway (the model source's windows above ``threshold`` cover at least
    ``COMBINE_SHARE`` of its points); else None (the contacts as they are).  Where the rungs predicted are
    the finest ones along a curve (``at_top_rung``), those rungs: the window is traced once.  Where they
    have the top harmonics but not the finest cells, the present rungs' cells at those harmonics
    (``harmonics_of``): the window is traced once at its new H with the bar's harmonics it needs, and the
    model pass refines only the cells, where the window's own estimate asks.  A coarser rung predicted
    from the start rung's estimates at the old H is not taken whole: estimated at the old H, it can be
    short of the harmonics the new H needs.  At the top harmonics no prediction can ask for more of
    them."""
    if "model" not in f.error_sources:
        return None
    source = f.error_sources["model"]
    covered = sum(b - a + 1 for a, b in windows(source, f._nodes, threshold, i0, i1 + 1))
    if covered < COMBINE_SHARE * (i1 - i0 + 1):
        return None
    excess = float(np.max(source[i0:i1 + 1])) / threshold
    better = refined_contacts(f.contacts, excess, span, (knobs.w0, knobs.w1), True)
    if better is None:
        return None
    if all(c.element.at_top_rung for c in better):
        return better
    raised = [c.element.harmonics_of(b.element) for c, b in zip(f.contacts, better)]
    return None if None in raised else [c.with_element(el) for c, el in zip(f.contacts, raised)]


# ------------------------------------------------------------------ the passes and the splice
@dataclasses.dataclass
class Plan:
    """What is chosen along the curve: the shares of ``tol`` above which a window is traced again
    with the refined model (None: the elements as given) and with ``2H + 1`` harmonics (None: H fixed)."""

    model_share: float | None
    harmonics_share: float | None
    max_harmonics: int
    rungs_only: bool = False  #: the model pass refines only the rungs of a discretisation (``refined_contacts``)
    at_peak: bool = False  #: the model pass refines the peak's window only (``peak_window``: ``model="peak"``)


def along(knobs: Knobs, frf: FrequencyResponse, plan: Plan) -> tuple[FrequencyResponse, list[str]]:
    """``frf`` (the whole range at the start setting) with its windows traced again: the model
    pass, then the harmonics pass on every segment (the other way round with ``plan.rungs_only``: the
    structure's harmonics do not depend on the rung, so a segment is traced at its H on the cheap rung
    first, and the expensive rungs once, at that H, or at once where the model pass would trace most of
    the harmonics window again: ``rungs_too``); one result and the notes of the windows that failed
    (their coarse points kept)."""
    work, notes, full = [frf], [], {id(frf)}
    segments_of = [(frf, 0, len(frf))]
    tol = knobs.tolerance

    def model_step(f, excess, span, points):
        better = refined_contacts(f.contacts, excess, span, (knobs.w0, knobs.w1), plan.rungs_only)
        return None if better is None else (balanced(better, f.harmonics), f.harmonics)

    def harmonics_step(f, excess, span, points):
        # H > 1 needs every element's time law (a first-harmonic element stays at H = 1, the warning says
        # why); a one-DOF system goes to the condensed form at H > 1 as any other
        if f.harmonics >= plan.max_harmonics or not all(c.element.has_time_law for c in f.contacts):
            return None
        contacts, H = f.contacts, next_harmonics(f.harmonics, excess, plan.max_harmonics)
        if plan.rungs_only and plan.model_share is not None:  # rungs chosen along the curve (not an element given)
            contacts = balanced(rungs_too(f, *points, plan.model_share * tol, span, knobs) or contacts, H)
        return contacts, H

    passes = [("model", plan.model_share, model_step), ("harmonics", plan.harmonics_share, harmonics_step)]
    for source, share, step in (passes[::-1] if plan.rungs_only else passes):
        if share is None:
            continue
        if source == "model" and plan.at_peak:  # the peak's window only; within it, as everywhere else
            segments_of = [p for f, lo, hi in segments_of
                           for p in _at_peak(knobs, f, lo, hi, share * tol, step, work, notes, full)]
            continue
        segments_of = [p for f, lo, hi in segments_of
                       for p in _split(knobs, f, lo, hi, source, share * tol, step, work, notes, full)]
    if plan.harmonics_share is not None:  # the harmonics take what the other sources leave of tol
        segments_of = [p for f, lo, hi in segments_of
                       for p in _split(knobs, f, lo, hi, "harmonics",
                                       lambda g, a, b: _left_for(g, a, b, "harmonics", tol),
                                       harmonics_step, work, notes, full)]
    note = "".join(f"; {n}" for n in notes)
    if len(segments_of) == 1 and segments_of[0][1] == 0 and segments_of[0][2] == len(segments_of[0][0]) and not notes:
        return segments_of[0][0], notes  # one setting everywhere: that solve's own result, as it was
    return FrequencyResponse.spliced(segments_of, work, note), notes


def _left_for(f: FrequencyResponse, lo: int, hi: int, source: str, tol: float) -> float:
    """The threshold of ``source`` on points ``lo..hi`` of ``f`` after the passes: where the whole estimate
    is above ``tol``, what the other sources leave of it at the worst such point; inf (nothing to refine)
    where no point is above tol, or where the others leave less than ``LEFT_FLOOR * tol`` (refining this
    source cannot bring the sum within tol there: the warning says which source is left).  A source within
    its share next to another that cannot be refined further (a rung at the top of its ladder) is so refined
    until the sum meets tol."""
    if not len(f) or source not in f.error_sources:
        return math.inf
    e, part = f.error_estimate[lo:hi], f.error_sources[source][lo:hi]
    over = e > tol
    if not np.any(over):
        return math.inf
    left = tol - float(np.max((e - part)[over]))
    return left if left >= LEFT_FLOOR * tol else math.inf


def _split(knobs: Knobs, f: FrequencyResponse, lo: int, hi: int, source: str, threshold: float | Callable,
           step: Callable, work: list, notes: list, full: set) -> list[tuple[FrequencyResponse, int, int]]:
    """Points ``lo <= i < hi`` of ``f`` as segments ``(result, lo, hi)``: its windows of ``source``
    above ``threshold`` traced again at ``step(f, excess, span, points)`` (new contacts and H, None:
    nothing to refine there, the window kept) and split the same way in turn.  Each window is asked
    with its own excess: a rung asked for a factor of 1, as a question for the whole segment once was,
    refines nothing where its parts are each within half of its estimate, and its rung probes cost solves."""
    if not len(f) or source not in f.error_sources:
        return [(f, lo, hi)]
    limit = threshold(f, lo, hi) if callable(threshold) else threshold  # a callable: asked again of each window
    out, at = [], lo
    for i0, i1 in windows(f.error_sources[source], f._nodes, limit, lo, hi):
        if i1 <= i0:  # a run of one point (between two others' windows) is not traced alone
            continue
        g = _retrace(knobs, f, i0, i1, source, limit, step, work, notes, full)
        if g is None:
            continue
        if at < i0:
            out.append((f, at, i0))
        out += _split(knobs, g, 0, len(g), source, threshold, step, work, notes, full)
        at = i1 + 1
    if at < hi:
        out.append((f, at, hi))
    return out


def _retrace(knobs: Knobs, f: FrequencyResponse, i0: int, i1: int, source: str, limit: float, step: Callable,
             work: list, notes: list, full: set) -> FrequencyResponse | None:
    """The window ``i0..i1`` of ``f`` traced again at ``step``'s next setting for ``source`` (whose share
    there is ``limit``); None where there is nothing to refine or the trace failed (the note says so,
    and the coarse points stay).  A whole-range window is solved again from the stuck start, as a
    solve without windows."""
    whole = id(f) in full and (i0, i1) == (0, len(f) - 1)
    nxt = step(f, float(np.max(f.error_sources[source][i0:i1 + 1])) / limit,
               (float(np.min(f.omega[i0:i1 + 1])), float(np.max(f.omega[i0:i1 + 1]))), (i0, i1))
    if nxt is None:  # nothing to refine for this window (a rung whose parts there are zero): kept
        return None
    if whole:
        g = solve(knobs, *nxt)
        why = None if len(g) else g.message
    else:
        g, why = window(knobs, f, i0, i1, *nxt)
    work.append(g)  # its work is counted, kept or not
    if why is not None:
        notes.append(f"the window omega = {f.omega[i0]:.6g}..{f.omega[i1]:.6g} rad/s traced again with H = "
                     f"{nxt[1]}, {model_label(nxt[0])} failed ({why}): its points at H = {f.harmonics} are kept")
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


def _at_peak(knobs: Knobs, f: FrequencyResponse, lo: int, hi: int, threshold: float, step: Callable, work: list,
             notes: list, full: set) -> list[tuple[FrequencyResponse, int, int]]:
    """Points ``lo <= i < hi`` of ``f`` as segments: of the model source's windows above ``threshold``
    (``windows``), those that meet the peak's window (``peak_window``) traced again and split in turn
    exactly as along a whole curve (``_split``); the rest as given."""
    near = peak_window(f, threshold) if (lo, hi) == (0, len(f)) else None
    if near is None:
        return [(f, lo, hi)]
    out, at = [], lo
    for i0, i1 in windows(f.error_sources["model"], f._nodes, threshold, lo, hi):
        if i1 <= i0 or i1 < near[0] or i0 > near[1]:
            continue
        g = _retrace(knobs, f, i0, i1, "model", threshold, step, work, notes, full)
        if g is None:
            continue
        if at < i0:
            out.append((f, at, i0))
        out += _split(knobs, g, 0, len(g), "model", threshold, step, work, notes, full)
        at = i1 + 1
    if at < hi:
        out.append((f, at, hi))
    return out


# ------------------------------------------------------------------ the peak
def locate_peak(frf: FrequencyResponse, omega_range: tuple[float, float], among: np.ndarray | None = None) -> Peak:
    """The peak of ``frf`` located on the branch, stored in it (``FrequencyResponse.peak`` returns it).

    Between the neighbours of the largest sampled point the branch is parametrised by its chord and
    the zero of ``d(a^2)/ds = 2 (x_c t_c + x_s t_s)`` (``t`` the tangent, with a fresh
    omega-derivative) is found by Brent's method (``hbm.continuation.locate``); every trial point is
    a converged Newton point, so the located peak carries the Newton tolerance alone as its peak
    source.  A maximum at an end of the branch is kept as sampled and is not interior: at an end of
    ``omega_range`` the resonance may lie outside the range, and where a branch stopped early the
    response may still rise beyond.  ``among``: the points the peak is sought among (a mask; the refined
    model's points for ``model="peak"``), else all.  The elements' warnings while locating join the call's."""
    if len(frf) == 0:
        raise ValueError("the frequency response has no points")
    n = len(frf)
    i = int(np.argmax(frf.amplitude if among is None or not np.any(among) else np.where(among, frf.amplitude, -np.inf)))
    w, a = float(frf.omega[i]), float(frf.amplitude[i])
    reasons = []
    located = False
    site, j = frf._site(i)  # located with the balance of the segment holding the maximum
    if 0 < j < len(site) - 1:
        loc, nit = _locate_on(site, j)
        frf._peak_nit += nit
        if loc is not None:
            X, w_loc = site._problem.to_physical(loc.y)
            a_loc = float(math.hypot(X[frf._r, 1], X[frf._r, 2]))
            if a_loc >= a * (1.0 - errors.PEAK_ACCEPT * frf.rtol):
                w, a, located = float(w_loc), a_loc, True
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
    elif not located:
        reasons.append("the maximum could not be located between points (the largest sampled point is given)")
    estimate = float(frf.error_estimate[i]) if len(frf.error_estimate) else math.nan
    if frf.tol is not None and estimate > frf.tol:
        reasons.append(f"its estimated error {estimate:.2g} exceeds tol {frf.tol:g}")
    interior = not (at_edge or at_stop)
    frf._peak = Peak(w, a, interior=interior, converged=not reasons, estimate=estimate, message="; ".join(reasons))
    return frf._peak


def _locate_on(f: FrequencyResponse, i: int) -> tuple[cont.Located | None, int]:
    """The zero of d(a^2)/ds near point ``i`` of the single-balance result ``f`` (None where there is
    none between its neighbours), and the Newton updates spent."""
    pr = f._problem
    pr.fresh_omega_derivative = True
    counter = cont._Count()
    y = f._run.y
    c, s_ = pr.response_components()

    def slope(u, t):  # proportional to d(a^2)/ds along the branch
        return u[c] * t[c] + u[s_] * t[s_]

    try:
        xtol = PEAK_XTOL_FACTOR * math.sqrt(f.rtol)
        for ja, jb in ((i - 1, i + 1), (i - 1, i), (i, i + 1)):
            loc = cont.locate(pr, y[ja], y[jb], slope, tol=f.newton_tol, scale=f._scale, xtol=xtol, count=counter)
            if loc is not None:
                return loc, counter.nit
        return None, counter.nit
    finally:
        pr.fresh_omega_derivative = False
