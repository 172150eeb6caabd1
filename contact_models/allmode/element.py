"""The all-mode dynamic microslip bar in the frequency domain (the paper's future work).

``AllModeMicroslip`` is the bar of Eq. 30 with every mode (n equal cells, a Jenkins element of stiffness
k c_i and slip force mu q(x_i) c_i at node i, the beta spring at node 0, node n driven), solved for its
steady periodic state directly, by multi-harmonic balance with alternating frequency-time (AFT) at the
nodes.  It resolves the phase differences along the bar that the single-mode elements neglect, works for
any normal load (any number of stick and slip regions) and any frequency, including above the cut-off
sqrt(k/(rho A)).  Between the nodes the bar is exact (``linear="exact"``, ``segments``: each cell the
continuous bar with its shear layer stuck, at every harmonic), or the finite-element bar of
``NumericalMicroslip`` with lumped masses (``linear="lumped"``).

Model.  Free nodes i = 0..n-1 with harmonic coefficients U_i (layout ``[U0, Uc1, Us1, ...]``,
H harmonics), driven node U_n = X (the end displacement, ``a sin(theta)`` for ``fourier``):

    R_i = D_i U_i + c (U_{i-1} + U_{i+1}) + T_i(U_i) = 0,

with D_i and c diagonal in the harmonics (the linear part, ``segments.linear_part``; lumped:
D_i = K_ii - (h omega)^2 m_i, c = K_off) and T_i = P tau_i(E U_i) the harmonic coefficients of node i's
periodic Jenkins force (exact return map, ``balance.jenkins_periodic``).  The end force ``EA u_x(L)`` is
the driven node's reaction, F = D_n X + c U_{n-1} + T_n(X).

Solution.  Newton's method on R (piecewise linear in U for a fixed stick/slip pattern, so it ends exactly
once the pattern settles) with an Armijo line search; the Jacobian is block tridiagonal (blocks (2H+1)^2
from AFT, coupling c), solved by block Thomas elimination in O(n H^3).  The derivatives of F follow from
the implicit function theorem: only node n-1 couples to X, so ``dF/dX = D_n + dT_n/dX - c C_{n-1}^{-1} c``
(C_{n-1} the last pivot block) and ``dF/domega = D_n' X + c' U_{n-1} + c dU_{n-1}/domega`` with ``J
dU/domega = -dR/domega`` (' the derivative in omega).  The last solution warm-starts the next call; a
failed Newton run falls back to continuation in the amplitude from the exactly linear (stuck) state.  One
discretisation is a ``contact_models.allmode.solve.FixedBar``.

Accuracy.  With ``cells`` and ``harmonics`` left None the element chooses them per call (amplitude,
frequency) so that its estimate of the relative error of (f_s, f_c), component by component relative to
max(|f|, 0.01 k* a) as in the validity map, is below ``tol``: cells double from a start tied to the
wavelength of the highest harmonic and to the shear layer's decay length (``accuracy.start_cells``),
and harmonics climb the ladder 7, 15, 31, whichever part of the estimate is larger.  The estimate is
Richardson extrapolation with the observed order on three rungs (cells n/2, n, 2n below 128 cells, with the
difference to 2n added, else n/4, n/2, n; harmonics H/2, H, 2H+1 below 15 with the difference to 2H+1 added,
else about H/4, H/2, H), guarded where the order is not
asymptotic (``contact_models.allmode.accuracy``); its two parts add.  The ladder starts where the previous
call ended and the estimate of a call within ``REUSE_AMPLITUDE`` and ``REUSE_FREQUENCY`` of the last
estimated point, whose estimate was below half the tolerance, is reused.  Where the largest rungs
(``MAX_CELLS``, ``MAX_HARMONICS``) cannot meet ``tol`` the call warns (``AccuracyWarning``) once, naming the
worst point.  While the bar is stuck (a <= ``slip_amplitude``) the answer is linear (exact segments: the
continuous bar's).  ``model_error(a, omega)`` returns the relative estimate.  Along a frequency response the
choice is made once per stretch instead, on fixed rungs (``start_rung``, ``refined_rung``:
``contact_models.allmode.rungs``).
"""
from __future__ import annotations

import math
import warnings
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..accuracy import AccuracyWarning
from ..bar import Bar
from ..base import DEFAULT_RTOL, AskedWhole, ContactElement
from ..loads import bound_load
from ..numerics.checks import count, flag, nonnegative, positive
from ..numerics.fe_bar import _Discretisation
from .accuracy import (FLOOR, cells_error, harmonics_error, relative, richardson, shortfall_message, start_cells,
                       stuck_data)
