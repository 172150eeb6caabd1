"""The periodic reference (``hbm.reference.shooting``): against closed forms, between its two integrators,
energy per cycle, Floquet multipliers, the stored reference data, bad input."""

from __future__ import annotations

import json
import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

import hbm
from contact_models import Macroslip
from hbm import periodic_peak, periodic_response

DATA = Path(__file__).parent / "data" / "periodic_reference.json"


def contact(element, *dofs):
    return SimpleNamespace(element=element, dofs=tuple(dofs))


class CubicSpring:
    """Stand-in: the shooting reads only ``k3``."""

    def __init__(self, k3):
        self.k3 = k3


def p1(damping=0.004, slip_force=0.02):
    return hbm.Blade(mass=1.0, stiffness=1.0, damping=damping, force=0.01), [contact(Macroslip(1.0, slip_force), 0)]


# ------------------------------------------------------------------ closed forms
def test_never_slipping_contact_is_the_exact_linear_response():
    """Slip force huge: the chain with both contacts stuck, X = (K_st - w^2 M + i w C)^-1 f."""
    K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    M, C, f = np.diag([1.0, 2.0, 0.5]), 0.01 * K + 0.02 * np.eye(3), np.array([0.0, 0.0, 0.01])
    cs = [contact(Macroslip(1.0, 1e3), 0), contact(Macroslip(2.0, 1e3), 0, 1)]
    Kst = K + np.outer([1, 0, 0], [1, 0, 0]) + 2.0 * np.outer([1, -1, 0], [1, -1, 0])
    w = 0.9
    X = np.linalg.solve(Kst - w * w * M + 1j * w * C, f)
    r = periodic_response((M, C, K, f), cs, omega=w, harmonics=3, steps=64)
    assert r.success
    for i in range(3):
        c = r.coefficients(i)
        assert abs(c[1] - X[i]) < 1e-12 * np.max(np.abs(X))
        assert np.max(np.abs(c[[0, 2, 3]])) < 1e-13 * np.max(np.abs(X))
    assert r.max_abs(2) == pytest.approx(abs(X[2]), rel=1e-12)
    # multipliers: exp(lambda T) of the stuck structure, and 1 twice (the two sliders' neutral offsets)
    A = np.block([[np.zeros((3, 3)), np.eye(3)], [-np.linalg.solve(M, Kst), -np.linalg.solve(M, C)]])
    expect = np.exp(np.linalg.eigvals(A) * 2 * np.pi / w)
    got = r.floquet
    assert np.sum(np.abs(got - 1.0) < 1e-8) == 2
    rest = got[np.abs(got - 1.0) >= 1e-8]
    assert np.allclose(np.sort_complex(rest), np.sort_complex(expect), atol=1e-8)


def test_floquet_multipliers_of_a_linear_damped_oscillator_are_exp_lambda_T():
    m, c, k, w = 2.0, 0.3, 5.0, 1.1
    r = periodic_response((np.array([[m]]), np.array([[c]]), np.array([[k]]), np.array([1.0])), omega=w,
                          harmonics=2, steps=32)
    lam = np.roots([m, c, k])
    expect = np.exp(lam * 2 * np.pi / w)
    assert np.allclose(np.sort_complex(r.floquet), np.sort_complex(expect), rtol=0, atol=1e-9)
    assert r.stable
    assert r.amplitude(0) == pytest.approx(1.0 / abs(k - m * w * w + 1j * c * w), rel=1e-13)


# ------------------------------------------------------------------ friction
@pytest.fixture(scope="module")
def p1_at_13():
    blade, cs = p1()
    r = periodic_response(blade, cs, omega=1.3, harmonics=200, steps=1024)
    assert r.success, r.message
    return blade, cs, r


