"""The paper-figure scripts in ``examples/``: each ``main(small=True)`` runs, writes its PNG and
returns numbers that are checked against closed forms and the paper's statements."""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
if str(EXAMPLES) not in sys.path:
    sys.path.insert(0, str(EXAMPLES))

import paper_figures  # noqa: E402

RATIOS = paper_figures.FREQUENCY_RATIOS


@pytest.fixture(scope="module")
def s():
    return paper_figures.setup()


def run(name, tmp_path):
    module = __import__(name)
    out = module.main(outdir=tmp_path, small=True)
    png = Path(out["path"])
    assert png.parent == Path(tmp_path) and png.stat().st_size > 10_000
    return out


def strictly_increasing(d):
    v = [d[r] for r in RATIOS]
    return all(b > a for a, b in zip(v, v[1:]))


def test_every_paper_figure_has_a_script():
    mine = {"fig02", "fig03", "fig06", "fig07", "fig08", "fig09", "fig10", "fig11", "fig12", "fig13",
            "fig14", "fig15"}
    assert mine <= {m[:5] for m in paper_figures.FIGURE_MODULES}


def test_fig02_contact_force_is_the_stuck_shape(tmp_path, s):
    out = run("fig02_contact_force", tmp_path)
    bar = s.bar
    for r, value in out["force_ratio_x0"].items():
        # u(0)/u(L) = 1/(cosh gL + beta sinh(gL)/(EA g)), g = gamma (Eq. 12), complex when imaginary
        g = np.sqrt(complex(bar.gamma2(r * s.omega_c)))
        exact = 1.0 / (np.cosh(g * bar.L) + bar.beta * np.sinh(g * bar.L) / (bar.EA * g))
        assert value == pytest.approx(exact.real, rel=1e-12)
    assert out["force_ratio_x0"][0.01] == pytest.approx(math.exp(-1.0), rel=1e-3)  # lambda L = 1, beta = EA lambda
    v = list(out["force_ratio_x0"].values())
    assert all(b > a for a, b in zip(v, v[1:])) and v[-1] < out["mode_shape_x0"] < 1.0


def test_fig03_slip_onset_points(tmp_path):
    onset = run("fig03_load_buildup", tmp_path)["onset"]
    assert onset["uniform"] == pytest.approx((1.0, 1.0), rel=1e-12)  # a_min = mu N/(k L) at x = L
    assert onset["convex (ratio 0.5)"] == pytest.approx((1.0, 0.6), rel=1e-12)  # q(L) = 3N/(5L)
    x_star, a_on = onset["concave (ratio 12)"]
    assert x_star == pytest.approx(0.5114, abs=1e-4) and a_on == pytest.approx(0.3513, abs=1e-4)


def test_fig06_minimum_stuck_length_is_the_virgin_one(tmp_path):
    out = run("fig06_two_region_history", tmp_path)
    assert 0.0 < out["min_L1_over_L"] < 1.0
    assert out["min_L1_over_L"] == pytest.approx(out["virgin_L1_at_a_over_L"], abs=1e-12)
    assert out["gross_slip_over_a_min"] == pytest.approx(2.5, rel=1e-3)  # statics: 2.5 a_min


def test_fig07_right_stuck_region_vanishes_before_gross_slip(tmp_path):
    out = run("fig07_three_region_history", tmp_path)
    amplitude = __import__("fig07_three_region_history").AMPLITUDE
    assert out["max_L2_over_L"] == 1.0
    assert out["min_L1_over_L"] == pytest.approx(out["virgin_L1_at_a_over_L"], abs=1e-12)
    assert 0.0 < out["min_L1_over_L"] < out["x_star_over_L"]
    # L2 = L when k x = mu q(L): x/a_min = q(L) L/N = 3/(1 + 2/12)
    assert out["L2_reaches_L_at_a_over_a_min"] == pytest.approx(18.0 / 7.0, abs=0.06)
    assert out["L2_reaches_L_at_a_over_a_min"] < amplitude < out["gross_slip_over_a_min"]


@pytest.mark.parametrize("name", ["fig08_two_region_hysteresis", "fig11_three_region_hysteresis"])
def test_fig08_fig11_loops_open_and_rotate_with_frequency(tmp_path, name):
    out = run(name, tmp_path)
    for r in RATIOS:  # loop area = pi a f_c (81-point polygon)
        assert out["area_over_pi_a_fc"][r] == pytest.approx(1.0, abs=2e-3)
    assert strictly_increasing(out["F_c"])
    assert strictly_increasing({r: -v for r, v in out["F_s"].items()})


