"""The one harmonic balance: one front function, one result type, for a blade and a structure.

A blade is its one-DOF structure; the balance evaluates a one-DOF system at H = 1 in floats and
every other problem in the condensed form.  These tests check that both evaluations solve the
same equation (a physical identity that sends the same blade through each), that the choice is
made by the problem and not by the system's type, and that every public name imports from its package.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import contact_models
import hbm
import hbm.balance.residual as residual
from contact_models import Bar, Macroslip, TwoRegionMicroslip, UniformLoad
from hbm import Blade, Contact, FrequencyResponse, HarmonicBalance, Structure, frequency_response


def blade():
    return Blade.from_modal(frequency=1.0, damping_ratio=2e-3, mass=1.0, force=0.01)


def test_two_half_jenkins_in_parallel_equal_one_jenkins():
    """Two Jenkins elements (k/2, F/2) in parallel are one Jenkins (k, F): the blade with the pair
    is solved in the condensed form, with the one in the one-DOF form; same branch."""
    one = frequency_response(blade(), Macroslip(1.0, 0.02), omega_range=(0.6, 1.8), harmonics=1)
    s = blade().as_structure()
    pair = [Contact(Macroslip(0.5, 0.01), dof=0), Contact(Macroslip(0.5, 0.01), dof=0)]
    two = frequency_response(s, pair, omega_range=(0.6, 1.8), harmonics=1)
    assert one._problem.one_dof and not two._problem.one_dof
    p1, p2 = one.peak(), two.peak()
    assert p2.omega == pytest.approx(p1.omega, rel=1e-7)
    assert p2.amplitude == pytest.approx(p1.amplitude, rel=1e-6)
    # every point of the pair's branch solves the one-DOF balance of the single element
    hb = HarmonicBalance(blade(), Macroslip(1.0, 0.02))
    R = np.array([hb.physical([xc, xs, w])[0] for xc, xs, w in zip(two.x_c, two.x_s, two.omega)])
    assert np.max(np.hypot(R[:, 0], R[:, 1])) / 0.01 < 1e-7


def test_the_form_follows_the_problem_not_the_system_type():
    el = Macroslip(1.0, 0.02)
    assert HarmonicBalance(blade(), el).one_dof
    assert HarmonicBalance(blade().as_structure(), [Contact(el, dof=0)]).one_dof  # a Structure of one DOF
    assert not HarmonicBalance(blade(), el, harmonics=3).one_dof
    two_dof = Structure(np.eye(2), 0.01 * np.eye(2), [[2.0, -1.0], [-1.0, 1.0]], force=[0.0, 1.0])
    assert not HarmonicBalance(two_dof, [Contact(el, dof=0)]).one_dof


def test_one_result_type_with_harmonics_and_stability():
    bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    frf = frequency_response(Blade(mass=0.0877147, stiffness=1.0e8, damping=11.8467, force=8.0),
                             TwoRegionMicroslip(bar, UniformLoad(N=100.0)), omega_range=(3.2e4, 4.4e4))
    mh = frequency_response(blade(), Macroslip(1.0, 0.02), omega_range=(0.6, 1.8), harmonics=3)
    for r, H in ((frf, 1), (mh, 3)):
        assert type(r) is FrequencyResponse and r.harmonics == H
        c = r.coefficients(0)
        assert c.shape == (len(r), H + 1)
        assert np.allclose(np.abs(c[:, 1]), r.amplitude, rtol=1e-15, atol=0.0)
        assert r.stable.shape == (len(r),) and r.exponents.shape[0] == len(r)
    assert hbm.MultiHarmonicResponse is FrequencyResponse
    assert frf.stable.all()  # a single DOF at H = 1 without folds is stable everywhere


def test_a_bare_element_needs_a_one_dof_system():
    two_dof = Structure(np.eye(2), 0.01 * np.eye(2), [[2.0, -1.0], [-1.0, 1.0]], force=[0.0, 1.0])
    with pytest.raises(ValueError, match="a bare element attaches only to a one-DOF system"):
        frequency_response(two_dof, Macroslip(1.0, 0.02), omega_range=(0.5, 1.5))
    with pytest.raises(ValueError, match="system must be an hbm.Blade or an hbm.Structure"):
        frequency_response("blade", None, omega_range=(0.5, 1.5))
    with pytest.raises(ValueError, match="contacts must hold hbm.Contact objects, got 3"):
        frequency_response(two_dof, [3], omega_range=(0.5, 1.5))


@pytest.mark.parametrize("kwargs, message", [
    # before, a zero, negative, NaN, infinite or string scale was taken, to divide the unknowns by later
    (dict(x_ref=0.0), r"^x_ref must be positive, got x_ref=0.0$"),
    (dict(x_ref=float("nan")), r"^x_ref must be finite, got x_ref=nan$"),
    (dict(x_ref="1"), r"^x_ref must be a number, got x_ref='1'$"),
    (dict(omega_ref=-1.0), r"^omega_ref must be positive, got omega_ref=-1.0$"),
    (dict(omega_ref=float("inf")), r"^omega_ref must be finite, got omega_ref=inf$"),
])
def test_the_balance_names_a_bad_scale(kwargs, message):
    s = Structure(np.eye(2), 0.01 * np.eye(2), [[2.0, -1.0], [-1.0, 2.0]], force=[1.0, 0.0])
    with pytest.raises(ValueError, match=message):
        HarmonicBalance(s, [Contact(Macroslip(1.0, 0.1), dof=0)], **kwargs)


def test_a_single_contact_past_the_structure_is_refused_by_name():
    s = Structure(np.eye(2), 0.01 * np.eye(2), [[2.0, -1.0], [-1.0, 2.0]], force=[1.0, 0.0])
    with pytest.raises(ValueError, match=r"^dof must be a DOF index in 0..1, got dof=5 in "):
        HarmonicBalance(s, Contact(Macroslip(1.0, 0.1), dof=5))  # one Contact, not in a list


@pytest.mark.parametrize("package", [hbm, contact_models])
def test_every_public_name_still_imports_from_its_package(package):
    with warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)
        for name in package.__all__:
            assert getattr(package, name) is not None, name


def test_a_very_stiff_jenkins_on_the_default_blade_traces_at_one_harmonic():
    """A Jenkins element of 1e12 N/m (slip amplitude 1e-12 m) slips everywhere on the default blade:
    the stuck start is far off, the force homotopy starts the branch.  Gross slip: f_s -> 0,
    f_c = 4 F_s/pi, so at the blade's own resonance a = (F - 4 F_s/pi)/(c omega_n)."""
    from hbm.cli.cases import default_case

    case = default_case()
    b = case.blade
    frf = frequency_response(b, Macroslip(stiffness=1e12, slip_force=1.0), omega_range=case.omega_range)
    assert frf.success and len(frf) > 100
    wn = np.sqrt(b.stiffness / b.mass)
    pk = frf.peak()
    assert pk.amplitude == pytest.approx((b.force - 4.0 / np.pi) / (b.damping * wn), rel=1e-5)
    assert pk.omega == pytest.approx(wn, rel=1e-5)


