"""Where the single-mode elements hold: the validity map
=====================================================

Where the single-mode elements hold: their F_s, F_c error against AllModeMicroslip.

For bars with lambda L in {0.3, 1, 3, 10} and beta L/EA in {0.1, 1, 10}, every pair (E, rho, A,
L, mu of the reference bar, ``E = 2e11, rho = 7850, A = 1e-5, L = 0.05, mu = 0.3``; k = (lambda L / L)^2 EA, beta = (beta L/EA) EA/L), the uniform load
(TwoRegionMicroslip) and the concave load of ratio 12 (ThreeRegionMicroslip), over a/a_min in
[0.5, 100] (a_min the element's static slip amplitude) and omega/omega_c in [0.01, 0.95]::

    e_s = |F_s(single) - F_s(all)| / max(|F_s(all)|, 0.01),
    e_c = |F_c(single) - F_c(all)| / max(F_c(all), 0.01)          (F in units of k* a),

the relative errors with a floor of 0.01 k* a (where F_c is below 1 % of k* a its relative error
says nothing about damping).  A single-mode element that refuses a point (its loading curve
folds: FloatingPointError) or the bar (ValueError when built) counts as out of range (error
inf).  The all-mode reference: H = 15 and 160 cells up to lambda L = 1.5, more for stiffer
shear layers (``reference_cells``), with its own error estimated from half the cells and from
H = 11 (columns de_s, de_c).

Stores the map in contact_models/data/validity_map.csv (the single-mode elements' warning reads
it, ``contact_models.model_range``) and 240 random off-grid points in docs/data/validity_check.csv
(which the warning does not read: they score its interpolation), writes
docs/figures/validity_map.png and prints the summary of docs/validation.md.  ``--recompute``
recomputes both files (about 10 minutes).

.. note::
   Not run when the site is built (it takes from several seconds to minutes): the figure is the one a committed run wrote; running this script regenerates it.

.. image:: /figures/validity_map.png
   :alt: Where the single-mode elements hold: the validity map
"""

# sphinx_gallery_thumbnail_path = "figures/validity_map.png"

from __future__ import annotations

import csv
import math
import time
from pathlib import Path

import numpy as np

from validation_common import FIGURES, markdown_table

from contact_models import (AllModeMicroslip, Bar, QuadraticLoad, ThreeRegionMicroslip, TwoRegionMicroslip,
                            UniformLoad)
from contact_models.base import DEFAULT_RTOL
from contact_models.model_range import MAP_FILE, single_mode_error, single_mode_frequency_limit

#: The map (the warning reads it): contact_models/data/validity_map.csv.
DATA = MAP_FILE
#: The off-grid check of the warning's interpolation: docs/data/validity_check.csv.
CHECK = Path(__file__).resolve().parent.parent / "docs" / "data" / "validity_check.csv"
E, RHO, A, L, MU = 2.0e11, 7850.0, 1.0e-5, 0.05, 0.3
EA = E * A
#: lambda L and beta L/EA of the bars, every pair (the reference bar is (1, 1)).
LAMBDA_L = (0.3, 1.0, 3.0, 10.0)
BETA_L = (0.1, 1.0, 10.0)
BARS = tuple((lL, bL) for lL in LAMBDA_L for bL in BETA_L)
LOADS = {"uniform": (UniformLoad(N=100.0), TwoRegionMicroslip),
         "concave12": (QuadraticLoad.from_ratio(N=100.0, ratio=12.0), ThreeRegionMicroslip)}
RATIOS = (0.5, 0.9, 1.2, 1.5, 2.0, 3.0, 5.0, 10.0, 30.0, 100.0)
FREQUENCIES = (0.01, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95)
FLOOR = 0.01
#: The all-mode reference's harmonics, and the fewer ones its harmonic error is estimated with.
HARMONICS = 15
HARMONICS_CHECK = 11
#: The reference is the bar with lumped masses (the stored map was computed with it; its estimate de holds
#: its mesh error, the change from half the cells).  The exact segments' bar converges to the same limit.
LINEAR = "lumped"
COLUMNS = ["lamL", "betaL_EA", "load", "w", "ratio", "e_s", "e_c", "de_s", "de_c", "Fs_all", "Fc_all"]


