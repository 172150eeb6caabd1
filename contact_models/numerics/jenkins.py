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
    H = (X.size - 1) // 2
    C = X[1::2] - 1j * X[2::2]  # x = X0 + Re sum_m C_m e^{i m theta}
    if not C.any():
        return _stuck(X, k, 0.0, 0.0, np.pi, H)
    th, grid = _reversals(C)
    xr = (X[0] + (np.exp(1j * np.outer(th, _grid(H)[3])) @ C).real).tolist()
    th = th.tolist()
    iM = max(range(len(xr)), key=xr.__getitem__)
    im = min(range(len(xr)), key=xr.__getitem__)
    a = 0.5 * (xr[iM] - xr[im])
    if k * a <= fs:
        return _stuck(X, k, 0.5 * (xr[iM] + xr[im]), th[iM], th[im], H)
    two_pi = 2.0 * math.pi  # from the global maximum round to it again
    th = th[iM:] + [t + two_pi for t in th[:iM + 1]]
    xr = xr[iM:] + xr[:iM + 1]
    pieces, levels = _march(xr, k, fs)
    return _integrals(X, k, th, _crossings(float(X[0]), C, th, xr, levels, grid), pieces, H)


def _stuck(X: Array, k: float, xc: float, th_max: float, th_min: float, H: int) -> tuple[Array, Array]:
    """Stuck all period: ``f = k (x - x_c)``, ``F = k X`` less ``k x_c`` in ``F0``;
    ``dx_c/dX = (phi(theta_max) + phi(theta_min))/2`` (``x' = 0`` at both)."""
    F = k * X.astype(float)
    F[0] -= k * xc
    J = k * np.eye(2 * H + 1)
    J[0] -= 0.5 * k * _basis(np.array([th_max, th_min]), H).sum(axis=0)
    return F, J


def _basis(theta: Array, H: int) -> Array:
    """Rows ``[1, cos theta, sin theta, ..., cos H theta, sin H theta]`` at the instants ``theta``."""
    ang = np.outer(theta, np.arange(1, H + 1))
    out = np.empty((theta.size, 2 * H + 1))
    out[:, 0] = 1.0
    out[:, 1::2], out[:, 2::2] = np.cos(ang), np.sin(ang)
    return out


# ------------------------------------------------------------------ reversals
def _derivatives(C: NDArray[np.complex128], theta: Array) -> Array:
    """``x'`` and ``x''`` at the instants ``theta`` (rows 0 and 1)."""
    m = np.arange(1, C.size + 1)
    return (np.exp(1j * theta[:, None] * m) @ np.stack((1j * m * C, -(m * m) * C), axis=1)).real.T


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
    return _reversals(C)[0]


