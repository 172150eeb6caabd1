"""Running a planned scene: every run computed, its points written as they come.

Each accepted point is appended to ``frf.partial.csv`` (``coefficients.partial.csv`` for an
amplitude sweep) and flushed; the file is renamed ``frf.csv`` once every run succeeded.
``summary.json`` (written last, atomically) lists each effect, simulated or not and why, the peaks,
counters and timing.  Runs are numbered from 1 in every output.
"""

from __future__ import annotations

import csv
import json
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

from ..balance.presets import DEFAULT_RTOL, Steps
from ..frf import DEFAULT_TOL, MODEL_SHARE, frequency_response
from ..output import (COMMENT, ERROR_COLUMN, HZ_COLUMN, RUN_COLUMNS, STABLE_COLUMN, TABLE_COLUMNS, CsvStream, error_value,
                      csv_lines, frf_columns, frf_row, harmonic_values, stable_value, with_hz)
from .contacts import damper_contact
from .modal import MODE_COLUMNS, OPTIMUM_COLUMNS, modal_figure, modal_summary, run_modes, run_optimum
from .planning import Plan, RunPlan, plan_scene
from .reporting import figure, jsonable, peak_point, run_summary
from .validation import Scene

#: The effect whose line says what the peak's check found (``hbm.scenes.effects.phase_differences``).
PHASE_EFFECT = "phase differences along the bar"
#: The accuracy keyword arguments of ``frequency_response`` in ``sweep["options"]`` (``hbm.balance.presets``).
ACCURACY_OPTIONS = ("rtol", "max_step", "min_step", "max_steps", "curve_tol", "tol")
#: The step settings of ``sweep["options"]`` (``hbm.Steps``).
STEP_OPTIONS = ("max_step", "min_step", "max_steps", "curve_tol")


@dataclass
class Progress:
    """Passed to the ``progress`` callback of :func:`run_scene` after each point.

    Parameters
    ----------
    run : int
        Number of the run the point belongs to, from 1.
    runs : int
        Number of runs of the scene.
    label : str
        The run's label (model, and normal load when the model has one).
    omega : float
        Frequency of the point (rad/s).
    fraction : float
        How far along the run's sweep the point is (0 to 1).
    points : int
        Points written so far, over all runs.
    elapsed : float
        Seconds since the scene started.
    """

    run: int  #: number of the run, from 1
    runs: int
    label: str
    omega: float
    fraction: float  #: how far along the run's sweep (0..1)
    points: int  #: points written so far (all runs)
    elapsed: float  #: seconds since the scene started

    @property
    def overall(self) -> float:
        """How far along the whole scene (0..1), counting runs as equal."""
        return (self.run - 1 + min(max(self.fraction, 0.0), 1.0)) / self.runs

    @property
    def eta(self) -> float | None:
        """Seconds left, estimated from the time so far (None before there is a basis)."""
        f = self.overall
        return self.elapsed * (1.0 - f) / f if f > 1e-3 else None

    def line(self) -> str:
        """``run i/n label: omega ... rad/s (xx %), N points, t s, about T left``."""
        eta = self.eta
        return (f"run {self.run}/{self.runs} {self.label}: omega {self.omega:.6g} rad/s "
                f"({100.0 * min(max(self.fraction, 0.0), 1.0):.0f} %), {self.points} points, {self.elapsed:.1f} s"
                + ("" if eta is None else f", about {duration(eta)} left"))


