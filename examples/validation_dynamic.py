"""Validation: single-mode elements against all modes
==================================================

The table of F_s, F_c of the single-mode analytic elements against the full numerical
solution (``NumericalMicroslip``, all modes) at omega/omega_c in {0.01, 0.2, 0.3, 0.5} and
a/a_min in {1.5, 3, 10, 30}, for the uniform and the ratio-12 concave load.

The numerical values are computed at (cells, steps_per_cycle) and again at half of both; the
change is quoted as the numerical solution's error bar (conservative: with second-order
convergence the finer run's own error is about a third of it).  Writes
``validation_dynamic.png`` (F_s, F_c against a/a_min: analytic lines, numerical points) and
returns the rows; ``python3 examples/validation_dynamic.py`` prints the markdown table::

    python3 examples/validation_dynamic.py                     # cells 200, 1024 steps (~15 min)
    python3 examples/validation_dynamic.py --cells 100 --steps 512

.. note::
   Not run when the site is built (about 15 min): the figure is the one a committed run wrote,
   ``docs/figures/validation_dynamic.png``; running this script regenerates it.

.. image:: /figures/validation_dynamic.png
   :alt: Validation: single-mode elements against all modes
"""

# sphinx_gallery_thumbnail_path = "figures/validation_dynamic.png"

from __future__ import annotations

import argparse
import time

import matplotlib.pyplot as plt
import numpy as np

from validation_common import BAR, FIGURES, FREQUENCIES, LOADS, RATIOS, analytic, markdown_table

from contact_models import NumericalMicroslip

STYLES = {0.01: ("k", "o"), 0.2: ("tab:blue", "s"), 0.3: ("tab:green", "^"), 0.5: ("tab:red", "D")}


def main(cells: int = 200, steps: int = 1024, frequencies=FREQUENCIES, ratios=RATIOS, outdir=FIGURES,
         small: bool = False):
    """``{"path", "rows"}``: rows with the analytic and numerical F_s, F_c, relative differences
    and error bars.  ``small``: 40 cells, 256 steps, 0.01 and 0.3 omega_c, a/a_min 1.5 and 10."""
    if small:
        cells, steps, frequencies, ratios = 40, 256, (0.01, 0.3), (1.5, 10.0)
    k_star = BAR.k_star
    rows = []
    for name, (load, _) in LOADS.items():
        el = analytic(name)
        a_min = el.slip_amplitude(0.0)
        a = np.array(ratios) * a_min
        fine = NumericalMicroslip(BAR, load, cells=cells, steps_per_cycle=steps)
        coarse = NumericalMicroslip(BAR, load, cells=cells // 2, steps_per_cycle=steps // 2)
        for wr in frequencies:
            w = wr * BAR.omega_c
            t0 = time.perf_counter()
            fs, fc = fine.fourier(a, w)
            seconds = (time.perf_counter() - t0) / a.size
            fs2, fc2 = coarse.fourier(a, w)
            fs_a, fc_a = el.fourier(a, w)
            for i, r in enumerate(ratios):
                k = k_star * a[i]
                rows.append(dict(load=name, w=wr, ratio=r, Fs=fs_a[i] / k, Fs_num=fs[i] / k, Fs_err=abs(fs[i] - fs2[i]) / k,
                                 Fc=fc_a[i] / k, Fc_num=fc[i] / k, Fc_err=abs(fc[i] - fc2[i]) / k,
                                 dFs=fs[i] / fs_a[i] - 1.0, dFc=fc[i] / fc_a[i] - 1.0 if fc_a[i] else np.nan,
                                 seconds=seconds))
    return {"path": str(_figure(rows, outdir, cells, steps)), "rows": rows}


def _figure(rows, outdir, cells, steps):
    fig, axes = plt.subplots(2, 2, figsize=(11, 8), sharex=True)
    for col, name in enumerate(LOADS):
        el = analytic(name)
        a_min = el.slip_amplitude(0.0)
        grid = np.geomspace(0.5, 40.0, 200)
        for wr, (color, mk) in STYLES.items():
            sel = [r for r in rows if r["load"] == name and r["w"] == wr]
            if not sel:
                continue
            fs, fc = el.fourier(grid * a_min, wr * BAR.omega_c)
            k = BAR.k_star * grid * a_min
            axes[0, col].semilogx(grid, fs / k, color=color, lw=1, label=rf"{wr:g} $\omega_c$ analytic")
            axes[1, col].semilogx(grid, fc / k, color=color, lw=1)
            x = [r["ratio"] for r in sel]
            axes[0, col].errorbar(x, [r["Fs_num"] for r in sel], yerr=[r["Fs_err"] for r in sel], fmt=mk, color=color,
                                  mfc="none", label="numerical")
            axes[1, col].errorbar(x, [r["Fc_num"] for r in sel], yerr=[r["Fc_err"] for r in sel], fmt=mk, color=color,
                                  mfc="none")
        axes[0, col].set_title(f"{name} load (numerical: {cells} cells, {steps} steps/cycle)")
        axes[1, col].set_xlabel(r"$a / a_{min}$")
    axes[0, 0].set_ylabel(r"$F_s = f_s/(k^* a)$")
    axes[1, 0].set_ylabel(r"$F_c = f_c/(k^* a)$")
    axes[0, 0].legend(fontsize=7, ncol=2)
    for ax in axes.ravel():
        ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    outdir.mkdir(parents=True, exist_ok=True)
    path = outdir / "validation_dynamic.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def table(rows) -> str:
    header = ["load", "w/w_c", "a/a_min", "F_s analytic", "F_s numerical", "rel. diff", "F_c analytic",
              "F_c numerical", "rel. diff"]
    body = [[r["load"], f"{r['w']:g}", f"{r['ratio']:g}", f"{r['Fs']:.5f}", f"{r['Fs_num']:.5f} ± {r['Fs_err']:.0e}",
             f"{r['dFs']:+.2%}", f"{r['Fc']:.5f}", f"{r['Fc_num']:.5f} ± {r['Fc_err']:.0e}", f"{r['dFc']:+.2%}"]
            for r in rows]
    return markdown_table(header, body)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=(__doc__ or "").partition("\n")[0])
    parser.add_argument("--cells", type=int, default=200)
    parser.add_argument("--steps", type=int, default=1024)
    args = parser.parse_args()
    t0 = time.perf_counter()
    rows = main(cells=args.cells, steps=args.steps)["rows"]
    print(table(rows))
    print(f"\nlargest error bar (units of k* a): {max(max(r['Fs_err'], r['Fc_err']) for r in rows):.1e}; "
          f"mean time per (a, omega) pair at {args.cells} cells: {np.mean([r['seconds'] for r in rows]):.1f} s; "
          f"{time.perf_counter() - t0:.0f} s in all")
