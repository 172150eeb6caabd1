"""Validation: the all-mode bar against time integration
=====================================================

AllModeMicroslip against converged time integration (NumericalMicroslip).

The reference runs (NumericalMicroslip, 200 cells, 1024 steps per cycle: about 5e-5 k* a from
its own convergence study) are slow (10-40 s per point), so they run once and are stored in
``docs/data/allmode_reference.csv``; later runs read that file (``--recompute`` to redo it).
Loads: uniform, concave12 (docs/validation.md) and "wavy": q = (N/L)(1 + 0.8 cos(6 pi x/L)),
N = 100 N, which slips in pockets (four or more stick and slip regions).

Writes the comparison table (markdown) to stdout and the stick/slip map of the wavy load over a
cycle, all-mode beside time integration, to docs/figures/allmode_regions.png.

.. note::
   Not run when the site is built (it takes from several seconds to minutes): the figure is the one a committed run wrote; running this script regenerates it.

.. image:: /figures/allmode_regions.png
   :alt: Validation: the all-mode bar against time integration
"""

# sphinx_gallery_thumbnail_path = "figures/allmode_regions.png"

from __future__ import annotations

import argparse
import csv
import time
from pathlib import Path

import numpy as np

from validation_common import BAR, FIGURES, LOADS, markdown_table

from contact_models import AllModeMicroslip, FunctionLoad, NumericalMicroslip

DATA = Path(__file__).resolve().parent.parent / "docs" / "data" / "allmode_reference.csv"
L = BAR.L
WAVY = FunctionLoad(lambda x: 100.0 / L * (1.0 + 0.8 * np.cos(6.0 * np.pi * x / L)))
ALL_LOADS = {"uniform": LOADS["uniform"][0], "concave12": LOADS["concave12"][0], "wavy": WAVY}
FREQUENCIES = (0.01, 0.2, 0.5, 0.8)
RATIOS = (0.5, 1.5, 3.0, 10.0, 30.0, 100.0)
#: (omega/omega_c, a/a_min) of the wavy-load points.
WAVY_POINTS = ((0.01, 3.0), (0.2, 3.0), (0.5, 3.0), (0.5, 10.0), (0.8, 3.0))
REF_CELLS, REF_STEPS = 200, 1024


def points():
    for name in ("uniform", "concave12"):
        for w in FREQUENCIES:
            for r in RATIOS:
                yield name, w, r
    for w, r in WAVY_POINTS:
        yield "wavy", w, r


def reference(recompute: bool = False, cells: int = REF_CELLS, steps: int = REF_STEPS, path: Path = DATA):
    """{(load, w/w_c, a/a_min): (F_s, F_c, seconds)} from the stored CSV or fresh runs."""
    if path.exists() and not recompute:
        with open(path) as fh:
            return {(r["load"], float(r["w"]), float(r["ratio"])): (float(r["Fs"]), float(r["Fc"]), float(r["seconds"]))
                    for r in csv.DictReader(fh)}
    out = {}
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as fh:
        wr = csv.writer(fh)
        wr.writerow(["load", "w", "ratio", "Fs", "Fc", "seconds", "converged"])
        for name, w, r in points():
            num = NumericalMicroslip(BAR, ALL_LOADS[name], cells=cells, steps_per_cycle=steps)
            a = r * num.slip_amplitude(0.0)
            t0 = time.process_time()
            res = num.simulate(a, w * BAR.omega_c) if a > num.slip_amplitude(w * BAR.omega_c) else None
            sec = time.process_time() - t0
            if res is None:
                fs, fc, ok = num.stuck_stiffness(w * BAR.omega_c) * a, 0.0, True
            else:
                fs, fc, ok = res.f_s, res.f_c, res.converged
            k = BAR.k_star * a
            out[(name, w, r)] = (fs / k, fc / k, sec)
            wr.writerow([name, w, r, repr(fs / k), repr(fc / k), f"{sec:.2f}", ok])
            fh.flush()
    return out


#: all-mode cells per load: the defaults, and 80 (about 27 cells per period of the load) for the wavy load,
#: whose three periods along the bar 40 cells resolve to only 2e-3 k* a (the error estimate says so)
CELLS = {"uniform": 40, "concave12": 40, "wavy": 80}


def compare(ref, cells: dict | None = None, harmonics: int = 15):
    """Rows (load, w, r, F_s ref, F_s all-mode, dF_s, F_c ref, F_c all-mode, dF_c, estimate, ms)."""
    rows = []
    cells = cells or CELLS
    for name in ALL_LOADS:
        el = AllModeMicroslip(BAR, ALL_LOADS[name], cells=cells[name], harmonics=harmonics)
        # the reference's physical amplitudes: a/a_min with a_min of its 200-cell bar
        amin = NumericalMicroslip(BAR, ALL_LOADS[name], cells=REF_CELLS).slip_amplitude(0.0)
        for (nm, w, r), (fs_ref, fc_ref, _) in sorted(ref.items()):
            if nm != name:
                continue
            a = r * amin
            t0 = time.perf_counter()
            sol = el.solve(a, w * BAR.omega_c, estimate_error=True)
            ms = 1e3 * (time.perf_counter() - t0)
            k = BAR.k_star * a
            rows.append((name, w, r, fs_ref, sol.f_s / k, sol.f_s / k - fs_ref, fc_ref, sol.f_c / k,
                         sol.f_c / k - fc_ref, sol.error / k, ms))
    return rows


