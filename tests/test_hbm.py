"""hbm: the blade, the balance and its Jacobian, linear FRFs against the closed form, the
stuck shortcut, results and the command line."""

import csv
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from contact_models import ContactElement
from hbm import Blade, FrequencyResponse, HarmonicBalance, Steps, frequency_response
from hbm.balance.residual import linear_response
from hbm.output import csv_lines


def macroslip(stiffness, slip_force):
    from contact_models import Macroslip

    return Macroslip(stiffness=stiffness, slip_force=slip_force)


def microslip():
    from contact_models import Bar, TwoRegionMicroslip, UniformLoad

    bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    return TwoRegionMicroslip(bar, UniformLoad(N=100.0))


def closed_form_error(frf, stiffness=0.0):
    """max relative error of the complex amplitude against the linear closed form."""
    z = frf.x_c - 1j * frf.x_s
    ref = linear_response(frf.blade, frf.omega, stiffness)
    return float(np.max(np.abs(z - ref) / np.abs(ref)))


# ---------------------------------------------------------------------- Blade
def test_blade_from_modal():
    b = Blade.from_modal(frequency=200.0, damping_ratio=0.01, mass=2.0, force=3.0)
    assert b.stiffness == pytest.approx(2.0 * 200.0**2)
    assert b.damping == pytest.approx(2 * 0.01 * 2.0 * 200.0)
    assert b.natural_frequency == pytest.approx(200.0)
    assert b.damping_ratio == pytest.approx(0.01)
    assert b.force == 3.0


@pytest.mark.parametrize("kwargs, name", [
    ({"mass": 0.0, "stiffness": 1.0, "damping": 0.0, "force": 1.0}, "mass"),
    ({"mass": 1.0, "stiffness": -1.0, "damping": 0.0, "force": 1.0}, "stiffness"),
    ({"mass": 1.0, "stiffness": 1.0, "damping": -0.1, "force": 1.0}, "damping"),
    ({"mass": 1.0, "stiffness": 1.0, "damping": 0.0, "force": float("nan")}, "force"),
    ({"mass": 1.0, "stiffness": 1.0, "damping": 0.0, "force": "big"}, "force"),
])
def test_blade_rejects_bad_parameters(kwargs, name):
    with pytest.raises(ValueError, match=name):
        Blade(**kwargs)


@pytest.mark.parametrize("kwargs, name", [
    ({"frequency": -1.0, "damping_ratio": 0.01, "mass": 1.0, "force": 1.0}, "frequency"),
    ({"frequency": 1.0, "damping_ratio": -0.01, "mass": 1.0, "force": 1.0}, "damping_ratio"),
    ({"frequency": 1.0, "damping_ratio": 0.01, "mass": math.inf, "force": 1.0}, "mass"),
])
def test_from_modal_rejects_bad_parameters(kwargs, name):
    with pytest.raises(ValueError, match=name):
        Blade.from_modal(**kwargs)


# ---------------------------------------------------------------------- linear FRFs
@pytest.mark.parametrize("zeta", [1e-2, 1e-4])
def test_bare_blade_frf_against_closed_form(zeta):
    blade = Blade.from_modal(frequency=100.0, damping_ratio=zeta, mass=1.0, force=1.0)
    frf = frequency_response(blade, None, omega_range=(50.0, 200.0))
    assert frf.success, frf.message
    assert frf.omega[0] == 50.0 and frf.omega[-1] == 200.0
    assert closed_form_error(frf) <= 1e-8
    # phase: lag of x behind F cos(omega t), arg of the dynamic stiffness
    D = blade.stiffness - blade.mass * frf.omega**2 + 1j * blade.damping * frf.omega
    assert np.max(np.abs(frf.phase - np.angle(D))) <= 1e-8
    # peak: omega_n sqrt(1 - 2 zeta^2), F / (2 zeta k sqrt(1 - zeta^2))
    w_pk, a_pk = frf.peak()
    assert w_pk == pytest.approx(100.0 * math.sqrt(1 - 2 * zeta**2), rel=1e-6)
    assert a_pk == pytest.approx(1.0 / (2 * zeta * blade.stiffness * math.sqrt(1 - zeta**2)), rel=1e-6)
    # the log-amplitude arclength keeps the point count nearly independent of the sharpness
    assert 150 <= len(frf) <= 700


