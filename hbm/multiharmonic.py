"""Multi-harmonic balance of a structure with contacts, condensed to the contact DOFs.

Model (``hbm.structure``; derivation with every coefficient in ``docs/multiharmonic.md``)::

    M x'' + C x' + K x + sum_k P_k f_k(x) = f cos(omega t)

Unknowns: the harmonic coefficients ``X_a = [X0, Xc1, Xs1, ..., XcH, XsH]`` of the
*condensation DOFs* ``a`` (every DOF a contact touches, and the response DOF), DOF-major, and
omega::

    y = (X_a0, X_a1, ..., omega),   length n_a (2H+1) + 1.

Condensation (exact, per harmonic): with ``Z(s) = K + s C + s^2 M`` and the compliance
``G_h = [Z(i h omega)^-1]_aa`` at those DOFs, the linear DOFs are eliminated and the balance is

    R = X - X_lin(omega) + G(omega) F(X) = 0,

``X_lin`` the linear response to ``f cos(omega t)`` at the DOFs a (first harmonic only),
``F`` the contact forces' harmonics at the DOFs a (AFT, ``ContactElement.harmonic_force``),
and ``G`` acting harmonic by harmonic on the complex coefficients ``c_h = Xc_h - i Xs_h``.
``G`` and its omega-derivative come from the state-space modes of (M, C, K) computed once
(``hbm.structure.modal_compliance``), so an evaluation costs ``O(n_a^2 n H)`` and the Newton
system has ``n_a (2H+1) + 1`` unknowns whatever the structure's size.

Jacobian: ``dR/dX = I + G dF/dX`` (``dF/dX = E J_t E^-1`` analytic), ``dR/domega =
-dX_lin/domega + (dG/domega) F + G dF/domega``.  Scaled for the continuation: X by ``x_ref``
(the stuck structure's largest static deflection), omega by the range width, R by ``x_ref``;
the arclength weights every harmonic of every DOF by the current first-harmonic amplitude of
the condensation DOFs (one weight for all harmonics, so a small harmonic's relative change does
not dictate the step), as ``hbm.frf`` does for the single harmonic.
"""

from __future__ import annotations

import math
from typing import Any, Callable, Sequence

import numpy as np
from numpy.typing import NDArray

from . import continuation as cont
from ._validation import count, omega_range_pair, positive
from .structure import Contact, Structure, modal_compliance

#: Newton tolerance on |R|/x_ref as a fraction of ``rtol`` (as ``hbm.frf``).
NEWTON_TOL_FACTOR = 5e-3
#: The peak is located to this fraction of its bracket times sqrt(rtol) in arclength.
PEAK_XTOL_FACTOR = 1e-3
#: Hill's method runs on the structure itself up to this many DOFs, else on a Craig-Bampton
#: model of the condensation DOFs plus ``STABILITY_MODES`` fixed-interface modes.
STABILITY_FULL_DOFS = 6
STABILITY_MODES = 4


