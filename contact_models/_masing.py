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

from functools import lru_cache
from typing import Callable

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


def masing_periodic(x: Array, loading: Callable[[Array], Array], slope: Callable[[Array], Array],
                    k_inf: float) -> tuple[Array, Array, NDArray[np.intp], Array]:
    """Periodic force of a Masing element for the samples ``x`` of one period, with its tangent.

    Returns ``(f, d, idx, C)``: the force samples and the exact Jacobian of the sampled map in
    the structured form ``J = diag(d) + S``, where ``S`` is zero except in the columns ``idx``
    (the reversal samples and the two extremes), ``S[:, idx] = C``.
    """
    n = x.size
    m0 = int(np.argmax(x))
    xr = np.concatenate((x[m0:], x[:m0]))  # sample 0 is the global maximum
    im = int(np.argmin(xr))
    xM, xm = float(xr[0]), float(xr[im])
    half, xc = 0.5 * (xM - xm), 0.5 * (xM + xm)

    # ---- directions of the steps k -> k+1 (flat steps keep the previous direction), reversals
    d = np.sign(np.diff(xr))
    if d.size and d[0] == 0.0:
        d[0] = -1.0  # leaving the maximum: downwards
    if d.size and not np.all(d):
        nz = np.flatnonzero(d)
        d = d[nz[np.maximum(np.searchsorted(nz, np.arange(d.size), side="right") - 1, 0)]]
    rev = (1 + np.flatnonzero(d[1:] != d[:-1])).tolist()

    # ---- branch origin of every sample: march the monotone segments with the turning-point stack
    xext = np.append(xr, xm)  # index n: the outer loop's lower tip (virtual reversal)
    origin = np.zeros(n, dtype=np.intp)
    stack = [n, 0]
    starts, ends = [0] + rev, rev + [n - 1]
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
            stack.append(e)

    # ---- branch forces and slopes, vectorised over the samples
    dx = xr - xext[origin]
    dx[0] = 0.0
    u = np.append(0.5 * np.abs(dx), half)
    Fu = np.asarray(loading(u), dtype=float)
    Su = np.asarray(slope(u), dtype=float)
    g = 2.0 * np.sign(dx) * Fu[:n]
    sl = Su[:n].copy()
    sl[0] = 0.0
    Fa, Sa = float(Fu[n]), float(Su[n])

    # ---- reversal forces in order (each depends on its origin only), then every sample
    fext = np.empty(n + 1)
    fext[0] = k_inf * xc + Fa
    fext[n] = k_inf * xc - Fa
    for r in rev:
        fext[r] = g[r] + fext[origin[r]]
    f = g + fext[origin]
    f[0] = fext[0]

    # ---- Jacobian rows of the reversal points in the columns idx (tips: through x_M and x_m)
    idx = np.array(sorted(set([0, im] + rev)), dtype=np.intp)
    pos = {int(j): i for i, j in enumerate(idx)}
    rows = np.zeros((n + 1, idx.size))  # only the rows of 0, n and the reversals are used
    rows[0, pos[0]] += 0.5 * (k_inf + Sa)
    rows[0, pos[im]] += 0.5 * (k_inf - Sa)
    rows[n, pos[0]] += 0.5 * (k_inf - Sa)
    rows[n, pos[im]] += 0.5 * (k_inf + Sa)
    col_of = np.full(n + 1, -1, dtype=np.intp)
    col_of[idx] = np.arange(idx.size)
    col_of[n] = pos[im]
    for r in rev:
        o = origin[r]
        rows[r] = rows[o]
        rows[r, pos[r]] += sl[r]
        rows[r, col_of[o]] -= sl[r]
    C = rows[origin]
    C[np.arange(n), col_of[origin]] -= sl
    C[0] = rows[0]
    # ---- back to the caller's sample order
    back = np.r_[n - m0:n, 0:n - m0]  # undo the rotation: sample i is rotated sample (i - m0) mod n
    return f[back], sl[back], (idx + m0) % n, C[back]


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
