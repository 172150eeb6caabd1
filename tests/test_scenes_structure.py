"""A scene describes a structure from matrix files: ``[structure]``.

The 3-DOF chain of docs/multiharmonic.md (unit masses and springs ground-0-1-2, C = 0.004 K, forced at DOF 2),
its M and K written as Matrix Market and .npz files, a Jenkins element to ground at DOF 0: the
scene's FRF is exactly ``frequency_response(Structure, [Contact])`` with the same options, at
H = 1 and at H = 5 (``effects.harmonics``), and bad input names its key.
"""

import csv

import numpy as np
import pytest
import scipy.io
import scipy.sparse

from contact_models import Macroslip
from hbm import Contact, Structure, frequency_response
from hbm.scenes import SceneError, plan_scene, run_scene, scene_from_dict
from hbm.output import csv_lines

K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
F = [0.0, 0.0, 0.01]


@pytest.fixture
def files(tmp_path):
    scipy.io.mmwrite(str(tmp_path / "K.mtx"), scipy.sparse.coo_matrix(K))
    np.savez(tmp_path / "mats.npz", M=np.eye(3))
    return tmp_path


def scene(folder, **structure):
    table = {"mass": "mats.npz:M", "stiffness": "K.mtx", "rayleigh": [0.0, 0.004], "force": F,
             "contact_dofs": [0], "response_dof": 2}
    table.update(structure)
    return {"structure": table,
            "damper": {"model": "macroslip", "stiffness": 1.0, "slip_force": 0.02},
            "sweep": {"omega": [0.3, 0.8]}, "output": {"formats": ["csv"]}}


@pytest.mark.parametrize("H", [1, 5])
def test_structure_scene_is_the_api_computation(files, H):
    data = scene(files)
    data["effects"] = {"harmonics": H}
    sc = scene_from_dict(data, files / "chain.toml")
    plan = plan_scene(sc)
    slip = next(e for e in plan.runs[0].effects if e.name == "damper slip")
    assert slip.simulated and "structure" in slip.reason
    result = run_scene(sc, files / "out", plan=plan)
    assert result.success, result.message
    s = Structure(np.eye(3), 0.004 * K, K, force=F)
    options = {"harmonics": H, **sc.sweep["options"]}  # the harmonics effect adds H > 1 and its n_t
    assert options["harmonics"] == H
    api = frequency_response(s, [Contact(Macroslip(stiffness=1.0, slip_force=0.02), dof=0)], omega_range=(0.3, 0.8),
                             response_dof=2, **options)
    frf = result.runs[0].frf
    assert len(frf.omega) == len(api.omega)
    np.testing.assert_allclose(frf.amplitude, api.amplitude, rtol=1e-12)
    rows = list(csv.DictReader(csv_lines((files / "out" / "frf.csv").open())))
    assert len(rows) == len(frf.omega)
    # in the stuck range the response is the chain's linear response with the contact as a spring
    w = frf.omega[0]
    Kc = K + np.diag([1.0, 0.0, 0.0])
    x = np.linalg.solve(Kc - w * w * np.eye(3) + 1j * w * 0.004 * K, F)
    assert frf.amplitude[0] == pytest.approx(abs(x[2]), rel=1e-8)


@pytest.mark.parametrize("dofs", [[[0, 1]], [[0, 0]], [0, [1]]])
def test_contact_dofs_holding_a_list_are_refused_naming_the_key(files, dofs):
    """A list among the DOFs was a TypeError "unhashable type: 'list'" out of the validation (a traceback, exit code 1)."""
    with pytest.raises(SceneError, match=r"structure.contact_dofs = \[.*\]: must be a list of one DOF index"):
        scene_from_dict(scene(files, contact_dofs=dofs), files / "bad.toml")


def test_structure_scene_errors_name_their_keys(files):
    with pytest.raises(SceneError) as err:
        scene_from_dict(scene(files, modal_damping=0.01, contact_dofs=[1, 1]), files / "bad.toml")
    text = "\n".join(err.value.problems)
    assert "structure.contact_dofs" in text and "give exactly one of structure.damping" in text
    with pytest.raises(SceneError, match="structure.contact_dofs = \\[7\\]: DOF 7 is out of range"):
        plan_scene(scene_from_dict(scene(files, contact_dofs=[7]), files / "bad.toml"))
    with pytest.raises(SceneError, match=r"\[structure\]:"):
        plan_scene(scene_from_dict(scene(files, stiffness="missing.mtx"), files / "bad.toml"))
    data = scene(files)
    data["blade"] = {"mass": 1.0, "stiffness": 1.0, "damping": 0.01, "force": 1.0}
    with pytest.raises(SceneError, match=r"\[blade\] and \[structure\] together"):
        scene_from_dict(data, files / "bad.toml")
