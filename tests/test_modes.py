"""Nonlinear modes (EPMC), the forced response from one mode, and the damper's optimum.

Independent answers: NLvib 1.3's EPMC (``docs/data/nlvib_epmc_*.csv``, written by
``benchmarks/peers/nlvib_epmc.m``), closed forms (the stuck linear mode, the one-DOF describing
function), the energy per cycle, the time integration of the autonomous system by the library's
event integrator, and the full FRF (``hbm.frequency_response``).
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from contact_models import Iwan, Macroslip, QuasiStatic, TwoRegionMicroslip, UniformLoad
from hbm import Contact, Structure, damper_optimum, forced_response, frequency_response, nonlinear_modes
from hbm.cli.cases import default_case
from hbm.reference.piecewise import EventIntegrator
from hbm.reference.system import build_model

DATA = Path(__file__).resolve().parent.parent / "docs" / "data"
K2 = np.array([[2.0, -1.0], [-1.0, 2.0]])
K3 = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])


def ground():
    """The NLvib script's first system: Jenkins (1, 0.1) from DOF 0 to the ground of a 2-DOF chain."""
    return Structure(np.eye(2), 0.01 * K2, K2, force=[1.0, 0.0]), [Contact(Macroslip(stiffness=1.0, slip_force=0.1), dof=0)]


def between():
    """The NLvib script's second system: Jenkins (1, 0.05) between DOFs 0 and 1 of the 3-DOF chain."""
    return (Structure(np.eye(3), 0.004 * K3, K3, force=[0.0, 0.0, 1.0]),
            [Contact(Macroslip(stiffness=1.0, slip_force=0.05), dofs=(0, 1))])


def chain():
    """The 3-DOF chain of docs/multiharmonic.md."""
    s = Structure(np.eye(3), 0.004 * K3, K3, force=[0.0, 0.0, 0.01])
    return s, [Contact(Macroslip(stiffness=1.0, slip_force=0.02), dof=0),
               Contact(Macroslip(stiffness=1.0, slip_force=0.05), dofs=(0, 1))]


@pytest.mark.parametrize("name, make", [("ground", ground), ("between", between)])
def test_against_nlvib(name, make):
    ref = np.loadtxt(DATA / f"nlvib_epmc_{name}.csv", delimiter=",", skiprows=2)
    s, contacts = make()
    m = nonlinear_modes(s, contacts, amplitudes=ref[:, 0], harmonics=7, n_t=1024)
    assert m.success and len(m) == 25
    np.testing.assert_allclose(m.amplitude, ref[:, 0], rtol=1e-14)
    assert np.max(np.abs(m.omega / ref[:, 1] - 1.0)) < 1e-4
    assert np.max(np.abs(m.damping_ratio / ref[:, 2] - 1.0)) < 1e-4
    # the range runs from stuck (omega constant) to gross slip (omega falls by more than 5 %)
    assert m.omega[0] == pytest.approx(m.omega[3], rel=1e-12)
    assert m.omega[-1] < 0.95 * m.omega[0]


def test_stuck_start_is_the_linear_mode():
    # mass-proportional damping c M: the stuck EPMC is the undamped mode with D = c / (2 omega)
    s = Structure(np.eye(2), 0.02 * np.eye(2), K2, force=[1.0, 0.0])
    m = nonlinear_modes(s, ground()[1], amplitudes=[1e-3], harmonics=3)
    # K + kt e0 e0^T = [[3, -1], [-1, 2]]: lowest eigenvalue (5 - sqrt 5)/2
    w = math.sqrt((5.0 - math.sqrt(5.0)) / 2.0)
    assert m.omega[0] == pytest.approx(w, rel=1e-12)
    assert m.damping_ratio[0] == pytest.approx(0.01 / w, rel=1e-10)
    phi = m.shapes[0, :, 1]
    assert phi @ phi == pytest.approx(1.0, rel=1e-12)  # M = I: mass-normalised
    assert np.max(np.abs(m.shapes[0, :, 3:])) < 1e-12  # stuck: no higher harmonics


