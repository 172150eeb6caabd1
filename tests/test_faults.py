"""Faults inside a solve and bad input a first round left open: a user's element that raises midway through
a curve ends the run keeping the curve, the message naming the element and where it was asked."""

import math
import re
import warnings

import numpy as np
import pytest

from contact_models import AccuracyWarning, ContactElement, Macroslip
from contact_models.macroslip import jenkins_fourier
from hbm import Blade, Contact, Structure, frequency_response, nonlinear_modes
from hbm.continuation import Status, continuation

K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
F = [0.0, 0.0, 0.01]
#: The amplitude (m) above which the spoilt elements below fail: past slip (0.02), on the way up to the peak.
AT = 0.03


class _Stop(Exception):
    pass


class Spoilt(ContactElement):
    """The Jenkins element (stiffness 1, slip force 0.02), written by a user, failing in one way above AT."""

    frequency_dependent = False

    def __init__(self, mode):
        self.mode, self.jen = mode, Macroslip(1.0, 0.02)

    def __repr__(self):
        return f"{type(self).__name__}({self.mode!r})"

    def _fail(self, a):
        if a > AT:
            if self.mode == "raise":
                raise _Stop("state lost")
            if self.mode == "divide":
                return 1 / 0
        return None

    def _fourier_derivatives(self, a, omega, rtol):
        self._fail(float(np.max(a, initial=0.0)))
        return jenkins_fourier(1.0, 0.02, a)

    def _stuck_stiffness(self, omega):
        return 1.0

    def _slip_amplitude(self, omega):
        return 0.02

    def _hysteresis(self, a, omega, n):
        return self.jen.hysteresis(a, omega, n=n)


class SpoiltLaw(Spoilt):
    """:class:`Spoilt` with its time law, failing there too (the multi-harmonic balance's)."""

    has_time_law = True

    def _periodic_force(self, x, omega):
        self._fail(0.5 * float(np.ptp(x)))
        return self.jen.periodic_force(x, omega)


def _blade():
    return Blade(mass=1.0, stiffness=1.0, damping=0.004, force=0.01)


def _solve(system, element, **kw):
    contacts = element if isinstance(system, Blade) else [Contact(element, dof=0)]
    w = (0.6, 1.8) if isinstance(system, Blade) else (0.3, 0.8)
    with pytest.warns(AccuracyWarning, match=r"the branch stopped at omega = .*the residual raised an exception"):
        return frequency_response(system, contacts, omega_range=w, **kw)


# ---------------------------------------------------------------- an element that raises midway: the curve kept
@pytest.mark.parametrize("kw", [dict(harmonics=1, tol=None), dict()])
def test_an_element_that_raises_midway_ends_the_run_keeping_the_curve_before(kw):
    frf = _solve(_blade(), Spoilt("raise"), **kw)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning)
        ref = frequency_response(_blade(), Spoilt("never"), omega_range=(0.6, 1.8), **kw)  # the same element, sound
    assert not frf.success and frf.status == Status.RESIDUAL_RAISED
    assert 10 < len(frf) < len(ref)
    assert float(np.max(frf.amplitude)) <= AT < float(np.max(ref.amplitude))
    np.testing.assert_allclose(frf.amplitude, ref.amplitude[:len(frf)], rtol=1e-9)  # the same points, kept
    assert re.search(r"\(_Stop: state lost \(in element=Spoilt\('raise'\): Spoilt._fourier_derivatives\(a, omega, "
                     r"rtol\) at a=0.03\d* m, omega=1.\d* rad/s\)\); the branch stops at omega = 1.\d* rad/s",
                     frf.message), frf.message
    assert np.all(np.isfinite(frf.amplitude)) and frf.peak().amplitude == float(np.max(frf.amplitude))


def test_an_element_whose_time_law_raises_in_the_multi_harmonic_balance_keeps_the_curve():
    s = Structure(np.eye(3), 0.004 * K, K, force=F)
    frf = _solve(s, SpoiltLaw("raise"), harmonics=3, tol=None)
    assert not frf.success and frf.status == Status.RESIDUAL_RAISED and len(frf) > 10
    assert re.search(r"_Stop: state lost \(in element=SpoiltLaw\('raise'\): SpoiltLaw._periodic_force\(x, omega\) at "
                     r"omega=0.4\d*, x of shape \(\d+,\) in \[-0.03\d*, 0.03\d*\]\)", frf.message), frf.message
    assert np.all(np.isfinite(frf.amplitude))


