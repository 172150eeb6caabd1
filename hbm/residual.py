"""Single-harmonic balance of the blade with a contact element (the damper) and its Jacobian.

Model: ``m x'' + c x' + k x + f_d(x) = F cos(omega t)``, ``f_d`` the damper force at the blade
(the damper's excited end moves with the blade).

Unknowns, the one layout used throughout ``hbm``::

    y = (x_c, x_s, omega),        x(t) ~ x_c cos(omega t) + x_s sin(omega t)

amplitude ``a = sqrt(x_c^2 + x_s^2)``, phase lag ``phi = atan2(x_s, x_c)`` (``x = a cos(omega t - phi)``;
0 <= phi <= pi for a passive system).

Writing ``x = a sin(theta)``, ``theta = omega t + psi`` (``sin psi = x_c / a``, ``cos psi = x_s / a``),
the element gives ``f_d ~ f_s sin(theta) + f_c cos(theta)`` (``contact_models.base``), i.e. in
``cos(omega t)``, ``sin(omega t)``::

    f_d ~ (f_s x_c + f_c x_s)/a cos(omega t) + (f_s x_s - f_c x_c)/a sin(omega t).

With ``p = f_s/a``, ``q = f_c/a`` (the element's equivalent stiffness and damping force per
unit amplitude) the balance of the cosine and sine terms is::

    R_c = (k - m omega^2 + p) x_c + (c omega + q) x_s - F
    R_s = (k - m omega^2 + p) x_s - (c omega + q) x_c

i.e. ``(k - m omega^2 + p + i (c omega + q)) (x_c - i x_s) = F``.

Derivatives: in ``(x_c, x_s)`` exact, from the element's ``df_s/da``, ``df_c/da``
(``dp/da = (f_s' - p)/a``, ``da/dx_c = x_c/a``).  In ``omega`` the blade part is exact; the
element gives no omega-derivative, so for an element with ``frequency_dependent = True`` it is a
forward difference of relative step ``OMEGA_FD_STEP = sqrt(rtol)``, taken at most once per
``OMEGA_REFRESH`` relative change of omega or ``AMP_REFRESH`` of a and reused in between.
That column enters only the Newton matrix (and the tangent), never the residual: its error
(O(sqrt(rtol)) relative, times the element's share of the omega-derivative, a few % for the
default case) slows Newton's convergence a little but does not move the converged points.
``fresh_omega_derivative = True`` takes it anew at every call (used to locate peaks and folds).
The stuck stiffness's omega-derivative (below a_min) is a central difference, reused likewise.

Up to the element's ``linear_amplitude(omega)`` (its slip amplitude for the bars and the Jenkins
element, 0 for an element that is never linear) the element is linear,
``(p, q) = linear_coefficients(omega)`` (``(k*(omega), 0)`` for a stuck bar): these are used
directly and the element's Fourier routine is not called.
"""

from __future__ import annotations

import math

from typing import TYPE_CHECKING, Callable

import numpy as np
from numpy.typing import ArrayLike

from .blade import Blade

if TYPE_CHECKING:
    from contact_models import ContactElement

#: omega-derivative of the stuck stiffness: central difference of this relative step.
STUCK_FD_STEP = 1e-5
#: Relative change of omega (or, next, of a) after which the element's omega-derivative is retaken.
OMEGA_REFRESH = 3e-3
AMP_REFRESH = 3e-2


