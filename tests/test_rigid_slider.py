"""A first-harmonic element with a tolerance: the rigid Coulomb slider (``Macroslip(math.inf, ...)``, no time
law) traced at H = 1, the only H its balance takes, whether or not ``harmonics=1`` is given, with a finite model
source, a harmonics source that says it cannot be estimated, and the warning that names the element.

Reference: the describing function of the rigid slider in closed form (``docs/point_contact.md``, "Rigid
Coulomb": ``f_s = 0``, ``f_c = 4 f_slip/pi``, an equivalent viscous damping ``4 f_slip/(pi a omega)``), so the
one-DOF amplitude solves ``|(k - m omega^2) + i omega (c + 4 f_slip/(pi a omega))| a = F``, found here by Brent's
method at each compared point's frequency.
"""

from __future__ import annotations

import math
import re
import warnings

import numpy as np
import pytest
from scipy.optimize import brentq

from contact_models import AccuracyWarning, Macroslip
from hbm import Blade, Contact, Structure, frequency_response
from hbm.balance import errors
from hbm.balance import residual
from hbm.cli.cases import default_case
from hbm.frf import start_harmonics

M, C, K, F, SLIP = 1.0, 0.004, 1.0, 0.01, 0.005  # F > 4 SLIP/pi: the mass never stops
RANGE = (0.6, 1.8)
RIGID = "Macroslip(stiffness=inf, slip_force=0.005)"


def systems():
    """The one-DOF system as a structure and as a blade (the two front doors of one balance)."""
    return {"structure": Structure([[M]], [[C]], [[K]], force=[F]),
            "blade": Blade(mass=M, stiffness=K, damping=C, force=F)}


