"""``contact_models.Gap``: its describing function, mean force and AFT against the closed-form
harmonics of ``k max(0, X0 + a cos(theta) - g)`` written here from the contact angle, and its
Jacobian against finite differences."""

import math

import numpy as np
import pytest

from contact_models import Gap


def closed_form(k, g, X0, a, H):
    """``[F0, Fc1, Fs1, ..., FcH, FsH]`` of ``k max(0, X0 + a cos(theta) - g)``: contact for
    ``|theta| < alpha``, ``cos(alpha) = (g - X0)/a``; even in theta, so no sine terms."""
    alpha = math.acos(min(1.0, max(-1.0, (g - X0) / a)))
    S = lambda m: alpha if m == 0 else math.sin(m * alpha) / m  # noqa: E731 - int_0^alpha cos(m t) dt
    F = np.zeros(2 * H + 1)
    F[0] = k / math.pi * ((X0 - g) * alpha + a * math.sin(alpha))
    for h in range(1, H + 1):
        F[2 * h - 1] = 2.0 * k / math.pi * ((X0 - g) * S(h) + 0.5 * a * (S(h - 1) + S(h + 1)))
    return F


@pytest.mark.parametrize("g", [0.5, 0.0, -0.3, 2.0, -2.0])
def test_describing_function_and_mean_force_are_the_closed_form(g):
    el = Gap(stiffness=3.0, gap=g)
    for a in (0.2, 0.7, 1.0, 1.9):
        F = closed_form(3.0, g, 0.0, a, 1)  # a cos(theta): f_s of a sin(theta) is its cos term
        f_s, f_c = el.fourier(a)
        assert abs(f_s - F[1]) < 1e-12 and f_c == 0.0
        assert abs(el.mean_force(a) - F[0]) < 1e-12


def test_the_amplitude_derivative_is_that_of_the_closed_form():
    el = Gap(stiffness=3.0, gap=0.4)
    for a in (0.5, 1.0, 3.0):
        h = 1e-6 * a
        fd = (closed_form(3.0, 0.4, 0.0, a + h, 1)[1] - closed_form(3.0, 0.4, 0.0, a - h, 1)[1]) / (2 * h)
        assert abs(el.fourier_derivatives(a)[2] - fd) < 1e-8


@pytest.mark.parametrize("X0, a", [(0.1, 1.0), (-0.4, 0.9), (0.6, 0.3)])
def test_aft_converges_to_the_closed_form_harmonics_with_a_mean(X0, a):
    """The kink at the contact angle makes the sampled harmonics converge as n_t^-2: to 1e-10 at 2^20."""
    el, H = Gap(stiffness=2.0, gap=0.25), 3
    X = np.zeros(2 * H + 1)
    X[0], X[1] = X0, a
    exact = closed_form(2.0, 0.25, X0, a, H)
    errors = [np.max(np.abs(el.harmonic_force(X, 1.0, n_t=n)[0] - exact)) for n in (2**12, 2**14, 2**20)]
    assert errors[2] < 1e-10
    assert errors[1] < errors[0] / 8.0 or errors[0] < 1e-12


def test_h1_answers_by_aft_with_the_mean_force():
    el = Gap(stiffness=2.0, gap=0.25)
    assert el.has_time_law and not el.exact_describing_function
    F = el.harmonic_force([0.0, 0.0, 1.0], 1.0, n_t=2**18)[0]
    assert abs(F[0] - el.mean_force(1.0)) < 1e-9 and abs(F[2] - el.fourier(1.0)[0]) < 1e-9


def test_the_jacobian_is_that_of_finite_differences():
    el = Gap(stiffness=2.0, gap=0.25)
    X = np.array([0.1, 0.8, 0.3, 0.05, -0.1, 0.02, 0.01])
    F, J, _ = el.harmonic_force(X, 1.0, n_t=256)
    h = 1e-7
    for j in range(X.size):
        d = np.zeros(X.size)
        d[j] = h
        fd = (el.harmonic_force(X + d, 1.0, n_t=256)[0] - el.harmonic_force(X - d, 1.0, n_t=256)[0]) / (2 * h)
        np.testing.assert_allclose(J[:, j], fd, atol=1e-6)


@pytest.mark.parametrize("kw, name", [({"stiffness": 0.0, "gap": 1.0}, "stiffness"),
                                      ({"stiffness": math.inf, "gap": 1.0}, "stiffness"),
                                      ({"stiffness": 1.0, "gap": math.nan}, "gap")])
def test_bad_input_names_the_parameter(kw, name):
    with pytest.raises(ValueError, match=name):
        Gap(**kw)


@pytest.mark.parametrize("a, message", [(-1.0, "a must be finite and >= 0, got a=-1.0"),
                                        (math.nan, "a must be finite and >= 0, got a=nan"),
                                        ("1", "a must be a number or an array of numbers, got a='1'")])
def test_mean_force_names_a_bad_amplitude(a, message):
    with pytest.raises(ValueError, match=f"^{message}$"):
        Gap(stiffness=1.0, gap=0.1).mean_force(a)
