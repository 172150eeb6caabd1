"""Error estimates of a frequency response, point by point and source by source.

Each source is a relative error of the response DOF's first-harmonic amplitude against the true
periodic response of the physical system, at the point's frequency (``docs/validation.md``,
"Error estimates", derives them and checks them against the references):

- ``harmonics``: the harmonics the balance leaves out.  Condensed form: one Newton step of the
  balance at ``2H + 1`` harmonics from the converged point padded with zeros (the residual's
  new harmonics are the missing response, to first order, and the step carries their effect
  back into the first harmonic); a first-harmonic element (no time law) takes part in that step by
  its stand-in with a time law (``ContactElement.harmonics_law``).  One-DOF form (a describing
  function, no time law, no stand-in): the element's own loop gives its force harmonics ``F_h``
  (``hysteresis``), the blade's dynamic stiffness at ``h omega`` the missing response ``X_h``, and
  the element's stuck stiffness ``k*`` bounds their effect on the first harmonic,
  ``|dX_1| <= k* sum |X_h| / s_min(J)``.  Where neither exists (the rigid slider: no stand-in, and
  ``k*`` infinite) the source cannot be estimated and reads inf, which the call's warning says.
- ``sampling``: the AFT's samples: the largest step, over time grids shifted by fractions of a sample,
  from the balance on one grid to the balance on their union, a Newton step with the union's Jacobian
  (``_sampling_condensed``); zero where every element declares ``exact_harmonics`` (its harmonic force
  uses no samples) and in the one-DOF form (a describing function).
- ``element``: the error of the elements' evaluation at ``rtol``: the balance's residual with the
  elements evaluated again at ``ELEMENT_TIGHTEN * rtol``, less the residual at ``rtol``, through
  the balance (one Newton step); at least ``ROUNDING``.  Where that evaluation fails, the bound
  ``rtol`` (one DOF: errors ``rtol |p|``, ``rtol |q|`` of the element's stiffness ``p + i q``); an
  answer of the wrong type or shape (``ElementContractError``) is raised at once, as during the trace.
- ``model``: the element's error against the physical contact it stands for
  (``ContactElement.model_error``: the validity map of the single-mode bars), through the balance:
  ``|dX_1| <= e |F_1| / s_min(J)``; 0 for an element exact for what it models, whatever its ``k*``
  (``_coefficient_error``).
- ``peak``: the error of the peak's location.  At the sampled maximum and its two neighbours
  (the peak lies between them) the parabola through the three points, in the frequency (in the
  chord length along the branch across a fold), bounds how far the peak rises above the sampled
  maximum: ``PEAK_SAFETY (a_v - a_i) / a_v`` with ``a_v`` its vertex (:func:`peak_location`),
  plus the Newton tolerance's part; at every other point (and at a maximum at an end of the branch, which is the peak as
  sampled) that part alone: ``NEWTON_SHARE * rtol`` relative to the scale the residual is measured in, the
  larger of the static deflection and the contact DOFs' first harmonics (:func:`newton_part`).

The estimate's element evaluations are counted in the result's ``nfev``.  ``J`` is the balance's Jacobian in the unknowns of the point (frequency fixed) and ``s_min`` its
smallest singular value: a force error ``dF`` moves the response by at most ``|dF| / s_min``.
The estimates are computed at ``NODES`` points spread along the branch, the sampled maximum and
its neighbours, and interpolated between them in the branch's order; ``error_estimate`` is their
sum.
"""

from __future__ import annotations

import contextlib
import math
import re
import warnings
from typing import Any, Iterator

import numpy as np
from numpy.typing import NDArray

from contact_models.accuracy import AccuracyWarning
from contact_models.base import ContactElement, default_samples

from .._steps import RESIDUAL_RAISED_AT_ONCE
from ..structure import Contact
from .residual import HarmonicBalance, first_harmonic_sizes

