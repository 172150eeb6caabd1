"""The generalized-alpha scheme shared by NumericalMicroslip and hbm.reference.transient, against its
closed-form properties (Chung & Hulbert 1993): Newmark's average acceleration at rho_inf = 1,
spectral radius rho_inf at infinite frequency, second-order accuracy."""

import numpy as np
import pytest

from contact_models.numerical import GeneralizedAlpha


def amplification(ga: GeneralizedAlpha, w_dt: float) -> np.ndarray:
    """One step of x'' + w^2 x = 0 (m = 1, dt = 1) as a matrix on (u, v, a), built from the
    scheme's own formulas, as the integrators use them."""
    dt, k = 1.0, w_dt**2
    cols = []
    for u, v, a in np.eye(3):
        pred = ga.predict(u, v, a, dt)
        rhs = ga.mass_coefficient(dt) * pred - ga.old_terms(1.0, a, k * u)
        u1 = rhs / (ga.mass_coefficient(dt) + k)
        a1 = ga.acceleration(u1, pred, dt)
        cols.append([u1, ga.velocity(v, a, a1, dt), a1])
    return np.array(cols).T


def test_rho_inf_one_is_average_acceleration():
    ga = GeneralizedAlpha.from_rho_inf(1.0)
    assert (ga.alpha_m, ga.alpha_f, ga.gamma, ga.beta) == (0.0, 0.0, 0.5, 0.25)


@pytest.mark.parametrize("rho_inf", [0.0, 0.5, 0.9, 1.0])
def test_spectral_radius_at_infinity_and_second_order(rho_inf):
    ga = GeneralizedAlpha.from_rho_inf(rho_inf)
    assert ga.gamma == pytest.approx(0.5 - ga.alpha_m + ga.alpha_f)  # the second-order condition
    # the three roots meet at -rho_inf (a defective root: they approach it as (w dt)^(-2/3))
    radius = max(abs(np.linalg.eigvals(amplification(ga, 1e6))))
    assert radius == pytest.approx(rho_inf, abs=2e-4)
    # the principal roots approximate exp(+-i w dt) with a local error O((w dt)^3)
    errors = []
    for w_dt in (0.02, 0.01):
        lam = np.linalg.eigvals(amplification(ga, w_dt))
        principal = lam[np.argmax(lam.imag)]
        errors.append(abs(principal - np.exp(1j * w_dt)))
    assert 7.0 < errors[0] / errors[1] < 9.0


def test_velocity_predictor_and_damping_coefficient_agree_with_the_corrector():
    ga = GeneralizedAlpha.from_rho_inf(0.9)
    dt, u, v, a, u1 = 0.3, 1.0, -2.0, 0.5, 1.7
    pred = ga.predict(u, v, a, dt)
    v1 = ga.velocity(v, a, ga.acceleration(u1, pred, dt), dt)
    assert v1 == pytest.approx(ga.velocity_predictor(v, a, dt) + ga.damping_coefficient(dt) * (u1 - pred), rel=1e-14)


def test_rho_inf_outside_zero_one_is_refused_by_name():
    with pytest.raises(ValueError, match="rho_inf"):
        GeneralizedAlpha.from_rho_inf(1.5)
