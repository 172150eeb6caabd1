"""The main job: a blade's FRF with a microslip damper
=====================================================

What ``python3 -m hbm`` computes, written with the public API: a blade (one mode) with the
two-region microslip bar of Cigeroglu, Lu & Menq (2006) as its damper, traced through resonance;
the peak solved again with the bar with every mode (``hbm.allmode_peak``), because the single-mode
bar is about 1.5 % off it there; and, for comparison, the macroslip damper that matches the
microslip bar: ``Macroslip(k*, mu N)``, a Jenkins element with the bar's stuck stiffness and its
gross-slip force.

The blade is the default case of the command line: the reference bar under a uniform normal load
of 100 N on a blade of stiffness 1e8 N/m whose stuck resonance is 0.3 omega_c, damping ratio
2e-3, force 8 N. Writes docs/figures/main_job_frf.png (the figure of the landing page).

The curves are traced at ``tol = 0.15``: the single-mode bar's model error, estimated from the
validity map, is up to 10 % just past slip on the lower flank and about 2 % at the peak, so the
curve is drawn at the accuracy it has and says so (``frf.error_estimate``); the peak is then
solved with every mode of the bar to ``tol = 1e-3``, the curve's other error sources at its
maximum added (the blade's own higher harmonics, the peak's location), as the main job does.
"""

from __future__ import annotations

import math
from pathlib import Path

from contact_models import Bar, Macroslip, TwoRegionMicroslip, UniformLoad
from hbm import Blade, allmode_peak, frequency_response
from paper_figures import DEFAULT_OUTDIR as FIGURES  # docs/figures (no __file__ here: the gallery runs this)

#: The tolerance of the traced curves (the single-mode bar's model error is within it) and of the
#: all-mode peak.
CURVE_TOL, PEAK_TOL = 0.15, 1e-3


def default_blade(bar: Bar, damper: TwoRegionMicroslip) -> tuple[Blade, tuple[float, float]]:
    """The default case's blade and sweep: stuck resonance ``sqrt((k + k*)/m) = 0.3 omega_c``."""
    w_stuck = 0.3 * bar.omega_c
    k = 1.0e8
    m = (k + damper.stuck_stiffness(0.0)) / w_stuck**2
    blade = Blade.from_modal(frequency=math.sqrt(k / m), damping_ratio=2e-3, mass=m, force=8.0)
    return blade, (0.8 * w_stuck, 1.1 * w_stuck)


def main(outdir=FIGURES, figure: bool = True) -> dict:
    bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    load = UniformLoad(N=100.0)
    micro = TwoRegionMicroslip(bar, load)
    # the macroslip match: the same stuck stiffness k*, sliding at the bar's gross-slip force mu N
    macro = Macroslip(stiffness=micro.stuck_stiffness(0.0), slip_force=bar.mu * load.N)
    blade, omega_range = default_blade(bar, micro)

    frf = frequency_response(blade, micro, omega_range=omega_range, tol=CURVE_TOL)
    jen = frequency_response(blade, macro, omega_range=omega_range, tol=CURVE_TOL)
    peak, jen_peak = frf.peak(), jen.peak()
    i = int(frf.amplitude.argmax())
    other = sum(float(v[i]) for name, v in frf.error_sources.items() if name != "model")
    best = allmode_peak(blade, bar, load, peak.omega, peak.amplitude, PEAK_TOL, other)

    print(f"microslip (single-mode bar): peak {peak.omega:.1f} rad/s, {peak.amplitude:.4e} m")
    print(f"microslip (bar with every mode): peak {best.omega:.1f} rad/s, {best.amplitude:.4e} m, "
          f"estimated error {best.error:.1e}")
    print(f"macroslip match Macroslip(k*, mu N): peak {jen_peak.omega:.1f} rad/s, {jen_peak.amplitude:.4e} m")
    out = {"peak": (peak.omega, peak.amplitude), "allmode_peak": (best.omega, best.amplitude),
           "allmode_error": best.error, "macroslip_peak": (jen_peak.omega, jen_peak.amplitude)}
    if figure:
        out["path"] = draw(frf, jen, best, micro.slip_amplitude(0.0), Path(outdir))
    return out


def draw(frf, jen, best, a_min: float, outdir: Path) -> Path:
    """The two FRFs in micrometres, the slip amplitude and the all-mode peak; written as a PNG."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.0, 4.2), layout="constrained")
    ax = fig.add_subplot()
    ax.plot(frf.omega, 1e6 * frf.amplitude, color="C0", label="microslip bar (TwoRegionMicroslip)")
    ax.plot(jen.omega, 1e6 * jen.amplitude, color="C1", ls="--", label="macroslip match Macroslip(k*, mu N)")
    ax.axhline(1e6 * a_min, color="0.5", ls=":", lw=1, label="slip begins (a_min)")
    ax.plot([best.omega], [1e6 * best.amplitude], "o", color="C3", ms=6,
            label=f"peak with every mode of the bar (error {best.error:.0e})")
    ax.set_xlabel("excitation frequency (rad/s)")
    ax.set_ylabel("blade amplitude (µm)")
    ax.set_title("Blade with a friction damper: forced response")
    ax.legend(fontsize=8, loc="upper left")
    outdir.mkdir(parents=True, exist_ok=True)
    path = outdir / "main_job_frf.png"
    fig.savefig(path, dpi=150)
    return path


if __name__ == "__main__":
    main()
