"""The all-mode microslip bar with normal motion: the normal load varies with the motion and may
vanish over part of the bar (partial separation).

``AllModeMicroslip2D`` is the bar of ``AllModeMicroslip`` (n equal cells, lumped mass, node i a
Jenkins element of stiffness k c_i, the beta spring at node 0, node n driven) whose nodal normal
load follows a normal displacement v(x, t) given by the structure,

    N_i(t) = max(0, q(x_i) c_i + kn c_i v(x_i, t)),     slip limit mu N_i(t),
    v(x, t) = s(x) v(t),   s(x) = s_0 + (s_L - s_0) x / L   (``normal_shape = (s_0, s_L)``),

with kn the normal contact stiffness per unit length (N/m^2) and v > 0 pressing.  The default shape
(1, 1) is a uniform normal motion; another shape is a rocking damper whose two ends move by
v_0 = s_0 v and v_L = s_L v.  Each node is exactly a ``Contact2D`` point contact (stick, slip,
separation with the spring unloaded on re-contact); the bar is solved by harmonic balance with
AFT at the nodes and Newton, as ``AllModeMicroslip`` (``contact_models.allmode.normal``).

Two components (``components = 2``, like ``Contact2D``): the input is the tangential end
displacement and the normal displacement v, the output the tangential end force EA u_x(L) and the
normal force conjugate to v, F_N(t) = sum_i s_i N_i(t) (for uniform motion the total normal
reaction, the integral of the clipped normal load).  ``hbm.Contact(el, dof=t, normal_dof=n)``
attaches it, v the displacement of DOF n (``normal_dofs=(k, l)``: v = x_k - x_l, as for
``Contact2D``).  Derivation and evidence: ``docs/contacts_normal.md``, "The all-mode bar with
normal motion".
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..bar import Bar
from ..base import ContactElement
from ..loads import bound_load
from ..numerics.checks import count, finite, flag, nonnegative
from .accuracy import FLOOR, ladder, relative
from .balance import aft_matrices
from .element import AllModeMicroslip
from .normal import NormalBar, NormalSolution
from .solve import checked_mesh

if TYPE_CHECKING:
    from ..loads import QuadraticLoad, UniformLoad

__all__ = ["AllModeMicroslip2D", "NormalSolution", "CELLS_2D", "HARMONICS_2D", "SAMPLES_PER_HARMONIC_2D"]

#: Default cells of the bar with normal motion (fixed; no choice per call).
CELLS_2D = 20
#: Default harmonics of every node's motion.
HARMONICS_2D = 15
#: Default AFT samples per harmonic (n_t = 16 H rounded up to a multiple of 4): separation makes
#: the sampled return map first order in 1/n_t at re-contact (docs/contacts_normal.md).
SAMPLES_PER_HARMONIC_2D = 16


def _coefficients(name: str, value: ArrayLike, H: int) -> NDArray[np.float64]:
    arr = np.asarray(value, dtype=float)
    if arr.ndim != 1 or arr.size % 2 == 0 or arr.size > 2 * H + 1 or not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be a finite coefficient vector of odd length <= {2 * H + 1}, got {name}={value!r}")
    return np.pad(arr, (0, 2 * H + 1 - arr.size))


class AllModeMicroslip2D(ContactElement):
    """Microslip bar with every mode under a normal load that follows a normal motion.

    Parameters
    ----------
    bar : Bar
        The damper bar.
    load : UniformLoad, QuadraticLoad, FunctionLoad or SampledLoad
        Normal load q(x) >= 0 at rest (v = 0): the preload.
    kn : float
        Normal contact stiffness per unit length (N/m^2), >= 0 and finite (0: the load stays q).
    cells : int
        Linear finite elements along the bar, >= 2 (default ``CELLS_2D`` = 20; fixed).
    harmonics : int
        Harmonics H of every node's motion, >= 1 (default ``HARMONICS_2D`` = 15; fixed).
    n_t : int, optional
        AFT samples per period, a multiple of 4 and >= 2H + 2 (default 16 H rounded up).
    normal_shape : tuple of two floats
        ``(s_0, s_L)``: v(x, t) = (s_0 + (s_L - s_0) x/L) v(t); default (1, 1), uniform.

    Raises
    ------
    ValueError
        ``bar`` not a ``Bar``, a load below 0, or a parameter out of range (named with its value).

    Notes
    -----
    ``components = 2``: :meth:`periodic_force` takes ``x`` of shape (2, n_t) (tangential end
    displacement, normal displacement v) and returns the forces (2, n_t) (tangential end force,
    normal force sum_i s_i N_i) with their Jacobian (2 n_t, 2 n_t); :meth:`harmonic_force` takes
    ``X`` (2, 2H+1).  With v = 0 it is ``AllModeMicroslip`` on the same cells and harmonics, which
    :meth:`fourier` answers (the normal at rest).  Cells and harmonics are fixed; ``solve(...,
    estimate_error=True)`` estimates their error by Richardson extrapolation.  A node stuck all
    period takes the midpoint of its admissible slider positions (``Contact2D``'s convention).

    Examples
    --------
    >>> import numpy as np
    >>> from contact_models import AllModeMicroslip2D, Bar, UniformLoad
    >>> bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    >>> el = AllModeMicroslip2D(bar, UniformLoad(N=100.0), kn=2.0e9, cells=10, harmonics=7)
    >>> sol = el.solve(3 * 7.5e-7, [0.0, 5.0e-7, 0.0], 0.5 * bar.omega_c)  # v = 0.5 um cos
    >>> sol.success, round(float(sol.FN[0]), 6), round(float(sol.FN[1]), 6)  # N = 100 (1 + 0.5 cos)
    (True, 100.0, 50.0)
    """

    has_time_law = True
    components = 2

    def __init__(self, bar: Bar, load: UniformLoad | QuadraticLoad, kn: float, cells: int = CELLS_2D,
                 harmonics: int = HARMONICS_2D, *, n_t: int | None = None,
                 normal_shape: tuple[float, float] = (1.0, 1.0)) -> None:
        if not isinstance(bar, Bar):
            raise ValueError(f"bar must be a contact_models.Bar, got bar={bar!r}")
        self.kn = nonnegative("kn", kn)
        self.cells = count("cells", cells, 2)
        self.harmonics = count("harmonics", harmonics, 1)
        if n_t is None:
            n_t = 4 * math.ceil(SAMPLES_PER_HARMONIC_2D * self.harmonics / 4)
        if isinstance(n_t, bool) or not isinstance(n_t, (int, np.integer)) or n_t % 4 or n_t < 2 * self.harmonics + 2:
            raise ValueError(f"n_t must be a multiple of 4 and >= 2 harmonics + 2 = {2 * self.harmonics + 2}, "
                             f"got n_t={n_t!r}")
        self.n_t = int(n_t)
        checked_mesh(self.cells, self.harmonics, self.n_t, f"cells={cells!r}, harmonics={harmonics!r}, n_t={n_t!r}")
        try:
            s0, sL = normal_shape
        except (TypeError, ValueError):
            raise ValueError(f"normal_shape must be a pair (s_0, s_L), got normal_shape={normal_shape!r}") from None
        self.normal_shape = (finite("normal_shape[0]", s0), finite("normal_shape[1]", sL))
        self.bar = bar
        self.load = bound_load(load, bar.L)
        # the normal at rest: the bar of AllModeMicroslip on the same cells and harmonics
        self.at_rest = AllModeMicroslip(bar, load, self.cells, self.harmonics, n_t=self.n_t, linear="lumped")
        self._levels: dict = {}

    def __repr__(self) -> str:
        return (f"AllModeMicroslip2D({self.bar!r}, {self.load!r}, kn={self.kn!r}, cells={self.cells}, "
                f"harmonics={self.harmonics}, n_t={self.n_t}, normal_shape={self.normal_shape})")

    def _level(self, cells: int, H: int, n_t: int) -> NormalBar:
        key = (cells, H, n_t)
        if key not in self._levels:
            self._levels[key] = NormalBar(self.bar, self.load, self.kn, self.normal_shape, cells, H, n_t)
        return self._levels[key]

    @property
    def nodes(self) -> NDArray[np.float64]:
        """Node positions x_i (m)."""
        return np.linspace(0.0, self.bar.L, self.cells + 1)

    def solve(self, a: float | ArrayLike, v: ArrayLike | None = None, omega: float = 0.0, *,
              estimate_error: bool = False) -> NormalSolution:
        """Steady periodic state of the bar for a driven-end displacement and a normal motion.

        Parameters
        ----------
        a : float or array_like
            An amplitude (m) for ``a sin(theta)``, or end-displacement coefficients (m) of odd
            length <= 2 ``harmonics`` + 1, layout ``[X0, Xc1, Xs1, ...]``.
        v : array_like, optional
            Coefficients (m) of the normal displacement v(t), same layout; default None: v = 0.
        omega : float
            Frequency (rad/s), >= 0.
        estimate_error : bool
            Also solve on cells n/4, n/2 (harmonics about H/4, H/2; samples n_t/4, n_t/2) and fill
            ``error``, ``relative_error`` and ``error_parts`` (``"cells"``, ``"harmonics"``,
            ``"samples"``) by Richardson extrapolation with the observed order.  Default False.

        Returns
        -------
        NormalSolution
            ``F`` (tangential end force), ``FN`` (normal force), the derivatives in X, V and
            omega, nodal coefficients, slip and separation maps, ``success``, ``message``.

        Raises
        ------
        ValueError
            ``a``, ``v`` or ``omega`` out of range (named).
        """
        estimate_error = flag("estimate_error", estimate_error)
        omega = nonnegative("omega", omega)
        H = self.harmonics
        if np.ndim(a) == 0:
            X = np.zeros(2 * H + 1)
            X[2] = nonnegative("a", a)
        else:
            X = _coefficients("a", a, H)
        V = np.zeros(2 * H + 1) if v is None else _coefficients("v", v, H)
        sol = self._level(self.cells, H, self.n_t).solve_normal(X, V, omega)
        if estimate_error and sol.success:
            self._estimate(sol, X, V, omega)
        return sol

    def _estimate(self, sol: NormalSolution, X, V, omega) -> None:
        """Richardson in cells (n/4, n/2, n), harmonics (H/4, H/2, H rungs) and samples (n_t/4, n_t/2,
        n_t, never below 2H + 2), each with the others at the given level; the parts add."""
        n, H, nt = self.cells, self.harmonics, self.n_t
        F = sol.F[1:3]
        hs = [max(1, (H - 1) // 4), max(1, (H - 1) // 2), H]
        rungs = {"cells": [(c, H, nt) for c in (n // 4, n // 2, n)],
                 "harmonics": [(n, h, nt) for h in hs],
                 "samples": [(n, H, m) for m in (nt // 4, nt // 2, nt)]}
        parts = {}
        for key, levels in rungs.items():
            ok = [lv for lv in levels if lv[0] >= 2 and lv[2] >= 2 * lv[1] + 2 and lv[2] % 4 == 0]
            vals = []
            for c, h, m in ok[:-1]:
                s = self._level(c, h, m).solve_normal(X[:2 * h + 1], V[:2 * h + 1], omega)
                vals.append(s.F[1:3] if s.success else np.full(2, np.nan))
            vals.append(F)
            res = [lv[{"cells": 0, "harmonics": 1, "samples": 2}[key]] for lv in ok]
            parts[key] = ladder(tuple(res), vals, np.full(2, np.inf))
        total = sum(parts.values())
        a = math.hypot(X[1], X[2]) or float(np.max(np.abs(X)))
        sol.error_parts = {k: float(np.max(v)) for k, v in parts.items()}
        sol.error = float(np.max(total))
        sol.relative_error = relative(total, F, FLOOR * self.bar.k_star * a)

    # ------------------------------------------------------------ the multi-harmonic hooks
    def _harmonic_force(self, X, omega, n_t, rtol):
        """``F`` (2, 2H+1): tangential and normal force coefficients, ``dF/dX`` (2(2H+1), 2(2H+1))
        and ``dF/domega`` (2, 2H+1) for ``X`` (2, 2H+1) (tangential end, normal) at ``omega``.  The
        bar is solved with max(H, ``harmonics``) harmonics and its own ``n_t`` (the caller's n_t
        and rtol are accepted and not used) and truncated to H.  Raises FloatingPointError when
        the nested solve fails (a continuation then shortens its step)."""
        L = X.shape[1]
        H = max((L - 1) // 2, self.harmonics)
        nt = self.n_t if H == self.harmonics else 4 * math.ceil(SAMPLES_PER_HARMONIC_2D * H / 4)
        pad = lambda r: np.pad(r, (0, 2 * H + 1 - L))  # noqa: E731
        sol = self._level(self.cells, H, nt).solve_normal(pad(X[0]), pad(X[1]), float(omega))
        if not sol.success:
            raise FloatingPointError(f"AllModeMicroslip2D: {sol.message} (omega={omega!r}, X={X!r})")
        F = np.vstack([sol.F[:L], sol.FN[:L]])
        J = np.zeros((2 * L, 2 * L))
        J[:L, :L] = sol.dF_dX[:L, :L]
        J[:L, L:] = sol.dF_dV[:L, :L]
        J[L:, L:] = sol.dFN_dV[:L, :L]
        Fw = np.zeros((2, L))
        Fw[0] = sol.dF_domega[:L]
        return F, J, Fw

    def _periodic_force(self, x, omega):
        """The time law the multi-harmonic contract asks for: the steady forces (2, n) for the sampled
        periodic motion ``x`` (2, n) through the harmonics the samples carry (H = (n - 2) // 2):
        f = E F(P x), df/dx = (E dF/dX P) blockwise."""
        n = x.shape[1]
        H = max(1, (n - 2) // 2)
        E, P, _ = aft_matrices(H, n)
        F, J, _ = self._harmonic_force(x @ P.T, float(omega), n, 1e-6)
        L = 2 * H + 1
        Jt = np.zeros((2 * n, 2 * n))
        for a in range(2):
            for b in range(2):
                Jt[a * n:(a + 1) * n, b * n:(b + 1) * n] = E @ J[a * L:(a + 1) * L, b * L:(b + 1) * L] @ P
        return F @ E.T, Jt

    # ------------------------------------------------------------ the normal at rest (AllModeMicroslip)
    def _fourier_derivatives(self, a, omega, rtol):
        return self.at_rest._fourier_derivatives(a, omega, rtol)

    def _stuck_stiffness(self, omega):
        return self.at_rest._stuck_stiffness(omega)

    def _slip_amplitude(self, omega):
        return self.at_rest._slip_amplitude(omega)

    def _hysteresis(self, a, omega, n):
        return self.at_rest._hysteresis(a, omega, n)
