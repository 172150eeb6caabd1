"""Fig. 15: F_s of two regions against three
=========================================

Fig. 15 of Cigeroglu et al. (2006): F_s of the two-region (uniform load, solid) and the
three-region (concave load q0/(q0 - q2) = 12, dashed) interfaces at 0.3 omega_c, same total
normal load, amplitudes over a_min of the two-region element (axis from 0.2 a_min; dotted
verticals mark both slip onsets).

The three-region stiffness drops first; after its onset the two-region stiffness falls faster
and the curves cross; at large amplitude both tend to the same sliding-bar stiffness.
"""

from __future__ import annotations

import numpy as np

from fig14_compare_fc import compare
from paper_figures import DEFAULT_OUTDIR, show

WHICH, YLABEL, NUMBER = 0, r"$F_s = f_s/(k^* a)$", 15


def main(outdir=DEFAULT_OUTDIR, small=False):
    """Write fig15.png; returns both F_s at 0.8 a_min and 100 a_min and where the curves cross."""
    a_over, two, three, path = compare(NUMBER, WHICH, YLABEL, outdir, small)
    i = int(np.flatnonzero(a_over == 0.8)[0])
    below = np.flatnonzero((a_over > 1.0) & (two < three))
    return {"path": str(path), "two_F_s_at_0.8": float(two[i]), "three_F_s_at_0.8": float(three[i]),
            "two_F_s_at_100": float(two[-1]), "three_F_s_at_100": float(three[-1]),
            "first_crossing_a_over_a_min": float(a_over[below[0]]) if below.size else float("nan")}


if __name__ == "__main__":
    show(main())
