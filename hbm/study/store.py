"""Running a study into a folder: each finished run written as it finishes, and resumed.

Files (``docs/studies.md``):

- ``runs.jsonl``: one JSON line per finished run (its number, id, point, results and curve),
  appended and flushed as the run finishes, so an interrupted study keeps every finished run;
- ``study.partial.csv`` while runs are missing, ``study.csv`` once every run is recorded: the
  tidy table, one row per run (:func:`columns`);
- ``study.json`` (written last, atomically): the summary and the table without curves;
- ``study.png``: the figure (``hbm.study.figures``);
- ``study.lock`` while a study writes there: the PID of its process (``hbm.study.lock``).

A run is named by :func:`hbm.designs.run_id` of its inputs and the library version; a
rerun into the same folder reuses the records whose id it finds and computes the rest (failed
runs again when ``retry_failed``).
"""

from __future__ import annotations

import contextlib
import json
import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

from ..output import CsvStream
from ..scenes.reporting import jsonable
from ..scenes.running import duration, replace_atomically
from .execute import signals_held
from .figures import figure
from .lock import LOCK, hold
from .runs import RESULT_COLUMNS

#: File names in a study's folder.
FILES = {"records": "runs.jsonl", "csv": "study.csv", "partial": "study.partial.csv", "json": "study.json",
         "png": "study.png", "lock": LOCK}


def columns(parameters: tuple) -> tuple:
    """The table's columns: ``run`` (from 1), ``id`` (the run's hash), the parameters, then
    :data:`hbm.study.RESULT_COLUMNS`.

    Parameters
    ----------
    parameters : tuple of str
        The names varied, in the study's order.

    Returns
    -------
    tuple of str
        The column names.

    Examples
    --------
    >>> columns(("damper.mu",))[:5]
    ('run', 'id', 'damper.mu', 'success', 'message')
    >>> columns(("damper.mu",))[5:]
    ('peak_omega_rad_s', 'peak_amplitude_m', 'peak_error_rel', 'peak_model', 'nfev', 'time_s')
    """
    return ("run", "id", *parameters, *RESULT_COLUMNS)


def _cell(v: Any) -> str:
    if v is None:
        return ""
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (float, np.floating)):
        return repr(float(v))
    return str(v)


def csv_row(record: dict, parameters: tuple) -> list[str]:
    """A record as the cells of :func:`columns` (floats round-trip exact)."""
    return [_cell(record["run"]), record["id"], *(_cell(record["params"].get(p)) for p in parameters),
            *(_cell(record.get(c)) for c in RESULT_COLUMNS)]


def read_records(path: str | Path) -> dict:
    """``{id: record}`` of a ``runs.jsonl`` (the last record of an id wins); a damaged line (cut
    short by an interruption, not UTF-8, not JSON, or not a record) is skipped.

    Parameters
    ----------
    path : str or pathlib.Path
        The ``runs.jsonl`` file; a missing file gives ``{}``.

    Returns
    -------
    dict
        ``{id: record}``, a record being the dict of one JSON line.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "runs.jsonl"
    >>> _ = path.write_text('{"id": "a", "run": 1}\\n{"id": "b", "run": 2}\\n{"id": "c", "ru')
    >>> sorted(read_records(path))
    ['a', 'b']
    """
    return scan_records(path)[0]


def scan_records(path: str | Path) -> tuple[dict, int]:
    """``(records, damaged)``: :func:`read_records` and the number of damaged lines it skipped.

    The file is read as bytes and each line decoded as UTF-8 on its own, so one line that is not
    UTF-8 (a disk fault, a foreign write) is one damaged line like any other.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "runs.jsonl"
    >>> _ = path.write_bytes(b'{"id": "a"}\\n\\xff\\xfe\\n[1, 2]\\n{"id": "b"}\\n{"id": "c", "ru')
    >>> records, damaged = scan_records(path)
    >>> sorted(records), damaged
    (['a', 'b'], 3)
    """
    out: dict = {}
    damaged = 0
    try:
        data = Path(path).read_bytes()
    except FileNotFoundError:
        return out, damaged
    conflicts: set = set()
    for line in data.split(b"\n"):
        if not line.strip():
            continue
        try:
            rec = json.loads(line.decode("utf-8"))
        except (UnicodeDecodeError, json.JSONDecodeError, RecursionError):  # RecursionError: nested past any record
            damaged += 1
            continue
        if isinstance(rec, dict) and isinstance(rec.get("id"), str):
            before = out.get(rec["id"])
            if before is not None and before.get("success") is True and _result(before) != _result(rec):
                conflicts.add(rec["id"])  # two different results of one run: neither is trusted
            out[rec["id"]] = rec
        else:
            damaged += 1
    for rid in conflicts:
        del out[rid]
        damaged += 1
    return out, damaged


