"""Readings of the sampling source near the gap's fold, against the shooting reference.

The gap of ``estimate_references.py`` (m = k = 1, c = 0.01, F = 0.01, ``Gap(1, 0.2)``) traced at H = 31,
n_t = 512 (``--tol``: as ``tests/test_estimate_honest.py`` traces it, ``tol = 1e-5``).  At every point of
1.12 to 1.13 rad/s on the gap-closing branch, and at five points away from the fold, the true error (the
point's amplitude against ``gap_reference`` shot from the point's state at its frequency) and, as
``max over the shifted grids k`` of the relative amplitude change:

- ``own``: one Newton step through the point's own grid's Jacobian, ``J_0 dX = -(R_u - R_k)``;
- ``union``: the same step through the union grid's Jacobian ``J_u`` (the sampling source);
- ``newton``: Newton iterated to convergence on the union and on each shifted grid at the point's
  frequency, the converged amplitudes' difference (inf where one finds no solution);
- ``bordered``: the step through ``[J_x J_w; t^T]`` with the branch tangent ``t``;
- ``quadratic``: the step with the second-order term along the null direction of ``J_0`` (its
  curvature by central differences of ``J_0`` over the step's size; inf where the quadratic has no
  real root).

Run: ``PYTHONPATH=. python3 benchmarks/fold_estimates.py [--tol]`` (about two minutes).  A point
whose shooting does not converge (``period residual`` above 1e-10: past the true fold) is marked.
"""

from __future__ import annotations

import argparse
import math
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from estimate_references import GAP, gap_reference  # noqa: E402
from contact_models import Gap  # noqa: E402
from hbm import Contact, Structure, frequency_response  # noqa: E402
from hbm.balance.errors import SAMPLING_SHIFTS, _turned  # noqa: E402
from hbm.balance.residual import HarmonicBalance  # noqa: E402

CONTROLS = (1.0, 1.05, 1.08, 1.1, 1.115)


def amplitude(x):
    return math.hypot(x[0, 1], x[0, 2])


def grids(s, cs, H, n_t, rtol, w):
    """``[f_k]`` for k = 0 .. SAMPLING_SHIFTS - 1 and the union's ``f_u``: ``f(x) -> (R, J_x, J_w)``."""
    same = HarmonicBalance(s, cs, harmonics=H, n_t=n_t, rtol=rtol)
    union = HarmonicBalance(s, cs, harmonics=H, n_t=SAMPLING_SHIFTS * n_t, rtol=rtol)
    L, h = 2 * H + 1, np.arange(1, H + 1)
    xl = same.cond.at(w)[2]
    lin = np.zeros((1, L))
    lin[:, 1], lin[:, 2] = xl.real, -xl.imag
    E = np.eye(L)

    def shifted(k):
        phi = 2.0 * math.pi * k / (SAMPLING_SHIFTS * n_t)
        S = np.column_stack([_turned(E[:, i][None], h * phi)[0] for i in range(L)])
        Sm = np.column_stack([_turned(E[:, i][None], -h * phi)[0] for i in range(L)])

        def f(x):
            R, J = same._condensed(_turned(x, h * phi), w)
            return (_turned(R.reshape(1, L) + lin, -h * phi) - lin).ravel(), Sm @ J[:, :-1] @ S, Sm @ J[:, -1]
        return f

    def plain(b):
        def f(x):
            R, J = b._condensed(x, w)
            return R, J[:, :-1], J[:, -1]
        return f
    return [plain(same)] + [shifted(k) for k in range(1, SAMPLING_SHIFTS)], plain(union)


def newton(f, x, maxit=40):
    """Newton at fixed frequency from ``x``: the solution, or None."""
    x = x.copy()
    for _ in range(maxit):
        R, Jx, _ = f(x)
        if np.linalg.norm(R) < 1e-15:
            return x
        d = np.linalg.solve(Jx, -R).reshape(x.shape)
        x = x + d
        if not np.all(np.isfinite(x)) or np.max(np.abs(x)) > 1e3:
            return None
        if np.max(np.abs(d)) < 1e-12 * max(1e-3, float(np.max(np.abs(x)))):
            return x
    return None


