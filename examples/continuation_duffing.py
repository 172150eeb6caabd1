"""Continuation of your own residual: a Duffing oscillator
=======================================================

A continuation script to copy: your own residual through ``hbm.continuation`` (example c).

The Duffing oscillator ``m x'' + c x' + k x + k3 x^3 = F cos(omega t)`` in single-harmonic
balance, ``x = x_c cos(omega t) + x_s sin(omega t)``: the cubic force's first harmonic is
``(3/4) k3 a^2 x`` (a^2 = x_c^2 + x_s^2).  The hardening response bends to the right and
folds twice; the continuation core (which knows nothing of this model) follows it through
both folds and locates them.  Checks: every point satisfies the frequency-amplitude relation
``a^2 [(k - m w^2 + 3/4 k3 a^2)^2 + (c w)^2] = F^2``, and the located folds solve that
relation together with its vertical-tangent condition (scipy's fsolve, independently).

Run ``python3 examples/continuation_duffing.py``; writes ``docs/figures/continuation_duffing.png``.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.optimize import fsolve  # noqa: E402

from hbm.continuation import continuation  # noqa: E402

from paper_figures import DEFAULT_OUTDIR, display_path  # noqa: E402  (docs/figures; no __file__ here: the gallery runs this)
M, C, K, K3, F = 1.0, 0.02, 1.0, 0.5, 0.1  # a lightly damped hardening oscillator


def residual(y):
    """R = (cos balance, sin balance) and dR/d(x_c, x_s, omega): the residual your model gives."""
    xc, xs, w = y
    kr = K - M * w * w + 0.75 * K3 * (xc * xc + xs * xs)  # in-phase stiffness, cubic included
    R = np.array([kr * xc + C * w * xs - F, kr * xs - C * w * xc])
    J = np.array([[kr + 1.5 * K3 * xc * xc, C * w + 1.5 * K3 * xc * xs, -2 * M * w * xc + C * xs],
                  [-C * w + 1.5 * K3 * xs * xc, kr + 1.5 * K3 * xs * xs, -2 * M * w * xs - C * xc]])
    return R, J


def amplitude_relation(a, w):
    """G(a, w) = a^2 [(k - m w^2 + 3/4 k3 a^2)^2 + (c w)^2] - F^2 and dG/da."""
    kr = K - M * w * w + 0.75 * K3 * a * a
    G = a * a * (kr * kr + (C * w) ** 2) - F * F
    dG = 2 * a * (kr * kr + (C * w) ** 2) + a * a * 2 * kr * 1.5 * K3 * a
    return G, dG


def main(outdir=DEFAULT_OUTDIR, small=False):
    """Trace the FRF over 0.5..2.5 rad/s; returns the path, the folds and the largest errors."""
    w0, w1 = 0.5, 2.5
    x0 = F / (K - M * w0 * w0)  # start: the linear response at w0 (continuation corrects it)
    res = continuation(residual, [x0, 0.0, w0], parameter=2, bounds=(w0, w1),
                       max_step=0.1 if small else 0.05, tol=1e-12)
    xc, xs, w = res.y.T
    a = np.hypot(xc, xs)
    G_err = np.max(np.abs(amplitude_relation(a, w)[0])) / F**2
    folds = []
    for fc, fs, fw in res.folds:  # independent check: G = 0 and dG/da = 0 at (a, w)
        ref = fsolve(lambda v: amplitude_relation(*v), [np.hypot(fc, fs), fw], xtol=1e-14)
        folds.append((fw, np.hypot(fc, fs), ref[1], ref[0]))

    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    ax.plot(w, a, ".-", ms=2, lw=1, label=f"continuation ({len(w)} points)")
    for fw, fa, *_ in folds:
        ax.plot(fw, fa, "rx", ms=9)
    ax.plot([], [], "rx", label="located folds")
    ax.set_xlabel(r"$\omega$ (rad/s)")
    ax.set_ylabel("amplitude")
    ax.set_title("Duffing oscillator, single-harmonic balance")
    ax.legend(fontsize=8)
    fig.tight_layout()
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    path = outdir / "continuation_duffing.png"
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return {"path": path, "result": res, "relation_error": G_err, "folds": folds}


if __name__ == "__main__":
    out = main()
    res = out["result"]
    print(f"{res.message}: {len(res.y)} points, {res.nsteps} steps, {res.nit} Newton iterations")
    print(f"largest |G|/F^2 on the branch: {out['relation_error']:.2e}")
    for fw, fa, rw, ra in out["folds"]:
        print(f"fold at omega = {fw:.12f}, a = {fa:.12f} (fsolve: {rw:.12f}, {ra:.12f})")
    print(f"wrote {display_path(out['path'])}")
