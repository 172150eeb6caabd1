"""The Jenkins element's harmonics in closed form (``contact_models.numerics.jenkins``) against
independent answers: the describing function at H = 1, the sampled AFT as n_t grows, time stepping
from rest, finite differences of the Jacobian, and properties of random paths (never slipping,
slipping all the time, 2 to 4 reversals per period, a near-double reversal)."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from contact_models import Macroslip
from contact_models.macroslip import jenkins_fourier
from contact_models.numerics.jenkins import jenkins_harmonics, reversals
from contact_models.numerics.masing import aft_scalar, to_harmonics


def aft(el, X, n_t):
    """The sampled AFT of the element's Masing march (what ``harmonic_force`` did before)."""
    return aft_scalar(el._masing_tangent, np.asarray(X, dtype=float), 1.0, n_t, masing=True)[:2]


def path(H, X0=0.0, **harmonics):
    """``X`` of length 2H+1 from keywords ``c1=..., s3=...``."""
    X = np.zeros(2 * H + 1)
    X[0] = X0
    for key, v in harmonics.items():
        h = int(key[1:])
        X[2 * h - 1 + (key[0] == "s")] = v
    return X


SMOOTH = path(5, X0=0.2, c1=0.8, s1=0.3, c2=0.1, s4=0.05)  # two reversals per period
LOOPS = path(5, s1=1.0, s3=0.6)  # six reversals: inner loops


# ------------------------------------------------------------------ H = 1: the describing function
@pytest.mark.parametrize("a", [0.3, 0.5, 0.5000001, 0.9, 2.0, 37.0])
@pytest.mark.parametrize("phase", [0.0, 0.7, -2.1])
def test_first_harmonic_is_the_describing_function(a, phase):
    """x = X0 + a sin(theta + phase): f_s, f_c of ``jenkins_fourier`` rotated by the phase, to rounding,
    and the Jacobian of the describing-function route ``harmonic_force`` takes at H = 1."""
    k, fs = 2.0, 1.0
    X = np.array([0.4, a * math.sin(phase), a * math.cos(phase)])
    F, J = jenkins_harmonics(X, k, fs)
    f_s, f_c = (float(v[0]) for v in jenkins_fourier(k, fs / k, np.array([a]))[:2])
    want = [0.0, f_s * math.sin(phase) + f_c * math.cos(phase), f_s * math.cos(phase) - f_c * math.sin(phase)]
    np.testing.assert_allclose(F, want, rtol=0, atol=1e-14 * k * a)
    J_df = Macroslip(k, fs).harmonic_force(X, 1.0)[1]
    np.testing.assert_allclose(J, J_df, rtol=0, atol=1e-12 * k)


# ------------------------------------------------------------------ against the sampled AFT
@pytest.mark.parametrize("X", [SMOOTH, LOOPS], ids=["smooth", "inner loops"])
def test_sampled_aft_converges_to_it(X):
    """The AFT's difference falls like its own error (about n_t^-2: by more than 50 per 16 times the
    samples), to 1e-11 of the slip force at 2^20 samples, on a smooth path and on one with inner loops."""
    el = Macroslip(1.0, 0.3)
    F = jenkins_harmonics(X, 1.0, 0.3)[0]
    err = [np.abs(aft(el, X, n)[0] - F).max() for n in (2**12, 2**16, 2**20)]
    assert err[0] / err[1] > 50.0 and err[1] / err[2] > 50.0, err
    assert err[2] < 1e-11 * 0.3, err


def test_time_stepping_from_rest():
    """Three periods of the element's own return map (``force_history``) from rest at 2^16 steps per
    period: the last period's harmonics (the path slips every period, so memory of the start is
    gone) agree to the rectangle rule's error on a path with inner loops."""
    el = Macroslip(1.0, 0.3)
    n = 2**16
    X = LOOPS
    theta = 2.0 * np.pi * np.arange(3 * n) / n
    H = (X.size - 1) // 2
    ang = np.outer(theta, np.arange(1, H + 1))
    x = X[0] + np.cos(ang) @ X[1::2] + np.sin(ang) @ X[2::2]
    f = el.force_history(x)[2 * n:]
    np.testing.assert_allclose(to_harmonics(f, H), jenkins_harmonics(X, 1.0, 0.3)[0], rtol=0, atol=1e-8)


@pytest.mark.parametrize("X", [SMOOTH, LOOPS], ids=["smooth", "inner loops"])
def test_jacobian_finite_differences(X):
    k, fs = 1.0, 0.3
    J = jenkins_harmonics(X, k, fs)[1]
    h = 1e-7
    fd = np.column_stack([(jenkins_harmonics(X + h * e, k, fs)[0] - jenkins_harmonics(X - h * e, k, fs)[0]) / (2 * h)
                          for e in np.eye(X.size)])
    np.testing.assert_allclose(J, fd, rtol=0, atol=1e-7 * k)


def test_harmonic_force_is_exact_and_ignores_n_t():
    """``Macroslip.harmonic_force`` at H > 1 is the closed form whatever n_t; the "from rest" slider
    still goes through AFT and declares it."""
    el = Macroslip(1.0, 0.3)
    assert el.exact_harmonics and not Macroslip(1.0, 0.3, slider="from rest").exact_harmonics
    F, J = jenkins_harmonics(LOOPS, 1.0, 0.3)
    for n_t in (12, 64, 4096):
        Fn, Jn, Fw = el.harmonic_force(LOOPS, 2.0, n_t=n_t)
        assert np.array_equal(Fn, F) and np.array_equal(Jn, J) and not np.any(Fw)


