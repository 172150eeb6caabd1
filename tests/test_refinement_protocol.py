"""The refinement questions a solve may ask an element are declared on the contract, with defaults,
and ``hbm`` asks them directly: no capability probed by ``getattr``/``hasattr``, no element type
switched on in the solve path."""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest

import contact_models
from contact_models import AllModeMicroslip, Bar, ContactElement, CubicSpring, Macroslip, QuasiStatic, TwoRegionMicroslip, UniformLoad
from hbm import Blade, frequency_response

ROOT = Path(__file__).resolve().parent.parent
#: The questions of docs/extending.md, "Refinement", and their defaults on an element with nothing to refine.
DEFAULTS = {"exact_harmonics": False, "discretised": False, "at_top_rung": False, "refined_no_further": False,
            "harmonics_reach": 1}
CAPABILITIES = ("exact_harmonics", "discretised", "harmonics_reach", "model_name", "harmonics_law", "refined_model", "start_rung",
                "refined_rung", "at_top_rung", "refined_no_further", "harmonics_of", "for_balance")
#: The solve path: the modules between frequency_response and the elements.
SOLVE_PATH = ("hbm/frf.py", "hbm/adapt.py", "hbm/result.py", "hbm/curve.py", "hbm/continuation.py",
              "hbm/balance/errors.py", "hbm/balance/residual.py")

BAR = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)


def test_every_question_is_declared_on_the_contract():
    for name in CAPABILITIES:
        assert hasattr(ContactElement, name), name


def test_an_element_with_nothing_to_refine_keeps_the_defaults():
    jen = Macroslip(stiffness=2.0, slip_force=1.0, slider="from rest")
    for name, value in DEFAULTS.items():
        assert getattr(jen, name) is value, name
    assert jen.model_name == "Macroslip"
    assert jen.harmonics_law() is jen  # its own time law
    assert jen.refined_model() is None and jen.start_rung((1.0, 2.0)) is None
    assert jen.refined_rung(2.0, (1.0, 2.0)) is None and jen.harmonics_of(jen) is None
    assert jen.for_balance(7) is jen


@pytest.mark.parametrize("cls", [contact_models.Contact2D, contact_models.Contact3D], ids=lambda c: c.__name__)
def test_the_point_contacts_with_a_normal_load_keep_the_defaults(cls):
    """A point contact's time law is complete: nothing to refine but the balance's own H and n_t."""
    el = cls(kt=2.0, kn=1.0, mu=0.5, n0=1.0)
    for name, value in DEFAULTS.items():
        assert getattr(el, name) is value, name
    assert el.model_name == cls.__name__ and el.harmonics_law() is el and el.for_balance(7) is el
    assert el.refined_model() is None and el.start_rung((1.0, 2.0)) is None
    assert el.refined_rung(2.0, (1.0, 2.0)) is None and el.harmonics_of(el) is None


def test_the_single_mode_bar_answers_with_its_quasi_static_bar_and_the_all_mode_bar():
    two = TwoRegionMicroslip(BAR, UniformLoad(N=100.0))
    law = two.harmonics_law()
    assert isinstance(law, QuasiStatic) and law.has_time_law and not two.has_time_law
    a = 3.0 * two.slip_amplitude()
    assert law.fourier(a, 0.0) == two.fourier(a, 0.0)  # the same loop at omega = 0
    refined = two.refined_model()
    assert isinstance(refined, AllModeMicroslip) and refined.discretised and not two.discretised


@pytest.mark.parametrize("inner", [Macroslip(stiffness=np.inf, slip_force=0.05), CubicSpring(k3=1.0)],
                         ids=["rigid slider", "cubic spring"])
