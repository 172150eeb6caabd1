"""The all-mode peak of a blade with a microslip damper: the physical answer at its resonance, with its error.

The single-mode damper neglects the phase differences along the bar, which at a blade's peak can
put it off the bar with every mode by more than a response tolerance (``docs/validation.md``, "The
default job's all-mode peak"); an all-mode FRF to a tolerance costs hundreds of times the
single-mode one, because the element must meet the tolerance at every evaluation, also where a
harmonic of the drive meets a mode of the bar.  The answer the job reports is the peak, so this
module computes the all-mode peak directly and estimates the error of that number itself.

**One frequency.**  The blade (one DOF, mass m, stiffness k, damping c, force F cos(omega t)) at
H = 1 with the damper's first harmonic: for x = a sin(theta) the damper force is
f_s sin(theta) + f_c cos(theta) + (higher harmonics), so the balance of the sine and cosine parts
gives the amplitude equation

    g(a) = P^2 + Q^2 - F^2 = 0,    P = (k - m omega^2) a + f_s(a, omega),   Q = c omega a + f_c(a, omega),

solved by Newton's method with dg/da = 2 P (k - m omega^2 + df_s/da) + 2 Q (c omega + df_c/da), the
derivatives exact (the nested balance's Jacobian, ``AllModeMicroslip.solve``), steps limited to
``MAX_STEP`` of a, to ``AMPLITUDE_RTOL``.  The bar is solved on one rung (cells n, harmonics H) per call.
The sampled bar's f(a) is piecewise smooth, with a kink wherever one more sample of a node starts
to slip; on fine rungs (128 cells, H = 31) the kinks are so dense that the local derivative is
not the slope of g over a Newton step, and Newton with it converges only linearly.  So from the
second iterate on, where the secant through the last two iterates differs from the local dg/da by
more than 25 % (and has its sign), the secant's slope is taken.  Below about 1e-7 of a the kinks make g non-monotone, so a bracketed
root is closed by bisection to ``AMPLITUDE_RTOL`` (1e-8, far below the differences between rungs' peaks,
so the peaks compared in the estimate are the rungs' and not the root finder's).

**The peak.**  a(omega) is scanned on the cheap rung ``SCAN`` around the single-mode peak (``SPAN``,
step ``SCAN_STEP``); on each rung the largest scanned point is refined by a parabola through three
frequencies h = ``REFINE_STEP`` omega apart (re-centred while the vertex leaves the middle
interval), starting from the peak of the nearest rung already refined; the peak is the vertex.
The scan runs on the first rung's cells (16) and the middle harmonics (15, which hold the 13th, where
the notch below comes from): its largest point is where the first refinement, 16 cells at H = 31, starts,
and on those cells 15 and 31 harmonics put their largest scanned point at the same frequency
(``docs/validation.md``, "The default job's all-mode peak"), so the cheaper 15 suffice for the scan.
Where the 13th harmonic meets a mode of the bar the response has a notch, which leaves a lower local
maximum on its left; the bar's exact segments keep that maximum below the peak on the scan's cells, so
the largest scanned point is on the peak's hill, and each finer rung starts from the previous rung's
peak, right of its notch (``docs/validation.md``, "The all-mode bar's exact segments against lumped
masses").

**The estimate.**  The cells part is the element's (``contact_models.allmode.cells_error``) on the peak
amplitudes at H = 31, read against the rung above on every rung: the change to 2n plus the Richardson error
of 2n from n/2, n, 2n (the element reads a rung of 128 cells or more from n/4, n/2, n instead, to save a
solve at every estimated point of a curve; here the rung above costs a few amplitude solves only, and from
the rungs below the peak's cells part reads short: ``docs/validation.md``, "The all-mode bar's exact
segments against lumped masses").  The harmonics part: H = 7, 15, 31 (at min(n,
``HARMONICS_CELLS``) cells) through ``richardson`` (observed order, guarded;
``contact_models.allmode.richardson``), never below what order 1 predicts (``_harmonics_part``).  The two
parts add, relative to the peak amplitude.  Cells double (to ``MAX_CELLS``) while the sum is above the
tolerance.  The sources this search does not resolve
(the blade's own higher harmonics, AFT sampling, the element evaluation, the peak's location) come
from the single-mode curve's estimate at its peak (``other``) and are added.  Checked against a converged reference in
``docs/validation.md`` ("The default blade with the all-mode damper").
"""

