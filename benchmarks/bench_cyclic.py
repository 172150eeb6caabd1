"""What one sector of a bladed disk costs: the EO sweep from one sector, one blade, the whole disk.

``python benchmarks/bench_cyclic.py``: a lumped disk of 24 sectors (disk, blade and platform DOF per
sector, the disks coupled to their neighbours) with a Jenkins under-platform damper between the
platforms of neighbouring blades, excited on the blades at engine order EO; the table gives the
wall time of the FRF over the first family's resonance

- from one sector (``hbm.CyclicStructure``, the damper ``next_sector=True``),
- of one blade with the same damper to ground (the same three DOFs as a plain ``Structure``: what a
  blade-alone design study costs),
- of the whole disk (``disk.full()``, 72 DOFs and 24 dampers, through the same front door),

at H = 3 fixed (``tol=None``: the same work per point) and with ``tol=1e-3`` (H chosen along the
curve) for the sector and the blade; the whole disk only at one EO (it takes minutes), and the peak
amplitudes beside the times (the sector's and the disk's agree).  docs/performance.md, "Bladed disks".
"""

from __future__ import annotations

import sys
import time
import warnings

import numpy as np

import hbm
from contact_models import Macroslip

SECTORS = 24
ENGINE_ORDERS = (2, 6, 12)
FULL_EO = 6


def sector(engine_order: int) -> hbm.CyclicStructure:
    """The lumped sector (kg, N/m): disk DOF 0, blade DOF 1, platform DOF 2."""
    kg, kb, kp, kc = 5e8, 1e8, 2e8, 2e8
    K = np.array([[kg + kb + 2 * kc, -kb, 0.0], [-kb, kb + kp, -kp], [0.0, -kp, kp]])
    K1 = np.zeros((3, 3))
    K1[0, 0] = -kc
    M = np.diag([0.5, 0.0877, 0.01])
    return hbm.CyclicStructure(M, 2e-7 * K, K, sectors=SECTORS, engine_order=engine_order, force=[0.0, 8.0, 0.0],
                               K_next=K1, C_next=2e-7 * K1)


DAMPER = Macroslip(stiffness=4e7, slip_force=20.0)


def timed(f):
    t = time.perf_counter()
    out = f()
    return out, time.perf_counter() - t


def main(argv: list[str] | None = None) -> None:
    rows = []
    for eo in ENGINE_ORDERS:
        disk = sector(eo)
        w = float(disk.natural_frequencies()[0])
        rng = (0.85 * w, 1.25 * w)
        # the blade alone: the sector with its disk held by the neighbours as in the wave (K + 2 cos(phi) K_next)
        turn = 2.0 * np.cos(disk.sector_angle)
        blade = hbm.Structure(disk.M, disk.C + turn * disk.C_next, disk.K + turn * disk.K_next, force=disk.force)
        cs = hbm.Contact(DAMPER, dofs=(2, 2), next_sector=True)
        cb = hbm.Contact(DAMPER, dof=2)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            for tol, H in ((None, 3), (1e-3, None)):
                fs, ts = timed(lambda: hbm.frequency_response(disk, [cs], omega_range=rng, tol=tol, harmonics=H,
                                                              stability=False, response_dof=1))
                fb, tb = timed(lambda: hbm.frequency_response(blade, [cb], omega_range=rng, tol=tol, harmonics=H,
                                                              stability=False, response_dof=1))
                rows.append((eo, "H=3" if tol is None else "tol=1e-3", "sector", 3, len(fs), ts, fs.peak().amplitude))
                rows.append((eo, "H=3" if tol is None else "tol=1e-3", "blade", 3, len(fb), tb, fb.peak().amplitude))
                if eo == FULL_EO and tol is None:
                    full, fc = disk.full()
                    ff, tf = timed(lambda: hbm.frequency_response(full, fc, omega_range=rng, tol=tol, harmonics=H,
                                                                  stability=False, response_dof=1))
                    rows.append((eo, "H=3", "full disk", full.n, len(ff), tf, ff.peak().amplitude))
    print(f"{'EO':>3} {'setting':>9} {'model':>10} {'DOFs':>5} {'points':>7} {'time s':>8} {'vs sector':>10} "
          f"{'peak m':>11}")
    base = {}
    for eo, setting, model, n, pts, t, pk in rows:
        if model == "sector":
            base[eo, setting] = t
        print(f"{eo:>3} {setting:>9} {model:>10} {n:>5} {pts:>7} {t:>8.2f} {t / base[eo, setting]:>10.2f} {pk:>11.4e}")
    sys.stdout.flush()


if __name__ == "__main__":
    main()
