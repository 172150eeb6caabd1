"""The all-mode microslip bar (Eq. 30 with every mode) solved in the frequency domain.

Two elements: ``AllModeMicroslip`` (module ``element``) and ``AllModeMicroslip2D``, the same bar
with normal motion (module ``element2d``).  The other modules are the bar's solve, each one idea:

- ``solve``: one discretisation (``FixedBar``), multi-harmonic balance with AFT and Newton;
- ``normal``: one discretisation of the bar with normal motion;
- ``balance``: the AFT matrices, the periodic Jenkins force and its Jacobian, the block-tridiagonal
  solves; ``compiled``: the same operations as numba kernels (optional);
- ``coupled``: the Jacobian's block elimination with the linear part on its diagonal;
- ``segments``: the linear part per harmonic between the nodes (exact segments or lumped);
- ``accuracy``: the discretisation error (Richardson extrapolation, guarded); ``estimate``: that
  estimate at many points; ``rungs``: the rungs chosen along a curve; ``memo``: what a fixed rung
  returned, kept and read again.

``hbm`` imports this package only (``from contact_models.allmode import cells_error, richardson``),
never its modules.
"""

from .element import (CELLS, HARMONIC_LADDER, HARMONICS, MAX_CELLS, MAX_HARMONICS, NEWTON_MAX_ITER, NEWTON_TOL,
                      SAMPLES_PER_HARMONIC, TOL, AllModeMicroslip, AllModeSolution, cells_error, richardson)
from .element2d import CELLS_2D, HARMONICS_2D, SAMPLES_PER_HARMONIC_2D, AllModeMicroslip2D, NormalSolution

__all__ = ["AllModeMicroslip", "AllModeSolution", "CELLS", "HARMONICS", "SAMPLES_PER_HARMONIC", "NEWTON_TOL",
           "NEWTON_MAX_ITER", "TOL", "HARMONIC_LADDER", "MAX_CELLS", "MAX_HARMONICS", "richardson", "cells_error",
           "AllModeMicroslip2D", "NormalSolution", "CELLS_2D", "HARMONICS_2D", "SAMPLES_PER_HARMONIC_2D"]
