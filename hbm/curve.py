"""The curve between the points of a branch: its interpolant and the check of it at mid-points.

The points of a branch are joined by the cubic through the four nearest points (two on each
side; one-sided at the ends), parametrised by chord length in the continuation's scaled
coordinates at the interval's first point (``hbm.continuation.lagrange``).  It uses the points'
positions only, not their tangents: with AFT the tangent of the balance jumps by about ``1/n_t``
wherever a stick-slip transition crosses a sample, while the points themselves are good to the
sampling error.  :func:`midpoint_errors` measures the interpolant against converged solves: at the
middle of each interval, Newton on the balance in the hyperplane through the interpolated point
normal to the interval's chord; the error is the distance between the two in the response DOF's
first harmonic and omega (scaled: relative to the first-harmonic amplitude, omega to its reference).
``docs/hbm.md`` ("Step control by accuracy") derives the step control that keeps it below ``curve_tol``.
"""

from __future__ import annotations

import dataclasses
import math

from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from contact_models.numerics.small import chords, lagrange

from . import continuation as cont
from ._steps import _fixed_step
from .continuation import Residual, Scale


def _window(n: int, i: int, corners: Sequence[int]) -> slice | None:
    """The four points of the smooth piece around the interval (i, i + 1) of n points, or None
    (the interval crosses a corner, or its piece has fewer than four points: the chord)."""
    cuts = [0] + sorted(int(c) for c in corners if 0 < c < n) + [n]
    for a, b in zip(cuts, cuts[1:]):  # pieces [a, b)
        if a <= i and i + 1 < b:
            if b - a < 4:
                return None
            lo = min(max(i - 1, a), b - 4)
            return slice(lo, lo + 4)
    return None


def interpolate(y: ArrayLike, scale: Scale, i: int, fraction: float, corners: Sequence[int] = ()) -> NDArray:
    """The interpolated point at ``fraction`` of the chord of interval ``(i, i + 1)``.

    Parameters
    ----------
    y : ndarray
        The points of the branch, (npoints, n), in continuation order.
    scale : callable
        The continuation's ``scale(y) -> s`` (positive weights; the chords are measured in ``y / s(y_i)``).
    i : int
        The interval, 0 <= i < npoints - 1.
    fraction : float
        Where on the interval's chord, 0 (point i) to 1 (point i + 1).
    corners : sequence of int, optional
        Indices of points where the tangent jumps (the point after the kink,
        ``ContinuationResult.corners``): no window crosses them, and an interval across one is its chord.

    Returns
    -------
    ndarray
        The interpolated point, (n,).

    Examples
    --------
    Four points 0.1 rad apart on the unit circle: the middle interval's mid-point is off the
    circle by ``(9/16) h^4 / 4! = 2.3e-6`` (``docs/hbm.md``), the chord's by ``h^2 / 8 = 1.25e-3``.

    >>> import numpy as np
    >>> a = np.array([0.0, 0.1, 0.2, 0.3])
    >>> pts = np.column_stack([np.cos(a), np.sin(a)])
    >>> p = interpolate(pts, lambda u: np.ones(2), 1, 0.5)
    >>> round(float(np.hypot(*p)) - 1.0, 7)
    -2.3e-06
    """
    y = np.asarray(y, dtype=float)
    w = _window(len(y), i, corners)
    if w is None:
        return y[i] + fraction * (y[i + 1] - y[i])
    s = scale(y[i])
    c = chords(y[w], s)
    j = i - w.start
    return lagrange(list(y[w]), s, at=c[j] + fraction * (c[j + 1] - c[j]))


def dense(y: ArrayLike, scale: Scale, per_interval: int, corners: Sequence[int] = ()) -> NDArray:
    """The points ``y`` with ``per_interval - 1`` interpolated points inserted in every interval.

    Parameters
    ----------
    y : ndarray
        The points, (npoints, n).
    scale : callable
        The continuation's scale.
    per_interval : int
        Sub-intervals per interval (>= 1).
    corners : sequence of int, optional
        As for :func:`interpolate`.

    Returns
    -------
    ndarray
        ((npoints - 1) per_interval + 1, n) points, the given ones among them.
    """
    y = np.asarray(y, dtype=float)
    out = [y[0]]
    for i in range(len(y) - 1):
        out.extend(interpolate(y, scale, i, k / per_interval, corners) for k in range(1, per_interval))
        out.append(y[i + 1])
    return np.array(out)


