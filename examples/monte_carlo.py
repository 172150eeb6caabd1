"""Monte Carlo of the resonant amplitude
=====================================

Monte Carlo of the resonant amplitude under uncertain friction coefficient and normal load.

The scene ``examples/scenes/monte_carlo.toml``: 1000 samples (seed 2006) of the friction
coefficient mu (uniform 0.2 .. 0.4) and the normal load N (lognormal, median 60 N, sigma 0.3)
of the two-region microslip damper on the blade of the default case; each run the FRF's peak.
Cheap on purpose: the damper is quasi-static (``effects.inertia = "off"``) and the accuracy the
"fast" preset: about 0.06 s of one core per run, 1000 runs in about 30 s on two quiet cores.
The figure (``hbm.study.figures``) shows the histogram of the peak amplitude with its 5th, 50th
and 95th percentiles, and the peak against mu coloured by N.

Run ``python examples/monte_carlo.py``; writes ``docs/figures/monte_carlo.png``.

.. note::
   Not run when the site is built (it takes from several seconds to minutes): the figure is the one a committed run wrote; running this script regenerates it.

.. image:: /figures/monte_carlo.png
   :alt: Monte Carlo of the resonant amplitude
"""

from __future__ import annotations

from pathlib import Path

from hbm.study import Study, run_study
from hbm.study.figures import figure, percentiles

HERE = Path(__file__).resolve().parent
SCENE = HERE / "scenes" / "monte_carlo.toml"
DEFAULT_OUTDIR = HERE.parent / "docs" / "figures"


def main(outdir=DEFAULT_OUTDIR, small=False, executor=None, workers=None, scheduler=None, folder=None, n=None):
    """Run the study and draw the histogram; returns ``{"path", "result", "percentiles"}``
    (``percentiles``: {5, 50, 95} -> peak amplitude in m).  ``small``: 12 samples, serially."""
    overrides = {"study.n": n if n is not None else (12 if small else 1000)}
    study = Study.from_scene(SCENE, overrides=overrides)
    outdir = Path(outdir)
    folder = Path(folder) if folder is not None else outdir / "monte_carlo_study"
    result = run_study(study, folder, executor=executor or ("serial" if small else None), workers=workers,
                       scheduler=scheduler, formats=("csv", "json"))
    outdir.mkdir(parents=True, exist_ok=True)
    path = figure(result, outdir / "monte_carlo.png", title=f"{study.title} ({len(study.points)} samples)",
                  samples=study.design["samples"])
    return {"path": path, "result": result, "study": study,
            "percentiles": percentiles(result.column("peak_amplitude_m"))}


if __name__ == "__main__":
    out = main(folder="monte_carlo")
    r = out["result"]
    times = r.column("time_s")
    print(f"{len(r.records)} runs: {r.computed} computed, {r.reused} found in monte_carlo/, {r.elapsed:.1f} s "
          f"({r.summary['executor']}); {times.mean():.3f} s of a worker per run; "
          f"{sum(not x['success'] for x in r.records)} failed")
    for q, v in out["percentiles"].items():
        print(f"{q:g}th percentile of the peak amplitude: {v:.4e} m")
    print(f"wrote {out['path']}")
