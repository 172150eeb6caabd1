"""AllModeMicroslip: closed-form limits, the exact Jacobians, the block solver, time
integration, users' loads."""

import math
import re
import warnings

import numpy as np
import pytest

from contact_models import (AccuracyWarning, AllModeMicroslip, Bar, FunctionLoad, Macroslip, NumericalMicroslip,
                            QuadraticLoad, SampledLoad, ThreeRegionMicroslip, TwoRegionMicroslip, UniformLoad)
from contact_models.allmode.solve import FixedBar
from contact_models.allmode.balance import (BlockTridiagonal, aft_matrices, jenkins_harmonic, jenkins_jacobian,
                                            jenkins_periodic, jenkins_state, rows_product)

BAR = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
UNIFORM = UniformLoad(N=100.0)
CONCAVE = QuadraticLoad.from_ratio(N=100.0, ratio=12.0)
WC = BAR.omega_c
KS = BAR.k_star


def wavy():
    return FunctionLoad(lambda x: 2000.0 * (1.0 + 0.8 * np.cos(6.0 * np.pi * x / BAR.L)))


# ---------------------------------------------------------------- the periodic Jenkins map
def _jenkins_by_cycling(u, kc, p, cycles=4):
    """Independent: the return map run from rest over several periods (steady after one reversal)."""
    f, z = 0.0, 0.0
    out = np.empty_like(u)
    for _ in range(cycles):
        for k, uk in enumerate(u):
            t = kc * (uk - z)
            if abs(t) > p:
                t = math.copysign(p, t)
                z = uk - t / kc
            out[k] = t
    return out


def test_jenkins_periodic_matches_cycling_from_rest_when_it_slips():
    rng = np.random.default_rng(1)
    E, P, _ = aft_matrices(5, 64)
    U = rng.normal(size=(6, 11))
    U[:, 0] = 0.0
    kc = np.full(6, 3.0)
    p = np.array([0.5, 1.0, 2.0, 4.0, 0.1, 0.0])
    u = U @ E.T
    f, *_ = jenkins_periodic(u, kc, p)
    for i in range(6):
        if kc[i] * np.ptp(u[i]) > 2 * p[i]:  # slips: the steady cycle is unique
            np.testing.assert_allclose(f[i], _jenkins_by_cycling(u[i], kc[i], p[i]), atol=1e-13)
        else:  # never slips: slider at the centre of the motion (the documented convention)
            np.testing.assert_allclose(f[i], kc[i] * (u[i] - 0.5 * (u[i].max() + u[i].min())), atol=1e-13)


def test_jenkins_periodic_over_half_a_period_for_odd_harmonics():
    """Half-wave antisymmetric motions (odd harmonics, wiggles from the higher ones included):
    marched over half the period and negated, the force is the independent cycling from rest's
    (and the never-slipping rows' closed form), and the stick/slip states are the full march's."""
    rng = np.random.default_rng(3)
    E, P, order = aft_matrices(9, 72)
    U = rng.normal(size=(7, 19)) / (1.0 + order)
    U[:, order % 2 == 0] = 0.0
    kc = np.full(7, 3.0)
    p = np.array([5.7, 0.3, 1.0, 2.0, 1.6, 0.0, 50.0])  # slips little, much, at once; the last never
    u = U @ E.T
    f, stuck, anchor, never = jenkins_periodic(u, kc, p, half=True)
    f_full, stuck_full, anchor_full, never_full = jenkins_periodic(u, kc, p)
    assert np.array_equal(never, never_full) and never[-1] and not never[:-1].any()
    assert np.array_equal(stuck, stuck_full) and np.array_equal(anchor[~never], anchor_full[~never])
    np.testing.assert_allclose(f, f_full, atol=1e-13)
    for i in range(6):
        np.testing.assert_allclose(f[i], _jenkins_by_cycling(u[i], kc[i], p[i]), atol=1e-13)
    np.testing.assert_allclose(f[6], kc[6] * (u[6] - 0.5 * (u[6].max() + u[6].min())), atol=1e-13)


def test_jenkins_harmonic_jacobian_against_finite_differences():
    rng = np.random.default_rng(2)
    E, P, _ = aft_matrices(4, 48)
    U = rng.normal(size=(4, 9))
    kc = np.full(4, 2.0)
    p = np.array([0.3, 1.0, 2.5, 50.0])  # the last never slips
    T, J, _ = jenkins_harmonic(U, kc, p, E, P)
    h = 1e-7
    for j in range(9):
        dU = np.zeros_like(U)
        dU[:, j] = h
        fd = (jenkins_harmonic(U + dU, kc, p, E, P, jacobian=False)[0]
              - jenkins_harmonic(U - dU, kc, p, E, P, jacobian=False)[0]) / (2 * h)
        np.testing.assert_allclose(J[:, :, j], fd, atol=1e-6)



