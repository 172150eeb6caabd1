"""Large structures: the condensed balance of a 1000-DOF chain with 10 friction contacts against the
dense solve of the same balance, and Hill's method (its time-invariant and parity shortcuts)
against the full eigenproblem of the QEP, both computed here independently of the library's
modal forms (``docs/performance.md``, "Large structures")."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import solve

from contact_models import Macroslip
from hbm import Blade, Contact, Structure, frequency_response
from hbm.balance.condensation import structure_modes
from hbm.balance.layout import to_complex
from hbm.balance.stability import HillProblem, derivative_operator, hill_exponents


def chain(n=1000, contacts=10):
    """The chain of ``benchmarks/bench_large.py``: masses 1 g, springs 4e6 N/m, the first mass tied
    to ground, the last forced by 1 N; modal damping 1 %; Macroslip contacts to ground."""
    k, m = 4e6, 1e-3
    K = 2.0 * k * np.eye(n) - k * np.eye(n, k=1) - k * np.eye(n, k=-1)
    K[-1, -1] = k
    f = np.zeros(n)
    f[-1] = 1.0
    s = Structure.with_modal_damping(m * np.eye(n), K, ratios=0.01, force=f)
    dofs = np.linspace(n // contacts - 1, n - 1, contacts).astype(int)
    return s, [Contact(Macroslip(stiffness=2e3, slip_force=0.05), dof=int(d)) for d in dofs]


def dense_response(s, dofs, F, omega, H):
    """Complex harmonics (n_a, H+1) at ``dofs`` of ``Z_h c_h = f delta_h1 - P F_h``, every
    ``Z_h = K - (h omega)^2 M + i h omega C`` solved densely (LU of the full n x n matrix)."""
    M, C, K = (np.asarray(A) for A in (s.M, s.C, s.K))
    cF = to_complex(F)  # (n_a, H+1): the contacts' forces on the DOFs
    out = np.zeros((len(dofs), H + 1), dtype=complex)
    for h in range(H + 1):
        Z = K - (h * omega) ** 2 * M + 1j * h * omega * C
        rhs = np.zeros(s.n, dtype=complex)
        rhs[dofs] = -cF[:, h]
        if h == 1:
            rhs += s.force
        out[:, h] = solve(Z, rhs, assume_a="sym")[dofs]  # Z is complex symmetric
    return out


def condition(s, omega, h):
    """2-norm condition number of ``Z_h(omega)`` (unit masses times m, modal damping: normal, its
    singular values ``m |w_k^2 - (h omega)^2 + 2 i zeta w_k h omega|``)."""
    w = s.natural_frequencies()
    sv = np.abs(w**2 - (h * omega) ** 2 + 2j * 0.01 * w * h * omega)
    return float(sv.max() / sv.min())


def test_1000_dof_chain_matches_the_dense_solve():
    s, contacts = chain()
    w1 = float(s.natural_frequencies()[0])
    frf = frequency_response(s, contacts, omega_range=(0.99 * w1, 1.01 * w1), harmonics=7, stability=False,
                             tol=None)
    assert frf.success and len(frf) > 10
    pr, H = frf._problem, frf.harmonics
    pk = int(np.argmax(frf.amplitude))
    for j in (0, pk):  # below the peak and at it
        X, w = frf._X[j], float(frf.omega[j])
        F = pr.forces(X, w)[0]
        dense = dense_response(s, pr.dofs, F, w, H)
        got = to_complex(X)
        scale = np.max(np.abs(got))
        # the FRF's point solves the dense balance to its Newton tolerance ...
        assert np.max(np.abs(dense - got)) <= 1e-6 * scale
        # ... and the condensed residual is the dense one to the dense solve's own accuracy,
        # (condition number of Z_1) x (unit roundoff): the modal form is exact
        R = pr._condensed(X, w)[0].reshape(pr.na, pr.L)
        kappa = max(condition(s, w, h) for h in range(1, H + 1))
        assert np.max(np.abs(to_complex(X - R) - dense)) <= kappa * np.finfo(float).eps * scale


def test_condensed_compliance_is_the_sum_over_the_poles():
    """``Condensed.at`` (the residues formed once, one product per omega) against the sum over the
    state-space poles written out, ``G_h = V_a diag(1/(i h omega - lam)) B_a``."""
    s, contacts = chain(n=200, contacts=4)
    from hbm.balance.condensation import Condensed

    dofs = sorted({c.dofs[0] for c in contacts} | {199})
    cond = Condensed(s, dofs, 7)
    for w in (0.0, 37.0, 491.0):
        G, dG, xl, dxl = cond.at(w)
        S = 1.0 / (1j * np.arange(8)[:, None] * w - cond.lam[None, :])
        ref = np.array([(cond.Va * S[h]) @ cond.Ba for h in range(8)])
        ref[0] = ref[0].real
        dref = np.array([(cond.Va * (-1j * h * S[h] ** 2)) @ cond.Ba for h in range(8)])
        np.testing.assert_allclose(G, ref, rtol=0, atol=1e-13 * np.max(np.abs(ref)))
        np.testing.assert_allclose(dG, dref, rtol=0, atol=1e-13 * max(np.max(np.abs(dref)), 1e-300))
        np.testing.assert_allclose(xl, cond.Va @ (S[1] * cond.bf), rtol=0, atol=1e-13 * np.max(np.abs(xl)))


def test_modal_decomposition_is_kept_while_the_matrices_stay():
    s = Structure(np.eye(2), 0.01 * np.eye(2), [[2.0, -1.0], [-1.0, 1.0]], force=[0.0, 1.0])
    first = structure_modes(s)
    assert structure_modes(s) is first
    s.K[0, 0] = 3.0  # changed in place: computed anew
    lam = structure_modes(s)[0]
    assert lam is not first[0]
    w2 = np.sort(np.linalg.eigvalsh(s.K))
    np.testing.assert_allclose(np.sort(np.abs(lam))[::2], np.sqrt(w2), rtol=1e-12)


def full_hill(M, C, K, omega, dF, H):
    """The QEP of ``hbm.balance.stability`` on every coefficient at once (no shortcut): all
    ``2 n (2H+1)`` eigenvalues and the ``2 n`` with the most centred eigenvectors."""
    n, L = M.shape[0], 2 * H + 1
    N, I = derivative_operator(H), np.eye(L)
    D1 = np.kron(C, I) + 2.0 * omega * np.kron(M, N)
    D0 = np.kron(K, I) + omega * np.kron(C, N) + omega**2 * np.kron(M, N @ N) + dF
    size = n * L
    A = np.block([[np.zeros((size, size)), np.eye(size)], [-np.linalg.solve(np.kron(M, I), D0),
                                                         -np.linalg.solve(np.kron(M, I), D1)]])
    lam, V = np.linalg.eig(A)
    P = V[:size].reshape(n, L, -1)
    z = [P[:, 0]] + [(P[:, 2 * h - 1] + s * 1j * P[:, 2 * h]) / 2 for h in range(1, H + 1) for s in (-1, 1)]
    k = [0] + [s * h for h in range(1, H + 1) for s in (1, -1)]  # z_{+h} = (c - i s)/2, z_{-h} = (c + i s)/2
    w = np.array([np.sum(np.abs(zk) ** 2, axis=0) for zk in z])
    centre = np.abs(np.array(k) @ w) / np.sum(w, axis=0)
    keep = np.lexsort((np.abs(lam.imag), np.round(centre, 2)))[:2 * n]
    return lam[keep]


def same_set(a, b, rtol):
    a, b = np.sort_complex(np.asarray(a)), np.sort_complex(np.asarray(b))
    assert a.shape == b.shape
    assert np.max(np.abs(a - b)) <= rtol * np.max(np.abs(b))


@pytest.mark.parametrize("static", [0.0, 0.3])
def test_hill_exponents_equal_the_full_eigenproblem(static):
    """A 3-DOF chain with a Macroslip contact, at slipping and stuck points of its FRF; with a
    static load the solution has even harmonics (no parity split), without it only odd ones."""
    Kc = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    M, C, H = np.diag([1.0, 0.8, 1.2]), 0.01 * Kc + 0.002 * np.eye(3), 3
    s = Structure(M, C, Kc, force=[0.0, 0.0, 0.01])
    contact = Contact(Macroslip(1.0, 0.01), dof=0)
    frf = frequency_response(s, [contact], omega_range=(0.3, 0.9), harmonics=H, stability=False,
                             tol=None)
    pr = frf._problem
    hill = HillProblem(M, C, Kc, H)
    kinds = set()
    for X, w in list(zip(frf._X, frf.omega))[::7]:
        X = X.copy()
        X[:, 0] += static  # a static offset: even harmonics in the contact's Jacobian
        dFa = pr.forces(X, float(w), perturbation=True)[1]
        assert np.array_equal(pr.perturbation_jacobian(X, float(w)), dFa)
        dF = np.zeros((3 * pr.L, 3 * pr.L))
        idx = (np.asarray(pr.dofs)[:, None] * pr.L + np.arange(pr.L)).ravel()
        dF[np.ix_(idx, idx)] = dFa
        kinds.add(bool(np.array_equal(dF, np.kron(dF[::pr.L, ::pr.L], np.eye(pr.L)))))
        got = hill.exponents(float(w), dF)
        same_set(got, full_hill(M, C, Kc, float(w), dF, H), 1e-10)
        same_set(hill_exponents(M, C, Kc, float(w), dF, H), got, 1e-13)
        assert np.all(np.diff(got.real) <= 0.0)
    assert kinds == {True, False}  # both stuck (time-invariant) and slipping points were checked


def test_hill_time_invariant_is_the_structures_own_eigenvalues():
    b = Blade(mass=2.0, stiffness=8.0, damping=0.1, force=1.0)
    M, C, K = (np.array([[v]]) for v in (b.mass, b.damping, b.stiffness))
    lam = hill_exponents(M, C, K, 1.7, 3.0 * np.eye(5), 2)  # a spring of 3 N/m on every harmonic
    root = np.sqrt(complex(0.1**2 - 4 * 2.0 * 11.0))
    same_set(lam, [(-0.1 + root) / 4.0, (-0.1 - root) / 4.0], 1e-14)


def test_hill_time_invariant_exponents_are_kept_per_contact_stiffness():
    """Stuck points of a branch share their exponents (they do not depend on omega); a new
    contact stiffness is computed anew, and a caller's copy cannot change the kept one."""
    M, C, K = np.diag([1.0, 2.0]), 0.02 * np.eye(2), np.array([[3.0, -1.0], [-1.0, 1.0]])
    hill = HillProblem(M, C, K, 2)
    for kc, omegas in ((0.5, (0.7, 1.9)), (2.0, (1.1,)), (0.5, (0.3,))):
        Kc = np.diag([kc, 0.0])
        ref = np.linalg.eigvals(np.block([[np.zeros((2, 2)), np.eye(2)],
                                          [-np.linalg.solve(M, K + Kc), -np.linalg.solve(M, C)]]))
        for w in omegas:
            lam = hill.exponents(w, np.kron(Kc, np.eye(5)))
            same_set(lam, ref, 1e-13)
            lam[:] = np.nan  # the caller's array only
    assert np.all(np.isfinite(hill.exponents(0.9, np.kron(np.diag([0.5, 0.0]), np.eye(5)))))


