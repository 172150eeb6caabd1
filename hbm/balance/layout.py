"""The layout of the harmonic coefficients, real and complex.

A DOF's displacement over one period is ``x(t) = X0 + sum_h (Xc_h cos(h omega t) + Xs_h sin(h omega t))``,
stored as the real vector ``[X0, Xc1, Xs1, ..., XcH, XsH]`` (length ``2H + 1``), or as the complex
coefficients ``c_0 = X0``, ``c_h = Xc_h - i Xs_h`` (``x = Re sum_h c_h exp(i h omega t)``).
"""

from __future__ import annotations

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


__all__ = ["to_complex", "from_complex"]