def test_jenkins_jacobian_by_runs_is_the_sum_over_every_stuck_sample():
    """The Jacobian from prefix sums per stick run (wrapping runs included) against the sum over
    every sample of kc stuck_k P[:, k] (E_k - E_anchor(k))^T, straight from the return map; and the
    state kept without the Jacobian gives the same one."""
    rng = np.random.default_rng(5)
    E, P, _ = aft_matrices(7, 64)
    U = rng.normal(size=(40, 15)) * np.exp(-0.3 * np.arange(15))  # many nodes, several runs, various phases
    kc = rng.uniform(0.5, 2.0, 40)
    p = rng.uniform(0.05, 1.5, 40)
    _, J, _ = jenkins_harmonic(U, kc, p, E, P)
    _, stuck, anchor, never = jenkins_periodic(U @ E.T, kc, p)
    wraps = 0
    for i in np.flatnonzero(~never):
        G = (E - E[anchor[i]]) * stuck[i][:, None]
        np.testing.assert_allclose(J[i], kc[i] * P @ G, rtol=0, atol=1e-13 * kc[i])
        wraps += bool(stuck[i, -1] and stuck[i, 0])
    assert wraps >= 3 and np.sum(never) >= 1 and np.sum(~never) >= 20
    T2, slip, state = jenkins_state(U, kc, p, E, P)
    np.testing.assert_array_equal(jenkins_jacobian(state, kc, E, P), J)


def test_rows_product_is_the_product_in_blocks():
    rng = np.random.default_rng(6)
    A, B = rng.normal(size=(300, 32)), rng.normal(size=(32, 248))
    np.testing.assert_allclose(rows_product(A, B), A @ B, rtol=1e-13, atol=1e-12)
    assert rows_product(A[:3], B).shape == (3, 248)


@pytest.mark.parametrize("odd", [False, True])
def test_jenkins_harmonic_jacobian_at_rest_is_the_stuck_stiffness(odd):
    """At rest (a constant motion: its max and min not unique) a node that never slips is a spring
    kc on every harmonic and nothing in the mean, in the full basis and in the odd one (whose first
    coefficient is cos 1, not the mean): the limit of the Jacobian at a small odd motion."""
    E, P, order = aft_matrices(3, 16)
    idx = np.flatnonzero(order % 2 == 1) if odd else np.arange(order.size)
    E, P = E[:, idx], P[idx]
    kc, p = np.array([2.0, 2.0]), np.array([1.0, 1.0])
    U = np.zeros((2, idx.size))  # row 0 at rest; row 1 a constant offset (the full basis only)
    if not odd:
        U[1, 0] = 5.0
    _, J, _ = jenkins_harmonic(U, kc, p, E, P)
    expected = 2.0 * np.diag((order[idx] > 0).astype(float))
    np.testing.assert_allclose(J[0], expected, atol=1e-12)
    np.testing.assert_allclose(J[1], expected, atol=1e-12)
    small = np.zeros((1, idx.size))
    small[0, list(order[idx]).index(1) + 1] = 1e-3  # sin 1, far below slip
    _, Js, _ = jenkins_harmonic(small, kc[:1], p[:1], E, P)
    h = order[idx] % 2 == 1
    np.testing.assert_allclose(J[0][np.ix_(h, h)], Js[0][np.ix_(h, h)], atol=1e-12)

def test_block_thomas_solves_like_a_dense_solver():
    rng = np.random.default_rng(3)
    n, s, c = 7, 5, -2.0
    B = rng.normal(size=(n, s, s)) + 8.0 * np.eye(s)
    A = np.zeros((n * s, n * s))
    for i in range(n):
        A[i * s:(i + 1) * s, i * s:(i + 1) * s] = B[i]
        if i:
            A[i * s:(i + 1) * s, (i - 1) * s:i * s] = c * np.eye(s)
            A[(i - 1) * s:i * s, i * s:(i + 1) * s] = c * np.eye(s)
    r = rng.normal(size=(n, s, 3))
    x = BlockTridiagonal(B, c).solve(r)
    np.testing.assert_allclose(x.reshape(n * s, 3), np.linalg.solve(A, r.reshape(n * s, 3)), atol=1e-12)


# ---------------------------------------------------------------- closed-form limits
@pytest.mark.parametrize("w", [0.0, 0.3, 0.76, 0.95, 1.2])
def test_stuck_is_the_exact_dynamic_stiffness_of_the_discretised_bar(w):
    """Below slip the Newton solve (not the shortcut) gives the discretised bar's stiffness, also
    above the cut-off sqrt(k/(rho A)) = 0.758 omega_c, with no higher harmonics (the lumped bar, the
    one ``NumericalMicroslip`` integrates)."""
    el = AllModeMicroslip(BAR, UNIFORM, cells=30, harmonics=5, linear="lumped")
    num = NumericalMicroslip(BAR, UNIFORM, cells=30)
    omega = w * WC
    a = 0.9 * el.slip_amplitude(omega)
    sol = el.solve(a, omega)
    assert sol.success
    assert sol.f_s == pytest.approx(num.stuck_stiffness(omega) * a, rel=1e-10)
    assert abs(sol.f_c) < 1e-12 * KS * a
    assert np.max(np.abs(sol.F[3:])) < 1e-12 * KS * a
    assert el.slip_amplitude(omega) == num.slip_amplitude(omega)


@pytest.mark.parametrize("cells, w", [(c, w) for c in (3, 8, 30) for w in (0.0, 0.3, 0.76, 0.95, 1.2)]
                         + [(8, 3.0), (30, 3.0)])
def test_the_exact_bar_stuck_is_the_continuous_bar_on_any_mesh(w, cells):
    """Below slip the exact segments give the continuous bar's dynamic stiffness (``Bar.stuck_stiffness``,
    the closed form of the bar on its stuck shear layer) on 3 cells as on 30, below and above the cut-off,
    and the nodes' displacements are the continuous bar's shape there (Newton solve, not the shortcut)."""
    el = AllModeMicroslip(BAR, UNIFORM, cells=cells, harmonics=5)
    omega = w * WC
    a = 0.9 * el.slip_amplitude(omega)
    sol = el.solve(a, omega)
    K = float(BAR.stuck_stiffness(omega))
    assert sol.success and sol.f_s == pytest.approx(K * a, rel=1e-10)
    assert abs(sol.f_c) < 1e-12 * KS * a and np.max(np.abs(sol.F[3:])) < 1e-12 * KS * a
    fine = AllModeMicroslip(BAR, UNIFORM, cells=10 * cells, harmonics=5).solve(a, omega)
    np.testing.assert_allclose(sol.U[:, 2], fine.U[::10, 2], rtol=0, atol=1e-10 * a)