def test_hill_keeps_the_modes_of_the_band_and_the_first_above():
    """The 200-DOF blade (``examples/blade_200dof.py``, H = 7, 0.8 .. 2 omega_1): its fixed-interface
    modes are at 7.7, 25.6, 50.6, 64.7 omega_1 and the band (H + 1/2) omega_max = 15 omega_1, so Hill's
    method keeps the mode at 7.7 and the first above (25.6).  Against Hill's method on a Craig-Bampton
    model with 12 modes (built here from ``Structure.reduce``), the four largest real parts at every
    point are as close as with the 4 modes kept before (measured 6.1e-5 and 5.8e-5 omega; 1 mode:
    3.6e-4) and every verdict is the same."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "examples"))
    from blade_200dof import blade

    s, cs, tip = blade(100)
    w1 = float(s.natural_frequencies()[0])
    frf = frequency_response(s, cs, omega_range=(0.8 * w1, 2.0 * w1), harmonics=7, n_t=256, response_dof=tip,
                             rtol=1e-9, max_step=0.03)
    assert frf.exponents.shape == (len(frf), 8)
    assert frf.stability_dofs == ["CB:58", "CB:198", "mode 0", "mode 1"]
    r = s.reduce(frf.dofs, modes=12)
    M, C, K = (np.asarray(A) for A in (r.M, r.C, r.K))
    np.testing.assert_allclose(np.sqrt(np.diag(K)[2:6] / np.diag(M)[2:6]) / w1, [7.732, 25.552, 50.635, 64.658],
                               rtol=1e-4)
    pr, L = frf._problem, frf._problem.L
    hill, ref = HillProblem(M, C, K, 7), []
    for X, w in zip(frf._X, frf.omega):
        dF = np.zeros((r.n * L, r.n * L))
        dF[: 2 * L, : 2 * L] = pr.perturbation_jacobian(X, float(w))
        ref.append(hill.exponents(float(w), dF))
    ref = np.array(ref)
    err = np.max(np.abs(frf.exponents[:, :4].real - ref[:, :4].real) / frf.omega[:, None])
    assert err < 1e-4
    np.testing.assert_array_equal(frf.stable, ref[:, 0].real <= 1e-7 * frf.omega)