@dataclass
class RunResult:
    """What one run computed: its FRF or table, success, message, points and time.

    Parameters
    ----------
    plan : RunPlan
        The planned run (model, normal load, element, effects).
    success : bool, optional
        True when the run finished (default False until it has).
    message : str, optional
        Why the run stopped: the solver's message, or the exception that ended it.
    frf : FRF or None, optional
        The traced response of a frequency sweep (``hbm.frequency_response``'s result), else None.
    table : dict or None, optional
        The table of an amplitude sweep: ``"omega"`` (rad/s), ``"a"`` (m), and the normalised
        ``"F_s"``, ``"F_c"`` per frequency; None for a frequency sweep.
    points : int, optional
        Points the run wrote.
    seconds : float, optional
        Wall-clock time of the run (s).
    peak : object, optional
        The FRF's peak (``FRF.peak()``) of a frequency sweep with points, else None.
    summary : dict, optional
        The run's entry in ``summary.json``.
    modes : NonlinearModes or None, optional
        The nonlinear mode of a ``[modes]`` scene's run (``hbm.nonlinear_modes``), else None.
    optimum : DamperOptimum or None, optional
        The optimum of an ``[optimum]`` scene's run (``hbm.damper_optimum``), else None.
    response_dof : int or None, optional
        The DOF whose response a mode's CSV reports.
    """

    plan: RunPlan
    success: bool = False
    message: str = ""
    frf: Any = None
    table: dict | None = None
    points: int = 0
    seconds: float = 0.0
    peak: Any = None
    summary: dict = field(default_factory=dict)
    modes: Any = None  #: the nonlinear mode of a [modes] scene's run
    optimum: Any = None  #: the damper's optimum of an [optimum] scene's run
    response_dof: int | None = None  #: the DOF a mode's CSV reports

    @property
    def number(self) -> int:
        """The run's number in the outputs (from 1)."""
        return self.plan.index + 1


@dataclass
class SceneResult:
    """What :func:`run_scene` did: ``success``, ``message``, per-run results, files, summary.

    Parameters
    ----------
    plan : Plan
        The plan that was run.
    runs : list of RunResult
        One result per run, in the plan's order.
    success : bool
        True when every run succeeded.
    message : str
        ``"every run succeeded"``, or which runs failed and why.
    files : dict
        Kind (``"csv"``, ``"png"``, ``"json"``) -> ``Path`` of the file written.  After a failed
        run the CSV is the ``.partial.csv`` file and no figure is drawn.
    summary : dict
        The content of ``summary.json`` (also returned when ``"json"`` is not among the formats).
    points : int
        Rows written to the CSV, over all runs.
    """

    plan: Plan
    runs: list
    success: bool
    message: str
    files: dict  #: kind ("csv", "png", "json") -> Path written
    summary: dict
    points: int  #: rows written to the CSV

    @property
    def exit_code(self) -> int:
        """0 when every run succeeded, else 1."""
        return 0 if self.success else 1


def output_names(scene: Scene) -> dict:
    """File names of a scene's outputs: ``{"csv", "partial", "png", "json"}``.

    Parameters
    ----------
    scene : Scene
        A validated scene.

    Returns
    -------
    dict
        Kind -> file name: ``frf.*`` for a frequency sweep, ``coefficients.*`` for an amplitude
        sweep, ``modes.*`` for a nonlinear mode, ``optimum.*`` for the damper's optimum, and
        ``summary.json``.

    Examples
    --------
    >>> from hbm.scenes import output_names, scene_from_dict
    >>> scene = scene_from_dict({"damper": {"model": "macroslip", "stiffness": 1.0e6, "slip_force": 1.0},
    ...                          "sweep": {"kind": "amplitude", "omega": [0.0], "amplitude": [0.1, 10.0]}})
    >>> output_names(scene)["csv"]
    'coefficients.csv'
    """
    stem = {"frequency": "frf", "amplitude": "coefficients"}.get(scene.sweep["kind"], scene.sweep["kind"])
    return {"csv": f"{stem}.csv", "partial": f"{stem}.partial.csv", "png": f"{stem}.png", "json": "summary.json"}


def columns(scene: Scene) -> tuple:
    """The CSV columns of ``scene``: the run's columns, then the FRF's or the table's.

    Parameters
    ----------
    scene : Scene
        A validated scene (its ``sweep.kind`` decides the columns).

    Returns
    -------
    tuple of str
        Column names: ``"run"``, ``"model"``, ``"normal_load_N"``, then those of the FRF
        (frequency sweep, ``hbm.output.frf_columns``: with every harmonic of the response DOF and
        ``stable`` when ``effects.harmonics`` > 1) or of the coefficient table (amplitude sweep);
        ``f_Hz`` after ``omega_rad_s`` when ``sweep.unit = "Hz"``.
    """
    hz = in_hz(scene)
    if scene.sweep["kind"] in ("modes", "optimum"):  # frequencies in rad/s whatever sweep.unit
        return RUN_COLUMNS + (MODE_COLUMNS if scene.sweep["kind"] == "modes" else OPTIMUM_COLUMNS)
    if scene.sweep["kind"] == "frequency":
        return RUN_COLUMNS + frf_columns(scene_harmonics(scene), hz=hz)
    return RUN_COLUMNS + ((TABLE_COLUMNS[0], HZ_COLUMN) + TABLE_COLUMNS[1:] if hz else TABLE_COLUMNS)