@pytest.mark.parametrize("load, cls", [(UNIFORM, TwoRegionMicroslip), (CONCAVE, ThreeRegionMicroslip),
                                       (QuadraticLoad.from_ratio(N=100.0, ratio=0.9), TwoRegionMicroslip)])
def test_quasi_static_limit_is_the_exact_single_mode_solution(load, cls):
    """At omega -> 0 the single-mode solution is exact; the all-mode bar agrees to its O(h^2) mesh
    error (5e-5 k* a at 40 cells for the uniform load, docs/validation.md quasi-static table: 4e-5
    at 50 cells for concave12) plus the harmonic truncation."""
    el = AllModeMicroslip(BAR, load, cells=40, harmonics=15)
    ref = cls(BAR, load)
    amin = ref.slip_amplitude(0.0)
    a = np.array([1.5, 3.0, 10.0, 30.0]) * amin
    fs, fc = el.fourier(a, 1e-6 * WC)
    fs0, fc0 = ref.fourier(a, 0.0)
    assert np.max(np.abs(fs - fs0) / (KS * a)) < 2e-4
    assert np.max(np.abs(fc - fc0) / (KS * a)) < 2e-4


def test_gross_slip_limit():
    """Far past gross slip (quasi-static) the bar slides as a whole: f_s/a -> beta EA/(EA + beta L)
    and f_c -> (4 mu/pi) int q(x) phi(x) dx with phi = (EA + beta x)/(EA + beta L) the sliding
    bar's shape, both with an O(a_min/a) correction (friction inside the bar) on the lumped bar; the exact
    segments' foundation is the consistent one at the driven node, so there f_s keeps -k h^2 / (6 EA) =
    -1.0e-4 at 40 cells while the bar slides (an O(h^2) error that falls with the cells, not with a)."""
    el = AllModeMicroslip(BAR, UNIFORM, cells=40, harmonics=15, linear="lumped")
    exact = AllModeMicroslip(BAR, UNIFORM, cells=40, harmonics=15)
    EA, beta, L = BAR.EA, BAR.beta, BAR.L
    k_slide = beta * EA / (EA + beta * L)
    fc_lim = 4.0 * BAR.mu * 100.0 / math.pi * (EA + 0.5 * beta * L) / (EA + beta * L)
    errs = []
    for r in (1e3, 1e4):
        a = r * 7.5e-7
        fs, fc = el.fourier(a, 0.0)
        errs.append(np.abs([fs / (k_slide * a) - 1.0, fc / fc_lim - 1.0]))
    # the departures fall at least like 1/a (f_c: the stick phase after each reversal, about
    # 1.6 a_min/a here; f_s faster) and are small at 1e4 a_min
    assert np.all(errs[1] < 3e-4)
    assert np.all(errs[0] / errs[1] > 5.0)
    fs, fc = exact.fourier(1e4 * 7.5e-7, 0.0)
    h = L / 40
    assert fs / (k_slide * 1e4 * 7.5e-7) - 1.0 == pytest.approx(-BAR.k * h**2 / (6 * EA), rel=0.1)
    assert abs(fc / fc_lim - 1.0) < 3e-4


# ---------------------------------------------------------------- derivatives (implicit function theorem)
def test_fourier_derivatives_against_finite_differences():
    el = AllModeMicroslip(BAR, UNIFORM, cells=12, harmonics=5)
    for w, r in ((0.3, 3.0), (0.8, 10.0)):
        a = r * 7.5e-7
        fs, fc, dfs, dfc = el.fourier_derivatives(a, w * WC)
        h = 1e-6 * a
        fsp, fcp = el.fourier(a + h, w * WC)
        fsm, fcm = el.fourier(a - h, w * WC)
        assert dfs == pytest.approx((fsp - fsm) / (2 * h), rel=1e-5, abs=1e-6 * KS)
        assert dfc == pytest.approx((fcp - fcm) / (2 * h), rel=1e-5, abs=1e-6 * KS)


def test_harmonic_force_jacobians_against_finite_differences():
    """A general multi-harmonic end motion (static part, even harmonics) at H = 3 inside the
    element's own H = 5: dF/dX and dF/domega by the implicit function theorem."""
    el = AllModeMicroslip(BAR, CONCAVE, cells=10, harmonics=5)
    X = 1e-6 * np.array([0.2, 0.5, 0.8, 0.1, -0.2, 0.15, 0.05])
    omega = 0.4 * WC
    F, dX, dw = el.harmonic_force(X, omega)
    assert F.shape == (7,) and dX.shape == (7, 7) and dw.shape == (7,)
    scale = KS * 1e-6
    for j in range(7):
        e = np.zeros(7)
        e[j] = 1e-6 * 1e-6
        fd = (el.harmonic_force(X + e, omega)[0] - el.harmonic_force(X - e, omega)[0]) / (2e-12)
        np.testing.assert_allclose(dX[:, j], fd, atol=1e-5 * KS)
    h = 1e-5 * omega
    fd = (el.harmonic_force(X, omega + h)[0] - el.harmonic_force(X, omega - h)[0]) / (2 * h)
    np.testing.assert_allclose(dw * omega, fd * omega, atol=1e-5 * scale)


