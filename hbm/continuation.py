"""Pseudo-arclength continuation of a curve ``R(y) = 0``, ``R: R^n -> R^(n-1)``.

The core knows nothing of friction or harmonic balance: it sees ``residual(y) -> (R, J)``
with ``J = dR/dy`` of shape ``(n-1, n)``.  Keller's method (H. B. Keller 1977; E. L.
Allgower & K. Georg, *Introduction to Numerical Continuation Methods*, SIAM 2003, ch. 2, 6):

1. tangent ``t``: ``J t = 0``, ``|t| = 1``, oriented so that ``t . t_prev > 0`` (at the start:
   the parameter component has the sign of ``direction``);
2. predictor ``y_p = y_i + h t + h^2 c_2 + h^3 c_3``: the cubic Hermite extrapolation through
   ``y_{i-1}``, ``y_i`` and their tangents (the tangent predictor at the start and after a corner);
3. corrector: Newton on ``[R(y); t . (y - y_p)] = 0`` (the pseudo-arclength constraint);
4. step control: ``h <- h * min(NEWTON_TARGET / iterations, MAX_TURN / turn, f_curve)``, the
   factor kept in ``[MIN_FACTOR, MAX_FACTOR]`` and ``h`` in ``[min_step, max_step]``; ``turn`` is the
   angle between successive tangents.  With ``curve_tol``, ``f_curve = SAFETY (e*/e)^(1/q)`` controls
   the local error like an ODE solver's error per step: ``e`` is the miss, at the corrected point,
   of the cubic through the last four points of the smooth piece (positions only, by chord length;
   before four points exist, of the predictor), in the ``curve_components``, scaled; ``q = 4`` (2 for
   the tangent predictor), ``e* = PREDICTOR_SHARE curve_tol``.  A step with ``e > REJECT_CURVE e*``
   is retried shorter, at most ``CURVE_RETRIES`` times running, then accepted and listed in
   ``coarse`` (a corner, where the error does not fall with the step).  A failed corrector, or a
   turn above ``REJECT_TURN`` (a likely
   jump to another branch), retries with ``h * FAIL_FACTOR``; a turn that does not shrink with
   the step is a corner (the branch of a piecewise-smooth residual) and is accepted; when the
   tangent at a failed predictor has turned that much (after ``CORNER_AFTER`` failures in a row, or as
   many showing the corner while shorter steps creep towards it),
   the corrector tries again from the
   same predictor on the hyperplane normal to the bisector of the old tangent and the new piece's
   (it crosses both pieces), the new piece's tangent oriented by the sign of ``det [J; t]``, which
   a branch keeps across the kinks of a continuous piecewise-smooth residual (Allgower & Georg
   ch. 12): so a corner fold, where the branch turns back by more than 90 degrees and no
   hyperplane normal to the old tangent ahead of the corner meets it, is passed too; a retry at
   a shorter step keeps that bisector's hyperplane;
5. folds (turning points in the parameter): the parameter component of ``t`` changes sign;
   each is then located by :func:`locate` on the stretch between the two points.

Optional scaling: ``scale(y)`` returns positive weights ``s``; the geometry of step ``i``
(tangent, step length, turn, constraint) is measured in ``u = y / s(y_i)``.

A failure (step below ``min_step``, the first point not converging, an exception raised by
``on_point``, or by the residual after the first point) ends the branch with a ``message`` and every
point computed so far; reaching the end of the parameter range puts the last point exactly on the bound.  A run
that starts on a bound (``from_bound``) and leaves the range through that same bound turned back
(``Status.TURNED_BACK``): the range beyond the turn was never traced, which is not success.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import IntEnum
from typing import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from contact_models.numerics.checks import ElementContractError, count as _whole, finite, flag, positive, shown
from contact_models.numerics.roots import brentq  # scipy's algorithm without importing scipy.optimize
from contact_models.numerics.small import lagrange

from ._steps import (MAX_BEND, MAX_CONTRACTION, REJECT_TURN, RESIDUAL_ERRORS, OutsideDomain,  # noqa: F401
                     _corner_normal, _Count, _counted, _hermite, _Newton, _newton, _norm, _orientation, _rescale, _scale, _tangent)
from ._steps import RAISED_BY, RESIDUAL_RAISED_AT_ONCE, _fixed_step, _told

#: Newton iterations (updates) per corrector before the step counts as failed.
NEWTON_MAX_ITER = 8
#: Corrector iterations the step-size control aims at.
NEWTON_TARGET = 3.0
#: Target angle (rad) between successive tangents (curvature control).
MAX_TURN = 0.12
#: A large turn that shrinks by less than this factor when the step is halved is a corner of a
#: piecewise-smooth branch (e.g. the onset of slip), not a jump: the step is then accepted.
CORNER_RATIO = 0.8
#: A corrected point farther than this many steps from its predictor, the tangent turning by at most
#: ``REJECT_TURN``, is a jump to another branch (``_Trace._judge``); the step is retried shorter.
JUMP_RATIO = 1.0
#: At a corner whose tangent turned by less than 60 degrees (``|t_new . t|`` at least this) the new tangent points
#: forward along the old one; nearer 90 degrees the determinant's orientation decides (``_Trace._oriented``).
ORIENT_DOT = 0.5
#: Failed correctors in a row at one point before a corner is rounded (a shorter step resolves
#: most failures; those that persist are the corners a shorter step only creeps towards).  Where the
#: shorter steps converge, each a little nearer a corner the failed predictors' Jacobians show, the
#: failures count on until a step as long as the longest of those is accepted (``_Trace.creep``).
CORNER_AFTER = 3
#: Two candidate tangents of a corner with ``|t1 . t2|`` above this are the same direction.
CORNER_SAME = 0.999
#: Bounds of the step-size factor after an accepted step.
MIN_FACTOR = 0.3
MAX_FACTOR = 2.0
#: Step-size factor after a rejected step.
FAIL_FACTOR = 0.5
#: Default first step as a fraction of ``max_step``.
FIRST_STEP = 0.25
#: Error per step (``curve_tol``): target predictor error over curve_tol, the safety factor, the
#: rejection threshold (over the target) and the shorter retries allowed in a row (docs/hbm.md).
PREDICTOR_SHARE = 4.0
SAFETY = 0.8
REJECT_CURVE = 4.0
CURVE_RETRIES = 3

#: ``residual(y) -> (R, J)``: R of shape (n-1,), its Jacobian dR/dy of shape (n-1, n).
Residual = Callable[[NDArray[np.float64]], tuple[NDArray[np.float64], NDArray[np.float64]]]
#: ``scale(y) -> s``: positive weights, one per component of y.
Scale = Callable[[NDArray[np.float64]], NDArray[np.float64]]


class Status(IntEnum):
    """How a branch ended (``success`` is ``status == REACHED_END``): an int that prints as its name.

    Examples
    --------
    >>> print(Status.CALLBACK_RAISED)
    Status.CALLBACK_RAISED
    >>> Status.CALLBACK_RAISED == -4, f"{Status.CALLBACK_RAISED:d}"
    (True, '-4')
    """

    def __str__(self) -> str:  # (an IntEnum prints as its number)
        return f"{type(self).__name__}.{self.name}"

    def __format__(self, spec: str) -> str:
        """As :meth:`__str__`, or as the int with a numeric format (``:d``)."""
        if spec and spec[-1] in "bcdoxXneEfFgG%":
            return format(int(self), spec)
        return format(str(self), spec)

    REACHED_END = 0
    MAX_STEPS = 1
    STEP_TOO_SMALL = -1
    START_FAILED = -2
    #: a run started on a bound (``from_bound``: a frequency response, a nonlinear mode, a damper optimum) left
    #: the range through that bound, never reaching the other: the range beyond the turn was not traced
    TURNED_BACK = -3
    #: ``on_point`` raised at the last point: the run ends there, keeping every point before it and that one
    CALLBACK_RAISED = -4
    #: the residual raised (not an arithmetic error, which is a failed step) after the first point: the run
    #: ends there, keeping every point before (a user's contact element that raises midway through a curve)
    RESIDUAL_RAISED = -5


MESSAGES = {
    Status.REACHED_END: "the branch reached the end of the parameter range",
    Status.MAX_STEPS: "the step budget (max_steps) was used up before the end of the parameter range",
    Status.STEP_TOO_SMALL: "the step fell below min_step: the corrector kept failing",
    Status.START_FAILED: "Newton's method did not converge at the starting point",
    Status.TURNED_BACK: "the branch turned back and left the parameter range where it started",
    Status.CALLBACK_RAISED: "the callback raised an exception at the last point, which ends the branch",
    Status.RESIDUAL_RAISED: "the residual raised an exception beyond the last point, which ends the branch",
}


@dataclass
class ContinuationResult:
    """Points of one branch, in continuation order, with how the run went."""

    y: np.ndarray  #: (npoints, n) points on the curve
    tangent: np.ndarray  #: (npoints, n) unit tangents (scaled coordinates of each point)
    residual_norm: np.ndarray  #: Euclidean norm of R at each point
    iterations: np.ndarray  #: Newton updates spent on each point
    fold_after: np.ndarray  #: index i: a fold lies between points i and i + 1
    corners: np.ndarray  #: indices of points where the tangent jumps (piecewise-smooth residual)
    folds: np.ndarray  #: (nfolds, n) located folds; where locating fails, the bracketing point at the turn
    status: Status
    message: str
    nsteps: int = 0  #: accepted steps
    nrejected: int = 0  #: rejected step attempts
    nit: int = 0  #: Newton updates in total (including fold location)
    nfev: int = 0  #: residual evaluations in total
    last_step: float = 0.0  #: step length at the end (scaled units)
    coarse: np.ndarray = None  #: indices of points accepted with a predictor error above REJECT_CURVE e*
    #: (npoints, n) per point the Newton step with the parameter held that its converged residual still asks
    #: (``J dy = -R``, the parameter's component 0): its distance from the curve at its parameter; NaN where unknown
    newton_step: np.ndarray = None

    @property
    def success(self) -> bool:
        return self.status == Status.REACHED_END


def continuation(residual: Residual, y0: ArrayLike, *, parameter: int = -1,
                 bounds: tuple[float, float] = (-math.inf, math.inf), direction: int = 1,
                 step: float | None = None, min_step: float = 1e-9, max_step: float = 0.1,
                 max_steps: int = 1000, tol: float = 1e-10, max_iter: int = NEWTON_MAX_ITER,
                 scale: Scale | None = None, locate_folds: bool = True, fold_xtol: float = 1e-10,
                 on_point: Callable[[NDArray[np.float64], float], object] | None = None,
                 curve_tol: float | None = None, curve_components: ArrayLike | None = None,
                 stop: Callable[[NDArray[np.float64]], bool] | None = None,
                 from_bound: bool = False) -> ContinuationResult:
    """Trace the branch of ``residual(y) = 0`` through ``y0`` in the direction of ``parameter``.

    ``residual(y) -> (R, J)``; ``y0`` is corrected with the parameter held fixed first.  The
    run stops when the parameter leaves ``bounds`` (last point put on the bound), after
    ``max_steps`` accepted steps, or when the step falls below ``min_step``.  ``tol`` bounds
    ``|R|`` (Euclidean) at every returned point.  ``scale(y)``: optional positive weights (see module).
    Folds are located to ``fold_xtol`` (relative arclength) when ``locate_folds``.
    ``on_point(y, residual_norm)``: called with each point and its ``|R|`` as soon as it is accepted,
    in order (streaming); an exception it raises (an ``Exception``: not ``KeyboardInterrupt``) ends the
    run at that point with ``Status.CALLBACK_RAISED``, the exception in the message, the points kept.
    ``curve_tol``: the step's error control (see module); None: off.
    ``stop(y)``: asked at each accepted point; True ends the run there as if at the end of the range; an
    exception it raises ends it there with ``Status.CALLBACK_RAISED``, as one of ``on_point``.
    ``from_bound``: the range starts at ``y0``, on the bound behind ``direction`` (``lo`` for +1): a branch
    that turns back and leaves the range through that bound, never reaching the other, ends with
    ``Status.TURNED_BACK`` (its points kept, the last on the start bound), the message saying where the
    parameter turned; without it such a run reached an end of the range (``REACHED_END``).
    An arithmetic error of ``residual`` is a failed step; any other ``Exception`` it raises propagates
    at the start, and after it ends the run with ``Status.RESIDUAL_RAISED``, the points kept (an
    element's answer of the wrong type or shape, or a warning an ``"error"`` filter raises, propagates at once:
    ``RESIDUAL_RAISED_AT_ONCE``).
    """
    if not callable(residual):
        raise ValueError(f"residual must be a function y -> (R, J), got residual={residual!r}")
    try:
        y0 = np.array(y0, dtype=float).ravel()
    except (TypeError, ValueError):
        raise ValueError(f"y0 must be an array of numbers, got y0={y0!r}") from None
    n = y0.size
    if n < 2:
        raise ValueError(f"y0 must have at least 2 components, got y0={y0!r}")
    if not np.all(np.isfinite(y0)):
        raise ValueError(f"y0 must be finite, got y0={y0!r}")
    if isinstance(parameter, bool) or not isinstance(parameter, (int, np.integer)) or not -n <= parameter < n:
        raise ValueError(f"parameter must be an index of y0 in {-n}..{n - 1}, got parameter={parameter!r}")
    p = int(parameter) % n
    try:
        lo, hi = bounds  # type: ignore[misc]
        lo, hi = float(lo), float(hi)
    except (TypeError, ValueError):
        raise ValueError(f"bounds must be a pair (lo, hi) of numbers, got bounds={bounds!r}") from None
    if not lo <= hi:  # (NaN too)
        raise ValueError(f"bounds must have lo <= hi, got bounds={bounds!r}")
    if not lo <= y0[p] <= hi:
        raise ValueError(f"y0's parameter y0[{p}]={y0[p]!r} is outside bounds=({lo!r}, {hi!r})")
    if isinstance(direction, bool) or not isinstance(direction, (int, np.integer, float)) or direction not in (1, -1):
        raise ValueError(f"direction must be +1 or -1, got direction={direction!r}")
    min_step, max_step = positive("min_step", min_step), positive("max_step", max_step)
    if not min_step <= max_step:
        raise ValueError(f"need 0 < min_step <= max_step, got min_step={min_step!r}, max_step={max_step!r}")
    if step is not None:
        step = positive("step", step)
    max_steps, max_iter = _whole("max_steps", max_steps), _whole("max_iter", max_iter)
    tol, fold_xtol = positive("tol", tol), positive("fold_xtol", fold_xtol)
    locate_folds = flag("locate_folds", locate_folds)
    if flag("from_bound", from_bound) and y0[p] != (lo if direction > 0 else hi):
        raise ValueError(f"from_bound=True needs y0 on the bound the range starts from, y0[{p}] == "
                         f"{'lo' if direction > 0 else 'hi'}={lo if direction > 0 else hi!r} for direction={direction!r}, "
                         f"got y0[{p}]={float(y0[p])!r}")
    if curve_tol is not None and not 0.0 < _finite_or_nan(curve_tol) < 1.0:
        raise ValueError(f"curve_tol must be in (0, 1) or None, got curve_tol={curve_tol!r}")
    if curve_components is not None:
        curve_components = np.asarray(curve_components)
        if curve_components.dtype.kind not in "iu" or np.any(curve_components < -n) or np.any(curve_components >= n):
            raise ValueError(f"curve_components must be indices of y0 in {-n}..{n - 1}, "
                             f"got curve_components={curve_components.tolist()!r}")
    for name, f in (("scale", scale), ("on_point", on_point), ("stop", stop)):
        if f is not None and not callable(f):
            raise ValueError(f"{name} must be a function or None, got {name}={f!r}")
    scale = scale if scale is not None else (lambda y: np.ones(n))
    count = _Count()
    trace = _Trace(_counted(_shaped(residual, n), count), p, lo, hi, tol, max_iter, scale, min_step, max_step, count,
                   on_point if on_point is not None else (lambda y, rnorm: None), curve_tol,
                   np.arange(n) if curve_components is None else np.asarray(curve_components, dtype=int), stop,
                   ("lower" if direction > 0 else "upper") if from_bound else None)
    failed = trace.start(y0, direction, step)
    if failed is not None:
        return failed
    while trace.status is None:
        try:
            trace.advance(max_steps)
        except RESIDUAL_RAISED_AT_ONCE:
            raise
        except Exception as exc:  # noqa: BLE001 - a residual of the caller's (an element's hook): the points stay
            trace.raised(exc)
    folds = _located_folds(trace, residual, tol, scale, fold_xtol, max_iter, count) if locate_folds else []
    if trace.status == Status.TURNED_BACK:
        far = (max if direction > 0 else min)([y[p] for y in trace.ys] + [f[p] for f in folds])
        trace.detail = (f" (it turned at y[{p}] = {far:.8g} and left through its start bound {(lo, hi)[direction < 0]!r} "
                        f"before reaching {(hi, lo)[direction < 0]!r}){trace.detail}")
    return _result(trace.ys, trace.ts, trace.rn, trace.its, trace.fold_after, folds, trace.status,
                   MESSAGES[trace.status] + trace.detail, trace.nsteps, trace.nrejected, count, trace.h,
                   trace.corners, trace.coarse, trace.steps)


class ResidualContractError(ElementContractError):
    """The residual given to :func:`continuation` returned the wrong type or shape at its first call (a defect of
    its code, raised at once, as an element's wrong answer is): a pair ``(R, J)`` of ``n - 1`` residuals and their
    ``(n - 1, n)`` Jacobian for ``n`` unknowns."""


def _shaped(residual: Residual, n: int) -> Residual:
    """``residual``, its first answer checked: a pair ``(R, J)`` with ``R`` of shape ``(n - 1,)`` and ``J`` of
    ``(n - 1, n)``; else ``ResidualContractError`` naming ``residual`` (a residual of wrong shape was traced,
    its Jacobian's null space taken for the branch's tangent, and the curve returned as converged)."""
    checked = False

    def fun(y):
        nonlocal checked
        out = residual(y)
        if not checked:
            ok = isinstance(out, tuple) and len(out) == 2
            shapes = (np.shape(out[0]), getattr(out[1], "shape", np.shape(out[1]))) if ok else None
            if not ok or shapes != ((n - 1,), (n - 1, n)):
                got = (f"R of shape {shapes[0]} and J of shape {shapes[1]}" if ok else
                       f"{type(out).__name__} {shown(out)}")
                raise ResidualContractError(f"residual(y) must return (R, J) with R of shape ({n - 1},) and J of "
                                            f"shape ({n - 1}, {n}) for y0 of {n} components, got {got}")
            checked = True
        return out

    return fun


def _located_folds(trace: "_Trace", residual: Residual, tol: float, scale: Scale, xtol: float, max_iter: int,
                   count: _Count) -> list:
    """The folds of ``trace``, each located between its neighbouring points; where locating fails (a
    corner of the branch, or a residual that raises), the bracketing point whose parameter is the extreme
    of the turn, a converged point within one step of it."""
    folds, p = [], trace.p
    for i in trace.fold_after:
        ya, yb = trace.ys[i], trace.ys[i + 1]
        try:
            loc = locate(residual, ya, yb, lambda yy, tt: tt[p], tol=tol, scale=scale, xtol=xtol, max_iter=max_iter,
                         count=count)
        except RESIDUAL_RAISED_AT_ONCE:
            raise
        except Exception:  # noqa: BLE001 - as a locator that fails
            loc = None
        folds.append(loc.y if loc is not None else max(ya, yb, key=lambda yy: yy[p] * np.sign(trace.ts[i][p])))
    return folds


def described(exc: BaseException) -> str:
    """``exc`` for a message: its type, its text and its notes (where an element's check added one)."""
    return f"{type(exc).__name__}: {_told(exc)}"


def _finite_or_nan(value: object) -> float:
    """``value`` as a finite float, NaN for anything else (a string, a bool, inf): for a range test."""
    try:
        return finite("value", value)
    except ValueError:
        return math.nan


class _Trace:
    """The state of :func:`continuation` along the branch, and its steps: the start, one step
    attempt (predictor, corrector, the turn test), a rejection, an acceptance (with the point on
    the bound at the end of the parameter range) and the step control."""

    def __init__(self, fun, p, lo, hi, tol, max_iter, scale, min_step, max_step, count, report, curve_tol=None,
                 curve_components=None, stop=None, start_side=None):
        self.fun, self.p, self.lo, self.hi, self.stop = fun, p, lo, hi, stop
        self.start_side = start_side  # "lower"/"upper": the bound the range starts from (from_bound); None: neither
        self.target = None if curve_tol is None else PREDICTOR_SHARE * curve_tol  # e*
        self.retries, self.coarse, self.curve_components = 0, [], curve_components
        self.tol, self.max_iter, self.scale, self.count, self.report = tol, max_iter, scale, count, report
        self.min_step, self.max_step = min_step, max_step
        self.status: Status | None = None
        self.detail = ""

    def start(self, y0, direction, step) -> ContinuationResult | None:
        """Newton with the parameter held at ``y0[p]``, then the tangent; a result if that fails."""
        n, p, count = y0.size, self.p, self.count
        self.e_p = np.zeros(n)
        self.e_p[p] = 1.0
        start = _newton(self.fun, y0, self.e_p, y0[p], self.tol, self.max_iter, count)
        if not start.converged:
            return _result([], [], [], [], [], [], Status.START_FAILED,
                           f"{MESSAGES[Status.START_FAILED]} ({start.reason}; |R|={start.rnorm:.3e}, "
                           f"tol={self.tol:.3e})", 0, 0, count, 0.0)
        y = start.y
        s = _scale(self.scale, y)
        try:
            t = _tangent(start.J, s, None)
        except np.linalg.LinAlgError as exc:
            return _result([], [], [], [], [], [], Status.START_FAILED,
                           f"{MESSAGES[Status.START_FAILED]} ({exc})", 0, 0, count, 0.0)
        if t[p] * direction < 0.0:
            t = -t
        self.y, self.s, self.t, self.J = y, s, t, start.J
        self.ys, self.ts, self.rn, self.its = [y], [t], [start.rnorm], [start.iterations]
        self.steps = [_fixed_step(start.R, start.J, p)]
        self.fold_after = []
        self.h = min(max(step if step is not None else FIRST_STEP * self.max_step, self.min_step), self.max_step)
        self.zero = np.zeros(n)
        self.c2 = self.c3 = self.zero  # curvature terms of the predictor
        self.normal = t  # normal of the corrector's hyperplane
        self.nsteps = self.nrejected = 0
        self.corners = []
        self.rejected = None  # (turn, step) of the last step rejected for turning
        self.failures = 0  # failed correctors in a row at this point, or since the trace began creeping towards a corner
        self.creep = 0.0  # the longest step whose failed predictor showed a corner, while shorter ones are accepted
        self._reported(y, start.rnorm)
        return None

    def advance(self, max_steps: int) -> None:
        """One step attempt: accepted, rejected (a shorter step next), or the end of the run."""
        if self.nsteps >= max_steps:
            self.status = Status.MAX_STEPS
            return
        # ---- predictor along the tangent (+ curvature), in the coordinates scaled at y
        y, s, h, p = self.y, self.s, self.h, self.p
        y_pred = y + h * s * (self.t + h * (self.c2 + h * self.c3))
        w = self.normal / s  # the constraint normal . (u - u_p) = 0 in physical coordinates
        new = _newton(self.fun, y_pred, w, float(w @ y_pred), self.tol, self.max_iter, self.count)
        ok, reason, t_new, turn = self._judge(new, y_pred)
        if not ok:
            if new.outside and not self.lo <= y_pred[p] <= self.hi and self._end_from(y_pred):
                return
            if not new.converged and self.failures >= CORNER_AFTER and self._round_corner(new, y_pred):
                self.failures = 0
                return
            self.failures += 1
            self._reject(new, reason)
            if self.normal is not self.t:  # the predictor's Jacobian shows a corner within the step
                self.creep = max(self.creep, h)
            return
        f_curve = self._curve_factor(new.y, y_pred, s, turn)
        if f_curve is not None and f_curve < 0.0:  # above REJECT_CURVE e*: shorter, unless at a corner
            self.nrejected += 1
            self.retries += 1
            self.h = max(self.h * min(-f_curve, FAIL_FACTOR), self.min_step)
            return
        self._accept(new, t_new, turn, f_curve)

    def _curve_factor(self, y_new, y_pred, s, turn):
        """The step factor of the error control (None: off); negative (its size) to retry shorter."""
        if self.target is None:
            return None
        k = self.curve_components
        last = self.corners[-1] if self.corners else 0  # the smooth piece starts at the last corner
        if len(self.ys) - last >= 4:  # the cubic through the piece's last four points, extrapolated
            y_pred = lagrange(self.ys[-4:] + [y_new], s)
        d = (y_new[k] - y_pred[k]) / s[k]
        e = math.sqrt(float(d @ d))
        q = 2.0 if len(self.ys) - last < 4 and self.c2 is self.zero else 4.0  # tangent predictor ~ h^2, cubic ~ h^4
        f = SAFETY * (self.target / max(e, 1e-300)) ** (1.0 / q)
        at_corner = bool(self.corners) and self.corners[-1] == len(self.ys)
        if e > REJECT_CURVE * self.target:
            if self.retries < CURVE_RETRIES and not at_corner and self.h > self.min_step:
                return -max(f, MIN_FACTOR * FAIL_FACTOR)
            self.coarse.append(len(self.ys))  # accepted above the tolerance: listed, never silent
        self.retries = 0
        return f

    def _judge(self, new, y_pred):
        """``(ok, reason, t_new, turn)`` of a corrected point: converged, with a tangent, and a turn
        of the tangent that is either small or a corner (a second, larger turn after a rejection).

        A small turn with the corrector ending more than ``JUMP_RATIO`` steps from the predictor is a
        jump to another branch, not a step along this one: along a smooth branch whose tangent turns
        by ``turn`` over the step ``h`` the corrector moves about ``h turn / 2`` (below ``h / 4`` for
        any turn accepted as smooth), while the hyperplane ahead of a sharp peak also crosses the
        other flank, where the corrector may land a whole peak's width away with a tangent that
        hardly turned.  Such a step is rejected and retried shorter."""
        ok, reason, t_new, turn = new.converged, new.reason, None, None
        if ok:
            try:
                t_new = _tangent(new.J, self.s, self.t)
            except np.linalg.LinAlgError:
                t_new = None
                ok, reason = False, "the Jacobian has no one-dimensional null space"
        if ok:
            turn = math.acos(min(1.0, abs(float(t_new @ self.t))))
            moved = float(np.linalg.norm((new.y - y_pred) / self.s))
            if turn <= REJECT_TURN and moved > JUMP_RATIO * self.h:
                ok, reason = False, (f"the corrector moved {moved / self.h:.3g} steps from the predictor "
                                     f"(a jump to another branch)")
            elif turn > REJECT_TURN:
                if self.rejected is not None and turn > CORNER_RATIO * self.rejected[0]:
                    self.corners.append(len(self.ys))
                    self.rejected = None
                    t_new = self._oriented(new.J, t_new)
                else:
                    ok, reason = False, f"tangent turned by {turn:.3g} rad"
                    self.rejected = (turn, self.h)
        return ok, reason, t_new, turn

    def _oriented(self, J, t_new):
        """``t_new`` (a unit null vector of ``J``, scaled at ``y``) oriented like the branch at a corner.

        Past a corner the tangent has turned by more than ``REJECT_TURN``.  Where it turned by less
        than 60 degrees (``|t_new . t| >= ORIENT_DOT``) the branch goes on forward, ``t_new . t > 0``.
        Near 90 degrees ``t_new . t`` is close to zero and its sign says nothing about which way the
        branch goes on (a branch whose tangent turned by 89 degrees in the scaled coordinates would
        be traced back the way it came); there ``t_new`` takes the sign of ``det [J diag(s); t]`` of
        the last point, which is kept along a smooth branch (Allgower & Georg, ch. 2).  Across a kink
        the two one-sided Jacobians may orient it differently (a chain's nonlinear mode turns by 37
        degrees at a slip onset with the determinant's sign flipped), so it decides only where the
        turn leaves the product no sign to go by."""
        if self.J is None or abs(float(t_new @ self.t)) >= ORIENT_DOT:
            return t_new if float(t_new @ self.t) >= 0.0 else -t_new
        old, new = _orientation(self.J, self.s, self.t), _orientation(J, self.s, t_new)
        return -t_new if old * new < 0.0 else t_new

    def _round_corner(self, new, y_pred) -> bool:
        """Step around a corner the failed corrector has shown; True if a point beyond it was accepted.

        The Jacobian at the failed predictor (or at the corrector's last iterate) may belong to the
        next smooth piece of a piecewise-smooth residual.  Its null vector ``t0`` is oriented like the
        branch: ``det [J; t]`` keeps its sign along a branch, across the kinks of a continuous
        piecewise-smooth residual too (the orientation of piecewise-linear continuation, Allgower &
        Georg ch. 12), so ``t0`` points along the new piece even at a corner fold, where the branch
        turns back by more than 90 degrees and the hyperplane normal to ``t`` ahead of the corner
        misses it.  If ``t0`` turned by more than ``REJECT_TURN`` from ``t``, the corrector works from
        the same predictor on the hyperplane normal to the bisector ``b`` of ``t`` and ``t0``, which
        crosses both pieces at the same arclength from the corner.  The point is taken if it lies
        ahead of ``y`` along ``b`` and its own tangent is ``t0``'s (the piece the Jacobian showed,
        not another branch).
        """
        y, s, t = self.y, self.s, self.t
        if self.J is None:
            return False
        sign = _orientation(self.J, s, t)
        seen = []
        for J in (new.J0, new.J):
            if J is None or sign == 0.0:
                continue
            try:
                t0 = _tangent(J, s, t)
            except np.linalg.LinAlgError:
                continue
            o = _orientation(J, s, t0)
            if o == 0.0:
                continue
            t0 = t0 * (o * sign)
            if float(t0 @ t) >= math.cos(REJECT_TURN) or any(float(t0 @ q) > CORNER_SAME for q in seen):
                continue
            seen.append(t0)
        for d in seen:
            b = t + d
            b /= math.sqrt(float(b @ b))
            w = b / s
            trial = _newton(self.fun, y_pred, w, float(w @ y_pred), self.tol, self.max_iter, self.count)
            if not trial.converged or float(b @ ((trial.y - y) / s)) <= 0.0:
                continue
            try:
                t_c = _tangent(trial.J, s, d)
            except np.linalg.LinAlgError:
                continue
            if float(t_c @ d) < math.cos(REJECT_TURN) or _orientation(trial.J, s, t_c) != sign:
                continue
            self.corners.append(len(self.ys))
            self.rejected = None
            self.nrejected += 1  # the failed attempt that showed the corner
            self._accept(trial, t_c, math.acos(max(-1.0, min(1.0, float(t_c @ t)))))
            return True
        return False

    def _reject(self, new, reason) -> None:
        self.normal = _corner_normal(new.J0, self.s, self.t)
        self.nrejected += 1
        self.h *= FAIL_FACTOR
        if self.h < self.min_step:
            self.status = Status.STEP_TOO_SMALL
            self.detail = (f" (last failure: {reason}; near y={np.array2string(self.y, precision=8)}, "
                           f"step {self.h / FAIL_FACTOR:.3g})")

    def _accept(self, new, t_new, turn, f_curve=None) -> None:
        p, ys, ts = self.p, self.ys, self.ts
        self.nsteps += 1
        if self.h >= self.creep:  # a step as long as the last that showed a corner: not creeping towards one
            self.failures, self.creep = 0, 0.0
        if self.rejected is not None and self.h >= self.rejected[1]:
            self.rejected = None  # back at the step that turned too much: not approaching a corner
        y_prev = self.y
        y, s_old = new.y, self.s
        s = _scale(self.scale, y)
        t = _rescale(t_new, s_old, s)
        self.y, self.s, self.t, self.J = y, s, t, new.J
        if ts[-1][p] * t[p] < 0.0:  # the parameter turned back: a fold
            self.fold_after.append(len(ys) - 1)
        if not self.lo <= y[p] <= self.hi:
            self._end_on_bound(y_prev)
            return
        ys.append(y)
        ts.append(t)
        self.rn.append(new.rnorm)
        self.steps.append(_fixed_step(new.R, new.J, p))
        self.its.append(new.iterations)
        if not self._reported(y, new.rnorm):
            return
        if self.stop is not None and self._stopped(y):
            return
        self.normal = t
        at_corner = bool(self.corners) and self.corners[-1] == len(ys) - 1
        if at_corner:
            self.c2 = self.c3 = self.zero
        else:
            self.c2, self.c3 = _hermite(y_prev, _rescale(ts[-2], s_old, s), y, t, s)  # s_old = scale(y_prev)
        # ---- step control from corrector effort and curvature
        f_newton = NEWTON_TARGET / max(new.iterations, 1)
        f_turn = MAX_TURN / max(turn, 1e-12) if not at_corner else 1.0
        f = min(f_newton, f_turn, f_curve if f_curve is not None else math.inf)
        self.h = min(max(self.h * min(max(f, MIN_FACTOR), MAX_FACTOR), self.min_step), self.max_step)

    def _end_from(self, y_pred) -> bool:
        """A predictor past the bound where the residual is not defined (``OutsideDomain``): the point on
        the bound from the chord to it, ending the run (True), as an accepted step past it would."""
        end, bound = self._on_bound(self.y, y_pred)
        if not end.converged:
            return False
        self.nsteps += 1
        self._append_end(end, bound)
        return True

    def _on_bound(self, inside, outside) -> tuple:
        """Newton on the bound that the chord from ``inside`` to ``outside`` crosses, from where it crosses:
        ``(the Newton result, the bound)``."""
        p = self.p
        bound = self.hi if outside[p] > self.hi else self.lo
        self.side = "upper" if outside[p] > self.hi else "lower"
        guess = inside + (bound - inside[p]) / (outside[p] - inside[p]) * (outside - inside)
        return _newton(self.fun, guess, self.e_p, bound, self.tol, self.max_iter, self.count), bound

    def _append_end(self, end, bound) -> None:
        """The converged point ``end`` on ``bound``: the last point of a run that reached the end."""
        s_end = _scale(self.scale, end.y)
        self.ys.append(end.y)
        self.steps.append(_fixed_step(end.R, end.J, self.p))
        self.ts.append(_tangent(end.J, s_end, _rescale(self.t, self.s, s_end)))
        self.rn.append(end.rnorm)
        self.its.append(end.iterations)
        self.status = self._ended()
        self.detail = f" (at its {self.side} end)" if self.status == Status.REACHED_END else ""
        self._reported(end.y, end.rnorm)

    def _ended(self) -> Status:
        """How a run that left the range (through ``self.side``) ended: ``TURNED_BACK`` through the bound it
        started from (``from_bound``), else ``REACHED_END``."""
        return Status.TURNED_BACK if self.side == self.start_side else Status.REACHED_END

    def _reported(self, y, rnorm) -> bool:
        """``on_point(y, rnorm)`` for the point just kept; False if it raised, which ends the run there
        (``Status.CALLBACK_RAISED``, the exception in the message): what was computed stays."""
        try:
            self.report(y, rnorm)
        except Exception as exc:  # noqa: BLE001 - the caller's code: any Exception ends the run, none is lost
            self.status = Status.CALLBACK_RAISED
            self.detail = f" ({type(exc).__name__}: {exc}; the last point is the one it was called with)"
            return False
        return True

    def _stopped(self, y) -> bool:
        """``stop(y)`` for the point just kept; True ends the run there: as at the end of the range where it
        says so, with ``Status.CALLBACK_RAISED`` where it raised (the caller's code, not the residual's)."""
        try:
            if not self.stop(y):
                return False
        except Exception as exc:  # noqa: BLE001 - the caller's code: any Exception ends the run, none is lost
            self.status = Status.CALLBACK_RAISED
            self.detail = f" (stop(y) raised {type(exc).__name__}: {exc}; the last point is the one it was asked at)"
            return True
        self.status, self.detail = Status.REACHED_END, " (where the caller's stop(y) ended it)"
        return True

    def raised(self, exc: Exception) -> None:
        """The residual raised ``exc`` during a step: the run ends with ``Status.RESIDUAL_RAISED``, the
        points accepted before kept (a fold marked after the last of them dropped); where the caller's
        ``scale(y)`` raised it, with ``Status.CALLBACK_RAISED`` naming it."""
        self.fold_after = [i for i in self.fold_after if i + 1 < len(self.ys)]
        caller = getattr(exc, RAISED_BY, None)
        if caller is not None:
            self.status = Status.CALLBACK_RAISED
            self.detail = f" ({caller} raised {described(exc)})"
            return
        self.status = Status.RESIDUAL_RAISED
        self.detail = f" ({described(exc)})"

    def _end_on_bound(self, y_prev) -> None:
        """The end of the parameter range: the last point goes on the bound."""
        end, bound = self._on_bound(y_prev, self.y)
        if end.converged:
            self._append_end(end, bound)
            return
        self.detail = (f" (the point on the bound {bound!r} did not converge: {end.reason}; kept the last "
                       "inside)")
        if self.fold_after and self.fold_after[-1] == len(self.ys) - 1:
            self.fold_after.pop()
        self.status = self._ended()


@dataclass
class Located:
    """A point on the branch where ``g`` vanishes."""

    y: np.ndarray
    tangent: np.ndarray  #: tangent in physical coordinates, oriented from ya to yb
    residual_norm: float
    nfev: int


def locate(residual: Residual, ya: ArrayLike, yb: ArrayLike,
           g: Callable[[NDArray[np.float64], NDArray[np.float64]], float], *, tol: float = 1e-10,
           scale: Scale | None = None, xtol: float = 1e-10, max_iter: int = NEWTON_MAX_ITER,
           count: _Count | None = None) -> Located | None:
    """The point between ``ya`` and ``yb`` (both on the branch) where ``g(y, t) = 0``.

    ``t`` is the tangent at ``y`` in physical coordinates, oriented from ``ya`` to ``yb``.  The
    branch between them is parametrised by the distance ``sigma`` along their chord (in
    coordinates scaled at ``ya``); Brent's method finds the root in ``sigma`` to ``xtol``
    times the chord length.  Returns None when ``g`` has the same sign at both ends.
    """
    count = count if count is not None else _Count()
    chord = _Chord(residual, ya, yb, tol, scale, max_iter, count)
    if chord.length == 0.0:
        return None
    ell, n0 = chord.length, count.nfev

    def G(sigma):
        sol, t = chord.point(sigma)
        return float(g(sol.y, t))

    try:
        ga, gb = G(0.0), G(ell)
        if ga == 0.0:
            root = 0.0
        elif gb == 0.0:
            root = ell
        elif ga * gb > 0.0:
            return None
        else:
            root = brentq(G, 0.0, ell, xtol=xtol * ell, rtol=4 * np.finfo(float).eps, maxiter=100)
        sol, t = chord.point(root)
    except _LocateFailed:
        return None
    return Located(sol.y, t, sol.rnorm, count.nfev - n0)


def maximise(residual: Residual, ya: ArrayLike, yb: ArrayLike, f: Callable[[NDArray[np.float64]], float], *,
             tol: float = 1e-10, scale: Scale | None = None, xtol: float = 1e-10, max_iter: int = NEWTON_MAX_ITER,
             count: _Count | None = None) -> Located | None:
    """The point of the branch between ``ya`` and ``yb`` where ``f(y)`` is largest, by golden-section search
    in the chord parameter of :func:`locate` to ``xtol`` times the chord length: every trial a converged
    point of the branch, no tangent asked.  It finds a maximum where a zero of ``f``'s slope along the
    tangent cannot be bracketed, the slope having one sign at both ends: a branch with structure finer than
    its points (a ripple between them), or an element whose tangent is not the branch's slope over a step
    (kinks denser than the points).  The maximum of a unimodal ``f``; of a rippled one, a ripple's top.
    None where a trial fails."""
    count = count if count is not None else _Count()
    chord = _Chord(residual, ya, yb, tol, scale, max_iter, count)
    if chord.length == 0.0:
        return None
    n0, inv = count.nfev, (math.sqrt(5.0) - 1.0) / 2.0  # 1/phi
    try:
        value = lambda sigma: f(chord.point(sigma)[0].y)  # noqa: E731
        lo, hi = 0.0, chord.length
        x1, x2 = hi - inv * (hi - lo), lo + inv * (hi - lo)
        f1, f2 = value(x1), value(x2)
        while hi - lo > xtol * chord.length:
            if f1 >= f2:
                hi, x2, f2 = x2, x1, f1
                x1 = hi - inv * (hi - lo)
                f1 = value(x1)
            else:
                lo, x1, f1 = x1, x2, f2
                x2 = lo + inv * (hi - lo)
                f2 = value(x2)
        sol, t = chord.point(x1 if f1 >= f2 else x2)
    except _LocateFailed:
        return None
    return Located(sol.y, t, sol.rnorm, count.nfev - n0)


class _Chord:
    """The branch between ``ya`` and ``yb`` by the distance ``sigma`` along their chord (coordinates scaled at
    ``ya``): ``point(sigma)`` is the branch's point on the hyperplane normal to the chord at ``sigma`` (a
    Newton solve from the chord's point there) and its tangent, kept by ``sigma``."""

    def __init__(self, residual: Residual, ya: ArrayLike, yb: ArrayLike, tol: float, scale: Scale | None,
                 max_iter: int, count: _Count):
        ya, yb = np.asarray(ya, dtype=float), np.asarray(yb, dtype=float)
        self.fun, self.tol, self.max_iter, self.count = _counted(residual, count), tol, max_iter, count
        self.ya, self.s = ya, _scale(scale if scale is not None else (lambda y: np.ones(ya.size)), ya)
        d = (yb - ya) / self.s
        self.length = float(np.linalg.norm(d))
        self.d = d / self.length if self.length > 0.0 else d
        self.w = self.d / self.s
        self.c_a = float(self.w @ ya)
        self.cache: dict = {}

    def point(self, sigma: float):
        if sigma not in self.cache:
            guess = self.ya + sigma * self.s * self.d
            sol = _newton(self.fun, guess, self.w, self.c_a + sigma, self.tol, self.max_iter, self.count)
            if not sol.converged:
                raise _LocateFailed(sol.reason)
            try:
                t = _tangent(sol.J, self.s, self.d) * self.s
            except np.linalg.LinAlgError as exc:
                raise _LocateFailed(str(exc)) from None
            self.cache[sigma] = (sol, t)
        return self.cache[sigma]


class _LocateFailed(Exception):
    pass


def _result(ys, ts, rn, its, fold_after, folds, status, message, nsteps, nrejected, count, h, corners=(),
            coarse=(), steps=None):
    n = len(ys[0]) if ys else 0
    return ContinuationResult(
        y=np.array(ys, dtype=float).reshape(-1, n) if ys else np.empty((0, 0)),
        tangent=np.array(ts, dtype=float).reshape(-1, n) if ts else np.empty((0, 0)),
        residual_norm=np.array(rn, dtype=float),
        iterations=np.array(its, dtype=int),
        fold_after=np.array(fold_after, dtype=int),
        corners=np.array(corners, dtype=int), coarse=np.array(coarse, dtype=int),
        folds=np.array(folds, dtype=float).reshape(-1, n) if folds else np.empty((0, n)),
        status=status, message=message, nsteps=nsteps, nrejected=nrejected,
        nit=count.nit, nfev=count.nfev, last_step=h,
        newton_step=np.array(steps, dtype=float).reshape(-1, n) if steps else np.full((len(ys), n), np.nan),
    )