def in_hz(scene: Scene) -> bool:
    """Whether the scene gives its frequencies in Hz (``sweep.unit = "Hz"``): its outputs then
    report them in Hz too (beside rad/s)."""
    return scene.sweep["unit"] == "Hz"


def scene_harmonics(scene: Scene) -> int:
    """The harmonics of a frequency sweep's table: ``effects.harmonics`` (1 for an amplitude sweep)."""
    return int(scene.effects["harmonics"]) if scene.sweep["kind"] == "frequency" else 1


#: What a resolved sweep table holds beside the scene's keys: the continuation's options and the elements'
#: rtol under the deprecated key's name (both internal), and the amplitude sweep's defaults.
_NOT_SETTINGS = ("options", "tolerance")
_AMPLITUDE_KEYS = ("amplitude", "amplitude_unit", "points")
_STEP_KEYS = ("max_step", "min_step", "max_steps")


def sweep_settings(sweep: dict) -> dict:
    """The sweep as ``summary.json`` states it: the scene's keys that apply to its kind, by their scene names
    (``sweep.tol``, the step controls of a continuation), without the resolved internals (the elements' rtol,
    the option dict) or another kind's defaults (a frequency sweep has no ``points``)."""
    kind = sweep.get("kind")
    out = {k: v for k, v in sweep.items() if v is not None and k not in _NOT_SETTINGS
           and not (kind != "amplitude" and k in _AMPLITUDE_KEYS)}
    if kind != "amplitude":
        out.update({k: sweep["options"][k] for k in _STEP_KEYS if sweep.get("options", {}).get(k) is not None})
    return out

