"""Fig. 11: hysteresis loops, three regions
========================================

Fig. 11 of Cigeroglu et al. (2006): hysteresis loops of the three-region interface (concave
load, q0/(q0 - q2) = 12) at 0.01, 0.2, 0.3 and 0.5 omega_c, amplitude a = 3 a_min (a_min of
the two-region element): past the amplitude where the right stuck region vanishes (about
2.6 a_min), below gross slip (4.9-5.6 a_min).

Axes x/a_min and f/(k* a_min); the thick grey line is the stuck line f = k* x.  As in Fig. 8
the loops rotate clockwise and open up with frequency.
"""

from __future__ import annotations

from paper_figures import DEFAULT_OUTDIR, plot_hysteresis_figure, setup, show

AMPLITUDE = 3.0  # a/a_min


def main(outdir=DEFAULT_OUTDIR, small=False):
    """Write fig11.png; returns per frequency the loop area over pi a f_c, and F_c, F_s."""
    s = setup()
    out, path = plot_hysteresis_figure(11, s.three, AMPLITUDE, rf"hysteresis, three-region interface, "
                                       rf"$a = {AMPLITUDE:g}\,a_{{min}}$", outdir, small)
    return {"path": str(path), "area_over_pi_a_fc": {r: v[0] for r, v in out.items()},
            "F_c": {r: v[1] for r, v in out.items()}, "F_s": {r: v[2] for r, v in out.items()}}


if __name__ == "__main__":
    show(main())