#: The sources of error, in the order of ``FrequencyResponse.error_sources``.
SOURCES = ("harmonics", "sampling", "element", "model", "peak")
#: Points along the branch at which the estimates are computed (plus the maximum and its neighbours).
NODES = 24
#: At this H and below (a structure's balance at few harmonics, where ``frequency_response`` decides
#: which windows need more), the harmonics source is computed at every point, not interpolated between
#: nodes: a superharmonic resonance can be narrower than the nodes' spacing (the 3-DOF Jenkins chain at
#: 0.62 rad/s, H = 3: 2.2e-4 interpolated, true error 1.6e-3), and at 2H + 1 = 7 harmonics the step is cheap.
EVERY_POINT_HARMONICS = 3
#: The harmonics source steps as many rungs of the ladder H -> 2H + 1 above the balance's H as its elements
#: reach (``ContactElement.harmonics_reach``), the rungs beyond the first up to the top of the ladder a curve
#: is refined to.  A superharmonic resonance of an element's own dynamics is seen only from a balance that
#: holds its order: the default blade with the bar of every mode at H = 3 read 4.6e-4 by the step to 7
#: harmonics near its peak, where the 13th harmonic meets a mode of the bar and moves the response by 1.4 %
#: (the step to 15 reads 1.5e-2).
REACH_TOP = 31
#: The sampling source is the largest change of the response, at each point, from the balance on the time
#: grid shifted by each of ``k / SAMPLING_SHIFTS`` of a sample to the balance on the union of these grids
#: (``SAMPLING_SHIFTS n_t`` samples).  A law with a kink (a gap closing, a slider sticking) aliases by an
#: error that falls like n_t^-2 on the whole but swings with where its kinks fall between the samples,
#: from point to point along the branch and between the points: read at the points as the step to
#: 2 n_t and interpolated between nodes it can be 1/19 of the true error (a one-DOF gap at H = 31,
#: n_t = 512).  The shifted grids read the swing's amplitude wherever the kinks fall.
SAMPLING_SHIFTS = 4
#: Samples of the element's loop for its force harmonics (one-DOF form).
LOOP_SAMPLES = 64
#: Highest harmonic of the loop counted (one-DOF form).
LOOP_HARMONICS = 9
#: The refined peak is accepted within this many rtol of the sampled maximum (``FrequencyResponse.peak``).
PEAK_ACCEPT = 10.0
#: The peak's estimate is the largest point estimate within this many points of the sampled maximum
#: (:func:`peak_estimate`).
PEAK_SPREAD = 2
#: Every point solves the balance to this fraction of rtol in its scaled residual (``hbm.frf.NEWTON_TOL_FACTOR``):
#: the relative amplitude error a converged point may carry, the peak source away from the maximum.
NEWTON_SHARE = 5e-3
#: The Newton part is the amplitude change of the Newton step a point's residual still asks where that exceeds the
#: tolerance's part and the point's other sources by more than this factor (the estimate is held to under-read by at
#: most 2x: ``newton_part``).
NEWTON_SLACK = 2.0
#: The peak source is this many times the parabola's rise above the sampled maximum: the parabola is exact
#: to leading order in the spacing, and the next order (the peak's asymmetry) makes it under-read by up to
#: 22 % on the default case and 0.1 % on the bare blade (``docs/error_estimates.md``, "peak").
PEAK_SAFETY = 2.0
#: The element source: the elements are evaluated again at this fraction of rtol; the change of the
#: balance's residual is their error at rtol (to first order, for an error that falls at least
#: linearly with the tolerance: at rtol/100 it is <= 1/100 of the one at rtol).
ELEMENT_TIGHTEN = 1e-2
#: Floor of the element source (relative): the rounding of an element exact to rounding, through the balance.
ROUNDING = 1e-13
#: What an element evaluation that cannot be repeated at the tighter tolerance raises: the bound rtol is kept.
#: Not ``RESIDUAL_RAISED_AT_ONCE`` (an ``ElementContractError`` is a ValueError): a defect of the element's code,
#: or a warning the caller made an error, is raised on at once, as during the trace.
_FAILED = (ValueError, ArithmeticError, np.linalg.LinAlgError)


@contextlib.contextmanager
def collected() -> Iterator[list[str]]:
    """Record the ``AccuracyWarning`` messages said in the block (an element may warn at every
    evaluation) into the yielded list, to be said once by the caller; every other warning is said
    again after the block as it was (the caller's filters apply; one from the same line once)."""
    heard: list[str] = []
    caught: list = []
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", AccuracyWarning)
            yield heard
    finally:
        registry: dict = {}
        for w in caught:
            if issubclass(w.category, AccuracyWarning):
                heard.append(str(w.message))
            else:
                warnings.warn_explicit(w.message, w.category, w.filename, w.lineno, registry=registry,
                                       source=w.source)


#: How the elements' warnings state their own relative error (``AllModeMicroslip``; the validity
#: map's ``ModelRangeWarning`` in percent): the worst of a solve's warnings is the one quoted.
_STATED = (re.compile(r"relative error ([0-9.]+(?:e[-+]?[0-9]+)?)"), re.compile(r"off by about ([0-9.]+)%"))


def stated_error(message: str) -> float:
    """The relative error an element's warning states, 0 if it states none."""
    m = _STATED[0].search(message)
    if m is not None:
        return float(m.group(1))
    m = _STATED[1].search(message)
    return 0.01 * float(m.group(1)) if m is not None else 0.0


def heard_line(heard: list[str], where: str) -> str:
    """``"the elements warned N time(s) <where>; the worst: ..."``."""
    return f"the elements warned {len(heard)} time(s) {where}; the worst: {max(heard, key=stated_error)}"


def nodes(amplitude: NDArray) -> NDArray[np.intp]:
    """Indices where the estimates are computed: ``NODES`` spread along the branch, the maximum
    and its neighbours."""
    n = len(amplitude)
    if n == 0:
        return np.empty(0, dtype=np.intp)
    i = int(np.argmax(amplitude))
    idx = np.round(np.linspace(0, n - 1, min(NODES, n))).astype(np.intp)
    return np.unique(np.concatenate([idx, [max(i - 1, 0), i, min(i + 1, n - 1)]]))


def onsets(problem: HarmonicBalance, X: NDArray, omega: NDArray, idx: NDArray) -> NDArray[np.intp]:
    """The points either side of each onset of slip along the branch: where a contact's motion amplitude
    crosses its element's ``linear_amplitude`` (taken at the nodes ``idx``, linear in between), for the
    elements with a model error (those exact for what they model have none to interpolate).  The
    model source has a kink there (the stuck stiffness's error, growing towards a resonance, gives way
    to the slipping bar's), which interpolation between nodes on either side can miss by a factor of 2
    (``docs/validation.md``, "Error estimates")."""
    out: list[int] = []
    n = len(omega)
    if n < 2 or len(idx) < 1:
        return np.empty(0, dtype=np.intp)
    for e, (el, comps) in enumerate(problem._attach):
        if not _has_model_error(el, comps):
            continue  # a contact with a normal direction (its onset is not one amplitude), or an exact element
        rel = problem.relative_motion(e, X)[:, 0]
        a = np.hypot(rel[:, 1], rel[:, 2])
        a_lin = np.interp(np.arange(n), idx, [float(el.linear_amplitude(float(omega[j]))) for j in idx])
        flips = np.flatnonzero(np.diff((a > a_lin).astype(np.int8)) != 0)
        out += [int(i) for f in flips for i in (f, f + 1)]
    return np.unique(np.asarray(out, dtype=np.intp))


