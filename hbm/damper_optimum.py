"""The damper parameter (normal load, or any scalar) that minimises the resonance peak, in one run.

The peak of single nonlinear mode theory (``hbm.single_mode``) is a point of the nonlinear mode
where the peak condition ``g = min_Omega |A(Omega)|^2 a^2 / |Psi_1^H f|^2 - 1`` vanishes.  With
the damper's parameter ``p`` as one more unknown, the mode's balance (``hbm.modes``) and ``g = 0``
define a curve ``(Psi, omega, D, log10 a, p)``: the peak followed in the parameter.  It is traced
by ``hbm.continuation`` from the peak at the first bound, and the optimum is the point where the
response amplitude ``a |Psi_1[dof]|`` is stationary along the curve (``hbm.continuation.locate``).
The Jacobian's p-column, ``g``'s entry included, is a forward difference (the elements rebuilt at
``p + h``, ``h = FD_STEP max(|p|, s)``, ``s`` the magnitude of the bound nearer zero, at least 1e-6 of the
bracket: a step by the bracket's width would be 0.1 N for a bracket of 1e6 N); ``g``'s row is a forward
difference in the mode's unknowns with the contacts' frequency term held.  The stationary point is
located with the tangent from this Jacobian: on the default blade the optimum load is within 2e-6 of
the minimum of a dense scan of FRF peaks, by a bracket of (30, 90) N as by (30, 1e6) N.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, Sequence

import numpy as np
from numpy.typing import NDArray

from . import continuation as cont
from ._validation import NEWTON_TOL, count, finite, newton_tolerance, positive, relative_tolerance
from .modes import ModeBalance, nonlinear_modes
from .result import Peak
from .single_mode import closest_minimum, coefficients, forced_response, forcing, frequency_term, peak_condition

#: Relative step of the forward differences in the parameter and in the mode's unknowns.
FD_STEP = 1e-7


@dataclass
class DamperOptimum:
    """The optimum ``parameter`` and its ``peak`` (frequency and response amplitude), the traced
    peak curve (``parameters``, ``peaks``: response amplitude, ``peak_omega``), and how it went."""

    parameter: float
    peak: Peak
    parameters: NDArray[np.float64]
    peaks: NDArray[np.float64]
    peak_omega: NDArray[np.float64]
    success: bool
    message: str
    nsteps: int
    nfev: int


class _PeakCurve:
    """``R(z)`` of the peak followed in the parameter: ``z = (y / uw, p / p_ref)``."""

    def __init__(self, make: Callable[[float], ModeBalance], uw: NDArray, rw: NDArray, p_ref: float,
                 force: NDArray, dof: int, p_scale: float) -> None:
        self.make, self.uw, self.rw, self.p_ref = make, uw, rw, p_ref
        self.force, self.dof, self.p_scale = force, dof, p_scale
        self.nfev = 0

    def parts(self, z: NDArray) -> tuple[ModeBalance, NDArray, NDArray, NDArray, NDArray, float]:
        p = float(z[-1]) * self.p_ref
        bal = self.make(p)
        y = z[:-1] * self.uw
        R, J = bal(y)
        self.nfev += 1
        return bal, y, R, J, frequency_term(bal, y, J), p

    def g(self, bal: ModeBalance, y: NDArray, fw: NDArray) -> float:
        re, im, r, _ = coefficients(bal, y, fw, self.force, self.dof)
        return peak_condition(re, im, r, float(y[bal.n * bal.L]))

    def __call__(self, z: NDArray) -> tuple[NDArray, NDArray]:
        bal, y, R, J, fw, p = self.parts(z)
        m = R.size
        h = FD_STEP * max(abs(p), self.p_scale)  # (by the bracket's width, a wide bracket's step was coarse)
        bal_h = self.make(p + h)
        R_h, J_h = bal_h(y)
        self.nfev += 1
        out_R = np.empty(m + 1)
        out_J = np.zeros((m + 1, z.size))
        out_R[:m] = R / self.rw
        out_J[:m, :-1] = J * self.uw[None, :] / self.rw[:, None]
        out_J[:m, -1] = (R_h - R) / h * self.p_ref / self.rw
        g0 = self.g(bal, y, fw)
        out_R[m] = g0
        out_J[m, -1] = (self.g(bal_h, y, frequency_term(bal_h, y, J_h)) - g0) / h * self.p_ref  # (the tangent's p part)
        N = bal.n * bal.L
        for k in np.concatenate([np.arange(bal.n) * bal.L + 1, np.arange(bal.n) * bal.L + 2, [N, N + 1, N + 2]]):
            yk = y.copy()
            dk = FD_STEP * self.uw[k]
            yk[k] += dk
            out_J[m, k] = (self.g(bal, yk, fw) - g0) / dk * self.uw[k]
        return out_R, out_J

    def amplitude(self, z: NDArray, bal: ModeBalance) -> tuple[float, NDArray]:
        """The response amplitude ``a |Psi_1[dof]|`` at ``z`` and its gradient in ``z``."""
        L, d = bal.L, self.dof
        y = z[:-1] * self.uw
        a = 10.0 ** float(y[-1])
        c, s = y[d * L + 1], y[d * L + 2]
        mag = math.hypot(c, s)
        grad = np.zeros(z.size)
        grad[d * L + 1] = a * c / mag * self.uw[d * L + 1]
        grad[d * L + 2] = a * s / mag * self.uw[d * L + 2]
        grad[-2] = math.log(10.0) * a * mag
        return a * mag, grad


def damper_optimum(system: Any, contacts_of: Callable[[float], Any], bounds: Sequence[float], *,
                   amplitude_range: Sequence[float], mode: int = 0, harmonics: int = 1, n_t: int | None = None,
                   force: Sequence[float] | None = None, response_dof: int | None = None,
                   max_step: float = 0.05, max_steps: int = 500, newton_tol: float = NEWTON_TOL,
                   tol: float | None = None) -> DamperOptimum:
    """The damper parameter in ``bounds`` that minimises the resonance peak of mode ``mode``.

    Parameters
    ----------
    system : hbm.Structure or hbm.Blade
    contacts_of : callable
        ``contacts_of(p)``: the contacts (as :func:`hbm.nonlinear_modes` takes them) at the
        parameter value ``p`` (e.g. the normal load).
    bounds : (p0, p1)
        The parameter's range, ``p0 < p1``; the peak is followed from ``p0``.
    amplitude_range : (a0, a1)
        Modal amplitudes of the mode traced at ``p0`` to find its peak (must contain it).
    mode, harmonics, n_t
        As :func:`hbm.nonlinear_modes`.
    force, response_dof
        As :func:`hbm.single_mode.forced_response`.
    max_step, max_steps, newton_tol
        Continuation of the peak in ``(Psi, omega, D, log10 a, p / (p1 - p0))``, its Newton tolerance.  The
        optimum is located to the accuracy of the curve's tangent (module docstring: about 2e-6 relative on
        the default blade, whatever the bracket), not to ``newton_tol``.
    tol : float, optional
        The earlier name of ``newton_tol``, read for one release with a ``DeprecationWarning`` (in
        :func:`hbm.frequency_response` ``tol`` is the answer's target error).

    Returns
    -------
    DamperOptimum
        The optimum on the traced peak curve.  Where the trace stopped short of ``p1`` (its step budget
        ``max_steps``, an element that raised) with the peak still falling, ``success`` is False and
        ``parameter``, ``peak`` are the last traced point's (not interior, not converged), the curve traced so
        far kept, ``message`` saying where and why it stopped.

    Raises
    ------
    ValueError
        Bad bounds or contacts_of (a bound at which ``contacts_of`` raises ``ValueError`` names ``bounds``);
        the response amplitude has no interior minimum on the traced curve (the optimum lies at or beyond a
        bound: the message names the bound).
    """
    if not callable(contacts_of):
        raise ValueError(f"contacts_of must be a function parameter -> contacts, got contacts_of={contacts_of!r}")
    try:
        p0, p1 = (finite(f"bounds[{i}]", v) for i, v in enumerate(bounds))
    except (TypeError, ValueError) as exc:
        raise ValueError(f"bounds must be a pair p0 < p1, got bounds={bounds!r}") from exc
    if not p0 < p1:
        raise ValueError(f"bounds must have p0 < p1, got bounds={bounds!r}")
    # the peak curve's controls, before the mode is traced (that would fail first, and say something else)
    tol = relative_tolerance("newton_tol", newton_tolerance("damper_optimum", newton_tol, tol), 1.0)
    max_step, max_steps = positive("max_step", max_step), count("max_steps", max_steps)
    first, _ = (_contacts_at(contacts_of, p, bounds) for p in (p0, p1))  # each bound builds its contacts
    modes = nonlinear_modes(system, first, mode=mode, amplitude_range=amplitude_range,
                            harmonics=harmonics, n_t=n_t)
    bal0 = modes.balance
    f, dof = forcing(bal0, force, response_dof)
    y_peak = forced_response(modes, force=f, response_dof=dof).peak_point
    H, nt, phase = bal0.H, bal0.n_t, bal0.phase_dof

    def make(p: float) -> ModeBalance:
        bal = ModeBalance(system, contacts_of(p), harmonics=H, n_t=nt, phase_dof=phase)
        bal.uw, bal.rw = bal0.uw, bal0.rw
        return bal

    p_ref = p1 - p0
    curve = _PeakCurve(make, bal0.uw, bal0.rw, p_ref, f, dof, max(min(abs(p0), abs(p1)), 1e-6 * p_ref))
    z0 = np.concatenate([y_peak / bal0.uw, [p0 / p_ref]])
    res = cont.continuation(curve, z0, parameter=-1, bounds=(p0 / p_ref, p1 / p_ref), tol=tol,
                            max_step=max_step, max_steps=max_steps, locate_folds=False, from_bound=True)
    amps = np.array([curve.amplitude(z, bal0)[0] for z in res.y])
    i = int(np.argmin(amps))
    omegas = res.y[:, bal0.n * bal0.L] * bal0.uw[bal0.n * bal0.L]
    if i == amps.size - 1 and not res.success:  # stopped before p1, the peak still falling: not the bracket's fault
        bal, y, _, _, fw, p = curve.parts(res.y[i])
        re, im, _, resp = coefficients(bal, y, fw, f, dof)
        w = closest_minimum(re, im, float(y[bal.n * bal.L]))[0]
        why = (f"the peak curve ended at p={p:.6g} before the optimum (the peak still falls there), short of "
               f"bounds[1]={p1!r}: {res.message}")
        return DamperOptimum(parameter=p, peak=Peak(float(w), float(resp), interior=False, converged=False, message=why),
                             parameters=res.y[:, -1] * p_ref, peaks=amps, peak_omega=omegas, success=False,
                             message=why, nsteps=res.nsteps, nfev=modes.nfev + curve.nfev)
    if i == 0 or i == amps.size - 1:
        where = "p0" if i == 0 else "p1"
        raise ValueError(f"bounds must contain the optimum: the smallest peak on the traced curve is at {where} "
                         f"({res.y[i, -1] * p_ref:.6g}), got bounds={bounds!r}")
    loc = cont.locate(curve, res.y[i - 1], res.y[i + 1], lambda z, t: float(curve.amplitude(z, bal0)[1] @ t),
                      tol=tol, xtol=1e-12)
    if loc is None:
        raise ValueError("the optimum could not be located on the peak curve between its points")
    bal, y, _, _, fw, p = curve.parts(loc.y)
    re, im, _, resp = coefficients(bal, y, fw, f, dof)
    w = closest_minimum(re, im, float(y[bal.n * bal.L]))[0]
    return DamperOptimum(parameter=p, peak=Peak(float(w), float(resp)), parameters=res.y[:, -1] * p_ref,
                         peaks=amps, peak_omega=omegas, success=bool(res.success), message=res.message,
                         nsteps=res.nsteps, nfev=modes.nfev + curve.nfev + loc.nfev)


def _contacts_at(contacts_of: Callable[[float], Any], p: float, bounds: Any) -> Any:
    """``contacts_of(p)`` at a bound; the ``ValueError`` of a value its elements refuse names ``bounds`` (the
    element's message named its own parameter, e.g. ``N``, which the caller never passed here).  Any scalar is
    a parameter (``log10 N`` may be negative): a bound is refused where its contacts are, not by its sign."""
    try:
        return contacts_of(p)
    except ValueError as exc:
        raise ValueError(f"bounds must lie where contacts_of builds contacts: contacts_of({p!r}) raised "
                         f"{type(exc).__name__}: {exc}; got bounds={bounds!r}") from exc


__all__ = ["damper_optimum", "DamperOptimum"]