def test_one_dof_describing_function_closed_form():
    # m x'' + c x' + k x + f_J = 0 at H = 1: omega^2 m = k + f_s/X, 2 D omega^2 m = c omega + f_c/X, X = a/sqrt(m)
    mass, k, c = 2.0, 3.0, 0.02
    el = Macroslip(stiffness=1.5, slip_force=0.2)
    s = Structure([[mass]], [[c]], [[k]], force=[1.0])
    amps = np.array([0.05, 0.5, 2.0, 20.0])
    m = nonlinear_modes(s, [Contact(el, dof=0)], amplitudes=amps, harmonics=1)
    X = amps / math.sqrt(mass)
    fs, fc = el.fourier(X)
    w = np.sqrt((k + fs / X) / mass)
    np.testing.assert_allclose(m.omega, w, rtol=1e-10)
    np.testing.assert_allclose(m.damping_ratio, (c * w + fc / X) / (2.0 * mass * w ** 2), rtol=1e-9)


def test_energy_balance_at_every_point():
    s, contacts = chain()
    m = nonlinear_modes(s, contacts, amplitude_range=(1e-3, 10.0), harmonics=7, n_t=512)
    assert m.success and len(m) > 20
    E = m.energies()
    assert np.all(E[:, 2] > 0.0) and np.all(E[:, 0] >= -1e-12 * E[:, 2])  # stuck: zero to rounding
    assert np.max(np.abs(E[:, 0] + E[:, 1] - E[:, 2]) / E[:, 2]) < 1e-8
    assert np.max(E[:, 0] / E[:, 2]) > 0.9  # the contacts' share dominates in slip


@pytest.mark.parametrize("a", [0.25, 1.0, 5.0])
def test_time_integration_returns_to_the_orbit(a):
    """The autonomous system M q'' + (C - 2 D omega M) q' + K q + f = 0, integrated exactly (event
    integrator) from the mode's state at t = 0 over three periods T = 2 pi / omega, stays on the orbit."""
    s, contacts = ground()
    H = 25
    m = nonlinear_modes(s, contacts, amplitudes=[a], harmonics=H, n_t=2048)
    w, D = float(m.omega[0]), float(m.damping_ratio[0])
    model = build_model((s.M, s.C - 2.0 * D * w * s.M, s.K, np.zeros(2)), contacts)
    Q = m.coefficients(0)[0], m.coefficients(1)[0]
    h = np.arange(1, H + 1)
    steps = 256
    theta = 2.0 * np.pi * np.arange(steps) / steps
    x_hb = np.array([q[0] + np.cos(np.outer(theta, h)) @ q[1::2] + np.sin(np.outer(theta, h)) @ q[2::2] for q in Q])
    x0 = x_hb[:, 0]
    v0 = np.array([w * h @ q[2::2] for q in Q])
    f0 = contacts[0].element.periodic_force(x_hb[0], w)[0][0]
    y = np.concatenate([x0, v0, [x0[0] - f0 / 1.0]])
    integ = EventIntegrator(model, w, steps)
    scale = np.max(np.abs(x_hb))
    for _ in range(3):
        y, rec = integ.period_map(y, record=True)
        assert np.max(np.abs(rec[:, :2].T - x_hb)) < 5e-5 * scale
    assert np.max(np.abs(y[:2] - x0)) < 5e-5 * scale


def test_other_time_laws_and_describing_functions():
    s, _ = ground()
    iwan = Iwan(slip_force=0.1, stiffness=1.0, chi=-0.5, beta=0.1)
    m = nonlinear_modes(s, [Contact(iwan, dof=0)], amplitude_range=(1e-3, 3.0), harmonics=5, n_t=256)
    E = m.energies()
    assert m.success and np.max(np.abs(E[:, 0] + E[:, 1] - E[:, 2]) / E[:, 2]) < 1e-8
    assert m.omega[-1] < m.omega[0]
    case = default_case()
    bar = case.element.bar
    blade = case.blade.as_structure()
    sm = math.sqrt(case.blade.mass)
    qs = QuasiStatic(TwoRegionMicroslip(bar, UniformLoad(N=100.0)))
    mq = nonlinear_modes(blade, [Contact(qs, dof=0)], amplitude_range=(1e-7 * sm, 3e-6 * sm), harmonics=3)
    assert mq.success and mq.damping_ratio.max() > 2.0 * mq.damping_ratio[0]
    with pytest.raises(ValueError, match="element"):
        nonlinear_modes(blade, [Contact(case.element, dof=0)], amplitude_range=(1e-7, 1e-6), harmonics=3)


