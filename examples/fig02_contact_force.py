"""Fig. 2: contact force along the stuck bar
=========================================

Fig. 2 of Cigeroglu et al. (2006): the contact elastic force k u(x) along the fully stuck bar.

A harmonic tip force drives the stuck bar (Eq. 1-2); the contact force is normalised by its
value at the excited end x = L, so the curves show its shape.  The paper's 1, 1500, 5000 and
10 000 Hz refer to a bar whose omega_c it does not give, so fractions 0.01, 0.2, 0.5, 0.8
omega_c of our bar are used, with the paper's line styles.  The thin grey curve is the first
mode of the stuck bar (free at x = L), u(x)/u(L) at omega_c, which the paper says the force
distribution resembles.
"""

from __future__ import annotations

import numpy as np

from paper_figures import DEFAULT_OUTDIR, new_figure, save, setup, show

#: Frequencies (fractions of omega_c) and line styles: the paper's 1, 1500, 5000, 10000 Hz
#: curves are solid, dotted, dash-dot and dashed.
RATIOS = (0.01, 0.2, 0.5, 0.8)
STYLES = {0.01: "-", 0.2: ":", 0.5: "-.", 0.8: "--"}
#: Tip force amplitude (N); it cancels in the normalised force.
TIP_FORCE = 1.0


def main(outdir=DEFAULT_OUTDIR, small=False):
    """Write fig02.png; returns k u(0)/k u(L) per frequency and for the mode shape."""
    s = setup()
    bar = s.bar
    x = np.linspace(0.0, bar.L, 21 if small else 201)
    fig, ax = new_figure(2, "contact elastic force along the stuck bar, tip force input")
    ax.plot(x / bar.L, bar.stuck_shape(x, s.omega_c), color="0.6", lw=3, alpha=0.5,
            label=r"first mode shape ($\omega = \omega_c$)")
    end_ratio = {}
    for r in RATIOS:
        w = s.omega(r)
        force = bar.contact_force(x, w, tip_force=TIP_FORCE)
        at_L = bar.contact_force(bar.L, w, tip_force=TIP_FORCE)
        ax.plot(x / bar.L, force / at_L, STYLES[r], color="k",
                label=rf"$\omega = {r:g}\,\omega_c$ ({w / (2 * np.pi):.0f} Hz)")
        end_ratio[r] = float(force[0] / at_L)
    ax.set_xlabel(r"$x/L$")
    ax.set_ylabel(r"$k\,u(x)\,/\,k\,u(L)$")
    ax.set_xlim(0.0, 1.0)
    ax.legend(fontsize=8, loc="upper left")
    path = save(fig, outdir, 2)
    return {"path": str(path), "force_ratio_x0": end_ratio,
            "mode_shape_x0": float(bar.stuck_shape(0.0, s.omega_c))}


if __name__ == "__main__":
    show(main())
