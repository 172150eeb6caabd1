"""Validation: blade and bar in time against the FRF
=================================================

The blade and the discretised bar integrated in time against the
harmonic-balance FRF, at three frequencies around resonance.

The default case of ``python3 -m hbm`` (blade k = 1e8 N/m, zeta = 2e-3, F = 8 N; the reference
bar under a uniform 100 N load as the damper).  At each frequency:

- HBM, analytic element: ``response_at(blade, TwoRegionMicroslip, omega)``, the FRF's value;
- HBM, numerical element: ``response_at(blade, NumericalMicroslip(cells, steps), omega)``, the
  same single-harmonic balance with the full bar (all modes) in place of the single-mode one;
- time integration: ``simulate_blade(blade, NumericalMicroslip(cells), omega)`` at the
  discretisation levels ``levels`` (cells, steps per cycle), each doubling both; the finest is
  quoted, with the whole change from the level before as its error bar.  Not a second-order
  estimate: the bar's second stuck mode (about 13 omega here, undamped in Eq. 30) rings between
  slip events, and how much of that ringing the integrator's numerical damping removes depends
  on the step, so the convergence is not yet asymptotic at these levels (docs/validation.md).

So time integration vs HBM-numerical measures what the single harmonic leaves out, and
HBM-numerical vs HBM-analytic what the single mode leaves out.  Writes ``validation_blade.png``
(the FRF with the three time-integration points; the damper's steady loops) and returns the
rows; ``python3 examples/validation_blade.py`` prints the markdown table (about 6 min).

.. note::
   Not run when the site is built (about 6 min): the figure is the one a committed run wrote,
   ``docs/figures/validation_blade.png``; running this script regenerates it.

.. image:: /figures/validation_blade.png
   :alt: Validation: blade and bar in time against the FRF
"""

# sphinx_gallery_thumbnail_path = "figures/validation_blade.png"

from __future__ import annotations

import argparse
import time

import matplotlib.pyplot as plt
import numpy as np

from paper_figures import default_case
from validation_common import FIGURES, markdown_table

from contact_models import NumericalMicroslip
from hbm import frequency_response, response_at, simulate_blade

#: The three frequencies (rad/s): on the steep rising flank, the peak (None), the falling flank.
OMEGAS = (38400.0, None, 40000.0)
#: (cells, steps per cycle) of the time integrations, and of the HBM with the numerical element.
LEVELS = ((40, 256), (80, 512), (160, 1024))
HBM_LEVEL = (80, 1024)
#: Steady-state tolerance of the time integrations (relative cycle-to-cycle change of x).
STEADY_TOL = 1e-7


def main(levels=LEVELS, hbm_level=HBM_LEVEL, omegas=OMEGAS, outdir=FIGURES, small: bool = False):
    """``{"path", "rows", "a_min", "peak"}``; ``small``: levels (20, 128), (40, 256), HBM level
    (40, 256), the peak and 40000 rad/s only."""
    if small:
        levels, hbm_level, omegas = ((20, 128), (40, 256)), (40, 256), (None, 40000.0)
    case = default_case()
    blade, element = case.blade, case.element
    bar, load = element.bar, element.load
    frf = frequency_response(blade, element, case.omega_range)
    peak = frf.peak()
    a_min = element.slip_amplitude(0.0)
    rows = []
    for w in omegas:
        w = peak.omega if w is None else float(w)
        a_guess = float(np.interp(w, frf.omega, frf.amplitude))
        bracket = (0.8 * a_guess, 1.2 * a_guess)
        hbm_a = response_at(blade, element, w, bracket)
        num = NumericalMicroslip(bar, load, cells=hbm_level[0], steps_per_cycle=hbm_level[1])
        t0 = time.process_time()
        hbm_n = response_at(blade, num, w, bracket, rtol=1e-7)
        t_hbm = time.process_time() - t0
        runs = []
        for cells, steps in levels:
            t0 = time.process_time()
            sim = simulate_blade(blade, NumericalMicroslip(bar, load, cells=cells), w, steps_per_cycle=steps,
                                 steady_tol=STEADY_TOL)
            runs.append((cells, steps, sim, time.process_time() - t0))
        fine, finest = runs[-2][2], runs[-1][2]
        a_ti = finest.amplitude
        rows.append(dict(omega=w, hbm=hbm_a, hbm_num=hbm_n, hbm_seconds=t_hbm, runs=runs, a_ti=a_ti,
                         a_err=abs(a_ti - fine.amplitude), phase_ti=finest.phase,
                         phase_err=abs(finest.phase - fine.phase),
                         d_hbm=a_ti / hbm_a.amplitude - 1.0, d_num=a_ti / hbm_n.amplitude - 1.0,
                         d_single=hbm_n.amplitude / hbm_a.amplitude - 1.0))
    path = _figure(case, frf, rows, a_min, outdir)
    return {"path": str(path), "rows": rows, "a_min": a_min, "peak": peak}