def test_symmetric_end_motion_solved_in_the_odd_basis_has_the_full_jacobian():
    """harmonic_force at a half-wave symmetric X (odd harmonics only) solves in the odd basis and
    adds the even block; it equals the full-basis solve's Jacobian, static and even columns too."""
    el = AllModeMicroslip(BAR, CONCAVE, cells=10, harmonics=5)
    X = np.zeros(7)
    X[2], X[5] = 2e-6, -0.3e-6
    F, dX, dw = el.harmonic_force(X, 0.4 * WC)
    full = el._solve(np.pad(X, (0, 4)), 0.4 * WC, 5, odd=False)
    np.testing.assert_allclose(F, full.F[:7], atol=1e-10 * np.max(np.abs(F)))
    np.testing.assert_allclose(dX, full.dF_dX[:7, :7], atol=1e-9 * KS)
    np.testing.assert_allclose(dw, full.dF_domega[:7], atol=1e-9 * np.max(np.abs(dw)))
    assert np.max(np.abs(dX[0::4, 0::4])) > 0.01 * KS  # the even block is not empty



def test_even_coefficients_of_rounding_size_are_solved_in_the_odd_basis():
    """Even coefficients at 1e-15 of the first harmonic (what a balance's linear solves leave of a
    half-wave symmetric response) are rounding: the bar is solved in the odd basis and the force
    gets its first-order even part; it equals the full-basis solve of the same X to Newton's
    tolerance.  Even coefficients at 1e-9 are motion: the full basis, as before."""
    X = np.zeros(7)
    X[2], X[5] = 2e-6, -0.3e-6
    X[0], X[3], X[4] = 3e-21, -2e-21, 1e-21
    el = AllModeMicroslip(BAR, CONCAVE, cells=10, harmonics=5)
    F, dX, dw = el.harmonic_force(X, 0.4 * WC)
    assert set(el._level(10, 5)._cache) == {True}  # one solve, in the odd basis
    full = el._solve(np.pad(X, (0, 4)), 0.4 * WC, 5, odd=False)
    np.testing.assert_allclose(F, full.F[:7], atol=1e-10 * np.max(np.abs(F)))
    np.testing.assert_allclose(dX, full.dF_dX[:7, :7], atol=1e-9 * KS)
    np.testing.assert_allclose(dw, full.dF_domega[:7], atol=1e-9 * np.max(np.abs(dw)))
    even = [0, 3, 4]
    assert F[0] != 0.0 and F[even] == pytest.approx(dX[np.ix_(even, even)] @ X[even], rel=1e-12)  # not 0
    X[0] = 2e-15
    motion = AllModeMicroslip(BAR, CONCAVE, cells=10, harmonics=5)
    F2 = motion.harmonic_force(X, 0.4 * WC)[0]
    assert set(motion._level(10, 5)._cache) == {False}
    assert F2[0] == pytest.approx(float(dX[0] @ X), rel=1e-6)  # the static force of the static motion


def test_a_three_harmonic_balance_keeps_the_bar_in_the_odd_basis():
    """The blade at H = 3 with the all-mode bar: the balance's even coefficients are rounding (0 here: the
    element leaves the even block of dF/dX out, so the balance's even block is the identity and its Newton
    steps set them to 0), and no nested solve is in the full basis (63 coefficients a node instead of 32 at
    H = 31)."""
    from hbm import Contact, Structure, frequency_response
    from hbm.cli.cases import default_case

    b = default_case().blade
    el = AllModeMicroslip(default_case().element.bar, UNIFORM, cells=8, harmonics=7)
    structure = Structure([[b.mass]], [[b.damping]], [[b.stiffness]], force=[b.force])
    frf = frequency_response(structure, [Contact(el, dof=0)], (38300.0, 38900.0), harmonics=3)
    assert frf.success and len(frf.omega) > 5
    assert set(el._level(8, 7)._cache) == {True}
    even = np.abs(frf.coefficients(0)[:, [0, 2]])
    assert np.max(even) <= 1e-12 * np.max(np.abs(frf.coefficients(0)[:, 1]))


def test_without_the_even_block_the_force_and_the_odd_block_are_the_whole_answer():
    """``harmonic_force_unchecked(..., even_block=False)``: for a half-wave symmetric motion the same
    force, odd block and omega-derivative as the whole answer, the even-even block 0; a later call that
    asks for the block gets it (the kept answer without it is not returned); a motion with even harmonics
    gets the whole answer anyway; an element without ``even_block_optional`` answers whole."""
    X = np.zeros(7)
    X[2], X[5] = 2e-6, -0.3e-6
    w = 0.4 * WC
    el = AllModeMicroslip(BAR, CONCAVE, cells=10, harmonics=5)
    F, dX, dw = el.harmonic_force_unchecked(X, w, 64, 1e-6, False)
    Fx, dXx, dwx = AllModeMicroslip(BAR, CONCAVE, cells=10, harmonics=5).harmonic_force(X, w)
    odd, even = [1, 2, 5, 6], [0, 3, 4]
    np.testing.assert_allclose(F, Fx, rtol=0, atol=1e-12 * np.max(np.abs(Fx)))
    np.testing.assert_allclose(dX[np.ix_(odd, odd)], dXx[np.ix_(odd, odd)], rtol=0, atol=1e-12 * KS)
    np.testing.assert_allclose(dw, dwx, rtol=0, atol=1e-12 * np.max(np.abs(dwx)))
    assert not dX[np.ix_(even, even)].any() and np.max(np.abs(dXx[np.ix_(even, even)])) > 0.01 * KS
    np.testing.assert_allclose(el.harmonic_force(X, w)[1], dXx, rtol=0, atol=1e-12 * KS)  # asked whole: whole
    X[0], X[3] = 0.2e-6, 0.1e-6  # even harmonics: the full basis, whole
    whole = AllModeMicroslip(BAR, CONCAVE, cells=10, harmonics=5).harmonic_force(X, w)[1]
    np.testing.assert_allclose(el.harmonic_force_unchecked(X, w, 64, 1e-6, False)[1], whole, rtol=0, atol=1e-9 * KS)
    jen = Macroslip(stiffness=2.0, slip_force=1.0)
    for a, b in zip(jen.harmonic_force_unchecked(X * 1e6, 1.0, 64, 1e-6, False), jen.harmonic_force(X * 1e6, 1.0)):
        np.testing.assert_array_equal(a, b)


