"""``contact_models.Contact2D`` against an independent time-stepped return map written here:
march many periods from rest until periodic and compare the last period.  Constant load equals
``Macroslip``; the load varying in phase, in quadrature and out of phase with the tangential
motion; separation over part of the cycle; the Jacobian against finite differences; the balance's
assembly of a two-component element."""

import numpy as np
import pytest

import hbm
from contact_models import Contact2D, Macroslip

KT, KN, MU, N0 = 4.0, 3.0, 0.4, 1.0
n = 128
TH = 2.0 * np.pi * np.arange(n) / n


def marched(u, v, kt=KT, kn=KN, mu=MU, n0=N0, periods=60):
    """Slider at 0 (spring relaxed), march ``periods`` periods with the return map; the last one."""
    w, T = 0.0, np.zeros(u.size)
    for _ in range(periods):
        for k in range(u.size):
            lim = mu * max(0.0, n0 + kn * v[k])
            t = kt * (u[k] - w)
            if abs(t) >= lim:
                t = np.sign(t) * lim
                w = u[k] - t / kt
            T[k] = t
    return T


def test_constant_load_is_macroslip_to_rounding():
    el, jen = Contact2D(KT, KN, MU, N0), Macroslip(KT, MU * N0)
    for u in (0.05 + 0.3 * np.cos(TH) + 0.1 * np.sin(3 * TH), 0.02 + 0.06 * np.cos(TH)):  # slipping, stuck
        f, J = el.periodic_force(np.vstack([u, np.zeros(n)]))
        fj, Jj = jen.periodic_force(u)
        assert np.max(np.abs(f[0] - fj)) < 1e-12 and np.all(f[1] == N0)
        assert np.max(np.abs(J[:n, :n] - Jj)) < 1e-12


@pytest.mark.parametrize("phase", [0.0, 0.5 * np.pi, np.pi], ids=["in phase", "quadrature", "out of phase"])
def test_varying_load_is_the_marched_return_map(phase):
    u = 0.4 * np.cos(TH) + 0.05 * np.sin(2 * TH)
    v = 0.2 * np.cos(TH + phase)  # N between 0.4 and 1.6: never separates
    f, _ = Contact2D(KT, KN, MU, N0).periodic_force(np.vstack([u, v]))
    assert np.max(np.abs(f[0] - marched(u, v))) < 1e-12
    np.testing.assert_allclose(f[1], N0 + KN * v, rtol=0, atol=1e-15)


def test_separation_over_part_of_the_cycle():
    u = 0.3 * np.cos(TH) + 0.1
    v = 0.5 * np.sin(TH)  # N = max(0, 1 + 1.5 sin): open for a third of the cycle
    el = Contact2D(KT, KN, MU, N0)
    f, _ = el.periodic_force(np.vstack([u, v]))
    open_ = N0 + KN * v <= 0.0
    assert open_.any() and np.all(f[:, open_] == 0.0)
    assert np.max(np.abs(f[0] - marched(u, v))) < 1e-12


def _fd_check(el, x, atol):
    f, J = el.periodic_force(x)
    h = 1e-7
    flat = x.ravel()
    for j in range(flat.size):
        d = np.zeros(flat.size)
        d[j] = h
        fd = (el.periodic_force((flat + d).reshape(x.shape))[0] - el.periodic_force((flat - d).reshape(x.shape))[0])
        np.testing.assert_allclose(J[:, j], fd.ravel() / (2 * h), atol=atol)


@pytest.mark.parametrize("case", ["slipping", "stuck", "separating"])
def test_the_jacobian_is_that_of_finite_differences(case):
    m = 24
    th = 2.0 * np.pi * (np.arange(m) + 0.3) / m
    u = {"slipping": 0.4 * np.cos(th), "stuck": 0.03 * np.cos(th), "separating": 0.3 * np.cos(th)}[case]
    v = {"slipping": 0.2 * np.sin(th), "stuck": 0.1 * np.sin(th), "separating": 0.5 * np.sin(th + 0.4)}[case]
    _fd_check(Contact2D(KT, KN, MU, N0), np.vstack([u + 0.01, v]), 1e-6)


