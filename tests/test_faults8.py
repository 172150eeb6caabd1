"""Faults at the edges of double precision and in the caller's own code: a value that leaves double precision
inside an element is named by the contract's checks (no numpy RuntimeWarning passes), and what was computed is
kept."""

import math
import re
import warnings

import numpy as np
import pytest

from contact_models import CubicSpring, Iwan, Macroslip
from contact_models.numerics.checks import ElementOutputError


@pytest.mark.parametrize("X", [[0.0, 0.0, 1e200], [0.0, 1e300, 0.0]])
def test_a_time_law_that_overflows_is_named_without_a_runtime_warning(X):
    """The cubic spring's k3 x**3 leaves double precision at 1e200 m: the harmonic force's output check names it, and
    numpy's "overflow encountered in power" (and "in dot" from the message's |X|) no longer leak."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        with pytest.raises(ElementOutputError, match=r"CubicSpring\._harmonic_force.* \(not finite\) at omega=1\.0, "
                                                     r"\|X\| = 1e\+(200|300) m"):
            CubicSpring(1e10).harmonic_force(X, 1.0, n_t=16)
        with pytest.raises(ElementOutputError, match=r"CubicSpring\._periodic_force.*not finite"):
            CubicSpring(1e10).periodic_force(np.array(X) * [1.0, 1.0, 1.0], 0.0)


def test_the_harmonic_force_of_a_huge_amplitude_masing_element_is_finite():
    """Past macroslip the Iwan element's harmonics are those of its slip force (its f_s was NaN at 1e200 m, and
    the message's |X| overflowed in numpy's dot)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        for el in (Iwan(10.0, 1e7, -0.5, 1.0), Macroslip(1e7, 10.0)):
            F, J, _ = el.harmonic_force([0.0, 0.0, 1e200], 1.0)
            assert F[1] == pytest.approx(4 * 10.0 / math.pi, rel=1e-12) and 0.0 <= F[2] < 1e-90
            assert np.all(np.isfinite(J))


def test_a_message_states_the_size_of_a_subnormal_x():
    """|X| in a message is scaled: 1e-320 m read "|X| = 0 m" (the square underflowed)."""
    from contact_models.numerics.checks import _norm

    assert _norm(np.array([0.0, 3e-320, 4e-320])) == pytest.approx(5e-320, rel=1e-3)
    assert _norm(np.array([3e300, 4e300])) == pytest.approx(5e300) and _norm(np.array([])) == 0.0


