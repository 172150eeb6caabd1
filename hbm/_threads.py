"""One BLAS thread while a call solves only small dense systems.

A harmonic balance of a few contact DOFs factors thousands of small matrices (the Newton steps of
every point, the error estimate's step at 2H + 1 harmonics: at H = 31 a 127 x 127 system per point).
OpenBLAS splits a factorisation of that size over its threads, and on a machine whose cores are
busy each split waits on a thread the scheduler has not run: on two loaded cores a 127 x 127
``numpy.linalg.solve`` measured 0.6 ms on one thread and 86 ms on two, a 511 x 511 one 3.6 ms
against 27 ms.  On one thread the arithmetic is the same and its cost does not depend on the
machine's load, so :func:`one_blas_thread` holds OpenBLAS at one thread while such a call runs
and gives back the count it found.

Only OpenBLAS libraries already loaded into the process are found (``/proc/self/maps``, Linux); the
environment variables are not touched, and elsewhere the context does nothing.
"""

from __future__ import annotations

import ctypes
import threading
from contextlib import contextmanager
from typing import Any, Iterator

#: The largest dense system (unknowns) a call may factor and still run BLAS on one thread.
SMALL_SYSTEM = 512

_SET = ("openblas_set_num_threads", "openblas_set_num_threads64_", "scipy_openblas_set_num_threads",
        "scipy_openblas_set_num_threads64_")
_GET = ("openblas_get_num_threads", "openblas_get_num_threads64_", "scipy_openblas_get_num_threads",
        "scipy_openblas_get_num_threads64_")
_LOCK = threading.Lock()
_DEPTH = 0
_SAVED: list[tuple[Any, int]] = []
_FOUND: dict[str, tuple[Any, Any] | None] = {}  # path -> its (set, get), None where it has neither


def _openblas() -> list[tuple[Any, Any]]:
    """``(set_num_threads, get_num_threads)`` of every OpenBLAS loaded into this process."""
    try:
        with open("/proc/self/maps") as maps:
            paths = sorted({line.split()[-1] for line in maps if "openblas" in line.lower() and ".so" in line})
    except OSError:
        return []
    for path in paths:
        if path not in _FOUND:
            _FOUND[path] = None
            try:
                lib = ctypes.CDLL(path)
            except OSError:
                continue
            setter = next((getattr(lib, f) for f in _SET if hasattr(lib, f)), None)
            getter = next((getattr(lib, f) for f in _GET if hasattr(lib, f)), None)
            if setter is not None and getter is not None:
                getter.restype = ctypes.c_int
                _FOUND[path] = (setter, getter)
    return [_FOUND[p] for p in paths if _FOUND[p] is not None]


def openblas_setters() -> list[tuple[str, Any]]:
    """``(path, set_num_threads)`` of every OpenBLAS loaded into this process that has one."""
    _openblas()
    return [(p, f[0]) for p, f in _FOUND.items() if f is not None]


@contextmanager
def one_blas_thread(active: bool = True) -> Iterator[None]:
    """Run the block with every loaded OpenBLAS on one thread; restore each one's count after.

    Nested or concurrent blocks (threads of one process) share one setting: the first to enter
    records the counts and sets one thread, the last to leave restores them.

    Parameters
    ----------
    active : bool, optional
        False: the block runs as it is (for a caller that decides by the size of its systems,
        :data:`SMALL_SYSTEM`).
    """
    global _DEPTH
    if not active:
        yield
        return
    with _LOCK:
        if _DEPTH == 0:
            _SAVED[:] = []
            for setter, getter in _openblas():
                count = int(getter())
                if count > 1:
                    setter(ctypes.c_int(1))
                    _SAVED.append((setter, count))
        _DEPTH += 1
    try:
        yield
    finally:
        with _LOCK:
            _DEPTH -= 1
            if _DEPTH == 0:
                for setter, count in _SAVED:
                    setter(ctypes.c_int(count))
                _SAVED[:] = []