def to_complex(V: NDArray) -> NDArray[np.complex128]:
    """``(.., 2H+1, ...)`` real layout on axis 1 -> ``(.., H+1, ...)`` complex ``c_h = Xc - i Xs``."""
    c = np.empty((V.shape[0], (V.shape[1] + 1) // 2) + V.shape[2:], dtype=complex)
    c[:, 0] = V[:, 0]
    c[:, 1:] = V[:, 1::2] - 1j * V[:, 2::2]
    return c


def from_complex(c: NDArray) -> NDArray[np.float64]:
    """Inverse of :func:`to_complex` (real layout on axis 1)."""
    V = np.empty((c.shape[0], 2 * c.shape[1] - 1) + c.shape[2:])
    V[:, 0] = c[:, 0].real
    V[:, 1::2] = c[:, 1:].real
    V[:, 2::2] = -c[:, 1:].imag
    return V


class Condensed:
    """The structure's compliance at a set of DOFs for harmonics 0..H (state-space modes)."""

    def __init__(self, structure: Structure, dofs: Sequence[int], harmonics: int) -> None:
        self.lam, V, B = modal_compliance(structure.M, structure.C, structure.K)
        self.V, self.B = V, B
        self.dofs = np.asarray(dofs, dtype=int)
        self.Va = V[self.dofs]  # (n_a, 2n)
        self.Ba = B[:, self.dofs]  # (2n, n_a)
        self.bf = B @ structure.force  # (2n,)
        self.h = np.arange(harmonics + 1)
        self._cache: tuple | None = None

    def at(self, omega: float) -> tuple[NDArray, NDArray, NDArray, NDArray]:
        """``(G, dG/domega, x_lin, dx_lin/domega)``: G (H+1, n_a, n_a) complex, x_lin (n_a,) complex."""
        if self._cache is not None and self._cache[0] == omega:
            return self._cache[1]
        S = 1.0 / (1j * self.h[:, None] * omega - self.lam[None, :])  # (H+1, 2n)
        dS = -1j * self.h[:, None] * S * S
        G = np.einsum("aj,hj,jb->hab", self.Va, S, self.Ba)
        dG = np.einsum("aj,hj,jb->hab", self.Va, dS, self.Ba)
        G[0] = G[0].real
        xl = self.Va @ (S[1] * self.bf)
        dxl = self.Va @ (dS[1] * self.bf)
        out = (G, dG, xl, dxl)
        self._cache = (omega, out)
        return out

    def response(self, omega: float, F: NDArray) -> NDArray[np.complex128]:
        """Complex harmonics (n, H+1) of every DOF for contact-force harmonics F (n_a, 2H+1)."""
        S = 1.0 / (1j * self.h[:, None] * omega - self.lam[None, :])
        c = to_complex(F)  # (n_a, H+1)
        Xall = -np.einsum("nj,hj,ja,ah->nh", self.V, S, self.Ba, c)
        Xall[:, 1] += self.V @ (S[1] * self.bf)
        Xall[:, 0] = Xall[:, 0].real
        return Xall


class MultiHarmonicBalance:
    """``R(u)`` and ``dR/du`` of the condensed balance in scaled unknowns (module docstring)."""

    def __init__(self, structure: Structure, contacts: Sequence[Contact], dofs: Sequence[int], *,
                 harmonics: int, n_t: int, rtol: float, x_ref: float, omega_ref: float) -> None:
        self.structure = structure
        self.contacts = list(contacts)
        self.dofs = list(dofs)
        self.H = harmonics
        self.L = 2 * harmonics + 1
        self.n_t = n_t
        self.rtol = rtol
        self.x_ref = x_ref
        self.omega_ref = omega_ref
        self.cond = Condensed(structure, dofs, harmonics)
        self.na = len(dofs)
        pos = {d: i for i, d in enumerate(dofs)}
        self._attach = [(c.element, [pos[d] for d in c.dofs]) for c in self.contacts]
        self.nfev = 0  #: element harmonic-force evaluations
        self.ncalls = 0  #: balance evaluations
        self.nstuck = 0  #: (the stuck-stiffness shortcut of ``hbm.residual`` is not taken here)
        self.fresh_omega_derivative = False  #: (read by ``FrequencyResponse.peak``; omega-derivatives are exact here)

    def forces(self, X: NDArray, omega: float, *, perturbation: bool = False) -> tuple[NDArray, NDArray, NDArray]:
        """Contact forces' harmonics F (n_a, L), dF/dX (n_a L, n_a L), dF/domega (n_a, L).

        ``perturbation=True`` (Hill's method): an element whose displacement stays within its
        linear range all period is a linear spring for a perturbation (nothing slips, its
        internal state does not move), so its Jacobian is ``k_s I``; the balance's own Jacobian
        differs only in the static term, where the centring convention of a Masing element's
        periodic state (``contact_models._masing``) gives ``K_inf``.
        """
        from contact_models.numerics.masing import to_time

        na, L = self.na, self.L
        F = np.zeros((na, L))
        dF = np.zeros((na, L, na, L))
        Fw = np.zeros((na, L))
        for el, ix in self._attach:
            Xrel = X[ix[0]] - X[ix[1]] if len(ix) == 2 else X[ix[0]]
            f, J, fw = el.harmonic_force_unchecked(np.ascontiguousarray(Xrel), omega, self.n_t, self.rtol)
            self.nfev += 1
            if perturbation:
                x = to_time(np.ascontiguousarray(Xrel), max(self.n_t, 4 * L))
                if 0.5 * float(np.ptp(x)) <= el.linear_amplitude(omega):
                    J = float(el.linear_coefficients(omega)[0]) * np.eye(L)
            signs = ((ix[0], 1.0), (ix[1], -1.0)) if len(ix) == 2 else ((ix[0], 1.0),)
            for i, si in signs:
                F[i] += si * f
                Fw[i] += si * fw
                for j, sj in signs:
                    dF[i, :, j, :] += (si * sj) * J
        return F, dF.reshape(na * L, na * L), Fw

    def physical(self, X: NDArray, omega: float) -> tuple[NDArray, NDArray]:
        """``R`` (n_a L,) and ``J`` (n_a L, n_a L + 1) in physical units."""
        self.ncalls += 1
        na, L = self.na, self.L
        G, dG, xl, dxl = self.cond.at(omega)
        F, dF, Fw = self.forces(X, omega)
        cF = to_complex(F)  # (n_a, H+1)
        GF = from_complex(np.einsum("hab,bh->ah", G, cF))
        R = X + GF
        R[:, 1] -= xl.real
        R[:, 2] += xl.imag
        dGF = from_complex(np.einsum("hab,bh->ah", dG, cF))
        GFw = from_complex(np.einsum("hab,bh->ah", G, to_complex(Fw)))
        Rw = dGF + GFw
        Rw[:, 1] -= dxl.real
        Rw[:, 2] += dxl.imag
        cdF = to_complex(dF.reshape(na, L, na * L))  # (n_a, H+1, n_a L)
        GdF = from_complex(np.einsum("hab,bhk->ahk", G, cdF)).reshape(na * L, na * L)
        J = np.empty((na * L, na * L + 1))
        J[:, :-1] = GdF
        J[np.arange(na * L), np.arange(na * L)] += 1.0
        J[:, -1] = Rw.ravel()
        return R.ravel(), J

    def __call__(self, u: NDArray) -> tuple[NDArray, NDArray]:
        """Scaled ``R/(x_ref sigma)`` and its Jacobian in ``u = (X/x_ref, omega/omega_ref)``.

        ``sigma = max(1, |u_1|)``, ``|u_1|`` the first-harmonic amplitude of the condensation
        DOFs in units of x_ref: the Newton tolerance is relative to the response once it
        exceeds the static deflection (rounding of a resonant amplitude cannot meet an absolute
        one).  sigma's own derivative multiplies R and vanishes on the branch, so it is left
        out of the Jacobian (Newton stays quadratic near the branch; the tangent is exact).
        """
        xr, wr = self.x_ref, self.omega_ref
        X = (u[:-1] * xr).reshape(self.na, self.L)
        R, J = self.physical(X, float(u[-1]) * wr)
        sigma = max(1.0, math.sqrt(float(np.sum(X[:, 1:3] ** 2))) / xr)
        J[:, -1] *= wr / xr
        return R / (xr * sigma), J / sigma

    def to_physical(self, u: NDArray) -> tuple[NDArray, NDArray]:
        """``(X (..., n_a, L), omega (...))`` from scaled points."""
        u = np.asarray(u, dtype=float)
        return (u[..., :-1] * self.x_ref).reshape(u.shape[:-1] + (self.na, self.L)), u[..., -1] * self.omega_ref


def check_problem(structure: Any, contacts: Any, harmonics: Any, n_t: Any,
                  response_dof: Any) -> tuple[list, int, int, int]:
    """Validate the multi-harmonic problem up front; returns ``(contacts, H, n_t, response_dof)``."""
    from contact_models.base import default_samples

    if not isinstance(structure, Structure):
        raise ValueError(f"structure must be an hbm.Structure, got structure={structure!r}")
    if isinstance(contacts, Contact):
        contacts = [contacts]
    try:
        contacts = list(contacts)
    except TypeError:
        raise ValueError(f"contacts must be a sequence of hbm.Contact, got contacts={contacts!r}") from None
    for c in contacts:
        if not isinstance(c, Contact):
            raise ValueError(f"contacts must hold hbm.Contact objects, got {c!r}")
        for d in c.dofs:
            if d >= structure.n:
                raise ValueError(f"dof must be a DOF index in 0..{structure.n - 1}, got dof={d!r} in {c!r}")
    H = count("harmonics", harmonics, 1)
    if n_t is None:
        n_t = default_samples(H)
    if isinstance(n_t, bool) or not isinstance(n_t, (int, np.integer)) or n_t < 2 * H + 2:
        raise ValueError(f"n_t must be an integer >= 2H + 2 = {2 * H + 2} (aliasing), got n_t={n_t!r}")
    if H > 1:
        for c in contacts:
            if not c.element.has_time_law:
                raise ValueError(f"element={c.element!r}: {type(c.element).__name__} has no time-domain force law, "
                                 f"so it works at harmonics=1 only, got harmonics={H}")
    if response_dof is None:
        if not np.any(structure.force):
            raise ValueError("force must not be all zero (nothing excites the structure), got force=0")
        response_dof = int(np.argmax(np.abs(structure.force)))
    response_dof = structure._dof("response_dof", response_dof)
    return contacts, H, int(n_t), response_dof


def _stuck_matrix(contacts, dofs, omega):
    """Complex stiffness (n_a, n_a) of the contacts held in their linear range at omega (rigid: 0)."""
    pos = {d: i for i, d in enumerate(dofs)}
    Kc = np.zeros((len(dofs), len(dofs)), dtype=complex)
    for c in contacts:
        ks, kc = c.element.linear_coefficients(omega)
        k = complex(ks, kc) if math.isfinite(ks) and math.isfinite(kc) else 0.0
        ix = [pos[d] for d in c.dofs]
        sg = [1.0, -1.0][:len(ix)]
        for i, si in zip(ix, sg):
            for j, sj in zip(ix, sg):
                Kc[i, j] += si * sj * k
    return Kc


def _force_homotopy(problem: MultiHarmonicBalance, w0: float, tol: float, scale: Callable) -> NDArray | None:
    """A start at ``w0`` when Newton from the stuck guess fails: continuation in the force scale
    ``s`` from 0 (X = 0) to 1 of ``R = X - s X_lin + G F(X)`` at fixed omega (``hbm.continuation``);
    None if it does not reach s = 1."""
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


def multiharmonic_response(structure: Structure, contacts: Sequence[Contact], *, omega_range: tuple[float, float],
                           harmonics: int = 1, n_t: int | None = None, response_dof: int | None = None,
                           rtol: float, max_step: float, min_step: float, max_steps: int, locate_folds: bool = True,
                           stability: bool = True,
                           on_point: Callable[[float, float, float, float], None] | None = None) -> Any:
    """Continuation of the condensed multi-harmonic balance (``hbm.frequency_response`` with a
    :class:`Structure`); returns a :class:`hbm.mhresult.MultiHarmonicResponse`."""
    from .mhresult import MultiHarmonicResponse

    contacts, H, n_t, response_dof = check_problem(structure, contacts, harmonics, n_t, response_dof)
    w0, w1 = omega_range_pair(omega_range)
    rtol = positive("rtol", rtol)
    if rtol >= 0.1:
        raise ValueError(f"rtol must be < 0.1, got rtol={rtol!r}")
    max_step, min_step = positive("max_step", max_step), positive("min_step", min_step)
    max_steps = count("max_steps", max_steps)
    dofs = sorted({d for c in contacts for d in c.dofs} | {response_dof})
    na, L = len(dofs), 2 * H + 1

    # ---- scales: the stuck structure's static deflection, the range width
    Kd = structure.K.toarray() if hasattr(structure.K, "toarray") else np.asarray(structure.K)
    try:
        x_static = np.linalg.solve(Kd, structure.force)
        if not np.all(np.isfinite(x_static)):
            raise np.linalg.LinAlgError
    except np.linalg.LinAlgError:
        raise ValueError("K must be nonsingular (a structure held only by its contacts has no static "
                         "compliance to condense with), got a singular K") from None
    problem = MultiHarmonicBalance(structure, contacts, dofs, harmonics=H, n_t=n_t, rtol=rtol,
                                   x_ref=1.0, omega_ref=abs(w1 - w0))
    G, _, xl, _ = problem.cond.at(0.0)
    Kc = _stuck_matrix(contacts, dofs, 0.0).real
    x0 = np.linalg.solve(np.eye(na) + G[0].real @ Kc, x_static[dofs])
    x_ref = float(np.max(np.abs(x0))) or float(np.max(np.abs(x_static))) or 1.0
    problem.x_ref = x_ref
    w_ref = problem.omega_ref

    # ---- start: the stuck (linear) first harmonic at w0
    G, _, xl, _ = problem.cond.at(w0)
    c1 = np.linalg.solve(np.eye(na) + G[1] @ _stuck_matrix(contacts, dofs, w0), xl)
    u0 = np.zeros(na * L + 1)
    u0[1:na * L:L] = c1.real / x_ref
    u0[2:na * L:L] = -c1.imag / x_ref
    u0[-1] = w0 / w_ref
    tol = NEWTON_TOL_FACTOR * rtol
    first = np.concatenate([np.arange(na) * L + 1, np.arange(na) * L + 2])

    def scale(u):
        a = max(math.sqrt(float(np.sum(u[first] ** 2))), 1e-300)
        s = np.full(u.size, a)
        s[-1] = 1.0
        return s

    report = None
    if on_point is not None:
        r = dofs.index(response_dof)

        def report(u, rnorm):
            on_point(float(u[-1] * w_ref), float(u[r * L + 1] * x_ref), float(u[r * L + 2] * x_ref), float(rnorm))

    def trace(u_start):
        return cont.continuation(problem, u_start, parameter=-1, bounds=(min(w0, w1) / w_ref, max(w0, w1) / w_ref),
                                 direction=1 if w1 > w0 else -1, max_step=max_step, min_step=min_step,
                                 max_steps=max_steps, tol=tol, scale=scale, locate_folds=locate_folds,
                                 fold_xtol=PEAK_XTOL_FACTOR * math.sqrt(rtol), on_point=report)

    run = trace(u0)
    if run.status == cont.Status.START_FAILED:  # the stuck guess is too far: homotopy in the force
        u_h = _force_homotopy(problem, w0, tol, scale)
        if u_h is not None:
            run = trace(u_h)
    return MultiHarmonicResponse(problem, run, response_dof=response_dof, rtol=rtol, tol=tol, scale=scale,
                                 stability=stability)


__all__ = ["MultiHarmonicBalance", "Condensed", "multiharmonic_response", "to_complex", "from_complex"]
