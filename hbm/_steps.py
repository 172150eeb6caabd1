"""The primitives of :mod:`hbm.continuation`, shared with :mod:`hbm.curve`: the corrector (Newton on
``[R(y); w . y - c] = 0``), the unit tangent and its orientation, the scaling and the Hermite
predictor terms.  Generic: they see only ``residual(y) -> (R, J)``."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from contact_models.numerics.checks import ElementContractError
from contact_models.numerics.small import solve_small as _solve

#: Largest accepted ratio ``|R_{k+1}| / |R_k|`` from the second Newton update on (``|.|`` Euclidean).
MAX_CONTRACTION = 0.5
#: A Newton update below ``ROUNDING_STEP |y|`` changes ``y`` by less than its rounding: the residual is at
#: the floor double precision leaves it (about ``eps |J| |y|``), and the point is converged if that floor
#: is within ``ROUNDING_REACH`` of the tolerance (a tolerance near the rounding of a residual whose terms
#: are much larger than it, as a lightly damped structure's near resonance, cannot always be met).
ROUNDING_STEP = 4.0 * np.finfo(float).eps
ROUNDING_REACH = 100.0


class OutsideDomain(ValueError):
    """Raised by a residual at a point where it is not defined (a negative frequency): the step that
    led there failed, and a shorter one is tried, instead of the error ending the run."""


#: Exceptions of the residual that count as a failed corrector instead of ending the run.
RESIDUAL_ERRORS = (ArithmeticError, np.linalg.LinAlgError, OutsideDomain)
#: Exceptions of the residual raised at once, wherever they occur: a defect of its code at any point (an
#: element's answer of the wrong type or shape), or a warning the caller's filter turned into an error (the
#: caller asked to stop there); any other exception after the first point ends the run, keeping it.
RESIDUAL_RAISED_AT_ONCE = (ElementContractError, Warning)


def _told(exc: BaseException) -> str:
    """``exc``'s text and its notes (an element's check names the element in one)."""
    return str(exc) + "".join(f" ({n})" for n in getattr(exc, "__notes__", ()))


#: A step whose tangent turns by more than this (rad) is rejected and retried shorter; a retry's
#: corrector uses the bisector normal when the tangent at the failed predictor turned that much.
REJECT_TURN = 0.5
#: Largest curvature correction of the predictor, relative to the step (at one chord ahead).
MAX_BEND = 0.25


@dataclass
class _Count:
    nfev: int = 0
    nit: int = 0


@dataclass
class _Newton:
    y: np.ndarray
    R: np.ndarray
    J: np.ndarray
    rnorm: float
    iterations: int
    converged: bool
    reason: str = ""
    J0: np.ndarray | None = None  # Jacobian at the first point (the predictor)
    outside: bool = False  # the residual was asked outside its domain (OutsideDomain)


def _counted(residual, count):
    def fun(y):
        count.nfev += 1
        return residual(y)

    return fun


#: The attribute by which an exception is marked as raised by the caller's ``scale(y)`` (not the residual): the
#: continuation ends a run it ends with ``Status.CALLBACK_RAISED`` naming it.
RAISED_BY = "_raised_by_caller"


def _scale(scale, y):
    """The caller's weights ``scale(y)``, checked; what it raises, or a wrong answer, is marked ``RAISED_BY``."""
    try:
        s = np.asarray(scale(y), dtype=float)
        if s.shape != y.shape or not (s.size == 0 or 0.0 < float(s.min()) and float(s.max()) < math.inf):  # nan
            raise ValueError(f"scale(y) must return finite positive weights of shape {y.shape}, got {s!r}")
    except Exception as exc:
        try:
            setattr(exc, RAISED_BY, "scale(y)")
        except AttributeError:  # (an exception type without a __dict__: said as the residual's)
            pass
        raise
    return s


def _rescale(t, s_old, s_new):
    """The same direction as ``t`` (scaled by ``s_old``) in coordinates scaled by ``s_new``."""
    v = t * (s_old / s_new)
    return v / math.sqrt(float(v @ v))


def _corner_normal(J0, s, t):
    """Corrector normal for a retry: ``t``, or, when the tangent at the failed predictor turned
    by more than ``REJECT_TURN`` (a corner ahead), the bisector of the two tangents, which
    crosses both smooth pieces (the hyperplane normal to ``t`` may be parallel to the next one)."""
    if J0 is None:
        return t
    try:
        t0 = _tangent(J0, s, t)
    except np.linalg.LinAlgError:
        return t
    if math.acos(min(1.0, abs(float(t0 @ t)))) <= REJECT_TURN:
        return t
    b = t + t0
    return b / math.sqrt(float(b @ b))


def _orientation(J, s, t) -> float:
    """The sign of ``det [J diag(s); t]`` (0.0 if singular): the orientation of the tangent ``t``
    (scaled coordinates) that continuation keeps along a branch (Allgower & Georg, ch. 2)."""
    sign, _ = np.linalg.slogdet(np.concatenate((J * s, t[None])))
    return float(sign)


