"""One harmonic balance for a structure with contacts, any number of DOFs and harmonics.

Model (``hbm.structure``; ``docs/multiharmonic.md`` derives every coefficient)::

    M x'' + C x' + K x + sum_k P_k f_k(x) = f cos(omega t)

A blade (``hbm.Blade``) is the one-DOF structure ``m x'' + c x' + k x + f_d(x) = F cos(omega t)``.

Unknowns: the harmonic coefficients of the *condensation DOFs* ``a`` (every DOF a contact
touches, and the response DOF), DOF-major, then omega::

    y = (X_a0, X_a1, ..., omega),   X = [X0, Xc1, Xs1, ..., XcH, XsH] per DOF.

The balance, harmonic by harmonic on the complex coefficients ``c_h = Xc_h - i Xs_h``::

    Z_h(omega) c_h + F_h(X, omega) = f_h,     Z_h = K - (h omega)^2 M + i h omega C,

with the linear DOFs eliminated exactly (``hbm.balance.condensation``). The contacts answer ``F``: at H = 1 an
element whose describing function is exact (``exact_describing_function``) answers with it, ``F_c = p x_c + q x_s``,
``F_s = p x_s - q x_c`` (``p = f_s/a``, ``q = f_c/a``, ``contact_models.numerics.describing``); otherwise its time
law enters through alternating frequency-time (AFT, ``ContactElement.harmonic_force``) with the analytic Jacobian
``E J_t E^-1``.  The balance asks each element what it can do; the solver has no switch over element types or
system types.

Two evaluations of this one balance, chosen by the problem's size:

- **condensed** (any structure, any H, any contacts): premultiplied by the compliance ``G_h = Z_h^-1`` restricted
  to the DOFs a, ``R = X - X_lin(omega) + G(omega) F(X)``, which stays bounded at the resonances of the eliminated
  DOFs; R is scaled by ``x_ref sigma`` (``sigma = max(1, |X_1|/x_ref)``, so the Newton tolerance is relative to the
  response).  One element between the one condensation DOF and ground (a blade with its damper) takes the same
  products in the real layout, without complex copies (``_condensed_one``).  Where X has no even harmonics an
  element may leave dF/dX's even-even block 0 (docs/multiharmonic.md, "Half-wave symmetry").
- **one DOF at H = 1** with at most one contact answering by its describing function (the blade of the paper): the
  same equations in stiffness form, in floats,

  ``R_c = (k - m omega^2 + p) x_c + (c omega + q) x_s - F``,
  ``R_s = (k - m omega^2 + p) x_s - (c omega + q) x_c``,

  scaled by F (no static term: it is exactly zero).  An array evaluation of three unknowns costs more than the
  element's own call, so this is twenty times faster; ``tests/test_balance.py`` checks both give the same branch.

In the one-DOF form the element's omega-derivative (a frequency-dependent element gives none) is a forward difference
of relative step ``sqrt(rtol)``, taken at most once per ``OMEGA_REFRESH`` relative change of omega or ``AMP_REFRESH``
of a and reused in between; it enters only the Newton matrix and the tangent, never the residual, so it does not move
the converged points.  ``fresh_omega_derivative = True`` takes it anew at every call (peaks, folds).  Up to its
``linear_amplitude(omega)`` an element is linear: its ``linear_coefficients(omega)`` are used, not its Fourier routine.
"""

from __future__ import annotations

import math
from typing import Any, Callable, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from contact_models import ContactElement, QuasiStatic
from contact_models.base import DEFAULT_RTOL, default_samples
from contact_models.numerics.describing import stiffness_terms as describing_terms
from contact_models.numerics.masing import to_time

from .._steps import OutsideDomain
from .._validation import count, nonzero_force, positive, relative_tolerance, shown
from ..structure import Contact, Structure, contact_within
from .condensation import condensed, stuck_matrix
from .layout import from_complex, next_sector_operator, to_complex
from .presets import MAX_RTOL

#: omega-derivative of the stuck stiffness: central difference of this relative step.
STUCK_FD_STEP = 1e-5
#: Relative change of omega (or, next, of a) after which the element's omega-derivative is retaken.
OMEGA_REFRESH = 3e-3
AMP_REFRESH = 3e-2
#: Bytes of the elements' Jacobians of the balance's evaluations kept for Hill's method, with what an element
#: keeps to make one whole (``ContactElement.harmonic_force_deferred``; the oldest dropped first).  The all-mode
#: bar keeps its odd solution's nodes, cells x (H + 1) floats (32 KiB at 128 cells and 31 harmonics, as much as
#: a Jacobian of 31 harmonics), at every evaluation of a trace, whose corrector evaluates several times a point:
#: the main job's longest all-mode trace needs about 9 MiB to hold all its points.
JACOBIAN_KEEP_BYTES = 16 * 2**20
#: The most harmonics a balance takes (its unknowns grow as 2H + 1 per contact DOF, a step's cost as their cube).
MAX_BALANCE_HARMONICS = 256
#: The most AFT samples per period a balance takes (each evaluation holds arrays of n_t by 2H + 1 per
#: contact DOF); eight times the default at ``MAX_BALANCE_HARMONICS``.
MAX_BALANCE_SAMPLES = 2**16