def test_forced_response_of_the_blade_is_its_frf():
    case = default_case()
    sm = math.sqrt(case.blade.mass)
    m = nonlinear_modes(case.blade.as_structure(), [Contact(case.element, dof=0)],
                        amplitude_range=(1e-8 * sm, 1e-5 * sm), harmonics=1)
    fr = forced_response(m)
    pk = frequency_response(case.blade, case.element, omega_range=case.omega_range).peak()
    assert fr.peak.omega == pytest.approx(pk.omega, rel=1e-7)
    assert fr.peak.amplitude == pytest.approx(pk.amplitude, rel=1e-7)
    # both flanks, up to the peak
    assert np.any(fr.side < 0) and np.any(fr.side > 0) and fr.amplitude.max() <= fr.peak.amplitude * (1 + 1e-12)


def test_forced_response_of_the_chain_near_its_frf():
    s, contacts = chain()
    fr = forced_response(nonlinear_modes(s, contacts, amplitude_range=(1e-3, 10.0), harmonics=7, n_t=512))
    pk = frequency_response(s, contacts, omega_range=(0.3, 0.9), harmonics=7, n_t=512, response_dof=2).peak()
    assert abs(fr.peak.omega / pk.omega - 1.0) < 5e-3
    assert abs(fr.peak.amplitude / pk.amplitude - 1.0) < 2.5e-2


def test_damper_optimum_is_the_frf_optimum():
    case = default_case()
    bar, sm = case.element.bar, math.sqrt(case.blade.mass)
    opt = damper_optimum(case.blade.as_structure(), lambda N: [Contact(TwoRegionMicroslip(bar, UniformLoad(N=N)), dof=0)],
                         (30.0, 90.0), amplitude_range=(1e-8 * sm, 1e-5 * sm))
    assert opt.success and 30.0 < opt.parameter < 90.0

    def frf_peak(N):
        el = TwoRegionMicroslip(bar, UniformLoad(N=N))
        return frequency_response(case.blade, el, omega_range=case.omega_range).peak()

    at = frf_peak(opt.parameter)
    assert opt.peak.amplitude == pytest.approx(at.amplitude, rel=1e-7)
    assert opt.peak.omega == pytest.approx(at.omega, rel=1e-7)
    assert at.amplitude < frf_peak(0.995 * opt.parameter).amplitude
    assert at.amplitude < frf_peak(1.005 * opt.parameter).amplitude


def test_damper_optimum_is_the_optimum_of_a_dense_frf_scan_whatever_the_bracket():
    """The optimum load by (30, 90) N was 52.3644 N and by (30, 1e6) N 52.3138 N: the Jacobian's p column left
    out the peak condition's derivative in p, and its step was 1e-7 of the bracket's width (0.1 N for 1e6 N), so
    the tangent the stationary amplitude is located with was off.  Checked against the minimum of the FRF's
    peaks: a parabola through 7 of them over +-0.05 N (its own bias, from the asymmetry of the minimum, about
    7e-7 relative against a quartic through 9 over +-0.3 N)."""
    case = default_case()
    bar, sm = case.element.bar, math.sqrt(case.blade.mass)

    def contacts_of(N):
        return [Contact(TwoRegionMicroslip(bar, UniformLoad(N=N)), dof=0)]

    loads = 52.36 + 0.05 * np.linspace(-1.0, 1.0, 7)
    peaks = np.array([frequency_response(case.blade, TwoRegionMicroslip(bar, UniformLoad(N=N)),
                                         omega_range=case.omega_range).peak().amplitude for N in loads])
    c2, c1, _ = np.polyfit(loads - 52.36, peaks / peaks[3], 2)
    assert c2 > 0.0
    scanned = 52.36 - c1 / (2.0 * c2)
    found = [damper_optimum(case.blade.as_structure(), contacts_of, bounds, amplitude_range=(1e-8 * sm, 1e-5 * sm))
             for bounds in ((30.0, 90.0), (30.0, 1e6))]
    assert all(opt.success for opt in found)
    for opt in found:
        assert opt.parameter == pytest.approx(scanned, rel=5e-6)
    assert found[1].parameter == pytest.approx(found[0].parameter, rel=1e-6)