def test_hill_on_an_all_mode_curve_is_that_of_the_balance_that_kept_whole_jacobians(monkeypatch):
    """A frequency response keeps the all-mode bar's Jacobians without their even block and fills it at
    its points for Hill's method: the curve, its exponents and its stability are those of the balance that
    kept the whole Jacobians (the element without ``even_block_optional``)."""
    from hbm import Contact, Structure, frequency_response
    from hbm.cli.cases import default_case

    case = default_case()
    b = case.blade
    structure = Structure([[b.mass]], [[b.damping]], [[b.stiffness]], force=[b.force])

    def run():
        el = AllModeMicroslip(case.element.bar, UNIFORM, cells=8, harmonics=7)
        frf = frequency_response(structure, [Contact(el, dof=0)], (38300.0, 38900.0), harmonics=3)
        return frf, frf.exponents, frf.stable

    frf, exponents, stable = run()
    monkeypatch.setattr(AllModeMicroslip, "even_block_optional", False)
    ref, ref_exponents, ref_stable = run()
    assert frf.success and len(frf.omega) == len(ref.omega) > 5
    np.testing.assert_allclose(frf.amplitude, ref.amplitude, rtol=1e-10)
    np.testing.assert_array_equal(stable, ref_stable)
    np.testing.assert_allclose(exponents, ref_exponents, rtol=0, atol=1e-8 * np.max(np.abs(ref_exponents)))


def test_hill_fills_the_even_block_of_the_kept_all_mode_jacobians_without_a_nested_solve(monkeypatch):
    """The balance keeps, with each all-mode Jacobian it traced without its even-even block, what the block
    needs (``harmonic_force_deferred``: the odd solution's nodes), and Hill's method fills the block from it:
    no nested solve at the curve's points, and the exponents (to 1e-10 of the largest) and the stability of
    the element asked again whole at the same points (``even_block=True``: a new solve each)."""
    from hbm import Contact, Structure, frequency_response
    from hbm.cli.cases import default_case
    from hbm.result import STABILITY_TOL

    case = default_case()
    b = case.blade
    structure = Structure([[b.mass]], [[b.damping]], [[b.stiffness]], force=[b.force])
    el = AllModeMicroslip(case.element.bar, UNIFORM, cells=8, harmonics=7)
    frf = frequency_response(structure, [Contact(el, dof=0)], (38300.0, 38900.0), harmonics=3)
    assert frf.success and len(frf) > 5
    solves, solve = [0], FixedBar.solve

    def counted(self, *args, **kw):
        solves[0] += 1
        return solve(self, *args, **kw)

    monkeypatch.setattr(FixedBar, "solve", counted)
    exponents, stable = frf.exponents, frf.stable
    assert solves[0] == 0
    assert frf._problem._jacobians == {}  # forgotten once Hill's method has run: asked again below
    again = frf._hill(range(len(frf)))
    assert solves[0] > 5  # every point where the bar slips: a new solve
    np.testing.assert_allclose(exponents, again, rtol=0, atol=1e-10 * np.max(np.abs(again)))
    np.testing.assert_array_equal(stable, again[:, 0].real <= STABILITY_TOL * frf.omega)


def test_end_at_rest_is_exact_with_the_stuck_jacobian_and_no_warning():
    """X = 0 (the start of the solver's force homotopy): F = 0 exactly, so its estimate is 0 (not
    0/0) on the first rung, and dF/dX is the stuck bar's dynamic stiffness on cos 1 and sin 1 alike
    (the continuous bar's, ``Bar.stuck_stiffness``: the exact segments on any mesh)."""
    omega = 0.29 * WC
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        chosen = AllModeMicroslip(BAR, UNIFORM)
        sol = chosen.solve(np.zeros(3), omega)
        F, dX, _ = AllModeMicroslip(BAR, UNIFORM, cells=10, harmonics=3).harmonic_force(np.zeros(3), omega)
    assert sol.success and sol.relative_error == 0.0 and not np.any(sol.F)
    assert sol.cells < 64 and sol.H == 7  # the first rung, not the top of the ladder
    k = float(BAR.stuck_stiffness(omega))
    assert not np.any(F)
    np.testing.assert_allclose(np.diag(dX)[1:], [k, k], rtol=1e-10)
    assert abs(dX[1, 2]) < 1e-10 * k and abs(dX[2, 1]) < 1e-10 * k



