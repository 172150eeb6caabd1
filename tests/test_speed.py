"""The speed shortcuts give the answers of the long way round.

Each shortcut is checked against an independent computation: the stuck answer against the
stuck stiffness (and that no loading path is built for it), the closed-form onset against the
path's first point, the one-step inversion against Newton iterated to convergence, the lazily
built three-region path against the whole path, the cmath point against the numpy one, the
interpolation matrix against numpy's least-squares fit, the public methods' float path for one
float a and omega against their general path (values, types and errors).
"""

import math

import numpy as np
import pytest
from numpy.polynomial import chebyshev as cheb

import contact_models._loading_path as lp
from contact_models import Bar, QuadraticLoad, ThreeRegionMicroslip, TwoRegionMicroslip, UniformLoad

from conftest import BAR

FREQS = (0.0, 0.1, 0.3, 0.5)  # fractions of omega_c


def _counting(el):
    builds = []
    build = el._build_path

    def counted(omega):
        builds.append(omega)
        return build(omega)

    el._build_path = counted
    return builds


@pytest.mark.parametrize("make", [lambda b: TwoRegionMicroslip(b, UniformLoad(N=100.0)),
                                  lambda b: ThreeRegionMicroslip(b, QuadraticLoad.from_ratio(100.0, 12.0))])
def test_stuck_evaluations_build_no_path_and_answer_the_stuck_stiffness(make):
    bar = Bar(**BAR)
    el = make(bar)
    builds = _counting(el)
    for f in (0.11, 0.23, 0.37):
        w = f * bar.omega_c
        a_min = el.linear_amplitude(w)
        fs, fc, dfs, dfc = el.fourier_derivatives(np.array([0.2, 0.9, 1.0]) * a_min, w)
        K = float(bar.stuck_stiffness(w))
        assert fs == pytest.approx(K * np.array([0.2, 0.9, 1.0]) * a_min, rel=1e-15)
        assert np.all(fc == 0.0) and np.all(dfs == K) and np.all(dfc == 0.0)
    assert builds == []
    # and the onset used for it is the path's first point (bit for bit for two regions)
    for f in FREQS:
        w = f * bar.omega_c
        assert el.linear_amplitude(w) == pytest.approx(el.slip_amplitude(w), rel=1e-14, abs=0.0)
    assert len(builds) == len(FREQS) - 1  # omega = 0 was built with the element


def test_two_region_onset_is_mu_q_over_k_and_the_paths_first_point_exactly():
    bar = Bar(**BAR)
    for load in (UniformLoad(N=100.0), QuadraticLoad.from_ratio(100.0, 0.8), UniformLoad(N=7.0)):
        el = TwoRegionMicroslip(bar, load)
        for f in FREQS:
            w = f * bar.omega_c
            assert el.linear_amplitude(w) == el.slip_amplitude(w)  # no rounding apart
            assert el.linear_amplitude(w) == bar.mu * float(el.load.q(bar.L)) / bar.k


@pytest.mark.parametrize("make", [lambda b: TwoRegionMicroslip(b, UniformLoad(N=100.0)),
                                  lambda b: ThreeRegionMicroslip(b, QuadraticLoad.from_ratio(100.0, 12.0))])
def test_one_step_inversion_is_converged_newton(make):
    bar = Bar(**BAR)
    el = make(bar)
    worst = 0.0
    for f in FREQS:
        w = f * bar.omega_c
        for p in el._path(w)[1]:
            for u in np.linspace(0.02, 0.98, 9):
                a = p.s0 + u * (p.s1 - p.s0)
                t = p._invert_one(a)
                # an independent answer: bisection on s(t) - a to the last bit
                lo, hi = 0.0, 1.0
                for _ in range(80):
                    mid = 0.5 * (lo + hi)
                    lo, hi = (mid, hi) if p._evaluate_one(mid)[0] < a else (lo, mid)
                worst = max(worst, abs(t - 0.5 * (lo + hi)))
                s = p._evaluate_one(t)[0]
                assert abs(s - a) <= 1e-13 * a
    assert worst < 1e-12