def _result(rec: dict) -> dict:
    """A record's result fields (what a rerun of the same point gives again; not its time)."""
    return {k: v for k, v in rec.items() if k not in ("time_s", "run")}


def _number(v: Any, *, optional: bool = True) -> bool:
    return (v is None and optional) or (not isinstance(v, bool) and isinstance(v, (int, float)) and math.isfinite(v))


def usable(rec: dict, point: dict) -> bool:
    """Whether ``rec`` (a line of ``runs.jsonl``) is a record of ``point`` that a resume may reuse:
    every field of :data:`hbm.study.RESULT_COLUMNS` present with its type (``success`` a bool, the
    peaks None or finite numbers, ``nfev`` None or an integer, ``time_s`` a finite number), ``curve`` a
    table of lists of numbers, and ``params`` the point.  Anything else is a damaged line: recomputed."""
    try:
        curve = rec.get("curve", {})
        return (rec.get("params") == json.loads(json.dumps(jsonable(point))) and isinstance(rec.get("success"), bool)
                and isinstance(rec.get("message"), str)
                and all(_number(rec.get(k, 0.0)) and k in rec for k in ("peak_omega_rad_s", "peak_amplitude_m",
                                                                          "peak_error_rel"))
                and (rec.get("peak_model") is None or isinstance(rec["peak_model"], str)) and "peak_model" in rec
                and (rec.get("nfev") is None or (isinstance(rec["nfev"], int) and not isinstance(rec["nfev"], bool)))
                and "nfev" in rec and _number(rec.get("time_s"), optional=False)
                and isinstance(curve, dict) and all(isinstance(k, str) and isinstance(v, list) and all(
                    not isinstance(x, bool) and isinstance(x, (int, float)) for x in v) for k, v in curve.items()))
    except (TypeError, ValueError, RecursionError):
        return False


@dataclass
class StudyProgress:
    """Passed to the ``progress`` callback of :func:`hbm.study.run_study` after each run.

    Attributes
    ----------
    points : int
        Runs finished, reused ones included.
    runs : int
        Runs of the study.
    failed : int
        Finished runs that failed.
    reused : int
        Runs found in the folder and not recomputed.
    elapsed : float
        Time since the study started, in s.

    Examples
    --------
    >>> p = StudyProgress(points=4, runs=10, failed=1, reused=2, elapsed=3.0)
    >>> p.eta
    9.0
    """

    points: int  #: runs finished (reused ones included)
    runs: int  #: runs of the study
    failed: int  #: finished runs that failed
    reused: int  #: runs found in the folder and not recomputed
    elapsed: float  #: seconds since the study started

    @property
    def eta(self) -> float | None:
        """Seconds left, from the time per run computed so far (None before the first)."""
        done = self.points - self.reused
        return self.elapsed * (self.runs - self.points) / done if done > 0 else None

    def line(self) -> str:
        """``run 12/57 (1 failed, 3 reused), 4.1 s, about 15 s left``."""
        notes = ", ".join(s for s in (f"{self.failed} failed" if self.failed else "",
                                      f"{self.reused} reused" if self.reused else "") if s)
        eta = self.eta

        return (f"run {self.points}/{self.runs}" + (f" ({notes})" if notes else "") + f", {self.elapsed:.1f} s"
                + ("" if eta is None else f", about {duration(eta)} left"))