def test_an_element_that_divides_by_zero_is_named_in_the_failed_step():
    with pytest.warns(AccuracyWarning):
        frf = frequency_response(_blade(), Spoilt("divide"), omega_range=(0.6, 1.8), harmonics=1, tol=None)
    assert not frf.success and frf.status == Status.STEP_TOO_SMALL and len(frf) > 10
    assert re.search(r"the residual failed: division by zero \(in element=Spoilt\('divide'\): "
                     r"Spoilt._fourier_derivatives\(a, omega, rtol\) at a=0.03\d* m, omega=1.\d* rad/s\)",
                     frf.message), frf.message


def test_a_public_call_of_a_raising_element_raises_its_own_exception_naming_the_element():
    with pytest.raises(_Stop, match="state lost") as info:
        Spoilt("raise").fourier(np.array([0.02, 0.04]), 1.0)
    assert info.value.__notes__ == ["in element=Spoilt('raise'): Spoilt._fourier_derivatives(a, omega, rtol) at "
                                    "a in [0.02, 0.04] m, omega=1 rad/s"]


def test_nonlinear_modes_keep_the_branch_before_an_element_that_raises():
    s = Structure(np.eye(3), 0.004 * K, K, force=F)
    modes = nonlinear_modes(s, [Contact(SpoiltLaw("raise"), dof=0)], amplitude_range=(1e-3, 10.0), harmonics=3)
    assert not modes.success and len(modes) > 5 and np.all(np.isfinite(modes.omega))
    assert "the residual raised an exception beyond the last point" in modes.message
    assert "_Stop: state lost (in element=SpoiltLaw('raise'): SpoiltLaw._periodic_force(x, omega)" in modes.message


# ---------------------------------------------------------------- the continuation core
def _circle_raising_past(x_min):
    def circle(y):  # x^2 + lam^2 = 1, traced from (1, 0) towards lam = 0.9: x falls
        if y[0] < x_min:
            raise KeyError("outside the table")
        return np.array([y[0] ** 2 + y[1] ** 2 - 1.0]), np.array([[2.0 * y[0], 2.0 * y[1]]])

    return circle


def test_the_continuation_keeps_its_points_when_the_residual_raises_after_the_first():
    run = continuation(_circle_raising_past(0.8), [1.0, 0.0], parameter=1, bounds=(-0.95, 0.95))
    assert run.status == Status.RESIDUAL_RAISED and not run.success and len(run.y) > 2
    assert run.message == ("the residual raised an exception beyond the last point, which ends the branch "
                           "(KeyError: 'outside the table')")
    assert np.all(run.y[:, 0] >= 0.8) and np.allclose(np.hypot(run.y[:, 0], run.y[:, 1]), 1.0, atol=1e-9)


def test_the_continuation_raises_what_the_residual_raises_at_the_start():
    with pytest.raises(KeyError, match="outside the table"):
        continuation(_circle_raising_past(2.0), [1.0, 0.0], parameter=1, bounds=(-0.95, 0.95))


# ---------------------------------------------------------------- a reduced structure: its modal coordinates
def _reduced():
    n = 6
    Kc = 2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    Kc[-1, -1] = 1.0
    f = np.zeros(n)
    f[3] = 0.01  # on a DOF not kept: the reduced force has entries on the modal coordinates too
    s = Structure(np.eye(n), 0.004 * Kc, Kc, force=f)
    return s, s.reduce([0, 5], modes=4)  # every mode: exact


def test_a_contact_on_a_modal_coordinate_of_a_reduced_structure_is_refused_by_name():
    _, r = _reduced()
    with pytest.raises(ValueError, match=r"^dof must be a kept DOF of the reduced structure, in 0..1 \(its DOFs from "
                                         r"2 on are modal coordinates; reduced.dof\(i\) is original DOF i's\), got "
                                         r"dof=2 in Contact\(Macroslip\(stiffness=1.0, slip_force=0.02\), dof=2\)$"):
        frequency_response(r, [Contact(Macroslip(1.0, 0.02), dof=2)], omega_range=(0.2, 0.6), harmonics=3, tol=None)
    with pytest.raises(ValueError, match=r"^dof must be a kept DOF .* got dof=4 in Contact\(.*dofs=\(0, 4\)\)$"):
        nonlinear_modes(r, [Contact(Macroslip(1.0, 0.02), dofs=(0, 4))], amplitude_range=(1e-3, 1.0))