def _jenkins_mode_amplitude(A, k=300.0, F=1.0):
    """The first mode's amplitude ``a`` (``a^2 = Q^H M Q``) of ``folded()`` at H = 1 where the contact's
    amplitude is ``A``, by hand: the Jenkins element's describing function (in phase ``k/pi (phi - sin(2 phi)/2)``,
    ``cos phi = 1 - 2 F/(k A)``; in quadrature ``4 F (A - F/k)/(pi A^2)``, its energy per cycle) in the stiffness,
    the complex eigenvector ``v`` of the lowest mode (M = I; C = c I only shifts the eigenvalues), ``a = A/|v_0|``."""
    xs = F / k
    phi = math.acos(1.0 - 2.0 * xs / A) if A > xs else math.pi
    kc = complex(k / math.pi * (phi - 0.5 * math.sin(2.0 * phi)), 4.0 * F * max(A - xs, 0.0) / (math.pi * A * A))
    lam, V = np.linalg.eig(K2 + np.diag([kc, 0.0]))
    v = V[:, int(np.argmin(lam.real))]
    return A * np.linalg.norm(v) / abs(v[0])


def folded():
    """A stiff Jenkins contact (300 times the chain's spring) on DOF 0 of the 2-DOF chain: as it slips, its
    DOF's share of the first mode grows faster than the contact's amplitude, and the mode folds in ``a``."""
    return (Structure(np.eye(2), 0.001 * np.eye(2), K2, force=[1.0, 0.0]),
            [Contact(Macroslip(stiffness=300.0, slip_force=1.0), dof=0)])


def test_a_mode_that_folds_back_through_its_start_amplitude_turned_back_and_says_where():
    """The mode of ``folded()`` rises to a = 1.26556 (A = 0.0891), turns back down to a = 1.07130 (A = 0.649) and
    rises again (``_jenkins_mode_amplitude``, independent of the balance).  Started at a0 = 1.1, between the two
    turns, its branch comes back through a0 without reaching a1 = 10: it reported success, "reached the end of the
    parameter range (at its lower end)".  Now it turned back and says at which amplitude; from a0 = 1.0, below the
    lower turn, the branch passes both folds and reaches a1."""
    grid = np.geomspace(1.0 / 300.0, 1.0, 20001)
    a = np.array([_jenkins_mode_amplitude(A) for A in grid])
    i = int(np.argmax(a[:-1] > a[1:]))  # the first turn
    j = i + int(np.argmax(a[i + 1:-1] < a[i + 2:]))  # the second
    a_turn, a_back = float(a[i]), float(a[j + 1])
    assert a_turn == pytest.approx(1.26556, rel=1e-5) and a_back == pytest.approx(1.07130, rel=1e-5)
    s, cs = folded()
    m = nonlinear_modes(s, cs, amplitude_range=(1.1, 10.0), harmonics=1)
    assert not m.success and m.amplitude[-1] == pytest.approx(1.1, rel=1e-14) and m.amplitude.max() < 1.3
    turned = float(re.search(r"it turned at amplitude a = (\S+) and came back to a0 = 1\.1 before reaching a1 = 10 ",
                             m.message).group(1))
    assert m.message.startswith("the branch turned back and left the parameter range where it started: ")
    assert turned == pytest.approx(a_turn, rel=1e-3)
    # the traced points are on the mode: each amplitude is the closed form's at the contact's amplitude
    A = m.amplitude * np.hypot(m.shapes[:, 0, 1], m.shapes[:, 0, 2])
    assert np.allclose([_jenkins_mode_amplitude(x) for x in A], m.amplitude, rtol=1e-6)
    whole = nonlinear_modes(s, cs, amplitude_range=(1.0, 10.0), harmonics=1)
    assert whole.success and whole.amplitude[-1] == pytest.approx(10.0, rel=1e-14)
    assert whole.amplitude.max() == pytest.approx(10.0, rel=1e-14) and np.any(np.diff(whole.amplitude) < 0.0)

