"""Rungs of the all-mode bar chosen along a curve: the cheap start rung and the next rung.

A choosing ``AllModeMicroslip`` (cells and harmonics None) climbs its ladder of rungs at every
call.  Along a frequency response the same choice is made once per stretch of the curve instead
(``hbm.adapt``, the model pass): the whole range is traced on a cheap fixed rung
(:meth:`contact_models.AllModeMicroslip.start_rung`), and the windows where the rung's own estimate
(Richardson on its lower rungs, through the balance) exceeds its share of the tolerance are traced
again on the rung :func:`next_rung` predicts, in turn.

**The next rung.**  The estimate of a rung (n cells, H harmonics) has two parts, ``rel_c`` (cells)
and ``rel_h`` (harmonics), relative errors of (f_s, f_c) as the element's ``tol``.  The window's
estimate must fall by the factor ``excess`` (its largest estimate over its threshold), so the
rung's estimate at its worst point must fall from ``rel_c + rel_h`` to ``target = (rel_c + rel_h) /
excess``.  The parts are predicted to fall like ``rel_c (n/n')^CELLS_ORDER`` (second order in the
cells, the bar's asymptotic order) and ``rel_h (H/H')^HARMONICS_ORDER`` (the balance's
``hbm.adapt.DECAY_ORDER``).  Shares: a part already within half the target is kept (its rung too)
and the other gets the rest of the target; where both miss half, each gets half.  Cells: the
smallest doubling of n within its share; harmonics: the smallest rung of the ladder within its share;
each at most its top.  Where the prediction is short (the cells converge at order 1 near the onset of
slip, the harmonics erratically where a harmonic meets a mode of the bar) the refined window's own
estimate asks again.  None where both are at their top.

**Tried before traced** (:func:`probed_rung`).  Tracing a window on a rung that turns out short costs
the whole window's points; so the predicted rung is first solved, with its estimate, at the window's
worst point alone, and while its estimate there still misses the target the rung after it is
predicted from that estimate, at most ``PROBES`` times.  The window is then traced on the last rung
tried; its own estimate along the window decides, as for any traced window, whether it is refined again.
"""

from __future__ import annotations

import math
from typing import Callable

#: The start rung's harmonics and its least cells (more where the wavelength of its highest harmonic
#: at the top of the range asks for more: ``accuracy.start_cells``).  32 cells: below that the exact
#: segments' estimate is read from rungs that are pre-asymptotic where the bar slips, and over-predicts
#: the cells a window needs (docs/performance.md, "The all-mode FRF: the bar's exact segments").
#: 7 harmonics: its harmonics part is read against 15 (``accuracy.harmonics_error``), so it sees a
#: harmonic up to 15 meet a mode of the bar, which a reading from 1, 3, 7 cannot, at the cost of a
#: 7-harmonic nested solve (docs/theory.md, "The all-mode bar along a curve").
START_HARMONICS = 7
START_CELLS = 32
#: The most cells a rung along a curve gets (the element alone: ``element.MAX_CELLS``): where a
#: harmonic of the drive meets a mode of the bar the estimate stops falling with the cells, so finer
#: rungs there cost every point of the window without bringing the estimate down (docs/theory.md,
#: "The all-mode bar along a curve"; docs/validation.md, "The all-mode FRF on rungs along the curve,
#: against a converged reference").
CURVE_MAX_CELLS = 128
#: The orders the parts of the estimate are predicted to fall with (module docstring).
CELLS_ORDER = 2.0
HARMONICS_ORDER = 4.0
#: The most rungs tried at a window's worst point before the window is traced (module docstring).
PROBES = 3


