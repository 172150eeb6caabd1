"""One sector of a tuned bladed disk (``hbm.CyclicStructure``) against the whole disk.

The whole disk (``disk.full()``, block-circulant, a plain ``Structure`` with every contact) is the
independent answer: its balance has no rotation in it.  A sector's solution, spread over the disk
(sector j's harmonic h its own times ``exp(-i h 2 pi EO j / N)``), must satisfy the whole disk's
balance, and the whole disk's Newton solve from it must stay there; the linear part is checked
against the dense block-circulant solve written here.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import hbm
from contact_models import Bar, Contact2D, Macroslip, TwoRegionMicroslip, UniformLoad
from hbm.balance.layout import from_complex, next_sector_operator, to_complex
from hbm.balance.residual import HarmonicBalance
from hbm.balance.stability import HillProblem

N = 6
BAR = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)


def sector(sectors: int = N, engine_order: int = 2, force: complex = 8.0) -> hbm.CyclicStructure:
    """Disk DOF 0 (to ground, to its neighbours), blade DOF 1, platform DOF 2 (kg, N/m)."""
    kg, kb, kp, kc = 5e8, 1e8, 2e8, 2e8
    K = np.array([[kg + kb + 2 * kc, -kb, 0.0], [-kb, kb + kp, -kp], [0.0, -kp, kp]])
    K1 = np.zeros((3, 3))
    K1[0, 0] = -kc
    M = np.diag([0.5, 0.0877, 0.01])
    M1 = np.zeros((3, 3))
    M1[0, 0] = 0.02  # a consistent-mass-like coupling, to exercise M_next
    return hbm.CyclicStructure(M, 2e-7 * K, K, sectors=sectors, engine_order=engine_order, force=[0.0, force, 0.0],
                               K_next=K1, C_next=2e-7 * K1, M_next=M1)


def dense_disk(disk: hbm.CyclicStructure) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The whole disk's M, C, K and force, built block by block (independent of ``full()``)."""
    n, S = disk.n, disk.sectors
    out = []
    for A, A1 in ((disk.M, disk.M_next), (disk.C, disk.C_next), (disk.K, disk.K_next)):
        B = np.zeros((n * S, n * S))
        for j in range(S):
            k = (j + 1) % S
            B[j * n:(j + 1) * n, j * n:(j + 1) * n] += A
            B[j * n:(j + 1) * n, k * n:(k + 1) * n] += A1
            B[k * n:(k + 1) * n, j * n:(j + 1) * n] += A1.T
        out.append(B)
    f = np.concatenate([disk.force * np.exp(-2j * math.pi * disk.engine_order * j / S) for j in range(S)])
    return (*out, f)


def contact(name: str, eo: int) -> tuple[hbm.Contact, int]:
    """A damper between neighbours and the harmonics to compare at."""
    pair = (2, 2) if eo else (2, 1)  # at EO 0 the neighbours' platforms move alike
    normal = (1, 1) if eo else (0, 0)
    if name == "jenkins":
        return hbm.Contact(Macroslip(stiffness=4e7, slip_force=20.0), dofs=pair, next_sector=True), 3
    if name == "contact3d":
        from contact_models import Contact3D

        second = (0, 0) if eo else (1, 2)  # the second tangential direction: no DOF shared side by side
        return hbm.Contact(Contact3D(kt=4e7, kn=4e7, mu=0.3, n0=60.0), dofs=pair, second_dofs=second,
                           normal_dofs=normal, next_sector=True), 3
    if name == "contact2d":
        return hbm.Contact(Contact2D(kt=4e7, kn=4e7, mu=0.3, n0=60.0), dofs=pair, normal_dofs=normal,
                           next_sector=True), 3
    return hbm.Contact(TwoRegionMicroslip(BAR, UniformLoad(N=60.0)), dofs=pair, next_sector=True), 1


def spread(sector_balance: HarmonicBalance, X: np.ndarray, disk: hbm.CyclicStructure,
           full_balance: HarmonicBalance) -> np.ndarray:
    """The sector's coefficients X (n_a, L) on the whole disk's condensation DOFs: sector j's are
    ``T^j X`` (it lags sector 0 by j phi)."""
    T = next_sector_operator(sector_balance.H, disk.sector_angle)
    out = np.zeros((full_balance.na, sector_balance.L))
    for i, d in enumerate(full_balance.dofs):
        j, local = divmod(d, disk.n)
        out[i] = np.linalg.matrix_power(T, j) @ X[sector_balance.dofs.index(local)]
    return out


