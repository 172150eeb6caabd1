"""Starts for the continuation where Newton from the stuck guess fails (a homotopy in the force; the
describing functions' equivalent linear system), and why none is found where an element that is rigid
while stuck cannot slip throughout the period.

The equivalent linear system (:func:`equivalent_start`): each contact replaced by the complex stiffness
of its first harmonic at its own amplitude, ``k_e(a) = (f_s(a) + i f_c(a))/a`` (``docs/hbm.md``, the
single-harmonic balance), and the amplitudes solved so that each contact's relative motion has
amplitude ``a_e``.  It is the H = 1 balance itself, solved for the amplitudes first, so it reaches the
solution where the stuck guess does not: an element rigid while stuck (``k_s`` infinite, e.g. the
rigid slider ``Macroslip(math.inf, F)``, ``f_c = 4 F/pi`` for every a > 0) has a first harmonic that
jumps at a = 0, and Newton from the free or the stuck guess does not find the amplitude.

The force that holds a rigid contact (:func:`held_forces`): the contacts that are rigid while stuck
held fixed (``B^T X = 0``), the others at their stuck stiffness; the force ``P`` on each.  With ``F_1``
the first harmonic of its force at vanishing amplitude (the rigid slider's ``4 F/pi``): where ``P <
F_1`` the H = 1 balance, whose force is that of slipping throughout (at least ``F_1``), has no solution
with it moving (for one such contact, ``|u(a)|/a -> P/F_1 < 1`` as a -> 0); the contact sticks for part
of each period or all of it (all where ``P`` is below its slip force: the rigid slider's ``F``).
"""

from __future__ import annotations

import math
from typing import Callable, Sequence

import numpy as np
from numpy.typing import NDArray

from contact_models.numerics.roots import brentq

from .. import continuation as cont
from .._steps import RESIDUAL_RAISED_AT_ONCE
from .condensation import stuck_matrix
from .residual import HarmonicBalance

#: The amplitudes an equivalent start looks for its contacts' amplitude in, relative to x_ref.
EQUIVALENT_SPAN = (1e-9, 1e6)
#: Grid points per decade of that span at which the sign change is sought.
EQUIVALENT_PER_DECADE = 8


def force_homotopy(problem: HarmonicBalance, w0: float, tol: float, scale: Callable) -> NDArray | None:
    """A start at ``w0`` by continuation in the force scale ``s`` from 0 (X = 0 solves the balance
    without forcing) to 1 of ``R(X) - (1 - s) R_f`` at fixed omega, ``R_f`` the forcing's part of
    the scaled residual (:meth:`HarmonicBalance.forcing_part`); None if it does not reach s = 1."""
    wr = problem.omega_ref
    n = problem.unknowns - 1

    def residual(v):
        u = np.append(v[:-1], w0 / wr)
        s = float(v[-1])
        R, J = problem(u)  # s = 1
        Rf = problem.forcing_part(u)
        Jh = np.empty((R.size, n + 1))
        Jh[:, :-1] = J[:, :-1]
        Jh[:, -1] = Rf
        return R - (1.0 - s) * Rf, Jh

    def hscale(v):  # every X component by max(its first-harmonic amplitude, x_ref), s by 1
        out = np.maximum(scale(np.append(v[:-1], 1.0)), 1.0)
        out[-1] = 1.0
        return out

    run = cont.continuation(residual, np.zeros(n + 1), parameter=-1, bounds=(0.0, 1.0), max_step=0.1,
                            min_step=1e-9, max_steps=2000, tol=tol, scale=hscale, locate_folds=False, from_bound=True)
    if not run.success or abs(run.y[-1, -1] - 1.0) > 1e-12:
        return None
    return np.append(run.y[-1, :-1], w0 / wr)


def _plain(problem: HarmonicBalance) -> bool:
    """True where every contact is tangential only, at one DOF or between two of this structure."""
    return all(len(c.components) == 1 and not c.next_sector for c in problem.contacts)


def _signs(problem: HarmonicBalance, c) -> tuple[list[int], list[float]]:
    pos = {d: i for i, d in enumerate(problem.dofs)}
    return [pos[d] for d in c.dofs], [1.0, -1.0][:len(c.dofs)]


def _equivalent_motion(problem: HarmonicBalance, w: float, amps: NDArray) -> tuple[NDArray, NDArray]:
    """The first-harmonic complex response ``c`` (n_a,) with each contact at ``k_e(a_e)``, and the
    amplitudes of the contacts' relative motions."""
    ks = []
    for c, a in zip(problem.contacts, amps):
        fs, fc = c.element.fourier(float(a), w, rtol=problem.rtol)
        ks.append(complex(float(fs), float(fc)) / a)
    if problem.one_dof:
        z = problem._F / (problem._k + ks[0] - problem._m * w * w + 1j * problem._c * w)
        return np.array([z]), np.array([abs(z)])
    G, _, xl, _ = problem.cond.at(w)
    Kc = stuck_matrix(problem.contacts, problem.dofs, w, problem._angle, stiffness=ks)
    z = np.linalg.solve(np.eye(problem.na) + G[1] @ Kc, xl)
    rel = []
    for c in problem.contacts:
        ix, sg = _signs(problem, c)
        rel.append(abs(sum(s * z[i] for i, s in zip(ix, sg))))
    return z, np.array(rel)


