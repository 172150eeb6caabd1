"""The hbm example scripts: each ``main(small=True)`` runs, writes its PNG and returns numbers
checked here against independent values."""

import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
if str(EXAMPLES) not in sys.path:
    sys.path.insert(0, str(EXAMPLES))

#: Default-case peak (python3 -m hbm, rtol 1e-6; converged to 1e-12 against rtol 1e-9).
DEFAULT_PEAK = 1.5119614110e-06


def run(name, tmp_path):
    out = __import__(name).main(outdir=tmp_path, small=True)
    png = Path(out["path"])
    assert png.parent == Path(tmp_path) and png.stat().st_size > 10_000
    return out


def test_frf_microslip_vs_point_contact(tmp_path):
    out = run("frf_microslip_vs_point_contact", tmp_path)
    micro, point = out["peaks"][100.0]
    assert micro == pytest.approx(DEFAULT_PEAK, rel=1e-6)  # the default case, on a coarser step
    # the fitted point contact stays stuck up to gross slip: it dissipates less, peaks higher
    for m, p in out["peaks"].values():
        assert m < p


def test_design_chart(tmp_path):
    out = run("design_chart", tmp_path)
    loads = list(out["loads"])
    peaks = out["peaks"]
    assert peaks["microslip"][loads.index(100.0)] == pytest.approx(DEFAULT_PEAK, rel=1e-6)
    # heavy load: microslip predicts about half the point contact's amplitude (paper: ~50 %)
    N, ratio = out["heavy_load_ratio"]
    assert N == 1000.0 and 0.4 < ratio < 0.6
    # every curve lies below the stuck-damper resonance (to 1e-3: the fitted point contact's
    # stiffness is the bar's at one frequency, the microslip bar's varies with omega)
    for v in peaks.values():
        assert max(v) <= out["stuck_peak"] * (1 + 1e-3)


def test_continuation_duffing(tmp_path):
    out = run("continuation_duffing", tmp_path)
    assert out["result"].success
    assert out["relation_error"] < 1e-10
    assert len(out["folds"]) == 2
    for fw, fa, rw, ra in out["folds"]:
        assert fw == pytest.approx(rw, rel=1e-8) and fa == pytest.approx(ra, rel=1e-8)


def test_design_chart_study(tmp_path):
    """The study version of the design chart gives the scene's numbers (tests/test_scenes_examples.py)."""
    out = run("design_chart_study", tmp_path)
    loads = list(out["loads"])
    assert loads == [30.0, 100.0, 1000.0] and len(out["result"].records) == 9
    p = out["peaks"]
    assert p["two-region"][1] == pytest.approx(DEFAULT_PEAK, rel=1e-6)
    assert p["two-region"][2] / p["point-contact"][2] == pytest.approx(0.5057, abs=1e-3)
    assert p["macroslip"][1] < p["two-region"][1]
    # the optimum of each model lies inside the grid and below every grid point
    for m, (N, a) in out["optimum"].items():
        assert 30.0 <= N <= 1000.0 and a <= min(p[m]) * (1 + 1e-12)


def test_monte_carlo(tmp_path):
    """A sample's peak equals the FRF computed directly with the public API, and the percentiles
    are numpy's of the table's column."""
    import math

    import numpy as np

    from contact_models import Bar, QuasiStatic, TwoRegionMicroslip, UniformLoad
    from hbm import Blade, Steps, frequency_response

    out = run("monte_carlo", tmp_path)
    result = out["result"]
    assert result.success and len(result.records) == 12
    peaks = result.column("peak_amplitude_m")
    assert out["percentiles"][50.0] == pytest.approx(float(np.median(peaks)), rel=1e-15)
    rec = result.records[3]
    mu, N = rec["params"]["damper.mu"], rec["params"]["damper.load.N"]
    assert 0.2 <= mu < 0.4 and N > 0
    bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=mu)
    m, k = 0.08771473371579717, 1.0e8
    blade = Blade(mass=m, stiffness=k, damping=2.0 * 2.0e-3 * math.sqrt(k * m), force=8.0)
    frf = frequency_response(blade, QuasiStatic(TwoRegionMicroslip(bar, UniformLoad(N=N))),
                             omega_range=(0.24 * bar.omega_c, 0.33 * bar.omega_c), tol="fast",
                             steps=Steps(max_step=0.095))
    assert rec["peak_amplitude_m"] == pytest.approx(frf.peak().amplitude, rel=1e-12)
