"""The all-mode bar with normal motion as a scene model (``damper.model = "allmode2d"``).

The example scene (``examples/scenes/allmode_normal.toml``) against the same problem built directly
with ``hbm.frequency_response`` (point for point), its normal DOF against the closed-form linear
response (the platform never separates from the bar there), its keys in ``python3 -m hbm keys`` and
``docs/scenes.md``, and bad input naming its key.
"""

import csv
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from contact_models import AllModeMicroslip2D, Bar, UniformLoad
from hbm import Contact, Structure, frequency_response
from hbm.scenes import load_scene, plan_scene, run_scene, scene_from_dict
from hbm.output import csv_lines

from conftest import scene_problems as problems  # the SceneError's problems, one string

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "examples" / "scenes" / "allmode_normal.toml"
KEYS = ("damper.kn", "damper.normal_shape", "damper.cells", "damper.bar_harmonics", "damper.bar_samples")
# the values written in examples/scenes/allmode_normal.toml (and its allmode_normal/*.mtx)
BAR = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
M, K, C = np.diag([0.1, 1.0]), np.diag([4.0e7, 1.0e10]), np.diag([40.0, 2.0e3])
FORCE = [40.0, 3.0e3]
KN, SHAPE, CELLS, H = 2.0e9, (0.5, 1.5), 8, 3
WINDOW = [2.3e4, 2.5e4]  # rad/s: the peak (about 2.44e4) and both flanks


def api_frf(omega):
    element = AllModeMicroslip2D(BAR, UniformLoad(N=100.0), KN, CELLS, H, normal_shape=SHAPE)
    return frequency_response(Structure(M, C, K, force=FORCE), Contact(element, dof=0, normal_dof=1), tuple(omega),
                              harmonics=H, response_dof=0)


@pytest.fixture(scope="module")
def scene_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("allmode2d")
    result = run_scene(load_scene(SCENE, overrides={"sweep.omega": WINDOW}), out, progress=None)
    return result, out


def test_scene_is_the_api_computation(scene_run):
    result, out = scene_run
    assert result.success, result.message
    frf = result.runs[0].frf
    api = api_frf(WINDOW)
    assert len(frf) == len(api) > 10
    np.testing.assert_allclose(frf.omega, api.omega, rtol=1e-12)
    np.testing.assert_allclose(frf.amplitude, api.amplitude, rtol=1e-12)
    np.testing.assert_allclose(frf.coefficients(1), api.coefficients(1), rtol=1e-12, atol=1e-12 * 3e-7)
    i = int(np.argmax(frf.amplitude))
    assert WINDOW[0] < frf.omega[i] < WINDOW[1]  # the peak is inside the window
    a_min = BAR.mu * 100.0 / (BAR.k * BAR.L)
    assert frf.amplitude[i] > 10 * a_min  # well into microslip: the bar's nonlinearity is exercised
    rows = list(csv.DictReader(csv_lines((out / "frf.csv").open())))
    assert len(rows) == len(api) and float(rows[-1]["omega_rad_s"]) == pytest.approx(WINDOW[1], rel=1e-9)


def test_normal_dof_is_the_closed_form_linear_response(scene_run):
    """While every node stays in contact, the normal force is linear in v: F_N = sum_i s_i N_i =
    q sum_i s_i c_i + kn (sum_i c_i s_i^2) v (trapezoid weights c_i, s_i = s(x_i)); the normal DOF
    is then a linear oscillator with that added stiffness, its mean pushed back by the preload."""
    frf = scene_run[0].runs[0].frf
    x = np.linspace(0.0, BAR.L, CELLS + 1)
    c = np.full(CELLS + 1, BAR.L / CELLS)
    c[[0, -1]] *= 0.5
    s = SHAPE[0] + (SHAPE[1] - SHAPE[0]) * x / BAR.L
    q = 100.0 / BAR.L
    k_add, preload = KN * np.sum(c * s * s), q * np.sum(c * s)
    assert preload == pytest.approx(100.0, rel=1e-12)  # the mean of s is 1 for this shape
    w = frf.omega
    v1 = FORCE[1] / (K[1, 1] + k_add - w * w * M[1, 1] + 1j * w * C[1, 1])
    v0 = -preload / (K[1, 1] + k_add)
    coef = frf.coefficients(1)
    # the least nodal load over the branch stays positive: the closed form holds at every point
    assert np.min(q + KN * s.min() * (v0 - np.abs(v1))) > 0.0 and np.min(q + KN * s.max() * (v0 - np.abs(v1))) > 0.0
    np.testing.assert_allclose(coef[:, 0].real, v0, rtol=1e-8)
    np.testing.assert_allclose(coef[:, 1], v1, rtol=1e-8)
    assert np.max(np.abs(coef[:, 2:])) < 1e-8 * np.max(np.abs(v1))  # no higher harmonics in the normal motion


def test_keys_are_listed_and_documented():
    out = subprocess.run([sys.executable, "-m", "hbm", "keys"], cwd=ROOT, capture_output=True, text=True,
                         check=True).stdout
    page = (ROOT / "docs" / "scenes.md").read_text()
    for key in KEYS:
        assert key in out, key
        assert f"| `{key}` |" in page, key
    models = subprocess.run([sys.executable, "-m", "hbm", "models"], cwd=ROOT, capture_output=True, text=True,
                            check=True).stdout
    assert "\nallmode2d " in "\n" + models