def test_the_chain_at_three_harmonics_traces_with_the_default_sampling():
    """The 3-DOF chain with a Jenkins element at H = 3: an explicit H takes the default preset's
    sampling (512), which traces the whole window, and the peak agrees with n_t = 2048."""
    K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    s = Structure(np.eye(3), 0.004 * K, K, force=[0.0, 0.0, 0.01])
    contacts = [Contact(Macroslip(1.0, 0.02), dof=0)]
    frf = frequency_response(s, contacts, omega_range=(0.3, 0.8), harmonics=3)
    assert frf.success and frf.n_t == 512 and frf.omega[-1] == pytest.approx(0.8)
    ref = frequency_response(s, contacts, omega_range=(0.3, 0.8), harmonics=3, n_t=2048).peak()
    assert frf.peak().amplitude == pytest.approx(ref.amplitude, rel=1e-4)
    assert frf.peak().omega == pytest.approx(ref.omega, rel=1e-3)


@pytest.mark.parametrize("element", [Macroslip(1.0, 0.02), Macroslip(1.0, 0.02, slider="from rest")],
                         ids=["centred", "from rest"])
def test_the_one_element_fast_path_is_the_general_condensed_balance(element):
    # one element between the one DOF and ground: G F in the real layout (a F + b F_swapped) must be
    # the complex product of the general assembly, for R and for every column of J (omega included)
    s = Structure(np.eye(1), np.array([[0.004]]), np.eye(1), force=[0.01])
    hb = HarmonicBalance(s, [Contact(element, dof=0)], harmonics=3, n_t=256)
    assert hb._grounded_one
    rng = np.random.default_rng(3)
    for _ in range(5):
        u = np.append(rng.normal(scale=0.05, size=hb.unknowns - 1), rng.uniform(0.6, 1.8))
        R, J = hb(u)
        hb._grounded_one = False
        R0, J0 = hb(u)
        hb._grounded_one = True
        np.testing.assert_allclose(R, R0, rtol=0.0, atol=1e-15 * np.abs(R0).max())
        np.testing.assert_allclose(J, J0, rtol=0.0, atol=1e-15 * np.abs(J0).max())