def newton_full(full_balance: HarmonicBalance, X: np.ndarray, omega: float) -> np.ndarray:
    """The whole disk's balance solved at fixed omega by Newton from X (n_a, L)."""
    x = X.ravel().copy()
    for _ in range(30):
        R, J = full_balance.physical(np.append(x, omega))
        dx = np.linalg.solve(J[:, :-1], -R)
        x += dx
        if np.max(np.abs(dx)) <= 1e-13 * np.max(np.abs(x)):
            break
    return x.reshape(X.shape)


# ---------------------------------------------------------------------------- the sector against the disk
@pytest.mark.parametrize("eo", [0, 2, N // 2])
@pytest.mark.parametrize("name", ["jenkins", "contact2d", "contact3d", "microslip"])
def test_sector_frf_equals_full_disk(name, eo):
    disk = sector(engine_order=eo)
    c, H = contact(name, eo)
    w = disk.natural_frequencies()[0]
    # n_t a multiple of N: every sector's motion is sector 0's shifted by whole samples, so the disk's
    # AFT sees the sector's samples (otherwise they differ by the sampling error, ``docs/bladed_disks.md``)
    frf = hbm.frequency_response(disk, [c], omega_range=(0.85 * w, 1.25 * w), harmonics=H, n_t=64 * N, tol=None,
                                 stability=False, response_dof=1)
    assert frf.success
    full, full_contacts = disk.full()
    assert len(full_contacts) == N
    fb = HarmonicBalance(full, full_contacts, harmonics=H, n_t=frf._problem.n_t, response_dof=1)
    sb = frf._problem
    peak = float(np.max(frf.amplitude))
    picks = np.unique(np.r_[np.linspace(0, len(frf) - 1, 5).astype(int), np.argmax(frf.amplitude)])
    for i in picks:
        Xs, w_i = frf._X[i], float(frf.omega[i])
        Xf = spread(sb, Xs, disk, fb)
        # the sector's point is the whole disk's: its residual vanishes there ...
        R, _ = fb.physical(np.append(Xf.ravel(), w_i))
        assert np.max(np.abs(R)) <= 1e-9 * peak
        # ... and the whole disk's own Newton solve, started a little off, returns to it
        Xn = newton_full(fb, Xf * 1.02, w_i)
        r = fb.dofs.index(1)
        assert math.hypot(*Xn[r, 1:3]) == pytest.approx(frf.amplitude[i], abs=1e-6 * peak)
        # every sector j moves as sector 0 turned by j phi (here: the blades)
        for j in range(N):
            cj = to_complex(Xn[fb.dofs.index(j * 3 + 1)][None])[0] if j * 3 + 1 in fb.dofs else None
            if cj is not None:
                c0 = to_complex(Xs[sb.dofs.index(1)][None])[0]
                h = np.arange(H + 1)
                assert np.allclose(cj, c0 * np.exp(-1j * h * disk.sector_angle * j), atol=1e-6 * peak)


@pytest.mark.slow
def test_sector_peak_equals_full_disk_curve():
    """The whole disk traced by the same front door (about 20 s): the same peak."""
    disk = sector(engine_order=2)
    c, H = contact("jenkins", 2)
    w = disk.natural_frequencies()[0]
    rng = (0.85 * w, 1.25 * w)
    frf = hbm.frequency_response(disk, [c], omega_range=rng, harmonics=H, tol=None, stability=False, response_dof=1)
    full, fc = disk.full()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ff = hbm.frequency_response(full, fc, omega_range=rng, harmonics=H, tol=None, stability=False, response_dof=1)
    p1, p2 = frf.peak(), ff.peak()
    assert p2.amplitude == pytest.approx(p1.amplitude, rel=1e-6)
    assert p2.omega == pytest.approx(p1.omega, rel=1e-6)


def test_full_disk_is_block_circulant_with_phased_force():
    disk = sector(engine_order=2)
    c, _ = contact("contact2d", 2)
    full, fc = disk.full([c])
    M, C, K, f = dense_disk(disk)
    for A, B in ((full.M, M), (full.C, C), (full.K, K)):
        assert np.array_equal(A.toarray(), B)
    assert np.allclose(full.force, f, rtol=0, atol=1e-12)
    # sector j's contact joins platform of j + 1 and platform of j, the normal pair likewise
    assert [x.dofs for x in fc] == [(((j + 1) % N) * 3 + 2, j * 3 + 2) for j in range(N)]
    assert [x.normal_dofs for x in fc] == [(((j + 1) % N) * 3 + 1, j * 3 + 1) for j in range(N)]
    # EO 0: the force is the same real force on every sector
    full0, _ = sector(engine_order=0).full()
    assert not np.iscomplexobj(full0.force)


def test_full_defaults_to_the_solved_contacts():
    disk = sector(engine_order=2)
    c, _ = contact("jenkins", 2)
    w = disk.natural_frequencies()[0]
    hbm.frequency_response(disk, [c], omega_range=(0.95 * w, 1.05 * w), harmonics=1, tol=None, stability=False)
    _, fc = disk.full()
    assert len(fc) == N and all(x.element is c.element for x in fc)


def test_nodal_diameter_frequencies_are_the_disks():
    disk = sector(engine_order=2)
    M, C, K, f = dense_disk(disk)
    from scipy.linalg import eigh

    w_full = np.sqrt(eigh(K, M, eigvals_only=True))
    w_nd = np.sort(np.concatenate([disk.natural_frequencies(k) for k in range(N)]))
    assert np.allclose(w_full, w_nd, rtol=1e-10)
    assert disk.nodal_diameter(1) == 2 and disk.nodal_diameter(3) == 0


# ---------------------------------------------------------------------------- the linear part: closed form
@pytest.mark.parametrize("eo", [0, 1, N // 2])
def test_linear_sector_equals_dense_disk_solve(eo):
    """No contact, then a stuck (linear) Jenkins spring between neighbours: harmonic 1 of the sector
    is the dense disk's ``Z(omega)^-1 f`` (sector 0's DOFs)."""
    disk = sector(engine_order=eo)
    M, C, K, f = dense_disk(disk)
    w = disk.natural_frequencies()[0]
    k = 3e7
    spring = hbm.Contact(Macroslip(stiffness=k, slip_force=1e9), dofs=(2, 1), next_sector=True)
    Ks = K.copy()
    for j in range(N):  # the spring between (j + 1, 2) and (j, 1), added by hand
        a, b = ((j + 1) % N) * 3 + 2, j * 3 + 1
        Ks[a, a] += k
        Ks[b, b] += k
        Ks[a, b] -= k
        Ks[b, a] -= k
    for contacts, KK in (([], K), ([spring], Ks)):
        frf = hbm.frequency_response(disk, contacts, omega_range=(0.8 * w, 1.3 * w), harmonics=1, tol=None,
                                     stability=False, response_dof=1)
        assert frf.success
        for dof in (0, 1, 2):
            got = frf.coefficients(dof)[:, 1]
            want = np.array([np.linalg.solve(KK - wi**2 * M + 1j * wi * C, f)[dof] for wi in frf.omega])
            assert np.max(np.abs(got - want)) <= 1e-7 * np.max(np.abs(want))  # the Newton tolerance


def test_complex_force_is_a_time_shift():
    """A phase psi on every force component shifts the steady response in time: the amplitudes stay,
    with a friction contact too; the linear response is ``Z^-1 f``."""
    M = np.diag([1.0, 0.5])
    K = np.array([[3.0, -1.0], [-1.0, 1.0]])
    C = 0.01 * K
    f = np.array([0.05, 0.02])
    c = [hbm.Contact(Macroslip(stiffness=1.0, slip_force=0.01), dofs=(1, 0))]
    psi = 0.7
    a = hbm.frequency_response(hbm.Structure(M, C, K, force=f), c, omega_range=(0.4, 2.0), harmonics=3, tol=None,
                               stability=False)
    b = hbm.frequency_response(hbm.Structure(M, C, K, force=f * np.exp(1j * psi)), c, omega_range=(0.4, 2.0),
                               harmonics=3, tol=None, stability=False)
    assert a.peak().amplitude == pytest.approx(b.peak().amplitude, rel=1e-8)
    lin = hbm.frequency_response(hbm.Structure(M, C, K, force=[0.05, 0.02j]), None, omega_range=(0.4, 2.0),
                                 harmonics=1, tol=None, stability=False)
    want = np.array([np.linalg.solve(K - w**2 * M + 1j * w * C, [0.05, 0.02j])[1] for w in lin.omega])
    assert np.allclose(lin.coefficients(1)[:, 1], want, rtol=0, atol=1e-10 * np.max(np.abs(want)))
    # one DOF with a complex force: the condensed form, the same amplitude as the real force
    one = [hbm.Structure([[1.0]], [[0.01]], [[1.0]], force=[v]) for v in (0.05, 0.05j)]
    peaks = [hbm.frequency_response(s, [hbm.Contact(Macroslip(1.0, 0.01), dof=0)], omega_range=(0.5, 2.0),
                                    harmonics=1, tol=None, stability=False).peak().amplitude for s in one]
    assert peaks[1] == pytest.approx(peaks[0], rel=1e-8)


# ---------------------------------------------------------------------------- stability
def test_hill_sector_families_equal_full_disk_exponents():
    """The sector's exponents (every family mu = 2 pi m / N) are the whole disk's Hill exponents."""
    disk = sector(engine_order=2)
    c, H = contact("jenkins", 2)
    w = disk.natural_frequencies()[0]
    frf = hbm.frequency_response(disk, [c], omega_range=(0.9 * w, 1.1 * w), harmonics=H, tol=None, response_dof=1)
    i = int(np.argmax(frf.amplitude))
    lam_s = frf.exponents[i]
    assert lam_s.shape == (2 * disk.n * N,)
    full, fc = disk.full()
    fb = HarmonicBalance(full, fc, harmonics=H, n_t=frf._problem.n_t, response_dof=1)
    Xf = spread(frf._problem, frf._X[i], disk, fb)
    L = fb.L
    dF = np.zeros((full.n * L, full.n * L))
    idx = (np.asarray(fb.dofs)[:, None] * L + np.arange(L)[None, :]).ravel()
    dF[np.ix_(idx, idx)] = fb.perturbation_jacobian(Xf, float(frf.omega[i]))
    lam_f = HillProblem(full.M.toarray(), full.C.toarray(), full.K.toarray(), H).exponents(float(frf.omega[i]), dF)
    assert lam_f[0].real == pytest.approx(lam_s[0].real, abs=1e-9 * float(frf.omega[i]))
    assert np.allclose(np.sort(lam_s.real), np.sort(lam_f.real), atol=1e-4 * float(frf.omega[i]) * 1e-3)


# ---------------------------------------------------------------------------- invalid input
def test_invalid_input_names_the_parameter():
    M, K = np.eye(2), np.array([[2.0, -1.0], [-1.0, 1.0]])
    ok = dict(sectors=4, engine_order=1, force=[0.0, 1.0])
    with pytest.raises(ValueError, match="sectors"):
        hbm.CyclicStructure(M, 0 * M, K, **{**ok, "sectors": 1})
    with pytest.raises(ValueError, match="sectors"):
        hbm.CyclicStructure(M, 0 * M, K, **{**ok, "sectors": 4.0})
    with pytest.raises(ValueError, match="engine_order"):
        hbm.CyclicStructure(M, 0 * M, K, **{**ok, "engine_order": 1.5})
    with pytest.raises(ValueError, match="K_next"):
        hbm.CyclicStructure(M, 0 * M, K, **ok, K_next=np.eye(3))
    with pytest.raises(ValueError, match="M_next"):
        hbm.CyclicStructure(M, 0 * M, K, **ok, M_next=-2.0 * np.eye(2))  # the disk's mass not positive definite
    assert hbm.CyclicStructure(M, 0 * M, K, **{**ok, "engine_order": 9}).engine_order == 1  # reduced mod N
    assert hbm.CyclicStructure(M, 0 * M, K, **{**ok, "engine_order": -1}).engine_order == 3
    el = Macroslip(1.0, 0.1)
    with pytest.raises(ValueError, match="next_sector"):
        hbm.Contact(el, dof=0, next_sector=True)
    with pytest.raises(ValueError, match="next_sector"):
        hbm.Contact(el, dofs=(0, 1), next_sector="yes")
    with pytest.raises(ValueError, match="dofs"):
        hbm.Contact(el, dofs=(1, 1))  # one DOF twice only across sectors
    assert hbm.Contact(el, dofs=(1, 1), next_sector=True).dofs == (1, 1)
    plain = hbm.Structure(M, 0.01 * M, K, force=[0.0, 1.0])
    with pytest.raises(ValueError, match="next_sector"):
        hbm.frequency_response(plain, [hbm.Contact(el, dofs=(0, 1), next_sector=True)], omega_range=(0.5, 1.0))
    with pytest.raises(ValueError, match="reduce"):
        hbm.CyclicStructure(M, 0 * M, K, **ok).reduce([0], modes=1)


# ---------------------------------------------------------------------------- the example
def test_bladed_disk_example(tmp_path):
    """The gallery script on 6 sectors at H = 1: the tuned whole disk has the sector's peak, the
    damper's chart has its optimum inside the loads, and mistuning raises the largest blade's peak."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "examples"))
    out = __import__("bladed_disk").main(outdir=tmp_path, small=True)
    t, w = out["tuned_peak"], out["whole_peak"]
    assert t.interior and t.converged
    assert w.amplitude == pytest.approx(t.amplitude, rel=1e-9)
    assert w.omega == pytest.approx(t.omega, rel=1e-9)
    loads, chart = out["chart"]
    assert chart[1] < min(chart[0], chart[-1]) < out["free_peak"]
    assert out["mistuned_max"] > t.amplitude
    assert all(Path(p).is_file() for p in out["paths"])


def _random_point(sb: HarmonicBalance, scale: float, seed: int = 1) -> np.ndarray:
    X = np.random.default_rng(seed).normal(size=(sb.na, sb.L)) * scale
    X[:, 3:] *= 0.1  # higher harmonics smaller
    return X


@pytest.mark.parametrize("name", ["jenkins", "contact2d", "contact3d", "microslip", "allmode"])
def test_sector_residual_is_the_disks_at_any_point(name):
    """At any coefficients (not only a solution), the whole disk's residual at the spread sector point
    is the sector's residual spread: the reduction is exact for every element, the all-mode bar too."""
    disk = sector(engine_order=2)
    if name == "allmode":
        from contact_models import AllModeMicroslip

        c = hbm.Contact(AllModeMicroslip(BAR, UniformLoad(N=60.0), cells=16, harmonics=7, n_t=64 * N), dofs=(2, 2),
                        next_sector=True)
        H = 3
    else:
        c, H = contact(name, 2)
    w = 1.1 * float(disk.natural_frequencies()[0])
    sb = HarmonicBalance(disk, [c], harmonics=H, n_t=64 * N, response_dof=1)
    full, fc = disk.full([c])
    fb = HarmonicBalance(full, fc, harmonics=H, n_t=64 * N, response_dof=1)
    X = _random_point(sb, 3e-7)
    Rs, Js = sb.physical(np.append(X.ravel(), w))
    Rf, Jf = fb.physical(np.append(spread(sb, X, disk, fb).ravel(), w))
    want = spread(sb, Rs.reshape(sb.na, sb.L), disk, fb).ravel()
    assert np.max(np.abs(Rf - want)) <= 1e-9 * np.max(np.abs(Rs))
    # the Jacobian's omega column too (the tangent of the continuation)
    want_w = spread(sb, Js[:, -1].reshape(sb.na, sb.L), disk, fb).ravel()
    assert np.max(np.abs(Jf[:, -1] - want_w)) <= 1e-7 * np.max(np.abs(Js[:, -1]))


@pytest.mark.parametrize("name", ["jenkins", "contact2d", "contact3d"])
def test_sector_jacobian_against_differences(name):
    """dR/dX of the sector's balance (the rotations on both sides) against central differences."""
    disk = sector(engine_order=2)
    c, H = contact(name, 2)
    w = 1.1 * float(disk.natural_frequencies()[0])
    sb = HarmonicBalance(disk, [c], harmonics=H, n_t=64 * N, response_dof=1)
    X = _random_point(sb, 3e-7, seed=4).ravel()
    _, J = sb.physical(np.append(X, w))
    h = 1e-12
    fd = np.column_stack([(sb.physical(np.append(X + h * e, w))[0] - sb.physical(np.append(X - h * e, w))[0]) / (2 * h)
                          for e in np.eye(X.size)])
    assert np.allclose(J[:, :-1], fd, rtol=1e-4, atol=1e-4 * np.max(np.abs(fd)))


@pytest.mark.parametrize("contacts, message", [
    (3, r"^contacts must be a contact element or a sequence of hbm.Contact, got contacts=3$"),  # was: not iterable
    ("x", r"^contacts must be a contact element \(a contact_models.ContactElement\), an hbm.Contact or a sequence "
          r"of hbm.Contact, got contacts='x'$"),
])
def test_the_whole_disk_refuses_contacts_that_are_no_contacts_by_name(contacts, message):
    K = np.array([[3.0, -1.0], [-1.0, 1.0]])
    disk = hbm.CyclicStructure(np.eye(2), 0.01 * np.eye(2), K, sectors=6, engine_order=2, force=[0.0, 1.0],
                               K_next=np.array([[-1.0, 0.0], [0.0, 0.0]]))
    with pytest.raises(ValueError, match=message):
        disk.full(contacts)
    one = hbm.Contact(Macroslip(stiffness=1.0, slip_force=0.1), dof=0)  # one Contact, as frequency_response takes it
    assert [c.dofs for c in disk.full(one)[1]] == [(2 * j,) for j in range(6)]
