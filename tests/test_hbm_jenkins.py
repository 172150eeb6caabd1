"""Blade + Macroslip (Jenkins) damper: every FRF point against the closed-form describing
function, the peak against an independent quartic computation, and the single-harmonic
approximation against time integration of the ODE with the slider state."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from hbm import Blade, frequency_response

K_D, SLIP = 1.0, 1.0  # damper spring and slip force; a* = 1
FORCE = 0.5  # below 4 SLIP / pi: the friction bounds the response even without blade damping


def macroslip(stiffness, slip_force):
    from contact_models import Macroslip

    return Macroslip(stiffness=stiffness, slip_force=slip_force)


def jenkins(a):
    """Closed-form describing function (f_s, f_c) of the Jenkins element, written out here
    independently of contact_models."""
    a_star = SLIP / K_D
    if a <= a_star:
        return K_D * a, 0.0
    psi = math.acos(1.0 - 2.0 * a_star / a)
    return K_D * a * (psi - math.sin(2 * psi) / 2) / math.pi, 4 * SLIP * (1 - a_star / a) / math.pi


def balance(blade, xc, xs, w):
    """R_c, R_s of m x'' + c x' + k x + f_d = F cos(w t) for x = x_c cos + x_s sin."""
    a = math.hypot(xc, xs)
    fs, fc = jenkins(a)
    kr = blade.stiffness - blade.mass * w * w + fs / a
    ki = blade.damping * w + fc / a
    return kr * xc + ki * xs - blade.force, kr * xs - ki * xc


def quartic_peak(blade, bracket):
    """Largest amplitude with a real frequency: for each a the balance
    a^2 [(k + p - m w^2)^2 + (c w + q)^2] = F^2 (p = f_s/a, q = f_c/a) is a quartic in w;
    its minimum over w (a root of the cubic P'(w)) touches F^2 at the peak."""
    m, c, k, F = blade.mass, blade.damping, blade.stiffness, blade.force

    def min_over_w(a):
        fs, fc = jenkins(a)
        K, q = k + fs / a, fc / a
        roots = np.roots([4 * m * m, 0.0, 2 * (c * c - 2 * m * K), 2 * c * q])
        best = min(((K - m * r.real**2) ** 2 + (c * r.real + q) ** 2, r.real)
                   for r in roots if abs(r.imag) <= 1e-9 * abs(r) and r.real > 0)
        return best

    a = brentq(lambda a: a * a * min_over_w(a)[0] - F * F, *bracket, xtol=1e-15, rtol=1e-15)
    return min_over_w(a)[1], a


@pytest.fixture(scope="module", params=[1e-2, 1e-4], ids=["zeta=1e-2", "zeta=1e-4"])
def case(request):
    blade = Blade.from_modal(frequency=1.0, damping_ratio=request.param, mass=1.0, force=FORCE)
    frf = frequency_response(blade, macroslip(K_D, SLIP), omega_range=(0.5, 2.0), harmonics=1)
    return blade, frf, (frf.nfev, frf.nit)  # the counters of the solve, before any test's peak() adds to them


def test_every_point_satisfies_the_balance(case):
    blade, frf, _ = case
    assert frf.success, frf.message
    R = np.array([balance(blade, xc, xs, w) for xc, xs, w in zip(frf.x_c, frf.x_s, frf.omega)])
    assert np.max(np.abs(R)) / blade.force <= 1e-8
    assert np.max(frf.amplitude) > 1.2  # the damper slips through resonance


def test_peak_against_the_quartic(case):
    blade, frf, _ = case
    w_pk, a_pk = frf.peak()
    w_ref, a_ref = quartic_peak(blade, (0.9 * a_pk, 1.1 * a_pk))
    assert a_pk == pytest.approx(a_ref, rel=1e-6)
    assert w_pk == pytest.approx(w_ref, rel=1e-6)
    # refined beyond the largest sampled point
    assert abs(np.max(frf.amplitude) / a_ref - 1) > abs(a_pk / a_ref - 1)


def test_cost(case):
    blade, frf, (nfev, nit) = case
    assert 200 <= len(frf) <= 300
    assert nfev <= 1.5 * len(frf)  # element calls: the stuck stretches cost none
    assert nit <= 1.5 * len(frf)


def time_integration(blade, omega, periods=60, samples=2048):
    """Blade + Jenkins slider integrated with solve_ivp, event-driven between stick and slip;
    returns the first-harmonic amplitude of x over the last period and over the one before."""
    m, c, k, F = blade.mass, blade.damping, blade.stiffness, blade.force
    T = 2 * math.pi / omega
    t_end = periods * T
    t, x, v, w, phase = 0.0, 0.0, 0.0, 0.0, 0  # phase 0: stuck (slider at w); +-1: slipping
    pieces = []
    while t < t_end * (1 - 1e-14):
        if phase == 0:
            def rhs(tt, y, w=w):
                return [y[1], (F * math.cos(omega * tt) - c * y[1] - k * y[0] - K_D * (y[0] - w)) / m]

            def event(tt, y, w=w):
                return abs(K_D * (y[0] - w)) - SLIP
            event.direction = 1
        else:
            def rhs(tt, y, s=phase):
                return [y[1], (F * math.cos(omega * tt) - c * y[1] - k * y[0] - s * SLIP) / m]

            def event(tt, y):  # the slider sticks when the velocity reverses
                return y[1]
            event.direction = -phase
        event.terminal = True
        sol = solve_ivp(rhs, (t, t_end), [x, v], method="DOP853", rtol=1e-10, atol=1e-12,
                        events=event, dense_output=True)
        pieces.append((t, sol.t[-1], sol.sol))
        t, (x, v) = sol.t[-1], sol.y[:, -1]
        if sol.status == 1:
            if phase == 0:
                phase = 1 if K_D * (x - w) > 0 else -1
            else:
                w, phase = x - phase * SLIP / K_D, 0

    def first_harmonic(t0):
        ts = t0 + T * np.arange(samples) / samples
        xs = np.empty(samples)
        for a, b, f in pieces:
            sel = (ts >= a) & (ts <= b)
            if np.any(sel):
                xs[sel] = f(ts[sel])[0]
        return 2 / samples * math.hypot(np.sum(xs * np.cos(omega * ts)), np.sum(xs * np.sin(omega * ts)))

    return first_harmonic(t_end - T), first_harmonic(t_end - 2 * T)


def test_against_time_integration_at_resonance():
    """Measured single-harmonic error at the peak: the time response's first harmonic is
    0.47 % above the HB amplitude (zeta = 1e-2, F = 0.5, a = 1.56 a*); docs/hbm.md."""
    blade = Blade.from_modal(frequency=1.0, damping_ratio=1e-2, mass=1.0, force=FORCE)
    frf = frequency_response(blade, macroslip(K_D, SLIP), omega_range=(0.5, 2.0), harmonics=1)
    w_pk, a_hb = frf.peak()
    a_ti, a_prev = time_integration(blade, w_pk)
    assert abs(a_ti / a_prev - 1) < 1e-8  # steady state reached
    err = a_ti / a_hb - 1
    assert 0.003 < err < 0.007
