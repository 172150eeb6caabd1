"""Fig. 10: damping coefficient F_c, two regions
=============================================

Fig. 10 of Cigeroglu et al. (2006): normalised damping F_c = f_c/(k* a) of the two-region
interface (uniform load) against a/a_min, at 0.01, 0.2, 0.3 and 0.5 omega_c.

F_c is zero until slip starts at a_min (dotted vertical), rises to a maximum near gross slip
and then falls like 1/a.  The thick grey curve is the large-amplitude limit at omega -> 0 from
closed-form statics of the sliding bar, 4 F0/(pi k* a) with F0 = 22.5 N.
"""

from __future__ import annotations

import numpy as np

from paper_figures import DEFAULT_OUTDIR, FREQUENCY_RATIOS, plot_fourier_figure, setup, show, static_gross_slip


def main(outdir=DEFAULT_OUTDIR, small=False):
    """Write fig10.png; returns F_c below a_min, at 1.5 a_min, its peak, and the ratio of F_c at
    100 a_min (0.01 omega_c) to the static gross-slip limit."""
    s = setup()
    s, a_over, curves, path = plot_fourier_figure(10, s.two, "c", r"$F_c$, two-region interface", outdir, small)
    i15 = int(np.flatnonzero(a_over == 1.5)[0])
    _, F0 = static_gross_slip(s.bar, s.two.load)
    limit = 4.0 * F0 / (np.pi * s.k_star * a_over[-1] * s.a_min)
    return {
        "path": str(path),
        "max_F_c_below_a_min": float(max(np.abs(curves[r][1][a_over <= 1.0]).max() for r in FREQUENCY_RATIOS)),
        "F_c_at_1.5": {r: float(curves[r][1][i15]) for r in FREQUENCY_RATIOS},
        "peak_F_c": {r: float(curves[r][1].max()) for r in FREQUENCY_RATIOS},
        "F_c_at_100_over_static_limit": float(curves[0.01][1][-1] / limit),
    }


if __name__ == "__main__":
    show(main())
