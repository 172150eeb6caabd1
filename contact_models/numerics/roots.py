"""Brent's root finder in plain Python, so that the packages need not import ``scipy.optimize``.

``import scipy.optimize`` costs about 0.25 s of CPU (it pulls in ``scipy.linalg`` and the
sparse machinery), more than the whole default frequency response; the library needs only a
bracketing scalar root finder.  :func:`brentq` follows R. P. Brent, *Algorithms for
Minimization without Derivatives* (1973), ch. 4, in the formulation of
``scipy.optimize.brentq`` (inverse quadratic extrapolation while ``|f|`` keeps falling, secant
after the bracket flips, bisection otherwise), with the same arguments, tolerance test
``|x_blk - x_cur| / 2 < (xtol + rtol |x_cur|) / 2`` and the same floating-point steps, so it
returns the same root to the last bit (``tests/test_imports.py`` compares them).
"""

from __future__ import annotations

import math
from typing import Callable

#: scipy.optimize.brentq's defaults and its smallest accepted rtol (4 eps).
XTOL = 2e-12
RTOL = 8.881784197001252e-16
MIN_RTOL = 4.0 * 2.220446049250313e-16


def brentq(f: Callable[[float], float], a: float, b: float, *, xtol: float = XTOL, rtol: float = RTOL,
           maxiter: int = 100) -> float:
    """A root of ``f`` in ``[a, b]`` (``f(a)``, ``f(b)`` of opposite signs) to ``xtol + rtol |x|``.

    Raises ``ValueError`` when ``f(a)`` and ``f(b)`` have the same sign or ``f`` returns NaN,
    ``RuntimeError`` when ``maxiter`` iterations do not converge (as ``scipy.optimize.brentq``).
    """
    if not xtol > 0.0:
        raise ValueError(f"xtol must be > 0, got xtol={xtol!r}")
    if rtol < MIN_RTOL:
        raise ValueError(f"rtol must be >= {MIN_RTOL!r}, got rtol={rtol!r}")

    def fun(x):
        v = float(f(x))
        if math.isnan(v):
            raise ValueError(f"the function value at x={x!r} is NaN; the root finder cannot continue")
        return v

    x_pre, x_cur = float(a), float(b)
    f_pre, f_cur = fun(x_pre), fun(x_cur)
    if f_pre == 0.0:
        return x_pre
    if f_cur == 0.0:
        return x_cur
    if math.copysign(1.0, f_pre) == math.copysign(1.0, f_cur):
        raise ValueError("f(a) and f(b) must have different signs")
    x_blk = f_blk = s_pre = s_cur = 0.0
    for _ in range(maxiter):
        if f_pre != 0.0 and f_cur != 0.0 and math.copysign(1.0, f_pre) != math.copysign(1.0, f_cur):
            x_blk, f_blk = x_pre, f_pre  # the root lies between x_cur and x_blk
            s_pre = s_cur = x_cur - x_pre
        if abs(f_blk) < abs(f_cur):  # x_cur is the best estimate so far
            x_pre, x_cur, x_blk = x_cur, x_blk, x_cur
            f_pre, f_cur, f_blk = f_cur, f_blk, f_cur
        delta = (xtol + rtol * abs(x_cur)) / 2
        s_bis = (x_blk - x_cur) / 2
        if f_cur == 0.0 or abs(s_bis) < delta:
            return x_cur
        if abs(s_pre) > delta and abs(f_cur) < abs(f_pre):
            if x_pre == x_blk:  # secant through x_pre, x_cur
                s_try = -f_cur * (x_cur - x_pre) / (f_cur - f_pre)
            else:  # inverse quadratic through the three points
                d_pre = (f_pre - f_cur) / (x_pre - x_cur)
                d_blk = (f_blk - f_cur) / (x_blk - x_cur)
                s_try = -f_cur * (f_blk * d_blk - f_pre * d_pre) / (d_blk * d_pre * (f_blk - f_pre))
            if 2 * abs(s_try) < min(abs(s_pre), 3 * abs(s_bis) - delta):
                s_pre, s_cur = s_cur, s_try  # a short enough step: take it
            else:
                s_pre = s_cur = s_bis
        else:
            s_pre = s_cur = s_bis
        x_pre, f_pre = x_cur, f_cur
        x_cur += s_cur if abs(s_cur) > delta else (delta if s_bis > 0 else -delta)
        f_cur = fun(x_cur)
    raise RuntimeError(f"brentq: no convergence in maxiter={maxiter} iterations (last x={x_cur!r})")
