"""Scenes with normal-contact elements: ``gap``, ``contact2d``, ``cubic`` and ``[[structure.contacts]]``.

The two example scenes (``examples/scenes/nlvib_ex07.toml``, ``examples/scenes/contact_normal.toml``)
against the same problems built directly with ``hbm.frequency_response`` (point for point), the
point contact's separation and its stuck start against the closed-form linear response, the new
keys in ``python3 -m hbm keys`` and ``docs/scenes.md``, and bad input naming its key.
"""

import csv
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from contact_models import Contact2D, CubicSpring, Gap, Macroslip
from hbm import Contact, Steps, Structure, frequency_response
from hbm.scenes import load_scene, run_scene
from hbm.output import csv_lines

from conftest import scene_problems as problems  # the SceneError's problems, one string

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "examples" / "scenes"
NEW_KEYS = ("damper.gap_stiffness", "damper.gap", "damper.kt", "damper.kn", "damper.friction", "damper.n0",
            "damper.k3", "damper.slider", "structure.normal_dofs", "structure.contacts", "effects.samples")


def nlvib_ex07():
    """NLvib's example 7 written out here (the values of examples/nlvib_ex07.py, NLvib's slider)."""
    K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 2.0]])
    s = Structure(np.eye(3), 0.02 * K, K, force=[0.0, 1.0, 0.0])
    return s, [Contact(Macroslip(20.0, 1.0, slider="from rest"), dof=0),
               Contact(Macroslip(20.0, 1.0, slider="from rest"), dofs=(1, 0)),
               Contact(CubicSpring(1.0), dof=1), Contact(CubicSpring(1.0), dofs=(2, 1)),
               Contact(Gap(1.0, 0.25), dof=2)]


K2 = np.array([[1.0, 0.3], [0.3, 1.5]])
POINT = dict(kt=1.0, kn=1.0, mu=0.3, n0=0.1)
DAMPER = {"model": "contact2d", "kt": 1.0, "kn": 1.0, "friction": 0.3, "n0": 0.1}


def contact_normal():
    s = Structure(np.eye(2), 0.01 * K2, K2, force=[0.015, 0.0])
    return s, [Contact(Contact2D(**POINT), dof=0, normal_dof=1)]


def api_frf(system, omega, **options):
    structure, contacts = system
    return frequency_response(structure, contacts, omega, **options)


@pytest.mark.parametrize("name, omega, system, options", [
    ("nlvib_ex07", [0.5, 0.75], nlvib_ex07, dict(harmonics=7, n_t=1024, response_dof=1, tol=0.02,
                                                   steps=Steps(max_steps=20000))),
    ("contact_normal", [1.45, 1.75], contact_normal, dict(harmonics=3, n_t=256, response_dof=0))])
def test_example_scene_is_the_api_computation(tmp_path, name, omega, system, options):
    scene = load_scene(SCENES / f"{name}.toml", overrides={"sweep.omega": omega})
    result = run_scene(scene, tmp_path, progress=None)
    assert result.success, result.message
    frf = result.runs[0].frf
    api = api_frf(system(), tuple(omega), **options)
    assert len(frf) == len(api) > 10
    np.testing.assert_allclose(frf.omega, api.omega, rtol=1e-12)
    np.testing.assert_allclose(frf.amplitude, api.amplitude, rtol=1e-12)
    rows = list(csv.DictReader(csv_lines((tmp_path / "frf.csv").open())))
    assert len(rows) == len(api) and float(rows[-1]["omega_rad_s"]) == pytest.approx(omega[1], rel=1e-9)


def open_fraction(frf, n_t=256):
    """Share of each period during which the point contact is open (N = 0), from the normal DOF's
    harmonics (x = X0 + sum Xc_h cos h theta + Xs_h sin h theta)."""
    c = frf.coefficients(1)
    theta = np.linspace(0.0, 2.0 * np.pi, n_t, endpoint=False)
    h = np.arange(1, c.shape[1])
    v = c[:, :1].real + (c[:, 1:, None] * np.exp(1j * h[:, None] * theta)).real.sum(axis=1)
    return np.mean(Contact2D(**POINT).normal_force(v) == 0.0, axis=1)


