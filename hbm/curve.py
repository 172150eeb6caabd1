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

import numpy as np
from numpy.typing import NDArray

from contact_models.numerics.small import chords, lagrange

from . import continuation as cont


def _window(n: int, i: int, corners) -> slice | None:
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


def interpolate(y: NDArray, scale, i: int, fraction: float, corners=()) -> NDArray:
    """The interpolated point at ``fraction`` (0..1) of the chord of interval ``(i, i + 1)`` of the
    points ``y`` (npoints, n), with the continuation's ``scale``; ``corners``: indices of points
    where the tangent jumps (the point after the kink, ``ContinuationResult.corners``)."""
    y = np.asarray(y, dtype=float)
    w = _window(len(y), i, corners)
    if w is None:
        return y[i] + fraction * (y[i + 1] - y[i])
    s = scale(y[i])
    c = chords(y[w], s)
    j = i - w.start
    return lagrange(list(y[w]), s, at=c[j] + fraction * (c[j + 1] - c[j]))


def dense(y: NDArray, scale, per_interval: int, corners=()) -> NDArray:
    """The points ``y`` with ``per_interval - 1`` interpolated points inserted in every interval."""
    y = np.asarray(y, dtype=float)
    out = [y[0]]
    for i in range(len(y) - 1):
        out.extend(interpolate(y, scale, i, k / per_interval, corners) for k in range(1, per_interval))
        out.append(y[i + 1])
    return np.array(out)


def midpoint_errors(residual, y: NDArray, scale, components, tol: float, corners=(), max_iter: int = 12) -> NDArray:
    """Per interval, the scaled distance (in ``components``) between the interpolated mid-point and
    the converged point of ``residual`` in the hyperplane through it normal to the chord; NaN where
    Newton did not converge."""
    y = np.asarray(y, dtype=float)
    k = np.asarray(components, dtype=int)
    out = np.full(max(len(y) - 1, 0), np.nan)
    count = cont._Count()
    for i in range(len(y) - 1):
        s = scale(y[i])
        um = interpolate(y, scale, i, 0.5, corners)
        w = (y[i + 1] - y[i]) / s / s  # the chord, as a normal in physical coordinates
        sol = cont._newton(residual, um, w, float(w @ um), tol, max_iter, count)
        if sol.converged:
            d = (sol.y[k] - um[k]) / s[k]
            out[i] = float(np.sqrt(d @ d))
    return out
