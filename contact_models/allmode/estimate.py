"""``AllModeMicroslip.model_error`` at many points: the estimate of every point, in two halves, on two threads where
they pay.

The points are estimated in order, each nested solve starting from the state its rung solved last (moved along its
tangent).  Where at least ``SPLIT_MIN_POINTS`` of them slip, they are estimated in two halves: the first on the
element's rungs, the second on a copy of them (the same states to start from); the element then takes over the copy's
last states, as if it had estimated all the points in turn.  The halves are fixed by the points alone, so the answer
does not depend on whether they run one after the other or at once, nor on the threads' timing.  With the compiled
kernels (the return map, the Jacobians, the block elimination), which release the interpreter's lock, the second half
runs on a second thread on the rungs whose Newton loop is compiled (31 harmonics): there the two overlap, those
kernels being most of the work.  On smaller rungs and on the numpy path the lock is held most of the time, so a
second thread only adds its switching, and a study's worker processes each have a core: there the halves run in
turn (docs/performance.md, "The all-mode FRF: less Python per nested solve, the estimate on two threads").
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

from .accuracy import relative
from .balance import BANDED_MAX_BLOCK
from .compiled import kernel

AllModeMicroslip = Any  # the element (``contact_models.allmode``, which imports this module)

#: Threads an estimate of many points runs on (1: the halves in turn).
ESTIMATE_THREADS = 2
#: The fewest points above the slip onset that an estimate splits in two halves.
SPLIT_MIN_POINTS = 8


def threads(el: AllModeMicroslip) -> int:
    """The threads an estimate of ``el`` uses here: ``ESTIMATE_THREADS`` where the compiled kernels are loaded, for a
    fixed rung whose nested Newton loop is compiled (more than ``BANDED_MAX_BLOCK`` coefficients a node in the odd
    basis: H = 31), in a main process, on a machine of at least as many cores; else 1 (module docstring).  A
    smaller rung's solves are mostly Python, which holds the lock, so two threads there cannot overlap and only
    add their switching."""
    if ESTIMATE_THREADS < 2 or kernel("newton") is None or multiprocessing.parent_process() is not None:
        return 1
    if not (el._fixed and el.harmonics + 1 > BANDED_MAX_BLOCK):
        return 1
    return min(ESTIMATE_THREADS, os.cpu_count() or 1)


def model_errors(el: AllModeMicroslip, a: NDArray, omega: NDArray) -> tuple[NDArray, NDArray]:
    """``(e_s, e_c)`` of ``el`` at the points ``a``, ``omega`` (the shape of ``a``): each point's estimate
    (``estimate_one``) in order, in two halves where at least ``SPLIT_MIN_POINTS`` of them slip (the second from
    the middle slipping point on, on a copy of the element's rungs), at once on two threads where ``threads(el)``
    allows (module docstring)."""
    a_f, w_f = (np.ravel(v).astype(float) for v in (a, omega))
    e_s, e_c = np.zeros(a_f.size), np.zeros(a_f.size)

    def run(element, points):
        return [estimate_one(element, float(a_f[i]), float(w_f[i]), e_s, e_c, i) for i in points]

    slipping = [i for i in range(a_f.size) if a_f[i] > el._stuck_data(float(w_f[i]))[2]]
    if len(slipping) < SPLIT_MIN_POINTS:
        seen = run(el, range(a_f.size))
    else:
        cut = slipping[len(slipping) // 2]
        other = _copy(el)
        if threads(el) < 2:
            seen = run(el, range(cut)) + run(other, range(cut, a_f.size))
        else:
            box: dict[str, Any] = {}

            def second():
                try:
                    box["seen"] = run(other, range(cut, a_f.size))
                except BaseException as exc:  # raised again on the caller's thread
                    box["error"] = exc

            worker = threading.Thread(target=second, name="AllModeMicroslip estimate")
            worker.start()
            try:
                seen = run(el, range(cut))
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
