"""Defaults of :func:`hbm.frequency_response`: the step controls (:class:`Steps`), the named
tolerances, the AFT samples per H, and the presets of an earlier release.

``tol`` is the one accuracy knob of a solve: the names "fast", "default" and "precise" stand for
the tolerances of ``TOLERANCE`` (1e-2, 1e-3, 1e-5) and adapt exactly as those numbers.  The step
controls set how densely a branch is sampled, not its accuracy (every point is a converged solve,
the peak is located between points): ``max_step`` bounds the chord error of the drawn curve
(about ``max_step**2``), ``curve_tol`` sizes the steps by the error of the curve between points
(``hbm.curve``) with ``max_step`` a safeguard, ``max_steps`` is a budget.

The presets of an earlier release (``frequency_response(..., accuracy=...)``, still read with a
``DeprecationWarning``) bundled an rtol with steps: ``max_step = DEFAULT_MAX_STEP
(rtol / DEFAULT_RTOL) ** STEP_EXPONENT`` at the default and coarser, and ``curve_tol = CURVE_FACTOR
rtol ** (1/3)`` finer; ``resolve`` and ``apply`` give them as they were.  What ``tol`` and the step
controls cost is measured by ``benchmarks/bench_frf_accuracy.py`` (``docs/performance.md``).
"""

from __future__ import annotations

import math
import numbers
from dataclasses import asdict, dataclass

from contact_models.base import DEFAULT_RTOL, default_samples  # the elements' default rtol is the FRF's too

#: Default largest step (scaled arclength, ``hbm.frf``'s module docstring).
DEFAULT_MAX_STEP = 0.03
#: Default smallest step.
DEFAULT_MIN_STEP = 1e-9
#: Default step budget.
DEFAULT_MAX_STEPS = 5000
#: max_step grows like rtol ** STEP_EXPONENT (0.03 at 1e-6, 0.095 at 1e-3, 0.0095 at 1e-9).
STEP_EXPONENT = 1.0 / 6.0
#: Limits of the preset max_step.
MIN_PRESET_STEP = 0.005
MAX_PRESET_STEP = 0.1
#: Below DEFAULT_RTOL the curve tolerance is CURVE_FACTOR * rtol ** (1/3): 1e-5 at rtol = 1e-9.
CURVE_FACTOR = 0.01
#: Largest rtol accepted (``frequency_response`` needs rtol < 0.1).
MAX_RTOL = 0.1

#: The named presets, as the rtol they stand for.
NAMED = {"fast": 1e-3, "default": DEFAULT_RTOL, "precise": 1e-9}
#: The named presets as tolerances: the target relative error of the response amplitude
#: (``frequency_response``'s ``tol``: the error estimate's target and the warning's threshold) that
#: ``accuracy=<name>`` stands for when no ``tol`` is given.  The preset still sets rtol, the steps and
#: (for a structure) H and n_t as above; a numeric ``accuracy`` (an rtol) keeps ``hbm.frf.DEFAULT_TOL``.
TOLERANCE = {"fast": 1e-2, "default": 1e-3, "precise": 1e-5}

#: Documented bound of the peak's relative error (max of amplitude and frequency) on
#: ``hbm.cli.cases.default_case()`` against a tight reference (rtol 1e-11): measured 1.9e-6, 6.0e-8
#: and 1.7e-9 (docs/performance.md, which the benchmark regenerates; tests/test_presets.py).
PEAK_ERROR_BOUND = {"fast": 1e-5, "default": 3e-7, "precise": 1e-8}


@dataclass(frozen=True)
class Accuracy:
    """Values of ``frequency_response``'s accuracy knobs."""

    rtol: float
    max_step: float
    min_step: float
    max_steps: int
    curve_tol: float | None = None

    def options(self) -> dict:
        """Keyword arguments for ``frequency_response`` (``curve_tol`` only where it is set).

        Examples
        --------
        >>> from hbm.balance.presets import resolve
        >>> resolve("default").options()
        {'rtol': 1e-06, 'max_step': 0.03, 'min_step': 1e-09, 'max_steps': 5000}
        >>> resolve("precise").options()["curve_tol"]
        1e-05
        """
        return {k: v for k, v in asdict(self).items() if k != "curve_tol" or v is not None}


