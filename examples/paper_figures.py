"""Shared set-up of the scripts that regenerate the figures of Cigeroglu, Lu & Menq (2006).

Every figure uses the same bar, the same two elements and the same normalisation:

- bar ``Bar(E=2e11, rho=7850, A=1e-5, L=0.05, k=8e8, beta=4e7, mu=0.3)``;
- two-region element ``TwoRegionMicroslip(bar, UniformLoad(N=100))``;
- three-region element ``ThreeRegionMicroslip(bar, QuadraticLoad.from_ratio(N=100, ratio=12))``;
- ``F_s = f_s/(k* a)``, ``F_c = f_c/(k* a)``, amplitudes ``a/a_min`` with ``a_min`` the slip
  amplitude of the two-region element (as the paper does in Figs. 14, 15, 17, 18);
- frequencies 0.01, 0.2, 0.3, 0.5 omega_c drawn solid, dashed, dotted, dash-dot (Figs. 8-10).

Each ``figNN_*.py`` script in this folder has ``main(outdir=..., small=False)`` that writes
``figNN.png`` and returns a few key numbers; ``main()`` here runs them all.  Run from the
repository root with ``python3 examples/paper_figures.py`` (or one script alone).
"""

from __future__ import annotations

import contextlib
import importlib
import math
import warnings
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import NamedTuple

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from contact_models import (  # noqa: E402
    Bar,
    ModelRangeWarning,
    QuadraticLoad,
    ThreeRegionMicroslip,
    TwoRegionMicroslip,
    UniformLoad,
)
from hbm import Blade  # noqa: E402