def lower_rung(H: int) -> int:
    """The rung of harmonics below H in the element's estimate (about H/2, odd for odd H: 31 -> 15 -> 7
    -> 3 -> 1)."""
    return max(1, (H - 1) // 2)


def next_rung(n: int, H: int, rel_c: float, rel_h: float, excess: float, *, max_cells: int,
              ladder: tuple[int, ...], cells_for: Callable[[int], int] | None = None) -> tuple[int, int] | None:
    """``(n', H')``: the rung after ``(n, H)`` predicted to bring the estimate ``rel_c + rel_h`` down by
    the factor ``excess`` (module docstring); at least one part is refined (an ``excess`` <= 1 asks
    for a factor just above 1); None at the top (``max_cells`` cells and the last rung of ``ladder``).
    ``cells_for(H')``: the least cells at H' (the wavelength of its highest harmonic), if any.

    Examples
    --------
    Cells only (the harmonics part within half the target), a factor 10: 16 -> 64 cells
    (1e-2 (16/64)^2 = 6.3e-4 <= 1.1e-3 - 1e-4):

    >>> next_rung(16, 7, 1e-2, 1e-4, 10.0, max_cells=640, ladder=(7, 15, 31))
    (64, 7)

    Both parts miss half the target (5e-4 each): 32 cells (1e-3 (16/32)^2 = 2.5e-4), H = 15
    (4e-3 (7/15)^4 = 1.9e-4):

    >>> next_rung(16, 7, 1e-3, 4e-3, 5.0, max_cells=640, ladder=(7, 15, 31))
    (32, 15)
    >>> next_rung(640, 31, 1.0, 1.0, 10.0, max_cells=640, ladder=(7, 15, 31)) is None
    True
    """
    top_h = ladder[-1]
    if n >= max_cells and H >= top_h:
        return None
    total = rel_c + rel_h
    excess = excess if excess > 1.0 else 1.0 + 1e-9
    if not math.isfinite(total):
        share_c = 0.0 if not math.isfinite(rel_c) else math.inf
        share_h = 0.0 if not math.isfinite(rel_h) else math.inf
    else:
        target = total / excess
        if rel_h <= 0.5 * target:
            share_c, share_h = target - rel_h, math.inf
        elif rel_c <= 0.5 * target:
            share_c, share_h = math.inf, target - rel_c
        else:
            share_c = share_h = 0.5 * target
        if n >= max_cells:  # one part at its top: the other gets what it can
            share_h = min(share_h, 0.5 * target)
        if H >= top_h:
            share_c = min(share_c, 0.5 * target)
    n_new = n
    while n_new < max_cells and not rel_c * (n / n_new) ** CELLS_ORDER <= share_c:
        n_new = min(2 * n_new, max_cells)
    H_new = H
    up = [h for h in ladder if h > H]
    if up and not rel_h <= share_h:
        H_new = next((h for h in up if rel_h * (H / h) ** HARMONICS_ORDER <= share_h), up[-1])
    if cells_for is not None:
        while n_new < max_cells and n_new < cells_for(H_new):
            n_new = min(2 * n_new, max_cells)
    if (n_new, H_new) == (n, H):
        return None
    return n_new, H_new


def probed_rung(rung: tuple[int, int], worst: tuple[float, float], target: float, build: Callable,
                predict: Callable) -> object:
    """The element a window is traced on: the rung ``rung = (cells, H)`` built by ``build(cells, H)``
    and solved with its estimate at the window's worst point ``worst = (omega, a)``; while that
    estimate (``rel_c + rel_h``, the parts the element records) is above ``target``, the rung
    ``predict(element, rel_c, rel_h, excess)`` gives (None at the top), at most ``PROBES`` rungs
    (module docstring)."""
    element = build(*rung)
    for _ in range(PROBES):
        seen = len(element._seen)
        element.model_error(worst[1], worst[0])
        if len(element._seen) == seen:  # nothing recorded (a failed solve): trace it as it is
            break
        rel_c, rel_h = element._seen[-1][2:]
        if not rel_c + rel_h > target:
            break
        rung = predict(element, rel_c, rel_h, (rel_c + rel_h) / target)
        if rung is None:
            break
        element = build(*rung)
    return element
