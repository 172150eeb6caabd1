"""Small dense numerics of the continuation: a pure-Python solve of a tiny system, and the cubic
through four points of a curve parametrised by chord length (``hbm.continuation``'s error per
step, ``hbm.curve``'s interpolant)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray


def chords(ys: ArrayLike, s: NDArray) -> NDArray:
    """Cumulative chord lengths of the points ``ys`` in coordinates scaled by ``s``.

    Parameters
    ----------
    ys : array_like
        Points, (m, n).
    s : ndarray
        Positive weights, (n,): lengths are measured in ``y / s``.

    Returns
    -------
    ndarray
        (m,) chord lengths from the first point (0 first).

    Examples
    --------
    >>> chords([[0.0, 0.0], [3.0, 4.0], [3.0, 5.0]], np.ones(2)).tolist()
    [0.0, 5.0, 6.0]
    """
    d = np.diff(np.asarray(ys, dtype=float), axis=0) / s
    out = np.zeros(len(d) + 1)
    np.cumsum(np.sqrt((d * d).sum(axis=1)), out=out[1:])
    return out


def lagrange(ys: ArrayLike, s: NDArray, at: float | None = None) -> NDArray:
    """The cubic through the first four of ``ys``, parametrised by chord length, at ``at``.

    Parameters
    ----------
    ys : array_like
        Four points or more, (m >= 4, n); the cubic goes through the first four.
    s : ndarray
        Positive weights, (n,): chords are measured in ``y / s``.
    at : float, optional
        The chord length (from the first point) to evaluate at.  Default: that of the fifth point
        (the extrapolation the continuation's step control compares with it).

    Returns
    -------
    ndarray
        (n,) the point of the cubic (Lagrange form in the chord length).

    Examples
    --------
    Points of a straight line are reproduced exactly:

    >>> lagrange([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0], [3.0, 3.0], [4.0, 4.0]], np.ones(2)).round(12).tolist()
    [4.0, 4.0]
    """
    ys = np.asarray(ys, dtype=float)
    c = chords(ys, s).tolist()
    x = c[4] if at is None else float(at)
    w = [1.0, 1.0, 1.0, 1.0]
    for j in range(4):
        for m in range(4):
            if m != j:
                w[j] *= (x - c[m]) / (c[j] - c[m])
    return np.array(w) @ ys[:4]


def solve_small(A: NDArray, b: NDArray) -> NDArray:
    """Solve the small square system ``A x = b`` (pure-Python elimination for n <= 3).

    Parameters
    ----------
    A : ndarray
        (n, n) matrix.
    b : ndarray
        (n,) right-hand side.

    Returns
    -------
    ndarray
        (n,) solution; ``numpy.linalg.solve`` above n = 3.

    Raises
    ------
    numpy.linalg.LinAlgError
        If a pivot is exactly zero.

    Examples
    --------
    >>> solve_small(np.array([[2.0, 1.0], [1.0, 3.0]]), np.array([3.0, 5.0])).round(12).tolist()
    [0.8, 1.4]
    """
    n = len(b)
    if n > 3:
        return np.linalg.solve(A, b)
    M = A.tolist()
    v = b.tolist()
    for k in range(n):  # Gaussian elimination with partial pivoting
        piv = max(range(k, n), key=lambda r: abs(M[r][k]))
        if M[piv][k] == 0.0:
            raise np.linalg.LinAlgError("singular corrector matrix")
        if piv != k:
            M[k], M[piv] = M[piv], M[k]
            v[k], v[piv] = v[piv], v[k]
        for r in range(k + 1, n):
            f = M[r][k] / M[k][k]
            if f != 0.0:
                Mr, Mk = M[r], M[k]
                for c in range(k, n):
                    Mr[c] -= f * Mk[c]
                v[r] -= f * v[k]
    x = [0.0] * n
    for k in range(n - 1, -1, -1):
        acc = v[k]
        for c in range(k + 1, n):
            acc -= M[k][c] * x[c]
        x[k] = acc / M[k][k]
    return np.array(x)