def test_load_zero_at_a_node_slips_at_once_without_a_nan():
    """A load that vanishes at the driven end: that node slips at any motion, so a_min = 0 on every
    mesh, and its relative estimate is 0 (not 0/0); the stuck stiffness is still the bar's."""
    load = FunctionLoad(lambda x: 4000.0 * (1.0 - x / BAR.L))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        el = AllModeMicroslip(BAR, load)
        cells, k, a_min, rel = el._stuck_data(0.2 * WC)
        err = float(el.model_error(1e-7, 0.2 * WC))
    assert a_min == 0.0 and el.slip_amplitude(0.2 * WC) == 0.0
    assert k == pytest.approx(float(BAR.stuck_stiffness(0.2 * WC)), rel=1e-10)
    assert 0.0 <= rel < el.tol and 0.0 <= err < el.tol

def test_frf_whose_first_point_slips_near_the_peak_starts():
    """The default blade (hbm.cli.cases) with the all-mode bar, started at 38600 rad/s where the
    bar already slips (a = 2 a_min, 200 rad/s below the peak): Newton from the stuck guess fails
    there, so the start comes from the force homotopy from X = 0.  It starts, its first point
    solves the blade's balance (k - m w^2 + i c w) x + F_1(x) = f with F_1 from the element, and it
    is the point the branch reaches from a stuck start at 38000 rad/s; no RuntimeWarning leaks."""
    from hbm import frequency_response
    from hbm.cli.cases import default_case

    b = default_case().blade

    def bar():
        return AllModeMicroslip(BAR, UNIFORM, cells=10, harmonics=3)

    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        warnings.simplefilter("ignore", AccuracyWarning)  # the coarse mesh's model error, reported
        frf = frequency_response(b, bar(), (38600.0, 38700.0), harmonics=1)
        below = frequency_response(b, bar(), (38000.0, 38600.0), harmonics=1)
    assert frf.success and len(frf) > 2 and frf.omega[0] == 38600.0
    assert below.success and below.amplitude[0] < 7.5e-7 and below.omega[-1] == 38600.0
    xc, xs, w = frf.x_c[0], frf.x_s[0], frf.omega[0]
    assert frf.amplitude[0] > 1.5 * 7.5e-7  # past the slip onset: the stuck guess is not the answer
    F, _, _ = bar().harmonic_force(np.array([0.0, xc, xs]), w)
    x = xc - 1j * xs
    r = (b.stiffness - b.mass * w * w + 1j * b.damping * w) * x + (F[1] - 1j * F[2]) - b.force
    assert abs(r) < 1e-9 * b.force
    assert xc == pytest.approx(below.x_c[-1], rel=1e-7)
    assert xs == pytest.approx(below.x_s[-1], rel=1e-7)

# ---------------------------------------------------------------- against time integration
@pytest.mark.parametrize("w, r", [(0.5, 3.0), (0.8, 10.0), (1.0, 3.0)])  # 1.0: at omega_c itself
def test_agrees_with_time_integration_on_the_same_mesh(w, r):
    """Same 20-cell bar, NumericalMicroslip at 256 steps per cycle: its time-step error is at most
    3e-4 k* a there (docs/validation.md convergence table, 256 -> 512 steps), the all-mode
    harmonic truncation at H = 15 below 1e-4 (decay of the harmonics)."""
    el = AllModeMicroslip(BAR, UNIFORM, cells=20, harmonics=15)
    num = NumericalMicroslip(BAR, UNIFORM, cells=20, steps_per_cycle=256)
    a = r * 7.5e-7
    sol = el.solve(a, w * WC)
    ref = num.simulate(a, w * WC)
    assert ref.converged and sol.success
    assert abs(sol.f_s - ref.f_s) < 1e-3 * KS * a
    assert abs(sol.f_c - ref.f_c) < 1e-3 * KS * a


def test_a_load_the_single_mode_elements_refuse():
    """A strongly convex load (ratio 0.7) also slips at the unloaded end x = 0 before gross slip,
    which the two- and three-region elements refuse; the all-mode bar takes it and agrees with the
    quasi-static time integration on the same mesh (exact return map, rate independent) to its
    harmonic truncation (2e-4 k* a at H = 15, docs/validation.md)."""
    load = QuadraticLoad.from_ratio(N=100.0, ratio=0.7)
    with pytest.raises(ValueError, match="x = 0 starts slipping"):
        TwoRegionMicroslip(BAR, load).slip_amplitude(0.0)
    el = AllModeMicroslip(BAR, load, cells=30, harmonics=15)
    num = NumericalMicroslip(BAR, load, cells=30)
    a = np.array([3.0, 10.0]) * el.slip_amplitude(0.0)
    fs, fc = el.fourier(a, 0.0)
    fs0, fc0 = num.fourier(a, 0.0)
    assert np.max(np.abs(fs - fs0) / (KS * a)) < 3e-4 and np.max(np.abs(fc - fc0) / (KS * a)) < 3e-4


def test_wavy_load_gives_seven_regions_and_agrees_with_time_integration():
    load = wavy()
    el = AllModeMicroslip(BAR, load, cells=30, harmonics=15)
    a = 3.0 * el.slip_amplitude(0.0)
    theta, x, slip = el.stick_slip_map(a, 0.5 * WC)
    regions = [1 + int(np.count_nonzero(c[1:] != c[:-1])) for c in slip.T]
    assert max(regions) >= 7
    ref = NumericalMicroslip(BAR, load, cells=30, steps_per_cycle=256).simulate(a, 0.5 * WC)
    sol = el.solve(a, 0.5 * WC)
    assert abs(sol.f_s - ref.f_s) < 1e-3 * KS * a
    assert abs(sol.f_c - ref.f_c) < 1e-3 * KS * a


