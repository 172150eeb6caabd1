"""The result of a multi-harmonic frequency response: points, harmonics, stability, peak.

:class:`MultiHarmonicResponse` has the arrays and methods of :class:`hbm.FrequencyResponse`
(``omega``, ``amplitude``, ``phase``, ``x_c``, ``x_s``, ``residual_norm``, folds, ``peak()``,
``success``, ``message``, counters, ``to_csv``, ``plot``) for the response DOF, plus
``coefficients(dof)``, ``harmonics``, ``stable``, ``exponents`` and ``stability_changes``.
"""

from __future__ import annotations

import math
from typing import Any, Callable

from . import continuation as cont

import numpy as np
from numpy.typing import NDArray

from .frf import FrequencyResponse, Peak
from .stability import STABILITY_TOL, hill_exponents, stability_changes


class MultiHarmonicResponse(FrequencyResponse):
    """FRF of a structure with contacts by multi-harmonic balance (``hbm.frequency_response``).

    Attributes: ``omega`` (rad/s), ``amplitude`` (m, first harmonic of ``response_dof``),
    ``phase``, ``x_c``, ``x_s`` (its first harmonic, ``x ~ x_c cos + x_s sin``),
    ``residual_norm`` (|R|/x_ref per point), ``harmonics`` (H), ``n_t``, ``dofs`` (the
    condensation DOFs), ``stable`` (bool per point, Hill's method), ``exponents`` (points, 2 n_s)
    Floquet exponents, ``stability_dofs`` (the DOFs of the model they are computed on),
    ``stability_changes`` (located, classified), ``folds_omega``/``folds_amplitude``,
    ``success``, ``status``, ``message``, counters ``nsteps``, ``nit``, ``nfev`` (element harmonic
    force evaluations).  Counters, ``success``, ``len`` and ``to_csv`` (the points of
    ``response_dof``) are those of :class:`hbm.FrequencyResponse`.
    """

    def __init__(self, problem: Any, run: cont.ContinuationResult, *, response_dof: int, rtol: float, tol: float,
                 scale: Callable, stability: bool = True) -> None:
        self._problem = problem
        self._run = run
        self._scale = scale
        self.rtol, self.tol = rtol, tol
        self.structure = problem.structure
        self.contacts = problem.contacts
        self.harmonics, self.n_t = problem.H, problem.n_t
        self.dofs = list(problem.dofs)
        self.response_dof = response_dof
        self._r = self.dofs.index(response_dof)
        L = problem.L
        X, w = problem.to_physical(run.y) if len(run.y) else (np.empty((0, problem.na, L)), np.empty(0))
        self._X, self.omega = X, w
        self.x_c, self.x_s = X[:, self._r, 1], X[:, self._r, 2]
        self.amplitude = np.hypot(self.x_c, self.x_s)
        self.phase = np.arctan2(self.x_s, self.x_c)
        self.residual_norm = run.residual_norm
        self.fold_after = run.fold_after
        if len(run.folds):
            FX, Fw = problem.to_physical(run.folds)
            self.folds_omega, self.folds_amplitude = Fw, np.hypot(FX[:, self._r, 1], FX[:, self._r, 2])
        else:
            self.folds_omega = self.folds_amplitude = np.empty(0)
        self._take_run(run)
        self._stable = np.ones(len(w), dtype=bool)
        self.exponents = np.empty((len(w), 0), dtype=complex)
        self.stability_changes: list = []
        self.stability_dofs: list[int] = []
        if stability and len(w):
            self._stability()

    def __repr__(self) -> str:
        return (f"MultiHarmonicResponse({len(self)} points, H={self.harmonics}, success={self.success}, "
                f"message={self.message!r})")

    # ------------------------------------------------------------------ harmonics
    def coefficients(self, dof: int) -> NDArray[np.complex128]:
        """Complex harmonics ``c_h`` (points, H+1) of DOF ``dof``: ``x = Re sum_h c_h exp(i h omega t)``,
        ``c_0 = X0``, ``c_h = Xc_h - i Xs_h``.  DOFs outside the condensation set are recovered
        exactly from the contact forces (``Z_h^-1 (f - P F_h)``)."""
        dof = self.structure._dof("dof", dof)
        if dof in self.dofs:
            return to_c(self._X[:, self.dofs.index(dof)])
        pr = self._problem
        out = np.empty((len(self), self.harmonics + 1), dtype=complex)
        for i, (X, w) in enumerate(zip(self._X, self.omega)):
            F = pr.forces(X, float(w))[0]
            out[i] = pr.cond.response(float(w), F)[dof]
        return out

    # ------------------------------------------------------------------ stability
    def _stability(self) -> None:
        from .multiharmonic import STABILITY_FULL_DOFS, STABILITY_MODES

        pr, s = self._problem, self.structure
        L = pr.L
        if s.n <= STABILITY_FULL_DOFS:
            model, place = s, self.dofs
        else:
            model = s.reduce(self.dofs, modes=min(STABILITY_MODES, s.n - len(self.dofs)))
            place = list(range(len(self.dofs)))
        self.stability_dofs = list(range(model.n)) if model is s else [f"CB:{d}" for d in self.dofs] + [
            f"mode {j}" for j in range(model.n - len(self.dofs))]
        M, C, K = (np.asarray(A.toarray() if hasattr(A, "toarray") else A) for A in (model.M, model.C, model.K))
        idx = (np.asarray(place)[:, None] * L + np.arange(L)[None, :]).ravel()
        lams = []
        for X, w in zip(self._X, self.omega):
            dFa = pr.forces(X, float(w), perturbation=True)[1]
            dF = np.zeros((model.n * L, model.n * L))
            dF[np.ix_(idx, idx)] = dFa
            lams.append(hill_exponents(M, C, K, float(w), dF, self.harmonics))
        self.exponents = np.array(lams)
        self._stable = self.exponents[:, 0].real <= STABILITY_TOL * np.maximum(self.omega, 1e-300)
        folds = list(zip(self.folds_omega, self.folds_amplitude))
        self.stability_changes = stability_changes(self.omega, self.amplitude, self.exponents, self.stable,
                                                   self.fold_after, folds)

    # ------------------------------------------------------------------ peak (FrequencyResponse.peak)
    @property
    def _peak_components(self) -> tuple[int, int]:
        return self._r * self._problem.L + 1, self._r * self._problem.L + 2

    def _peak_point(self, y: NDArray) -> tuple[float, float]:
        X, w = self._problem.to_physical(y)
        return float(w), float(math.hypot(X[self._r, 1], X[self._r, 2]))

def to_c(X: NDArray) -> NDArray[np.complex128]:
    """(points, 2H+1) real layout -> (points, H+1) complex ``c_h = Xc_h - i Xs_h``."""
    c = np.empty((X.shape[0], (X.shape[1] + 1) // 2), dtype=complex)
    c[:, 0] = X[:, 0]
    c[:, 1:] = X[:, 1::2] - 1j * X[:, 2::2]
    return c


__all__ = ["MultiHarmonicResponse"]