from .balance import aft_matrices
from .compiled import kernels
from .estimate import model_errors
from .memo import EvenBlockLater, ForceMemo, truncated
from .rungs import CURVE_MAX_CELLS, START_CELLS, START_HARMONICS, next_rung, probed_rung
from .segments import KINDS as LINEAR_KINDS, UnresolvedWave, cells_for_phase
from .solve import (EVEN_ROUNDING, NEWTON_MAX_ITER, NEWTON_TOL, AllModeSolution, FixedBar, checked_mesh,
                    checked_samples, end_vector, is_odd, pad_harmonics, scaled_samples, transferred)

if TYPE_CHECKING:
    from ..loads import QuadraticLoad, UniformLoad

__all__ = ["AllModeMicroslip", "AllModeSolution", "CELLS", "HARMONICS", "SAMPLES_PER_HARMONIC", "NEWTON_TOL",
           "NEWTON_MAX_ITER", "TOL", "HARMONIC_LADDER", "MAX_CELLS", "MAX_HARMONICS", "richardson", "cells_error"]
# ``richardson`` and ``cells_error`` are re-exported for estimates built on the element's answers.

#: Cells of a bar with a fixed mesh where one is wanted (the scenes' ``cells`` key); the element's
#: own default is None: cells chosen per call to ``tol``.
CELLS = 40
#: Harmonics of a bar with fixed harmonics where one is wanted; the element's default is None.
HARMONICS = 15
#: Default time samples per harmonic (n_t = SAMPLES_PER_HARMONIC * H, rounded up to a multiple of 4).
SAMPLES_PER_HARMONIC = 8
#: Default tolerance on the relative error of (f_s, f_c) (relative to max(|f|, 0.01 k* a)).
TOL = 1e-3
#: The rungs of harmonics the element climbs when it chooses H (a rung is about twice the last).
HARMONIC_LADDER = (7, 15, 31)
#: The largest number of cells the element doubles to, and the largest H it climbs to.
MAX_CELLS = 640
MAX_HARMONICS = HARMONIC_LADDER[-1]
#: An estimate is reused within these relative distances in amplitude and frequency of the point it
#: was made at, when it was below half the tolerance (continuation steps are smaller).
REUSE_AMPLITUDE = 0.01
REUSE_FREQUENCY = 0.005


def _samples(H: int) -> int:
    return 4 * math.ceil(SAMPLES_PER_HARMONIC * H / 4)


