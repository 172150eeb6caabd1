"""A 200-DOF blade with an under-platform damper
=============================================

A 200-DOF Euler-Bernoulli cantilever blade with an under-platform friction damper.

The blade: a steel cantilever (length 0.1 m, section 20 x 4 mm) of 100 Hermite beam elements,
transverse displacement and rotation at each free node (200 DOFs), modal damping 0.5 %.  The
under-platform damper: a Jenkins element (contact stiffness 1e6 N/m, slip force 20 N) from the
transverse DOF of the node at 0.3 L to ground.  The tip is forced by 1 N cos(omega t).  The
multi-harmonic balance (H = 7) is condensed to the contact and tip DOFs, so the Newton system
has 2 x 15 + 1 unknowns; the same run after Craig-Bampton reduction to 20 DOFs (the two kept
DOFs and 18 fixed-interface modes) gives the same curve (compared at the peak and at located
frequencies), and both times are reported side by side.  Check: the first natural frequency of
the FE model against the Euler-Bernoulli value ``1.87510^2 sqrt(EI/(rho A L^4))``.

Run ``python3 examples/blade_200dof.py``; writes ``docs/figures/blade_200dof.png``.

.. note::
   Not run when the site is built (it takes from several seconds to minutes): the figure is the one a committed run wrote; running this script regenerates it.

.. image:: /figures/blade_200dof.png
   :alt: A 200-DOF blade with an under-platform damper
"""

# sphinx_gallery_thumbnail_path = "figures/blade_200dof.png"

from __future__ import annotations

import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from contact_models import Macroslip  # noqa: E402
from hbm import Contact, Steps, Structure, continuation, frequency_response  # noqa: E402

from chain_3dof import save_log_figure  # noqa: E402  (examples/ is on the path when run or imported)

DEFAULT_OUTDIR = Path(__file__).resolve().parent.parent / "docs" / "figures"
E, RHO, LENGTH, WIDTH, HEIGHT = 2.0e11, 7850.0, 0.1, 0.02, 0.004
ZETA = 0.005
CONTACT_AT = 0.3  # fraction of L
KT, SLIP = 1.0e6, 20.0
TIP_FORCE = 1.0


def beam(elements: int) -> tuple[np.ndarray, np.ndarray]:
    """Consistent mass and stiffness of a clamped-free Hermite beam (DOFs w, theta per free node)."""
    A, I = WIDTH * HEIGHT, WIDTH * HEIGHT**3 / 12.0
    h = LENGTH / elements
    k = E * I / h**3 * np.array([[12, 6 * h, -12, 6 * h], [6 * h, 4 * h * h, -6 * h, 2 * h * h],
                                 [-12, -6 * h, 12, -6 * h], [6 * h, 2 * h * h, -6 * h, 4 * h * h]])
    m = RHO * A * h / 420.0 * np.array([[156, 22 * h, 54, -13 * h], [22 * h, 4 * h * h, 13 * h, -3 * h * h],
                                       [54, 13 * h, 156, -22 * h], [-13 * h, -3 * h * h, -22 * h, 4 * h * h]])
    n = 2 * (elements + 1)
    K, M = np.zeros((n, n)), np.zeros((n, n))
    for e in range(elements):
        sl = slice(2 * e, 2 * e + 4)
        K[sl, sl] += k
        M[sl, sl] += m
    return M[2:, 2:], K[2:, 2:]  # clamp node 0


def blade(elements: int = 100) -> tuple[Structure, list[Contact], int]:
    """The blade, its damper contact and the tip DOF."""
    M, K = beam(elements)
    tip = 2 * elements - 2
    force = np.zeros(M.shape[0])
    force[tip] = TIP_FORCE
    s = Structure.with_modal_damping(M, K, ratios=ZETA, force=force)
    node = round(CONTACT_AT * elements)
    return s, [Contact(Macroslip(stiffness=KT, slip_force=SLIP), dof=2 * (node - 1))], tip


