"""Nonlinear modes of friction-damped structures: the extended periodic motion concept (EPMC).

The autonomous system (Krack 2015, "Nonlinear modal analysis of nonconservative systems using
harmonic balance", Computers & Structures 154, 59-71)::

    M q'' + (C - 2 D omega M) q' + K q + sum_k P_k f_k(q) = 0

has a periodic motion at every modal amplitude ``a``: the negative mass-proportional damping
``-2 D omega M`` supplies per cycle what the contacts and ``C`` dissipate, and ``D`` is the
modal damping ratio.  Harmonic balance with H harmonics, ``q = a Psi(omega t)``, unknowns
``y = (Psi (n (2H+1)), omega, D, log10 a)``, ``Psi`` DOF-major in the layout
``[Psi0, Psic1, Psis1, ..., PsicH, PsisH]`` of every DOF.  Per harmonic ``h`` (complex
``Psi_h = Psic_h - i Psis_h``)::

    R_h = [K - (h omega)^2 M + i h omega (C - 2 D omega M)] Psi_h + F_h(a Psi, omega) / a = 0,
    sum_h Psi_h^H M Psi_h = 1                     (amplitude normalisation: a^2 = sum Q_h^H M Q_h),
    sum_h h Psis_h[phase_dof] = 0                 (the velocity of phase_dof is zero at t = 0),

as NLvib's ``HB_residual`` with 'NMA'.  ``F_h`` are the contacts' force harmonics
(``HarmonicBalance.forces``: AFT of the time law, or the describing function at H = 1).
``docs/nonlinear_modes.md`` derives every coefficient and the Jacobian.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np
from numpy.typing import NDArray

from contact_models.base import DEFAULT_RTOL

from . import continuation as cont
from ._validation import NEWTON_TOL, count, newton_tolerance, number_array, positive, relative_tolerance
from .balance.residual import HarmonicBalance, as_contacts, as_structure, samples_within_bound
from .structure import Structure

LN10 = math.log(10.0)


def _dense(A: Any) -> NDArray[np.float64]:
    return np.asarray(A.toarray() if hasattr(A, "toarray") else A, dtype=float)


class ModeBalance:
    """``R(y)`` and ``dR/dy`` of the EPMC balance (module docstring), in physical units.

    Parameters
    ----------
    system : hbm.Structure or hbm.Blade
    contacts : sequence of hbm.Contact (or a bare element on a one-DOF system)
    harmonics : int
    n_t : int, optional
        AFT samples per period (default of ``hbm.HarmonicBalance``).
    phase_dof : int
        The DOF whose velocity vanishes at t = 0.
    rtol : float
        Relative tolerance passed to the elements.
    """

    def __init__(self, system: Any, contacts: Any, *, harmonics: int = 1, n_t: int | None = None,
                 phase_dof: int = 0, rtol: float = DEFAULT_RTOL) -> None:
        s = self.structure = as_structure(system)
        if s.sector_angle is not None:
            raise ValueError(f"system must be a whole structure: the nonlinear modes of one sector of a cyclic "
                             f"structure are not provided (solve its full() disk), got system={system!r}")
        self.contacts = as_contacts(contacts, s.n, s.physical_dofs)
        if not self.contacts:
            raise ValueError("contacts must hold at least one contact (a linear structure's modes are its "
                             "eigenvectors), got contacts=[]")
        dof0 = self.contacts[0].dofs[0]
        # the one balance's assembly of the contacts' harmonics (its forcing is not used here)
        self.hb = HarmonicBalance(Structure(s.M, s.C, s.K, force=np.eye(s.n)[dof0]), self.contacts,
                                  harmonics=harmonics, n_t=n_t, response_dof=dof0, rtol=rtol)
        self.H, self.L, self.n_t, self.n = self.hb.H, self.hb.L, self.hb.n_t, s.n
        self.phase_dof = s._dof("phase_dof", phase_dof)
        self.M, self.C, self.K = _dense(s.M), _dense(s.C), _dense(s.K)
        L = self.L
        self.idx = (np.asarray(self.hb.dofs)[:, None] * L + np.arange(L)).ravel()  # contact DOFs in Psi
        self.nfev = 0
        self.uw = np.ones(self.n * self.L + 3)
        self.rw = np.ones(self.n * self.L + 2)

    @property
    def unknowns(self) -> int:
        return self.n * self.L + 3

    def operator(self, omega: float, D: float) -> tuple[NDArray, NDArray, NDArray]:
        """The linear part ``A`` (n L, n L) of ``R = A Psi + F/a`` and its derivatives in omega and D."""
        n, L, H = self.n, self.L, self.H
        M, C, K = self.M, self.C, self.K
        A = np.zeros((3, n, L, n, L))  # A, dA/domega, dA/dD
        A[0, :, 0, :, 0] = K
        for h in range(1, H + 1):
            c, s = 2 * h - 1, 2 * h
            blocks = ((K - (h * omega) ** 2 * M, h * omega * C - 2.0 * D * h * omega ** 2 * M),
                      (-2.0 * h * h * omega * M, h * C - 4.0 * D * h * omega * M),
                      (np.zeros_like(M), -2.0 * h * omega ** 2 * M))
            for k, (Zr, Zi) in enumerate(blocks):
                A[k, :, c, :, c] = Zr
                A[k, :, s, :, s] = Zr
                A[k, :, c, :, s] = Zi
                A[k, :, s, :, c] = -Zi
        N = n * L
        return A[0].reshape(N, N), A[1].reshape(N, N), A[2].reshape(N, N)

    def contact_forces(self, Q: NDArray, omega: float) -> tuple[NDArray, NDArray, NDArray]:
        """The contacts' harmonics on every DOF: ``F`` (n L,), ``dF/dQ`` (n L, n L), ``dF/domega`` (n L,)."""
        N, i = self.n * self.L, self.idx
        Fa, dFa, Fwa = self.hb.forces(Q.reshape(self.n, self.L)[self.hb.dofs], omega)
        self.nfev += 1
        F, Fw, dF = np.zeros(N), np.zeros(N), np.zeros((N, N))
        F[i], Fw[i] = Fa.ravel(), Fwa.ravel()
        dF[np.ix_(i, i)] = dFa
        return F, dF, Fw

    def __call__(self, y: NDArray) -> tuple[NDArray, NDArray]:
        """``R`` (n L + 2,) and ``J`` (n L + 2, n L + 3) at ``y = (Psi, omega, D, log10 a)``."""
        N = self.n * self.L
        psi, omega, D, la = y[:N], float(y[N]), float(y[N + 1]), float(y[N + 2])
        a = 10.0 ** la
        A, Aw, AD = self.operator(omega, D)
        F, dF, Fw = self.contact_forces(a * psi, omega)
        R = np.empty(N + 2)
        J = np.zeros((N + 2, N + 3))
        R[:N] = A @ psi + F / a
        J[:N, :N] = A + dF
        J[:N, N] = Aw @ psi + Fw / a
        J[:N, N + 1] = AD @ psi
        J[:N, N + 2] = LN10 * (dF @ psi - F / a)  # d(F(a Psi)/a)/da * da/dlog10(a)
        Mpsi = np.kron(self.M, np.eye(self.L)) @ psi
        R[N] = psi @ Mpsi - 1.0
        J[N, :N] = 2.0 * Mpsi
        ph = self.phase_dof * self.L + 2 * np.arange(1, self.H + 1)  # the Psis_h of phase_dof
        R[N + 1] = float(np.arange(1, self.H + 1) @ psi[ph])
        J[N + 1, ph] = np.arange(1, self.H + 1)
        return R, J

    def set_scales(self, phi: NDArray, omega: float) -> None:
        """Scales of :meth:`scaled` from the stuck mode: ``Psi`` by ``max|phi|``, omega by the stuck
        frequency, D and log10 a by 1; the dynamic rows by the mode's largest inertia force
        ``omega^2 max|M phi|``, the phase row by ``max|phi|``."""
        n = self.n * self.L
        psi_ref, r_ref = float(np.max(np.abs(phi))), omega ** 2 * float(np.max(np.abs(self.M @ phi)))
        self.uw = np.concatenate([np.full(n, psi_ref), [omega, 1.0, 1.0]])
        self.rw = np.concatenate([np.full(n, r_ref), [1.0, psi_ref]])

    def scaled(self, u: NDArray) -> tuple[NDArray, NDArray]:
        """``R`` and ``J`` in the scaled unknowns ``u = y / uw``, rows divided by ``rw`` (:meth:`set_scales`)."""
        R, J = self(u * self.uw)
        return R / self.rw, J * self.uw[None, :] / self.rw[:, None]

    def energies(self, y: NDArray) -> tuple[float, float, float]:
        """Per cycle at the point ``y``: the contacts' dissipation, the dissipation of ``C`` and the
        work of the negative damping ``2 D omega M`` (J): the first two sum to the third on a mode.

        From the harmonics: ``int f u' dt = pi sum_h h (Fc_h Us_h - Fs_h Uc_h)`` for a force
        ``f`` on a displacement ``u``, and ``int q'^T B q' dt = pi omega sum_h h^2 Q_h^H B Q_h``.
        """
        N, L, H = self.n * self.L, self.L, self.H
        omega, D, a = float(y[N]), float(y[N + 1]), 10.0 ** float(y[N + 2])
        Q = (a * y[:N]).reshape(self.n, L)
        h = np.arange(1, H + 1)
        w_contacts = 0.0
        for c in self.contacts:
            u = Q[c.dofs[0]] - Q[c.dofs[1]] if len(c.dofs) == 2 else Q[c.dofs[0]]
            f = c.element.harmonic_force(u, omega, n_t=self.n_t, rtol=self.hb.rtol)[0]
            w_contacts += math.pi * float(h @ (f[1::2] * u[2::2] - f[2::2] * u[1::2]))

        def quad(B):
            return math.pi * omega * float(sum(h[k] ** 2 * (Q[:, 2 * k + 1] @ B @ Q[:, 2 * k + 1]
                                                           + Q[:, 2 * k + 2] @ B @ Q[:, 2 * k + 2])
                                               for k in range(H)))

        return w_contacts, quad(self.C), 2.0 * D * omega * quad(self.M)

    def stuck_mode(self, mode: int) -> tuple[NDArray, float, float]:
        """``(phi, omega, D)``: the linear mode ``mode`` (from 0, by frequency) with every contact
        at its linear coefficients ``(k_s, k_c)``, mass-normalised; D from ``phi^T (omega C + K_c) phi /
        (2 omega^2)`` (a first guess that Newton corrects when the damping is not modal)."""
        Linv = np.linalg.inv(np.linalg.cholesky(self.M))  # M = L L^T: the symmetric problem L^-1 K L^-T
        omega = 0.0
        for _ in range(6):  # fixed point for frequency-dependent stiffnesses
            Ks, Kc = self._stuck_matrices(omega)
            lam, V = np.linalg.eigh(Linv @ (self.K + Ks) @ Linv.T)
            if lam[mode] <= 0.0:
                raise ValueError(f"mode must have a positive stuck stiffness, got mode={mode} with eigenvalue "
                                 f"{lam[mode]:.3g}")
            new = math.sqrt(lam[mode])
            done = abs(new - omega) <= 1e-13 * new
            omega = new
            if done:
                break
        phi = Linv.T @ V[:, mode]
        phi *= np.sign(phi[np.argmax(np.abs(phi))])
        D = float(phi @ (omega * self.C + Kc) @ phi) / (2.0 * omega ** 2)
        return phi, omega, D

    def _stuck_matrices(self, omega: float) -> tuple[NDArray, NDArray]:
        Ks, Kc = np.zeros((self.n, self.n)), np.zeros((self.n, self.n))
        for c in self.contacts:
            ks, kc = (float(v) for v in c.element.linear_coefficients(omega))
            if not (math.isfinite(ks) and math.isfinite(kc)):
                raise ValueError(f"element={c.element!r} is rigid while stuck (stiffness={ks!r}): the stuck "
                                 f"linear mode the branch starts from does not exist")
            P = np.zeros(self.n)
            P[c.dofs[0]] = 1.0
            if len(c.dofs) == 2:
                P[c.dofs[1]] = -1.0
            Ks += ks * np.outer(P, P)
            Kc += kc * np.outer(P, P)
        return Ks, Kc


