"""Monte Carlo of the resonant amplitude
=====================================

Monte Carlo of the resonant amplitude under uncertain friction coefficient and normal load.

The scene ``examples/scenes/monte_carlo.toml``: 1000 samples (seed 2006) of the friction
coefficient mu (uniform 0.2 .. 0.4) and the normal load N (lognormal, median 60 N, sigma 0.3)
of the two-region microslip damper on the blade of the default case; each run the FRF's peak.
Cheap on purpose: the damper is quasi-static (``effects.inertia = "off"``) and the accuracy the
"fast" preset, about 0.08 s of CPU per run; every run warns that the inertia left out moves this
blade's resonance by about 1 % (its peak by 3 to 6 %; ``docs/studies.md``).
The figure (drawn here by ``figure()``) shows the histogram of the peak amplitude in um with its
5th, 50th and 95th percentiles, and the peak against mu coloured by N (in N).

Run ``python3 examples/monte_carlo.py``; writes ``docs/figures/monte_carlo.png``.

.. note::
   Not run when the site is built (it takes from several seconds to minutes): the figure is the one a committed run wrote; running this script regenerates it.

.. image:: /figures/monte_carlo.png
   :alt: Monte Carlo of the resonant amplitude
"""

# sphinx_gallery_thumbnail_path = "figures/monte_carlo.png"

from __future__ import annotations

from pathlib import Path

import numpy as np

from hbm.study import Study, run_study
from paper_figures import display_path

#: The percentiles the figure marks.
PERCENTILES = (5.0, 50.0, 95.0)


def percentiles(values) -> dict:
    """``{q: value}`` of the finite ``values`` at ``PERCENTILES`` (numpy's linear interpolation)."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    return {q: float(np.percentile(v, q)) for q in PERCENTILES}


HERE = Path(__file__).resolve().parent
SCENE = HERE / "scenes" / "monte_carlo.toml"
DEFAULT_OUTDIR = HERE.parent / "docs" / "figures"
#: Resolution of the saved PNG (the site shows it at about its width in pixels / 1.5).
DPI = 150
#: Amplitudes are drawn in micrometres: m -> um.
UM = 1e6


def draw(result, title: str = ""):
    """The figure of a Monte Carlo ``result`` (a :class:`hbm.study.StudyResult` over ``damper.mu``
    and ``damper.load.N``): left the histogram of the peak amplitude (um) with its 5th, 50th and
    95th percentiles, right the peak against mu coloured by N.  Returns the matplotlib figure."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    recs = [r for r in result.records if r is not None and r["success"] and r["peak_amplitude_m"] is not None]
    peaks = [UM * r["peak_amplitude_m"] for r in recs]
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10.0, 4.2), layout="constrained")
    ax.hist(peaks, bins=min(60, max(10, len(peaks) // 20)), color="0.7", edgecolor="0.4")
    for (q, v), style in zip(percentiles(peaks).items(), (":", "-", "--")):
        ax.axvline(v, color="C3", ls=style, label=f"{q:g}th percentile: {v:.2f} µm")
    ax.set_xlabel("peak amplitude (µm)")
    ax.set_ylabel("runs")
    ax.legend(fontsize=8)
    sc = bx.scatter([r["params"]["damper.mu"] for r in recs], peaks, s=5,
                    c=[r["params"]["damper.load.N"] for r in recs], cmap="viridis")
    fig.colorbar(sc, ax=bx).set_label("normal load N (N)")
    bx.set_xlabel("friction coefficient mu")
    bx.set_ylabel("peak amplitude (µm)")
    for axis in (ax.xaxis, bx.yaxis):  # plain numbers, no "1e-6" or offset above the axis
        axis.get_major_formatter().set_useOffset(False)
    fig.suptitle(title or "Monte Carlo", fontsize=10)
    return fig


def figure(result, path, title: str = "") -> Path:
    """Draw ``result`` (:func:`draw`) to ``path`` at ``DPI``; returns the path."""
    import matplotlib.pyplot as plt

    fig = draw(result, title)
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return Path(path)


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
    path = figure(result, outdir / "monte_carlo.png", title=f"Monte Carlo of the peak amplitude ({len(study.points)} samples)")
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
        print(f"{q:g}th percentile of the peak amplitude: {v * UM:.3f} um")
    print(f"wrote {display_path(out['path'])}")
