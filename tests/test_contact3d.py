"""``contact_models.Contact3D`` against an independent return map written here (many periods from a
relaxed spring until the slider repeats, first harmonics by FFT) on elliptic paths whose slip
direction turns, with and without separation; its reductions to ``Contact2D`` (one tangential row
zero) and to the Jenkins element (constant load, straight path, any direction); its Jacobians
against central differences; its attachment by ``hbm.Contact`` and a balance that equals the one
with ``Contact2D`` where the second direction and the normal stay at rest."""

import math
import warnings

import numpy as np
import pytest

import hbm
from contact_models import Contact2D, Contact3D, Macroslip
from contact_models.contact3d import clearance_centre

KT, KN, MU, N0 = 4.0, 3.0, 0.4, 1.0  # slip radius mu n0 / kt = 0.1


def marched(u, v, kt=KT, kn=KN, mu=MU, n0=N0, max_periods=400):
    """The return map from the slider at 0, period after period until the slider repeats to 1e-14;
    the tangential forces (2, n) of the last period.  Written from the law: the trial force
    ``kt (u - w)`` sticks inside the circle ``mu N``, else it is put back on the circle along itself."""
    w, T = np.zeros(2), np.zeros((2, u.shape[1]))
    for _ in range(max_periods):
        w_start = w.copy()
        for k in range(u.shape[1]):
            lim = mu * max(0.0, n0 + kn * v[k])
            trial = kt * (u[:, k] - w)
            size = math.sqrt(trial[0] ** 2 + trial[1] ** 2)
            if size >= lim:
                trial = trial * (lim / size) if size > 0.0 else trial
                w = u[:, k] - trial / kt
            T[:, k] = trial
        if np.max(np.abs(w - w_start)) < 1e-14:
            return T
    raise AssertionError("the marched return map did not become periodic")


def first_harmonic(f):
    c = np.fft.rfft(f, axis=-1)[..., 1] * 2.0 / f.shape[-1]
    return np.stack([c.real, -c.imag], axis=-1)  # (cos, sin) coefficients


@pytest.mark.parametrize("b", [0.15, 0.03], ids=["round", "flat"])
@pytest.mark.parametrize("v_of", [lambda th: 0.1 * np.sin(th + 0.4),  # closed all period
                                  lambda th: -0.2 + 0.5 * np.sin(th + 0.4)],  # opens part of it
                         ids=["closed", "separating"])
def test_elliptic_paths_are_the_marched_return_map(v_of, b):
    n = 16384
    th = 2.0 * np.pi * np.arange(n) / n
    u, v = np.vstack([0.3 * np.cos(th), b * np.sin(th)]), v_of(th)
    N = np.maximum(0.0, N0 + KN * v)
    assert (np.min(N) == 0.0) == (np.max(v) > 0.0 and np.min(v) < -0.2)  # the case is the one named
    ref = marched(u, v)
    sticks = (np.hypot(ref[0], ref[1]) < MU * N - 1e-12) & (N > 0.0)
    assert sticks.any() == (b < 0.1 or np.min(N) == 0.0) and not sticks.all()  # the round closed one slips always
    X = np.stack([np.fft.rfft(r)[:2] for r in (u[0], u[1], v)]) / n
    X = np.column_stack([X[:, 0].real, 2.0 * X[:, 1].real, -2.0 * X[:, 1].imag])
    F = Contact3D(KT, KN, MU, N0).harmonic_force(X, 1.0, n_t=n)[0]
    assert np.max(np.abs(F[:2, 1:] - first_harmonic(ref))) < 1e-6 * MU * N0
    assert np.max(np.abs(F[:2, 0] - np.mean(ref, axis=1))) < 1e-6 * MU * N0
    assert np.max(np.abs(F[:2, 1:])) > 0.3 * MU * N0  # a real force, not zeros on both sides
    print(f"max |dF| / (mu n0) = {np.max(np.abs(F[:2, 1:] - first_harmonic(ref))) / (MU * N0):.1e}")


def paths(n):
    th = 2.0 * np.pi * np.arange(n) / n
    return {"slip": (0.05 + 0.3 * np.cos(th) + 0.1 * np.sin(3 * th), 0.1 * np.sin(th + 0.3)),
            "stuck": (0.02 + 0.06 * np.cos(th), 0.05 * np.cos(2 * th)),
            "separating": (0.3 * np.cos(th), -0.5 + 0.3 * np.sin(th))}