def test_bad_input_names_the_parameter():
    s, contacts = ground()
    for kwargs, name in [({"amplitude_range": (1.0, 0.5)}, "amplitude_range"),
                         ({"amplitude_range": (-1.0, 0.5)}, "amplitude_range"),
                         ({"amplitude_range": None}, "amplitude_range"),
                         ({"amplitude_range": (0.1, 1.0), "amplitudes": [2.0]}, "amplitudes"),
                         ({"amplitudes": [0.0, 1.0]}, "amplitudes"),
                         ({"amplitude_range": (0.1, 1.0), "mode": 2}, "mode"),
                         ({"amplitude_range": (0.1, 1.0), "harmonics": 0}, "harmonics"),
                         ({"amplitude_range": (0.1, 1.0), "phase_dof": 5}, "phase_dof")]:
        with pytest.raises(ValueError, match=name):
            nonlinear_modes(s, contacts, **kwargs)
    with pytest.raises(ValueError, match="contacts"):
        nonlinear_modes(s, [], amplitude_range=(0.1, 1.0))
    with pytest.raises(ValueError, match="contacts_of"):
        damper_optimum(s, None, (1.0, 2.0), amplitude_range=(0.1, 1.0))
    with pytest.raises(ValueError, match="bounds"):
        damper_optimum(s, lambda p: contacts, (2.0, 1.0), amplitude_range=(0.1, 1.0))
    m = nonlinear_modes(s, contacts, amplitude_range=(1e-3, 1e-2), harmonics=1)
    with pytest.raises(ValueError, match="modes must reach"):
        forced_response(m)


@pytest.mark.parametrize("kwargs, message", [
    # before, a tol of 2 was taken (a Newton residual twice the inertia force counted as converged), strings
    # among the amplitudes failed inside numpy, and a contact on a DOF past the structure raised an IndexError
    (dict(newton_tol=2.0), r"^newton_tol must be < 1, got newton_tol=2.0$"),
    (dict(amplitudes=["a"]), r"^amplitudes must be finite numbers > 0, got amplitudes=\['a'\]$"),
])
def test_bad_input_names_the_value(kwargs, message):
    s, contacts = ground()
    with pytest.raises(ValueError, match=message):
        nonlinear_modes(s, contacts, **{"amplitudes": [0.01, 1.0], **kwargs})


@pytest.mark.parametrize("amplitudes", [True, [True, 2.0]])
def test_a_boolean_amplitude_is_refused_by_name(amplitudes):
    """True was read as an amplitude of 1.0 (alone, or among numbers in a list, which numpy converts)."""
    s, contacts = ground()
    with pytest.raises(ValueError, match=rf"^amplitudes must be finite numbers > 0, got amplitudes={re.escape(repr(amplitudes))}$"):
        nonlinear_modes(s, contacts, amplitudes=amplitudes)


@pytest.mark.parametrize("force", [True, [True]])
def test_the_forced_response_refuses_a_boolean_force_by_name(force):
    """True was read as a force of 1 N (forced_response and damper_optimum share the check)."""
    case = default_case()
    sm = math.sqrt(case.blade.mass)
    m = nonlinear_modes(case.blade.as_structure(), [Contact(case.element, dof=0)],
                        amplitude_range=(1e-8 * sm, 1e-5 * sm))
    with pytest.raises(ValueError, match=rf"^force must be 1 finite numbers, not all zero, got force={re.escape(repr(force))}$"):
        forced_response(m, force=force)


@pytest.mark.parametrize("force, where", [
    # before: numpy.linalg.LinAlgError (r^2 = inf in the quartic's roots) and ZeroDivisionError (r^2 = 0)
    (1e300, "beyond the branch's last amplitude"), (1e200, "beyond the branch's last amplitude"),
    (1e-300, "below the branch's first amplitude"), (1e-200, "below the branch's first amplitude"),
])
def test_a_force_whose_square_leaves_double_precision_says_where_the_peak_lies(force, where):
    case = default_case()
    sm = math.sqrt(case.blade.mass)
    m = nonlinear_modes(case.blade.as_structure(), [Contact(case.element, dof=0)],
                        amplitude_range=(1e-8 * sm, 1e-5 * sm))
    with pytest.raises(ValueError, match=rf"^modes must reach the peak's modal amplitude .*the peak lies {where}.* "
                                         rf"max \|f\| = {re.escape(format(force, '.4g'))} N$"):
        forced_response(m, force=[force])