def test_the_fast_path_is_only_for_one_element_to_ground():
    K = np.array([[2.0, -1.0], [-1.0, 1.0]])
    s = Structure(np.eye(2), 0.004 * K, K, force=[0.0, 0.01])
    between = HarmonicBalance(s, [Contact(Macroslip(1.0, 0.02), dofs=(0, 1))], harmonics=3)
    two = HarmonicBalance(s, [Contact(Macroslip(1.0, 0.02), dof=0)], harmonics=3)  # response DOF 1 too
    assert not between._grounded_one and not two._grounded_one


def test_hill_reuses_the_balances_element_jacobians_bit_for_bit(monkeypatch):
    # Hill's method asks the elements for dF/dX again at the branch's points: where the balance
    # evaluated the same displacement it gets that call's Jacobian (no new element call), equal bit for
    # bit to a fresh evaluation; the kept Jacobians stay within their byte bound, the oldest dropped
    K = np.array([[2.0, -1.0], [-1.0, 1.0]])
    s = Structure(np.eye(2), 0.004 * K, K, force=[0.0, 0.05])
    contacts = [Contact(Macroslip(1.0, 0.02), dof=0), Contact(Macroslip(2.0, 0.01), dofs=(0, 1))]
    hb = HarmonicBalance(s, contacts, harmonics=3, n_t=128)
    hb.keep_jacobians = True  # as frequency_response sets it where Hill's method will run
    fresh = HarmonicBalance(s, contacts, harmonics=3, n_t=128)
    X = np.zeros((2, hb.L))
    X[0, 1:3], X[1, 1:3] = (0.08, 0.03), (0.2, -0.05)  # both elements slip
    hb.forces(X, 1.3)
    calls = hb.nfev
    dF = hb.perturbation_jacobian(X, 1.3)
    assert hb.nfev == calls  # nothing evaluated again
    dF0 = fresh.perturbation_jacobian(X, 1.3)
    assert fresh.nfev == 2 and np.abs(dF0).max() > 0.0
    np.testing.assert_array_equal(dF, dF0)
    fresh.forces(X, 1.3)
    assert fresh._jacobians == {}  # a balance not asked to keeps none
    monkeypatch.setattr(residual, "JACOBIAN_KEEP_BYTES", 3 * hb.L**2 * 8)  # room for three
    for factor in (1.0, 1.1, 1.2, 1.3):
        hb.forces(X * factor, 1.3)
    assert hb._jacobian_bytes <= 3 * hb.L**2 * 8 and len(hb._jacobians) == 3
    calls = hb.nfev
    hb.perturbation_jacobian(X * 1.3, 1.3)
    assert hb.nfev == calls
    hb.perturbation_jacobian(X, 1.3)  # dropped: evaluated again
    assert hb.nfev == calls + 2
    hb.forget_jacobians()  # what a FrequencyResponse does once Hill's method has run
    assert hb._jacobians == {} and hb._jacobian_bytes == 0
    frf = frequency_response(s, contacts, omega_range=(0.9, 1.3), harmonics=3, n_t=128)
    assert frf._problem._jacobians and frf.stable.size == len(frf) and frf._problem._jacobians == {}
    frf = frequency_response(s, contacts, omega_range=(0.9, 1.3), harmonics=3, n_t=128, stability=False)
    assert frf._problem._jacobians == {}  # kept for Hill's method only: none without stability
    # one element on the one condensation DOF to ground (its own fast path) keeps them the same way
    one = HarmonicBalance(Structure(np.eye(1), np.array([[0.004]]), np.eye(1), force=[0.05]),
                          [Contact(Macroslip(1.0, 0.02), dof=0)], harmonics=3, n_t=128)
    one.keep_jacobians = True
    assert one._grounded_one
    u = np.zeros(one.unknowns)
    u[1:3], u[-1] = (0.08, 0.03), 1.3
    one(u)
    calls = one.nfev
    dF = one.perturbation_jacobian(u[:-1].reshape(1, -1), 1.3)
    assert one.nfev == calls
    np.testing.assert_array_equal(dF, one._attach[0][0].harmonic_force_unchecked(u[:-1], 1.3, 128, one.rtol)[1])
