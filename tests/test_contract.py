"""The element contract is enforced when a class is defined: the public methods of
``ContactElement`` are defined once, in the base (validation, broadcasting, the model-range
check), and an element implements the private hooks they call.  A class that overrides a public
method, or declares a time law it does not have, is refused with a TypeError naming the method.
"""

import inspect
import math
import warnings

import numpy as np
import pytest

import contact_models
from contact_models import Bar, ContactElement, ModelRangeWarning, TwoRegionMicroslip, UniformLoad
from contact_models.base import PUBLIC_HOOKS
from contact_models.quasi_static import StuckContact

BAR = dict(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)


def _element_classes():
    """Every public element class of ``contact_models`` (and ``StuckContact``, which hbm uses)."""
    found = [obj for name in contact_models.__all__ for obj in (getattr(contact_models, name),)
             if inspect.isclass(obj) and issubclass(obj, ContactElement) and obj is not ContactElement]
    return found + [StuckContact]


class _Linear:
    """The hooks of a linear spring k = 2 N/m, mixed into the test classes below."""

    def _fourier_derivatives(self, a, omega, rtol):
        return 2.0 * a, np.zeros_like(a), np.full_like(a, 2.0), np.zeros_like(a)

    def _stuck_stiffness(self, omega):
        return 2.0

    def _slip_amplitude(self, omega):
        return 1.0

    def _hysteresis(self, a, omega, n):
        x = a * np.sin(np.linspace(-0.5 * np.pi, 1.5 * np.pi, n))
        return x, 2.0 * x


def test_the_contract_table_names_methods_and_hooks_of_the_base():
    assert len(PUBLIC_HOOKS) == 15  # model_error, refined_model and harmonic_force_deferred joined the first twelve
    for name, hook in PUBLIC_HOOKS.items():
        assert name in ContactElement.__dict__ and hook.startswith("_") and hasattr(ContactElement, hook)


def test_overriding_fourier_is_refused_naming_the_method_and_the_hook():
    with pytest.raises(TypeError) as err:
        class Bad(_Linear, ContactElement):
            def fourier(self, a, omega=0.0, *, rtol=1e-6):
                return 0.0, 0.0
    msg = str(err.value)
    assert msg.startswith("Bad overrides fourier()")
    assert "implement the hook _fourier() instead" in msg


@pytest.mark.parametrize("name", sorted(PUBLIC_HOOKS))
def test_overriding_any_public_method_is_refused(name):
    with pytest.raises(TypeError, match=rf"Bad overrides {name}\(\).*implement the hook {PUBLIC_HOOKS[name]}\(\)"):
        type("Bad", (_Linear, ContactElement), {name: lambda self, *args, **kw: None})


def test_has_time_law_without_a_time_law_is_refused_naming_the_missing_methods():
    with pytest.raises(TypeError) as err:
        class NoLaw(_Linear, ContactElement):
            has_time_law = True
    msg = str(err.value)
    assert msg.startswith("NoLaw declares has_time_law = True but has no time law")
    assert "loading_curve() and _loading_slope()" in msg and "_periodic_force()" in msg


def test_half_a_masing_law_is_refused_naming_the_missing_hook():
    with pytest.raises(TypeError) as err:
        class HalfMasing(_Linear, ContactElement):
            has_time_law = True

            def loading_curve(self, x, omega=0.0):
                return 2.0 * np.asarray(x, dtype=float)
    assert "implement _loading_slope() (Masing" in str(err.value)
    assert "loading_curve() and" not in str(err.value)


def test_a_class_with_a_time_law_is_accepted_and_answers():
    class Spring(_Linear, ContactElement):
        has_time_law = True
        frequency_dependent = False

        def _periodic_force(self, x, omega):
            return 2.0 * x, 2.0 * np.eye(x.size)

    f, J = Spring().periodic_force([0.0, 1.0, 0.0, -1.0])
    assert f.tolist() == [0.0, 2.0, 0.0, -2.0] and np.trace(J) == 8.0
    F, dF, _ = Spring().harmonic_force([0.5, 0.0, 1.0, 0.0, 0.0], 1.0)  # H = 2: AFT of the law
    np.testing.assert_allclose(F, [1.0, 0.0, 2.0, 0.0, 0.0], atol=1e-15)
    np.testing.assert_allclose(dF, 2.0 * np.eye(5), atol=1e-15)


