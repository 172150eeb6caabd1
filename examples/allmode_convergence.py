"""All-mode bar: convergence in cells, harmonics and samples
=========================================================

Convergence of AllModeMicroslip in cells, harmonics H and samples n_t, with observed rates.

At 0.5 omega_c (the reference bar, uniform and concave12 loads, a/a_min in {1.5, 3, 10, 30}):
each knob is varied with the others at a fine setting, and the error is
``max |F(level) - F(finest)|`` over the amplitudes, in units of k* a.  Prints markdown tables
(docs/validation.md) and writes docs/figures/allmode_convergence.png.

.. note::
   Not run when the site is built (it takes from several seconds to minutes): the figure is the one a committed run wrote; running this script regenerates it.

.. image:: /figures/allmode_convergence.png
   :alt: All-mode bar: convergence in cells, harmonics and samples
"""

# sphinx_gallery_thumbnail_path = "figures/allmode_convergence.png"

from __future__ import annotations

import math
import time

import numpy as np

from validation_common import BAR, FIGURES, LOADS, markdown_table

from contact_models import AllModeMicroslip

RATIOS = (1.5, 3.0, 10.0, 30.0)
#: one physical amplitude per level: a/a_min with a_min of the (continuous) single-mode element
A_MIN = {id(load): cls(BAR, load).slip_amplitude(0.0) for load, cls in LOADS.values()}


def values(load, cells, H, n_t=None, w=0.5):
    el = AllModeMicroslip(BAR, load, cells=cells, harmonics=H, n_t=n_t)
    a = np.array(RATIOS) * A_MIN[id(load)]
    t0 = time.perf_counter()
    fs, fc = el.fourier(a, w * BAR.omega_c)
    ms = 1e3 * (time.perf_counter() - t0) / a.size
    k = BAR.k_star * a
    return np.concatenate([fs / k, fc / k]), ms


def study(cells_levels=(10, 20, 40, 80, 160), H_levels=(3, 5, 7, 11, 15, 23), nt_levels=(32, 64, 128, 256),
          fine_cells=320, fine_H=31, w=0.5):
    out = {}
    for name in ("uniform", "concave12"):
        load = LOADS[name][0]
        ref, _ = values(load, fine_cells, fine_H, w=w)
        rows = []
        for c in cells_levels:
            v, ms = values(load, c, fine_H, w=w)
            rows.append(("cells", c, float(np.max(np.abs(v - ref))), ms))
        ref_h, _ = values(load, 80, 47, w=w)
        for H in H_levels:
            v, ms = values(load, 80, H, w=w)
            rows.append(("H", H, float(np.max(np.abs(v - ref_h))), ms))
        ref_t, _ = values(load, 80, 15, n_t=512, w=w)
        for nt in nt_levels:
            v, ms = values(load, 80, 15, n_t=nt, w=w)
            rows.append(("n_t", nt, float(np.max(np.abs(v - ref_t))), ms))
        out[name] = rows
    return out


def rates(rows, knob):
    sel = [(lv, e) for k, lv, e, _ in rows if k == knob]
    return [math.log(e0 / e1) / math.log(l1 / l0) if e1 > 0 and e0 > 0 else float("nan")
            for (l0, e0), (l1, e1) in zip(sel, sel[1:])]


def main(outdir=FIGURES, **kw):
    import matplotlib.pyplot as plt

    res = study(**kw)
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.6))
    for name, rows in res.items():
        table = []
        for knob, ax in zip(("cells", "H", "n_t"), axes):
            sel = [(lv, e, ms) for k, lv, e, ms in rows if k == knob]
            r = rates(rows, knob)
            for i, (lv, e, ms) in enumerate(sel):
                table.append((knob, lv, f"{e:.2e}", "" if i == 0 else f"{r[i - 1]:.2f}", f"{ms:.1f}"))
            ax.loglog([s[0] for s in sel], [max(s[1], 1e-16) for s in sel], "o-", label=name)
            ax.set_xlabel(knob)
        print(f"\n{name} (0.5 omega_c; error in k* a; rate = -d log(error)/d log(level); ms per amplitude point)\n")
        print(markdown_table(["knob", "level", "max error F_s, F_c", "rate", "ms/point"], table))
    axes[0].set_ylabel("max |dF| (k* a)")
    axes[0].legend()
    fig.suptitle("AllModeMicroslip convergence at 0.5 omega_c")
    fig.tight_layout()
    fig.savefig(outdir / "allmode_convergence.png", dpi=110)
    plt.close(fig)
    return res


if __name__ == "__main__":
    main()