@pytest.mark.parametrize("case", ["slip", "stuck", "separating"])
@pytest.mark.parametrize("row", [0, 1])
def test_one_tangential_row_zero_is_contact2d(case, row):
    n = 128
    u, v = paths(n)[case]
    x = np.zeros((3, n))
    x[row], x[2] = u, v
    f, J = Contact3D(KT, KN, MU, N0).periodic_force(x)
    f2, J2 = Contact2D(KT, KN, MU, N0).periodic_force(np.vstack([u, v]))
    keep = np.r_[row * n:(row + 1) * n, 2 * n:3 * n]
    assert np.max(np.abs(f[[row, 2]] - f2)) < 1e-12 and np.all(f[1 - row] == 0.0)
    assert np.max(np.abs(J[np.ix_(keep, keep)] - J2)) < 1e-12


@pytest.mark.parametrize("angle", [0.0, 0.5, 2.0])
@pytest.mark.parametrize("a", [0.05, 0.15, 0.4])  # stuck, near and far past the slip amplitude 0.1
def test_a_straight_path_at_constant_load_is_jenkins(angle, a):
    """kn = 0, u = a sin(theta) along a direction: the force along it is Macroslip(kt, mu n0),
    across it zero (the slip radius is isotropic)."""
    n = 16384
    th = 2.0 * np.pi * np.arange(n) / n
    d = np.array([math.cos(angle), math.sin(angle)])
    X = np.zeros((3, 3))
    X[:2, 2] = a * d
    F = Contact3D(KT, 0.0, MU, N0).harmonic_force(X, 1.0, n_t=n)[0]
    fs, fc = Macroslip(KT, MU * N0).fourier(a)
    along, across = d @ F[:2], np.array([-d[1], d[0]]) @ F[:2]
    assert np.max(np.abs(along - [0.0, fc, fs])) < 1e-6 * MU * N0
    assert np.max(np.abs(across)) < 1e-12 * MU * N0
    assert np.all(np.abs(F[2] - [N0, 0.0, 0.0]) < 1e-15)
    assert fc == 0.0 if a < 0.1 else fc > 0.01 * MU * N0


def fd_jacobian(el, x, h=1e-7):
    J = np.empty((x.size, x.size))
    for j in range(x.size):
        e = np.zeros(x.size)
        e[j] = h
        J[:, j] = (el.periodic_force(x + e.reshape(x.shape))[0] - el.periodic_force(x - e.reshape(x.shape))[0]).ravel()
    return J / (2 * h)


def cases3d(n):
    th = 2.0 * np.pi * np.arange(n) / n
    return {"slip": np.vstack([0.3 * np.cos(th) + 0.05, 0.15 * np.sin(th) + 0.02 * np.cos(2 * th),
                               0.1 * np.sin(th + 0.3)]),
            "stuck": np.vstack([0.04 * np.cos(th) + 0.01, 0.03 * np.sin(th), 0.05 * np.cos(th + 0.3)]),
            "stuck-circle": np.vstack([0.05 * np.cos(th), 0.03 * np.sin(th) + 0.01 * np.sin(2 * th), 0.0 * th]),
            "barely-slipping": np.vstack([0.11 * np.cos(th), 0.09 * np.sin(th), 0.0 * th]),
            "separating": np.vstack([0.3 * np.cos(th), 0.2 * np.sin(th), -0.2 + 0.5 * np.sin(th)])}


@pytest.mark.parametrize("case", ["slip", "stuck", "stuck-circle", "barely-slipping", "separating"])
def test_the_jacobian_is_that_of_finite_differences(case):
    el = Contact3D(KT, KN, MU, N0)
    x = cases3d(48)[case]
    f, J = el.periodic_force(x)
    assert np.max(np.abs(J - fd_jacobian(el, x))) < 1e-6 * np.max(np.abs(J))