def equivalent_start(problem: HarmonicBalance, w0: float) -> NDArray | None:
    """Scaled unknowns at ``w0`` of the equivalent linear system (module docstring), or None where it has
    no solution (or there is not exactly one contact, a plain tangential one): the root of
    ``log(|u(a)|/a)`` bracketed on a grid of amplitudes and refined by Brent's method, the largest (the
    slipping one) where there are several."""
    if not _plain(problem) or len(problem.contacts) != 1:
        return None
    xr = problem.x_ref

    def gap(log_a):
        return math.log(_equivalent_motion(problem, w0, np.array([math.exp(log_a)]))[1][0]) - log_a

    try:
        lo, hi = (math.log(xr * f) for f in EQUIVALENT_SPAN)
        grid = np.linspace(lo, hi, int(EQUIVALENT_PER_DECADE * (hi - lo) / math.log(10.0)) + 1)
        g = [gap(v) for v in grid]
        cross = [j for j in range(len(g) - 1) if g[j] > 0.0 >= g[j + 1]]
        if not cross:
            return None
        j = cross[-1]  # the largest amplitude that balances (the slipping one)
        amps = np.array([math.exp(brentq(gap, grid[j], grid[j + 1], xtol=1e-14, rtol=1e-14))])
        z = _equivalent_motion(problem, w0, amps)[0]
    except RESIDUAL_RAISED_AT_ONCE:  # an element's answer of the wrong type or shape: a defect, not "no start"
        raise
    except (ValueError, ArithmeticError, np.linalg.LinAlgError):
        return None
    if not np.all(np.isfinite(z)):
        return None
    if problem.one_dof:
        return np.array([z[0].real / xr, -z[0].imag / xr, w0 / problem.omega_ref])
    u0 = np.zeros(problem.unknowns)
    L = problem.L
    u0[1:problem.na * L:L] = z.real / xr
    u0[2:problem.na * L:L] = -z.imag / xr
    u0[-1] = w0 / problem.omega_ref
    return u0


def rigid_contacts(problem: HarmonicBalance, w: float) -> list[int]:
    """Indices of the contacts whose stuck stiffness at ``w`` is infinite (rigid while stuck)."""
    out = []
    for e, c in enumerate(problem.contacts):
        ks, kc = c.element.linear_coefficients(w)
        if not (math.isfinite(ks) and math.isfinite(kc)):
            out.append(e)
    return out


def held_forces(problem: HarmonicBalance, w: float, rigid: Sequence[int]) -> NDArray | None:
    """Amplitudes of the forces on the ``rigid`` contacts held fixed at ``w`` (the others at their
    stuck stiffness), or None where the contacts are not all plain tangential ones."""
    if not _plain(problem):
        return None
    if problem.one_dof:
        return np.array([abs(problem._F)])
    G, _, xl, _ = problem.cond.at(w)
    A = np.eye(problem.na) + G[1] @ stuck_matrix(problem.contacts, problem.dofs, w, problem._angle)
    B = np.zeros((problem.na, len(rigid)), dtype=complex)
    for col, e in enumerate(rigid):
        ix, sg = _signs(problem, problem.contacts[e])
        B[ix, col] = sg
    Ai_xl = np.linalg.solve(A, xl)
    Ai_GB = np.linalg.solve(A, G[1] @ B)
    try:
        f = np.linalg.solve(B.T @ Ai_GB, B.T @ Ai_xl)
    except np.linalg.LinAlgError:
        return None
    return np.abs(f)


def stuck_reason(problem: HarmonicBalance, w: float) -> str | None:
    """Why the H = 1 balance has no solution at ``w`` with its contacts that are rigid while stuck
    moving (module docstring), naming each such contact, its element and the forces; None where it is
    not that (no such contact, or every one is held by more than its ``F_1``)."""
    if problem.H != 1:
        return None
    try:
        parts = _stuck_parts(problem, w)
    except RESIDUAL_RAISED_AT_ONCE:  # a defect of the element's code, raised as during the trace
        raise
    except (ValueError, ArithmeticError, np.linalg.LinAlgError):  # no reason found: the run's own message stands
        return None
    if not parts:
        return None
    return (f"at omega = {w:.6g} rad/s the first-harmonic balance has no solution with "
            + "; and ".join(parts)
            + ". The describing function (harmonics=1) describes an element that slips all period, and an element "
              "with no stuck stiffness has no time law for more harmonics: for this response give it a finite "
              "stiffness (e.g. Macroslip(k, slip_force) for the rigid slider), which has a time-domain force law")


def _stuck_parts(problem: HarmonicBalance, w: float) -> list[str]:
    """For :func:`stuck_reason`: one phrase for each contact rigid while stuck and held by less than its ``F_1``."""
    rigid = rigid_contacts(problem, w)
    P = held_forces(problem, w, rigid) if rigid else None
    if P is None:
        return []
    parts = []
    for e, p in zip(rigid, P):
        c = problem.contacts[e]
        el = c.element
        tiny = problem.x_ref * EQUIVALENT_SPAN[0]
        f1 = math.hypot(*(float(v) for v in el.fourier(tiny, w, rtol=problem.rtol)))
        if not p < f1:
            continue
        where = f"dof={c.dofs[0]}" if len(c.dofs) == 1 else f"dofs={c.dofs}"
        parts.append(f"{el!r} at {where}: held fixed, it would carry a force of amplitude {p:.6g} N, less than "
                     f"{f1:.6g} N, the first harmonic of its force while it slips throughout, so it sticks for "
                     f"part of each period or all of it")
    return parts


__all__ = ["equivalent_start", "force_homotopy", "held_forces", "rigid_contacts", "stuck_reason"]
