"""Defects users reported on inputs, outputs and the command line: each test fails without its fix.

The scenes here are the 3-DOF chain of ``examples/scenes/chain_3dof.toml`` (unit masses and
springs ground-0-1-2, C = 0.004 K, forced at DOF 2, a Jenkins damper to ground at DOF 0) with one
of its files or keys spoilt.
"""

import os
import re
import warnings

import numpy as np
import pytest
import scipy.sparse

from contact_models import Macroslip, SampledLoad
from hbm import Contact, Structure, frequency_response, periodic_response
from hbm.cli.main import main
from hbm.scenes import SceneError, load_scene, plan_scene, scene_from_dict
from hbm.structure import load_matrix

K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
F = [0.0, 0.0, 0.01]


def chain(folder, **structure):
    np.save(folder / "M.npy", np.eye(3))
    np.save(folder / "K.npy", K)
    table = {"mass": "M.npy", "stiffness": "K.npy", "rayleigh": [0.0, 0.004], "force": F,
             "contact_dofs": [0], "response_dof": 2}
    table.update(structure)
    return {"structure": table, "damper": {"model": "macroslip", "stiffness": 1.0, "slip_force": 0.02},
            "effects": {"harmonics": 3}, "sweep": {"omega": [0.3, 0.8]}}


def problems(data, folder):
    with pytest.raises(SceneError) as info:
        plan_scene(scene_from_dict(data, folder / "chain.toml"))
    return info.value.problems


# ----------------------------------------------------------------------------- inputs
@pytest.mark.parametrize("sparse", [False, True])
def test_complex_stiffness_is_refused_by_name(sparse):
    Kc = K + 1j
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no ComplexWarning on the way: refused before any cast
        with pytest.raises(ValueError, match=r"^K must be real, got a complex matrix \(max\|Im K\| = 1\)"):
            Structure(np.eye(3), 0.01 * np.eye(3), scipy.sparse.csr_matrix(Kc) if sparse else Kc, force=F)


def test_a_complex_force_is_a_phase_per_dof_and_the_time_references_refuse_it_by_name():
    s = Structure(np.eye(3), 0.01 * np.eye(3), K, force=[0.0, 0.0, 1.0 + 2.0j])  # amplitude and phase of cos
    assert s.force.dtype == np.complex128 and s.force[2] == 1.0 + 2.0j
    with pytest.raises(ValueError, match=r"^force must be real for the time-domain references"):
        periodic_response(s, [Contact(Macroslip(1.0, 0.02), dof=0)], omega=1.0)


def test_complex_matrix_with_zero_imaginary_part_is_its_real_part():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        s = Structure(np.eye(3), 0.01 * np.eye(3), K + 0j, force=np.array(F, dtype=complex))
    assert s.K.dtype == np.float64 and np.array_equal(s.K, K)
    assert s.force.tolist() == F


def test_complex_npy_in_a_scene_names_structure_stiffness(tmp_path):
    data = chain(tmp_path)
    np.save(tmp_path / "K.npy", K + 1j)
    assert problems(data, tmp_path) == [
        f"{tmp_path / 'chain.toml'}: structure.stiffness: K must be real, got a complex matrix (max|Im K| = 1)"]


def test_sampled_load_nan_names_values():
    with pytest.raises(ValueError, match=r"^values must be finite, got values=\[1.0, nan, 1.0\]"):
        SampledLoad(x=[0.0, 0.025, 0.05], values=[1.0, float("nan"), 1.0])
    with pytest.raises(ValueError, match=r"^x must be finite"):
        SampledLoad(x=[0.0, float("nan"), 0.05], values=[1.0, 1.0, 1.0])


def test_garbage_npy_names_the_parameter_and_the_file(tmp_path):
    bad = tmp_path / "K.npy"
    bad.write_bytes(b"\x80\x04garbage, not an array")
    with pytest.raises(ValueError, match="^stiffness must name a matrix file that numpy can read, got stiffness="):
        load_matrix(bad, name="stiffness")
    with pytest.raises(ValueError, match=r"^mass must name a matrix file that numpy can read, got mass='.*K\.npy'"):
        Structure.from_files(bad, bad, force=F, rayleigh=(0.0, 0.004))


def test_garbage_npy_in_a_scene_names_the_key_and_the_file(tmp_path):
    data = chain(tmp_path)
    (tmp_path / "K.npy").write_bytes(b"garbage")
    (message,) = problems(data, tmp_path)
    assert message.startswith(f"{tmp_path / 'chain.toml'}: [structure]: structure.stiffness must name a matrix file that numpy "
                              f"can read, got structure.stiffness={str(tmp_path / 'K.npy')!r}")


def test_pickled_npy_in_a_scene_is_not_loaded_and_named(tmp_path):
    data = chain(tmp_path)
    np.save(tmp_path / "K.npy", np.array([{"K": 1}], dtype=object), allow_pickle=True)
    (message,) = problems(data, tmp_path)
    assert "structure.stiffness must name a matrix file" in message
    assert "pickled Python objects, which are not loaded" in message


def test_singular_stiffness_fails_the_check_and_writes_nothing(tmp_path, capsys):
    data = chain(tmp_path)
    np.save(tmp_path / "K.npy", np.array([[1.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]]))  # free-free
    expected = (f"{tmp_path / 'chain.toml'}: structure.stiffness: K must be nonsingular (a structure held only by "
                "its contacts has no static compliance to condense with), got a singular K")
    assert problems(data, tmp_path) == [expected]
    path = tmp_path / "chain.toml"
    path.write_text('[structure]\nmass = "M.npy"\nstiffness = "K.npy"\nrayleigh = [0.0, 0.004]\n'
                    'force = [0.0, 0.0, 0.01]\ncontact_dofs = [0]\n[damper]\nmodel = "macroslip"\n'
                    'stiffness = 1.0\nslip_force = 0.02\n[effects]\nharmonics = 3\n[sweep]\nomega = [0.3, 0.8]\n')
    assert main(["run", str(path), "--check"]) == 2
    assert expected in capsys.readouterr().err
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out)]) == 2
    assert not out.exists()


def test_singular_stiffness_of_one_dof_at_one_harmonic_still_runs(tmp_path):
    # the one-DOF single-harmonic balance needs no K^-1: k = 0 with a damper is a valid scene
    np.save(tmp_path / "M1.npy", np.eye(1))
    np.save(tmp_path / "K1.npy", np.zeros((1, 1)))
    data = {"structure": {"mass": "M1.npy", "stiffness": "K1.npy", "rayleigh": [0.01, 0.0], "force": [0.01],
                          "contact_dofs": [0]},
            "damper": {"model": "macroslip", "stiffness": 1.0, "slip_force": 0.02}, "sweep": {"omega": [0.3, 0.8]}}
    assert len(plan_scene(scene_from_dict(data, tmp_path / "one.toml")).runs) == 1