def test_a_time_law_left_undeclared_is_not_checked():
    class Plain(_Linear, ContactElement):
        pass

    assert Plain().fourier(0.5) == (1.0, 0.0)


@pytest.mark.parametrize("cls", _element_classes(), ids=lambda c: c.__name__)
def test_every_element_class_passes_the_contract(cls):
    """Each class inherits the public methods unchanged and implements a hook for each; one that
    declares a time law as a class attribute has one."""
    for name, hook in PUBLIC_HOOKS.items():
        assert getattr(cls, name) is getattr(ContactElement, name), name
        assert callable(getattr(cls, hook)), hook
    assert not inspect.isabstract(cls)
    assert (cls._fourier is not ContactElement._fourier
            or cls._fourier_derivatives is not ContactElement._fourier_derivatives)
    if getattr(cls, "has_time_law", False) is True:
        assert (cls._periodic_force is not ContactElement._periodic_force
                or cls._harmonic_force is not ContactElement._harmonic_force
                or (callable(getattr(cls, "loading_curve", None))
                    and cls._loading_slope is not ContactElement._loading_slope))


def test_the_registered_classes_are_all_found():
    names = sorted(c.__name__ for c in _element_classes())
    assert names == ["AllModeMicroslip", "AllModeMicroslip2D", "Contact2D", "Contact3D", "CubicSpring", "Gap", "Iwan",
                     "Macroslip", "NumericalMicroslip",
                     "PointContact",
                     "QuasiStatic", "RotatingPreload", "StuckContact", "ThreeRegionMicroslip", "TwoRegionMicroslip"]


def test_the_range_warning_comes_from_the_base_and_points_at_the_caller():
    """The model-range check runs in the base's public methods (the element's ``_check_range``
    hook) and its warning names the caller's line, for the float path and the array path."""
    bar = Bar(**BAR)
    two = TwoRegionMicroslip(bar, UniformLoad(N=100.0))
    a, w = 2.0 * 7.5e-7, 0.5 * bar.omega_c
    for args in ((a, w), (np.array([a]), np.array(w))):
        for method in (two.fourier, two.fourier_derivatives):
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                method(*args)
            assert [c.category for c in caught] == [ModelRangeWarning]
            assert caught[0].filename == __file__
    with warnings.catch_warnings(record=True) as caught:  # within 1 % at 0.06 omega_c: no warning
        warnings.simplefilter("always")
        two.fourier(a, 0.06 * bar.omega_c)
    assert caught == []


def test_harmonic_force_names_a_bad_shape_and_the_first_non_finite_coefficient():
    from contact_models import Macroslip

    el = Macroslip(1.0, 0.02)
    with pytest.raises(ValueError, match=r"^X must be of shape \('2H\+1',\) with 2H\+1 odd >= 3, got X with shape \(4,\)$"):
        el.harmonic_force(np.zeros(4), 1.0)
    with pytest.raises(ValueError, match=r"^X must be finite, got X\[2\]=nan$"):
        el.harmonic_force(np.array([0.0, 1.0, math.nan]), 1.0)
    with pytest.raises(ValueError, match=r"^X must be finite, got X\[1\]=inf$"):
        el.harmonic_force(np.array([0.0, math.inf, 0.0, 1.0, 1.0]), 1.0)


