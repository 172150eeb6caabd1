"""Parameter studies: many runs (a grid, random samples), on every core or a Dask cluster.

A :class:`Study` is a runner (a picklable function of one point) and its points
(:func:`grid`, :func:`samples` with :func:`uniform`, :func:`normal`, :func:`lognormal`, or
both with :func:`combine`); :meth:`Study.from_scene` makes one from a scene file's ``[study]``
table.  :func:`run_study` runs it serially, on local processes (the default) or on Dask, writes
each finished run as it finishes, and on a rerun into the same folder computes only the runs it
does not find there (``hbm.study.store``).  ``docs/studies.md`` shows it all.

Examples
--------
>>> import tempfile
>>> def run(point):  # any picklable function of a point: an FRF, or a dict of results
...     return {"peak_amplitude_m": point["x"] ** 2}
>>> study = Study(run, grid({"x": [1.0, 2.0, 3.0]}))
>>> result = run_study(study, tempfile.mkdtemp(), executor="serial", formats=("csv",))
>>> result.success, result.column("peak_amplitude_m").tolist()
(True, [1.0, 4.0, 9.0])
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

import numpy as np

import contact_models  # its __version__ is read at each call (a new version recomputes)
from contact_models.accuracy import AccuracyWarning

from ..scenes import SceneError, effect_lines, plan_scene, scene_from_dict
from ..scenes.validation import apply_overrides, read_toml

from ..designs import (DISTRIBUTIONS, MAX_RUNS, Distribution, Points, combine, grid, lognormal, normal, point_list,
                       run_id, samples, uniform)
from .execute import DASK_MISSING, EXECUTORS, check_executor, cores, run_tasks
from .lock import FolderInUse
from .runs import RESULT_COLUMNS, SceneRun, execute, outcome
from .store import FILES, StudyProgress, StudyResult, columns, read_records, run_into


@dataclass
class Study:
    """A study: ``runner(point)`` for every point of ``points``.

    Parameters
    ----------
    runner : callable
        A pure, picklable function of one point (a dict) returning an ``hbm.FrequencyResponse``
        or a dict of results (:func:`hbm.study.runs.outcome`); a module-level function or an object
        such as :class:`SceneRun`.  It may define ``identity(point)``, the inputs its run depends on
        (default: its qualified name and the point).
    points : sequence of dict
        The points, every one with the same names (:func:`grid`, :func:`samples`, :func:`combine`).
    title : str, optional
        Copied to ``study.json`` and the figure.
    settings : dict, optional
        Defaults of :func:`run_study` (``executor``, ``workers``, ``scheduler``, ``folder``,
        ``formats``), set by :meth:`from_scene`.
    design : dict, optional
        How the points were made (``grid``, ``samples``, ``n``, ``seed``), for ``study.json``.

    Raises
    ------
    ValueError
        If ``runner`` is not callable, ``points`` is empty or longer than :data:`MAX_RUNS`, or the
        points' names differ.
    """

    runner: Callable[[Mapping[str, Any]], Any]
    points: Sequence[Mapping[str, Any]]
    title: str = ""
    settings: dict = field(default_factory=dict)
    design: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not callable(self.runner):
            raise ValueError(f"runner must be callable, got runner={self.runner!r}")
        point_list("points", self.points)
        if len(self.points) > MAX_RUNS:  # refused before a single point is made
            raise ValueError(f"points = {len(self.points)} runs, more than a study may make (MAX_RUNS = {MAX_RUNS})")
        self.points = [{k: v.item() if isinstance(v, np.generic) else v for k, v in p.items()} for p in self.points]
        if not self.points:
            raise ValueError("points must hold at least one point, got points=[]")
        names = set(self.points[0])
        for i, p in enumerate(self.points):
            if set(p) != names:
                raise ValueError(f"every point must name the same parameters: point {i + 1} has {sorted(p)}, "
                                 f"point 1 has {sorted(names)}")

    @property
    def parameters(self) -> tuple:
        """The names varied, in the order of the first point."""
        return tuple(self.points[0])

    def identity(self, point: Mapping[str, Any]) -> Any:
        """The inputs of the run of ``point`` (what its id hashes)."""
        own = getattr(self.runner, "identity", None)
        if own is not None:
            return own(point)
        r = self.runner
        return {"runner": f"{getattr(r, '__module__', '?')}.{getattr(r, '__qualname__', repr(r))}",
                "point": dict(point)}

    def ids(self) -> list[str]:
        """The id of every run: :func:`run_id` of its inputs and ``contact_models.__version__``."""

        return [run_id(self.identity(p), contact_models.__version__) for p in self.points]

    @classmethod
    def from_scene(cls, path: str | Path, *, overrides: Mapping[str, Any] | None = None) -> "Study":
        """The study of the scene file ``path`` (its ``[study]`` table; ``docs/studies.md``).

        ``overrides`` as for :func:`hbm.scenes.load_scene`.  Raises :class:`hbm.scenes.SceneError`
        for an invalid scene, one without ``[study]``, or a point whose scene is invalid or makes
        more than one run (every problem at once, naming the run); ``ValueError`` for a study of
        more than :data:`MAX_RUNS` runs.
        """
        scene, runner = _scene_study(path, overrides)
        problems = []
        for i, point in enumerate(scene.study["points"]):
            problems += _problems(runner, i, point)
        _refuse(problems)
        st = scene.study
        settings = {k: st.get(k) for k in ("executor", "workers", "scheduler", "time_limit")}
        settings.update(folder=scene.output["folder"], formats=scene.output["formats"])
        design = {"grid": st.get("grid"), "n": st.get("n"), "seed": st.get("seed"),
                  "samples": {k: d.as_dict() for k, d in (st.get("samples") or {}).items()} or None}
        return cls(runner, scene.study["points"], title=scene.title, settings=settings, design=design)


def _scene_study(path: str | Path, overrides: Mapping[str, Any] | None) -> tuple:
    """``(scene, runner)`` of a study scene; its points are made when asked for (``Points``)."""

    path = Path(path)
    data = read_toml(path)
    scene = scene_from_dict(data, path, overrides=overrides)
    if scene.study is None:
        raise SceneError([f"{path}: [study] is missing: a study needs study.grid or study.samples"])
    return scene, SceneRun(apply_overrides(data, overrides or {}), str(path))


def _problems(runner: SceneRun, i: int, point: Mapping[str, Any]) -> list:
    """The problems of the scene of run ``i + 1``, each naming the run."""

    try:
        runner.scene(point)
    except SceneError as exc:
        where = ", ".join(f"{k} = {v!r}" for k, v in point.items())
        return [f"run {i + 1} ({where}): {p}" for p in exc.problems]
    return []


def _refuse(problems: list) -> None:

    if problems:
        raise SceneError(list(dict.fromkeys(problems)))


def check_scene(path: str | Path, *, overrides: Mapping[str, Any] | None = None) -> list[str]:
    """Validate a study scene without making its runs: what ``python3 -m hbm run SCENE --check``
    prints for a scene with ``[study]``.

    It checks the scene, its ``[study]`` table, the number of runs (at most :data:`MAX_RUNS`)
    and the scene of run 1, whose effects it lists; it costs the same for ten runs as for a
    million, since no other run's point is made.  The scene of every run is checked when the
    study starts (:meth:`Study.from_scene`).

    Parameters
    ----------
    path : str or pathlib.Path
        The scene file.
    overrides : mapping, optional
        As for :func:`hbm.scenes.load_scene`.

    Returns
    -------
    list of str
        The lines to print.

    Raises
    ------
    hbm.scenes.SceneError
        For an invalid scene, one without ``[study]``, or an invalid scene of run 1.
    ValueError
        For a study of more than :data:`MAX_RUNS` runs.
    """

    scene, runner = _scene_study(path, overrides)
    points = scene.study["points"]
    first = points[0]
    _refuse(_problems(runner, 0, first))
    return [f"scene {path} is valid: a study of {len(points)} run(s) over {', '.join(first)}",
            "(checked: the scene, its [study] table and run 1; every run's scene is checked when the study starts)",
            "effects of run 1:", *effect_lines(plan_scene(runner.scene(first)))]


def run_study(study: Study, out: str | Path | None = None, *, executor: Any = None, workers: int | None = None,
              scheduler: str | None = None, progress: Callable[[StudyProgress], None] | None = None,
              retry_failed: bool = True, formats: Sequence[str] | None = None,
              time_limit: float | None = None) -> StudyResult:
    """Run every run of ``study`` not already in the folder ``out``; see ``hbm.study.store``.

    Parameters
    ----------
    study : Study
    out : path, optional
        The output folder (default ``study.settings["folder"]``, else ``"study"``).
    executor : {"processes", "serial", "dask"} or concurrent.futures.Executor, optional
        Default ``study.settings["executor"]``, else ``"processes"`` (every core; ``workers=1``
        runs serially).  ``"dask"`` needs ``pip install "frictiondamp[dask]"``.
    workers : int, optional
        Processes, or workers of the Dask ``LocalCluster``; default every core.
    scheduler : str, optional
        Address of a running Dask scheduler (``tcp://host:8786``): sets ``executor="dask"``;
        without it Dask starts a ``LocalCluster``.
    progress : callable, optional
        Called with a :class:`StudyProgress` after each finished run.
    retry_failed : bool, default True
        Recompute runs recorded as failed in the folder (successful runs are never recomputed).
    formats : sequence of {"csv", "json", "png"}, optional
        Default ``study.settings["formats"]``, else all three.  ``runs.jsonl`` is always written.
    time_limit : float, optional
        Seconds each run may take; default ``study.settings["time_limit"]``, else no limit.  A run over
        it is a failed run whose message names the limit (``hbm.study.execute.run_tasks``).

    Returns
    -------
    StudyResult
        ``records`` in the study's order, ``success`` (every run recorded and succeeded),
        ``lost`` (runs not computed: a worker died), ``files``, ``summary``.

    Raises
    ------
    FolderInUse
        If another live process is writing a study into ``out`` (a ``ValueError``; nothing is
        changed there).  The folder's ``study.lock`` holds this process's PID for the call and is
        removed when it ends, however it ends; a lock left by a killed process is taken over.
    ValueError
        For an unknown executor or invalid ``workers``, ``scheduler`` or ``formats``, or a Dask
        scheduler that cannot be reached or is not one (the folder is then left as it was).
    ImportError
        For ``executor="dask"`` without dask and distributed (the message says how to install them).

    Warns
    -----
    AccuracyWarning
        Once, if any run emitted one (:attr:`StudyResult.warning`: how many runs warned, the
        worst and its warning); the runs' own warnings are recorded, not shown.

    Notes
    -----
    Points are drawn before any run starts and every run is the pure function
    :func:`hbm.study.runs.execute` of its point, so the table (apart from ``time_s``) is the same
    to the last bit on every executor.  Ctrl-C (KeyboardInterrupt) stops the workers and
    propagates (a further Ctrl-C while the workers stop is ignored); every run finished before
    it is in ``runs.jsonl`` and ``study.partial.csv``.  Worker processes end on their own within
    a second when this process is killed (SIGKILL).
    """
    if not isinstance(study, Study):
        raise ValueError(f"study must be an hbm.study.Study, got study={study!r}")
    s = study.settings
    if executor is None:  # the study's settings, unless asked otherwise
        scheduler = scheduler if scheduler is not None else s.get("scheduler")
        executor = "dask" if scheduler is not None else (s.get("executor") or "processes")
    elif executor == "dask" and scheduler is None:
        scheduler = s.get("scheduler")
    workers = workers if workers is not None else s.get("workers")
    time_limit = time_limit if time_limit is not None else s.get("time_limit")
    check_executor(executor, workers, scheduler)
    formats = tuple(formats if formats is not None else s.get("formats") or ("csv", "json", "png"))
    unknown = set(formats) - {"csv", "json", "png"}
    if unknown:
        raise ValueError(f"formats may hold 'csv', 'json', 'png', got formats={formats!r}")
    folder = Path(out if out is not None else s.get("folder") or "study")

    describe = {"title": study.title, "version": contact_models.__version__, "parameters": list(study.parameters),
                **study.design, "executor": executor if isinstance(executor, str) else type(executor).__name__,
                "scheduler": scheduler}
    local = executor in ("processes", "dask") and scheduler is None
    describe["workers"] = 1 if executor == "serial" else workers or (cores() if local else None)
    describe["time_limit_s"] = time_limit

    def run(tasks, on_done, on_start):
        return run_tasks(study.runner, tasks, on_done, executor=executor, workers=workers, scheduler=scheduler,
                         on_start=on_start, time_limit=time_limit)

    result = run_into(study, folder, run=run, formats=formats, retry_failed=retry_failed, progress=progress,
                      describe=describe)
    if result.warning is not None:  # the runs' warnings, said once for the study (each is in its record)
        warnings.warn(f"run_study: {result.warning}", AccuracyWarning, stacklevel=2)
    return result


__all__ = ["Study", "run_study", "check_scene", "MAX_RUNS", "Points", "StudyResult", "StudyProgress", "grid",
           "samples", "combine", "uniform", "normal", "lognormal", "Distribution", "DISTRIBUTIONS", "SceneRun",
           "execute", "outcome", "run_id", "columns", "read_records", "run_tasks", "cores", "FolderInUse",
           "EXECUTORS", "DASK_MISSING", "RESULT_COLUMNS", "FILES"]
