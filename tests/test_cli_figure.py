"""The main job's figure (hbm.cli.figure): the curve alone, or a refined curve with the single-mode one
beside it and an inset of the peak; and the job's --tol, which sets where the peak is refined."""

import warnings

import numpy as np
import pytest

from hbm import frequency_response
from hbm.cli.cases import default_case
from hbm.cli.figure import DPI, SIZE, job_figure
from hbm.cli.main import _single_mode_curve, main


@pytest.fixture(scope="module")
def job():
    """The default case's single-mode curve and a refined one (``model="peak"`` at tol 1e-2: quick)."""
    case = default_case()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        given = frequency_response(case.blade, case.element, omega_range=case.omega_range, tol=1e-2)
        peak = frequency_response(case.blade, case.element, omega_range=case.omega_range, tol=1e-2, model="peak")
    assert len(set(np.asarray(peak.point_models).tolist())) > 1  # refined near the peak, as given elsewhere
    return case, given, peak


def _pixels(path):
    import matplotlib.image

    return matplotlib.image.imread(path)


def _grey(img):
    """Pixels of the single-mode curve's colour (0.45 grey), not the lighter grey of the linear reference."""
    rgb = img[..., :3]
    return int(np.sum((np.abs(rgb - 0.45) < 0.02).all(axis=-1)))


def test_the_figure_is_the_curve_and_beside_a_refined_one_the_single_mode_curve(job, tmp_path):
    case, given, peak = job
    alone = job_figure(given, case, tmp_path / "alone.png")
    beside = job_figure(peak, case, tmp_path / "beside.png", given=given)
    assert alone == tmp_path / "alone.png" and beside == tmp_path / "beside.png"
    a, b = _pixels(alone), _pixels(beside)
    size = (round(SIZE[1] * DPI), round(SIZE[0] * DPI), 4)
    assert a.shape == b.shape == size
    # the single-mode curve drawn in grey beside the refined one, on the whole curve and in the inset
    assert _grey(b) > _grey(a) + 150


def test_the_single_mode_curve_beside_a_refined_one_is_the_one_a_given_call_traces(job):
    # the job draws the refined call's first trace, not a second call: the same points and the same legend number
    case, given, peak = job
    beside = _single_mode_curve(peak, case, 1e-2)
    assert beside is not peak and set(np.asarray(beside.point_models).tolist()) == {"TwoRegionMicroslip"}
    assert np.array_equal(beside.omega, given.omega) and np.array_equal(beside.amplitude, given.amplitude)
    assert float(max(beside.error_estimate)) == float(max(given.error_estimate))


def test_a_figure_that_cannot_be_written_raises(job, tmp_path):
    case, given, _ = job
    with pytest.raises(FileNotFoundError):
        job_figure(given, case, tmp_path / "missing" / "frf.png")


def test_tol_sets_where_the_peak_job_refines_its_peak(tmp_path, capsys):
    # 5 %: the single-mode damper (1.9 % off the bar with every mode at the peak) is within its share of
    # it, nothing is refined
    assert main(["--model", "peak", "--tol", "0.05", "--out", str(tmp_path)]) == 0
    last = capsys.readouterr().out.strip().splitlines()[-1]
    assert "(model: TwoRegionMicroslip, within tol = 0.05" in last
    # 2e-3: the windows that hold the peak are traced again with the bar of every mode, to within it
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["default", "--model", "peak", "--tol", "2e-3", "--out", str(tmp_path)]) == 0
    last = capsys.readouterr().out.strip().splitlines()[-1]
    assert "(model: AllModeMicroslip(cells=" in last and "within tol = 0.002" in last
    stated = float(last.split("estimated error ")[1].split(" %")[0]) / 100.0
    assert 0.0 < stated <= 2e-3
    assert (tmp_path / "frf.png").stat().st_size > 10000


def test_tol_takes_the_names_of_frequency_response_tol(tmp_path, capsys):
    # --tol fast is frequency_response(tol="fast"): the tolerance 0.01, as the line says
    assert main(["--model", "given", "--tol", "fast", "--out", str(tmp_path)]) == 0
    last = capsys.readouterr().out.strip().splitlines()[-1]
    assert "(model: TwoRegionMicroslip, further than tol = 0.01;" in last
    with pytest.raises(SystemExit) as exc:  # a misspelt name: refused, listing the names and their numbers
        main(["--tol", "fats", "--out", str(tmp_path)])
    assert exc.value.code == 2 and ("or one of fast (0.01), default (0.001), precise (1e-05), got --tol fats"
                                    in capsys.readouterr().err)


def test_tol_is_checked_and_belongs_to_the_default_job(tmp_path, capsys):
    with pytest.raises(SystemExit) as exc:  # refused by the parser, naming the option and its range
        main(["--tol", "2", "--out", str(tmp_path)])
    assert exc.value.code == 2 and "argument --tol: must be a number in [1e-10, 1)" in capsys.readouterr().err
    with pytest.raises(SystemExit) as exc:
        main(["--tol", "1e-3", "models"])
    assert exc.value.code == 2 and "--tol does not apply to models" in capsys.readouterr().err