def estimate(problem: HarmonicBalance, X: NDArray, omega: NDArray, rtol: float,
             steps: NDArray | None = None) -> dict[str, NDArray]:
    """``{source: relative error per point}`` for the converged points ``X`` (points, n_a, 2H+1),
    ``omega`` (points,) of ``problem``'s balance; ``steps`` as :func:`newton_part` takes them."""
    n = len(omega)
    out = {s: np.zeros(n) for s in SOURCES}
    if n == 0:
        return out
    amplitude = np.hypot(X[:, problem.dofs.index(problem.response_dof), 1],
                         X[:, problem.dofs.index(problem.response_dof), 2])
    idx = nodes(amplitude)
    idx = np.union1d(idx, onsets(problem, X, omega, idx))
    at = _one_dof if problem.one_dof else _condensed
    values = at(problem, X[idx], omega[idx], rtol)
    every = not problem.one_dof and 1 < problem.H <= EVERY_POINT_HARMONICS
    if not problem.one_dof and not every:
        values["harmonics"] = _harmonics_condensed(problem, X[idx], omega[idx], rtol)
    for s, v in values.items():
        out[s] = np.interp(np.arange(n), idx, v) if len(idx) > 1 else np.full(n, v[0])
    if every:  # at few harmonics, where the windows are decided: at every point, not interpolated
        out["harmonics"] = _harmonics_condensed(problem, X, omega, rtol)
    if not problem.one_dof and not all(el.exact_harmonics for el, _ in problem._attach):
        out["sampling"] = _sampling_condensed(problem, X, omega, rtol)  # at every point, not interpolated
    others = np.sum([out[s] for s in SOURCES if s != "peak"], axis=0)
    out["peak"] = peak_location(amplitude, omega, newton_part(problem, X, rtol, steps, others))
    return out


def peak_estimate(estimate: NDArray, i: int) -> float:
    """The estimated error of the peak found at the sampled maximum ``i``: the largest of the point estimates
    ``estimate`` within ``PEAK_SPREAD`` points of it.

    Each point's estimate reads the error at that point.  Where the error oscillates along the curve faster
    than the points follow it (a bar truncated in cells and harmonics: a harmonic of the drive meeting one
    of its modes moves the response up and down from one point to the next), the maximum is the point whose
    error happens to be upward, chosen because it is: its own reading is one phase of the oscillation, which
    may be near a zero of it, and the envelope of the readings near it bounds what the choice can gain (on
    the all-mode bar at heavy loads the reading at the maximum was a quarter of the peak's true error, the
    readings two points away held it; ``docs/error_estimates.md``).  NaN without an estimate."""
    if len(estimate) == 0:
        return math.nan
    lo, hi = max(i - PEAK_SPREAD, 0), min(i + PEAK_SPREAD + 1, len(estimate))
    near = np.asarray(estimate[lo:hi], dtype=float)
    near = near[~np.isnan(near)]  # (a point without an estimate has none to lend; a failed one, inf, is kept)
    return float(np.max(near)) if len(near) and not math.isnan(estimate[i]) else float(estimate[i])


def newton_part(problem: HarmonicBalance, X: NDArray, rtol: float, steps: NDArray | None = None,
                others: NDArray | None = None) -> NDArray:
    """The Newton tolerance's part of each point's error, relative to the response DOF's amplitude ``a``: the
    tolerance's, below, or ``steps`` (per point the change of ``a`` that the Newton step its converged residual
    still asks would make, ``hbm.continuation.ContinuationResult.newton_step``) where that is more than
    ``NEWTON_SLACK`` times the tolerance's part and the point's ``others`` sources together (the estimate would
    under-read the point's error by more than that factor).

    The corrector stops at ``|R| <= NEWTON_SHARE rtol`` in the balance's scaled residual, which is the
    condensed residual over ``max(x_ref, |X_1|)`` (``HarmonicBalance.__call__``: the static deflection, or the
    first harmonics of the contact DOFs where they are larger).  With the balance's Jacobian about the
    identity in those units, a point is off by that tolerance times ``max(x_ref, |X_1|) / a``: the tolerance
    itself where the response is at least that scale, more where it is far below it (a tail far above
    resonance, a DOF that barely moves), inf where it is zero.  The one-DOF form's residual is a force
    relative to the load, of the response's own size: ``NEWTON_SHARE rtol`` at every point.

    Near a lightly damped resonance the Jacobian is far from the identity: a residual within the tolerance may
    leave the point up to ``|J^-1|`` times farther (about 1 / (2 zeta) at a damping ratio zeta).  The Newton
    step with the point's own Jacobian measures how far (its error after that step is of second order): at
    0.01 % damping, just past the slip onset at the peak, a point 5.0e-7 off read 5.0e-9 without it."""
    base = NEWTON_SHARE * rtol
    if problem.one_dof or len(X) == 0:
        return np.full(len(X), base)
    r = problem.dofs.index(problem.response_dof)
    a = np.hypot(X[:, r, 1], X[:, r, 2])
    scale = np.maximum(problem.x_ref, first_harmonic_sizes(X))
    with np.errstate(divide="ignore"):
        part = base * np.maximum(1.0, scale / a)
    if steps is None:
        return part
    bar = NEWTON_SLACK * (part if others is None else part + others)
    with np.errstate(invalid="ignore"):
        return np.where(steps > bar, steps, part)  # (NaN, a step not known: the tolerance's)