def reference_cells(lam_L: float) -> int:
    """All-mode reference cells: 160 up to lambda L = 1.5, beyond it in proportion to lambda L (about
    107 cells per decay length 1/lambda: 320 at lambda L = 3, 1066 at 10), even."""
    return 160 if lam_L <= 1.5 else 2 * round(80 * lam_L / 1.5)


def make_bar(lam_L: float, beta_L: float) -> Bar:
    return Bar(E=E, rho=RHO, A=A, L=L, k=(lam_L / L) ** 2 * EA, beta=beta_L * EA / L, mu=MU)


def static_slip_amplitude(bar, load, single):
    """a_min(0), the map's amplitude unit: the element's, or where it refuses the bar the
    stuck bar's slip onset (the all-mode bar's, which is the same model at omega = 0)."""
    if single is not None:
        return single.slip_amplitude(0.0)
    return AllModeMicroslip(bar, load, cells=reference_cells(bar.lam * bar.L), linear=LINEAR).slip_amplitude(0.0)


def single_mode(single, a, w):
    """The single-mode F pair at each amplitude (N), NaN where the element refuses the point."""
    fs, fc = np.full(a.size, np.nan), np.full(a.size, np.nan)
    for i, ai in enumerate(a):
        try:  # the unchecked path: the map is what the check reads, so it must not need it
            fs[i], fc[i] = (float(v[0]) for v in single.fourier_derivatives_unchecked(
                np.array([ai]), np.array([float(w)]), DEFAULT_RTOL)[:2])
        except FloatingPointError:
            pass  # refused: out of the single-mode range
    return fs, fc


def single_element(cls, bar, load):
    """The single-mode element, or None where it refuses the bar and load when built (its static
    loading curve folds: stiff shear layers under the concave load)."""
    try:
        return cls(bar, load)
    except ValueError:
        return None


