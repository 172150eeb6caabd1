"""Where the single-mode elements hold: the validity map
=====================================================

Where the single-mode elements hold: their F_s, F_c error against AllModeMicroslip (issue 13).

For bars with lambda L and beta L/EA by decades around the DESIGN.md bar (E, rho, A, L, mu
fixed; k = (lambda L / L)^2 EA, beta = (beta L/EA) EA/L), the uniform load (TwoRegionMicroslip)
and the concave load of ratio 12 (ThreeRegionMicroslip), over a/a_min in [0.5, 100] (a_min the
element's static slip amplitude) and omega/omega_c in [0.01, 0.95]::

    e_s = |F_s(single) - F_s(all)| / max(|F_s(all)|, 0.01),
    e_c = |F_c(single) - F_c(all)| / max(F_c(all), 0.01)          (F in units of k* a),

the relative errors with a floor of 0.01 k* a (where F_c is below 1 % of k* a its relative error
says nothing about damping).  A single-mode element that refuses a point (its loading curve
folds: FloatingPointError) counts as out of range (error inf).  The all-mode reference:
40 cells (60 for lambda L = 3, 120 for 10), H = 15.  Stores docs/data/validity_map.csv, writes
docs/figures/validity_map.png and prints the summary table of docs/validation.md.

.. note::
   Not run when the site is built (it takes from several seconds to minutes): the figure is the one a committed run wrote; running this script regenerates it.

.. image:: /figures/validity_map.png
   :alt: Where the single-mode elements hold: the validity map
"""

from __future__ import annotations

import csv
import math
import time
import warnings
from pathlib import Path

import numpy as np

from validation_common import FIGURES, markdown_table

from contact_models.model_range import single_mode_frequency_limit
from contact_models import (AllModeMicroslip, Bar, QuadraticLoad, ThreeRegionMicroslip, TwoRegionMicroslip,
                            UniformLoad)

DATA = Path(__file__).resolve().parent.parent / "docs" / "data" / "validity_map.csv"
E, RHO, A, L, MU = 2.0e11, 7850.0, 1.0e-5, 0.05, 0.3
EA = E * A
#: (lambda L, beta L/EA) of the bars: the DESIGN.md bar is (1, 1).
BARS = ((1.0, 1.0), (0.3, 1.0), (3.0, 1.0), (10.0, 1.0), (1.0, 0.1), (1.0, 10.0))
LOADS = {"uniform": (UniformLoad(N=100.0), TwoRegionMicroslip),
         "concave12": (QuadraticLoad.from_ratio(N=100.0, ratio=12.0), ThreeRegionMicroslip)}
RATIOS = (0.5, 0.9, 1.2, 1.5, 2.0, 3.0, 5.0, 10.0, 30.0, 100.0)
FREQUENCIES = (0.01, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95)
FLOOR = 0.01
#: all-mode cells per bar: about 12 cells per decay length 1/lambda, at least 40
CELLS = {0.3: 40, 1.0: 40, 3.0: 60, 10.0: 120}


def make_bar(lam_L: float, beta_L: float) -> Bar:
    return Bar(E=E, rho=RHO, A=A, L=L, k=(lam_L / L) ** 2 * EA, beta=beta_L * EA / L, mu=MU)


def errors(single, allm, ks, a, w):
    """(e_s, e_c, F_s all, F_c all) at amplitudes a (array) and omega w."""
    fs_a, fc_a = allm.fourier(a, w)
    k = ks * a
    fs_1 = np.full(a.size, np.nan)
    fc_1 = np.full(a.size, np.nan)
    for i, ai in enumerate(a):
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                fs_1[i], fc_1[i] = single.fourier(ai, w)
        except FloatingPointError:
            pass  # refused: out of the single-mode range
    with np.errstate(invalid="ignore"):
        es = np.abs(fs_1 - fs_a) / k / np.maximum(np.abs(fs_a) / k, FLOOR)
        ec = np.abs(fc_1 - fc_a) / k / np.maximum(fc_a / k, FLOOR)
    es[~np.isfinite(es)] = np.inf
    ec[~np.isfinite(ec)] = np.inf
    return es, ec, fs_a / k, fc_a / k


def compute(path: Path = DATA, bars=BARS, ratios=RATIOS, frequencies=FREQUENCIES):
    rows = []
    t0 = time.perf_counter()
    for lam_L, beta_L in bars:
        bar = make_bar(lam_L, beta_L)
        ks, wc = bar.k_star, bar.omega_c
        for name, (load, cls) in LOADS.items():
            single = cls(bar, load)
            cells = CELLS[lam_L]
            allm = AllModeMicroslip(bar, load, cells=cells, harmonics=15)
            a = np.array(ratios) * single.slip_amplitude(0.0)
            for fw in frequencies:
                es, ec, fs, fc = errors(single, allm, ks, a, fw * wc)
                for r, e1, e2, f1, f2 in zip(ratios, es, ec, fs, fc):
                    rows.append((lam_L, beta_L, name, fw, r, e1, e2, f1, f2))
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as fh:
        wr = csv.writer(fh)
        wr.writerow(["lamL", "betaL_EA", "load", "w", "ratio", "e_s", "e_c", "Fs_all", "Fc_all"])
        wr.writerows(rows)
    return rows, time.perf_counter() - t0