def run_scene(scene: Scene, out: str | Path | None = None, *, plan: Plan | None = None,
              progress: Callable[[Progress], None] | None = None) -> SceneResult:
    """Run every computation of ``scene``, writing its outputs to ``out`` (default
    ``scene.output["folder"]``) as they are computed; see the module docstring.

    ``progress(Progress)`` is called after each point.  A run that fails (the continuation stops
    short, or the element raises) is recorded and the next run goes on; the result's
    ``success`` is False and the CSV keeps its ``.partial.csv`` name.

    Parameters
    ----------
    scene : Scene
        A validated scene (``load_scene``, ``scene_from_dict``).
    out : str, Path or None, optional
        Output folder, created if needed; files of an earlier run of the scene there are removed
        first.  Default ``scene.output["folder"]``.
    plan : Plan or None, optional
        The scene's plan, when it is made already (``plan_scene(scene)``); default planned here.
    progress : callable or None, optional
        ``progress(Progress)``, called after each point written; default None.

    Returns
    -------
    SceneResult
        ``success``, ``message``, the per-run results, the files written and the summary.  A
        failed run does not raise: it is reported here, and the points before it are kept.

    Raises
    ------
    SceneError
        When ``plan`` is None and the scene is physically impossible (see ``plan_scene``).

    Examples
    --------
    An amplitude sweep of a Jenkins element at one frequency: 5 amplitudes, 5 rows.

    >>> import tempfile
    >>> from hbm.scenes import run_scene, scene_from_dict
    >>> scene = scene_from_dict({"damper": {"model": "macroslip", "stiffness": 1.0e6, "slip_force": 1.0},
    ...                          "sweep": {"kind": "amplitude", "omega": [0.0], "amplitude": [0.1, 10.0],
    ...                                    "points": 5},
    ...                          "output": {"formats": ["csv"]}})
    >>> with tempfile.TemporaryDirectory() as out:
    ...     result = run_scene(scene, out)
    >>> result.success, result.points, result.files["csv"].name
    (True, 5, 'coefficients.csv')
    """
    plan = plan if plan is not None else plan_scene(scene)
    folder = Path(out if out is not None else scene.output["folder"])
    formats = scene.output["formats"]
    names = output_names(scene)
    folder.mkdir(parents=True, exist_ok=True)
    for key in ("csv", "partial", "png", "json"):  # stale outputs of an earlier run of this scene
        (folder / names[key]).unlink(missing_ok=True)
    t_start = time.perf_counter()
    files = {}
    results = [RunResult(p) for p in plan.runs]
    written = 0
    partial = folder / names["partial"]
    kind = scene.sweep["kind"]
    freq = kind == "frequency"
    compute = {"frequency": _run_frequency, "amplitude": _run_amplitude, "modes": run_modes,
               "optimum": run_optimum}[kind]
    stream = CsvStream(partial, columns(scene), comments=csv_comments(scene, plan)) if "csv" in formats else None
    try:
        for res in results:
            head = [res.number, res.plan.model, "" if res.plan.N is None else repr(float(res.plan.N))]

            def emit(row, omega, fraction, res=res, head=head):
                nonlocal written
                if stream is not None:
                    stream.write(head + row)
                written += 1
                res.points += 1
                if progress is not None:
                    progress(Progress(res.number, len(results), res.plan.label, omega, fraction, written,
                                      time.perf_counter() - t_start))

            t0 = time.perf_counter()
            try:
                compute(scene, plan, res, emit)
            except (ArithmeticError, ValueError, RuntimeError, np.linalg.LinAlgError) as exc:
                res.success = False
                res.message = f"{type(exc).__name__}: {exc}"
            res.seconds = time.perf_counter() - t0
            res.summary = run_summary(res, hz=in_hz(scene)) | modal_summary(res, scene)
    finally:
        if stream is not None:
            stream.close()
    if stream is not None and freq:
        _fill_after_run(partial, results)
    success = all(r.success for r in results)
    if "csv" in formats:
        files["csv"] = partial.replace(folder / names["csv"]) if success else partial
    if success and "png" in formats:
        files["png"] = (figure(scene, results, folder / names["png"], blade=plan.blade) if kind in ("frequency", "amplitude")
                        else modal_figure(scene, results, folder / names["png"]))
    message = ("every run succeeded" if success else
               "; ".join(f"run {r.number} ({r.plan.label}) failed: {r.message}" for r in results if not r.success))
    summary = {
        "scene": str(scene.path),
        "title": scene.title,
        "status": "success" if success else "failed",
        "message": message,
        "kind": scene.sweep["kind"],
        "settings": sweep_settings(scene.sweep),
        **({"modes": scene.modes} if scene.modes is not None else {}),
        **({"optimum": scene.optimum} if scene.optimum is not None else {}),
        "tol": scene.sweep["tol"],
        "effects_tolerance": scene.effects["tolerance"],
        "runs": [r.summary for r in results],
        "points_written": written,
        "elapsed_s": time.perf_counter() - t_start,
        "outputs": {k: str(v) for k, v in files.items()},
    }
    if "json" in formats:
        files["json"] = folder / names["json"]
        summary["outputs"]["json"] = str(files["json"])
        replace_atomically(files["json"], lambda fh: fh.write(json.dumps(jsonable(summary), indent=2) + "\n"))
    return SceneResult(plan, results, success, message, files, summary, written)


def _run_frequency(scene, plan, res, emit):
    p = res.plan
    w0, w1 = p.omega
    H, hz = scene_harmonics(scene), in_hz(scene)

    def on_point(point):  # above one harmonic, stability is known once the run ends (_fill_stability)
        omega = point.omega
        row = frf_row(omega, point.x_c, point.x_s, point.residual)
        row = with_hz(row, omega) if hz else row
        if H > 1:
            row = row + harmonic_values(point.harmonics, H) + [stable_value(None)]
        emit(row, omega, (omega - w0) / (w1 - w0))

    damper, response_dof = p.element, None
    if scene.structure is not None:  # a structure from matrices: the damper at structure.contact_dofs, its contacts
        damper = [damper_contact(scene, p.element, p.model), *plan.contacts]
        response_dof = scene.structure.get("response_dof")
    at_peak = peak_refined(scene, p)
    with warnings.catch_warnings():  # the scene's keys of an earlier release warned on loading, in its terms
        warnings.filterwarnings("ignore", r"frequency_response\((accuracy|rtol)=\.\.\.\) is deprecated",
                                DeprecationWarning)
        frf = frequency_response(plan.blade, damper, (w0, w1), harmonics=p.harmonics, n_t=p.n_t,
                                 response_dof=response_dof, callback=on_point,
                                 **({"model": "peak"} if at_peak else {}), **accuracy_options(scene))
    res.frf = frf
    res.success = frf.success
    res.message = frf.message
    if len(frf):
        res.peak = frf.peak()
        if at_peak:
            _said(p, frf)