def _figure(case, frf, rows, a_min, outdir):
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.8))
    sel = (frf.omega > 37500.0) & (frf.omega < 41500.0)
    ax.plot(frf.omega[sel], frf.amplitude[sel] / a_min, "k-", lw=1, label="HBM, TwoRegionMicroslip (single mode)")
    hbm_cells = None
    for r in rows:
        cells, steps, sim, _ = r["runs"][-1]
        ax.errorbar(r["omega"], r["a_ti"] / a_min, yerr=r["a_err"] / a_min, fmt="o", color="tab:red", mfc="none",
                    ms=8, label=None if hbm_cells else "time integration, blade + discretised bar")
        ax.plot(r["omega"], r["hbm_num"].amplitude / a_min, "s", color="tab:blue", ms=5,
                label=None if hbm_cells else "HBM, NumericalMicroslip (all modes)")
        hbm_cells = True
        x, f = np.append(sim.x, sim.x[0]), np.append(sim.f, sim.f[0])
        line, = bx.plot(x / a_min, f, lw=1.2, label=f"{r['omega']:.0f} rad/s, time integration")
        # the analytic element's loop at the HBM amplitude
        xa, fa = case.element.hysteresis(r["hbm"].amplitude, r["omega"], n=400)
        bx.plot(xa / a_min, fa, "--", color=line.get_color(), lw=1, label="analytic element at the HBM amplitude")
    ax.set_xlabel(r"$\omega$ (rad/s)")
    ax.set_ylabel(r"first-harmonic amplitude / $a_{min}$")
    ax.set_title("default case: FRF and time integration")
    ax.legend(fontsize=8)
    bx.set_xlabel(r"blade displacement / $a_{min}$")
    bx.set_ylabel("damper force on the blade (N)")
    bx.set_title("steady damper loops")
    bx.legend(fontsize=7)
    for a in (ax, bx):
        a.grid(True, alpha=0.3)
    fig.tight_layout()
    outdir.mkdir(parents=True, exist_ok=True)
    path = outdir / "validation_blade.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def ringing(f) -> float:
    """rms of the 5th and higher harmonics of a periodic signal over its first harmonic."""
    F = np.fft.rfft(f)
    return float(np.sqrt(np.sum(np.abs(F[5:]) ** 2)) / np.abs(F[1]))


def tables(rows, a_min) -> str:
    header = ["omega (rad/s)", "HBM analytic a/a_min", "HBM numerical a/a_min", "time integration a/a_min",
              "TI vs HBM analytic", "TI vs HBM numerical", "HBM numerical vs analytic",
              "phase (rad): HBM analytic / numerical / TI"]
    body = [[f"{r['omega']:.1f}", f"{r['hbm'].amplitude / a_min:.5f}", f"{r['hbm_num'].amplitude / a_min:.5f}",
             f"{r['a_ti'] / a_min:.5f} ± {r['a_err'] / a_min:.0e}", f"{r['d_hbm']:+.2%}", f"{r['d_num']:+.2%}",
             f"{r['d_single']:+.2%}", f"{r['hbm'].phase:.4f} / {r['hbm_num'].phase:.4f} / {r['phase_ti']:.4f} ± {r['phase_err']:.0e}"]
            for r in rows]
    out = [markdown_table(header, body), ""]
    header = ["omega (rad/s)", "cells", "steps/cycle", "a/a_min", "phase (rad)", "ringing", "cycles",
              "last change", "distance", "CPU (s)"]
    body = [[f"{r['omega']:.1f}", c, s, f"{sim.amplitude / a_min:.5f}", f"{sim.phase:.4f}", f"{ringing(sim.f):.3f}",
             sim.cycles, f"{sim.change:.0e}", f"{sim.distance:.0e}", f"{sec:.1f}"]
            for r in rows for c, s, sim, sec in r["runs"]]
    out.append(markdown_table(header, body))
    return "\n".join(out)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=(__doc__ or "").partition("\n")[0])
    parser.parse_args()
    t0 = time.perf_counter()
    out = main()
    print(tables(out["rows"], out["a_min"]))
    print(f"\nHBM with the numerical element: "
          + ", ".join(f"{r['hbm_seconds']:.0f} s" for r in out["rows"])
          + f" CPU per frequency; {time.perf_counter() - t0:.0f} s in all")
