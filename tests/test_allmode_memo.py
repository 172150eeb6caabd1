"""A fixed rung of the all-mode bar keeps its harmonic forces by their exact end motion and frequency
(``contact_models.allmode.memo.ForceMemo``): a balance's error estimate asks again at the points it
converged to, and at those points padded with zeros to 2H + 1 harmonics."""

import numpy as np
import pytest

from contact_models import AllModeMicroslip, Bar, QuadraticLoad
from contact_models.allmode.memo import ForceMemo
from contact_models.allmode.solve import FixedBar

BAR = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
LOAD = QuadraticLoad.from_ratio(N=100.0, ratio=12.0)
OMEGA = 0.4 * BAR.omega_c


@pytest.fixture
def solves(monkeypatch):
    """The number of nested solves made so far (a list of one count)."""
    count = [0]
    solve = FixedBar.solve

    def counted(self, X, omega, odd=False, guess=None, derivatives=True):
        count[0] += 1
        return solve(self, X, omega, odd, guess, derivatives)

    monkeypatch.setattr(FixedBar, "solve", counted)
    return count


def motion(H):
    X = np.zeros(2 * H + 1)
    X[1], X[2] = 0.4e-6, 2e-6
    return X


def test_the_same_motion_again_is_answered_without_a_solve(solves):
    el = AllModeMicroslip(BAR, LOAD, cells=10, harmonics=7)
    X = motion(1)
    first = el.harmonic_force(X, OMEGA)
    assert solves[0] == 1
    first[0][:] = 0.0  # the caller's arrays are copies: changing them changes nothing kept
    again = el.harmonic_force(X.copy(), OMEGA)
    assert solves[0] == 1
    fresh = AllModeMicroslip(BAR, LOAD, cells=10, harmonics=7).harmonic_force(X, OMEGA)
    assert solves[0] == 2
    for a, b in zip(again, fresh):
        assert np.array_equal(a, b)
    el.harmonic_force(X, OMEGA * (1.0 + 1e-15))  # another frequency, however close: a solve
    assert solves[0] == 3


def test_the_motion_padded_to_more_harmonics_is_the_same_solve(solves):
    """At 2H + 1 = 3 harmonics from H = 1 (an estimate's Newton step): the kept answer, whose first
    block is the H = 1 answer and whose third harmonic is a fresh solve's to Newton's tolerance."""
    el = AllModeMicroslip(BAR, LOAD, cells=10, harmonics=7)
    F1, J1, w1 = el.harmonic_force(motion(1), OMEGA)
    F3, J3, w3 = el.harmonic_force(motion(3), OMEGA)
    assert solves[0] == 1
    assert np.array_equal(F3[:3], F1) and np.array_equal(J3[:3, :3], J1) and np.array_equal(w3[:3], w1)
    Ff, Jf, wf = AllModeMicroslip(BAR, LOAD, cells=10, harmonics=7).harmonic_force(motion(3), OMEGA)
    np.testing.assert_allclose(F3, Ff, atol=1e-10 * np.max(np.abs(Ff)))
    np.testing.assert_allclose(J3, Jf, atol=1e-9 * BAR.k_star)
    assert abs(F3[5]) > 1e-4 * abs(F3[1])  # the third harmonic is there to compare
    el.harmonic_force(motion(7), OMEGA)  # more than was kept (2 * 3 + 1 coefficients): a solve
    assert solves[0] == 3


def test_a_choosing_element_keeps_nothing(solves):
    el = AllModeMicroslip(BAR, LOAD, tol=1e-2)
    el.harmonic_force(motion(1), OMEGA)
    n = solves[0]
    el.harmonic_force(motion(1), OMEGA)  # its rungs depend on what it solved before: solved again
    assert solves[0] > n


def test_the_memo_keeps_at_most_its_bytes_dropping_the_oldest():
    fb = FixedBar(BAR, LOAD.on(BAR.L), 10, 7, 56)
    memo = ForceMemo(max_bytes=2000)
    keys = []
    for i in range(6):
        X = motion(7) * (1.0 + 0.1 * i)
        sol = fb.solve(X, OMEGA, odd=True)
        keys.append(ForceMemo.key(X, OMEGA, 7, True))
        memo.put(keys[-1], (sol.F, sol.dF_dX, sol.dF_domega), 7)
    kept = [memo.get(k, 7) is not None for k in keys]
    assert kept[-1] and not kept[0] and 1 <= sum(kept) < 6
    assert memo._bytes <= 2000
    assert memo.get(keys[-1], 9) is None  # asked for more coefficients than kept