def test_the_forced_response_of_a_mode_without_points_is_refused_by_name():
    """A mode of no points (none of the amplitudes asked for located): its first amplitude was an IndexError."""
    from dataclasses import replace

    s, contacts = ground()
    m = nonlinear_modes(s, contacts, amplitudes=[0.01, 1.0])
    m = replace(m, amplitude=m.amplitude[:0], omega=m.omega[:0], damping_ratio=m.damping_ratio[:0],
                shapes=m.shapes[:0], points=m.points[:0], residual_norm=m.residual_norm[:0])
    assert len(m) == 0
    with pytest.raises(ValueError, match=r"^modes must reach the peak's modal amplitude, got a mode of no points$"):
        forced_response(m)


def test_a_contact_past_the_structure_is_refused_by_name():
    s, _ = ground()
    with pytest.raises(ValueError, match=r"^dof must be a DOF index in 0..1, got dof=5 in "):
        nonlinear_modes(s, [Contact(Macroslip(1.0, 0.1), dof=5)], amplitudes=[1.0])


def test_mode_coefficients_and_forced_response_name_bad_input():
    s, contacts = ground()
    m = nonlinear_modes(s, contacts, amplitude_range=(1e-3, 1e-2), harmonics=1)
    for dof in (5, -1, 1.5):  # before: an IndexError, a silent count from the end, an IndexError
        with pytest.raises(ValueError, match=rf"^dof must be a DOF index in 0..1, got dof={dof}$"):
            m.coefficients(dof)
    with pytest.raises(ValueError, match=r"^force must be 2 finite numbers, not all zero, got force='ab'$"):
        forced_response(m, force="ab")  # before: numpy's "could not convert string to float"


@pytest.mark.parametrize("kwargs, message", [
    # checked before the mode at the first bound is traced: that trace failed first, and said the mode
    # does not reach the peak
    (dict(max_step=0.0), r"^max_step must be positive, got max_step=0.0$"),
    (dict(max_steps=0), r"^max_steps must be an integer >= 1, got max_steps=0$"),
    (dict(newton_tol=-1.0), r"^newton_tol must be positive, got newton_tol=-1.0$"),
    (dict(newton_tol=2.0), r"^newton_tol must be < 1, got newton_tol=2.0$"),
])
def test_damper_optimum_checks_its_controls_first(kwargs, message):
    s, contacts = ground()
    traced = []

    def contacts_of(p):
        traced.append(p)
        return contacts
    with pytest.raises(ValueError, match=message):
        damper_optimum(s, contacts_of, (1.0, 2.0), amplitude_range=(0.1, 1.0), **kwargs)
    assert traced == []


@pytest.mark.parametrize("bounds, at, why", [
    ((-10.0, 90.0), -10.0, "N must be >= 0, got N=-10.0"),  # before: that message alone, naming N, not bounds
    ((0.05, 0.2), 0.2, "slip_force must be positive, got slip_force=-0.1"),
])
def test_damper_optimum_names_bounds_where_a_bound_gives_no_contacts(bounds, at, why):
    """The element's own message names its parameter (N), which the caller never passed to damper_optimum: the
    refusal names ``bounds`` and keeps it.  Any scalar parametrisation is taken (p = log10 N may be negative),
    so the bounds are refused where ``contacts_of`` refuses them, not by their sign; nothing is traced."""
    s, _ = ground()
    traced = []

    def contacts_of(p):
        traced.append(p)
        if bounds[0] < 0.0:
            return [Contact(TwoRegionMicroslip(default_case().element.bar, UniformLoad(N=p)), dof=0)]
        return [Contact(Macroslip(stiffness=1.0, slip_force=round(0.1 - p, 12)), dof=0)]

    with pytest.raises(ValueError, match=rf"^bounds must lie where contacts_of builds contacts: contacts_of\({at}\) "
                                         rf"raised ValueError: {re.escape(why)}; "
                                         rf"got bounds={re.escape(repr(bounds))}$"):
        damper_optimum(s, contacts_of, bounds, amplitude_range=(0.1, 1.0))
    assert traced == list(bounds)[:list(bounds).index(at) + 1]  # each bound built once, nothing traced


