"""The single-mode elements' range: the warning against the validity map it reads
(contact_models/data/validity_map.csv, examples/validity_map.py), against off-grid points it does
not read (docs/data/validity_check.csv), and the warning itself."""

import csv
import math
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

from contact_models import (Bar, ModelRangeWarning, QuadraticLoad, ThreeRegionMicroslip, TwoRegionMicroslip,
                            UniformLoad)
from contact_models.model_range import (MAP_FILE, TOLERANCE, early_snap, single_mode_error,
                                        single_mode_frequency_limit, validity_map)

ROOT = Path(__file__).resolve().parent.parent
CHECK = ROOT / "docs" / "data" / "validity_check.csv"
BAR = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
EA, L = BAR.EA, BAR.L
CLASSES = {"uniform": TwoRegionMicroslip, "concave12": ThreeRegionMicroslip}


def make_bar(lam_L, beta_L):
    return Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=L, k=(lam_L / L) ** 2 * EA, beta=beta_L * EA / L, mu=0.3)


def make_load(name):
    return UniformLoad(N=100.0) if name == "uniform" else QuadraticLoad.from_ratio(N=100.0, ratio=12.0)


def element(lam_L, beta_L, load):
    return CLASSES[load](make_bar(lam_L, beta_L), make_load(load))


def read(path):
    with open(path) as fh:
        rows = list(csv.DictReader(fh))
    for r in rows:
        for k in ("lamL", "betaL_EA", "w", "ratio", "e_s", "e_c", "de_s", "de_c"):
            r[k] = float(r[k])
        r["e"], r["de"] = max(r["e_s"], r["e_c"]), max(r["de_s"], r["de_c"])
    return rows


@pytest.fixture(scope="module")
def elements():
    """Elements by (lambda L, beta L/EA, load), None where the element refuses the bar when built."""
    cache = {}

    def get(lam_L, beta_L, load):
        key = (lam_L, beta_L, load)
        if key not in cache:
            try:
                cache[key] = element(*key)
            except ValueError:
                cache[key] = None
        return cache[key]

    return get


def decided(r):
    """A point whose error is farther from the tolerance than the reference's own error."""
    return math.isfinite(r["e"]) and abs(r["e"] - TOLERANCE) > r["de"]


def test_the_map_is_a_full_grid_with_a_reference_finer_than_the_tolerance():
    rows = read(MAP_FILE)
    assert len(rows) == 4 * 3 * 2 * 14 * 10
    assert set(validity_map()) == {"uniform", "concave12"}
    finite = [r for r in rows if math.isfinite(r["e"])]
    assert len(finite) > 2000
    # a 1 % warning needs a reference better than 1 %: the reference's own error is below the
    # tolerance at 95 % of the points, and leaves at most 5 % of them undecided (the error
    # within it of the tolerance: mostly points whose error is close to 1 %)
    assert np.mean([r["de"] < TOLERANCE for r in finite]) > 0.95
    assert sum(not decided(r) for r in finite) < 0.05 * len(finite)


def test_warning_decision_is_the_map_at_every_map_point(elements):
    """Where the map says the error exceeds 1 % (a slipping point, decided), ``single_mode_error``
    does too, and nowhere else; where the bar is stuck the map itself shows the single-mode
    element exact (the all-mode reference agrees with its stuck stiffness)."""
    checked = flagged = stuck = 0
    for r in read(MAP_FILE):
        el = elements(r["lamL"], r["betaL_EA"], r["load"])
        if el is None or not math.isfinite(r["e"]):
            continue  # the single-mode element refuses the bar or the point: nothing to warn about
        omega = r["w"] * el.bar.omega_c
        a = r["ratio"] * el.slip_amplitude(0.0)
        e = float(single_mode_error(el, a, omega))
        if a <= el.linear_amplitude(omega):
            stuck += 1
            assert e == 0.0 and r["e"] < 0.1 * TOLERANCE, r
            continue
        if not decided(r):
            continue
        checked += 1
        flagged += r["e"] > TOLERANCE
        assert (e > TOLERANCE) == (r["e"] > TOLERANCE), r
        assert e == pytest.approx(r["e"], rel=1e-9)
    assert checked > 1200 and flagged > 600 and stuck > 300


@pytest.mark.parametrize("load", ["uniform", "concave12"])
def test_fourier_warns_where_the_map_says_and_not_elsewhere(load):
    """The same through the public ``fourier``, for the reference bar: the warning fires at every
    map point with more than 1 % error and at no other."""
    el = element(1.0, 1.0, load)
    fired = quiet = 0
    for r in read(MAP_FILE):
        if (r["lamL"], r["betaL_EA"], r["load"]) != (1.0, 1.0, load) or not decided(r):
            continue
        omega = r["w"] * el.bar.omega_c
        a = r["ratio"] * el.slip_amplitude(0.0)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", ModelRangeWarning)
            el.fourier(a, omega)
        warned = any("outside its single-mode range" in str(w.message) for w in caught)
        expected = r["e"] > TOLERANCE and a > el.linear_amplitude(omega)
        assert warned == expected, r
        fired += warned
        quiet += not warned
    assert fired > 40 and quiet > 40


def test_off_grid_points_the_map_does_not_hold():
    """240 random bars, loads, frequencies and amplitudes off the map's grid (stored with their
    all-mode errors, not read by the warning), scored by the script's ``score``: the interpolated
    map misses no point with more than 3 % error and raises no warning where the error is below
    1/3 %; between those it may err (a factor 3 is what the map's grid, a decade apart in lambda L
    and beta L/EA, resolves)."""
    scored, _, _, _, miss, false = example().score(CHECK)
    assert scored > 100
    assert miss == 0 and false == 0