def test_a_response_on_a_modal_coordinate_is_refused_and_the_default_is_a_kept_dof():
    s, r = _reduced()
    assert int(np.argmax(np.abs(r.force))) == 2  # the largest reduced force is on a modal coordinate
    contacts = [Contact(Macroslip(1.0, 0.02), dof=0)]
    with pytest.raises(ValueError, match=r"^response_dof must be a kept DOF of the reduced structure, in 0..1 .*got "
                                         r"response_dof=3$"):
        frequency_response(r, contacts, omega_range=(0.2, 0.6), harmonics=3, tol=None, response_dof=3)
    frf = frequency_response(r, contacts, omega_range=(0.2, 0.6), harmonics=3, tol=None)
    full = frequency_response(s, contacts, omega_range=(0.2, 0.6), harmonics=3, tol=None, response_dof=5)
    assert r.response_dof() == 1 == r.dof(5)  # the kept DOF of the largest force: original DOF 5
    assert frf.peak().amplitude == pytest.approx(full.peak().amplitude, rel=1e-6)  # a displacement, not a mode's


# ---------------------------------------------------------------- the shooting reference takes contacts as frf does
def test_the_periodic_reference_takes_one_contact_or_a_bare_element_and_refuses_the_rest_by_name():
    from hbm import periodic_response

    blade = _blade()
    bare = periodic_response(blade, Macroslip(1.0, 0.02), omega=1.0)
    listed = periodic_response(blade, [Contact(Macroslip(1.0, 0.02), dof=0)], omega=1.0)
    one = periodic_response(blade, Contact(Macroslip(1.0, 0.02), dof=0), omega=1.0)
    np.testing.assert_array_equal(bare.harmonics, listed.harmonics)
    np.testing.assert_array_equal(one.harmonics, listed.harmonics)
    s = Structure(np.eye(3), 0.004 * K, K, force=F)
    with pytest.raises(ValueError, match=r"^a bare element attaches only to a one-DOF system; give "
                                         r"hbm.Contact\(element, dof=...\) for a structure of 3 DOFs, got "
                                         r"contacts=Macroslip\(stiffness=1.0, slip_force=0.02\)$"):
        periodic_response(s, Macroslip(1.0, 0.02), omega=0.5)
    for bad in (5, "jenkins", {"dof": 0}):
        with pytest.raises(ValueError, match=rf"^contacts must be a sequence of hbm.Contact .*got "
                                             rf"contacts={re.escape(repr(bad))}$"):
            periodic_response(s, bad, omega=0.5)


# ---------------------------------------------------------------- a study's designs: dicts of points, named
def test_designs_and_a_study_refuse_what_is_not_a_dict_of_points_by_name():
    from hbm.study import Study, combine, grid, samples, uniform

    with pytest.raises(ValueError, match=r"^axes must be a dict of parameter name to its values, got axes=\[1, 2\]$"):
        grid([1, 2])
    with pytest.raises(ValueError, match=r"^distributions must be a dict of parameter name to a Distribution, got "
                                         r"distributions=\[1, 2\]$"):
        samples(3, [1, 2], seed=1)
    with pytest.raises(ValueError, match=r"^second must be a sequence of points .*got second=5$"):
        combine(grid({"a": [1.0]}), 5)
    with pytest.raises(ValueError, match=r"^points must be a sequence of points .*got points='abc'$"):
        Study(lambda p: p, "abc")
    with pytest.raises(ValueError, match=r"^points\[1\] must be a dict of parameter name to value, got points\[1\]=3$"):
        Study(lambda p: p, [{"a": 1.0}, 3])
    assert len(combine(grid({"a": [1.0, 2.0]}), samples(3, {"b": uniform(0.0, 1.0)}, seed=1))) == 6


# ---------------------------------------------------------------- an element's scalar answers, checked
class Stated(Spoilt):
    """A sound Jenkins element whose stuck stiffness or slip amplitude is stated wrongly."""

    def __init__(self, k=1.0, a_min=0.02):
        super().__init__("never")
        self.k, self.a_min = k, a_min

    def __repr__(self):
        return f"Stated(k={self.k!r}, a_min={self.a_min!r})"

    def _stuck_stiffness(self, omega):
        return self.k

    def _slip_amplitude(self, omega):
        return self.a_min


