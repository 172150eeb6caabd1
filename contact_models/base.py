"""The contact-element interface every model implements.

An element answers the first-harmonic question: for the steady displacement
``x = a sin(theta)``, ``theta = omega t`` at its attachment point, what are

    f_s = (1/pi) * integral_0^{2 pi} f(theta) sin(theta) dtheta   (in phase, "spring")
    f_c = (1/pi) * integral_0^{2 pi} f(theta) cos(theta) dtheta   (quadrature, "damping")

with ``f`` the force the element needs at that point.  ``pi * a * f_c`` is the
energy dissipated per cycle, so a passive element has ``f_c >= 0``.

The public methods are defined here, once: they validate and broadcast, then call the element's
private hooks (``_fourier`` and friends) on flat float arrays (the scipy
``OdeSolver.step``/``_step_impl`` split), and check the element's model range after the
evaluation.  An element implements hooks and may not override a public method
(``__init_subclass__`` refuses it, and a class that declares ``has_time_law = True`` without a
time law).  ``PUBLIC_HOOKS`` pairs each public method with its hook; docs/extending.md, section 1
("The contract"), says for every hook what it receives, in which units, which are optional and
their defaults, and what the base does before calling it, and describes the time laws
(section 1, "Time laws"): a Masing element implements ``loading_curve`` and ``_loading_slope``,
and the shared march of ``contact_models.numerics.masing`` gives its periodic force; any other
law implements ``_periodic_force``.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from typing import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .numerics.describing import first_harmonic, stiffness_terms
from .numerics.checks import (ElementContractError, ElementOutputError, amount_checked, count,  # noqa: F401
                              flag, fourier_checked, harmonics_asked, harmonics_checked, loop_checked, nonnegative,
                              nonnegative_array, number_array, pair_checked, positive, relative, scalar_checked,
                              time_law_checked)
from .numerics.masing import (SAMPLES_PER_HARMONIC, aft_matrices, aft_scalar, aft_vector, default_samples,  # noqa: F401
                              dense_jacobian, diagonal_product, masing_loop, masing_periodic,  # (public here)
                              to_harmonics, to_time, true_extremes)

#: Default relative tolerance of ``fourier`` on f_s and f_c.
DEFAULT_RTOL = 1e-6
#: Relative step of the central difference used by the default ``fourier_derivatives``.
FD_REL_STEP = 1e-6
#: The scalar types the public methods answer through an element's float path (``_scalar_call``).
_FLOAT_TYPES = (float, np.float64)


class ContactElement(ABC):
    """Abstract contact element: f_s, f_c as functions of amplitude and frequency.

    For the steady displacement ``x = a sin(theta)``, ``theta = omega t``, at its attachment
    point, an element gives the first-harmonic coefficients of the force ``f`` it needs there,

    .. math::

        f_s = \\frac{1}{\\pi} \\int_0^{2\\pi} f \\sin\\theta \\, d\\theta, \\qquad
        f_c = \\frac{1}{\\pi} \\int_0^{2\\pi} f \\cos\\theta \\, d\\theta
        \\quad \\text{(N)},

    in phase ("spring") and in quadrature ("damping"); ``pi a f_c`` is the energy dissipated per
    cycle, so a passive element has ``f_c >= 0``.

    Attributes
    ----------
    frequency_dependent : bool
        Class attribute, default True: whether f_s, f_c depend on omega; False lets the solver
        skip the derivative in omega.
    has_time_law : bool
        Class attribute, default False: True for an element with a time-domain force law
        (``periodic_force``, used by the multi-harmonic alternating frequency-time method).
    components : int
        Class attribute, default 1: the displacement components the element reads; 2 for a point
        contact's tangential and normal motion (``Contact2D``), whose ``periodic_force`` takes
        ``x`` of shape (2, n_t) and ``harmonic_force`` ``X`` of shape (2, 2H+1); it implements
        ``_periodic_entries(x, omega)``, the forces and the Jacobian's entries ``(rows, cols, vals)``
        (``contact_models.numerics.masing.aft_vector``).  3 for a point contact's two tangential
        directions and its normal (``Contact3D``: x (3, n_t), X (3, 2H+1)), whose memory spans the
        period, so it implements ``_harmonic_force`` with its tangent along ``E^-1`` instead.

    Notes
    -----
    A subclass implements ``_fourier_derivatives`` (or ``_fourier``), ``_stuck_stiffness``,
    ``_slip_amplitude`` and ``_hysteresis``, and may implement the optional hooks; the public
    methods, defined here only, validate and broadcast, then call them on flat float arrays
    (``PUBLIC_HOOKS``).  What a solver reads of an element (and nothing else): :attr:`frequency_dependent`,
    :attr:`has_time_law`, :meth:`fourier`, :meth:`fourier_derivatives`, :meth:`fourier_derivatives_unchecked`,
    :meth:`stuck_stiffness`, :meth:`slip_amplitude`, :meth:`linear_amplitude`, :meth:`linear_coefficients`,
    :meth:`reference_amplitude`, :meth:`hysteresis`, :meth:`harmonic_force`, :meth:`harmonic_force_unchecked`,
    :attr:`even_block_optional`, :meth:`harmonic_force_deferred` and :meth:`model_error`, and the refinement
    questions declared with their defaults (:attr:`exact_harmonics`, :attr:`discretised`, :attr:`harmonics_reach`,
    :attr:`model_name`, :meth:`harmonics_law`, :meth:`refined_model`, :meth:`start_rung`,
    :meth:`refined_rung`, :attr:`at_top_rung`, :attr:`refined_no_further`, :meth:`harmonics_of`, :meth:`for_balance`);
    docs/extending.md, section 1, states each hook and default.

    Examples
    --------
    >>> from contact_models import Macroslip
    >>> jen = Macroslip(stiffness=2.0, slip_force=1.0)
    >>> jen.linear_amplitude(), jen.linear_coefficients()
    (0.5, (2.0, 0.0))
    """

    #: True when f_s, f_c depend on omega; False lets the solver skip the omega-derivative.
    frequency_dependent: bool = True
    #: True for an element with a time-domain force law (``periodic_force``, multi-harmonic AFT).
    has_time_law: bool = False
    #: Displacement components read (rows of x and X): 1, 2 (tangential, normal) for Contact2D, 3 for Contact3D.
    components: int = 1
    #: True where ``_harmonic_force`` takes ``even_block=False`` (then dF/dX's even-even block may be 0: all-mode bar).
    even_block_optional: bool = False

    # ------------------------------------------------------------------ public
    def fourier(self, a: ArrayLike, omega: ArrayLike = 0.0, *,
                rtol: float = DEFAULT_RTOL) -> tuple[float | NDArray, float | NDArray]:
        """First-harmonic coefficients ``(f_s, f_c)`` in N for amplitude ``a`` (m) and ``omega`` (rad/s).

        ``a`` and ``omega`` broadcast against each other; both must be finite and >= 0.
        ``rtol`` is the relative accuracy asked of f_s and f_c.

        Parameters
        ----------
        a : array_like
            Amplitude of the displacement ``x = a sin(theta)`` (m), finite and >= 0.
        omega : array_like, optional
            Frequency (rad/s), finite and >= 0; broadcasts against ``a``.  Default 0.
        rtol : float, optional
            Relative accuracy asked of f_s and f_c, in (0, 1).  Default 1e-6.

        Returns
        -------
        f_s, f_c : float or ndarray
            In-phase and quadrature coefficients (N), of the broadcast shape of ``a`` and
            ``omega`` (floats for scalar input).

        Raises
        ------
        ValueError
            If ``a`` or ``omega`` is negative or not finite (or not a number: a string, a bool), if they
            do not broadcast, or if ``rtol`` is not in (0, 1), naming it.

        Examples
        --------
        The Jenkins element against its closed form
        ``f_c = (4 F_s/pi)(1 - F_s/(k a))`` past slip:

        >>> import math
        >>> from contact_models import Macroslip
        >>> jen = Macroslip(stiffness=1.0e7, slip_force=10.0)
        >>> f_s, f_c = jen.fourier(2.0e-6)
        >>> round(float(f_c), 9) == round(4 * 10.0 / math.pi * (1 - 10.0 / (1.0e7 * 2.0e-6)), 9)
        True
        >>> jen.fourier([0.5e-6, 1.0e-6], 0.0)[1]          # stuck up to a_min = 1e-6 m: no dissipation
        array([0., 0.])
        """
        one = self._scalar_call(a, omega, rtol)
        if one is None:
            a_b, w_b, shape = self._prepare(a, omega)
            rtol = relative("rtol", rtol)
            fs, fc = fourier_checked(self, a_b, w_b, rtol, values=True)
            out = _shaped(fs, shape), _shaped(fc, shape)
        else:
            out = one[:2]
        self._check_range(a, omega)
        return out

    def fourier_derivatives(self, a: ArrayLike, omega: ArrayLike = 0.0, *,
                            rtol: float = DEFAULT_RTOL) -> tuple[float | NDArray, ...]:
        """``(f_s, f_c, df_s/da, df_c/da)``, broadcasting like :meth:`fourier`.

        Elements implement ``_fourier_derivatives`` with analytic derivatives; the
        fallback (for elements that implement only ``_fourier``) is a central difference
        of relative step ``FD_REL_STEP`` in ``a``.  Validation, the float path of
        ``_derivatives_one`` and the model-range check are those of :meth:`fourier`.
        """
        one = self._scalar_call(a, omega, rtol)
        if one is None:
            a_b, w_b, shape = self._prepare(a, omega)
            rtol = relative("rtol", rtol)
            out = tuple(_shaped(v, shape) for v in fourier_checked(self, a_b, w_b, rtol))
        else:
            out = one
        self._check_range(a, omega)
        return out

    def model_error(self, a: ArrayLike, omega: ArrayLike = 0.0, *, parts: bool = False) -> float | NDArray | tuple:
        """Relative error of ``(f_s, f_c)`` against the physical contact the element stands for.

        0 for an element exact for what it models (Jenkins); the single-mode bars: the validity
        map's error against the all-mode bar (``contact_models.model_range``).  The solver's error
        estimate reads it (``FrequencyResponse.error_sources["model"]``).

        Parameters
        ----------
        a, omega : array_like
            Amplitudes (m) and frequencies (rad/s), >= 0; they broadcast.
        parts : bool, optional
            True: the pair ``(e_s, e_c)``, the errors of f_s and of f_c, each relative to
            ``max(|f|, 0.01 k* a)`` of its own component (an element that knows one error gives it for
            both).  Default False: their larger.

        Returns
        -------
        float or ndarray, or a pair of them
            The relative error (0.01 is 1 %), of the broadcast shape.

        Examples
        --------
        >>> from contact_models import Macroslip
        >>> float(Macroslip(stiffness=1.0, slip_force=0.5).model_error(2.0, 1.0))
        0.0
        """
        parts = flag("parts", parts)
        a_b, w_b, shape = self._prepare(a, omega)
        e = self._model_error(a_b, w_b)
        e_s, e_c = e if isinstance(e, tuple) else (e, e)
        return (_shaped(e_s, shape), _shaped(e_c, shape)) if parts else _shaped(np.maximum(e_s, e_c), shape)

    def fourier_derivatives_unchecked(self, a: NDArray, omega: NDArray, rtol: float) -> tuple[NDArray, ...]:
        """``(f_s, f_c, df_s/da, df_c/da)``, four flat arrays, on flat float64 arrays ``a``, ``omega`` of one
        size: the solver's fast path (finite a, omega >= 0, rtol > 0; the element's outputs checked, not the input)."""
        return fourier_checked(self, a, omega, rtol)

    def linear_amplitude(self, omega: float = 0.0) -> float:
        """Amplitude (m) up to which ``f_s + i f_c = (k_s + i k_c) a`` (see ``linear_coefficients``).

        Default: ``slip_amplitude(omega)``.  0 for an element that is nonlinear at any amplitude.
        """
        omega = nonnegative("omega", omega)
        return amount_checked(self, "_linear_amplitude", self._linear_amplitude(omega), omega, amplitude=True)

    def linear_coefficients(self, omega: float = 0.0) -> tuple[float, float]:
        """``(k_s, k_c)`` (N/m): ``f_s = k_s a``, ``f_c = k_c a`` for ``a <= linear_amplitude(omega)``.

        Default: ``(stuck_stiffness(omega), 0.0)``.
        """
        omega = nonnegative("omega", omega)
        return pair_checked(self, "_linear_coefficients", self._linear_coefficients(omega), omega)

    def reference_amplitude(self, omega: float = 0.0) -> float:
        """An amplitude (m) at which the element is clearly nonlinear (default ``slip_amplitude``):
        amplitude sweeps are measured in it, and property tests sample amplitudes around it."""
        omega = nonnegative("omega", omega)
        return amount_checked(self, "_reference_amplitude", self._reference_amplitude(omega), omega, amplitude=True)

    def stuck_stiffness(self, omega: float = 0.0) -> float:
        """Dynamic stiffness (N/m) while nothing slips; ``k* = stuck_stiffness(0)``."""
        omega = nonnegative("omega", omega)
        return amount_checked(self, "_stuck_stiffness", self._stuck_stiffness(omega), omega)

    def slip_amplitude(self, omega: float = 0.0) -> float:
        """``a_min`` (m): the amplitude at which slip begins."""
        omega = nonnegative("omega", omega)
        return amount_checked(self, "_slip_amplitude", self._slip_amplitude(omega), omega, amplitude=True)

    def hysteresis(self, a: float, omega: float = 0.0, *, n: int = 401) -> tuple[NDArray, NDArray]:
        """One closed loop ``(x, f)`` of the steady response to ``x = a sin(theta)``.

        ``n`` points, theta from -pi/2 to 3 pi/2 (the loop starts and ends at x = -a).

        Parameters
        ----------
        a : float
            Amplitude (m), >= 0.
        omega : float, optional
            Frequency (rad/s), >= 0.  Default 0.
        n : int, optional
            Number of points, >= 5.  Default 401.

        Returns
        -------
        x, f : ndarray
            Displacement (m) and force (N) along the loop, ``n`` points each.

        Raises
        ------
        ValueError
            If ``a`` or ``omega`` is negative, or ``n`` is not an integer >= 5.

        Examples
        --------
        The loop's area is the energy dissipated per cycle, ``pi a f_c``:

        >>> import numpy as np
        >>> from contact_models import Macroslip
        >>> jen = Macroslip(stiffness=1.0e7, slip_force=10.0)
        >>> x, f = jen.hysteresis(2.0e-6, n=2001)
        >>> area = 0.5 * abs(np.dot(x[:-1], f[1:]) - np.dot(x[1:], f[:-1]))
        >>> round(float(area / (np.pi * 2.0e-6 * jen.fourier(2.0e-6)[1])), 4)
        1.0
        """
        a = nonnegative("a", a)
        omega = nonnegative("omega", omega)
        n = count("n", n, 5)
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):  # the loop is checked finite
            loop = self._hysteresis(a, omega, n)
        return loop_checked(self, loop, a, omega)

    # ------------------------------------------------------------ time domain
    def periodic_force(self, x: ArrayLike, omega: float = 0.0) -> tuple[NDArray, NDArray]:
        """Steady periodic force samples ``f`` (n_t,) for the displacement samples ``x`` (n_t,) of
        one period (uniform in time), and the exact Jacobian ``df/dx`` (n_t, n_t) of that map.

        Parameters
        ----------
        x : array_like
            Displacement samples (m), at least 2, finite; the path is monotone between samples.
        omega : float
            Frequency (rad/s) of the period, >= 0 (for laws that depend on it).

        Returns
        -------
        f, df_dx : ndarray
            Force samples (N) and their Jacobian (N/m).

        Raises
        ------
        ValueError
            For an element without a time law (named), or bad ``x``/``omega``.

        Notes
        -----
        Masing elements: turning-point stack marched from the global maximum
        (``contact_models.numerics.masing``; ``docs/multiharmonic.md``).

        Examples
        --------
        >>> import numpy as np
        >>> from contact_models import Macroslip
        >>> f, J = Macroslip(stiffness=1.0, slip_force=0.5).periodic_force(np.cos(np.arange(8) * np.pi / 4))
        >>> np.round(f, 3).tolist()
        [0.5, 0.207, -0.5, -0.5, -0.5, -0.207, 0.5, 0.5]
        """
        self._require_time_law()
        x = number_array("x", x)
        rows = () if self.components == 1 else (self.components,)
        if x.ndim == 0 or x.shape[:-1] != rows or x.shape[-1] < 2:
            raise ValueError(f"x must be an array of shape {rows + ('n_t',)} with n_t >= 2 samples, "
                             f"got x with shape {x.shape}")
        if not np.all(np.isfinite(x)):
            bad = tuple(int(i) for i in np.argwhere(~np.isfinite(x))[0])
            at = ", ".join(map(str, bad))
            raise ValueError(f"x must be finite, got x[{at}]={float(x[bad])!r}")
        omega = nonnegative("omega", omega)
        return time_law_checked(self, x, omega)

    def harmonic_force(self, X: ArrayLike, omega: float, *, n_t: int | None = None,
                       rtol: float = DEFAULT_RTOL) -> tuple[NDArray, NDArray, NDArray]:
        """Harmonic coefficients of the periodic force for the displacement coefficients ``X``.

        Parameters
        ----------
        X : array_like
            ``[X0, Xc1, Xs1, ..., XcH, XsH]`` (m), length 2H+1, H >= 1:
            ``x(t) = X0 + sum_h (Xc_h cos(h omega t) + Xs_h sin(h omega t))``.
        omega : float
            Fundamental frequency (rad/s), >= 0.
        n_t : int, optional
            Time samples per period of the AFT, >= 2H+2 (aliasing); default
            ``default_samples(H)``.  Not used at H = 1 (exact describing function).
        rtol : float
            Relative tolerance passed to ``fourier_derivatives`` at H = 1, in (0, 1).

        Returns
        -------
        F, dF_dX, dF_domega : ndarray
            Force coefficients (N, same layout), Jacobian (2H+1, 2H+1), omega-derivative.

        Raises
        ------
        ValueError
            H > 1 for an element without a time law (named); bad X, omega or n_t.

        Notes
        -----
        AFT: ``x = E^-1 X`` at ``t_k = 2 pi k/(n_t omega)``, ``f = periodic_force(x)``,
        ``F = E f`` (real FFT), ``dF/dX = E J_t E^-1``; ``dF/domega = 0`` (rate-independent).
        A Masing element puts its outer loop's tips at the true extremes of ``x(t)`` (Newton
        between samples, ``contact_models.numerics.masing.true_extremes``) instead of the sampled ones,
        removing an O((2 pi/n_t)^2) error that moves with the phase of the sample grid.
        At H = 1 an element without a time law, and a Masing element (exactly), answer from the
        describing function ``fourier_derivatives``: ``F0 = K_inf X0``,
        ``Fc = p Xc + q Xs``, ``Fs = p Xs - q Xc`` with ``p = f_s/a``, ``q = f_c/a``.

        Examples
        --------
        >>> import numpy as np
        >>> from contact_models import Macroslip
        >>> F, J, Fw = Macroslip(stiffness=1.0, slip_force=0.5).harmonic_force([0.0, 0.0, 1.0], 1.0)
        >>> np.round(F, 4).tolist()  # f_c = 4 F_s (1 - y/a)/pi in cos, f_s = a/2 in sin
        [0.0, 0.3183, 0.5]
        """
        X = number_array("X", X)
        rows = () if self.components == 1 else (self.components,)
        if X.ndim != len(rows) + 1 or X.shape[:-1] != rows or X.shape[-1] < 3 or X.shape[-1] % 2 == 0:
            raise ValueError(f"X must be of shape {rows + ('2H+1',)} with 2H+1 odd >= 3, got X with shape {X.shape}")
        if not np.all(np.isfinite(X)):
            bad = tuple(int(i) for i in np.argwhere(~np.isfinite(X))[0])
            raise ValueError(f"X must be finite, got X[{', '.join(map(str, bad))}]={float(X[bad])!r}")
        H = (X.shape[-1] - 1) // 2
        omega = nonnegative("omega", omega)
        rtol = relative("rtol", rtol)
        if H > 1:
            self._require_time_law(f" at harmonics={H} (it is a first-harmonic element: use harmonics=1)")
        if n_t is None:
            n_t = default_samples(H)
        n_t = count("n_t", n_t, 2 * H + 2)
        return harmonics_checked(self, harmonics_asked(self, X, omega, n_t, rtol), X, omega)

    def harmonic_force_unchecked(self, X: NDArray, omega: float, n_t: int, rtol: float = DEFAULT_RTOL,
                                 even_block: bool = True) -> tuple[NDArray, NDArray, NDArray]:
        """:meth:`harmonic_force` without validation: the solver's fast path (float64 ``X`` of
        length 2H+1, ``omega >= 0``, ``n_t >= 2H+2``, and a time law if H > 1).  ``even_block=False``: where X has
        no even harmonics beyond rounding, an element with :attr:`even_block_optional` may leave the even-even block
        of dF/dX 0 (a balance in receptance form does not use it there: docs/multiharmonic.md, "Half-wave symmetry")."""
        kw = {} if even_block or not self.even_block_optional else {"even_block": False}  # only elements that take it
        return harmonics_checked(self, harmonics_asked(self, X, omega, n_t, rtol, **kw), X, omega)

    def harmonic_force_deferred(self, X: NDArray, omega: float, n_t: int, rtol: float = DEFAULT_RTOL
                                ) -> tuple[NDArray, NDArray, NDArray, Callable[[NDArray], NDArray] | None]:
        """:meth:`harmonic_force_unchecked` with ``even_block=False`` (the same input and answer), and ``whole``:
        how that same answer's dF/dX is made whole later.  None where it is whole already (an element without
        :attr:`even_block_optional`, or an ``X`` with even harmonics); else a callable ``whole(dF_dX)`` returning
        dF/dX (that answer's, as given) with its even-even block filled, whose ``nbytes`` is what it keeps.  A
        balance that keeps its Jacobians for Hill's method (``HarmonicBalance.keep_jacobians``) asks this and
        keeps ``whole`` with dF/dX: Hill's method needs the block (docs/multiharmonic.md, "Half-wave symmetry")
        that the trace does without, at the points only.  F, dF/dX and dF/domega are checked as
        :meth:`harmonic_force_unchecked`'s; what ``whole`` returns is the element's own."""
        F, J, Fw, whole = harmonics_asked(self, X, omega, n_t, rtol, hook="_harmonic_force_deferred")
        return (*harmonics_checked(self, (F, J, Fw), X, omega), whole)

    # ------------------------------------------------------------------ hooks
    def _harmonic_force(self, X: NDArray, omega: float, n_t: int, rtol: float) -> tuple[NDArray, NDArray, NDArray]:
        """``(F, dF/dX, dF/domega)`` for checked input: the describing function at H = 1 (no time
        law, or a Masing element), else AFT of the time law.  An element with its own harmonic
        balance (``AllModeMicroslip``) implements this instead.  A 2-component element: AFT per row."""
        if self.components > 1:
            return aft_vector(self._periodic_entries, X, omega, n_t)
        H = (X.size - 1) // 2
        if H == 1 and self.exact_describing_function:
            return self._describing_force(X, omega, rtol)
        tangent = self._masing_tangent if self._is_masing() else (lambda x, w, ext: self._periodic_tangent(x, w))
        return aft_scalar(tangent, X, omega, n_t, masing=self._is_masing())

    def _harmonic_force_deferred(self, X: NDArray, omega: float, n_t: int, rtol: float):
        """Hook of :meth:`harmonic_force_deferred`: ``(F, dF/dX, dF/domega, whole)``.  Default: an element
        without :attr:`even_block_optional` answers whole (``whole`` None); one with it answers with
        ``even_block=False`` and is asked again, whole, when ``whole`` is called (:class:`AskedWhole`).  An
        element that can fill its block from what it keeps of this answer, for less than a new answer
        (``AllModeMicroslip``: no new nested solve), implements it."""
        if not self.even_block_optional:
            return (*self._harmonic_force(X, omega, n_t, rtol), None)
        return (*self._harmonic_force(X, omega, n_t, rtol, even_block=False),
                AskedWhole(self, X, omega, n_t, rtol))

    # ----------------------------------------------------------------- private
    def _require_time_law(self, detail: str = "") -> None:
        if not self.has_time_law:
            raise ValueError(f"element={self!r}: {type(self).__name__} has no time-domain force law{detail}")

    @property
    def exact_describing_function(self) -> bool:
        """Whether :meth:`harmonic_force` at H = 1 answers with the describing function: an element
        without a time law, or a Masing element (whose describing function is exact at H = 1)."""
        return not self.has_time_law or self._is_masing()

    def _is_masing(self) -> bool:
        return type(self)._periodic_force is ContactElement._periodic_force

    def _loading_slope(self, x: NDArray, omega: float) -> NDArray:
        """dF/dx of the virgin loading curve (Masing elements implement it)."""
        raise NotImplementedError(f"{type(self).__name__} has no _loading_slope")

    def _masing_centre_stiffness(self, omega: float) -> float:
        """K_inf: the loading curve's slope past full slip (``slip_stiffness``), else 0."""
        k = getattr(self, "slip_stiffness", None)
        return float(k(omega)) if callable(k) else 0.0

    def _periodic_force(self, x: NDArray, omega: float) -> tuple[NDArray, NDArray]:
        f, d, idx, C = self._periodic_tangent(x, omega)
        return f, dense_jacobian(d, idx, C)

    def _periodic_tangent(self, x: NDArray, omega: float):
        """``(f, d, idx, C)``: force samples and ``J = diag(d)`` plus the columns ``C`` at ``idx``."""
        if self._is_masing():
            return self._masing_tangent(x, omega, None)
        f, J = time_law_checked(self, x, omega)
        return f, np.zeros_like(f), np.arange(f.size), J

    def _masing_tangent(self, x: NDArray, omega: float, extremes):
        loading = self.loading_curve
        return masing_periodic(x, lambda u: loading(u, omega), lambda u: self._loading_slope(u, omega),
                               self._masing_centre_stiffness(omega), extremes)

    def _describing_force(self, X: NDArray, omega: float, rtol: float):
        """H = 1 from the describing function (``contact_models.numerics.describing.first_harmonic``)."""
        return first_harmonic(self._pq, X, omega, rtol, self._masing_centre_stiffness(omega), self.frequency_dependent)

    def _pq(self, a: float, omega: float, rtol: float):
        """``(p, q, dp/da, dq/da)``, ``p = f_s/a``, ``q = f_c/a``; the linear range without ``fourier``."""
        if a == 0.0 or a <= self.linear_amplitude(omega):
            ks, kc = self.linear_coefficients(omega)
            return float(ks), float(kc), 0.0, 0.0
        return stiffness_terms(self.fourier_derivatives_unchecked, a, omega, rtol)

    def __init_subclass__(cls, **kwargs):
        """Refuse, when it is defined, a subclass that overrides a method of ``PUBLIC_HOOKS`` (it would
        bypass the checks), implements neither ``_fourier`` nor ``_fourier_derivatives``, or declares
        ``has_time_law = True`` without ``_periodic_force`` or ``loading_curve`` and ``_loading_slope``."""
        super().__init_subclass__(**kwargs)
        for name, hook in PUBLIC_HOOKS.items():
            if name in cls.__dict__:
                raise TypeError(f"{cls.__name__} overrides {name}(), which ContactElement defines (it validates "
                                f"and broadcasts the input and checks the model range); implement the hook "
                                f"{hook}() instead (docs/extending.md, section 1)")
        if (cls._fourier is ContactElement._fourier
                and cls._fourier_derivatives is ContactElement._fourier_derivatives):
            raise TypeError(f"{cls.__name__} must implement _fourier or _fourier_derivatives")
        missing = _missing_time_law(cls)
        if missing:
            raise TypeError(f"{cls.__name__} declares has_time_law = True but has no time law: implement "
                            f"{' and '.join(m + '()' for m in missing)} (Masing's rules with memory), or "
                            f"_periodic_force() (any other law; docs/extending.md, section 1)")

    def _scalar_call(self, a, omega, rtol):
        """``(f_s, f_c, df_s/da, df_c/da)`` as ``numpy.float64`` (the general path's scalar type) from
        the element's float path ``_derivatives_one``, for float ``a``, ``omega``, ``rtol`` passing the
        checks of ``_prepare`` and ``relative`` (for floats: finite and >= 0; rtol in (0, 1)).  None for an
        element without that path and for anything else: the general path validates and raises."""
        one = self._derivatives_one
        if (one is not None and type(a) in _FLOAT_TYPES and type(omega) in _FLOAT_TYPES and type(rtol) in _FLOAT_TYPES
                and 0.0 <= a < math.inf and 0.0 <= omega < math.inf and 0.0 < rtol < 1.0):
            return tuple(map(np.float64, scalar_checked(self, one(float(a), float(omega), float(rtol)), a, omega)))
        return None

    #: Optional hook ``_derivatives_one(a, omega, rtol)``: ``(f_s, f_c, df_s/da, df_c/da)`` in Python
    #: floats for one amplitude (m) and one frequency (rad/s), checked.  An element that has such a
    #: float path (no arrays) defines it as a method, and the public methods answer a float ``a``
    #: and ``omega`` through it; None: every call takes the array hooks.
    _derivatives_one: Callable[[float, float, float], tuple[float, float, float, float]] | None = None

    def _check_range(self, a: ArrayLike, omega: ArrayLike) -> None:
        """Hook called by ``fourier`` and ``fourier_derivatives`` after the evaluation, with the
        caller's ``a`` and ``omega``: warn (``ModelRangeWarning``) where the element's model is
        outside its range.  Default: no range, no warning.  The warning's ``stacklevel`` is 4
        (the caller of the public method)."""

    def refined_model(self) -> ContactElement | None:
        """The more complete element this one stands for, or None: the solver's ``model="auto"``
        solves with it where this element's ``model_error`` exceeds the tolerance (the single-mode
        microslip bars return the all-mode bar of the same bar and load)."""
        return self._refined_model()

    def _refined_model(self) -> ContactElement | None:
        """Hook of :meth:`refined_model`.  Default: None (the element is the complete model)."""
        return None

    # ------------------------------------------------------------ refinement: what a solver may ask
    # Declared here with their defaults (docs/extending.md, "Refinement"): the solver asks every element
    # the same questions and branches on no element type.  An element with nothing to refine keeps them.

    #: True where the element's harmonic force uses no AFT samples and is exact to rounding at any rtol (its
    #: discretisation error, if any, is its ``model_error``): the estimate's sampling and element sources are 0.
    exact_harmonics: bool = False
    #: True for an element whose accuracy is set by its own discretisation (cells, internal harmonics):
    #: its ``model_error`` is that discretisation's error, which ``start_rung``/``refined_rung`` refine.
    discretised: bool = False
    #: Rungs of the ladder H -> 2H + 1 above a balance's H that the harmonics the balance leaves out are read
    #: from (``hbm.balance.errors``): 1 (to 2H + 1) for a force whose harmonics fall smoothly with their order;
    #: more (2: to 4H + 3, 3: to 8H + 7, beyond the first rung at most 31) for an element with dynamics of its
    #: own, whose modes a high harmonic of the drive can meet (a superharmonic resonance that a step of one rung
    #: does not hold).
    harmonics_reach: int = 1

    @property
    def model_name(self) -> str:
        """The name a frequency response gives the points solved with this element
        (``FrequencyResponse.point_models``).  Default: the class name."""
        return type(self).__name__

    def harmonics_law(self) -> ContactElement | None:
        """An element with a time law that carries this element's higher force harmonics, for the
        estimate of the harmonics a first-harmonic balance leaves out.  Default: the element itself
        where it has a time law, else None (the estimate then bounds them from its loop)."""
        return self if self.has_time_law else None

    def start_rung(self, omega_range: tuple[float, float]) -> ContactElement | None:
        """The fixed, cheap discretisation of this element that a curve over ``omega_range`` (rad/s) is
        traced on first and refined from (:meth:`refined_rung`), or None: the element as given.
        Default None (an element that does not choose its own discretisation)."""
        return None

    def refined_rung(self, excess: float | None = None,
                     omega: tuple[float, float] | None = None) -> ContactElement | None:
        """The next rung of this element's own discretisation ladder for the points it was estimated
        at (``model_error``), whose estimate must fall by the factor ``excess`` (within ``omega = (lo,
        hi)`` rad/s if given), or None at the end of the ladder.  Default None (no ladder)."""
        return None

    @property
    def at_top_rung(self) -> bool:
        """Whether this is the finest rung a curve refines to.  Default False."""
        return False

    @property
    def refined_no_further(self) -> bool:
        """Whether a curve refines this rung no further where it was estimated worst (the ladder's end
        there).  Default False."""
        return False

    def harmonics_of(self, rung: ContactElement) -> ContactElement | None:
        """This rung with the internal harmonics of ``rung`` (a rung refined from it) and its own cells
        where that is the cheaper way to reach them, or None.  Default None."""
        return None

    def for_balance(self, H: int) -> ContactElement:
        """The element to use in a balance of ``H`` harmonics (a rung of a nested balance keeps enough of
        its own harmonics above the drive's).  Default: the element itself."""
        return self

    def _model_error(self, a: np.ndarray, omega: np.ndarray) -> np.ndarray:
        """Hook of :meth:`model_error`: flat float arrays in (m, rad/s), the relative error of
        ``(f_s, f_c)`` against the physical contact the element stands for out, or the pair of the
        components' errors ``(e_s, e_c)``.  Default: zeros (the element is exact for what it models)."""
        return np.zeros(np.shape(a))

    def _fourier(self, a: np.ndarray, omega: np.ndarray, rtol: float):
        """Flat float arrays in, ``(f_s, f_c)`` flat arrays out.

        Elements with analytic derivatives implement only ``_fourier_derivatives``; the values
        are its first two outputs.  Elements without implement this instead.
        """
        return self._fourier_derivatives(a, omega, rtol)[:2]

    @abstractmethod
    def _stuck_stiffness(self, omega: float) -> float: ...

    @abstractmethod
    def _slip_amplitude(self, omega: float) -> float: ...

    @abstractmethod
    def _hysteresis(self, a: float, omega: float, n: int): ...

    # the defaults below read another hook: its answer is checked as its public method checks it, naming it
    def _linear_amplitude(self, omega: float) -> float:
        return float(amount_checked(self, "_slip_amplitude", self._slip_amplitude(omega), omega, amplitude=True))

    def _linear_coefficients(self, omega: float) -> tuple[float, float]:
        return float(amount_checked(self, "_stuck_stiffness", self._stuck_stiffness(omega), omega)), 0.0

    def _reference_amplitude(self, omega: float) -> float:
        return float(amount_checked(self, "_slip_amplitude", self._slip_amplitude(omega), omega, amplitude=True))

    def _fourier_derivatives(self, a, omega, rtol):
        fs, fc = self._fourier(a, omega, rtol)
        h = FD_REL_STEP * np.maximum(a, 1e-300)
        lo = np.maximum(a - h, 0.0)
        hi = a + h
        fs_hi, fc_hi = self._fourier(hi, omega, rtol)
        fs_lo, fc_lo = self._fourier(lo, omega, rtol)
        return fs, fc, (fs_hi - fs_lo) / (hi - lo), (fc_hi - fc_lo) / (hi - lo)

    @staticmethod
    def _prepare(a, omega):
        a = nonnegative_array("a", a)
        omega = nonnegative_array("omega", omega)
        try:
            a_b, w_b = np.broadcast_arrays(a, omega)
        except ValueError:
            raise ValueError(f"a and omega must broadcast against each other, got a with shape {np.shape(a)} and "
                             f"omega with shape {np.shape(omega)}") from None
        shape = a_b.shape
        return a_b.ravel().astype(float), w_b.ravel().astype(float), shape


#: The class attributes that declare what kind of element an element is (its time law, its components,
#: how its harmonics are computed and read): an element that stands for others it builds (a preload that
#: follows the speed) declares what they declare, attribute by attribute from this list.
KIND_ATTRIBUTES = ("has_time_law", "components", "even_block_optional", "exact_harmonics", "discretised",
                   "harmonics_reach")


#: The public methods of the contract, defined once here, and the hook each calls: a subclass
#: implements the hook and may not override the method (``__init_subclass__`` refuses it).
PUBLIC_HOOKS = {
    "fourier": "_fourier",
    "fourier_derivatives": "_fourier_derivatives",
    "fourier_derivatives_unchecked": "_fourier_derivatives",
    "stuck_stiffness": "_stuck_stiffness",
    "slip_amplitude": "_slip_amplitude",
    "linear_amplitude": "_linear_amplitude",
    "linear_coefficients": "_linear_coefficients",
    "reference_amplitude": "_reference_amplitude",
    "hysteresis": "_hysteresis",
    "periodic_force": "_periodic_force",
    "model_error": "_model_error",
    "refined_model": "_refined_model",
    "harmonic_force": "_harmonic_force",
    "harmonic_force_unchecked": "_harmonic_force",
    "harmonic_force_deferred": "_harmonic_force_deferred",
}


class AskedWhole:
    """The default ``whole`` of :meth:`ContactElement.harmonic_force_deferred`: the element asked again at
    the same input with the even-even block (``harmonic_force_unchecked(..., even_block=True)``), keeping
    only that input (``nbytes``)."""

    __slots__ = ("element", "X", "omega", "n_t", "rtol", "nbytes")

    def __init__(self, element: ContactElement, X: NDArray, omega: float, n_t: int, rtol: float) -> None:
        self.element, self.X, self.omega, self.n_t, self.rtol = element, np.array(X, dtype=float), omega, n_t, rtol
        self.nbytes = self.X.nbytes

    def __call__(self, dF_dX: NDArray) -> NDArray:
        return self.element.harmonic_force_unchecked(self.X, self.omega, self.n_t, self.rtol)[1]


def _missing_time_law(cls: type) -> list[str]:
    """The time-law hooks a class that declares ``has_time_law = True`` lacks (empty when it has a
    time law, or does not declare one as a plain class attribute, e.g. a property)."""
    if getattr(cls, "has_time_law", False) is not True:
        return []
    if (cls._periodic_force is not ContactElement._periodic_force
            or cls._harmonic_force is not ContactElement._harmonic_force):
        return []
    missing = [] if callable(getattr(cls, "loading_curve", None)) else ["loading_curve"]
    if cls._loading_slope is ContactElement._loading_slope:
        missing.append("_loading_slope")
    return missing


def _shaped(v, shape):
    v = np.asarray(v, dtype=float).reshape(shape)
    return v[()] if v.ndim == 0 else v