@dataclass
class NonlinearModes:
    """One nonlinear mode along its amplitude: per point ``amplitude`` (a, the modal amplitude with
    ``a^2 = sum_h Q_h^H M Q_h``), ``omega`` (rad/s), ``damping_ratio`` (D), ``shapes`` (points, n,
    2H+1: the amplitude-normalised harmonics Psi, ``q = a Psi``), and how the run went."""

    amplitude: NDArray[np.float64]
    omega: NDArray[np.float64]
    damping_ratio: NDArray[np.float64]
    shapes: NDArray[np.float64]
    harmonics: int
    n_t: int
    success: bool
    message: str
    nsteps: int = 0  #: accepted continuation steps
    nrejected: int = 0  #: rejected step attempts
    nit: int = 0  #: Newton updates (location of requested amplitudes included)
    nfev: int = 0  #: residual evaluations
    residual_norm: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))
    balance: ModeBalance | None = field(default=None, repr=False)
    points: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 0)), repr=False)

    def __len__(self) -> int:
        return self.amplitude.size

    def coefficients(self, dof: int) -> NDArray[np.float64]:
        """The displacement harmonics ``a Psi`` of ``dof`` along the branch (points, 2H+1)."""
        n = self.shapes.shape[1]
        if isinstance(dof, bool) or not isinstance(dof, (int, np.integer)) or not 0 <= dof < n:
            raise ValueError(f"dof must be a DOF index in 0..{n - 1}, got dof={dof!r}")
        return self.amplitude[:, None] * self.shapes[:, dof, :]

    def energies(self) -> NDArray[np.float64]:
        """(points, 3): per cycle the contacts' dissipation, that of C, and the negative damping's work."""
        return np.array([self.balance.energies(y) for y in self.points])


