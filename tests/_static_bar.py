"""Static reference for the microslip bar under a growing tip displacement (tests only).

At omega = 0 and under monotone loading every point's shear layer is elastic-perfectly
plastic, so the bar solves one nonlinear boundary value problem per tip displacement X,

    EA u'' = min(k u, mu q(x)),    EA u'(0) = beta u(0),    u(L) = X,

with no assumption on how many slip zones there are.  Its energy is strictly convex, so the
solution is unique and rises with X everywhere: the slip set only grows and the tip force
EA u'(L) rises with X (the static loading curve cannot fold).  Solved here by second-order
finite differences on ``n`` cells (the x = 0 condition by a ghost node) and semi-smooth Newton;
the tip force by the global balance F = beta u(0) + int min(k u, mu q) (the trapezoid rule).
"""

import numpy as np
from scipy.linalg import solve_banded


def static_state(bar, load, X, n=20000):
    """``(x, u, F, slip)`` at tip displacement X > 0: nodes, displacement, tip force, and
    where the layer slips (k u >= mu q)."""
    S, L, k, beta, mu = bar.E * bar.A, bar.L, bar.k, bar.beta, bar.mu
    x = np.linspace(0.0, L, n + 1)
    h = L / n
    limit = mu * np.asarray(load.q(x), dtype=float)
    lam = np.sqrt(k / S)
    u = X * np.cosh(lam * x[:-1]) / np.cosh(lam * L)  # the stuck bar: a start inside the basin
    ab = np.zeros((3, n))  # the tridiagonal matrix of S u'' (free nodes 0 .. n-1), banded
    ab[0, 1:] = S / h**2
    ab[0, 1] = 2.0 * S / h**2  # node 0: ghost u_-1 = u_1 - 2 h beta u_0 / S
    ab[2, :-1] = S / h**2
    for _ in range(100):
        full = np.append(u, X)
        stuck = k * u < limit[:-1]
        g = np.where(stuck, k * u, limit[:-1])
        r = np.empty(n)
        r[1:] = S * (full[2:] - 2.0 * full[1:-1] + full[:-2]) / h**2 - g[1:]
        r[0] = S * (2.0 * full[1] - 2.0 * full[0]) / h**2 - 2.0 * beta * full[0] / h - g[0]
        ab[1] = -2.0 * S / h**2 - np.where(stuck, k, 0.0)
        ab[1, 0] -= 2.0 * beta / h
        du = solve_banded((1, 1), ab, -r)
        u = u + du
        if np.max(np.abs(du)) <= 1e-15 * X:
            break
    else:
        raise RuntimeError("static_state: Newton did not converge")
    u = np.append(u, X)
    slip = k * u >= limit
    g = np.where(slip, limit, k * u)
    F = beta * u[0] + h * (g.sum() - 0.5 * (g[0] + g[-1]))
    return x, u, F, slip


def slip_zones(x, slip):
    """The slip set as a list of intervals ``(start, end)`` (node positions)."""
    d = np.diff(slip.astype(int))
    starts = list(x[1:][d == 1])
    ends = list(x[:-1][d == -1])
    if slip[0]:
        starts.insert(0, x[0])
    if slip[-1]:
        ends.append(x[-1])
    return list(zip(starts, ends))
