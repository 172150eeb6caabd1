"""A bladed disk with under-platform dampers, from one sector
===========================================================

A lumped disk of 24 blades: per sector a disk DOF (to ground, and to the neighbouring disks), a
blade DOF and a platform DOF; an under-platform Jenkins damper between the platforms of every
pair of neighbouring blades (``hbm.Contact(..., dofs=(2, 2), next_sector=True)``).  An engine-order
EO excitation drives the blades as a travelling wave, and ``hbm.CyclicStructure`` solves the whole
tuned disk from one sector (``docs/bladed_disks.md``).  Figures: the blade's FRF at a few engine
orders; the damper's design chart (the resonant peak against the damper's slip force) from one
sector at one EO; and one mistuned disk (blade stiffnesses scattered by 3 %) solved whole from
``disk.full()``, its blades' responses beside the tuned sector's.  Check: the tuned whole disk
(the same ``disk.full()`` unperturbed) has the sector's peak.

Run ``python3 examples/bladed_disk.py``; writes ``docs/figures/bladed_disk_eo.png``,
``docs/figures/bladed_disk_chart.png`` and ``docs/figures/bladed_disk_mistuned.png``.

.. note::
   Not run when the site is built (the whole disks take about a minute): the figures are the ones a committed run wrote; running this script regenerates them.

.. image:: /figures/bladed_disk_eo.png
   :alt: The blade's FRF at several engine orders, from one sector

.. image:: /figures/bladed_disk_chart.png
   :alt: The damper's design chart from one sector

.. image:: /figures/bladed_disk_mistuned.png
   :alt: A mistuned disk solved whole against the tuned sector
"""

# sphinx_gallery_thumbnail_path = "figures/bladed_disk_eo.png"

from __future__ import annotations

import time
import warnings
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import hbm  # noqa: E402
from contact_models import Macroslip  # noqa: E402

DEFAULT_OUTDIR = Path(__file__).resolve().parent.parent / "docs" / "figures"
#: Per sector (kg, N/m): disk to ground, disk to blade, blade to platform, disk to the next disk.
KG, KB, KP, KC = 5e8, 1e8, 2e8, 2e8
MASSES = (0.5, 0.0877, 0.01)
BETA = 2e-7  #: stiffness-proportional damping C = BETA K (s)
FORCE = 8.0  #: on each blade (N)
DAMPER_STIFFNESS = 4e7  #: the damper's contact stiffness (N/m)
SLIP_FORCE = 20.0  #: mu N of the damper (N)


def sector(sectors: int = 24, engine_order: int = 6, kb: float = KB) -> hbm.CyclicStructure:
    """One sector: disk DOF 0, blade DOF 1, platform DOF 2."""
    K = np.array([[KG + kb + 2 * KC, -kb, 0.0], [-kb, kb + KP, -KP], [0.0, -KP, KP]])
    K1 = np.zeros((3, 3))
    K1[0, 0] = -KC
    return hbm.CyclicStructure(np.diag(MASSES), BETA * K, K, sectors=sectors, engine_order=engine_order,
                               force=[0.0, FORCE, 0.0], K_next=K1, C_next=BETA * K1)


def damper(slip_force: float = SLIP_FORCE) -> hbm.Contact:
    """The under-platform damper between this sector's platform and the next one's."""
    return hbm.Contact(Macroslip(stiffness=DAMPER_STIFFNESS, slip_force=slip_force), dofs=(2, 2), next_sector=True)


def around(disk: hbm.CyclicStructure, lo: float = 0.85, hi: float = 1.15) -> tuple[float, float]:
    """From below the first mode of the nodal diameter EO meets, damper slipping freely, to above it with
    the damper stuck (the damper as a spring between the platforms: K_22 + 2 k, K_next,22 = -k)."""
    K, K1 = disk.K.copy(), disk.K_next.copy()
    K[2, 2] += 2 * DAMPER_STIFFNESS
    K1[2, 2] -= DAMPER_STIFFNESS
    stuck = hbm.CyclicStructure(disk.M, disk.C, K, sectors=disk.sectors, engine_order=disk.engine_order,
                                force=disk.force, K_next=K1)
    return lo * float(disk.natural_frequencies()[0]), hi * float(stuck.natural_frequencies()[0])


def mistuned(full: hbm.Structure, sectors: int, scatter: float, seed: int = 3) -> tuple[hbm.Structure, np.ndarray]:
    """The whole disk with blade j's stiffness KB (1 + scatter d_j), d_j uniform in [-1, 1]."""
    d = np.random.default_rng(seed).uniform(-1.0, 1.0, sectors)
    K = full.K.toarray()
    for j, dj in enumerate(d):
        disk_dof, blade = 3 * j, 3 * j + 1
        dk = KB * scatter * dj
        K[disk_dof, disk_dof] += dk
        K[blade, blade] += dk
        K[disk_dof, blade] -= dk
        K[blade, disk_dof] -= dk
    return hbm.Structure(full.M, full.C, K, force=full.force), d


