"""A preload that follows the rotation (``CentrifugalLoad``, ``RotatingPreload``).

The independent answer at each frequency is the element built by hand at ``N0 = m r (omega/EO)^2``:
a point of the FRF with the rotating preload must be a solution of the balance with that fixed
element at its own omega; the omega-derivative against a difference of the force in omega.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

import hbm
from contact_models import CentrifugalLoad, Contact2D, Macroslip, RotatingPreload
from hbm.balance.residual import HarmonicBalance


def test_load_is_m_r_omega_squared():
    load = CentrifugalLoad(mass=0.02, radius=0.25, engine_order=3)
    w = 3.0e3
    assert load(w) == pytest.approx(0.02 * 0.25 * (w / 3) ** 2, rel=1e-15)
    assert load.derivative(w) == pytest.approx((load(w * (1 + 1e-7)) - load(w * (1 - 1e-7))) / (2e-7 * w), rel=1e-7)
    assert load.speed(w) == pytest.approx(1.0e3)
    for kw in ({"mass": 0.0}, {"radius": -1.0}, {"engine_order": 0}, {"engine_order": 2.5}):
        with pytest.raises(ValueError, match=next(iter(kw))):
            CentrifugalLoad(**{"mass": 0.02, "radius": 0.25, "engine_order": 3, **kw})


def test_harmonic_force_is_the_fixed_element_and_its_omega_derivative():
    load = CentrifugalLoad(mass=0.01, radius=0.3, engine_order=4)
    el = RotatingPreload(lambda N: Contact2D(kt=1e7, kn=1e7, mu=0.3, n0=N), load)
    X = np.zeros((2, 7))
    X[0, 1], X[0, 2], X[1, 1] = 2e-5, 1e-5, 1e-6
    w = 4.0e3
    F, J, Fw = el.harmonic_force(X, w, n_t=128)
    F0, J0, _ = Contact2D(kt=1e7, kn=1e7, mu=0.3, n0=load(w)).harmonic_force(X, w, n_t=128)
    assert np.array_equal(F, F0) and np.array_equal(J, J0)
    h = 1e-4 * w
    Fd = (el.harmonic_force(X, w + h, n_t=128)[0] - el.harmonic_force(X, w - h, n_t=128)[0]) / (2 * h)
    assert np.allclose(Fw, Fd, rtol=1e-4, atol=1e-6 * np.max(np.abs(Fd)))


def test_frf_points_solve_the_balance_at_their_own_preload():
    """A 2-DOF platform (tangential DOF 0, normal DOF 1) with a Contact2D whose preload rises along the sweep."""
    M = np.diag([0.05, 0.05])
    K = np.diag([2e5, 4e5])
    s = hbm.Structure(M, 2e-5 * K, K, force=[1.0, 0.0])
    load = CentrifugalLoad(mass=1e-4, radius=0.3, engine_order=4)  # mu N0 about the force at resonance

    def build(N):
        return Contact2D(kt=1e5, kn=1e5, mu=0.3, n0=N)

    el = RotatingPreload(build, load)
    w0 = np.sqrt(3e5 / 0.05)
    frf = hbm.frequency_response(s, [hbm.Contact(el, dof=0, normal_dof=1)], omega_range=(0.85 * w0, 1.15 * w0),
                                 harmonics=3, tol=None, stability=False)
    assert frf.success
    peak = float(np.max(frf.amplitude))
    for i in np.linspace(0, len(frf) - 1, 6).astype(int):
        w = float(frf.omega[i])
        fixed = HarmonicBalance(s, [hbm.Contact(build(load(w)), dof=0, normal_dof=1)],
                                harmonics=3, n_t=frf._problem.n_t)
        R, _ = fixed.physical(np.append(frf._X[i].ravel(), w))
        assert np.max(np.abs(R)) <= 1e-9 * peak


def test_jenkins_slip_force_follows_the_speed():
    """One DOF, a Jenkins slider of slip force mu N0(omega) at H = 1: each point against the fixed element."""
    load = CentrifugalLoad(mass=0.01, radius=0.3, engine_order=2)
    el = RotatingPreload(lambda N: Macroslip(stiffness=5e6, slip_force=0.3 * N), load)
    blade = hbm.Blade(mass=0.0877, stiffness=1e8, damping=11.8, force=8.0)
    frf = hbm.frequency_response(blade, el, omega_range=(3.0e4, 4.6e4), tol=None)
    assert frf.success
    for i in np.linspace(0, len(frf) - 1, 5).astype(int):
        w = float(frf.omega[i])
        fixed = HarmonicBalance(blade, Macroslip(stiffness=5e6, slip_force=0.3 * load(w)))
        R, _ = fixed.physical([frf.x_c[i], frf.x_s[i], w])
        assert np.max(np.abs(R)) <= 1e-8 * blade.force


def test_bad_input():
    with pytest.raises(ValueError, match="build"):
        RotatingPreload(3.0, CentrifugalLoad(0.01, 0.3, 2))
    with pytest.raises(ValueError, match="load"):
        RotatingPreload(lambda N: Macroslip(1.0, N), 5.0)


def _centrifugal_scene():
    import tomllib
    from pathlib import Path

    from hbm.scenes import scene_from_dict

    path = Path(__file__).resolve().parent.parent / "examples" / "scenes" / "default_microslip_frf.toml"
    data = tomllib.loads(path.read_text())
    data["damper"]["load"] = {"kind": "centrifugal", "mass": 4e-4, "radius": 0.28, "engine_order": 40}
    data["output"] = {"formats": ["csv"]}
    return data, path, scene_from_dict(data, path)


def test_scene_centrifugal_load_is_planned_per_omega():
    """``[damper.load] kind = "centrifugal"``: the run's element is the run planned at N0(omega) at each omega."""
    from hbm.scenes import plan_scene, scene_from_dict
    from hbm.scenes.checks import SceneError

    data, path, scene = _centrifugal_scene()
    (run,) = plan_scene(scene).runs
    load = CentrifugalLoad(mass=4e-4, radius=0.28, engine_order=40)
    assert isinstance(run.element, RotatingPreload) and "centrifugal" in run.label
    for w in (3.6e4, 3.8e4):
        assert run.element.at(w).load.N == pytest.approx(load(w), rel=1e-15)
    bad = dict(data, damper=dict(data["damper"], load={"kind": "centrifugal", "mass": 4e-4, "N": 100.0}))
    with pytest.raises(SceneError, match="radius"):
        scene_from_dict(bad, path)
    with pytest.raises(SceneError, match="mass"):
        scene_from_dict(dict(data, damper=dict(data["damper"], load={"kind": "uniform", "N": 1.0, "mass": 1.0})), path)


