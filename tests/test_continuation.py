"""The continuation core on curves with known answers (it knows nothing of friction)."""

import math
import re

import numpy as np
import pytest

from hbm.continuation import Status, continuation, locate, maximise

TOL = 1e-12


def circle(y):
    x, z = y
    return np.array([x * x + z * z - 1.0]), np.array([[2.0 * x, 2.0 * z]])


def sine(y):
    """sin(u) = lam: folds at u = pi/2 + k pi, lam = +-1."""
    u, lam = y
    return np.array([math.sin(u) - lam]), np.array([[math.cos(u), -1.0]])


def test_circle_points_on_curve_and_folds_located():
    r = continuation(circle, [0.0, -1.0], parameter=0, max_step=0.1, max_steps=80, tol=TOL)
    assert r.status == Status.MAX_STEPS and not r.success  # a closed curve never leaves the range
    assert len(r.y) == 81 and r.nsteps == 80
    assert np.all(np.abs(np.hypot(r.y[:, 0], r.y[:, 1]) - 1.0) <= TOL)
    assert np.all(r.residual_norm <= TOL)
    # one full turn: folds of x at (1, 0), then (-1, 0), in that order
    assert len(r.folds) >= 2
    assert np.allclose(r.folds[0], [1.0, 0.0], atol=1e-9)
    assert np.allclose(r.folds[1], [-1.0, 0.0], atol=1e-9)
    # orientation kept: the angle always increases (counter-clockwise from (0, -1))
    theta = np.unwrap(np.arctan2(r.y[:, 1], r.y[:, 0]))
    assert np.all(np.diff(theta) > 0)
    assert theta[-1] - theta[0] > 2 * math.pi
    # steps respect max_step (chord <= arc <= max_step)
    assert np.max(np.linalg.norm(np.diff(r.y, axis=0), axis=1)) <= 0.1 * 1.01
    # cost: the quadratic predictor leaves about two Newton updates per step at tol 1e-12
    assert r.nit <= 2.5 * r.nsteps
    assert r.nfev <= r.nit + r.nsteps + 20


def test_circle_stops_on_the_bound():
    r = continuation(circle, [0.0, -1.0], parameter=0, bounds=(-0.5, 0.5), max_step=0.1, tol=TOL)
    assert r.success and r.status == Status.REACHED_END
    assert r.y[-1, 0] == pytest.approx(0.5, abs=1e-15)
    assert r.y[-1, 1] == pytest.approx(-math.sqrt(0.75), abs=1e-12)
    assert np.all(np.abs(r.y[:, 0]) <= 0.5)
    assert len(r.folds) == 0


def test_on_point_streams_exactly_the_returned_points():
    seen = []
    r = continuation(sine, [0.0, 0.0], parameter=1, bounds=(-2.0, 2.0), max_step=0.1, max_steps=400,
                     tol=TOL, on_point=lambda y, rnorm: seen.append(np.array(y)))
    assert len(r.folds) >= 2  # through folds, and onto the bound at the end
    np.testing.assert_array_equal(np.array(seen), r.y)