# ---------------------------------------------------------------- interface, estimates, input
def test_interface_and_passivity():
    el = AllModeMicroslip(BAR, CONCAVE, cells=16, harmonics=7)
    amin = el.slip_amplitude(0.2 * WC)
    a = np.array([0.5, 2.0, 20.0]) * amin
    fs, fc = el.fourier(a, 0.2 * WC)
    assert fs[0] == pytest.approx(el.stuck_stiffness(0.2 * WC) * a[0], rel=1e-12) and fc[0] == 0.0
    assert np.all(fc[1:] > 0)
    x, f = el.hysteresis(a[1], 0.2 * WC, n=801)
    theta = np.linspace(-0.5 * np.pi, 1.5 * np.pi, 801)
    # the loop's first harmonic is (f_s, f_c) (trapezoid rule on the periodic samples)
    assert 2 / 800 * np.sum(f[:-1] * np.sin(theta[:-1])) == pytest.approx(fs[1], rel=2e-3)
    assert 2 / 800 * np.sum(f[:-1] * np.cos(theta[:-1])) == pytest.approx(fc[1], rel=2e-2)
    c = el.solve(a[1], 0.2 * WC).harmonics
    assert c.shape == (8,) and abs(c[3]) > 0.01 * abs(c[1])  # a third harmonic, no even ones
    assert abs(c[2]) < 1e-9 * abs(c[1])


def test_warm_start_along_amplitude():
    el = AllModeMicroslip(BAR, UNIFORM, cells=16, harmonics=7)
    el.solve(3.0e-6, 0.3 * WC)
    assert el.solve(3.03e-6, 0.3 * WC).iterations <= 1


@pytest.mark.parametrize("rel", [1e-9, 1e-7])
def test_tangent_start_is_the_next_state_while_the_pattern_holds(rel):
    # The cached state moved along its tangent to a nearby motion and frequency (amplitude, phase,
    # third harmonic and omega all changed) is the state a cold solve finds there, to rounding: the
    # forces are linear in U while no sample changes between stick and slip.  Newton takes no step.
    X0 = np.zeros(15)
    X0[1], X0[2], X0[5] = 1e-7, 3e-6, 2e-8
    X1 = X0.copy()
    X1[1] += 3e-6 * rel
    X1[2] *= 1 + rel
    X1[5] -= 1e-8 * rel
    w0, w1 = 0.3 * WC, 0.3 * WC * (1 + rel)
    bar = FixedBar(BAR, UNIFORM.on(BAR.L), 16, 7, 64)
    bar.solve(X0, w0, odd=True)
    b = bar.basis(True)
    guess = bar.tangent_guess(X1[b.idx], w1, b)
    warm = bar.solve(X1, w1, odd=True)
    cold = FixedBar(BAR, UNIFORM.on(BAR.L), 16, 7, 64).solve(X1, w1, odd=True)
    assert cold.iterations >= 2 and warm.iterations == 0
    scale = float(np.max(np.abs(cold.U)))
    assert np.max(np.abs(guess - cold.U[:-1, b.idx])) < 1e-12 * scale
    assert np.max(np.abs(warm.F - cold.F)) < 1e-11 * np.max(np.abs(cold.F))
    # a step too long for its pattern is corrected by Newton to the same state
    X2 = X0 * 1.02
    assert np.allclose(bar.solve(X2, w0, odd=True).F,
                       FixedBar(BAR, UNIFORM.on(BAR.L), 16, 7, 64).solve(X2, w0, odd=True).F, rtol=1e-10, atol=0)


def test_error_estimate_brackets_the_mesh_error():
    el = AllModeMicroslip(BAR, UNIFORM, cells=10, harmonics=7)
    fine = AllModeMicroslip(BAR, UNIFORM, cells=80, harmonics=7)
    a = 3.0 * 7.5e-7
    sol = el.solve(a, 0.5 * WC, estimate_error=True)
    err = float(np.max(np.abs(sol.F[1:3] - fine.solve(a, 0.5 * WC).F[1:3])))
    assert sol.error_parts["cells"] / 3 < err < 3 * sol.error_parts["cells"]
    assert sol.error >= sol.error_parts["cells"]


def test_bad_input_is_refused_by_name():
    with pytest.raises(ValueError, match="cells"):
        AllModeMicroslip(BAR, UNIFORM, cells=1)
    with pytest.raises(ValueError, match="harmonics"):
        AllModeMicroslip(BAR, UNIFORM, harmonics=0)
    with pytest.raises(ValueError, match="n_t"):
        AllModeMicroslip(BAR, UNIFORM, harmonics=5, n_t=10)
    el = AllModeMicroslip(BAR, UNIFORM, cells=4, harmonics=2)
    with pytest.raises(ValueError, match="X"):
        el.harmonic_force(np.zeros(4), 1.0)
    with pytest.raises(ValueError, match="omega"):
        el.fourier(1e-6, -1.0)
    with pytest.raises(ValueError, match="func"):
        FunctionLoad(3.0)
    with pytest.raises(ValueError, match="values"):
        SampledLoad(x=[0.0, 1.0], values=[1.0, -1.0])