def test_the_harmonic_jacobian_is_that_of_finite_differences():
    el = Contact3D(KT, KN, MU, N0)
    X = np.zeros((3, 5))
    X[0, 1], X[0, 3], X[1, 2], X[1, 0], X[2, 2], X[2, 0] = 0.3, 0.05, 0.15, 0.02, 0.3, -0.1
    F, J, Fw = el.harmonic_force(X, 1.0, n_t=64)
    h = 1e-7
    for j in range(X.size):
        d = np.zeros(X.size)
        d[j] = h
        fd = (el.harmonic_force(X + d.reshape(3, 5), 1.0, n_t=64)[0]
              - el.harmonic_force(X - d.reshape(3, 5), 1.0, n_t=64)[0]).ravel() / (2 * h)
        np.testing.assert_allclose(J[:, j], fd, atol=1e-6)
    assert np.all(Fw == 0.0)
    np.testing.assert_allclose(el.normal_force([-1.0, 0.0, 0.1]), [0.0, N0, N0 + 0.1 * KN], rtol=1e-15)


def test_the_stuck_centre_is_the_clearance_centre():
    """The points of a circle about c with equal radii: the centre is c; a straight path: the midpoint
    of Contact2D; the centre of a stuck period lies inside every disc, its clearance the largest."""
    th = 2.0 * np.pi * np.arange(7) / 7
    u = np.vstack([0.3 + 0.2 * np.cos(th), -0.1 + 0.2 * np.sin(th)])
    w, basis, F = clearance_centre(u, np.full(7, 0.5))
    np.testing.assert_allclose(w, [0.3, -0.1], atol=1e-14)
    assert F == pytest.approx(0.2 - 0.5, abs=1e-14) and len(basis) >= 2
    rng = np.random.default_rng(1)
    u, r = rng.normal(size=(2, 30)), 3.0 + rng.uniform(size=30)
    w, basis, F = clearance_centre(u, r)
    excess = np.hypot(u[0] - w[0], u[1] - w[1]) - r
    assert np.max(excess) == pytest.approx(F, abs=1e-13) and F < 0.0
    for step in rng.normal(size=(200, 2)) * 1e-3:  # no other point has a smaller largest excess
        moved = np.hypot(u[0] - w[0] - step[0], u[1] - w[1] - step[1]) - r
        assert np.max(moved) > F


def test_the_periodic_state_is_continuous_across_the_onset_of_slip():
    """Scale a turning path through the amplitude where the discs stop meeting (found by bisection on
    the clearance centre's F): the mean tangential force, the one the stuck convention decides,
    changes by O(step) across it, stuck on one side and slipping on the other."""
    n = 256
    th = 2.0 * np.pi * np.arange(n) / n
    el = Contact3D(KT, 0.0, MU, N0)

    def path(s):
        return np.vstack([0.03 + s * (0.1 * np.cos(th) + 0.02 * np.cos(2 * th)),
                          0.01 + s * (0.07 * np.sin(th) + 0.01 * np.sin(3 * th)), np.zeros(n)])

    lo, hi = 0.1, 2.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if clearance_centre(path(mid)[:2], np.full(n, MU * N0 / KT))[2] <= 0.0 else (lo, mid)
    means = []
    for d in (-1e-6, 1e-6):
        f = el.periodic_force(path(lo * (1.0 + d)))[0]
        means.append(np.mean(f[:2], axis=1))
        slipping = np.max(np.hypot(f[0], f[1])) >= MU * N0 * (1.0 - 1e-12)
        assert slipping == (d > 0.0)
    print(f"mean force change across the onset: {np.max(np.abs(means[1] - means[0])) / (MU * N0):.1e} mu n0")
    assert np.max(np.abs(means[1] - means[0])) < 1e-5 * MU * N0


def structure(K, force):
    return hbm.Structure(np.eye(3), 0.01 * K, K, force=force)


POINT = dict(kt=1.0, kn=1.0, mu=0.3, n0=0.1)
OPTIONS = dict(harmonics=3, n_t=128, response_dof=0, tol=None, stability=False)