def test_harmonics_string_is_refused_by_key(tmp_path):
    data = chain(tmp_path)
    data["effects"]["harmonics"] = "3"
    with pytest.raises(SceneError) as info:
        scene_from_dict(data, tmp_path / "chain.toml")
    assert info.value.problems == [f"{tmp_path / 'chain.toml'}: effects.harmonics = \"3\": must be an integer >= 1"]


@pytest.mark.parametrize("H", ["3", b"3"])
def test_harmonics_string_is_refused_by_the_api(H):
    s = Structure(np.eye(3), 0.004 * K, K, force=F)
    with pytest.raises(ValueError, match=r"^harmonics must be an integer >= 1, got harmonics="):
        frequency_response(s, [Contact(Macroslip(stiffness=1.0, slip_force=0.02), dof=0)], (0.3, 0.8), harmonics=H)


def test_binary_scene_file_is_named(tmp_path):
    path = tmp_path / "binary.toml"
    path.write_bytes(b'title = "\xff\xfe"\n')
    with pytest.raises(SceneError) as info:
        load_scene(path)
    assert info.value.problems == [f"{path}: not valid TOML: not UTF-8 text (byte b'\\xff' at offset 9); a scene "
                                   "is a UTF-8 text file"]


def test_binary_scene_file_is_named_on_the_command_line(tmp_path, capsys):
    path = tmp_path / "binary.toml"
    path.write_bytes(bytes(range(256)))
    assert main(["run", str(path), "--check"]) == 2
    assert f"{path}: not valid TOML: not UTF-8 text" in capsys.readouterr().err


def test_a_negative_stiffness_mode_is_refused_when_the_structure_is_built():
    Kn = np.array([[2.0, -1.0], [-1.0, -3.0]])  # eigenvalues 2.19, -3.19: before natural_frequencies refused it
    with pytest.raises(ValueError, match=r"^K must be positive semi-definite \(no negative stiffness: the structure "
                                         r"would be statically unstable\), got K with a negative eigenvalue \(smallest "
                                         r"-3.19\d*, largest in magnitude 3.19\d*\)$"):
        Structure(np.eye(2), 0.01 * np.eye(2), Kn, force=[1.0, 0.0])


def test_natural_frequencies_keep_a_rigid_body_mode_at_zero():
    s = Structure(np.eye(2), 0.01 * np.eye(2), [[1.0, -1.0], [-1.0, 1.0]], force=[1.0, 0.0])
    w = s.natural_frequencies()
    assert w[0] == 0.0 and w[1] == pytest.approx(np.sqrt(2.0), rel=1e-14)


# ----------------------------------------------------------------------------- the command line
@pytest.mark.parametrize("argv", [["new", "{path}", "--out", "sub"], ["--out", "sub", "new", "{path}"],
                                  ["new", "{path}", "--rtol", "1e-3"], ["models", "--rtol", "1e-3"],
                                  ["keys", "--out", "sub"], ["--rtol", "1e-3", "keys"]])
def test_subcommands_refuse_options_they_do_not_take(tmp_path, capsys, argv):
    path = tmp_path / "s2.toml"
    with pytest.raises(SystemExit) as stop:
        main([a.format(path=path) for a in argv])
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert "unrecognized arguments: --" in err or "does not apply to" in err
    assert not path.exists() and not (tmp_path / "sub").exists()


def test_new_writes_where_it_is_told_and_nothing_else(tmp_path):
    path = tmp_path / "s2.toml"
    assert main(["new", str(path)]) == 0 and path.exists()
    assert main(["new", str(path), "--force"]) == 0


def test_help_lists_every_option_of_run():
    from hbm.cli.main import build_parser

    text = " ".join(build_parser("python3 -m hbm").format_help().split())
    run = text[text.index("run run a scene file"):text.index("new write")]
    for option in ("--out DIR", "--set TABLE.KEY=VALUE", "--rtol X", "--quiet", "--check", "--workers N",
                   "--scheduler ADDRESS", "--executor NAME"):
        assert option in run, option


# ----------------------------------------------------------------------------- outputs
import csv  # noqa: E402
import math  # noqa: E402
import tomllib  # noqa: E402
from pathlib import Path  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")
from matplotlib.figure import Figure  # noqa: E402

from hbm.output import csv_lines, FRF_COLUMNS, harmonic_columns  # noqa: E402
from hbm.scenes import run_scene, summary_lines  # noqa: E402

EXAMPLES = Path(__file__).resolve().parent.parent / "examples" / "scenes"
DEFAULT = EXAMPLES / "default_microslip_frf.toml"


def read_csv(path):
    with open(path, newline="") as fh:
        rows = list(csv.reader(csv_lines(fh)))
    return rows[0], rows[1:]