def test_the_harmonic_jacobian_is_that_of_finite_differences():
    el = Contact2D(KT, KN, MU, N0)
    X = np.array([[0.02, 0.4, 0.1, 0.03, -0.02], [0.0, 0.1, 0.25, 0.02, 0.01]])
    F, J, _ = el.harmonic_force(X, 1.0, n_t=64)
    assert F.shape == (2, 5) and J.shape == (10, 10)
    h = 1e-7
    for j in range(10):
        d = np.zeros(10)
        d[j] = h
        fd = (el.harmonic_force(X + d.reshape(2, 5), 1.0, n_t=64)[0]
              - el.harmonic_force(X - d.reshape(2, 5), 1.0, n_t=64)[0]).ravel() / (2 * h)
        np.testing.assert_allclose(J[:, j], fd, atol=1e-6)


def test_the_balance_assembles_both_components_with_their_signs():
    el = Contact2D(KT, KN, MU, N0)
    s = hbm.Structure(np.eye(4), 0.01 * np.eye(4), 2 * np.eye(4), force=[1.0, 0, 0, 0])
    c = hbm.Contact(el, dofs=(0, 1), normal_dofs=(3, 2))
    hb = hbm.balance.HarmonicBalance(s, [c], harmonics=2, n_t=32)
    X = np.zeros((4, 5))
    X[0, 1], X[1, 2], X[3, 1], X[2, 2] = 0.3, 0.1, 0.2, -0.1
    F, dF, _ = hb.forces(X, 1.0)
    Fe, Je, _ = el.harmonic_force(np.array([X[0] - X[1], X[3] - X[2]]), 1.0, n_t=32)
    np.testing.assert_allclose(F, np.array([Fe[0], -Fe[0], -Fe[1], Fe[1]]), atol=1e-14)
    Je = Je.reshape(2, 5, 2, 5)
    np.testing.assert_allclose(dF.reshape(4, 5, 4, 5)[3, :, 0, :], Je[1, :, 0, :], atol=1e-14)
    np.testing.assert_allclose(dF.reshape(4, 5, 4, 5)[0, :, 2, :], -Je[0, :, 1, :], atol=1e-14)


def test_contact_validates_the_normal_attachment():
    el = Contact2D(KT, KN, MU, N0)
    with pytest.raises(ValueError, match="normal_dof"):
        hbm.Contact(el, dof=0)
    with pytest.raises(ValueError, match="normal_dof"):
        hbm.Contact(Macroslip(1.0, 1.0), dof=0, normal_dof=1)
    with pytest.raises(ValueError, match="normal_dof"):
        hbm.Contact(el, dof=0, normal_dof=0)
    with pytest.raises(ValueError, match="x must be"):
        el.periodic_force(np.zeros(8))


@pytest.mark.parametrize("kw, name", [(dict(kt=0.0, kn=1.0, mu=0.3, n0=1.0), "kt"),
                                      (dict(kt=1.0, kn=-1.0, mu=0.3, n0=1.0), "kn"),
                                      (dict(kt=1.0, kn=1.0, mu=0.0, n0=1.0), "mu"),
                                      (dict(kt=1.0, kn=1.0, mu=0.3, n0=np.inf), "n0")])
def test_bad_parameters_are_named(kw, name):
    with pytest.raises(ValueError, match=name):
        Contact2D(**kw)


def test_normal_force_names_a_normal_displacement_that_is_not_a_finite_number():
    import math

    el = Contact2D(kt=1.0, kn=1.0, mu=0.3, n0=1.0)
    with pytest.raises(ValueError, match=r"^v must be finite, got v=nan$"):
        el.normal_force(math.nan)
    with pytest.raises(ValueError, match=r"^v must be a number or an array of numbers, got v='0'$"):
        el.normal_force("0")
