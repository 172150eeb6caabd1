"""The default job's all-mode peak (hbm.allmode_peak): the amplitude equation, the parabola, the peak and
its error estimate against a converged reference, and the job's last line."""

import warnings

import numpy as np
import pytest

from contact_models import AccuracyWarning
from hbm import frequency_response
from hbm.cli.cases import default_case
from hbm.cli.main import main
from hbm.allmode_peak import _vertex, allmode_peak, amplitude_at

#: The default case's all-mode peak on finer rungs (the same peak search; 38820 rad/s).  Cells at
#: H = 31, lumped masses: 128, 256, 512 cells give 1.5354640e-6, 1.5353988e-6, 1.5353834e-6 m (observed
#: order 2.1; the limit CELLS_LIMIT, 5e-12 m from 512 cells); the exact segments (the default) approach it
#: from below, irregularly: 1.5352841e-6, 1.5353577e-6, 1.5353707e-6, 1.5353751e-6 m on 64 to 512 cells.
#: Harmonics on 128 cells: H = 31, 47, 63 give 1.5354640e-6, 1.5352972e-6, 1.5352775e-6 m (at H >= 47 a
#: sample point near a narrow superharmonic feature: the local maximum is at least that).  The limit of both, REFERENCE_AMPLITUDE, is known to about 3e-5.
CELLS_LIMIT = 1.535378e-6
HARMONICS_CHANGE = (1.5354640e-6 - 1.5352775e-6) / 1.5354640e-6  # H = 31 -> 63 on 128 cells
REFERENCE_AMPLITUDE = 1.535378e-6 - (1.5354640e-6 - 1.5352775e-6)
REFERENCE_DOUBT = 3e-5
REFERENCE_OMEGA = 38821.7


class SingleMode:
    """The single-mode element behind the solve() the amplitude equation asks of a bar."""

    def __init__(self, element):
        self.element = element

    def solve(self, a, omega):
        fs, fc, dfs, dfc = (float(v) for v in self.element.fourier_derivatives(a, omega))
        dF = np.zeros((3, 3))
        dF[2, 2], dF[1, 2] = dfs, dfc
        return type("Sol", (), {"success": True, "f_s": fs, "f_c": fc, "dF_dX": dF})()


@pytest.fixture(scope="module")
def case():
    return default_case()


def test_amplitude_equation_gives_the_continuation_s_points(case):
    """The scalar amplitude equation with the single-mode damper lands on the points the continuation
    of the H = 1 balance found (an independent solver), from 3 % away."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        frf = frequency_response(case.blade, case.element, omega_range=case.omega_range)
        el = SingleMode(case.element)
        for i in (int(np.argmax(frf.amplitude)), 60, 150):
            a = amplitude_at(case.blade, el, float(frf.omega[i]), 1.03 * float(frf.amplitude[i]))
            assert a == pytest.approx(float(frf.amplitude[i]), rel=1e-8)


def test_vertex_of_three_points_on_a_parabola_is_exact():
    w = (10.0, 12.0, 14.0)
    A = tuple(3.0 - 0.5 * (x - 12.7) ** 2 for x in w)
    wv, av = _vertex(w, A)
    assert wv == pytest.approx(12.7, rel=1e-13) and av == pytest.approx(3.0, rel=1e-13)


def test_allmode_peak_and_its_estimate_against_the_converged_reference(case):
    el = case.element
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        frf = frequency_response(case.blade, el, omega_range=case.omega_range)
    pk = frf.peak()
    best = allmode_peak(case.blade, el.bar, el.load, pk.omega, pk.amplitude, 1e-3)
    true = abs(best.amplitude - REFERENCE_AMPLITUDE) / REFERENCE_AMPLITUDE
    assert best.error <= 1e-3
    assert true + REFERENCE_DOUBT <= best.error  # the estimate holds, the reference's own doubt included
    # each part holds against its own reference: cells at H = 31, harmonics 31 -> 63 on 128 cells
    a_31 = best.rungs[(best.cells, 31)][1]
    assert abs(a_31 - CELLS_LIMIT) / CELLS_LIMIT <= best.parts["cells"]
    assert HARMONICS_CHANGE <= best.parts["harmonics"]
    assert best.omega == pytest.approx(REFERENCE_OMEGA, abs=10.0)  # the peak is flat: 10 rad/s is 1e-5 in a
    # the single-mode peak is 1.5 % low: the all-mode answer is the physical one
    assert (REFERENCE_AMPLITUDE - pk.amplitude) / REFERENCE_AMPLITUDE == pytest.approx(0.0152, abs=5e-4)


def test_the_peak_job_says_the_allmode_peak_on_its_last_line(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert main(["--model", "peak"]) == 0
    last = capsys.readouterr().out.strip().splitlines()[-1]
    assert last.startswith("peak 388") and "AllModeMicroslip" in last and "estimated error 0.0" in last
    assert sum(issubclass(w.category, AccuracyWarning) for w in caught) <= 1
    # the stated error includes what the peak search does not resolve: the blade's own harmonics
    # (2.2e-4 at this peak, from the curve's estimate), so it cannot be below them, and it is within tol
    stated = float(last.split("estimated error ")[1].split(" %")[0]) / 100.0
    blade_harmonics = float(last.split("; ")[1].split(" %")[0]) / 100.0
    assert 2.0e-4 <= blade_harmonics < stated <= 1e-3
    assert (tmp_path / "frf.csv").exists() and (tmp_path / "frf.png").exists()
    assert main(["--model", "given"]) == 0
    last = capsys.readouterr().out.strip().splitlines()[-1]
    # the single-mode peak is 1.5 % below the all-mode one (1.512e-6 against 1.535e-6 m): the estimate
    # must not under-read that by a factor 2, and the model source's over-read stays moderate
    given = float(last.split("estimated error ")[1].split(" %")[0]) / 100.0
    assert "TwoRegionMicroslip" in last and 0.015 <= given <= 0.03


@pytest.mark.parametrize("kw", [dict(w_single=0.0), dict(a_single=-1e-6), dict(tol=1.5), dict(w_single=float("nan")),
                                dict(other=-1e-4)])
def test_allmode_peak_refuses_bad_input_naming_it(case, kw):
    args = dict(w_single=38768.0, a_single=1.5e-6, tol=1e-3) | kw
    with pytest.raises(ValueError, match=next(iter(kw))):
        allmode_peak(case.blade, case.element.bar, case.element.load, **args)


def test_at_a_tight_tolerance_the_peak_s_cells_part_reads_the_rung_above(case):
    """At tol = 5e-4 the search doubles to 256 cells; its cells part, |a_512 - a_256| plus the Richardson
    error of a_512, holds against the cells limit within that limit's own doubt (5e-12 m); read from 64, 128,
    256 cells it gave 1.8e-6 against a true 4.8e-6 (docs/validation.md)."""
    el = case.element
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        frf = frequency_response(case.blade, el, omega_range=case.omega_range)
    pk = frf.peak()
    best = allmode_peak(case.blade, el.bar, el.load, pk.omega, pk.amplitude, 5e-4, other=2.2e-4)
    assert best.cells == 256 and (512, 31) in best.rungs
    a_31 = best.rungs[(256, 31)][1]
    assert abs(a_31 - CELLS_LIMIT) / CELLS_LIMIT <= best.parts["cells"] + 5e-12 / CELLS_LIMIT
