"""A point contact that separates: the scene with a normal load
============================================================

The scene ``examples/scenes/contact_normal.toml`` run through the scene API and its FRF drawn with
the separation marked.

Two DOFs of a contact point, tangential (DOF 0) and normal (DOF 1), unit masses, stiffnesses 1 and
1.5 coupled by 0.3 (an inclined support: tangential motion drives normal motion), C = 0.01 K, the
force 0.015 cos(omega t) on the tangential DOF.  The damper is ``contact_models.Contact2D`` to
ground (``damper.model = "contact2d"``): Jenkins friction (kt = 1, mu = 0.3) under the normal load
N = max(0, n0 + kn v) with n0 = 0.1 and kn = 1, attached by ``structure.contact_dofs = [0]`` and
``structure.normal_dofs = [1]``; H = 3 harmonics, 256 samples per period.

The friction peak (first mode, about 1.12 rad/s) is damped by slip.  Near the second (normal) mode,
about 1.6 rad/s, the normal motion opens the contact over part of each cycle: there N = 0 and the
tangential force vanishes.  The share of the period during which the contact is open is computed
from the normal DOF's harmonics, ``N(t)`` sampled by ``Contact2D.normal_force``, and marked
on the FRF.  The same scene runs from the command line as
``python3 -m hbm run examples/scenes/contact_normal.toml``.

Run ``python3 examples/contact_normal_scene.py``; writes ``docs/figures/contact_normal_scene.png``.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from hbm.scenes import load_scene, plan_scene, run_scene  # noqa: E402

from paper_figures import DEFAULT_OUTDIR, ROOT, display_path  # noqa: E402  (no __file__ here: the gallery runs this)

SCENE = ROOT / "examples" / "scenes" / "contact_normal.toml"
#: The frequency window of the small (test) setting: around the separation.
SMALL_OMEGA = [1.5, 1.7]


def open_share(element, frf, dof=1, n_t=256):
    """Share of each period during which the contact is open (N = 0), from the harmonics of the
    normal DOF: ``x = X0 + sum_h Re(c_h e^(i h theta))``, ``N = element.normal_force(x)``."""
    c = frf.coefficients(dof)
    theta = np.linspace(0.0, 2.0 * np.pi, n_t, endpoint=False)
    h = np.arange(1, c.shape[1])
    v = c[:, :1].real + (c[:, 1:, None] * np.exp(1j * h[:, None] * theta)).real.sum(axis=1)
    return np.mean(element.normal_force(v) == 0.0, axis=1)


def main(outdir=DEFAULT_OUTDIR, small=False):
    """Run the scene, draw the FRF with the separation marked; returns ``{"path", "peak",
    "open_max", "open_range"}`` (the largest open share of a period, and the frequencies where
    the contact opens)."""
    scene = load_scene(SCENE, overrides={"sweep.omega": SMALL_OMEGA} if small else None)
    plan = plan_scene(scene)
    with tempfile.TemporaryDirectory() as folder:
        result = run_scene(scene, folder, plan=plan, progress=None)
    if not result.success:
        raise RuntimeError(result.message)
    frf = result.runs[0].frf
    share = open_share(plan.runs[0].element, frf)
    opened = share > 0.0

    fig, (ax, bx) = plt.subplots(2, 1, figsize=(7.0, 5.5), sharex=True, height_ratios=(3, 1.3))
    ax.semilogy(frf.omega, frf.amplitude, color="k", lw=1.2, label="tangential DOF 0, first harmonic")
    ax.semilogy(frf.omega, np.where(opened, frf.amplitude, np.nan), color="tab:red", lw=3.0, alpha=0.6,
                label="contact open over part of the cycle")
    ax.set_ylabel("amplitude (m)")
    ax.set_title("Contact2D damper: friction under a varying normal load (H = 3)")
    ax.legend(fontsize=8)
    bx.plot(frf.omega, share, color="tab:red")
    bx.set_ylabel("open share\nof the period")
    bx.set_xlabel("excitation frequency omega (rad/s)")
    bx.set_ylim(0.0, max(0.5, float(share.max()) * 1.1))
    fig.tight_layout()
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    path = outdir / "contact_normal_scene.png"
    fig.savefig(path, dpi=120)
    plt.close(fig)
    peak = frf.peak()
    print(f"peak: {peak.amplitude:.6g} m at {peak.omega:.6g} rad/s; the contact opens over up to "
          f"{share.max():.0%} of the period"
          + (f" between {frf.omega[opened].min():.4g} and {frf.omega[opened].max():.4g} rad/s" if opened.any() else ""))
    print(f"wrote: {display_path(path)}")
    return {"path": path, "peak": peak, "open_max": float(share.max()),
            "open_range": (float(frf.omega[opened].min()), float(frf.omega[opened].max())) if opened.any() else None}


if __name__ == "__main__":
    main()