def solve(*args, **kwargs):
    """``frequency_response`` with every warning recorded: (frf, [(category, message)])."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        frf = frequency_response(*args, **kwargs)
    return frf, [(w.category, str(w.message)) for w in caught]


def closed_form_amplitude(w: float) -> float:
    """The rigid slider's describing-function amplitude at ``w``: the root of
    ``|(k - m w^2) a + i (c w a + 4 f_slip/pi)| - F`` (increasing in a, negative at a = 0)."""
    def g(a):
        return math.hypot((K - M * w * w) * a, C * w * a + 4.0 * SLIP / math.pi) - F
    return brentq(g, 1e-12, 10.0, xtol=1e-300, rtol=1e-15)


def test_the_tolerance_driver_starts_a_first_harmonic_element_at_one_harmonic():
    s = systems()["structure"]
    assert start_harmonics(s, [Contact(Macroslip(math.inf, SLIP), dof=0)], None, 1e-3) == 1
    assert start_harmonics(s, [Contact(Macroslip(1.0, SLIP), dof=0)], None, 0.2) == 3  # a time law: from 3


@pytest.mark.parametrize("given", [{}, {"harmonics": 1}], ids=["tol", "tol-and-harmonics-1"])
@pytest.mark.parametrize("front", ["structure", "blade"])
def test_the_rigid_slider_with_tol_is_traced_at_one_harmonic_to_the_closed_form(front, given):
    frf, said = solve(systems()[front], [Contact(Macroslip(math.inf, SLIP), dof=0)], omega_range=RANGE, tol=1e-3,
                      **given)
    assert frf.success and abs(float(frf.omega[-1]) - RANGE[1]) <= 1e-12 and len(frf) > 100
    assert frf.harmonics == 1 and np.all(frf.point_harmonics == 1) and len(frf.segments) == 1
    # the curve against the closed form, point by point (a handful along it and the peak's neighbours)
    i = int(np.argmax(frf.amplitude))
    for j in sorted({0, len(frf) // 5, len(frf) // 3, i - 1, i, i + 1, 3 * len(frf) // 4, len(frf) - 1}):
        w, a = float(frf.omega[j]), float(frf.amplitude[j])
        assert abs(a / closed_form_amplitude(w) - 1.0) <= 1e-8, (w, a)
    pk = frf.peak()
    assert pk.interior and abs(pk.amplitude / closed_form_amplitude(pk.omega) - 1.0) <= 1e-8
    assert abs(pk.amplitude - 0.9084555691310807) <= 1e-8 * pk.amplitude  # the closed form's maximum, 0.99999 rad/s
    # the estimate: never NaN; the exact element has no model error (its infinite k* notwithstanding), its
    # closed-form force no sampling error; the harmonics H = 1 leaves out have no bound: inf, not a claim
    for source, v in frf.error_sources.items():
        assert not np.any(np.isnan(v)), source
    assert not np.any(np.isnan(frf.error_estimate))
    assert np.all(frf.error_sources["model"] == 0.0) and np.all(frf.error_sources["sampling"] == 0.0)
    assert np.all(frf.error_sources["element"] <= 1e-12)
    assert np.all(np.isinf(frf.error_sources["harmonics"])) and np.all(np.isinf(frf.error_estimate))
    assert not pk.converged and pk.estimate == math.inf
    assert pk.message == ("its error cannot be estimated (a source of it has no bound there), so it is not known "
                          "to be within tol 0.001")
    # one warning, and it is the AccuracyWarning that says why (no RuntimeWarning of inf arithmetic)
    assert [c for c, _ in said] == [AccuracyWarning]
    message = said[0][1]
    assert frf.accuracy_warning == message
    assert f"the harmonics source of the error cannot be estimated at {len(frf)} of {len(frf)} points" in message
    assert "omega = 0.6 to 1.8 rad/s, H = 1" in message
    assert (f"Macroslip is a first-harmonic element: {RIGID} has no time-domain force law, so the balance cannot "
            f"raise H above 1 with it, and harmonics=1 is its describing-function answer") in message
    assert "AllModeMicroslip" not in message  # no advice about a microslip bar the user does not have


@pytest.mark.parametrize("tol", [1e-3, None])
@pytest.mark.parametrize("front", ["structure", "blade"])
def test_the_rigid_slider_at_three_harmonics_is_refused_by_name(front, tol):
    with pytest.raises(ValueError, match=r"^harmonics must be 1 with Macroslip, which has no time-domain force law "
                                         r"\(a first-harmonic element\), got harmonics=3; use harmonics=1 \(its "
                                         rf"describing-function answer\); the element: {re.escape(RIGID)}$"):
        frequency_response(systems()[front], [Contact(Macroslip(math.inf, SLIP), dof=0)], omega_range=RANGE,
                           tol=tol, harmonics=3)


def test_the_rigid_slider_on_a_structure_of_two_dofs_is_traced_with_tol():
    """The condensed balance's harmonics source at H = 1 steps to no balance of more harmonics (none holds the
    slider): it reads inf, and the estimate is finite elsewhere."""
    s = Structure(np.eye(2), 0.004 * np.eye(2), [[2.0, -1.0], [-1.0, 2.0]], force=[0.05, 0.0])
    frf, said = solve(s, [Contact(Macroslip(math.inf, SLIP), dof=1)], omega_range=(0.6, 2.0), tol=1e-3)
    assert frf.success and abs(float(frf.omega[-1]) - 2.0) <= 1e-12 and np.all(frf.point_harmonics == 1)
    assert not frf._problem.one_dof
    assert not np.any(np.isnan(frf.error_estimate))
    assert np.all(np.isinf(frf.error_sources["harmonics"])) and np.all(frf.error_sources["model"] == 0.0)
    assert [c for c, _ in said] == [AccuracyWarning] and RIGID in said[0][1]


def test_the_condensed_harmonics_source_takes_a_first_harmonic_elements_stand_in_as_the_one_dof_form():
    """The single-mode bar (no time law) at H = 1: the condensed form's step to 3 harmonics with its quasi-static
    bar standing in reads what the one-DOF form reads at the same points."""
    case = default_case()
    frf, _ = solve(case.blade, case.element, omega_range=(3.2e4, 4.4e4), tol=1e-3)
    idx = np.arange(0, len(frf), 10)
    X, w = frf._X[idx], frf.omega[idx]
    one = errors._one_dof(frf._problem, X, w, frf.rtol)["harmonics"]
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(residual, "solved_as_one_dof", lambda *args: False)
        condensed = residual.HarmonicBalance(case.blade, case.element, harmonics=1, rtol=frf.rtol)
    assert not condensed.one_dof and np.max(one) > 1e-3  # (slipping points, whose harmonics matter)
    np.testing.assert_allclose(errors._harmonics_condensed(condensed, X, w, frf.rtol), one, rtol=1e-6, atol=1e-20)


def test_a_single_mode_bar_on_a_structure_of_two_dofs_is_traced_with_the_default_tol():
    """No harmonics given: H = 1, the only H the bar takes (not the structure's start at 3, which it refuses), and a
    finite estimate with the harmonics source from the bar's quasi-static stand-in."""
    case = default_case()
    b = case.blade
    s = Structure(np.diag([b.mass, b.mass]), np.diag([b.damping, b.damping]),
                  [[2.0 * b.stiffness, -b.stiffness], [-b.stiffness, b.stiffness]], force=[0.0, b.force])
    frf, said = solve(s, [Contact(case.element, dof=1)], omega_range=(2.0e4, 4.4e4))
    assert frf.success and np.all(frf.point_harmonics == 1) and not frf._problem.one_dof
    assert np.all(np.isfinite(frf.error_estimate))
    assert 1e-3 < float(np.max(frf.error_sources["harmonics"])) < 1e-2  # 4.4e-3 at the resonance
    assert len([c for c, _ in said if c is AccuracyWarning]) == 1