from __future__ import annotations

import math
import warnings
from typing import Any, NamedTuple

import numpy as np

from contact_models import AllModeMicroslip
from contact_models.accuracy import AccuracyWarning
from contact_models.allmode import cells_error, richardson
from contact_models.numerics.checks import nonnegative, positive

__all__ = ["AllModePeak", "allmode_peak", "physical_peak", "amplitude_at", "SCAN", "SPAN", "SCAN_STEP", "CELLS", "HARMONICS",
           "MAX_CELLS", "MAX_STEP", "AMPLITUDE_RTOL", "REFINE_STEP", "HARMONICS_CELLS"]

#: The rung the scan for the peak runs on (cells, harmonics).
SCAN = (16, 15)
#: The scan covers the single-mode peak frequency times (1 - SPAN[0], 1 + SPAN[1]), in steps SCAN_STEP (relative).
SPAN = (0.004, 0.006)
SCAN_STEP = 1e-3
#: The parabolas' half-width on every rung (relative to the single-mode peak frequency).
REFINE_STEP = 2.5e-4
#: The finest rung to start from (cells, harmonics = the top of the harmonic ladder 7, 15, 31).
CELLS = 64
HARMONICS = 31
#: The harmonics part of the estimate is taken on at most this many cells: it hardly depends on them,
#: so finer cells would only make the three harmonics rungs dearer (``docs/validation.md``, "The
#: default job's all-mode peak").
HARMONICS_CELLS = 64
#: Cells double up to this while the estimate is above the tolerance.
MAX_CELLS = 256
#: Newton steps on the amplitude are limited to this fraction of it; it is converged to AMPLITUDE_RTOL
#: (the sampled bar's g(a) is not monotone below about 1e-7 of a on 128 cells: the module docstring).
MAX_STEP = 0.02
AMPLITUDE_RTOL = 1e-8


class AllModePeak(NamedTuple):
    """The all-mode peak: ``omega`` (rad/s), ``amplitude`` (m), ``error`` (relative estimate of the
    amplitude), ``parts`` (``{"cells": ..., "harmonics": ...}``, relative), ``cells``, ``harmonics``
    (the finest rung), ``rungs`` (``{(cells, H): (omega, amplitude)}``: the peak on every rung),
    ``scan`` (frequencies and amplitudes of the scan, on ``SCAN``, where it converged)."""

    omega: float
    amplitude: float
    error: float
    parts: dict
    cells: int
    harmonics: int
    rungs: dict
    scan: tuple


