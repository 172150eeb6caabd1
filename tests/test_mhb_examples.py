"""The multi-harmonic examples: each ``main(small=True)`` runs, writes its figures and returns
numbers checked here against independent values."""

import sys
from pathlib import Path

import numpy as np
import pytest

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
if str(EXAMPLES) not in sys.path:
    sys.path.insert(0, str(EXAMPLES))


def test_chain_3dof(tmp_path):
    out = __import__("chain_3dof").main(outdir=tmp_path, small=True)
    for key in ("path", "harmonics_path"):
        assert Path(out[key]).stat().st_size > 10_000
    # stuck at the start of the sweep: the chain with both contacts as springs (closed form)
    assert out["first_point"] == pytest.approx(out["stuck_closed_form"], rel=1e-9)
    assert out["all_stable"]


def test_blade_200dof_small(tmp_path):
    out = __import__("blade_200dof").main(outdir=tmp_path, small=True, reduced_dofs=10)
    assert Path(out["path"]).stat().st_size > 10_000
    # 8 Hermite elements: the first natural frequency within 1e-5 of Euler-Bernoulli's
    assert out["first_frequency"] == pytest.approx(out["euler_bernoulli"], rel=1e-5)
    # Craig-Bampton to 10 of 16 DOFs: the same curve to 1e-5, the same peak to 1e-7
    assert out["max_curve_difference"] < 1e-5 and out["peak_difference"] < 1e-7
    assert out["stable"]
    assert np.isfinite(out["seconds_reduced"])