def _hermite(y_prev, t_prev, y, t, s):
    """``(c2, c3)`` of the cubic ``u(h) = u + h t + h^2 c2 + h^3 c3`` (u = y/s) that also passes
    through ``u_prev`` with slope ``t_prev`` at ``h = -|u - u_prev|`` (Hermite, chord length as
    arclength); the cubic terms are scaled down so that one chord ahead they bend the
    predictor by at most ``MAX_BEND`` of the step."""
    d = (y_prev - y) / s
    ell2 = float(d @ d)
    if not ell2 > 0.0:
        return np.zeros_like(t), np.zeros_like(t)
    ell = math.sqrt(ell2)
    g = d + ell * t
    c3 = (t_prev - t + 2.0 * g / ell) / ell2
    c2 = g / ell2 + ell * c3
    bend_vec = ell * (c2 + ell * c3)  # (h^2 c2 + h^3 c3) / h at h = ell
    bend = math.sqrt(float(bend_vec @ bend_vec))
    if bend > MAX_BEND:
        c2, c3 = c2 * (MAX_BEND / bend), c3 * (MAX_BEND / bend)
    return c2, c3


def _tangent(J, s, prev):
    """Unit null vector of ``J diag(s)`` (the tangent in scaled coordinates), along ``prev``."""
    Js = J * s
    if Js.shape == (2, 3):  # fast path: the cross product of the two rows
        (a0, a1, a2), (b0, b1, b2) = Js.tolist()
        t = np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])
    else:
        n = Js.shape[1]
        rhs = np.zeros(n)
        rhs[-1] = 1.0
        try:
            if prev is None:
                raise np.linalg.LinAlgError
            t = np.linalg.solve(np.concatenate((Js, prev[None])), rhs)
        except np.linalg.LinAlgError:  # no reference, or the null space is orthogonal to it: the last
            t = np.linalg.svd(Js)[2][-1]  # right-singular vector, not orthogonal to the null space
    nrm = math.sqrt(float(t @ t))
    if not nrm > 0.0 or not math.isfinite(nrm):
        raise np.linalg.LinAlgError("the Jacobian has no one-dimensional null space here")
    t = t / nrm
    if prev is not None and float(t @ prev) < 0.0:
        t = -t
    return t


def _newton(fun, y, w, c, tol, max_iter, count) -> _Newton:
    """Newton on ``[R(y); w . y - c] = 0`` from ``y`` until ``|R| <= tol``, or until an update is below
    the rounding of ``y`` with ``|R|`` within ``ROUNDING_REACH tol`` (the residual's floor: no update can
    lower it).

    An arithmetic error raised by the residual, or ``OutsideDomain``, counts as a failed corrector
    (its message is kept as the reason), so that the branch computed so far survives it.
    """
    y = np.array(y, dtype=float)
    try:
        R, J = fun(y)
    except RESIDUAL_ERRORS as exc:
        return _Newton(y, None, None, math.inf, 0, False, f"the residual failed: {_told(exc)}",
                       outside=isinstance(exc, OutsideDomain))
    rnorm = _norm(R)
    J0 = J
    for k in range(max_iter + 1):
        if not math.isfinite(rnorm):
            return _Newton(y, R, J, rnorm, k, False, "non-finite residual", J0)
        if rnorm <= tol:
            return _Newton(y, R, J, rnorm, k, True)
        if k == max_iter:
            break
        A = np.concatenate((J, w[None]))  # [J; w], [R; w . y - c]
        b = np.concatenate((R, [float(w @ y) - c]))
        try:
            dy = _solve(A, -b)
        except np.linalg.LinAlgError:
            return _Newton(y, R, J, rnorm, k, False, "singular corrector matrix", J0)
        if rnorm <= ROUNDING_REACH * tol and _norm(dy) <= ROUNDING_STEP * _norm(y):
            return _Newton(y, R, J, rnorm, k, True)
        y = y + dy
        count.nit += 1
        try:
            R, J = fun(y)
        except RESIDUAL_ERRORS as exc:
            return _Newton(y, R, J, math.inf, k + 1, False, f"the residual failed: {_told(exc)}", J0,
                           isinstance(exc, OutsideDomain))
        r_new = _norm(R)
        if k >= 1 and r_new > MAX_CONTRACTION * rnorm:
            return _Newton(y, R, J, r_new, k + 1, False,
                           f"Newton stopped contracting (|R| {rnorm:.3e} -> {r_new:.3e})", J0)
        rnorm = r_new
    return _Newton(y, R, J, rnorm, max_iter, False, f"no convergence in {max_iter} Newton iterations", J0)


def _fixed_step(R, J, p) -> np.ndarray:
    """The Newton step ``dy`` from a converged point with its component ``p`` held (``J dy = -R``, ``dy[p] = 0``):
    the point's remaining distance from the solution at its parameter, to second order in it; NaN where ``J``
    without its column ``p`` is singular."""
    n = J.shape[1]
    keep = np.arange(n) != p % n
    dy = np.zeros(n)
    try:
        dy[keep] = np.linalg.solve(J[:, keep], -np.asarray(R, dtype=float))
    except np.linalg.LinAlgError:
        dy[:] = math.nan
    return dy


def _norm(R) -> float:
    """Euclidean norm of a short residual vector."""
    return math.sqrt(sum(v * v for v in R.tolist()))