def amplitude_at(blade: Any, element: AllModeMicroslip, omega: float, a0: float, max_iter: int = 60) -> float:
    """The blade's amplitude at one frequency with the damper at H = 1 (the amplitude equation).

    Parameters
    ----------
    blade : hbm.Blade
        The one-DOF blade (``mass``, ``stiffness``, ``damping``, ``force``).
    element : AllModeMicroslip
        The damper on one rung (``cells`` and ``harmonics`` given); anything with its ``solve(a,
        omega)`` returning ``success``, ``f_s``, ``f_c`` and ``dF_dX``.
    omega : float
        Frequency (rad/s).
    a0 : float
        Start amplitude (m), > 0.
    max_iter : int
        Newton iterations at most.

    Returns
    -------
    float
        The amplitude (m) solving g(a) = 0 (module docstring), converged to ``AMPLITUDE_RTOL``
        (Newton's method, with the secant's slope where the local derivative misses the bar's kinks,
        safeguarded by bisection once a sign change of g is bracketed: the bar's f(a) has kinks where
        one more cell starts to slip, where plain Newton can cycle).

    Raises
    ------
    FloatingPointError
        Where the bar's balance or this iteration does not converge (numerical trouble, not bad input).
    """
    k_dyn = blade.stiffness - blade.mass * omega * omega
    cw = blade.damping * omega
    a, lo, hi = a0, None, None  # lo: g < 0 (below the root), hi: g > 0
    last = None  # (a, g) of the previous iterate: the secant's slope
    for _ in range(max_iter):
        sol = element.solve(a, omega)
        if not sol.success:
            raise FloatingPointError(f"the all-mode bar did not converge at omega = {omega:.6g} rad/s, a = {a:.4g} m")
        P = k_dyn * a + sol.f_s
        Q = cw * a + sol.f_c
        g = P * P + Q * Q - blade.force ** 2
        if g < 0.0:
            lo = a if lo is None else max(lo, a)
        else:
            hi = a if hi is None else min(hi, a)
        dg = 2.0 * P * (k_dyn + sol.dF_dX[2, 2]) + 2.0 * Q * (cw + sol.dF_dX[1, 2])
        if last is not None and last[0] != a:  # the secant: the local slope misses the kinks (docstring)
            secant = (g - last[1]) / (a - last[0])
            dg = secant if secant * dg > 0.0 and not 0.8 < secant / dg < 1.25 else dg
        last = (a, g)
        step = -g / dg if dg != 0.0 else math.nan
        step = max(-MAX_STEP * a, min(MAX_STEP * a, step)) if math.isfinite(step) else MAX_STEP * a
        new = a + step
        if lo is not None and hi is not None:
            if not min(lo, hi) < new < max(lo, hi):
                new = 0.5 * (lo + hi)
            if abs(hi - lo) <= AMPLITUDE_RTOL * a:
                return 0.5 * (lo + hi)
        if abs(new - a) <= AMPLITUDE_RTOL * a:
            return new
        a = new
    raise FloatingPointError(f"the amplitude equation did not converge at omega = {omega:.6g} rad/s in {max_iter} "
                             "iterations")


def _vertex(w: tuple, A: tuple) -> tuple[float, float]:
    """The vertex (omega, value) of the parabola through three equally spaced points."""
    h = w[1] - w[0]
    d2 = A[0] - 2.0 * A[1] + A[2]
    if not d2 < 0.0:
        i = int(np.argmax(A))
        return w[i], A[i]
    s = 0.5 * (A[0] - A[2]) / d2
    return w[1] + s * h, A[1] - 0.125 * (A[0] - A[2]) ** 2 / d2


def _refine(blade, element, w0: float, a0: float, h: float, shape: Any = None) -> tuple[float, float, Any]:
    """The peak of a(omega) on one rung near (w0, a0): the vertex of the parabola through three
    frequencies h apart, re-centred on the largest while the vertex leaves the middle interval.
    Returns the vertex and the last parabola (a function of omega).  ``shape`` (a previous rung's
    parabola) predicts how a changes between frequencies: each amplitude's Newton starts from the
    nearest one found plus that change (the rungs' curves differ in level far more than in shape)."""
    cache: dict = {}

    def amp(w):
        if w not in cache:
            near = min(cache, key=lambda x: abs(x - w)) if cache else None
            start = a0 if near is None else cache[near] + (shape(w) - shape(near) if shape is not None else 0.0)
            cache[w] = amplitude_at(blade, element, w, start)
        return cache[w]

    centre = w0
    for _ in range(12):
        pts = (centre - h, centre, centre + h)
        vals = tuple(amp(w) for w in pts)
        wv, av = _vertex(pts, vals)
        if abs(wv - centre) <= h:
            break
        centre = pts[int(np.argmax(vals))]
    return wv, av, _parabola(pts, vals)