def regions_figure(outdir: Path = FIGURES, w: float = 0.5, r: float = 3.0, cells: int = 100, steps: int = 512):
    """Stick/slip map of the wavy load over a cycle: all-mode (left) and time integration (right)."""
    import matplotlib.pyplot as plt

    el = AllModeMicroslip(BAR, WAVY, cells=cells, harmonics=15)
    a = r * NumericalMicroslip(BAR, WAVY, cells=REF_CELLS).slip_amplitude(0.0)
    theta, x, slip = el.stick_slip_map(a, w * BAR.omega_c)
    num = NumericalMicroslip(BAR, WAVY, cells=cells, steps_per_cycle=steps)
    slip_num = _numerical_slip(num, a, w * BAR.omega_c)
    fig, axes = plt.subplots(1, 3, figsize=(12, 4), gridspec_kw={"width_ratios": [1, 1, 0.5]})
    for ax, s, title in ((axes[0], slip, "all-mode (frequency domain)"), (axes[1], slip_num, "time integration")):
        th = np.linspace(0, 2 * np.pi, s.shape[1] + 1)  # sample k drawn over [theta_k, theta_k+1)
        xe = (np.arange(s.shape[0] + 1) - 0.5) / cells  # node i drawn over x_i -+ h/2
        ax.pcolormesh(th / np.pi, xe, s * 1.0, cmap="Greys", vmin=0, vmax=1.6, shading="flat")
        ax.set_xlabel("theta / pi")
        ax.set_title(title)
    axes[0].set_ylabel("x / L (dark: slipping)")
    xx = np.linspace(0, L, 400)
    axes[2].plot(WAVY.on(L).q(xx) * L / 100.0, xx / L)
    axes[2].set_xlabel("q L / N")
    axes[2].set_title("normal load")
    fig.suptitle(f"wavy load, {w} omega_c, a = {r} a_min")
    fig.tight_layout()
    fig.savefig(outdir / "allmode_regions.png", dpi=110)
    plt.close(fig)
    return slip, slip_num


def _numerical_slip(num, a, omega):
    """Slip mask (nodes, steps) of the steady cycle of a time integration: the nodes that slipped
    in the step ending at theta_k = 2 pi k / steps (recorded from the integrator's steps)."""
    from contact_models.numerics import stepping as _stepping

    record = []
    original = _stepping._Batch.step

    def step(batch, ut=None):
        f = original(batch, ut)
        record.append((batch.count, batch.slip[0].copy()))
        return f

    _stepping._Batch.step = step
    try:
        res = num.simulate(a, omega)
    finally:
        _stepping._Batch.step = original
    steps = res.steps
    mask = np.zeros((num.cells + 1, steps), bool)
    for cnt, sl in record[-steps:]:
        mask[:, cnt % steps] = sl
    return mask


def count_regions(slip_column) -> int:
    """Number of stick and slip regions along the bar in one sample."""
    return 1 + int(np.count_nonzero(slip_column[1:] != slip_column[:-1]))


def main(recompute: bool = False, harmonics: int = 15, outdir: Path = FIGURES, figure: bool = True):
    ref = reference(recompute)
    rows = compare(ref, CELLS, harmonics)
    header = ["load", "w/w_c", "a/a_min", "F_s TI", "F_s all-mode", "dF_s", "F_c TI", "F_c all-mode", "dF_c",
              "estimate", "ms"]
    fmt = [(n, w, r, f"{a:.5f}", f"{b:.5f}", f"{c:+.1e}", f"{d:.5f}", f"{e:.5f}", f"{f:+.1e}", f"{g:.0e}", f"{h:.0f}")
           for n, w, r, a, b, c, d, e, f, g, h in rows]
    print(markdown_table(header, fmt))
    worst = max(max(abs(r[5]), abs(r[8])) for r in rows)
    print(f"\nlargest |dF_s|, |dF_c|: {worst:.2e} k* a over {len(rows)} points")
    if figure:
        slip, slip_num = regions_figure(outdir)
        print("regions along the bar over the cycle (all-mode): max", max(count_regions(c) for c in slip.T),
              "; time integration: max", max(count_regions(c) for c in slip_num.T))
    return rows


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--recompute", action="store_true", help="redo the time integrations (about 30 min)")
    parser.add_argument("--harmonics", type=int, default=15)
    args = parser.parse_args()
    main(args.recompute, args.harmonics)
