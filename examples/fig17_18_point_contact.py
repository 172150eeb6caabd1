"""Figs. 17-18: microslip bar against its point contact
====================================================

Figs. 17 and 18 of Cigeroglu et al. (2006): F_s and F_c of the two-region microslip bar
against those of its equivalent point contact (Section 3.4, Fig. 16).

The point contact is ``PointContact.fit(two)``: equal stuck stiffness, fully-slipping stiffness
and gross-slip amplitude, at omega = 0 (the paper does not give the frequency of Figs. 17-18;
both curves are drawn at omega = 0).  The fitted contact stays stuck (F_s = 1, F_c = 0) up to the
gross-slip amplitude a_g, where the microslip bar has long been dissipating; past a_g both
slide as a whole and the curves merge.  Dotted lines mark a_min and a_g.
"""

from __future__ import annotations

import numpy as np

from paper_figures import DEFAULT_OUTDIR, amplitude_grid, new_figure, save, setup, show

from contact_models import PointContact

#: Multiples of the gross-slip amplitude at which the two models are compared.
GROSS_MULTIPLES = (3.0, 10.0, 30.0)
#: Line styles of the paper: solid microslip, dashed point contact.
MICRO_STYLE = dict(ls="-", color="k")
POINT_STYLE = dict(ls="--", color="tab:red")


def compare(element, k_star, a_min, a_over, omega=0.0):
    """Fit a point contact to ``element`` and return ``(point_contact, micro, point, gaps)``.

    ``micro`` and ``point`` are ``(F_s, F_c)`` on ``a = a_over * a_min``; ``gaps`` maps each of
    ``GROSS_MULTIPLES`` to ``(|dF_s|, |dF_c|)`` between the two models at that multiple of a_g.
    """
    pc = PointContact.fit(element, omega)
    a = np.asarray(a_over, dtype=float) * a_min

    def normalised(el, amp):
        fs, fc = el.fourier(amp, omega)
        return fs / (k_star * amp), fc / (k_star * amp)

    micro, point = normalised(element, a), normalised(pc, a)
    a_far = np.array(GROSS_MULTIPLES) * element.gross_slip_amplitude(omega)
    (ms, mc), (ps, pcc) = normalised(element, a_far), normalised(pc, a_far)
    gaps = {m: (float(abs(ms[i] - ps[i])), float(abs(mc[i] - pcc[i]))) for i, m in enumerate(GROSS_MULTIPLES)}
    return pc, micro, point, gaps


def draw(ax, a_over, micro, point, i, a_marks, micro_label="two-region microslip bar"):
    """F_s (i = 0) or F_c (i = 1) of both models on ``ax``, dotted lines at ``a_marks``."""
    ax.semilogx(a_over, micro[i], label=micro_label, **MICRO_STYLE)
    ax.semilogx(a_over, point[i], label="point contact (Fig. 16, fitted)", **POINT_STYLE)
    for x in a_marks:
        ax.axvline(x, color="0.5", lw=0.8, ls=":")
    ax.set_xlim(a_over[0], a_over[-1])
    ax.set_xlabel(r"$a/a_{min}$  ($a_{min}$ of the two-region element)")
    ax.set_ylabel(r"$F_s = f_s/(k^* a)$" if i == 0 else r"$F_c = f_c/(k^* a)$")
    ax.legend(fontsize=8)


def main(outdir=DEFAULT_OUTDIR, small=False):
    """Write fig17.png (F_s) and fig18.png (F_c); returns the fit and the model gaps."""
    s = setup()
    two = s.two
    a_g = two.gross_slip_amplitude(0.0)
    a_over = amplitude_grid(small, keep=(1.0, a_g / s.a_min))
    pc, micro, point, gaps = compare(two, s.k_star, s.a_min, a_over)
    marks = (1.0, a_g / s.a_min)
    paths = []
    for number, i, what in ((17, 0, "$F_s$"), (18, 1, "$F_c$")):
        fig, ax = new_figure(number, f"{what}: two-region microslip bar and its point contact")
        draw(ax, a_over, micro, point, i, marks)
        paths.append(str(save(fig, outdir, number)))
    stuck = (a_over > 1.0) & (a_over < a_g / s.a_min)
    return {
        "paths": paths,
        "point_contact": pc,
        "a_g_over_a_min": a_g / s.a_min,
        "gaps": gaps,
        "max_Fc_micro": float(np.max(micro[1])),
        "max_Fc_point": float(np.max(point[1])),
        "point_Fc_below_a_g": float(np.max(point[1][stuck], initial=0.0)),
    }


if __name__ == "__main__":
    show(main())
