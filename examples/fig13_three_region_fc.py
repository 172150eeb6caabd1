"""Fig. 13: damping coefficient F_c, three regions
===============================================

Fig. 13 of Cigeroglu et al. (2006): F_c = f_c/(k* a) of the three-region interface (concave
load, q0/(q0 - q2) = 12) against a/a_min (a_min of the two-region element), at 0.01, 0.2, 0.3
and 0.5 omega_c.

Damping starts at 0.35 a_min (dotted vertical; the axis starts at 0.2 a_min so that it shows),
peaks lower and later than the two-region one (Fig. 10) and falls like 1/a past gross slip.
The knee near 2.57 a_min is where the right stuck region vanishes (L2 = L): the loading curve's
curvature jumps there.  Thick grey: the omega -> 0 large-amplitude limit 4 F0/(pi k* a) of the
sliding bar under this load (closed-form statics).
"""

from __future__ import annotations

import numpy as np

from paper_figures import DEFAULT_OUTDIR, FREQUENCY_RATIOS, plot_fourier_figure, setup, show, static_gross_slip

#: Left end of the amplitude axis (a/a_min), below the three-region slip onset (0.35).
LOWEST = 0.2


def main(outdir=DEFAULT_OUTDIR, small=False):
    """Write fig13.png; returns F_c at 0.2 (still stuck), 0.5 and 1.5 a_min, its peak, and the
    ratio of F_c at 100 a_min (0.01 omega_c) to the static large-amplitude limit."""
    s = setup()
    s, a_over, curves, path = plot_fourier_figure(13, s.three, "c", r"$F_c$, three-region interface",
                                                  outdir, small, lo=LOWEST)
    at = {v: int(np.flatnonzero(a_over == v)[0]) for v in (0.5, 1.5)}
    _, F0 = static_gross_slip(s.bar, s.three.load)
    limit = 4.0 * F0 / (np.pi * s.k_star * a_over[-1] * s.a_min)
    return {
        "path": str(path),
        "F_c_at_0.2": {r: float(curves[r][1][0]) for r in FREQUENCY_RATIOS},
        "F_c_at_0.5": {r: float(curves[r][1][at[0.5]]) for r in FREQUENCY_RATIOS},
        "F_c_at_1.5": {r: float(curves[r][1][at[1.5]]) for r in FREQUENCY_RATIOS},
        "peak_F_c": {r: float(curves[r][1].max()) for r in FREQUENCY_RATIOS},
        "F_c_at_100_over_static_limit": float(curves[0.01][1][-1] / limit),
    }


if __name__ == "__main__":
    show(main())