@dataclass
class StudyResult:
    """What :func:`hbm.study.run_study` did.

    ``records`` holds one record per run in the study's order (None for a run not computed:
    interrupted, or lost with its worker); a record is a dict with ``run``, ``id``, ``params``,
    the :data:`hbm.study.RESULT_COLUMNS` and ``curve``.

    Attributes
    ----------
    parameters : tuple of str
        The names varied.
    records : list of dict or None
        One record per run, in the study's order (None for a run not computed).
    files : dict
        The files written, by kind (``"records"``, ``"csv"``, ``"partial"``, ``"json"``,
        ``"png"``) as ``pathlib.Path``.
    computed : int
        Runs computed by this call.
    reused : int
        Runs found in the folder and not recomputed.
    lost : list of (int, str)
        ``(run number, reason)`` of the runs not computed (a worker died); a rerun into the same
        folder computes them.
    elapsed : float
        Wall-clock time of the call, in s.
    summary : dict
        The summary written to ``study.json``.
    damaged : int
        Damaged lines of the folder's ``runs.jsonl`` skipped when it was read (cut short, not
        UTF-8, not JSON, not a record); they are dropped from it.

    Examples
    --------
    >>> r = StudyResult(parameters=("x",), records=[None], files={}, computed=0, reused=0,
    ...                 lost=[(1, "worker died")], elapsed=0.0)
    >>> r.complete, r.success, r.exit_code
    (False, False, 1)
    """

    parameters: tuple  #: the names varied
    records: list
    files: dict  #: kind -> Path written
    computed: int  #: runs computed by this call
    reused: int  #: runs found in the folder
    lost: list  #: ``[(run number, reason)]`` of runs not computed
    elapsed: float
    summary: dict = field(default_factory=dict)
    damaged: int = 0  #: damaged lines of runs.jsonl skipped (cut short, not UTF-8, not a record)

    @property
    def complete(self) -> bool:
        """Every run has a record (succeeded or failed)."""
        return all(r is not None for r in self.records)

    @property
    def success(self) -> bool:
        """Every run recorded and succeeded."""
        return self.complete and all(r["success"] for r in self.records)

    @property
    def exit_code(self) -> int:
        return 0 if self.success else 1

    @property
    def message(self) -> str:
        failed = [r for r in self.records if r is not None and not r["success"]]
        parts = [f"run {r['run']} failed: {r['message']}" for r in failed[:5]]
        if len(failed) > 5:
            parts.append(f"and {len(failed) - 5} more failed runs")
        if self.lost:
            parts.append(f"{len(self.lost)} run(s) not computed (first: run {self.lost[0][0]}: {self.lost[0][1]}); "
                         "run the study again into the same folder to compute them")
        missing = sum(r is None for r in self.records) - len(self.lost)
        if missing > 0:
            parts.append(f"{missing} run(s) not computed")
        return "; ".join(parts) if parts else "every run succeeded"

    @property
    def warned(self) -> list[dict]:
        """The recorded runs whose computation emitted an ``AccuracyWarning`` (their record's
        ``warning``, :func:`hbm.study.runs.execute`), in run order."""
        return [r for r in self.records if r is not None and r.get("warning")]

    @property
    def worst(self) -> dict | None:
        """The run of :attr:`warned` with the largest ``peak_error_rel`` (a run without one counts
        as below every other; the first such run where none has one); None if no run warned."""
        warned = self.warned
        if not warned:
            return None
        return max(warned, key=lambda r: -math.inf if r.get("peak_error_rel") is None else r["peak_error_rel"])

    @property
    def warning(self) -> str | None:
        """The study's runs' warnings in one line: how many runs warned, the worst (:attr:`worst`)
        and its warning; None if no run warned.  :func:`hbm.study.run_study` emits it once as an
        ``AccuracyWarning``; every run's own warning stays in its record.

        Examples
        --------
        >>> recs = [{"run": 1, "params": {"N": 10.0}, "warning": "estimated error 0.02 > tol 0.001",
        ...          "peak_error_rel": 0.02},
        ...         {"run": 2, "params": {"N": 20.0}, "warning": None, "peak_error_rel": 1e-4},
        ...         {"run": 3, "params": {"N": 30.0}, "warning": "estimated error 0.05 > tol 0.001",
        ...          "peak_error_rel": 0.05}]
        >>> r = StudyResult(("N",), recs, {}, 3, 0, [], 1.0)
        >>> print(r.warning)
        2 of 3 runs warned (each run's warning is in its record: runs.jsonl "warning", the table's "message"); the worst, run 3 (N = 30.0), peak_error_rel 0.05: estimated error 0.05 > tol 0.001
        """
        worst = self.worst
        if worst is None:
            return None
        where = ", ".join(f"{p} = {worst['params'].get(p)}" for p in self.parameters)
        err = worst.get("peak_error_rel")
        return (f"{len(self.warned)} of {len(self.records)} runs warned (each run's warning is in its record: "
                f"runs.jsonl \"warning\", the table's \"message\"); the worst, run {worst['run']} ({where})"
                + ("" if err is None else f", peak_error_rel {err:.2g}") + f": {worst['warning']}")

    @property
    def columns(self) -> tuple:
        return columns(self.parameters)

    @property
    def rows(self) -> list[dict]:
        """The table: one dict per recorded run (:attr:`columns`, no curves), in run order."""
        return [{"run": r["run"], "id": r["id"], **{p: r["params"].get(p) for p in self.parameters},
                 **{c: r.get(c) for c in RESULT_COLUMNS}} for r in self.records if r is not None]

    def to_dataframe(self) -> Any:
        """The table (:attr:`rows`, the columns of ``study.csv``) as a ``pandas.DataFrame``, one row
        per recorded run in run order; needs pandas (``pip install "frictiondamp[pandas]"``),
        ``ImportError`` naming the extra without it."""
        from ..output import pandas_module  # lazily, as pandas itself

        return pandas_module().DataFrame(self.rows, columns=list(self.columns))

    def column(self, name: str) -> np.ndarray:
        """One column over the recorded runs as an array (numbers as float, None as NaN)."""
        if name not in self.columns:
            raise ValueError(f"column must be one of {', '.join(self.columns)}, got column={name!r}")
        values = [row[name] for row in self.rows]
        if all(v is None or (isinstance(v, (int, float)) and not isinstance(v, bool)) for v in values):
            return np.array([math.nan if v is None else float(v) for v in values])
        return np.array(values, dtype=object)