def peak_location(amplitude: NDArray, omega: NDArray, newton: Any) -> NDArray:
    """The peak source per point: ``newton`` (the Newton tolerance's part, relative: one number, or one per
    point, :func:`newton_part`) everywhere, and at the
    sampled maximum ``i`` and its neighbours, when ``i`` is inside the branch, ``newton`` plus
    ``PEAK_SAFETY (a_v - a_i) / a_v``: ``a_v`` the vertex of the parabola through the three points in the
    frequency (where it is monotonic over them; across a fold in the chord length along the branch,
    ``a / a_i`` and ``omega / omega_i`` its coordinates), which the
    true peak exceeds the sampled maximum by to leading order in the spacing (``docs/validation.md``,
    "Error estimates").

    Examples
    --------
    The bare blade (m = 1, k = 1e4, c = 2, F = 1) sampled at three frequencies: the middle one,
    100 rad/s, falls short of the resonance 1/(2 sqrt(1e4 - 1)) by 5.00e-5 (relative); the parabola
    gives 4.94e-5 of it, times ``PEAK_SAFETY``:

    >>> import numpy as np
    >>> w = np.array([99.9, 100.0, 100.1]); a = 1.0 / np.abs(1.0e4 - w**2 + 2.0j * w)
    >>> [round(float(v) / PEAK_SAFETY, 7) for v in peak_location(a, w, 0.0)]
    [4.94e-05, 4.94e-05, 4.94e-05]
    """
    n = len(amplitude)
    out = np.array(np.broadcast_to(np.asarray(newton, dtype=float), (n,)))
    if n < 3:
        return out
    i = int(np.argmax(amplitude))
    if not 0 < i < n - 1:
        return out  # a maximum at an end of the branch is the peak as sampled
    a = np.asarray(amplitude[i - 1:i + 2], dtype=float) / amplitude[i]
    w = np.asarray(omega[i - 1:i + 2], dtype=float) / omega[i]
    dw = np.diff(w)
    # the frequency where it is monotonic over the three points; across a fold the chord length
    ds = np.abs(dw) if dw[0] * dw[1] > 0.0 else np.hypot(np.diff(a), dw)
    if not np.all(ds > 0.0):
        return out
    s0, s2 = -ds[0], ds[1]  # the parabola a(s) = 1 + b s + c s^2 through (s0, a0), (0, 1), (s2, a2)
    d0, d2 = (a[0] - 1.0) / s0, (a[2] - 1.0) / s2
    c = (d2 - d0) / (s2 - s0)
    b = d0 - c * s0
    rise = -b * b / (4.0 * c) if c < 0.0 else 0.0  # a_v - a_i in units of a_i
    out[i - 1:i + 2] += PEAK_SAFETY * rise / (1.0 + rise)
    return out


def total(sources: dict[str, NDArray]) -> NDArray:
    """The estimate of all sources together: their sum (each is a bound of its own part)."""
    return np.sum([sources[s] for s in SOURCES], axis=0)


# ------------------------------------------------------------------ one DOF, describing function
def _one_dof(problem: HarmonicBalance, X: NDArray, omega: NDArray, rtol: float) -> dict[str, NDArray]:
    fresh = HarmonicBalance(problem.system, problem.contacts, harmonics=1, rtol=rtol)  # no shared caches
    tight = HarmonicBalance(problem.system, problem.contacts, harmonics=1, rtol=ELEMENT_TIGHTEN * rtol)
    el = fresh.element
    n = len(omega)
    out = {s: np.zeros(n) for s in ("harmonics", "element", "model")}
    if el is None:
        return out
    k_star = abs(float(el.linear_coefficients(0.0)[0]))
    proxies = _harmonic_proxies(problem, el, rtol)
    for j, (x, w) in enumerate(zip(X[:, 0], omega)):
        xc, xs, w = float(x[1]), float(x[2]), float(w)
        a = math.hypot(xc, xs)
        if a == 0.0 or a <= el.linear_amplitude(w):
            continue  # the element is linear: exact, no higher harmonics
        R, J = fresh.balance(xc, xs, w)
        Jx = np.array([[J[0], J[1]], [J[3], J[4]]])
        p, q = fresh.stiffness_terms(a, w)[:2]
        e_s, e_c = (float(v) for v in el.model_error(a, w, parts=True))
        # a change dp, dq of the element's stiffness is the force (x_c, x_s) dp + (x_s, -x_c) dq
        out["element"][j] = _element_one_dof(tight, R, Jx, xc, xs, w, rtol * abs(p), rtol * abs(q)) / a
        floor = 0.01 * k_star  # the validity map's floor of 0.01 k* a on each coefficient
        out["model"][j] = _amplitude_change(Jx, xc, xs, _coefficient_error(e_s, p, floor),
                                            _coefficient_error(e_c, q, floor)) / a
        while proxies:
            Xp = np.zeros((1, proxies[0].L))
            Xp[0, 1], Xp[0, 2] = xc, xs
            try:
                out["harmonics"][j] = abs(_truncation_step(proxies[0], Xp, w, 0, 1)) / a
                break
            except RESIDUAL_RAISED_AT_ONCE:
                raise
            except ValueError:  # the stand-in cannot resolve so many harmonics (too few cells): a rung lower
                if len(proxies) == 1:
                    raise
                _count(problem, proxies.pop(0))
        else:
            s_min = float(np.linalg.svd(Jx, compute_uv=False)[-1])
            out["harmonics"][j] = _loop_truncation(fresh, el, a, w) / (s_min * a)
    _count(problem, fresh, tight, *proxies)
    return out


