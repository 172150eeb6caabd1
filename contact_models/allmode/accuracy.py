"""The all-mode bar's discretisation error: Richardson extrapolation with the observed order, and
where the ladder of cells starts.

``AllModeMicroslip`` estimates the error of its (F_s, F_c) from three solutions on a ladder of
resolutions N_1 < N_2 < N_3 (harmonics about H/4, H/2, H; cells n/4, n/2, n from 128 cells on, and
below them n/2, n, 2n with the difference of n to 2n added: ``cells_error``), component by
component.  With e(N) = C N^-p the differences d_1 = F_2 - F_1, d_2 = F_3 - F_2 fix the observed
order p (``observed_order``) and the error of the finest, |d_2| / ((N_3/N_2)^p - 1).  It is used
only where it is safe:

- the differences do not shrink (|d_2| >= |d_1|), change sign (not one asymptotic branch) or the
  observed order is below ``MIN_ORDER`` = 1: the estimate is |d_2| itself (no division);
- the observed order is above ``MAX_ORDER`` = 3 (a difference small by a crossing, not by
  convergence: on a load with many slip pockets the sequence is erratic until every pocket is
  resolved): the larger of |d_2| and the error that d_1 predicts for the finest at order
  ``MIN_ORDER``, |d_1| / ((N_2/N_1 - 1) N_3/N_2).

The order is assumed by nothing: the bar converges at second order in cells only once every
stick/slip front and wavelength is resolved, and the harmonics converge erratically where a
harmonic meets a mode of the bar (``docs/validation.md``, the all-mode section).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Callable

import numpy as np
from numpy.typing import NDArray

from .rungs import lower_rung

if TYPE_CHECKING:
    from ..bar import Bar

#: Observed orders below this are not trusted: the estimate is the last difference.
MIN_ORDER = 1.0
#: Observed orders above this are capped (see the module docstring).
MAX_ORDER = 3.0
#: A rung of fewer cells than this is checked against the rung above it (``cells_error``); the finest
#: rung along a curve (``rungs.CURVE_MAX_CELLS``) and finer ones by the two rungs below them.
CHECK_ABOVE_CELLS = 128
#: A rung of fewer harmonics than this is checked against the rung above it, 2H + 1 (``harmonics_error``): from
#: below (H/4, H/2, H) a rung of H = 7 cannot see a harmonic above it meet a mode of the bar, and reads its
#: error short there (docs/validation.md, "Accuracy to a tolerance: the estimate against converged
#: references"); the rungs of 15 and 31 harmonics, the ones a curve refines to, by the two rungs below them.
CHECK_ABOVE_HARMONICS = 15
#: The validity map's floor: errors relative to max(|F|, FLOOR k* a), component by component.
FLOOR = 0.01
#: Cells per wavelength of the highest harmonic, and per decay length 1/lambda of the shear
#: layer, at the start of the ladder (at least ``MIN_START_CELLS``).
CELLS_PER_WAVELENGTH = 8.0
CELLS_PER_DECAY = 4.0
MIN_START_CELLS = 8


def observed_order(N: tuple[float, float, float], d1: float, d2: float) -> float:
    """The order p with (N_1^-p - N_2^-p) / (N_2^-p - N_3^-p) = d_1 / d_2 for positive d_1/d_2 > 1
    (bisection: the left side grows with p); 0 if d_1/d_2 <= 1.

    >>> round(observed_order((10, 20, 40), 4.0, 1.0), 12)
    2.0
    """
    ratio = d1 / d2
    if not ratio > 1.0:
        return 0.0

    def g(p):
        a, b, c = (n ** -p for n in N)
        return (a - b) / (b - c)

    lo, hi = 1e-6, 60.0
    if g(hi) < ratio:
        return hi
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if g(mid) < ratio else (lo, mid)
    return 0.5 * (lo + hi)


def richardson(N: tuple[float, float, float], F: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray]:
    """``(error, order)``: the estimated error of ``F[2]`` (the finest, resolution ``N[2]``) from the
    values ``F`` (3, k) at resolutions ``N`` (increasing), component by component, and the
    observed order used (nan where the guard took the last difference).

    >>> e, p = richardson((10, 20, 40), np.array([[1.0 + 1e-2], [1.0 + 2.5e-3], [1.0 + 6.25e-4]]))
    >>> round(float(e[0]), 12), round(float(p[0]), 6)
    (0.000625, 2.0)
    """
    F = np.asarray(F, dtype=float)
    r = N[2] / N[1]
    err = np.empty(F.shape[1])
    order = np.full(F.shape[1], np.nan)
    for j in range(F.shape[1]):
        d1, d2 = F[1, j] - F[0, j], F[2, j] - F[1, j]
        if d2 == 0.0 and d1 == 0.0:
            err[j] = 0.0
            continue
        if d1 * d2 <= 0.0 or abs(d2) >= abs(d1):
            err[j] = abs(d2)
            continue
        p = observed_order(N, abs(d1), abs(d2))
        if p < MIN_ORDER:
            err[j] = abs(d2)
        elif p > MAX_ORDER:
            r1 = N[1] / N[0]
            err[j] = max(abs(d2), abs(d1) / ((r1**MIN_ORDER - 1.0) * r**MIN_ORDER))
        else:
            err[j] = abs(d2) / (r**p - 1.0)
            order[j] = p
    return err, order


def ladder(N: tuple, F: list, alone: NDArray[np.float64]) -> NDArray[np.float64]:
    """The error of the last of the values ``F`` (rows) on the rungs ``N`` (their resolutions, the
    finest last): :func:`richardson` on three rungs, the last difference on two, ``alone`` on one;
    inf wherever it is not finite (a failed solve on a lower rung)."""
    if len(N) == 3:
        e, _ = richardson(tuple(N), np.array(F))
    elif len(N) == 2:
        e = np.abs(F[1] - F[0])
    else:
        e = alone
    return np.where(np.isfinite(e), e, np.inf)


def cells_error(n: int, F: NDArray[np.float64], at: Callable[[int], NDArray[np.float64] | None],
                check_above: float = CHECK_ABOVE_CELLS) -> NDArray[np.float64]:
    """The cells part of the estimate (N, component by component) of the force ``F`` on n cells; ``at(c)``
    is the force on c cells (nan where its solve failed, None where c cells cannot hold the rung's highest
    harmonic: a lower rung that is None is left out, the estimate then read from the rungs above it).

    Below ``CHECK_ABOVE_CELLS`` cells, against the rung above: |F_2n - F_n| plus the error of F_2n,
    Richardson from n/2, n, 2n (``ladder``); for a force e(n) = C n^-p exactly that error, C n^-p.
    A coarse rung's own rungs below it, n/4 and n/2, are far from asymptotic where the bar slips, so
    Richardson from them reads a coarse rung's error short; the rung above is close enough to
    asymptotic that the difference to it bounds the error (``docs/validation.md``, "The element's
    estimate along the default FRF").  From
    ``CHECK_ABOVE_CELLS`` cells on (``check_above``), Richardson from n/4, n/2, n: the rung above would cost
    twice the rung itself at every estimated point.  inf wherever a solve failed.

    >>> at = lambda c: np.array([1.0 + 2.0 / c**2])
    >>> float(cells_error(16, at(16), at)[0]) * 16**2, float(cells_error(128, at(128), at)[0]) * 128**2
    (2.0, 2.0)
    """
    below = [] if n < check_above else [(c, at(c)) for c in (n // 4, n // 2) if c >= 2 and c < n]
    below = [(c, v) for c, v in below if v is not None]
    if n < check_above or not below:  # (from 128 cells on too where no rung below holds the harmonics)
        lower = at(n // 2) if n >= 4 else None
        fine = at(2 * n)
        if fine is None:
            return np.full(F.shape, np.inf)
        rungs, vals = ([n // 2], [lower]) if lower is not None else ([], [])
        e = above(F, fine, ladder((*rungs, n, 2 * n), vals + [F, fine], np.full(F.shape, np.inf)))
    else:
        e = ladder(tuple(c for c, _ in below) + (n,), [v for _, v in below] + [F], np.full(F.shape, np.inf))
    return np.where(np.isfinite(e), e, np.inf)


def harmonics_error(H: int, Hx: int, F: NDArray[np.float64], at: Callable[[int], NDArray[np.float64] | None],
                    alone: NDArray[np.float64]) -> NDArray[np.float64]:
    """The harmonics part of the estimate (N, component by component) of the force ``F`` with H harmonics, for a
    drive of ``Hx`` harmonics (no rung below it); ``at(h)`` is the force with h harmonics (nan where its solve
    failed, None where the cells cannot hold the h-th harmonic).

    Below ``CHECK_ABOVE_HARMONICS``, against the rung above: |F_2H+1 - F_H| plus the error of F_2H+1, Richardson
    from about H/2, H, 2H + 1 (``ladder``), as ``cells_error`` below 128 cells; where the cells cannot hold the
    rung above, and from ``CHECK_ABOVE_HARMONICS`` on, Richardson from about H/4, H/2, H with the observed order
    (with two rungs only, the last difference; with one, ``alone``: the decay of the harmonics kept).  inf
    wherever a solve failed.

    >>> at = lambda h: np.array([1.0 + 2.0 / h**4])
    >>> float(harmonics_error(7, 1, at(7), at, np.zeros(1))[0]) > 2.0 / 7**4 - 2.0 / 15**4
    True
    """
    fine = at(2 * H + 1) if H < CHECK_ABOVE_HARMONICS else None
    if fine is not None:
        low = max(lower_rung(H), Hx)
        rungs, vals = ([low], [at(low)]) if low < H else ([], [])
        e = np.abs(fine - F) + ladder((*rungs, H, 2 * H + 1), vals + [F, fine], np.full(F.shape, np.inf))
    else:
        hs = sorted({h for h in (max(lower_rung(lower_rung(H)), Hx), max(lower_rung(H), Hx)) if h < H})
        below = [at(h) for h in hs]
        e = ladder((*hs, H), below + [F], alone)
        if len(hs) == 2 and not asymptotic(tuple(hs) + (H,), np.array(below + [F])):
            fine = at(2 * H + 1)  # a harmonic below H met a mode of the bar: checked against the rung above
            if fine is not None and np.all(np.isfinite(fine)):
                e = above(F, fine, ladder((hs[1], H, 2 * H + 1), [below[1], F, fine], np.full(F.shape, np.inf)))
    return np.where(np.isfinite(e), e, np.inf)


def asymptotic(N: tuple[float, float, float], F: NDArray[np.float64]) -> bool:
    """Whether the values ``F`` (3, k) on the rungs ``N`` converge at an order Richardson trusts in every
    component: differences of one sign that shrink at an observed order in [``MIN_ORDER``, ``MAX_ORDER``]
    (or vanish).  Where a harmonic between two rungs meets a mode of the bar, a difference is large because
    the mode is met and the next small because it is resolved (an order above ``MAX_ORDER``), or the
    differences grow: such a ladder says nothing of what lies above its finest rung, and the guards of
    :func:`richardson` then read its first difference, which the finest rung has already resolved."""
    F = np.asarray(F, dtype=float)
    for j in range(F.shape[1]):
        d1, d2 = F[1, j] - F[0, j], F[2, j] - F[1, j]
        if d1 == 0.0 and d2 == 0.0:
            continue
        if d1 * d2 <= 0.0 or abs(d2) >= abs(d1) or not MIN_ORDER <= observed_order(N, abs(d1), abs(d2)) <= MAX_ORDER:
            return False
    return True


def above(F: NDArray[np.float64], fine: NDArray[np.float64], e_fine: NDArray[np.float64]) -> NDArray[np.float64]:
    """The error of ``F`` checked against the rung above it, ``fine``, whose own error ``e_fine`` is read from a
    ladder: |fine - F| plus ``e_fine``, the latter at most |fine - F| (the rung above is taken to be in the
    range where the differences at least halve from rung to rung, so its error is at most the difference to
    it; a ladder whose lowest rung is pre-asymptotic would otherwise lend the finest rung its coarse error)."""
    d = np.abs(fine - F)
    return d + np.minimum(e_fine, d)


def relative(error: NDArray[np.float64], F: NDArray[np.float64], floor: float) -> float:
    """max_j error_j / max(|F_j|, floor): the relative error of the validity map (``floor`` is
    ``FLOOR`` k* a in N).  Where the scale is 0 (no end motion: F = 0 and a = 0) an error of 0 is
    relative 0 (the answer is exact) and any other error is inf.

    >>> relative(np.zeros(2), np.zeros(2), 0.0), relative(np.array([0.0, 1e-9]), np.zeros(2), 0.0)
    (0.0, inf)
    """
    error = np.asarray(error, dtype=float)
    scale = np.maximum(np.abs(F), floor)
    zero_scale = np.where(error > 0.0, math.inf, 0.0)
    return float(np.max(np.divide(error, scale, out=zero_scale, where=scale > 0.0)))


def start_cells(bar: Bar, omega: float, H: int) -> int:
    """The first rung of the ladder of cells at ``omega`` with H harmonics: ``CELLS_PER_WAVELENGTH``
    cells on the wavelength 2 pi / sqrt(rho (H omega)^2 / E) of the highest harmonic and
    ``CELLS_PER_DECAY`` on the shear layer's decay length 1/lambda, at least ``MIN_START_CELLS``."""
    wave = math.sqrt(bar.rho / bar.E) * H * omega  # wave number of harmonic H (1/m)
    n = max(CELLS_PER_WAVELENGTH * bar.L * wave / (2.0 * math.pi), CELLS_PER_DECAY * bar.lam * bar.L,
            MIN_START_CELLS)
    return int(math.ceil(n))


def shortfall_message(shortfalls: list, tol: float, cells: str, harmonics: str) -> str:
    """The warning of a call of ``AllModeMicroslip`` that missed ``tol``: its worst point of the
    ``shortfalls`` ``(omega, a, relative estimate, [(cells, H, estimate) tried])`` and the rungs tried;
    ``cells``, ``harmonics``: how they were set (``"as given"``, ``"up to 640"``)."""
    omega, a, rel, tried = max(shortfalls, key=lambda s: s[2])
    rungs = ", ".join(f"{n} cells H = {h}: {e:.2g}" for n, h, e in tried)
    return (f"AllModeMicroslip: estimated relative error {rel:.3g} of (f_s, f_c) above tol = {tol:g} at omega = "
            f"{omega:.6g} rad/s, a = {a:.4g} m ({len(shortfalls)} point(s) of this call); tried {rungs}; cells "
            f"{cells}, harmonics {harmonics}")


def stuck_data(bar: Bar, disc_of: Callable, omega: float, n: int, fixed: bool, tol: float, linear: str,
               max_cells: int) -> tuple[int, float, float, float]:
    """``(cells, K, a_min, relative estimate of K)`` of the bar stuck everywhere at omega, from n cells on:
    exact segments, ``segments.exact_stuck`` (the continuous bar's K on any mesh); lumped, n cells if
    ``fixed``, else cells doubling from n until the Richardson estimates of the stuck stiffness (relative to
    max(|K|, 0.01 k*)) and of the slip onset a_min are below tol / 4 (at most ``max_cells``)."""
    from .segments import exact_stuck, stuck_end

    if linear == "exact":
        return exact_stuck(bar, disc_of, omega, n, max_cells)
    from ..numerics.waves import cells_for_phase

    floor = FLOOR * bar.k_star
    need = cells_for_phase(bar, omega, 1)
    while True:
        # a rung that cannot hold the wave is left out (the lumped bar refuses it: ``numerics.waves``); where
        # n itself cannot, the estimate is inf and n doubles (given cells: n is solved and refused by name)
        rungs = [c for c in (n // 4, n // 2) if c >= max(2, need)] + [n]
        vals = np.array([stuck_end(bar, disc_of(c), omega, linear) for c in rungs]) if n >= need or fixed \
            or 2 * n > max_cells else np.full((1, 2), math.inf)
        if len(rungs) == 3:
            e = richardson(tuple(rungs), vals)[0]
        else:
            e = np.abs(vals[-1] - vals[0]) if len(rungs) == 2 else np.full(2, math.inf)
        rel = e[0] / max(abs(vals[-1, 0]), floor)
        rel_a = relative(e[1:], vals[-1, 1:], 0.0) if math.isfinite(vals[-1, 1]) else 0.0  # a_min = 0: 0/0
        if fixed or max(rel, rel_a) <= 0.25 * tol or 2 * n > max_cells:
            return n, float(vals[-1, 0]), float(vals[-1, 1]), float(rel)
        n *= 2