#: The bar of every figure (the reference bar of docs/theory.md).
BAR_PARAMETERS = dict(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
#: Total normal load (N) of both elements.
NORMAL_LOAD = 100.0
#: q0/(q0 - q2) of the concave (three-region) load, Section 3.3.
CONCAVE_RATIO = 12.0
#: Excitation frequencies of Figs. 8-15, as fractions of omega_c.
FREQUENCY_RATIOS = (0.01, 0.2, 0.3, 0.5)
#: The paper's line styles for those frequencies (captions of Figs. 8-10).
LINESTYLES = {0.01: "-", 0.2: "--", 0.3: ":", 0.5: "-."}
COLORS = {0.01: "k", 0.2: "tab:blue", 0.3: "tab:green", 0.5: "tab:red"}
#: Figure size (in) and resolution of the PNGs.
FIGSIZE = (6.0, 4.5)
DPI = 120
#: The gross-slip limits are drawn from this many gross-slip amplitudes (at 0.01 omega_c) on.
REFERENCE_FROM = 3.0
#: Where the PNGs go by default: docs/figures of the repository.
DEFAULT_OUTDIR = Path(__file__).resolve().parent.parent / "docs" / "figures"
#: The figure scripts: every ``fig*.py`` beside this file, in the paper's order.
FIGURE_MODULES = tuple(sorted(p.stem for p in Path(__file__).resolve().parent.glob("fig[0-9]*.py")))


@dataclass(frozen=True)
class Setup:
    """The bar, both elements and the normalising constants."""

    bar: Bar
    two: TwoRegionMicroslip
    three: ThreeRegionMicroslip
    omega_c: float  # rad/s
    k_star: float  # N/m
    a_min: float  # m, slip amplitude of the two-region (uniform-load) element

    def omega(self, ratio: float) -> float:
        return ratio * self.omega_c


@lru_cache(maxsize=1)
def setup() -> Setup:
    """The shared set-up (cached, so the elements' per-frequency paths are built once)."""
    bar = Bar(**BAR_PARAMETERS)
    two = TwoRegionMicroslip(bar, UniformLoad(N=NORMAL_LOAD))
    three = ThreeRegionMicroslip(bar, QuadraticLoad.from_ratio(N=NORMAL_LOAD, ratio=CONCAVE_RATIO))
    return Setup(bar=bar, two=two, three=three, omega_c=bar.omega_c, k_star=bar.k_star,
                 a_min=two.slip_amplitude(0.0))


def amplitude_grid(small: bool, *, lo=0.5, hi=100.0, keep=(0.5, 0.8, 1.0, 1.5)):
    """a/a_min on a log grid from ``lo`` to ``hi``, with the points ``keep`` included exactly."""
    grid = np.logspace(np.log10(lo), np.log10(hi), 25 if small else 300)
    return np.union1d(grid, np.asarray(keep, dtype=float))


def fourier_curves(element, s: Setup, a_over, ratios=FREQUENCY_RATIOS):
    """``{ratio: (F_s, F_c)}`` on ``a_over = a/a_min``: one vectorised ``fourier`` call per curve."""
    a = np.asarray(a_over) * s.a_min
    out = {}
    for r in ratios:
        with beyond_the_single_mode_range():
            fs, fc = element.fourier(a, s.omega(r))
        out[r] = (fs / (s.k_star * a), fc / (s.k_star * a))
    return out


def static_gross_slip(bar: Bar, load):
    """Closed-form statics (omega -> 0) of the bar sliding as a whole: ``(K_slip, F0)``.

    Tip held at u(L) = 0, EA u'' = mu q, EA u'(0) = beta u(0) give u(0) = -mu I2(L)/(EA + beta L)
    and the intercept F0 = EA u'(L) = mu N + beta u(0); the slope is beta and EA/L in series.
    Large amplitudes then give F_s -> K_slip/k* and F_c -> 4 F0/(pi k* a) (a parallelogram loop).
    """
    load = load.on(bar.L)
    u0 = -bar.mu * float(load.I2(bar.L)) / (bar.EA + bar.beta * bar.L)
    F0 = bar.mu * load.N + bar.beta * u0
    K_slip = 1.0 / (1.0 / bar.beta + bar.L / bar.EA)
    return K_slip, F0


def new_figure(number: int, subtitle: str):
    fig, ax = plt.subplots(figsize=FIGSIZE)
    ax.set_title(f"Fig. {number} (after Cigeroglu et al. 2006)\n{subtitle}", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    return fig, ax


def save(fig, outdir, number: int) -> Path:
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    path = outdir / f"fig{number:02d}.png"
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return path


#: The repository's root: paths under it are printed relative to it.

@contextlib.contextmanager
def beyond_the_single_mode_range():
    """The paper's figures draw the single-mode elements up to 0.5 omega_c, beyond the range where
    the validity map puts them within 1 % of the bar with every mode (docs/validation.md, "Where the
    single-mode model holds"): the figures show the paper's model as printed, so its
    ``ModelRangeWarning`` is left out here, on purpose."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelRangeWarning)
        yield


# ------------------------------------------------------------------------------ the default blade
class DefaultCase(NamedTuple):
    """The blade of ``python3 -m hbm``, its damper and its sweep (rad/s)."""

    blade: Blade
    element: TwoRegionMicroslip
    omega_range: tuple[float, float]


def default_case() -> DefaultCase:
    """The default case of ``python3 -m hbm``, built with the public API: the reference bar as a
    two-region microslip damper under a uniform load of 100 N, on a blade of stiffness 1e8 N/m whose
    stuck resonance sqrt((k + k*)/m) is 0.3 omega_c, damping ratio 2e-3, force 8 N, swept over 0.8
    to 1.1 times the stuck resonance (the same numbers, operation for operation, as the command
    line's case; ``tests/test_examples_figures.py`` compares them)."""
    bar = Bar(**BAR_PARAMETERS)
    element = TwoRegionMicroslip(bar, UniformLoad(N=NORMAL_LOAD))
    w_stuck = 0.3 * bar.omega_c
    k = 1.0e8
    m = (k + element.stuck_stiffness(0.0)) / w_stuck**2
    blade = Blade.from_modal(frequency=math.sqrt(k / m), damping_ratio=2.0e-3, mass=m, force=8.0)
    return DefaultCase(blade, element, (0.8 * w_stuck, 1.1 * w_stuck))


def stuck_response(blade: Blade, omega, stiffness) -> np.ndarray:
    """Complex amplitude ``F / (k + k_d - m w^2 + i c w)`` of ``blade`` with a linear spring in place
    of its damper: ``stiffness`` a number or a function of the frequencies (the damper held
    stuck: its ``stuck_stiffness``). Closed form of the blade's equation of motion."""
    omega = np.asarray(omega, dtype=float)
    kd = stiffness(omega) if callable(stiffness) else stiffness
    return blade.force / (blade.stiffness + kd - blade.mass * omega**2 + 1j * blade.damping * omega)


ROOT = Path(__file__).resolve().parent.parent


def display_path(path) -> str:
    """``path`` as printed by the examples: relative to the repository's root when it lies inside
    it (``docs/figures/fig02.png``), so no machine's absolute folder shows in the output."""
    path = Path(path).resolve()
    return path.relative_to(ROOT).as_posix() if path.is_relative_to(ROOT) else path.name


def _format_warning(message, category, filename, lineno, line=None) -> str:
    """Warnings (a paper figure goes beyond the single-mode range on purpose) name the file as
    :func:`display_path` does, so the output shows no machine's absolute folder."""
    return f"{display_path(filename)}:{lineno}: {category.__name__}: {message}\n"


warnings.formatwarning = _format_warning


def _shown(value) -> str:
    if isinstance(value, (str, Path)) and Path(value).suffix in (".png", ".csv", ".json"):
        return display_path(value)
    if isinstance(value, (bool, np.bool_)):
        return str(bool(value))
    if isinstance(value, (float, np.floating)):
        return f"{float(value):.6g}"
    if isinstance(value, (int, np.integer, str)):
        return str(value)
    if isinstance(value, dict):
        return ", ".join(f"{_shown(k)}: {_shown(v)}" for k, v in value.items())
    if isinstance(value, (list, tuple, np.ndarray)):
        values = list(np.asarray(value).ravel()) if isinstance(value, np.ndarray) else list(value)
        text = ", ".join(_shown(v) for v in values[:8])
        return f"[{text}{', ...' if len(values) > 8 else ''}] ({len(values)} values)" if len(values) > 8 else f"[{text}]"
    return str(value)


#: Symbols of the paper that keep their underscore when a key is printed (``F_s_at_1``: ``F_s at 1``).
SYMBOLS = ("F_s", "F_c", "a_min", "a_g")


def _key_name(key: str) -> str:
    """``key`` as words: its underscores as spaces, but for the paper's symbols (:data:`SYMBOLS`)."""
    for symbol in SYMBOLS:
        key = key.replace(symbol, symbol.replace("_", "\0"))
    return key.replace("_", " ").replace("\0", "_")


def show(out: dict) -> None:
    """Print what an example's ``main()`` returned, one readable line per entry (``path`` first,
    relative to the repository; numbers to 6 digits; a dict of numbers as ``key: value`` pairs)."""
    for key in sorted(out, key=lambda k: k != "path"):
        name = "wrote" if key == "path" else _key_name(key)
        print(f"{name}: {_shown(out[key])}")


def frequency_label(ratio: float) -> str:
    return rf"$\omega = {ratio:g}\,\omega_c$"


def plot_fourier_figure(number, element, coefficient, subtitle, outdir, small, *, lo=0.5):
    """Figs. 9, 10, 12, 13: F_s or F_c against a/a_min (``lo`` to 100) at the four frequencies,
    with the omega -> 0 gross-slip limit (thick grey) from ``REFERENCE_FROM`` gross-slip amplitudes on.

    Returns the setup, the grid, the curves and the PNG path for the caller's key numbers.
    """
    s = setup()
    a_over = amplitude_grid(small, lo=lo)
    curves = fourier_curves(element, s, a_over)
    i = 0 if coefficient == "s" else 1
    fig, ax = new_figure(number, subtitle)
    for r, pair in curves.items():
        ax.semilogx(a_over, pair[i], LINESTYLES[r], color=COLORS[r], label=frequency_label(r))
    K_slip, F0 = static_gross_slip(s.bar, element.load)
    a_g = element.gross_slip_amplitude(s.omega(0.01)) / s.a_min
    tail = a_over[a_over >= REFERENCE_FROM * a_g]
    if coefficient == "s":
        ax.semilogx(tail, np.full_like(tail, K_slip / s.k_star), color="0.6", lw=3, alpha=0.5,
                    label=r"large-$a$ limit $K_{slip}/k^*$, statics")
    else:
        ax.semilogx(tail, 4.0 * F0 / (np.pi * s.k_star * tail * s.a_min), color="0.6", lw=3, alpha=0.5,
                    label=r"large-$a$ limit $4F_0/(\pi k^* a)$, statics")
    ax.axvline(element.slip_amplitude(s.omega(0.01)) / s.a_min, color="0.5", lw=0.8, ls=":")
    ax.set_xlabel(r"$a/a_{min}$  ($a_{min}$ of the two-region element)")
    ax.set_ylabel(r"$F_s = f_s/(k^* a)$" if coefficient == "s" else r"$F_c = f_c/(k^* a)$")
    ax.set_xlim(a_over[0], a_over[-1])
    ax.legend(fontsize=8)
    path = save(fig, outdir, number)
    return s, a_over, curves, path


def plot_hysteresis_figure(number, element, a_over, subtitle, outdir, small):
    """Figs. 8, 11: closed loops at the four frequencies, x/a_min against f/(k* a_min).

    Returns ``{ratio: (loop area / (pi a f_c), f_c / (k* a))}`` besides the path.
    """
    s = setup()
    a = a_over * s.a_min
    n = 81 if small else 801
    fig, ax = new_figure(number, subtitle)
    x_ref = np.array([-a_over, a_over])
    ax.plot(x_ref, x_ref, color="0.6", lw=3, alpha=0.5, label=r"stuck line $f = k^* x$")
    out = {}
    for r in FREQUENCY_RATIOS:
        with beyond_the_single_mode_range():
            x, f = element.hysteresis(a, s.omega(r), n=n)
            fs, fc = element.fourier(a, s.omega(r))
        ax.plot(x / s.a_min, f / (s.k_star * s.a_min), LINESTYLES[r], color=COLORS[r],
                label=frequency_label(r))
        area = 0.5 * abs(np.dot(x[:-1], f[1:]) - np.dot(x[1:], f[:-1]))  # shoelace, closed loop
        out[r] = (float(area / (np.pi * a * fc)), float(fc / (s.k_star * a)), float(fs / (s.k_star * a)))
    ax.set_xlabel(r"$x/a_{min}$")
    ax.set_ylabel(r"$f/(k^* a_{min})$")
    ax.legend(fontsize=8, loc="upper left")
    path = save(fig, outdir, number)
    return out, path


def main(outdir=DEFAULT_OUTDIR, small=False):
    """Run every figure script; ``{module name: its key numbers}``."""
    return {name: importlib.import_module(name).main(outdir=outdir, small=small) for name in FIGURE_MODULES}


if __name__ == "__main__":
    for name, numbers in main().items():
        print(f"{name}:")
        show(numbers)
