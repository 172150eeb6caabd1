"""Design chart from the nonlinear mode
=====================================

The default blade's design chart (resonant amplitude against the damper's normal load N) from
its nonlinear mode, in one run: ``hbm.damper_optimum`` follows the resonance peak of single
nonlinear mode theory by continuation in the load (parametrised as log10 N, 10 N to 3000 N) and
locates the load where the peak is smallest.  The dots are the peaks of full FRFs
(``hbm.frequency_response``) at a few loads: for one DOF at H = 1 the mode's peak is the FRF's
(the forced balance projected on the mode is the forced balance itself).

Run ``python3 examples/design_chart_from_modes.py``; writes
``docs/figures/design_chart_from_modes.png``.  The optimum alone from a scene file (30 N to 90 N):
``python3 -m hbm run examples/scenes/damper_optimum.toml`` (an ``[optimum]`` table, ``docs/scenes.md``).

.. note::
   Not run when the site is built: the figure is the one a committed run wrote; running this
   script regenerates it.

.. image:: /figures/design_chart_from_modes.png
   :alt: Resonant amplitude against normal load from the nonlinear mode, with FRF peaks
"""

# sphinx_gallery_thumbnail_path = "figures/design_chart_from_modes.png"

from __future__ import annotations

import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from contact_models import TwoRegionMicroslip, UniformLoad  # noqa: E402
from hbm import Contact, damper_optimum, frequency_response  # noqa: E402
from paper_figures import default_case  # noqa: E402

DEFAULT_OUTDIR = Path(__file__).resolve().parent.parent / "docs" / "figures"
#: FRF checks (N): a few loads across the chart.
CHECK_LOADS = (10.0, 30.0, 100.0, 300.0, 1000.0, 3000.0)


def main(outdir: Path | str = DEFAULT_OUTDIR, small: bool = False) -> dict:
    """Chart and optimum; returns ``{"path", "optimum", "seconds", "checks"}``."""
    case = default_case()
    bar, sm = case.element.bar, np.sqrt(case.blade.mass)
    t = time.perf_counter()
    opt = damper_optimum(case.blade.as_structure(),
                         lambda p: [Contact(TwoRegionMicroslip(bar, UniformLoad(N=10.0 ** p)), dof=0)],
                         (1.0, 3.5), amplitude_range=(1e-8 * sm, 1e-4 * sm))
    seconds = time.perf_counter() - t
    loads = (30.0, 300.0) if small else CHECK_LOADS
    checks = [(N, frequency_response(case.blade, TwoRegionMicroslip(bar, UniformLoad(N=N)),
                                     omega_range=case.omega_range).peak().amplitude) for N in loads]
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.loglog(10.0 ** opt.parameters, opt.peaks * 1e6, "k-", label="peak from the nonlinear mode")
    ax.loglog([c[0] for c in checks], [c[1] * 1e6 for c in checks], "o", color="tab:red", label="peak of the FRF")
    ax.plot(10.0 ** opt.parameter, opt.peak.amplitude * 1e6, "*", ms=12, color="tab:blue",
            label=f"optimum N = {10.0 ** opt.parameter:.2f} N")
    ax.set_xlabel("normal load N (N)")
    ax.set_ylabel(r"resonant amplitude ($\mu$m)")
    ax.set_title(f"Design chart from the mode ({seconds:.1f} s, {opt.nsteps} steps)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    path = outdir / "design_chart_from_modes.png"
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return {"path": path, "optimum": opt, "optimal_load": 10.0 ** opt.parameter, "seconds": seconds,
            "checks": checks}


if __name__ == "__main__":
    out = main()
    opt = out["optimum"]
    print(f"optimum N = {out['optimal_load']:.6f} N, peak {opt.peak.amplitude:.8e} m at {opt.peak.omega:.6f} rad/s "
          f"({out['seconds']:.2f} s); wrote {out['path']}")
    for N, a in out["checks"]:
        print(f"FRF peak at N = {N:g}: {a:.6e} m; mode: {np.interp(np.log10(N), opt.parameters, opt.peaks):.6e} m")