def _reversals(C: NDArray[np.complex128]) -> tuple[Array, tuple]:
    """The instants in [0, 2 pi) where ``x'`` changes sign, for ``x = Re sum_m C_m e^{i m theta}``
    (m = 1..H), sorted.

    ``x'`` and ``x''`` on a grid (inverse real FFT); with ``M3 = sum m^3 |C_m|`` and
    ``M4 = sum m^4 |C_m|`` bounding ``|x'''|`` and ``|x''''|``, a cell of width ``w`` is certified
    free of roots where ``x'`` keeps its sign and ``min |x'| > M3 w^2/8`` at its ends (the linear
    interpolant's error bound), and to hold one root where ``x'`` changes sign and ``x''`` keeps
    its sign with ``min |x''| > M4 w^2/8``.  Other cells are split (:data:`SPLIT`) until certified or
    until a pair of roots they might hide would open an inner loop below ``M3 w^3/8 <=
    WIGGLE_RTOL sum |C_m|``.  Each root is then found by bracketed Newton from the cubic through
    the cell's ends.  Also returns the grid ``(x - X0, x', w, n)`` (the starts of the stick -> slip
    instants).
    """
    H = C.size
    n, fac, m34, _, im, mm = _grid(H)
    absC = np.abs(C)
    M3, M4 = (absC @ m34).tolist()
    bounds = (M3, M4, WIGGLE_RTOL * float(absC.sum()))
    spec = np.zeros((3, n // 2 + 1), dtype=complex)
    spec[:, 1:H + 1] = fac * C
    xg, g, gp = np.fft.irfft(spec, n=n)
    g1 = np.concatenate((g[1:], g[:1]))
    w = 2.0 * np.pi / n
    # the cells [i w, (i + 1) w] that the grid alone does not certify free of roots: next to the roots
    cells = np.flatnonzero(((g >= 0.0) != (g1 >= 0.0))
                           | (np.minimum(np.abs(g), np.abs(g1)) <= M3 * w * w / 8.0)).tolist()
    found: list = []
    for i in cells:
        _cell(C, bounds, i * w, w, float(g[i]), float(g1[i]), float(gp[i]), float(gp[(i + 1) % n]), found)
    A, B = (im * C).tolist(), (mm * C).tolist()
    roots = [_newton(A, B, 0.0, _hermite_root(t, cw, p, q, dp, dq), t, t + cw, q > p) for t, cw, p, q, dp, dq in found]
    two_pi = 2.0 * math.pi
    th = sorted(r % two_pi for r in roots)  # Python floats: a few roots, cheaper than arrays
    if len(th) > 1:  # one reversal found from two cells (the grid's and the direct sums' rounding differ)
        nxt = th[1:] + [th[0] + two_pi]
        th = [t for t, u in zip(th, nxt) if u - t > SAME_REVERSAL] or th[:1]
    return np.array(th), (xg, g, w, n)


def _hermite_root(lo: float, w: float, g0: float, g1: float, p0: float, p1: float) -> float:
    """The root in ``[lo, lo + w]`` of the cubic through the values g0, g1 (of opposite signs) with
    the slopes p0, p1 at the ends (Newton on it from the secant, kept in the cell): a start within
    O(w^4) of the root of a smooth function."""
    t = -g0 / (g1 - g0) if g1 != g0 else 0.5  # in units of w
    d0, d1 = p0 * w, p1 * w
    for _ in range(3):  # Hermite basis on t in [0, 1]
        t2, t3 = t * t, t * t * t
        v = (2 * t3 - 3 * t2 + 1) * g0 + (t3 - 2 * t2 + t) * d0 + (-2 * t3 + 3 * t2) * g1 + (t3 - t2) * d1
        dv = (6 * t2 - 6 * t) * g0 + (3 * t2 - 4 * t + 1) * d0 + (-6 * t2 + 6 * t) * g1 + (3 * t2 - 2 * t) * d1
        if dv == 0.0:
            break
        t = min(max(t - v / dv, 0.0), 1.0)
    return lo + t * w


def _cell(C: NDArray[np.complex128], bounds: tuple, lo: float, w: float, g0: float, g1: float, p0: float,
          p1: float, found: list) -> None:
    """Certify the cell ``[lo, lo + w]`` (``x'`` = g0, g1 and ``x''`` = p0, p1 at its ends): append
    ``(lo, w, g0, g1, p0, p1)`` to ``found`` if it holds one root (or is finest and ``x'`` changes sign),
    nothing if it holds none, else split it (:func:`reversals`)."""
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
    gg, pp = (v.tolist() for v in _derivatives(C, pts))
    for j in range(SPLIT):
        _cell(C, bounds, float(pts[j]), w, gg[j], gg[j + 1], pp[j], pp[j + 1], found)


@lru_cache(maxsize=32)
def _grid(H: int) -> tuple[int, NDArray[np.complex128], Array, NDArray[np.intp], NDArray[np.complex128],
                           NDArray[np.intp]]:
    """For :func:`reversals`: the grid's size ``n`` (a power of two >= GRID_PER_HARMONIC H and
    >= GRID_MIN), the factors taking ``C_m`` to the inverse real FFT's input of ``x - X0``, ``x'``
    and ``x''`` (3, H), ``[m^3, m^4]`` (H, 2), and ``m``, ``i m``, ``-m^2`` (the factors of ``x'``
    and ``x''``), m = 1..H."""
    n = max(GRID_MIN, 1 << int(math.ceil(math.log2(GRID_PER_HARMONIC * H))))
    m = np.arange(1, H + 1, dtype=float)
    mi = np.arange(1, H + 1)
    return (n, (0.5 * n) * np.stack((np.ones(H) + 0j, 1j * m, -m * m + 0j)), np.stack((m**3, m**4), axis=1),
            mi, 1j * mi, -(mi * mi))


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


def _newton(A: list, B: list, offset: float, th: float, a: float, b: float, up: bool) -> float:
    """The root in ``[a, b]`` of ``r = offset + Re sum A_m e^{i m theta}`` (derivative
    ``Re sum B_m e^{i m theta}``), which increases through it if ``up``: Newton from ``th``, the
    bracket's middle where a step leaves the bracket, until a step is below :data:`STEP_DONE`."""
    for _ in range(NEWTON_ITERATIONS):
        r, d = _pair(A, B, th)
        r += offset
        if (r < 0.0) == up:
            a = th
        else:
            b = th
        new = th - r / d if d != 0.0 else math.nan
        if not a <= new <= b:  # also nan
            th = 0.5 * (a + b)
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


def _crossings(X0: float, C: NDArray[np.complex128], th: list, xr: list, levels: list, grid: tuple) -> list:
    """The instants where ``x`` crosses ``levels[j][1]`` in the monotone stretch after reversal
    ``levels[j][0]``: the grid cell that holds it (bisection on the grid's ``x`` in the stretch),
    the cubic through its ends (``x``, ``x'``; a reversal's ``x' = 0`` where the stretch ends in
    the cell), then Newton, kept in the stretch."""
    xg, dg, w, n = grid
    xg, dg = xg.tolist(), dg.tolist()
    A, B = C.tolist(), (_grid(C.size)[4] * C).tolist()
    out = []
    for i, level in levels:
        a, b, xa, xb = th[i], th[i + 1], xr[i] - X0, xr[i + 1] - X0
        L = level - X0
        s = 1.0 if xb > xa else -1.0
        j0, j1 = math.floor(a / w) + 1, math.ceil(b / w)  # the grid points in (a, b): j0 .. j1 - 1
        lo, hi = j0, j1
        while lo < hi:  # the first grid point at or past the level
            mid = (lo + hi) // 2
            if s * (xg[mid % n] - L) >= 0.0:
                hi = mid
            else:
                lo = mid + 1
        tl, vl, dl = (a, xa, 0.0) if lo == j0 else ((lo - 1) * w, xg[(lo - 1) % n], dg[(lo - 1) % n])
        tr, vr, dr = (b, xb, 0.0) if lo == j1 else (lo * w, xg[lo % n], dg[lo % n])
        t = _hermite_root(tl, tr - tl, vl - L, vr - L, dl, dr) if tr > tl else tl
        out.append(_newton(A, B, X0 - level, t, a, b, s > 0.0))
    return out


@lru_cache(maxsize=32)
def _toeplitz_index(H: int) -> tuple[NDArray[np.intp], NDArray[np.intp], NDArray[np.intp], NDArray[np.complex128]]:
    """``(h - m + 2H, h + m + 2H)`` for h = 0..H (rows), m = 1..H (columns); ``n`` and ``i/n``, n = 1..2H."""
    h, m = np.arange(H + 1)[:, None], np.arange(1, H + 1)[None, :]
    n = np.arange(1, 2 * H + 1)
    return h - m + 2 * H, h + m + 2 * H, n, 1j / n


def _integrals(X: Array, k: float, th: list, cross: list, pieces: list, H: int) -> tuple[Array, Array]:
    """``(F, dF/dX)`` from the pieces: ``hat F_h = (1/pi) integral f e^{-i h theta}`` =
    ``(1/pi)[sum_p g_p E_h(p) + k (T X)_h]`` with ``E_n(p) = integral_p e^{-i n theta}`` and ``T`` the
    stuck pieces' integrals of the basis times ``e^{-i h theta}``; ``d hat F/dX = (k/pi)[T - sum_stuck
    E(p) phi(theta_a(p))^T]``; ``F0 = Re hat F_0/2``, ``Fc_h = Re hat F_h``, ``Fs_h = -Im hat F_h``."""
    P = len(pieces)
    b = [th[p[0]] if p[0] >= 0 else cross[-p[0] - 1] for p in pieces] + [th[-1]]
    stuck = [j for j, p in enumerate(pieces) if p[3] >= 0]
    anchors = [th[pieces[j][3]] for j in stuck]
    mi, pl, n, i_n = _toeplitz_index(H)
    Z = np.exp(-1j * np.outer(b + anchors, n))  # e^{-i n theta} at the breakpoints, then the anchors
    E = np.empty((P, 2 * H + 1), dtype=complex)
    E[:, 0] = [v - u for u, v in zip(b, b[1:])]
    E[:, 1:] = (Z[1:P + 1] - Z[:P]) * i_n
    Es = E[stuck]
    S = Es.sum(axis=0)
    Sf = np.concatenate((S[:0:-1].conj(), S))  # S_n at n + 2H, n = -2H..2H
    T = np.empty((H + 1, 2 * H + 1), dtype=complex)
    T[:, 0] = S[:H + 1]
    T[:, 1::2] = 0.5 * (Sf[mi] + Sf[pl])
    T[:, 2::2] = -0.5j * (Sf[mi] - Sf[pl])
    phi = np.ones((len(stuck), 2 * H + 1))
    Za = Z[P + 1:, :H]
    phi[:, 1::2], phi[:, 2::2] = Za.real, -Za.imag
    g = np.array([p[2] for p in pieces])
    Fhat = (g @ E[:, :H + 1] + k * (T @ X)) * (1.0 / np.pi)
    Jhat = (k / np.pi) * (T - Es[:, :H + 1].T @ phi)
    F = np.empty(2 * H + 1)
    J = np.empty((2 * H + 1, 2 * H + 1))
    F[0], J[0] = 0.5 * Fhat[0].real, 0.5 * Jhat[0].real
    F[1::2], F[2::2] = Fhat[1:].real, -Fhat[1:].imag
    J[1::2], J[2::2] = Jhat[1:].real, -Jhat[1:].imag
    return F, J


__all__ = ["jenkins_harmonics", "reversals"]