def test_damper_optimum_stopped_before_the_optimum_keeps_its_curve_and_says_why():
    """A trace that used up max_steps at 30.8 N was reported as 'bounds must contain the optimum: the smallest peak
    on the traced curve is at p1 (30.8352)': the bracket blamed, p1 named for a point short of it, the curve lost."""
    case = default_case()
    bar, sm = case.element.bar, math.sqrt(case.blade.mass)
    opt = damper_optimum(case.blade.as_structure(), lambda N: [Contact(TwoRegionMicroslip(bar, UniformLoad(N=N)), dof=0)],
                         (30.0, 90.0), amplitude_range=(1e-8 * sm, 1e-5 * sm), max_steps=2)
    assert not opt.success and not opt.peak.interior and not opt.peak.converged
    assert opt.parameter == opt.parameters[-1] < 52.0 and opt.peak.amplitude == opt.peaks[-1] == opt.peaks.min()
    assert re.match(r"^the peak curve ended at p=30\.\d+ before the optimum \(the peak still falls there\), short of "
                    r"bounds\[1\]=90\.0: the step budget \(max_steps\) was used up", opt.message)
    assert opt.peak.message == opt.message and np.isfinite(opt.peak.omega)


def _example(name):
    import importlib
    import sys

    examples = str(Path(__file__).resolve().parent.parent / "examples")
    if examples not in sys.path:
        sys.path.insert(0, examples)
    return importlib.import_module(name)


def test_example_nonlinear_modes_chain(tmp_path):
    out = _example("nonlinear_modes_chain").main(outdir=tmp_path, small=True)
    assert Path(out["path"]).stat().st_size > 10_000
    # stuck: K + both contacts as unit springs = [[4, -2, 0], [-2, 3, -1], [0, -1, 1]]
    w = math.sqrt(np.linalg.eigvalsh([[4.0, -2.0, 0.0], [-2.0, 3.0, -1.0], [0.0, -1.0, 1.0]])[0])
    # to 1.5e-7: C = 0.004 K is not proportional to the stuck stiffness, which moves the EPMC's omega
    assert out["modes"].omega[0] == pytest.approx(w, rel=1e-6)


def test_example_design_chart_from_modes(tmp_path):
    out = _example("design_chart_from_modes").main(outdir=tmp_path, small=True)
    assert Path(out["path"]).stat().st_size > 10_000
    # the optimum of 50 FRFs over 30..90 N, their peaks through a cubic spline (benchmarks/bench_modes.py)
    assert out["optimal_load"] == pytest.approx(52.3637, rel=1e-4)


def test_the_newton_tolerance_is_newton_tol_and_its_earlier_name_warns():
    """``tol`` means the answer's target error in frequency_response; here it was the Newton tolerance, now
    ``newton_tol``: the earlier name gives the same mode with a DeprecationWarning naming the new one."""
    import warnings

    from contact_models import Macroslip
    from hbm import Contact, Structure, nonlinear_modes

    s = Structure(np.eye(2), 0.01 * np.eye(2), [[2.0, -1.0], [-1.0, 2.0]], force=[1.0, 0.0])
    c = [Contact(Macroslip(stiffness=1.0, slip_force=0.1), dof=0)]
    new = nonlinear_modes(s, c, amplitudes=[0.01, 10.0], newton_tol=1e-9)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        old = nonlinear_modes(s, c, amplitudes=[0.01, 10.0], tol=1e-9)
    assert np.array_equal(old.omega, new.omega)
    assert [str(w.message) for w in caught if w.category is DeprecationWarning and "newton_tol" in str(w.message)]
    with pytest.raises(ValueError, match="newton_tol"):
        nonlinear_modes(s, c, amplitudes=[0.01, 10.0], tol=1e-8, newton_tol=1e-9)