def test_fig09_stuck_value_and_frequency_trend(tmp_path, s):
    out = run("fig09_two_region_fs", tmp_path)
    for r in RATIOS:
        stuck = s.bar.stuck_stiffness(r * s.omega_c) / s.k_star
        assert out["F_s_at_1"][r] == pytest.approx(stuck, rel=1e-9)
    assert strictly_increasing({r: -v for r, v in out["F_s_at_1.5"].items()})
    assert out["F_s_at_100"][0.01] == pytest.approx(0.5, rel=5e-3)  # K_slip/k* of the sliding bar
    assert out["min_F_s"] > 0.0  # the paper's F_s < 0 at 0.5 omega_c does not occur for this bar


def test_fig10_damping_starts_at_a_min_and_grows_with_frequency(tmp_path):
    out = run("fig10_two_region_fc", tmp_path)
    assert out["max_F_c_below_a_min"] == 0.0
    assert strictly_increasing(out["F_c_at_1.5"]) and strictly_increasing(out["peak_F_c"])
    assert 0.97 < out["F_c_at_100_over_static_limit"] < 1.0


def test_fig12_three_region_softens_before_a_min(tmp_path, s):
    out = run("fig12_three_region_fs", tmp_path)
    assert out["a_min_three_over_a_min"] == pytest.approx(0.3513, abs=1e-4)
    for r in RATIOS:
        stuck = s.bar.stuck_stiffness(r * s.omega_c) / s.k_star
        assert out["F_s_at_0.2"][r] == pytest.approx(stuck, rel=1e-9)
        assert out["F_s_at_0.5"][r] < stuck
    assert strictly_increasing({r: -v for r, v in out["F_s_at_1.5"].items()})
    assert out["F_s_at_100"][0.01] == pytest.approx(0.5, rel=5e-3)


def test_fig13_three_region_damping(tmp_path):
    out = run("fig13_three_region_fc", tmp_path)
    assert all(v == 0.0 for v in out["F_c_at_0.2"].values())
    assert min(out["F_c_at_0.5"].values()) > 0.0
    assert strictly_increasing(out["F_c_at_0.5"]) and strictly_increasing(out["F_c_at_1.5"])
    assert 0.96 < out["F_c_at_100_over_static_limit"] < 1.0


def test_fig14_three_region_damps_first_two_region_peaks_higher(tmp_path):
    out = run("fig14_compare_fc", tmp_path)
    assert out["two_F_c_at_0.8"] == 0.0 and out["three_F_c_at_0.8"] > 0.0
    assert out["two_peak"] > out["three_peak"]
    assert out["three_F_c_at_100"] == pytest.approx(out["two_F_c_at_100"], rel=2e-2)


def test_fig15_stiffness_curves_cross_and_merge(tmp_path, s):
    out = run("fig15_compare_fs", tmp_path)
    assert out["two_F_s_at_0.8"] == pytest.approx(s.bar.stuck_stiffness(0.3 * s.omega_c) / s.k_star, rel=1e-9)
    assert out["three_F_s_at_0.8"] < out["two_F_s_at_0.8"]
    assert 1.5 < out["first_crossing_a_over_a_min"] < 10.0
    assert out["three_F_s_at_100"] == pytest.approx(out["two_F_s_at_100"], rel=1e-3)


def test_the_examples_default_case_is_the_command_lines():
    """``paper_figures.default_case`` (the public API) builds the blade, damper and sweep of
    ``python3 -m hbm`` to the last bit, and ``stuck_response`` is the blade's closed-form response."""
    from hbm.cli.cases import default_case

    mine, cli = paper_figures.default_case(), default_case()
    for name in ("mass", "stiffness", "damping", "force"):
        assert getattr(mine.blade, name) == getattr(cli.blade, name)
    assert mine.omega_range == cli.omega_range
    assert mine.element.stuck_stiffness(0.0) == cli.element.stuck_stiffness(0.0)
    assert mine.element.slip_amplitude(0.0) == cli.element.slip_amplitude(0.0)
    b, w, kd = mine.blade, 38000.0, 4.0e7
    x = paper_figures.stuck_response(b, w, kd)
    # x (k + kd - m w^2 + i c w) = F: the equation of motion of the blade with the spring
    assert x * (b.stiffness + kd - b.mass * w * w + 1j * b.damping * w) == pytest.approx(b.force, rel=1e-12)
    assert abs(x) == pytest.approx(b.force / math.hypot(b.stiffness + kd - b.mass * w * w, b.damping * w), rel=1e-12)
