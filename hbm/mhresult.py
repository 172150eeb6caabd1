"""The result of a multi-harmonic frequency response: points, harmonics, stability, peak.

:class:`MultiHarmonicResponse` has the arrays and methods of :class:`hbm.FrequencyResponse`
(``omega``, ``amplitude``, ``phase``, ``x_c``, ``x_s``, ``residual_norm``, folds, ``peak()``,
``success``, ``message``, counters, ``to_csv``, ``plot``) for the response DOF, plus
``coefficients(dof)``, ``harmonics``, ``stable``, ``exponents`` and ``stability_changes``.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Callable

import numpy as np
from numpy.typing import NDArray

from . import continuation as cont
from .frf import Peak
from .output import write_frf_csv
from .stability import STABILITY_TOL, hill_exponents, stability_changes


class MultiHarmonicResponse:
    """FRF of a structure with contacts by multi-harmonic balance (``hbm.frequency_response``).

    Attributes: ``omega`` (rad/s), ``amplitude`` (m, first harmonic of ``response_dof``),
    ``phase``, ``x_c``, ``x_s`` (its first harmonic, ``x ~ x_c cos + x_s sin``),
    ``residual_norm`` (|R|/x_ref per point), ``harmonics`` (H), ``n_t``, ``dofs`` (the
    condensation DOFs), ``stable`` (bool per point, Hill's method), ``exponents`` (points, 2 n_s)
    Floquet exponents, ``stability_dofs`` (the DOFs of the model they are computed on),
    ``stability_changes`` (located, classified), ``folds_omega``/``folds_amplitude``,
    ``success``, ``status``, ``message``, counters ``nsteps``, ``nit``, ``nfev`` (element harmonic
    force evaluations).
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
        self.status, self.message = run.status, run.message
        if not run.success and len(w):
            self.message += f"; the branch stops at omega = {w[-1]:.9g} rad/s, amplitude {self.amplitude[-1]:.6g} m"
        self.nsteps = run.nsteps
        self._nit0 = run.nit
        self._peak = None
        self._peak_nit = 0
        self.peak_refined = False
        self.stable = np.ones(len(w), dtype=bool)
        self.exponents = np.empty((len(w), 0), dtype=complex)
        self.stability_changes: list = []
        self.stability_dofs: list[int] = []
        if stability and len(w):
            self._stability()

    # ------------------------------------------------------------------ counters
    @property
    def success(self) -> bool:
        return self._run.success

    @property
    def nit(self) -> int:
        return self._nit0 + self._peak_nit

    @property
    def nfev(self) -> int:
        return self._problem.nfev

    @property
    def nstuck(self) -> int:
        """0: every point evaluates the elements (the counter of ``FrequencyResponse`` for the shortcut
        through the stuck stiffness, which the multi-harmonic balance does not take)."""
        return 0

    def __len__(self) -> int:
        return len(self.omega)

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
        self.stable = self.exponents[:, 0].real <= STABILITY_TOL * np.maximum(self.omega, 1e-300)
        folds = list(zip(self.folds_omega, self.folds_amplitude))
        self.stability_changes = stability_changes(self.omega, self.amplitude, self.exponents, self.stable,
                                                   self.fold_after, folds)

    # ------------------------------------------------------------------ peak
    def peak(self) -> Peak:
        """``(omega, amplitude)`` of the largest first-harmonic amplitude of ``response_dof``,
        refined between the neighbours of the largest sampled point (zero of ``d(a^2)/ds`` by
        Brent's method on converged points, as ``FrequencyResponse.peak``)."""
        if self._peak is not None:
            return self._peak
        if len(self) == 0:
            raise ValueError("the frequency response has no points")
        i = int(np.argmax(self.amplitude))
        best = Peak(float(self.omega[i]), float(self.amplitude[i]))
        if 0 < i < len(self) - 1:
            pr, L, r = self._problem, self._problem.L, self._r
            counter = cont._Count()
            y = self._run.y

            def slope(u, t):
                return u[r * L + 1] * t[r * L + 1] + u[r * L + 2] * t[r * L + 2]

            try:
                xtol = 1e-3 * math.sqrt(self.rtol)
                loc = None
                for ja, jb in ((i - 1, i + 1), (i - 1, i), (i, i + 1)):
                    loc = cont.locate(pr, y[ja], y[jb], slope, tol=self.tol, scale=self._scale, xtol=xtol,
                                      count=counter)
                    if loc is not None:
                        break
            finally:
                self._peak_nit += counter.nit
            if loc is not None:
                X, w = pr.to_physical(loc.y)
                a = float(math.hypot(X[r, 1], X[r, 2]))
                if a >= best.amplitude * (1.0 - 10.0 * self.rtol):
                    best = Peak(float(w), a)
                    self.peak_refined = True
        self._peak = best
        return best

    # ------------------------------------------------------------------ output
    def to_csv(self, path: str | Path) -> Path:
        """Write the points of ``response_dof`` as ``hbm.output.FRF_COLUMNS``; returns the path."""
        return write_frf_csv(path, self)

    def plot(self, ax: Any = None, *, label: str | None = None, peak: bool = True, **kwargs: Any) -> Any:
        """Amplitude against omega on ``ax`` (new figure if None): stable stretches solid,
        unstable dashed (``hbm.output.plot_branch``); marks the peak.  Returns ax."""
        from .output import plot_branch

        ax, color = plot_branch(ax, self.omega, self.amplitude, self.stable, label=label, **kwargs)
        if peak and len(self):
            pk = self.peak()
            ax.plot([pk.omega], [pk.amplitude], "o", color=color, ms=4)
        return ax


def to_c(X: NDArray) -> NDArray[np.complex128]:
    """(points, 2H+1) real layout -> (points, H+1) complex ``c_h = Xc_h - i Xs_h``."""
    c = np.empty((X.shape[0], (X.shape[1] + 1) // 2), dtype=complex)
    c[:, 0] = X[:, 0]
    c[:, 1:] = X[:, 1::2] - 1j * X[:, 2::2]
    return c


__all__ = ["MultiHarmonicResponse"]
