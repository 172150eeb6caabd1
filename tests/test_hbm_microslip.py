"""The default case: blade + two-region microslip damper near 0.3 omega_c (the main job)."""

import numpy as np
import pytest

from hbm import frequency_response
from hbm.cli.main import main
from hbm.cli.cases import default_case
from hbm.balance.residual import linear_response
from hbm.output import csv_lines


@pytest.fixture(scope="module")
def run():
    case = default_case()
    frf = frequency_response(case.blade, case.element, omega_range=case.omega_range)
    return case, frf


def test_default_case_is_the_documented_blade_and_damper(run):
    case, frf = run
    bar = case.element.bar
    k_star = case.element.stuck_stiffness(0.0)
    w_stuck = np.sqrt((case.blade.stiffness + k_star) / case.blade.mass)
    assert w_stuck == pytest.approx(0.3 * bar.omega_c, rel=1e-12)
    assert case.omega_range[0] < w_stuck < case.omega_range[1]
    # at resonance the damper is in microslip: above a_min, below gross slip
    w_pk, a_pk = frf.peak()
    assert case.element.slip_amplitude(w_pk) < a_pk < case.element.gross_slip_amplitude(w_pk)
    assert 1.5 < a_pk / case.element.slip_amplitude(w_pk) < 2.5


def test_default_frf(run):
    case, frf = run
    assert frf.success, frf.message
    assert len(frf) >= 200
    assert frf.omega[0] == pytest.approx(case.omega_range[0], rel=1e-15)
    assert frf.omega[-1] == pytest.approx(case.omega_range[1], rel=1e-15)
    assert np.all(frf.residual_norm <= 1e-8)
    # below a_min the FRF is the blade with the stuck bar's dynamic stiffness, in closed form
    el = case.element
    stuck = frf.amplitude < el.slip_amplitude(0.0)
    assert 50 < np.count_nonzero(stuck) < len(frf) - 50
    K = lambda w: np.array([el.stuck_stiffness(x) for x in np.atleast_1d(w)])  # noqa: E731
    ref = linear_response(case.blade, frf.omega[stuck], K)
    z = frf.x_c[stuck] - 1j * frf.x_s[stuck]
    assert np.max(np.abs(z / ref - 1)) <= 1e-8
    # the damper limits the peak far below the stuck-damper resonance
    assert frf.peak().amplitude < 0.2 * np.max(np.abs(linear_response(case.blade, frf.omega, K)))


def test_default_peak_converged(run):
    """The default rtol's peak against a run at rtol = 1e-9: 1e-6 relative (measured: 1e-12)."""
    case, frf = run
    ref = frequency_response(case.blade, case.element, omega_range=case.omega_range, rtol=1e-9).peak()
    w_pk, a_pk = frf.peak()
    assert a_pk == pytest.approx(ref.amplitude, rel=1e-6)
    assert w_pk == pytest.approx(ref.omega, rel=1e-6)


def test_main_writes_csv_and_png(tmp_path, capsys):
    assert main(["--model", "given", "--out", str(tmp_path)]) == 0  # the files, not the model (test_physical_curve)
    out = capsys.readouterr().out
    assert (tmp_path / "frf.csv").stat().st_size > 10000
    assert (tmp_path / "frf.png").stat().st_size > 10000
    assert "peak: omega =" in out and str(tmp_path / "frf.csv") in out and str(tmp_path / "frf.png") in out
    rows = list(csv_lines((tmp_path / "frf.csv").read_text().splitlines()))
    assert len(rows) >= 201


def test_main_rejects_unknown_command(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["frobnicate"])
    assert exc.value.code == 2
