"""A start for the continuation where Newton from the stuck guess fails: homotopy in the force."""

from __future__ import annotations

from typing import Callable

import numpy as np
from numpy.typing import NDArray

from .. import continuation as cont
from .residual import HarmonicBalance


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
                            min_step=1e-9, max_steps=2000, tol=tol, scale=hscale, locate_folds=False)
    if not run.success or abs(run.y[-1, -1] - 1.0) > 1e-12:
        return None
    return np.append(run.y[-1, :-1], w0 / wr)


__all__ = ["force_homotopy"]