def nonlinear_modes(system: Any, contacts: Any, *, mode: int = 0, amplitude_range: Sequence[float] | None = None,
                    harmonics: int = 1, n_t: int | None = None, amplitudes: Sequence[float] | None = None,
                    phase_dof: int | None = None, rtol: float = DEFAULT_RTOL, newton_tol: float = NEWTON_TOL,
                    max_step: float = 0.1, max_steps: int = 2000, tol: float | None = None) -> NonlinearModes:
    """Trace the nonlinear mode ``mode`` of a structure with contacts over its modal amplitude (EPMC).

    Parameters
    ----------
    system : hbm.Structure or hbm.Blade
    contacts : sequence of hbm.Contact (a bare element on a one-DOF system)
        At H > 1 every element needs a time law; at H = 1 any element works.
    mode : int, default 0
        Which linear mode (from 0, by frequency) of the stuck structure the branch starts from.
    amplitude_range : (a0, a1)
        Modal amplitudes (``a^2 = sum_h Q_h^H M Q_h``), ``0 < a0 < a1``; default the span of
        ``amplitudes``.
    harmonics : int, default 1
    n_t : int, optional
        AFT samples per period (default ``contact_models.base.default_samples(H)``).
    amplitudes : sequence of float, optional
        Return the mode at exactly these amplitudes (located on the traced branch) instead of
        at the continuation's points.
    phase_dof : int, optional
        DOF whose velocity is zero at t = 0; default the largest entry of the stuck mode.
    rtol : float
        Relative tolerance passed to the elements.
    newton_tol : float
        Newton tolerance on the scaled residual (relative to the mode's inertia force), in (0, 1).
    max_step, max_steps
        Continuation step (scaled units: log10 a, omega/omega_0, D, Psi/max|phi|) and budget.
    tol : float, optional
        The earlier name of ``newton_tol``, read for one release with a ``DeprecationWarning``: in
        :func:`hbm.frequency_response` ``tol`` is the target error of the answer, which the modes do not take.

    Examples
    --------
    >>> import numpy as np
    >>> from contact_models import Macroslip
    >>> from hbm import Contact, Structure
    >>> s = Structure(np.eye(2), 0.01 * np.eye(2), [[2.0, -1.0], [-1.0, 2.0]], force=[1.0, 0.0])
    >>> m = nonlinear_modes(s, [Contact(Macroslip(stiffness=1.0, slip_force=0.1), dof=0)],
    ...                     amplitudes=[0.01, 10.0], harmonics=1)
    >>> np.round(m.omega, 4).tolist()  # stuck: sqrt((5 - sqrt(5))/2); gross slip: towards the free 1
    [1.1756, 1.0007]
    """
    mode = count("mode", mode, 0)
    tol = relative_tolerance("newton_tol", newton_tolerance("nonlinear_modes", newton_tol, tol), 1.0)
    max_step, max_steps = positive("max_step", max_step), count("max_steps", max_steps)
    a0, a1, targets = _amplitudes(amplitude_range, amplitudes)
    bal = ModeBalance(system, contacts, harmonics=harmonics, n_t=samples_within_bound(n_t), phase_dof=0, rtol=rtol)
    if mode >= bal.n:
        raise ValueError(f"mode must be in 0..{bal.n - 1}, got mode={mode}")
    phi, w0, D0 = bal.stuck_mode(mode)
    bal.phase_dof = int(np.argmax(np.abs(phi))) if phase_dof is None else bal.structure._dof("phase_dof", phase_dof)
    y0 = np.zeros(bal.unknowns)
    y0[np.arange(bal.n) * bal.L + 1] = phi
    y0[-3:] = w0, D0, math.log10(a0)
    bal.set_scales(phi, w0)
    scaled = bal.scaled

    res = cont.continuation(scaled, y0 / bal.uw, parameter=-1, bounds=(math.log10(a0), math.log10(a1)),
                            tol=tol, max_step=max_step, max_steps=max_steps, locate_folds=False, from_bound=True)
    ys, rn, nit, nfev = res.y, res.residual_norm, res.nit, res.nfev
    if targets is not None:
        ys, rn, extra = _locate_amplitudes(scaled, res, np.log10(targets), tol)
        nit, nfev = nit + extra[0], nfev + extra[1]
    ys = ys * bal.uw
    N = bal.n * bal.L
    message = res.message
    if res.status == cont.Status.TURNED_BACK:  # in the mode's own terms: the amplitude where it turned
        message = (f"{cont.MESSAGES[res.status]}: it turned at amplitude a = {10.0 ** float(res.y[:, -1].max()):.6g} "
                   f"and came back to a0 = {a0:.6g} before reaching a1 = {a1:.6g} (the mode folds in its amplitude: "
                   "start amplitude_range at an a0 below the amplitude the branch comes back down to)")
    if targets is not None and len(ys) < len(targets):
        message += f"; {len(targets) - len(ys)} of the {len(targets)} amplitudes asked for were not reached or located"
    return NonlinearModes(amplitude=10.0 ** ys[:, -1], omega=ys[:, N], damping_ratio=ys[:, N + 1],
                          shapes=ys[:, :N].reshape(-1, bal.n, bal.L), harmonics=bal.H, n_t=bal.n_t,
                          success=bool(res.success and (targets is None or len(ys) == len(targets))),
                          message=message, nsteps=res.nsteps, nrejected=res.nrejected, nit=nit, nfev=nfev,
                          residual_norm=rn, balance=bal, points=ys)


