"""The result of a frequency response, whatever the system and the number of harmonics.

:class:`FrequencyResponse` holds the branch traced by :func:`hbm.frequency_response`: the
response DOF's first harmonic along the branch, every harmonic of every DOF
(:meth:`~FrequencyResponse.coefficients`), stability by Hill's method, the peak located between
points, how the run went, and the CSV and plot of the points.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Callable, NamedTuple

import numpy as np
from numpy.typing import NDArray

from . import continuation as cont  # the module (hbm.continuation)
from ._validation import flag, shown
from .balance import errors
from .balance.layout import to_complex
from .balance.residual import HarmonicBalance
from .balance.stability import STABILITY_TOL, HillProblem, band_modes, stability_changes
from .output import (AMPLITUDE_UNITS, OMEGA_UNITS, frf_comments, frf_table, pandas_module, plot_branch,
                     plot_error_band, write_frf_csv)

#: The peak is located to this fraction of its bracket times sqrt(rtol) in arclength; the
#: amplitude error is quadratic in that distance.
PEAK_XTOL_FACTOR = 1e-3
#: Hill's method runs on the structure itself up to this many DOFs, else on a Craig-Bampton
#: model of the condensation DOFs plus at most ``STABILITY_MODES`` fixed-interface modes: those
#: within the band the balance resolves, ``(H + 1/2)`` times the branch's largest omega, and the
#: first one above it (``hbm.balance.stability.band_modes``).
STABILITY_FULL_DOFS = 6
STABILITY_MODES = 4


class Peak(tuple):
    """The largest first-harmonic amplitude on the branch, ``(omega, amplitude)``, and what it is.

    It unpacks as the pair ``omega, amplitude = frf.peak()``; its attributes say whether it can be
    trusted as the resonance peak of the range asked for.

    Attributes
    ----------
    omega : float
        Frequency (rad/s).
    amplitude : float
        First-harmonic amplitude (m).
    interior : bool
        The maximum lies inside the branch: not at an end of ``omega_range`` (the resonance may be
        outside the range) and not at the point where a branch that stopped early ends.
    converged : bool
        ``interior``, on a branch that reached the end of its range, located between points (the
        zero of d(a^2)/ds), and, where a tolerance was asked for, with its error estimate within it
        (``tol=None`` asks for none: nothing is estimated, and ``converged`` says only the rest).
    estimate : float or None
        The estimated relative error of ``amplitude`` at the peak: the largest point estimate within
        two points of the sampled maximum (``hbm.balance.errors.peak_estimate``); inf where a source
        of it cannot be bounded; None where nothing was estimated (``tol=None``, a peak from a mode).
    message : str
        Why the peak is not converged ("" where it is).
    """

    def __new__(cls, omega: float, amplitude: float, *, interior: bool = True, converged: bool = True,
                estimate: float | None = None, message: str = "") -> "Peak":
        out = super().__new__(cls, (float(omega), float(amplitude)))
        out.interior, out.converged = bool(interior), bool(converged)
        estimate = None if estimate is None else float(estimate)
        out.estimate = None if estimate is None or math.isnan(estimate) else estimate  # (NaN: none made)
        out.message = message
        return out

    @property
    def omega(self) -> float:
        return self[0]

    @property
    def amplitude(self) -> float:
        return self[1]

    def __repr__(self) -> str:
        return (f"Peak(omega={self.omega!r}, amplitude={self.amplitude!r}, interior={self.interior}, "
                f"converged={self.converged}, estimate={'None' if self.estimate is None else f'{self.estimate:.2g}'})")

    def __reduce__(self):
        return (_peak, (self.omega, self.amplitude, self.interior, self.converged, self.estimate, self.message))


def _peak(omega: float, amplitude: float, interior: bool, converged: bool, estimate: float | None,
          message: str) -> Peak:
    """A :class:`Peak` from its fields (pickling)."""
    return Peak(omega, amplitude, interior=interior, converged=converged, estimate=estimate, message=message)


class Response(NamedTuple):
    """The single-harmonic response at one frequency (``response_at``).

    Attributes
    ----------
    omega : float
        Excitation frequency (rad/s).
    x_c, x_s : float
        Cosine and sine coefficients of the displacement (m):
        ``x = x_c cos(omega t) + x_s sin(omega t)``.
    amplitude : float
        First-harmonic amplitude ``hypot(x_c, x_s)`` (m).
    phase : float
        Lag of the displacement behind the force (rad), ``x = amplitude cos(omega t - phase)``.
    """

    omega: float
    x_c: float
    x_s: float
    amplitude: float
    phase: float  #: lag of the displacement behind the force, x = a cos(omega t - phase)


class Segment(NamedTuple):
    """A segment of a :class:`FrequencyResponse`: the points solved with one balance.

    Attributes
    ----------
    start, stop : int
        The segment's points are ``start <= i < stop`` (indices into the result's arrays).
    harmonics, n_t : int
        The number of harmonics H and the AFT samples per period of its balance.
    model : str
        The element names of its contacts, ``"+"``-joined (``hbm.result.model_label``).
    """

    start: int
    stop: int
    harmonics: int
    n_t: int
    model: str


def model_label(contacts: list) -> str:
    """The element names of ``contacts`` (``hbm.Contact``), ``"+"``-joined: a point's model.  An element's
    name is its ``ContactElement.model_name`` (its class name; a fixed rung of ``AllModeMicroslip`` names
    its cells and H)."""
    return "+".join(c.element.model_name for c in contacts)


class FrequencyResponse:
    """The FRF: arrays along the branch, in continuation order, and how the run went.

    Made by :func:`hbm.frequency_response`, not by hand.  The same type for a blade and a
    structure, at one harmonic or many.

    Attributes
    ----------
    omega, amplitude, phase, x_c, x_s, residual_norm : ndarray
        One value per point along the branch: frequency (rad/s), first-harmonic amplitude of the
        response DOF (m), its lag behind the force (rad, ``x = a cos(omega t - phase)``), its
        cosine and sine coefficients (m, ``x ~ x_c cos + x_s sin``), and the scaled residual of
        the point (``|R|/F`` for a one-DOF system at H = 1, ``|R|/x_ref`` otherwise; dimensionless).
    folds_omega, folds_amplitude : ndarray
        The located turning points of the branch (rad/s, m); where the locator cannot converge (a
        corner of the branch), the converged point at the turn, within one step of it.
    harmonics, n_t : int
        The number of harmonics H and the AFT samples per period (the largest along the curve).
    point_harmonics : ndarray of int
        The H of each point (``hbm.frequency_response`` with ``tol`` may choose H along the curve).
    point_models : ndarray of str
        The model of each point: its contacts' element names (``model_name``, else the class name), ``"+"``-joined.
    segments : list of Segment
        The segments, each solved with one balance, in order (one for a curve at one H and model).
    dofs : list of int
        The condensation DOFs (the contacts' DOFs and the response DOF).
    response_dof : int
        The DOF whose response ``amplitude`` is.
    structure : hbm.Structure
        The system solved (a blade's one-DOF structure).
    system, blade : hbm.Blade or hbm.Structure
        The system as given (``blade``: the same object, under the name of a blade's result).
    contacts : list of hbm.Contact
        The contacts.
    element : contact_models.ContactElement or None
        The contact's element when there is exactly one contact.
    stable : ndarray of bool
        Stability of every point by Hill's method (computed on first use).
    exponents : ndarray
        Floquet exponents per point (points, 2 n_s), computed with :attr:`stable`.
    stability_changes : list
        Located, classified changes of stability (``hbm.balance.stability.StabilityChange``).
    success : bool
        Whether the branch reached the end of ``omega_range`` (and the callback, if any, took every point).
    status, message
        How the continuation ended, as an :class:`hbm.Status` (an int that prints as its name) and in
        words; on failure the points computed before are kept.
    coarse, corners : ndarray of int
        With ``curve_tol``: indices ``i`` of the points whose interval ``(i - 1, i)`` is off by more
        than the tolerance at its mid-point after the check (``hbm.curve.refine``: an interval across
        a corner of the branch, drawn as its chord); the corners found (the tangent jumps between
        ``i - 1`` and ``i``).
    nsteps, nit, nfev, nstuck : int
        Accepted steps, Newton iterations, element evaluations, stuck evaluations, with those of
        locating the peak.
    tol : float or None
        The target relative error asked for (``frequency_response(..., tol=...)``; None: no
        estimate was asked for).
    error_estimate : ndarray
        Per point, the estimated relative error of ``amplitude`` against the true periodic
        response of the physical system (all sources; NaN without an estimate; inf where a source
        cannot be estimated, which the call's ``AccuracyWarning`` names with its reason: also at every
        point of a solve whose estimate an element's hook raised in, the curve kept).
    error_sources : dict of ndarray
        The estimate per source, ``"harmonics"``, ``"sampling"``, ``"element"``, ``"model"``,
        ``"peak"`` (``hbm.balance.errors``).
    rtol, newton_tol : float
        The elements' tolerance and the Newton tolerance on the scaled residual, both derived from ``tol``.
    accuracy_warning : str or None
        The message of the one ``AccuracyWarning`` the call emitted (the estimate above the
        tolerance, and the elements' own warnings during the solve, merged), or None.

    Examples
    --------
    >>> from hbm import Blade, frequency_response
    >>> frf = frequency_response(Blade(mass=1.0, stiffness=1.0e4, damping=2.0, force=1.0),
    ...                          omega_range=(90.0, 110.0))
    >>> frf.success, len(frf.omega) == len(frf.amplitude) > 100
    (True, True)
    >>> float(frf.residual_norm.max()) < 1e-6              # |R|/F at every point
    True
    >>> round(float(frf.amplitude.max()), 6)           # largest sampled point, m (peak() refines it)
    0.005
    >>> frf.harmonics, frf.coefficients(0).shape[1]    # H, and H + 1 complex coefficients
    (1, 2)
    """

    def __init__(self, problem: HarmonicBalance, run: cont.ContinuationResult, *, rtol: float, newton_tol: float,
                 scale: Callable[[np.ndarray], np.ndarray], stability: bool = True,
                 tol: float | None = None) -> None:
        self._problem = problem
        self._run = run
        self._scale = scale
        self.rtol = rtol
        self.newton_tol = newton_tol
        self.tol = tol
        self.structure = problem.structure
        self.system = self.blade = problem.system
        self.contacts = problem.contacts
        self.element = problem.element
        self.harmonics, self.n_t = problem.H, problem.n_t
        self.dofs = list(problem.dofs)
        self.response_dof = problem.response_dof
        self._r = self.dofs.index(self.response_dof)
        X, w = problem.to_physical(run.y) if len(run.y) else (np.empty((0, problem.na, problem.L)), np.empty(0))
        self._X, self.omega = X, w
        self.x_c, self.x_s = X[:, self._r, 1], X[:, self._r, 2]
        self.amplitude = np.hypot(self.x_c, self.x_s)
        self._newton_steps = _newton_steps(problem, run, self.amplitude)
        self.phase = np.arctan2(self.x_s, self.x_c)
        self.residual_norm = run.residual_norm
        self.fold_after = run.fold_after
        if len(run.folds):
            FX, Fw = problem.to_physical(run.folds)
            self.folds_omega, self.folds_amplitude = Fw, np.hypot(FX[:, self._r, 1], FX[:, self._r, 2])
        else:
            self.folds_omega = self.folds_amplitude = np.empty(0)
        self.status = run.status
        self.message = run.message
        if not run.success and len(w):
            self.message += f"; the branch stops at omega = {w[-1]:.9g} rad/s, amplitude {self.amplitude[-1]:.6g} m"
        self.nsteps = run.nsteps
        #: indices i of points whose interval (i - 1, i) is off by more than ``curve_tol`` (a corner)
        self.coarse = run.coarse if run.coarse is not None else np.empty(0, dtype=int)
        self.corners = run.corners
        self._nit0 = run.nit
        self._peak: Peak | None = None
        self._peak_nit = 0
        self.peak_refined = False  #: whether peak() located the maximum between samples
        self._with_stability = bool(stability)
        self._stable: NDArray | None = None
        self._exponents: NDArray | None = None
        self._changes: list = []
        self.stability_dofs: list = []
        self.accuracy_warning: str | None = None  #: set by frequency_response
        self._heard: list[str] = []  # the elements' AccuracyWarning messages during this result's solve
        self._nodes = np.empty(0, dtype=np.intp)
        self.error_sources: dict = {}
        self.error_estimate = np.full(len(w), np.nan)
        self._estimate_failed: str | None = None  # what raised during this solve's error estimate (inf there)
        label = model_label(self.contacts)
        self.point_harmonics, self.point_models = np.full(len(w), self.harmonics), np.full(len(w), label)
        self.segments = [Segment(0, len(w), self.harmonics, self.n_t, label)]
        self._segments_of: list | None = None  # a spliced result: its (result, lo, hi) segments (``spliced``)
        self._work = [self]  # every solve the result's work counters sum

    def _estimated(self, sources: dict, nodes: NDArray) -> None:
        """Store the error estimate the solve computed for these points (``hbm.balance.errors.estimate``) and
        the indices it was computed at (``nodes``)."""
        self.error_sources, self._nodes = sources, np.asarray(nodes, dtype=np.intp)
        self.error_estimate = errors.total(sources)

    @property
    def tolerance(self) -> float | None:
        """The target relative error asked for: the same as ``tol`` (an older name)."""
        return self.tol

    @classmethod
    def spliced(cls, segments_of: list, work: list, note: str = "") -> "FrequencyResponse":
        """One result of the segments ``segments_of`` ``[(frf, lo, hi), ...]`` (points ``lo <= i < hi`` of
        each single-balance result ``frf``, in order along the branch); ``work``: every result solved
        for it, the whole range's trace first (its status and message, with ``note`` added; their
        counters are summed).  The problem, contacts and element are those of the segment holding
        the sampled maximum."""
        out = object.__new__(cls)
        out.__dict__.update(segments_of[0][0].__dict__)
        out._segments_of, out._work = list(segments_of), list(work)
        cat = lambda name: np.concatenate([getattr(f, name)[lo:hi] for f, lo, hi in segments_of])  # noqa: E731
        for name in ("omega", "x_c", "x_s", "amplitude", "phase", "residual_norm", "error_estimate",
                     "point_harmonics", "point_models"):
            setattr(out, name, cat(name))
        out.error_sources = {k: np.concatenate([f.error_sources[k][lo:hi] for f, lo, hi in segments_of])
                             for k in segments_of[0][0].error_sources}
        out._newton_steps = np.concatenate([f._newton_steps[lo:hi] for f, lo, hi in segments_of])
        if "peak" in out.error_sources:  # the peak's location is a property of the whole curve, not of each segment's
            newton = np.concatenate([f._newton_part(slice(lo, hi)) for f, lo, hi in segments_of])
            out.error_sources["peak"] = errors.peak_location(out.amplitude, out.omega, newton)
            out.error_estimate = errors.total(out.error_sources)
        out.harmonics, out.n_t = max(f.harmonics for f, _, _ in segments_of), max(f.n_t for f, _, _ in segments_of)
        L = 2 * out.harmonics + 1
        out._X = np.concatenate([np.pad(f._X[lo:hi], ((0, 0), (0, 0), (0, L - f._X.shape[2]))) for f, lo, hi in segments_of])
        out.segments, out.fold_after, fw, fa, out.coarse, out.corners, at = [], [], [], [], [], [], 0
        out._nodes = []
        for f, lo, hi in segments_of:
            out.segments.append(Segment(at, at + hi - lo, f.harmonics, f.n_t, str(f.point_models[0])))
            for k, i in enumerate(f.fold_after):
                if lo <= i < hi - 1:
                    out.fold_after.append(at + i - lo)
                    if k < len(f.folds_omega):
                        fw.append(f.folds_omega[k])
                        fa.append(f.folds_amplitude[k])
            out.coarse += [at + i - lo for i in f.coarse if lo < i < hi]
            out._nodes += [at + i - lo for i in f._nodes if lo <= i < hi]
            out.corners += [at + i - lo for i in f.corners if lo < i < hi]
            at += hi - lo
        out.fold_after, out.coarse, out.corners, out._nodes = (np.array(v, dtype=int) for v in (
            out.fold_after, out.coarse, out.corners, out._nodes))
        out.folds_omega, out.folds_amplitude = np.array(fw, dtype=float), np.array(fa, dtype=float)
        top = out._site(int(np.argmax(out.amplitude)))[0] if len(out.omega) else segments_of[0][0]
        out._problem, out._run, out._scale = top._problem, top._run, top._scale
        out.contacts, out.element = top.contacts, top.element
        out.nsteps = sum(f.nsteps for f in work)
        out.status, out.message = work[0].status, work[0].message + note
        out._peak, out._peak_nit, out.peak_refined = None, 0, False
        out._stable, out._exponents, out._changes = None, None, []
        return out

    def _site(self, i: int) -> tuple["FrequencyResponse", int]:
        """The single-balance result holding point ``i`` and its index there."""
        if self._segments_of is None:
            return self, i
        for f, lo, hi in self._segments_of:
            if i < hi - lo:
                return f, lo + i
            i -= hi - lo
        raise IndexError(i)

    def _interval(self, i: int) -> tuple["FrequencyResponse", int]:
        """``(result, j)``: points ``j``, ``j + 1`` of one single-balance result that bracket the
        interval ``(i, i + 1)`` of this one (across a splice: the segment that continues the branch)."""
        f, j = self._site(i)
        if j + 1 < len(f):
            return f, j
        f, j = self._site(i + 1)
        return f, j - 1

    # ------------------------------------------------------------------ counters
    @property
    def success(self) -> bool:
        # the whole range's first trace reached the end, and the callback took every point (``status``)
        return self._work[0]._run.success and self.status != cont.Status.CALLBACK_RAISED

    @property
    def nit(self) -> int:
        if self._segments_of is not None:
            return sum(f.nit for f in self._work) + self._peak_nit
        return self._nit0 + self._peak_nit

    @property
    def nfev(self) -> int:
        return sum({id(f._problem): f._problem.nfev for f in self._work}.values())

    @property
    def nstuck(self) -> int:
        return sum({id(f._problem): f._problem.nstuck for f in self._work}.values())

    def __len__(self) -> int:
        return len(self.omega)

    def __repr__(self) -> str:
        return (f"FrequencyResponse({len(self)} points, H={self.harmonics}, omega {self.omega[0]:.6g}.."
                f"{self.omega[-1]:.6g} rad/s, success={self.success}, message={self.message!r})" if len(self) else
                f"FrequencyResponse(0 points, H={self.harmonics}, success=False, message={self.message!r})")

    # ------------------------------------------------------------------ harmonics
    def coefficients(self, dof: int) -> NDArray[np.complex128]:
        """Complex harmonics ``c_h`` (points, H+1) of DOF ``dof``: ``x = Re sum_h c_h exp(i h omega t)``,
        ``c_0 = X0``, ``c_h = Xc_h - i Xs_h``.  DOFs outside the condensation set are recovered
        exactly from the contact forces (``Z_h^-1 (f - P F_h)``)."""
        dof = self.structure._dof("dof", dof)
        if self._segments_of is not None and dof not in self.dofs:
            return np.concatenate([np.pad(f.coefficients(dof)[lo:hi], ((0, 0), (0, self.harmonics - f.harmonics)))
                                   for f, lo, hi in self._segments_of])
        if dof in self.dofs:
            return to_complex(self._X[:, self.dofs.index(dof)])
        pr = self._problem
        out = np.empty((len(self), self.harmonics + 1), dtype=complex)
        for i, (X, w) in enumerate(zip(self._X, self.omega)):
            F = pr.forces(X, float(w))[0]
            out[i] = pr.cond.response(float(w), F)[dof]
        return out

    # ------------------------------------------------------------------ stability
    @property
    def stable(self) -> NDArray[np.bool_]:
        """Stability of every point (bool), by Hill's method, computed on first use (all True when
        the solve was asked for ``stability=False``); unstable parts are drawn dashed by :meth:`plot`."""
        if self._stable is None:
            self._stability()
        return self._stable

    @property
    def exponents(self) -> NDArray[np.complex128]:
        """Floquet exponents (points, 2 n_s) by Hill's method, largest real part first."""
        if self._stable is None:
            self._stability()
        return self._exponents

    @property
    def stability_changes(self) -> list:
        """The located, classified changes of stability along the branch."""
        if self._stable is None:
            self._stability()
        return self._changes

    def _stability(self) -> None:
        n = len(self)
        self._stable = np.ones(n, dtype=bool)
        self._exponents = np.empty((n, 0), dtype=complex)
        if not (self._with_stability and n):
            return
        self._exponents = self._hill(range(n))
        for f in self._balances():
            f._problem.forget_jacobians()  # every point's exponents are kept: the balances' Jacobians are not needed
        self._stable = self._exponents[:, 0].real <= STABILITY_TOL * np.maximum(self.omega, 1e-300)
        folds = list(zip(self.folds_omega, self.folds_amplitude))
        self._changes = stability_changes(self.omega, self.amplitude, self._exponents, self._stable,
                                          self.fold_after, folds)

    def _balances(self) -> list:
        """The results whose own balance solved this one's points: itself, or a spliced result's segments'."""
        if self._segments_of is None:
            return [self] if self._problem is not None else []
        return list(dict.fromkeys(g for f, _, _ in self._segments_of for g in f._balances()))

    def _hill(self, rows: range) -> NDArray[np.complex128]:
        """Floquet exponents (len(rows), 2 n_s) by Hill's method at the points ``rows`` of this result
        (a spliced result asks each segment for the rows it keeps, and no more)."""
        if not (self._with_stability and len(rows)):
            return np.empty((len(rows), 0), dtype=complex)
        if self._segments_of is not None:  # each segment by its own balance (2 n_s exponents at any H)
            parts, start = [], 0
            for f, lo, hi in self._segments_of:
                a, b = max(rows.start, start), min(rows.stop, start + hi - lo)
                if a < b:
                    parts.append(f._hill(range(lo + a - start, lo + b - start)))
                    self.stability_dofs = self.stability_dofs or f.stability_dofs  # (the first segment asked)
                start += hi - lo
            return np.concatenate(parts)
        pr, s = self._problem, self.structure
        L = pr.L
        coupling = None
        if s.sector_angle is not None:  # a sector: Hill within its travelling-wave family, on the sector itself
            model, place = s, self.dofs
            coupling = (s.M_next, s.C_next, s.K_next)
        elif s.n <= STABILITY_FULL_DOFS:
            model, place = s, self.dofs
        else:
            model = s.reduce(self.dofs, modes=min(STABILITY_MODES, s.n - len(self.dofs)))
            place = list(range(len(self.dofs)))
        M, C, K = (np.asarray(A.toarray() if hasattr(A, "toarray") else A) for A in (model.M, model.C, model.K))
        if model is not s:
            keep = band_modes(M, K, len(self.dofs), (self.harmonics + 0.5) * float(np.max(self.omega)))
            M, C, K = (A[np.ix_(keep, keep)] for A in (M, C, K))
        self.stability_dofs = list(range(model.n)) if model is s else [f"CB:{d}" for d in self.dofs] + [
            f"mode {j}" for j in range(M.shape[0] - len(self.dofs))]
        idx = (np.asarray(place)[:, None] * L + np.arange(L)[None, :]).ravel()
        lams = []
        hill = HillProblem(M, C, K, self.harmonics, coupling, s.sector_angle or 0.0)
        dF = np.zeros((M.shape[0] * L, M.shape[0] * L))  # zero but on the contacts' rows, every point
        block = np.ix_(idx, idx)
        # a sector: every family of perturbations mu = 2 pi m / N (the whole tuned disk's exponents)
        families = [0.0] if coupling is None else [2.0 * math.pi * m / s.sectors for m in range(s.sectors)]
        for X, w in zip(self._X[rows.start:rows.stop], self.omega[rows.start:rows.stop]):
            lam = []
            for mu in families:
                dF = dF.astype(complex) if mu and not np.iscomplexobj(dF) else dF
                dF[block] = pr.perturbation_jacobian(X, float(w), mu)
                lam.append(hill.exponents(float(w), dF if mu else dF.real, mu))
            lam = np.concatenate(lam) if len(lam) > 1 else lam[0]
            lams.append(lam[np.argsort(-lam.real, kind="stable")] if len(families) > 1 else lam)
        return np.array(lams)

    # ------------------------------------------------------------------ peak
    def peak(self) -> Peak:
        """The largest response on the branch, as the solve located it (``hbm.adapt.locate_peak``).

        Between the neighbours of the largest sampled point the solve found the zero of
        ``d(a^2)/ds`` on the branch; the :class:`Peak` says whether that maximum is interior (not at
        an end of the range or where a stopped branch ends) and converged (located, on a branch that
        reached the end of its range, its estimate within ``tol`` where one was given), and why not.

        Returns
        -------
        Peak
            ``(omega, amplitude)`` in rad/s and m, with ``interior``, ``converged``, ``estimate``
            and ``message``.

        Raises
        ------
        ValueError
            If the response has no points.

        Examples
        --------
        The default case of ``python3 -m hbm``: the damper is in microslip at resonance, the
        peak at about twice its slip amplitude a_min = 7.5e-7 m.

        >>> from hbm import frequency_response
        >>> from hbm.cli.cases import default_case
        >>> case = default_case()
        >>> frf = frequency_response(case.blade, case.element, omega_range=case.omega_range, model="given")
        >>> pk = frf.peak()
        >>> round(pk.omega, -1), round(pk.amplitude / 7.5e-7, 2), pk.interior     # rad/s, a/a_min
        (38770.0, 2.02, True)
        """
        if self._peak is not None:
            return self._peak
        if len(self) == 0:
            raise ValueError("the frequency response has no points")
        i = int(np.argmax(self.amplitude))
        est = errors.peak_estimate(self.error_estimate, i)
        return Peak(float(self.omega[i]), float(self.amplitude[i]), interior=0 < i < len(self) - 1, converged=False,
                    estimate=est, message="the largest sampled point, not located between points")

    def _located_peak_source(self, i: int) -> None:
        """The located peak is a converged point where d(a^2)/ds = 0: the peak source at the sampled
        maximum ``i`` and its neighbours becomes the Newton tolerance, in place of the parabola's bound
        on how far the sampled maximum falls short (``hbm.balance.errors.peak_location``)."""
        if "peak" not in self.error_sources:
            return
        src = self.error_sources["peak"].copy()
        at = slice(max(i - 1, 0), i + 2)
        src[at] = self._newton_part(at)
        self.error_sources = {**self.error_sources, "peak": src}
        self.error_estimate = errors.total(self.error_sources)

    def _newton_part(self, at: slice) -> NDArray[np.float64]:
        """The Newton tolerance's part of the error at the points ``at`` (``hbm.balance.errors.newton_part``)."""
        n = len(self.omega[at])
        if self._problem is None or self._X is None:
            return np.full(n, errors.NEWTON_SHARE * self.rtol)
        others = (np.sum([self.error_sources[s][at] for s in errors.SOURCES if s != "peak"], axis=0)
                  if all(s in self.error_sources for s in errors.SOURCES) else None)
        return errors.newton_part(self._problem, self._X[at], self.rtol, self._newton_steps[at], others)

    # ------------------------------------------------------------------ output
    def to_csv(self, path: str | Path, *, case: str | None = None) -> Path:
        """Write the points as ``hbm.output.FRF_COLUMNS`` (omega, amplitude, phase, x_c, x_s,
        residual, error estimate, units in the names); above one harmonic also every harmonic of
        the response DOF (``X0_m, Xc1_m, Xs1_m, ..., XcH_m, XsH_m`` from :meth:`coefficients`) and
        ``stable`` (0/1, :attr:`stable`).  After the column names, ``# key: value`` lines say what
        the table is: the library version, ``case``, the model, ``tol`` and H
        (``hbm.output.frf_comments``); ``numpy.loadtxt(path, delimiter=",", skiprows=1)`` and
        ``pandas.read_csv(path, comment="#")`` skip them.  Returns the path.

        Parameters
        ----------
        path : str or Path
            The CSV file to write.
        case : str, optional
            What was solved, in words (the ``# case:`` line); default none.

        Returns
        -------
        Path
            The file written.

        Raises
        ------
        ValueError
            Naming ``path``: not a str or Path, a folder, in a folder that does not exist, or a file that cannot
            be written (no permission, a name too long: the operating system's reason in brackets).

        Examples
        --------
        >>> import tempfile, pathlib
        >>> from hbm import Blade, frequency_response
        >>> frf = frequency_response(Blade(mass=1.0, stiffness=1.0e4, damping=2.0, force=1.0),
        ...                          omega_range=(90.0, 110.0))
        >>> path = frf.to_csv(pathlib.Path(tempfile.mkdtemp()) / "frf.csv")
        >>> lines = path.read_text().splitlines()
        >>> [line for line in lines if line.startswith("#")]
        ['# frictiondamp: ...', '# model: none (linear)', "# tol: 0.001 (target relative error of amplitude_m; error_rel is each point's estimate)", '# harmonics: 1']
        >>> table = [line for line in lines if not line.startswith("#")]
        >>> table[0].split(",")[:2], len(table) == len(frf.omega) + 1
        (['omega_rad_s', 'amplitude_m'], True)
        >>> import numpy as np
        >>> data = np.loadtxt(path, delimiter=",", skiprows=1)   # the comment lines are skipped
        >>> float(data[0, 0]), float(data[-1, 0])                # omega_range, rad/s
        (90.0, 110.0)
        """
        try:
            return write_frf_csv(path, self, case=case)
        except OSError as exc:  # a folder one may not write in, a name too long: named, as a missing folder is
            raise ValueError(f"path must be a file that can be written, got path={shown(str(path))} "
                             f"({exc.strerror or exc})") from exc

    def to_dataframe(self, *, case: str | None = None) -> Any:
        """The points as a ``pandas.DataFrame`` with the columns of :meth:`to_csv` (units in the
        names), one row per point in continuation order; ``attrs`` holds the CSV's header lines
        (version, ``case``, model, ``tol``, H: ``hbm.output.frf_comments``).

        Needs pandas (the optional extra: ``pip install "frictiondamp[pandas]"``).

        Parameters
        ----------
        case : str, optional
            What was solved, in words (``attrs["case"]``).

        Returns
        -------
        pandas.DataFrame
            The same numbers as :meth:`to_csv` writes (it writes them with ``repr``, so
            ``pandas.read_csv(path, comment="#")`` reads the same frame back).

        Raises
        ------
        ImportError
            Without pandas, naming the extra.
        """
        pd = pandas_module()
        frame = pd.DataFrame(frf_table(self))
        frame.attrs.update({k: v for k, v in frf_comments(self, case).items() if v is not None})
        return frame

    def plot(self, ax: Any = None, *, label: str | None = None, peak: bool = True, omega_unit: str = "rad/s",
             amplitude_unit: str = "m", error_band: bool = True, **kwargs: Any) -> Any:
        """Amplitude against omega on ``ax`` (a new figure if None): stable parts solid, unstable
        dashed (:attr:`stable`), the estimated error as a shaded band; marks the peak. Returns ax.

        The band is ``amplitude * (1 +- error_estimate)``: ``error_estimate`` is the relative
        error of the amplitude against the physical system, so the band is where the true
        response lies by the estimate (``docs/validation.md``, "Error estimates").  A ribbon along
        the branch (the upper edge out, the lower edge back), so it follows folds; a point
        without an estimate (NaN) has no width.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Where to draw; default a new figure.
        label : str, optional
            Legend label of the curve.
        peak : bool, optional
            Mark the peak (:meth:`peak`) with a dot.  Default True.
        omega_unit : {"rad/s", "Hz"}, optional
            Unit of the frequency axis.  Default "rad/s".
        amplitude_unit : {"m", "um"}, optional
            Unit of the amplitude axis.  Default "m".
        error_band : bool, optional
            Draw the estimated error as a band in the curve's colour, where the result has an
            estimate (``tol`` not None).  Default True.
        **kwargs
            Passed to ``ax.plot`` (colour, line style): properties of a matplotlib line; another keyword is a
            TypeError naming it.

        Returns
        -------
        matplotlib.axes.Axes
            The axes drawn on.

        Examples
        --------
        >>> import matplotlib
        >>> matplotlib.use("Agg")
        >>> from hbm import Blade, frequency_response
        >>> frf = frequency_response(Blade(mass=1.0, stiffness=1.0e4, damping=2.0, force=1.0),
        ...                          omega_range=(90.0, 110.0))
        >>> ax = frf.plot(label="bare blade")
        >>> ax.get_ylabel(), len(ax.lines), len(ax.patches)   # the curve, its peak and the error band
        ('amplitude (m)', 2, 1)
        >>> len(frf.plot(error_band=False).patches)
        0
        """
        peak, error_band = flag("peak", peak), flag("error_band", error_band)
        # a single DOF at H = 1 with a passive element loses stability only at folds (the sum of
        # its two exponents is minus its damping): its stability is computed only on a folded branch
        known = (self._stable is not None or not self._problem.one_dof or len(self.fold_after) > 0)
        ax, color = plot_branch(ax, self.omega, self.amplitude, self.stable if known else None, label=label,
                                omega_unit=omega_unit, amplitude_unit=amplitude_unit, **kwargs)
        if error_band and len(self) and np.any(np.isfinite(self.error_estimate)):
            plot_error_band(ax, self.omega, self.amplitude, self.error_estimate, color=color, omega_unit=omega_unit,
                            amplitude_unit=amplitude_unit)
        if peak and len(self):
            pk = self.peak()
            ax.plot([pk.omega * OMEGA_UNITS[omega_unit][0]], [pk.amplitude * AMPLITUDE_UNITS[amplitude_unit][0]], "o",
                    color=color, ms=4)
        return ax


__all__ = ["FrequencyResponse", "Peak", "Response", "Segment", "model_label", "PEAK_XTOL_FACTOR"]


def _newton_steps(problem: HarmonicBalance, run: cont.ContinuationResult, amplitude: NDArray) -> NDArray:
    """Per point the relative change of the response DOF's amplitude that the Newton step its converged residual
    still asks makes (``ContinuationResult.newton_step``: ``hbm.balance.errors.newton_part`` takes it where it
    exceeds the tolerance's part); NaN where it is not known."""
    step = run.newton_step
    if step is None or len(step) != len(run.y) or not len(run.y):
        return np.full(len(run.y), np.nan)
    X = problem.to_physical(run.y + step)[0]
    r = list(problem.dofs).index(problem.response_dof)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.abs(np.hypot(X[:, r, 1], X[:, r, 2]) - amplitude) / amplitude