def test_a_quasi_static_element_claims_a_time_law_only_where_its_loading_curve_is_one(inner):
    """The rigid slider's loading curve is a step and a cubic spring has none: neither quasi-static element (nor one
    wrapped twice) has a time law, so H > 1 is refused by name (a time law claimed for them gives NaN in the rigid
    slider's Masing march and an AttributeError from the doubly wrapped cubic spring)."""
    blade = Blade.from_modal(frequency=1.0, damping_ratio=1e-2, mass=1.0, force=0.1)
    for el in (QuasiStatic(inner), QuasiStatic(QuasiStatic(inner))):
        assert el.has_time_law is False
        with pytest.raises(ValueError, match=r"harmonics must be 1 with QuasiStatic.*got harmonics=3"):
            frequency_response(blade, el, omega_range=(0.5, 1.5), harmonics=3)
    two = QuasiStatic(QuasiStatic(TwoRegionMicroslip(BAR, UniformLoad(N=100.0))))
    assert two.has_time_law is True  # the quasi-static bar's loading curve is Masing's, however often wrapped


def test_the_all_mode_bar_answers_with_its_rungs():
    el = AllModeMicroslip(BAR, UniformLoad(N=100.0))
    rung = el.start_rung((3.2e4, 4.4e4))
    assert (rung.cells, rung.harmonics) == (32, 7) and rung.model_name == "AllModeMicroslip(cells=32, H=7)"
    assert rung.exact_harmonics and rung.discretised and rung.harmonics_law() is rung
    assert rung.refined_rung() is None  # nothing estimated yet: no rung to predict from
    assert rung.for_balance(1) is rung and rung.for_balance(3).harmonics == 31 and rung.for_balance(7).harmonics == 31
    assert rung.harmonics_reach == 3  # its modes meet high harmonics of the drive


def _calls(path: Path):
    tree = ast.parse(path.read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in ("getattr", "hasattr"):
            yield node


@pytest.mark.parametrize("module", SOLVE_PATH)
def test_the_solve_path_probes_no_capability(module):
    """No ``getattr``/``hasattr`` naming one of the declared questions or an element's parameters."""
    probed = []
    for call in _calls(ROOT / module):
        names = [a.value for a in call.args if isinstance(a, ast.Constant) and isinstance(a.value, str)]
        probed += [n for n in names if n in CAPABILITIES or n in ("bar", "load", "cells", "harmonics")]
    assert probed == [], (module, probed)


def test_a_users_element_is_asked_the_same_questions():
    """A user's element that declares a harmonics stand-in is used for the harmonics estimate at H = 1:
    the same element with the stand-in's law gives the same harmonics source as the law itself."""

    class FirstHarmonicJenkins(ContactElement):
        """Jenkins by its describing function only, with the time-law Jenkins as its harmonics stand-in."""

        frequency_dependent = False

        def __init__(self):
            self.law = Macroslip(stiffness=1.0, slip_force=0.02)

        def _fourier_derivatives(self, a, omega, rtol):
            return self.law.fourier_derivatives_unchecked(a, omega, rtol)

        def _stuck_stiffness(self, omega):
            return 1.0

        def _slip_amplitude(self, omega):
            return 0.02

        def _hysteresis(self, a, omega, n):
            return self.law.hysteresis(a, omega, n=n)

        def harmonics_law(self):
            return self.law

    blade = Blade(mass=1.0, stiffness=1.0, damping=0.004, force=0.01)
    mine = frequency_response(blade, FirstHarmonicJenkins(), omega_range=(0.8, 1.4))
    lib = frequency_response(blade, Macroslip(stiffness=1.0, slip_force=0.02), omega_range=(0.8, 1.4), harmonics=1)
    np.testing.assert_allclose(mine.amplitude, lib.amplitude, rtol=1e-9)
    np.testing.assert_allclose(mine.error_sources["harmonics"], lib.error_sources["harmonics"], rtol=1e-6, atol=1e-12)
    assert float(np.max(mine.error_sources["harmonics"])) > 1e-4  # a real source, not zeros on both sides


def test_every_library_element_answers():
    for name in contact_models.__all__:
        cls = getattr(contact_models, name)
        if isinstance(cls, type) and issubclass(cls, ContactElement) and cls is not ContactElement:
            for q in CAPABILITIES:
                assert hasattr(cls, q), (name, q)