def _amplitudes(amplitude_range, amplitudes) -> tuple[float, float, NDArray | None]:
    """``(a0, a1, targets)`` from the two ways of asking (validated)."""
    targets = None
    if amplitudes is not None:
        try:  # numbers only: a bool (True read as 1.0 m) or a string is refused below, naming amplitudes
            targets = number_array("amplitudes", amplitudes).ravel()
        except ValueError:
            targets = np.full(1, np.nan)
        if targets.size == 0 or not np.all(np.isfinite(targets)) or np.any(targets <= 0.0):
            raise ValueError(f"amplitudes must be finite numbers > 0, got amplitudes={amplitudes!r}")
    if amplitude_range is None:
        if targets is None:
            raise ValueError("amplitude_range must be given as (a0, a1) (or amplitudes), got amplitude_range=None")
        return float(targets.min()), float(targets.max()), targets
    try:
        a0, a1 = (positive(f"amplitude_range[{i}]", v) for i, v in enumerate(amplitude_range))
    except (TypeError, ValueError) as exc:
        raise ValueError(f"amplitude_range must be a pair 0 < a0 < a1, got amplitude_range={amplitude_range!r}"
                         ) from exc
    if not a0 < a1:
        raise ValueError(f"amplitude_range must have a0 < a1, got amplitude_range={amplitude_range!r}")
    if targets is not None and (targets.min() < a0 or targets.max() > a1):
        raise ValueError(f"amplitudes must lie in amplitude_range={amplitude_range!r}, got amplitudes={amplitudes!r}")
    return a0, a1, targets