def test_an_a_min_decades_away_from_the_response_leaves_the_figure_drawable(tmp_path):
    """A normal load of 1e300 N puts a_min at 7.5e291 m beside a response of 1e-7 m: its line is left out, and the
    figure is written (matplotlib's logarithmic ticks overflowed: "cannot convert float infinity to integer", and
    the command line said "the computation failed" after the curve was computed)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from hbm import Blade
    from hbm.output import plot_linear_reference

    blade = Blade(mass=0.0877, stiffness=1e8, damping=11.8, force=8.0)
    for a_min, lines in ((7.5e291, 1), (1e-6, 2)):
        fig, ax = plt.subplots()
        ax.set_yscale("log")
        ax.plot([3.2e4, 4.4e4], [1e-7, 2e-7])
        plot_linear_reference(ax, blade, Macroslip(4e7, 30.0), (3.2e4, 4.4e4), a_min=a_min,
                              stiffness=lambda w: 4e7 + 0 * w)
        assert len(ax.get_lines()) == 1 + lines
        fig.savefig(tmp_path / "f.png")
        plt.close(fig)


@pytest.mark.parametrize("kind", ["TwoRegionMicroslip", "ThreeRegionMicroslip"])
def test_the_single_mode_bar_far_past_gross_slip_slides_not_nan(kind):
    """Far past gross slip f_s is K_slip a and f_c the sliding line's friction force 4 F_fric/pi: the Stieltjes
    integrals, of order K a^2, overflowed from about 1e150 m and f_s was NaN (a force of 1e300 N on the default
    blade failed at its start with "returned f_s = nan"); the float and the array paths agree, and the values run
    on continuously through FAR a_gross."""
    import contact_models
    from contact_models import Bar, ModelRangeWarning, UniformLoad
    from contact_models._path_integrals import FAR

    bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    el = getattr(contact_models, kind)(bar, UniformLoad(N=100.0))
    w = 3e4
    K_slip, a_g = el.slip_stiffness(w), el.gross_slip_amplitude(w)
    F_fric = float(el.loading_curve(np.array([2.0 * a_g]), w)[0]) - K_slip * 2.0 * a_g
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelRangeWarning)
        warnings.simplefilter("error", RuntimeWarning)
        for a in (1e155, 1e200, 1e292):
            fs, fc, dfs, dfc = el.fourier_derivatives(a, w)
            assert fs == pytest.approx(K_slip * a, rel=1e-14) and fc == pytest.approx(4 * F_fric / math.pi, rel=1e-9)
            assert dfs == pytest.approx(K_slip, rel=1e-14) and abs(dfc) < 1e-100
            arrays = el.fourier_derivatives(np.array([1e-6, a]), w)
            assert [float(v[1]) for v in arrays] == [fs, fc, dfs, dfc]
        below, above = (el.fourier_derivatives(FAR * a_g * f, w) for f in (1 - 1e-9, 1 + 1e-9))
        for u, v in zip(below[:3], above[:3]):
            assert v == pytest.approx(u, rel=1e-8)
        with pytest.raises(ElementOutputError, match=r"returned f_s = inf"):  # K_slip a itself leaves double precision
            el.fourier(1e307, w)


def test_the_blade_references_refuse_a_frequency_past_double_precision_by_name():
    """simulate_blade at 1e200 rad/s raised a bare ZeroDivisionError, and response_at blamed its amplitude_bracket
    ("does not bracket a solution ... inf N"): both now name omega, by the structures' check; simulate_blade also
    refuses, naming omega and the cells, a frequency whose wave the bar's cells cannot hold (UnresolvedWave)."""
    from contact_models import Bar, NumericalMicroslip, UniformLoad
    from contact_models.numerics.waves import UnresolvedWave
    from hbm import Blade, response_at, simulate_blade

    blade = Blade(mass=1.0, stiffness=1.0, damping=0.004, force=0.01)
    damper = NumericalMicroslip(Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3),
                                UniformLoad(N=100.0))
    for omega in (1e200, 1e300):
        with pytest.raises(ValueError, match=rf"^omega={re.escape(repr(omega))} reaches too high for the structure"):
            simulate_blade(blade, damper, omega)
        with pytest.raises(ValueError, match=rf"^omega={re.escape(repr(omega))} reaches too high for the structure"):
            response_at(blade, Macroslip(1.0, 0.02), omega, (1e-300, 10.0))
    with pytest.raises(UnresolvedWave, match=r"^cells=200 are too few for omega=100000000\.0 rad/s"):
        simulate_blade(blade, damper, 1e8)
    assert response_at(blade, Macroslip(1.0, 0.02), 1e140, (1e-300, 10.0)).amplitude == pytest.approx(1e-282)


@pytest.mark.parametrize("F", [1e160, 1e300])
def test_a_structure_forced_past_1e154_is_traced_as_the_scaled_problem(F):
    """The structure, forces and slip force scaled by F give the unit problem's curve times F: the first harmonic's
    sum of squares overflowed in the residual's scale (inf: the scaled residual was 0 at every point, and the
    2-DOF chain's curve was 36 points of a line, success True, peak/F 0.49 for 121.8) and, in the error estimate,
    leaked numpy's "overflow encountered in square" and gave the peak no estimate."""
    from hbm import Contact, Structure, frequency_response

    def solve(f, **kw):
        s = Structure(np.eye(2), 0.004 * np.eye(2), np.array([[2.0, -1.0], [-1.0, 2.0]]), force=[f, 0.0])
        return frequency_response(s, [Contact(Macroslip(1.0, 0.02 * f), dof=0)], omega_range=(0.6, 1.8), **kw)

    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        for kw in (dict(harmonics=3, tol=None), dict(tol=1e-3)):
            ref, big = solve(1.0, **kw), solve(F, **kw)
            assert big.success and len(big) == len(ref)
            assert big.peak().amplitude / F == pytest.approx(ref.peak().amplitude, rel=1e-9)
            if "tol" in kw and kw["tol"] is not None:
                assert np.nanmax(big.error_estimate) == pytest.approx(np.nanmax(ref.error_estimate), rel=1e-6)
