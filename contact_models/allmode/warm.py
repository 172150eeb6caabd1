"""The warm-up of the compiled kernels: every kernel compiled into numba's cache, group by group (each
listed in the progress file once cached, for a process that waits for it), then the marker
(``contact_models.allmode.compiled``, "No first-use wait").  Run in a background process by the first
process that would load the kernels from a cold cache; callable directly (the kernels' tests call it
first, so that they find the kernels loaded)."""

from __future__ import annotations

import numpy as np

from ..bar import Bar
from ..loads import UniformLoad
from . import compiled
from .element import AllModeMicroslip

__all__ = ["warm"]


def warm() -> None:
    """Compile the kernels in this process, group by group (``compiled.GROUPS``, each listed in the progress file
    once cached, so that a process waiting for them loads it at once), by running the nested solves of the
    all-mode bar on its rungs of 7, 15 and 31 harmonics, on a curve's first harmonic and on a blade's three, at a
    slipping and a stuck amplitude (so that the kernels' signatures a curve uses are in the cache), then leave
    the marker."""
    for group in compiled.GROUPS:
        compiled._compiled_now((group,))
        _solves()
        compiled.mark_group(group)
    compiled.mark_warm()


def _solves() -> None:
    """The nested solves of :func:`warm` (a tenth of a second on the numpy path)."""
    bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    load = UniformLoad(N=100.0)
    omega = 3.9e4
    for H in (7, 15, 31):
        el = AllModeMicroslip(bar, load, cells=32, harmonics=H)
        el.fourier(np.array([5.0e-7, 1.5e-6]), omega)
        el.model_error(np.array([1.5e-6]), omega)
        X = np.zeros(7)
        X[1], X[2], X[5] = 1.5e-6, 2.0e-7, 3.0e-8
        el.harmonic_force(X, omega, n_t=8 * 31 + 8)
