"""A 3-DOF chain with two friction contacts
========================================

Multi-harmonic balance of a 3-DOF chain with two friction contacts.

Unit masses and springs ground-0-1-2, damping C = 0.004 K, forced at DOF 2 by 0.01 cos(omega t);
a Jenkins element (k = 1, slip force 0.02) ties DOF 0 to ground and another (k = 1, slip force
0.05) acts between DOFs 0 and 1.  ``hbm.frequency_response`` traces the branch with H harmonics,
condensed to the contact DOFs, with the stability of every point (Hill's method).  Figures: the
FRF of every DOF (unstable stretches dashed) and the harmonic content of DOF 2.  Check: in the
stuck range the response is the closed-form linear response of the chain with both contacts as
springs.

Run ``python3 examples/chain_3dof.py``; writes ``docs/figures/chain_3dof_frf.png`` and
``docs/figures/chain_3dof_harmonics.png``.

.. note::
   Not run when the site is built (it takes from several seconds to minutes): the figures are the ones a committed run wrote; running this script regenerates them.

.. image:: /figures/chain_3dof_frf.png
   :alt: A 3-DOF chain with two friction contacts

.. image:: /figures/chain_3dof_harmonics.png
   :alt: A 3-DOF chain with two friction contacts
"""

# sphinx_gallery_thumbnail_path = "figures/chain_3dof_frf.png"

from __future__ import annotations

import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from contact_models import Macroslip  # noqa: E402
from hbm import Contact, Steps, Structure, frequency_response  # noqa: E402

DEFAULT_OUTDIR = Path(__file__).resolve().parent.parent / "docs" / "figures"
K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
FORCE = np.array([0.0, 0.0, 0.01])


def chain() -> tuple[Structure, list[Contact]]:
    """The structure and its two contacts."""
    s = Structure(np.eye(3), 0.004 * K, K, force=FORCE)
    return s, [Contact(Macroslip(stiffness=1.0, slip_force=0.02), dof=0),
               Contact(Macroslip(stiffness=1.0, slip_force=0.05), dofs=(0, 1))]


def save_log_figure(fig, ax, title: str, path: Path) -> Path:
    """Log amplitude axis, title, legend; write ``path`` and close the figure."""
    ax.set_yscale("log")
    ax.set_title(title)
    ax.legend(fontsize=7)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def main(outdir: Path | str = DEFAULT_OUTDIR, small: bool = False, harmonics: int = 7, n_t: int = 512) -> dict:
    """Trace the FRF, draw both figures, return the run's numbers."""
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    s, contacts = chain()
    H = 2 if small else harmonics
    t0 = time.perf_counter()
    frf = frequency_response(s, contacts, omega_range=(0.3, 1.8), harmonics=H, n_t=64 if small else n_t,
                             response_dof=2, steps=Steps(max_step=0.1 if small else 0.03))
    seconds = time.perf_counter() - t0

    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for dof in range(3):
        amp = np.abs(frf.coefficients(dof)[:, 1])
        from hbm.output import plot_branch

        plot_branch(ax, frf.omega, amp, frf.stable, label=f"DOF {dof}")
    path = save_log_figure(fig, ax, f"3-DOF chain, two Jenkins contacts, H = {H} (dashed: unstable)",
                           outdir / "chain_3dof_frf.png")

    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    c = frf.coefficients(2)
    for h in range(1, H + 1, 2 if H > 3 else 1):
        ax.plot(frf.omega, np.abs(c[:, h]), label=f"h = {h}")
    ax.set_yscale("log")
    ax.set_xlabel(r"$\omega$ (rad/s)")
    ax.set_ylabel(r"$|c_h|$ of DOF 2 (m)")
    ax.set_ylim(bottom=1e-10)  # below: rounding
    ax.set_title("harmonic content of the response at DOF 2")
    ax.legend(fontsize=7)
    hpath = outdir / "chain_3dof_harmonics.png"
    fig.savefig(hpath, dpi=120)
    plt.close(fig)

    # closed form in the stuck range: both contacts springs
    Kst = K + np.array([[2.0, -1.0, 0.0], [-1.0, 1.0, 0.0], [0.0, 0.0, 0.0]])
    w0 = float(frf.omega[0])
    stuck = np.linalg.solve(Kst - w0 * w0 * np.eye(3) + 1j * w0 * 0.004 * K, FORCE)
    return {"path": str(path), "harmonics_path": str(hpath), "frf": frf, "seconds": seconds,
            "peak": frf.peak(), "first_point": frf.coefficients(2)[0, 1], "stuck_closed_form": stuck[2],
            "all_stable": bool(np.all(frf.stable))}


if __name__ == "__main__":
    out = main()
    pk = out["peak"]
    print(f"peak at DOF 2: omega = {pk.omega:.6f} rad/s, amplitude = {pk.amplitude:.6e} m; "
          f"{len(out['frf'])} points in {out['seconds']:.2f} s; all stable: {out['all_stable']}")
