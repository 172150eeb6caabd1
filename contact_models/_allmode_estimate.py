"""``AllModeMicroslip.model_error`` at many points: the estimate of every point, on two threads where they pay.

The points are estimated in order, each nested solve starting from the state its rung solved last (moved along its
tangent).  Where at least ``THREAD_MIN_POINTS`` of them slip, the second half runs on a second thread on a copy of
the element's rungs (the same states to start from), and the element takes over that copy's last states at the end,
as if it had estimated all the points in turn.  The compiled kernels (the return map, the Jacobians, the block
elimination) release the interpreter's lock, so the two halves overlap where those kernels are most of the work (the
rungs of 31 harmonics: along the default all-mode FRF the estimate of its peak window takes 0.11 s instead of 0.16 s
on the 2-core machine).  The halves are fixed by the points alone, so the answer does not depend on the threads'
timing; it differs from the one-thread answer only by where the second half's first solves start (within the nested
Newton's tolerance).  Threads are used only in a process's main process (a study's workers each use one core).
"""

from __future__ import annotations

import copy
import math
import multiprocessing
import os
import threading
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._allmode_accuracy import relative

AllModeMicroslip = Any  # the element (``contact_models.allmode``, which imports this module)

#: Threads an estimate of many points runs on (1: none besides the caller's).
ESTIMATE_THREADS = 2
#: The fewest points above the slip onset that an estimate spreads over threads.
THREAD_MIN_POINTS = 8


def threads() -> int:
    """The threads an estimate may use here: ``ESTIMATE_THREADS`` in a main process on a machine of at least as many
    cores, else 1."""
    if ESTIMATE_THREADS < 2 or multiprocessing.parent_process() is not None:
        return 1
    return min(ESTIMATE_THREADS, os.cpu_count() or 1)


def model_errors(el: AllModeMicroslip, a: NDArray, omega: NDArray) -> tuple[NDArray, NDArray]:
    """``(e_s, e_c)`` of ``el`` at the points ``a``, ``omega`` (the shape of ``a``): each point's estimate
    (``estimate_one``); the points above the slip onset split between two threads where there are at least
    ``THREAD_MIN_POINTS`` of them (module docstring)."""
    a_f, w_f = (np.ravel(v).astype(float) for v in (a, omega))
    e_s, e_c = np.zeros(a_f.size), np.zeros(a_f.size)
    slipping = [i for i in range(a_f.size) if a_f[i] > el._stuck_data(float(w_f[i]))[2]]
    if threads() < 2 or len(slipping) < THREAD_MIN_POINTS:
        seen = [estimate_one(el, float(ai), float(wi), e_s, e_c, i) for i, (ai, wi) in enumerate(zip(a_f, w_f))]
    else:
        cut = slipping[len(slipping) // 2]  # the second thread from the middle slipping point on
        other = _copy(el)
        box: dict[str, Any] = {}

        def second():
            try:
                box["seen"] = [estimate_one(other, float(a_f[i]), float(w_f[i]), e_s, e_c, i)
                               for i in range(cut, a_f.size)]
            except BaseException as exc:  # raised again on the caller's thread
                box["error"] = exc

        worker = threading.Thread(target=second, name="AllModeMicroslip estimate")
        worker.start()
        try:
            seen = [estimate_one(el, float(a_f[i]), float(w_f[i]), e_s, e_c, i) for i in range(cut)]
        finally:
            worker.join()
        if "error" in box:
            raise box["error"]
        seen += box["seen"]
        _take_over(el, other)
    if el._fixed:
        el._seen.extend(s for s in seen if s is not None)
    return e_s.reshape(np.shape(a)), e_c.reshape(np.shape(a))


def estimate_one(el: AllModeMicroslip, ai: float, wi: float, e_s: NDArray, e_c: NDArray, i: int) -> tuple | None:
    """The estimate at one point into ``e_s[i]``, ``e_c[i]``: of the stuck stiffness below slip (f_c = 0 exactly
    there), else of the solution the element gives (its rungs, or the fixed one with its estimate); the record
    ``(omega, a, cells part, harmonics part)`` a fixed rung keeps (``refined_rung``), or None."""
    _, _, a_lin, rel_s = el._stuck_data(wi)
    if ai <= a_lin:
        e_s[i] = rel_s
        return wi, ai, rel_s, 0.0
    X = np.array([0.0, 0.0, ai])
    floor = el._floor(X)
    sol, _ = el._resolved(X, wi, True, False)  # the force and the rungs' forces alone
    parts = None
    if sol.relative_error is None and sol.success:
        parts = el._parts(X, wi, True, sol)
        el._fill(sol, parts, floor)
    if not sol.success:
        e_s[i] = e_c[i] = math.inf
        return wi, ai, math.inf, math.inf
    scale = np.maximum(np.abs(sol.F[1:3]), floor)  # (F_c, F_s)
    e_c[i], e_s[i] = (float(v) for v in sol.error_components / scale)
    if parts is None:
        return None
    return (wi, ai, *(relative(parts[k], sol.F[1:3], floor) for k in ("cells", "harmonics")))


def _copy(el: AllModeMicroslip) -> AllModeMicroslip:
    """``el`` with its own copies of what an estimate changes: its rungs (their last states and linear parts; the
    bases, meshes and segment constants shared, never changed), the stuck data, and the records of the last call."""
    other = copy.copy(el)
    other._levels = {k: _level_copy(v) for k, v in el._levels.items()}
    other._stuck = dict(el._stuck)
    other._seen = []
    return other


def _level_copy(level: Any) -> Any:
    out = copy.copy(level)
    out._cache, out._linear = dict(level._cache), dict(level._linear)
    return out


def _take_over(el: AllModeMicroslip, other: AllModeMicroslip) -> None:
    """The element after the second half: the copy's last states of every rung, its stuck data and last call."""
    for key, level in other._levels.items():
        mine = el._levels.get(key)
        if mine is None:
            el._levels[key] = level
        else:
            mine._cache, mine._linear, mine._last = level._cache, level._linear, level._last
    el._stuck.update(other._stuck)
    el._last, el._reuse = other._last, other._reuse
