"""Validation: convergence of the numerical bar
============================================

Convergence of ``NumericalMicroslip`` in the cell size and the time step (docs/validation.md).

Quasi-static (omega = 0): errors against the analytic elements, which are exact there, for
n = 50 ... 1600 cells (4096 steps per cycle, so the theta quadrature does not interfere), and
for 256 ... 4096 steps at n = 400.  Dynamic (omega = 0.3 omega_c): successive differences of
F_s, F_c as n doubles at 1024 steps per cycle, and as the steps per cycle double at n = 100.
Observed rates are log2 of successive ratios.  Writes ``validation_convergence.png``::

    python3 examples/validation_convergence.py          # the full study (a few minutes)

.. note::
   Not run when the site is built (a few minutes): the figure is the one a committed run wrote,
   ``docs/figures/validation_convergence.png``; running this script regenerates it.

.. image:: /figures/validation_convergence.png
   :alt: Validation: convergence of the numerical bar
"""

# sphinx_gallery_thumbnail_path = "figures/validation_convergence.png"

from __future__ import annotations

import time

import matplotlib.pyplot as plt
import numpy as np

from validation_common import BAR, FIGURES, LOADS, RATIOS, analytic, markdown_table

from contact_models import NumericalMicroslip


def _normalised(fs, fc, a):
    k = BAR.k_star * np.asarray(a)
    return fs / k, fc / k


def quasi_static_cells(name, cells, steps=4096):
    """Max over the amplitudes of |F - F_exact| (F_s and F_c, units of k* a) for each n."""
    el = analytic(name)
    a = np.array(RATIOS) * el.slip_amplitude(0.0)
    ex_s, ex_c = _normalised(*el.fourier(a, 0.0), a)
    out = []
    for n in cells:
        s, c = _normalised(*NumericalMicroslip(BAR, LOADS[name][0], cells=n, steps_per_cycle=steps).fourier(a, 0.0), a)
        out.append((np.max(np.abs(s - ex_s)), np.max(np.abs(c - ex_c))))
    return np.array(out)


def quasi_static_steps(name, steps, cells=400):
    el = analytic(name)
    a = np.array(RATIOS) * el.slip_amplitude(0.0)
    ex_s, ex_c = _normalised(*el.fourier(a, 0.0), a)
    out = []
    for m in steps:
        s, c = _normalised(*NumericalMicroslip(BAR, LOADS[name][0], cells=cells, steps_per_cycle=m).fourier(a, 0.0), a)
        out.append((np.max(np.abs(s - ex_s)), np.max(np.abs(c - ex_c))))
    return np.array(out)


def dynamic_sweep(name, levels, w_ratio=0.3):
    """F_s, F_c (units of k* a) for each (cells, steps) level; shape (levels, 2, amplitudes)."""
    el = analytic(name)
    a = np.array(RATIOS) * el.slip_amplitude(0.0)
    w = w_ratio * BAR.omega_c
    out = []
    for n, m in levels:
        num = NumericalMicroslip(BAR, LOADS[name][0], cells=n, steps_per_cycle=m)
        out.append(_normalised(*num.fourier(a, w), a))
    return np.array(out)


