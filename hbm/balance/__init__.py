"""The one harmonic balance: any structure (a blade is one DOF), any number of harmonics.

- :mod:`~hbm.balance.residual`: :class:`HarmonicBalance`, the residual and its Jacobian,
  condensed onto the contact DOFs; the contacts answer by describing function at H = 1 or by
  their time law through AFT.
- :mod:`~hbm.balance.condensation`: the structure's compliance at the contact DOFs, harmonic by
  harmonic, from its state-space modes.
- :mod:`~hbm.balance.layout`: the real and complex layouts of the harmonic coefficients.
- :mod:`~hbm.balance.start`: a start by homotopy in the force where the stuck guess fails.
- :mod:`~hbm.balance.stability`: Hill's method, stability changes along a branch.
- :mod:`~hbm.balance.presets`: the defaults and the accuracy presets.
"""

from .residual import HarmonicBalance

__all__ = ["HarmonicBalance"]
