"""The all-mode bar's linear part per harmonic: exact segments between the nodes, or the lumped bar.

Between two nodes the bar is linear: while its shear layer sticks, a segment of length h is a rod on the
elastic foundation k (N/m per metre), EA u'' - k u + rho A Omega^2 u = 0 at the frequency Omega = j omega
of harmonic j.  Its end forces for the end displacements (u_l, u_r) are exact:

    f_l = (EA/h) (A(z) u_l - B(z) u_r),   f_r = (EA/h) (-B(z) u_l + A(z) u_r),
    z = q h^2,   q = (rho A Omega^2 - k) / EA,
    A(z) = sqrt(z) cot sqrt(z),   B(z) = sqrt(z) / sin sqrt(z)      (z > 0, a travelling wave),
    A(z) = s coth s,   B(z) = s / sinh s,   s = sqrt(-z)            (z < 0, an evanescent one),

both analytic in z (A = 1 - z/3 - z^2/45 - 2 z^3/945 + ..., B = 1 + z/6 + 7 z^2/360 + 31 z^3/15120 + ...;
A(0) = B(0) = 1 is the static spring EA/h).  Assembled, node i carries the diagonal (EA/h)(A_left +
A_right) (one segment at the ends, the beta spring at node 0) and neighbouring nodes couple by
c_j = -(EA/h) B(z_j), the same for every pair (equal cells).  The shear layer's Jenkins elements stay
lumped at the nodes (k c_i, mu q(x_i) c_i with trapezoid weights c_i): since the segments already hold
the foundation's springs, node i's residual carries T_i - k c_i U_i, which is zero wherever the node
sticks.  So a bar that sticks everywhere is the continuous bar itself, on any mesh; the cells resolve
only where the shear layer slips (``docs/theory.md``, "The all-mode bar's exact segments").

``kind="lumped"`` is the finite-element bar of ``NumericalMicroslip`` (linear elements, lumped mass
m_i = rho A c_i): diagonal K_ii - Omega^2 m_i (the Jenkins force carries k c_i), coupling -EA/h.

A segment resonates with both its ends held where sqrt(z) reaches pi (a cell half a wavelength of the
harmonic long): the coupling diverges there and the nodes no longer see the shear layer between them.
:func:`linear_part` refuses meshes with sqrt(z) above ``MAX_SEGMENT_PHASE``, naming the cells needed.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Callable, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..numerics.waves import MAX_SEGMENT_PHASE, UnresolvedWave, cells_for_phase

if TYPE_CHECKING:
    from ..bar import Bar
    from ..numerics.fe_bar import _Discretisation

Array = NDArray[np.float64]

#: Below this |z| the series of A, B and their derivatives are used (their omitted terms are below 1e-13).
SERIES_Z = 1e-3
KINDS = ("exact", "lumped")
#: The floor of the stuck stiffness's relative estimate, a share of k* (as the validity map's).
FLOOR_SHARE = 0.01
#: The most cells the stuck bar is built on to hold the wavelength of harmonic 1 (``exact_stuck``): a frequency
#: that asks for more is refused by name (the bar's arrays would exhaust the memory: 1e50 rad/s asked 1e45).
MAX_STUCK_CELLS = 2**22


class LinearPart(NamedTuple):
    """The bar's linear part at one frequency on coefficients of the harmonic orders ``order`` (s,): the
    diagonal ``lin`` (n + 1, s) of every node (the driven node last), the coupling ``c`` (s,) of
    neighbouring nodes, and their derivatives in omega ``dlin``, ``dc``."""

    lin: Array
    c: Array
    dlin: Array
    dc: Array


#: The series of A, B, A', B' in powers z^0..z^3 (rows), for |z| < ``SERIES_Z``.
_SERIES = np.array([[1.0, -1.0 / 3.0, -1.0 / 45.0, -2.0 / 945.0],
                    [1.0, 1.0 / 6.0, 7.0 / 360.0, 31.0 / 15120.0],
                    [-1.0 / 3.0, -2.0 / 45.0, -6.0 / 945.0, 0.0],
                    [1.0 / 6.0, 7.0 / 180.0, 93.0 / 15120.0, 0.0]])
_POWERS = np.arange(4.0)[:, None]


def segment_functions(z: Array) -> tuple[Array, Array, Array, Array]:
    """``A(z), B(z), A'(z), B'(z)`` (module docstring) for the array z (z < pi^2): one complex formula for
    both signs (sqrt(z) = i s turns cot and sin into coth and sinh), the series near z = 0.  With
    csc = 1/sin s and cot = cos s csc: A = s cot, B = s csc, A' = (cot - B csc)/(2 s), B' = (1 - A) csc/(2 s)."""
    z = np.asarray(z, dtype=float)
    small = np.abs(z) < SERIES_Z
    series = _SERIES @ (z[None, :] ** _POWERS)  # (4, m)
    if small.all():
        return series[0], series[1], series[2], series[3]
    s = np.sqrt(np.where(small, 1.0, z).astype(complex))  # the small ones' closed form is not used
    csc = 1.0 / np.sin(s)
    cot = np.cos(s) * csc
    A, B = s * cot, s * csc
    half = 0.5 / s
    out = np.where(small, series, np.array([A, B, (cot - B * csc) * half, (1.0 - A) * csc * half]).real)
    return out[0], out[1], out[2], out[3]


class Segments:
    """The :class:`LinearPart` of the bar on ``disc`` for the harmonic orders ``order`` (s,), ``kind`` "exact"
    (segments) or "lumped" (the finite-element bar), at any omega: ``at(omega)``.  What does not depend on
    omega is done once, and the segment functions once for each distinct order (a basis holds each harmonic
    twice, cos and sin)."""

    def __init__(self, bar: Bar, disc: _Discretisation, order: ArrayLike, kind: str) -> None:
        order = np.asarray(order, dtype=float)
        self.kind, self.bar, self.disc, self.order = kind, bar, disc, order
        if kind == "lumped":
            self.w2 = order[None, :] ** 2
            return
        uniq, self.inv = np.unique(order, return_inverse=True)
        h, EA = disc.h, bar.EA
        self.zq = (bar.rho * bar.A / EA * h**2) * uniq**2  # z = zq omega^2 - z0
        self.z0 = bar.k / EA * h**2
        self.dzq = (2.0 * bar.rho * bar.A / EA * h**2) * uniq**2  # dz/domega = dzq omega
        self.k = EA / h
        ends = np.full((disc.n + 1, 1), 2.0)  # two segments meet at an inner node, one at each end
        ends[0] = ends[-1] = 1.0
        self.ends = ends
        offs = -disc.kc
        offs[0] += bar.beta
        self.offs = offs[:, None]

    def at(self, omega: float) -> LinearPart:
        """The linear part at omega; ``UnresolvedWave`` where a segment's phase exceeds ``MAX_SEGMENT_PHASE``
        (too few cells for the highest harmonic)."""
        disc = self.disc
        if self.kind == "lumped":
            s = self.order.size
            lin = disc.kdiag[:, None] - omega**2 * disc.m[:, None] * self.w2
            return LinearPart(lin, np.full(s, disc.off), -2.0 * omega * disc.m[:, None] * self.w2, np.zeros(s))
        z = self.zq * omega**2 - self.z0
        if z.size and float(np.max(z)) > MAX_SEGMENT_PHASE**2:
            H = int(np.max(self.order))
            raise UnresolvedWave(f"cells={disc.n} are too few for harmonic {H} at omega={omega!r} rad/s: a cell is "
                                 f"more than 0.9 of half its wavelength; use at least "
                                 f"{cells_for_phase(self.bar, omega, H)} cells")
        A, B, dA, dB = segment_functions(z)
        k, i = self.k, self.inv
        dz = self.dzq * omega
        return LinearPart(self.ends * (k * A)[i] + self.offs, (-k * B)[i], self.ends * (k * dA * dz)[i],
                          (-k * dB * dz)[i])


def linear_part(bar: Bar, disc: _Discretisation, omega: float, order: Array, kind: str) -> LinearPart:
    """The :class:`LinearPart` of the bar on ``disc`` at omega for the harmonic orders ``order`` (module
    docstring); ``kind`` "exact" (segments) or "lumped" (the finite-element bar).  ValueError where a
    segment's phase exceeds ``MAX_SEGMENT_PHASE`` (too few cells for the highest harmonic).  At many
    frequencies, :class:`Segments` does the work that does not depend on omega once."""
    return Segments(bar, disc, order, kind).at(omega)


def stuck_end(bar: Bar, disc: _Discretisation, omega: float, kind: str) -> tuple[float, float]:
    """``(K, a_min)`` of the bar stuck everywhere at omega: the driven end's stiffness K (N/m; its force
    K a for the motion a sin) and the least end amplitude a_min at which a node's spring force k c_i |u_i|
    reaches its slip force mu q(x_i) c_i (inf where none can).  Exact (the continuous bar's, at the nodes)
    for ``kind="exact"``; the finite-element bar's for "lumped"."""
    from .balance import scalar_tridiagonal  # the Thomas solve of the whole package

    if kind == "lumped":  # the finite-element bar's own (``NumericalMicroslip`` gives the same numbers)
        return disc.stuck_solution(omega)[1], disc.slip_amplitude(omega)
    part = linear_part(bar, disc, omega, np.ones(1), kind)
    c = float(part.c[0])
    diag = part.lin[:, :1] + disc.kc[:, None]  # the stuck Jenkins elements are the springs k c_i
    u = np.append(scalar_tridiagonal(diag[:-1] / c, 1.0, -np.ones(1))[:, 0], 1.0)
    K = float(diag[-1, 0] + c * u[-2])
    with np.errstate(divide="ignore"):
        ratio = np.where(np.abs(u) > 0, disc.p / (disc.kc * np.abs(u)), np.inf)
    return K, float(np.min(ratio))


def exact_stuck(bar: Bar, disc_of: Callable[[int], _Discretisation], omega: float, n: int,
                fine: int) -> tuple[int, float, float, float]:
    """``(n, K, a_min, relative estimate of K)`` of the exact bar stuck everywhere on n cells (at least
    the fewest that hold harmonic 1): K is the continuous bar's on any mesh, so its estimate is the change
    to 2n cells (rounding); a_min is the least of n cells' nodes and of ``fine`` cells' nodes, which sample
    the load q(x) finely (the nodes of a coarse mesh can miss a pocket of low load, where slip starts)."""
    n = max(n, cells_for_phase(bar, omega, 1))
    if n > MAX_STUCK_CELLS:
        raise UnresolvedWave(f"omega={omega!r} rad/s is too high for the bar with every mode: its stuck bar needs "
                             f"{n:.3g} cells to hold the wavelength of harmonic 1, more than MAX_STUCK_CELLS = "
                             f"{MAX_STUCK_CELLS} (contact_models.allmode.segments)")
    K, a_own = stuck_end(bar, disc_of(n), omega, "exact")
    K2, _ = stuck_end(bar, disc_of(2 * n), omega, "exact")
    a_fine = stuck_end(bar, disc_of(max(fine, n)), omega, "exact")[1]
    rel = abs(K2 - K) / max(abs(K), FLOOR_SHARE * bar.k_star)
    return n, K, min(a_own, a_fine), max(rel, 2 * n * np.finfo(float).eps)  # at least the solve's rounding