def rates(errors):
    e = np.asarray(errors, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.log2(e[:-1] / e[1:])


def main(small=False, outdir=FIGURES):
    """Run the study; returns a dict of arrays and writes the figure."""
    if small:
        cells, qsteps = (50, 100, 200), (256, 512)
        n_levels = [(20, 256), (40, 256)]
        m_levels = [(20, 128), (20, 256)]
    else:
        cells, qsteps = (50, 100, 200, 400, 800, 1600), (256, 512, 1024, 2048, 4096)
        n_levels = [(25, 1024), (50, 1024), (100, 1024), (200, 1024)]
        m_levels = [(100, 128), (100, 256), (100, 512), (100, 1024)]
    res = {"cells": cells, "qsteps": qsteps, "n_levels": n_levels, "m_levels": m_levels, "qsteps_cells": 100 if small else 400}
    for name in LOADS:
        res[f"qs_cells_{name}"] = quasi_static_cells(name, cells)
        res[f"qs_steps_{name}"] = quasi_static_steps(name, qsteps, cells=res["qsteps_cells"])
        for key, levels in (("n", n_levels), ("m", m_levels)):
            F = dynamic_sweep(name, levels)
            res[f"dyn_{key}_{name}"] = np.max(np.abs(np.diff(F, axis=0)), axis=2)  # (levels-1, 2)
    res["path"] = str(_figure(res, outdir))
    return res


def _figure(res, outdir):
    fig, axes = plt.subplots(1, 3, figsize=(13, 4))
    for name, mk in zip(LOADS, ("o", "s")):
        e = res[f"qs_cells_{name}"]
        axes[0].loglog(res["cells"], e[:, 0], "-" + mk, label=f"{name}: F_s")
        axes[0].loglog(res["cells"], e[:, 1], "--" + mk, label=f"{name}: F_c")
        for key, ax, lv in (("n", axes[1], res["n_levels"]), ("m", axes[2], res["m_levels"])):
            x = [l[0] if key == "n" else l[1] for l in lv][1:]
            d = res[f"dyn_{key}_{name}"]
            ax.loglog(x, d[:, 0], "-" + mk, label=f"{name}: F_s")
            ax.loglog(x, d[:, 1], "--" + mk, label=f"{name}: F_c")
    n = np.array(res["cells"], dtype=float)
    axes[0].loglog(n, 0.5 * (n / n[0]) ** -2 * res["qs_cells_uniform"][0].max(), ":", color="0.5", label="slope -2")
    axes[0].set(xlabel="cells n", ylabel="max |F - F_analytic| (units of k* a)", title="quasi-static, vs exact")
    axes[1].set(xlabel="cells n (1024 steps/cycle)", ylabel="max |F(n) - F(n/2)|", title=r"dynamic, $0.3\,\omega_c$")
    axes[2].set(xlabel="steps per cycle (n = 100)", ylabel="max |F(m) - F(m/2)|", title=r"dynamic, $0.3\,\omega_c$")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    outdir.mkdir(parents=True, exist_ok=True)
    path = outdir / "validation_convergence.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def report(res) -> str:
    parts = []
    for name in LOADS:
        e = res[f"qs_cells_{name}"]
        r = rates(e.max(axis=1))
        parts.append(f"### quasi-static, {name}: error against the analytic element (4096 steps/cycle)\n")
        parts.append(markdown_table(["cells", "max err F_s", "max err F_c", "rate"],
                                    [[n, f"{s:.2e}", f"{c:.2e}", "" if i == 0 else f"{r[i - 1]:.2f}"]
                                     for i, (n, (s, c)) in enumerate(zip(res["cells"], e))]))
        e = res[f"qs_steps_{name}"]
        parts.append(f"\n\nquasi-static, {name}, n = {res['qsteps_cells']}, steps per cycle:\n")
        parts.append(markdown_table(["steps", "max err F_s", "max err F_c"],
                                    [[m, f"{s:.2e}", f"{c:.2e}"] for m, (s, c) in zip(res["qsteps"], e)]))
        for key, lv, label in (("n", res["n_levels"], "cells (1024 steps)"), ("m", res["m_levels"], "steps (100 cells)")):
            d = res[f"dyn_{key}_{name}"]
            r = rates(d.max(axis=1))
            parts.append(f"\n\ndynamic 0.3 omega_c, {name}, successive differences in {label}:\n")
            parts.append(markdown_table(["level", "max dF_s", "max dF_c", "rate"],
                                        [[f"{lv[i + 1]}", f"{s:.2e}", f"{c:.2e}", "" if i == 0 else f"{r[i - 1]:.2f}"]
                                         for i, (s, c) in enumerate(d)]))
        parts.append("\n\n")
    return "".join(parts)


if __name__ == "__main__":
    t0 = time.perf_counter()
    out = main()
    print(report(out))
    print(f"{time.perf_counter() - t0:.0f} s")