def midpoint_errors(residual: Residual, y: ArrayLike, scale: Scale, components: Sequence[int], tol: float,
                    corners: Sequence[int] = (), max_iter: int = 12) -> NDArray:
    """Per interval, the error of the interpolant at its mid-point against a converged solve.

    Parameters
    ----------
    residual : callable
        ``residual(y) -> (R, J)`` of the branch (e.g. the balance, ``hbm.balance.HarmonicBalance``).
    y : ndarray
        The points, (npoints, n).
    scale : callable
        The continuation's scale.
    components : sequence of int
        The components of ``y`` the error is measured in (the response DOF's first harmonic and omega).
    tol : float
        Newton's tolerance on ``|R|``.
    corners : sequence of int, optional
        As for :func:`interpolate`.
    max_iter : int, optional
        Newton iterations.  Default 12.

    Returns
    -------
    ndarray
        (npoints - 1,) scaled distances between the interpolated mid-point and the converged point
        in the hyperplane through it normal to the chord; inf where Newton did not converge.
    """
    y = np.asarray(y, dtype=float)
    k = np.asarray(components, dtype=int)
    count = cont._Count()
    return np.array([_midpoint(residual, y, scale, i, corners, k, tol, max_iter, count)[1]
                     for i in range(len(y) - 1)])


def _midpoint(residual: Residual, y: NDArray, scale: Scale, i: int, corners: Sequence[int], k: NDArray,
              tol: float, max_iter: int, count: cont._Count) -> tuple[cont._Newton, float]:
    """Newton at the mid-point of interval ``i``, in the hyperplane through the interpolated point
    normal to the chord, and the scaled distance (components ``k``) of the converged point from the
    interpolated one (inf where Newton did not converge)."""
    s = scale(y[i])
    um = interpolate(y, scale, i, 0.5, corners)
    w = (y[i + 1] - y[i]) / s / s  # the chord, as a normal in physical coordinates
    sol = cont._newton(residual, um, w, float(w @ um), tol, max_iter, count)
    if not sol.converged:
        return sol, math.inf
    d = (sol.y[k] - um[k]) / s[k]
    return sol, float(np.sqrt(d @ d))


#: Rounds of the refinement; an interval is solved at its mid-point when the two cubics of the
#: neighbouring windows disagree there by more than ``EMBEDDED_SHARE * curve_tol`` (or it has no
#: second window), and split at the converged mid-point when that is off by more than ``curve_tol``.
REFINE_ROUNDS = 3
EMBEDDED_SHARE = 0.25


def _disagreement(y: NDArray, scale: Scale, i: int, corners: Sequence[int], k: NDArray) -> float:
    """The largest distance (scaled, components ``k``) at the mid-point of interval ``i`` between
    its interpolant and the cubic of a neighbouring window of the same piece; inf without one."""
    n = len(y)
    w = _window(n, i, corners)
    if w is None:
        return math.inf
    s = scale(y[i])
    um = interpolate(y, scale, i, 0.5, corners)
    best = -1.0
    for lo in (w.start - 1, w.start + 1):
        if lo < 0 or lo + 4 > n or not lo <= i < i + 1 <= lo + 3:
            continue
        if any(lo < int(c) <= lo + 3 for c in corners):  # the window would cross a corner
            continue
        c = chords(y[lo:lo + 4], s)
        j = i - lo
        alt = lagrange(list(y[lo:lo + 4]), s, at=c[j] + 0.5 * (c[j + 1] - c[j]))
        d = (alt[k] - um[k]) / s[k]
        best = max(best, float(np.sqrt(d @ d)))
    return best if best >= 0.0 else math.inf