def example():
    sys.path.insert(0, str(ROOT / "examples"))
    try:
        import validity_map
    finally:
        sys.path.remove(str(ROOT / "examples"))
    return validity_map


def test_the_stored_map_is_reproduced(tmp_path):
    """The script on a small grid of the reference bar (examples/validity_map.py ``compute``) gives the
    stored map's rows."""
    vm = example()
    rows, _ = vm.compute(tmp_path / "map.csv", bars=((1.0, 1.0),), ratios=(0.5, 2.0), frequencies=(0.01, 0.3),
                         loads=("uniform",))
    assert len(read(tmp_path / "map.csv")) == 4
    stored = {(r["w"], r["ratio"]): r for r in read(MAP_FILE)
              if (r["lamL"], r["betaL_EA"], r["load"]) == (1.0, 1.0, "uniform")}
    for r in read(tmp_path / "map.csv"):
        assert r["e"] == pytest.approx(stored[(r["w"], r["ratio"])]["e"], rel=1e-6, abs=1e-9)
        assert r["de"] == pytest.approx(stored[(r["w"], r["ratio"])]["de"], rel=1e-6, abs=1e-9)


def test_the_stored_check_points_are_reproduced():
    """Two rows of docs/data/validity_check.csv recomputed from scratch (the script's own code)."""
    vm = example()
    rows = [r for r in read(CHECK) if math.isfinite(r["e"]) and r["lamL"] < 2.0][:2]
    assert len(rows) == 2
    for r in rows:
        load, cls = vm.LOADS[r["load"]]
        bar = vm.make_bar(r["lamL"], r["betaL_EA"])
        single = vm.single_element(cls, bar, load)
        a = np.array([r["ratio"] * single.slip_amplitude(0.0)])
        es, ec, *_ = vm.errors(single, bar, load, a, r["w"] * bar.omega_c, vm.reference_cells(r["lamL"]))
        assert float(es[0]) == pytest.approx(r["e_s"], rel=1e-6, abs=1e-9)
        assert float(ec[0]) == pytest.approx(r["e_c"], rel=1e-6, abs=1e-9)


@pytest.mark.parametrize("load", ["uniform", "concave12"])
def test_frequency_limit_lies_where_the_map_first_exceeds_one_percent(load):
    """omega_1 of the reference bar lies between the last map frequency at which every amplitude is
    within 1 % and the first at which one is not (read from the CSV here)."""
    rows = [r for r in read(MAP_FILE) if (r["lamL"], r["betaL_EA"], r["load"]) == (1.0, 1.0, load)]
    el = element(1.0, 1.0, load)
    ws = sorted({r["w"] for r in rows})
    worst = {w: max(r["e"] for r in rows if r["w"] == w) for w in ws}
    first_over = min(w for w in ws if worst[w] > TOLERANCE)
    last_within = max(w for w in ws if w < first_over)
    w1 = single_mode_frequency_limit(el) / el.bar.omega_c
    assert last_within < w1 <= first_over


def test_warning_fires_out_of_range_and_not_inside():
    two = TwoRegionMicroslip(BAR, UniformLoad(N=100.0))
    a = 3 * 7.5e-7
    with pytest.warns(ModelRangeWarning, match=r"outside its single-mode range: F_s, F_c are off by about"):
        two.fourier(a, 0.3 * BAR.omega_c)
    with pytest.warns(ModelRangeWarning, match=r"and a = 2\.25e-06 m \(3 a_min\)"):
        two.fourier_derivatives(np.array([0.5, 3.0]) * 7.5e-7, 0.3 * BAR.omega_c)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ModelRangeWarning)
        two.fourier(a, 0.0)  # quasi-static: exact
        two.fourier(a, 0.05 * BAR.omega_c)  # the map: within 1 %
        two.fourier(0.5 * 7.5e-7, 0.3 * BAR.omega_c)  # stuck: exact
        two.fourier_derivatives_unchecked(np.array([a]), np.array([0.3 * BAR.omega_c]), 1e-6)  # the solver's path


def test_error_below_the_map_falls_like_omega_squared():
    """Below the map's lowest frequency (0.01 omega_c) the error is extrapolated as omega^2: exact at 0."""
    two = TwoRegionMicroslip(BAR, UniformLoad(N=100.0))
    a = 3 * 7.5e-7
    e1, e2 = (float(single_mode_error(two, a, f * BAR.omega_c)) for f in (0.005, 0.0025))
    assert e1 / e2 == pytest.approx(4.0, rel=1e-9)
    assert float(single_mode_error(two, a, 0.0)) == 0.0


def test_early_gross_slip_snap_warns():
    """lambda L = 3 at 0.3 omega_c: the loading curve folds with 0.07 L still stuck."""
    el = element(3.0, 1.0, "uniform")
    omega = 0.3 * el.bar.omega_c
    assert early_snap(el, omega) == pytest.approx(0.0708, abs=2e-3)
    with pytest.warns(ModelRangeWarning, match="snaps onto gross slip early, with 0.07 L still stuck"):
        el.fourier(30 * el.slip_amplitude(0.0), omega)
    assert early_snap(element(1.0, 1.0, "uniform"), omega) == 0.0