def test_a_nan_or_a_negative_scalar_answer_of_an_element_is_named_not_returned():
    from contact_models.base import ElementContractError, ElementOutputError

    with pytest.raises(ElementOutputError, match=r"^element=Stated\(k=nan, a_min=0.02\): Stated._stuck_stiffness"
                                                 r"\(omega\) returned nan \(not a number\) at omega=0.0$"):
        Stated(k=float("nan")).stuck_stiffness()
    with pytest.raises(ElementContractError, match=r"^element=Stated\(k=1.0, a_min=-1.0\): Stated._slip_amplitude"
                                                   r"\(omega\) must return an amplitude >= 0 \(m\), got -1.0 at "
                                                   r"omega=2.0$"):
        Stated(a_min=-1.0).slip_amplitude(2.0)
    with pytest.raises(ElementContractError, match=r"^element=Stated\(k='stiff', a_min=0.02\): "
                                                   r"Stated._stuck_stiffness\(omega\) must return a real number, got "
                                                   r"str 'stiff'$"):
        Stated(k="stiff").stuck_stiffness()
    with pytest.raises(ElementContractError, match=r"^element=Stated\(k=1.0, a_min=-1.0\): Stated._slip_amplitude"):
        frequency_response(_blade(), Stated(a_min=-1.0), omega_range=(0.6, 1.8), harmonics=1, tol=None)
    assert Stated(a_min=math.inf).slip_amplitude() == math.inf and Stated(k=math.inf).stuck_stiffness() == math.inf


@pytest.mark.parametrize("method, kw, hook, bad", [
    ("linear_coefficients", {"k": "stiff"}, "_stuck_stiffness", "str 'stiff'"),
    ("linear_amplitude", {"a_min": "small"}, "_slip_amplitude", "str 'small'"),
    ("reference_amplitude", {"a_min": [0.02]}, "_slip_amplitude", "a list of 1"),
])
def test_the_defaults_built_on_a_scalar_hook_check_its_answer_as_the_hook_itself_is_checked(method, kw, hook, bad):
    """The defaults of _linear_coefficients, _linear_amplitude and _reference_amplitude took float() of the user's
    _stuck_stiffness or _slip_amplitude: a string raised numpy's 'could not convert string to float', not the
    contract error that stuck_stiffness() and slip_amplitude() raise for it."""
    from contact_models.base import ElementContractError

    el = Stated(**kw)
    with pytest.raises(ElementContractError, match=rf"^element={re.escape(repr(el))}: Stated.{hook}\(omega\) must "
                                                   rf"return a real number, got {re.escape(bad)}$"):
        getattr(el, method)(0.5)
    with pytest.raises(ElementContractError, match=rf"Stated.{hook}\(omega\) must return a real number"):
        frequency_response(_blade(), el, omega_range=(0.6, 1.8), harmonics=1, tol=None)


# ---------------------------------------------------------------- an element that raises in the error estimate
class Coarse(Spoilt):
    """A sound Jenkins element that raises where it is asked at a tighter rtol than ``rtol``: what the error
    estimate does after the curve (its element source, at rtol / 100)."""

    def __init__(self, rtol=0.0):
        super().__init__("never")
        self.rtol = rtol

    def __repr__(self):
        return f"{type(self).__name__}()"

    def _fourier_derivatives(self, a, omega, rtol):
        if rtol < self.rtol:
            raise _Stop("no table that fine")
        return jenkins_fourier(1.0, 0.02, a)


class CoarseLaw(SpoiltLaw):
    """The same with its time law, raising on more samples than ``samples``: the estimate's balance at 2H + 1."""

    def __init__(self, samples=10**9):
        super().__init__("never")
        self.samples = samples

    def __repr__(self):
        return f"{type(self).__name__}()"

    def _periodic_force(self, x, omega):
        if x.shape[0] > self.samples:
            raise _Stop("no table that fine")
        return self.jen.periodic_force(x, omega)


def _estimate_raised(frf, ref, name, hook):
    assert frf.status == ref.status == Status.REACHED_END and frf.success  # the curve traced to the end, kept
    np.testing.assert_array_equal(frf.amplitude, ref.amplitude)
    assert np.all(np.isinf(frf.error_estimate)) and np.all(np.isfinite(ref.error_estimate))  # unknown, not NaN
    assert not np.any(np.isnan(frf.error_estimate)) and not frf.peak().converged
    assert re.search(rf"the error estimate raised an exception \(_Stop: no table that fine \(in element={name}\(\): "
                     rf"{name}.{hook}.*\)\): it is unknown \(inf\) at {len(frf)} of {len(frf)} points "
                     r"\(omega = [0-9.]+ to [0-9.]+ rad/s\); the points are kept", frf.accuracy_warning), \
        frf.accuracy_warning
    assert f"the error estimate raised an exception (_Stop: no table that fine (in element={name}()" in frf.message


