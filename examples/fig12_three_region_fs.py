"""Fig. 12: stiffness coefficient F_s, three regions
=================================================

Fig. 12 of Cigeroglu et al. (2006): F_s = f_s/(k* a) of the three-region interface (concave
load, q0/(q0 - q2) = 12) against a/a_min (a_min of the two-region element), at 0.01, 0.2, 0.3
and 0.5 omega_c.

The axis starts at 0.2 a_min (not 0.5 as Figs. 9-10) so that the slip onset at 0.35 a_min
(dotted vertical) shows.  The thick grey line is the omega -> 0 large-amplitude limit
K_slip/k* = 0.5 of the sliding bar (closed-form statics).
"""

from __future__ import annotations

import numpy as np

from paper_figures import DEFAULT_OUTDIR, FREQUENCY_RATIOS, plot_fourier_figure, setup, show

#: Left end of the amplitude axis (a/a_min), below the three-region slip onset (0.35).
LOWEST = 0.2


def main(outdir=DEFAULT_OUTDIR, small=False):
    """Write fig12.png; returns F_s at a/a_min = 0.2 (still stuck), 0.5, 1.5 and 100."""
    s = setup()
    s, a_over, curves, path = plot_fourier_figure(12, s.three, "s", r"$F_s$, three-region interface",
                                                  outdir, small, lo=LOWEST)
    at = {v: int(np.flatnonzero(a_over == v)[0]) for v in (0.5, 1.5)}
    return {
        "path": str(path),
        "a_min_three_over_a_min": s.three.slip_amplitude(s.omega(0.01)) / s.a_min,
        "F_s_at_0.2": {r: float(curves[r][0][0]) for r in FREQUENCY_RATIOS},
        "F_s_at_0.5": {r: float(curves[r][0][at[0.5]]) for r in FREQUENCY_RATIOS},
        "F_s_at_1.5": {r: float(curves[r][0][at[1.5]]) for r in FREQUENCY_RATIOS},
        "F_s_at_100": {r: float(curves[r][0][-1]) for r in FREQUENCY_RATIOS},
        "min_F_s": float(min(curves[r][0].min() for r in FREQUENCY_RATIOS)),
    }


if __name__ == "__main__":
    show(main())