def test_periodic_force_names_a_bad_shape_and_the_first_non_finite_sample():
    from contact_models import Contact2D, Macroslip

    el = Macroslip(1.0, 0.02)
    with pytest.raises(ValueError, match=r"^x must be an array of shape \('n_t',\) with n_t >= 2 samples, "
                                         r"got x with shape \(2, 2\)$"):
        el.periodic_force(np.zeros((2, 2)))
    with pytest.raises(ValueError, match=r"^x must be finite, got x\[1\]=nan$"):
        el.periodic_force(np.array([0.0, math.nan, 0.0]))
    with pytest.raises(ValueError, match=r"^x must be finite, got x\[1, 0\]=inf$"):  # two components
        Contact2D(1.0, 1.0, 0.5, 1.0).periodic_force(np.array([[0.0, 1.0, 0.0], [math.inf, 0.0, 0.0]]))


@pytest.mark.parametrize("rtol", [0.0, 1.0, 2.0, -1e-3, math.nan])
def test_fourier_takes_a_relative_accuracy_in_0_1_only(rtol):
    two = TwoRegionMicroslip(Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3),
                             UniformLoad(N=100.0))
    pattern = r"^rtol must be (in \(0, 1\) \(a relative accuracy\)|finite), got rtol="
    for call in (lambda: two.fourier(1e-6, 100.0, rtol=rtol), lambda: two.fourier_derivatives(1e-6, 100.0, rtol=rtol),
                 lambda: two.fourier(np.array([1e-6, 2e-6]), 100.0, rtol=rtol),
                 lambda: two.harmonic_force(np.array([0.0, 1e-6, 0.0]), 100.0, rtol=rtol)):
        with pytest.raises(ValueError, match=pattern):
            call()


def test_amplitudes_and_frequencies_that_do_not_broadcast_are_named():
    from contact_models import Macroslip

    with pytest.raises(ValueError, match=r"^a and omega must broadcast against each other, got a with shape \(3,\) "
                                         r"and omega with shape \(2,\)$"):
        Macroslip(1.0, 0.02).fourier(np.ones(3), np.ones(2))


@pytest.mark.parametrize("a", ["1", True, [True, False], None])
def test_fourier_refuses_an_amplitude_that_is_not_a_number(a):
    from contact_models import Macroslip

    el = Macroslip(1.0, 0.5)
    for method in (el.fourier, el.fourier_derivatives, el.model_error):
        with pytest.raises(ValueError, match=r"^a must be a number or an array of numbers, got a="):
            method(a)
    with pytest.raises(ValueError, match=r"^omega must be a number or an array of numbers, got omega='1'$"):
        el.fourier(1.0, "1")


def test_model_error_parts_must_be_a_bool():
    from contact_models import Macroslip

    with pytest.raises(ValueError, match=r"^parts must be True or False, got parts='yes'$"):
        Macroslip(1.0, 0.5).model_error(1.0, parts="yes")


@pytest.mark.parametrize("n", [None, math.nan, math.inf, "401", 4])
def test_hysteresis_names_a_bad_number_of_points(n):
    from contact_models import Macroslip

    with pytest.raises(ValueError, match=rf"^n must be an integer >= 5, got n={n!r}$"):
        Macroslip(1.0, 0.5).hysteresis(1.0, n=n)


def test_the_time_laws_refuse_samples_that_are_not_real_numbers():
    from contact_models import Macroslip

    el = Macroslip(1.0, 0.5)
    for x in ("abc", ["a", "b"], np.array([0.0, 1j, 1.0, 0.5])):
        with pytest.raises(ValueError, match=r"^x must be a number or an array of numbers, got x="):
            el.periodic_force(x)
    with pytest.raises(ValueError, match=r"^x must be an array of shape \('n_t',\) with n_t >= 2 samples, "
                                         r"got x with shape \(\)$"):
        el.periodic_force(1.0)
    for X in (["a", "b", "c"], None, np.array([0.0, 1j, 1.0])):
        with pytest.raises(ValueError, match=r"^X must be a number or an array of numbers, got X="):
            el.harmonic_force(X, 1.0)
    with pytest.raises(ValueError, match=r"^X must be of shape \('2H\+1',\) with 2H\+1 odd >= 3, got X with shape \(\)$"):
        el.harmonic_force(0.0, 1.0)