def test_an_element_that_raises_in_the_error_estimate_keeps_the_curve_its_estimate_unknown():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning)
        ref = frequency_response(_blade(), Coarse(), omega_range=(0.6, 1.8), harmonics=1)
    with pytest.warns(AccuracyWarning, match=r"the error estimate raised an exception"):  # rtol / 100 in the estimate
        frf = frequency_response(_blade(), Coarse(rtol=ref.rtol), omega_range=(0.6, 1.8), harmonics=1)
    _estimate_raised(frf, ref, "Coarse", r"_fourier_derivatives\(a, omega, rtol\) at a=0.0\d* m")


@pytest.mark.parametrize("kw", [dict(harmonics=3), dict()])
def test_an_element_whose_time_law_raises_in_the_multi_harmonic_estimate_keeps_the_curve(kw):
    s = Structure(np.eye(3), 0.004 * K, K, force=F)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning)
        ref = frequency_response(s, [Contact(CoarseLaw(), dof=0)], omega_range=(0.3, 0.8), harmonics=3)
    with pytest.warns(AccuracyWarning, match=r"the error estimate raised an exception"):  # 2H + 1 in the estimate
        frf = frequency_response(s, [Contact(CoarseLaw(samples=ref.n_t), dof=0)], omega_range=(0.3, 0.8), **kw)
    if kw:
        _estimate_raised(frf, ref, "CoarseLaw", r"_periodic_force\(x, omega\) at omega=")
    else:  # the balance's own start (H, samples): the estimate unknown, so no window is refined
        assert frf.success and len(frf.segments) == 1 and np.all(np.isinf(frf.error_estimate))
        assert "the error estimate raised an exception (_Stop: no table that fine" in frf.accuracy_warning


def test_a_contract_error_in_the_error_estimate_still_raises_at_once():
    from contact_models.base import ElementContractError

    class Wrong(CoarseLaw):
        def _periodic_force(self, x, omega):
            f, df = self.jen.periodic_force(x, omega)
            return (f, df) if x.shape[0] <= self.samples else (f[:-1], df)  # a force of the wrong shape

    s = Structure(np.eye(3), 0.004 * K, K, force=F)
    with pytest.raises(ElementContractError, match=r"Wrong._periodic_force\(x, omega\) must return"):
        frequency_response(s, [Contact(Wrong(samples=512), dof=0)], omega_range=(0.3, 0.8), harmonics=3)


class Misshapen(Coarse):
    """A Jenkins element that answers one value too few where it is asked at a tighter rtol than ``rtol`` (the
    error estimate's element source, at rtol / 100), or raises an ordinary ``ValueError`` there (``plain``)."""

    def __init__(self, rtol=0.0, plain=False):
        super().__init__(rtol)
        self.plain = plain

    def _fourier_derivatives(self, a, omega, rtol):
        out = jenkins_fourier(1.0, 0.02, a)
        if rtol >= self.rtol:
            return out
        if self.plain:
            raise ValueError("no table that fine")
        return tuple(np.atleast_1d(v)[:-1] for v in out)


def _element_source_case(system):
    if isinstance(system, Blade):
        return (lambda el: el), (0.6, 1.8)
    return (lambda el: [Contact(el, dof=0)]), (0.3, 0.8)


_ONE_DOF_AND_CONDENSED = dict(argvalues=[_blade(), Structure(np.eye(3), 0.004 * K, K, force=F)],
                              ids=["one_dof", "condensed"])


@pytest.mark.parametrize("system", **_ONE_DOF_AND_CONDENSED)
def test_a_contract_error_in_the_element_source_of_the_estimate_raises_at_once(system):
    from contact_models.base import ElementContractError

    contacts, w = _element_source_case(system)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning)
        ref = frequency_response(system, contacts(Misshapen()), omega_range=w, harmonics=1)
    assert ref.success and ref.rtol == 1e-6  # the trace's rtol: the estimate's element source asks at 1e-8
    with pytest.raises(ElementContractError, match=r"^element=Misshapen\(\): Misshapen._fourier_derivatives\(a, omega, "
                                                   r"rtol\) must return f_s with one value per amplitude \(1\), got "
                                                   r"f_s of shape \(0,\)$"):
        frequency_response(system, contacts(Misshapen(rtol=ref.rtol)), omega_range=w, harmonics=1)