@pytest.fixture
def drawn(monkeypatch):
    """The figures a scene saves, kept for inspection."""
    figures = []
    save = Figure.savefig

    def keep(self, *args, **kwargs):
        figures.append(self)
        return save(self, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", keep)
    return figures


def test_multiharmonic_scene_csv_holds_every_harmonic_and_the_stability(tmp_path):
    data = tomllib.loads((EXAMPLES / "chain_3dof.toml").read_text())
    data["effects"]["harmonics"] = 3
    data["output"] = {"formats": ["csv"]}
    result = run_scene(scene_from_dict(data, EXAMPLES / "chain_3dof.toml"), tmp_path)
    assert result.success
    header, rows = read_csv(tmp_path / "frf.csv")
    assert tuple(header) == ("run", "model", "normal_load_N") + FRF_COLUMNS + (
        "X0_m", "Xc1_m", "Xs1_m", "Xc2_m", "Xs2_m", "Xc3_m", "Xs3_m", "stable")
    frf = result.runs[0].frf
    c = frf.coefficients(2)
    first = header.index("X0_m")
    table = np.array([r[first:first + 7] for r in rows], dtype=float)
    assert len(rows) == len(frf) > 50
    assert np.array_equal(table[:, 0], c[:, 0].real)
    assert np.array_equal(table[:, 1::2], c[:, 1:].real) and np.array_equal(table[:, 2::2], -c[:, 1:].imag)
    assert np.array_equal(table[:, 1], frf.x_c) and np.array_equal(table[:, 2], frf.x_s)
    assert [r[-1] for r in rows] == [str(int(s)) for s in frf.stable]
    assert float(np.max(np.abs(table[:, 5:7]))) > 1e-4  # the third harmonic is there, not zeros
    assert not (tmp_path / "frf.csv.tmp").exists()


def test_to_csv_of_a_multiharmonic_response_holds_every_harmonic_and_the_stability(tmp_path):
    s = Structure.with_rayleigh(np.eye(3), K, alpha=0.0, beta=0.004, force=F)
    frf = frequency_response(s, [Contact(Macroslip(stiffness=1.0, slip_force=0.02), dof=0)], (0.3, 0.8),
                             harmonics=3, response_dof=2)
    header, rows = read_csv(frf.to_csv(tmp_path / "frf.csv"))
    assert tuple(header) == FRF_COLUMNS + harmonic_columns(3) + ("stable",)
    table = np.array([r[:-1] for r in rows], dtype=float)
    c = frf.coefficients(2)
    x0 = header.index("X0_m")  # the harmonics follow the library columns
    assert np.array_equal(table[:, 0], frf.omega) and np.array_equal(table[:, x0], c[:, 0].real)
    assert np.array_equal(table[:, x0 + 1::2], c[:, 1:].real) and np.array_equal(table[:, x0 + 2::2], -c[:, 1:].imag)
    assert [r[-1] for r in rows] == ["1" if s else "0" for s in frf.stable]


def test_to_csv_at_one_harmonic_keeps_the_library_columns(tmp_path):
    s = Structure.with_rayleigh(np.eye(3), K, alpha=0.0, beta=0.004, force=F)
    frf = frequency_response(s, [Contact(Macroslip(stiffness=1.0, slip_force=0.02), dof=0)], (0.3, 0.8),
                             harmonics=1, response_dof=2)
    header, rows = read_csv(frf.to_csv(tmp_path / "frf.csv"))
    assert tuple(header) == FRF_COLUMNS and len(rows) == len(frf)


def hz_scene(**sweep):
    data = tomllib.loads(DEFAULT.read_text())
    data["sweep"].update({"unit": "Hz", "omega": [5000.0, 6500.0], "max_step": 0.1, **sweep})
    return scene_from_dict(data, DEFAULT)


def test_sweep_in_hz_is_reported_in_hz(tmp_path, drawn):
    result = run_scene(hz_scene(), tmp_path)
    header, rows = read_csv(tmp_path / "frf.csv")
    assert header[3:5] == ["omega_rad_s", "f_Hz"] and header[5:] == list(FRF_COLUMNS[1:])
    omega, f = (np.array([r[i] for r in rows], dtype=float) for i in (3, 4))
    assert np.array_equal(f, omega / (2.0 * math.pi)) and f[0] == pytest.approx(5000.0, rel=1e-15)
    peak = result.summary["runs"][0]["peak"]
    assert peak["frequency_Hz"] == peak["omega_rad_s"] / (2.0 * math.pi)
    assert peak["frequency_Hz"] == pytest.approx(6170.17, rel=1e-5)
    line = next(x for x in summary_lines(result) if "peak:" in x)
    assert line.startswith(f"  peak: f = {peak['frequency_Hz']:.9g} Hz (omega = {peak['omega_rad_s']:.9g} rad/s)")
    (fig,) = drawn
    ax = fig.axes[0]
    assert ax.get_xlabel() == "frequency (Hz)" and ax.get_ylabel() == "amplitude (m)"  # SI, as the CSV
    curve = next(line for line in ax.lines if line.get_label() == "two-region, N = 100 N")
    assert curve.get_xdata()[0] == pytest.approx(5000.0, rel=1e-15)
    assert max(curve.get_ydata()) == float(np.max(result.runs[0].frf.amplitude))


def test_sweep_in_rad_per_second_keeps_its_columns(tmp_path):
    data = tomllib.loads(DEFAULT.read_text())
    data["sweep"]["max_step"] = 0.1
    data["output"] = {"formats": ["csv"]}
    run_scene(scene_from_dict(data, DEFAULT), tmp_path)
    assert tuple(read_csv(tmp_path / "frf.csv")[0]) == ("run", "model", "normal_load_N") + FRF_COLUMNS


def test_sweep_unit_in_lower_case_suggests_hz(tmp_path):
    with pytest.raises(SceneError) as info:
        hz_scene(unit="hz")
    assert info.value.problems == [f'{DEFAULT}: sweep.unit = "hz": must be one of "rad/s", "Hz", "omega_c" '
                                   '(did you mean "Hz"?)']


def test_scene_figure_draws_the_stuck_response_and_a_min_as_the_main_job(tmp_path, drawn):
    from hbm.balance.residual import linear_response

    result = run_scene(hz_scene(), tmp_path)
    (fig,) = drawn
    ax = fig.axes[0]
    by_label = {line.get_label(): line for line in ax.lines}
    stuck, a_min = by_label["damper stuck (linear)"], by_label["$a_{min}$ (slip begins)"]
    plan = result.runs[0].plan
    assert a_min.get_ydata()[0] == pytest.approx(plan.a_min, rel=1e-15)  # metres, as the CSV
    assert plan.a_min == pytest.approx(7.5e-7, rel=1e-3)
    w = np.array(stuck.get_xdata()) * 2.0 * math.pi
    el = plan.element
    expected = np.abs(linear_response(result.plan.blade, w, lambda om: np.array([el.stuck_stiffness(x) for x in om])))
    np.testing.assert_allclose(np.array(stuck.get_ydata()), expected, rtol=1e-12)
    assert max(stuck.get_ydata()) == pytest.approx(17.04e-6, rel=1e-3)  # the stuck resonance on 600 points, m


def test_main_job_figure_draws_the_same_references(tmp_path, drawn, monkeypatch):
    # drawn in this process, where savefig is seen (else in a forked one: the same picture,
    # tests/test_cli_figure.py)
    monkeypatch.delattr(os, "fork", raising=False)
    assert main(["--model", "given", "--out", str(tmp_path)]) == 0  # the references, the same for every model
    (fig,) = drawn
    labels = [line.get_label() for line in fig.axes[0].lines]
    assert "damper stuck (linear)" in labels and "$a_{min}$ (slip begins)" in labels
    a_min = next(line for line in fig.axes[0].lines if line.get_label() == "$a_{min}$ (slip begins)")
    assert a_min.get_ydata()[0] == pytest.approx(7.5e-7, rel=1e-12)


# ----------------------------------------------------------------------------- frictionless single-mode bars
def _frictionless(mu, N, three):
    from contact_models import Bar, QuadraticLoad, ThreeRegionMicroslip, TwoRegionMicroslip, UniformLoad

    bar = Bar(2e11, 7850.0, 1e-5, 0.05, 8e8, 4e7, mu)
    if three:
        return ThreeRegionMicroslip(bar, QuadraticLoad.from_ratio(N=N, ratio=12.0))
    return TwoRegionMicroslip(bar, UniformLoad(N))


@pytest.mark.parametrize("mu, N", [(0.0, 100.0), (0.3, 0.0)])
@pytest.mark.parametrize("three", [False, True])
def test_frictionless_single_mode_bar_is_the_linear_slipping_bar_at_any_frequency(mu, N, three):
    from contact_models import AllModeMicroslip
    from contact_models.model_range import single_mode_error, single_mode_frequency_limit

    el = _frictionless(mu, N, three)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no range warning: the linear bar is exact
        fs, fc = el.fourier(np.array([1e-6, 2e-6]), 4e4)
        assert float(np.max(single_mode_error(el, [1e-6, 1e-5], 4e4))) == 0.0
    K = el.slip_stiffness(4e4)
    assert np.allclose(fs, K * np.array([1e-6, 2e-6]), rtol=1e-12) and np.all(fc == 0.0)
    assert single_mode_frequency_limit(el) == np.inf
    ref_s, ref_c = AllModeMicroslip(el.bar, el.load).fourier(1e-6, 4e4)
    assert fs[0] == pytest.approx(float(ref_s), rel=2e-3) and abs(float(ref_c)) < 1e-6 * fs[0]


def test_frictionless_bar_frequency_response_is_the_linear_response():
    from hbm.cli.cases import default_case

    case = default_case()
    el = _frictionless(0.0, 100.0, False)
    frf = frequency_response(case.blade, el, omega_range=case.omega_range)
    assert frf.success
    b = case.blade
    w = frf.omega
    linear = np.abs(b.force / (b.stiffness + np.array([el.slip_stiffness(x) for x in w]) - b.mass * w ** 2
                               + 1j * b.damping * w))
    assert np.allclose(frf.amplitude, linear, rtol=1e-6)


@pytest.mark.parametrize("key", ["damper.mu=0.0", "damper.load.N=0.0"])
def test_frictionless_scene_checks_and_runs(tmp_path, capsys, key):
    scene = os.path.join(os.path.dirname(__file__), "..", "examples", "scenes", "default_microslip_frf.toml")
    assert main(["run", scene, "--check", "--set", key]) == 0
    assert "no friction (mu N = 0)" in capsys.readouterr().out
    assert main(["run", scene, "--quiet", "--set", key, "--out", str(tmp_path)]) == 0
    assert (tmp_path / "frf.csv").exists()


# ------------------------------------------------------------------------- a user's element that breaks its contract
class _Law:
    """A Jenkins element written by a user, spoilt in one way (``mode``)."""

    @staticmethod
    def make(mode, time_law=True):
        from contact_models.base import ContactElement

        class Law(ContactElement):
            has_time_law = time_law
            frequency_dependent = False

            def __init__(self):
                self.jen = Macroslip(1.0, 0.02)

            def __repr__(self):
                return f"Law({mode!r})"

            def _fourier_derivatives(self, a, w, rtol):
                out = self.jen.fourier_derivatives_unchecked(a, w, rtol)
                if mode == "complex":
                    return tuple(v + 1j for v in out)
                if mode == "long":
                    return tuple(np.concatenate([v, v]) for v in out)
                if mode == "none":
                    return None
                return out

            def _periodic_force(self, x, w):
                f, J = self.jen.periodic_force(x, w)
                if mode == "list":
                    return list(f), J
                if mode == "none":
                    return None
                if mode == "nan jacobian":
                    J = J.copy()
                    J[0, 0] = np.nan
                if mode == "jacobian shape":
                    J = J[:, :-1]
                return f, J

            def _stuck_stiffness(self, w):
                return 1.0

            def _slip_amplitude(self, w):
                return 0.02

            def _hysteresis(self, a, w, n):
                return self.jen.hysteresis(a, w, n=n)

        return Law()


def _chain_response(element, H):
    s = Structure(np.eye(3), 0.004 * K, K, force=F)
    return frequency_response(s, [Contact(element, dof=0)], (0.3, 0.8), harmonics=H)


def test_time_law_returning_none_or_a_wrong_shaped_jacobian_is_named_at_once():
    import time

    with pytest.raises(ValueError, match=r"^element=Law\('none'\): Law._periodic_force\(x, omega\) must return a "
                                         r"pair \(f, df_dx\), got NoneType None"):
        _chain_response(_Law.make("none"), 3)
    t0 = time.perf_counter()
    with pytest.raises(ValueError, match=r"^element=Law\('jacobian shape'\): Law._periodic_force\(x, omega\) must "
                                         r"return df_dx of shape \(\d+, \d+\) for x of shape \(\d+,\), got df_dx of "
                                         r"shape \(\d+, \d+\)"):
        _chain_response(_Law.make("jacobian shape"), 3)
    assert time.perf_counter() - t0 < 5.0


def test_time_law_returning_a_list_is_read_as_its_array():
    frf = _chain_response(_Law.make("list"), 3)
    assert frf.success


def test_a_nan_jacobian_is_named_as_not_finite_and_the_curve_fails_without_an_exception():
    frf = _chain_response(_Law.make("nan jacobian"), 3)
    assert not frf.success
    assert "element=Law('nan jacobian'): Law._periodic_force(x, omega) returned df_dx = " in frf.message
    assert "(not finite) at omega=0.3" in frf.message
    from contact_models.base import ElementOutputError

    with pytest.raises(ElementOutputError, match="not finite"):
        _Law.make("nan jacobian").periodic_force(np.cos(np.linspace(0.0, 2 * np.pi, 16, endpoint=False)), 0.3)


@pytest.mark.parametrize("mode, message", [
    ("complex", r"f_s must be real, got a complex array \(max\|Im\| = 1\)"),
    ("long", r"must return f_s with one value per amplitude \(2\), got f_s of shape \(4,\)"),
    ("none", r"must return 4 arrays \(f_s, f_c, df_s/da, df_c/da\), got NoneType None")])
def test_fourier_outputs_that_are_complex_too_long_or_none_are_refused_naming_the_element(mode, message):
    el = _Law.make(mode, time_law=False)
    with pytest.raises(ValueError, match=rf"^element=Law\('{mode}'\): Law._fourier_derivatives\(a, omega, rtol\)"
                                         rf".*{message}"):
        el.fourier(np.array([0.1, 0.2]), 0.5)
    with pytest.raises(ValueError, match=rf"^element=Law\('{mode}'\): Law._fourier_derivatives"):
        _chain_response(el, 1)


def test_point_contact_fit_of_an_element_without_a_bar_and_forced_response_of_a_string_are_named():
    from hbm import forced_response
    from contact_models import PointContact

    with pytest.raises(ValueError, match=r"^element must have stuck_stiffness, slip_stiffness and "
                                         r"gross_slip_amplitude .* without slip_stiffness, gross_slip_amplitude"):
        PointContact.fit(Macroslip(1.0, 1.0))
    with pytest.raises(ValueError, match=r"^modes must be the result of hbm.nonlinear_modes .* got modes='x'"):
        forced_response("x")


def test_strings_are_refused_as_numbers_like_counts():
    from contact_models import Bar

    with pytest.raises(ValueError, match=r"^E must be a number, got E='2e11'"):
        Bar(E="2e11", rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)


# ------------------------------------------------------------------------- files that would crash or exhaust the reader
def test_truncated_npz_is_a_scene_error_naming_the_key(tmp_path):
    data = chain(tmp_path)
    np.savez(tmp_path / "Kz.npz", K=K)
    raw = (tmp_path / "Kz.npz").read_bytes()
    (tmp_path / "Kz.npz").write_bytes(raw[:len(raw) // 2])
    data["structure"]["stiffness"] = "Kz.npz"
    (message,) = problems(data, tmp_path)
    assert "structure.stiffness must name a .npz file (a zip archive)" in message and "truncated" in message


def test_a_matrix_path_too_long_for_the_system_is_a_scene_error(tmp_path):
    data = chain(tmp_path)
    data["structure"]["stiffness"] = "x" * 5000 + ".npy"
    (message,) = problems(data, tmp_path)
    assert "structure.stiffness must name a matrix file that can be opened" in message
    assert "characters" in message


@pytest.mark.parametrize("header", ["%%MatrixMarket matrix array real general\n200000 200000\n1.0\n",
                                    "%%MatrixMarket matrix coordinate real general\n200000 200000 4000000000\n1 1 1\n"])
def test_a_matrix_file_declaring_more_than_the_bound_is_refused_before_reading(tmp_path, header):
    from hbm.scenes.matrices import MAX_MATRIX_BYTES

    data = chain(tmp_path)
    (tmp_path / "K.mtx").write_text(header)
    data["structure"]["stiffness"] = "K.mtx"
    (message,) = problems(data, tmp_path)
    assert "structure.stiffness: the file declares a matrix of" in message
    assert f"MAX_MATRIX_BYTES = {MAX_MATRIX_BYTES / 2 ** 30:g} GiB" in message and "load_matrix" in message


def test_a_truncated_npy_is_named_before_it_is_read(tmp_path):
    data = chain(tmp_path)
    with open(tmp_path / "K.npy", "wb") as fh:
        np.lib.format.write_array_header_1_0(fh, {"descr": "<f8", "fortran_order": False, "shape": (3000, 3000)})
        fh.write(b"\0" * 16)
    (message,) = problems(data, tmp_path)
    assert "structure.stiffness must name a complete .npy file" in message and "truncated" in message


@pytest.mark.parametrize("text", ["v = " + "[" * 5000 + "]" * 5000, "[" + ".".join(["a"] * 5000) + "]\nx = 1\n",
                                  "a = " + "[" * 20 + "]" * 20])
def test_deeply_nested_toml_is_a_scene_error_not_a_recursion_error(tmp_path, capsys, text):
    path = tmp_path / "deep.toml"
    path.write_text(text)
    with pytest.raises(SceneError, match="nest"):
        load_scene(path)
    assert main(["run", str(path), "--check"]) == 2
    assert "a scene nests at most 16 levels" in capsys.readouterr().err


# ----------------------------------------------------------------------------- values near the float limits
@pytest.mark.parametrize("make, names", [
    (lambda: __import__("contact_models").Iwan(1e-300, 1e300, -0.5, 0.1), "slip_force=1e-300, stiffness=1e+300"),
    (lambda: __import__("contact_models").Iwan(1e300, 1.0, -0.5, 0.1), "slip_force=1e+300, stiffness=1.0"),
    (lambda: __import__("contact_models").PointContact(k_s=1e-300, beta_p=1.0, k_p=1.0, slip_force=1.0),
     "k_s=1e-300, beta_p=1.0")])
def test_element_parameters_too_far_apart_for_double_precision_are_refused_naming_them(make, names):
    with pytest.raises(ValueError, match=re.escape(f"({names}") + ".*keep their ratios within about 1e150"):
        make()


def test_an_amplitude_whose_force_overflows_is_named_not_returned_as_nan():
    from contact_models import Bar, TwoRegionMicroslip, UniformLoad
    from contact_models.base import ElementOutputError

    # (1e300 m, whose K a^2 overflowed in the closed forms and gave NaN, now answers K_slip a = 1.8e307 N: the
    # expansions past gross slip; K_slip a itself overflows at 1e307 m)
    two = TwoRegionMicroslip(Bar(2e11, 7850.0, 1e-5, 0.05, 8e8, 4e7, 0.3), UniformLoad(100.0))
    for a in (1e307, np.array([1e-6, 1e307])):
        with warnings.catch_warnings():
            warnings.simplefilter("error", RuntimeWarning)  # the error names it; numpy's overflow warning stays inside
            with pytest.raises(ElementOutputError, match=r"^element=TwoRegionMicroslip\(.*returned f_s = inf \(not "
                                                         r"finite\) at a=1e\+307 m, omega=1000 rad/s"):
                two.fourier(a, 1e3)


# ----------------------------------------------------------------------------- bounds on the work a request starts
def test_numerical_bar_cells_are_bounded_with_the_bound_named():
    from contact_models import Bar, NumericalMicroslip, UniformLoad
    from contact_models.numerical import MAX_CELLS

    bar = Bar(2e11, 7850.0, 1e-5, 0.05, 8e8, 4e7, 0.3)
    with pytest.raises(ValueError, match=rf"^cells must be an integer in 2..{MAX_CELLS}, got cells=1000000000 "
                                         r"\(the bound is contact_models.numerical.MAX_CELLS"):
        NumericalMicroslip(bar, UniformLoad(100.0), cells=10**9)
    with pytest.raises(ValueError, match="got cells='3'"):
        NumericalMicroslip(bar, UniformLoad(100.0), cells="3")


def test_balance_harmonics_are_bounded_with_the_bound_named():
    import time

    from hbm.balance.residual import MAX_BALANCE_HARMONICS

    s = Structure(np.eye(1), [[0.004]], np.eye(1), force=[0.01])
    t0 = time.perf_counter()
    with pytest.raises(ValueError, match=rf"^harmonics must be an integer in 1..{MAX_BALANCE_HARMONICS}, got "
                                         r"harmonics=1000 \(the bound is hbm.balance.residual.MAX_BALANCE_HARMONICS"):
        frequency_response(s, [Contact(Macroslip(1.0, 0.02), dof=0)], omega_range=(0.6, 1.8), harmonics=1000)
    assert time.perf_counter() - t0 < 2.0


def test_nonlinear_modes_refuse_the_rtol_frequency_response_refuses():
    from hbm import nonlinear_modes

    s = Structure(np.eye(1), [[0.004]], np.eye(1), force=[0.01])
    for rtol in (1, 0.1):
        with pytest.raises(ValueError, match=rf"^rtol must be < 0.1, got rtol={rtol}"):
            nonlinear_modes(s, [Contact(Macroslip(1.0, 0.02), dof=0)], amplitudes=[0.01, 1.0], rtol=rtol)
        with pytest.raises(ValueError, match=rf"^rtol must be < 0.1, got rtol={rtol}"):
            frequency_response(s, [Contact(Macroslip(1.0, 0.02), dof=0)], omega_range=(0.6, 1.8), rtol=rtol)


def test_a_full_disk_leaves_no_tmp_file(tmp_path):
    import errno

    from hbm.scenes.running import replace_atomically

    (tmp_path / "frf.partial.csv").write_text("kept\n")

    def full(fh):
        fh.write("half")
        raise OSError(errno.ENOSPC, "No space left on device")

    with pytest.raises(OSError):
        replace_atomically(tmp_path / "frf.partial.csv", full)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["frf.partial.csv"]
    assert (tmp_path / "frf.partial.csv").read_text() == "kept\n"


def test_a_scene_on_a_full_disk_exits_1_and_leaves_no_tmp_file(tmp_path, capsys, monkeypatch):
    import errno

    import hbm.scenes.running as running

    class Full:
        def __init__(self, fh):
            pass

        def writerows(self, rows):
            raise OSError(errno.ENOSPC, "No space left on device")

    import csv
    import types

    # the partial table's last rewrite (its error column) meets the full disk
    monkeypatch.setattr(running, "csv", types.SimpleNamespace(reader=csv.reader, writer=Full))
    scene = os.path.join(os.path.dirname(__file__), "..", "examples", "scenes", "default_microslip_frf.toml")
    out = tmp_path / "out"
    assert main(["run", scene, "--quiet", "--out", str(out), "--set", "sweep.tolerance=1e-3",
                 "--set", "effects.phase_differences=\"off\""]) == 1
    err = capsys.readouterr().err
    assert "error: cannot write the outputs: [Errno 28] No space left on device" in err
    assert not [p for p in out.iterdir() if p.name.endswith(".tmp")]


def _nan_above(w_bad):
    """A Jenkins element written by a user that turns non-finite above ``w_bad`` (rad/s)."""
    from contact_models.base import ContactElement

    class Fragile(ContactElement):
        has_time_law = True

        def __init__(self):
            self.jen = Macroslip(1.0, 0.02)

        def __repr__(self):
            return f"Fragile(w_bad={w_bad})"

        def _fourier_derivatives(self, a, w, rtol):
            out = self.jen.fourier_derivatives_unchecked(a, w, rtol)
            return tuple(np.where(w > w_bad, np.nan, v) for v in out)

        def _periodic_force(self, x, w):
            f, J = self.jen.periodic_force(x, w)
            return (f * np.nan if w > w_bad else f), J

        def _stuck_stiffness(self, w):
            return 1.0

        def _slip_amplitude(self, w):
            return 0.02

        def _hysteresis(self, a, w, n):
            return self.jen.hysteresis(a, w, n=n)

    return Fragile()


@pytest.mark.parametrize("options", [{"harmonics": 1}, {"tol": 1e-3}])
def test_an_element_non_finite_mid_curve_ends_the_branch_keeping_the_points_before(options):
    s = Structure(np.eye(1), [[0.004]], np.eye(1), force=[0.01])
    frf = frequency_response(s, [Contact(_nan_above(1.0), dof=0)], omega_range=(0.6, 1.8), **options)
    assert not frf.success and len(frf) > 10
    assert frf.omega.max() <= 1.0 and np.all(np.isfinite(frf.amplitude))
    assert "element=Fragile(w_bad=1.0): Fragile._periodic_force(x, omega) returned f = nan (not finite)" in frf.message


def test_a_bar_whose_slip_forces_leave_double_precision_is_refused_when_built():
    from contact_models import Bar, TwoRegionMicroslip, UniformLoad

    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # the error names it; numpy's overflow warning stays inside
        with pytest.raises(ValueError, match=r"^bar, load: the slip amplitudes and forces leave double precision "
                                             r"\(a_min = 6e\+302 m"):
            TwoRegionMicroslip(Bar(2e11, 7850.0, 1e-5, 0.05, 1e-300, 4e7, 0.3), UniformLoad(100.0))


def test_a_non_finite_hysteresis_loop_is_named():
    from contact_models.base import ElementOutputError

    class Loop(type(_Law.make("plain", time_law=False))):
        def _hysteresis(self, a, w, n):
            return np.zeros(n), np.full(n, np.nan)

    with pytest.raises(ElementOutputError, match=r"_hysteresis\(a, omega, n\) returned f = nan \(not finite\)"):
        Loop().hysteresis(0.1)


# ------------------------------------------------------------------ a result's output, and Blade.from_modal
@pytest.fixture(scope="module")
def chain_frf():
    s = Structure(np.eye(2), 0.01 * np.eye(2), [[2.0, -1.0], [-1.0, 2.0]], force=[1.0, 0.0])
    return frequency_response(s, [Contact(Macroslip(1.0, 0.1), dof=0)], omega_range=(0.5, 2.0), harmonics=1)


def test_to_csv_names_a_path_that_is_no_path_and_a_case_that_is_no_string(chain_frf, tmp_path):
    # before: Python's "expected str, bytes or os.PathLike object", and case=3 written as "# case: 3"
    for bad in (None, 3):
        with pytest.raises(ValueError, match=rf"^path must be a file path \(a str or pathlib.Path\), got path={bad}$"):
            chain_frf.to_csv(bad)
    with pytest.raises(ValueError, match=r"^case must be a str \(what was solved, in words\) or None, got case=3$"):
        chain_frf.to_csv(tmp_path / "frf.csv", case=3)
    assert not (tmp_path / "frf.csv").exists()  # refused before the file is opened


def test_plot_flags_must_be_bools(chain_frf):
    import matplotlib
    matplotlib.use("Agg")
    for name in ("peak", "error_band"):  # before: "no" was taken as True
        with pytest.raises(ValueError, match=rf"^{name} must be True or False, got {name}='no'$"):
            chain_frf.plot(**{name: "no"})


def test_blade_from_modal_names_the_parameters_whose_product_overflows():
    from hbm import Blade

    # before: "stiffness must be finite, got stiffness=inf", a parameter from_modal does not take
    with pytest.raises(ValueError, match=r"^frequency, damping_ratio and mass must give a finite stiffness m w\^2 "
                                         r"and damping 2 zeta m w, got frequency=1e\+200, damping_ratio=0.01, "
                                         r"mass=1e\+200$"):
        Blade.from_modal(frequency=1e200, damping_ratio=0.01, mass=1e200, force=1.0)


# ------------------------------------------------------------------ bad input probed as a new user would
def test_balance_samples_are_bounded_with_the_bound_named():
    import time

    from contact_models import Iwan
    from hbm.balance.residual import MAX_BALANCE_SAMPLES

    # before: numpy's MemoryError allocating 7.45 GiB (or the machine swapping)
    s = Structure(np.eye(3), 0.004 * K, K, force=F)
    t0 = time.perf_counter()
    for call in (frequency_response, __import__("hbm").nonlinear_modes):
        with pytest.raises(ValueError, match=rf"^n_t must be an integer in 4..{MAX_BALANCE_SAMPLES}, got n_t=1000000000"
                                             r" \(the bound is hbm.balance.residual.MAX_BALANCE_SAMPLES"):
            if call is frequency_response:
                call(s, [Contact(Iwan(1.0, 0.02, -0.5, 0.1), dof=0)], (0.3, 0.8), harmonics=3, n_t=10**9)
            else:
                call(s, [Contact(Iwan(1.0, 0.02, -0.5, 0.1), dof=0)], amplitudes=[0.01, 1.0], harmonics=3, n_t=10**9)
    assert time.perf_counter() - t0 < 2.0


@pytest.mark.parametrize("effects, expected", [
    ({"harmonics": 1000}, "effects.harmonics = 1000: must be an integer in 1..256 (the bound is "
                          "hbm.balance.residual.MAX_BALANCE_HARMONICS"),
    ({"harmonics": 3, "samples": 7}, "effects.samples = 7: must be at least 2 H + 2 = 8"),
    ({"harmonics": 3, "samples": 10**9}, "effects.samples = 1000000000: must be an integer in 3..65536 (the bound is "
                                         "hbm.balance.residual.MAX_BALANCE_SAMPLES")])
def test_scene_harmonics_and_samples_the_balance_refuses_fail_the_check(tmp_path, effects, expected):
    # before: the check passed and the run failed with the balance's ValueError, 0 points kept
    data = chain(tmp_path)
    data["effects"] = effects
    with pytest.raises(SceneError) as info:
        plan_scene(scene_from_dict(data, tmp_path / "chain.toml"))
    assert any(expected in p for p in info.value.problems), info.value.problems


@pytest.mark.parametrize("name", ["M", "C", "K"])
@pytest.mark.parametrize("bad", [[["2", "-1"], ["-1", "2"]], np.eye(2, dtype=bool), None])
def test_matrices_of_strings_booleans_or_none_are_refused_by_name(name, bad):
    # before: strings read as numbers and booleans as 0/1 (a structure built), None "of shape ()"
    given = {"M": np.eye(2), "C": 0.01 * np.eye(2), "K": [[2.0, -1.0], [-1.0, 2.0]], name: bad}
    with pytest.raises(ValueError, match=rf"^{name} must be a square matrix of numbers, got {name}="):
        Structure(given["M"], given["C"], given["K"], force=[1.0, 0.0])


@pytest.mark.parametrize("bad", [[["-1", "0"], ["0", "0"]], np.eye(2, dtype=bool)])
def test_a_sector_coupling_of_strings_or_booleans_is_refused_by_name(bad):
    from hbm import CyclicStructure

    with pytest.raises(ValueError, match=r"^K_next must be a square matrix of numbers, got K_next="):
        CyclicStructure(np.eye(2), 0.01 * np.eye(2), [[3.0, -1.0], [-1.0, 1.0]], sectors=4, engine_order=1,
                        force=[1.0, 0.0], K_next=bad)


@pytest.mark.parametrize("bad", [["1", "0"], [True, False], None])
def test_a_force_of_strings_booleans_or_none_is_refused_by_name(bad):
    # before: ["1", "0"] and [True, False] built a structure; None was "a force of length 1"
    with pytest.raises(ValueError, match=r"^force must be a vector of 2 numbers, got force="):
        Structure(np.eye(2), 0.01 * np.eye(2), [[2.0, -1.0], [-1.0, 2.0]], force=bad)


@pytest.mark.parametrize("bad", ["a", [0.01, "x"], True, [[0.01], [0.01, 0.02]]])
def test_modal_damping_ratios_that_are_no_numbers_are_refused_by_name(bad):
    # before: numpy's "could not convert string to float: 'a'", and True taken as a ratio of 1
    with pytest.raises(ValueError, match=r"^ratios must be one number >= 0 or 2 of them, got ratios="):
        Structure.with_modal_damping(np.eye(2), [[2.0, -1.0], [-1.0, 2.0]], ratios=bad, force=[1.0, 0.0])


def test_a_centrifugal_load_out_of_double_precision_is_named_not_an_overflow_or_inf():
    from contact_models import CentrifugalLoad

    # before: Python's OverflowError (34, 'Numerical result out of range'), and inf from the product
    with pytest.raises(ValueError, match=r"^omega=1e\+200 is too large for this load: the preload mass radius "
                                         r"\(omega / engine_order\)\^2 is not finite in double precision$"):
        CentrifugalLoad(1.0, 1.0, 1)(1e200)
    with pytest.raises(ValueError, match=r"^mass and radius must give a finite mass \* radius, got mass=1e\+300, "
                                         r"radius=1e\+300$"):
        CentrifugalLoad(1e300, 1e300, 4)
    with pytest.raises(ValueError, match=r"^omega=1e\+300 is too large for this load: dN0/domega"):
        CentrifugalLoad(1e300, 1.0, 1).derivative(1e300)


@pytest.mark.parametrize("where", [{"dofs": (0, 5), "next_sector": True}, {"dof": 2}])
def test_the_whole_disk_refuses_a_sector_contact_on_a_dof_the_sector_has_not(where):
    from hbm import CyclicStructure

    # before: full() placed dofs=(0, 5) of a 2-DOF sector on DOFs of other sectors, silently
    disk = CyclicStructure(np.eye(2), 0.01 * np.eye(2), [[3.0, -1.0], [-1.0, 1.0]], sectors=6, engine_order=2,
                           force=[0.0, 1.0], K_next=[[-1.0, 0.0], [0.0, 0.0]])
    c = Contact(Macroslip(1.0, 0.1), **where)
    with pytest.raises(ValueError, match=rf"^dof must be a DOF index in 0..1, got dof={c.all_dofs[-1]} in "
                                         + re.escape(repr(c))):
        disk.full([c])


def test_to_csv_names_a_path_in_a_missing_folder_or_a_folder(chain_frf, tmp_path):
    # before: FileNotFoundError and IsADirectoryError from open()
    missing = tmp_path / "no" / "frf.csv"
    with pytest.raises(ValueError, match=rf"^path must be in an existing folder, got path={re.escape(repr(str(missing)))} "
                                         r"\(no folder .*; create it first\)$"):
        chain_frf.to_csv(missing)
    for folder in (tmp_path, ""):
        with pytest.raises(ValueError, match=rf"^path must be a file path, not a folder, got path="
                                             rf"{re.escape(repr(str(folder)))}$"):
            chain_frf.to_csv(folder)
    assert not (tmp_path / "no").exists()


def two_dof(damping=0.01):
    return Structure(np.eye(2), damping * np.eye(2), [[2.0, -1.0], [-1.0, 2.0]], force=[1.0, 0.0])


def test_a_predictor_below_omega_zero_is_a_failed_step_not_an_error():
    # before: "omega must be >= 0, got omega=-0.0026..." from inside the solve, every point lost
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        frf = frequency_response(two_dof(), [Contact(Macroslip(1.0, 0.1), dof=0)], (2.0, 0.0), harmonics=1)
    assert frf.success and frf.omega[0] == 2.0 and frf.omega[-1] == 0.0


@pytest.mark.parametrize("omega_range, turn", [((0.5, 1e140), None), ((1e140, 1e141), 1.00936e140)])
def test_a_range_too_wide_to_trace_keeps_its_points_and_says_the_branch_came_back(omega_range, turn):
    # before: (0.5, 1e300) raised "omega must be >= 0" from inside the solve; (1e150, 1e151) came back
    # to w0 after two points and said success=True.  Those two ranges are now refused by name, since their omega^2 M
    # leaves double precision (below); ranges within it still keep their points and say the branch came back
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        frf = frequency_response(two_dof(), [Contact(Macroslip(1.0, 0.1), dof=0)], omega_range, harmonics=1)
    assert not frf.success and len(frf) >= 3 and frf.omega[0] == omega_range[0]
    assert re.match(r"^the branch turned back and left the parameter range where it started: it turned at omega = "
                    r"\S+ rad/s and came back to w0 = " + re.escape(f"{omega_range[0]:.6g}") + r" rad/s before reaching "
                    r"w1 = " + re.escape(f"{omega_range[1]:.6g}"), frf.message)
    if turn is not None:
        assert f"it turned at omega = {turn:.6g} rad/s" in frf.message


@pytest.mark.parametrize("omega_range", [(0.5, 1e300), (1e150, 1e151)])
def test_a_range_whose_inertia_leaves_double_precision_is_refused_by_name(omega_range):
    with pytest.raises(ValueError, match=rf"^omega_range={re.escape(repr(omega_range))} reaches too high for the "
                                         r"structure: at harmonic 1 of omega="):
        frequency_response(two_dof(), [Contact(Macroslip(1.0, 0.1), dof=0)], omega_range, harmonics=1)


def test_an_undamped_structure_on_its_pole_gives_no_numpy_warning_and_no_nan():
    # before: numpy's divide-by-zero and invalid-value RuntimeWarnings from the compliance at 2 * 0.5 = 1 rad/s
    # (the second harmonic of the estimate on the first natural frequency), and NaN error estimates
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        frf = frequency_response(two_dof(0.0), [], (0.5, 2.0), harmonics=1)
    assert not [w for w in said if issubclass(w.category, RuntimeWarning)]
    assert len(frf) > 100 and not frf.success and not np.isnan(frf.error_estimate).any()
    assert frf.error_estimate[0] < 1e-6  # no contacts: no harmonic above the first is excited
    with pytest.raises(ValueError, match=r"^omega_range must not start on a natural frequency of the undamped "
                                         r"structure, got omega_range\[0\]=1\.0 \(omega=1\.0 puts harmonic 1 on"):
        frequency_response(two_dof(0.0), [], (1.0, 2.0), harmonics=1)


def test_a_zero_force_is_refused_with_a_response_dof_too(tmp_path):
    # before: with response_dof given the zero-force check was skipped: a zero response was solved, and a
    # scene passed --check and wrote a zero FRF (with matplotlib's "no positive values" warning)
    s = Structure(np.eye(3), 0.01 * np.eye(3), K, force=[0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"^force must not be all zero \(nothing excites the structure\), got "
                                         r"force=\[0\.0, 0\.0, 0\.0\]$"):
        frequency_response(s, [Contact(Macroslip(1.0, 0.02), dof=0)], (0.3, 0.8), response_dof=2, harmonics=1)
    data = chain(tmp_path, force=[0.0, 0.0, 0.0])
    assert problems(data, tmp_path) == [f"{tmp_path / 'chain.toml'}: structure.force: force must not be all zero "
                                        "(nothing excites the structure), got force=[0.0, 0.0, 0.0]"]


def test_an_invalid_damper_key_is_said_once_without_its_follow_on_problems(tmp_path):
    # before: damper.stiffness = -1.0 was reported, then eight "damper.E ... is missing" (and [damper.load])
    # lines as if macroslip had no stiffness and needed the bar
    data = chain(tmp_path)
    data["damper"]["stiffness"] = -1.0
    assert problems(data, tmp_path) == [f"{tmp_path / 'chain.toml'}: damper.stiffness = -1.0: must be a number > 0 "
                                        "(N/m)"]
    # and so in a contact of the structure: no "as given it needs the bar and load of [damper]"
    data = chain(tmp_path)
    data["structure"]["contacts"] = [{"model": "macroslip", "dofs": [1], "stiffness": -1.0, "slip_force": 0.01}]
    assert problems(data, tmp_path) == [f"{tmp_path / 'chain.toml'}: structure.contacts[0].stiffness = -1.0: must be "
                                        "a number > 0 (N/m)"]


def test_plot_refuses_a_keyword_that_is_no_line_property(chain_frf):
    import matplotlib
    import matplotlib.pyplot as plt
    matplotlib.use("Agg")
    # before: matplotlib's AttributeError "Line2D.set() got an unexpected keyword argument 'foo'"
    with pytest.raises(TypeError, match=r"^plot\(\) got an unexpected keyword argument 'foo': not a property of a "
                                        r"matplotlib line \(matplotlib.lines.Line2D\), got foo=1$"):
        chain_frf.plot(foo=1)
    ax = chain_frf.plot(ls=":", lw=2.0, color="k", alpha=0.5, marker="o")  # line properties and their aliases
    assert ax.lines[0].get_linestyle() == ":" and ax.lines[0].get_linewidth() == 2.0
    plt.close("all")


@pytest.mark.parametrize("bad, shape", [([[1.0], [0.0]], "(2, 1)"), (np.ones((1, 2)), "(1, 2)"), (1.0, "()")])
def test_a_force_that_is_not_one_dimensional_is_refused_naming_its_shape(bad, shape):
    # before: the column [[1.0], [0.0]] (and a (1, 2) row) was flattened silently
    with pytest.raises(ValueError, match=rf"^force must be a one-dimensional vector of 2 numbers, got force of shape "
                                         rf"{re.escape(shape)}: force="):
        Structure(np.eye(2), np.zeros((2, 2)), np.eye(2), force=bad)
    assert Structure(np.eye(1), np.zeros((1, 1)), np.eye(1), force=2.0).force.tolist() == [2.0]  # one DOF: a number


def test_a_cyclic_structure_bounds_its_sectors_at_the_module_constant():
    from hbm import CyclicStructure
    from hbm.cyclic import MAX_SECTORS

    # before: sectors=10**7 was taken (and the constructor went on to check ten million nodal diameters)
    with pytest.raises(ValueError, match=rf"^sectors must be an integer in 2\.\.{MAX_SECTORS}, got sectors=10000000 "
                                         r"\(the bound is hbm\.cyclic\.MAX_SECTORS: raise it to go further\)$"):
        CyclicStructure(np.eye(2), 0.01 * np.eye(2), [[3.0, -1.0], [-1.0, 1.0]], sectors=10**7, engine_order=2,
                        force=[0.0, 1.0])


def test_a_response_far_below_the_static_deflection_states_its_newton_error():
    # before: at omega = 1e5 the response (1.0e-10 m) was 41 % off with an estimate of 5e-9 and no warning: the
    # corrector stops at a residual measured against the static deflection (0.67 m here), far above the response
    from contact_models import Macroslip

    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        frf = frequency_response(two_dof(), [Contact(Macroslip(1.0, 0.1), dof=0)], (1e4, 1e5), harmonics=1)
    K = np.array([[3.0, -1.0], [-1.0, 2.0]])  # the slider stays stuck (|x| < 1e-7 m): its spring k = 1 at DOF 0
    true = np.array([abs(np.linalg.solve(K - w * w * np.eye(2) + 0.01j * w * np.eye(2), [1.0, 0.0])[0])
                     for w in frf.omega])
    error = np.abs(frf.amplitude / true - 1.0)
    assert error.max() > 0.1  # the case: a real error, not a rounding one
    assert np.all(frf.error_estimate >= 0.5 * error)  # never under-read by more than 2x
    assert any("estimated error" in str(w.message) and "> tol 0.001" in str(w.message) for w in said)
