"""Nonlinear modes of the 3-DOF chain
===================================

The first nonlinear mode of the 3-DOF chain of the multi-harmonic guide (unit masses and springs
ground-0-1-2, C = 0.004 K, a Jenkins element k = 1, slip force 0.02 from DOF 0 to the ground and
one k = 1, slip force 0.05 between DOFs 0 and 1), by the extended periodic motion concept
(``hbm.nonlinear_modes``, H = 7, n_t = 512): frequency and modal damping ratio against the modal
amplitude a (``a^2 = sum_h Q_h^H M Q_h``).  Stuck at small amplitudes (the linear mode with both
contacts as springs), then the ground contact slips, then both: the frequency falls towards the
mode with both contacts free and the damping ratio rises to a maximum and falls again as the
sliders' dissipation grows more slowly than the mode's energy.  Check: the stuck frequency is
the lowest undamped eigenfrequency of K with both contacts as springs, to 1.5e-7 (C = 0.004 K is
not proportional to the stuck stiffness, which moves the damped mode's frequency a little).

Run ``python3 examples/nonlinear_modes_chain.py``; writes ``docs/figures/nonlinear_modes_chain.png``.
The same kind of mode from a scene file (the chain with its ground contact only, H = 5):
``python3 -m hbm run examples/scenes/nonlinear_modes_chain.toml`` (a ``[modes]`` table, ``docs/scenes.md``).

.. note::
   Not run when the site is built: the figure is the one a committed run wrote; running this
   script regenerates it.

.. image:: /figures/nonlinear_modes_chain.png
   :alt: Frequency and damping ratio of the chain's first nonlinear mode against its amplitude
"""

# sphinx_gallery_thumbnail_path = "figures/nonlinear_modes_chain.png"

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from contact_models import Macroslip  # noqa: E402
from hbm import Contact, Structure, nonlinear_modes  # noqa: E402

DEFAULT_OUTDIR = Path(__file__).resolve().parent.parent / "docs" / "figures"
K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
#: The stiffness the two stuck contacts add (k = 1 to ground at DOF 0, k = 1 between DOFs 0 and 1).
K_CONTACTS = np.array([[2.0, -1.0, 0.0], [-1.0, 1.0, 0.0], [0.0, 0.0, 0.0]])


def chain() -> tuple[Structure, list[Contact]]:
    """The structure and its two contacts."""
    s = Structure(np.eye(3), 0.004 * K, K, force=[0.0, 0.0, 0.01])
    return s, [Contact(Macroslip(stiffness=1.0, slip_force=0.02), dof=0),
               Contact(Macroslip(stiffness=1.0, slip_force=0.05), dofs=(0, 1))]


def main(outdir: Path | str = DEFAULT_OUTDIR, small: bool = False) -> dict:
    """Trace the mode, draw the figure, return ``{"path", "modes", "stuck_omega"}``."""
    s, contacts = chain()
    H, n_t = (3, 128) if small else (7, 512)
    modes = nonlinear_modes(s, contacts, amplitude_range=(1e-3, 10.0), harmonics=H, n_t=n_t)
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(6.4, 5.6), sharex=True)
    ax.semilogx(modes.amplitude, modes.omega, "k-")
    ax.set_ylabel(r"$\omega$ (rad/s)")
    ax.set_title(f"3-DOF chain, first nonlinear mode (EPMC, H = {H})")
    bx.semilogx(modes.amplitude, 100.0 * modes.damping_ratio, "k-")
    bx.set_ylabel("modal damping ratio D (%)")
    bx.set_xlabel("modal amplitude a")
    fig.tight_layout()
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    path = outdir / "nonlinear_modes_chain.png"
    fig.savefig(path, dpi=120)
    plt.close(fig)
    stuck = float(np.sqrt(np.linalg.eigvalsh(K + K_CONTACTS)[0]))
    return {"path": path, "modes": modes, "stuck_omega": stuck}


if __name__ == "__main__":
    out = main()
    m = out["modes"]
    print(f"{len(m)} points; omega {m.omega[0]:.6f} (stuck, closed form {out['stuck_omega']:.6f}) .. "
          f"{m.omega[-1]:.6f} rad/s; largest damping ratio {m.damping_ratio.max():.4f}; wrote {out['path']}")
