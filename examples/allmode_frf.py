"""All-mode damper: FRF of the default blade
=========================================

FRF of the default blade with the all-mode damper (AllModeMicroslip), against the single-mode
FRF, the time integration of blade + bar, and the converged H = 1 amplitude
(``hbm.reference.amplitude.amplitude_at`` on 1024 cells at H = 63).

The default case of ``python3 -m hbm`` (``paper_figures.default_case``): blade k = 1e8 N/m, zeta = 2e-3,
F = 8 N, uniform 100 N load on the reference bar (``paper_figures.BAR_PARAMETERS``).  The time-integration numbers are the ones
stored in docs/validation.md ("The blade in time against the FRF": ``hbm.simulate_blade``,
160 cells, 1024 steps per cycle, a 345 s run), not re-run here.  Writes
docs/figures/allmode_frf.png and prints the comparison table.

.. note::
   Not run when the site is built (it takes from several seconds to minutes): the figure is the one a committed run wrote; running this script regenerates it.

.. image:: /figures/allmode_frf.png
   :alt: All-mode damper: FRF of the default blade
"""

# sphinx_gallery_thumbnail_path = "figures/allmode_frf.png"

from __future__ import annotations

import time
import warnings

import numpy as np

from paper_figures import default_case
from validation_common import FIGURES, markdown_table

from contact_models import AllModeMicroslip, ModelRangeWarning, UniformLoad
from hbm import Contact, Structure, frequency_response, response_at
from hbm.reference.amplitude import amplitude_at

#: omega (rad/s) -> (a/a_min, phase) of the time integration, docs/validation.md (stored, not re-run).
TIME_INTEGRATION = {38400.0: (1.70788, 0.6661), 38768.3: (2.04257, 1.5568), 40000.0: (1.60920, 2.5986)}


def main(cells: int = 40, harmonics: int = 15, outdir=FIGURES, figure: bool = True, low_harmonics: int = 11):
    warnings.simplefilter("ignore", ModelRangeWarning)  # the single-mode FRF is out of its range here: shown on purpose
    case = default_case()
    amin = case.element.slip_amplitude(0.0)
    b = case.blade
    structure = Structure([[b.mass]], [[b.damping]], [[b.stiffness]], force=[b.force])  # the blade as 1 DOF
    # the all-mode damper at its defaults through the multi-harmonic solver at H = 1: it uses the
    # element's exact dF/dX and dF/domega (implicit function theorem)
    fine = AllModeMicroslip(case.element.bar, UniformLoad(N=100.0), cells=cells, harmonics=harmonics)
    t0 = time.perf_counter()
    frf = frequency_response(structure, [Contact(fine, dof=0)], case.omega_range, harmonics=1)
    seconds = time.perf_counter() - t0
    # the same through the one-DOF path (the blade, its damper's omega-derivative a forward difference)
    one_dof = frequency_response(case.blade, fine, case.omega_range, harmonics=1)
    single = frequency_response(case.blade, case.element, case.omega_range)
    # the blade at H = 3 with the bar as a substructure
    coarse = AllModeMicroslip(case.element.bar, UniformLoad(N=100.0), cells=20, harmonics=7)
    t0 = time.perf_counter()
    multi = frequency_response(structure, [Contact(coarse, dof=0)], case.omega_range, harmonics=3)
    seconds_multi = time.perf_counter() - t0
    el = AllModeMicroslip(case.element.bar, UniformLoad(N=100.0), cells=cells, harmonics=low_harmonics)
    # the converged all-mode bar at the blade's H = 1 (its amplitude equation, no continuation)
    converged = AllModeMicroslip(case.element.bar, UniformLoad(N=100.0), cells=1024, harmonics=63)
    rows = []
    for w, (a_ti, ph_ti) in TIME_INTEGRATION.items():
        lo, hi = 0.5 * a_ti * amin, 1.5 * a_ti * amin
        amps = [response_at(case.blade, e, w, (lo, hi)).amplitude / amin for e in (case.element, el, fine)]
        amps.append(amplitude_at(case.blade, converged, w, amps[-1] * amin) / amin)
        rows.append((w, *amps, a_ti))
    table = markdown_table(["omega (rad/s)", "time integration a/a_min (stored)", "single-mode", "vs TI",
                            f"all-mode H = {low_harmonics}", "vs TI", f"all-mode H = {harmonics}", "vs TI",
                            "converged H = 1", "vs TI"],
                           [(f"{w:g}", f"{ti:.5f}", f"{a:.5f}", f"{a / ti - 1:+.2%}", f"{b:.5f}", f"{b / ti - 1:+.2%}",
                             f"{c:.5f}", f"{c / ti - 1:+.2%}", f"{d:.5f}", f"{d / ti - 1:+.2%}")
                            for w, a, b, c, d, ti in rows])
    pk = frf.peak() if callable(getattr(frf, "peak", None)) else None
    print(f"all-mode FRF (multi-harmonic solver at H = 1): {frf.omega.size} points in {seconds:.1f} s ({cells} cells, "
          f"H = {harmonics}), success {frf.success}; peak {np.max(frf.amplitude) / amin:.5f} a_min"
          + (f" (refined {pk.amplitude / amin:.5f} a_min at {pk.omega:.6g} rad/s)" if pk is not None else "")
          + f"; single-mode peak {single.peak().amplitude / amin:.5f} a_min at {single.peak().omega:.6g} rad/s")
    print(f"the same through the one-DOF path (forward-difference omega-derivative): {one_dof.omega.size} points, "
          f"success {one_dof.success}, up to {one_dof.omega.max():.6g} rad/s; "
          f"peak {np.max(one_dof.amplitude) / amin:.5f} a_min")
    c = multi.coefficients(0)
    i = int(np.argmax(multi.amplitude))
    print(f"blade at H = 3 with the all-mode bar (20 cells, H = 7) as a substructure: {multi.omega.size} points in "
          f"{seconds_multi:.1f} s, success {multi.success}; peak {multi.amplitude[i] / amin:.5f} a_min at "
          f"{multi.omega[i]:.6g} rad/s; |x_3|/|x_1| there {abs(c[i, 3]) / abs(c[i, 1]):.2e}")
    print(table)
    if figure:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(7, 4.5))
        ax.plot(single.omega, single.amplitude / amin, label="single-mode (TwoRegionMicroslip)")
        ax.plot(frf.omega, frf.amplitude / amin, "--", label=f"all-mode (AllModeMicroslip, {cells} cells, H={harmonics})")
        ax.plot(multi.omega, multi.amplitude / amin, ":", label="all-mode, blade at H = 3 (20 cells, H = 7)")
        ax.plot(list(TIME_INTEGRATION), [v[0] for v in TIME_INTEGRATION.values()], "ko",
                label="time integration (simulate_blade, stored)")
        ax.set_xlabel("omega (rad/s)")
        ax.set_ylabel("a / a_min")
        ax.set_xlim(37000, 41500)
        ax.legend()
        fig.tight_layout()
        fig.savefig(outdir / "allmode_frf.png", dpi=110)
        plt.close(fig)
    return frf, single, rows, seconds, multi


if __name__ == "__main__":
    main()
