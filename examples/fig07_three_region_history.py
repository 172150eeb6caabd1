"""Fig. 7: region boundaries over one cycle, three regions
=======================================================

Fig. 7 of Cigeroglu et al. (2006): L1/L (solid) and L2/L (dashed) of the three-region
interface over one steady cycle, at low frequency (0.01 omega_c).

Amplitude a = 4 a_min (a_min of the two-region element): above the amplitude at which the
right stuck region vanishes on the loading curve (L2 = L, about 2.57 a_min) and below gross
slip (about 5.64 a_min).  Slip nucleates at x* ~ 0.51 L and grows both ways, reaches the
excited end first, and then the left stuck region keeps shrinking.  While the whole interface
is stuck (just after each reversal) both boundaries are drawn at the nucleation point x*.
"""

from __future__ import annotations

import numpy as np

from fig06_two_region_history import theta_axis, wrapped_cycle
from paper_figures import DEFAULT_OUTDIR, new_figure, save, setup, show

RATIO = 0.01
AMPLITUDE = 4.0  # a/a_min


def right_region_vanishes(element, omega, a_min, L, *, hi=10.0, n=2001):
    """Smallest virgin tip displacement (units of a_min) with L2 = L, on a grid of ``n`` points."""
    x = np.linspace(0.0, hi, n) * a_min
    _, L2 = element.boundaries(x, omega)
    return float(x[np.argmax(L2 >= L * (1.0 - 1e-12))] / a_min)


def main(outdir=DEFAULT_OUTDIR, small=False):
    """Write fig07.png; returns the extremes of L1/L, L2/L over the cycle and the amplitudes
    at which L2 reaches L and gross slip occurs."""
    s = setup()
    el, L, w = s.three, s.bar.L, s.omega(RATIO)
    a = AMPLITUDE * s.a_min
    theta, L1, L2 = el.stick_slip_history(a, w, n=73 if small else 721)
    th, L1w, L2w = wrapped_cycle(theta, L1, L2)
    x_star = s.bar.slip_onset(el.load, w)[0]
    fig, ax = new_figure(7, rf"stick-slip boundaries, three-region interface, $a = {AMPLITUDE:g}\,a_{{min}}$, "
                            rf"$\omega = {RATIO:g}\,\omega_c$")
    ax.plot(th, L1w / L, "-", color="k", label=r"$L_1/L$")
    ax.plot(th, L2w / L, "--", color="k", label=r"$L_2/L$")
    ax.axhline(x_star / L, color="0.6", lw=3, alpha=0.5, label=r"onset point $x^*/L$")
    theta_axis(ax)
    ax.set_ylabel(r"$L_1/L$,  $L_2/L$")
    ax.set_ylim(-0.02, 1.05)
    ax.legend(fontsize=8, loc="lower left", bbox_to_anchor=(0.255, 0.01))
    path = save(fig, outdir, 7)
    return {
        "path": str(path),
        "min_L1_over_L": float(L1.min() / L),
        "virgin_L1_at_a_over_L": float(el.boundaries(a, w)[0]) / L,
        "max_L2_over_L": float(L2.max() / L),
        "x_star_over_L": float(x_star / L),
        "L2_reaches_L_at_a_over_a_min": right_region_vanishes(el, w, s.a_min, L, n=201 if small else 2001),
        "gross_slip_over_a_min": el.gross_slip_amplitude(w) / s.a_min,
    }


if __name__ == "__main__":
    show(main())
