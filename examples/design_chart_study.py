"""The design chart as a parameter study
=====================================

The damper design chart as a parameter study (``hbm.study``, ``docs/studies.md``).

The same chart as ``examples/design_chart.py`` (resonant amplitude against normal load for the
microslip bar, its fitted point contact and the macroslip contact, the optimum load of each
starred), computed from the scene ``examples/scenes/design_chart_study.toml``: its
``[study.grid]`` makes one run per model and load (57 runs), run on every core by default
(``executor="dask"`` or a ``scheduler`` address for a Dask cluster).  The runs are written to
``design_chart_study/`` as they finish; a rerun computes only what is missing.

Run ``python3 examples/design_chart_study.py``; writes ``docs/figures/design_chart_study.png``.

.. note::
   Not run when the site is built (it takes from several seconds to minutes): the figure is the one a committed run wrote; running this script regenerates it.

.. image:: /figures/design_chart_study.png
   :alt: The design chart as a parameter study
"""

# sphinx_gallery_thumbnail_path = "figures/design_chart_study.png"

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from design_chart import optimum  # noqa: E402  (the parabola through the best grid points)

from hbm.study import Study, run_study  # noqa: E402
from paper_figures import display_path  # noqa: E402

HERE = Path(__file__).resolve().parent
SCENE = HERE / "scenes" / "design_chart_study.toml"
DEFAULT_OUTDIR = HERE.parent / "docs" / "figures"
#: Loads of the small (test) setting.
SMALL_LOADS = [30.0, 100.0, 1000.0]
#: Labels and styles of the scene's models.
MODELS = {"two-region": ("microslip", dict(color="k", ls="-", marker="o")),
          "point-contact": ("point contact", dict(color="tab:red", ls="--", marker="s")),
          "macroslip": ("macroslip", dict(color="tab:blue", ls="-.", marker="^"))}


def main(outdir=DEFAULT_OUTDIR, small=False, executor=None, workers=None, scheduler=None, folder=None):
    """Run the study and draw the chart; returns ``{"path", "result", "loads", "peaks", "optimum"}``
    (``peaks``: model -> resonant amplitudes (m) over ``loads``)."""
    overrides = {}
    if small:
        overrides = {"study.grid": {"damper.model": list(MODELS), "damper.load.N": SMALL_LOADS},
                     "sweep.max_step": 0.1}
    study = Study.from_scene(SCENE, overrides=overrides)
    outdir = Path(outdir)
    folder = Path(folder) if folder is not None else outdir / "design_chart_study"
    result = run_study(study, folder, executor=executor, workers=workers, scheduler=scheduler,
                       formats=("csv", "json"))
    if not result.success:
        raise RuntimeError(result.message)
    rows = result.rows
    loads = np.array(sorted({r["damper.load.N"] for r in rows}))
    by = {(r["damper.model"], r["damper.load.N"]): r["peak_amplitude_m"] for r in rows}
    peaks = {m: np.array([by[m, N] for N in loads]) for m in MODELS}
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    best = {}
    for m, (label, style) in MODELS.items():
        best[m] = optimum(loads, peaks[m])
        ax.loglog(loads, peaks[m] * 1e6, label=f"{label}: optimum {best[m][0]:.3g} N", ms=3, **style)
        ax.plot(best[m][0], best[m][1] * 1e6, "*", ms=12, color=style["color"])
    ax.set_xlabel("normal load N (N)")
    ax.set_ylabel(r"resonant amplitude ($\mu$m)")
    ax.set_title(f"Design chart as a study: {len(rows)} runs, {result.summary['executor']} "
                 f"(stars: optimum load)", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    outdir.mkdir(parents=True, exist_ok=True)
    path = outdir / "design_chart_study.png"
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return {"path": path, "result": result, "loads": loads, "peaks": peaks, "optimum": best}


if __name__ == "__main__":
    out = main(folder="design_chart_study")
    r = out["result"]
    print(f"{len(r.records)} runs: {r.computed} computed, {r.reused} found in design_chart_study/, "
          f"{r.elapsed:.1f} s ({r.summary['executor']})")
    for m, (N, a) in out["optimum"].items():
        print(f"optimum {MODELS[m][0]}: N = {N:.4g} N, resonant amplitude {a:.4e} m")
    print(f"wrote {display_path(out['path'])}")
