"""A scene of one sector of a tuned bladed disk: ``structure.sectors``.

The shipped ``examples/scenes/bladed_disk.toml`` is the lumped 24-blade disk of
``examples/bladed_disk.py`` with a Jenkins under-platform damper between neighbouring platforms:
its matrix files are that script's sector, its FRF is exactly ``frequency_response`` of
``hbm.CyclicStructure`` with the same options, its stuck start is the linear travelling-wave
response solved here by hand, and every new key's bad value names the key.
"""

import math
import re
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.io
import scipy.sparse

from contact_models import Macroslip
from hbm import Contact, CyclicStructure, frequency_response
from hbm.scenes import SceneError, load_scene, plan_scene, run_scene, scene_from_dict

ROOT = Path(__file__).resolve().parent.parent
SCENE = ROOT / "examples" / "scenes" / "bladed_disk.toml"
# the lumped disk, written out here from its description (examples/bladed_disk.py): kg, N/m, s
KG, KB, KP, KC = 5e8, 1e8, 2e8, 2e8
M = np.diag([0.5, 0.0877, 0.01])
K = np.array([[KG + KB + 2 * KC, -KB, 0.0], [-KB, KB + KP, -KP], [0.0, -KP, KP]])
K1 = np.zeros((3, 3))
K1[0, 0] = -KC
BETA, F, KD, FS = 2e-7, [0.0, 8.0, 0.0], 4e7, 20.0


def test_matrix_files_are_the_example_sector():
    folder = SCENE.parent / "bladed_disk"
    for name, A in (("M", M), ("K", K), ("K_next", K1)):
        np.testing.assert_array_equal(scipy.io.mmread(str(folder / f"{name}.mtx")).toarray(), A)
    sys.path.insert(0, str(ROOT / "examples"))
    try:
        import bladed_disk
    finally:
        sys.path.remove(str(ROOT / "examples"))
    disk = bladed_disk.sector(24, 6)
    np.testing.assert_array_equal(np.asarray(disk.K), K)
    np.testing.assert_array_equal(disk.K_next, K1)
    assert (bladed_disk.DAMPER_STIFFNESS, bladed_disk.SLIP_FORCE, bladed_disk.BETA) == (KD, FS, BETA)


def test_bladed_disk_scene_is_the_api_computation(tmp_path):
    sc = load_scene(SCENE)
    plan = plan_scene(sc)
    assert isinstance(plan.blade, CyclicStructure)
    assert (plan.blade.sectors, plan.blade.engine_order) == (24, 6)
    result = run_scene(sc, tmp_path / "out", plan=plan)
    assert result.success, result.message
    H = sc.effects["harmonics"]
    assert H == 5
    disk = CyclicStructure(M, BETA * K, K, sectors=24, engine_order=6, force=F, K_next=K1, C_next=BETA * K1)
    damper = Contact(Macroslip(stiffness=KD, slip_force=FS), dofs=(2, 2), next_sector=True)
    api = frequency_response(disk, [damper], omega_range=tuple(sc.sweep["omega"]), response_dof=1,
                             harmonics=H, **sc.sweep["options"])
    frf = result.runs[0].frf
    assert len(frf.omega) == len(api.omega)
    np.testing.assert_allclose(frf.omega, api.omega, rtol=1e-9)
    np.testing.assert_allclose(frf.amplitude, api.amplitude, rtol=1e-9)
    # the start, damper stuck (below its slip amplitude FS/KD): the linear travelling wave at nodal diameter 6,
    # the damper a spring KD between the platforms, solved from the nodal-diameter matrices written out here
    w = frf.omega[0]
    e = np.exp(-2j * math.pi * 6 / 24)
    Kd = np.zeros((3, 3))
    Kd[2, 2] = 2 * KD
    Kd1 = np.zeros((3, 3))
    Kd1[2, 2] = -KD
    Kn = K + Kd + (K1 + Kd1) * e + (K1 + Kd1).T * np.conj(e)
    Cn = BETA * (K + K1 * e + K1.T * np.conj(e))
    x = np.linalg.solve(Kn - w * w * M + 1j * w * Cn, F)
    assert frf.amplitude[0] == pytest.approx(abs(x[1]), rel=1e-8)
    assert abs(x[2] * (e - 1)) < FS / KD  # the platforms' relative motion: stuck indeed


def files(tmp_path):
    scipy.io.mmwrite(str(tmp_path / "M.mtx"), scipy.sparse.coo_matrix(M))
    scipy.io.mmwrite(str(tmp_path / "K.mtx"), scipy.sparse.coo_matrix(K))
    scipy.io.mmwrite(str(tmp_path / "K1.mtx"), scipy.sparse.coo_matrix(K1))
    np.save(tmp_path / "C.npy", BETA * K)
    np.save(tmp_path / "C1.npy", BETA * K1)
    np.save(tmp_path / "K4.npy", np.zeros((4, 4)))
    return tmp_path


def scene(**structure):
    table = {"mass": "M.mtx", "stiffness": "K.mtx", "next_stiffness": "K1.mtx", "rayleigh": [0.0, BETA],
             "force": F, "sectors": 24, "engine_order": 6, "contact_dofs": [2, 2], "next_sector": True,
             "response_dof": 1}
    table.update(structure)
    for k in [k for k, v in table.items() if v is None]:
        del table[k]
    return {"structure": table, "damper": {"model": "macroslip", "stiffness": KD, "slip_force": FS},
            "sweep": {"omega": [30000.0, 40000.0], "tol": 0.05}, "output": {"formats": ["csv"]}}


