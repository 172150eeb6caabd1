"""Masing's rules with memory for a sampled periodic displacement, and the AFT matrices.

Used by :class:`contact_models.base.ContactElement` (``periodic_force``, ``harmonic_force``);
derivation in ``docs/multiharmonic.md``, "Masing's rules with memory" and "AFT".

Masing with memory (extended Masing rules; Iwan 1966, Jayakumar & Stelson 1988): an element with
the odd virgin loading curve ``F`` follows, after a reversal at ``(x_r, f_r)``, the branch

    f = f_r + 2 F((x - x_r)/2);

when the displacement passes the reversal point that opened the branch it came from, the inner
loop closes and the older branch is followed again (the turning-point stack pops two entries).

Periodic state, reached in one pass (the stated criterion): the march starts at the sample of
the global maximum ``x_M``.  Any history that has reached ``x_M`` since ``x_m`` (the global
minimum) has wiped every inner loop, so the state there is the tip of the outer loop,
``f_M = f_centre + F(a)``, ``a = (x_M - x_m)/2``, with the branch from ``(x_m, f_centre - F(a))``
below it on the stack.  ``f_centre = K_inf x_c`` (``x_c = (x_M + x_m)/2``, ``K_inf`` the slope
of the loading curve past full slip): the state of an element that has slipped fully, which is
exact for every periodic path that gross-slips once per period and, for a path that does not,
the state left by a decaying shake-down about ``x_c`` (a mean displacement carried only by the
element's elastic part).  One pass over the samples then gives the periodic force, with no
iteration over periods.  Between samples the displacement is taken monotone (as in the time
steppers ``Macroslip.step``), so the sampled map is exact for sampled paths.
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import Callable

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


def masing_periodic(x: Array, loading: Callable[[Array], Array], slope: Callable[[Array], Array],
                    k_inf: float, extremes: tuple[float, float, bool, bool] | None = None
                    ) -> tuple[Array, Array, NDArray[np.intp], Array]:
    """Periodic force of a Masing element for the samples ``x`` of one period, with its tangent.

    ``extremes = (x_max, x_min, after_max, after_min)``: the true extreme values of the
    continuous path (between samples) and whether the sample of the largest (smallest) value
    lies after the true maximum (minimum); None takes the sampled extremes.  The outer loop's
    tips are then at the true extremes, which removes the O(dtheta^2) error of sampled tips.

    Returns ``(f, d, idx, C)``: the force samples and the exact Jacobian in the structured form
    ``J = diag(d) + S``, ``S`` zero except in the columns ``idx`` (reversal samples and the tips),
    ``S[:, idx] = C``.  Column ``n`` stands for ``x_min`` and ``n + 1`` for ``x_max`` when
    ``extremes`` is given (their derivatives are the caller's); otherwise the tips are samples.
    """
    n = x.size
    m0 = int(np.argmax(x))
    xr = np.concatenate((x[m0:], x[:m0]))  # sample 0 holds the largest value
    im = int(np.argmin(xr))
    if extremes is None:
        xM, xm, after_max, after_min = float(xr[0]), float(xr[im]), True, False
        colT, colB = 0, im
    else:
        xM, xm, after_max, after_min = extremes
        colT, colB = n + 1, n
    half, xc = 0.5 * (xM - xm), 0.5 * (xM + xm)
    B, T = n, n + 1  # the outer loop's lower and upper tips (virtual reversal points)

    # ---- directions of the steps k -> k+1 (flat steps keep the previous direction), reversals
    d = np.sign(np.diff(xr))
    if d.size and d[0] == 0.0:
        d[0] = -1.0  # leaving the maximum: downwards
    if d.size and not np.all(d):
        nz = np.flatnonzero(d)
        d = d[nz[np.maximum(np.searchsorted(nz, np.arange(d.size), side="right") - 1, 0)]]
    rev = (1 + np.flatnonzero(d[1:] != d[:-1])).tolist()

    # ---- branch origin of every sample: march the monotone segments with the turning-point stack
    xext = np.concatenate((xr, (xm, xM)))
    origin = np.zeros(n, dtype=np.intp)
    stack = [B, T]
    starts, ends = [0] + rev, rev + [n - 1]
    pushed = []
    for s, e in zip(starts, ends):
        if e <= s:
            continue
        sgn = d[s]
        cur = s + 1
        seg = sgn * xr[cur:e + 1]
        while True:
            if len(stack) >= 3:
                p = int(np.searchsorted(seg, sgn * xext[stack[-2]], side="right"))
                if p < seg.size:  # the inner loop closes at sample cur + p
                    origin[cur:cur + p] = stack[-1]
                    del stack[-2:]
                    seg = seg[p:]
                    cur += p
                    continue
            origin[cur:e + 1] = stack[-1]
            break
        if e < n - 1:
            top = B if xr[e] == xr[im] and stack[-1] == T else e  # the global minimum: the lower tip
            stack.append(top)
            if top == e:
                pushed.append(e)
    origin[0] = T if after_max else B
    if after_min and origin[im] == T:
        origin[im] = B

    # ---- branch forces and slopes, vectorised over the samples
    dx = xr - xext[origin]
    u = np.append(0.5 * np.abs(dx), half)
    Fu = np.asarray(loading(u), dtype=float)
    Su = np.asarray(slope(u), dtype=float)
    g = 2.0 * np.sign(dx) * Fu[:n]
    sl = Su[:n].copy()
    Fa, Sa = float(Fu[n]), float(Su[n])

    # ---- reversal forces in order (each depends on its origin only), then every sample
    fext = np.empty(n + 2)
    fext[T] = k_inf * xc + Fa
    fext[B] = k_inf * xc - Fa
    for r in pushed:
        fext[r] = g[r] + fext[origin[r]]
    f = g + fext[origin]

    idx, C = _reversal_columns(origin, pushed, sl, colT, colB, k_inf, Sa)
    # ---- back to the caller's sample order
    back = np.r_[n - m0:n, 0:n - m0]  # undo the rotation: sample i is rotated sample (i - m0) mod n
    idx = np.where(idx < n, (idx + m0) % n, idx)
    return f[back], sl[back], idx, C[back]


def _reversal_columns(origin: NDArray[np.intp], pushed: list[int], sl: Array, colT: int, colB: int,
                      k_inf: float, Sa: float) -> tuple[NDArray[np.intp], Array]:
    """The non-diagonal part of ``masing_periodic``'s Jacobian: ``(idx, C)``, the columns ``idx`` (the
    tips' columns ``colT``, ``colB`` and the pushed reversal samples, in rotated sample order) and
    their entries ``C`` (n, idx.size).

    The tips ``T = n + 1``, ``B = n`` move with both extremes (``f = K_inf x_c +- F(a)``); a pushed
    reversal ``r`` takes the row of its origin plus ``sl[r] (dx_r - dx_origin)``; every sample then
    takes the row of its origin minus ``sl`` in its origin's column (``d`` carries ``+sl``).
    """
    n = origin.size
    B, T = n, n + 1
    idx = np.array(sorted(set([colT, colB] + pushed)), dtype=np.intp)
    col_of = np.full(n + 2, -1, dtype=np.intp)
    col_of[idx[idx < n]] = np.flatnonzero(idx < n)
    col_of[T], col_of[B] = int(np.searchsorted(idx, colT)), int(np.searchsorted(idx, colB))
    rows = np.zeros((n + 2, idx.size))  # only the rows of the tips and the pushed reversals are used
    rows[T, col_of[T]] += 0.5 * (k_inf + Sa)
    rows[T, col_of[B]] += 0.5 * (k_inf - Sa)
    rows[B, col_of[T]] += 0.5 * (k_inf - Sa)
    rows[B, col_of[B]] += 0.5 * (k_inf + Sa)
    for r in pushed:
        o = origin[r]
        rows[r] = rows[o]
        rows[r, col_of[r]] += sl[r]
        rows[r, col_of[o]] -= sl[r]
    C = rows[origin]
    C[np.arange(n), col_of[origin]] -= sl
    return idx, C


#: Newton iterations locating a true extremum between samples (quadratic convergence from
#: within half a sample spacing: 4 reach rounding for any smooth periodic path).
EXTREMUM_ITERATIONS = 4


def true_extremes(X: Array, x: Array) -> tuple[tuple[float, float, bool, bool], Array, Array]:
    """The extremes of the trigonometric polynomial ``X`` near its largest and smallest samples
    ``x``: ``((x_max, x_min, after_max, after_min), basis(theta_max), basis(theta_min))``.

    Newton on ``x'(theta) = 0`` from the sample, kept within one sample spacing;
    ``basis(theta) = [1, cos theta, sin theta, ...]`` is also ``d x_max / dX`` (``x'`` vanishes
    there).  ``after_*``: the sample lies after the extremum.
    """
    n = x.size
    H = (X.size - 1) // 2
    hh = np.arange(1, H + 1)
    dth = 2.0 * np.pi / n
    th0 = dth * np.array([int(np.argmax(x)), int(np.argmin(x))], dtype=float)
    if H <= SCALAR_NEWTON_HARMONICS:  # a few harmonics: the same iteration on floats, no array calls
        th = np.array([_newton_extremum(X[1::2].tolist(), X[2::2].tolist(), float(t), dth) for t in th0])
    else:
        th = _newton_extrema(X, th0, dth, hh)
    ang = np.outer(th, hh)
    basis = np.empty((2, 2 * H + 1))
    basis[:, 0] = 1.0
    basis[:, 1::2], basis[:, 2::2] = np.cos(ang), np.sin(ang)
    xM, xm = basis @ X
    if not (xM >= x.max() and xm <= x.min()):  # Newton went astray (flat top): keep the samples
        return (float(x.max()), float(x.min()), True, False), basis[0] * np.nan, basis[1] * np.nan
    return (float(xM), float(xm), bool(th0[0] > th[0]), bool(th0[1] > th[1])), basis[0], basis[1]


#: Up to this many harmonics :func:`true_extremes` iterates on Python floats (cheaper than the
#: array calls for a few harmonics; the same Newton iteration, equal to rounding).
SCALAR_NEWTON_HARMONICS = 16


def _newton_extremum(Xc: list, Xs: list, th0: float, dth: float) -> float:
    """Newton on ``x'(theta) = 0`` from ``th0``, kept within ``dth`` of it (``EXTREMUM_ITERATIONS``)."""
    th = th0
    for _ in range(EXTREMUM_ITERATIONS):
        d1 = d2 = 0.0
        for h, (xc, xs) in enumerate(zip(Xc, Xs), start=1):
            c, s = math.cos(h * th), math.sin(h * th)
            d1 += h * (xs * c - xc * s)
            d2 -= h * h * (xc * c + xs * s)
        step = d1 / d2 if d2 != 0.0 else 0.0
        th = min(max(th - step, th0 - dth), th0 + dth)
    return th


def _newton_extrema(X: Array, th0: Array, dth: float, hh: Array) -> Array:
    """:func:`_newton_extremum` for both starts at once, on arrays (many harmonics)."""
    Xc, Xs = X[1::2], X[2::2]
    th = th0.copy()
    for _ in range(EXTREMUM_ITERATIONS):  # both extremes at once
        ang = np.outer(th, hh)
        c, s = np.cos(ang), np.sin(ang)
        d1 = (s * -Xc + c * Xs) @ hh
        d2 = -((c * Xc + s * Xs) @ (hh * hh))
        step = np.divide(d1, d2, out=np.zeros(2), where=d2 != 0.0)
        th = np.clip(th - step, th0 - dth, th0 + dth)
    return th


def dense_jacobian(d: Array, idx: NDArray[np.intp], C: Array) -> Array:
    """``diag(d)`` plus the columns ``C`` at ``idx``: the structured tangent as a dense matrix."""
    J = np.diag(d)
    J[:, idx] += C
    return J


@lru_cache(maxsize=64)
def aft_matrices(harmonics: int, n_t: int) -> tuple[Array, Array]:
    """``(E, E_inv)``: harmonic coefficients from samples, and samples from coefficients.

    Layout ``X = [X0, Xc1, Xs1, ..., XcH, XsH]``, samples at ``theta_k = 2 pi k / n_t``:
    ``x = E_inv X`` (n_t, 2H+1) and ``X = E x`` (2H+1, n_t), ``E E_inv = I`` for n_t >= 2H+1.
    The forward map is the real FFT: ``E x`` equals :func:`to_harmonics` of ``x``.
    """
    k = np.arange(n_t)
    h = np.arange(1, harmonics + 1)
    ang = 2.0 * np.pi * np.outer(k, h) / n_t
    Einv = np.empty((n_t, 2 * harmonics + 1))
    Einv[:, 0] = 1.0
    Einv[:, 1::2] = np.cos(ang)
    Einv[:, 2::2] = np.sin(ang)
    E = Einv.T * (2.0 / n_t)
    E[0] *= 0.5
    Einv.setflags(write=False)
    E.setflags(write=False)
    return E, Einv


@lru_cache(maxsize=64)
def _product_index(harmonics: int, n_t: int) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """``((p - h) mod n_t, (p + h) mod n_t)`` for p, h = 1..H (rows p, columns h)."""
    h = np.arange(1, harmonics + 1)
    return (h[:, None] - h[None, :]) % n_t, (h[:, None] + h[None, :]) % n_t


def diagonal_product(d: Array, harmonics: int) -> Array:
    """``E diag(d) E^-1`` (2H+1, 2H+1) without forming it.

    The sampled product ``d x`` is the discrete convolution of the DFT coefficients
    ``D_m = (1/n_t) sum_k d_k exp(-i m theta_k)`` (exact for samples, indices mod n_t).  With
    ``D-`` = ``D_(p-h)``, ``D+`` = ``D_(p+h)``: column X0 is ``(Re D_0; 2 Re D_p; -2 Im D_p)``,
    column Xc_h is ``(Re D_h; Re(D- + D+); -Im(D- + D+))``, column Xs_h is
    ``(-Im D_h; Im D- - Im D+; Re D- - Re D+)`` (rows: F0, Fc_p, Fs_p).  Index arithmetic only
    (no BLAS call: small threaded products are slow on a loaded machine).
    """
    H = harmonics
    D = np.fft.fft(d) / d.size
    im, ip = _product_index(H, d.size)
    Dm, Dp = D[im], D[ip]
    Dh = D[1:H + 1]
    J = np.empty((2 * H + 1, 2 * H + 1))
    J[0, 0] = D[0].real
    J[0, 1::2], J[0, 2::2] = Dh.real, -Dh.imag
    J[1::2, 0], J[2::2, 0] = 2.0 * Dh.real, -2.0 * Dh.imag
    J[1::2, 1::2] = Dm.real + Dp.real
    J[2::2, 1::2] = -(Dm.imag + Dp.imag)
    J[1::2, 2::2] = Dm.imag - Dp.imag
    J[2::2, 2::2] = Dm.real - Dp.real
    return J


def aft_vector(law: Callable[[Array, float], tuple[Array, NDArray[np.intp], NDArray[np.intp], Array]],
               X: Array, omega: float, n_t: int) -> tuple[Array, Array, Array]:
    """AFT of a law of ``c`` displacement components (a point contact's tangential and normal rows).

    ``X`` (c, 2H+1) are the components' coefficients; ``law(x, omega)`` takes the samples ``x``
    (c, n_t) and returns the force samples (c, n_t) and their Jacobian as entries
    ``(rows, cols, vals)`` in the flattened, component-major sample index (``c n_t`` each way;
    repeated entries add up).  Returns ``F`` (c, 2H+1), ``dF/dX`` (c (2H+1), c (2H+1)) and
    ``dF/domega = 0`` (a rate-independent law): ``dF/dX = sum_e E[:, row_e] val_e E^-1[col_e, :]``
    blockwise, O(entries H^2) instead of the dense ``E J E^-1``.
    """
    c, L = X.shape
    H = (L - 1) // 2
    x = np.stack([to_time(row, n_t) for row in X])
    f, rows, cols, vals = law(x, omega)
    E, Einv = aft_matrices(H, n_t)
    left = np.zeros((c * L, rows.size))
    right = np.zeros((cols.size, c * L))
    for a in range(c):
        m = rows // n_t == a
        left[a * L:(a + 1) * L, m] = E[:, rows[m] % n_t] * vals[m]
        m = cols // n_t == a
        right[m, a * L:(a + 1) * L] = Einv[cols[m] % n_t]
    F = to_harmonics(f, H)
    return F, left @ right, np.zeros_like(F)


def to_time(X: Array, n_t: int) -> Array:
    """Samples at ``theta_k = 2 pi k / n_t`` of the coefficients ``X`` (layout above), by the
    inverse real FFT (``E_inv X``)."""
    H = (X.size - 1) // 2
    c = np.zeros(n_t // 2 + 1, dtype=complex)
    c[0] = X[0] * n_t
    c[1:H + 1] = (X[1::2] - 1j * X[2::2]) * (0.5 * n_t)
    return np.fft.irfft(c, n=n_t)


def to_harmonics(f: Array, harmonics: int) -> Array:
    """Harmonic coefficients (layout above) of the samples ``f`` of one period, by the real FFT."""
    n_t = f.shape[-1]
    c = np.fft.rfft(f, axis=-1) / n_t
    out = np.empty(f.shape[:-1] + (2 * harmonics + 1,))
    out[..., 0] = c[..., 0].real
    out[..., 1::2] = 2.0 * c[..., 1:harmonics + 1].real
    out[..., 2::2] = -2.0 * c[..., 1:harmonics + 1].imag
    return out


def masing_loop(loading: Callable[[NDArray], NDArray], a: float, n: int) -> tuple[NDArray, NDArray]:
    """Closed loop from a loading curve by the Masing rule.

    ``loading(x)`` is the virgin loading curve F(x) for x >= 0 (vectorised).  The
    branch from x = -a upwards is ``-F(a) + 2 F((a + x)/2)``, the branch down from
    x = +a is ``F(a) - 2 F((a - x)/2)``.  Returns ``(x, f)`` for theta from -pi/2
    to 3 pi/2 with ``x = a sin(theta)``.
    """
    theta = np.linspace(-0.5 * np.pi, 1.5 * np.pi, n)
    x = a * np.sin(theta)
    fa = float(np.asarray(loading(np.array([a])))[0])
    up = theta <= 0.5 * np.pi
    f = np.empty_like(x)
    f[up] = -fa + 2.0 * loading(0.5 * (a + x[up]))
    f[~up] = fa - 2.0 * loading(0.5 * (a - x[~up]))
    return x, f


#: Default AFT samples per period: at least this many per harmonic, a power of two.
SAMPLES_PER_HARMONIC = 16


def default_samples(harmonics: int) -> int:
    """Default AFT samples per period for ``harmonics`` harmonics: the power of two
    ``>= SAMPLES_PER_HARMONIC * (harmonics + 1)`` (and so >= 2H+2)."""
    return 1 << int(np.ceil(np.log2(SAMPLES_PER_HARMONIC * (harmonics + 1))))


def aft_scalar(tangent: Callable, X: NDArray, omega: float, n_t: int, *,
               masing: bool) -> tuple[NDArray, NDArray, NDArray]:
    """``(F, dF/dX, dF/domega)`` of a one-component time law by alternating frequency-time.

    ``tangent(x, omega, extremes)`` gives the force samples and their tangent ``(f, d, idx, C)``
    (``J_t = diag(d)`` plus the columns ``C`` at ``idx``).  A Masing law (``masing``) puts its outer
    loop's tips at the true extremes of ``x(t)`` (Newton between samples, :func:`true_extremes`)
    instead of the sampled ones; their derivatives are the two extra columns of ``dx/dX``.
    """
    H = (X.size - 1) // 2
    x = to_time(X, n_t)  # to time (inverse real FFT)
    Einv = aft_matrices(H, n_t)[1]
    if masing:  # the force law, with the outer loop's tips at the true extremes
        ext, b_max, b_min = true_extremes(X, x)
        if not np.isfinite(b_max[0]):
            ext = None
        f, d, idx, C = tangent(x, omega, ext)
        dxdX = np.vstack([Einv, b_min, b_max])[idx]  # columns n, n+1: the true extremes
    else:
        f, d, idx, C = tangent(x, omega, None)  # the force law
        dxdX = Einv[idx]
    F = to_harmonics(f, H)  # back, by the real FFT
    # E J_t E^-1 with J_t = diag(d) + the columns C at idx (einsum: no small threaded BLAS call); the
    # product in the cheaper order: few columns to harmonics first, many (a dense law) into dx/dX first
    J = diagonal_product(d, H)
    if 0 < idx.size <= 2 * H + 1:
        J += np.einsum("ir,rj->ij", to_harmonics(C.T, H).T, dxdX)
    elif idx.size:
        J += to_harmonics((C @ dxdX).T, H).T
    return F, J, np.zeros_like(F)

