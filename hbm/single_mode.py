"""Forced response from one nonlinear mode (single nonlinear mode theory), its peak, and the
damper parameter that minimises the peak.

Near an isolated resonance the forced response ``M q'' + C q' + K q + f_nl = f cos(Omega t)`` is
taken on the mode's shape at the same modal amplitude, ``c_1 = a Psi_1 exp(i theta)``
(``Psi_1 = Psic_1 - i Psis_1``, ``hbm.modes``).  The first harmonic's balance projected on
``Psi_1`` (Galerkin), with the mode's own balance at (omega, D) substituted, is::

    A(Omega) a = Psi_1^H f exp(-i theta),
    A(Omega) = m1 (omega^2 - Omega^2) + i (c1 Omega + 2 D omega^2 m1 - c1 omega) + (Omega - omega) eta,

``m1 = Psi_1^H M Psi_1``, ``c1 = Psi_1^H C Psi_1``, ``eta = Psi_1^H (dF_1/domega) / a`` (the
contacts' frequency dependence, first order in ``Omega - omega``; zero for a rate-independent
law).  So ``a^2 |A(Omega)|^2 = |Psi_1^H f|^2``: a quartic in Omega at every point of the mode.
The viscous part ``c1`` scales with Omega, the contacts' part does not: for one DOF at H = 1 the
equation is the forced balance itself.  The peak is the largest ``a`` that has a solution:
``min_Omega |A|^2 = |Psi_1^H f|^2 / a^2``.  ``docs/nonlinear_modes.md`` derives it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np
from numpy.typing import NDArray

from . import continuation as cont
from ._validation import number_array
from .modes import ModeBalance, NonlinearModes
from .result import Peak


def frequency_term(bal: ModeBalance, y: NDArray, J: NDArray) -> NDArray:
    """``dF/domega / a`` (n L,) at the mode point ``y``, read off the omega column of its Jacobian ``J``."""
    N = bal.n * bal.L
    return J[:N, N] - bal.operator(float(y[N]), float(y[N + 1]))[1] @ y[:N]


def coefficients(bal: ModeBalance, y: NDArray, fw: NDArray, force: NDArray, dof: int
                 ) -> tuple[NDArray, NDArray, float, float]:
    """At the mode point ``y`` (physical; ``fw`` its :func:`frequency_term`): the real and imaginary
    parts of ``A(Omega)`` as polynomial coefficients (highest first), ``r = |Psi_1^H f| / a`` and the
    response amplitude ``a |Psi_1[dof]|``."""
    n, L = bal.n, bal.L
    N = n * L
    omega, D, a = float(y[N]), float(y[N + 1]), 10.0 ** float(y[N + 2])
    psi = y[:N].reshape(n, L)
    P1 = psi[:, 1] - 1j * psi[:, 2]
    Fw = fw.reshape(n, L)
    eta = complex(np.conj(P1) @ (Fw[:, 1] - 1j * Fw[:, 2]))
    m1 = float(np.real(np.conj(P1) @ bal.M @ P1))
    c1 = float(np.real(np.conj(P1) @ bal.C @ P1))
    re = np.array([-m1, eta.real, m1 * omega ** 2 - omega * eta.real])
    im = np.array([c1 + eta.imag, 2.0 * D * omega ** 2 * m1 - c1 * omega - omega * eta.imag])
    return re, im, abs(complex(np.conj(P1) @ force)) / a, a * abs(P1[dof])


def _squared(re: NDArray, im: NDArray) -> NDArray:
    """``|A(Omega)|^2`` as a quartic's coefficients."""
    return np.polymul(re, re) + np.concatenate([[0.0, 0.0], np.polymul(im, im)])


def closest_minimum(re: NDArray, im: NDArray, omega: float) -> tuple[float, float]:
    """``(Omega*, |A(Omega*)|^2)``: the minimum of ``|A|^2`` nearest to ``omega``."""
    q = _squared(re, im)
    roots = np.roots(np.polyder(q))
    real = roots[np.abs(roots.imag) <= 1e-9 * max(1.0, abs(omega))].real
    real = real[np.polyval(np.polyder(q, 2), real) > 0.0]
    w = float(real[np.argmin(np.abs(real - omega))])
    return w, float(np.polyval(q, w))


def peak_condition(re: NDArray, im: NDArray, r: float, omega: float) -> float:
    """``min_Omega |A|^2 / r^2 - 1``: negative below the peak's modal amplitude, zero at it.  Where ``r^2``
    leaves double precision (a force of 1e-300 or 1e300 N) the ratio is formed as ``(sqrt(min |A|^2) / r)^2``:
    inf for an ``r`` of zero (the point is above the peak), -1 for an infinite one (below it)."""
    m = closest_minimum(re, im, omega)[1]
    r2 = r * r
    if 0.0 < r2 < math.inf:
        return m / r2 - 1.0
    q = math.sqrt(max(m, 0.0)) / r if r > 0.0 else math.inf
    return q * q - 1.0