def test_contact_entry_to_the_next_sector_and_a_damping_file(tmp_path):
    """The damper to ground at the disk DOF and the platforms' damper as a [[structure.contacts]] entry, the
    damping from files (structure.damping, structure.next_damping) and EO 30 = 6 mod 24."""
    folder = files(tmp_path)
    data = scene(rayleigh=None, damping="C.npy", next_damping="C1.npy", engine_order=30, contact_dofs=[0],
                 next_sector=None)
    data["damper"] = {"model": "macroslip", "stiffness": 1e6, "slip_force": 1.0}
    data["structure"]["contacts"] = [{"model": "macroslip", "dofs": [2, 2], "next_sector": True,
                                      "stiffness": KD, "slip_force": FS}]
    sc = scene_from_dict(data, folder / "disk.toml")
    result = run_scene(sc, folder / "out")
    assert result.success, result.message
    disk = CyclicStructure(M, BETA * K, K, sectors=24, engine_order=6, force=F, K_next=K1, C_next=BETA * K1)
    contacts = [Contact(Macroslip(stiffness=1e6, slip_force=1.0), dof=0),
                Contact(Macroslip(stiffness=KD, slip_force=FS), dofs=(2, 2), next_sector=True)]
    api = frequency_response(disk, contacts, omega_range=(30000.0, 40000.0), response_dof=1,
                             harmonics=sc.effects["harmonics"], **sc.sweep["options"])
    frf = result.runs[0].frf
    assert len(frf.omega) == len(api.omega)
    np.testing.assert_allclose(frf.amplitude, api.amplitude, rtol=1e-9)


@pytest.mark.parametrize("structure, message", [
    ({"sectors": 1}, r"structure.sectors = 1: must be an integer >= 2"),
    ({"sectors": 2.5}, r"structure.sectors = 2.5: must be an integer >= 2"),
    ({"engine_order": 1.5}, r"structure.engine_order = 1.5: must be an integer"),
    ({"engine_order": True}, r"structure.engine_order = true: must be an integer"),
    ({"engine_order": None}, r"structure.engine_order is missing: required with structure.sectors"),
    ({"sectors": None}, r"structure.engine_order = 6: not allowed unless structure.sectors is given"),
    ({"sectors": None, "engine_order": None}, r"structure.next_stiffness = \"K1.mtx\": not allowed unless "
                                              r"structure.sectors"),
    ({"sectors": None, "engine_order": None, "next_stiffness": None},
     r"structure.next_sector = true: not allowed unless structure.sectors"),
    ({"next_sector": "yes"}, r"structure.next_sector = \"yes\": must be true or false"),
    ({"next_sector": False}, r"structure.contact_dofs = \[2, 2\]: must be two different DOFs"),
    ({"next_stiffness": 3}, r"structure.next_stiffness = 3: must be"),
    ({"rayleigh": None, "modal_damping": 0.01},
     r"structure.modal_damping = \[0.01\]: not allowed with structure.sectors"),
    ({"next_damping": "C1.npy"}, r"structure.next_damping = \"C1.npy\": not allowed unless structure.damping"),
])
def test_cyclic_keys_errors_name_their_keys(tmp_path, structure, message):
    folder = files(tmp_path)
    with pytest.raises(SceneError) as err:
        scene_from_dict(scene(**structure), folder / "bad.toml")
    assert any(re.search(message, p) for p in err.value.problems), err.value.problems


def test_nonlinear_modes_of_a_sector_are_refused(tmp_path):
    folder = files(tmp_path)
    data = scene()
    data["modes"] = {"amplitude": [1e-8, 1e-6]}
    with pytest.raises(SceneError, match=r"structure.sectors = 24: not allowed with \[modes\]"):
        scene_from_dict(data, folder / "bad.toml")


def test_contact_entry_next_sector_errors(tmp_path):
    folder = files(tmp_path)
    data = scene(sectors=None, engine_order=None, next_stiffness=None, next_sector=None, contact_dofs=[0])
    entry = {"model": "macroslip", "dofs": [2, 2], "next_sector": True, "stiffness": KD, "slip_force": FS}
    data["structure"]["contacts"] = [entry]
    with pytest.raises(SceneError, match=r"structure.contacts\[0\].next_sector = true: not allowed unless "
                                         r"structure.sectors"):
        scene_from_dict(data, folder / "bad.toml")
    data = scene(contact_dofs=[0], next_sector=None)
    data["structure"]["contacts"] = [dict(entry, next_sector=False)]
    with pytest.raises(SceneError, match=r"structure.contacts\[0\].dofs = \[2, 2\]: must be two different DOFs"):
        scene_from_dict(data, folder / "bad.toml")
    data["structure"]["contacts"] = [dict(entry, next_sector=1)]
    with pytest.raises(SceneError, match=r"structure.contacts\[0\].next_sector = 1: must be true or false"):
        scene_from_dict(data, folder / "bad.toml")


def test_cyclic_plan_errors_name_their_keys(tmp_path):
    folder = files(tmp_path)
    with pytest.raises(SceneError, match=r"structure.contact_dofs = \[2\]: with structure.next_sector = true it "
                                         r"must be a pair"):
        plan_scene(scene_from_dict(scene(contact_dofs=[2]), folder / "bad.toml"))
    with pytest.raises(SceneError, match=r"structure.next_stiffness: K_next must be 3 x 3 like M"):
        plan_scene(scene_from_dict(scene(next_stiffness="K4.npy"), folder / "bad.toml"))
    with pytest.raises(SceneError, match=r"structure.next_stiffness must name an existing matrix file"):
        plan_scene(scene_from_dict(scene(next_stiffness="missing.mtx"), folder / "bad.toml"))
