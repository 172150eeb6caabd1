"""The one CSV layout and the one FRF figure (hbm.output)."""

import csv
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from contact_models import Macroslip  # noqa: E402
from hbm import Blade, Steps, frequency_response  # noqa: E402
from hbm.output import csv_lines, FRF_COLUMNS, LEGEND_LIMIT, plot_frfs  # noqa: E402

BLADE = Blade(mass=1.0, stiffness=1.0, damping=0.01, force=0.01)


def frfs(loads):
    return [frequency_response(BLADE, Macroslip(stiffness=1.0, slip_force=s), omega_range=(0.6, 1.8), harmonics=1,
                               steps=Steps(max_step=0.2))
            for s in loads]


def test_to_csv_has_the_library_columns_with_units_and_the_residual(tmp_path):
    frf = frfs([0.02])[0]
    rows = list(csv.reader(csv_lines(frf.to_csv(tmp_path / "f.csv").open())))
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
    assert len(fig.axes) == 1
    texts = [t.get_text() for t in ax.get_legend().get_texts()]
    assert sorted(texts) == ["estimated error (shaded)", "run 0", "run 1"]  # the shading named once
    plt.close(fig)


def test_plot_draws_the_estimated_error_as_a_band_around_the_curve():
    frf = frequency_response(BLADE, Macroslip(stiffness=1.0, slip_force=0.003), omega_range=(0.6, 1.8), tol=1e-2)
    assert np.all(np.isfinite(frf.error_estimate)) and frf.error_estimate.max() > 0.0
    ax = frf.plot(omega_unit="Hz", amplitude_unit="um")
    (band,) = ax.patches
    xy = band.get_xy()
    n = len(frf)
    # the ribbon: amplitude (1 + e) out along the branch, amplitude (1 - e) back, in the axis' units
    assert np.allclose(xy[:n, 0], frf.omega / (2.0 * np.pi), rtol=1e-15, atol=0.0)
    assert np.allclose(xy[:n, 1], 1e6 * frf.amplitude * (1.0 + frf.error_estimate), rtol=1e-14, atol=0.0)
    assert np.allclose(xy[n:2 * n, 1], (1e6 * frf.amplitude * (1.0 - frf.error_estimate))[::-1], rtol=1e-14, atol=0.0)
    assert band.get_facecolor()[:3] == matplotlib.colors.to_rgb(ax.lines[0].get_color())
    assert not frf.plot(error_band=False).patches
    untold = frequency_response(BLADE, Macroslip(stiffness=1.0, slip_force=0.003), omega_range=(0.6, 1.8), tol=None)
    assert not untold.plot().patches  # no estimate, no band
    plt.close("all")


def test_study_figure_draws_each_peaks_error_bar_and_names_the_key_with_its_unit(tmp_path):
    from hbm.study.figures import figure
    from hbm.study.store import StudyResult

    loads = [10.0, 30.0, 100.0]
    peaks, errors = [2.0e-6, 1.0e-6, 1.5e-6], [0.02, 0.001, None]
    recs = [{"run": i + 1, "id": str(i), "params": {"damper.load.N": N}, "success": True, "message": "",
             "peak_omega_rad_s": 3.8e4, "peak_amplitude_m": a, "peak_error_rel": e, "peak_model": "m", "nfev": 1,
             "curve": {"omega_rad_s": [3.7e4, 3.8e4, 3.9e4], "amplitude_m": [a / 2, a, a / 2]}, "time_s": 0.1}
            for i, (N, a, e) in enumerate(zip(loads, peaks, errors))]
    result = StudyResult(("damper.load.N",), recs, {}, 3, 0, [], 1.0)
    shown = []
    save = matplotlib.figure.Figure.savefig
    matplotlib.figure.Figure.savefig = lambda self, *a, **k: (shown.append(self), save(self, *a, **k))
    try:
        figure(result, tmp_path / "study.png")
    finally:
        matplotlib.figure.Figure.savefig = save
    bx = shown[0].axes[1]
    assert bx.get_xlabel() == "normal load N (N)"
    (bars,) = bx.containers
    segments = bars.lines[2][0].get_segments()
    half = [(seg[1][1] - seg[0][1]) / 2.0 for seg in segments]  # symmetric: peak * peak_error_rel either way
    assert np.allclose(half, [2.0e-6 * 0.02, 1.0e-6 * 0.001, 0.0], rtol=1e-12, atol=1e-30)


def test_to_dataframe_holds_the_csv_table_with_its_header(tmp_path):
    pd = pytest.importorskip("pandas")
    frf = frequency_response(BLADE, Macroslip(stiffness=1.0, slip_force=0.003), omega_range=(0.6, 1.8), harmonics=3)
    frame = frf.to_dataframe(case="a blade with a Jenkins damper")
    back = pd.read_csv(frf.to_csv(tmp_path / "f.csv", case="a blade with a Jenkins damper"), comment="#")
    assert list(frame.columns) == list(back.columns) and len(frame) == len(back) == len(frf)
    for name in frame.columns:  # the same numbers by two paths: arrays, and repr text read back
        assert np.array_equal(frame[name].to_numpy(float), back[name].to_numpy(float), equal_nan=True), name
    assert np.array_equal(frame["amplitude_m"], np.hypot(frame["x_c_m"], frame["x_s_m"]))
    assert frame.attrs["case"] == "a blade with a Jenkins damper" and frame.attrs["harmonics"] == 3
    assert frame.attrs["model"] == "Macroslip" and frame.attrs["tol"].startswith("0.001 ")
    assert np.loadtxt(tmp_path / "f.csv", delimiter=",", skiprows=1).shape == frame.shape  # numpy skips it too


