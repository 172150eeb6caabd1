"""The main job with ``--model peak``: the peak of the curve whose windows that hold it are traced again
with the bar of every mode, on the job's last line, against the converged reference."""

import csv
import json
import warnings
from pathlib import Path

import pytest

from contact_models import AccuracyWarning
from hbm.cli.main import main

#: The peak of the default case's periodic response with the bar of every mode
#: (``benchmarks/physical_peak_reference.py``: plain Newton at frequencies 5 rad/s apart up a ladder of cells
#: and harmonics to 256 cells, 127 bar harmonics, 47 blade harmonics, the vertex through the largest three).
REFERENCE = json.loads((Path(__file__).resolve().parent / "data" / "physical_peak_reference.json").read_text())
REFERENCE_PEAK = REFERENCE["amplitude"]


def _number(text, before, after=" "):
    return float(text.split(before)[1].split(after)[0])


def test_the_reference_peak_is_converged_and_interior_to_its_samples():
    omegas = [p["omega"] for p in REFERENCE["samples"]]
    assert REFERENCE["spread"] < 1e-4 and min(omegas) < REFERENCE["omega"] < max(omegas)
    assert REFERENCE_PEAK >= max(p["ladder"][-1] for p in REFERENCE["samples"])


def test_the_peak_job_says_the_refined_peak_on_its_last_line(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert main(["--model", "peak"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    last = lines[-1]
    # the last line: the peak, its estimate and the model that answered there (the bar of every mode)
    assert last.startswith("peak 387") and "(model: AllModeMicroslip(cells=" in last and "within tol = 0.001" in last
    stated = _number(last, "estimated error ") / 100.0
    assert 0.0 < stated <= 1e-3
    peak = next(t for t in lines if t.startswith("peak: omega = "))
    amplitude, omega = _number(peak, "amplitude = "), _number(peak, "omega = ")
    true = abs(amplitude - REFERENCE_PEAK) / REFERENCE_PEAK
    assert true <= 1e-3 and true <= 2.0 * stated + REFERENCE["spread"]  # within tol, the estimate honest to 2x
    assert omega == pytest.approx(REFERENCE["omega"], abs=10.0)  # within two of the reference's spacings
    # the model named is the CSV's at the point nearest the peak
    with open(tmp_path / "frf.csv") as fh:
        rows = list(csv.DictReader(line for line in fh if not line.startswith("#")))
    key = next(k for k in rows[0] if k.startswith("amplitude"))
    near = min(rows, key=lambda r: abs(float(r["omega_rad_s"]) / omega - 1.0) + abs(float(r[key]) / amplitude - 1.0))
    assert f"(model: {near['model']}, " in last
    assert sum(issubclass(w.category, AccuracyWarning) for w in caught) <= 1
    assert (tmp_path / "frf.png").stat().st_size > 10000
    assert main(["--model", "given"]) == 0
    last = capsys.readouterr().out.strip().splitlines()[-1]
    # the single-mode peak, 1.512e-6 m, is 1.9 % below the converged 1.540e-6 m: its estimate must not
    # under-read that by a factor 2, and the model source's over-read stays moderate
    given = _number(last, "estimated error ") / 100.0
    assert "TwoRegionMicroslip" in last and 0.015 <= given <= 0.03
