"""Fig. 14: F_c of two regions against three
=========================================

Fig. 14 of Cigeroglu et al. (2006): F_c of the two-region (uniform load, solid) and the
three-region (concave load q0/(q0 - q2) = 12, dashed) interfaces at 0.3 omega_c, same total
normal load N = 100 N, amplitudes over a_min of the two-region element.

The axis starts at 0.2 a_min so that the three-region slip onset (0.34 a_min at this
frequency) shows; dotted verticals mark both onsets.  The three-region interface damps from a
lower amplitude, the two-region one rises faster after its onset and peaks higher, and both
meet at large amplitude (Section 3.3).
"""

from __future__ import annotations

import numpy as np

from paper_figures import DEFAULT_OUTDIR, amplitude_grid, fourier_curves, new_figure, save, setup, show

RATIO = 0.3
LOWEST = 0.2
#: Coefficient index in fourier_curves' (F_s, F_c) pairs, y label and figure number.
WHICH, YLABEL, NUMBER = 1, r"$F_c = f_c/(k^* a)$", 14


def compare(number, which, ylabel, outdir, small):
    """Figs. 14, 15: one coefficient of both elements at 0.3 omega_c; returns grid, curves, path."""
    s = setup()
    a_over = amplitude_grid(small, lo=LOWEST)
    w = s.omega(RATIO)
    two = fourier_curves(s.two, s, a_over, ratios=(RATIO,))[RATIO][which]
    three = fourier_curves(s.three, s, a_over, ratios=(RATIO,))[RATIO][which]
    name = "F_s" if which == 0 else "F_c"
    fig, ax = new_figure(number, rf"${name}$ of both interfaces, $\omega = {RATIO:g}\,\omega_c$")
    ax.semilogx(a_over, two, "-", color="k", label="two-region (uniform load)")
    ax.semilogx(a_over, three, "--", color="tab:red", label="three-region (concave load, ratio 12)")
    for el, style in ((s.two, "k"), (s.three, "tab:red")):
        ax.axvline(el.slip_amplitude(w) / s.a_min, color=style, lw=0.8, ls=":")
    ax.set_xlabel(r"$a/a_{min}$  ($a_{min}$ of the two-region element)")
    ax.set_ylabel(ylabel)
    ax.set_xlim(a_over[0], a_over[-1])
    ax.legend(fontsize=8)
    path = save(fig, outdir, number)
    return a_over, two, three, path


def main(outdir=DEFAULT_OUTDIR, small=False):
    """Write fig14.png; returns both F_c at 0.8 a_min and at 100 a_min, and both peaks."""
    a_over, two, three, path = compare(NUMBER, WHICH, YLABEL, outdir, small)
    i = int(np.flatnonzero(a_over == 0.8)[0])
    return {"path": str(path), "two_F_c_at_0.8": float(two[i]), "three_F_c_at_0.8": float(three[i]),
            "two_F_c_at_100": float(two[-1]), "three_F_c_at_100": float(three[-1]),
            "two_peak": float(two.max()), "three_peak": float(three.max())}


if __name__ == "__main__":
    show(main())