def peak_refined(scene: Scene, p: RunPlan) -> bool:
    """Whether the run's peak is solved with the damper's refined model where the estimate asks for it
    (``frequency_response(..., model="peak")``): ``damper.model = "auto"`` with
    ``effects.phase_differences = "auto"`` that kept the single-mode element (one with a refined model:
    not held stuck, with inertia) for a blade at H = 1, the case the "phase differences" effect names
    (``hbm.scenes.effects.phase_differences``).  The solve then traces again, with the bar of every
    mode, the windows of the curve that hold the peak where the model part of the estimate exceeds
    half of tol, as ``damper.model = "auto"`` over the bulk of a sweep would trace the whole curve."""
    el = p.element  # a single-mode bar has a refined model; a discretised one (the all-mode bar) refines its rungs
    return (p.name == "auto" and scene.effects["phase_differences"] == "auto" and scene.structure is None
            and p.harmonics in (None, 1) and not el.discretised and el.frequency_dependent  # (with inertia)
            and el.refined_model() is not None)


def accuracy_options(scene: Scene) -> dict:
    """``frequency_response``'s accuracy keywords of a scene: ``tol`` from ``sweep.tol``; ``steps`` from
    the step keys that differ from ``hbm.Steps()``; and the keys of an earlier release, read as the API
    reads them: ``sweep.accuracy`` as ``accuracy=<name>`` (a named tolerance with its old rtol, steps and
    H), ``sweep.tolerance`` as ``rtol``."""
    opts = scene.sweep["options"]
    out: dict = {}
    if "tol" in opts:
        out["tol"] = opts["tol"]
    if scene.sweep.get("accuracy"):
        out["accuracy"] = scene.sweep["accuracy"]
        return out
    base = Steps()
    steps = {k: opts[k] for k in STEP_OPTIONS if k in opts and opts[k] != getattr(base, k)}
    if steps:
        out["steps"] = Steps(**steps)
    if opts.get("rtol", DEFAULT_RTOL) != DEFAULT_RTOL:
        out["rtol"] = opts["rtol"]
    return out


def _said(p: RunPlan, frf: Any) -> None:
    """Add to the run's "phase differences" effect what the peak's check found (``damper.model = "auto"``):
    the model part of the single-mode curve's estimate at its largest point (the curve the solve traced
    first, with the element as given), and, where it exceeded tol/2, the model, H and estimate of the
    point the peak was answered from and how far the single-mode curve's largest point is off the peak."""
    effect = next((e for e in p.effects if e.name == PHASE_EFFECT and not e.simulated), None)
    if effect is None or frf.tol is None or "computed:" in effect.reason:
        return
    first = frf._work[0]  # the whole range traced with the element as given (hbm.adapt.along)
    i = int(np.argmax(first.amplitude))
    model = float(first.error_sources["model"][i])
    j = peak_point(frf)
    half = MODEL_SHARE * frf.tol
    if frf.point_models[j] == first.point_models[i]:
        effect.reason += (f"; computed: the model part of the estimate at the peak is {model:.2g}, "
                          f"{'not above' if model <= half else 'above'} tol/2 = {half:g}: the single-mode peak stands")
        return
    pk = frf.peak()
    off = float(first.amplitude[i]) / pk.amplitude - 1.0
    effect.reason += (f"; computed: the model part of the estimate at the peak is {model:.2g} > tol/2 = {half:g}: "
                      f"the peak is the bar's with every mode ({frf.point_models[j]}, H = {frf.point_harmonics[j]}, "
                      f"estimated error {pk.estimate:.2g}); the single-mode curve's largest point is "
                      f"{100.0 * off:+.2g} % off it")


