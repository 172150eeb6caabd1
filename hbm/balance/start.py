"""A start for the continuation where Newton from the stuck guess fails: homotopy in the force."""

from __future__ import annotations

import math
from typing import Callable

import numpy as np
from numpy.typing import NDArray

from .. import continuation as cont
from .residual import HarmonicBalance


def force_homotopy(problem: HarmonicBalance, w0: float, tol: float, scale: Callable) -> NDArray | None:
    """A start at ``w0`` by continuation in the force scale ``s`` from 0 (X = 0) to 1 of
    ``R = X - s X_lin + G F(X)`` at fixed omega (the condensed form); None if it does not reach
    s = 1, or for the one-DOF form (which starts from the stuck solution only)."""
    if problem.one_dof:
        return None
    wr, xr = problem.omega_ref, problem.x_ref
    n = problem.na * problem.L

    def residual(v):
        u = np.append(v[:-1], w0 / wr)
        s = float(v[-1])
        R, J = problem(u)  # s = 1
        sigma = max(1.0, math.sqrt(float(np.sum(u[:-1].reshape(problem.na, problem.L)[:, 1:3] ** 2))))
        xl = problem.cond.at(w0)[2]
        lin = np.zeros((problem.na, problem.L))
        lin[:, 1], lin[:, 2] = xl.real, -xl.imag
        lin = lin.ravel() / (xr * sigma)
        Jh = np.empty((n, n + 1))
        Jh[:, :-1] = J[:, :-1]
        Jh[:, -1] = -lin
        return R + (1.0 - s) * lin, Jh

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