@pytest.mark.parametrize("system", **_ONE_DOF_AND_CONDENSED)
def test_an_ordinary_failure_in_the_element_source_of_the_estimate_keeps_the_bound(system):
    contacts, w = _element_source_case(system)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning)
        ref = frequency_response(system, contacts(Misshapen()), omega_range=w, harmonics=1)
        frf = frequency_response(system, contacts(Misshapen(rtol=ref.rtol, plain=True)), omega_range=w, harmonics=1)
    assert frf.success and frf._estimate_failed is None  # the estimate ran: the element source took its bound
    np.testing.assert_array_equal(frf.amplitude, ref.amplitude)
    got, sound = frf.error_sources["element"], ref.error_sources["element"]
    if isinstance(system, Blade):  # rtol |p|, rtol |q| of the element's stiffness through the balance
        slipping = sound > 0.0
        assert np.all(got[slipping] > sound[slipping]) and 1e-7 < float(np.max(got)) < 1e-4
    else:
        assert float(np.max(got)) == ref.rtol and float(np.max(sound)) < 1e-12  # the bound rtol, where it moves
    for s in ("harmonics", "sampling", "model"):
        np.testing.assert_array_equal(frf.error_sources[s], ref.error_sources[s])


class MisshapenAbove(SpoiltLaw):
    """A Jenkins element with its time law whose harmonic force has one coefficient too few above ``H``
    harmonics (the error estimate's harmonics source, at 2H + 1)."""

    def __init__(self, H):
        super().__init__("never")
        self.H = H

    def __repr__(self):
        return f"MisshapenAbove(H={self.H})"

    def _harmonic_force(self, X, omega, n_t, rtol):
        Fh, J, Fw = super()._harmonic_force(X, omega, n_t, rtol)
        return (Fh, J, Fw) if X.size <= 2 * self.H + 1 else (Fh[:-1], J, Fw)


def test_a_contract_error_in_the_harmonics_source_of_the_estimate_raises_at_once():
    from contact_models.base import ElementContractError

    s = Structure(np.eye(3), 0.004 * K, K, force=F)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning)
        ref = frequency_response(s, [Contact(MisshapenAbove(H=7), dof=0)], omega_range=(0.3, 0.8), harmonics=3)
    assert ref.success and np.all(np.isfinite(ref.error_estimate))  # sound up to the estimate's 7 harmonics
    with pytest.raises(ElementContractError, match=r"^element=MisshapenAbove\(H=3\): MisshapenAbove._harmonic_force"
                                                   r".* must return F of shape \(15,\).*got F of shape \(14,\)"):
        frequency_response(s, [Contact(MisshapenAbove(H=3), dof=0)], omega_range=(0.3, 0.8), harmonics=3)


# ---------------------------------------------------------------- an element that raises while the peak is located
class Armed(Spoilt):
    """A sound Jenkins element that fails once armed: the callback arms it at the point that ends the range, so
    the trace (and the estimate) are done and locating the peak is what asks it next.  ``wrong``: it answers
    with one value too few instead of raising (a contract error)."""

    def __init__(self, wrong=False):
        super().__init__("never")
        self.armed, self.wrong = False, wrong

    def __repr__(self):
        return f"{type(self).__name__}()"

    def arm_at(self, w1):
        def callback(point):
            if point.omega >= w1:
                self.armed = True
        return callback

    def _fourier_derivatives(self, a, omega, rtol):
        out = jenkins_fourier(1.0, 0.02, a)
        if self.armed:
            if not self.wrong:
                raise RuntimeError("state lost")
            return tuple(np.atleast_1d(v)[:-1] for v in out)
        return out


class ArmedLaw(Armed):
    """:class:`Armed` with its time law, failing there too once armed (the multi-harmonic balance's)."""

    has_time_law = True

    def _periodic_force(self, x, omega):
        f, df = self.jen.periodic_force(x, omega)
        if self.armed:
            if not self.wrong:
                raise RuntimeError("state lost")
            return f[:-1], df
        return f, df


def _armed_case(case):
    """``(system, contacts of an element, omega_range, options, element class, its hook)``."""
    law = r"_periodic_force\(x, omega\) at omega=[0-9.]+, x of shape"
    if case == "condensed":
        s = Structure(np.eye(3), 0.004 * K, K, force=F)
        return s, (lambda el: [Contact(el, dof=0)]), (0.3, 0.8), dict(harmonics=3, tol=None), ArmedLaw, law
    if case == "default":  # tol's default: the estimate, H chosen along the curve (windows), then the peak
        return _blade(), (lambda el: el), (0.6, 1.8), {}, ArmedLaw, law
    return _blade(), (lambda el: el), (0.6, 1.8), dict(harmonics=1, tol=None), Armed, \
        r"_fourier_derivatives\(a, omega, rtol\) at a=[0-9.]+ m, omega=[0-9.]+ rad/s"