def test_energy_balance_per_cycle(p1_at_13):
    """pi F Xs1 (work of the force) = pi c omega sum h^2 |X_h|^2 (damper) + fs sum |dz| (slider)."""
    blade, cs, r = p1_at_13
    X = r.harmonics[0]
    h = np.arange(1, (X.size - 1) // 2 + 1)
    work_in = math.pi * blade.force * X[2]
    damper = math.pi * blade.damping * r.omega * np.sum(h**2 * (X[1::2] ** 2 + X[2::2] ** 2))
    z = r.z[:, 0]
    slider = cs[0].element.slip_force * np.sum(np.abs(np.diff(np.append(z, z[0]))))
    assert slider > 0.3 * work_in  # the slider slips: a real test of the friction term
    assert damper + slider == pytest.approx(work_in, rel=1e-10)


def test_two_integrators_agree_and_newmark_converges_at_second_order(p1_at_13):
    blade, cs, r = p1_at_13
    a = r.amplitude(0)
    err = []
    for N in (1024, 4096):
        rn = periodic_response(blade, cs, omega=1.3, integrator="newmark", steps=N, initial=r, harmonics=1,
                               floquet=False, tol=1e-10)
        assert rn.success, rn.message
        err.append(abs(rn.amplitude(0) / a - 1.0))
    assert err[1] < 3e-7
    assert err[0] / err[1] > 4.0 ** 1.5  # rate above 1.5 over a factor 4 in the step


def test_event_integrator_independent_of_its_grid(p1_at_13):
    """The event-driven flow is exact between events: 128 grid steps give the 1024-step orbit."""
    blade, cs, r = p1_at_13
    coarse = periodic_response(blade, cs, omega=1.3, steps=128, harmonics=1, initial=r, floquet=False)
    assert np.allclose(coarse.state, r.state, rtol=0, atol=1e-12 * np.max(np.abs(r.state)))
    assert coarse.max_abs(0) == pytest.approx(r.max_abs(0), rel=1e-12)


def test_dop853_path_agrees_with_the_exact_path(p1_at_13):
    """A vanishing cubic spring sends the event-driven integrator through DOP853 (rtol 1e-12)
    with located events instead of the matrix exponential: the same orbit."""
    blade, cs, r = p1_at_13
    r2 = periodic_response(blade, cs + [contact(CubicSpring(1e-300), 0)], omega=1.3, steps=64, harmonics=1,
                           initial=r, floquet=False)
    assert r2.success
    assert np.allclose(r2.state, r.state, rtol=0, atol=1e-9 * np.max(np.abs(r.state)))
    assert r2.max_abs(0) == pytest.approx(r.max_abs(0), rel=1e-9)


def test_friction_orbit_is_stable_with_a_zero_multiplier(p1_at_13):
    """Slipping at t = 0 would make the slider's state forgotten; P1 at 1.3 sticks at t = 0, so
    all three multipliers are inside the unit circle, and the orbit is stable."""
    _, _, r = p1_at_13
    assert r.floquet.size == 3 and r.stable
    assert np.max(np.abs(r.floquet)) < 0.9


def test_duffing_middle_branch_is_unstable():
    """Three coexisting responses at omega = 1.08 (m = k = 1, c = 0.02, k3 = 0.1, F = 0.05):
    the middle one has a real multiplier > 1 (a saddle), the outer ones are stable."""
    system = (np.eye(1), np.array([[0.02]]), np.eye(1), np.array([0.05]))
    cs = [contact(CubicSpring(0.1), 0)]
    w = 1.08
    states = []
    for A in (0.31, 1.35, 1.59):  # single-harmonic amplitudes of the three branches
        X = 0.05 / (1 - w * w + 0.075 * A * A + 0.02j * w)
        r = periodic_response(system, cs, omega=w, initial=np.array([X]), harmonics=5, steps=64)
        assert r.success, r.message
        states.append(r)
    amps = [r.amplitude(0) for r in states]
    assert amps[0] < amps[1] < amps[2]
    assert states[0].stable and states[2].stable and not states[1].stable
    top = states[1].floquet[0]
    assert abs(top.imag) < 1e-9 and top.real > 1.05
    # the product of the multipliers is exp(-c T / m) (Liouville), whatever the branch
    for r in states:
        assert np.prod(r.floquet).real == pytest.approx(math.exp(-0.02 * 2 * math.pi / w), rel=1e-6)


# ------------------------------------------------------------------ stored reference
@pytest.fixture(scope="module")
def stored():
    return json.loads(DATA.read_text())


@pytest.mark.parametrize("name, stated", [("P1", -0.431), ("P2", 0.024), ("P3", -0.419)])
def test_single_harmonic_misses_the_true_peaks_by_the_documented_percentages(stored, name, stated):
    err = stored["jenkins"][name]["single_harmonic"]["amplitude_error"]
    assert round(100 * err, 3) == stated


def test_stored_p1_peak_reproduced(stored):
    ref = stored["jenkins"]["P1"]["peak_amplitude"]
    blade, cs = p1()
    r = periodic_response(blade, cs, omega=ref["omega"], harmonics=1, steps=256, floquet=False)
    assert r.amplitude(0) == pytest.approx(ref["amplitude"], rel=1e-11)
    # and it is a maximum: 1e-4 to either side the amplitude is lower
    for dw in (-1e-4, 1e-4):
        side = periodic_response(blade, cs, omega=ref["omega"] + dw, harmonics=1, steps=256, initial=r, floquet=False)
        assert side.amplitude(0) < ref["amplitude"]
    check = stored["jenkins"]["P1"]["check_parabola_vertex_omega"]
    assert abs(check) < 1e-7


def test_stored_chain_point_reproduced(stored):
    ch = stored["chain"]
    p = ch["parameters"]
    system = (np.array(p["M"]), np.array(p["C"]), np.array(p["K"]), np.array(p["force"]))
    cs = [contact(Macroslip(c["stiffness"], c["slip_force"]), *c["dofs"]) for c in p["contacts"]]
    pt = ch["points"][3]
    r = periodic_response(system, cs, omega=pt["omega"], harmonics=21, steps=stored["steps"], floquet=False)
    assert r.success
    H = np.array(pt["harmonics"]["real"])
    # harmonics h >= 1 are unique; X0 only where no contact sticks all period (static offset)
    assert np.max(np.abs(r.harmonics[:, 1:] - H[:, 1:])) < 1e-10 * np.max(np.abs(H))
    if not pt["never_slipping_contacts"]:
        assert np.max(np.abs(r.harmonics[:, 0] - H[:, 0])) < 1e-10 * np.max(np.abs(H))
    assert all(q["up_down_difference"] < 1e-9 for q in ch["points"])


# ------------------------------------------------------------------ interface
def test_structure_and_contact_of_hbm():
    s = hbm.Structure(np.eye(1), np.array([[0.004]]), np.eye(1), force=np.array([0.01]))
    r = periodic_response(s, [hbm.Contact(Macroslip(1.0, 0.02), dof=0)], omega=1.3, steps=128, harmonics=1)
    blade, cs = p1()
    ref = periodic_response(blade, cs, omega=1.3, steps=128, harmonics=1)
    assert r.amplitude(0) == pytest.approx(ref.amplitude(0), rel=1e-12)


def test_peak_of_a_linear_oscillator():
    """Peak of F/|k - m w^2 + i c w| at w = sqrt(k/m - c^2/(2 m^2))."""
    system = (np.eye(1), np.array([[0.1]]), np.eye(1) * 2.0, np.array([0.01]))
    p = periodic_peak(system, bracket=(1.3, 1.5), steps=32, harmonics=1, xtol=1e-10)
    assert p.success
    assert p.omega == pytest.approx(math.sqrt(2.0 - 0.005), rel=1e-8)
    assert p.value == pytest.approx(0.01 / (0.1 * math.sqrt(2.0 - 0.0025)), rel=1e-12)


@pytest.mark.parametrize("kwargs, name", [
    (dict(omega=-1.0), "omega"), (dict(omega=1.0, harmonics=0), "harmonics"),
    (dict(omega=1.0, integrator="rk4"), "integrator"), (dict(omega=1.0, steps=4), "steps"),
    (dict(omega=1.0, harmonics=40, steps=64), "steps"), (dict(omega=1.0, initial=np.zeros(2)), "initial"),
])
def test_bad_options_are_refused_by_name(kwargs, name):
    blade, cs = p1()
    with pytest.raises(ValueError, match=name):
        periodic_response(blade, cs, **kwargs)


@pytest.mark.parametrize("kwargs, message", [
    # before, a string or a bool was read as the frequency, a NaN or negative tol and a negative max_iter
    # were taken, floquet="no" computed the multipliers, and the others failed inside numpy without a name
    (dict(omega="1"), r"^omega must be a number, got omega='1'$"),
    (dict(omega=True), r"^omega must be a number, got omega=True$"),
    (dict(omega=None), r"^omega must be a number, got omega=None$"),
    (dict(omega=1.0, tol=-1.0), r"^tol must be positive, got tol=-1.0$"),
    (dict(omega=1.0, tol=math.nan), r"^tol must be finite, got tol=nan$"),
    (dict(omega=1.0, tol="a"), r"^tol must be a number, got tol='a'$"),
    (dict(omega=1.0, max_iter=-1), r"^max_iter must be an integer >= 1, got max_iter=-1$"),
    (dict(omega=1.0, max_iter=1.5), r"^max_iter must be an integer >= 1, got max_iter=1.5$"),
    (dict(omega=1.0, floquet="no"), r"^floquet must be True or False, got floquet='no'$"),
    (dict(omega=1.0, initial="abc"), r"^initial must be a finite state of length 3, got initial='abc'$"),
])
def test_bad_options_are_refused_with_the_value(kwargs, message):
    blade, cs = p1()
    with pytest.raises(ValueError, match=message):
        periodic_response(blade, cs, steps=16, harmonics=1, **kwargs)


def test_a_contact_without_element_and_dofs_is_refused_by_name():
    blade, _ = p1()
    with pytest.raises(ValueError, match=r"^contacts must hold objects with .element and .dofs \(e.g. hbm.Contact\), "
                                         r"got 3$"):
        periodic_response(blade, [3], omega=1.0)


@pytest.mark.parametrize("kwargs, message", [
    # before, a bracket of three or of strings failed in the unpacking without a name, a negative or NaN
    # xtol was taken, and an initial that is no response failed with an AttributeError
    (dict(bracket=(1.1, 1.3, 1.5)), r"^bracket must be two increasing positive frequencies, got "
                                    r"bracket=\(1.1, 1.3, 1.5\)$"),
    (dict(bracket="ab"), r"^bracket must be two increasing positive frequencies, got bracket='ab'$"),
    (dict(bracket=(1.3, 1.5), xtol=-1.0), r"^xtol must be positive, got xtol=-1.0$"),
    (dict(bracket=(1.3, 1.5), xtol=math.nan), r"^xtol must be finite, got xtol=nan$"),
    (dict(bracket=(1.3, 1.5), initial=3), r"^initial must be a PeriodicResponse \(from periodic_response\) or "
                                          r"None, got initial=3$"),
])
def test_bad_peak_options_are_refused_with_the_value(kwargs, message):
    blade, cs = p1()
    with pytest.raises(ValueError, match=message):
        periodic_peak(blade, cs, steps=16, harmonics=1, **kwargs)


@pytest.mark.parametrize("system, cs, name", [
    ((np.eye(2), np.eye(2), np.eye(3), np.ones(2)), [], "K"),
    ((np.eye(2), np.eye(2), np.eye(2), np.ones(3)), [], "force"),
    ((-np.eye(1), np.eye(1), np.eye(1), np.ones(1)), [], "M"),
    ((np.eye(2), np.eye(2), np.eye(2), np.ones(2)), [contact(Macroslip(1.0, 1.0), 0, 0)], "dofs"),
    ((np.eye(2), np.eye(2), np.eye(2), np.ones(2)), [contact(Macroslip(1.0, 1.0), 2)], "dofs"),
    ((np.eye(1), np.eye(1), np.eye(1), np.ones(1)), [contact(Macroslip(math.inf, 1.0), 0)], "stiffness"),
    ((np.eye(1), np.eye(1), np.eye(1), np.ones(1)), [contact(object(), 0)], "element"),
    ("blade", [], "system"),
])
def test_bad_models_are_refused_by_name(system, cs, name):
    with pytest.raises(ValueError, match=name):
        periodic_response(system, cs, omega=1.0)


# ------------------------------------------------------------------ slow
@pytest.mark.slow
def test_newmark_converges_to_the_event_reference_to_3e8():
    blade, cs = p1()
    r = periodic_response(blade, cs, omega=1.3, steps=1024, harmonics=1)
    rn = periodic_response(blade, cs, omega=1.3, integrator="newmark", steps=16384, initial=r, harmonics=1,
                           floquet=False, tol=1e-10)
    assert abs(rn.amplitude(0) / r.amplitude(0) - 1.0) < 3e-8


@pytest.mark.slow
def test_stored_peaks_refound(stored):
    for name, (c, fs) in {"P2": (0.004, 0.005), "P3": (0.0002, 0.02)}.items():
        ref = stored["jenkins"][name]["peak_amplitude"]
        blade, cs = p1(c, fs)
        start = periodic_response(blade, cs, omega=ref["omega"] * (1 + 2e-3), steps=512, harmonics=1,
                                  initial=np.array([ref["amplitude"] * np.exp(-0.5j * np.pi)]), floquet=False)
        p = periodic_peak(blade, cs, bracket=(ref["omega"] * 0.995, ref["omega"] * 1.005), initial=start,
                          steps=512, harmonics=1, xtol=1e-10)
        assert p.value == pytest.approx(ref["amplitude"], rel=1e-10)
        # a maximum's location is conditioned by its curvature: an amplitude known to 1e-10 places it only to
        # sqrt(2e-10 / kappa), kappa = |a'' omega^2 / a| (P3's flat top: about 1e-6; measured from the responses
        # 1e-4 apart in omega)
        h = 1e-4
        a = [periodic_response(blade, cs, omega=p.omega * (1.0 + k * h), steps=512, harmonics=1, initial=start,
                               floquet=False).amplitude(0) for k in (-1, 0, 1)]
        kappa = abs(a[0] - 2.0 * a[1] + a[2]) / (h * h * a[1])
        assert kappa > 0.0 and abs(p.omega / ref["omega"] - 1.0) <= math.sqrt(2e-10 / kappa)