def test_sampled_load_equals_the_function_it_samples():
    x = np.linspace(0.0, BAR.L, 401)
    q = 2000.0 * (1.0 + 0.8 * np.cos(6.0 * np.pi * x / BAR.L))
    s = AllModeMicroslip(BAR, SampledLoad(x=x, values=q), cells=20, harmonics=5)
    f = AllModeMicroslip(BAR, wavy(), cells=20, harmonics=5)
    a = 3.0 * f.slip_amplitude(0.0)
    # nodes fall on sample points, so the nodal slip forces agree exactly
    np.testing.assert_allclose(s.fourier(a, 0.3 * WC), f.fourier(a, 0.3 * WC), rtol=1e-9)


# ---------------------------------------------------------------- inside the multi-harmonic solver
def test_periodic_force_is_the_synthesis_of_the_harmonic_force():
    el = AllModeMicroslip(BAR, UNIFORM, cells=10, harmonics=5)
    theta = 2 * np.pi * np.arange(16) / 16
    x = 2e-6 * np.sin(theta) + 0.4e-6 * np.cos(3 * theta)
    f, J = el.periodic_force(x, 0.3 * WC)
    X = np.zeros(15)
    X[2], X[5] = 2e-6, 0.4e-6
    F = el.harmonic_force(X, 0.3 * WC)[0]
    synth = F[0] + sum(F[2 * h - 1] * np.cos(h * theta) + F[2 * h] * np.sin(h * theta) for h in range(1, 8))
    np.testing.assert_allclose(f, synth, atol=1e-9 * np.max(np.abs(f)))
    assert J.shape == (16, 16)


def test_blade_with_the_all_mode_damper_at_three_harmonics():
    """The default blade (hbm.cli.cases) as a one-DOF structure with the all-mode bar at H = 3 near its
    peak: the multi-harmonic solver couples the bar as a substructure; its first-harmonic peak
    agrees with the single-harmonic all-mode FRF (the blade's motion is nearly harmonic: 3rd
    harmonic 0.15 % of the first, docs/validation.md)."""
    from hbm import Contact, Structure, frequency_response
    from hbm.cli.cases import default_case

    case = default_case()
    el = AllModeMicroslip(case.element.bar, UNIFORM, cells=8, harmonics=5)
    rng = (38000.0, 39500.0)
    one = frequency_response(case.blade, el, rng)
    b = case.blade
    structure = Structure([[b.mass]], [[b.damping]], [[b.stiffness]], force=[b.force])
    three = frequency_response(structure, [Contact(el, dof=0)], rng, harmonics=3)
    assert three.success
    a1, a3 = one.peak().amplitude, np.max(three.amplitude)
    assert a3 == pytest.approx(a1, rel=5e-3)
    c = three.coefficients(0)
    assert c.shape[1] == 4 and np.max(np.abs(c[:, 3])) < 0.01 * np.max(np.abs(c[:, 1]))


def test_docstring_examples():
    import doctest

    import contact_models.allmode.element
    import contact_models.loads
    import contact_models.model_range

    for mod in (contact_models.allmode.element, contact_models.loads, contact_models.model_range):
        assert doctest.testmod(mod).failed == 0, mod.__name__


@pytest.mark.parametrize("load", ["x", None])
def test_the_all_mode_bars_name_a_load_that_is_not_a_load(load):
    from contact_models import AllModeMicroslip2D

    bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    message = (r"^load must be a normal load \(UniformLoad, QuadraticLoad, FunctionLoad or SampledLoad\), "
               rf"got load={load!r}$")
    with pytest.raises(ValueError, match=message):
        AllModeMicroslip(bar, load, 8, 1)
    with pytest.raises(ValueError, match=message):
        AllModeMicroslip2D(bar, load, 1e7, 8, 1)


def test_solve_and_for_balance_name_a_bad_flag_or_harmonic_count():
    from contact_models import AllModeMicroslip2D

    bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    el = AllModeMicroslip(bar, UniformLoad(N=100.0), 8, 1)
    for solve in (el.solve, AllModeMicroslip2D(bar, UniformLoad(N=100.0), 1e7, 8, 1).solve):
        with pytest.raises(ValueError, match=r"^estimate_error must be True or False, got estimate_error='yes'$"):
            solve(1e-6, estimate_error="yes")
    for H in (0, "2", 2.5):
        with pytest.raises(ValueError, match=rf"^H must be an integer >= 1, got H={H!r}$"):
            el.for_balance(H)


def test_linear_given_an_array_is_refused_by_name():
    """``linear not in KINDS`` with an array was numpy's "truth value of an array is ambiguous", naming nothing."""
    with pytest.raises(ValueError, match=r"^linear must be one of .*, got linear=array\(\['exact', 'lumped'\]"):
        AllModeMicroslip(BAR, UniformLoad(N=100.0), linear=np.array(["exact", "lumped"]))


@pytest.mark.parametrize("omega", [1e50, 1e160])
def test_a_frequency_whose_stuck_bar_needs_more_cells_than_memory_holds_is_refused_naming_omega(omega):
    """1e50 rad/s asked for a stuck bar of 1e45 cells (numpy's 'Maximum allowed size exceeded'); above about
    1e154 rad/s (H omega)^2 overflowed in the cells' count (OverflowError: Numerical result out of range)."""
    from contact_models.allmode.segments import UnresolvedWave

    with pytest.raises(UnresolvedWave, match=rf"^omega={re.escape(repr(omega))} rad/s is too high for the bar with every mode: its stuck "
                                              r"bar needs .* cells to hold the wavelength of harmonic 1, more than "
                                              r"MAX_STUCK_CELLS = 4194304"):
        AllModeMicroslip(BAR, UniformLoad(N=100.0)).fourier(1e-6, omega)