def _write_json(path: Path, data: Any) -> Path:

    return replace_atomically(path, lambda fh: fh.write(json.dumps(jsonable(data), indent=2) + "\n"))


def run_into(study: Any, folder: Path, *, run: Callable, formats: tuple, retry_failed: bool,
             progress: Callable[[StudyProgress], None] | None, describe: dict) -> StudyResult:
    """The bookkeeping of :func:`hbm.study.run_study`: lock, reuse, record, write.

    ``run(tasks, on_done, on_start)`` computes ``tasks`` (an executor of ``hbm.study.execute``),
    calls ``on_start()`` once, when its executor is up and before the first run, and returns the
    lost runs.  Nothing in the folder changes before ``on_start``: a study whose executor cannot
    start (a Dask scheduler that cannot be reached) leaves the folder as it was (and no folder
    where there was none).  The folder is locked for the call (:mod:`hbm.study.lock`):
    :class:`hbm.study.lock.FolderInUse` if another process writes a study there.
    """
    created = not folder.exists()
    folder.mkdir(parents=True, exist_ok=True)
    started: list = []
    try:
        with hold(folder):
            return _run_locked(study, folder, run, formats, retry_failed, progress, describe, started)
    finally:
        if created and not started:
            with contextlib.suppress(OSError):
                folder.rmdir()  # only if empty


def _reusable(study: Any, ids: list, old: dict, retry_failed: bool) -> tuple[list, int]:
    """``(records, unusable)``: the record of each run found in ``old`` that may be reused (None
    elsewhere), and how many found were unusable (:func:`usable`: computed again, counted as damaged)."""
    records: list = [None] * len(ids)
    unusable = 0
    for i, rid in enumerate(ids):
        rec = old.get(rid)
        if rec is not None and not usable(rec, study.points[i]):
            unusable += 1  # wrong types, a non-finite peak, another point's record
            rec = None
        if rec is not None and (rec["success"] or not retry_failed):
            records[i] = {**rec, "run": i + 1, "params": study.points[i]}
    return records, unusable


def table_comments(describe: dict) -> dict:
    """The ``#`` lines of a study's table (``hbm.output.CsvStream``): the library version, the
    study's title and what it varies, and what ``peak_error_rel`` is."""
    return {"frictiondamp": describe.get("version"), "case": describe.get("title") or None,
            "parameters": ", ".join(describe.get("parameters") or ()),
            "peak_error_rel": "each run's estimated relative error of its peak amplitude (empty: not estimated)"}


