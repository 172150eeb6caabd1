"""Point contact fitted to the three-region bar
============================================

Figs. 17-18 for the three-region element: F_s and F_c of the concave-load microslip bar
(``QuadraticLoad.from_ratio(N=100, ratio=12)``) against its fitted point contact.

Same comparison as ``fig17_18_point_contact.py``, omega = 0, amplitudes normalised by a_min of
the two-region element (as the paper's Figs. 14-15 do).  The three-region bar starts to slip
earlier and reaches gross slip later (a_g = 5.6 a_min), so the range of amplitudes where the
point contact is stuck but the bar dissipates is wider.  Writes
``point_contact_three_region.png`` (two panels: F_s and F_c).
"""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt

from fig17_18_point_contact import compare, draw
from paper_figures import DEFAULT_OUTDIR, DPI, amplitude_grid, setup, show

#: Range of a/a_min: from below the three-region slip onset (0.35) to past 30 gross-slip amplitudes.
A_OVER_RANGE = (0.1, 300.0)
FILENAME = "point_contact_three_region.png"


def main(outdir=DEFAULT_OUTDIR, small=False):
    """Write point_contact_three_region.png; returns the fit and the model gaps."""
    s = setup()
    three = s.three
    a_min3, a_g = three.slip_amplitude(0.0), three.gross_slip_amplitude(0.0)
    a_over = amplitude_grid(small, lo=A_OVER_RANGE[0], hi=A_OVER_RANGE[1], keep=(a_min3 / s.a_min, a_g / s.a_min))
    pc, micro, point, gaps = compare(three, s.k_star, s.a_min, a_over)
    fig, axes = plt.subplots(1, 2, figsize=(11.0, 4.5))
    for i, ax in enumerate(axes):
        draw(ax, a_over, micro, point, i, (a_min3 / s.a_min, a_g / s.a_min), "three-region microslip bar")
        ax.grid(True, which="both", alpha=0.3)
    fig.suptitle("Three-region (concave load, ratio 12) bar and its fitted point contact", fontsize=10)
    fig.tight_layout()
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    path = outdir / FILENAME
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return {
        "path": str(path),
        "point_contact": pc,
        "a_min_over_a_min2": a_min3 / s.a_min,
        "a_g_over_a_min2": a_g / s.a_min,
        "gaps": gaps,
    }


if __name__ == "__main__":
    show(main())
