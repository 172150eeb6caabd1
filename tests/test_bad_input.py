"""Bad input at the front door: each refusal a ValueError naming the parameter and its value, and what
was computed before a failure kept (a callback that raises ends the run, it does not lose the curve)."""

import math
import re
import warnings

import numpy as np
import pytest

from contact_models import (AccuracyWarning, AllModeMicroslip, AllModeMicroslip2D, Bar, Contact2D, Contact3D,
                            ContactElement, Gap, Iwan,
                            Macroslip, NumericalMicroslip, PointContact,
                            UniformLoad)
from contact_models.allmode.solve import MAX_MESH
from contact_models.numerics.checks import count
from hbm import Blade, Contact, Structure, frequency_response, nonlinear_modes
from hbm.continuation import Status, continuation

from conftest import BAR, MACROSLIP_BLADE


def _jenkins():
    return Structure(np.eye(1), [[0.004]], np.eye(1), force=[0.01]), [Contact(Macroslip(1.0, 0.02), dof=0)]


class _Stop(Exception):
    pass


def _raising_after(n):
    seen = []

    def callback(point):
        seen.append(point.omega)
        if len(seen) == n:
            raise _Stop("enough points")

    return callback, seen


# ---------------------------------------------------------------- the callback raises: the curve is kept
def test_a_callback_that_raises_ends_the_run_and_keeps_its_points():
    s, contacts = _jenkins()
    callback, seen = _raising_after(20)
    with pytest.warns(AccuracyWarning, match=r"the branch stopped at omega = .*_Stop: enough points.*the points "
                                             r"before are kept"):
        frf = frequency_response(s, contacts, omega_range=(0.6, 1.8), harmonics=3, tol=None, callback=callback)
    assert not frf.success and frf.status == Status.CALLBACK_RAISED
    assert len(frf) == 20 and frf.omega[-1] == pytest.approx(seen[-1])  # the point it was called with is kept
    assert "the callback raised an exception" in frf.message and "_Stop: enough points" in frf.message
    assert np.all(np.isfinite(frf.amplitude))
    assert math.isfinite(frf.peak().amplitude) and frf.peak().omega <= frf.omega[-1]


def test_the_status_is_public_and_reads_as_its_name_while_comparing_as_its_code():
    import hbm

    s, contacts = _jenkins()
    callback, _ = _raising_after(5)
    with pytest.warns(AccuracyWarning):
        frf = frequency_response(s, contacts, omega_range=(0.6, 1.8), harmonics=3, tol=None, callback=callback)
    assert "Status" in hbm.__all__ and hbm.Status is Status  # before: only hbm.continuation.Status
    assert type(frf.status) is hbm.Status and frf.status == -4 and frf.status == Status.CALLBACK_RAISED
    assert str(frf.status) == "Status.CALLBACK_RAISED" and f"{frf.status}" == "Status.CALLBACK_RAISED"  # before: -4
    assert int(frf.status) == -4 and str(hbm.Status.REACHED_END) == "Status.REACHED_END"


def test_a_peak_without_an_estimate_says_none_not_nan():
    import pickle

    from hbm import Peak

    s, contacts = _jenkins()
    frf = frequency_response(s, contacts, omega_range=(0.6, 1.8), harmonics=3, tol=None)
    pk = frf.peak()  # before: Peak(..., converged=True, estimate=nan)
    assert pk.estimate is None and "estimate=None" in repr(pk) and "nan" not in repr(pk)
    assert pk.interior and pk.converged and pk.message == ""  # located, interior, the range traced: nothing estimated
    assert pickle.loads(pickle.dumps(pk)).estimate is None
    assert Peak(1.0, 2.0).estimate is None and Peak(1.0, 2.0, estimate=math.nan).estimate is None
    assert frequency_response(s, contacts, omega_range=(0.6, 1.8), harmonics=3, tol=1e-2).peak().estimate > 0.0


def test_a_callback_that_raises_while_the_final_points_stream_keeps_every_point():
    s, contacts = _jenkins()  # tol without harmonics: the points are streamed once the run ends
    ref = frequency_response(s, contacts, omega_range=(0.6, 1.8))
    callback, _ = _raising_after(5)
    with pytest.warns(AccuracyWarning, match=r"the callback raised an exception \(_Stop: enough points\) at omega = "
                                             r"[0-9.]+ rad/s, point 5 of"):
        frf = frequency_response(s, contacts, omega_range=(0.6, 1.8), callback=callback)
    assert not frf.success and frf.status == Status.CALLBACK_RAISED
    assert len(frf) == len(ref)  # every point computed is kept
    np.testing.assert_allclose(frf.amplitude, ref.amplitude)


def test_a_keyboard_interrupt_in_the_callback_goes_through():
    s, contacts = _jenkins()

    def callback(point):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        frequency_response(s, contacts, omega_range=(0.6, 1.8), harmonics=3, tol=None, callback=callback)


def test_the_continuation_core_keeps_the_points_when_on_point_raises():
    def circle(y):  # x^2 + lam^2 = 1
        return np.array([y[0] ** 2 + y[1] ** 2 - 1.0]), np.array([[2.0 * y[0], 2.0 * y[1]]])

    calls = []

    def on_point(y, rnorm):
        calls.append(y.copy())
        if len(calls) == 4:
            raise ValueError("stop here")

    run = continuation(circle, [1.0, 0.0], parameter=1, bounds=(-0.9, 0.9), on_point=on_point)
    assert run.status == Status.CALLBACK_RAISED and not run.success
    assert len(run.y) == 4 and "ValueError: stop here" in run.message
    np.testing.assert_array_equal(run.y[-1], calls[-1])

    first = continuation(circle, [1.0, 0.0], parameter=1, bounds=(-0.9, 0.9),
                         on_point=lambda y, r: 1 / 0)  # at the start point already
    assert first.status == Status.CALLBACK_RAISED and len(first.y) == 1 and "ZeroDivisionError" in first.message


