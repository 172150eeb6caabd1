"""Fig. 6: stuck length over one cycle, two regions
================================================

Fig. 6 of Cigeroglu et al. (2006): the stuck length L1/L of the two-region interface over
one steady cycle x = a sin(theta), at low frequency (0.01 omega_c).

``TwoRegionMicroslip.stick_slip_history`` gives the boundaries by the Masing rule.  Solid:
a = 2 a_min, below gross slip (2.5 a_min for this bar), so a stuck region always remains.
Dashed: a = 3 a_min, where the bar slides as a whole (L1 = 0) around the extremes.  After
each reversal (theta = pi/2, 3 pi/2) the interface sticks again and slip restarts at x = L.
The grey lines mark L1/L of the virgin loading curve at x = a, the cycle's minimum.
"""

from __future__ import annotations

import numpy as np

from paper_figures import DEFAULT_OUTDIR, new_figure, save, setup, show

RATIO = 0.01
#: Amplitudes (fractions of a_min): the first is the one whose numbers are returned.
AMPLITUDES = (2.0, 3.0)
STYLES = ("-", "--")


def wrapped_cycle(theta, *values):
    """The cycle on theta in [0, 2 pi] (stick_slip_history gives [-pi/2, 3 pi/2], ends equal)."""
    th = np.mod(theta[:-1], 2.0 * np.pi)
    order = np.argsort(th, kind="stable")
    th = np.append(th[order], 2.0 * np.pi)
    out = [np.append(v[:-1][order], v[:-1][order][0]) for v in values]
    return (th, *out)


def theta_axis(ax):
    ax.set_xlim(0.0, 2.0 * np.pi)
    ax.set_xticks(np.arange(5) * 0.5 * np.pi, ["0", r"$\pi/2$", r"$\pi$", r"$3\pi/2$", r"$2\pi$"])
    ax.set_xlabel(r"$\theta = \omega t$   (tip motion $x = a \sin\theta$)")


def main(outdir=DEFAULT_OUTDIR, small=False):
    """Write fig06.png; returns min L1/L over the cycle and the virgin L1(a)/L for a = 2 a_min."""
    s = setup()
    el, L, w = s.two, s.bar.L, s.omega(RATIO)
    n = 73 if small else 721
    fig, ax = new_figure(6, rf"stuck length, two-region interface, $\omega = {RATIO:g}\,\omega_c$")
    out = {}
    for a_over, style in zip(AMPLITUDES, STYLES):
        a = a_over * s.a_min
        theta, L1, _ = el.stick_slip_history(a, w, n=n)
        th, L1w = wrapped_cycle(theta, L1)
        ax.plot(th, L1w / L, style, color="k", label=rf"$a = {a_over:g}\,a_{{min}}$")
        virgin = float(el.boundaries(a, w)[0]) / L
        ax.axhline(virgin, color="0.6", lw=3, alpha=0.5)
        out[a_over] = {"min_L1_over_L": float(L1.min() / L), "virgin_L1_at_a_over_L": virgin}
    ax.plot([], [], color="0.6", lw=3, alpha=0.5, label=r"$L_1(a)/L$, loading curve")
    theta_axis(ax)
    ax.set_ylabel(r"$L_1/L$")
    ax.set_ylim(-0.02, 1.05)
    ax.legend(fontsize=8, loc="center left", bbox_to_anchor=(0.265, 0.45))
    path = save(fig, outdir, 6)
    return {"path": str(path), **out[AMPLITUDES[0]], "gross_slip_over_a_min": el.gross_slip_amplitude(w) / s.a_min}


if __name__ == "__main__":
    show(main())