def test_lazy_three_region_path_gives_the_whole_paths_answers():
    bar = Bar(**BAR)
    load = QuadraticLoad.from_ratio(100.0, 12.0)
    lazy, whole = ThreeRegionMicroslip(bar, load), ThreeRegionMicroslip(bar, load)
    w = 0.3 * bar.omega_c
    whole._path(w)  # built to gross slip first
    s1 = whole._path(w)[1][0].s1  # end of the three-region piece
    a = np.array([0.5, 0.9]) * s1 + 0.1 * whole.slip_amplitude(w)
    got = lazy.fourier_derivatives(a, w)
    assert len(lazy._paths[w].pieces) == 1  # the two-region continuation was not built
    ref = whole.fourier_derivatives(a, w)
    for g, r in zip(got, ref):
        assert np.all(g == r)
    lazy.fourier_derivatives(np.array([2.0 * s1]), w)  # past it: the rest is built
    assert len(lazy._paths[w].pieces) == 2


def test_cmath_point_agrees_with_the_numpy_table():
    bar = Bar(**BAR)
    for el in (TwoRegionMicroslip(bar, UniformLoad(N=100.0)),
               ThreeRegionMicroslip(bar, QuadraticLoad.from_ratio(100.0, 12.0))):
        for f in (0.1, 0.3, 0.5):
            p = el._path(f * bar.omega_c)[1][0]
            t = np.array([0.1, 0.5, 0.9])
            table = np.array(p.evaluate(t))
            one = np.array([p._evaluate_one(v) for v in t]).T
            assert np.max(np.abs(one - table) / np.abs(table)) < 1e-13


@pytest.mark.parametrize("deg", [24, 48, 96])
def test_chebyshev_interpolation_matrix_is_the_least_squares_fit(deg):
    u, to_coef = lp._chebyshev_gauss(deg)
    f = np.exp(np.sin(3.0 * u)) / (1.2 - u)
    assert np.max(np.abs(to_coef @ f - cheb.chebfit(u, f, deg))) < 1e-13
    x = np.linspace(-1.0, 1.0, 7)
    c = to_coef @ f
    s, ds = lp._chebyshev_sum(x, c, cheb.chebder(c))
    assert np.max(np.abs(s - cheb.chebval(x, c))) < 1e-13
    assert np.max(np.abs(ds - cheb.chebval(x, cheb.chebder(c)))) < 1e-11 * math.fsum(np.abs(cheb.chebder(c)))


def test_float_path_for_one_amplitude_agrees_with_the_array_path():
    """``_fourier_one`` (one amplitude in floats, the solver's call) against ``_fourier_one_omega``
    (arrays) over stuck, microslip, gross slip, both folds (beta = 0 has a gross-slip fold, the
    three-region path an onset fold).  f_s, f_c agree to rounding; df_s/da to 1e-10 k*: just
    above a_min it is ill-conditioned in the end point t(a) of the quadrature (its integrand
    has a 1/sqrt(a - s) end), which the two paths find by the same Newton steps in numpy and in
    cmath, one rounding apart."""
    import contact_models.microslip as ms

    bar = Bar(**BAR)
    bar0 = Bar(**{**BAR, "beta": 0.0})
    for el in (TwoRegionMicroslip(bar, UniformLoad(N=100.0)),
               ThreeRegionMicroslip(bar, QuadraticLoad.from_ratio(100.0, 12.0)),
               TwoRegionMicroslip(bar0, UniformLoad(N=100.0))):
        for f in (0.0, 0.06, 0.3, 0.5):
            path = el._path(f * bar.omega_c)
            a = path[0] * np.concatenate([[0.5, 1.0, 1.001], np.geomspace(1.01, 3.0 * path[2] / path[0], 25)])
            v = np.array(ms._fourier_one_omega(path, a, 1e-6))
            s = np.array([ms._fourier_one(path, float(x), 1e-6) for x in a]).T
            F = np.hypot(v[0], v[1])
            assert np.max(np.abs(s[:2] - v[:2]) / F) < 1e-14
            assert np.max(np.abs(s[2:] - v[2:])) < 1e-10 * abs(path[5])


def _scalar_elements():
    bar = Bar(**BAR)
    return (TwoRegionMicroslip(bar, UniformLoad(N=100.0)),
            ThreeRegionMicroslip(bar, QuadraticLoad.from_ratio(100.0, 12.0)),
            TwoRegionMicroslip(Bar(**{**BAR, "beta": 0.0}), UniformLoad(N=100.0)))


