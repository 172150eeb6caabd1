"""Validation: hysteresis loops against the numerical bar
======================================================

Hysteresis loops of the single-mode analytic element (Masing loop of its loading curve)
against the full numerical solution, uniform load, at 0.01 and 0.5 omega_c (docs/validation.md).

At low frequency the two coincide; at 0.5 omega_c the numerical loop is no longer a Masing
loop: after each reversal the interior of the bar keeps slipping for a while (its inertia
carries it on), which the single-mode solution, with the whole bar in phase, cannot show.
Writes ``validation_loops.png``; returns F_c analytic and numerical per panel.
"""

from __future__ import annotations

import matplotlib.pyplot as plt

from validation_common import BAR, FIGURES, LOADS, analytic
from paper_figures import beyond_the_single_mode_range, show

from contact_models import NumericalMicroslip

CASES = ((0.01, 1.5), (0.5, 1.5), (0.01, 3.0), (0.5, 3.0))


def main(cells: int = 100, steps: int = 512, outdir=FIGURES, small: bool = False):
    if small:
        cells, steps = 30, 256
    el = analytic("uniform")
    num = NumericalMicroslip(BAR, LOADS["uniform"][0], cells=cells, steps_per_cycle=steps)
    a_min = el.slip_amplitude(0.0)
    fig, axes = plt.subplots(1, len(CASES), figsize=(15, 3.8))
    out = {}
    for ax, (wr, ratio) in zip(axes, CASES):
        w, a = wr * BAR.omega_c, ratio * a_min
        with beyond_the_single_mode_range():  # at 0.5 omega_c on purpose: where the two part
            xa, fa = el.hysteresis(a, w, n=801)
        r = num.simulate(a, w)
        xn, fn = r.loop(801)
        k = BAR.k_star * a
        ax.plot(xa / a, fa / k, "k-", lw=1.2, label="analytic (single mode, Masing)")
        ax.plot(xn / a, fn / k, "--", color="tab:red", lw=1.2, label=f"numerical ({cells} cells)")
        with beyond_the_single_mode_range():
            fs_a, fc_a = el.fourier(a, w)
        out[f"{wr:g}@{ratio:g}"] = {"Fc_analytic": float(fc_a / k), "Fc_numerical": r.f_c / k,
                                    "Fs_analytic": float(fs_a / k), "Fs_numerical": r.f_s / k}
        ax.set_title(rf"$\omega = {wr:g}\,\omega_c$, $a = {ratio:g}\,a_{{min}}$" + "\n"
                     + f"F_c: analytic {fc_a / k:.4f}, numerical {r.f_c / k:.4f}", fontsize=9)
        ax.set_xlabel(r"$x/a$")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel(r"$f/(k^* a)$")
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    outdir.mkdir(parents=True, exist_ok=True)
    path = outdir / "validation_loops.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return {"path": str(path), **out}


if __name__ == "__main__":
    show(main())
