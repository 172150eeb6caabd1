"""Fig. 19: stuck length, analytic against numerical
=================================================

Fig. 19 of Cigeroglu et al. (2006): the stuck length L1/L over one steady cycle, analytic
(single-mode, line) against the full numerical solution (``NumericalMicroslip``, points).

Left: the paper's figure, two-region (uniform) interface at low frequency (0.01 omega_c),
a = 2 a_min.  Middle: the three-region (ratio-12 concave) interface, L1 and L2, a = 3 a_min.
Right: the two-region interface at 0.5 omega_c, where the single-mode solution departs.
Writes ``validation_fig19.png``; returns the largest ``|L1_numerical - L1_analytic| / L`` per panel
(over the part of the cycle where the analytic slip zone is longer than two cells).
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from validation_common import BAR, FIGURES, LOADS, analytic
from paper_figures import show

from contact_models import NumericalMicroslip

PANELS = (("uniform", 0.01, 2.0), ("concave12", 0.01, 3.0), ("uniform", 0.5, 2.0))


def boundaries_over_cycle(el, a, w, theta):
    """Analytic (L1, L2) at the numerical run's theta (Masing rule), L where nothing slips."""
    th = np.where(theta <= 1.5 * np.pi, theta, theta - 2.0 * np.pi)
    x = a * np.sin(th)
    s = np.where(th <= 0.5 * np.pi, 0.5 * (a + x), 0.5 * (a - x))
    L1, L2 = el.boundaries(s, w)
    slipping = s > el.slip_amplitude(w)
    return np.where(slipping, L1, BAR.L), np.where(slipping, L2, BAR.L), slipping


def main(cells: int = 100, steps: int = 512, outdir=FIGURES, every: int = 8, small: bool = False):
    """Write validation_fig19.png; ``small``: 30 cells, 256 steps per cycle."""
    if small:
        cells, steps, every = 30, 256, 4
    fig, axes = plt.subplots(1, 3, figsize=(14, 4), sharey=True)
    out = {}
    L = BAR.L
    for ax, (name, wr, ratio) in zip(axes, PANELS):
        el = analytic(name)
        w = wr * BAR.omega_c
        a = ratio * el.slip_amplitude(0.0)
        r = NumericalMicroslip(BAR, LOADS[name][0], cells=cells, steps_per_cycle=steps).simulate(a, w)
        fine = np.linspace(0.0, 2.0 * np.pi, 1441)[:-1]
        L1a, L2a, _ = boundaries_over_cycle(el, a, w, fine)
        ax.plot(fine, L1a / L, "k-", lw=1.2, label=r"$L_1/L$ analytic")
        L1n, L2n, slipping = boundaries_over_cycle(el, a, w, r.theta)
        ax.plot(r.theta[::every], r.L1[::every] / L, "o", mfc="none", color="k", ms=4, label=r"$L_1/L$ numerical")
        zone = slipping & (L2n - L1n > 2.0 * L / cells)
        err = {"L1": float(np.max(np.abs(r.L1 - L1n)[zone]) / L)}
        if name != "uniform":
            ax.plot(fine, L2a / L, "-", color="tab:red", lw=1.2, label=r"$L_2/L$ analytic")
            ax.plot(r.theta[::every], r.L2[::every] / L, "s", mfc="none", color="tab:red", ms=4, label=r"$L_2/L$ numerical")
            err["L2"] = float(np.max(np.abs(r.L2 - L2n)[zone]) / L)
        out[f"{name}@{wr:g}"] = err
        err["min_L1_analytic"] = float(L1a.min() / L)
        err["min_L1_numerical"] = float(r.L1.min() / L)
        ax.set_title(rf"{name}, $\omega = {wr:g}\,\omega_c$, $a = {ratio:g}\,a_{{min}}$" + "\n"
                     + f"min L1/L: analytic {err['min_L1_analytic']:.3f}, numerical {err['min_L1_numerical']:.3f}",
                     fontsize=9)
        ax.set_xticks(np.arange(5) * 0.5 * np.pi, ["0", r"$\pi/2$", r"$\pi$", r"$3\pi/2$", r"$2\pi$"])
        ax.set_xlabel(r"$\theta$  ($x = a\sin\theta$)")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("stuck-region boundary / L")
    axes[1].legend(fontsize=7, loc="lower right")
    axes[0].legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    outdir.mkdir(parents=True, exist_ok=True)
    path = outdir / "validation_fig19.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return {"path": str(path), **out}


if __name__ == "__main__":
    show(main())
