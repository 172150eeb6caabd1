"""Structures and contacts: bad input refused up front by name, helpers
(damping, files, Craig-Bampton), and a property suite over random small structures."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from contact_models import Macroslip, TwoRegionMicroslip
from hbm import Contact, ReducedStructure, Steps, Structure, frequency_response
from hbm.structure import load_matrix

K2 = np.array([[2.0, -1.0], [-1.0, 1.0]])
GOOD = dict(M=np.eye(2), C=0.01 * np.eye(2), K=K2)


def build(**change):
    args = {**GOOD, **change}
    return Structure(args["M"], args["C"], args["K"], force=change.get("force", [0.0, 1.0]))


@pytest.mark.parametrize("change, match", [
    (dict(M=np.ones((2, 3))), "M must be a square matrix"),
    (dict(K=np.eye(3)), "K must be 2 x 2"),
    (dict(C=np.array([[0.0, np.nan], [np.nan, 0.0]])), "C must be finite"),
    (dict(K=np.array([[2.0, -1.0], [-0.5, 1.0]])), "K must be symmetric"),
    (dict(M=np.array([[1.0, 0.0], [0.0, -1.0]])), "M must be positive definite"),
    (dict(force=[1.0, 2.0, 3.0]), "force must have length n = 2"),
    (dict(force=[1.0, math.inf]), "force must be finite"),
])
def test_bad_structures_refused_by_name(change, match):
    with pytest.raises(ValueError, match=match):
        build(**change)


def test_bad_contacts_and_options_refused_by_name(two):
    s = build()
    jen = Macroslip(1.0, 0.1)
    with pytest.raises(ValueError, match="dofs must be two different DOFs"):
        Contact(jen, dofs=(1, 1))
    with pytest.raises(ValueError, match="dof must be a DOF index in 0..1, got dof=2"):
        frequency_response(s, [Contact(jen, dof=2)], omega_range=(0.5, 1.5))
    with pytest.raises(ValueError, match="harmonics must be an integer >= 1, got harmonics=0"):
        frequency_response(s, [Contact(jen, dof=0)], omega_range=(0.5, 1.5), harmonics=0)
    with pytest.raises(ValueError, match=r"n_t must be an integer >= 2H \+ 2 = 8"):
        frequency_response(s, [Contact(jen, dof=0)], omega_range=(0.5, 1.5), harmonics=3, n_t=7)
    with pytest.raises(ValueError, match="^harmonics must be 1 with TwoRegionMicroslip, which has no time-domain"):
        frequency_response(s, [Contact(two, dof=0)], omega_range=(0.5, 1.5), harmonics=3)
    with pytest.raises(ValueError, match="response_dof must be a DOF index"):
        frequency_response(s, [Contact(jen, dof=0)], omega_range=(0.5, 1.5), response_dof=5)
    with pytest.raises(ValueError, match="element must be a contact_models.ContactElement"):
        Contact("jenkins", dof=0)
    with pytest.raises(ValueError, match="K must be nonsingular"):
        frequency_response(build(K=np.zeros((2, 2))), [Contact(jen, dof=0)], omega_range=(0.5, 1.5))


def test_reduce_and_reduced_structure_refuse_bad_input_by_name():
    s3 = Structure(np.eye(3), 0.01 * np.eye(3), 2 * np.eye(3) - np.eye(3, k=1) - np.eye(3, k=-1), force=[0, 0, 1.0])
    with pytest.raises(ValueError, match=r"^keep must be a sequence of DOF indices, got keep=2$"):
        s3.reduce(2, modes=1)  # before: "'int' object is not iterable"
    r = s3.reduce([2], modes=1)
    for bad in (2.0, True):  # before: 2.0 and True (== 1 of another reduction) were looked up as DOFs
        with pytest.raises(ValueError, match=rf"^original must be one of the kept DOFs \(2,\), got original={bad}$"):
            r.dof(bad)
    M, force = np.eye(2), [1.0, 0.0]
    # made by hand: before, a T of the wrong shape, kept DOFs outside the full structure and a full that is
    # no structure were all taken
    with pytest.raises(ValueError, match=r"^T must be a finite 3 x 2 matrix \(original x reduced DOFs\), "
                                         r"got T of shape \(3, 3\)$"):
        ReducedStructure(M, M, M, force=force, T=np.eye(3), kept=(0,), full=s3)
    with pytest.raises(ValueError, match=r"^kept must be a DOF index in 0..2, got kept=7$"):
        ReducedStructure(M, M, M, force=force, T=np.ones((3, 2)), kept=(7,), full=s3)
    with pytest.raises(ValueError, match=r"^kept must be distinct DOFs of full, at most 2, got kept=\(0, 0\)$"):
        ReducedStructure(M, M, M, force=force, T=np.ones((3, 2)), kept=(0, 0), full=s3)
    with pytest.raises(ValueError, match=r"^full must be the hbm.Structure reduced, got full=3$"):
        ReducedStructure(M, M, M, force=force, T=np.ones((3, 2)), kept=(0,), full=3)


def test_damping_helpers_and_files(tmp_path):
    from scipy import sparse
    from scipy.io import mmwrite

    M, K = np.diag([1.0, 2.0]), K2
    s = Structure.with_rayleigh(M, K, alpha=0.1, beta=0.01, force=[0.0, 1.0])
    np.testing.assert_allclose(s.C, 0.1 * M + 0.01 * K)
    s = Structure.with_modal_damping(M, K, ratios=[0.01, 0.02], force=[0.0, 1.0])
    from scipy.linalg import eigh

    lam, Phi = eigh(K, M)
    np.testing.assert_allclose(Phi.T @ s.C @ Phi, np.diag(2 * np.array([0.01, 0.02]) * np.sqrt(lam)), atol=1e-14)
    with pytest.raises(ValueError, match=r"positive semi-definite for modal damping: \(K, M\) has omega\^2 = -1"):
        Structure.with_modal_damping(np.eye(2), np.diag([-1.0, 1.0]), ratios=0.01, force=[0.0, 1.0])
    free = Structure.with_modal_damping(np.eye(2), [[1.0, -1.0], [-1.0, 1.0]], ratios=0.1, force=[0.0, 1.0])
    np.testing.assert_allclose(free.C, 0.1 * np.sqrt(2.0) * np.array([[1.0, -1.0], [-1.0, 1.0]]), atol=1e-14)
    mmwrite(str(tmp_path / "K.mtx"), sparse.csr_matrix(K))
    sparse.save_npz(tmp_path / "M.npz", sparse.csr_matrix(M))
    np.savez(tmp_path / "both.npz", M=M, K=K)
    s1 = Structure.from_files(tmp_path / "M.npz", tmp_path / "K.mtx", force=[0.0, 1.0], rayleigh=(0.1, 0.0))
    s2 = Structure.from_files(f"{tmp_path / 'both.npz'}:M", f"{tmp_path / 'both.npz'}:K", force=[0.0, 1.0],
                              rayleigh=(0.1, 0.0))
    np.testing.assert_allclose(s1.K.toarray(), s2.K)
    np.testing.assert_allclose(s1.C.toarray(), 0.1 * M)
    with pytest.raises(ValueError, match="path must name an existing matrix file"):
        load_matrix(tmp_path / "nope.mtx")


def test_craig_bampton_exact_statically_and_converging_dynamically():
    n = 30
    K = 2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    K[-1, -1] = 1.0
    f = np.zeros(n)
    f[-1] = 1.0
    s = Structure.with_rayleigh(np.eye(n), K, alpha=0.0, beta=0.01, force=f)
    exact = np.linalg.solve(K, f)
    for modes in (2, 8):
        r = s.reduce([0, n - 1], modes=modes)
        np.testing.assert_allclose(np.linalg.solve(r.K, r.force)[:2], exact[[0, n - 1]], rtol=1e-12)
    w = 0.5 * s.natural_frequencies()[0]
    full = np.linalg.solve(K - w * w * np.eye(n) + 1j * w * s.C, f)[n - 1]
    errs = []
    for modes in (2, 8, n - 2):  # n - 2: every fixed-interface mode, an exact change of basis
        r = s.reduce([0, n - 1], modes=modes)
        errs.append(abs(np.linalg.solve(r.K - w * w * r.M + 1j * w * r.C, r.force)[1] - full) / abs(full))
    assert errs[0] > errs[1] > 1e3 * errs[2] and errs[2] < 1e-12


# ------------------------------------------------------------------ properties
@st.composite
def problems(draw):
    n = draw(st.integers(1, 3))
    m = draw(st.lists(st.floats(0.5, 2.0), min_size=n, max_size=n))
    k = draw(st.lists(st.floats(0.5, 2.0), min_size=n, max_size=n))
    K = np.zeros((n, n))
    for i, ki in enumerate(k):  # a chain: ground-0-1-...
        K[i, i] += ki
        if i:
            K[i - 1, i - 1] += ki
            K[i - 1, i] -= ki
            K[i, i - 1] -= ki
    zeta = draw(st.floats(0.002, 0.05))
    force = np.zeros(n)
    force[draw(st.integers(0, n - 1))] = draw(st.floats(0.005, 0.05))
    s = Structure.with_rayleigh(np.diag(m), K, alpha=0.0, beta=2 * zeta, force=force)
    contacts = []
    for _ in range(draw(st.integers(1, 2))):
        el = Macroslip(draw(st.floats(0.2, 3.0)), draw(st.floats(0.002, 0.05)))
        i = draw(st.integers(0, n - 1))
        j = draw(st.integers(-1, n - 1))
        contacts.append(Contact(el, dofs=(i, j)) if 0 <= j != i else Contact(el, dof=i))
    return s, contacts, draw(st.integers(1, 3))


@settings(deadline=None, max_examples=12)  # each example traces a branch
@given(problems())
def test_random_structures_every_point_finite_every_failure_a_message(problem):
    s, contacts, H = problem
    frf = frequency_response(s, contacts, omega_range=(0.2, 2.5), harmonics=H, n_t=64, steps=Steps(max_steps=80))
    assert len(frf.omega) == len(frf.amplitude) == len(frf.stable) == len(frf.residual_norm)
    assert np.all(np.isfinite(frf.omega)) and np.all(np.isfinite(frf.amplitude))
    assert np.all(frf.residual_norm <= frf.newton_tol)
    assert np.all(np.isfinite(frf.exponents))
    assert frf.success or (isinstance(frf.message, str) and frf.message)
    if len(frf):
        assert np.all(np.isfinite(frf.coefficients(0)))
        assert frf.coefficients(0).shape == (len(frf), H + 1)


@pytest.mark.parametrize("classical", [True, False])
def test_modal_compliance_is_the_inverse_dynamic_stiffness(classical):
    from hbm.structure import modal_compliance

    rng = np.random.default_rng(4)
    A = rng.normal(size=(5, 5))
    K = A @ A.T + 5 * np.eye(5)
    M = np.diag(rng.uniform(1.0, 2.0, 5))
    C = 0.01 * K + 0.02 * M
    if not classical:
        C[0, 1] += 0.01
        C[1, 0] += 0.01
    lam, V, B = modal_compliance(M, C, K)
    for s in (0.0, 0.7j, 0.3 + 1.1j):
        np.testing.assert_allclose(V @ np.diag(1 / (s - lam)) @ B, np.linalg.inv(K + s * C + s * s * M), atol=1e-13)


def test_a_reduced_structure_refuses_a_boolean_T_and_a_kept_that_is_no_sequence_by_name():
    """T of booleans was taken as ones and zeros, and kept=3 was a TypeError 'not iterable'."""
    from hbm import ReducedStructure

    n = 6
    K = 2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    r = Structure(np.eye(n), 0.01 * np.eye(n), K, force=np.eye(n)[-1]).reduce([0, 5], modes=2)
    with pytest.raises(ValueError, match=r"^T must be a 6 x 4 matrix of numbers, got T=array\(\[\[ True"):
        ReducedStructure(r.M, r.C, r.K, force=r.force, T=np.ones(r.T.shape, dtype=bool), kept=r.kept, full=r.full)
    with pytest.raises(ValueError, match=r"^kept must be a sequence of DOF indices of full, got kept=3$"):
        ReducedStructure(r.M, r.C, r.K, force=r.force, T=r.T, kept=3, full=r.full)


@pytest.mark.parametrize("kw, name", [(dict(force=[True, 1.0]), "force"), (dict(M=[[1.0, False], [False, 1.0]]), "M")])
def test_a_boolean_among_the_numbers_of_a_list_is_refused_by_name(kw, name):
    """numpy reads [True, 1.0] as [1.0, 1.0]: the booleans were taken among the numbers of a list."""
    args = dict(M=np.eye(2), C=0.01 * np.eye(2), K=np.eye(2), force=[0.0, 1.0], **{})
    args.update(kw)
    with pytest.raises(ValueError, match=rf"^{name} must be a .*of .*numbers, got {name}=\["):
        Structure(args.pop("M"), args.pop("C"), args.pop("K"), **args)
