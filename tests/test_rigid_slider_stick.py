"""The rigid Coulomb slider (``Macroslip(math.inf, ...)``) where it does not slip all period: the first-harmonic
balance has no solution with it moving, and the call says so, naming the element, omega and the forces.

The system: two unit masses, ``K = [[2, -1], [-1, 2]]``, ``C = 0.004 I``, the force on DOF 0, the slider of slip
force 0.005 from DOF 1 to ground.  Held, the slider carries ``P = |F/(2 - w^2 + 0.004 i w)|`` (DOF 0 alone); its
describing function's force is ``4 slip_force/pi`` for every amplitude > 0, so the H = 1 balance has a moving
solution only where ``P > 4 slip_force/pi`` (module ``hbm.balance.start``).

Independent answers: the closed forms above and the time integration with exact stick/slip events
(``tests/_rigid_slider_events.py``), which says how much of the period the slider sticks.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.optimize import brentq

from _rigid_slider_events import reference
from contact_models import Macroslip
from hbm import Contact, Structure, frequency_response

M, C, K, SLIP = np.eye(2), 0.004 * np.eye(2), np.array([[2.0, -1.0], [-1.0, 2.0]]), 0.005
F1 = 4.0 * SLIP / math.pi
RIGID = "Macroslip(stiffness=inf, slip_force=0.005)"


def solve(force, omega_range):
    s = Structure(M, C, K, force=[force, 0.0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return frequency_response(s, [Contact(Macroslip(math.inf, SLIP), dof=1)], omega_range=omega_range, tol=1e-3)


def held(force, w):
    """The force on the slider held fixed: DOF 0 alone on its spring 2, coupled by -1."""
    return abs(force / (2.0 - w * w + 0.004j * w))


def describing_amplitudes(force, w):
    """(|X0|, |X1|) of the H = 1 balance: the slider as the viscous damper 4 slip_force/(pi a w) at its own
    amplitude a = |X1|, solved for a by Brent's method (the largest root; None where there is none)."""
    def X(a):
        D = K - w * w * M + 1j * w * C
        D[1, 1] += 1j * F1 / a
        return np.linalg.solve(D, [force, 0.0])

    a = np.logspace(-9, 2, 2000)
    g = [abs(X(v)[1]) / v - 1.0 for v in a]
    cross = [j for j in range(len(a) - 1) if g[j] > 0.0 >= g[j + 1]]
    if not cross:
        return None
    j = cross[-1]
    root = brentq(lambda v: abs(X(v)[1]) / v - 1.0, a[j], a[j + 1], xtol=1e-300, rtol=1e-15)
    return tuple(abs(X(root)))


def test_the_event_reference_of_a_slider_stuck_all_period_is_the_linear_response():
    """The reference against a closed form: held by less than its slip force, the slider never moves."""
    w, force = 0.6, 0.005
    assert held(force, w) < SLIP
    amp, stuck, gap = reference(M, C, K, [force, 0.0], 1, SLIP, w, periods=20)
    assert gap < 1e-12 and stuck == pytest.approx(1.0, abs=1e-9)
    assert abs(amp[0] / held(force, w) - 1.0) < 1e-8 and amp[1] < 1e-12


def test_the_start_where_the_slider_sticks_part_of_each_period_says_so_by_name():
    w, force = 0.6, 0.01
    P = held(force, w)
    assert SLIP < P < F1  # 0.0061: above the slip force, below the describing function's 4 slip_force/pi
    assert describing_amplitudes(force, w) is None  # no moving H = 1 solution
    # the physics, independently: stick-slip, the slider stuck for 40 % of the period, not the linear answer
    amp, stuck, gap = reference(M, C, K, [force, 0.0], 1, SLIP, w)
    assert gap < 1e-12 and 0.35 < stuck < 0.45
    assert amp[0] > 1.2 * P and amp[1] > 0.5 * SLIP  # x0 0.00775, x1 0.00443 (held: 0.0061, 0)
    frf = solve(force, (0.6, 2.0))
    assert not frf.success and len(frf) == 0
    m = frf.message
    assert m.startswith("Newton's method did not converge at the starting point")
    assert f"at omega = 0.6 rad/s the first-harmonic balance has no solution with {RIGID} at dof=1" in m
    assert f"held fixed, it would carry a force of amplitude {P:.6g} N, less than {F1:.6g} N" in m
    assert "so it sticks for part of each period or all of it" in m
    assert "Macroslip(k, slip_force)" in m and "time-domain force law" in m
    assert m in frf.accuracy_warning


def test_the_start_where_the_slider_sticks_all_period_says_so():
    w, force = 0.6, 0.005
    assert held(force, w) < SLIP < F1
    frf = solve(force, (w, 1.0))
    assert not frf.success and len(frf) == 0
    assert f"held fixed, it would carry a force of amplitude {held(force, w):.6g} N, less than {F1:.6g} N" in frf.message
    assert "so it sticks for part of each period or all of it" in frf.message


def test_a_start_where_the_describing_function_has_a_moving_solution_finds_it():
    """At 0.7 rad/s the H = 1 solution exists (a = 0.0021, close to the a = 0 the force jumps at) though
    neither the free-slider guess nor the force homotopy reaches it: the equivalent linear start does."""
    frf = solve(0.01, (0.7, 1.85))
    assert frf.success and abs(float(frf.omega[0]) - 0.7) < 1e-12 and abs(float(frf.omega[-1]) - 1.85) < 1e-12
    for w in (0.7, 0.8, 1.0, 1.2, 1.6, 1.85):
        i = int(np.argmin(np.abs(frf.omega - w)))
        a0, _ = describing_amplitudes(0.01, float(frf.omega[i]))
        assert abs(float(frf.amplitude[i]) / a0 - 1.0) < 1e-7, w
    # against the time integration where the slider slips all period (at the resonance of the free slider)
    amp, stuck, _ = reference(M, C, K, [0.01, 0.0], 1, SLIP, 1.0)
    assert stuck == 0.0
    i = int(np.argmin(np.abs(frf.omega - 1.0)))
    assert abs(float(frf.omega[i]) - 1.0) < 1e-3
    a0, _ = describing_amplitudes(0.01, 1.0)
    assert abs(a0 / amp[0] - 1.0) < 1e-3  # 0.45417 against 0.45427


def test_the_branch_that_ends_where_the_slider_starts_to_stick_says_why():
    frf = solve(0.01, (0.7, 2.0))
    w_end = math.sqrt(2.0 + 0.01 / F1)  # where the held force falls to 4 slip_force/pi (damping aside)
    assert not frf.success and len(frf) > 100
    assert abs(float(frf.omega[-1]) - w_end) < 1e-3
    m = frf.message
    assert "just beyond its last point, at omega = " in m and RIGID in m and "sticks for part of each period" in m
    # the physics there: stick-slip, as said
    _, stuck, _ = reference(M, C, K, [0.01, 0.0], 1, SLIP, 1.9)
    assert 0.2 < stuck < 0.4