@dataclass
class ModalFRF:
    """The forced response from one mode: ``omega`` and ``amplitude`` (the response DOF's first
    harmonic) on both flanks (``side`` -1 below, +1 above the peak), the modal amplitude of each
    point, and the peak (located on the mode between its points)."""

    omega: NDArray[np.float64]
    amplitude: NDArray[np.float64]
    modal_amplitude: NDArray[np.float64]
    side: NDArray[np.int_]
    peak: Peak
    peak_modal_amplitude: float
    peak_point: NDArray[np.float64]  #: the mode's unknowns (Psi, omega, D, log10 a) at the peak


def forced_response(modes: NonlinearModes, *, force: Sequence[float] | None = None,
                    response_dof: int | None = None) -> ModalFRF:
    """Single nonlinear mode theory: the forced response near the mode (module docstring).

    Parameters
    ----------
    modes : NonlinearModes
        The mode from :func:`hbm.nonlinear_modes`, traced past the peak's amplitude.
    force : array_like, optional
        The force amplitudes (``f cos(Omega t)``); default the structure's ``force``.
    response_dof : int, optional
        Default the forced DOF.

    Raises
    ------
    ValueError
        The mode does not reach the peak's amplitude (the forcing needs a larger amplitude_range).
    """
    if not isinstance(modes, NonlinearModes):
        raise ValueError(f"modes must be the result of hbm.nonlinear_modes (a NonlinearModes), got modes={modes!r}")
    bal = modes.balance
    f, dof = forcing(bal, force, response_dof)
    N = bal.n * bal.L
    rows, g = [], []
    for y in modes.points:
        re, im, r, resp = coefficients(bal, y, frequency_term(bal, y, bal(y)[1]), f, dof)
        g.append(peak_condition(re, im, r, float(y[N])))
        if not 0.0 < r * r < math.inf:  # the forcing's r^2 out of double precision: no flank point here
            continue
        rq = _squared(re, im)
        rq[-1] -= r * r
        roots = np.roots(rq)
        for w in roots[np.abs(roots.imag) <= 1e-7 * abs(roots)].real:
            if w > 0.0:
                rows.append((w, resp, 10.0 ** y[-1], float(y[N])))
    g = np.array(g)
    above = np.flatnonzero((g[:-1] <= 0.0) & (g[1:] > 0.0))
    if above.size == 0:
        where = ("below the branch's first amplitude (a smaller amplitude_range[0], or a larger force)"
                 if g.size and g[0] > 0.0 else
                 "beyond the branch's last amplitude (a larger amplitude_range[1], or a smaller force)")
        raise ValueError(f"modes must reach the peak's modal amplitude (the peak condition changes sign "
                         f"nowhere on the branch: the peak lies {where}), got amplitudes "
                         f"{modes.amplitude[0]:.4g}..{modes.amplitude[-1]:.4g} with a force of max |f| = {np.max(np.abs(f)):.4g} N"
                         if len(modes) else "modes must reach the peak's modal amplitude, got a mode of no points")
    y_peak = locate_peak(bal, modes.points[above[0]], modes.points[above[0] + 1], f, dof)
    re, im, r, resp = coefficients(bal, y_peak, frequency_term(bal, y_peak, bal(y_peak)[1]), f, dof)
    w_peak = closest_minimum(re, im, float(y_peak[N]))[0]
    rows = np.array([row for row in rows if row[2] <= 10.0 ** y_peak[-1]]).reshape(-1, 4)
    side = np.where(rows[:, 0] < w_peak, -1, 1)
    order = np.lexsort((rows[:, 0], side))
    return ModalFRF(omega=rows[order, 0], amplitude=rows[order, 1], modal_amplitude=rows[order, 2],
                    side=side[order], peak=Peak(float(w_peak), float(resp)), peak_modal_amplitude=10.0 ** float(y_peak[-1]), peak_point=y_peak)


def locate_peak(bal: ModeBalance, ya: NDArray, yb: NDArray, force: NDArray, dof: int) -> NDArray:
    """The mode point between ``ya`` and ``yb`` (physical) where the peak condition vanishes."""
    N = bal.n * bal.L

    def g(u, t):
        y = u * bal.uw
        re, im, r, _ = coefficients(bal, y, frequency_term(bal, y, bal(y)[1]), force, dof)
        return peak_condition(re, im, r, float(y[N]))

    loc = cont.locate(bal.scaled, ya / bal.uw, yb / bal.uw, g, tol=1e-10, xtol=1e-12)
    if loc is None:
        raise ValueError("the peak could not be located on the mode between its points")
    return loc.y * bal.uw


def forcing(bal: ModeBalance, force, response_dof) -> tuple[NDArray, int]:
    s = bal.structure
    if force is None and np.iscomplexobj(s.force):
        raise ValueError("force must be real for the single-mode forced response (a phase per DOF is not "
                         "provided here; hbm.frequency_response takes it), got a complex structure force")
    try:  # numbers only: a bool (True read as 1 N) or a string is refused below, naming force
        f = s.force if force is None else number_array("force", force).ravel()
    except ValueError:
        f = np.empty(0)
    if f.size != s.n or not np.all(np.isfinite(f)) or not np.any(f):
        raise ValueError(f"force must be {s.n} finite numbers, not all zero, got force={force!r}")
    return f, s.response_dof(response_dof, f)


__all__ = ["forced_response", "ModalFRF", "frequency_term", "coefficients", "closest_minimum", "peak_condition", "locate_peak"]
