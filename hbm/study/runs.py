"""One run of a study: a pure function of its point, returning a record.

:func:`execute` is what every executor calls (in this process, a worker process or a Dask
worker): it calls the study's runner on the point, times it, turns what came back (an
:class:`hbm.FrequencyResponse` or a dict) into a record, and records any exception as a failed
run with its message.  :class:`SceneRun` is the runner of a scene study: the scene with the
point's keys set, planned and run as ``hbm.scenes.run_scene`` runs it.
"""

from __future__ import annotations

import math
import time
import warnings
from typing import Any, Callable, Mapping

import numpy as np

from contact_models.accuracy import AccuracyWarning

from ..result import FrequencyResponse
from ..scenes import SceneError, plan_scene, scene_from_dict
from ..scenes.reporting import peak_point
from ..scenes.running import RunResult, _run_amplitude, _run_frequency
from ..scenes.validation import apply_overrides

#: The numbers of a record, in the table's order (after the run number, id and parameters).
RESULT_COLUMNS = ("success", "message", "peak_omega_rad_s", "peak_amplitude_m", "peak_error_rel", "peak_model", "nfev",
                  "time_s")


class SceneRun:
    """The runner of a scene study: ``SceneRun(data, path)(point)`` runs the scene ``data`` (parsed
    TOML, without ``[study]`` and ``[output]``) with the point's ``"table.key"`` values set.

    The scene of a point must make exactly one run (one model, one normal load).  A frequency
    sweep returns its FRF; an amplitude sweep returns the table of F_s, F_c, its "peak" the largest
    F_c (the amplitude and frequency of the most damping).

    Parameters
    ----------
    data : mapping
        The scene as parsed TOML (``[study]`` and ``[output]`` are dropped).
    path : str, default "<scene>"
        The scene file's path, named in error messages.

    Attributes
    ----------
    data : dict
        The scene without ``[study]`` and ``[output]``.
    path : str
        As given.

    Raises
    ------
    hbm.scenes.SceneError
        When called on a point whose scene is invalid or makes more than one run.
    """

    def __init__(self, data: Mapping[str, Any], path: str = "<scene>") -> None:
        self.data = {k: v for k, v in data.items() if k not in ("study", "output")}
        self.path = str(path)

    def identity(self, point: Mapping[str, Any]) -> dict:
        """The run's inputs, for its hash: the scene as run (the point's keys set; not its title)."""

        scene = apply_overrides(self.data, point)
        scene.pop("title", None)
        return {"scene": scene}

    def scene(self, point: Mapping[str, Any]) -> Any:
        """The validated scene of ``point``; :class:`hbm.scenes.SceneError` unless it makes one run."""

        scene = scene_from_dict(self.data, self.path, overrides=point)
        loads = len(scene.load.get("N") or (None,)) if scene.load is not None else 1
        if len(scene.damper["model"]) * loads != 1:
            raise SceneError([f"{self.path}: a study run must make one computation: give damper.model and "
                              "damper.load.N one value each (in the scene, or as study.grid keys); "
                              f"this point gives {len(scene.damper['model'])} model(s) and {loads} load(s)"])
        return scene

    def __call__(self, point: Mapping[str, Any]) -> dict:

        scene = self.scene(point)
        plan = plan_scene(scene)
        res = RunResult(plan.runs[0])
        if scene.sweep["kind"] == "frequency":
            _run_frequency(scene, plan, res, lambda *a: None)  # its warnings: in the run's record (execute)
            return outcome(res.frf)
        _run_amplitude(scene, plan, res, lambda *a: None)
        t = res.table
        best = max(((float(Fc[i]), w, float(t["a"][i])) for w, Fc in zip(t["omega"], t["F_c"])
                    for i in range(len(Fc))), key=lambda x: x[0])
        return {"success": True, "message": res.message, "peak_omega_rad_s": float(best[1]),
                "peak_amplitude_m": best[2], "peak_model": type(res.plan.element).__name__,
                "curve": {"omega_rad_s": [float(w) for w in t["omega"]], "a_m": [float(a) for a in t["a"]],
                          "F_s": [[float(v) for v in r] for r in t["F_s"]],
                          "F_c": [[float(v) for v in r] for r in t["F_c"]]}}

    def __repr__(self) -> str:
        return f"SceneRun({self.path!r})"