def csv_comments(scene: Scene, plan: Plan) -> dict:
    """The ``#`` lines of a scene's CSV (``hbm.output.CsvStream``): the library version, the case
    (the scene's title and file), the models of its runs and the tolerance the error column is
    estimated against (``sweep.tol``, else ``frequency_response``'s default)."""
    from contact_models import __version__  # lazily, as hbm.output.frf_comments

    tol = scene.sweep.get("tol")
    shown = f"{DEFAULT_TOL:g} (frequency_response's default)" if tol is None else f"{tol:g} (sweep.tol)"
    return {"frictiondamp": __version__, "case": f"{scene.title or scene.name} ({scene.path})",
            "model": ", ".join(dict.fromkeys(r.model for r in plan.runs)),
            "tol": shown + ("; error_rel is each point's estimate" if scene.sweep["kind"] == "frequency" else "")}


def _fill_after_run(path, results):
    """Fill what is known once a run ends into a scene's CSV: ``error_rel`` from each run's
    ``frf.error_estimate`` and, above one harmonic, the ``stable`` column (the last) from
    ``frf.stable`` (Hill's method), rewriting the file through a temporary name; a run without a
    result, or whose points differ from its rows, keeps them empty."""
    with path.open(newline="") as fh:
        lines = fh.readlines()
    comments = [line for line in lines[1:] if line.startswith(COMMENT)]  # after the column names (CsvStream)
    rows = list(csv.reader(csv_lines(lines)))
    by_number = {r.number: r for r in results}
    error = rows[0].index(ERROR_COLUMN)
    stable = rows[0][-1] == STABLE_COLUMN
    seen = {}
    for row in rows[1:]:
        res = by_number.get(int(row[0]))
        k = seen[res.number] = seen.get(res.number, -1) + 1
        if res.frf is not None and len(res.frf) == res.points:
            row[error] = error_value(res.frf.error_estimate[k])
            if stable:
                row[-1] = stable_value(res.frf.stable[k])

    def write(fh):
        out = csv.writer(fh)
        out.writerows(rows[:1])
        fh.writelines(comments)
        out.writerows(rows[1:])

    replace_atomically(path, write)


def replace_atomically(path: Path, write: Callable[[Any], Any]) -> Path:
    """Write ``path`` whole or not at all: ``write(fh)`` into ``path.tmp``, then rename it onto ``path``;
    on any failure (a full disk) the ``.tmp`` file is removed and the error raised."""
    tmp = path.with_name(path.name + ".tmp")
    try:
        with tmp.open("w", newline="") as fh:
            write(fh)
        return tmp.replace(path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def _run_amplitude(scene, plan, res, emit):
    p = res.plan
    a0, a1 = scene.sweep["amplitude"]
    over = np.geomspace(a0, a1, scene.sweep["points"])
    a = over * p.a_ref
    el = p.element
    k_star = float(el.stuck_stiffness(0.0))
    table = {"omega": [], "a": a, "F_s": [], "F_c": []}
    for j, w in enumerate(p.omega):
        fs, fc = el.fourier(a, w, rtol=scene.sweep["tolerance"])
        Fs, Fc = fs / (k_star * a), fc / (k_star * a)
        for i in range(len(a)):
            row = [repr(float(v)) for v in (w, a[i], over[i], fs[i], fc[i], Fs[i], Fc[i])]
            emit(with_hz(row, w) if in_hz(scene) else row, w, (j + (i + 1) / len(a)) / len(p.omega))
        table["omega"].append(w)
        table["F_s"].append(Fs)
        table["F_c"].append(Fc)
    res.table = table
    res.success = True
    res.message = "table complete"


def duration(seconds: float) -> str:
    """``42 s``, ``3 min 5 s``, ``2 h 10 min``: a time left, for the progress lines of a scene and a study."""
    s = int(round(seconds))
    if s < 60:
        return f"{s} s"
    if s < 3600:
        return f"{s // 60} min {s % 60} s"
    return f"{s // 3600} h {s % 3600 // 60} min"


__all__ = ["run_scene", "Progress", "RunResult", "SceneResult", "output_names", "columns", "in_hz", "scene_harmonics",
           "accuracy_options", "peak_refined"]