class HarmonicBalance:
    """``R(y)`` and ``dR/dy`` of the single-harmonic balance, physical or scaled.

    ``element`` is any contact element (or None for the bare blade).  ``rtol`` is passed to the
    element.  The scaled form used by the continuation is ``u = (x_c/x_ref, x_s/x_ref,
    omega/omega_ref)``, ``R/F``.

    The element is called through its fast path ``fourier_derivatives_unchecked`` on 1-element
    float arrays: the public method's validation and broadcasting would cost more than the balance
    itself in the Newton loop; (a, omega) are finite and >= 0 here by construction.

    Parameters
    ----------
    blade : hbm.Blade
        The single-DOF blade (mass kg, stiffness N/m, damping N s/m, force N).
    element : contact_models.ContactElement or None, default None
        The damper; None gives the bare blade.
    rtol : float, default 1e-6
        Relative tolerance passed to the element's Fourier coefficients.
    x_ref : float, default 1.0
        Displacement scale of the scaled form (m).
    omega_ref : float, default 1.0
        Frequency scale of the scaled form (rad/s).

    Attributes
    ----------
    nfev : int
        Calls of the element's Fourier routine, omega differences included.
    nstuck : int
        Evaluations answered by the stuck (linear) stiffness.
    nfev_omega : int
        Of ``nfev``, the calls made for the derivative in omega.
    ncalls : int
        Balance evaluations.

    Notes
    -----
    With ``p = F_s/a`` and ``q = F_c/a`` (N/m), the element's in-phase and dissipative
    first-harmonic stiffness at the amplitude ``a = sqrt(x_c^2 + x_s^2)``, the residual (N) is ``R_c = (k - m omega^2 + p) x_c + (c omega + q) x_s - F`` and
    ``R_s = (k - m omega^2 + p) x_s - (c omega + q) x_c``.  The arguments are not validated.

    Examples
    --------
    >>> from hbm import Blade
    >>> hb = HarmonicBalance(Blade(mass=1.0, stiffness=4.0, damping=0.0, force=1.0))
    >>> R, J = hb.physical([1.0, 0.0, 1.0])   # (k - m omega^2) x_c - F = 3 - 1
    >>> R.tolist(), J.tolist()
    ([2.0, 0.0], [[3.0, 0.0, -2.0], [0.0, 3.0, 0.0]])
    """

    def __init__(self, blade: Blade, element: ContactElement | None = None, *, rtol: float = 1e-6,
                 x_ref: float = 1.0, omega_ref: float = 1.0) -> None:
        self.blade = blade
        self.element = element
        self.rtol = float(rtol)
        self.x_ref = float(x_ref)
        self.omega_ref = float(omega_ref)
        self.fresh_omega_derivative = False
        self.nfev = 0  #: calls of the element's Fourier routine (omega differences included)
        self.nstuck = 0  #: evaluations answered by the stuck stiffness
        self.nfev_omega = 0  #: of nfev, the calls made for the omega-derivative
        self.ncalls = 0  #: balance evaluations
        el = element
        self._freq_dep = el is not None and bool(getattr(el, "frequency_dependent", True))
        self._derivs = el.fourier_derivatives_unchecked if el is not None else None
        self._dw = None  # (omega, a, dp/domega, dq/domega) of the last omega difference
        self._stuck_dw_cache = None  # (omega, dk*/domega)
        self.omega_fd_step = math.sqrt(max(self.rtol, 1e-14))

    # ------------------------------------------------------------------ element
    def stiffness_terms(self, a: float, omega: float) -> tuple[float, float, float, float, float, float]:
        """``(p, q, dp/da, dq/da, dp/domega, dq/domega)`` of the element at amplitude ``a``."""
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

    def _pq(self, a, omega):
        self.nfev += 1
        fs, fc, dfs, dfc = self._derivs(np.array([a]), np.array([omega]), self.rtol)
        fs, fc, dfs, dfc = float(fs[0]), float(fc[0]), float(dfs[0]), float(dfc[0])
        p, q = fs / a, fc / a
        return p, q, (dfs - p) / a, (dfc - q) / a

    def _linear(self, omega):
        k_s, k_c = self.element.linear_coefficients(omega)
        return float(k_s), float(k_c)

    def _linear_dw(self, omega):
        """d(k_s, k_c)/domega of the linear range: central difference, retaken after a relative
        change OMEGA_REFRESH of omega."""
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

    # ------------------------------------------------------------------ balance
    def balance(self, xc: float, xs: float, omega: float) -> tuple[tuple[float, float], tuple[float, ...]]:
        """Physical ``(R_c, R_s)`` and ``dR/d(x_c, x_s, omega)`` as a flat 6-tuple (row-major)."""
        self.ncalls += 1
        b = self.blade
        a = math.hypot(xc, xs)
        p, q, dp, dq, dpw, dqw = self.stiffness_terms(a, omega)
        kr = b.stiffness - b.mass * omega * omega + p  # real part of the dynamic stiffness
        ki = b.damping * omega + q  # imaginary part
        Rc = kr * xc + ki * xs - b.force
        Rs = kr * xs - ki * xc
        if a > 0.0:
            gc, gs = xc / a, xs / a  # da/dx_c, da/dx_s
        else:
            gc = gs = 0.0
        u = dp * xc + dq * xs  # d(R_c)/da (through p and q)
        v = dp * xs - dq * xc  # d(R_s)/da
        krw = -2.0 * b.mass * omega + dpw
        kiw = b.damping + dqw
        J = (kr + u * gc, ki + u * gs, krw * xc + kiw * xs,
             -ki + v * gc, kr + v * gs, krw * xs - kiw * xc)
        return (Rc, Rs), J

    def physical(self, y: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """``R`` (2,) and ``J`` (2, 3) at ``y = (x_c, x_s, omega)`` in physical units."""
        R, J = self.balance(float(y[0]), float(y[1]), float(y[2]))
        return np.array(R), np.array(J).reshape(2, 3)

    def __call__(self, u: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Scaled ``R/F`` (2,) and its Jacobian in ``u = (x_c/x_ref, x_s/x_ref, omega/omega_ref)``."""
        xr, wr, F = self.x_ref, self.omega_ref, self.blade.force
        (Rc, Rs), J = self.balance(float(u[0]) * xr, float(u[1]) * xr, float(u[2]) * wr)
        cx, cw = xr / F, wr / F
        return (np.array((Rc / F, Rs / F)),
                np.array(((J[0] * cx, J[1] * cx, J[2] * cw), (J[3] * cx, J[4] * cx, J[5] * cw))))

    def to_physical(self, u: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(x_c, x_s, omega)`` arrays from scaled points ``u`` (..., 3)."""
        u = np.asarray(u, dtype=float)
        return u[..., 0] * self.x_ref, u[..., 1] * self.x_ref, u[..., 2] * self.omega_ref


def linear_response(blade: Blade, omega: ArrayLike,
                    stiffness: complex | Callable[[np.ndarray], ArrayLike] = 0.0) -> np.ndarray:
    """Closed-form complex amplitude ``x_c - i x_s = F / (k + k_d - m w^2 + i c w)`` of the blade
    with a linear spring ``stiffness`` (a number or a function of omega) in place of the damper."""
    omega = np.asarray(omega, dtype=float)
    kd = stiffness(omega) if callable(stiffness) else stiffness
    return blade.force / (blade.stiffness + kd - blade.mass * omega**2 + 1j * blade.damping * omega)
