"""The all-mode bar's linear part per harmonic (``contact_models.allmode.segments``): the exact segments' functions
against their closed forms and finite differences, the lumped bar's coefficients, the refused meshes."""

from __future__ import annotations

import math

import numpy as np
import pytest

from contact_models import Bar, UniformLoad
from contact_models.allmode.segments import (MAX_SEGMENT_PHASE, SERIES_Z, UnresolvedWave, cells_for_phase,
                                             linear_part, segment_functions, stuck_end)
from contact_models.numerics.fe_bar import _Discretisation

BAR = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
LOAD = UniformLoad(N=100.0).on(BAR.L)


@pytest.mark.parametrize("z", [-30.0, -2.0, -0.3, -2 * SERIES_Z, -0.5 * SERIES_Z, 1e-9, 0.5 * SERIES_Z,
                               2 * SERIES_Z, 0.4, 2.5, 6.0, 0.95 * MAX_SEGMENT_PHASE**2])
def test_segment_functions_are_the_rod_s_and_their_derivatives(z):
    """A = s cot s, B = s / sin s (z = s^2 > 0), s coth s and s / sinh s (z = -s^2 < 0), 1 at z = 0; the
    series near 0 join them; A', B' against central differences."""
    A, B, dA, dB = (float(v[0]) for v in segment_functions(np.array([z])))
    s = math.sqrt(abs(z))
    if z > 0:
        A0, B0 = s / math.tan(s), s / math.sin(s)
    else:
        A0, B0 = (s / math.tanh(s), s / math.sinh(s)) if s > 0 else (1.0, 1.0)
    assert A == pytest.approx(A0, rel=1e-13, abs=1e-13) and B == pytest.approx(B0, rel=1e-13)
    e = 1e-5 * max(1.0, abs(z))
    Ap, Bp, _, _ = segment_functions(np.array([z + e]))
    Am, Bm, _, _ = segment_functions(np.array([z - e]))
    assert dA == pytest.approx(float(Ap[0] - Am[0]) / (2 * e), rel=1e-7, abs=1e-9)
    assert dB == pytest.approx(float(Bp[0] - Bm[0]) / (2 * e), rel=1e-7, abs=1e-9)


def test_the_lumped_part_is_the_finite_element_bar():
    d = _Discretisation(BAR, LOAD, 12)
    order = np.array([0.0, 1.0, 1.0, 3.0, 3.0])
    p = linear_part(BAR, d, 3.0e4, order, "lumped")
    np.testing.assert_array_equal(p.lin, d.kdiag[:, None] - 3.0e4**2 * d.m[:, None] * order**2)
    assert np.all(p.c == d.off) and not np.any(p.dc)
    np.testing.assert_array_equal(p.dlin, -2.0 * 3.0e4 * d.m[:, None] * order**2)


def test_the_exact_part_and_its_frequency_derivative():
    """Interior nodes carry two segments, the ends one (beta at node 0), each less its Jenkins spring
    k c_i; dlin and dc against central differences in omega."""
    d = _Discretisation(BAR, LOAD, 10)
    order = np.array([1.0, 1.0, 5.0, 5.0, 9.0])
    w = 3.5e4
    p = linear_part(BAR, d, w, order, "exact")
    A, B, _, _ = segment_functions((BAR.rho * BAR.A * (w * order) ** 2 - BAR.k) / BAR.EA * d.h**2)
    k = BAR.EA / d.h
    np.testing.assert_allclose(p.lin[3], 2 * k * A - d.kc[3], rtol=1e-14)
    np.testing.assert_allclose(p.lin[0], k * A + BAR.beta - d.kc[0], rtol=1e-14)
    np.testing.assert_allclose(p.lin[-1], k * A - d.kc[-1], rtol=1e-14)
    np.testing.assert_allclose(p.c, -k * B, rtol=1e-14)
    hi, lo = (linear_part(BAR, d, w * (1 + s * 1e-6), order, "exact") for s in (1, -1))
    np.testing.assert_allclose(p.dlin, (hi.lin - lo.lin) / (2e-6 * w), rtol=1e-6, atol=1e-6 * np.max(np.abs(p.dlin)))
    np.testing.assert_allclose(p.dc, (hi.c - lo.c) / (2e-6 * w), rtol=1e-6)


def test_too_long_exact_cells_are_refused_naming_the_cells_needed():
    w = 10 * BAR.omega_c
    n = cells_for_phase(BAR, w, 7)
    linear_part(BAR, _Discretisation(BAR, LOAD, n), w, np.array([7.0]), "exact")  # accepted
    with pytest.raises(UnresolvedWave, match=rf"cells={n - 1} are too few for harmonic 7 .* at least {n} cells"):
        linear_part(BAR, _Discretisation(BAR, LOAD, n - 1), w, np.array([7.0]), "exact")
    assert issubclass(UnresolvedWave, ValueError)


@pytest.mark.parametrize("w", [0.0, 0.5, 0.9, 2.0])
def test_the_exact_stuck_end_is_the_continuous_bar_s(w):
    """``Bar.stuck_stiffness`` (the closed form) on 2 cells as on 200; the lumped bar converges to it."""
    omega = w * BAR.omega_c
    K = float(BAR.stuck_stiffness(omega))
    for n in (max(2, cells_for_phase(BAR, omega, 1)), 200):
        assert stuck_end(BAR, _Discretisation(BAR, LOAD, n), omega, "exact")[0] == pytest.approx(K, rel=1e-11)
    lumped = [stuck_end(BAR, _Discretisation(BAR, LOAD, n), omega, "lumped")[0] for n in (50, 100)]
    assert abs(lumped[1] - K) < 0.3 * abs(lumped[0] - K)  # second order: a quarter