def _element_one_dof(tight: HarmonicBalance, R: tuple, Jx: NDArray, xc: float, xs: float, w: float,
                     dp: float, dq: float) -> float:
    """``|da|`` (m) from the element's evaluation error: ``g . Jx^-1 (R_tight - R)`` with the
    balance's residual ``R`` at ``rtol`` and ``R_tight`` at ``ELEMENT_TIGHTEN rtol``; the bound from
    ``dp = rtol |p|``, ``dq = rtol |q|`` where the tighter evaluation fails."""
    a = math.hypot(xc, xs)
    try:
        Rt, _ = tight.balance(xc, xs, w)
        d = np.linalg.solve(Jx, np.subtract(Rt, R))
    except RESIDUAL_RAISED_AT_ONCE:
        raise
    except _FAILED:
        return _amplitude_change(Jx, xc, xs, dp, dq)
    da = abs(float(xc * d[0] + xs * d[1])) / a
    return max(da, ROUNDING * a) if math.isfinite(da) else _amplitude_change(Jx, xc, xs, dp, dq)


def _count(problem: HarmonicBalance, *helpers: HarmonicBalance | None) -> None:
    """The estimate's element evaluations join the problem's counters (``FrequencyResponse.nfev``)."""
    for h in helpers:
        if h is not None:
            problem.nfev += h.nfev
            problem.nstuck += h.nstuck


def _coefficient_error(e: float, coefficient: float, floor: float) -> float:
    """The error (N/m) of a first-harmonic stiffness ``coefficient`` (``p`` or ``q``) whose relative model error is
    ``e``, relative to ``max(|coefficient|, floor)`` (``ContactElement.model_error``; ``floor`` the validity map's
    0.01 k*): 0 where ``e`` is 0, whatever the floor.  An element exact for what it models has no model error
    also where its stuck stiffness k* is infinite (the rigid slider, ``Macroslip(math.inf, ...)``), where the
    product ``0 * max(|p|, 0.01 k*)`` would be ``0 * inf``, NaN.

    Examples
    --------
    >>> _coefficient_error(0.0, 0.0, math.inf), _coefficient_error(0.02, 3.0, 0.5), _coefficient_error(0.02, 0.1, 0.5)
    (0.0, 0.06, 0.01)
    """
    return 0.0 if e == 0.0 else float(e) * max(abs(float(coefficient)), float(floor))


def _amplitude_change(Jx: NDArray, xc: float, xs: float, dp: float, dq: float) -> float:
    """``|da|`` (m) from stiffness errors ``dp``, ``dq`` (signs unknown: their effects add); 0 for none."""
    if dp == 0.0 and dq == 0.0:
        return 0.0
    a = math.hypot(xc, xs)
    g = np.array([xc, xs]) / a
    try:
        Jinv = np.linalg.inv(Jx)
    except np.linalg.LinAlgError:
        return math.inf
    return abs(g @ Jinv @ np.array([xc, xs])) * dp + abs(g @ Jinv @ np.array([xs, -xc])) * dq


def _harmonic_proxies(problem: HarmonicBalance, el: Any, rtol: float) -> list[HarmonicBalance]:
    """The balances (condensed form) of the one-DOF system with the element's stand-in with a time law
    (``ContactElement.harmonics_law``: the element itself, or for a single-mode dynamic bar its
    quasi-static bar) at the harmonics its reach from H = 1 asks and the rungs below (``_steps``: 3, or
    15, 7, 3), farthest first; none where it has no stand-in."""
    law = el.harmonics_law()
    if law is None or not law.has_time_law:
        return []
    return [HarmonicBalance(problem.structure, [Contact(law, dof=0)], harmonics=H2, n_t=default_samples(H2), rtol=rtol)
            for H2 in _steps(1, [law])]


def _time_law_contacts(contacts: list) -> list | None:
    """``contacts`` (a balance's ``hbm.Contact`` list) for a balance above H = 1: as given where every element has a
    time law, else each first-harmonic element replaced by its stand-in (``ContactElement.harmonics_law``); None
    where an element has no stand-in with a time law (the rigid slider: no balance above H = 1 holds it).

    Examples
    --------
    >>> from contact_models import Macroslip
    >>> jen = [Contact(Macroslip(1.0, 0.5), dof=0)]
    >>> _time_law_contacts(jen) is jen, _time_law_contacts([Contact(Macroslip(math.inf, 0.5), dof=0)])
    (True, None)
    """
    if all(c.element.has_time_law for c in contacts):
        return contacts
    out = []
    for c in contacts:
        law = c.element if c.element.has_time_law else c.element.harmonics_law()
        if law is None or not law.has_time_law:
            return None
        out.append(c if law is c.element else c.with_element(law))
    return out


def _steps(H: int, elements: list) -> list[int]:
    """The harmonics the harmonics source tries, farthest first: ``reach`` and the rungs below it down to 2H + 1
    (an element refuses a balance of more harmonics than its own discretisation resolves).

    Examples
    --------
    >>> from contact_models import AllModeMicroslip, Bar, UniformLoad
    >>> bar = AllModeMicroslip(Bar(E=2e11, rho=7850.0, A=1e-5, L=0.05, k=8e8, beta=4e7, mu=0.3), UniformLoad(N=100.0))
    >>> _steps(1, [bar]), _steps(3, [bar])
    ([15, 7, 3], [31, 15, 7])
    """
    top, out = reach(H, elements), [2 * H + 1]
    while out[-1] < top:
        out.append(min(2 * out[-1] + 1, top))
    return out[::-1]


