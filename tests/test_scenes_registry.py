"""Models and effects as data: a user's element registered with one call runs in scenes; a scene's
accuracy preset gives exactly frequency_response's options; a new effect is one call.

The element below lives outside the library (it is defined here) and is registered with
``hbm.scenes.register_model``: no library file is edited for it.  It is nonlinear at every
amplitude (``linear_amplitude = 0``), the case that used to divide by a_min.
"""

import csv
import math

import numpy as np
import pytest

from contact_models import ContactElement
from hbm import Blade, frequency_response
from hbm.balance import presets
from hbm.scenes import (EFFECTS, Effect, Key, MODELS, SceneError, number, plan_scene, register_effect,
                        register_model, run_scene, scene_from_dict, unregister_effect, unregister_model)
from hbm.output import csv_lines


class QuadraticDamper(ContactElement):
    """A spring k in parallel with a quadratic damper: f_s = k a, f_c = c a^2 (dissipation pi c a^3).

    Nonlinear at every amplitude: it has no linear range and no slip amplitude.
    """

    frequency_dependent = False

    def __init__(self, k, c):
        self.k, self.c = float(k), float(c)

    def _fourier_derivatives(self, a, omega, rtol):
        return self.k * a, self.c * a * a, np.full_like(a, self.k), 2.0 * self.c * a

    def _stuck_stiffness(self, omega):
        return self.k

    def _slip_amplitude(self, omega):
        return 0.0

    def _linear_amplitude(self, omega):
        return 0.0

    def _reference_amplitude(self, omega):
        return 1e-3

    def _hysteresis(self, a, omega, n):
        theta = np.linspace(-0.5 * np.pi, 1.5 * np.pi, n)
        return a * np.sin(theta), self.k * a * np.sin(theta) + self.c * a * a * np.cos(theta)


K_Q = Key(number(gt=0, unit="N/m"), 200.0, "spring of the quadratic damper (N/m)")
C_Q = Key(number(ge=0, unit="N/m^2"), 3.0e4, "quadratic damping coefficient c: f_c = c a^2 (N/m^2)")


@pytest.fixture
def quadratic():
    spec = register_model("quadratic", lambda run: QuadraticDamper(run.params["k_q"], run.params["c_q"]),
                          keys={"k_q": K_Q, "c_q": C_Q}, doc="spring + quadratic damper (a test's own model)",
                          example=lambda: QuadraticDamper(200.0, 3.0e4))
    yield spec
    unregister_model("quadratic")


def scene(**tables):
    data = {"blade": {"mass": 1.0, "stiffness": 1.0e3, "damping": 0.05, "force": 0.2},
            "damper": {"model": "quadratic", "c_q": 3.0e4},
            "sweep": {"omega": [25.0, 45.0]}}
    for name, table in tables.items():
        data[name] = table
    return data


