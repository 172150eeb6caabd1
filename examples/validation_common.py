"""Shared set-up of the validation scripts (``validation_*.py``, docs/validation.md).

The reference bar (docs/theory.md), the two analytic elements and their numerical counterparts:

- bar ``Bar(E=2e11, rho=7850, A=1e-5, L=0.05, k=8e8, beta=4e7, mu=0.3)``;
- ``"uniform"``: ``UniformLoad(N=100)``, analytic ``TwoRegionMicroslip``;
- ``"concave12"``: ``QuadraticLoad.from_ratio(N=100, ratio=12)``, analytic ``ThreeRegionMicroslip``;
- ``F_s = f_s/(k* a)``, ``F_c = f_c/(k* a)``; amplitudes in units of each element's own
  static slip amplitude ``a_min = slip_amplitude(0)`` (7.5e-7 m and 2.63e-7 m).
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")

from contact_models import Bar, QuadraticLoad, ThreeRegionMicroslip, TwoRegionMicroslip, UniformLoad  # noqa: E402

BAR = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
#: name -> (load, analytic element class)
LOADS = {
    "uniform": (UniformLoad(N=100.0), TwoRegionMicroslip),
    "concave12": (QuadraticLoad.from_ratio(N=100.0, ratio=12.0), ThreeRegionMicroslip),
}
#: The amplitudes (a/a_min) and frequencies (omega/omega_c) of the quasi-static and dynamic tables (docs/validation.md).
RATIOS = (1.5, 3.0, 10.0, 30.0)
FREQUENCIES = (0.01, 0.2, 0.3, 0.5)
#: Where the PNGs go: docs/figures of the repository.
FIGURES = Path(__file__).resolve().parent.parent / "docs" / "figures"


def analytic(name: str):
    load, cls = LOADS[name]
    return cls(BAR, load)


def markdown_table(header, rows) -> str:
    """A GitHub markdown table from a header list and rows of already formatted cells."""
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def text_table(header, rows) -> str:
    """The same table as plain text, its columns aligned (for a terminal or the gallery's output)."""
    cells = [list(map(str, header))] + [[str(c) for c in row] for row in rows]
    widths = [max(len(row[j]) for row in cells) for j in range(len(header))]
    lines = ["  ".join(c.rjust(w) if j else c.ljust(w) for j, (c, w) in enumerate(zip(row, widths))).rstrip()
             for row in cells]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines)
