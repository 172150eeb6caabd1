"""The single-mode elements' range (issue 13): the closed-form criterion against the stored
validity map (docs/data/validity_map.csv, examples/validity_map.py), and the warning itself."""

import csv
import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from contact_models import (Bar, ModelRangeWarning, QuadraticLoad, ThreeRegionMicroslip, TwoRegionMicroslip,
                            UniformLoad)
from contact_models.model_range import (TOLERANCE, early_snap, single_mode_error_bound,
                                        single_mode_frequency_limit)

MAP = Path(__file__).resolve().parent.parent / "docs" / "data" / "validity_map.csv"
BAR = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
EA, L = BAR.EA, BAR.L


def make_bar(lam_L, beta_L):
    return Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=L, k=(lam_L / L) ** 2 * EA, beta=beta_L * EA / L, mu=0.3)


def element(lam_L, beta_L, load):
    bar = make_bar(lam_L, beta_L)
    if load == "uniform":
        return TwoRegionMicroslip(bar, UniformLoad(N=100.0))
    return ThreeRegionMicroslip(bar, QuadraticLoad.from_ratio(N=100.0, ratio=12.0))


def test_the_bound_flags_every_map_point_with_more_than_one_percent_error():
    """No miss: wherever the map's error exceeds 1 % (a > a_min(omega), the element not refusing the
    point nor snapping early, which warns separately), the bound exceeds 1 % too; where the bar is
    stuck the bound is 0.  At 0.01 omega_c the map measures the all-mode reference's own mesh error
    (the single-mode solution is exact at omega -> 0), so those points are left out."""
    with open(MAP) as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 1320
    els, checked, flagged = {}, 0, 0
    for r in rows:
        lam_L, beta_L, load, w, ratio = float(r["lamL"]), float(r["betaL_EA"]), r["load"], float(r["w"]), float(r["ratio"])
        e = max(float(r["e_s"]), float(r["e_c"]))
        if w < 0.1 or not math.isfinite(e):
            continue
        key = (lam_L, beta_L, load)
        if key not in els:
            els[key] = element(*key)
        el = els[key]
        omega = w * el.bar.omega_c
        a = ratio * el.slip_amplitude(0.0)
        try:
            bound = float(single_mode_error_bound(el, a, omega))
            snap = early_snap(el, omega) > 0.01 and a > el.gross_slip_amplitude(omega)
        except FloatingPointError:
            continue
        if a <= el.slip_amplitude(omega):
            assert bound == 0.0
            continue
        checked += 1
        if e > TOLERANCE and not snap:
            flagged += 1
            assert bound > TOLERANCE, (key, w, ratio, e)
    assert checked > 500 and flagged > 300


def test_frequency_limits_of_the_design_bar():
    two = element(1.0, 1.0, "uniform")
    three = element(1.0, 1.0, "concave12")
    # C = c (1 + (lambda L)^2)(1 + 0.2/(beta L/EA)) = 0.42 * 2 * 1.2 and 0.62 * 2 * 1.2
    assert single_mode_frequency_limit(two) / BAR.omega_c == pytest.approx(math.sqrt(0.01 / 1.008), rel=1e-9)
    assert single_mode_frequency_limit(three) / BAR.omega_c == pytest.approx(math.sqrt(0.01 / 1.488), rel=1e-9)


def test_warning_fires_out_of_range_and_not_inside():
    two = TwoRegionMicroslip(BAR, UniformLoad(N=100.0))
    a = 3 * 7.5e-7
    with pytest.warns(ModelRangeWarning, match="outside its single-mode range"):
        two.fourier(a, 0.3 * BAR.omega_c)
    with pytest.warns(ModelRangeWarning):
        two.fourier_derivatives(np.array([0.5, 3.0]) * 7.5e-7, 0.3 * BAR.omega_c)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ModelRangeWarning)
        two.fourier(a, 0.0)  # quasi-static: exact
        two.fourier(a, 0.05 * BAR.omega_c)  # below omega_1 = 0.0996 omega_c
        two.fourier(0.5 * 7.5e-7, 0.3 * BAR.omega_c)  # stuck: exact
        two.fourier_derivatives_unchecked(np.array([a]), np.array([0.3 * BAR.omega_c]), 1e-6)  # the solver's path


def test_early_gross_slip_snap_warns():
    """lambda L = 3 at 0.3 omega_c: the loading curve folds with 0.07 L still stuck."""
    el = element(3.0, 1.0, "uniform")
    omega = 0.3 * el.bar.omega_c
    assert early_snap(el, omega) == pytest.approx(0.0708, abs=2e-3)
    with pytest.warns(ModelRangeWarning, match="snaps onto gross slip early, with 0.07 L still stuck"):
        el.fourier(30 * el.slip_amplitude(0.0), omega)
    assert early_snap(element(1.0, 1.0, "uniform"), omega) == 0.0