def test_the_continuation_core_says_the_callers_stop_raised_not_the_residual():
    """A ``stop(y)`` that raises ends the run at the point it was asked at with ``Status.CALLBACK_RAISED`` and
    names it (it was "the residual raised an exception beyond the last point", ``Status.RESIDUAL_RAISED``)."""
    def circle(y):
        return np.array([y[0] ** 2 + y[1] ** 2 - 1.0]), np.array([[2.0 * y[0], 2.0 * y[1]]])

    asked = []

    def stop(y):
        asked.append(y.copy())
        if len(asked) == 3:
            raise ValueError("stop broke")
        return False

    run = continuation(circle, [1.0, 0.0], parameter=1, bounds=(-0.9, 0.9), stop=stop)
    assert run.status == Status.CALLBACK_RAISED and not run.success
    assert "stop(y) raised ValueError: stop broke" in run.message and "residual" not in run.message
    assert len(run.y) == 4  # the start and the three points stop was asked at
    np.testing.assert_array_equal(run.y[-1], asked[-1])


@pytest.mark.parametrize("bad, said", [(lambda: 1 / 0, "scale(y) raised ZeroDivisionError: division by zero"),
                                       (lambda: -np.ones(2), "scale(y) raised ValueError: scale(y) must return finite "
                                                             "positive weights")])
def test_the_continuation_core_says_the_callers_scale_raised_not_the_residual(bad, said):
    """The caller's ``scale(y)`` raising (or answering wrong) after the start ends the run with
    ``Status.CALLBACK_RAISED`` naming it, the points before kept (it was "the residual raised an exception")."""
    def circle(y):
        return np.array([y[0] ** 2 + y[1] ** 2 - 1.0]), np.array([[2.0 * y[0], 2.0 * y[1]]])

    run = continuation(circle, [1.0, 0.0], parameter=1, bounds=(-0.9, 0.9),
                       scale=lambda y: np.ones(2) if y[1] < 0.3 else bad())
    assert run.status == Status.CALLBACK_RAISED and said in run.message and "residual" not in run.message
    assert len(run.y) >= 2 and np.all(run.y[:, 1] < 0.3)


# ---------------------------------------------------------------- the options, refused by name
@pytest.mark.parametrize("omega_range, at", [((1e300, 1.7e308), "harmonic 3 of omega=1.7e+308"),
                                             ((1e155, 1e156), "harmonic 3 of omega=1e+156")])
def test_a_frequency_range_past_double_precision_is_refused_by_name(omega_range, at):
    """(H omega)^2 M overflows: refused naming omega_range and the highest frequency taken (the start failed with
    "SVD did not converge" after numpy's "invalid value encountered in multiply", or a "non-finite residual")."""
    s, contacts = _jenkins()
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        with pytest.raises(ValueError, match=rf"^omega_range={re.escape(repr(omega_range))} reaches too high for the "
                                             rf"structure: at {re.escape(at)} rad/s .* omega_range must stay below "
                                             r"3\.33e\+149 rad/s at 3 harmonics"):
            frequency_response(s, contacts, omega_range=omega_range, harmonics=3, tol=None)
    with pytest.raises(ValueError, match=r"at harmonic 31 of omega=1e\+156 rad/s"):  # a tol may climb to H = 31
        frequency_response(s, contacts, omega_range=(1e155, 1e156))
    with pytest.raises(ValueError, match=r"at harmonic 1 of omega=1e\+156 rad/s"):  # a blade's own H = 1
        frequency_response(Blade(1.0, 1.0, 0.01, 1.0), Macroslip(1.0, 0.02), omega_range=(1e155, 1e156), tol=None)


@pytest.mark.parametrize("omega", [1e160, 1e300])
def test_the_periodic_reference_refuses_a_frequency_past_double_precision_by_name(omega):
    """The same check as frequency_response's, at the shooting's one frequency: omega^2 M overflowed in its stuck
    start, a bare OverflowError (34, 'Numerical result out of range'); 1e140 rad/s is still solved."""
    from hbm import periodic_response

    s, contacts = _jenkins()
    with pytest.raises(ValueError, match=rf"^omega={re.escape(repr(omega))} reaches too high for the structure: at "
                                         r"harmonic 1 .*omega must stay below 1e\+150 rad/s"):
        periodic_response(s, contacts, omega=omega)
    assert periodic_response(s, contacts, omega=1e140).amplitude(0) == pytest.approx(0.01 / 1e280, rel=1e-9)


def test_contacts_from_an_iterator_are_refused_not_read_once():
    """A generator of contacts was read by the first of the solve's checks and the curve traced without them (the
    contact-free structure's 747 points, success True): refused, naming contacts; a tuple is taken."""
    s, contacts = _jenkins()
    with pytest.raises(ValueError, match=r"^contacts must be a sequence of hbm\.Contact \(a list or a tuple\), not "
                                         r"an iterator"):
        frequency_response(s, (c for c in contacts), omega_range=(0.6, 1.8), harmonics=3, tol=None)
    with pytest.raises(ValueError, match=r"not an iterator"):
        nonlinear_modes(s, iter(contacts), amplitudes=[0.01, 0.1])
    assert frequency_response(s, tuple(contacts), omega_range=(0.6, 1.8), harmonics=3, tol=None).success


@pytest.mark.parametrize("omega_range", [{0.6, 1.8}, {0.6: 0, 1.8: 1}])
def test_an_omega_range_without_an_order_is_refused_by_name(omega_range):
    """A set's order is its hashes': which end was w0 was not the caller's choice."""
    s, contacts = _jenkins()
    with pytest.raises(ValueError, match=r"^omega_range must be a pair \(w0, w1\) in order"):
        frequency_response(s, contacts, omega_range=omega_range, harmonics=3, tol=None)


