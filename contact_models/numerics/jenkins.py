"""The Jenkins element's periodic force in closed form: Fourier coefficients and Jacobian, no sampling.

For a relative displacement ``x(theta) = X0 + sum_h (Xc_h cos h theta + Xs_h sin h theta)`` (h = 1..H)
the steady force of a Jenkins element (spring ``k`` behind a Coulomb slider of force ``fs``, the
centred slider of :mod:`contact_models.numerics.masing`) is piecewise:

- stuck: ``f = f_a + k (x(theta) - x(theta_a))``, ``theta_a`` the reversal (``x' = 0``) that ended
  the last slip, ``f_a = +-fs`` there; never slipping (``k a <= fs``, ``a`` half the range of ``x``),
  ``f = k (x - (x_max + x_min)/2)``;
- slipping: ``f = +-fs``,

with the switching instants at the reversals and where ``f`` reaches ``+-fs`` (one level crossing of
``x`` in a monotone stretch).  The march starts at the global maximum, where ``f = min(k a, fs)``:
Masing's rules with memory, as :func:`contact_models.numerics.masing.masing_periodic` marches them on
samples.  Every piece is a constant or ``k x(theta)`` plus a constant, so the Fourier integrals are
sums of ``integral exp(-i n theta)`` over the pieces, n = 0..2H; the force is continuous in theta,
so the Jacobian is the integral of ``df/dX`` (the switching instants drop out).  Derivation, every
coefficient and the handling of close reversals: ``docs/multiharmonic.md``, "The Jenkins element
in closed form".
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]

#: Grid of x' for the reversals: at least this many cells per harmonic (a power of two, >= GRID_MIN).
GRID_PER_HARMONIC = 8
GRID_MIN = 32
#: A cell the grid cannot certify is split into this many parts, level after level.
SPLIT = 8
#: Two reversals closer than the finest cell are not resolved: the inner loop they would open is
#: then smaller than this fraction of the displacement's oscillation (``sum_h |X_h|``).
WIGGLE_RTOL = 1e-15
#: Reversals closer than this (rad) are one: the same root found from two cells, or a pair whose
#: inner loop (about |x''| 1e-24) is below rounding.  The march takes each stretch's direction from
#: the values of x, so a reversal too many or a pair too few changes nothing.
SAME_REVERSAL = 1e-12
#: Most iterations (Newton; bisection where Newton leaves the bracket) for a reversal or a
#: stick -> slip instant (bisection alone halves a bracket of at most 2 pi to rounding in 55).
NEWTON_ITERATIONS = 60
#: Newton stops after a step below this (rad): quadratic convergence leaves an error of about its
#: square times |x''/(2 x')| (1e-14 rad for a path of a few harmonics; the starts from the cubic
#: through a grid cell are usually within it already).  The force is continuous at every switching
#: instant, so an error dtheta there moves F by O(k |x'| dtheta^2) (stick -> slip) or
#: O(k |x''| dtheta^3) (a reversal), and the Jacobian by O(k H dtheta) (the anchors, the pieces' ends).
STEP_DONE = 1e-7
#: ``x`` at a reversal comes from its Newton start by Taylor's formula where the remainder is below
#: this fraction of ``sum |C_m|`` (a sixteenth of a rounding unit of ``x``); else it is summed again.
TAYLOR_RTOL = 2.0**-56


def jenkins_harmonics(X: Array, k: float, fs: float) -> tuple[Array, Array]:
    """``(F, dF/dX)`` of the Jenkins element's steady force for the displacement coefficients ``X``.

    Parameters
    ----------
    X : ndarray
        ``[X0, Xc1, Xs1, ..., XcH, XsH]`` (m), length 2H+1, finite.
    k, fs : float
        Spring stiffness (N/m, finite, > 0) and slip force (N, > 0).

    Returns
    -------
    F : ndarray
        The force's coefficients (N), same layout, exact to rounding (no sampling).
    J : ndarray
        ``dF/dX`` (2H+1, 2H+1), exact where the force is differentiable.

    Examples
    --------
    >>> import numpy as np
    >>> F, J = jenkins_harmonics(np.array([0.0, 0.0, 2.0, 0.0, 0.0]), 1.0, 1.0)
    >>> np.round(F * np.pi, 12).tolist()   # f_s = a (psi - sin 2 psi/2)/pi at psi = pi/2; f_c = 2/pi
    [0.0, 2.0, 3.14159265359, 0.0, 0.0]
    """
    X = np.ascontiguousarray(X, dtype=float)
    H = (X.size - 1) // 2
    if H == 0:
        return _stuck(X, k, 0.0, 0.0, np.pi, H)
    C = np.conjugate(X[1:].view(np.complex128))  # C_m = Xc_m - i Xs_m: x = X0 + Re sum_m C_m e^{i m theta}
    c = _constants(H)
    bounds = (np.abs(C) @ c.m341).tolist()  # M3, M4, sum |C_m|
    if bounds[2] == 0.0:
        return _stuck(X, k, 0.0, 0.0, np.pi, H)
    D = C[:, None] * c.dfac  # columns: C_m, i m C_m, -m^2 C_m (x - X0, x', x'')
    th, xr, grid = _reversals(C, D, c, bounds)
    if xr is None:
        xr = (np.exp(np.multiply.outer(th, c.im)) @ C).real.tolist()
    X0 = float(X[0])
    xr = [X0 + v for v in xr]
    iM = max(range(len(xr)), key=xr.__getitem__)
    im = min(range(len(xr)), key=xr.__getitem__)
    a = 0.5 * (xr[iM] - xr[im])
    if k * a <= fs:
        return _stuck(X, k, 0.5 * (xr[iM] + xr[im]), th[iM], th[im], H)
    two_pi = 2.0 * math.pi  # from the global maximum round to it again
    th = th[iM:] + [t + two_pi for t in th[:iM + 1]]
    xr = xr[iM:] + xr[:iM + 1]
    pieces, levels = _march(xr, k, fs)
    return _integrals(X, k, th, _crossings(X0, D, th, xr, levels, grid, c), pieces, H, c)


def _stuck(X: Array, k: float, xc: float, th_max: float, th_min: float, H: int) -> tuple[Array, Array]:
    """Stuck all period: ``f = k (x - x_c)``, ``F = k X`` less ``k x_c`` in ``F0``;
    ``dx_c/dX = (phi(theta_max) + phi(theta_min))/2`` (``x' = 0`` at both)."""
    F = k * X
    F[0] -= k * xc
    J = k * np.eye(2 * H + 1)
    J[0, 0] -= k  # the basis' 1 at both instants
    if H:  # cos m theta, sin m theta: e^{i m theta} seen as floats
        e = np.exp(np.multiply.outer([th_max, th_min], _constants(H).im))
        J[0, 1:] -= (0.5 * k) * (e[0] + e[1]).view(np.float64)
    return F, J


class _Constants:
    """What depends on H only, formed once per H (:func:`_constants`)."""

    __slots__ = ("n_h", "n", "w", "fac", "m341", "im", "dfac", "exps", "i_n", "half")

    def __init__(self, H: int):
        n = max(GRID_MIN, 1 << int(math.ceil(math.log2(GRID_PER_HARMONIC * H))))
        self.n_h = H
        m = np.arange(1, H + 1, dtype=float)
        mi = np.arange(1, H + 1)
        #: the grid: its size (a power of two >= GRID_PER_HARMONIC H and >= GRID_MIN) and its cell
        self.n, self.w = n, 2.0 * np.pi / n
        #: the factors taking C_m to the inverse real FFT's input of x - X0, x' and x'' (3, H)
        self.fac = (0.5 * n) * np.stack((np.ones(H) + 0j, 1j * m, -m * m + 0j))
        #: [m^3, m^4, 1] (H, 3): from |C_m|, the bounds M3, M4 and sum |C_m|
        self.m341 = np.stack((m**3, m**4, np.ones(H)), axis=1)
        #: i m, the exponents of e^{i m theta}; [1, i m, -m^2] (H, 3), the factors of x - X0, x', x''
        self.im = 1j * mi
        self.dfac = np.stack((np.ones(H, dtype=complex), 1j * mi, -(mi * mi) + 0j), axis=1)
        #: i r (r = 0..7) and 8i q (q = 0.., 8q > 2H): e^{i n theta} = e^{8i q theta} e^{i r theta}, n = 8q + r;
        #: [1, -i/n], n = 1..2H: the pieces' (conjugated) integrals from their ends
        self.exps = 1j * np.concatenate((np.arange(8), 8 * np.arange(-(-(2 * H + 1) // 8))))
        self.i_n = np.concatenate(([1.0 + 0j], -1j / np.arange(1, 2 * H + 1)))
        #: [1/2, i/2, -i/2]: the factors of the S_n in T
        self.half = np.array([[0.5], [0.5j], [-0.5j]])


@lru_cache(maxsize=32)
def _constants(H: int) -> _Constants:
    return _Constants(H)


# ------------------------------------------------------------------ reversals
def reversals(C: NDArray[np.complex128]) -> Array:
    """The reversals of a trigonometric path: the instants in [0, 2 pi) where ``x'`` changes sign.

    Parameters
    ----------
    C : ndarray of complex
        ``C_m = Xc_m - i Xs_m``, m = 1..H: ``x = X0 + Re sum_m C_m e^{i m theta}``; not all zero.

    Returns
    -------
    ndarray
        The instants (rad), sorted; two that enclose an inner loop below ``WIGGLE_RTOL sum |C_m|``
        may be missed, and two closer than ``SAME_REVERSAL`` are kept once.

    Examples
    --------
    >>> import numpy as np
    >>> np.round(reversals(np.array([1.0 + 0j])), 12).tolist()   # x = cos theta
    [0.0, 3.14159265359]
    """
    C = np.asarray(C, dtype=complex)
    c = _constants(C.size)
    return np.array(_reversals(C, C[:, None] * c.dfac, c, (np.abs(C) @ c.m341).tolist())[0])


def _reversals(C: NDArray[np.complex128], D: NDArray[np.complex128], c: _Constants,
               bounds: list) -> tuple[list, list | None, tuple]:
    """The instants in [0, 2 pi) where ``x'`` changes sign, for ``x = Re sum_m C_m e^{i m theta}``
    (m = 1..H; ``D`` the columns ``C_m, i m C_m, -m^2 C_m``, ``bounds`` = ``[M3, M4, sum |C_m|]``),
    sorted; ``x - X0`` there, or None (:func:`_polish`); the grid ``(x - X0, x', w, n)``, where the
    stick -> slip instants start.

    ``x'`` and ``x''`` on a grid (inverse real FFT); with ``M3 = sum m^3 |C_m|`` and
    ``M4 = sum m^4 |C_m|`` bounding ``|x'''|`` and ``|x''''|``, a cell of width ``w`` is certified
    free of roots where ``x'`` keeps its sign and ``min |x'| > M3 w^2/8`` at its ends (the linear
    interpolant's error bound), and to hold one root where ``x'`` changes sign and ``x''`` keeps
    its sign with ``min |x''| > M4 w^2/8``.  Other cells are split (:data:`SPLIT`) until certified or
    until a pair of roots they might hide would open an inner loop below ``M3 w^3/8 <=
    WIGGLE_RTOL sum |C_m|``.  Each root is then found by bracketed Newton from the cubic through
    the cell's ends.
    """
    H, n, w = C.size, c.n, c.w
    M3, M4, sum_abs = bounds
    spec = np.zeros((3, n // 2 + 1), dtype=complex)
    np.multiply(c.fac, C, out=spec[:, 1:H + 1])
    xg, g, gp = np.fft.irfft(spec, n=n)
    # the cells [i w, (i + 1) w] the grid alone does not certify free of roots (next to the roots):
    # x' neither above M3 w^2/8 at both ends nor below -M3 w^2/8 at both (a sign change, or small)
    free = M3 * w * w / 8.0
    ge = np.concatenate((g, g[:1]))
    lo, hi = np.minimum(ge[:-1], ge[1:]), np.maximum(ge[:-1], ge[1:])
    cells = np.flatnonzero((lo <= free) & (hi >= -free)).tolist()
    found: list = []
    gi, gpi = ge.item, gp.item
    dx = D[:, 1:]  # x', x''
    cell_bounds = (M3, M4, WIGGLE_RTOL * sum_abs)
    for i in cells:
        _cell(dx, cell_bounds, i * w, w, gi(i), gi(i + 1), gpi(i), gpi((i + 1) % n), found, c)
    roots, xs = _polish(D, c, [0.0] * len(found), [_hermite_root(*f) for f in found],
                        [(t, t + cw, q > p) for t, cw, p, q, _, _ in found], (M3, sum_abs))
    two_pi = 2.0 * math.pi
    th = sorted(zip([r % two_pi for r in roots], xs or [0.0] * len(roots)))  # Python floats: a few roots
    if len(th) > 1:  # one reversal found from two cells (the grid's and the direct sums' rounding differ)
        nxt = th[1:] + [(th[0][0] + two_pi, 0.0)]
        th = [t for t, u in zip(th, nxt) if u[0] - t[0] > SAME_REVERSAL] or th[:1]
    return [t for t, _ in th], None if xs is None else [v for _, v in th], (xg, g, w, n)


def _hermite_root(lo: float, w: float, g0: float, g1: float, p0: float, p1: float) -> float:
    """The root in ``[lo, lo + w]`` of the cubic through the values g0, g1 (of opposite signs) with
    the slopes p0, p1 at the ends (Newton on it from the secant, kept in the cell): a start within
    O(w^4) of the root of a smooth function."""
    t = -g0 / (g1 - g0) if g1 != g0 else 0.5  # in units of w
    d0, d1 = p0 * w, p1 * w  # the cubic g0 + t (d0 + t (c2 + t c3)) on t in [0, 1]
    c2, c3 = 3.0 * (g1 - g0) - 2.0 * d0 - d1, 2.0 * (g0 - g1) + d0 + d1
    for _ in range(3):
        dv = d0 + t * (2.0 * c2 + 3.0 * c3 * t)
        if dv == 0.0:
            break
        t = min(max(t - (g0 + t * (d0 + t * (c2 + t * c3))) / dv, 0.0), 1.0)
    return lo + t * w


def _cell(dx: NDArray[np.complex128], bounds: tuple, lo: float, w: float, g0: float, g1: float, p0: float,
          p1: float, found: list, c: _Constants) -> None:
    """Certify the cell ``[lo, lo + w]`` (``x'`` = g0, g1 and ``x''`` = p0, p1 at its ends; ``dx`` the
    columns ``i m C_m, -m^2 C_m``): append ``(lo, w, g0, g1, p0, p1)`` to ``found`` if it holds one
    root (or is finest and ``x'`` changes sign), nothing if it holds none, else split it
    (:func:`_reversals`)."""
    M3, M4, tiny = bounds
    change = (g0 >= 0.0) != (g1 >= 0.0)
    if M3 * w**3 / 8.0 <= tiny:  # finest: a pair of roots it may hide is an inner loop below rounding
        if change:
            found.append((lo, w, g0, g1, p0, p1))
        return
    if change and p0 * p1 > 0.0 and min(abs(p0), abs(p1)) > M4 * w * w / 8.0:
        found.append((lo, w, g0, g1, p0, p1))
        return
    if not change and min(abs(g0), abs(g1)) > M3 * w * w / 8.0:
        return
    w /= SPLIT
    pts = lo + w * np.arange(SPLIT + 1)
    gg, pp = (v.tolist() for v in (np.exp(np.multiply.outer(pts, c.im)) @ dx).real.T)
    for j in range(SPLIT):
        _cell(dx, bounds, float(pts[j]), w, gg[j], gg[j + 1], pp[j], pp[j + 1], found, c)


def _polish(D: NDArray[np.complex128], c: _Constants, offsets: list, starts: list, brackets: list,
            taylor: tuple | None = None) -> tuple[list, list | None]:
    """The roots of ``r_j = offsets[j] + Re sum_m D[m, -2] e^{i m theta}`` (its derivative
    ``Re sum_m D[m, -1] e^{i m theta}``), each from ``starts[j]`` in its bracket
    ``brackets[j] = (a, b, up)`` (``up``: ``r_j`` increases through it), as :func:`_newton` finds
    them, its first step taken for all the roots in one product (usually the only step).

    With ``taylor = (M3, sum |C_m|)`` and ``D``'s columns ``x - X0, x', x''``, also ``x - X0`` at the
    roots: ``x + d (x' + x'' d/2)`` at the start, ``d`` the step, where every root took that one step
    and the remainder ``M3 |d|^3/6`` (``M3`` bounds ``|x'''|``) is below ``TAYLOR_RTOL sum |C_m|``;
    else None (then the caller sums ``x`` again)."""
    xs = [] if taylor is not None else None
    if not starts:
        return [], xs
    vals = (np.exp(np.multiply.outer(starts, c.im)) @ D).real.tolist()
    out = []
    AB = None
    for th, off, v, (a, b, up) in zip(starts, offsets, vals, brackets):
        r, d = v[-2] + off, v[-1]
        new, a, b, stepped = _step(th, r, d, a, b, up)
        done = stepped and abs(new - th) <= STEP_DONE
        if not done:  # the rest of the iterations one root at a time
            if AB is None:
                AB = D[:, -2].tolist(), D[:, -1].tolist()
            new = _newton(*AB, off, new, a, b, up, NEWTON_ITERATIONS - 1)
            xs = None
        elif xs is not None:
            step = new - th
            if taylor[0] * abs(step) ** 3 <= 6.0 * TAYLOR_RTOL * taylor[1]:
                xs.append(v[0] + step * (r + 0.5 * d * step))
            else:
                xs = None
        out.append(new)
    return out, xs


def _pair(A: list, B: list, th: float) -> tuple[float, float]:
    """``(Re sum_m A_m e^{i m th}, Re sum_m B_m e^{i m th})``, m = 1.., on Python floats (the powers by
    recurrence: a relative error of m rounding units, cheaper than arrays for a few points)."""
    z = complex(math.cos(th), math.sin(th))
    p, sa, sb = z, 0j, 0j
    for a, b in zip(A, B):
        sa += a * p
        sb += b * p
        p *= z
    return sa.real, sb.real


def _step(th: float, r: float, d: float, a: float, b: float, up: bool) -> tuple[float, float, float, bool]:
    """One safeguarded Newton step on ``r`` (derivative ``d``) at ``th``: the bracket ``[a, b]`` narrowed to
    the side the root is on (``up``: ``r`` increases through it), then ``(new, a, b, True)`` for the Newton
    step, or ``(middle, a, b, False)`` where that step leaves the bracket (or ``d`` is 0)."""
    if (r < 0.0) == up:
        a = th
    else:
        b = th
    new = th - r / d if d != 0.0 else math.nan
    if not a <= new <= b:  # also nan
        return 0.5 * (a + b), a, b, False
    return new, a, b, True


def _newton(A: list, B: list, offset: float, th: float, a: float, b: float, up: bool,
            iterations: int = NEWTON_ITERATIONS) -> float:
    """The root in ``[a, b]`` of ``r = offset + Re sum A_m e^{i m theta}`` (derivative
    ``Re sum B_m e^{i m theta}``), which increases through it if ``up``: Newton from ``th``, the
    bracket's middle where a step leaves the bracket, until a step is below :data:`STEP_DONE`."""
    for _ in range(iterations):
        r, d = _pair(A, B, th)
        new, a, b, stepped = _step(th, r + offset, d, a, b, up)
        if not stepped:
            th = new
            continue
        done = abs(new - th) <= STEP_DONE
        th = new
        if done:
            break
    return th


# ------------------------------------------------------------------ the march and the integrals
def _march(xr: list, k: float, fs: float) -> tuple[list, list]:
    """Masing's rules with memory over the reversals ``xr`` (from the global maximum, ``xr[-1]`` the
    same maximum a period later) of a path that slips.

    Returns the pieces ``(start, end, g, anchor)``, ``f = g + k x`` on a stuck piece (``anchor`` the
    reversal that ended the last slip) and ``f = g = +-fs`` on a slipping one (``anchor = -1``);
    ``start`` and ``end`` are reversal indices, or ``-(j + 1)`` for the j-th stick -> slip instant,
    the level ``x = levels[j][1]`` crossed in the stretch after reversal ``levels[j][0]``.
    """
    anchor, fa = 0, fs  # the tip of the outer loop: the slip upwards has just ended
    pieces: list = []
    levels: list = []
    for i in range(len(xr) - 1):
        s = 1.0 if xr[i + 1] > xr[i] else -1.0
        g = fa - k * xr[anchor]
        level = xr[anchor] + (s * fs - fa) / k  # f = f_a + k (x - x_a) reaches s fs here
        if s * (xr[i + 1] - level) > 0.0:
            code = -(len(levels) + 1)
            levels.append((i, level))
            pieces += [(i, code, g, anchor), (code, i + 1, s * fs, -1)]
            anchor, fa = i + 1, s * fs
        else:
            pieces.append((i, i + 1, g, anchor))
    return pieces, levels


def _crossings(X0: float, D: NDArray[np.complex128], th: list, xr: list, levels: list, grid: tuple,
               c: _Constants) -> list:
    """The instants where ``x`` crosses ``levels[j][1]`` in the monotone stretch after reversal
    ``levels[j][0]``: the grid cell that holds it (bisection on the grid's ``x`` in the stretch),
    the cubic through its ends (``x``, ``x'``; a reversal's ``x' = 0`` where the stretch ends in
    the cell), then Newton, kept in the stretch (:func:`_polish`)."""
    xg, dg, w, n = grid
    xi, di = xg.item, dg.item
    starts, offsets, brackets = [], [], []
    for i, level in levels:
        a, b, xa, xb = th[i], th[i + 1], xr[i] - X0, xr[i + 1] - X0
        L = level - X0
        s = 1.0 if xb > xa else -1.0
        j0, j1 = math.floor(a / w) + 1, math.ceil(b / w)  # the grid points in (a, b): j0 .. j1 - 1
        lo, hi = j0, j1
        while lo < hi:  # the first grid point at or past the level
            mid = (lo + hi) // 2
            if s * (xi(mid % n) - L) >= 0.0:
                hi = mid
            else:
                lo = mid + 1
        tl, vl, dl = (a, xa, 0.0) if lo == j0 else ((lo - 1) * w, xi((lo - 1) % n), di((lo - 1) % n))
        tr, vr, dr = (b, xb, 0.0) if lo == j1 else (lo * w, xi(lo % n), di(lo % n))
        starts.append(_hermite_root(tl, tr - tl, vl - L, vr - L, dl, dr) if tr > tl else tl)
        offsets.append(X0 - level)
        brackets.append((a, b, s > 0.0))
    return _polish(D[:, :2], c, offsets, starts, brackets)[0]


def _integrals(X: Array, k: float, th: list, cross: list, pieces: list, H: int, c: _Constants) -> tuple[Array, Array]:
    """``(F, dF/dX)`` from the pieces: ``hat F_h = (1/pi) integral f e^{-i h theta}`` =
    ``(1/pi)[sum_p g_p E_h(p) + k (T X)_h]`` with ``E_n(p) = integral_p e^{-i n theta}`` and ``T`` the
    stuck pieces' integrals of the basis times ``e^{-i h theta}``; ``d hat F/dX = (k/pi)[T - sum_stuck
    E(p) phi(theta_a(p))^T]``; ``F0 = Re hat F_0/2``, ``Fc_h = Re hat F_h``, ``Fs_h = -Im hat F_h``.

    Formed in that real layout directly (a complex row ``v_0..v_H`` conjugated and seen as floats is
    ``[Re v_0, -Im v_0, Re v_1, -Im v_1, ...]``), where ``T = diag(1/2, 1, 1, ...) G``, ``G`` the stuck
    pieces' integral of ``phi phi^T``.  The rows of ``conj(T^T)`` (entries ``S_{m-h}``, ``S_{-m-h}``
    as ``conj S_n = S_{-n}``: Toeplitz and Hankel views of the ``S_n``) seen as floats without their
    second entry (``-Im v_0``) are the columns of ``G``, so its rows (``G`` is symmetric); halving
    the first gives ``T``."""
    P = len(pieces)
    stuck = [j for j, p in enumerate(pieces) if p[3] >= 0]
    L, q = 2 * H + 1, c.exps.size - 8  # 8 + q exponents
    # the breakpoints: theta, then e^{i n theta} = e^{8i q theta} e^{i r theta}, n = 8q + r = 1..
    ba = np.array([th[p[0]] if p[0] >= 0 else cross[-p[0] - 1] for p in pieces] + [th[-1]])
    U = np.empty((P + 1, 8 * q), dtype=complex)
    e = np.exp(np.multiply.outer(ba, c.exps))
    np.multiply(e[:, 8:, None], e[:, None, :8], out=U.reshape(P + 1, q, 8))
    U[:, 0] = ba
    Ec = (U[1:, :L] - U[:-1, :L]) * c.i_n  # conj E_n(p), n = 0..2H
    Sc = Ec[stuck[0]].copy()  # conj S_n, n = 0..2H
    for j in stuck[1:]:
        Sc += Ec[j]
    # S_{2H - j} at j = 0..4H (S_{-n} = conj S_n), times 1/2, i/2 and -i/2
    hs = c.half * np.concatenate((Sc[::-1].conj(), Sc[1:]))
    Tc = np.empty((L, H + 1), dtype=complex)  # conj(T^T) but its first row halved
    Tc[0] = hs[0, 2 * H:3 * H + 1]  # conj S_h / 2
    # (S_{m-h} + S_{-m-h})/2 and i (S_{m-h} - S_{-m-h})/2, rows 2m-1 and 2m: Toeplitz and Hankel views
    np.add(_view(hs, 2 * H - 1, -1, 1, c), _view(hs, 2 * H + 1, 1, 2, c), out=Tc[1:].reshape(H, 2, H + 1))
    T = Tc.view(np.float64)
    T[:, 1] = T[:, 0]  # the second entry of each row left out
    T = T[:, 1:]  # T in the real layout
    Er = Ec[:, :H + 1].view(np.float64)
    np.multiply(Er[:, 0], 0.5, out=Er[:, 1])
    Er = Er[:, 1:]  # E_h(p) in the real layout (P, 2H+1)
    # phi(theta_a) of each stuck piece: [1, e^{i m theta_a}] from the row of U where the piece starts
    first = {p[0]: j for j, p in enumerate(pieces) if p[0] >= 0}  # the piece that starts at each reversal
    phi = U[[first[pieces[j][3]] for j in stuck], :H + 1].view(np.float64)
    phi[:, 1] = 1.0
    phi = phi[:, 1:]
    F = (np.array([p[2] for p in pieces]) @ Er + k * (T @ X)) * (1.0 / np.pi)
    J = Er[stuck].T @ phi
    np.subtract(T, J, out=J)
    J *= k / np.pi
    return F, J


def _view(hs: NDArray[np.complex128], start: int, sign: int, rows: int, c: _Constants) -> NDArray[np.complex128]:
    """The (H, 2, H+1) view ``hs[rows j, start + sign (m - 1) + h]`` of ``hs`` (3, 4H+1), m = 1..H, j = 0, 1,
    h = 0..H: Toeplitz (``sign = -1``) or Hankel (``sign = 1``) in (m, h), without a copy.  For the
    starts used the indices stay in ``0..4H`` (``2H - 1``: ``H..3H - 1``; ``2H + 1``: ``2H + 1..4H``)."""
    H, item = c.n_h, hs.itemsize
    return np.ndarray((H, 2, H + 1), hs.dtype, hs, start * item, (sign * item, rows * (4 * H + 1) * item, item))


__all__ = ["jenkins_harmonics", "reversals"]