def from_rtol(rtol: float) -> Accuracy:
    """The knobs for a relative tolerance ``rtol`` (0 < rtol < 0.1)."""
    curve_tol = curve_tol_for(rtol)
    max_step = max_step_for(rtol) if curve_tol is None else MAX_PRESET_STEP
    # the budget covers the default's arclength at the default's step (a step by accuracy may be short)
    max_steps = math.ceil(DEFAULT_MAX_STEPS * DEFAULT_MAX_STEP / min(max_step, max_step_for(rtol)) * (1.0 - 1e-12))
    return Accuracy(rtol=float(rtol), max_step=max_step, min_step=DEFAULT_MIN_STEP, max_steps=max_steps,
                    curve_tol=curve_tol)


def curve_tol_for(rtol: float) -> float | None:
    """The curve tolerance of a preset finer than the default, ``CURVE_FACTOR * rtol ** (1/3)``; None
    at the default and coarser (the step is then limited by ``max_step``, as before)."""
    if rtol >= DEFAULT_RTOL:
        return None
    return float(f"{CURVE_FACTOR * rtol ** (1.0 / 3.0):.12g}")  # 1e-05 at 1e-9, not 1.0000000000000004e-05


def max_step_for(rtol: float) -> float:
    """``DEFAULT_MAX_STEP * (rtol / DEFAULT_RTOL) ** STEP_EXPONENT``, clipped; the default at 1e-6."""
    if rtol == DEFAULT_RTOL:
        return DEFAULT_MAX_STEP  # exactly the default, not a rounding of it
    step = DEFAULT_MAX_STEP * (rtol / DEFAULT_RTOL) ** STEP_EXPONENT
    return min(max(step, MIN_PRESET_STEP), MAX_PRESET_STEP)


def resolve(accuracy: str | float) -> Accuracy:
    """``accuracy``: "fast", "default", "precise" or a number 0 < rtol < 0.1."""
    if isinstance(accuracy, str):
        if accuracy not in NAMED:
            raise ValueError(f"accuracy must be one of {', '.join(map(repr, NAMED))} or an rtol "
                             f"0 < rtol < {MAX_RTOL}, got accuracy={accuracy!r}")
        return from_rtol(NAMED[accuracy])
    if isinstance(accuracy, bool) or not isinstance(accuracy, numbers.Real):
        raise ValueError(f"accuracy must be one of {', '.join(map(repr, NAMED))} or an rtol "
                         f"0 < rtol < {MAX_RTOL}, got accuracy={accuracy!r}")
    value = float(accuracy)
    if not 0.0 < value < MAX_RTOL:  # also rejects nan
        raise ValueError(f"accuracy as an rtol must satisfy 0 < rtol < {MAX_RTOL}, got accuracy={accuracy!r}")
    return from_rtol(value)


def apply(accuracy: str | float, *, rtol: float, max_step: float, min_step: float, max_steps: int,
          curve_tol: float | None = None) -> tuple[float, float, float, int, float | None]:
    """``(rtol, max_step, min_step, max_steps, curve_tol)`` for ``frequency_response(..., accuracy=...)``.

    The preset sets all four; passing one of them too (with a value other than its default)
    is ambiguous and raises ValueError: to adjust a preset, start from
    ``resolve(accuracy).options()`` and pass the knobs themselves.
    """
    preset = resolve(accuracy)
    given = {"rtol": (rtol, DEFAULT_RTOL), "max_step": (max_step, DEFAULT_MAX_STEP),
             "min_step": (min_step, DEFAULT_MIN_STEP), "max_steps": (max_steps, DEFAULT_MAX_STEPS),
             "curve_tol": (curve_tol, None)}
    clash = [f"{k}={v!r}" for k, (v, d) in given.items() if v != d]
    if clash:
        raise ValueError(f"accuracy={accuracy!r} sets rtol, max_step, min_step, max_steps and curve_tol; got also "
                         f"{', '.join(clash)} (pass either accuracy or the knobs, e.g. "
                         f"**hbm.balance.presets.resolve({accuracy!r}).options() with changes)")
    return preset.rtol, preset.max_step, preset.min_step, preset.max_steps, preset.curve_tol