def refine(residual: Residual, run: cont.ContinuationResult, scale: Scale, components: Sequence[int],
           curve_tol: float, tol: float, parameter: int = -1,
           max_iter: int = cont.NEWTON_MAX_ITER) -> cont.ContinuationResult:
    """The branch with every interval's interpolant within ``curve_tol`` at its mid-point, or listed.

    An interval whose neighbouring cubics disagree at its mid-point by more than
    ``EMBEDDED_SHARE * curve_tol`` (or that has no second window) is solved there; where the
    converged point is more than ``curve_tol`` off it is inserted, and the new halves and their
    neighbours are checked again (``REFINE_ROUNDS`` rounds).  Intervals still off, and intervals
    across a corner that are off, are listed in ``coarse`` by the index of their second point.

    Parameters
    ----------
    residual : callable
        ``residual(y) -> (R, J)``.
    run : hbm.continuation.ContinuationResult
        The branch.
    scale : callable
        The continuation's scale.
    components : sequence of int
        The components the error is measured in.
    curve_tol : float
        The tolerance (scaled distance).
    tol : float
        Newton's tolerance on ``|R|``.
    parameter : int, optional
        The index of the continuation parameter (for the folds).  Default -1.
    max_iter : int, optional
        Newton iterations.

    Returns
    -------
    hbm.continuation.ContinuationResult
        ``run`` with the inserted points (tangents, residual norms, iterations), the folds and
        corners re-indexed, ``coarse`` as measured, and the work added to ``nit`` and ``nfev``.
    """
    k = np.asarray(components, dtype=int)
    y, t = list(run.y), list(run.tangent)
    rn, its = list(run.residual_norm), list(run.iterations)
    steps = list(run.newton_step) if run.newton_step is not None and len(run.newton_step) == len(y) else None
    corners = [int(c) for c in run.corners]
    fold_after = [int(f) for f in run.fold_after]
    count = cont._Count()
    check = set(range(len(y) - 1))
    coarse = set()
    for rnd in range(REFINE_ROUNDS + 1):
        inserted = []
        Y = np.asarray(y)
        for i in sorted(check):
            if _disagreement(Y, scale, i, corners, k) <= EMBEDDED_SHARE * curve_tol:
                continue
            sol, err = _midpoint(residual, Y, scale, i, corners, k, tol, max_iter, count)
            if not sol.converged:
                coarse.add(i + 1)
                continue
            if err <= curve_tol:
                continue
            if (i + 1) in corners or rnd == REFINE_ROUNDS:  # a kink inside, or the last round: listed
                coarse.add(i + 1)
                continue
            inserted.append((i, sol))
        if not inserted:
            break
        for i, sol in reversed(inserted):  # from the end, so that the indices before stay valid
            s = scale(sol.y)
            tm = cont._tangent(sol.J, s, cont._rescale(t[i], scale(y[i]), s))
            y.insert(i + 1, sol.y)
            t.insert(i + 1, tm)
            rn.insert(i + 1, sol.rnorm)
            its.insert(i + 1, sol.iterations)
            if steps is not None:
                steps.insert(i + 1, _fixed_step(sol.R, sol.J, parameter))
            corners = [c + 1 if c > i else c for c in corners]
            coarse = {c + 1 if c > i else c for c in coarse}
            fold_after = [f if f < i else f + 1 if f > i else (f if t[i][parameter] * tm[parameter] < 0.0 else f + 1)
                          for f in fold_after]
        check = set()  # the new halves and their neighbours (their windows changed)
        for j, (i, _) in enumerate(inserted):
            at = i + j  # index of interval (i, mid) after the earlier insertions
            check.update(range(max(at - 2, 0), min(at + 4, len(y) - 1)))
    return dataclasses.replace(run, y=np.array(y), tangent=np.array(t), residual_norm=np.array(rn),
                               newton_step=None if steps is None else np.array(steps),
                               iterations=np.array(its, dtype=int), fold_after=np.array(fold_after, dtype=int),
                               corners=np.array(corners, dtype=int), coarse=np.array(sorted(coarse), dtype=int),
                               nit=run.nit + count.nit, nfev=run.nfev + count.nfev)