def as_structure(system: Any) -> Structure:
    """The :class:`hbm.Structure` of ``system`` (a Structure, or a Blade: its one-DOF structure)."""
    if isinstance(system, Structure):
        return system
    as_s = getattr(system, "as_structure", None)
    if callable(as_s):
        return as_s()
    raise ValueError(f"system must be an hbm.Blade or an hbm.Structure (a blade is a one-DOF structure), "
                     f"got system={system!r}")


def as_contacts(contacts: Any, n: int, physical: int | None = None) -> list[Contact]:
    """A list of :class:`hbm.Contact` from None, one Contact, a sequence of them, or a bare element at DOF 0,
    each on DOFs of a structure of ``n`` DOFs (with ``physical``, on its first ``physical``: contact_within)."""
    if contacts is None:
        return []
    if isinstance(contacts, Contact):
        contacts = [contacts]
    elif isinstance(contacts, ContactElement):
        if n != 1:
            raise ValueError(f"a bare element attaches only to a one-DOF system; give "
                             f"hbm.Contact(element, dof=...) for a structure of {n} DOFs, got contacts={contacts!r}")
        return [Contact(contacts, dof=0)]
    if callable(getattr(contacts, "fourier", None)) or isinstance(contacts, (str, bytes, dict)):
        raise ValueError(f"contacts must be a contact element (a contact_models.ContactElement), an hbm.Contact or a "
                         f"sequence of hbm.Contact, got contacts={shown(contacts)}")
    try:
        once = iter(contacts) is contacts  # an iterator (a generator): it can be read only once
        contacts = list(contacts)
    except TypeError:
        raise ValueError(f"contacts must be a contact element or a sequence of hbm.Contact, "
                         f"got contacts={contacts!r}") from None
    if once:  # a solve reads its contacts more than once: after the first the iterator is empty (no contacts)
        raise ValueError(f"contacts must be a sequence of hbm.Contact (a list or a tuple), not an iterator, which is "
                         f"read once: the solve reads the contacts more than once and would solve the rest without "
                         f"them; got contacts={shown(contacts)} from an iterator (give list(...))")
    for c in contacts:
        if not isinstance(c, Contact):
            raise ValueError(f"contacts must hold hbm.Contact objects, got {c!r}")
        contact_within(c, n, physical)
    return contacts


def first_harmonic_size(X: NDArray) -> float:
    """sqrt of the sum of the squares of the first harmonic's coefficients ``X[:, 1:3]`` (m): the residual's
    scale.  Past about 1e154 m the squares overflow (the scale was inf, the scaled residual 0 at every point, and
    a curve of 1e160 m was traced as any line through the range): there it is taken scaled by its largest entry."""
    with np.errstate(over="ignore"):
        s2 = float(np.sum(X[:, 1:3] ** 2))
    if s2 < math.inf:
        return math.sqrt(s2)
    return float(first_harmonic_sizes(X[None])[0])


def first_harmonic_sizes(X: NDArray) -> NDArray[np.float64]:
    """:func:`first_harmonic_size` of each point of a stack ``X`` (points, DOFs, coefficients)."""
    with np.errstate(over="ignore"):
        s2 = np.sum(X[:, :, 1:3] ** 2, axis=(1, 2))
    out = np.sqrt(s2)
    big = ~(s2 < math.inf)
    if np.any(big):  # (past 1e154 m only)
        Y = X[big][:, :, 1:3]
        top = np.max(np.abs(Y), axis=(1, 2))
        out[big] = top * np.sqrt(np.sum((Y / top[:, None, None]) ** 2, axis=(1, 2)))
    return out


def samples_within_bound(n_t: Any) -> Any:
    """``n_t`` as given (None, or an int <= ``MAX_BALANCE_SAMPLES``; its lower bound 2H + 2 is
    :func:`check_problem`'s): the bound on what a caller asks for, checked in the public solves
    (the error estimate's own balances sample up to ``SAMPLING_SHIFTS`` times more)."""
    if isinstance(n_t, (int, np.integer)) and not isinstance(n_t, bool) and n_t > MAX_BALANCE_SAMPLES:
        count("n_t", n_t, 4, MAX_BALANCE_SAMPLES, "hbm.balance.residual.MAX_BALANCE_SAMPLES")  # (raises, naming it)
    return n_t


def first_harmonic_only(contacts: list[Contact], H: Any, tol_remedy: bool = False) -> None:
    """Refuse ``harmonics=H`` > 1 with an element that has no time-domain force law, naming H, the element's type
    and the ways out that exist for it: harmonics=1; with ``tol_remedy`` (``frequency_response``), a tol and
    ``model="auto"`` where its refined model has a time law; ``QuasiStatic(element)`` where that has one.  An H
    that is no integer is left to :func:`check_problem`, which names it."""
    if isinstance(H, bool) or not isinstance(H, (int, np.integer)) or H <= 1:
        return
    for c in contacts:
        el = c.element
        if el.has_time_law:
            continue
        name, refined = type(el).__name__, el.refined_model()
        ways = ["harmonics=1 (its describing-function answer)"]
        if tol_remedy and refined is not None and refined.has_time_law:
            ways.append(f"leave harmonics out and give tol= with model='auto' (where tol asks for more harmonics "
                        f"the balance takes {name}'s refined model, contact_models.{type(refined).__name__}, "
                        f"which has a time law)")
        if el.frequency_dependent and QuasiStatic(el).has_time_law:
            ways.append(f"contact_models.QuasiStatic(element) in its place (Masing's rules on {name}'s loading "
                        f"curve at omega = 0: without the damper's inertia)")
        raise ValueError(f"harmonics must be 1 with {name}, which has no time-domain force law (a first-harmonic "
                         f"element), got harmonics={int(H)}; use {'; or '.join(ways)}; the element: {el!r}")