def reach(H: int, elements: list) -> int:
    """The harmonics the harmonics source of a balance of ``H`` reads the missing ones from: ``H -> 2H + 1``
    as many times as the elements reach (``ContactElement.harmonics_reach``), the steps beyond the first up to
    ``REACH_TOP``.

    Examples
    --------
    >>> from contact_models import AllModeMicroslip, Bar, Macroslip, UniformLoad
    >>> jen = Macroslip(stiffness=1.0, slip_force=1.0)
    >>> bar = AllModeMicroslip(Bar(E=2e11, rho=7850.0, A=1e-5, L=0.05, k=8e8, beta=4e7, mu=0.3), UniformLoad(N=100.0))
    >>> reach(3, [jen]), reach(3, [jen, bar]), reach(15, [bar]), reach(31, [bar])
    (7, 31, 31, 63)
    """
    H2 = 2 * H + 1
    for _ in range(max((el.harmonics_reach for el in elements), default=1) - 1):
        H2 = min(2 * H2 + 1, max(REACH_TOP, 2 * H + 1))
    return H2


def _loop_truncation(fresh: HarmonicBalance, el: Any, a: float, w: float) -> float:
    """``k* sum_h |X_h|`` (N): the element's higher force harmonics through the system at ``h omega``
    (an element with neither a time law nor a quasi-static bar: a bound).  Infinite where ``k*`` is (the
    rigid slider: its force is no Lipschitz function of the displacement, so the loop bounds nothing and the
    harmonics source cannot be estimated: inf, which the call's warning says); 0 where the loop has no
    higher harmonics."""
    _, f = el.hysteresis(a, w, n=LOOP_SAMPLES + 1)
    F = np.abs(np.fft.rfft(f[:-1])) * (2.0 / LOOP_SAMPLES)
    k_star = abs(float(el.linear_coefficients(0.0)[0]))
    missing = 0.0
    for h in range(2, min(LOOP_HARMONICS, len(F) - 1) + 1):
        wh = h * w
        Z = complex(fresh._k - fresh._m * wh * wh, fresh._c * wh)
        Zc = Z + complex(*(float(v) for v in el.linear_coefficients(wh)))
        missing += F[h] / max(min(abs(Z), abs(Zc)), 1e-300)
    return k_star * missing if missing > 0.0 else 0.0


# ------------------------------------------------------------------ condensed, AFT
def _condensed(problem: HarmonicBalance, X: NDArray, omega: NDArray, rtol: float) -> dict[str, NDArray]:
    H, n_t, L = problem.H, problem.n_t, problem.L
    kw = dict(response_dof=problem.response_dof, rtol=rtol)
    same = HarmonicBalance(problem.structure, problem.contacts, harmonics=H, n_t=n_t, **kw)
    sampled = not all(el.exact_harmonics for el, _ in same._attach)  # (its source: ``_sampling_condensed``)
    # elements exact to rounding at every H (``exact_harmonics``) ignore rtol: their source is the floor
    tight = HarmonicBalance(problem.structure, problem.contacts, harmonics=H, n_t=n_t, response_dof=problem.response_dof,
                            rtol=ELEMENT_TIGHTEN * rtol) if sampled else None
    r = problem.dofs.index(problem.response_dof)
    n = len(omega)
    out = {s: np.zeros(n) for s in ("sampling", "element", "model")}  # the harmonics, sampling: their own functions
    known = _model_errors(same, X, omega)
    # elements exact at every H with no model error: no balance at the nodes would change a number
    exact = not sampled and not any(_has_model_error(el, comps) for el, comps in same._attach)
    for j, (x, w) in enumerate(zip(X, omega)):
        w = float(w)
        a = math.hypot(x[r, 1], x[r, 2])
        if a == 0.0:
            continue
        if exact:
            out["element"][j] = ROUNDING
            continue
        R, J = same._condensed(x, w)
        Jx = J[:, :-1]
        out["element"][j] = ROUNDING if tight is None else _element_condensed(tight, R, Jx, x, w, r, L, rtol)
        out["model"][j] = _model(problem, same, x, w, Jx, {c: (e_s[j], e_c[j]) for c, (e_s, e_c) in known.items()}) / a
    _count(problem, same, tight)
    return out


def _harmonics_condensed(problem: HarmonicBalance, X: NDArray, omega: NDArray, rtol: float) -> NDArray:
    """The harmonics source (condensed form) at the points ``X`` (points, n_a, 2H+1), ``omega``: one
    Newton step of the balance at as many rungs of the ladder above H as the elements reach
    (``ContactElement.harmonics_reach``: 2H + 1 for one, 4H + 3 for two; beyond the first at most
    ``REACH_TOP``) from each point padded with zeros.  A first-harmonic element (no time law: the balance is at
    H = 1) takes part in that balance by its stand-in with a time law (``ContactElement.harmonics_law``, as in
    the one-DOF form); where one has none (the rigid slider) the source cannot be estimated: inf at every
    point that moves, which the call's warning says.  Without contacts the balance is linear and no harmonic
    above the first is excited: zero.  A harmonic above H exactly on a natural frequency of the undamped
    structure (its compliance infinite) makes the error unbounded: inf at that point."""
    H, L = problem.H, problem.L
    if not problem._attach:
        return np.zeros(len(omega))
    r = problem.dofs.index(problem.response_dof)
    contacts = _time_law_contacts(problem.contacts)
    if contacts is None:
        return np.array([math.inf if math.hypot(x[r, 1], x[r, 2]) > 0.0 else 0.0 for x in X])
    steps = _steps(H, [el for el, _ in problem._attach] if contacts is problem.contacts else
                   [c.element for c in contacts])
    for k, H2 in enumerate(steps):
        more = HarmonicBalance(problem.structure, contacts, harmonics=H2,
                               n_t=max(problem.n_t, default_samples(H2)), response_dof=problem.response_dof, rtol=rtol)
        out = np.zeros(len(omega))
        try:
            for j, (x, w) in enumerate(zip(X, omega)):
                a = math.hypot(x[r, 1], x[r, 2])
                if a == 0.0:
                    continue
                Xp = np.zeros((problem.na, 2 * H2 + 1))
                Xp[:, :L] = x
                try:
                    out[j] = abs(_truncation_step(more, Xp, float(w), r, H)) / a
                except ZeroDivisionError:  # on an undamped pole (Condensed._poles)
                    out[j] = math.inf
        except RESIDUAL_RAISED_AT_ONCE:
            raise
        except ValueError as e:  # an element that cannot resolve so many harmonics (too few cells): a rung lower
            if k < len(steps) - 1:
                continue
            warnings.warn(f"the harmonics a balance of H = {H} leaves out are not in the estimate: at {H2} harmonics "
                          f"{e}", AccuracyWarning, stacklevel=2)
            return out  # (zero: the call's warning says they are left out, with the element's reason)
        finally:
            _count(problem, more)
        return out
    raise AssertionError("unreachable: the last step returns")


