"""The macroslip element: a Coulomb slider behind a tangential spring (Jenkins element).

The classic macroslip model of the paper's introduction (refs. [1-5] there): the contact
is a rigid body that is either stuck (force ``stiffness * (x - w)``, w the slider
position) or slipping at ``|f| = slip_force``.  It holds when the whole interface slips
at once (light normal load); it predicts no dissipation below ``slip_force/stiffness``.

``fourier`` is the describing function (``docs/point_contact.md``, "Jenkins element"):
stuck, ``f_s = k a, f_c = 0``, for ``a <= y = slip_force/k``; above, with
``psi = arccos(1 - 2 y/a) = 2 arcsin(sqrt(y/a))``,

    f_s = k a (psi - sin(2 psi)/2) / pi,      f_c = 4 slip_force (1 - y/a) / pi.

``stiffness=math.inf`` is the rigid Coulomb slider: ``f_s = 0``, ``f_c = 4 slip_force/pi``
for ``a > 0``.  The time-domain law (``step``, ``force_history``) is the exact return map
of the slider for a displacement that is monotone between samples; ``periodic_force`` follows Masing's rules
with memory from ``loading_curve`` and its slope (``contact_models.base``).  ``harmonic_force`` at
H > 1 is exact for the centred slider: the Fourier coefficients of the piecewise force and their
Jacobian in closed form (``contact_models.numerics.jenkins``, no samples: ``n_t`` is not used,
``exact_harmonics``); "from rest" goes through AFT.  The rigid slider has no time law there (its
tangent is a Dirac at each reversal): it is a first-harmonic element.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .numerics.checks import finite_array, nonnegative, positive
from .numerics.jenkins import jenkins_harmonics
from .base import ContactElement, masing_loop

#: The slider conventions of the time law: "centred" (the library's, the Masing march of
#: ``contact_models.numerics.masing``) and "from rest" (marched two periods from a relaxed spring at
#: x = 0, as NLvib does); ``docs/contacts_normal.md``, "The stuck slider".
SLIDERS = ("centred", "from rest")

#: Below this value of z = 2 psi, z - sin z is summed as its Taylor series (no cancellation).
SERIES_BELOW = 0.5


def z_minus_sin(z: ArrayLike) -> NDArray[np.float64]:
    """``z - sin(z)`` for z >= 0, accurate to rounding also for small z (f_s at large amplitude)."""
    z = np.asarray(z, dtype=float)
    z2 = z * z
    # z^3/3! - z^5/5! + ... - z^13/13!; the next term is < 2e-16 of the sum for z < 0.5
    series = z * z2 / 6.0 * (1.0 - z2 / 20.0 * (1.0 - z2 / 42.0 * (1.0 - z2 / 72.0 * (
        1.0 - z2 / 110.0 * (1.0 - z2 / 156.0)))))
    return np.where(z < SERIES_BELOW, series, z - np.sin(z))


def jenkins_fourier(k: float, y: float, a: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """``(f_s, f_c, df_s/da, df_c/da)`` of a Jenkins element (spring k, slip displacement y > 0).

    The slip force is ``k y``.  ``a`` is a flat float array of amplitudes >= 0.  f_s is
    continuously differentiable; df_c/da jumps from 0 to 4 k/pi at ``a = y``, where the
    stuck (left) value is returned.
    """
    a = np.asarray(a, dtype=float)
    fs = k * a
    fc = np.zeros_like(a)
    dfs = np.full_like(a, k)
    dfc = np.zeros_like(a)
    slip = a > y
    if np.any(slip):
        A = a[slip]
        r = y / A  # in (0, 1)
        psi = 2.0 * np.arcsin(np.sqrt(r))  # = arccos(1 - 2 y/a), stable for small y/a
        sin_psi = 2.0 * np.sqrt(r * (1.0 - r))
        fs_slip = k * A * z_minus_sin(2.0 * psi) / (2.0 * np.pi)
        fs[slip] = fs_slip
        fc[slip] = 4.0 * k * y * (1.0 - r) / np.pi
        # d/da [k a (psi - sin 2psi/2)/pi] = f_s/a + (k a/pi) 2 sin^2 psi dpsi/da,
        # dpsi/da = -(2 y/a^2)/sin psi  ->  f_s/a - 4 k (y/a) sin psi / pi
        dfs[slip] = fs_slip / A - 4.0 * k * r * sin_psi / np.pi
        dfc[slip] = 4.0 * k * r * r / np.pi
    return fs, fc, dfs, dfc


class Macroslip(ContactElement):
    """Jenkins element: spring ``stiffness`` (N/m, may be ``math.inf``) behind a Coulomb
    slider of force ``slip_force`` (N).  Frequency independent.

    Parameters
    ----------
    stiffness : float
        Tangential spring k (N/m), > 0 (negative, zero, NaN, -inf refused by name); ``math.inf`` for
        the rigid Coulomb slider.
    slip_force : float
        Slider force (N), > 0.
    slider : {"centred", "from rest"}, optional
        The periodic state of the time law (``periodic_force``, ``harmonic_force`` at H > 1) where
        it is not unique, i.e. while the slider sticks all period.  "centred" (default): the slider
        at the middle of the displacement's range, the state a decaying shake-down leaves and the
        limit of the slipping states (``contact_models.numerics.masing``); the describing function
        answers at H = 1, the exact harmonics above (``contact_models.numerics.jenkins``).  "from rest": the slider starts at 0 and the element is marched two
        periods (NLvib's convention), answering by AFT at every H (``docs/contacts_normal.md``).

    Raises
    ------
    ValueError
        If ``stiffness`` or ``slip_force`` is not positive, or ``slider`` is not one of the two
        (or "from rest" for the rigid slider), naming it and its value.

    See Also
    --------
    PointContact : a Jenkins element with two more springs, fitted to a microslip element.

    Notes
    -----
    The describing function: stuck, ``f_s = k a`` and ``f_c = 0``, up to
    ``a_min = y = slip_force/k``; above, with ``psi = arccos(1 - 2 y/a)``,

    .. math::

        f_s = \\frac{k a}{\\pi}\\left(\\psi - \\tfrac{1}{2}\\sin 2\\psi\\right), \\qquad
        f_c = \\frac{4 F_{slip}}{\\pi}\\left(1 - \\frac{y}{a}\\right).

    The rigid slider gives ``f_s = 0``, ``f_c = 4 slip_force/pi`` for ``a > 0``.  The
    time-domain law (:meth:`step`, :meth:`force_history`) is the slider's exact return map.

    Examples
    --------
    >>> import math
    >>> from contact_models import Macroslip
    >>> jen = Macroslip(stiffness=1.0e7, slip_force=10.0)
    >>> jen.slip_amplitude()                           # slip_force/stiffness, m
    1e-06
    >>> f_s, f_c = jen.fourier(2.0e-6)                 # psi = pi/2 at a = 2 y
    >>> round(float(f_s), 6), round(float(f_c) * math.pi / 40.0, 12)
    (10.0, 0.5)
    """

    frequency_dependent = False

    def __init__(self, stiffness: float, slip_force: float, *, slider: str = "centred") -> None:
        self.stiffness = _stiffness("stiffness", stiffness)
        self.slip_force = positive("slip_force", slip_force)
        if slider not in SLIDERS:
            raise ValueError(f"slider must be one of {SLIDERS}, got slider={slider!r}")
        if slider == "from rest" and self.rigid:
            raise ValueError(f"slider='from rest' needs a finite stiffness (the rigid slider has no time law), "
                             f"got stiffness={stiffness!r}")
        self.slider = slider

    @property
    def has_time_law(self) -> bool:
        """True for the elastic Jenkins element; False for the rigid slider (H = 1 only)."""
        return not self.rigid

    def __repr__(self) -> str:
        extra = "" if self.slider == "centred" else f", slider={self.slider!r}"
        return f"Macroslip(stiffness={self.stiffness!r}, slip_force={self.slip_force!r}{extra})"

    def _is_masing(self) -> bool:
        """The centred slider follows the base's Masing march; "from rest" has its own time law."""
        return self.slider == "centred"

    @property
    def exact_harmonics(self) -> bool:
        """True for the centred slider: :meth:`harmonic_force` is exact at every H (the describing
        function at H = 1, the closed form of ``contact_models.numerics.jenkins`` above), so ``n_t``
        is not used and the error estimate's "sampling" source is zero; False for "from rest"
        (AFT)."""
        return self.slider == "centred"

    def _harmonic_force(self, X, omega, n_t, rtol):
        """At H > 1 the centred slider's exact harmonics (``jenkins_harmonics``); else the base's."""
        if X.size > 3 and self.exact_harmonics and not self.rigid:
            F, J = jenkins_harmonics(X, self.stiffness, self.slip_force)
            return F, J, np.zeros_like(F)
        return super()._harmonic_force(X, omega, n_t, rtol)

    def _periodic_tangent(self, x, omega):
        if self.slider == "centred":
            return super()._periodic_tangent(x, omega)
        return from_rest_tangent(x, self.stiffness, self.slip_force)

    @property
    def rigid(self) -> bool:
        """True for the rigid Coulomb slider (infinite stiffness)."""
        return self.stiffness == math.inf

    # ------------------------------------------------------------ time domain
    def step(self, x_old: ArrayLike, f_old: ArrayLike, x_new: ArrayLike) -> NDArray[np.float64]:
        """Force after moving monotonically from ``x_old`` (force ``f_old``) to ``x_new``.

        The state is the last pair (x, f); the slider sits at ``x - f/stiffness``.  Exact
        return map: ``f = clip(f_old + k (x_new - x_old), -slip_force, slip_force)``;
        for the rigid slider ``f = slip_force * sign(x_new - x_old)`` (``f_old`` at rest).
        Broadcasts over arrays.
        """
        dx = np.asarray(x_new, dtype=float) - np.asarray(x_old, dtype=float)
        F = self.slip_force
        if self.rigid:
            return np.where(dx > 0.0, F, np.where(dx < 0.0, -F, f_old))
        return np.clip(f_old + self.stiffness * dx, -F, F)

    def slider_position(self, x: ArrayLike, f: ArrayLike) -> NDArray[np.float64]:
        """Slider position ``w = x - f/stiffness`` for the state (x, f)."""
        return np.asarray(x, dtype=float) - np.asarray(f, dtype=float) / self.stiffness

    def force_history(self, x: ArrayLike, *, x0: float = 0.0, f0: float = 0.0) -> NDArray[np.float64]:
        """Force for the displacement history ``x`` (time along the last axis).

        The element starts in the state (x0, f0) (default: relaxed at rest) and moves
        monotonically between successive samples; leading axes are independent histories.
        """
        return _history(self.step, x, x0, f0)

    # ------------------------------------------------------------ frequency domain
    def loading_curve(self, x: ArrayLike, omega: float = 0.0) -> NDArray[np.float64]:
        """Virgin loading force ``F(x) = min(k x, slip_force)`` for x >= 0."""
        x = finite_array("x", x)
        nonnegative("omega", omega)
        if self.rigid:
            return np.where(x > 0.0, self.slip_force, 0.0)
        return np.minimum(self.stiffness * x, self.slip_force)

    def _loading_slope(self, x, omega):
        """dF/dx: k below the slip displacement (k at it, the stuck side), 0 above."""
        return np.where(np.asarray(x) <= self.slip_force / self.stiffness, self.stiffness, 0.0)

    def _stuck_stiffness(self, omega):
        return self.stiffness

    def _slip_amplitude(self, omega):
        return self.slip_force / self.stiffness

    def _hysteresis(self, a, omega, n):
        return masing_loop(self.loading_curve, a, n)

    def _fourier_derivatives(self, a, omega, rtol):
        if self.rigid:  # Coulomb: a square wave in phase with the velocity
            fc = np.where(a > 0.0, 4.0 * self.slip_force / np.pi, 0.0)
            zero = np.zeros_like(a)
            return zero, fc, zero.copy(), zero.copy()
        return jenkins_fourier(self.stiffness, self.slip_force / self.stiffness, a)


def from_rest_periodic(x: NDArray, k: float, slip_force: float) -> tuple[NDArray, NDArray]:
    """The force samples of a Jenkins element marched from rest over two periods, and their Jacobian.

    The slider starts at 0 (spring relaxed at ``x = 0``) before sample 1; the return map
    ``f = clip(k (x_j - w), +-slip_force)`` (slip where ``|k (x_j - w)| >= slip_force``) runs over
    samples 1..n-1 and then 0..n-1, and the second pass is returned: the march of NLvib's
    elastic dry friction element (Krack & Gross 2019).  Each sample's force is
    ``k (x_j - x_r) + s_r slip_force`` with ``r`` the last slip before it (or ``k x_j`` if none),
    which gives the exact Jacobian of the march (dense here; ``from_rest_tangent`` gives it as
    a diagonal and the few columns of the slip samples).
    """
    f, d, idx, C = from_rest_tangent(x, k, slip_force)
    J = np.diag(d)
    J[:, idx] += C
    return f, J


def from_rest_tangent(x: NDArray, k: float, slip_force: float) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """:func:`from_rest_periodic` as ``(f, d, idx, C)``: its Jacobian is ``diag(d)`` (``k`` where
    stuck) plus the columns ``C`` at the samples ``idx`` the stuck samples were last slipping at
    (``-k`` in the rows held from there).  A cycle has a few slip stretches, so ``idx`` is short
    and the AFT Jacobian costs O(n_t H), not O(n_t^2)."""
    n = x.size
    w, r = 0.0, -1
    f = np.empty(n)
    origin = np.full(n, -1)
    slipped = np.zeros(n, dtype=bool)
    for step, j in enumerate(np.r_[1:n, 0:n]):
        trial = k * (x[j] - w)
        if abs(trial) >= slip_force:
            val = math.copysign(slip_force, trial)
            w, r, slip = x[j] - val / k, j, True
        else:
            val, slip = trial, False
        if step >= n - 1:
            f[j], origin[j], slipped[j] = val, r, slip
    d = np.where(slipped, 0.0, k)
    held = np.flatnonzero(~slipped & (origin >= 0))
    idx, col = np.unique(origin[held], return_inverse=True)
    C = np.zeros((n, idx.size))
    C[held, col] = -k
    return f, d, idx, C


def _is_inf(v) -> bool:
    """True for +inf given as a Python or numpy float (an allowed 'rigid' stiffness)."""
    return isinstance(v, (int, float)) and not isinstance(v, bool) and v == math.inf


def _stiffness(name: str, v) -> float:
    """A stuck (tangential) stiffness: +inf (rigid, :func:`_is_inf`) or finite and > 0 (:func:`positive`); else a
    ValueError naming ``name`` and its value, -inf as "must be positive" (not "finite": +inf is taken)."""
    if _is_inf(v):
        return math.inf
    if isinstance(v, (int, float)) and not isinstance(v, bool) and v == -math.inf:
        raise ValueError(f"{name} must be positive (finite, or inf: rigid), got {name}={v!r}")
    return positive(name, v)


def _history(step, x, x0, f0):
    """Apply ``step(x_old, f_old, x_new)`` along the last axis of ``x``."""
    x = np.asarray(x, dtype=float)
    if x.ndim == 0:
        raise ValueError(f"x must be an array of displacements in time, got x={x!r}")
    if not np.all(np.isfinite(x)):
        raise ValueError("x must be finite, got a non-finite displacement")
    lead = x.shape[:-1]
    x_old = np.broadcast_to(np.asarray(x0, dtype=float), lead).copy()
    f_old = np.broadcast_to(np.asarray(f0, dtype=float), lead).copy()
    if not (np.all(np.isfinite(x_old)) and np.all(np.isfinite(f_old))):
        raise ValueError(f"x0 and f0 must be finite, got x0={x0!r}, f0={f0!r}")
    f = np.empty_like(x)
    for j in range(x.shape[-1]):
        x_new = x[..., j]
        f_old = step(x_old, f_old, x_new)
        f[..., j] = f_old
        x_old = x_new
    return f


__all__ = ["Macroslip", "from_rest_periodic", "jenkins_fourier", "z_minus_sin"]