def test_a_balance_with_the_second_direction_and_the_normal_at_rest_is_contact2d():
    K = np.diag([1.0, 1.2, 1.5])  # DOF 1 (second tangential) and DOF 2 (normal) decoupled and unforced
    s = structure(K, [0.015, 0.0, 0.0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r3 = hbm.frequency_response(s, [hbm.Contact(Contact3D(**POINT), dof=0, second_dof=1, normal_dof=2)],
                                    (1.05, 1.6), **OPTIONS)
        r2 = hbm.frequency_response(s, [hbm.Contact(Contact2D(**POINT), dof=0, normal_dof=2)], (1.05, 1.6), **OPTIONS)
    assert r3.success and r2.success and r3.omega.size == r2.omega.size
    np.testing.assert_allclose(r3.omega, r2.omega, rtol=1e-8, atol=0.0)
    np.testing.assert_allclose(r3.amplitude, r2.amplitude, rtol=1e-8, atol=0.0)
    assert np.max(np.abs(r3.coefficients(1))) < 1e-12 and np.max(r3.amplitude) > 1.5 * 0.03  # slips: a > mu n0/kt


def test_a_balance_with_a_turning_slip_direction_and_normal_motion_completes():
    K = np.array([[1.0, 0.0, 0.3], [0.0, 1.2, 0.2], [0.3, 0.2, 1.5]])
    s = structure(K, [0.015, 0.01, 0.0])
    c = hbm.Contact(Contact3D(**POINT), dof=0, second_dof=1, normal_dof=2)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = hbm.frequency_response(s, [c], (1.0, 1.7), **OPTIONS)
    assert res.success and np.max(res.residual_norm) < 1e-6
    i = int(np.argmax(res.amplitude))
    x = [np.abs(res.coefficients(d)[i, 1]) for d in range(3)]
    assert x[1] > 0.1 * x[0] and x[2] > 1e-3 * x[0]  # both directions move, and the normal does


def test_the_balance_assembles_three_components_with_their_signs():
    el = Contact3D(KT, KN, MU, N0)
    s = hbm.Structure(np.eye(5), 0.01 * np.eye(5), 2 * np.eye(5), force=[1.0, 0, 0, 0, 0])
    c = hbm.Contact(el, dofs=(0, 1), second_dof=4, normal_dofs=(3, 2))
    assert c.components == ((0, 1), (4,), (3, 2)) and c.all_dofs == (0, 1, 4, 3, 2)
    assert repr(c).endswith("dofs=(0, 1), second_dof=4, normal_dofs=(3, 2))")
    assert c.with_element(Contact3D(1.0, 1.0, 1.0, 1.0)).components == c.components
    hb = hbm.balance.HarmonicBalance(s, [c], harmonics=2, n_t=32)
    X = np.zeros((5, 5))
    X[0, 1], X[1, 2], X[4, 2], X[3, 1], X[2, 2] = 0.3, 0.1, 0.2, 0.2, -0.1
    F, dF, _ = hb.forces(X, 1.0)
    Fe, Je, _ = el.harmonic_force(np.array([X[0] - X[1], X[4], X[3] - X[2]]), 1.0, n_t=32)
    np.testing.assert_allclose(F, np.array([Fe[0], -Fe[0], -Fe[2], Fe[2], Fe[1]]), atol=1e-14)
    Je, dF = Je.reshape(3, 5, 3, 5), dF.reshape(5, 5, 5, 5)
    np.testing.assert_allclose(dF[4, :, 0, :], Je[1, :, 0, :], atol=1e-14)
    np.testing.assert_allclose(dF[2, :, 4, :], -Je[2, :, 1, :], atol=1e-14)
    np.testing.assert_allclose(dF[1, :, 3, :], -Je[0, :, 2, :], atol=1e-14)


def test_contact_validates_the_three_attachments():
    el = Contact3D(KT, KN, MU, N0)
    for kw, match in ((dict(dof=0, normal_dof=2), "second_dof"), (dict(dof=0, second_dof=1), "normal_dof"),
                      (dict(dof=0, second_dof=0, normal_dof=2), "second_dof"),
                      (dict(dof=0, second_dof=1, normal_dof=1), "normal_dof"),
                      (dict(dof=0, second_dof=1, second_dofs=(1, 2), normal_dof=3), "second_dof"),
                      (dict(dof=0, second_dofs=(1,), normal_dof=3), "second_dofs")):
        with pytest.raises(ValueError, match=match):
            hbm.Contact(el, **kw)
    for other in (Contact2D(KT, KN, MU, N0), Macroslip(1.0, 1.0)):
        with pytest.raises(ValueError, match="second_dof"):
            hbm.Contact(other, dof=0, second_dof=1, normal_dof=2)
    with pytest.raises(ValueError, match="x must be"):
        el.periodic_force(np.zeros((2, 8)))
    with pytest.raises(ValueError, match="X must be"):
        el.harmonic_force(np.zeros((2, 3)), 1.0)


@pytest.mark.parametrize("kw, name", [(dict(kt=0.0, kn=1.0, mu=0.3, n0=1.0), "kt"),
                                      (dict(kt=np.inf, kn=1.0, mu=0.3, n0=1.0), "kt"),
                                      (dict(kt=1.0, kn=-1.0, mu=0.3, n0=1.0), "kn"),
                                      (dict(kt=1.0, kn=np.nan, mu=0.3, n0=1.0), "kn"),
                                      (dict(kt=1.0, kn=1.0, mu=0.0, n0=1.0), "mu"),
                                      (dict(kt=1.0, kn=1.0, mu=0.3, n0=np.inf), "n0")])
def test_bad_parameters_are_named(kw, name):
    with pytest.raises(ValueError, match=f"{name}="):
        Contact3D(**kw)


# ---------------------------------------------------------------------------------------- scenes
def scene_tables(folder, damper=None, **structure):
    K = np.array([[1.0, 0.0, 0.3], [0.0, 1.2, 0.2], [0.3, 0.2, 1.5]])
    np.save(folder / "M.npy", np.eye(3))
    np.save(folder / "K.npy", K)
    table = {"mass": "M.npy", "stiffness": "K.npy", "rayleigh": [0.0, 0.01], "force": [0.015, 0.01, 0.0],
             "contact_dofs": [0], "second_dofs": [1], "normal_dofs": [2], "response_dof": 0, **structure}
    damper = damper or {"model": "contact3d", "kt": 1.0, "kn": 1.0, "friction": 0.3, "n0": 0.1}
    return {"structure": table, "damper": damper, "effects": {"harmonics": 3, "samples": 128},
            "sweep": {"omega": [1.0, 1.2]}, "output": {"formats": ["csv"]}}, K


def test_a_scene_attaches_the_second_direction_and_is_the_api_computation(tmp_path):
    from hbm.scenes import run_scene, scene_from_dict

    data, K = scene_tables(tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = run_scene(scene_from_dict(data, tmp_path / "s.toml"), tmp_path / "out", progress=None)
        api = hbm.frequency_response(structure(K, [0.015, 0.01, 0.0]),
                                     [hbm.Contact(Contact3D(**POINT), dof=0, second_dof=1, normal_dof=2)], (1.0, 1.2),
                                     harmonics=3, n_t=128, response_dof=0)
    assert result.success, result.message
    frf = result.runs[0].frf
    assert len(frf) == len(api) > 5
    np.testing.assert_allclose(frf.amplitude, api.amplitude, rtol=1e-12)


def test_a_scene_names_a_wrong_second_attachment(tmp_path):
    from conftest import scene_problems as problems

    data, _ = scene_tables(tmp_path)
    del data["structure"]["second_dofs"]
    assert "structure.second_dofs is missing: the contact3d element acts on two tangential displacements" in problems(
        data, tmp_path / "a.toml", plan=True)
    data, _ = scene_tables(tmp_path, second_dofs=[0])
    assert "structure.second_dofs = [0]: second_dof(s) must differ from the first tangential dof(s)" in problems(
        data, tmp_path / "a.toml", plan=True)
    data, _ = scene_tables(tmp_path, {"model": "contact2d", "kt": 1.0, "kn": 1.0, "friction": 0.3, "n0": 0.1})
    assert "structure.second_dofs = [1]: not allowed: the contact2d element has one tangential direction" in problems(
        data, tmp_path / "a.toml", plan=True)
    data, _ = scene_tables(tmp_path, second_dofs=[7])
    assert "structure.second_dofs = [7]: DOF 7 is out of range for the structure's 3 DOFs" in problems(
        data, tmp_path / "a.toml", plan=True)
    data, _ = scene_tables(tmp_path, contacts=[{"model": "contact3d", "dofs": [0, 1], "normal_dofs": [2], "kt": 1.0,
                                                "kn": 1.0, "friction": 0.3, "n0": 0.1}])
    assert "structure.contacts[0].second_dofs is missing" in problems(data, tmp_path / "a.toml", plan=True)
