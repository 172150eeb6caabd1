"""A point contact with tangential and normal motion: Jenkins friction under a varying normal load.

Two relative displacements at the contact point: tangential ``u`` and normal ``v`` (``v > 0``
presses the surfaces together).  The normal force is a unilateral spring with preload ``n0``,

    N = max(0, n0 + kn v),

zero when the contact separates.  Tangentially a spring ``kt`` in series with a Coulomb slider at
``w`` (a Jenkins element) carries ``T = kt (u - w)`` with ``|T| <= mu N(t)``; while separated the
spring is unloaded (``T = 0``, the slider follows ``u``), so on re-contact the tangential force
restarts from 0.  The element's force is the pair ``(T, N)``, acting on the tangential and the
normal DOF(s) as a restoring force.  Derivations, conventions and evidence:
``docs/contacts_normal.md``.

**Time law** (``periodic_force``; ``x`` has shape (2, n_t): the tangential row, the normal row).
The return map on the samples: with ``L_k = mu N_k``, the trial force ``T* = kt (u_k - w)``
sticks if ``|T*| < L_k``, else slips, ``T_k = L_k sign(T*)``, ``w = u_k - T_k/kt`` (the limit at
the new sample; at ``L_k = 0`` it is separation, ``T_k = 0``).  For constant ``N`` it is the exact
map of the Jenkins element for a path monotone between samples (``Macroslip.step``); for varying
``N`` it is the backward-Euler return map of the continuous law, to which it converges as O(1/n_t).

**Periodic state.** The slider positions ``w`` for which nothing slips over the period form the
interval ``[max_k(u_k - L_k/kt), min_k(u_k + L_k/kt)]``.  If it is not empty the periodic states
are that whole family (a stuck slider keeps any admissible position); the element takes its
midpoint, the centred state of the library's Masing elements (``contact_models.numerics.masing``:
for constant ``N`` it is ``w = (max u + min u)/2``, exactly Macroslip's).  If it is empty, the
element slips (or separates) in every period, and the period map ``w -> P(w)`` is monotone with
slope 0 wherever a slip occurs (the slip sets ``w`` whatever it was) and slope 1 only on stuck
states; on an empty stuck interval it is a monotone step function, so iterating it from any
``w`` reaches its fixed point exactly in finitely many periods (in practice one or two).  Each
sample then belongs to the last slip sample before it (cyclically), and the force and its
Jacobian follow in closed form from that origin (``T_k = kt (u_k - u_r) + s_r L_r`` while stuck
since the slip at ``r``, ``s_r`` its direction).

**Describing function** (``fourier``, H = 1): the tangential first harmonic with the normal DOF at
rest (``N = n0``), which is the Jenkins element ``Macroslip(kt, mu n0)``.  With normal motion the
load varies and no closed form is offered: ``exact_describing_function`` is False and the
balance answers through AFT at every H.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .base import ContactElement
from .macroslip import jenkins_fourier
from .numerics.checks import derived, finite, finite_array, nonnegative, positive
from .numerics.masing import masing_loop

#: Periods of the period map tried before giving up on a fixed point (finite in theory: two suffice
#: for every path tried; the bound only guards against a pathological path).
MAX_PERIODS = 200


def slip_origins(u: NDArray, lim: NDArray, kt: float) -> tuple[NDArray, NDArray, NDArray] | None:
    """The periodic slip pattern of the sampled return map, or None when a stuck state exists.

    Returns ``(T, origin, sgn)``: the tangential force samples, for each sample the last slip
    sample at or before it (cyclically) and the slip directions (+1, -1, or 0 at a sample that
    does not slip; separation slips with ``T = 0``).
    """
    n = u.size
    lo, hi = float(np.max(u - lim / kt)), float(np.min(u + lim / kt))
    if lo <= hi:
        return None
    w = 0.5 * (lo + hi)
    for _ in range(MAX_PERIODS):
        w_start = w
        T = np.empty(n)
        sgn = np.zeros(n)
        for k in range(n):
            trial = kt * (u[k] - w)
            if abs(trial) >= lim[k]:
                s = math.copysign(1.0, trial)
                T[k], sgn[k] = s * lim[k], s
                w = u[k] - T[k] / kt
            else:
                T[k] = trial
        if w == w_start:
            slips = np.flatnonzero(sgn != 0.0)
            last = np.searchsorted(slips, np.arange(n), side="right") - 1
            return T, slips[last], sgn  # last = -1 takes the period's last slip (cyclic)
    raise RuntimeError(f"no periodic state of the return map after {MAX_PERIODS} periods")


class PointContactLaw(ContactElement):
    """What ``Contact2D`` and ``Contact3D`` share: the parameters ``(kt, kn, mu, n0)`` and their checks,
    the unilateral normal spring ``N = max(0, n0 + kn v)``, and the first-harmonic answers with the normal
    DOF at rest, which are the Jenkins element ``Macroslip(kt, mu n0)``'s (module docstring).  The time law,
    the periodic state and its Jacobian are each subclass's own."""

    frequency_dependent = False

    def __init__(self, kt: float, kn: float, mu: float, n0: float) -> None:
        self.kt = positive("kt", kt)
        self.kn = nonnegative("kn", kn)
        self.mu = positive("mu", mu)
        self.n0 = finite("n0", n0)
        for name in ("kt", "kn", "mu"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"{name} must be finite, got {name}={getattr(self, name)!r}")
        load = max(self.n0, 0.0)  # what the time law divides by kt (the slip amplitude and its normal slope)
        derived(type(self).__name__, dict(kt=kt, kn=kn, mu=mu, n0=n0),
                lambda: {"mu n0": self.mu * load, "mu n0/kt": self.mu * load / self.kt, "mu kn": self.mu * self.kn,
                         "mu kn/kt": self.mu * self.kn / self.kt})

    def __repr__(self) -> str:
        return f"{type(self).__name__}(kt={self.kt!r}, kn={self.kn!r}, mu={self.mu!r}, n0={self.n0!r})"

    def normal_force(self, v: ArrayLike) -> NDArray:
        """``N = max(0, n0 + kn v)`` (N) for normal displacements ``v`` (m)."""
        return np.maximum(self.n0 + self.kn * finite_array("v", v), 0.0)

    def _fourier_derivatives(self, a, omega, rtol):
        if self.n0 <= 0.0:  # open at rest: no tangential force
            zero = np.zeros_like(a)
            return zero, zero.copy(), zero.copy(), zero.copy()
        return jenkins_fourier(self.kt, self.mu * self.n0 / self.kt, a)

    def _stuck_stiffness(self, omega):
        return self.kt if self.n0 > 0.0 else 0.0

    def _slip_amplitude(self, omega):
        return self.mu * max(self.n0, 0.0) / self.kt

    def _linear_amplitude(self, omega):
        return 0.0

    def _reference_amplitude(self, omega):
        return self.mu * abs(self.n0) / self.kt if self.n0 != 0.0 else 1.0

    def _hysteresis(self, a, omega, n):
        slip = self.mu * max(self.n0, 0.0)
        return masing_loop(lambda x: np.minimum(self.kt * x, slip), a, n)