def test_sine_folds_found_where_they_are():
    r = continuation(sine, [0.0, 0.0], parameter=1, max_step=0.1, max_steps=400, tol=TOL)
    assert np.all(np.abs(np.sin(r.y[:, 0]) - r.y[:, 1]) <= TOL)
    u_end = r.y[-1, 0]
    k_max = int((u_end - math.pi / 2) // math.pi)
    assert len(r.folds) == k_max + 1 >= 5  # every fold passed, none invented
    for k, (u, lam) in enumerate(r.folds):
        assert u == pytest.approx(math.pi / 2 + k * math.pi, abs=1e-7)
        assert lam == pytest.approx((-1) ** k, abs=1e-12)
    # u increases monotonically through the folds (orientation kept)
    assert np.all(np.diff(r.y[:, 0]) > 0)
    # the parameter direction reverses at each fold and nowhere else
    turns = np.flatnonzero(np.diff(np.sign(np.diff(r.y[:, 1]))) != 0)
    assert len(turns) == len(r.folds)


def test_sine_backwards_direction():
    r = continuation(sine, [0.0, 0.0], parameter=1, direction=-1, bounds=(-0.5, 2.0), max_step=0.1, tol=TOL)
    assert r.success
    assert r.y[-1, 1] == pytest.approx(-0.5, abs=1e-15)
    assert r.y[-1, 0] == pytest.approx(math.asin(-0.5), abs=1e-12)


def curve_in_r4(y):
    """A circle lifted into R^4 (three equations): exercises the general tangent path."""
    a, b, c, d = y
    R = np.array([a * a + b * b - 1.0, c - a, d - a * b])
    J = np.array([[2 * a, 2 * b, 0, 0], [-1.0, 0, 1, 0], [-b, -a, 0, 1]])
    return R, J


def test_general_dimension():
    r = continuation(curve_in_r4, [0.0, -1.0, 0.0, 0.0], parameter=0, bounds=(-0.9, 0.9), max_step=0.1, tol=TOL)
    assert r.success
    assert np.all(r.residual_norm <= TOL)
    assert r.y[-1, 0] == pytest.approx(0.9)
    assert r.y[-1, 3] == pytest.approx(0.9 * -math.sqrt(1 - 0.81), abs=1e-12)


def test_corner_of_a_piecewise_smooth_curve_is_passed():
    """u = |lam - 0.5|: the tangent turns by 90 degrees at lam = 0.5."""
    def vee(y):
        u, lam = y
        s = 1.0 if lam >= 0.5 else -1.0
        return np.array([u - abs(lam - 0.5)]), np.array([[1.0, -s]])

    r = continuation(vee, [0.5, 0.0], parameter=1, bounds=(0.0, 1.0), max_step=0.05, tol=TOL)
    assert r.success
    assert len(r.corners) == 1
    assert np.all(np.abs(r.y[:, 0] - np.abs(r.y[:, 1] - 0.5)) <= TOL)
    assert r.y[-1, 1] == 1.0


@pytest.mark.parametrize("a", [1.5, 3.0, 10.0])
def test_corner_fold_is_passed(a):
    """lam = -a |u| - 0.1 u^2: the branch turns back at u = 0 by 2 atan(a) (112 to 169 degrees), so
    no hyperplane normal to the incoming tangent ahead of the corner meets the outgoing piece.  The
    run passes the corner once, marks it a fold, and comes back down to the lower bound."""
    def fold(y):
        u, lam = y
        s = 1.0 if u >= 0 else -1.0
        return np.array([lam + a * abs(u) + 0.1 * u**2]), np.array([[a * s + 0.2 * u, 1.0]])

    r = continuation(fold, [-1.0 / a, -1.0], parameter=1, bounds=(-1.0, 1.0), max_step=0.05, tol=TOL)
    assert r.success and r.y[-1, 1] == -1.0 and r.y[-1, 0] > 0.0
    assert len(r.corners) == 1 and len(r.fold_after) == 1
    assert np.all(np.diff(r.y[:, 0]) > 0.0)  # never back along the incoming piece
    assert np.all(np.abs(r.y[:, 1] + a * np.abs(r.y[:, 0]) + 0.1 * r.y[:, 0] ** 2) <= TOL)



@pytest.mark.parametrize("direction", [1, -1])
def test_a_run_from_a_bound_that_comes_back_through_it_turned_back(direction):
    """The circle x^2 + (lam - c)^2 = 0.3^2 entered from the bound behind ``direction`` (lam = 0 going up,
    or 1 going down, c = 0.2 or 0.8): the branch turns at lam = c + 0.3 (or c - 0.3), comes back and
    leaves through the bound it started from, never reaching the other.  Without ``from_bound`` that run
    reached an end of the range; from a bound, it turned back, and says where."""
    start, c = (0.0, 0.2) if direction > 0 else (1.0, 0.8)

    def shifted(y):
        x, lam = y
        return np.array([x * x + (lam - c) ** 2 - 0.09]), np.array([[2.0 * x, 2.0 * (lam - c)]])

    y0 = [-math.sqrt(0.09 - (start - c) ** 2), start]
    plain = continuation(shifted, y0, parameter=1, bounds=(0.0, 1.0), direction=direction, max_step=0.05, tol=TOL)
    assert plain.status == Status.REACHED_END and plain.y[-1, 1] == start  # the old answer: success, nothing traced
    r = continuation(shifted, y0, parameter=1, bounds=(0.0, 1.0), direction=direction, max_step=0.05, tol=TOL,
                     from_bound=True)
    assert r.status == Status.TURNED_BACK and not r.success
    assert r.y[-1, 1] == start and r.y[-1, 0] == pytest.approx(-y0[0], abs=1e-10)  # out where it came in
    turn = c + 0.3 * direction
    assert len(r.folds) == 1 and r.folds[0, 1] == pytest.approx(turn, abs=1e-9)
    other = 1.0 - start
    assert r.message == (f"the branch turned back and left the parameter range where it started (it turned at "
                         f"y[1] = {turn:.8g} and left through its start bound {start!r} before reaching {other!r})")
    through = continuation(shifted, y0, parameter=1, bounds=(0.0, 1.0), direction=direction, max_step=0.05, tol=TOL, from_bound=True, locate_folds=False)
    assert through.status == Status.TURNED_BACK  # the farthest point when folds are not located
    assert f"it turned at y[1] = {float((max if direction > 0 else min)(through.y[:, 1])):.8g}" in through.message


def test_a_run_from_a_bound_that_reaches_the_other_succeeds_and_from_bound_needs_y0_on_the_start_bound():
    r = continuation(sine, [0.0, 0.0], parameter=1, bounds=(0.0, 0.5), max_step=0.1, tol=TOL, from_bound=True)
    assert r.status == Status.REACHED_END and r.y[-1, 1] == 0.5
    with pytest.raises(ValueError, match=r"^from_bound=True needs y0 on the bound the range starts from, y0\[1\] == "
                                         r"lo=-1\.0 for direction=1, got y0\[1\]=0\.0$"):
        continuation(sine, [0.0, 0.0], parameter=1, bounds=(-1.0, 1.0), from_bound=True)

def test_failure_keeps_points_and_says_why():
    def breaks(y):
        if y[1] > 0.5:
            raise FloatingPointError("beyond the model's range")
        return sine(y)

    r = continuation(breaks, [0.0, 0.0], parameter=1, bounds=(-2.0, 2.0), max_step=0.1, tol=TOL)
    assert r.status == Status.STEP_TOO_SMALL and not r.success
    assert "min_step" in r.message and "beyond the model's range" in r.message
    assert len(r.y) > 3
    assert np.all(r.y[:, 1] <= 0.5)
    assert r.y[-1, 1] > 0.5 - 1e-6  # it went as far as it could
    assert np.all(np.abs(np.sin(r.y[:, 0]) - r.y[:, 1]) <= TOL)


def test_newton_divergence_at_the_start():
    def no_solution(y):
        u, lam = y
        return np.array([u * u + 1.0]), np.array([[2 * u, 0.0]])

    r = continuation(no_solution, [0.3, 0.0], parameter=1)
    assert r.status == Status.START_FAILED and not r.success
    assert "starting point" in r.message
    assert len(r.y) == 0


def test_locate_a_level_on_the_branch():
    ya, yb = np.array([0.1, math.sin(0.1)]), np.array([0.4, math.sin(0.4)])
    loc = locate(sine, ya, yb, lambda y, t: y[1] - 0.25, tol=TOL, xtol=1e-14)
    assert loc.y[0] == pytest.approx(math.asin(0.25), abs=1e-12)
    assert locate(sine, ya, yb, lambda y, t: y[1] - 0.9, tol=TOL) is None


def test_maximise_finds_the_largest_point_of_the_branch_between_two_points():
    ya, yb = np.array([1.2, math.sin(1.2)]), np.array([1.9, math.sin(1.9)])
    loc = maximise(sine, ya, yb, lambda y: y[1], tol=TOL, xtol=1e-10)
    assert loc.y[0] == pytest.approx(math.pi / 2, abs=1e-7) and loc.y[1] == pytest.approx(1.0, abs=1e-13)


def _rippled(y):
    """lam = 1 - (u - 1)^2 + a triangle wave of 1e-3 and period 0.01: kinks denser than the two ends
    below, whose slope (0.2) beats the envelope's (at most 0.14) so the tangent misreads the trend."""
    u, lam = y
    phase = (u / 0.01) % 1.0
    tri, dtri = (2e-3 * phase, 0.2) if phase < 0.5 else (2e-3 * (1.0 - phase), -0.2)
    return np.array([1.0 - (u - 1.0) ** 2 + tri - lam]), np.array([[-2.0 * (u - 1.0) + dtri, -1.0]])


def test_maximise_finds_a_maximum_where_kinks_hide_the_slope_from_the_tangent():
    f = lambda u: _rippled(np.array([u, 0.0]))[0][0]  # noqa: E731  (lam on the branch)
    u_a, u_b = 0.9325, 1.0725  # both on a rising stretch of the ripple: the slope along the tangent is > 0 at both
    ya, yb = np.array([u_a, f(u_a)]), np.array([u_b, f(u_b)])
    assert locate(_rippled, ya, yb, lambda y, t: t[1], tol=TOL) is None  # no sign change to bracket
    loc = maximise(_rippled, ya, yb, lambda y: y[1], tol=TOL, xtol=1e-10)
    grid = np.linspace(u_a, u_b, 20001)
    best = max(f(u) for u in grid)
    assert abs(loc.y[0] - 1.0) <= 0.02 and best - 1e-3 <= loc.y[1] <= best + 1e-12  # a peak of the ripple at the top
    assert loc.y[1] > max(ya[1], yb[1])


@pytest.mark.parametrize("kwargs, name", [
    ({"direction": 0}, "direction"),
    ({"bounds": (1.0, 2.0)}, "bounds"),
    ({"min_step": 1.0, "max_step": 0.1}, "min_step"),
])
def test_bad_options(kwargs, name):
    with pytest.raises(ValueError, match=name):
        continuation(sine, [0.0, 0.0], parameter=1, **kwargs)


@pytest.mark.parametrize("kwargs, message", [
    # each refused where it enters, naming it: before, an index past y0 wrapped around, a NaN step or an
    # infinite max_step never ended, a negative tolerance failed the start, a string was taken as True
    ({"parameter": 5}, r"^parameter must be an index of y0 in -2..1, got parameter=5$"),
    ({"parameter": True}, r"^parameter must be an index of y0 in -2..1, got parameter=True$"),
    ({"parameter": 1.5}, r"^parameter must be an index of y0 in -2..1, got parameter=1.5$"),
    ({"bounds": 1.0}, r"^bounds must be a pair \(lo, hi\) of numbers, got bounds=1.0$"),
    ({"bounds": (1.0, 0.0)}, r"^bounds must have lo <= hi, got bounds=\(1.0, 0.0\)$"),
    ({"bounds": (math.nan, 1.0)}, r"^bounds must have lo <= hi, got bounds=\(nan, 1.0\)$"),
    ({"direction": True}, r"^direction must be \+1 or -1, got direction=True$"),
    ({"step": -1.0}, r"^step must be positive, got step=-1.0$"),
    ({"step": math.nan}, r"^step must be finite, got step=nan$"),
    ({"max_step": math.inf}, r"^max_step must be finite, got max_step=inf$"),
    ({"max_steps": 0}, r"^max_steps must be an integer >= 1, got max_steps=0$"),
    ({"max_steps": 2.5}, r"^max_steps must be an integer >= 1, got max_steps=2.5$"),
    ({"max_iter": 0}, r"^max_iter must be an integer >= 1, got max_iter=0$"),
    ({"tol": -1.0}, r"^tol must be positive, got tol=-1.0$"),
    ({"tol": math.nan}, r"^tol must be finite, got tol=nan$"),
    ({"fold_xtol": 0.0}, r"^fold_xtol must be positive, got fold_xtol=0.0$"),
    ({"locate_folds": "no"}, r"^locate_folds must be True or False, got locate_folds='no'$"),
    ({"curve_tol": "0.01"}, r"^curve_tol must be in \(0, 1\) or None, got curve_tol='0.01'$"),
    ({"curve_tol": 1e-3, "curve_components": [5]}, r"^curve_components must be indices of y0 in -2..1, got "
                                                   r"curve_components=\[5\]$"),
    ({"on_point": 3}, r"^on_point must be a function or None, got on_point=3$"),
    ({"stop": 3}, r"^stop must be a function or None, got stop=3$"),
])
def test_bad_options_named(kwargs, message):
    with pytest.raises(ValueError, match=message):
        continuation(sine, [0.0, 0.0], **{"parameter": 1, "bounds": (-2.0, 2.0), **kwargs})


def test_bad_residual_and_start_named():
    with pytest.raises(ValueError, match=r"^residual must be a function y -> \(R, J\), got residual=3$"):
        continuation(3, [0.0, 0.0])
    with pytest.raises(ValueError, match=r"^y0 must be finite, got y0=array\(\[nan,  0.\]\)$"):
        continuation(sine, [math.nan, 0.0])


@pytest.mark.parametrize("returned, got", [
    # before: a residual of the wrong shape was traced (the null space of its Jacobian taken for the tangent) and
    # returned as a converged branch; None was "cannot unpack non-iterable NoneType object"
    ((np.zeros(3), np.zeros((3, 2))), "R of shape (3,) and J of shape (3, 2)"),
    ((np.zeros(1), np.zeros((2, 2))), "R of shape (1,) and J of shape (2, 2)"),
    (None, "NoneType None"),
])
def test_a_residual_of_the_wrong_shape_is_refused_at_its_first_call(returned, got):
    from hbm.continuation import ResidualContractError

    with pytest.raises(ResidualContractError, match=r"^residual\(y\) must return \(R, J\) with R of shape \(1,\) and J "
                                                    rf"of shape \(1, 2\) for y0 of 2 components, got {re.escape(got)}$"):
        continuation(lambda y: returned, [1.0, 0.0], bounds=(0.0, 0.9))


def test_a_direction_that_is_an_array_is_refused_by_name():
    """``direction not in (1, -1)`` with an array was numpy's "truth value of an array is ambiguous"."""
    with pytest.raises(ValueError, match=r"^direction must be \+1 or -1, got direction=array"):
        continuation(lambda y: (np.array([y[0] ** 2 + y[1] ** 2 - 1.0]), np.array([[2 * y[0], 2 * y[1]]])),
                     [1.0, 0.0], bounds=(0.0, 0.9), direction=np.ones((2, 2)))