#: Harmonics H and AFT samples per period n_t of each named preset for the multi-harmonic balance
#: (``frequency_response`` with an ``hbm.Structure``).  Chosen from ``benchmarks/bench_mhb_accuracy.py``
#: (``docs/performance.md``, "What accuracy costs: harmonics"); a number (an rtol) takes "default"'s.
HARMONICS = {"fast": (3, 256), "default": (7, 512), "precise": (15, 2048)}


def harmonic_knobs(accuracy: str | float) -> tuple[int, int | None]:
    """``(harmonics, n_t)`` of a preset name, or of "default" for an rtol (validated by :func:`resolve`).

    Examples
    --------
    >>> harmonic_knobs("precise")
    (15, 2048)
    """
    resolve(accuracy)
    return HARMONICS[accuracy] if isinstance(accuracy, str) else HARMONICS["default"]


def samples_for(harmonics: int, accuracy: str | float = "default") -> int:
    """AFT samples per period for ``harmonics`` harmonics under the preset ``accuracy``.

    The element's floor ``contact_models.base.default_samples(H)``, raised above H = 1 to the
    preset's own ``n_t`` (:data:`HARMONICS`): a harmonic count given explicitly never lowers the
    sampling the accuracy asks for.  At H = 1 the floor (the describing functions need no samples).

    Examples
    --------
    >>> samples_for(1), samples_for(5), samples_for(15, "precise"), samples_for(31)
    (32, 512, 2048, 512)
    """
    floor = default_samples(harmonics)
    return floor if harmonics == 1 else max(floor, harmonic_knobs(accuracy)[1])



@dataclass(frozen=True)
class Steps:
    """The continuation's step controls (``frequency_response(..., steps=Steps(...))``).

    They set how densely the branch is sampled and how long the run may go on, not its accuracy,
    which ``tol`` sets: every point is a converged solve and the peak is located between points.

    Attributes
    ----------
    max_step : float
        Largest step in scaled arclength (omega by the range width, the coefficients by the current
        amplitude).  Default 0.03 (about ``max_step**2`` of chord error in the drawn curve).
    min_step : float
        Smallest step; a run whose corrector keeps failing below it stops.  Default 1e-9.
    max_steps : int
        The step budget.  Default 5000.
    curve_tol : float or None
        Step control by accuracy: steps sized so that the curve between points is within
        ``curve_tol`` of the branch (``hbm.curve``), ``max_step`` a safeguard.  Default None.
    locate_folds : bool
        Locate the branch's turning points.  Default True.

    Examples
    --------
    >>> Steps().max_step, Steps(max_step=0.01).max_steps
    (0.03, 5000)
    """

    max_step: float = DEFAULT_MAX_STEP
    min_step: float = DEFAULT_MIN_STEP
    max_steps: int = DEFAULT_MAX_STEPS
    curve_tol: float | None = None
    locate_folds: bool = True

    def __post_init__(self) -> None:
        self.checked()  # a bad control is refused where it is given, naming it

    def checked(self) -> dict:
        """The controls as the continuation's keyword arguments, each validated (``ValueError`` naming it)."""
        for name in ("max_step", "min_step"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, numbers.Real) or not 0.0 < float(v) < math.inf:
                raise ValueError(f"steps.{name} must be a positive number, got {name}={v!r}")
        if isinstance(self.max_steps, bool) or not isinstance(self.max_steps, numbers.Integral) or self.max_steps < 1:
            raise ValueError(f"steps.max_steps must be an integer >= 1, got max_steps={self.max_steps!r}")
        c = self.curve_tol
        if c is not None and (isinstance(c, bool) or not isinstance(c, numbers.Real) or not 0.0 < float(c) < 1.0):
            raise ValueError(f"steps.curve_tol must be None or in (0, 1) (a relative error), got curve_tol={c!r}")
        if type(self.locate_folds).__name__ not in ("bool", "bool_"):  # (numpy's bool too)
            raise ValueError(f"steps.locate_folds must be True or False, got locate_folds={self.locate_folds!r}")
        if self.min_step > self.max_step:
            raise ValueError(f"steps.min_step must be <= max_step, got min_step={self.min_step!r}, "
                             f"max_step={self.max_step!r}")
        return dict(max_step=float(self.max_step), min_step=float(self.min_step), max_steps=int(self.max_steps),
                    locate_folds=bool(self.locate_folds), curve_tol=None if c is None else float(c))