class Contact2D(PointContactLaw):
    """Point contact: tangential Jenkins friction with the normal load ``N = max(0, n0 + kn v)``.

    Parameters
    ----------
    kt : float
        Tangential contact stiffness (N/m), > 0 and finite.
    kn : float
        Normal contact stiffness (N/m), >= 0 and finite (0: the load stays ``n0``).
    mu : float
        Friction coefficient, > 0 and finite.
    n0 : float
        Normal preload (N) at zero normal displacement, finite; <= 0 is a contact open at rest.

    Raises
    ------
    ValueError
        For a parameter out of range, naming it and its value, or parameters whose slip force ``mu n0``,
        slip amplitude ``mu n0 / kt`` or their normal slopes overflow double precision.

    Notes
    -----
    ``components = 2``: :meth:`periodic_force` takes ``x`` of shape (2, n_t) (tangential row,
    normal row) and returns the forces (2, n_t) with the Jacobian (2 n_t, 2 n_t);
    :meth:`harmonic_force` takes ``X`` (2, 2H+1).  ``hbm.Contact(el, dof=t, normal_dof=n)``
    attaches it.  :meth:`fourier` is the Jenkins element at the load ``n0`` (module docstring).

    Examples
    --------
    >>> import numpy as np
    >>> from contact_models import Contact2D
    >>> c = Contact2D(kt=1.0, kn=2.0, mu=0.5, n0=1.0)
    >>> theta = np.arange(8) * np.pi / 4
    >>> f, J = c.periodic_force(np.vstack([np.cos(theta), np.zeros(8)]))  # N = 1: Macroslip(1, 0.5)
    >>> np.round(f[0], 3).tolist()
    [0.5, 0.207, -0.5, -0.5, -0.5, -0.207, 0.5, 0.5]
    """

    has_time_law = True
    components = 2

    def _periodic_force(self, x, omega):
        f, rows, cols, vals = self._periodic_entries(x, omega)
        J = np.zeros((f.size, f.size))
        np.add.at(J, (rows, cols), vals)
        return f, J

    def _periodic_entries(self, x, omega):
        """Forces (2, n) and the Jacobian's entries ``(rows, cols, vals)`` (indices into the
        flattened samples: tangential 0..n-1, normal n..2n-1; repeated entries add)."""
        u, v = x
        n = u.size
        kt = self.kt
        p = self.n0 + self.kn * v
        N = np.maximum(p, 0.0)
        dN = np.where(p > 0.0, self.kn, 0.0)
        lim, dlim = self.mu * N, self.mu * dN
        k = np.arange(n)
        found = slip_origins(u, lim, kt)
        if found is None:  # stuck all period: the midpoint of the admissible slider positions
            i, j, w = stuck_midpoint(u, lim, kt)
            ii, jj, half = np.full(n, i), np.full(n, j), np.full(n, 0.5)
            rows = np.concatenate([k, k, k, k, k, n + k])
            cols = np.concatenate([k, ii, jj, n + ii, n + jj, n + k])
            vals = np.concatenate([np.full(n, kt), -half * kt, -half * kt, half * dlim[i], -half * dlim[j], dN])
            return np.vstack([kt * (u - w), N]), rows, cols, vals
        T, r, sgn = found
        ks = k[sgn == 0.0]
        rows = np.concatenate([ks, ks, k, n + k])
        cols = np.concatenate([ks, r[ks], n + r, n + k])
        vals = np.concatenate([np.full(ks.size, kt), np.full(ks.size, -kt), sgn[r] * dlim[r], dN])
        return np.vstack([T, N]), rows, cols, vals



def stuck_midpoint(u: NDArray, lim: NDArray, kt: float) -> tuple[int, int, float]:
    """``(i, j, w)`` of a contact stuck all period: its slider at the midpoint ``w`` of the admissible
    positions, ``((u_i - lim_i/kt) + (u_j + lim_j/kt)) / 2`` with ``i`` the argmax of ``u - lim/kt``
    and ``j`` the argmin of ``u + lim/kt`` (for a constant limit the centre of the motion)."""
    i, j = int(np.argmax(u - lim / kt)), int(np.argmin(u + lim / kt))
    return i, j, 0.5 * ((u[i] - lim[i] / kt) + (u[j] + lim[j] / kt))


__all__ = ["Contact2D", "PointContactLaw", "slip_origins", "stuck_midpoint"]