def _sampling_condensed(problem: HarmonicBalance, X: NDArray, omega: NDArray, rtol: float) -> NDArray:
    """The sampling source (condensed form) at the points ``X`` (points, n_a, 2H+1), ``omega``: the largest
    amplitude change of one Newton step from the balance on the time grid shifted by ``k / SAMPLING_SHIFTS``
    of a sample (k = 0, 1, ...) to the balance on their union, ``SAMPLING_SHIFTS n_t`` samples, at each point.
    A shifted grid's residual is the residual at the point shifted in time by that much, shifted back:
    ``R_k(X) = S(-phi) R(S(phi) X) + (S(-phi) - 1) X_lin`` (``S(phi)`` turns harmonic h by ``h phi``; the
    structure's part commutes with it, the force ``X_lin`` does not).

    The step is taken with the union's Jacobian, the one its residual comes with: from the point (converged on
    the grid k = 0) it is the first Newton iterate of the better-resolved balance.  A sampled law with a kink
    has a Jacobian that jumps as samples cross the kink, by about the kink's share of one sample; near a fold,
    where the smallest singular value of ``J`` falls to that size, the point's own grid can state the
    response's sensitivity several times too stiff, and a step through it reads the error short by as much.
    The union's jumps are ``SAMPLING_SHIFTS`` times smaller (``docs/error_estimates.md``, "At a fold")."""
    kw = dict(response_dof=problem.response_dof, rtol=rtol)
    H, L = problem.H, problem.L
    same = HarmonicBalance(problem.structure, problem.contacts, harmonics=H, n_t=problem.n_t, **kw)
    union = HarmonicBalance(problem.structure, problem.contacts, harmonics=H, n_t=SAMPLING_SHIFTS * problem.n_t, **kw)
    r = problem.dofs.index(problem.response_dof)
    h = np.arange(1, H + 1)
    out = np.zeros(len(omega))
    for j, (x, w) in enumerate(zip(X, omega)):
        w = float(w)
        a = math.hypot(x[r, 1], x[r, 2])
        if a == 0.0:
            continue
        R0 = same._condensed(x, w)[0]
        Ru, Ju = union._condensed(x, w)
        Jx = Ju[:, :-1]  # the better-resolved balance's own Jacobian (docstring)
        xl = same.cond.at(w)[2]
        lin = np.zeros((problem.na, L))
        lin[:, 1], lin[:, 2] = xl.real, -xl.imag
        dR = [Ru - R0]
        for k in range(1, SAMPLING_SHIFTS):
            phi = 2.0 * math.pi * k / (SAMPLING_SHIFTS * problem.n_t)
            Rk = _turned(same._condensed(_turned(x, h * phi), w)[0].reshape(problem.na, L) + lin, -h * phi) - lin
            dR.append(Ru - Rk.ravel())
        try:  # the Newton steps Jx dX = -dR of every shift, one factorisation
            dX = np.linalg.solve(Jx, -np.column_stack(dR))
        except np.linalg.LinAlgError:
            dX = np.linalg.lstsq(Jx, -np.column_stack(dR), rcond=None)[0]
        out[j] = float(np.max(np.abs(x[r, 1] * dX[r * L + 1] + x[r, 2] * dX[r * L + 2]))) / (a * a)
    _count(problem, same, union)
    return out


def _turned(x: NDArray, angle: NDArray) -> NDArray:
    """Coefficients ``x`` (n_a, 2H+1) of ``x(theta)`` turned to those of ``x(theta + phi)``: harmonic h by
    ``angle[h - 1] = h phi``."""
    c, s = x[:, 1::2], x[:, 2::2]
    co, si = np.cos(angle), np.sin(angle)
    out = x.copy()
    out[:, 1::2], out[:, 2::2] = c * co + s * si, s * co - c * si
    return out


def _element_condensed(tight: HarmonicBalance, R: NDArray, Jx: NDArray, x: NDArray, w: float, r: int, L: int,
                       rtol: float) -> float:
    """The relative amplitude change from the elements' evaluation error: one Newton step driven by
    the residual at ``ELEMENT_TIGHTEN rtol`` less the one at ``rtol`` (``R``); ``rtol`` where the
    tighter evaluation fails."""
    try:
        Rt, _ = tight._condensed(x, w)
        da = abs(_amplitude_step(Jx, Rt - R, x, r, L)) / math.hypot(x[r, 1], x[r, 2])
    except RESIDUAL_RAISED_AT_ONCE:
        raise
    except _FAILED:
        return rtol
    return max(da, ROUNDING) if math.isfinite(da) else rtol


