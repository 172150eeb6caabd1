"""The hbm example scripts: each ``main(small=True)`` runs, writes its PNG and returns numbers
checked here against independent values."""

import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
if str(EXAMPLES) not in sys.path:
    sys.path.insert(0, str(EXAMPLES))

#: Default-case peak (python -m hbm, rtol 1e-6; converged to 1e-12 against rtol 1e-9).
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