def _write_table(path: Path, records: list, params: tuple, comments: dict | None = None) -> Path:
    """The whole table at ``path``, written beside it and renamed onto it; on a failure (a full
    disk) no half table is left behind."""
    tmp = path.with_name(path.name + ".tmp")
    try:
        with CsvStream(tmp, columns(params), comments=comments) as csv_out:
            for r in records:
                csv_out.write(csv_row(r, params))
        return tmp.replace(path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def _run_locked(study: Any, folder: Path, run: Callable, formats: tuple, retry_failed: bool,
                progress: Callable[[StudyProgress], None] | None, describe: dict, started: list) -> StudyResult:
    t_start = time.perf_counter()
    ids = study.ids()
    params = study.parameters
    log_path = folder / FILES["records"]
    old, damaged = scan_records(log_path)
    records, unusable = _reusable(study, ids, old, retry_failed)
    damaged += unusable
    reused = sum(r is not None for r in records)
    counts = {"points": reused, "failed": sum(not r["success"] for r in records if r is not None)}
    out: dict = {}  # "log", "stream": open once the executor is up

    def on_start() -> None:
        if started:
            return
        started.append(True)
        for key in ("csv", "partial", "json", "png"):  # outputs of an earlier run of this folder
            (folder / FILES[key]).unlink(missing_ok=True)
        replace_atomically(log_path, lambda fh: fh.write(  # keep only this study's records, atomically
            "".join(json.dumps(r) + "\n" for r in records if r is not None)))
        out["stream"] = stream = (CsvStream(folder / FILES["partial"], columns(params), comments=table_comments(describe))
                                  if "csv" in formats else None)
        out["log"] = log_path.open("a")
        if stream is not None:
            for r in records:
                if r is not None:
                    stream.write(csv_row(r, params))

    def on_done(i: int, rec: dict) -> None:
        rec = {"run": i + 1, "id": ids[i], "params": study.points[i], **rec}
        line = json.dumps(rec) + "\n"
        row = csv_row(rec, params) if out["stream"] is not None else None
        with signals_held():  # the log and the table take the run together, or neither does
            out["log"].write(line)
            out["log"].flush()
            if row is not None:
                out["stream"].write(row)
            records[i] = rec
        counts["points"] += 1
        counts["failed"] += not rec["success"]
        if progress is not None:
            progress(StudyProgress(counts["points"], len(ids), counts["failed"], reused,
                                   time.perf_counter() - t_start))

    try:
        lost = run([(i, study.points[i]) for i, r in enumerate(records) if r is None], on_done, on_start)
        on_start()  # a run() that had nothing to start
    finally:
        if out.get("log") is not None:
            out["log"].close()
        if out.get("stream") is not None:
            out["stream"].close()
    stream = out["stream"]
    result = StudyResult(params, records, {}, counts["points"] - reused, reused,
                         [(i + 1, why) for i, why in lost], time.perf_counter() - t_start, damaged=damaged)
    if stream is not None:
        result.files["csv"] = folder / FILES["partial"]
        if result.complete:
            result.files["csv"] = _write_table(folder / FILES["csv"], records, params, table_comments(describe))
            (folder / FILES["partial"]).unlink()
    result.files["records"] = log_path
    if "png" in formats and any(r is not None and r["success"] for r in records):

        result.files["png"] = figure(result, folder / FILES["png"], title=describe.get("title", ""),
                                     samples=describe.get("samples"))
    ok = sum(r is not None and r["success"] for r in records)
    result.summary = {**describe, "status": "success" if result.success else "failed", "message": result.message,
                      "runs": len(records), "succeeded": ok, "failed": counts["failed"],
                      "not_computed": sum(r is None for r in records), "computed": result.computed,
                      "reused": reused, "lost": [list(x) for x in result.lost], "damaged_lines": damaged,
                      "elapsed_s": result.elapsed, "warned": len(result.warned),
                      "worst_warning": None if result.worst is None else {
                          "run": result.worst["run"], "warning": result.worst["warning"]},
                      "columns": list(result.columns),
                      "outputs": {k: str(v) for k, v in result.files.items()}, "table": result.rows}
    if "json" in formats:
        result.files["json"] = folder / FILES["json"]
        result.summary["outputs"]["json"] = str(result.files["json"])
        _write_json(result.files["json"], result.summary)
    return result


__all__ = ["FILES", "columns", "csv_row", "read_records", "scan_records", "StudyProgress", "StudyResult", "run_into"]
