"""f_s, f_c and their amplitude derivatives from a loading path: the Stieltjes integrals of the
single-mode microslip elements (``contact_models.microslip``), in closed form on the straight
stretches and by Gauss-Legendre quadrature on the microslip pieces.

With the virgin loading curve F(s), s the tip displacement, the Masing loop of amplitude a gives

    f_s = 8/(pi a) int_0^a sqrt(s (a - s)) dF(s),    f_c = 4/(pi a) int_0^a (a - 2 s) dF(s),

(``docs/theory.md``, "From the loading curve to f_s, f_c").  A path is the tuple
``(a_min, pieces, a_gross, F_gross, K_slip, K_stuck)`` of ``microslip._Path``: stuck (slope K)
up to a_min, the microslip pieces (``_loading_path._Piece``, parametrised by their boundary
parameter t in [0, 1]: ``evaluate``, ``invert``, ``_invert_one``), then the sliding line of slope
K_slip past a_gross.  A piece is integrated in t by Gauss-Legendre rules of doubling size,
refined until two successive rules agree to ``rtol``.  Everything here is arithmetic on a path:
it builds none and knows no element.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

#: Gauss-Legendre nodes of the first rule; doubled until two rules agree to rtol.
GAUSS_START = 12
#: Largest Gauss-Legendre rule tried before giving up refining.
GAUSS_MAX = 384
#: A piece ending this close below a (relative) is integrated on geometrically graded cells.
GRADE_BELOW = 0.05
#: Number of geometric cells (ratio 1/4) used for a near-singular piece.
GRADE_CELLS = 14


_EPS = float(np.finfo(float).eps)
#: Past ``FAR`` times the gross-slip amplitude f_s, f_c and their slopes follow their expansions past gross slip
#: (``_beyond``): there the closed forms still hold to about eps FAR (their differences of terms of order a lose
#: a_gross to rounding: from 1e11 a_gross f_c read the stuck stretch's 70 N for the sliding line's 28.6 N, and K a^2
#: overflowed from about 1e150 m, f_s NaN), and the terms the expansions leave out are (1/FAR)^2 of f_c.
FAR = 1e6
#: The largest K a^2 the closed forms are taken at (a far amplitude's values start from there).
_MAX_SQUARE = 1e300
_TINY = float(np.finfo(float).tiny)


def _far(path) -> float:
    """The amplitude (m) from which ``_fourier_one`` and ``_fourier_one_omega`` answer by the expansions past
    gross slip: ``FAR`` times a_gross, inf where the whole path is not built, there is no friction (a_gross 0: a
    linear bar) or K a^2 would leave double precision before it."""
    a_g, K_slip, K = path[2], path[4], path[5]
    top = FAR * a_g
    if not 0.0 < top < math.inf or not top * top * max(abs(K), abs(K_slip)) < _MAX_SQUARE:
        return math.inf
    return top


def _beyond(path, at_top, top, a):
    """f_s, f_c, df_s/da, df_c/da at amplitudes ``a`` > ``top`` past gross slip from their values ``at_top`` at
    ``top``: on the sliding line F = F_fric + K_slip s, f_s = K_slip a + O(a^-1/2), f_c = 4 F_fric/pi + O(1/a),
    df_s/da = K_slip + O(a^-3/2), df_c/da = O(a^-2), each correction scaled from its value at ``top``."""
    a_g, F_g, K_slip = path[2], path[3], path[4]
    fs, fc, dfs, dfc = at_top
    fc_inf = 4.0 / math.pi * (F_g - K_slip * a_g)
    r = top / a
    return (K_slip * a + (fs - K_slip * top) * r**0.5, fc_inf + (fc - fc_inf) * r, K_slip + (dfs - K_slip) * r**1.5,
            dfc * r * r)


@lru_cache(maxsize=None)
def _gauss(n: int):
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1.0), 0.5 * w


#: (arcsin, sqrt, clip to [-1, 1]) for arrays and for one float amplitude.
_ARRAYS = (np.arcsin, np.sqrt, lambda u: np.minimum(np.maximum(u, -1.0), 1.0))
_FLOATS = (math.asin, math.sqrt, lambda u: min(max(u, -1.0), 1.0))


def _stretch(a, K, s1, s2, fns=_ARRAYS):
    """The integrals (J_s, J_c, J_d) of a straight stretch dF = K ds of the loading curve from
    s1 to s2 <= a, in closed form (s = a (1 + u)/2, u = sin th):

    J_s = K int sqrt(s (a - s)) ds = K a^2/8 [asin u + u sqrt(1 - u^2)],
    J_c = K int (a - 2 s) ds = K (a - s1 - s2)(s2 - s1),
    J_d = K int sqrt(s / (a - s)) / 2 ds = K a/4 [asin u - sqrt(1 - u^2)].

    ``fns``: ``_ARRAYS`` for arrays a, ``_FLOATS`` for one float a.
    """
    asin, sqrt, clip = fns
    u1 = clip(2.0 * s1 / a - 1.0)
    u2 = clip(2.0 * s2 / a - 1.0)
    as1, as2 = asin(u1), asin(u2)
    r1, r2 = sqrt(1.0 - u1 * u1), sqrt(1.0 - u2 * u2)
    Js = K * a * a / 8.0 * ((as2 - as1) + (u2 * r2 - u1 * r1))
    Jc = K * (a - s1 - s2) * (s2 - s1)
    Jd = K * a / 4.0 * ((as2 - as1) - (r2 - r1))
    return Js, Jc, Jd


def _fourier_one_omega(path, a, rtol):
    """f_s, f_c, df_s/da, df_c/da for amplitudes ``a`` at one frequency (see module docstring)."""
    a_min, pieces, a_g, F_g, K_slip, K = path
    a = np.asarray(a, dtype=float)
    top = _far(path)
    if top < math.inf and np.any(a > top):  # (rare: an amplitude 1e6 times the gross-slip one)
        out = [np.empty_like(a) for _ in range(4)]
        far = a > top
        near = _fourier_one_omega(path, a[~far], rtol)
        there = _beyond(path, _fourier_one(path, top, rtol), top, a[far])
        for o, v, w in zip(out, near, there):
            o[~far], o[far] = v, w
        return tuple(out)
    slip = a > a_min
    if not np.any(slip):
        return K * a, np.zeros_like(a), np.full_like(a, K), np.zeros_like(a)
    every = bool(np.all(slip))
    A = a if every else a[slip]
    # Stieltjes integrals J_s = int sqrt(s(a-s)) dF, J_c = int (a - 2s) dF, Jd = int sqrt(s/(a-s))/2 dF;
    # first the stuck stretch [0, a_min] (A > a_min here)
    Js, Jc, Jd = _stretch(A, K, 0.0, a_min)
    gross = A > a_g
    any_gross = bool(np.any(gross))
    Fa = np.where(gross, F_g + K_slip * (A - a_g), 0.0) if any_gross else np.zeros_like(A)
    dFa = np.where(gross, K_slip, 0.0) if any_gross else np.zeros_like(A)
    # A skipped onset fold leaves F(s0) - K s0 as a jump of the loading curve: a point mass of dF.
    if pieces:
        s0, jump = pieces[0].s0, pieces[0].F0 - K * pieces[0].s0
        Js += jump * np.sqrt(s0 * np.maximum(A - s0, 0.0))
        Jc += jump * (A - 2.0 * s0)
        Jd += jump * 0.5 * np.sqrt(s0 / np.maximum(A - s0, _TINY))
    # Likewise a gross-slip fold: the curve snaps from the piece's end onto the sliding line at a_g.
    if any_gross and pieces:
        jump = F_g - pieces[-1].F1
        G = A[gross]
        Js[gross] += jump * np.sqrt(a_g * (G - a_g))
        Jc[gross] += jump * (G - 2.0 * a_g)
        Jd[gross] += jump * 0.5 * np.sqrt(a_g / (G - a_g))
    for p in pieces:
        act = A > p.s0
        if not np.any(act):
            continue
        all_act = bool(np.all(act))
        Aa = A if all_act else A[act]
        inside = Aa < p.s1
        if np.all(inside):
            t_end = p.invert(Aa)
        else:
            t_end = np.ones_like(Aa)
            if np.any(inside):
                t_end[inside] = p.invert(Aa[inside])
        (js, jc, jd), (Fe, dse, dFe) = _piece_integrals(p, Aa, t_end, inside, rtol)
        if all_act:
            Js += js
            Jc += jc
            Jd += jd
        else:
            Js[act] += js
            Jc[act] += jc
            Jd[act] += jd
        if all_act and np.all(inside):
            Fa, dFa = Fe, dFe / dse
        else:
            idx = np.flatnonzero(act)[inside]
            Fa[idx] = Fe[inside]
            dFa[idx] = dFe[inside] / dse[inside]
    if any_gross:
        G = A[gross]
        js, jc, jd = _stretch(G, K_slip, a_g, G)
        Js[gross] += js
        Jc[gross] += jc
        Jd[gross] += jd
    fs_s = 8.0 / (np.pi * A) * Js
    fc_s = 4.0 / (np.pi * A) * Jc
    # J_c cancels exactly on linear stretches; clear rounding-level negatives (|.| <= 64 eps K a).
    fc_s = np.where((fc_s < 0.0) & (fc_s > -64 * _EPS * abs(K) * A), 0.0, fc_s)
    dfs_s = -fs_s / A + 8.0 / (np.pi * A) * Jd
    dfc_s = -fc_s / A + 4.0 / (np.pi * A) * (Fa - A * dFa)
    if every:
        return fs_s, fc_s, dfs_s, dfc_s
    fs, fc, dfs, dfc = K * a, np.zeros_like(a), np.full_like(a, K), np.zeros_like(a)
    fs[slip], fc[slip], dfs[slip], dfc[slip] = fs_s, fc_s, dfs_s, dfc_s
    return fs, fc, dfs, dfc


def _fourier_one(path, a: float, rtol):
    """``_fourier_one_omega`` for one float amplitude, term by term the same (numpy's cost per
    call on 1-element arrays would be most of the time): f_s, f_c, df_s/da, df_c/da."""
    a_min, pieces, a_g, F_g, K_slip, K = path
    if not a > a_min:
        return K * a, 0.0, K, 0.0
    if a > a_g * FAR:  # (one comparison on the common path: a_g is inf where the path is not built that far)
        top = _far(path)
        if a > top:
            return tuple(float(v) for v in _beyond(path, _fourier_one(path, top, rtol), top, a))
    Js, Jc, Jd = _stretch(a, K, 0.0, a_min, _FLOATS)
    Fa = dFa = 0.0
    if pieces:  # the onset fold's point mass (see _fourier_one_omega)
        s0, jump = pieces[0].s0, pieces[0].F0 - K * pieces[0].s0
        Js += jump * math.sqrt(s0 * max(a - s0, 0.0))
        Jc += jump * (a - 2.0 * s0)
        Jd += jump * 0.5 * math.sqrt(s0 / max(a - s0, _TINY))
    gross = a > a_g
    if gross and pieces:  # the gross-slip fold's
        jump = F_g - pieces[-1].F1
        Js += jump * math.sqrt(a_g * (a - a_g))
        Jc += jump * (a - 2.0 * a_g)
        Jd += jump * 0.5 * math.sqrt(a_g / (a - a_g))
    for p in pieces:
        if not a > p.s0:
            continue
        inside = a < p.s1
        t_end = p._invert_one(a) if inside else 1.0
        graded = not inside and (a - p.s1) < GRADE_BELOW * (p.s1 - p.s0)  # as _piece_integrals
        (js, jc, jd), (Fe, dse, dFe) = _converged_rules(p, a, t_end, graded, rtol)
        Js, Jc, Jd = Js + js, Jc + jc, Jd + jd
        if inside:
            Fa, dFa = Fe, dFe / dse
    if gross:
        Fa, dFa = F_g + K_slip * (a - a_g), K_slip
        js, jc, jd = _stretch(a, K_slip, a_g, a, _FLOATS)
        Js, Jc, Jd = Js + js, Jc + jc, Jd + jd
    fs = 8.0 / (math.pi * a) * Js
    fc = 4.0 / (math.pi * a) * Jc
    if -64 * _EPS * abs(K) * a < fc < 0.0:  # rounding-level negatives, as _fourier_one_omega
        fc = 0.0
    return fs, fc, -fs / a + 8.0 / (math.pi * a) * Jd, -fc / a + 4.0 / (math.pi * a) * (Fa - a * dFa)


def _piece_integrals(p, a, t_end, exact_end, rtol):
    """Integrals of one piece from t = 0 to t_end for each amplitude, to relative ``rtol``,
    and ``(F, s', F')`` at t_end (the end node of the first evaluation).

    With t = t_end (1 - tau^2) the square-root end (s = a) becomes smooth in tau.  A piece
    that ends just below a (near-singular) is split into geometrically graded cells in tau.
    The first two rules (``GAUSS_START`` and twice as many nodes) and the end node share one
    evaluation of the loading curve.
    """
    near = ~exact_end & ((a - p.s1) < GRADE_BELOW * (p.s1 - p.s0))
    if not np.any(near):
        return _converged_rules(p, a, t_end, False, rtol)
    out = [np.zeros_like(a) for _ in range(3)]
    end = [np.zeros_like(a) for _ in range(3)]
    for mask, graded in ((~near, False), (near, True)):
        if np.any(mask):
            cur, at_end = _converged_rules(p, a[mask], t_end[mask], graded, rtol)
            for k in range(3):
                out[k][mask] = cur[k]
                end[k][mask] = at_end[k]
    return out, end


def _converged_rules(p, a, t_end, graded, rtol):
    """The piece's integrals by rules of doubling size until two agree to ``rtol / 10``, and the
    curve's ``(F, s', F')`` at t_end.  ``a``, ``t_end``: arrays, or floats for one amplitude (the
    solver's call; everything is then a float)."""
    n = 2 * GAUSS_START
    (prev, cur), at_end = _graded_rules(p, a, t_end, graded, (GAUSS_START, n), with_end=True)
    while True:
        if isinstance(a, float):  # one amplitude: the same test in floats
            agree = (max(abs(cur[0] - prev[0]), abs(cur[1] - prev[1])) / max(abs(cur[0]) + abs(cur[1]), 1e-300)
                     <= 0.1 * rtol)
        else:
            scale = np.maximum(np.abs(cur[0]) + np.abs(cur[1]), 1e-300)
            err = np.maximum(np.abs(cur[0] - prev[0]), np.abs(cur[1] - prev[1])) / scale
            agree = bool(np.all(err <= 0.1 * rtol))
        if agree or n >= GAUSS_MAX:
            return cur, at_end
        n *= 2
        prev, ((cur,), _) = cur, _graded_rules(p, a, t_end, graded, (n,))