def main(outdir: Path | str = DEFAULT_OUTDIR, small: bool = False) -> dict:
    """Trace the FRFs, draw the three figures, return the run's numbers."""
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    sectors = 6 if small else 24
    orders = (1, 3) if small else (2, 6, 12)
    chart_eo = orders[-1] if small else 6
    loads = np.geomspace(2.0, 200.0, 3 if small else 9)
    kw = dict(harmonics=1, tol=None) if small else dict(tol=1e-3)
    t0 = time.perf_counter()

    # --- FRFs at a few engine orders, each from one sector
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    peaks = {}
    for eo in orders:
        disk = sector(sectors, eo)
        frf = hbm.frequency_response(disk, [damper()], omega_range=around(disk), response_dof=1, **kw)
        peaks[eo] = frf.peak()
        ax.plot(frf.omega, frf.amplitude, label=f"EO {eo} (nodal diameter {disk.nodal_diameter(1)})")
    ax.set_xlabel(r"$\omega$ (rad/s)")
    ax.set_ylabel("blade amplitude, first harmonic (m)")
    ax.set_title(f"{sectors} blades, under-platform Jenkins dampers: one sector per engine order")
    ax.legend(fontsize=7)
    eo_path = outdir / "bladed_disk_eo.png"
    fig.savefig(eo_path, dpi=120)
    plt.close(fig)

    # --- the damper's design chart at one EO: peak against slip force, one sector per point
    disk = sector(sectors, chart_eo)
    chart = []
    for fs in loads:
        frf = hbm.frequency_response(disk, [damper(float(fs))], omega_range=around(disk), response_dof=1,
                                     **kw)
        chart.append(frf.peak().amplitude)
    free = hbm.frequency_response(disk, None, omega_range=around(disk), response_dof=1, harmonics=1,
                                  tol=None).peak().amplitude
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    ax.loglog(loads, chart, "o-", label="with the damper")
    ax.axhline(free, color="k", ls=":", label="no damper")
    ax.set_xlabel("damper slip force $\\mu N$ (N)")
    ax.set_ylabel("resonant blade amplitude (m)")
    ax.set_title(f"design chart at EO {chart_eo}, from one sector")
    ax.legend(fontsize=7)
    chart_path = outdir / "bladed_disk_chart.png"
    fig.savefig(chart_path, dpi=120)
    plt.close(fig)

    # --- one mistuned disk, solved whole (H = 1: the Jenkins describing function is exact there)
    eo = chart_eo
    disk = sector(sectors, eo)
    rng = around(disk)
    tuned = hbm.frequency_response(disk, [damper()], omega_range=rng, response_dof=1, harmonics=1, tol=None)
    full, contacts = disk.full()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # (a whole disk's peak is not the question here)
        whole = hbm.frequency_response(full, contacts, omega_range=rng, response_dof=1, harmonics=1, tol=None,
                                       stability=False)
        mis, scatter = mistuned(full, sectors, 0.03)
        frf_mis = hbm.frequency_response(mis, contacts, omega_range=rng, response_dof=1, harmonics=1, tol=None,
                                         stability=False)
    blades = np.array([np.abs(frf_mis.coefficients(3 * j + 1)[:, 1]) for j in range(sectors)])
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for j in range(sectors):
        ax.plot(frf_mis.omega, blades[j], color="tab:orange", lw=0.6, alpha=0.7,
                label="mistuned disk (3 % scatter), each blade" if j == 0 else None)
    ax.plot(tuned.omega, tuned.amplitude, "k", lw=1.6, label="tuned: one sector")
    ax.set_xlabel(r"$\omega$ (rad/s)")
    ax.set_ylabel("blade amplitude, first harmonic (m)")
    ax.set_title(f"EO {eo}: the mistuned disk needs the whole disk")
    ax.legend(fontsize=7)
    mis_path = outdir / "bladed_disk_mistuned.png"
    fig.savefig(mis_path, dpi=120)
    plt.close(fig)
    return {"paths": [str(eo_path), str(chart_path), str(mis_path)], "peaks": peaks, "chart": (loads, chart),
            "free_peak": free, "tuned_peak": tuned.peak(), "whole_peak": whole.peak(),
            "mistuned_max": float(np.max(blades)), "seconds": time.perf_counter() - t0}


if __name__ == "__main__":
    out = main()
    t, w = out["tuned_peak"], out["whole_peak"]
    print(f"tuned peak from one sector {t.amplitude:.6e} m at {t.omega:.2f} rad/s; the whole tuned disk "
          f"{w.amplitude:.6e} m at {w.omega:.2f} rad/s; the mistuned disk's largest blade {out['mistuned_max']:.4e} m; "
          f"{out['seconds']:.1f} s")
