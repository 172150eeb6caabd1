"""Fig. 9: stiffness coefficient F_s, two regions
==============================================

Fig. 9 of Cigeroglu et al. (2006): normalised stiffness F_s = f_s/(k* a) of the two-region
interface (uniform load) against a/a_min, at 0.01, 0.2, 0.3 and 0.5 omega_c.

One vectorised ``fourier`` call per curve.  Below a_min (dotted vertical) F_s is the stuck
value K(omega)/k*; past gross slip it tends to the sliding bar's stiffness.  The thick grey
line is that limit at omega -> 0 from closed-form statics, K_slip/k* = 0.5.
"""

from __future__ import annotations

import numpy as np

from paper_figures import DEFAULT_OUTDIR, FREQUENCY_RATIOS, plot_fourier_figure, setup, show


def main(outdir=DEFAULT_OUTDIR, small=False):
    """Write fig09.png; returns F_s at a/a_min = 1, 1.5 and 100 per frequency."""
    s = setup()
    s, a_over, curves, path = plot_fourier_figure(9, s.two, "s", r"$F_s$, two-region interface", outdir, small)
    pick = {v: int(np.flatnonzero(a_over == v)[0]) for v in (1.0, 1.5)}
    return {
        "path": str(path),
        "F_s_at_1": {r: float(curves[r][0][pick[1.0]]) for r in FREQUENCY_RATIOS},
        "F_s_at_1.5": {r: float(curves[r][0][pick[1.5]]) for r in FREQUENCY_RATIOS},
        "F_s_at_100": {r: float(curves[r][0][-1]) for r in FREQUENCY_RATIOS},
        "min_F_s": float(min(curves[r][0].min() for r in FREQUENCY_RATIOS)),
    }


if __name__ == "__main__":
    show(main())