@pytest.mark.parametrize("case", ["one_dof", "condensed", "default"])
def test_an_element_that_raises_while_the_peak_is_located_keeps_the_curve_and_the_sampled_peak(case):
    system, contacts, w, kw, kind, hook = _armed_case(case)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning)
        ref = frequency_response(system, contacts(kind()), omega_range=w, **kw)  # never armed: sound
    assert ref.peak().interior and ref.peak_refined and ref.peak().converged
    el = kind()
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        frf = frequency_response(system, contacts(el), omega_range=w, callback=el.arm_at(w[1]), **kw)
    assert el.armed and frf.success and frf.status == Status.REACHED_END  # the traced points kept, as they are
    np.testing.assert_array_equal(frf.amplitude, ref.amplitude)
    i = int(np.argmax(frf.amplitude))
    near = np.zeros(len(frf), dtype=bool)
    near[i - 1:i + 2] = True  # the located peak's Newton part (ref) in place of the parabola's bound (frf) there
    np.testing.assert_array_equal(frf.error_estimate[~near], ref.error_estimate[~near])
    if frf.tol is not None:
        assert np.all(frf.error_estimate[near] > ref.error_estimate[near])
    pk = frf.peak()
    assert (pk.omega, pk.amplitude) == (frf.omega[i], frf.amplitude[i]) and 0 < i < len(frf) - 1
    assert pk.interior and not pk.converged and not frf.peak_refined  # the largest traced point, not located
    assert pk.amplitude <= ref.peak().amplitude <= pk.amplitude * (1.0 + 1e-3)
    assert re.fullmatch(rf"the maximum could not be located between points: locating it near omega = "
                        rf"{frf.omega[i]:.6g} rad/s raised an exception \(RuntimeError: state lost \(in "
                        rf"element={kind.__name__}\(\): {kind.__name__}.{hook}.*\)\); the largest sampled point is "
                        rf"given", pk.message), pk.message
    accuracy = [m for m in said if issubclass(m.category, AccuracyWarning)]
    assert len(accuracy) == 1 and pk.message in str(accuracy[0].message) == frf.accuracy_warning
    assert [m for m in said if not issubclass(m.category, AccuracyWarning)] == []


@pytest.mark.parametrize("case", ["one_dof", "condensed"])
def test_a_contract_error_while_the_peak_is_located_still_raises(case):
    from contact_models.base import ElementContractError

    system, contacts, w, kw, kind, hook = _armed_case(case)
    el = kind(wrong=True)
    with pytest.raises(ElementContractError, match=rf"^element={kind.__name__}\(\): {kind.__name__}."
                                                   rf"{hook.split(' at ')[0]} must return f(_s)? "):
        frequency_response(system, contacts(el), omega_range=w, callback=el.arm_at(w[1]), **kw)
    assert el.armed


# ---------------------------------------------------------------- a contract error where a start or its reason is sought
#: The rigid slider (slip force 0.005) from DOF 1 of two unit masses to ground, the force 0.01 on DOF 0: at 0.7 rad/s
#: only the describing functions' equivalent linear start finds the branch (tests/test_rigid_slider_stick.py).
RIGID_PAIR = Structure(np.eye(2), 0.004 * np.eye(2), np.array([[2.0, -1.0], [-1.0, 2.0]]), force=[0.01, 0.0])


class FarSlider(Macroslip):
    """The rigid slider, failing above 100 m: amplitudes only the equivalent start's grid asks (the branch
    stays below 0.5 m); ``wrong``: one value too few (a contract error), else an ordinary ValueError."""

    def __init__(self, wrong):
        super().__init__(math.inf, 0.005)
        self.wrong = wrong

    def __repr__(self):
        return f"FarSlider(wrong={self.wrong})"

    def _fourier_derivatives(self, a, omega, rtol):
        out = super()._fourier_derivatives(a, omega, rtol)
        if float(np.max(a, initial=0.0)) <= 100.0:
            return out
        if not self.wrong:
            raise ValueError("no table that far")
        return tuple(np.atleast_1d(v)[:-1] for v in out)


def test_a_contract_error_in_the_equivalent_start_raises_at_once():
    from contact_models.base import ElementContractError

    with pytest.raises(ElementContractError, match=r"^element=FarSlider\(wrong=True\): FarSlider._fourier_derivatives"
                                                   r"\(a, omega, rtol\) must return f_s with one value per amplitude "
                                                   r"\(1\), got f_s of shape \(0,\)$"):
        frequency_response(RIGID_PAIR, [Contact(FarSlider(wrong=True), dof=1)], omega_range=(0.7, 1.85), tol=1e-3)