def check_problem(structure: Structure, contacts: list[Contact], harmonics: Any, n_t: Any,
                  response_dof: Any) -> tuple[int, int, int]:
    """Validate H, n_t, the contacts' sectors and the response DOF; returns ``(H, n_t, response_dof)``."""
    for c in contacts:  # (their DOFs are checked by as_contacts)
        if c.next_sector and structure.sector_angle is None:
            raise ValueError(f"next_sector=True joins two sectors of a cyclic structure (hbm.CyclicStructure); "
                             f"{type(structure).__name__} is the whole model, got next_sector=True in {c!r}")
    H = count("harmonics", harmonics, 1, MAX_BALANCE_HARMONICS, "hbm.balance.residual.MAX_BALANCE_HARMONICS")
    if n_t is None:
        n_t = default_samples(H)
    if isinstance(n_t, bool) or not isinstance(n_t, (int, np.integer)) or n_t < 2 * H + 2:
        raise ValueError(f"n_t must be an integer >= 2H + 2 = {2 * H + 2} (aliasing), got n_t={n_t!r}")
    first_harmonic_only(contacts, H)
    nonzero_force(structure.force)
    return H, int(n_t), structure.response_dof(response_dof)


class HarmonicBalance:
    """``R(u)`` and ``dR/du`` of the harmonic balance of a structure with contacts (module docstring).

    Parameters
    ----------
    system : hbm.Structure or hbm.Blade
        The linear structure (a blade is its one-DOF structure).
    contacts : sequence of hbm.Contact, hbm.Contact, contact element or None, default None
        The contacts; a bare element attaches to the DOF of a one-DOF system.
    harmonics : int, default 1
        The highest harmonic H.
    n_t : int, optional
        AFT samples per period, >= 2H + 2; default ``contact_models.base.default_samples(H)``.
    response_dof : int, optional
        The DOF whose response is reported; default the forced DOF.
    rtol : float, default 1e-6
        Relative tolerance passed to the elements.
    x_ref : float, default 1.0
        Displacement scale of the scaled unknowns (m), > 0.
    omega_ref : float, default 1.0
        Frequency scale of the scaled unknowns (rad/s), > 0.

    Attributes
    ----------
    structure : hbm.Structure
        The system as a structure.
    contacts : list of hbm.Contact
        The contacts.
    H, n_t, L : int
        Harmonics, AFT samples, real coefficients per DOF ``2H + 1``.
    dofs : list of int
        The condensation DOFs; ``na`` their number.
    one_dof : bool
        Whether the one-DOF, H = 1 evaluation is used (module docstring).
    nfev : int
        Element evaluations (Fourier routine or harmonic force; omega differences included).
    nstuck : int
        Evaluations answered by the stuck (linear) stiffness (one-DOF form).
    nfev_omega : int
        Of ``nfev``, the calls made for the omega-derivative (one-DOF form).
    ncalls : int
        Balance evaluations.

    Notes
    -----
    In the one-DOF form ``physical(y)`` takes ``y = (x_c, x_s, omega)`` and returns ``R`` (2,) in N and ``J`` (2, 3);
    in the condensed form ``y = (X_a (n_a (2H+1)), omega)`` and ``R`` is in m.  The arguments are not validated.

    Examples
    --------
    >>> from hbm import Blade
    >>> hb = HarmonicBalance(Blade(mass=1.0, stiffness=4.0, damping=0.0, force=1.0))
    >>> R, J = hb.physical([1.0, 0.0, 1.0])   # (k - m omega^2) x_c - F = 3 - 1
    >>> R.tolist(), J.tolist()
    ([2.0, 0.0], [[3.0, 0.0, -2.0], [0.0, 3.0, 0.0]])
    """

    def __init__(self, system: Any, contacts: Any = None, *, harmonics: int = 1, n_t: int | None = None,
                 response_dof: int | None = None, rtol: float = DEFAULT_RTOL, x_ref: float = 1.0,
                 omega_ref: float = 1.0) -> None:
        s = self.structure = as_structure(system)
        self.system = system
        self.contacts = as_contacts(contacts, s.n, s.physical_dofs)
        self.H, self.n_t, self.response_dof = check_problem(s, self.contacts, harmonics, n_t, response_dof)
        self.L = 2 * self.H + 1
        self.dofs = sorted({d for c in self.contacts for d in c.all_dofs} | {self.response_dof})
        self.na = len(self.dofs)
        self.rtol = relative_tolerance("rtol", rtol, MAX_RTOL)
        self.x_ref = positive("x_ref", x_ref)
        self.omega_ref = positive("omega_ref", omega_ref)
        pos = {d: i for i, d in enumerate(self.dofs)}
        self._attach = [(c.element, [[pos[d] for d in ix] for ix in c.components]) for c in self.contacts]
        # a contact to the next sector sees that sector's harmonic h turned by -h phi (docs/bladed_disks.md)
        self._angle = float(s.sector_angle or 0.0)
        self._next = [c.next_sector for c in self.contacts]
        self._turn = next_sector_operator(self.H, self._angle)
        self.one_dof = solved_as_one_dof(s, self.contacts, self.H)
        self.element = self.contacts[0].element if len(self.contacts) == 1 else None
        self.fresh_omega_derivative = False
        self.keep_jacobians, self._jacobians, self._jacobian_bytes = False, {}, 0  # for Hill: frequency_response
        self.nfev = 0
        self.nstuck = 0
        self.nfev_omega = 0
        self.ncalls = 0
        if self.one_dof:
            self._init_one_dof()
        else:
            self.cond = condensed(s, self.dofs, self.H)
        # the fast path of the condensed form: one element between the one condensation DOF and ground
        self._grounded_one = (not self.one_dof and self.na == 1 and len(self._attach) == 1
                              and self._attach[0][1] == [[0]])
        self._swap = np.array([0] + [j - 1 + 2 * (j % 2) for j in range(1, self.L)])  # 1 <-> 2, 3 <-> 4, ..

    # ------------------------------------------------------------------ layout
    @property
    def unknowns(self) -> int:
        """Number of unknowns, omega included."""
        return 3 if self.one_dof else self.na * self.L + 1

    @property
    def first_harmonic(self) -> NDArray[np.intp]:
        """Indices in ``u`` of the first-harmonic (cos, sin) coefficients of every condensation DOF."""
        if self.one_dof:
            return np.array([0, 1])
        return np.concatenate([np.arange(self.na) * self.L + 1, np.arange(self.na) * self.L + 2])

    def response_components(self) -> tuple[int, int]:
        """Indices in ``u`` of the response DOF's first-harmonic (cos, sin) coefficients."""
        if self.one_dof:
            return 0, 1
        r = self.dofs.index(self.response_dof)
        return r * self.L + 1, r * self.L + 2

    def to_physical(self, u: ArrayLike) -> tuple[NDArray, NDArray]:
        """``(X (..., n_a, 2H+1), omega (...))`` in m and rad/s from scaled points ``u`` (..., unknowns)."""
        u = np.asarray(u, dtype=float)
        if self.one_dof:
            X = np.zeros(u.shape[:-1] + (1, 3))
            X[..., 0, 1] = u[..., 0] * self.x_ref
            X[..., 0, 2] = u[..., 1] * self.x_ref
            return X, u[..., 2] * self.omega_ref
        return (u[..., :-1] * self.x_ref).reshape(u.shape[:-1] + (self.na, self.L)), u[..., -1] * self.omega_ref

    # ------------------------------------------------------------------ evaluation
    def physical(self, y: ArrayLike) -> tuple[NDArray, NDArray]:
        """``R`` and ``J = dR/dy`` at the physical unknowns ``y`` (class Notes)."""
        if self.one_dof:
            R, J = self.balance(float(y[0]), float(y[1]), float(y[2]))
            return np.array(R), np.array(J).reshape(2, 3)
        y = np.asarray(y, dtype=float)
        return self._condensed(y[:-1].reshape(self.na, self.L), float(y[-1]))

    def __call__(self, u: ArrayLike) -> tuple[NDArray, NDArray]:
        """Scaled residual and its Jacobian in ``u = (X/x_ref, omega/omega_ref)``.

        A negative omega (a continuation's predictor past omega = 0) raises ``OutsideDomain``: the
        continuation's step failed there and is retried, instead of the elements' ValueError ending it."""
        if not u[-1] >= 0.0:
            raise OutsideDomain(f"omega must be >= 0, got omega={float(u[-1]) * self.omega_ref!r}")
        if self.one_dof:
            return self._scaled_one_dof(u)
        xr, wr = self.x_ref, self.omega_ref
        if self._grounded_one:
            x = u[:-1] * xr
            self.ncalls += 1
            R, J = self._condensed_one(x, float(u[-1]) * wr)
            xc, xs = float(x[1]), float(x[2])
            s2 = xc * xc + xs * xs
            sigma = max(1.0, (math.sqrt(s2) if s2 < math.inf else math.hypot(xc, xs)) / xr)
        else:
            X = (u[:-1] * xr).reshape(self.na, self.L)
            R, J = self._condensed(X, float(u[-1]) * wr)
            # sigma's own derivative multiplies R and vanishes on the branch: left out of J
            sigma = max(1.0, first_harmonic_size(X) / xr)
        J[:, -1] *= wr / xr
        J /= sigma  # J is the balance's own new array
        return R / (xr * sigma), J

    # ------------------------------------------------------------------ the contacts' forces
    def forces(self, X: NDArray, omega: float, *, perturbation: bool = False) -> tuple[NDArray, NDArray, NDArray]:
        """Contact forces' harmonics F (n_a, L), dF/dX (n_a L, n_a L), dF/domega (n_a, L).

        ``perturbation=True`` (Hill's method): an element whose displacement stays within its linear range all
        period is a linear spring for a perturbation (nothing slips, its internal state does not move), so its
        Jacobian is ``k_s I``; the balance's own Jacobian differs only in the static term, where the centring
        convention of a Masing element's periodic state (``contact_models.numerics.masing``) gives ``K_inf``.  A
        two-component element (``Contact2D``) gets the rows of its tangential and normal attachments, (2, L)."""
        return self._assemble(X, omega, perturbation, True, True)

    def perturbation_jacobian(self, X: NDArray, omega: float, family: float = 0.0) -> NDArray:
        """``dF/dX`` (n_a L, n_a L) of :meth:`forces` with ``perturbation=True``, without the forces:
        an element in its linear range all period is not evaluated (its Jacobian is ``k_s I``).  For a
        sector, ``family = mu`` (rad) takes the perturbations whose next sector is this one's turned
        and times ``exp(-i mu)`` (complex for mu != 0; ``hbm.balance.stability.HillProblem``)."""
        return self._assemble(X, omega, True, False, True, family)[1]

    def _assemble(self, X: NDArray, omega: float, perturbation: bool, force: bool,
                  whole: bool, family: float = 0.0) -> tuple[NDArray, NDArray, NDArray]:  # whole: with the even block
        na, L = self.na, self.L
        F = np.zeros((na, L))
        dF = np.zeros((na, L, na, L), dtype=complex if family else float)
        Fw = np.zeros((na, L))
        for e, (el, comps) in enumerate(self._attach):
            Xrel = self.relative_motion(e, X)
            c, linear = len(comps), False
            if perturbation and c == 1:
                x = to_time(Xrel[0], max(self.n_t, 4 * L))
                linear = 0.5 * float(np.ptp(x)) <= el.linear_amplitude(omega)
            key = (e, omega, Xrel.tobytes()) if self.keep_jacobians else None  # (for Hill's method)
            if not force and not linear and key in self._jacobians:  # that same call's Jacobian, bit for bit
                f, J, fw = np.zeros(c * L), self._kept_jacobian(key), np.zeros(c * L)
            elif force or not linear:
                f, J, fw = self._asked(el, Xrel if c > 1 else Xrel[0], omega, None if perturbation else key, whole)
            else:  # the forces are not asked for
                f, fw = np.zeros(L), np.zeros(L)
            if linear:
                J = float(el.linear_coefficients(omega)[0]) * np.eye(L)
            f, fw, J = f.reshape(c, L), fw.reshape(c, L), J.reshape(c, L, c, L)
            if self._next[e]:
                self._add_next_sector(comps, f, fw, J, F, Fw, dF, family)
                continue
            signs = [((ix[0], 1.0), (ix[1], -1.0)) if len(ix) == 2 else ((ix[0], 1.0),) for ix in comps]
            for a in range(c):
                for i, si in signs[a]:
                    F[i] += si * f[a]
                    Fw[i] += si * fw[a]
                    for b in range(c):
                        for j, sj in signs[b]:
                            dF[i, :, j, :] += (si * sj) * J[a, :, b, :]
        return F, dF.reshape(na * L, na * L), Fw

    def relative_motion(self, e: int, X: NDArray) -> NDArray:
        """Contact ``e``'s relative motion (..., components, 2H+1) at the coefficients ``X`` (..., n_a, 2H+1):
        ``X_i - X_j``, ``X_i`` or, across sectors, ``T X_p - X_q`` (``T``: :func:`hbm.balance.layout.next_sector_operator`)."""
        comps = self._attach[e][1]
        if self._next[e]:
            return np.stack([X[..., ix[0], :] @ self._turn.T - X[..., ix[1], :] for ix in comps], axis=-2)
        return np.stack([X[..., ix[0], :] - X[..., ix[1], :] if len(ix) == 2 else X[..., ix[0], :] for ix in comps],
                        axis=-2)

    def _add_next_sector(self, comps: list, f: NDArray, fw: NDArray, J: NDArray, F: NDArray, Fw: NDArray,
                         dF: NDArray, family: float = 0.0) -> None:
        """A contact to the next sector into the balance: its force f acts -f on this sector's q and, by
        the symmetry of the travelling wave, ``T^T f`` on p (the previous sector's contact, whose force
        leads by h phi); ``dF`` gets ``T^T J T``, ``-T^T J``, ``-J T`` and ``J`` (docs/bladed_disks.md).
        A perturbation of the family ``mu = family`` has ``exp(-i mu) T`` for ``T``."""
        c = len(comps)
        for a in range(c):
            p, q = comps[a]
            F[p] += self._turn.T @ f[a]
            F[q] -= f[a]
            Fw[p] += self._turn.T @ fw[a]
            Fw[q] -= fw[a]
        turn = np.exp(-1j * family) if family else 1.0
        T = turn * self._turn
        Tt = np.conj(T).T
        for a in range(c):
            p, q = comps[a]
            for b in range(c):
                pb, qb = comps[b]
                Jab = J[a, :, b, :]
                TJ = Tt @ Jab
                dF[p, :, pb, :] += TJ @ T
                dF[p, :, qb, :] -= TJ
                dF[q, :, pb, :] -= Jab @ T
                dF[q, :, qb, :] += Jab

    def _asked(self, el: ContactElement, x: NDArray, omega: float, key: tuple | None,
               whole: bool) -> tuple[NDArray, NDArray, NDArray]:
        """``el``'s answer ``(f, dF/dX, df/domega)`` at ``x``, ``omega`` (counted in ``nfev``), with dF/dX's even
        block where ``whole``; kept under ``key`` for Hill's method where one is given, with how ``el`` makes a
        Jacobian without its even block whole at the point (``ContactElement.harmonic_force_deferred``)."""
        if key is None or whole:
            f, J, fw = el.harmonic_force_unchecked(x, omega, self.n_t, self.rtol, whole)
            later = None
        else:
            f, J, fw, later = el.harmonic_force_deferred(x, omega, self.n_t, self.rtol)
        self.nfev += 1
        if key is not None:
            self._keep_jacobian(key, J, later)
        return f, J, fw

    def forget_jacobians(self) -> None:
        """Drop the elements' Jacobians kept for :meth:`perturbation_jacobian` (Hill's method has run)."""
        self._jacobians, self._jacobian_bytes = {}, 0

    def _keep_jacobian(self, key: tuple, J: NDArray, later: Callable[[NDArray], NDArray] | None = None) -> None:
        """Keep an element's Jacobian (a copy) at key (contact, omega, its X's bytes), for ``keep_jacobians``, with
        ``later``, how the element makes it whole (``ContactElement.harmonic_force_deferred``; None: it is)."""
        kept = self._jacobians
        if key not in kept:
            kept[key] = np.array(J, dtype=float), later
            self._jacobian_bytes += _kept_bytes(*kept[key])
        while self._jacobian_bytes > JACOBIAN_KEEP_BYTES:
            self._jacobian_bytes -= _kept_bytes(*kept.pop(next(iter(kept))))

    def _kept_jacobian(self, key: tuple) -> NDArray:
        """The whole Jacobian kept at key: as kept, or made whole by the element (then kept so, for the next
        family of perturbations of a sector)."""
        J, later = self._jacobians[key]
        if later is not None:
            J = later(J)
            self._jacobians[key] = J, None
            self._jacobian_bytes -= int(later.nbytes)
        return J

    # ------------------------------------------------------------------ condensed form
    def _condensed(self, X: NDArray, omega: float) -> tuple[NDArray, NDArray]:
        """``R = X - X_lin + G F(X)`` (n_a L,) and ``J`` (n_a L, n_a L + 1), physical units."""
        self.ncalls += 1
        if self._grounded_one:
            return self._condensed_one(X[0], omega)
        na, L = self.na, self.L
        G, dG, xl, dxl = self.cond.at(omega)
        F, dF, Fw = self._assemble(X, omega, False, True, False)
        cF = to_complex(F)  # (n_a, H+1)
        R = X + from_complex(np.einsum("hab,bh->ah", G, cF))
        R[:, 1] -= xl.real
        R[:, 2] += xl.imag
        # dR/domega = -dX_lin/domega + (dG/domega) F + G dF/domega
        Rw = from_complex(np.einsum("hab,bh->ah", dG, cF)) + from_complex(np.einsum("hab,bh->ah", G, to_complex(Fw)))
        Rw[:, 1] -= dxl.real
        Rw[:, 2] += dxl.imag
        # dR/dX = I + G dF/dX
        cdF = to_complex(dF.reshape(na, L, na * L))  # (n_a, H+1, n_a L)
        J = np.empty((na * L, na * L + 1))
        J[:, :-1] = from_complex(np.einsum("hab,bhk->ahk", G, cdF)).reshape(na * L, na * L)
        J[np.arange(na * L), np.arange(na * L)] += 1.0
        J[:, -1] = Rw.ravel()
        return R.ravel(), J

    def _condensed_one(self, x: NDArray, omega: float) -> tuple[NDArray, NDArray]:
        """:meth:`_condensed` for one element on the one condensation DOF, to ground: the same products in the real
        layout, ``(g F)_c = g_r F_c + g_i F_s``, ``(g F)_s = g_r F_s - g_i F_c`` (``g_h = g_r + i g_i``,
        ``c_h = F_c - i F_s``), without the complex copies."""
        a, b, aw, bw, xl, dxl = self.cond.real_at(omega)
        el = self._attach[0][0]
        key = (0, omega, x.tobytes()) if self.keep_jacobians else None  # the key _assemble looks up (its Xrel is [x])
        f, dF, fw = self._asked(el, x, omega, key, False)
        p = self._swap  # cos <-> sin of each harmonic; the static term onto itself (b[0] = 0)
        fp = f[p]
        R = x + (a * f + b * fp)
        R[1] -= xl.real
        R[2] += xl.imag
        Rw = aw * f + bw * fp
        if fw.any():  # an element with an omega-derivative (the exact Jenkins element has none)
            Rw += a * fw + b * fw[p]
        Rw[1] -= dxl.real
        Rw[2] += dxl.imag
        L = self.L
        Jx = a[:, None] * dF  # formed apart, then copied into J once
        swapped = dF[p]
        swapped *= b[:, None]
        Jx += swapped
        J = np.empty((L, L + 1))
        J[:, :-1] = Jx
        J.reshape(-1)[::L + 2] += 1.0  # the diagonal of J[:, :-1]
        J[:, -1] = Rw
        return R, J

    # ------------------------------------------------------------------ one-DOF form
    def _init_one_dof(self) -> None:
        s = self.structure
        self._m, self._c, self._k = (float(np.asarray(A.toarray() if hasattr(A, "toarray") else A)[0, 0])
                                     for A in (s.M, s.C, s.K))
        self._F = float(s.force[0])
        el = self.element
        self._freq_dep = el is not None and bool(el.frequency_dependent)
        self._derivs = el.fourier_derivatives_unchecked if el is not None else None
        self._dw: tuple | None = None  # (omega, a, dp/domega, dq/domega) of the last omega difference
        self._stuck_dw_cache: tuple | None = None  # (omega, (dk_s/domega, dk_c/domega))
        self.omega_fd_step = math.sqrt(max(self.rtol, 1e-14))

    def stiffness_terms(self, a: float, omega: float) -> tuple[float, float, float, float, float, float]:
        """``(p, q, dp/da, dq/da, dp/domega, dq/domega)`` of the element at amplitude ``a`` (one-DOF form)."""
        el = self.element
        if el is None:
            return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
        if a == 0.0 or a <= el.linear_amplitude(omega):
            self.nstuck += 1
            p, q = self._linear(omega)
            dpw, dqw = self._linear_dw(omega)
            return p, q, 0.0, 0.0, dpw, dqw
        p, q, dp, dq = self._pq(a, omega)
        if not self._freq_dep:
            return p, q, dp, dq, 0.0, 0.0
        c = self._dw
        if (self.fresh_omega_derivative or c is None or abs(omega - c[0]) > OMEGA_REFRESH * omega
                or abs(a - c[1]) > AMP_REFRESH * a):
            h = self.omega_fd_step * omega if omega > 0.0 else self.omega_fd_step * self.omega_ref
            self.nfev_omega += 1
            p_h, q_h, _, _ = self._pq(a, omega + h)
            c = self._dw = (omega, a, (p_h - p) / h, (q_h - q) / h)
        return p, q, dp, dq, c[2], c[3]

    def _pq(self, a: float, omega: float) -> tuple[float, float, float, float]:
        self.nfev += 1
        return describing_terms(self._derivs, a, omega, self.rtol)

    def _linear(self, omega: float) -> tuple[float, float]:
        k_s, k_c = self.element.linear_coefficients(omega)
        return float(k_s), float(k_c)

    def _linear_dw(self, omega: float) -> tuple[float, float]:
        """d(k_s, k_c)/domega of the linear range: central difference, retaken after OMEGA_REFRESH of omega."""
        if not self._freq_dep:
            return 0.0, 0.0
        c = self._stuck_dw_cache
        if c is not None and not self.fresh_omega_derivative and abs(omega - c[0]) <= OMEGA_REFRESH * omega:
            return c[1]
        h = STUCK_FD_STEP * max(omega, 1e-3 * self.omega_ref)
        lo = omega - h if omega >= h else omega
        (ps_hi, pc_hi), (ps_lo, pc_lo) = self._linear(omega + h), self._linear(lo)
        d = ((ps_hi - ps_lo) / (omega + h - lo), (pc_hi - pc_lo) / (omega + h - lo))
        self._stuck_dw_cache = (omega, d)
        return d

    def balance(self, xc: float, xs: float, omega: float) -> tuple[tuple[float, float], tuple[float, ...]]:
        """Physical ``(R_c, R_s)`` and ``dR/d(x_c, x_s, omega)`` as a flat 6-tuple, row-major (one-DOF form)."""
        self.ncalls += 1
        a = math.hypot(xc, xs)
        p, q, dp, dq, dpw, dqw = self.stiffness_terms(a, omega)
        kr = self._k - self._m * omega * omega + p  # real part of the dynamic stiffness
        ki = self._c * omega + q  # imaginary part
        Rc = kr * xc + ki * xs - self._F
        Rs = kr * xs - ki * xc
        if a > 0.0:
            gc, gs = xc / a, xs / a  # da/dx_c, da/dx_s
        else:
            gc = gs = 0.0
        u = dp * xc + dq * xs  # d(R_c)/da (through p and q)
        v = dp * xs - dq * xc  # d(R_s)/da
        krw = -2.0 * self._m * omega + dpw
        kiw = self._c + dqw
        J = (kr + u * gc, ki + u * gs, krw * xc + kiw * xs,
             -ki + v * gc, kr + v * gs, krw * xs - kiw * xc)
        return (Rc, Rs), J

    def _scaled_one_dof(self, u: ArrayLike) -> tuple[NDArray, NDArray]:
        xr, wr, F = self.x_ref, self.omega_ref, self._F
        (Rc, Rs), J = self.balance(float(u[0]) * xr, float(u[1]) * xr, float(u[2]) * wr)
        cx, cw = xr / F, wr / F
        return (np.array((Rc / F, Rs / F)),
                np.array(((J[0] * cx, J[1] * cx, J[2] * cw), (J[3] * cx, J[4] * cx, J[5] * cw))))

    def forcing_part(self, u: NDArray) -> NDArray[np.float64]:
        """The excitation's part of the scaled residual ``self(u)`` (``-F/F`` in R_c in the one-DOF
        form, ``-X_lin/(x_ref sigma)`` condensed): the force homotopy scales it from 0 to 1."""
        if self.one_dof:
            return np.array([-1.0, 0.0])
        X = (u[:-1] * self.x_ref).reshape(self.na, self.L)
        sigma = max(1.0, first_harmonic_size(X) / self.x_ref)
        xl = self.cond.at(float(u[-1]) * self.omega_ref)[2]
        lin = np.zeros((self.na, self.L))
        lin[:, 1], lin[:, 2] = -xl.real, xl.imag
        return lin.ravel() / (self.x_ref * sigma)

    # ------------------------------------------------------------------ scales and start
    def set_scales(self, w0: float, w1: float) -> None:
        """``x_ref`` from the stuck system's static deflection, ``omega_ref = |w1 - w0|``."""
        self.omega_ref = abs(w1 - w0)
        if self.one_dof:
            el = self.element
            k0 = self._k + _finite_or_zero(el.stuck_stiffness(0.0) if el is not None else 0.0)
            k_ref = k0 if k0 > 0.0 else self._m * max(w0, w1) ** 2
            self.x_ref = self._F / k_ref
            return
        s = self.structure
        x_static = static_deflection(s)
        G = self.cond.at(0.0)[0]
        Kc = stuck_matrix(self.contacts, self.dofs, 0.0).real
        x0 = np.linalg.solve(np.eye(self.na) + G[0].real @ Kc, x_static[self.dofs])
        self.x_ref = float(np.max(np.abs(x0))) or float(np.max(np.abs(x_static))) or 1.0

    def stuck_start(self, w0: float) -> NDArray[np.float64]:
        """Scaled unknowns of the stuck (linear) first-harmonic response at ``w0``."""
        xr = self.x_ref
        if self.one_dof:
            el = self.element
            kd = _finite_or_zero(el.stuck_stiffness(w0)) if el is not None else 0.0
            z = self._F / (self._k + kd - self._m * w0 * w0 + 1j * self._c * w0)
            return np.array([z.real / xr, -z.imag / xr, w0 / self.omega_ref])
        G, _, xl, _ = self.cond.at(w0)
        Kc = stuck_matrix(self.contacts, self.dofs, w0, self._angle)
        c1 = np.linalg.solve(np.eye(self.na) + G[1] @ Kc, xl)
        u0 = np.zeros(self.unknowns)
        u0[1:self.na * self.L:self.L] = c1.real / xr
        u0[2:self.na * self.L:self.L] = -c1.imag / xr
        u0[-1] = w0 / self.omega_ref
        return u0

    def arclength_scale(self) -> Callable[[NDArray], NDArray]:
        """The continuation's scale: every coefficient by the current first-harmonic amplitude of
        the condensation DOFs (one weight for all harmonics), omega by 1."""
        if self.one_dof:
            def scale(u):  # (a, a, 1): one array, no copies (the continuation calls it at every step)
                a = max(math.hypot(u[0], u[1]), 1e-300)
                return np.array([a, a, 1.0])

            return scale
        first = self.first_harmonic

        def scale(u):
            a = max(math.hypot(*u[first]), 1e-300)
            s = np.full(u.size, a)
            s[-1] = 1.0
            return s

        return scale