def test_point_contact_scene_separates_and_starts_stuck(tmp_path):
    scene = load_scene(SCENES / "contact_normal.toml", overrides={"sweep.omega": [0.8, 0.85]})
    frf = run_scene(scene, tmp_path, progress=None).runs[0].frf
    # stuck, in contact all period at 0.8 rad/s: the first harmonic is the linear response with kt on the
    # tangential DOF and kn on the normal one (the preload only shifts the mean)
    w = frf.omega[0]
    Kc = K2 + np.diag([POINT["kt"], POINT["kn"]])
    x = np.linalg.solve(Kc - w * w * np.eye(2) + 1j * w * 0.01 * K2, [0.015, 0.0])
    assert frf.amplitude[0] == pytest.approx(abs(x[0]), rel=1e-8)
    assert abs(x[0]) < POINT["mu"] * POINT["n0"] / POINT["kt"]  # below the slip amplitude indeed
    assert np.all(open_fraction(frf) == 0.0)
    near = run_scene(load_scene(SCENES / "contact_normal.toml", overrides={"sweep.omega": [1.55, 1.65]}),
                     tmp_path / "near", progress=None).runs[0].frf
    share = open_fraction(near)
    assert 0.2 < share.max() < 0.5 and share.min() == 0.0  # open over part of the cycle, near the normal mode


def test_new_keys_are_listed_and_documented():
    out = subprocess.run([sys.executable, "-m", "hbm", "keys"], cwd=ROOT, capture_output=True, text=True, check=True)
    page = (ROOT / "docs" / "scenes.md").read_text()
    for key in NEW_KEYS:
        assert key in out.stdout, key
        assert f"| `{key}` |" in page, key
    models = subprocess.run([sys.executable, "-m", "hbm", "models"], cwd=ROOT, capture_output=True, text=True,
                            check=True).stdout
    assert all(f"\n{m} " in "\n" + models for m in ("gap", "contact2d", "cubic"))


def structure_scene(folder, damper=None, contacts=None, **structure):
    np.save(folder / "M.npy", np.eye(2))
    np.save(folder / "K.npy", K2)
    table = {"mass": "M.npy", "stiffness": "K.npy", "rayleigh": [0.0, 0.01], "force": [0.015, 0.0],
             "contact_dofs": [0], "normal_dofs": [1], **structure}
    if contacts is not None:
        table["contacts"] = contacts
    return {"structure": table, "damper": damper or DAMPER,
            "sweep": {"omega": [0.8, 0.9]}, "output": {"formats": ["csv"]}}


def test_bad_contacts_name_their_entry_and_key(tmp_path):
    damper = DAMPER
    bad = [{"model": "gap", "dofs": [1], "gap_stifness": 1.0},                # misspelt, gap missing
           {"model": "gap", "dofs": [1], "gap_stiffness": -1.0, "gap": 0.1},  # out of range
           {"dofs": [0]},                                                      # no model
           {"model": "macroslip", "dofs": [1]},                                # needs the bar
           {"model": "gapp", "dofs": [0]},                                     # unknown model
           {"model": "cubic", "k3": 0.0}]                                      # k3 = 0, no dofs
    text = problems(structure_scene(tmp_path, damper, bad), tmp_path / "bad.toml")
    for expected in ("structure.contacts[0].gap_stifness = 1.0: unknown key (did you mean structure.contacts[0]."
                     "gap_stiffness?)", "structure.contacts[0].gap_stiffness is missing",
                     "structure.contacts[0].gap is missing", "structure.contacts[1].gap_stiffness = -1.0: must be "
                     "a number > 0 (N/m)", "structure.contacts[2].model is missing",
                     "structure.contacts[3].model = \"macroslip\": as given it needs the bar and load of [damper]",
                     "structure.contacts[4].model = \"gapp\": must be one of", "(did you mean \"gap\"?)",
                     "structure.contacts[5].k3 = 0.0: must be a nonzero finite number",
                     "structure.contacts[5].dofs is missing"):
        assert expected in text, (expected, text)
    text = problems(structure_scene(tmp_path, damper, [{"model": "gap", "dofs": [5], "gap_stiffness": 1.0,
                                                        "gap": 0.1}]), tmp_path / "bad.toml", plan=True)
    assert "structure.contacts[0].dofs = [5]: DOF 5 is out of range for the structure's 2 DOFs" in text
    text = problems(structure_scene(tmp_path, damper, [{"model": "gap", "dofs": [0], "normal_dofs": [1],
                                                        "gap_stiffness": 1.0, "gap": 0.1}]), tmp_path / "b.toml",
                    plan=True)
    assert "structure.contacts[0].normal_dofs = [1]: not allowed: the gap element acts on one displacement" in text