@pytest.mark.slow
def test_scene_centrifugal_load_runs(tmp_path):
    """The scene's FRF (each frequency's run planned again: about a minute) is the front door's with the
    element built by hand."""
    from contact_models import Bar, TwoRegionMicroslip, UniformLoad
    from hbm.scenes import plan_scene, run_scene

    data, path, scene = _centrifugal_scene()
    plan = plan_scene(scene)
    (run,) = plan.runs
    load = CentrifugalLoad(mass=4e-4, radius=0.28, engine_order=40)
    result = run_scene(scene, tmp_path, plan=plan)
    assert result.success
    d = data["damper"]
    bar = Bar(E=d["E"], rho=d["rho"], A=d["A"], L=d["L"], k=d["k"], beta=d["beta"], mu=d["mu"])
    el = RotatingPreload(lambda N: TwoRegionMicroslip(bar, UniformLoad(N=N)), load)
    frf = hbm.frequency_response(plan.blade, el, omega_range=tuple(run.omega), tol=None)
    got = result.runs[0].frf.peak()
    assert got.amplitude == pytest.approx(frf.peak().amplitude, rel=1e-6)


def test_the_preload_keeps_the_kind_of_the_elements_it_builds():
    """A rotating preload declares what the elements it builds declare: a slider's closed form (a structure's
    balance with tol starts at the H its tolerance predicts), the all-mode bar's discretisation (its harmonics
    are exact but solved for, so the start stays at 3; its own modes, read three rungs up)."""
    from contact_models import AllModeMicroslip, Bar, UniformLoad
    from contact_models.base import KIND_ATTRIBUTES
    from hbm.frf import start_harmonics

    load = CentrifugalLoad(mass=0.01, radius=0.3, engine_order=2)
    bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    slider = RotatingPreload(lambda N: Macroslip(stiffness=5e6, slip_force=0.3 * N), load)
    allmode = RotatingPreload(lambda N: AllModeMicroslip(bar, UniformLoad(N=N)), load)
    assert (slider.exact_harmonics, slider.discretised, slider.harmonics_reach) == (True, False, 1)
    assert (allmode.exact_harmonics, allmode.discretised, allmode.harmonics_reach) == (True, True, 3)
    for preload in (slider, allmode):  # every attribute that declares the kind, as the element built declares it
        built = preload.at(preload.omega_ref)
        assert {n: getattr(preload, n) for n in KIND_ATTRIBUTES} == {n: getattr(built, n) for n in KIND_ATTRIBUTES}
    s = hbm.Structure(np.eye(1), [[0.004]], np.eye(1), force=[0.01])
    assert start_harmonics(s, [hbm.Contact(slider, dof=0)], None, 1e-5) == 31
    assert start_harmonics(s, [hbm.Contact(allmode, dof=0)], None, 1e-5) == 3


@pytest.mark.parametrize("omega", [-1.0, float("nan"), "100", None])
def test_the_load_and_the_preloaded_element_name_a_bad_frequency(omega):
    load = CentrifugalLoad(mass=0.01, radius=0.3, engine_order=4)
    el = RotatingPreload(lambda N: Contact2D(kt=1e7, kn=1e7, mu=0.3, n0=N), load)
    for call in (load, load.derivative, load.speed, el.at):
        with pytest.raises(ValueError, match=r"^omega must be (>= 0|finite|a number), got omega="):
            call(omega)


@pytest.mark.parametrize("returned", ["x", None, np.array([1.0, 2.0]), True, 1.0 + 0.0j])
def test_a_load_that_returns_no_real_number_is_refused_naming_load(returned):
    """A string, None or an array failed in float() (naming nothing), and True was taken as a preload of 1 N."""
    from contact_models import Macroslip

    with pytest.raises(ValueError, match=rf"^load must return a preload \(N\), a real number, got load\(1\.0\) = "
                                         rf"{re.escape(repr(returned))}$"):
        RotatingPreload(lambda N: Macroslip(1e6, N + 1.0), lambda omega: returned)
