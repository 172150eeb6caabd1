"""``frequency_response`` for a structure with contacts (or a blade asked for more harmonics):
the options of ``hbm.frf.frequency_response`` resolved, then ``hbm.multiharmonic``."""

from __future__ import annotations

from typing import Any

import numpy as np

from .blade import Blade
from .presets import apply, harmonic_knobs
from .structure import Contact, Structure


def structure_response(structure: Any, contacts: Any, omega_range: Any, *, rtol: float, max_step: float,
                       min_step: float, max_steps: int, locate_folds: bool, on_point: Any,
                       accuracy: str | float | None, harmonics: int | None, n_t: int | None,
                       response_dof: int | None, stability: bool) -> Any:
    """Resolve a Blade to a one-DOF Structure, the accuracy preset to its knobs, and run."""
    from .multiharmonic import multiharmonic_response

    if isinstance(structure, Blade):
        b = structure
        structure = Structure([[b.mass]], [[b.damping]], [[b.stiffness]], force=[b.force])
        if contacts is not None and not isinstance(contacts, (list, tuple, Contact)):
            contacts = [Contact(contacts, dof=0)] if hasattr(contacts, "fourier") else contacts
    elif not isinstance(structure, Structure):
        raise ValueError(f"blade must be an hbm.Blade or an hbm.Structure, got blade={structure!r}")
    contacts = [] if contacts is None else contacts
    H_preset, n_t_preset = harmonic_knobs(accuracy if accuracy is not None else "default")
    if accuracy is not None:
        rtol, max_step, min_step, max_steps = apply(accuracy, rtol=rtol, max_step=max_step, min_step=min_step,
                                                    max_steps=max_steps)
    if harmonics is None:
        harmonics = H_preset
        if n_t is None and n_t_preset is not None and isinstance(harmonics, (int, np.integer)):
            n_t = n_t_preset
    return multiharmonic_response(structure, contacts, omega_range=omega_range, harmonics=harmonics, n_t=n_t,
                                  response_dof=response_dof, rtol=rtol, max_step=max_step, min_step=min_step,
                                  max_steps=max_steps, locate_folds=locate_folds, stability=stability,
                                  on_point=on_point)
