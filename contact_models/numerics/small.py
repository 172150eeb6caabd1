"""Small dense numerics of the continuation: a pure-Python solve of a tiny system, and the cubic
through four points of a curve parametrised by chord length (``hbm.continuation``'s error per
step, ``hbm.curve``'s interpolant)."""

from __future__ import annotations

import numpy as np


def chords(ys, s) -> np.ndarray:
    """Cumulative chord lengths of the points ``ys`` in coordinates scaled by ``s`` (from 0)."""
    d = np.diff(np.asarray(ys, dtype=float), axis=0) / s
    return np.concatenate([[0.0], np.cumsum(np.sqrt(np.einsum("ij,ij->i", d, d)))])


def lagrange(ys, s, at=None) -> np.ndarray:
    """The cubic through the first four of ``ys`` (parametrised by chord length, scaled by ``s``) at
    chord length ``at`` (default: that of the fifth point, the extrapolation the step control checks)."""
    c = chords(ys, s)
    x = c[4] if at is None else at
    out = np.zeros_like(np.asarray(ys[0], dtype=float))
    for j in range(4):
        w = 1.0
        for m in range(4):
            if m != j:
                w *= (x - c[m]) / (c[j] - c[m])
        out = out + w * ys[j]
    return out


def solve_small(A, b):
    """Solve the small square system ``A x = b`` (pure-Python elimination for n <= 3)."""
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
