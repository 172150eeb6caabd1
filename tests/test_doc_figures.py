"""The committed documentation figures are readable at the size the site shows them: enough
resolution, few panels with short titles, amplitudes in micrometres without an offset, and every
colour bar with its unit."""

import sys
from pathlib import Path

import matplotlib
import pytest

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
if str(EXAMPLES) not in sys.path:
    sys.path.insert(0, str(EXAMPLES))


def _panels(fig):
    """The plotting axes of ``fig`` (colour bars left out)."""
    return [ax for ax in fig.axes if ax.get_label() != "<colorbar>"]


def test_validity_map_figure_has_few_panels_short_titles_and_150_dpi(tmp_path):
    import matplotlib.pyplot as plt
    from PIL import Image

    import validity_map

    rows = validity_map.load_rows()
    fig = validity_map.draw(rows)
    panels = _panels(fig)
    assert len(panels) <= 8
    for ax in panels:
        assert len(ax.get_title()) <= 12
    plt.close(fig)
    assert validity_map.DPI >= 150
    path = validity_map.figure(rows, tmp_path)
    dpi = Image.open(path).info["dpi"]
    assert round(dpi[0]) >= 150


def test_monte_carlo_figure_shows_micrometres_without_offset_and_a_colour_bar_with_its_unit(tmp_path):
    import matplotlib.pyplot as plt

    import monte_carlo

    out = monte_carlo.main(outdir=tmp_path, small=True, folder=tmp_path / "runs")
    fig = monte_carlo.draw(out["result"])
    fig.canvas.draw()
    hist, scatter = _panels(fig)
    assert "(µm)" in hist.get_xlabel() and "(µm)" in scatter.get_ylabel()
    assert hist.xaxis.get_offset_text().get_text() == "" and scatter.yaxis.get_offset_text().get_text() == ""
    ticks = [float(t.get_text().replace("\u2212", "-")) for t in scatter.get_yticklabels() if t.get_text()]
    peaks = out["result"].column("peak_amplitude_m")
    assert min(ticks) <= 1e6 * max(peaks) and max(ticks) >= 1e6 * min(peaks)  # micrometres, not metres
    colorbar = [ax for ax in fig.axes if ax.get_label() == "<colorbar>"]
    assert len(colorbar) == 1 and colorbar[0].get_ylabel().endswith("(N)")
    plt.close(fig)
    assert monte_carlo.DPI >= 150
