"""The one CSV layout and the one FRF figure (hbm.output)."""

import csv

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from contact_models import Macroslip  # noqa: E402
from hbm import Blade, Steps, frequency_response  # noqa: E402
from hbm.output import FRF_COLUMNS, LEGEND_LIMIT, plot_frfs  # noqa: E402

BLADE = Blade(mass=1.0, stiffness=1.0, damping=0.01, force=0.01)


def frfs(loads):
    return [frequency_response(BLADE, Macroslip(stiffness=1.0, slip_force=s), omega_range=(0.6, 1.8), harmonics=1,
                               steps=Steps(max_step=0.2))
            for s in loads]


def test_to_csv_has_the_library_columns_with_units_and_the_residual(tmp_path):
    frf = frfs([0.02])[0]
    rows = list(csv.reader(frf.to_csv(tmp_path / "f.csv").open()))
    assert tuple(rows[0]) == FRF_COLUMNS and all(c.endswith(("_rad_s", "_m", "_rad", "_rel")) for c in rows[0])
    data = np.array(rows[1:], dtype=float)
    assert np.array_equal(data[:, 5], frf.residual_norm) and np.all(data[:, 5] < 1e-6)


def test_many_curves_are_coloured_by_the_parameter_with_a_colour_bar():
    loads = np.geomspace(0.005, 0.05, LEGEND_LIMIT + 2)
    curves = [(f, f"slip {s:g}", "macroslip" if i % 2 else "other", s) for i, (f, s) in enumerate(zip(frfs(loads), loads))]
    fig, ax = plt.subplots()
    plot_frfs(curves, ax, parameter="slip force (N)")
    assert len(fig.axes) == 2 and fig.axes[1].get_ylabel() == "slip force (N)"  # the colour bar
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["other", "macroslip"]  # styles by model
    colours = {tuple(line.get_color()) for line in ax.get_lines() if line.get_linestyle() in ("-", "--")}
    assert len(colours) == len(loads)  # one colour per value
    plt.close(fig)


def test_few_curves_get_a_legend_of_their_labels():
    fig, ax = plt.subplots()
    plot_frfs([(f, f"run {i}", "macroslip", None) for i, f in enumerate(frfs([0.01, 0.02]))], ax)
    assert len(fig.axes) == 1 and [t.get_text() for t in ax.get_legend().get_texts()] == ["run 0", "run 1"]
    plt.close(fig)