BAR_KEYS = dict(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)


def structure_scene(folder, damper=None, **structure):
    """The example's problem as a dict scene; ``structure`` entries set to None are left out."""
    np.save(folder / "M.npy", M)
    np.save(folder / "K.npy", K)
    np.save(folder / "C.npy", C)
    table = {"mass": "M.npy", "stiffness": "K.npy", "damping": "C.npy", "force": FORCE, "contact_dofs": [0],
             "normal_dofs": [1], **structure}
    damper = damper or {"model": "allmode2d", **BAR_KEYS, "kn": KN, "cells": CELLS}
    if damper["model"] == "allmode2d":
        damper = {**damper, "load": {"N": 100.0}}
    return {"structure": {k: v for k, v in table.items() if v is not None}, "damper": damper,
            "sweep": {"omega": WINDOW}, "output": {"formats": ["csv"]}}


def test_the_scene_plans_the_element_of_its_keys(tmp_path):
    data = structure_scene(tmp_path)
    data["damper"].update(normal_shape=[0.2, 1.8], bar_samples=64, bar_harmonics=5)
    el = plan_scene(scene_from_dict(data, tmp_path / "a.toml")).runs[0].element
    assert isinstance(el, AllModeMicroslip2D)
    assert (el.cells, el.harmonics, el.n_t, el.kn, el.normal_shape) == (CELLS, 5, 64, KN, (0.2, 1.8))
    del data["damper"]["cells"], data["damper"]["bar_samples"], data["damper"]["bar_harmonics"]
    el = plan_scene(scene_from_dict(data, tmp_path / "a.toml")).runs[0].element
    assert (el.cells, el.harmonics, el.n_t) == (20, 15, 240)  # the element's own defaults


def test_bad_input_names_its_key(tmp_path):
    bar = BAR_KEYS
    data = structure_scene(tmp_path)
    del data["structure"]["normal_dofs"]
    assert ("structure.normal_dofs is missing: the allmode2d element acts on a tangential and a normal "
            "displacement") in problems(data, tmp_path / "a.toml", plan=True)
    text = problems(structure_scene(tmp_path, {"model": "allmode2d", **bar, "normal_shape": [1.0], "cells": 1,
                                               "bar_harmonics": 0, "kn": -1.0}), tmp_path / "a.toml")
    for expected in ("damper.normal_shape = [1.0]: must be a list of 2 numbers", "damper.cells = 1: must be an "
                     "integer >= 2", "damper.bar_harmonics = 0: must be an integer >= 1",
                     "damper.kn = -1.0: must be a number >= 0 (N/m for contact2d and contact3d, N/m^2 for allmode2d)"):
        assert expected in text, (expected, text)
    text = problems(structure_scene(tmp_path, {"model": "allmode2d", **bar, "bar_samples": 30}), tmp_path / "a.toml")
    assert "damper.kn is missing: required with damper.model = \"allmode2d\"" in text
    assert "damper.bar_samples = 30: must be a multiple of 4 and at least 2 damper.bar_harmonics + 2 = 32" in text
    data = structure_scene(tmp_path)
    data["effects"] = {"inertia": "off"}
    assert "effects.inertia = \"off\": not available with damper.model = \"allmode2d\"" in problems(
        data, tmp_path / "a.toml", plan=True)
    text = problems(structure_scene(tmp_path, {"model": "macroslip", "stiffness": 1.0, "slip_force": 0.03,
                                               "normal_shape": [1.0, 1.0]}), tmp_path / "a.toml")
    assert "damper.normal_shape = [1.0, 1.0]: not allowed unless damper.model includes \"allmode2d\"" in text
    entry = [{"model": "allmode2d", "dofs": [0], "normal_dofs": [1], "kn": KN}]
    text = problems(structure_scene(tmp_path, {"model": "macroslip", "stiffness": 1.0, "slip_force": 0.03},
                                    contacts=entry, normal_dofs=None), tmp_path / "a.toml")
    assert "structure.contacts[0].model = \"allmode2d\": as given it needs the bar and load of [damper]" in text
    blade = {"damper": {"model": "allmode2d", **bar, "kn": KN, "load": {"N": 100.0}},
             "blade": {"mass": 0.1, "stiffness": 4.0e7, "damping": 40.0, "force": 40.0}, "sweep": {"omega": WINDOW}}
    assert "damper.model = \"allmode2d\": the element acts on a tangential and a normal displacement; a [blade]" in (
        problems(blade, tmp_path / "a.toml", plan=True))


@pytest.mark.slow
def test_example_scene_runs_in_full_from_the_command_line(tmp_path):
    subprocess.run([sys.executable, "-m", "hbm", "run", str(SCENE), "--out", str(tmp_path), "--quiet"], cwd=ROOT,
                   check=True, capture_output=True)
    assert (tmp_path / "frf.csv").is_file() and (tmp_path / "frf.png").is_file()
    rows = list(csv.DictReader(csv_lines((tmp_path / "frf.csv").open())))
    assert float(rows[-1]["omega_rad_s"]) == pytest.approx(2.8e4, rel=1e-9)