@pytest.mark.parametrize("omega_range", [(1.0, 1.0 + 1e-15), (2.0 + 1e-14, 2.0)])
def test_a_frequency_range_a_few_roundings_wide_is_refused_by_name(omega_range):
    """A range a few roundings of omega wide stopped at once, its corrector "moved 9.94e+11 steps from the
    predictor"; 1e-13 of omega wide is still traced to its end."""
    s, contacts = _jenkins()
    with pytest.raises(ValueError, match=rf"^omega_range must be at least 1e-12 of its upper end wide .*got "
                                         rf"omega_range={re.escape(repr(omega_range))}"):
        frequency_response(s, contacts, omega_range=omega_range, harmonics=3, tol=None)
    assert frequency_response(s, contacts, omega_range=(1.0, 1.0 + 1e-11), harmonics=3, tol=None).success


@pytest.mark.parametrize("tol", [1e-11, 1e-300, 5e-324])
def test_a_tol_below_what_double_precision_meets_is_refused_as_the_command_line_refuses_it(tol):
    s, contacts = _jenkins()
    with pytest.raises(ValueError, match=rf"^tol must be >= 1e-10 .*got tol={re.escape(repr(tol))}$"):
        frequency_response(s, contacts, omega_range=(0.6, 1.8), tol=tol)


@pytest.mark.parametrize("damping", [2.0, 0.4])
def test_the_smallest_tol_is_still_taken(damping):
    """At tol = 1e-10 the Newton tolerance (5e-15 of the load) lies below the rounding of a residual whose
    terms are 1/(2 zeta) times the load near resonance (25 and 125 times here): the corrector stops where its
    update is below the rounding of the unknowns, and the peak is the closed form's to rounding."""
    m, k, F = 1.0, 1.0e4, 1.0
    blade = Blade(mass=m, stiffness=k, damping=damping, force=F)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning)
        frf = frequency_response(blade, omega_range=(90.0, 110.0), tol=1e-10)
    assert frf.success and frf.tolerance == 1e-10 and frf.omega[-1] == 110.0
    assert np.all(frf.residual_norm <= 100.0 * frf.newton_tol)
    exact = F / (damping * math.sqrt(k / m - damping**2 / (4.0 * m * m)))  # max |F / (k - m w^2 + i c w)|
    assert frf.peak().amplitude == pytest.approx(exact, rel=1e-12)


@pytest.mark.parametrize("contacts", [{}, "two", b"two"])
def test_contacts_of_the_wrong_type_are_refused_naming_contacts(contacts):
    blade = Blade(mass=1.0, stiffness=1.0e4, damping=2.0, force=1.0)
    got = re.escape(repr(contacts))
    with pytest.raises(ValueError, match=rf"^contacts must be a contact element .*got contacts={got}$"):
        frequency_response(blade, contacts, omega_range=(90.0, 110.0))


# ---------------------------------------------------------------- the work an element may start, bounded
def test_count_names_its_bound():
    assert count("cells", 64, 2, 128, "X.MAX") == 64
    with pytest.raises(ValueError, match=r"^cells must be an integer in 2..128, got cells=129 \(the bound is X.MAX: "):
        count("cells", 129, 2, 128, "X.MAX")
    with pytest.raises(ValueError, match=r"^cells must be an integer >= 2, got cells=1$"):
        count("cells", 1, 2, 128, "X.MAX")


@pytest.mark.parametrize("kw", [dict(cells=10**9, harmonics=3), dict(cells=10**9), dict(cells=20, harmonics=10**9),
                                dict(harmonics=10**6), dict(cells=20, harmonics=3, n_t=4 * 10**9)])
def test_an_all_mode_bar_too_large_for_the_memory_is_refused_when_built(kw):
    bar = Bar(**BAR)
    given = ", ".join(f"{k}={v!r}" for k, v in {"cells": None, "harmonics": None, **kw}.items())
    with pytest.raises(ValueError, match=rf"^{re.escape(given)}: a bar of .* more than .*the bound is "
                                         r"contact_models.allmode.solve.MAX_MESH"):
        AllModeMicroslip(bar, UniformLoad(N=100.0), **kw)


def test_the_largest_reference_bars_are_still_built():
    bar = Bar(**BAR)
    for cells, H in ((8192, 63), (4096, 31), (1024, 63)):
        assert cells * (2 * H + 1) ** 2 <= MAX_MESH
        AllModeMicroslip(bar, UniformLoad(N=100.0), cells=cells, harmonics=H)


def test_the_normal_all_mode_bar_is_bounded_too():
    bar = Bar(**BAR)
    with pytest.raises(ValueError, match=r"^cells=1000000000, harmonics=15, n_t=240: .*MAX_MESH"):
        AllModeMicroslip2D(bar, UniformLoad(N=100.0), kn=2.0e9, cells=10**9)


def test_the_numerical_bar_takes_the_shared_bounded_count():
    bar = Bar(**BAR)
    assert NumericalMicroslip(bar, UniformLoad(N=100.0), cells=20.0).cells == 20
    for cells in (math.inf, math.nan, 2.5, True):
        with pytest.raises(ValueError, match=rf"^cells must be an integer >= 2, got cells={re.escape(repr(cells))}$"):
            NumericalMicroslip(bar, UniformLoad(N=100.0), cells=cells)