def readings(s, cs, H, n_t, rtol, x, w):
    a = amplitude(x)
    L = x.shape[1]
    g = np.zeros(L)
    g[1], g[2] = x[0, 1] / a, x[0, 2] / a
    fs, fu = grids(s, cs, H, n_t, rtol, w)
    _, J0, Jw = fs[0](x)
    Ru, Ju, _ = fu(x)
    dR = [Ru - f(x)[0] for f in fs]
    own = max(abs(g @ np.linalg.solve(J0, -d)) for d in dR) / a
    union = max(abs(g @ np.linalg.solve(Ju, -d)) for d in dR) / a
    xu = newton(fu, x)
    xk = [x] + [newton(f, x) for f in fs[1:]]
    conv = math.inf if xu is None or any(v is None for v in xk) else \
        max(abs(amplitude(xu) - amplitude(v)) for v in xk) / a
    t = np.linalg.svd(np.column_stack([J0, Jw]))[2][-1]
    B = np.block([[J0, Jw[:, None]], [t[None]]])
    bordered = max(abs(g @ np.linalg.solve(B, np.concatenate([-d, [0.0]]))[:L]) for d in dR) / a
    U, sv, Vt = np.linalg.svd(J0)
    phi, psi, sigma = Vt[-1], U[:, -1], sv[-1]
    quad = []
    for d in dR:
        step = max(abs(psi @ d) / sigma, 1e-6 * a)
        Jp = fs[0](x + step * phi.reshape(1, L))[1]
        Jm = fs[0](x - step * phi.reshape(1, L))[1]
        kappa = psi @ ((Jp - Jm) @ phi) / (2.0 * step)
        qa, qb, qc = 0.5 * kappa, sigma, psi @ d
        disc = qb * qb - 4.0 * qa * qc
        if disc < 0.0:
            quad.append(math.inf)
            continue
        roots = [-qc / qb] if qa == 0.0 else [(-qb + sg * math.sqrt(disc)) / (2.0 * qa) for sg in (1.0, -1.0)]
        sq = min(roots, key=abs)
        rest = -np.linalg.lstsq(J0, d - psi * (psi @ d), rcond=None)[0]
        rest -= phi * (phi @ rest)
        quad.append(abs(g @ (sq * phi + rest)) / a)
    return dict(own=own, union=union, newton=conv, bordered=bordered, quadratic=max(quad))


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tol", action="store_true", help="trace as the test does (tol = 1e-5)")
    args = ap.parse_args(argv)
    p = GAP
    s = Structure([[p["mass"]]], [[p["damping"]]], [[p["stiffness"]]], force=[p["force"]])
    cs = [Contact(Gap(p["k_gap"], p["gap"]), dof=0)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        frf = frequency_response(s, cs, omega_range=(0.9, 1.2), **(dict(tol=1e-5) if args.tol else
                                                                  dict(harmonics=31, n_t=512)))
    top = [j for j in range(len(frf.omega)) if frf.point_harmonics[j] == 31 and frf.amplitude[j] > 0.3]
    pr = frf._site(top[0])[0]._problem
    idx = {j for j in top if 1.12 <= frf.omega[j] <= 1.13}
    idx |= {min(top, key=lambda j: abs(frf.omega[j] - w)) for w in CONTROLS}
    names = ("own", "union", "newton", "bordered", "quadratic")
    print(f"{'omega':>10} {'true':>8} " + " ".join(f"{n:>16}" for n in names))
    for j in sorted(idx):
        x, w = frf._X[j], float(frf.omega[j])
        h = np.arange(1, pr.H + 1)
        y0 = np.array([x[0, 0] + np.sum(x[0, 1::2]), np.sum(h * w * x[0, 2::2])])
        _, a_ref, res = gap_reference(p, w, y0)
        true = abs(amplitude(x) / a_ref - 1.0)
        r = readings(s, cs, pr.H, pr.n_t, frf.rtol, x, w)
        mark = "" if res < 1e-10 else f"  (no reference: period residual {res:.0e})"
        print(f"{w:10.7f} {true:8.2e} " + " ".join(f"{r[n]:8.2e} ({r[n] / true:5.2f})" for n in names) + mark,
              flush=True)


if __name__ == "__main__":
    main()