def test_an_ordinary_failure_in_the_equivalent_start_is_still_no_start():
    with pytest.warns(AccuracyWarning):
        frf = frequency_response(RIGID_PAIR, [Contact(FarSlider(wrong=False), dof=1)], omega_range=(0.7, 1.85),
                                 tol=1e-3)
    assert frf.status == Status.START_FAILED and len(frf) == 0
    assert frf.message.startswith("Newton's method did not converge at the starting point")


class OddRigid(Macroslip):
    """The rigid slider whose linear coefficients are a string above 1.5 rad/s: asked only for the reason the
    branch from 1 rad/s stops near 1.89 rad/s (where the slider starts to stick)."""

    def __init__(self):
        super().__init__(math.inf, 0.005)

    def __repr__(self):
        return "OddRigid()"

    def _linear_coefficients(self, omega):
        return ("rigid", 0.0) if omega > 1.5 else (math.inf, 0.0)


def test_a_contract_error_where_the_stuck_reason_is_sought_raises_at_once():
    from contact_models.base import ElementContractError

    with pytest.raises(ElementContractError, match=r"^element=OddRigid\(\): OddRigid._linear_coefficients\(omega\) "
                                                   r"must return a real number, got str 'rigid'"):
        frequency_response(RIGID_PAIR, [Contact(OddRigid(), dof=1)], omega_range=(1.0, 2.0), tol=1e-3)


# ---------------------------------------------------------------- a rippled peak: every candidate tried
def _scan_peak(system, contact, n_t, H, omegas, guess, r):
    """The largest response amplitude of DOF ``dofs[r]`` over ``omegas`` (increasing), each point solved at its
    fixed omega by Newton's method on the balance (from the previous point's solution, the first from ``guess``):
    ``(omega, amplitude, solution)`` of the largest."""
    from hbm import HarmonicBalance

    hb = HarmonicBalance(system, [contact], harmonics=H, n_t=n_t)
    x, best = np.asarray(guess, dtype=float), (-1.0, -1.0, None)
    for w in omegas:
        for _ in range(30):
            R, J = hb.physical(np.append(x, w))
            dx = np.linalg.solve(J[:, :-1], -R)
            x = x + dx
            if np.linalg.norm(dx) <= 1e-13 * np.linalg.norm(x):
                break
        else:
            raise AssertionError(f"Newton did not converge at omega={w}")
        X = x.reshape(hb.na, hb.L)
        a = math.hypot(X[r, 1], X[r, 2])
        if a > best[1]:
            best = (float(w), a, x.copy())
    return best


def test_a_peak_whose_first_bracket_is_a_ripple_is_located_on_the_other_one():
    """The sampled Jenkins law at H = 3 ripples between the points: the zero of d(a^2)/ds between the
    maximum and the point before it lies below the sampled maximum, and the one after it is the peak.
    The reference: the same balance solved at fixed omega on ever finer grids around the maximum."""
    s = Structure(np.eye(3), 0.004 * K, K, force=F)
    c = Contact(SpoiltLaw("never"), dof=0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning)
        frf = frequency_response(s, [c], omega_range=(0.3, 0.8), harmonics=3, tol=None)
    pk, i = frf.peak(), int(np.argmax(frf.amplitude))
    assert pk.interior and pk.converged and frf.peak_refined and pk.message == ""
    assert pk.amplitude >= float(frf.amplitude[i])
    assert frf.omega[i - 1] < pk.omega < frf.omega[i + 1]
    dofs = [0, 2]  # the condensation DOFs: the contact's and the forced (response) DOF
    guess = np.concatenate([[v[0].real, *(p for h in v[1:] for p in (h.real, -h.imag))]
                            for v in (frf.coefficients(d)[i - 1] for d in dofs)])
    lo, hi, n = float(frf.omega[i - 1]), float(frf.omega[i + 1]), 41
    for _ in range(3):  # a grid, then two finer ones about its largest point
        w, a, x = _scan_peak(s, c, frf.n_t, 3, np.linspace(lo, hi, n), guess, 1)
        step = (hi - lo) / (n - 1)
        lo, hi, n, guess = w - step, w + step, 21, x
    assert abs(pk.amplitude / a - 1.0) <= frf.rtol, (pk, w, a)
    assert abs(pk.omega - w) <= 1e-5, (pk, w, a)  # 1e-5 rad/s off the top moves the amplitude by about rtol here