def _parabola(w: tuple, A: tuple) -> Any:
    """The parabola through three equally spaced points, as a function of omega."""
    h = w[1] - w[0]
    slope, curve = (A[2] - A[0]) / (2.0 * h), (A[0] - 2.0 * A[1] + A[2]) / (2.0 * h * h)
    return lambda x: A[1] + slope * (x - w[1]) + curve * (x - w[1]) ** 2


def _scan(blade, bar, load, w_single: float, a_single: float) -> tuple[np.ndarray, np.ndarray]:
    """The frequencies and amplitudes of the scan where the amplitude equation converged."""
    el = AllModeMicroslip(bar, load, cells=SCAN[0], harmonics=SCAN[1])
    ws, As = [], []
    for w in w_single * (1.0 + np.arange(-SPAN[0], SPAN[1] + 0.5 * SCAN_STEP, SCAN_STEP)):
        if len(ws) >= 2:  # the secant through the last two points predicts the next
            a0 = As[-1] + (As[-1] - As[-2]) * (w - ws[-1]) / (ws[-1] - ws[-2])
        else:
            a0 = As[-1] if As else a_single
        try:
            As.append(amplitude_at(blade, el, float(w), a0))
            ws.append(float(w))
        except FloatingPointError:  # a frequency the scan passes over; the peak is refined elsewhere
            continue
    return np.array(ws), np.array(As)


def _harmonics_part(ladder: list) -> float:
    """The relative harmonics part from the peak on H = 7, 15, 31: Richardson with the observed order,
    never below what order 1 predicts, |d_2| / (31/15 - 1).  The harmonics converge irregularly at this
    peak: each higher rung brings a harmonic to another mode of the bar (13 meets the second, about 39
    the fifth), so the order observed on 7, 15, 31 says little about 31 -> 47 -> 63."""
    e = float(richardson((7, 15, HARMONICS), np.array(ladder)[:, None])[0][0])
    return max(e, abs(ladder[2] - ladder[1]) / (HARMONICS / 15 - 1.0)) / ladder[-1]


def allmode_peak(blade: Any, bar: Any, load: Any, w_single: float, a_single: float, tol: float,
                 other: float = 0.0) -> AllModePeak:
    """The peak of the blade with ``AllModeMicroslip(bar, load)`` and its relative error estimate.

    Parameters
    ----------
    blade : hbm.Blade
        The one-DOF blade.
    bar : contact_models.Bar
        The damper bar.
    load : contact_models.UniformLoad or any load of ``AllModeMicroslip``
        Its normal load.
    w_single, a_single : float
        The single-mode peak (rad/s, m), > 0: where the scan is centred and starts.
    tol : float
        The relative error of the peak amplitude aimed at, in (0, 1): cells double (to ``MAX_CELLS``)
        while the estimate (``other`` included) is above it.
    other : float, optional
        The relative error of the peak amplitude from the sources this search does not resolve (the
        blade's own higher harmonics, AFT sampling, the element evaluation, the peak's location: the
        curve's estimate at its peak, ``FrequencyResponse.error_sources``), >= 0: added to the
        estimate as the part ``"other"``.  Default 0.

    Returns
    -------
    AllModePeak
        The peak on the finest rung, the estimate and its parts, and the peak on every rung.

    Raises
    ------
    ValueError
        ``w_single``, ``a_single`` not positive and finite, ``tol`` outside (0, 1), or ``other`` negative.
    FloatingPointError
        Where the amplitude equation does not converge near the peak.
    """
    w_single, a_single, tol = positive("w_single", w_single), positive("a_single", a_single), positive("tol", tol)
    if not tol < 1.0:
        raise ValueError(f"tol must be in (0, 1), got tol={tol!r}")
    other = nonnegative("other", other)
    ws, As = _scan(blade, bar, load, w_single, a_single)
    if not As.size:
        raise FloatingPointError("the all-mode amplitude did not converge on the scan around the peak")
    i = int(np.argmax(As))
    w0, a0 = float(ws[i]), float(As[i])
    h = REFINE_STEP * w_single
    rungs: dict = {}
    shapes: dict = {}  # the last parabola of every rung refined

    def peak(n, H):
        if (n, H) not in rungs:  # start from the closest rung already refined (the peak moves little)
            near = max(rungs, key=lambda r: (r[1] == H, -abs(math.log(r[0] / n))), default=None)
            ws_, as_ = rungs[near] if near is not None else (w0, a0)
            w_, a_, shapes[(n, H)] = _refine(blade, AllModeMicroslip(bar, load, cells=n, harmonics=H), ws_, as_, h,
                                             shapes.get(near))
            rungs[(n, H)] = (w_, a_)
        return rungs[(n, H)]

    n = CELLS
    while True:
        a_n = peak(n, HARMONICS)[1]
        e_c = float(cells_error(n, np.array([a_n]), lambda c: np.array([peak(c, HARMONICS)[1]]), math.inf)[0]) / a_n
        ladder_h = [peak(min(n, HARMONICS_CELLS), H)[1] for H in (7, 15, HARMONICS)]
        e_h = _harmonics_part(ladder_h)
        if e_c + e_h + other <= tol or 2 * n > MAX_CELLS:
            break
        n *= 2
    w, a = peak(n, HARMONICS)
    return AllModePeak(w, a, e_c + e_h + other, {"cells": e_c, "harmonics": e_h, "other": other}, n, HARMONICS,
                       dict(rungs), (ws, As))