def load_rows(path: Path = DATA):
    with open(path) as fh:
        return [(float(r["lamL"]), float(r["betaL_EA"]), r["load"], float(r["w"]), float(r["ratio"]),
                 float(r["e_s"]), float(r["e_c"]), float(r["Fs_all"]), float(r["Fc_all"])) for r in csv.DictReader(fh)]


def summary(rows):
    """Per bar and load: the largest frequency up to which max(e_s, e_c) <= 1 % at every amplitude,
    and the largest errors at 0.2, 0.5 and 0.8 omega_c."""
    out = []
    keys = sorted({(r[0], r[1], r[2]) for r in rows})
    for key in keys:
        sel = [r for r in rows if (r[0], r[1], r[2]) == key]
        ok_up_to = 0.0
        for fw in sorted({r[3] for r in sel}):
            worst = max(max(r[5], r[6]) for r in sel if r[3] == fw and r[4] > 1.0)
            if worst > 0.01:
                break
            ok_up_to = fw
        cells = [key[0], key[1], key[2], ok_up_to]
        for fw in (0.2, 0.5, 0.8):
            e = [max(r[5], r[6]) for r in sel if r[3] == fw and r[4] > 1.0]
            cells.append(max(e) if e else float("nan"))
        out.append(cells)
    return out


def figure(rows, outdir: Path = FIGURES):
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm

    fig, axes = plt.subplots(2, len(BARS), figsize=(3.0 * len(BARS), 6), sharex=True, sharey=True)
    ratios = sorted({r[4] for r in rows})
    freqs = sorted({r[3] for r in rows})
    for j, (lam_L, beta_L) in enumerate(BARS):
        for i, name in enumerate(LOADS):
            Z = np.full((len(ratios), len(freqs)), np.nan)
            for r in rows:
                if (r[0], r[1], r[2]) == (lam_L, beta_L, name):
                    Z[ratios.index(r[4]), freqs.index(r[3])] = max(r[5], r[6])
            ax = axes[i, j]
            refused = ~np.isfinite(Z)
            Zp = np.where(np.isfinite(Z), np.maximum(Z, 1e-5), 10.0)
            cmap = plt.get_cmap("viridis").copy()
            cmap.set_bad("lightgrey")
            m = ax.pcolormesh(freqs, ratios, np.ma.masked_where(refused, Zp), norm=LogNorm(1e-4, 1.0), cmap=cmap,
                              shading="nearest")
            ax.contour(freqs, ratios, Zp, levels=[0.01], colors="w")
            el = LOADS[name][1](make_bar(lam_L, beta_L), LOADS[name][0])
            ax.axvline(single_mode_frequency_limit(el) / el.bar.omega_c, color="r", ls="--", lw=1)
            ax.set_yscale("log")
            ax.set_title(f"{name}, lL={lam_L:g}, bL/EA={beta_L:g}", fontsize=8)
            if i == 1:
                ax.set_xlabel("omega / omega_c")
            if j == 0:
                ax.set_ylabel("a / a_min")
    fig.colorbar(m, ax=axes, label="max(e_s, e_c) (white: 1 %; red dashed: omega_1 of the warning; grey: refused)")
    fig.savefig(outdir / "validity_map.png", dpi=100)
    plt.close(fig)


def main(recompute: bool = False, outdir: Path = FIGURES):
    if DATA.exists() and not recompute:
        rows, sec = load_rows(), float("nan")
    else:
        rows, sec = compute()
    figure(rows, outdir)
    def pct(e):
        return f"{e:.1%}" if math.isfinite(e) else "refused"

    table = []
    for lL, bL, n, ok, e2, e5, e8 in summary(rows):
        el = LOADS[n][1](make_bar(lL, bL), LOADS[n][0])
        table.append((lL, bL, n, f"{ok:g}", f"{single_mode_frequency_limit(el) / el.bar.omega_c:.3f}",
                      pct(e2), pct(e5), pct(e8)))
    print(markdown_table(["lambda L", "beta L/EA", "load", "map: <= 1 % up to w/w_c (grid)", "warning from w_1/w_c",
                          "worst at 0.2", "worst at 0.5", "worst at 0.8"], table))
    if math.isfinite(sec):
        print(f"\n{len(rows)} points in {sec:.0f} s")
    return rows


if __name__ == "__main__":
    import sys

    main("--recompute" in sys.argv)