# ---------------------------------------------------------------- a structure's C and K: positive semi-definite
@pytest.mark.parametrize("name, C, K, smallest", [
    ("C", [[-0.004]], [[1.0]], "-0.004"),
    ("C", [[0.01, 0.02], [0.02, 0.01]], [[2.0, -1.0], [-1.0, 1.0]], "-0.01"),  # positive entries, indefinite
    ("K", [[0.004]], [[-1.0]], "-1"),
    ("K", np.zeros((2, 2)), [[1.0, 2.0], [2.0, 1.0]], "-1"),
])
def test_negative_damping_or_stiffness_is_refused_naming_the_matrix_and_its_smallest_eigenvalue(name, C, K, smallest):
    n = len(K)
    with pytest.raises(ValueError, match=rf"^{name} must be positive semi-definite \(no negative (damping|stiffness)"
                                         rf".*\), got {name} with a negative eigenvalue \(smallest "
                                         rf"{re.escape(smallest)}, largest in magnitude "):
        Structure(np.eye(n), C, K, force=[1.0] * n)


def test_a_sparse_indefinite_stiffness_is_refused_and_zero_eigenvalues_within_rounding_are_taken():
    from scipy import sparse

    with pytest.raises(ValueError, match=r"^K must be positive semi-definite .*smallest -1"):
        Structure(sparse.eye(2, format="csr"), sparse.csr_matrix((2, 2)), sparse.csr_matrix(np.diag([1.0, -1.0])),
                  force=[1.0, 0.0])
    n = 8  # a free-free chain (a rigid-body mode), its matrices rounded as a model's are: zero within 1e-10
    K = 1e8 * (2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
    K[0, 0] = K[-1, -1] = 1e8
    K -= 1e-7 * np.eye(n)  # rounding: the zero eigenvalue slightly negative (-1e-7 of 4e8)
    assert np.linalg.eigvalsh(K)[0] < 0.0
    s = Structure(np.eye(n), 0.0 * K, K, force=[1.0] + [0.0] * (n - 1))  # undamped and free-free: taken
    assert s.natural_frequencies()[0] == 0.0


@pytest.mark.parametrize("name, kw, smallest, largest", [
    # K_0 = K + 2 K1 = K - 10 I: eigenvalues 2 -+ sqrt(2) - 10
    ("K", dict(K_next=-5.0 * np.eye(2)), 2.0 - math.sqrt(2.0) - 10.0, 10.0 - 2.0 + math.sqrt(2.0)),
    # C_0 = C + 2 C1 = (0.01 - 0.1) I
    ("C", dict(C_next=-0.05 * np.eye(2)), -0.09, 0.09),
])
def test_a_disk_whose_coupling_makes_its_stiffness_or_damping_indefinite_is_refused_naming_the_nodal_diameter(
        name, kw, smallest, largest):
    """The sector's own K and C are positive definite and its nodal diameter 2 (the engine order's) is too, but at
    nodal diameter 0 the disk cannot stand: refused when built, as a Structure refuses such K or C (a branch was
    traced and its peak called converged)."""
    from hbm import CyclicStructure

    with pytest.raises(ValueError, match=rf"^{name}, {name}_next must give a positive semi-definite disk "
                                         rf"(stiffness|damping) \(no negative .*\), got one with a negative eigenvalue "
                                         rf"at nodal diameter 0 \(smallest {smallest:.6g}, largest in magnitude "
                                         rf"{largest:.6g}\)$"):
        CyclicStructure(np.eye(2), 0.01 * np.eye(2), [[3.0, -1.0], [-1.0, 1.0]], sectors=6, engine_order=2,
                        force=[0.0, 1.0], **kw)


@pytest.mark.parametrize("method, name", [("nodal_matrices", "k"), ("nodal_diameter", "h"),
                                          ("harmonic_matrices", "h"), ("natural_frequencies", "nodal_diameter")])
@pytest.mark.parametrize("value", [2.5, 2.0, "1", None, True])
def test_a_harmonic_or_nodal_diameter_that_is_not_an_integer_is_refused_by_name(method, name, value):
    """2.5 was read as 2 and "1" as 1 (int()), None raised a TypeError from inside; natural_frequencies(None) is
    the engine order's nodal diameter."""
    from hbm import CyclicStructure

    disk = CyclicStructure(np.eye(2), 0.01 * np.eye(2), [[3.0, -1.0], [-1.0, 1.0]], sectors=6, engine_order=2,
                           force=[0.0, 1.0], K_next=[[-1.0, 0.0], [0.0, 0.0]])
    if value is None and method == "natural_frequencies":
        np.testing.assert_array_equal(disk.natural_frequencies(None), disk.natural_frequencies(2))
        return
    with pytest.raises(ValueError, match=rf"^{name} must be an integer, got {name}={re.escape(repr(value))}$"):
        getattr(disk, method)(value)
    np.testing.assert_array_equal(np.array(getattr(disk, method)(np.int64(8))),
                                  np.array(getattr(disk, method)(2)))  # an integer taken mod N


def _rounded_disk():
    """A ring of sectors whose rigid rotation (nodal diameter 0) has K's eigenvalue -2e-9 of the largest, 1."""
    from hbm import CyclicStructure

    return CyclicStructure(np.eye(2), 0.01 * np.eye(2), np.diag([2.0 * (1.0 - 1e-9), 1.0]), sectors=4, engine_order=1,
                           force=[1.0, 0.0], K_next=[[-1.0, 0.0], [0.0, 0.0]])


def test_every_negative_eigenvalue_check_reads_the_one_rounding_constant(monkeypatch):
    import hbm.cyclic
    import hbm.structure

    assert hbm.structure.NEGATIVE_EIGENVALUE_RTOL == 1e-10
    with pytest.raises(ValueError, match=r"^K, K_next must give a positive semi-definite disk stiffness .* at nodal "
                                         r"diameter 0 \(smallest -2e-09, largest in magnitude 1\)$"):
        _rounded_disk()
    with pytest.raises(ValueError, match=r"^K must be positive semi-definite for modal damping: \(K, M\) has "
                                         r"omega\^2 = -2e-09$"):
        Structure.with_modal_damping(np.eye(2), np.diag([-2e-9, 1.0]), ratios=0.05, force=[0.0, 1.0])
    for module in (hbm.structure, hbm.cyclic):  # a looser rounding: -2e-9 of the largest is a zero eigenvalue
        monkeypatch.setattr(module, "NEGATIVE_EIGENVALUE_RTOL", 1e-8)
    disk = _rounded_disk()
    np.testing.assert_allclose(disk.natural_frequencies(0), [0.0, 1.0], atol=1e-15)
    monkeypatch.setattr(hbm.cyclic, "NEGATIVE_EIGENVALUE_RTOL", 1e-10)  # the frequencies' own check reads it too
    with pytest.raises(ValueError, match=r"^K has a negative eigenvalue -2e-09 at nodal diameter 0: the disk is "
                                         r"unstable$"):
        disk.natural_frequencies(0)
    monkeypatch.setattr(hbm.cyclic, "NEGATIVE_EIGENVALUE_RTOL", 1e-8)
    s = Structure.with_modal_damping(np.eye(2), np.diag([-2e-9, 1.0]), ratios=0.05, force=[0.0, 1.0])
    np.testing.assert_allclose(s.C, np.diag([0.0, 0.1]), atol=1e-15)  # 2 zeta omega; the rigid mode undamped


# ---------------------------------------------------------------- a frequency grid: NaN and inf refused by name
@pytest.mark.parametrize("omega_range, name", [((0.5, math.nan), "omega_range[1]"), ((0.5, math.inf), "omega_range[1]"),
                                               ((math.nan, 1.5), "omega_range[0]")])
def test_the_stuck_reference_curve_refuses_a_frequency_range_with_nan_or_inf_by_name(omega_range, name):
    from hbm.output import plot_linear_reference

    blade = Blade(mass=1.0, stiffness=1.0, damping=0.004, force=0.01)
    got = re.escape(f"{name}={omega_range[int(name[-2])]!r}")
    with pytest.raises(ValueError, match=rf"^{re.escape(name)} must be finite, got {got}$"):
        plot_linear_reference(None, blade, Macroslip(1.0, 0.02), omega_range)  # before anything is drawn
    with pytest.raises(ValueError, match=r"^points must be an integer >= 2, got points=1$"):
        plot_linear_reference(None, blade, Macroslip(1.0, 0.02), (0.5, 1.5), points=1)
    with pytest.raises(ValueError, match=rf"^{re.escape(name)} must be finite, got {got}$"):  # as the solve refuses it
        frequency_response(blade, Macroslip(1.0, 0.02), omega_range=omega_range)


# ---------------------------------------------------------------- a contact's stuck (tangential) stiffness
@pytest.mark.parametrize("build, name", [
    (lambda k: Macroslip(k, 0.02), "stiffness"), (lambda k: Macroslip(k, 0.02, slider="from rest"), "stiffness"),
    (lambda k: PointContact(k, 1.0, 1.0, 1.0), "k_s"), (lambda k: PointContact(1.0, 1.0, k, 1.0), "k_p"),
    (lambda k: Iwan(0.02, k, 0.0, 1.0), "stiffness"), (lambda k: Gap(k, 0.1), "stiffness"),
    (lambda k: Contact2D(k, 1.0, 0.3, 1.0), "kt"), (lambda k: Contact3D(k, 1.0, 0.3, 1.0), "kt"),
    (lambda k: Bar(**{**BAR, "k": k}), "k"),  # the microslip bars' shear-layer stiffness, before any element
])
@pytest.mark.parametrize("k", [-1.0, 0.0, math.nan, -math.inf])
def test_a_negative_zero_or_nan_stuck_stiffness_is_refused_by_name_at_construction(build, name, k):
    got = re.escape(f"{name}={k!r}")
    with pytest.raises(ValueError, match=rf"^{name} must be (positive|finite)\b.*, got {got}$"):
        build(k)


def test_a_stiffness_that_may_be_inf_refuses_minus_inf_as_not_positive():
    for build, name in ((lambda k: Macroslip(k, 0.02), "stiffness"), (lambda k: PointContact(k, 1.0, 1.0, 1.0), "k_s")):
        assert getattr(build(math.inf), name) == math.inf  # rigid: taken
        with pytest.raises(ValueError, match=rf"^{name} must be positive \(finite, or inf: rigid\), got {name}=-inf$"):
            build(-math.inf)  # before: "must be finite", though inf is taken


# ---------------------------------------------------------------- a structure's matrices in any scipy.sparse format
def _chain_peak(M, C, K):
    s = Structure(M, C, K, force=[0.0, 0.0, 0.01])
    frf = frequency_response(s, [Contact(Macroslip(0.5, 0.01), dof=2)], omega_range=(0.3, 0.7), harmonics=3, tol=None,
                             response_dof=2)
    return s, frf.peak()


def test_every_scipy_sparse_format_is_taken_as_the_dense_matrix_with_the_same_peak():
    from scipy import sparse

    K3 = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    M3, C3 = np.eye(3), 0.004 * K3 + 0.002 * np.eye(3)
    _, dense = _chain_peak(M3, C3, K3)
    assert dense.interior and 0.45 < dense.omega < 0.55
    # diags builds DIA: abs(A - A.T) stays DIA, which has no max()
    dia = tuple(sparse.diags([np.diag(A, -1), np.diag(A), np.diag(A, 1)], [-1, 0, 1]) for A in (M3, C3, K3))
    assert dia[0].format == "dia"
    s, pk = _chain_peak(*dia)
    assert pk.omega == pytest.approx(dense.omega, rel=1e-12)
    assert pk.amplitude == pytest.approx(dense.amplitude, rel=1e-12)
    for A, B in zip((s.M, s.C, s.K), (M3, C3, K3)):
        assert sparse.issparse(A) and A.format == "csr"
        np.testing.assert_array_equal(A.toarray(), B)
    for fmt in ("csr", "csc", "coo", "bsr", "lil", "dok", "dia"):
        for kind in (sparse.csr_matrix, sparse.csr_array):  # the sparse matrices and the sparse arrays
            mats = [kind(A).asformat(fmt) for A in (M3, C3, K3)]
            s = Structure(*mats, force=[0.0, 0.0, 0.01])
            for A, B in zip((s.M, s.C, s.K), (M3, C3, K3)):
                assert A.format == "csr", (fmt, kind)
                np.testing.assert_array_equal(A.toarray(), B)
    with pytest.raises(ValueError, match=r"^K must be symmetric, got K with max\|K - K\^T\| = 1 \(max\|K\| = 2\)$"):
        Structure(sparse.diags([1.0, 1.0]), sparse.diags([0.0, 0.0]), sparse.diags([[2.0, 2.0], [1.0]], [0, 1]),
                  force=[1.0, 0.0])
    with pytest.raises(ValueError, match=r"^M must be finite, got M with a non-finite entry$"):
        Structure(sparse.diags([1.0, math.nan]), np.zeros((2, 2)), np.eye(2), force=[1.0, 0.0])


# ---------------------------------------------------------------- a study's grid: NaN and inf refused downstream
_STUDY_SCENE = """title = "a study with a non-finite value"
""" + MACROSLIP_BLADE + """[sweep]
omega = [0.24, 0.33]
unit = "omega_c"
[study]
executor = "serial"
[study.grid]
"""


@pytest.mark.parametrize("key, values, bad, why", [
    ("damper.load.N", "[100.0, nan]", "nan", "must be a number >= 0 (N) (finite)"),
    ("damper.mu", "[0.3, inf]", "inf", "must be a number >= 0 (finite)"),
    ("blade.force", "[8.0, -inf]", "-inf", "must be a number > 0 (N) (finite)"),
])
def test_a_nan_or_inf_on_a_scene_grid_axis_is_refused_naming_the_run_the_key_and_the_value(tmp_path, key, values, bad,
                                                                                            why):
    from hbm.scenes import SceneError
    from hbm.study import Study

    path = tmp_path / "study.toml"
    path.write_text(_STUDY_SCENE + f'"{key}" = {values}\n')
    with pytest.raises(SceneError) as info:
        Study.from_scene(path)  # every run's scene checked before any run is made
    assert len(info.value.problems) == 1
    assert info.value.problems[0].startswith(f"run 2 ({key} = {bad}): {path}: {key} = {bad}: {why}")


def _jenkins_run(point):
    blade = Blade(mass=1.0, stiffness=1.0, damping=0.004, force=0.01)
    return frequency_response(blade, Macroslip(1.0, point["slip_force"]), omega_range=(0.6, 1.8), harmonics=1, tol=None)


def test_a_nan_or_inf_on_a_grid_axis_reaches_the_element_which_refuses_it_by_name(tmp_path):
    from hbm.study import Study, grid, run_study

    points = grid({"slip_force": [0.02, math.nan, math.inf]})
    assert math.isnan(points[1]["slip_force"]) and points[2]["slip_force"] == math.inf  # the grid takes them
    result = run_study(Study(_jenkins_run, points), tmp_path, executor="serial", formats=("csv",))
    assert [r["success"] for r in result.records] == [True, False, False]
    assert [r["message"] for r in result.records[1:]] == ["ValueError: slip_force must be finite, got slip_force=nan",
                                                          "ValueError: slip_force must be finite, got slip_force=inf"]
    assert result.records[0]["peak_amplitude_m"] == pytest.approx(_jenkins_run({"slip_force": 0.02}).peak().amplitude,
                                                                  rel=1e-12)


# ---------------------------------------------------------------- the time-domain reference takes whole models only
def test_the_periodic_reference_refuses_one_sector_of_a_disk_and_a_contact_to_the_next_sector():
    """A CyclicStructure's M, C, K are one sector's: integrated alone they left out the couplings to its
    neighbours (with a slider at DOF 0, at 1 rad/s: 2.05 m at DOF 1 against the whole disk's 0.135 m), and a
    next_sector contact was integrated as
    one between two DOFs of the same sector.  Both are refused by name; the whole disk is taken."""
    from hbm import CyclicStructure, periodic_peak, periodic_response

    disk = CyclicStructure(np.eye(2), 0.01 * np.eye(2), [[3.0, -1.0], [-1.0, 1.0]], sectors=6, engine_order=0,
                           force=[0.0, 1.0], K_next=[[-1.0, 0.0], [0.0, 0.0]])
    el = Macroslip(1.0, 0.1)
    with pytest.raises(ValueError, match=r"^system must be the whole model: a cyclic structure is one sector .* "
                                         r"disk.full\(contacts\), got system=CyclicStructure\(n=2 per sector, "
                                         r"sectors=6"):
        periodic_response(disk, [Contact(el, dof=0)], omega=1.0, harmonics=3, floquet=False)
    with pytest.raises(ValueError, match=r"^system must be the whole model"):
        periodic_peak(disk, [Contact(el, dof=0)], bracket=(0.9, 1.1), dof=1)
    plain = Structure(np.eye(2), 0.01 * np.eye(2), [[2.0, -1.0], [-1.0, 2.0]], force=[1.0, 0.0])
    c = Contact(el, dofs=(0, 1), next_sector=True)
    with pytest.raises(ValueError, match=r"^next_sector=True joins two sectors of a cyclic structure, .* got "
                                         rf"next_sector=True in {re.escape(repr(c))}$"):
        periodic_response(plain, [c], omega=1.0, harmonics=3, floquet=False)
    full, contacts = disk.full([c])
    r = periodic_response(full, contacts, omega=1.0, harmonics=3, floquet=False)
    assert r.success and np.isfinite(r.amplitude(1))


@pytest.mark.parametrize("tol", [1.0, 2.0, 1e300])
def test_the_time_domain_references_refuse_a_relative_tolerance_of_one_or_more(tol):
    """A tolerance relative to the state's scale (shooting) or to the peak (the transient run) of 1 or more
    accepts any iterate: periodic_response answered the stuck guess as "converged in 0 Newton iterations" and
    simulate_blade called the run steady at its second cycle after the ramp."""
    from hbm import periodic_response, simulate_blade

    s, contacts = _jenkins()
    with pytest.raises(ValueError, match=rf"^tol must be < 1, got tol={re.escape(repr(tol))}$"):
        periodic_response(s, contacts, omega=1.0, harmonics=3, floquet=False, tol=tol)
    blade = Blade(mass=0.0877, stiffness=1.0e8, damping=0.3, force=8.0)
    with pytest.raises(ValueError, match=rf"^steady_tol must be in \(0, 1\) \(a relative accuracy\), got "
                                         rf"steady_tol={re.escape(repr(tol))}$"):
        simulate_blade(blade, NumericalMicroslip(Bar(**BAR), UniformLoad(N=100.0), cells=20), 3.0e4, steps_per_cycle=64,
                       steady_tol=tol)


# ---------------------------------------------------------------- a point contact's constants in double precision
@pytest.mark.parametrize("cls", [Contact2D, Contact3D])
@pytest.mark.parametrize("kw, quantity", [
    (dict(kt=1e-300, kn=0.0, mu=0.5, n0=1e300), "mu n0/kt"),  # the slip amplitude
    (dict(kt=1e-200, kn=1e200, mu=1.0, n0=1.0), "mu kn/kt"),  # its slope in the normal displacement
    (dict(kt=1.0, kn=0.0, mu=1e10, n0=1e300), "mu n0"),  # the slip force
])
def test_a_point_contact_whose_slip_amplitude_or_force_overflows_is_refused_when_built(cls, kw, quantity):
    """Contact3D(kt=1e-300, ..., n0=1e300) was built, gave slip_amplitude() = inf and its periodic_force raised
    RuntimeError("no covering centre of 1 samples within inf"), Contact2D's an ElementOutputError (a NaN force).
    Refused by name when built."""
    shown = ", ".join(f"{k}={v!r}" for k, v in kw.items())
    with pytest.raises(ValueError, match=rf"^{cls.__name__}\({re.escape(shown)}\): the parameters give "
                                         rf"{re.escape(quantity)} = inf, which must be finite; keep their ratios "
                                         r"within about 1e150$"):
        cls(**kw)
    tiny = cls(kt=1e300, kn=0.0, mu=1e-300, n0=1e-300)  # underflow to a zero slip amplitude: still taken
    assert tiny.slip_amplitude() == 0.0


def test_a_misspelt_keyword_of_frequency_response_names_the_closest_one():
    from contact_models import Macroslip
    from hbm import Blade, frequency_response

    blade = Blade(mass=1.0, stiffness=1.0, damping=0.01, force=0.1)
    with pytest.raises(TypeError, match=r"unexpected keyword argument 'harmonic' \(did you mean harmonics\?\)$"):
        frequency_response(blade, Macroslip(1.0, 0.05), (0.5, 1.5), harmonic=3)
    with pytest.raises(TypeError, match=r"unexpected keyword argument 'zzz'$"):  # nothing close: as Python says it
        frequency_response(blade, Macroslip(1.0, 0.05), (0.5, 1.5), zzz=3)


# ---------------------------------------------------------------- a first-harmonic element above H = 1
class _FirstHarmonic(ContactElement):
    """A user's element with a describing function only: no time law, no loading curve, no refined model."""

    frequency_dependent = False

    def __repr__(self):
        return "_FirstHarmonic()"

    def _fourier(self, a, omega):
        return 1.0 * a, 0.0 * a

    def _stuck_stiffness(self, omega):
        return 1.0

    def _slip_amplitude(self, omega):
        return math.inf

    def _hysteresis(self, a, omega, n):
        x = a * np.sin(np.linspace(0.0, 2.0 * np.pi, n))
        return x, 1.0 * x


def test_harmonics_above_one_with_the_single_mode_bar_names_harmonics_and_the_ways_out(two):
    # before: "element=TwoRegionMicroslip(Bar(...), UniformLoad(...)): TwoRegionMicroslip has no time-domain
    # force law, so it works at harmonics=1 only, got harmonics=5" (element=, which the caller never passed)
    blade = Blade(mass=0.0877147, stiffness=1.0e8, damping=11.8467, force=8.0)
    with pytest.raises(ValueError) as err:
        frequency_response(blade, two, (3.2e4, 4.4e4), harmonics=5)
    message = str(err.value)
    assert message.startswith("harmonics must be 1 with TwoRegionMicroslip, which has no time-domain force law")
    assert "got harmonics=5;" in message and "element=" not in message
    assert "harmonics=1 (its describing-function answer)" in message
    assert ("leave harmonics out and give tol= with model='auto' (where tol asks for more harmonics the balance "
            "takes TwoRegionMicroslip's refined model, contact_models.AllModeMicroslip, which has a time law)"
            ) in message
    assert "contact_models.QuasiStatic(element) in its place" in message
    assert message.endswith(f"; the element: {two!r}")


def test_harmonics_above_one_with_a_users_first_harmonic_element_offers_harmonics_one_only():
    s = Structure(np.eye(1), [[0.004]], np.eye(1), force=[0.01])
    with pytest.raises(ValueError, match=r"^harmonics must be 1 with _FirstHarmonic, which has no time-domain force "
                                         r"law \(a first-harmonic element\), got harmonics=3; use harmonics=1 \(its "
                                         r"describing-function answer\); the element: _FirstHarmonic\(\)$"):
        frequency_response(s, [Contact(_FirstHarmonic(), dof=0)], omega_range=(0.6, 1.8), harmonics=3)


def test_the_modes_refuse_harmonics_above_one_without_offering_a_tol_they_do_not_take(two):
    blade = Blade(mass=0.0877147, stiffness=1.0e8, damping=11.8467, force=8.0)
    with pytest.raises(ValueError) as err:
        nonlinear_modes(blade.as_structure(), [Contact(two, dof=0)], amplitude_range=(1e-9, 1e-6), harmonics=3)
    message = str(err.value)
    assert message.startswith("harmonics must be 1 with TwoRegionMicroslip") and "got harmonics=3;" in message
    assert "model='auto'" not in message and "contact_models.QuasiStatic(element) in its place" in message


# ---------------------------------------------------------------- the references' budgets and tolerances
@pytest.mark.parametrize("ramp, budget", [(3, 2), (10**9, 1000)])
def test_a_ramp_longer_than_the_cycle_budget_is_refused_naming_both(ramp, budget):
    """The budget counts the cycles after the ramp (``BladeSimulation.cycles``): a ramp of 10**9 cycles ran
    without bound, and a ramp of 3 with a budget of 2 was taken."""
    from hbm import simulate_blade

    blade = Blade(mass=0.0877, stiffness=1.0e8, damping=0.3, force=8.0)
    with pytest.raises(ValueError, match=rf"^ramp_cycles must be <= max_cycles \(.*\), got ramp_cycles={ramp}, "
                                         rf"max_cycles={budget}$"):
        simulate_blade(blade, NumericalMicroslip(Bar(**BAR), UniformLoad(N=100.0), cells=20), 3.0e4, steps_per_cycle=64,
                       max_cycles=budget, ramp_cycles=ramp)


def test_a_ramp_as_long_as_the_budget_is_still_taken():
    from hbm import simulate_blade

    blade = Blade(mass=0.0877, stiffness=1.0e8, damping=0.3, force=8.0)
    run = simulate_blade(blade, NumericalMicroslip(Bar(**BAR), UniformLoad(N=100.0), cells=4), 3.0e4,
                         steps_per_cycle=8, max_cycles=2, ramp_cycles=2)
    assert run.cycles == 2 and math.isfinite(run.amplitude)


def test_the_periodic_reference_refuses_no_newton_iteration_by_name():
    # before: taken, and answered "Newton did not converge in 0 iterations"
    from hbm import periodic_response

    s, contacts = _jenkins()
    with pytest.raises(ValueError, match=r"^max_iter must be an integer >= 1, got max_iter=0$"):
        periodic_response(s, contacts, omega=1.0, harmonics=3, floquet=False, max_iter=0)


@pytest.mark.parametrize("xtol", [0.0125, 10.0])
def test_the_periodic_peak_refuses_a_frequency_tolerance_its_bracket_cannot_hold(xtol):
    """xtol is absolute (rad/s) and a maximum counts as interior 10 xtol inside the bracket: at 10.0 over (0.9, 1.1)
    the search stopped at once and said "no interior maximum"."""
    from hbm import periodic_peak

    s, contacts = _jenkins()
    with pytest.raises(ValueError, match=rf"^xtol must be < \(bracket\[1\] - bracket\[0\]\) / 20 = 0.01 \(.*\), got "
                                         rf"xtol={xtol!r} with bracket=\(0.9, 1.1\)$"):
        periodic_peak(s, contacts, bracket=(0.9, 1.1), xtol=xtol, harmonics=3)


@pytest.mark.parametrize("kwargs", [dict(ramp_cycles=1e9), dict(ramp_cycles=5.0, max_cycles=4)])
def test_the_numerical_bar_refuses_a_ramp_longer_than_its_cycle_budget(kwargs):
    """The ramp runs before the budget of cycles after it; a ramp of 1e9 cycles ran without bound."""
    from contact_models import Bar, UniformLoad
    from contact_models.numerical import NumericalMicroslip

    with pytest.raises(ValueError, match=r"^ramp_cycles must be <= max_cycles .* got ramp_cycles="):
        NumericalMicroslip(Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3),
                           UniformLoad(N=100.0), **kwargs)


@pytest.mark.parametrize("kw, message", [
    # before: TypeError "unhashable type: 'list'" while counting the balance's DOFs, and numpy's "truth value of an
    # array is ambiguous" for the model
    (dict(response_dof=[0]), r"^response_dof must be a DOF index in 0..0, got response_dof=\[0\]$"),
    (dict(response_dof=np.zeros((2, 2))), r"^response_dof must be a DOF index in 0..0, got response_dof=array"),
    (dict(model=np.array(["given", "peak"])), r"^model must be one of 'given', 'peak', 'auto', got model=array"),
])
def test_a_response_dof_or_model_that_is_an_array_is_refused_by_name(kw, message):
    from contact_models import Macroslip
    from hbm import Blade, frequency_response

    with pytest.raises(ValueError, match=message):
        frequency_response(Blade(mass=1.0, stiffness=1.0e4, damping=2.0, force=1.0), Macroslip(1e3, 0.5),
                           omega_range=(90.0, 110.0), **kw)