# ------------------------------------------------------------------ close reversals
@pytest.mark.parametrize("delta", [1e-3, 1e-6, 1e-9, 1e-12])
def test_near_double_reversal(delta):
    """x = sin theta + b sin 3 theta has a double reversal at theta = pi/2 for b = 1/9: for b above it a
    tiny inner loop (of height about delta^2) opens at the top.  Across b = 1/9 the force moves as the
    Jacobian says, to the loop's size; and it is the AFT's answer."""
    el = Macroslip(1.0, 0.05)
    lo, hi = path(3, s1=1.0, s3=1.0 / 9.0 - delta), path(3, s1=1.0, s3=1.0 / 9.0 + delta)
    (Flo, Jlo), (Fhi, Jhi) = jenkins_harmonics(lo, 1.0, 0.05), jenkins_harmonics(hi, 1.0, 0.05)
    step = 0.5 * (Jlo + Jhi) @ (hi - lo)
    assert np.abs(Fhi - Flo - step).max() <= 50.0 * delta**2 + 1e-15, (Fhi - Flo - step)
    assert len(reversals(hi[1::2] - 1j * hi[2::2])) >= len(reversals(lo[1::2] - 1j * lo[2::2])) >= 2
    for X, F in ((lo, Flo), (hi, Fhi)):
        assert np.abs(aft(el, X, 2**16)[0] - F).max() < 1e-8


# ------------------------------------------------------------------ random paths
def _random_path(draw, H, loops):
    a1 = draw(st.floats(0.05, 10.0))
    X = np.zeros(2 * H + 1)
    X[0] = draw(st.floats(-5.0, 5.0))
    phase = draw(st.floats(0.0, 2.0 * np.pi))
    X[1], X[2] = a1 * math.cos(phase), a1 * math.sin(phase)
    for h in range(2, H + 1):
        size = a1 * (draw(st.floats(0.3, 0.9)) if loops and h == draw(st.sampled_from([2, 3])) else
                     draw(st.floats(0.0, 0.2)) / h**2)
        ph = draw(st.floats(0.0, 2.0 * np.pi))
        X[2 * h - 1], X[2 * h] = size * math.cos(ph), size * math.sin(ph)
    return X


@st.composite
def cases(draw):
    H = draw(st.integers(2, 6))
    X = _random_path(draw, H, draw(st.booleans()))
    k = draw(st.floats(0.1, 10.0))
    # from sticking all period (fs above k times the half range) to slipping nearly all of it
    fs = k * float(np.sum(np.abs(X[1:]))) * draw(st.sampled_from([1e-4, 0.01, 0.2, 0.6, 1.5]))
    return X, k, fs


@given(cases())
def test_random_paths_against_aft(case):
    X, k, fs = case
    F, J = jenkins_harmonics(X, k, fs)
    el = Macroslip(k, fs)
    scale = fs + k * float(np.sum(np.abs(X[1:])))
    Fa = aft(el, X, 2**14)[0]
    assert np.abs(F - Fa).max() <= 1e-6 * scale
    # dissipation per cycle, pi sum_h h (Xs_h Fc_h - Xc_h Fs_h), is >= 0; |f| <= fs bounds the power
    h = np.arange(1, (X.size - 1) // 2 + 1)
    assert float(np.sum(h * (X[2::2] * F[1::2] - X[1::2] * F[2::2]))) >= -1e-12 * scale * np.abs(X[1:]).sum()
    assert F[0] ** 2 + 0.5 * float(np.sum(F[1:] ** 2)) <= fs * fs * (1.0 + 1e-12) or fs >= k * np.abs(X[1:]).sum()


@given(cases())
def test_random_paths_jacobian(case):
    """Each column of the Jacobian is the derivative by finite differences; where F has a kink at X
    (the slip onset, a reversal where the force just reaches fs, two equal extremes) it is one of
    the one-sided derivatives."""
    X, k, fs = case
    F, J = jenkins_harmonics(X, k, fs)
    hstep = 1e-7 * float(np.abs(X[1:]).sum())
    for j, e in enumerate(np.eye(X.size)):
        fwd = (jenkins_harmonics(X + hstep * e, k, fs)[0] - F) / hstep
        bwd = (F - jenkins_harmonics(X - hstep * e, k, fs)[0]) / hstep
        assert min(np.abs(J[:, j] - fwd).max(), np.abs(J[:, j] - bwd).max()) <= 1e-5 * k, (j, J[:, j], fwd, bwd)


def test_stuck_and_always_slipping():
    """Never slipping: F = k X less k x_c in F0 (x_c the centre of the range).  A slip force 1e-9 of
    the range: a square wave fs sign(x') but for the stuck arcs after each reversal (about
    sqrt(8 fs/(k a)) = 9e-5 rad wide); for x = a sin theta its harmonics are
    (4 fs/(pi h)) (-1)^((h-1)/2) in cos for odd h."""
    X = path(4, X0=1.0, s1=1.0, c2=0.2)
    F = jenkins_harmonics(X, 3.0, 100.0)[0]
    theta = np.linspace(0.0, 2.0 * np.pi, 200001)
    x = 1.0 + np.sin(theta) + 0.2 * np.cos(2.0 * theta)
    xc = 0.5 * (x.max() + x.min())
    np.testing.assert_allclose(F, 3.0 * (X - xc * np.eye(X.size)[0]), rtol=0, atol=1e-9)
    fs = 1e-9
    F = jenkins_harmonics(path(5, s1=1.0), 1.0, fs)[0]
    square = np.zeros(11)
    h = np.arange(1, 6, 2)
    square[1::4] = 4.0 * fs / (np.pi * h) * (-1.0) ** ((h - 1) // 2)
    np.testing.assert_allclose(F, square, rtol=0, atol=1e-4 * fs)