def outcome(out: Any) -> dict:
    """The record fields of what a runner returned: an FRF (``hbm.FrequencyResponse``) or a dict
    with any of ``success`` (default True), ``message``, ``peak_omega_rad_s``, ``peak_amplitude_m``,
    ``peak_error_rel``, ``peak_model``, ``nfev`` and ``curve`` (a dict of arrays or lists of numbers,
    stored as lists of floats).

    Parameters
    ----------
    out : hbm.FrequencyResponse or mapping
        What the runner returned.  Peak frequency in rad/s, peak amplitude in m.

    Returns
    -------
    dict
        ``success``, ``message``, ``peak_omega_rad_s``, ``peak_amplitude_m`` (None where absent
        or not finite), ``peak_error_rel`` (the peak amplitude's estimated relative error: for an FRF
        the located peak's ``estimate``, the estimate at the sampled point it was located from, which
        bounds the located peak's too; None where absent, not finite or not estimated), ``peak_model``
        (the model the peak was computed with: for an FRF the class of the element at that point,
        ``"AllModeMicroslip"`` where ``model="peak"`` solved the peak with the bar of every mode,
        ``""`` for several contacts or none; None where absent), ``nfev`` (None where absent) and
        ``curve`` (for an FRF: ``omega_rad_s`` and ``amplitude_m``).

    Raises
    ------
    ValueError
        If ``out`` is neither an FRF nor a mapping, or the mapping holds another key.

    Examples
    --------
    >>> rec = outcome({"peak_amplitude_m": 2e-3, "peak_error_rel": 4e-4, "curve": {"a_m": [1, 2]}})
    >>> rec["success"], rec["peak_amplitude_m"], rec["peak_omega_rad_s"], rec["peak_error_rel"], rec["curve"]
    (True, 0.002, None, 0.0004, {'a_m': [1.0, 2.0]})
    """
    if isinstance(out, Mapping):
        rec = {"success": bool(out.get("success", True)), "message": str(out.get("message", "")),
               "peak_omega_rad_s": _float(out.get("peak_omega_rad_s")),
               "peak_amplitude_m": _float(out.get("peak_amplitude_m")),
               "peak_error_rel": _float(out.get("peak_error_rel")),
               "peak_model": None if out.get("peak_model") is None else str(out["peak_model"]),
               "nfev": None if out.get("nfev") is None else int(out["nfev"]),
               "curve": {str(k): np.asarray(v, dtype=float).tolist() for k, v in (out.get("curve") or {}).items()}}
        unknown = set(out) - set(rec)
        if unknown:
            raise ValueError(f"a runner's dict may hold {', '.join(rec)}; got also {', '.join(sorted(unknown))}")
        return rec

    if not isinstance(out, FrequencyResponse):
        raise ValueError(f"a runner must return an hbm.FrequencyResponse or a dict, got {type(out).__name__}")
    pk = out.peak() if len(out) else None
    return {"success": bool(out.success), "message": out.message,
            "peak_omega_rad_s": None if pk is None else pk.omega,
            "peak_amplitude_m": None if pk is None else pk.amplitude,
            "peak_error_rel": None if pk is None else _float(pk.estimate),
            "peak_model": _peak_model(out), "nfev": int(out.nfev),
            "curve": {"omega_rad_s": out.omega.tolist(), "amplitude_m": out.amplitude.tolist()}}


def _peak_model(frf: FrequencyResponse) -> str:
    """The model of the point the peak of ``frf`` was located from (``hbm.scenes.reporting.peak_point``):
    its element's class name, so that a record names the model as a class (the class of the refined
    model where ``model="peak"`` refined the peak; without points, the element's); ``""`` for several
    contacts or none."""
    if frf.element is None:
        return ""
    if not len(frf):
        return type(frf.element).__name__
    return str(frf.point_models[peak_point(frf)]).split("(")[0]


def _float(v: Any) -> float | None:
    if v is None:
        return None
    v = float(v)
    return v if math.isfinite(v) else None


def execute(runner: Callable[[Mapping[str, Any]], Any], point: Mapping[str, Any]) -> dict:
    """Run ``runner(point)``: its record fields (:func:`outcome`) and ``time_s``; an exception
    makes a failed record whose message names it (so one bad run never stops a study).

    Parameters
    ----------
    runner : callable
        A function of one point, returning an ``hbm.FrequencyResponse`` or a dict (``outcome``).
    point : mapping of str to object
        The point, handed to ``runner`` as is.

    Returns
    -------
    dict
        The fields of ``outcome``, ``time_s`` (the run's wall-clock time in s) and ``warning``:
        the ``AccuracyWarning`` messages the run emitted, joined by ``"; "`` (None for none),
        which are also appended to ``message``.  They are recorded, not shown, so a study of many
        runs says them once in its summary (:attr:`hbm.study.StudyResult.warning`) instead of once
        per run from every worker; any other warning is shown as usual.  It never raises for an
        ``Exception`` of the runner: that makes ``success`` False and ``message``
        ``"ExceptionType: text"``.

    Examples
    --------
    >>> rec = execute(lambda p: {"peak_amplitude_m": 2.0 * p["x"]}, {"x": 1.5})
    >>> rec["success"], rec["peak_amplitude_m"], rec["time_s"] >= 0.0
    (True, 3.0, True)
    >>> rec = execute(lambda p: 1.0 / p["x"], {"x": 0.0})
    >>> rec["success"], rec["message"]
    (False, 'ZeroDivisionError: float division by zero')
    >>> import warnings
    >>> def loose(p):
    ...     warnings.warn("estimated error 0.1 > tol 0.001", AccuracyWarning)
    ...     return {"peak_error_rel": 0.1}
    >>> rec = execute(loose, {"x": 1.0})
    >>> rec["warning"], rec["message"]
    ('estimated error 0.1 > tol 0.001', 'estimated error 0.1 > tol 0.001')
    """
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", AccuracyWarning)
        try:
            rec = outcome(runner(point))
        except Exception as exc:  # any failure of one run is that run's result
            rec = {"success": False, "message": f"{type(exc).__name__}: {exc}", "peak_omega_rad_s": None,
                   "peak_amplitude_m": None, "peak_error_rel": None, "peak_model": None, "nfev": None, "curve": {}}
    said = list(dict.fromkeys(str(w.message) for w in caught if issubclass(w.category, AccuracyWarning)))
    for w in caught:  # any other warning as it would have been shown
        if not issubclass(w.category, AccuracyWarning):
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    rec["warning"] = "; ".join(said) if said else None
    if said:
        rec["message"] = "; ".join(m for m in (rec["message"], rec["warning"]) if m)
    rec["time_s"] = time.perf_counter() - t0
    return rec


__all__ = ["SceneRun", "outcome", "execute", "RESULT_COLUMNS"]