def _locate_amplitudes(fun, res: cont.ContinuationResult, targets: NDArray, tol: float):
    """The branch's points at exactly ``log10 a = targets`` (scaled units), with the work spent
    ``(Newton updates, evaluations)``: located between their neighbours on the branch
    (``hbm.continuation.locate``), then corrected by Newton with ``log10 a`` held at the target."""
    ys = res.y
    out, rn, work = [], [], [0, 0]
    for t in targets:
        i = np.flatnonzero((ys[:-1, -1] - t) * (ys[1:, -1] - t) <= 0.0)
        if i.size == 0:
            continue
        ya, yb = ys[i[0]], ys[i[0] + 1]
        if ya[-1] == t or yb[-1] == t:
            y = ya if ya[-1] == t else yb
        else:
            loc = cont.locate(fun, ya, yb, lambda y, tg, t=t: y[-1] - t, tol=tol, xtol=1e-12)
            if loc is None:
                continue
            work[1] += loc.nfev
            y = loc.y
        y, r, it = _fixed_parameter_newton(fun, y, t, tol)
        work[0] += it
        work[1] += it + 1
        if r <= tol:
            out.append(y)
            rn.append(r)
    return np.array(out).reshape(-1, ys.shape[1]), np.array(rn), work


def _fixed_parameter_newton(fun, y, t, tol, max_iter=8):
    """Newton on ``R(y) = 0`` with the last component held at ``t``: ``(y, |R|, updates)``."""
    y = np.array(y, dtype=float)
    y[-1] = t
    R, J = fun(y)
    r = float(np.linalg.norm(R))
    it = 0
    while r > tol and it < max_iter:
        y[:-1] -= np.linalg.solve(J[:, :-1], R)
        R, J = fun(y)
        r = float(np.linalg.norm(R))
        it += 1
    return y, r, it


__all__ = ["nonlinear_modes", "NonlinearModes", "ModeBalance"]
