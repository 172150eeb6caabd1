"""The layout of the harmonic coefficients, real and complex.

A DOF's displacement over one period is ``x(t) = X0 + sum_h (Xc_h cos(h omega t) + Xs_h sin(h omega t))``,
stored as the real vector ``[X0, Xc1, Xs1, ..., XcH, XsH]`` (length ``2H + 1``), or as the complex
coefficients ``c_0 = X0``, ``c_h = Xc_h - i Xs_h`` (``x = Re sum_h c_h exp(i h omega t)``).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray


def to_complex(V: NDArray) -> NDArray[np.complex128]:
    """``(.., 2H+1, ...)`` real layout on axis 1 -> ``(.., H+1, ...)`` complex ``c_h = Xc - i Xs``.

    Examples
    --------
    >>> import numpy as np
    >>> to_complex(np.array([[0.5, 1.0, 2.0]])).tolist()
    [[(0.5+0j), (1-2j)]]
    """
    c = np.empty((V.shape[0], (V.shape[1] + 1) // 2) + V.shape[2:], dtype=complex)
    c[:, 0] = V[:, 0]
    c[:, 1:] = V[:, 1::2] - 1j * V[:, 2::2]
    return c


def from_complex(c: NDArray) -> NDArray[np.float64]:
    """Inverse of :func:`to_complex` (real layout on axis 1).

    Examples
    --------
    >>> import numpy as np
    >>> from_complex(np.array([[0.5, 1.0 - 2.0j]])).tolist()
    [[0.5, 1.0, 2.0]]
    """
    V = np.empty((c.shape[0], 2 * c.shape[1] - 1) + c.shape[2:])
    V[:, 0] = c[:, 0].real
    V[:, 1::2] = c[:, 1:].real
    V[:, 2::2] = -c[:, 1:].imag
    return V


def next_sector_operator(harmonics: int, angle: float) -> NDArray[np.float64]:
    """``T`` (2H+1, 2H+1): the next sector's coefficients ``T X`` in the real layout from this sector's ``X``
    when harmonic h of the next sector is this one's times ``exp(-i h angle)``: ``c_h = Xc - i Xs`` turned,
    ``Xc' = Xc cos(h angle) - Xs sin(h angle)``, ``Xs' = Xs cos(h angle) + Xc sin(h angle)``; the static term
    as it is.  ``T`` is orthogonal: ``T^T`` turns by ``+h angle``.

    Examples
    --------
    >>> import numpy as np
    >>> T = next_sector_operator(1, np.pi / 2)
    >>> (T @ [0.5, 1.0, 0.0]).round(12).tolist()   # cos(theta) becomes cos(theta - pi/2) = sin(theta)
    [0.5, 0.0, 1.0]
    """
    L = 2 * harmonics + 1
    T = np.eye(L)
    for h in range(1, harmonics + 1):
        co, si = math.cos(h * angle), math.sin(h * angle)
        T[2 * h - 1, 2 * h - 1], T[2 * h - 1, 2 * h] = co, -si
        T[2 * h, 2 * h - 1], T[2 * h, 2 * h] = si, co
    return T


__all__ = ["to_complex", "from_complex", "next_sector_operator"]