def test_bad_damper_attachment_and_keys_are_named(tmp_path):
    damper = DAMPER
    data = structure_scene(tmp_path, damper)
    del data["structure"]["normal_dofs"]
    assert "structure.normal_dofs is missing: the contact2d element acts on a tangential and a normal" in problems(
        data, tmp_path / "a.toml", plan=True)
    assert "structure.normal_dofs = [0]: normal_dof(s) must differ from the tangential dof(s)" in problems(
        structure_scene(tmp_path, damper, normal_dofs=[0]), tmp_path / "a.toml", plan=True)
    assert "structure.normal_dofs = [1]: not allowed: the macroslip element acts on one displacement" in problems(
        structure_scene(tmp_path, {"model": "macroslip", "stiffness": 1.0, "slip_force": 0.03}), tmp_path / "a.toml",
        plan=True)
    text = problems(structure_scene(tmp_path, {"model": "contact2d", "kt": 1.0, "kn": -1.0}), tmp_path / "a.toml")
    assert "damper.kn = -1.0: must be a number >= 0 (N/m for contact2d and contact3d, N/m^2 for allmode2d)" in text
    assert "damper.friction is missing: required with damper.model = \"contact2d\"" in text
    assert "damper.n0 is missing" in text
    blade = {"damper": damper, "blade": {"mass": 1.0, "stiffness": 1.0, "damping": 0.01, "force": 0.01},
             "sweep": {"omega": [0.8, 0.9]}}
    assert "damper.model = \"contact2d\": the element acts on a tangential and a normal displacement; a [blade]" in (
        problems(blade, tmp_path / "a.toml", plan=True))
    table = {"damper": {"model": "gap", "gap_stiffness": 1.0, "gap": 0.1},
             "sweep": {"kind": "amplitude", "omega": [0.0], "amplitude": [0.1, 10.0]}}
    assert "sweep.kind = \"amplitude\": damper.model = \"gap\" has no stuck stiffness (k* = 0" in problems(
        table, tmp_path / "a.toml", plan=True)
    data = structure_scene(tmp_path, damper)
    data["effects"] = {"harmonics": 3, "samples": 7}
    assert "effects.samples = 7: must be at least 2 H + 2 = 8" in problems(data, tmp_path / "a.toml", plan=True)
    blade["damper"] = {"model": "macroslip", "stiffness": 1.0, "slip_force": 0.03}
    blade["effects"] = {"samples": 64}
    assert "effects.samples = 64: not used here" in problems(blade, tmp_path / "a.toml", plan=True)


def test_gallery_example_draws_the_separation(tmp_path):
    sys.path.insert(0, str(ROOT / "examples"))
    try:
        import contact_normal_scene
    finally:
        sys.path.remove(str(ROOT / "examples"))
    out = contact_normal_scene.main(outdir=tmp_path, small=True)
    assert Path(out["path"]).stat().st_size > 10_000
    lo, hi = out["open_range"]
    assert 0.2 < out["open_max"] < 0.5 and 1.5 < lo < hi < 1.7


@pytest.mark.slow
@pytest.mark.parametrize("name", ["nlvib_ex07", "contact_normal"])
def test_example_scene_runs_in_full_from_the_command_line(tmp_path, name):
    subprocess.run([sys.executable, "-m", "hbm", "run", str(SCENES / f"{name}.toml"), "--out", str(tmp_path),
                    "--quiet"], cwd=ROOT, check=True, capture_output=True)
    assert (tmp_path / "frf.csv").is_file() and (tmp_path / "frf.png").is_file()
    rows = list(csv.DictReader(csv_lines((tmp_path / "frf.csv").open())))
    assert float(rows[-1]["omega_rad_s"]) == pytest.approx(2.0, rel=1e-9)