@pytest.mark.filterwarnings("ignore::contact_models.model_range.ModelRangeWarning")
def test_scalar_call_answers_as_the_array_path():
    """The public methods' float path (``_scalar_call``: one float a and omega) against the general
    path (validation, broadcasting, ``_fourier_derivatives`` on arrays) on fresh elements, over
    stuck, onset, microslip and gross slip: the same values and the same type (numpy.float64)."""
    for fast, slow in zip(_scalar_elements(), _scalar_elements()):
        for f in (0.0, 0.06, 0.3, 0.5):
            w = f * fast.bar.omega_c
            a_min = slow.slip_amplitude(w)
            for r in (0.0, 0.5, 1.0, 1.001, 2.0, 3.0, 10.0):
                a = r * a_min
                got = fast.fourier_derivatives(a, np.float64(w))
                ref = slow.fourier_derivatives(np.array(a), np.array([w]))
                assert all(type(v) is np.float64 for v in got)
                assert np.array_equal(np.array(got), np.concatenate(ref))
                got2 = fast.fourier(np.float64(a), w, rtol=1e-8)
                ref2 = slow.fourier(np.array(a), np.array(w), rtol=1e-8)
                assert all(type(v) is np.float64 for v in got2) and all(type(v) is np.float64 for v in ref2)
                assert got2 == ref2


@pytest.mark.parametrize("args", [(-1e-6, 1e3, 1e-6), (math.nan, 1e3, 1e-6), (math.inf, 1e3, 1e-6),
                                  (1e-6, -1.0, 1e-6), (1e-6, math.nan, 1e-6), (1e-6, math.inf, 1e-6),
                                  (1e-6, 1e3, 0.0), (1e-6, 1e3, -1e-6), (1e-6, 1e3, math.nan),
                                  (np.float64(-2e-6), np.float64(1e3), 1e-6), (-1e-6, -1.0, -1.0)])
def test_bad_scalar_input_raises_the_general_paths_errors(args):
    """A float that fails a check leaves the float path: the general path raises its ValueError,
    naming the parameter and the value, for a, omega and rtol alike (a checked first, then omega,
    then rtol), with the same message as ``ContactElement``'s own checks."""
    a, w, rtol = args
    from contact_models.base import ContactElement

    el = TwoRegionMicroslip(Bar(**BAR), UniformLoad(N=100.0))
    for name in ("fourier", "fourier_derivatives"):
        with pytest.raises(ValueError) as fast:
            getattr(el, name)(a, w, rtol=rtol)
        with pytest.raises(ValueError) as slow:  # the general path's checks (the base class's method)
            getattr(ContactElement, name)(el, a, w, rtol=rtol)
        assert str(fast.value) == str(slow.value)
        name = "a" if not 0.0 <= a < math.inf else ("omega" if not 0.0 <= w < math.inf else "rtol")
        assert str(fast.value).startswith(f"{name} must be")


def test_table_with_the_kept_friction_part_is_the_fresh_region_solution():
    """The per-frequency table of a two-region piece takes the friction part of its region
    solution from the element (computed at the first frequency): against region_solution computed
    afresh at the same boundaries, bit for bit, at several frequencies, also with a gross-slip fold
    (beta = 0), whose table is taken anew on [t0, t1] (t1 depends on omega: computed afresh)."""
    for bar in (Bar(**BAR), Bar(**{**BAR, "beta": 0.0})):
        el = TwoRegionMicroslip(bar, UniformLoad(N=100.0))
        for f in (0.06, 0.3, 0.5, 0.3001):
            p = el._path(f * bar.omega_c)[1][0]
            tt = lp._table_nodes(p.table_points)
            L1, L2 = p.boundaries(tt + 1j * lp.CSTEP)
            fresh = lp.region_solution(bar, el.load, L1, L2, p.omega, left=True)
            assert np.array_equal(p.s_tab, fresh.x1.real) and np.array_equal(p.ds_tab, fresh.x1.imag / lp.CSTEP)
            kept = p._evaluate(tt, left=True, table=p.t1 == 1.0)[4]
            for k, new in zip(kept, fresh):
                assert new is None and k is None or np.array_equal(k, new)
            assert p.sliding() == tuple(float(v[-1].real) for v in (fresh.F_fric, fresh.K_tip)) or p.t1 < 1.0
        kept = el._friction_tables
        assert list(kept) == [(("two", bar.L), 0.0, 1.0, lp.TABLE_POINTS, True)]  # the first table's only
        assert all(not v.flags.writeable for fr in kept.values() for v in fr if isinstance(v, np.ndarray))