@lru_cache(maxsize=64)
def _rule_nodes(graded: bool, ns: tuple, with_end: bool):
    """Nodes tau in [0, 1] of the Gauss-Legendre rules of sizes ``ns`` (one after the other, and
    tau = 0 last when ``with_end``) on one cell or on the graded cells, ``1 - tau^2`` at them, and
    each rule's weights."""
    if graded:
        # cells [r^(j+1), r^j] in tau, the innermost [0, r^GRADE_CELLS]
        edges = np.concatenate(([0.0], 0.25 ** np.arange(GRADE_CELLS, -1, -1)))
    else:
        edges = np.array([0.0, 1.0])
    lo, hi = edges[:-1], edges[1:]
    taus, wts = [], []
    for n in ns:
        x, w = _gauss(n)
        taus.append((lo[:, None] + (hi - lo)[:, None] * x[None, :]).ravel())  # nodes in (0, 1)
        wts.append(((hi - lo)[:, None] * w[None, :]).ravel())
    tau = np.concatenate(taus + ([np.zeros(1)] if with_end else []))
    shrink = 1.0 - tau * tau  # t = t_end (1 - tau^2)
    for v in [tau, shrink] + wts:
        v.flags.writeable = False
    return tau, shrink, tuple(wts)


def _graded_rules(p, a, t_end, graded, ns, *, with_end=False):
    """``([(J_s, J_c, J_d) for each rule of n in ns], (F, s', F') at t_end or None)``: one
    evaluation of the loading curve at the nodes of all the rules (and at tau = 0).

    ``a``, ``t_end``: arrays (one row of nodes per amplitude), or floats for one amplitude (one
    row, 1-D, and float results).
    """
    tau, shrink, wts = _rule_nodes(graded, ns, with_end)
    one = isinstance(a, float)
    te, A = (t_end, a) if one else (t_end[:, None], a[:, None])
    s, F, ds, dF = p.evaluate(te * shrink)
    gap = np.maximum(A - s, 0.0)
    sq = np.sqrt(np.maximum(s, 0.0))
    dFj = dF * ((2.0 * te) * tau)  # dF/dt |dt/dtau|
    rg = np.sqrt(gap)
    g_s = sq * rg * dFj
    g_c = (A - 2.0 * s) * dFj
    g_d = 0.5 * sq / np.where(gap > 0.0, rg, np.inf) * dFj  # 0 at the end s = a (gap = 0)
    rules, i = [], 0
    for wt in wts:
        cols = slice(i, i + wt.size)
        rule = (g_s[..., cols] @ wt, g_c[..., cols] @ wt, g_d[..., cols] @ wt)
        rules.append(tuple(map(float, rule)) if one else rule)
        i += wt.size
    if not with_end:
        return rules, None
    return rules, ((float(F[-1]), float(ds[-1]), float(dF[-1])) if one else (F[:, -1], ds[:, -1], dF[:, -1]))
