"""The figure of a study (``study.png``).

Random samples: a histogram of the peak amplitude with its 5th, 50th and 95th percentiles, and
the peak against the first sampled parameter.  A grid: the runs' FRFs (``hbm.output.plot_frfs``)
and the peak against the numeric parameter with the most values, one line per combination of
the others, the smallest peak of each line starred.  Every peak carries an error bar of its
estimated error (``peak_error_rel`` times the peak); axes are named by
``hbm.output.key_label`` (the key's name and SI unit), amplitudes in metres.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from ..output import key_label, plot_frfs

#: Percentiles marked on a sampled study's histogram.
PERCENTILES = (5.0, 50.0, 95.0)
#: At most this many FRFs are drawn (evenly chosen).
MAX_CURVES = 120


class _Branch:
    """A recorded FRF curve drawn as ``plot_frfs`` draws an ``hbm.FrequencyResponse``."""

    def __init__(self, rec: dict) -> None:
        self.omega = np.asarray(rec["curve"]["omega_rad_s"])
        self.amplitude = np.asarray(rec["curve"]["amplitude_m"])
        self.success = rec["success"]
        self.peak_point = (rec["peak_omega_rad_s"], rec["peak_amplitude_m"])

    def plot(self, ax: Any, *, label: str | None = None, peak: bool = True, error_band: bool = False,
             **kwargs: Any) -> Any:  # a record keeps the peak's estimate, not the curve's: no band
        line, = ax.plot(self.omega, self.amplitude, label=label, **kwargs)
        if peak and self.peak_point[1] is not None:
            ax.plot([self.peak_point[0]], [self.peak_point[1]], "o", color=line.get_color(), ms=3)
        ax.set_xlabel(r"$\omega$ (rad/s)")
        ax.set_ylabel("amplitude (m)")
        return ax


def _bars(recs: list) -> np.ndarray:
    """The error bars of the runs' peaks: ``(2, n)`` distances below and above, ``peak_amplitude_m``
    times ``peak_error_rel`` (the peak's estimated relative error; none where a run has no estimate),
    the lower one capped below the peak so a logarithmic axis draws it."""
    a = np.array([r["peak_amplitude_m"] for r in recs], dtype=float)
    e = np.array([np.nan if r.get("peak_error_rel") is None else r["peak_error_rel"] for r in recs], dtype=float)
    e = np.nan_to_num(e, nan=0.0)
    return np.array([a * np.minimum(e, 0.99), a * e])


def _numeric(values: list) -> bool:
    return all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values)


def percentiles(values: Any, q: tuple = PERCENTILES) -> dict:
    """``{q: value}`` of the finite ``values`` (linear interpolation, numpy's default).

    Examples
    --------
    >>> percentiles([1.0, 2.0, 3.0, 4.0, 5.0])
    {5.0: 1.2, 50.0: 3.0, 95.0: 4.8}
    """
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    return {p: float(np.percentile(v, p)) for p in q}


def figure(result: Any, path: str | Path, *, title: str = "", samples: dict | None = None) -> Path:
    """Draw ``result`` (an :class:`hbm.study.StudyResult`) to ``path``; returns the path."""
    import matplotlib  # lazily: matplotlib only when a figure is drawn

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # lazily, as above

    recs = [r for r in result.records if r is not None and r["success"] and r["peak_amplitude_m"] is not None]
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11.0, 4.4))
    params = result.parameters
    if samples:
        _histogram(ax, [r["peak_amplitude_m"] for r in recs])
        name = next(iter(samples))
        other = [p for p in params if p != name]
        cval = [r["params"][other[0]] for r in recs] if other else None
        cval = cval if cval is not None and _numeric(cval) else None
        xs, ys = [r["params"][name] for r in recs], [r["peak_amplitude_m"] for r in recs]
        bx.errorbar(xs, ys, yerr=_bars(recs), fmt="none", ecolor="0.6", elinewidth=0.6, zorder=1)
        sc = bx.scatter(xs, ys, s=4, c=cval, cmap="viridis" if cval is not None else None, zorder=2)
        if cval is not None:
            fig.colorbar(sc, ax=bx).set_label(key_label(other[0]))
        bx.set_xlabel(key_label(name))
        bx.set_ylabel("peak amplitude (m)")
        bx.set_title("peaks; bars: estimated error", fontsize=8)
    else:
        _grid(ax, bx, recs, params)
    fig.suptitle(title or "study", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return Path(path)


def _histogram(ax: Any, peaks: list) -> None:
    ax.hist(peaks, bins=min(60, max(10, len(peaks) // 20)), color="0.7", edgecolor="0.4")
    for (q, v), style in zip(percentiles(peaks).items(), (":", "-", "--")):
        ax.axvline(v, color="C3", ls=style, label=f"{q:g}th percentile: {v:.4g} m")
    ax.set_xlabel("peak amplitude (m)")
    ax.set_ylabel("runs")
    ax.legend(fontsize=7)


def _grid(ax: Any, bx: Any, recs: list, params: tuple) -> None:

    numeric = [p for p in params if _numeric([r["params"][p] for r in recs])]
    x = max(numeric, key=lambda p: len({r["params"][p] for r in recs})) if numeric else None
    groups = [p for p in params if p != x]
    label = lambda r: ", ".join(f"{p.split('.')[-1]} = {r['params'][p]}" for p in groups) or None  # noqa: E731
    curves = [r for r in recs if "omega_rad_s" in r["curve"] and "amplitude_m" in r["curve"]]
    curves = [curves[i] for i in np.unique(np.linspace(0, len(curves) - 1, min(MAX_CURVES, len(curves))).astype(int))] \
        if curves else []
    full = lambda r: ", ".join(f"{p.split('.')[-1]} = {r['params'][p]}" for p in params)  # noqa: E731
    plot_frfs([(_Branch(r), full(r), label(r), r["params"][x] if x else None) for r in curves], ax,
              parameter=key_label(x) if x else None)
    if x is None:
        bx.set_axis_off()
        return
    by = {}
    for r in recs:
        by.setdefault(label(r), []).append(r)
    for name, rs in by.items():
        rs.sort(key=lambda r: r["params"][x])
        xs = np.array([r["params"][x] for r in rs], dtype=float)
        ys = np.array([r["peak_amplitude_m"] for r in rs], dtype=float)
        bars = bx.errorbar(xs, ys, yerr=_bars(rs), fmt="o-", ms=3, capsize=2, elinewidth=0.8, label=name)
        k = int(np.argmin(ys))
        bx.plot(xs[k], ys[k], "*", ms=12, color=bars.lines[0].get_color())
    xs = np.array([r["params"][x] for r in recs], dtype=float)
    if xs.min() > 0 and xs.max() / xs.min() > 20:
        bx.set_xscale("log")
    bx.set_yscale("log")
    bx.set_xlabel(key_label(x))
    bx.set_ylabel("peak amplitude (m)")
    bx.set_title("peaks; stars: the smallest; bars: estimated error", fontsize=8)
    if len(by) > 1:
        bx.legend(fontsize=7)


__all__ = ["figure", "percentiles", "PERCENTILES"]