def euler_bernoulli_first_frequency() -> float:
    """``1.8751^2 sqrt(EI/(rho A L^4))`` (rad/s)."""
    A, I = WIDTH * HEIGHT, WIDTH * HEIGHT**3 / 12.0
    return 1.875104068711961**2 * np.sqrt(E * I / (RHO * A * LENGTH**4))


def at(frf, w):
    """First-harmonic amplitude of the response DOF at frequency w (every crossing)."""
    pr = frf._problem
    r = frf.dofs.index(frf.response_dof)
    out = []
    for j in np.flatnonzero((frf.omega[:-1] - w) * (frf.omega[1:] - w) <= 0.0):
        loc = continuation.locate(pr, frf._run.y[j], frf._run.y[j + 1], lambda y, t: y[-1] * pr.omega_ref - w,
                                  tol=frf.newton_tol, scale=frf._scale, xtol=1e-13)
        X = pr.to_physical(loc.y)[0]
        out.append(float(np.hypot(X[r, 1], X[r, 2])))
    return out


def main(outdir: Path | str = DEFAULT_OUTDIR, small: bool = False, harmonics: int = 7, n_t: int = 256,
         reduced_dofs: int = 20) -> dict:
    """Full and reduced runs through the first resonance; figure; numbers."""
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    elements = 8 if small else 100
    H = 2 if small else harmonics
    s, contacts, tip = blade(elements)
    w1 = float(s.natural_frequencies()[0])
    keep = [contacts[0].dofs[0], tip]
    red = s.reduce(keep, modes=reduced_dofs - len(keep))
    rcontacts = [Contact(contacts[0].element, dof=red.dof(keep[0]))]
    rng = (0.8 * w1, 2.0 * w1)  # the damper stiffens the blade: the resonance moves up
    runs = {}
    for name, (st, cs, resp) in {"full": (s, contacts, tip), "reduced": (red, rcontacts, red.dof(tip))}.items():
        t0 = time.perf_counter()
        frf = frequency_response(st, cs, omega_range=rng, harmonics=H, n_t=64 if small else n_t, response_dof=resp,
                                 tol=None, steps=Steps(max_step=0.1 if small else 0.03))  # the settings given, no estimate
        pk = frf.peak()
        runs[name] = (frf, pk, time.perf_counter() - t0)
    full, red_run = runs["full"][0], runs["reduced"][0]
    probes = np.linspace(rng[0], rng[1], 5 if small else 9)[1:-1]
    diffs = [abs(a - b) / b for w in probes for a, b in zip(at(red_run, w), at(full, w))]
    peak_diff = abs(runs["reduced"][1].amplitude - runs["full"][1].amplitude) / runs["full"][1].amplitude

    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    full.plot(ax, label=f"full, {s.n} DOFs ({runs['full'][2]:.2f} s)", peak=True)
    red_run.plot(ax, label=f"Craig-Bampton, {red.n} DOFs ({runs['reduced'][2]:.2f} s)", peak=True, ls=":")
    path = save_log_figure(fig, ax, f"cantilever blade with an under-platform damper, H = {H}",
                           outdir / "blade_200dof.png")
    return {"path": str(path), "n": s.n, "reduced_n": red.n, "first_frequency": w1,
            "euler_bernoulli": euler_bernoulli_first_frequency(), "peak_full": runs["full"][1],
            "peak_reduced": runs["reduced"][1], "seconds_full": runs["full"][2], "seconds_reduced": runs["reduced"][2],
            "max_curve_difference": max(diffs), "peak_difference": peak_diff, "stable": bool(np.all(full.stable))}


if __name__ == "__main__":
    out = main()
    print(f"{out['n']} DOFs: first frequency {out['first_frequency']:.3f} rad/s (Euler-Bernoulli "
          f"{out['euler_bernoulli']:.3f}); peak {out['peak_full'].amplitude:.6e} m at {out['peak_full'].omega:.3f} rad/s")
    print(f"full {out['seconds_full']:.2f} s, reduced to {out['reduced_n']} DOFs {out['seconds_reduced']:.2f} s; "
          f"largest relative difference of the curves {out['max_curve_difference']:.2e}, "
          f"of the peaks {out['peak_difference']:.2e}; all stable: {out['stable']}")