def physical_peak(frf: Any, share: float = 0.5) -> AllModePeak | None:
    """The all-mode peak where the single-mode damper of a blade's FRF is too far off it, else None.

    ``frf`` is a blade's :class:`hbm.FrequencyResponse` with one element whose refined model
    (``ContactElement.refined_model``) is the all-mode bar (a single-mode microslip bar), and its
    error estimate.  Where the model source of the estimate at the sampled maximum exceeds
    ``share * frf.tol``, the peak is solved again with the bar with every mode
    (:func:`allmode_peak`, centred on ``frf.peak()``), the other sources of the curve's estimate there
    added to its own; otherwise (or for any other FRF: a structure, no estimate, no refined model, a
    failed run) None, and the curve's own peak stands.

    Numerical trouble is said, not raised: where the all-mode amplitude equation does not converge
    near the peak, an ``AccuracyWarning`` says so and None is returned (the single-mode peak stands);
    where the all-mode peak's own estimate is above the tolerance, an ``AccuracyWarning`` says that
    too (the finest rungs reached).
    """
    el = frf.element
    refined = el.refined_model() if el is not None and not el.discretised else None
    if (not frf.success or not len(frf) or frf.tol is None or not frf._problem.one_dof
            or not isinstance(refined, AllModeMicroslip)):
        return None
    i = int(np.argmax(frf.amplitude))
    if float(frf.error_sources["model"][i]) <= share * frf.tol:
        return None
    other = sum(float(v[i]) for k, v in frf.error_sources.items() if k != "model")
    pk = frf.peak()
    try:
        best = allmode_peak(frf.blade, refined.bar, refined.load, pk.omega, pk.amplitude, frf.tol, other)
    except FloatingPointError as exc:  # numerical trouble: the single-mode answer stands, said so
        warnings.warn(f"the all-mode peak was not found ({exc}); the peak is the single-mode one", AccuracyWarning,
                      stacklevel=2)
        return None
    if best.error > frf.tol:
        warnings.warn(f"the all-mode peak's estimated error {best.error:.2g} is above tol = {frf.tol:g} "
                      f"({best.cells} cells, H = {best.harmonics}, the finest rungs)", AccuracyWarning, stacklevel=2)
    return best
