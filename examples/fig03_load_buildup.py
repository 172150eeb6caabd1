"""Fig. 3: build-up of the contact force under three loads
=======================================================

Fig. 3 of Cigeroglu et al. (2006): build-up of the contact elastic force against three
normal-load distributions, at low frequency (0.01 omega_c).

Solid: the friction limits mu q(x) of a uniform load, a convex (hump) load
``QuadraticLoad.from_ratio(100, 0.5)`` and the concave load ``from_ratio(100, 12)``, all with
N = 100 N.  Dashed: the contact force k u(x) of the stuck bar for growing tip amplitudes; each
coloured dashed curve is at the slip-onset amplitude of the load of its colour and touches it
at the onset point ``Bar.slip_onset`` (marked).  Uniform and convex loads slip first at the
excited end, the concave one near mid-length (Section 2.1).
"""

from __future__ import annotations

import numpy as np

from contact_models import QuadraticLoad, UniformLoad
from paper_figures import DEFAULT_OUTDIR, NORMAL_LOAD, new_figure, save, setup, show

#: Frequency (fraction of omega_c): "low-frequency excitation".
RATIO = 0.01
#: Extra tip amplitudes (fractions of a_min) drawn below the first onset.
BELOW_ONSET = (0.1, 0.2)


def loads():
    return {
        "uniform": (UniformLoad(N=NORMAL_LOAD), "tab:blue"),
        "convex (ratio 0.5)": (QuadraticLoad.from_ratio(N=NORMAL_LOAD, ratio=0.5), "tab:orange"),
        "concave (ratio 12)": (QuadraticLoad.from_ratio(N=NORMAL_LOAD, ratio=12.0), "tab:green"),
    }


def main(outdir=DEFAULT_OUTDIR, small=False):
    """Write fig03.png; returns per load the onset point x*/L and amplitude a_onset/a_min."""
    s = setup()
    bar, w = s.bar, s.omega(RATIO)
    x = np.linspace(0.0, bar.L, 41 if small else 401)
    fig, ax = new_figure(3, rf"contact force $k\,u(x)$ (dashed) vs. friction limit $\mu q(x)$ (solid), "
                            rf"$\omega = {RATIO:g}\,\omega_c$")
    for frac in BELOW_ONSET:
        ax.plot(x / bar.L, bar.contact_force(x, w, tip_displacement=frac * s.a_min), "--", color="0.5", lw=1)
    onset = {}
    for name, (load, color) in loads().items():
        load = load.on(bar.L)
        x_star, a_on = bar.slip_onset(load, w)
        ax.plot(x / bar.L, bar.mu * load.q(x), "-", color=color, lw=2, label=rf"$\mu q(x)$, {name}")
        ax.plot(x / bar.L, bar.contact_force(x, w, tip_displacement=a_on), "--", color=color, lw=1.2,
                label=rf"$k u(x)$ at $a = {a_on / s.a_min:.3f}\,a_{{min}}$")
        ax.plot(x_star / bar.L, bar.mu * load.q(x_star), "o", color=color, mfc="none", ms=9)
        onset[name] = (float(x_star / bar.L), float(a_on / s.a_min))
    ax.plot([], [], "--", color="0.5", lw=1,
            label=rf"$k u(x)$ at $a = {', '.join(f'{f:g}' for f in BELOW_ONSET)}\,a_{{min}}$")
    ax.plot([], [], "o", color="0.3", mfc="none", ms=9, label="slip-onset point (Bar.slip_onset)")
    ax.set_xlabel(r"$x/L$")
    ax.set_ylabel("force per unit length (N/m)")
    ax.set_xlim(0.0, 1.0)
    ax.set_ylim(0.0, None)
    ax.legend(fontsize=7, loc="upper center", ncol=1)
    path = save(fig, outdir, 3)
    return {"path": str(path), "onset": onset}


if __name__ == "__main__":
    show(main())