class AllModeMicroslip(ContactElement):
    """Microslip bar of Eq. 30 with every mode, solved in the frequency domain.

    Parameters
    ----------
    bar : Bar
        The damper bar.
    load : UniformLoad, QuadraticLoad, FunctionLoad or SampledLoad
        Normal load q(x) >= 0 (any shape: any number of stick and slip regions).
    cells : int, optional
        Cells along the bar, >= 2.  Default None: chosen per call to ``tol``
        (doubling from a start tied to the wavelength, up to ``MAX_CELLS``).
    harmonics : int, optional
        Harmonics H kept in every node's motion, >= 1.  Default None: chosen per call to ``tol``
        (the rungs ``HARMONIC_LADDER`` = 7, 15, 31).
    n_t : int, optional
        Time samples per period of the AFT, a multiple of 4 and >= 2H + 2; only with ``harmonics``
        (default ``SAMPLES_PER_HARMONIC * H`` rounded up to a multiple of 4).
    tol : float, optional
        The relative error of (f_s, f_c) the element's choices aim at, in (0, 1): component by
        component relative to max(|f|, 0.01 k* a).  Default ``TOL`` = 1e-3.  Used where cells or
        harmonics are chosen; an explicit ``cells`` or ``harmonics`` is kept as given.
    linear : {"exact", "lumped"}, optional
        The bar between the nodes.  "exact" (default): each cell is the continuous bar with its shear
        layer stuck, exact at every harmonic, so the cells resolve only where the layer slips (a bar
        stuck everywhere is exact on any mesh).  "lumped": linear finite elements with lumped masses,
        the bar ``NumericalMicroslip`` integrates in time.

    Notes
    -----
    The model, the solution and the choice of cells and harmonics are in the module docstring and ``docs/theory.md``
    (section "The all-mode bar").  Accuracy against converged references and the cost of each knob:
    ``docs/validation.md`` and ``docs/performance.md``.  The steady state of a node that never slips is taken with its
    slider at the centre of its motion (the Masing convention; the symmetric state for the drive ``a sin(theta)``).
    ``fourier``'s ``rtol`` is not used: Newton converges to rounding (relative residual 1e-11), and the accuracy is
    set by ``tol`` (or by ``cells``, ``harmonics`` and ``n_t`` when both are given: then ``solve(...,
    estimate_error=True)`` and ``model_error`` estimate it, and nothing warns).  ``fourier`` raises FloatingPointError
    where the balance does not converge; ``solve`` reports it in ``success`` and ``message``.  Where the largest rungs
    cannot meet ``tol`` a call warns ``contact_models.AccuracyWarning`` once.

    Raises
    ------
    ValueError
        ``bar`` not a ``Bar``; ``cells``, ``harmonics``, ``n_t``, ``tol`` or ``linear`` out of range; a load
        below 0; at a call, exact cells longer than 0.9 of half the wavelength of the highest harmonic.

    Examples
    --------
    >>> from contact_models import AllModeMicroslip, Bar, UniformLoad
    >>> bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    >>> el = AllModeMicroslip(bar, UniformLoad(N=100.0), cells=20, harmonics=7)
    >>> fs, fc = el.fourier(3 * 7.5e-7, 0.0)
    >>> round(float(fs) / (bar.k_star * 3 * 7.5e-7), 2), round(float(fc) / (bar.k_star * 3 * 7.5e-7), 2)
    (0.75, 0.15)
    >>> sol = AllModeMicroslip(bar, UniformLoad(N=100.0)).solve(3 * 7.5e-7, 0.3 * bar.omega_c)
    >>> bool(sol.relative_error < 1e-3), sol.cells >= 8
    (True, True)
    """

    #: A force law for any periodic end motion (a nested balance: the hook ``_harmonic_force``), usable at H > 1.
    has_time_law = True
    #: Its harmonic force is the nested balance solved to rounding (relative residual 1e-11) whatever the caller's
    #: ``n_t`` and ``rtol`` (its own samples go with its H): the solver's estimate counts no sampling error and no
    #: evaluation error beyond rounding; its discretisation error (cells, H and its own samples) is ``model_error``.
    exact_harmonics = True
    #: Its accuracy is its discretisation's (cells, harmonics): refined along a curve by its rungs.
    discretised = True
    #: The bar's own modes meet high harmonics of the drive (near the default blade's peak the 13th meets the
    #: second mode with the end held): the harmonics a balance leaves out are read three rungs up (from H = 1
    #: at 15, from H = 3 at 31).
    harmonics_reach = 3

    def __init__(self, bar: Bar, load: UniformLoad | QuadraticLoad, cells: int | None = None,
                 harmonics: int | None = None, *, n_t: int | None = None, tol: float = TOL,
                 linear: str = "exact") -> None:
        if not isinstance(bar, Bar):
            raise ValueError(f"bar must be a contact_models.Bar, got bar={bar!r}")
        self.cells = None if cells is None else count("cells", cells, 2)
        self.harmonics = None if harmonics is None else count("harmonics", harmonics, 1)
        self.n_t = checked_samples(n_t, self.harmonics, _samples)
        most = MAX_HARMONICS if self.harmonics is None else self.harmonics  # the most it may climb to
        checked_mesh(MAX_CELLS if self.cells is None else self.cells, most,
                     _samples(most) if self.n_t is None else self.n_t,
                     f"cells={cells!r}, harmonics={harmonics!r}" + ("" if n_t is None else f", n_t={n_t!r}"))
        self.tol = positive("tol", tol)
        if not self.tol < 1.0:
            raise ValueError(f"tol must be in (0, 1), got tol={tol!r}")
        if not isinstance(linear, str) or linear not in LINEAR_KINDS:  # (an array: numpy's ambiguous truth)
            raise ValueError(f"linear must be one of {', '.join(map(repr, LINEAR_KINDS))}, got linear={linear!r}")
        self.bar, self.linear = bar, linear
        self.load = bound_load(load, bar.L)
        self._levels: dict = {}  # (cells, H) -> FixedBar
        self._discs: dict = {}  # cells -> _Discretisation (the stuck bar)
        self._stuck: dict = {}  # omega -> (cells, K, a_min, relative estimate)
        self._last: tuple | None = None  # (cells, H, cells part, harmonics part) the previous call ended at
        self._reuse: tuple | None = None  # the last estimate: (a, omega, odd, cells, H, parts, relative)
        self._seen: list = []  # a fixed rung's estimates (omega, a, cells part, harmonics part): refined_rung
        self._memo = ForceMemo()  # a fixed rung's harmonic forces by their exact motion and frequency

    def __repr__(self) -> str:
        return (f"AllModeMicroslip({self.bar!r}, {self.load!r}, cells={self.cells}, "
                f"harmonics={self.harmonics}, n_t={self.n_t}, tol={self.tol!r}, linear={self.linear!r})")

    @property
    def _fixed(self) -> bool:
        return self.cells is not None and self.harmonics is not None

    @property
    def at_top_rung(self) -> bool:
        """Whether this is a fixed rung a curve does not refine (``CURVE_MAX_CELLS`` cells or more at
        ``MAX_HARMONICS``): ``refined_rung`` returns None."""
        return self._fixed and self.cells >= CURVE_MAX_CELLS and self.harmonics >= MAX_HARMONICS

    @property
    def refined_no_further(self) -> bool:
        """Whether a curve refines this fixed rung no further where it was estimated worst (``_predict`` None)."""
        if self.at_top_rung or not self._fixed or not self._seen:
            return self.at_top_rung
        _, _, rc, rh = max(self._seen, key=lambda s: s[2] + s[3])
        return self._predict(self, rc, rh, (rc + rh) / self.tol, max(s[0] for s in self._seen)) is None

    def _predict(self, el, rc, rh, excess, w_hi):
        """The rung after the fixed rung ``el`` for its parts (``next_rung``; cells held to the wavelength at w_hi)."""
        return next_rung(el.cells, el.harmonics, rc, rh, excess, max_cells=max(el.cells, CURVE_MAX_CELLS),
                         ladder=HARMONIC_LADDER, cells_for=lambda h: start_cells(self.bar, w_hi, h))

    @property
    def model_name(self) -> str:
        """The name a frequency response gives the points solved with this element
        (``FrequencyResponse.point_models``): with its rung where cells and harmonics are fixed."""
        return f"AllModeMicroslip(cells={self.cells}, H={self.harmonics})" if self._fixed else "AllModeMicroslip"

    # ------------------------------------------------------------ rungs along a curve
    def start_rung(self, omega_range: tuple[float, float]) -> AllModeMicroslip | None:
        """The cheap fixed rung a frequency response over ``omega_range`` (rad/s) starts on where this element chooses
        its cells and harmonics (both None): ``START_HARMONICS`` = 7 harmonics and ``START_CELLS`` = 32 cells, doubled
        while fewer than the wavelength of its top harmonic at the top of the range asks for (``start_cells``); the
        same ``tol``; None where cells or harmonics are given.  Refined along the curve (``refined_rung``; see
        docs/theory.md, "The all-mode bar along a curve").  A curve follows: the compiled kernels load now."""
        kernels(load=True)
        if self.cells is not None or self.harmonics is not None:
            return None
        w_hi = max(nonnegative("omega_range", w) for w in omega_range)
        n = START_CELLS
        while n < min(MAX_CELLS, start_cells(self.bar, w_hi, START_HARMONICS)):
            n *= 2
        return AllModeMicroslip(self.bar, self.load, n, START_HARMONICS, tol=self.tol, linear=self.linear)

    def refined_rung(self, excess: float | None = None,
                     omega: tuple[float, float] | None = None) -> AllModeMicroslip | None:
        """The next fixed rung for the points this fixed rung was estimated at (``model_error``): at
        the worst of them (within ``omega = (lo, hi)`` rad/s if given and any is), the rung predicted
        to bring its estimate down by the factor ``excess`` (default: its estimate over ``tol``;
        ``rungs.next_rung``), tried at that point first and predicted again from there while
        short (``rungs.probed_rung``).  None where cells or harmonics are chosen per call,
        where nothing was estimated yet, or at the top (``CURVE_MAX_CELLS``, ``MAX_HARMONICS``).

        Raises
        ------
        ValueError
            ``excess`` not a positive number.
        """
        if not self._fixed or not self._seen:
            return None
        seen = [s for s in self._seen if omega is None or min(omega) <= s[0] <= max(omega)] or self._seen
        w, a, rel_c, rel_h = max(seen, key=lambda s: s[2] + s[3])
        excess = (rel_c + rel_h) / self.tol if excess is None else positive("excess", excess)
        w_hi = max(s[0] for s in seen)
        predict = lambda el, rc, rh, ex: self._predict(el, rc, rh, ex, w_hi)  # noqa: E731 (also probed_rung's)
        rung = predict(self, rel_c, rel_h, excess)
        build = lambda n, h: AllModeMicroslip(self.bar, self.load, n, h, tol=self.tol, linear=self.linear)  # noqa: E731
        return None if rung is None else probed_rung(rung, (w, a), (rel_c + rel_h) / excess, build, predict)

    def harmonics_of(self, rung: AllModeMicroslip) -> AllModeMicroslip | None:
        """This fixed rung at ``rung``'s top harmonics if it has fewer (``rung`` refined from it), its cells doubled
        up to ``rung``'s while the top harmonic's wavelength at its estimated points asks (``start_cells``); else None."""
        if not (self._fixed and rung._fixed and rung.harmonics >= MAX_HARMONICS > self.harmonics):
            return None
        n, w_hi = self.cells, max((s[0] for s in self._seen), default=0.0)
        n *= 2 ** max(0, math.ceil(math.log2(min(rung.cells, start_cells(self.bar, w_hi, rung.harmonics)) / n)))
        return AllModeMicroslip(self.bar, self.load, n, rung.harmonics, tol=self.tol, linear=self.linear)

    def for_balance(self, H: int, at_least: int = 0) -> AllModeMicroslip:
        """This fixed rung in a balance of H > 1 harmonics: with the top of the harmonic ladder
        (``MAX_HARMONICS``) and ``at_least`` of its own; itself where it has them, or where it chooses.

        The rung's estimate is made at the drive ``a sin``, one of whose samples is its maximum; in a balance
        of more harmonics the drive has other harmonics and any phase, and the sampled return map's force
        moves with the phase: on 15 harmonics (120 samples) by up to 4.6 times the estimate, on 31 (248
        samples) by about the estimate or less (``docs/validation.md``, "The phase of the nested solve's
        samples").  At H = 1 the element is evaluated at its own phase: the rung as it is."""
        H = count("H", H, 1)
        at_least = count("at_least", at_least, 0)
        if H <= 1:
            return self
        h = max(MAX_HARMONICS, at_least)
        if not self._fixed or h <= self.harmonics:
            return self
        return AllModeMicroslip(self.bar, self.load, self.cells, h, tol=self.tol, linear=self.linear)

    def _refined_model(self):
        """A fixed rung's refined model: the next rung (``refined_rung``) for its own ``tol``."""
        return self.refined_rung()

    # ------------------------------------------------------------ extras
    @property
    def nodes(self) -> NDArray[np.float64]:
        """Node positions x_i (m): of the fixed mesh, or of the cells the last call ended at."""
        n = self.cells or (self._last[0] if self._last else start_cells(self.bar, 0.0, 1))
        return np.linspace(0.0, self.bar.L, n + 1)

    def solve(self, a: float | ArrayLike, omega: float = 0.0, *, estimate_error: bool = False) -> AllModeSolution:
        """Steady periodic state of the bar for a driven-end displacement.

        Parameters
        ----------
        a : float or array_like
            An amplitude (m) for ``a sin(theta)``, or end-displacement coefficients (m) of length
            2H'+1, layout ``[X0, Xc1, Xs1, ...]``, H' <= ``harmonics`` (or ``MAX_HARMONICS``).
        omega : float
            Frequency (rad/s), >= 0.
        estimate_error : bool
            With fixed ``cells`` and ``harmonics``: also solve on the other rungs (cells n/2, 2n
            below 128 cells, else n/4, n/2; harmonics about H/4, H/2) and fill ``error``,
            ``relative_error`` and ``error_parts``.  Where the element chooses, they are always filled.
            Default False.

        Returns
        -------
        AllModeSolution
            End force harmonics, nodal coefficients, derivatives, slip map, ``success``, ``message``.

        Raises
        ------
        ValueError
            ``a`` or ``omega`` negative, not finite, or ``a`` of a bad length.

        Examples
        --------
        >>> from contact_models import AllModeMicroslip, Bar, UniformLoad
        >>> bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
        >>> sol = AllModeMicroslip(bar, UniformLoad(N=100.0), cells=20, harmonics=7).solve(
        ...     3 * 7.5e-7, 0.5 * bar.omega_c, estimate_error=True)
        >>> sol.success, round(sol.f_c / (bar.k_star * 3 * 7.5e-7), 3), sol.error < 1e-3 * bar.k_star * 3 * 7.5e-7
        (True, 0.19, True)
        """
        estimate_error = flag("estimate_error", estimate_error)
        omega = nonnegative("omega", omega)
        X = end_vector(a, self.harmonics or MAX_HARMONICS)
        odd = is_odd(X)
        if self._fixed:
            sol = self._level(self.cells, max(self.harmonics, (X.size - 1) // 2)).solve(
                pad_harmonics(X, self.harmonics), omega, odd)
            if estimate_error and sol.success:
                self._fill(sol, self._parts(X, omega, odd, sol), self._floor(X))
            return sol
        sol, short = self._choose(X, omega, odd)
        self._warn([short] if short else [])
        return sol

    def _harmonic_force(self, X: NDArray[np.float64], omega: float, n_t: int, rtol: float, even_block: bool = True
                        ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """End force coefficients ``F`` (2H+1), ``dF/dX`` and ``dF/domega`` for the end displacement coefficients
        ``X`` (length 2H+1, H >= 1) at ``omega`` (rad/s): the multi-harmonic hook (docs/extending.md, section 1,
        "Time laws"), checked by ``harmonic_force`` (or trusted by ``harmonic_force_unchecked``).  A nested solve with
        at least H harmonics (the bar's own resolution: ``harmonics``, or the rung chosen to ``tol``) on its own
        samples (``n_t`` and ``rtol`` are not used: Newton converges to rounding), truncated to H; derivatives by the
        implicit function theorem (exact for the discrete model).  FloatingPointError where the nested solve fails
        (the solver's continuation shortens its step).  Even coefficients of rounding size (``EVEN_ROUNDING``): the
        odd basis (``truncated``), where ``even_block=False`` (``even_block_optional``) leaves the even-even block of
        dF/dX 0 instead of its elimination on the even harmonics; a fixed rung's answers are kept by their exact
        motion and frequency (``ForceMemo``).
        """
        return self._answer(X, omega, even_block)[:3]

    def _harmonic_force_deferred(self, X: NDArray[np.float64], omega: float, n_t: int, rtol: float) -> tuple:
        """``_harmonic_force(..., even_block=False)`` and how to fill its even-even block later
        (``ContactElement.harmonic_force_deferred``): where this call solved in the odd basis, from what is
        kept of its solution (``EvenBlockLater``: one evaluation and one elimination, no nested Newton
        solve); where it answered from the memo, by asking again whole (``AskedWhole``); None where the
        answer is whole (X with even harmonics)."""
        F, J, dw, later = self._answer(X, omega, False)
        return F, J, dw, (AskedWhole(self, X, omega, n_t, rtol) if later is True else later)

    def _answer(self, X: NDArray[np.float64], omega: float, even_block: bool) -> tuple:
        """``(F, dF/dX, dF/domega, later)`` of ``_harmonic_force``; ``later``: None where dF/dX is whole, an
        ``EvenBlockLater`` where its even block was left out of a solve, True where it was left out of an
        answer from the memo (which keeps no solution)."""
        odd = is_odd(X, EVEN_ROUNDING)
        even_block = even_block or not odd
        key = ForceMemo.key(X, omega, max((X.size - 1) // 2, self.harmonics), odd, even_block) if self._fixed else None
        if key is not None and (kept := self._memo.get(key, X.size)) is not None:
            return (*truncated(kept, X, odd), None if even_block else True)
        sol, short = self._resolved(X, float(omega), odd)
        if not sol.success:  # numerical trouble, not bad input: a continuation shrinks its step on it
            raise FloatingPointError(f"AllModeMicroslip: {sol.message} (omega={omega!r}, X={X!r})")
        self._warn([short] if short else [])
        level = self._level(sol.cells, sol.H)
        if odd and even_block:
            level.even_block(sol)
        force = (sol.F, sol.dF_dX, sol.dF_domega)
        if key is not None:  # kept for an estimate's Newton step at 2H + 1 harmonics too
            self._memo.put(key, force, 2 * X.size + 1)
        return (*truncated(force, X, odd), None if even_block else EvenBlockLater(level, sol))

    even_block_optional = True  # harmonic_force_unchecked(..., even_block=False) passes even_block on to the hook

    def _periodic_force(self, x, omega):
        """The time law the multi-harmonic contract asks for (``periodic_force``): the steady end
        force for the sampled periodic end displacement ``x`` (n samples over one period), through
        the harmonics the samples carry (H = (n - 2) // 2): f = E F(P x), df/dx = E (dF/dX) P."""
        n = x.size
        H = max(1, (n - 2) // 2)
        E, P, _ = aft_matrices(H, n)
        F, J, _ = self._harmonic_force(P @ x, float(omega), n, DEFAULT_RTOL)
        return E @ F, E @ J @ P

    def stick_slip_map(self, a: float, omega: float = 0.0) -> tuple[NDArray[np.float64], NDArray[np.float64],
                                                                        NDArray[np.bool_]]:
        """``(theta, x, slip)``: where the bar slips over one cycle of ``a sin(theta)`` (``a`` in m,
        ``omega`` in rad/s): ``slip[i, k]`` is True when node ``x[i]`` (m) slips at
        ``theta[k] = 2 pi k / n_t`` (the return map clipped there; the mesh and n_t of the
        solution).  Draws like the paper's Figs. 6-7 for any number of stick and slip regions
        (docs/validation.md, wavy load)."""
        sol = self.solve(a, omega)
        n_t = sol.slip.shape[1]
        return 2.0 * np.pi * np.arange(n_t) / n_t, np.linspace(0.0, self.bar.L, sol.cells + 1), sol.slip

    # ------------------------------------------------------------ levels and the choice
    def _level(self, cells: int, H: int) -> FixedBar:
        key = (cells, H)
        if key not in self._levels:
            n_t = _samples(H) if self.n_t is None else scaled_samples(self.n_t, self.harmonics, H)
            self._levels[key] = FixedBar(self.bar, self.load, cells, H, n_t, self.linear)
        return self._levels[key]

    def _solve(self, X, omega, H, odd=False) -> AllModeSolution:
        """Steady state for the full-layout X (2H+1) at omega on the fixed mesh (or the last one used)."""
        return self._level(self.cells or (self._last[0] if self._last else CELLS), H).solve(X, omega, odd)

    def _floor(self, X) -> float:
        a = math.hypot(X[1], X[2]) if X.size >= 3 else 0.0
        return FLOOR * self.bar.k_star * (a if a > 0.0 else float(np.max(np.abs(X))))

    def _resolved(self, X, omega, odd, derivatives=True):
        """``(solution, shortfall)`` for the full-layout X at omega: on the fixed mesh and harmonics (no estimate;
        without ``derivatives``, none), or on the rungs chosen to ``tol``."""
        if self._fixed:
            H = max((X.size - 1) // 2, self.harmonics)
            return self._level(self.cells, H).solve(pad_harmonics(X, H), omega, odd, None, derivatives), None
        return self._choose(X, omega, odd)

    def _first_rung(self, omega, Hx):
        """Where the ladder starts: the given cells/harmonics, else the previous call's rung, one rung
        lower in cells (harmonics) where the previous parts predict that rung within half the
        tolerance (a cells part 4 times, a harmonics part 8 times larger), never below the start
        tied to the wavelength and never below the caller's harmonics."""
        last_n, last_H, rel_c, rel_h = self._last if self._last else (0, 0, math.inf, math.inf)
        H = self.harmonics
        if H is None:
            H = next((h for h in HARMONIC_LADDER if h >= max(Hx, last_H)), max(Hx, MAX_HARMONICS))
            lower = [h for h in HARMONIC_LADDER if max(Hx, 1) <= h < H]
            if lower and rel_c + 8.0 * rel_h <= 0.5 * self.tol:
                H = lower[-1]
        H = max(H, Hx)
        n = self.cells
        if n is None:
            n = last_n // 2 if 4.0 * rel_c + rel_h <= 0.5 * self.tol else last_n
            n = min(MAX_CELLS, max(start_cells(self.bar, omega, H), n))
        return n, H

    def _choose(self, X, omega, odd):
        """Climb the ladder (cells doubling, harmonics up the rungs: the larger part of the estimate
        first) until the relative estimate is below ``tol`` or the ladder ends: ``(solution,
        shortfall)``, shortfall None or ``(omega, a, relative estimate, rungs tried)``."""
        n, H = self._first_rung(omega, (X.size - 1) // 2)
        floor = self._floor(X)
        a = floor / (FLOOR * self.bar.k_star)
        tried = []
        while True:
            sol = self._level(n, H).solve(pad_harmonics(X, H), omega, odd)
            if not sol.success:
                return sol, None
            reused = self._reused(a, omega, odd, n, H)
            parts = reused or self._parts(X, omega, odd, sol)
            rel = self._fill(sol, parts, floor)
            tried.append((n, H, rel))
            if rel <= self.tol:
                break
            rel_c, rel_h = (relative(parts[k], sol.F[1:3], floor) for k in ("cells", "harmonics"))
            can_n = self.cells is None and n < MAX_CELLS
            up = [h for h in HARMONIC_LADDER if h > H] if self.harmonics is None else []
            if (self.cells and rel_c > self.tol) or (self.harmonics and rel_h > self.tol):
                break  # the part given by the caller misses tol alone (the other cannot mend it)
            if not up and rel_h > self.tol and rel_c <= 0.5 * self.tol:
                break  # H at the top and the cells resolved: more cells do not mend the harmonics
            if can_n and (rel_c >= rel_h or not up):
                n = min(2 * n, MAX_CELLS)
            elif up:
                H = up[0]
                if self.cells is None:  # at least the fewest cells that hold its wavelength (the mesh chosen for
                    n = min(MAX_CELLS, max(n, cells_for_phase(self.bar, omega, H)))  # the lower one: UnresolvedWave)
            else:
                break
        self._last = (n, H, *(relative(parts[k], sol.F[1:3], floor) for k in ("cells", "harmonics")))
        if reused is None:
            self._reuse = (a, omega, odd, n, H, parts, sol.relative_error)
        short = None if sol.relative_error <= self.tol else (omega, a, sol.relative_error, tried)
        return sol, short

    def _reused(self, a, omega, odd, n, H):
        """The parts of the last estimate, scaled to ``a``, if it was made close by on these rungs and
        was below half the tolerance; else None."""
        r = self._reuse
        if (r is None or r[2:5] != (odd, n, H) or r[6] > 0.5 * self.tol or abs(a - r[0]) > REUSE_AMPLITUDE * r[0]
                or abs(omega - r[1]) > REUSE_FREQUENCY * r[1]):
            return None
        return {k: v * (a / r[0]) for k, v in r[5].items()}

    def _fill(self, sol, parts, floor) -> float:
        total = parts["cells"] + parts["harmonics"]
        sol.error_parts = {k: float(np.max(v)) for k, v in parts.items()}
        sol.error_components = total
        sol.error = float(np.max(total))
        sol.relative_error = relative(total, sol.F[1:3], floor)
        return sol.relative_error

    def _parts(self, X, omega, odd, sol):
        """The estimate's parts (N, on (F_c, F_s)): in cells ``cells_error`` (against the rung above
        below 128 cells, else from n/4, n/2, n), in harmonics ``harmonics_error`` (against the rung above
        below 15 harmonics, else from about H/4, H/2, H; never below the drive's harmonics)."""
        n, H, Hx = sol.cells, sol.H, (X.size - 1) // 2
        F = sol.F[1:3]

        def at(cells, h):
            try:
                s = self._level(cells, h).solve(pad_harmonics(X, h), omega, odd, transferred(sol.U, cells, h), False)
            except UnresolvedWave:  # too few exact cells for this rung's highest harmonic: left out
                return None
            return s.F[1:3] if s.success else np.full(2, np.nan)

        alone = np.full(2, sol.decay * math.hypot(*F))
        return {"cells": cells_error(n, F, lambda c: at(c, H)),
                "harmonics": harmonics_error(H, Hx, F, lambda h: at(n, h), alone)}

    def _warn(self, shortfalls) -> None:
        """One AccuracyWarning for the worst point of a call that missed ``tol``."""
        if shortfalls:
            cells = f"up to {MAX_CELLS}" if self.cells is None else "as given"
            warnings.warn(shortfall_message(shortfalls, self.tol, cells, f"up to {MAX_HARMONICS}"
                                            if self.harmonics is None else "as given"), AccuracyWarning, stacklevel=4)

    # ------------------------------------------------------------ the stuck bar
    def _disc(self, cells: int) -> _Discretisation:
        if cells not in self._discs:
            self._discs[cells] = _Discretisation(self.bar, self.load, cells)
        return self._discs[cells]

    def _stuck_data(self, omega: float):
        """``(cells, K, a_min, relative estimate of K)`` of the stuck bar at omega
        (``accuracy.stuck_data``)."""
        if omega not in self._stuck:
            if len(self._stuck) > 512:
                self._stuck.clear()
            self._stuck[omega] = stuck_data(self.bar, self._disc, omega, self.cells or start_cells(self.bar, omega, 1),
                                            self.cells is not None, self.tol, self.linear, MAX_CELLS)
        return self._stuck[omega]

    # ------------------------------------------------------------ interface
    def _stuck_stiffness(self, omega):
        return self._stuck_data(float(omega))[1]

    def _slip_amplitude(self, omega):
        return self._stuck_data(float(omega))[2]

    def _model_error(self, a, omega):
        """The pair ``(e_s, e_c)``: the relative estimates of the discretisation error of f_s and of
        f_c, each relative to max(|f|, 0.01 k* a) of its own component: of the stuck stiffness below
        slip (f_c = 0 exactly there), else of the solution this element gives (the rungs it chooses,
        or the fixed ones with their estimate).  A fixed rung records each estimate's parts
        (``refined_rung``).  Many points: on two threads where they pay (``estimate``)."""
        return model_errors(self, a, omega)

    def _fourier_derivatives(self, a, omega, rtol):
        fs, fc, dfs, dfc = (np.zeros_like(a) for _ in range(4))
        short = []
        for w in np.unique(omega):
            sel = np.flatnonzero(omega == w)
            sel = sel[np.argsort(a[sel])]
            _, K, a_lin, _ = self._stuck_data(float(w))
            for i in sel:
                if a[i] <= a_lin:
                    fs[i], dfs[i] = K * a[i], K
                    continue
                sol, s = self._resolved(np.array([0.0, 0.0, a[i]]), float(w), True)
                if not sol.success:
                    raise FloatingPointError(f"AllModeMicroslip: {sol.message} at a={a[i]!r}, omega={w!r}")
                if s:
                    short.append(s)
                fs[i], fc[i] = sol.f_s, sol.f_c
                dfs[i], dfc[i] = sol.dF_dX[2, 2], sol.dF_dX[1, 2]
        self._warn(short)
        return fs, fc, dfs, dfc

    def _hysteresis(self, a, omega, n):
        theta = np.linspace(-0.5 * np.pi, 1.5 * np.pi, n)
        x = a * np.sin(theta)
        if a <= self._slip_amplitude(omega):
            return x, self._stuck_stiffness(omega) * x
        sol = self.solve(a, omega)
        return x, self._level(sol.cells, sol.H).end_force(sol, theta, x)