def test_to_dataframe_without_pandas_names_the_extra(monkeypatch):
    from hbm.study.store import StudyResult

    frf = frequency_response(BLADE, Macroslip(stiffness=1.0, slip_force=0.003), omega_range=(0.6, 1.8), harmonics=1)
    monkeypatch.setitem(sys.modules, "pandas", None)  # import pandas raises ImportError
    with pytest.raises(ImportError, match=r'pip install "frictiondamp\[pandas\]"'):
        frf.to_dataframe()
    with pytest.raises(ImportError, match=r"frictiondamp\[pandas\]"):
        StudyResult(("x",), [], {}, 0, 0, [], 0.0).to_dataframe()


def test_study_to_dataframe_is_its_table():
    pytest.importorskip("pandas")
    from hbm.study.store import StudyResult

    recs = [{"run": i + 1, "id": str(i), "params": {"x": x}, "success": True, "message": "", "peak_omega_rad_s": x,
             "peak_amplitude_m": x * x, "peak_error_rel": None, "peak_model": "m", "nfev": 3, "time_s": 0.5,
             "curve": {}} for i, x in enumerate([1.0, 2.0])]
    frame = StudyResult(("x",), recs, {}, 2, 0, [], 1.0).to_dataframe()
    assert list(frame.columns)[:3] == ["run", "id", "x"] and frame["peak_amplitude_m"].tolist() == [1.0, 4.0]


def test_plot_refuses_a_unit_that_is_no_name_by_name():
    """A list or an array for a unit failed as ``TypeError: unhashable type: 'list'``, naming nothing."""
    import matplotlib

    matplotlib.use("Agg")
    from hbm import Blade, frequency_response

    frf = frequency_response(Blade(mass=1.0, stiffness=1.0e4, damping=2.0, force=1.0), omega_range=(90.0, 110.0))
    with pytest.raises(ValueError, match=r"^omega_unit must be one of 'rad/s', 'Hz', got omega_unit=\['Hz'\]$"):
        frf.plot(omega_unit=["Hz"])
    with pytest.raises(ValueError, match=r"^amplitude_unit must be one of 'm', 'um', got amplitude_unit=\[\]$"):
        frf.plot(amplitude_unit=[])


def test_plot_refuses_an_unknown_unit_and_an_ax_that_cannot_draw_by_name():
    import matplotlib

    matplotlib.use("Agg")
    from hbm import Blade, frequency_response

    frf = frequency_response(Blade(mass=1.0, stiffness=1.0e4, damping=2.0, force=1.0), omega_range=(90.0, 110.0))
    with pytest.raises(ValueError, match=r"^omega_unit must be one of 'rad/s', 'Hz', got omega_unit='rpm'$"):
        frf.plot(omega_unit="rpm")
    with pytest.raises(ValueError, match=r"^amplitude_unit must be one of 'm', 'um', got amplitude_unit='in'$"):
        frf.plot(amplitude_unit="in")
    with pytest.raises(ValueError, match=r"^ax must be a matplotlib Axes or None, got ax=3$"):
        frf.plot(ax=3)
    assert frf.plot(omega_unit="Hz", amplitude_unit="um").get_xlabel() == "frequency (Hz)"


def test_to_csv_names_a_path_that_cannot_be_written(tmp_path, monkeypatch):
    """A folder one may not write in (PermissionError), a name too long (OSError) and a null character came out as
    the operating system's bare errors, naming no parameter."""
    import pathlib

    from hbm import Blade, frequency_response

    frf = frequency_response(Blade(mass=1.0, stiffness=1.0e4, damping=2.0, force=1.0), omega_range=(90.0, 110.0))
    long = tmp_path / ("x" * 300 + ".csv")
    with pytest.raises(ValueError, match=r"^path must be a file that can be written, got path='.*\.\.\. \(File name too long\)$"):
        frf.to_csv(long)
    with pytest.raises(ValueError, match=r"^path must be a file path without a null character, got path="):
        frf.to_csv(str(tmp_path / "a\0b.csv"))

    def refused(self, *args, **kwargs):
        raise PermissionError(13, "Permission denied", str(self))

    monkeypatch.setattr(pathlib.Path, "open", refused)
    with pytest.raises(ValueError, match=rf"^path must be a file that can be written, got path='{re.escape(str(tmp_path))}/"
                                         r"frf\.csv' \(Permission denied\)$"):
        frf.to_csv(tmp_path / "frf.csv")