def test_registered_element_runs_a_frequency_sweep_scene(quadratic, tmp_path):
    sc = scene_from_dict(scene(), "q.toml")
    plan = plan_scene(sc)
    run = plan.runs[0]
    assert isinstance(run.element, QuadraticDamper) and run.element.k == 200.0  # the key's default
    slip = next(e for e in run.effects if e.name == "damper slip")
    assert slip.simulated and "linear_amplitude = 0" in slip.reason
    inertia = next(e for e in run.effects if e.name == "damper inertia")
    assert not inertia.simulated and "frequency independent" in inertia.reason
    result = run_scene(sc, tmp_path, plan=plan)
    assert result.success, result.message
    api = frequency_response(plan.blade, QuadraticDamper(200.0, 3.0e4), omega_range=(25.0, 45.0))
    frf = result.runs[0].frf
    assert np.array_equal(frf.omega, api.omega) and np.array_equal(frf.amplitude, api.amplitude)
    # independent check of one point: (k + k_d - m w^2 + i (c w + c_q a)) X = F with |X| = a
    w, a = frf.omega[len(frf) // 2], frf.amplitude[len(frf) // 2]
    z = 1.0e3 + 200.0 - w * w + 1j * (0.05 * w + 3.0e4 * a)
    assert abs(z) * a == pytest.approx(0.2, rel=1e-6)
    assert result.summary["runs"][0]["peak"]["amplitude_over_a_min"] is None  # no a_min to divide by
    rows = list(csv.DictReader(csv_lines((tmp_path / "frf.csv").open())))
    assert len(rows) == len(frf) and rows[0]["model"] == "quadratic" and "residual_rel" in rows[0]


def test_registered_element_runs_an_amplitude_sweep_scene(quadratic, tmp_path):
    data = scene(sweep={"kind": "amplitude", "omega": [0.0], "amplitude": [0.5, 8.0], "points": 5})
    del data["blade"]
    result = run_scene(scene_from_dict(data, "qa.toml"), tmp_path)
    assert result.success
    rows = list(csv.DictReader(csv_lines((tmp_path / "coefficients.csv").open())))
    a = np.array([float(r["a_m"]) for r in rows])
    assert np.allclose(a, 1e-3 * np.geomspace(0.5, 8.0, 5), rtol=1e-14)  # in units of the reference amplitude
    assert np.allclose([float(r["f_c_N"]) for r in rows], 3.0e4 * a**2, rtol=1e-14)
    assert result.summary["runs"][0]["amplitude_unit"]["name"] == "reference amplitude"
    with pytest.raises(SceneError, match='sweep.amplitude_unit = "a_min": damper.model = "quadratic"'):
        data["sweep"]["amplitude_unit"] = "a_min"
        plan_scene(scene_from_dict(data, "qa.toml"))


def test_registered_keys_are_validated_and_owned(quadratic):
    with pytest.raises(SceneError) as err:
        scene_from_dict(scene(damper={"model": "macroslip", "c_q": -1.0, "stiffness": 1.0, "slip_force": 1.0}),
                        "bad.toml")
    text = "\n".join(err.value.problems)
    assert "damper.c_q = -1.0: must be a number >= 0" in text  # its check
    assert 'not allowed unless damper.model includes "quadratic"' in text  # its owner
    with pytest.raises(ValueError, match="belongs to model 'macroslip'"):
        register_model("other", lambda run: None, keys={"slip_force": K_Q})
    with pytest.raises(ValueError, match="registered already"):
        register_model("quadratic", lambda run: None)


def test_a_new_effect_is_one_call_and_is_reported(quadratic):
    def flutter(run):
        return Effect("aerodynamic damping", False, f"effects.aero = {run.scene.effects['aero']}: not modelled")

    register_effect("aerodynamic damping", flutter, key_name="aero",
                    key=Key(number(ge=0), 0.0, "aerodynamic damping ratio (a test's own effect)"))
    try:
        plan = plan_scene(scene_from_dict(scene(effects={"aero": 0.5}), "e.toml"))
        assert [e.name for e in plan.runs[0].effects][-1] == "aerodynamic damping"
        assert "effects.aero = 0.5" in plan.runs[0].effects[-1].reason
    finally:
        unregister_effect("aerodynamic damping")
    assert all(e.name != "aerodynamic damping" for e in EFFECTS)


@pytest.mark.parametrize("accuracy", sorted(presets.NAMED))
def test_a_scene_preset_gives_exactly_the_api_options(accuracy, tmp_path):
    data = scene(sweep={"omega": [25.0, 45.0], "accuracy": accuracy})
    data["damper"] = {"model": "macroslip", "stiffness": 200.0, "slip_force": 0.05}
    sc = scene_from_dict(data, "p.toml")
    expected = presets.resolve(accuracy).options()
    assert sc.sweep["options"] == expected
    result = run_scene(sc, tmp_path)
    frf = result.runs[0].frf
    from contact_models import Macroslip

    api = frequency_response(Blade(mass=1.0, stiffness=1.0e3, damping=0.05, force=0.2),
                             Macroslip(stiffness=200.0, slip_force=0.05), omega_range=(25.0, 45.0), accuracy=accuracy,
                             harmonics=1)
    assert (frf.rtol, len(frf)) == (api.rtol, len(api)) and np.array_equal(frf.amplitude, api.amplitude)


def test_every_library_model_has_an_example_element():
    from contact_models import ContactElement as Base

    for name, spec in MODELS.items():
        if name == "auto":
            continue  # auto resolves to two or three regions, whose examples exist
        if name == "cubic":
            assert spec.example is None  # k* = 0 at every amplitude: the suite's units divide by it (models.py)
            continue
        assert spec.example is not None, name
        assert isinstance(spec.example(), Base), name
