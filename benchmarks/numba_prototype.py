"""A numba prototype of the two-region element's scalar call (is a compiled
accelerator worth an optional dependency?).  Not used by the library.

``fused_numba`` is ``bench_speed.fused_two_region`` (the element's formulas at its node counts,
without its checks) compiled by numba, one loop over the nodes in complex scalars.
``python benchmarks/bench_speed.py --numba`` times it against the numpy element and projects
the default FRF with such an element: the FRF with a free element (the harmonic balance and
continuation alone) plus the element's calls at the prototype's cost.
"""

import math

import numba
import numpy as np

@numba.njit(cache=False)
def _curve(t, S, L, lam, mu, k, beta, q, a2, g2, ga, gg, cstep):
    n = t.size
    xs = np.empty(n); Fs = np.empty(n); dxs = np.empty(n); dFs = np.empty(n)
    for i in range(n):
        L1 = L * (1.0 - (t[i] + 1j * cstep))
        ell = L - L1
        sn0 = np.tanh(lam * L1) / lam
        k0 = S * (S * lam * lam * sn0 + beta) / (S + beta * sn0)
        if g2 > 0.0:
            c1 = 1.0 + 0j; sn1 = np.tanh(gg * L1) / gg
        else:
            c1 = np.cos(gg * L1); sn1 = np.sin(gg * L1) / gg
        kap = S * (S * g2 * sn1 + beta * c1) / (S * c1 + beta * sn1)
        c2 = np.cos(ga * ell); sn2 = np.sin(ga * ell) / ga
        den = S * c2 + kap * sn2
        k_mid = S * (-S * a2 * sn2 + kap * c2) / den; t1 = S / den
        D2 = mu / S * q * ell * ell / 2; dQ = mu / S * q * ell
        d0 = -D2 / (1.0 + k0 * ell / S)
        x = (mu * q / k - d0) / t1
        F = S * dQ + k0 * d0 + k_mid * x
        xs[i] = x.real; Fs[i] = F.real; dxs[i] = x.imag / cstep; dFs[i] = F.imag / cstep
    return xs, Fs, dxs, dFs

@numba.njit(cache=False)
def fused_numba(S, L, lam, mu, k, beta, q, rho, E, omega, a, tt, tau, w1, w2, n1):
    cstep = 1e-30
    a2 = rho * omega * omega / E; g2 = k / S - a2
    ga = math.sqrt(a2); gg = math.sqrt(abs(g2))
    s, F, ds, _ = _curve(tt, S, L, lam, mu, k, beta, q, a2, g2, ga, gg, cstep)
    if g2 > 0.0:
        c = 1.0; sn = math.tanh(gg * L) / gg
    else:
        c = math.cos(gg * L); sn = math.sin(gg * L) / gg
    K = S * (S * g2 * sn + beta * c) / (S * c + beta * sn)
    a_min = s[0]
    j = np.searchsorted(s, a)
    u = (a - s[j - 1]) / (s[j] - s[j - 1]); lo = tt[j - 1]; hi = tt[j]
    t = lo + u * u * (3 - 2 * u) * (hi - lo) + (s[j] - s[j - 1]) * u * (1 - u) * ((1 - u) / ds[j - 1] - u / ds[j])
    s1, _, ds1, _ = _curve(np.array([t]), S, L, lam, mu, k, beta, q, a2, g2, ga, gg, cstep)
    t_end = t - (s1[0] - a) / ds1[0]
    sq, _, _, dF = _curve(t_end * (1.0 - tau * tau), S, L, lam, mu, k, beta, q, a2, g2, ga, gg, cstep)
    js1 = jc1 = js = jc = 0.0
    for i in range(tau.size - 1):
        g = dF[i] * 2.0 * t_end * tau[i]
        vs = math.sqrt(max(sq[i], 0.0) * max(a - sq[i], 0.0)) * g
        vc = (a - 2.0 * sq[i]) * g
        if i < n1:
            js1 += vs * w1[i]; jc1 += vc * w1[i]
        else:
            js += vs * w2[i - n1]; jc += vc * w2[i - n1]
    u0 = 2.0 * a_min / a - 1.0
    js += K * a * a / 8.0 * (math.asin(u0) + u0 * math.sqrt(1.0 - u0 * u0) + math.pi / 2)
    jc += K * (a - a_min) * a_min
    return 8.0 / (math.pi * a) * js, 4.0 / (math.pi * a) * jc
