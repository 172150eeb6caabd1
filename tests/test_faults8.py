"""Faults at the edges of double precision and in the caller's own code: a value that leaves double precision
inside an element is named by the contract's checks (no numpy RuntimeWarning passes), and what was computed is
kept."""

import math
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
        plot_linear_reference(ax, blade, Macroslip(4e7, 30.0), (3.2e4, 4.4e4), a_min=a_min, stiffness=lambda w: 4e7 + 0 * w)
        assert len(ax.get_lines()) == 1 + lines
        fig.savefig(tmp_path / "f.png")
        plt.close(fig)