def errors(single, bar, load, a, w, cells):
    """``(e_s, e_c, de_s, de_c, F_s all, F_c all)`` at amplitudes a (array) and omega w.

    e = |F(single) - F(all)| / max(|F(all)|, FLOOR) (F in units of k* a); de is the reference's
    own error in the same units: the larger of the cell part |F(n) - F(n/2)|/3 and the harmonic
    part |F(H) - F(H')| H'^2/(H^2 - H'^2), H' = ``HARMONICS_CHECK`` (both second order, as measured
    in docs/validation.md; the harmonics converge slowest in gross slip of stiff shear layers).
    Where the single-mode element refuses every amplitude the all-mode bar is not solved (e = inf,
    de = 0, F = NaN).
    """
    ks = bar.k_star * a
    fs_1, fc_1 = single_mode(single, a, w) if single is not None else (np.full(a.size, np.nan),) * 2
    if not np.any(np.isfinite(fs_1)):
        inf, nan = np.full(a.size, np.inf), np.full(a.size, np.nan)
        return inf, inf, np.zeros(a.size), np.zeros(a.size), nan, nan
    ref = AllModeMicroslip(bar, load, cells=cells, harmonics=HARMONICS, linear=LINEAR)
    half_cells = AllModeMicroslip(bar, load, cells=cells // 2, harmonics=HARMONICS, linear=LINEAR)
    fewer_h = AllModeMicroslip(bar, load, cells=cells, harmonics=HARMONICS_CHECK, linear=LINEAR)
    fs_a, fc_a = (v / ks for v in ref.fourier(a, w))
    d = [np.abs(np.array(e.fourier(a, w)) / ks - (fs_a, fc_a)) for e in (half_cells, fewer_h)]
    err = np.maximum(d[0] / 3.0, d[1] * HARMONICS_CHECK**2 / (HARMONICS**2 - HARMONICS_CHECK**2))
    sc_s, sc_c = np.maximum(np.abs(fs_a), FLOOR), np.maximum(fc_a, FLOOR)
    with np.errstate(invalid="ignore"):
        es = np.abs(fs_1 / ks - fs_a) / sc_s
        ec = np.abs(fc_1 / ks - fc_a) / sc_c
    es[~np.isfinite(es)] = np.inf
    ec[~np.isfinite(ec)] = np.inf
    return es, ec, err[0] / sc_s, err[1] / sc_c, fs_a, fc_a


def compute(path: Path = DATA, bars=BARS, ratios=RATIOS, frequencies=FREQUENCIES, loads=tuple(LOADS)):
    """The map: every bar, load, frequency and amplitude; written to ``path`` (CSV, ``COLUMNS``)."""
    rows = []
    t0 = time.perf_counter()
    for lam_L, beta_L in bars:
        bar = make_bar(lam_L, beta_L)
        for name in loads:
            load, cls = LOADS[name]
            single = single_element(cls, bar, load)
            a = np.array(ratios) * static_slip_amplitude(bar, load, single)
            for fw in frequencies:
                cols = errors(single, bar, load, a, fw * bar.omega_c, reference_cells(lam_L))
                rows += [(lam_L, beta_L, name, fw, r, *vals) for r, *vals in zip(ratios, *cols)]
    write_rows(path, rows)
    return rows, time.perf_counter() - t0


def compute_check(path: Path = CHECK, n: int = 240, seed: int = 20261125):
    """The off-grid check: ``n`` points drawn uniformly in log lambda L in [0.3, 10], log beta L/EA
    in [0.1, 10], omega/omega_c in [0.01, 0.95] and log a/a_min in [log 1.1, log 100], both loads;
    the same errors as the map.  The warning's interpolation is scored against them (docs/validation.md)."""
    rng = np.random.default_rng(seed)
    rows = []
    t0 = time.perf_counter()
    for i in range(n):
        lam_L = float(np.exp(rng.uniform(np.log(0.3), np.log(10.0))))
        beta_L = float(np.exp(rng.uniform(np.log(0.1), np.log(10.0))))
        fw = float(rng.uniform(0.01, 0.95))
        ratio = float(np.exp(rng.uniform(np.log(1.1), np.log(100.0))))
        name = tuple(LOADS)[i % 2]
        bar = make_bar(lam_L, beta_L)
        load, cls = LOADS[name]
        single = single_element(cls, bar, load)
        a = np.array([ratio * static_slip_amplitude(bar, load, single)])
        cols = errors(single, bar, load, a, fw * bar.omega_c, reference_cells(lam_L))
        rows.append((lam_L, beta_L, name, fw, ratio, *(float(v[0]) for v in cols)))
    write_rows(path, rows)
    return rows, time.perf_counter() - t0


def write_rows(path: Path, rows) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as fh:
        wr = csv.writer(fh)
        wr.writerow(COLUMNS)
        wr.writerows(rows)


def load_rows(path: Path = DATA):
    """The stored rows: ``(lamL, betaL_EA, load, w, ratio, e, de)`` with e = max(e_s, e_c), de its
    reference error."""
    with open(path) as fh:
        return [(float(r["lamL"]), float(r["betaL_EA"]), r["load"], float(r["w"]), float(r["ratio"]),
                 max(float(r["e_s"]), float(r["e_c"])), max(float(r["de_s"]), float(r["de_c"])))
                for r in csv.DictReader(fh)]


def summary(rows):
    """Per bar and load: the largest map frequency up to which e <= 1 % at every amplitude, the
    warning's omega_1, and the largest errors at 0.2, 0.5 and 0.8 omega_c ("refused" where the
    element refuses the bar)."""
    out = []
    for key in sorted({(r[0], r[1], r[2]) for r in rows}):
        sel = [r for r in rows if (r[0], r[1], r[2]) == key]
        el = single_element(LOADS[key[2]][1], make_bar(key[0], key[1]), LOADS[key[2]][0])
        ok_up_to = 0.0
        for fw in sorted({r[3] for r in sel}):
            if max(r[5] for r in sel if r[3] == fw) > FLOOR:
                break
            ok_up_to = fw
        w1 = single_mode_frequency_limit(el) / el.bar.omega_c if el is not None else math.nan
        out.append([*key, ok_up_to, w1] + [max(r[5] for r in sel if r[3] == fw) for fw in (0.2, 0.5, 0.8)])
    return out


def score(path: Path = CHECK):
    """The warning's interpolation against the off-grid points: ``(scored, agree, missed, false,
    missed above 3 %, false below 1/3 %)`` over the points where the element slips and the
    reference's error does not straddle 1 % (tests/test_model_range.py asserts the last two are 0)."""
    counts = [0] * 6
    elements = {}
    with open(path) as fh:
        for r in csv.DictReader(fh):
            lam_L, beta_L, name = float(r["lamL"]), float(r["betaL_EA"]), r["load"]
            e, de = max(float(r["e_s"]), float(r["e_c"])), max(float(r["de_s"]), float(r["de_c"]))
            key = (lam_L, beta_L, name)
            if key not in elements:
                elements[key] = single_element(LOADS[name][1], make_bar(lam_L, beta_L), LOADS[name][0])
            el = elements[key]
            if el is None or not math.isfinite(e) or abs(e - FLOOR) <= de:
                continue
            omega, a = float(r["w"]) * el.bar.omega_c, float(r["ratio"]) * el.slip_amplitude(0.0)
            if a <= el.linear_amplitude(omega):
                continue
            warned = float(single_mode_error(el, a, omega)) > FLOOR
            truth = e > FLOOR
            counts[0] += 1
            counts[1] += warned == truth
            counts[2] += truth and not warned
            counts[3] += warned and not truth
            counts[4] += (not warned) and e - de > 3 * FLOOR
            counts[5] += warned and e + de < FLOOR / 3
    return tuple(counts)


#: The figure shows the bars of this beta L/EA (the reference bar's); the table lists all twelve.
FIGURE_BETA_L = 1.0
#: Resolution of the saved PNG.
DPI = 150
#: Short row labels of the figure.
LOAD_LABELS = {"uniform": "uniform load", "concave12": "concave load (ratio 12)"}


def draw(rows, beta_L: float = FIGURE_BETA_L):
    """The map at one ``beta_L`` (beta L/EA): a row per load, a column per lambda L; the map's error
    (colour), its 1 % contour (white), the warning's 1 % contour from ``single_mode_error`` on a
    fine grid (red dashed: it follows the map), omega_1 (red dotted), refused points grey.
    Returns the matplotlib figure."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    nl = len(LAMBDA_L)
    fig, axes = plt.subplots(len(LOADS), nl, figsize=(3.0 * nl + 1.4, 2.9 * len(LOADS) + 0.9), sharex=True,
                             sharey=True, layout="constrained", squeeze=False)
    ratios = sorted({r[4] for r in rows})
    freqs = sorted({r[3] for r in rows})
    w_fine = np.linspace(freqs[0], freqs[-1], 90)
    r_fine = np.geomspace(ratios[0], ratios[-1], 90)
    cmap = plt.get_cmap("viridis").with_extremes(bad="lightgrey")
    m = None
    for k, name in enumerate(LOADS):
        for j, lam_L in enumerate(LAMBDA_L):
            ax = axes[k, j]
            Z = np.full((len(ratios), len(freqs)), np.nan)
            for r in rows:
                if (r[0], r[1], r[2]) == (lam_L, beta_L, name):
                    Z[ratios.index(r[4]), freqs.index(r[3])] = r[5]
            refused = ~np.isfinite(Z)
            Zp = np.where(refused, 10.0, np.maximum(Z, 1e-5))
            m = ax.pcolormesh(freqs, ratios, np.ma.masked_where(refused, Zp), norm=LogNorm(1e-4, 1.0),
                              cmap=cmap, shading="nearest")
            if np.any(Zp > FLOOR) and np.any(Zp <= FLOOR):
                ax.contour(freqs, ratios, Zp, levels=[FLOOR], colors="w", linewidths=1.8)
            el = single_element(LOADS[name][1], make_bar(lam_L, beta_L), LOADS[name][0])
            if el is not None:
                a0, wc = el.slip_amplitude(0.0), el.bar.omega_c
                W = np.array([single_mode_error(el, r_fine * a0, w * wc) for w in w_fine]).T
                if np.any(W > FLOOR) and np.any(W <= FLOOR):
                    ax.contour(w_fine, r_fine, W, levels=[FLOOR], colors="r", linestyles="--", linewidths=1.2)
                w1 = single_mode_frequency_limit(el) / wc
                if w1 < freqs[-1]:
                    ax.axvline(w1, color="r", ls=":", lw=1.5)
            ax.set_yscale("log")
            if k == 0:
                ax.set_title(f"λL = {lam_L:g}")
            if k == len(LOADS) - 1:
                ax.set_xlabel("ω / ω_c")
            if j == 0:
                ax.set_ylabel(f"{LOAD_LABELS[name]}\na / a_min")
    fig.colorbar(m, ax=axes, shrink=0.8, label="error max(e_s, e_c)")
    handles = [Line2D([], [], color="w", lw=1.8, label="map: 1 % contour"),
               Line2D([], [], color="r", ls="--", lw=1.2, label="warning: 1 % contour"),
               Line2D([], [], color="r", ls=":", lw=1.5, label="ω_1 (the warning's frequency limit)"),
               Patch(facecolor="lightgrey", label="refused by the single-mode element")]
    fig.legend(handles=handles, loc="outside lower center", ncols=4, facecolor="0.55", framealpha=1.0)
    fig.suptitle(f"Single-mode error against the all-mode bar, βL/EA = {beta_L:g}")
    return fig


def figure(rows, outdir: Path = FIGURES, beta_L: float = FIGURE_BETA_L) -> Path:
    """Draw the map (:func:`draw`) to ``outdir/validity_map.png`` at ``DPI``; returns the path."""
    import matplotlib.pyplot as plt

    fig = draw(rows, beta_L)
    path = Path(outdir) / "validity_map.png"
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return path


def main(recompute: bool = False, outdir: Path = FIGURES):
    if recompute or not DATA.exists():
        rows, sec = compute()
        _, sec_check = compute_check()
        print(f"map: {len(rows)} points in {sec:.0f} s; off-grid check in {sec_check:.0f} s")
    rows = load_rows()
    figure(rows, outdir)

    def pct(e):
        return f"{e:.1%}" if math.isfinite(e) else "refused"

    table = [(lL, bL, n, f"{ok:g}", f"{w1:.3f}" if math.isfinite(w1) else "refused", pct(e2), pct(e5), pct(e8))
             for lL, bL, n, ok, w1, e2, e5, e8 in summary(rows)]
    print(markdown_table(["lambda L", "beta L/EA", "load", "map: <= 1 % up to w/w_c (grid)", "omega_1/omega_c",
                          "worst at 0.2", "worst at 0.5", "worst at 0.8"], table))
    finite = [r for r in rows if math.isfinite(r[5])]
    print(f"\n{len(rows)} map points, {len(finite)} the single-mode element evaluates; reference error below "
          f"0.1 % at {np.mean([r[6] < 0.001 for r in finite]):.1%} of them, straddling 1 % at "
          f"{sum(abs(r[5] - FLOOR) <= r[6] for r in finite)}")
    n, agree, missed, false, missed3, false3 = score()
    print(f"off-grid check: {n} slipping points scored, the warning agrees at {agree}; missed {missed} "
          f"(above 3 %: {missed3}), false {false} (below 1/3 %: {false3})")
    return rows


if __name__ == "__main__":
    import sys

    main("--recompute" in sys.argv)