def solved_as_one_dof(structure: Structure, contacts: Sequence[Contact], H: int) -> bool:
    """Whether the balance of ``structure`` with ``contacts`` at ``H`` harmonics is the one-DOF single-harmonic
    balance (which needs no static compliance; every other needs K nonsingular, :func:`static_deflection`):
    one real-forced DOF, not a sector of a cyclic structure."""
    return (structure.n == 1 and H == 1 and len(contacts) <= 1 and structure.sector_angle is None
            and not np.iscomplexobj(structure.force) and all(c.element.exact_describing_function for c in contacts))


def static_deflection(structure: Structure) -> NDArray:
    """``K_1^-1 force`` of ``structure`` (``K_1`` its stiffness at harmonic 1,
    :meth:`hbm.Structure.harmonic_matrices`: K itself but for a cyclic sector; complex with a complex
    force); ValueError naming K if it is singular (the condensation of a structure held only by its
    contacts has no static compliance).  The balance calls it to set its scales; a scene's planning
    calls it so that ``--check`` refuses what the run would."""
    K = structure.harmonic_matrices(1)[2]
    Kd = K.toarray() if hasattr(K, "toarray") else np.asarray(K)
    try:
        x_static = np.linalg.solve(Kd, structure.force)
        if not np.all(np.isfinite(x_static)):
            raise np.linalg.LinAlgError
    except np.linalg.LinAlgError:
        raise ValueError("K must be nonsingular (a structure held only by its contacts has no static compliance to "
                         "condense with), got a singular K") from None
    return x_static


def linear_response(blade: Any, omega: ArrayLike, stiffness: complex | Callable[[np.ndarray], ArrayLike] = 0.0
                    ) -> np.ndarray:
    """Closed-form complex amplitude ``x_c - i x_s = F / (k + k_d - m w^2 + i c w)`` of the blade with a linear
    spring ``stiffness`` (a number or a function of omega) in place of the damper."""
    omega = np.asarray(omega, dtype=float)
    kd = stiffness(omega) if callable(stiffness) else stiffness
    return blade.force / (blade.stiffness + kd - blade.mass * omega**2 + 1j * blade.damping * omega)


def _kept_bytes(J: NDArray, later: Any) -> int:
    """Bytes of a kept Jacobian and of what its element keeps to make it whole."""
    return J.nbytes + (0 if later is None else int(later.nbytes))


def _finite_or_zero(k: Any) -> float:
    """A stuck stiffness for scales and the first guess (a rigid stuck contact gives none: 0)."""
    k = float(k)
    return k if math.isfinite(k) else 0.0


__all__ = ["HarmonicBalance", "as_structure", "as_contacts", "check_problem", "first_harmonic_only", "linear_response",
           "solved_as_one_dof", "static_deflection"]