@settings(max_examples=15, deadline=None)
@given(wn=st.floats(1.0, 1e5), zeta=st.floats(1e-4, 0.5), mass=st.floats(1e-3, 1e3), force=st.floats(1e-3, 1e3),
       lo=st.floats(0.0, 0.9), hi=st.floats(1.1, 5.0))
def test_linear_frf_property(wn, zeta, mass, force, lo, hi):
    blade = Blade.from_modal(frequency=wn, damping_ratio=zeta, mass=mass, force=force)
    frf = frequency_response(blade, None, omega_range=(lo * wn, hi * wn))
    assert frf.success, frf.message
    assert closed_form_error(frf) <= 1e-8
    assert np.all(np.diff(frf.omega) > 0)  # a linear FRF has no folds


def test_stuck_jenkins_damper_is_the_linear_blade():
    """A slip force never reached: the FRF is the linear one and the element's Fourier
    routine is never called (the stuck stiffness answers)."""
    blade = Blade.from_modal(frequency=1.0, damping_ratio=1e-2, mass=1.0, force=1e-3)
    frf = frequency_response(blade, macroslip(2.0, 1.0), omega_range=(0.5, 3.0))
    assert frf.success
    assert np.max(frf.amplitude) < 0.5  # below a_min = 0.5
    assert closed_form_error(frf, 2.0) <= 1e-8
    assert frf.nfev == 0 and frf.nstuck > 0


def test_stuck_microslip_damper_follows_the_dynamic_stiffness():
    el = microslip()
    blade = Blade(mass=0.05, stiffness=1e8, damping=5.0, force=1e-2)
    frf = frequency_response(blade, el, omega_range=(2e4, 6e4))
    assert frf.success
    assert np.max(frf.amplitude) < el.slip_amplitude(0.0)
    K = lambda w: np.array([el.stuck_stiffness(x) for x in np.atleast_1d(w)])  # noqa: E731
    assert closed_form_error(frf, K) <= 1e-8
    assert frf.nfev == 0


class CountingElement(ContactElement):
    """Wraps an element and records the amplitudes its Fourier routine sees."""

    def __init__(self, el):
        self.el = el
        self.frequency_dependent = el.frequency_dependent
        self.seen = []

    def _stuck_stiffness(self, omega):
        return self.el.stuck_stiffness(omega)

    def _slip_amplitude(self, omega):
        return self.el.slip_amplitude(omega)

    def _hysteresis(self, a, omega, n):
        return self.el.hysteresis(a, omega, n=n)

    def _fourier_derivatives(self, a, omega, rtol):
        self.seen.extend(zip(a.tolist(), omega.tolist()))
        return self.el._fourier_derivatives(a, omega, rtol)


def test_element_evaluated_only_above_its_slip_amplitude():
    el = CountingElement(macroslip(1.0, 1.0))
    blade = Blade.from_modal(frequency=1.0, damping_ratio=1e-2, mass=1.0, force=0.5)
    frf = frequency_response(blade, el, omega_range=(0.5, 2.0))
    assert frf.success
    a_seen = np.array([a for a, _ in el.seen])
    assert len(a_seen) == frf.nfev > 0
    assert np.all(a_seen > 1.0)  # a_min = slip_force / stiffness = 1
    assert frf.nstuck > 0


# ---------------------------------------------------------------------- the balance
def fd_jacobian(hb, y, rel=1e-6):
    J = np.empty((2, 3))
    for j in range(3):
        h = rel * abs(y[j])
        yp, ym = y.copy(), y.copy()
        yp[j] += h
        ym[j] -= h
        J[:, j] = (hb.physical(yp)[0] - hb.physical(ym)[0]) / (2 * h)
    return J


@pytest.mark.parametrize("y", [[1.3, 0.7, 1.1], [-0.2, 2.5, 0.9], [0.3, -0.4, 1.7]])
def test_jacobian_jenkins_against_finite_differences(y):
    blade = Blade.from_modal(frequency=1.0, damping_ratio=0.05, mass=1.0, force=0.5)
    hb = HarmonicBalance(blade, macroslip(1.0, 0.2))
    y = np.array(y)
    J = hb.physical(y)[1]
    assert np.allclose(J, fd_jacobian(hb, y), rtol=1e-6, atol=1e-8 * np.max(np.abs(J)))


