"""The equivalent point contact of Section 3.4 (Fig. 16), and its fit to a microslip element.

Layout (``docs/point_contact.md``): input x -> spring ``k_s`` -> node y; the node is tied
to ground by a spring ``beta_p`` in parallel with a Jenkins element (spring ``k_p`` behind
a Coulomb slider of force ``slip_force``).  One slider, so the contact is either fully
stuck or in gross slip: it cannot represent partial slip, which is the point of the
paper's comparison (Figs. 17-18).

Eliminating the node (``docs/point_contact.md``, "Eliminating the node") shows that for
*any* displacement history the input force is ``f = K2 x + g`` with ``g`` the force of a
Jenkins element of stiffness ``K1 - K2`` and slip force ``F0 = slip_force k_s/(k_s + beta_p)``:

    K1 = series(k_s, beta_p + k_p)     stuck stiffness
    K2 = series(k_s, beta_p)           slipping stiffness
    a_y = F0 / (K1 - K2)               slip (= gross-slip) amplitude

so the loop is the bilinear Masing loop and f_s, f_c are ``K2 a`` plus the Jenkins
describing function (``contact_models.macroslip.jenkins_fourier``).  Frequency independent.
Its time law for multi-harmonic balance is Masing's with memory on that bilinear curve
(``periodic_force``, ``harmonic_force``; centre force ``K2 x_c``, ``contact_models.numerics.masing``).

``PointContact.fit(element)`` matches conditions (1)-(3) of Section 3.4 (equal stuck
stiffness, fully-slipping stiffness and gross-slip amplitude).  These fix K1, K2, a_y and
hence f_s, f_c; the layout has a fourth unknown, fixed here by ``k_p = k L`` (the
interface's shear-layer stiffness) unless ``k_p`` or ``slip_force`` is given.  The slider
cannot be at mu N for the uniform bar: that needs ``(K1 - K2) a_g <= mu N``, which fails
for every uniform-load bar (proof in ``docs/point_contact.md``).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .numerics.checks import derived, finite, finite_array, nonnegative, positive
from .base import ContactElement, masing_loop
from .macroslip import _history, _is_inf, _stiffness, jenkins_fourier

#: A slip_force this close (relative) to the intercept (K1 - K2) a_g is taken as equal: k_s = inf.
INTERCEPT_RTOL = 1e-12


class PointContact(ContactElement):
    """Point contact of Fig. 16: ``k_s`` (N/m, may be ``math.inf``) in series with
    ``beta_p`` (N/m, >= 0) parallel to a Jenkins element (``k_p`` N/m, ``slip_force`` N).

    Usually made by :meth:`fit` from a microslip element.  Frequency independent.

    Parameters
    ----------
    k_s : float
        Series spring between the input and the node (N/m), > 0 or ``math.inf`` (negative, zero, NaN, -inf refused).
    beta_p : float
        Spring from the node to ground (N/m), >= 0.
    k_p : float
        Spring of the Jenkins element from the node to ground (N/m), > 0.
    slip_force : float
        Slider force of the Jenkins element (N), > 0.

    Raises
    ------
    ValueError
        If a parameter is out of its range, naming it and its value.

    See Also
    --------
    Macroslip, TwoRegionMicroslip

    Notes
    -----
    One Coulomb slider makes a bilinear Masing loop: stuck stiffness
    ``K1 = 1/(1/k_s + 1/(beta_p + k_p))``, fully slipping stiffness
    ``K2 = 1/(1/k_s + 1/beta_p)``, slip at the input amplitude
    ``slip_force k_s/((k_s + beta_p)(K1 - K2))``.  ``docs/point_contact.md`` derives it.

    References
    ----------
    .. [1] Cigeroglu, Lu & Menq (2006), Section 3.4, Fig. 16; Figs. 17-18.

    Examples
    --------
    >>> from contact_models import PointContact
    >>> pc = PointContact(k_s=float("inf"), beta_p=1.0e7, k_p=3.0e7, slip_force=30.0)
    >>> pc.stuck_stiffness(), pc.slip_stiffness(), pc.slip_amplitude()   # N/m, N/m, m
    (40000000.0, 10000000.0, 1e-06)
    """

    frequency_dependent = False
    has_time_law = True

    def __init__(self, k_s: float, beta_p: float, k_p: float, slip_force: float) -> None:
        self.k_s = _stiffness("k_s", k_s)
        self.beta_p = nonnegative("beta_p", beta_p)
        self.k_p = positive("k_p", k_p)
        self.slip_force = positive("slip_force", slip_force)
        bp, kp = self.beta_p, self.k_p

        def constants():
            cs = 1.0 / self.k_s  # compliance of k_s (0 when rigid)
            # K1 - K2 = k_s^2 k_p / ((k_s + beta_p + k_p)(k_s + beta_p)), without cancellation
            D = kp / ((1.0 + cs * (bp + kp)) * (1.0 + cs * bp))
            # slider force seen at the input: F0 = slip_force k_s/(k_s + beta_p)
            F0 = self.slip_force / (1.0 + cs * bp)
            return {"1/k_s": cs, "K1": (bp + kp) / (1.0 + cs * (bp + kp)), "K2": bp / (1.0 + cs * bp), "D": D,
                    "F0": F0, "a_y": F0 / D}

        params = {"k_s": k_s, "beta_p": beta_p, "k_p": k_p, "slip_force": slip_force}
        k = derived("PointContact", params, constants, positive_names=("K1", "D", "F0", "a_y"))
        self._cs, self._K1, self._K2 = k["1/k_s"], k["K1"], k["K2"]
        self._D, self._F0, self._a_y = k["D"], k["F0"], k["a_y"]

    def __repr__(self) -> str:
        return (f"PointContact(k_s={self.k_s!r}, beta_p={self.beta_p!r}, k_p={self.k_p!r}, "
                f"slip_force={self.slip_force!r})")

    # ------------------------------------------------------------ the fit (Section 3.4)
    @classmethod
    def fit(cls, element: ContactElement, omega: float = 0.0, *, k_p: float | None = None,
            slip_force: float | None = None) -> PointContact:
        """Point contact with the stuck stiffness, fully-slipping stiffness and gross-slip
        amplitude of the microslip ``element`` at ``omega`` (Section 3.4, conditions 1-3).

        Fourth condition (it does not change f_s, f_c): ``k_p`` if given, else
        ``slip_force`` if given, else ``k_p = element.bar.k * element.bar.L``, the total
        shear-layer stiffness, which is always admissible at omega = 0.  A positive layout
        needs ``(K1 - K2) a_g <= slip_force < K1 a_g`` (equality: ``k_s = inf``), so the
        slider cannot sit at mu N for the uniform bar.  Raises ``ValueError`` naming the
        condition that no all-positive layout can meet.

        Parameters
        ----------
        element : ContactElement
            The element to match, with ``stuck_stiffness``, ``slip_stiffness`` and
            ``gross_slip_amplitude`` (the microslip elements).
        omega : float, optional
            Frequency (rad/s) at which the three are matched, >= 0.  Default 0.
        k_p : float, optional
            The fourth condition: the Jenkins spring (N/m).  Default ``bar.k * bar.L``.
        slip_force : float, optional
            The fourth condition instead of ``k_p``: the slider force (N).

        Returns
        -------
        PointContact
            The fitted contact; ``stuck_stiffness()``, ``slip_stiffness()`` and
            ``gross_slip_amplitude()`` equal the element's at ``omega``.

        Raises
        ------
        ValueError
            If no all-positive layout meets the conditions, or ``element`` has no bar for the
            default ``k_p``; the message names the condition.

        References
        ----------
        .. [1] Cigeroglu, Lu & Menq (2006), Section 3.4 (conditions 1-3), Figs. 16-18.

        Examples
        --------
        >>> from contact_models import Bar, UniformLoad, TwoRegionMicroslip, PointContact
        >>> bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
        >>> two = TwoRegionMicroslip(bar, UniformLoad(N=100.0))
        >>> pc = PointContact.fit(two)
        >>> pc.stuck_stiffness(), round(pc.slip_stiffness(), 3), pc.gross_slip_amplitude()
        (40000000.0, 20000000.0, 1.875e-06)
        >>> round(pc.k_p), round(pc.slip_force, 4)          # k L (N/m); the slider (N), not mu N
        (40000000, 46.3525)
        """
        omega = nonnegative("omega", omega)
        missing = [m for m in ("stuck_stiffness", "slip_stiffness", "gross_slip_amplitude")
                   if not callable(getattr(element, m, None))]
        if missing:
            raise ValueError(f"element must have stuck_stiffness, slip_stiffness and gross_slip_amplitude (a "
                             f"microslip element: TwoRegionMicroslip, ThreeRegionMicroslip), got element={element!r} "
                             f"without {', '.join(missing)}")
        K1 = float(element.stuck_stiffness(omega))
        K2 = float(element.slip_stiffness(omega))
        a_g = float(element.gross_slip_amplitude(omega))
        if k_p is None and slip_force is None:
            bar = getattr(element, "bar", None)
            if bar is None or not hasattr(bar, "k"):
                raise ValueError(f"k_p: element={element!r} has no bar.k for the default k_p = k L; "
                                 "give k_p or slip_force")
            k_p = bar.k * bar.L
        return cls.from_bilinear(K1, K2, a_g, k_p=k_p, slip_force=slip_force)

    @classmethod
    def from_bilinear(cls, stuck_stiffness: float, slip_stiffness: float, gross_slip_amplitude: float, *,
                      k_p: float | None = None, slip_force: float | None = None) -> PointContact:
        """Point contact whose bilinear loading curve has slopes ``stuck_stiffness`` (K1) and
        ``slip_stiffness`` (K2) with the kink at ``gross_slip_amplitude`` (a_g), and the given
        ``k_p`` or ``slip_force`` (exactly one).  ``docs/point_contact.md``, "The fit"."""
        K1, K2, a_g = (finite(n, v) for n, v in (
            ("stuck_stiffness", stuck_stiffness), ("slip_stiffness", slip_stiffness),
            ("gross_slip_amplitude", gross_slip_amplitude)))
        if (k_p is None) == (slip_force is None):
            raise ValueError(f"give exactly one of k_p and slip_force, got k_p={k_p!r}, slip_force={slip_force!r}")
        if not K2 > 0.0:
            raise ValueError(
                f"condition (2), equal fully-slipping stiffness, cannot be met with positive stiffnesses: "
                f"the point contact slips with series(k_s, beta_p) > 0, got slip_stiffness={K2!r}")
        if not K1 > K2:
            raise ValueError(
                f"condition (1), equal stuck stiffness, cannot be met with positive stiffnesses: "
                f"it needs stuck_stiffness > slip_stiffness, got stuck_stiffness={K1!r}, slip_stiffness={K2!r}")
        if not a_g > 0.0:
            raise ValueError(
                f"condition (3), equal gross-slip amplitude, cannot be met: a point contact with a slider "
                f"slips at a > 0, got gross_slip_amplitude={a_g!r}")
        D = K1 - K2
        F0 = D * a_g  # force intercept of the slipping branch, fixed by (1)-(3)
        if slip_force is not None:
            Fs = positive("slip_force", slip_force)
            # c = F0/Fs = k_s/(k_s + beta_p) must lie in (1 - K2/K1, 1]; c = 1 is k_s = inf
            if Fs < F0 * (1.0 - INTERCEPT_RTOL):
                raise ValueError(
                    f"condition (3), equal gross-slip amplitude, cannot be met with slip_force={Fs!r} and "
                    f"positive stiffnesses: with (1) and (2) it needs slip_force >= (K1 - K2) a_g = {F0!r} N "
                    f"(it would take k_s = {K2 * Fs / (Fs - F0)!r} N/m)")
            if not Fs < K1 * a_g:
                raise ValueError(
                    f"condition (3), equal gross-slip amplitude, cannot be met with slip_force={Fs!r} and "
                    f"positive stiffnesses: with (1) and (2) it needs slip_force < K1 a_g = {K1 * a_g!r} N")
            Fs = max(Fs, F0)
            c = F0 / Fs
            one_minus_c = (Fs - F0) / Fs
            kp = K2 * Fs * Fs / (F0 * (K1 * a_g - Fs))
        else:
            kp = positive("k_p", k_p)
            if not kp >= D:
                raise ValueError(
                    f"condition (1), equal stuck stiffness, cannot be met with k_p={kp!r} and positive "
                    f"stiffnesses: with (2) and (3) it needs k_p >= K1 - K2 = {D!r} N/m")
            # c solves k_p K1 c^2 - k_p D c - K2 D = 0 (positive root); 1 - c without cancellation
            root = math.sqrt(D * D + 4.0 * K1 * K2 * D / kp)
            c = (D + root) / (2.0 * K1)
            one_minus_c = 2.0 * K2 * (1.0 - D / kp) / (K1 + K2 + root)
            Fs = F0 / c
        k_s = K2 / one_minus_c if one_minus_c > 0.0 else math.inf
        return cls(k_s=k_s, beta_p=K2 / c, k_p=kp, slip_force=Fs)

    # ------------------------------------------------------------ bilinear loading curve
    def slip_stiffness(self, omega: float = 0.0) -> float:
        """K2 = series(k_s, beta_p): the slope while the slider slips."""
        nonnegative("omega", omega)
        return self._K2

    def gross_slip_amplitude(self, omega: float = 0.0) -> float:
        """Amplitude at which the slider starts to slip (one slider: slip is gross slip)."""
        nonnegative("omega", omega)
        return self._a_y

    def loading_curve(self, x: ArrayLike, omega: float = 0.0) -> NDArray[np.float64]:
        """Virgin loading force ``F(x) = K2 x + (K1 - K2) min(x, a_y)`` for x >= 0."""
        x = finite_array("x", x)
        nonnegative("omega", omega)
        return self._K2 * x + self._D * np.minimum(x, self._a_y)

    def _loading_slope(self, x, omega):
        """dF/dx: K1 up to a_y (the stuck side at it), K2 beyond."""
        return np.where(np.asarray(x) <= self._a_y, self._K1, self._K2)

    # ------------------------------------------------------------ time domain (the layout itself)
    def internal_state(self, x: ArrayLike, f: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """``(y, z)``: node displacement and slider position for the state (x, f)."""
        x = np.asarray(x, dtype=float)
        f = np.asarray(f, dtype=float)
        y = x - f * self._cs  # k_s (x - y) = f
        f_jenkins = f - self.beta_p * y  # node equilibrium
        return y, y - f_jenkins / self.k_p

    def step(self, x_old: ArrayLike, f_old: ArrayLike, x_new: ArrayLike) -> NDArray[np.float64]:
        """Force after moving monotonically from ``x_old`` (force ``f_old``) to ``x_new``.

        Solves the node equilibrium ``k_s (x - y) = beta_p y + f_J`` of the layout with the
        Jenkins force ``f_J = k_p (y - z)`` stuck, or ``+-slip_force`` slipping (exact return
        map: one slider, linear springs).  The state is the pair (x, f).  Broadcasts.
        """
        cs, bp, kp, Fs = self._cs, self.beta_p, self.k_p, self.slip_force
        x_new = np.asarray(x_new, dtype=float)
        _, z = self.internal_state(x_old, f_old)
        y = (x_new + cs * kp * z) / (1.0 + cs * (bp + kp))  # trial: slider stuck
        f_jenkins = kp * (y - z)
        slipping = np.abs(f_jenkins) > Fs
        f_jenkins = np.where(slipping, np.sign(f_jenkins) * Fs, f_jenkins)
        y = np.where(slipping, (x_new - cs * f_jenkins) / (1.0 + cs * bp), y)
        return bp * y + f_jenkins

    def force_history(self, x: ArrayLike, *, x0: float = 0.0, f0: float = 0.0) -> NDArray[np.float64]:
        """Force for the displacement history ``x`` (time along the last axis), starting in
        the state (x0, f0) (default: relaxed at rest), monotone between samples."""
        return _history(self.step, x, x0, f0)

    # ------------------------------------------------------------ interface
    def _stuck_stiffness(self, omega):
        return self._K1

    def _slip_amplitude(self, omega):
        return self._a_y

    def _hysteresis(self, a, omega, n):
        return masing_loop(self.loading_curve, a, n)

    def _fourier_derivatives(self, a, omega, rtol):
        # f = K2 x + Jenkins(K1 - K2, slip displacement a_y): docs/point_contact.md
        fs, fc, dfs, dfc = jenkins_fourier(self._D, self._a_y, a)
        fs = np.where(a <= self._a_y, self._K1 * a, fs + self._K2 * a)  # stuck: exactly K1 a
        return fs, fc, dfs + self._K2, dfc


__all__ = ["PointContact"]
