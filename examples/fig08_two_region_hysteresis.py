"""Fig. 8: hysteresis loops, two regions
=====================================

Fig. 8 of Cigeroglu et al. (2006): hysteresis loops of the two-region interface (uniform
load) at 0.01, 0.2, 0.3 and 0.5 omega_c, amplitude a = 2 a_min (below gross slip, 2.15-2.5
a_min over these frequencies).

``TwoRegionMicroslip.hysteresis`` builds each loop from the loading curve by the Masing rule.
Axes are x/a_min and f/(k* a_min); the thick grey line is the stuck line f = k* x.  With
frequency the loops rotate clockwise (lower f_s) and enclose more area (higher f_c).
"""

from __future__ import annotations

from paper_figures import DEFAULT_OUTDIR, plot_hysteresis_figure, setup, show

AMPLITUDE = 2.0  # a/a_min


def main(outdir=DEFAULT_OUTDIR, small=False):
    """Write fig08.png; returns per frequency the loop area over pi a f_c, and F_c, F_s."""
    s = setup()
    out, path = plot_hysteresis_figure(8, s.two, AMPLITUDE, rf"hysteresis, two-region interface, "
                                       rf"$a = {AMPLITUDE:g}\,a_{{min}}$", outdir, small)
    return {"path": str(path), "area_over_pi_a_fc": {r: v[0] for r, v in out.items()},
            "F_c": {r: v[1] for r, v in out.items()}, "F_s": {r: v[2] for r, v in out.items()}}


if __name__ == "__main__":
    show(main())
