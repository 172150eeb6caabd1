"""A unilateral spring behind a gap: ``f = k max(0, x - g)`` (impact stop, contact that opens).

The force of a displacement (or, through ``hbm.Contact(..., dofs=(i, j))``, of a relative
displacement) ``x``: nothing while ``x < g``, a spring ``k`` once the gap ``g`` is closed.  A
negative ``g`` is a preloaded contact (in contact at rest, force ``-k g``); it opens for
``x < g``.  Derivations and conventions in ``docs/contacts_normal.md``.

**Time law** (exact, no memory): sample by sample ``f = k max(0, x - g)``, Jacobian
``diag(k [x > g])``; the multi-harmonic balance uses it by AFT at every H, H = 1 included.

**Describing function** (``fourier``: the first harmonic for ``x = a sin(theta)``, no mean).
With ``s = g/a`` and the contact angle ``theta_1 = arcsin(s)`` (``a sin(theta) = g``), the spring
acts on ``theta_1 < theta < pi - theta_1``; for ``-1 <= s <= 1``

    f_s = (k a/pi) (pi/2 - arcsin(s) - s sqrt(1 - s^2)),     f_c = 0,
    df_s/da = (k/pi) (pi/2 - arcsin(s) + s sqrt(1 - s^2)),

``f_s = 0`` for ``s >= 1`` (never closed) and ``f_s = k a`` for ``s <= -1`` (never open).  The
law is elastic (single-valued), so ``f_c = 0``.  The force also has a mean,

    F_0 = (k a/pi) (sqrt(1 - s^2) - s (pi/2 - arcsin(s))),

which the describing function does not carry, and a mean displacement ``X_0`` changes both
``F_0`` and ``f_s`` (the contact angle moves with ``g - X_0``).  A first-harmonic balance that
answers from ``f_s`` alone would drop the mean force and the mean's effect, so the element's
``exact_describing_function`` is False and the balance answers it through its time law (AFT) at
H = 1 too, which carries both; ``fourier`` remains the describing function about a zero mean.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .base import ContactElement
from .numerics.checks import finite, nonnegative_array, positive


def gap_fourier(k: float, g: float, a: ArrayLike) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """``(f_s, f_c, df_s/da, df_c/da)`` of ``k max(0, a sin(theta) - g)`` for flat float arrays ``a``."""
    a = np.asarray(a, dtype=float)
    fs = np.where(g < 0.0, k * a, 0.0)
    dfs = np.full_like(a, k if g < 0.0 else 0.0)
    mixed = a > abs(g)
    if np.any(mixed):
        A = a[mixed]
        s = g / A
        root = np.sqrt(1.0 - s * s)
        rest = 0.5 * np.pi - np.arcsin(s)
        fs[mixed] = k * A * (rest - s * root) / np.pi
        dfs[mixed] = k * (rest + s * root) / np.pi
    zero = np.zeros_like(a)
    return fs, zero, dfs, zero.copy()


class Gap(ContactElement):
    """Unilateral spring ``f = stiffness * max(0, x - gap)`` (N).

    Parameters
    ----------
    stiffness : float
        Contact stiffness k (N/m), > 0 and finite.
    gap : float
        Gap g (m), finite: the displacement at which contact closes; negative for a preloaded
        contact (force ``-k g`` at ``x = 0``).

    Raises
    ------
    ValueError
        If ``stiffness`` is not positive and finite or ``gap`` is not finite, naming it.

    Notes
    -----
    ``fourier`` is the describing function about a zero mean (module docstring); the balance uses
    the exact time law at every H because the force has a mean the describing function does not
    carry (``exact_describing_function`` is False).  ``slip_amplitude`` is ``|g|``, the amplitude
    at which the contact state starts to change over a cycle; ``linear_amplitude`` is 0 (with a
    mean displacement the contact state is not a function of the amplitude alone).

    Examples
    --------
    >>> from contact_models import Gap
    >>> stop = Gap(stiffness=2.0, gap=0.5)
    >>> f_s, f_c = stop.fourier(1.0)      # s = 1/2: (k a/pi)(pi/3 - sqrt(3)/4)
    >>> round(float(f_s), 12), float(f_c)
    (0.391002218956, 0.0)
    >>> stop.periodic_force([0.0, 1.0, 0.0, -1.0])[0].tolist()
    [0.0, 1.0, 0.0, 0.0]
    """

    frequency_dependent = False
    has_time_law = True

    def __init__(self, stiffness: float, gap: float) -> None:
        self.stiffness = positive("stiffness", stiffness)
        if not math.isfinite(self.stiffness):
            raise ValueError(f"stiffness must be finite, got stiffness={stiffness!r}")
        self.gap = finite("gap", gap)

    def __repr__(self) -> str:
        return f"Gap(stiffness={self.stiffness!r}, gap={self.gap!r})"

    def mean_force(self, a: ArrayLike) -> float | NDArray:
        """``F_0`` (N), the mean of ``k max(0, a sin(theta) - g)`` over a period (module docstring)."""
        a = nonnegative_array("a", a)
        k, g = self.stiffness, self.gap
        s = np.clip(np.divide(g, a, out=np.full_like(a, math.copysign(math.inf, g) if g else 0.0),
                              where=a > 0.0), -1.0, 1.0)
        out = k * a * (np.sqrt(1.0 - s * s) - s * (0.5 * np.pi - np.arcsin(s))) / np.pi
        out = np.where(a <= -g, -k * g, out)  # never open: the mean of k (x - g)
        return out if out.ndim else float(out)

    def _periodic_force(self, x, omega):
        f, d, _, _ = self._periodic_tangent(x, omega)
        return f, np.diag(d)

    def _periodic_tangent(self, x, omega):
        closed = x > self.gap
        f = np.where(closed, self.stiffness * (x - self.gap), 0.0)
        return f, np.where(closed, self.stiffness, 0.0), np.empty(0, dtype=np.intp), np.empty((x.size, 0))

    def _fourier_derivatives(self, a, omega, rtol):
        return gap_fourier(self.stiffness, self.gap, a)

    def _stuck_stiffness(self, omega):
        return self.stiffness if self.gap < 0.0 else 0.0

    def _slip_amplitude(self, omega):
        return abs(self.gap)

    def _linear_amplitude(self, omega):
        return 0.0

    def _reference_amplitude(self, omega):
        return abs(self.gap) if self.gap != 0.0 else 1.0

    def _hysteresis(self, a, omega, n):
        x = a * np.sin(np.linspace(-0.5 * np.pi, 1.5 * np.pi, n))
        return x, self.stiffness * np.maximum(x - self.gap, 0.0)


__all__ = ["Gap", "gap_fourier"]