def _truncation_step(big: HarmonicBalance, Xp: NDArray, w: float, r: int, H: int) -> float:
    """The response amplitude's change (m) in one Newton step of the balance ``big`` (more harmonics)
    from ``Xp``, driven by the residual of the harmonics above H only (the first H are converged)."""
    R, J = big._condensed(Xp, w)
    L2 = Xp.shape[1]
    R = R.reshape(-1, L2)
    R[:, :2 * H + 1] = 0.0
    return _amplitude_step(J[:, :-1], R.ravel(), Xp, r, L2)


def _amplitude_step(Jx: NDArray, R: NDArray, x: NDArray, r: int, L: int) -> float:
    """The response amplitude's change (m) in the Newton step ``Jx dX = -R`` from ``x``."""
    try:
        dX = np.linalg.solve(Jx, -R)
    except np.linalg.LinAlgError:
        dX = np.linalg.lstsq(Jx, -R, rcond=None)[0]
    a = math.hypot(x[r, 1], x[r, 2])
    return float(x[r, 1] / a * dX[r * L + 1] + x[r, 2] / a * dX[r * L + 2])  # (the unit vector first: no overflow)


def _has_model_error(el: Any, comps: list) -> bool:
    """Whether the contact ``el`` on the components ``comps`` has a model source: one direction (a contact with
    a normal direction is exact for what it models) and its own ``_model_error`` (the base's is zero)."""
    return len(comps) == 1 and type(el)._model_error is not ContactElement._model_error


def _model_errors(same: HarmonicBalance, X: NDArray, omega: NDArray) -> dict[int, tuple[NDArray, NDArray]]:
    """``{contact index: (e_s, e_c)}`` at every point of ``X`` (points, n_a, 2H+1), ``omega`` for the contacts with
    a model error (one direction): each element asked once for all points, which it may spread over threads
    (``AllModeMicroslip``); ``_model`` reads them."""
    out = {}
    for c, (el, comps) in enumerate(same._attach):
        if not _has_model_error(el, comps):
            continue
        a = np.array([math.hypot(*(float(v) for v in same.relative_motion(c, x)[0, 1:3])) for x in X])
        e_s, e_c = (np.zeros(len(a)) for _ in range(2))
        some = a > 0.0
        if np.any(some):
            e_s[some], e_c[some] = el.model_error(a[some], np.asarray(omega, dtype=float)[some], parts=True)
        out[c] = (e_s, e_c)
    return out


def _model(problem: HarmonicBalance, same: HarmonicBalance, x: NDArray, w: float, Jx: NDArray,
           known: dict | None = None) -> float:
    """The response amplitude's change (m) from each contact's model error ``e`` as errors
    ``e_s max(|p|, 0.01 k*)``, ``e_c max(|q|, 0.01 k*)`` of its first-harmonic stiffness, through the
    condensed balance (``R = X + G F``, so ``dR = G dF``); the contacts' effects add.  ``known``: the
    errors ``(e_s, e_c)`` of contacts (by index) at this point, asked for before (``_model_errors``)."""
    G1 = same.cond.at(w)[0][1]
    L, na = same.L, same.na
    r = same.dofs.index(same.response_dof)
    total = 0.0
    for c, (el, comps) in enumerate(same._attach):
        if len(comps) > 1:  # a contact with a normal direction is exact for what it models
            continue
        ix = comps[0]
        Xrel = same.relative_motion(c, x)[0]
        xc, xs = float(Xrel[1]), float(Xrel[2])
        a_c = math.hypot(xc, xs)
        if known is not None and c in known:
            e_s, e_c = (float(v) for v in known[c])
        else:
            e_s, e_c = (float(v) for v in el.model_error(a_c, w, parts=True)) if a_c > 0.0 else (0.0, 0.0)
        if e_s == e_c == 0.0:
            continue
        Fc, Fs = el.harmonic_force_unchecked(np.ascontiguousarray(Xrel), w, same.n_t, same.rtol, False)[0][1:3]
        p, q = (Fc * xc + Fs * xs) / a_c**2, (Fc * xs - Fs * xc) / a_c**2
        floor = 0.01 * abs(float(el.linear_coefficients(0.0)[0]))
        for dk, direction in ((_coefficient_error(e_s, p, floor), (xc, xs)),
                              (_coefficient_error(e_c, q, floor), (xs, -xc))):
            if dk == 0.0:
                continue
            dF = np.zeros(na, dtype=complex)  # the force error's first harmonic c = Fc - i Fs on the DOFs
            # on p of a contact to the next sector: the previous sector's, leading by phi
            first = complex(math.cos(same._angle), math.sin(same._angle)) if same._next[c] else 1.0
            for i, sign in zip(ix, (first, -1.0)):
                dF[i] += sign * dk * complex(direction[0], -direction[1])
            dR = np.zeros((na, L))
            gdF = G1 @ dF
            dR[:, 1], dR[:, 2] = gdF.real, -gdF.imag
            total += abs(_amplitude_step(Jx, dR.ravel(), x, r, L))
    return total


__all__ = ["SOURCES", "NODES", "NEWTON_SHARE", "newton_part", "PEAK_SAFETY", "PEAK_SPREAD", "peak_estimate", "estimate", "total",
           "peak_location", "nodes", "onsets", "collected", "stated_error", "heard_line"]