def test_jacobian_microslip_against_finite_differences():
    el = microslip()
    blade = Blade(mass=0.0877, stiffness=1e8, damping=11.8, force=8.0)
    hb = HarmonicBalance(blade, el, rtol=1e-10)
    hb.fresh_omega_derivative = True
    for y in ([1.2e-6, 0.4e-6, 3.9e4], [-0.5e-6, 1.5e-6, 3.8e4]):
        y = np.array(y)
        J = hb.physical(y)[1]
        Jfd = fd_jacobian(hb, y, rel=1e-5)
        scale = np.max(np.abs(J), axis=0)
        # x columns exact (the element's df/da); omega column: a forward difference of step sqrt(rtol)
        assert np.all(np.abs(J[:, :2] - Jfd[:, :2]) <= 1e-6 * scale[:2])
        assert np.all(np.abs(J[:, 2] - Jfd[:, 2]) <= 1e-4 * scale[2])


def test_residual_is_the_complex_balance():
    """R_c - i R_s = (k - m w^2 + f_s/a + i (c w + f_c/a)) (x_c - i x_s) - F."""
    blade = Blade(mass=2.0, stiffness=3.0, damping=0.1, force=0.7)
    el = macroslip(1.5, 0.3)
    hb = HarmonicBalance(blade, el)
    xc, xs, w = 0.4, -0.9, 1.3
    a = math.hypot(xc, xs)
    fs, fc = el.fourier(a, w)
    R = hb.physical([xc, xs, w])[0]
    D = blade.stiffness - blade.mass * w * w + fs / a + 1j * (blade.damping * w + fc / a)
    assert R[0] - 1j * R[1] == pytest.approx(D * (xc - 1j * xs) - blade.force, rel=1e-14, abs=1e-15)


# ---------------------------------------------------------------------- results and input checks
def test_csv_and_plot(tmp_path):
    blade = Blade.from_modal(frequency=1.0, damping_ratio=1e-2, mass=1.0, force=0.5)
    frf = frequency_response(blade, macroslip(1.0, 1.0), omega_range=(0.5, 2.0), harmonics=1)
    assert isinstance(frf, FrequencyResponse) and len(frf) == len(frf.omega)
    assert frf.nsteps == len(frf) - 1 and frf.nit > 0 and frf.nfev > 0
    path = frf.to_csv(tmp_path / "frf.csv")
    with open(path) as fh:
        rows = list(csv.reader(csv_lines(fh)))
    assert rows[0][:3] == ["omega_rad_s", "amplitude_m", "phase_rad"]
    data = np.array(rows[1:], dtype=float)
    assert np.array_equal(data[:, 0], frf.omega) and np.array_equal(data[:, 1], frf.amplitude)
    import matplotlib

    matplotlib.use("Agg")
    ax = frf.plot()
    assert np.array_equal(ax.lines[0].get_ydata(), frf.amplitude)
    import matplotlib.pyplot as plt

    plt.close("all")


@pytest.mark.parametrize("kwargs, name", [
    ({"omega_range": None}, "omega_range"),
    ({"omega_range": (1.0, 1.0)}, "omega_range"),
    ({"omega_range": (-1.0, 2.0)}, "omega_range"),
    ({"omega_range": (1.0, 2.0), "rtol": 0.0}, "rtol"),
    ({"omega_range": (1.0, 2.0), "max_steps": 0}, "max_steps"),
    ({"omega_range": (1.0, 2.0), "max_step": -1.0}, "max_step"),
])
def test_frequency_response_rejects_bad_options(kwargs, name):
    blade = Blade.from_modal(frequency=1.0, damping_ratio=1e-2, mass=1.0, force=0.5)
    with pytest.raises(ValueError, match=name):
        frequency_response(blade, None, **kwargs)


def test_frequency_response_rejects_non_blade():
    with pytest.raises(ValueError, match="blade"):
        frequency_response({"mass": 1.0}, None, omega_range=(1.0, 2.0))


def test_step_budget_keeps_points():
    blade = Blade.from_modal(frequency=1.0, damping_ratio=1e-2, mass=1.0, force=0.5)
    frf = frequency_response(blade, macroslip(1.0, 1.0), omega_range=(0.5, 2.0), steps=Steps(max_steps=20))
    assert not frf.success and "max_steps" in frf.message
    assert len(frf) == 21
    assert np.all(frf.residual_norm <= 1e-8)
