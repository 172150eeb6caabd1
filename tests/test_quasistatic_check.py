"""The analytic elements at omega = 0 against an independent discretised bar.

``NumericalMicroslip(..., quasi_static=True)`` is a bar of n cells with one Jenkins element per
node, driven quasi-statically through full cycles with exact return mapping (no Masing rule,
no single-mode assumption; docs/validation.md).  The analytic loading curve enters f_s, f_c
and the loop only through the Masing construction, so matching the numerical loop pointwise
checks the loading curve too.
"""

import numpy as np
import pytest

from contact_models import QuadraticLoad, ThreeRegionMicroslip, TwoRegionMicroslip, UniformLoad
from contact_models.numerical import NumericalMicroslip

RATIOS = [1.5, 3.0, 10.0, 30.0]
CELLS = 400


@pytest.fixture(scope="module", params=["uniform", "concave12"])
def pair(request, bar):
    if request.param == "uniform":
        load = UniformLoad(100.0)
        el = TwoRegionMicroslip(bar, load)
    else:
        load = QuadraticLoad.from_ratio(100.0, 12.0)
        el = ThreeRegionMicroslip(bar, load)
    return el, NumericalMicroslip(bar, load, cells=CELLS, quasi_static=True)


def test_fourier_coefficients_agree_to_half_a_percent(pair):
    el, num = pair
    a = np.array(RATIOS) * el.slip_amplitude(0.0)  # 1.5, 3: microslip; 10: two regions; 30: gross slip
    fs_a, fc_a = el.fourier(a, 0.0, rtol=1e-9)
    fs_n, fc_n = num.fourier(a, 0.0)
    np.testing.assert_allclose(fs_n, fs_a, rtol=5e-3)
    np.testing.assert_allclose(fc_n, fc_a, rtol=5e-3)


@pytest.mark.parametrize("ratio", RATIOS)
def test_loops_agree_pointwise(pair, ratio):
    el, num = pair
    a = ratio * el.slip_amplitude(0.0)
    x_n, f_n = num.hysteresis(a, 0.0, n=401)
    x_a, f_a = el.hysteresis(a, 0.0, n=401)  # same theta grid: -pi/2 .. 3 pi/2
    np.testing.assert_allclose(x_n, x_a, rtol=0, atol=1e-12 * a)
    span = f_a.max() - f_a.min()
    assert np.max(np.abs(f_n - f_a)) < 5e-3 * span


def test_slip_onset_and_gross_slip_amplitudes(pair):
    """Below a_min the numerical bar dissipates nothing; past gross slip it dissipates like the analytic one."""
    el, num = pair
    am = el.slip_amplitude(0.0)
    fs, fc = num.fourier(0.95 * am, 0.0)
    assert fc == pytest.approx(0.0, abs=1e-9 * el.stuck_stiffness(0.0) * am)
    assert fs == pytest.approx(el.stuck_stiffness(0.0) * 0.95 * am, rel=5e-3)
