"""Compiled kernels of the all-mode bar's nested solve (``contact_models.allmode.balance``), used where numba
is installed (the optional ``fast`` extra: ``pip install -e ".[fast]"``).

The numpy path stays the library's definition: every kernel here does the same floating-point
operations in the same order (the return map, the stick-run sums of the Jacobian, LAPACK's
``dgetrf`` and ``dgetri`` on each pivot block and BLAS for the products), so the answers are those of the numpy
path; ``tests/test_hbal_compiled.py`` holds them to it.  What
the kernels remove is Python's cost per sample, per node and per block: the return map is a loop
over n_t samples in numpy, each step three array calls.

Loading them costs a process a fixed time (numba's import, its typing registries at the first cached
kernel, the kernels themselves), which the nested solves, roughly halved, repay only after a while.  So
they are loaded when they pay: once the nested solves have spent ``LOAD_AFTER`` seconds on the numpy path
(the rent-or-buy rule: a process whose bar work is shorter is faster without them, and a longer one is late
by at most those seconds of numpy work), or at once where a whole curve is about to be traced on the bar
(``AllModeMicroslip.start_rung``, which a frequency response asks first, calls ``kernels(load=True)``).
The answers do not depend on when: both paths give the same numbers.  What loading costs and saves is
measured in ``docs/performance.md``, "Compiled kernels (the optional `fast` extra)".

The environment variable ``FRICTIONDAMP_COMPILED`` overrides the rule: ``0`` keeps the numpy path with
numba installed, ``1`` loads the kernels at the first nested solve (compiling them there if numba's cache
holds none).

**No first-use wait.**  Compiling the kernels takes a fresh installation some fifteen seconds, more than
a whole job.  numba caches them in the ``__pycache__`` folder beside this module, and the warm-up
(``contact_models.allmode.warm``) leaves a marker there once every kernel is in the cache.  Where the
rule would load the kernels and the marker is missing (a first run after an install or a clone), the process
starts that warm-up in a background process of low priority and goes on on the numpy path, with the same
numbers.  The warm-up compiles the kernels in groups (:data:`GROUPS`, those that save a curve the most per
second of compiling first) and lists each group in a progress file once it is cached; the process looks at
it every ``LOOK_AGAIN`` seconds (of nested solves while it has no kernel, of wall time after) and loads each
group as it appears: a kernel not yet cached is None (:func:`kernel`) and its caller takes the numpy path.
The processes after the marker load them all at once.  Where that folder is not writable (or
``NUMBA_CACHE_DIR`` moves numba's cache), the kernels are compiled where they are first used, as numba does.

The kernels assign no array to a slice (they copy element by element, update rows in place and write
products with ``np.dot``'s ``out``): numba compiles such an assignment's broadcasting and error message in
seconds, in every kernel that links it, and the same floating-point operations need none of it.
"""

from __future__ import annotations

import contextlib
import os
import subprocess
import threading
import sys
import time
from pathlib import Path
from collections.abc import Iterator
from types import SimpleNamespace

import numpy as np
from numpy.typing import NDArray

Array = NDArray  # any dtype: float samples and forces, bool masks, intp anchors
# compiled kernels that other kernels call (set by ``_load``)
_march = _rows_c = _block_factor_c = _jacobians_c = _same_c = _residual_c = _coupled_c = _block_solve_c = None
_KERNELS: SimpleNamespace | None = None
_TRIED = False
#: False while :func:`numpy_only` is in force.
_ENABLED = True
#: Seconds of nested solves on the numpy path after which the kernels are loaded (module docstring):
#: about what loading them costs, the rent-or-buy break-even, and above the bar work of a short job
#: such as the all-mode peak, which then runs without them (docs/performance.md, "Compiled kernels
#: (the optional `fast` extra)").
LOAD_AFTER = 0.5
_NUMPY_SECONDS = 0.0  # the nested solves' time on the numpy path while the kernels were not loaded
#: While a background warm-up compiles the kernels, the process looks at its progress again after each
#: further ``LOOK_AGAIN`` seconds of nested solves on the numpy path (of wall time once it has loaded some;
#: one file read), and loads from numba's cache each group of kernels the warm-up has cached: a first run
#: is on the numpy path only until the warm-up has compiled the first group, and on it alone only until the next.
LOOK_AGAIN = 0.5
_LOOK_AT = 0.0
_WARMING_STARTED = False  # this process has started (or found under way) the warm-up


def kernels(load: bool = False) -> SimpleNamespace | None:
    """The compiled kernels, or None: numba not installed, ``FRICTIONDAMP_COMPILED=0``, inside
    :func:`numpy_only`, or not loaded yet (the module docstring's rule; ``load=True`` loads them now).
    Compiled, or loaded from numba's cache, once.  While a background warm-up is under way, a kernel
    not yet in the cache is None here (:func:`kernel`), and taken up once it is."""
    global _KERNELS, _TRIED, _LOOK_AT, _WARMING_STARTED
    mode = os.environ.get("FRICTIONDAMP_COMPILED", "")
    if not _ENABLED or mode == "0":
        return None
    if _TRIED:
        if _MISSING and time.perf_counter() >= _LOOK_WALL:
            _take_up()
        return _KERNELS
    if not (load or mode == "1" or _NUMPY_SECONDS >= max(LOAD_AFTER, _LOOK_AT)):
        return None
    try:
        import numba  # lazily, and optional: the fast extra; the numpy path needs none of it
    except ImportError:
        _TRIED = True
        return None
    groups = tuple(GROUPS) if mode == "1" else cached_groups(numba)
    if len(groups) < len(GROUPS) and not _WARMING_STARTED:  # compiled in the background; numpy here
        _WARMING_STARTED = True
        _start_warming()
    if not groups:
        _LOOK_AT = _NUMPY_SECONDS + LOOK_AGAIN  # and taken up once the warm-up has cached some
        return None
    _TRIED = True
    _load(numba, groups)
    return _KERNELS


def kernel(name: str) -> object | None:
    """The compiled kernel ``name`` (an attribute of :func:`kernels`), or None where the kernels are not
    loaded or this one is not in numba's cache yet: its caller takes the numpy path, with the same numbers."""
    fused = kernels()
    return None if fused is None else getattr(fused, name)


#: The marker the warm-up leaves beside numba's cache, and the lock of a warm-up under way (stale after
#: ``WARMING_STALE`` seconds: a warm-up that died).
MARKER = "compiled.warm"
WARMING = "compiled.warming"
#: The warm-up's progress: the stamp, then the name of each group of kernels it has cached so far.
PROGRESS = "compiled.part"
WARMING_STALE = 600.0


def _cache_folder() -> Path | None:
    """The folder numba caches this module's kernels in, where it is this module's ``__pycache__`` and
    writable; else None (the module docstring)."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return None
    folder = Path(__file__).resolve().parent / "__pycache__"
    try:
        folder.mkdir(exist_ok=True)
    except OSError:
        return None
    return folder if os.access(folder, os.W_OK) else None


def _stamp(numba: object) -> str:
    """What the cached kernels depend on: numba's version and this source file (numba's own key)."""
    st = os.stat(__file__)
    return f"numba {getattr(numba, '__version__', '?')} source {st.st_mtime_ns} {st.st_size}\n"


def cache_ready(numba: object) -> bool:
    """Whether numba's cache holds the kernels (the warm-up's marker, for this numba and this source),
    or no background warm-up can help (no writable cache folder of our own): then load now."""
    folder = _cache_folder()
    if folder is None:
        return True
    try:
        return (folder / MARKER).read_text() == _stamp(numba)
    except OSError:
        return False


def cached_groups(numba: object) -> tuple[str, ...]:
    """The groups of :data:`GROUPS` whose kernels numba's cache holds: all where :func:`cache_ready`, else
    those the warm-up under way has listed in its progress file (for this numba and this source), in order up
    to the first it has not listed."""
    if cache_ready(numba):
        return tuple(GROUPS)
    folder = _cache_folder()
    try:
        stamp, *done = (folder / PROGRESS).read_text().splitlines(keepends=True)
    except (OSError, ValueError):
        return ()
    if stamp != _stamp(numba):
        return ()
    done = {g.strip() for g in done}
    out: list[str] = []
    for g in GROUPS:  # the groups in order up to the first not listed (a group's kernels call earlier groups')
        if g not in done:
            break
        out.append(g)
    return tuple(out)


def _start_warming() -> None:
    """Start the warm-up (``contact_models.allmode.warm``) in a detached process of low priority, unless one is
    under way."""
    folder = _cache_folder()
    if folder is None:
        return
    lock = folder / WARMING
    try:
        if time.time() - lock.stat().st_mtime < WARMING_STALE:
            return
        lock.unlink()
    except OSError:
        pass
    try:
        os.close(os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY))
    except OSError:  # another process started one this instant
        return
    env = dict(os.environ, FRICTIONDAMP_COMPILED="1")
    root = str(Path(__file__).resolve().parents[2])
    env["PYTHONPATH"] = root + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    try:
        subprocess.Popen([sys.executable, "-c", WARM_COMMAND], env=env, stdin=subprocess.DEVNULL,
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    except OSError:
        lock.unlink(missing_ok=True)


#: The background warm-up: at low priority where the system has one, then ``warm.warm``.
WARM_COMMAND = ("import os\nif hasattr(os, 'nice'): os.nice(10)\n"
                "from contact_models.allmode.warm import warm\nwarm()")


def _compiled_now(groups: tuple[str, ...] | None = None) -> None:
    """Load the kernels of ``groups`` (all by default) in this process now, compiling them into numba's cache
    at their first call: ``contact_models.allmode.warm.warm``, group by group."""
    global _TRIED
    import numba

    _load(numba, tuple(GROUPS) if groups is None else groups)
    _TRIED = True


def mark_group(group: str) -> None:
    """Add ``group`` to the warm-up's progress file: its kernels are in numba's cache."""
    import numba

    folder = _cache_folder()
    if folder is None:
        return
    try:
        stamp, *done = (folder / PROGRESS).read_text().splitlines(keepends=True)
    except (OSError, ValueError):
        stamp, done = "", []
    if stamp != _stamp(numba):
        done = []
    # one temporary file per process and thread (two processes warming one cache at once, as pytest's workers
    # on a clean clone do, would otherwise move each other's file away), replaced whole for a process reading
    # it now; a mark lost to a write at the same moment only makes a process load that group at mark_warm
    tmp = folder / f"{PROGRESS}.{os.getpid()}.{threading.get_ident()}.tmp"
    try:
        tmp.write_text(_stamp(numba) + "".join(done) + group + "\n")
        os.replace(tmp, folder / PROGRESS)
    except OSError:
        tmp.unlink(missing_ok=True)


def mark_warm() -> None:
    """Leave the marker that every kernel is in numba's cache, and drop the warm-up's lock."""
    import numba

    folder = _cache_folder()
    if folder is not None:
        (folder / MARKER).write_text(_stamp(numba))
        (folder / WARMING).unlink(missing_ok=True)
        (folder / PROGRESS).unlink(missing_ok=True)


#: The kernels by group, in the order the warm-up compiles them (the kernels' own, ``python_name``), the
#: groups that save the most on a curve per second of compiling first; a group's kernels call only those of
#: its own and of earlier groups.  A process loads each group once it is in numba's cache.
GROUPS = {
    "residual": ("march", "rows", "residual"),
    "jacobians": ("jacobians", "same_pattern"),
    "elimination": ("block_factor", "coupled_factor", "block_solve"),
    "thomas": ("thomas",),
    "newton": ("newton",),
}
_MISSING: tuple[str, ...] = ()  # the groups a process that loaded some still waits for
_LOOK_WALL = 0.0  # when it looks for them again
_JIT = None  # numba.njit with numba's cache, or without where it has no writable place


def _take_up() -> None:
    """Load the groups the warm-up has cached since this process last looked; look again after ``LOOK_AGAIN``
    seconds."""
    global _LOOK_WALL
    import numba

    _LOOK_WALL = time.perf_counter() + LOOK_AGAIN
    groups = cached_groups(numba)
    if any(g in _MISSING for g in groups):
        _load(numba, groups)


def _load(numba: object, groups: tuple[str, ...]) -> None:
    """The kernels of ``groups`` (compiled, or loaded from numba's cache) in :func:`kernels`'s namespace, the others
    None there.  Kernels that call others (``residual``, ``coupled_factor``, ``newton``) find them compiled as the
    module's ``_march``, ``_rows_c``, ... when they are compiled."""
    global _KERNELS, _JIT, _MISSING, _LOOK_WALL
    global _march, _rows_c, _block_factor_c, _jacobians_c, _same_c, _residual_c, _coupled_c, _block_solve_c
    funcs = dict(march=march, jacobians=jacobians, block_factor=block_factor, block_solve=block_solve, thomas=thomas,
                 same_pattern=same_pattern, residual=residual, rows=rows_kernel, coupled_factor=coupled_factor,
                 newton=newton)
    if _KERNELS is None:
        try:
            _JIT = numba.njit(cache=True, nogil=True)
            _JIT(march)  # (the test of a writable cache)
        except RuntimeError:  # no writable place for numba's cache: compiled in every process instead
            _JIT = numba.njit(nogil=True)
        _KERNELS = SimpleNamespace(**dict.fromkeys(funcs))
    out = _KERNELS
    for group in GROUPS:  # in their order: a group's callees before it
        if group in groups:
            for name in GROUPS[group]:
                if getattr(out, name) is None:
                    setattr(out, name, _JIT(funcs[name]))
    _MISSING = tuple(g for g in GROUPS if any(getattr(out, n) is None for n in GROUPS[g]))
    _LOOK_WALL = time.perf_counter() + LOOK_AGAIN
    _march, _rows_c, _block_factor_c = out.march, out.rows, out.block_factor
    _jacobians_c, _same_c, _residual_c = out.jacobians, out.same_pattern, out.residual
    _coupled_c, _block_solve_c = out.coupled_factor, out.block_solve


def numpy_clock() -> float | None:
    """The time now where the kernels may still be loaded (enabled and not yet loaded), else None: a
    nested solve that starts with it reports its time with :func:`numpy_spent`."""
    return None if _TRIED or not _ENABLED else time.perf_counter()


def numpy_spent(since: float) -> None:
    """Count the time since ``since`` (from :func:`numpy_clock`) towards ``LOAD_AFTER``."""
    global _NUMPY_SECONDS
    _NUMPY_SECONDS += time.perf_counter() - since


@contextlib.contextmanager
def numpy_only() -> Iterator[None]:
    """Within the block the nested solve takes the numpy path (the kernels' tests compare the two)."""
    global _ENABLED
    before, _ENABLED = _ENABLED, False
    try:
        yield
    finally:
        _ENABLED = before


# The kernels, plain Python here (``kernels`` compiles them): each mirrors the numpy function named.

def march(u: Array, kc: Array, p: Array, half: bool) -> tuple[Array, Array, Array, Array]:
    """``balance.jenkins_periodic(u, kc, p, half)``: one row at a time, the same operations."""
    m, n_t = u.shape
    f = np.empty((m, n_t))
    stuck = np.empty((m, n_t), np.bool_)
    anchor = np.empty((m, n_t), np.intp)
    never = np.empty(m, np.bool_)
    steps = n_t // 2 if half else n_t
    trial = np.empty(n_t)
    for i in range(m):
        km = 0
        umax = u[i, 0]
        umin = u[i, 0]
        for k in range(1, n_t):
            if u[i, k] > umax:
                umax = u[i, k]
                km = k
            if u[i, k] < umin:
                umin = u[i, k]
        ki, pi = kc[i], p[i]
        nv = ki * (umax - umin) <= 2.0 * pi
        never[i] = nv
        lo = -pi
        fk = 0.5 * ki * (umax - umin) if nv else pi
        trial[0] = fk
        prev = umax
        for j in range(1, steps):
            k = km + j if km + j < n_t else km + j - n_t
            t = fk + ki * (u[i, k] - prev)
            prev = u[i, k]
            trial[j] = t
            fk = max(t, lo)
            fk = min(fk, pi)
        if half:
            for j in range(steps):
                trial[steps + j] = -trial[j]
        last = 0
        for j in range(n_t):
            t = trial[j]
            st = nv if j == 0 or (half and j == steps) else abs(t) <= pi
            if not st:
                last = j
            k = km + j if km + j < n_t else km + j - n_t
            f[i, k] = min(max(t, lo), pi)
            stuck[i, k] = st
            anchor[i, k] = km + last if km + last < n_t else km + last - n_t
    return f, stuck, anchor, never


def residual(U: Array, X: Array, lin: Array, c: Array, kc: Array, p: Array, ET: Array, PT: Array,
             half: bool) -> tuple:
    """``FixedBar.evaluate`` without the Jacobian: ``(R, max|R|, T, u, stuck, anchor, never)`` for the free nodes'
    coefficients U (n, s) and the end's X (s,), the linear part's diagonal ``lin`` (n + 1, s) and coupling ``c``
    (s,), with ``ET``, ``PT`` the basis's E^T and P^T (``half``: its ``balance.half_products``): the samples
    u = [U; X] E^T and the forces T = f P^T in blocks of rows as ``balance.rows_product`` (``half``: on the first
    half of the samples, as ``balance.jenkins_state``), the return map ``march`` and R = lin U + T + c (neighbours),
    the same operations in the same order."""
    n, s = U.shape
    full = np.empty((n + 1, s))
    for i in range(n):  # (copies element by element: no array assignment, whose compilation costs seconds)
        for q in range(s):
            full[i, q] = U[i, q]
    for q in range(s):
        full[n, q] = X[q]
    if half:
        uh = _rows_c(full, ET)
        h = uh.shape[1]
        u = np.empty((n + 1, 2 * h))
        for i in range(n + 1):
            for j in range(h):
                u[i, j] = uh[i, j]
                u[i, h + j] = -uh[i, j]
        f, stuck, anchor, never = _march(u, kc, p, half)
        T = _rows_c(np.ascontiguousarray(f[:, :h]), PT)
    else:
        u = _rows_c(full, ET)
        f, stuck, anchor, never = _march(u, kc, p, half)
        T = _rows_c(f, PT)
    R = np.empty((n, s))
    for i in range(n):
        for q in range(s):
            R[i, q] = lin[i, q] * U[i, q] + T[i, q]
    for i in range(1, n):
        for q in range(s):
            R[i, q] += c[q] * U[i - 1, q]
    for i in range(n - 1):
        for q in range(s):
            R[i, q] += c[q] * U[i + 1, q]
    res = 0.0
    for q in range(s):
        R[n - 1, q] += c[q] * X[q]
    for i in range(n):
        for q in range(s):
            a = abs(R[i, q])
            if a > res or a != a:  # a NaN stays, as in np.max
                res = a
    return R, res, T, u, stuck, anchor, never


#: Products are done in blocks of rows of at most this many multiply-adds: OpenBLAS runs a GEMM of more
#: than 4 * 65536 of them on every thread it has, and for products this small waking and waiting for the
#: threads costs more than the product (docs/performance.md, "Large structures", on BLAS threads).
GEMM_SERIAL = 1 << 18


def rows_product(A: Array, B: Array) -> Array:
    """``A @ B`` (A of shape (m, k), B (k, n)) in blocks of rows of at most :data:`GEMM_SERIAL`
    multiply-adds each, so that a threaded BLAS runs every block on one thread.  Plain numpy; the kernels'
    ``rows`` is :func:`rows_kernel`."""
    m, k = A.shape
    n = B.shape[1]
    rows = max(1, GEMM_SERIAL // max(1, k * n))
    if m <= rows:
        return A @ B
    out = np.empty((m, n))
    for i in range(0, m, rows):
        out[i:i + rows] = A[i:i + rows] @ B
    return out


def rows_kernel(A: Array, B: Array) -> Array:
    """:func:`rows_product` as the kernels compile it: each block's product written into its rows by ``np.dot``'s
    ``out`` (the call numba's ``A @ B`` makes into a new array: the same BLAS routine on the same operands) rather
    than assigned to them, an array assignment whose compilation costs seconds."""
    m, k = A.shape
    n = B.shape[1]
    rows = max(1, GEMM_SERIAL // max(1, k * n))
    if m <= rows:
        return A @ B
    out = np.empty((m, n))
    for i in range(0, m, rows):
        np.dot(A[i:i + rows], B, out[i:i + rows])
    return out


def same_pattern(ua: Array, sa: Array, aa: Array, na: Array, ub: Array, sb: Array, ab: Array, nb: Array) -> bool:
    """``balance.same_jacobian`` of the states ``(ua, sa, aa, na)`` and ``(ub, sb, ab, nb)``: the rows that never
    slip equal, the stuck masks and anchors of the others equal, and for the rows that never slip the samples
    of the maximum and the minimum (``np.argmax``, ``np.argmin``) and whether the row moves."""
    if ua.shape != ub.shape or sa.shape != sb.shape or aa.shape != ab.shape or na.shape != nb.shape:
        return False
    m, n_t = sa.shape
    for i in range(m):
        if na[i] != nb[i]:
            return False
    for i in range(m):
        if na[i]:
            ka, kb = np.argmax(ua[i]), np.argmax(ub[i])
            ja, jb = np.argmin(ua[i]), np.argmin(ub[i])
            if ka != kb or ja != jb or (ua[i, ka] == ua[i, ja]) != (ub[i, kb] == ub[i, jb]):
                return False
        else:
            for k in range(n_t):
                if sa[i, k] != sb[i, k] or aa[i, k] != ab[i, k]:
                    return False
    return True


def jacobians(u: Array, st: Array, anchor: Array, never: Array, kc: Array, E: Array, P1: Array, Emean: Array,
              S: Array, CP: Array, I1: Array, I2: Array, coefs: Array) -> Array:
    """``balance.jenkins_jacobian`` of the state ``(u, st, anchor, never)``: the nodes that slip from
    their stick runs (``_slip_jacobians``), the others ``kc (I - P1 dc)``; ``P1`` the rounded
    coefficients of a constant, ``Emean`` the mean row of E."""
    m, n_t = st.shape
    s = E.shape[1]
    L = S.shape[1]
    J = np.empty((m, s, s))
    V = np.empty(L)
    dc = np.empty(s)
    ends = np.empty(n_t, np.intp)
    c1, v1, c2, v2 = np.empty(s * s), I1 % L, np.empty(s * s), I2 % L  # once a call, not once a node
    for q in range(s * s):
        c1[q], c2[q] = coefs[I1[q] // L], coefs[I2[q] // L]
    for i in range(m):
        Ji = J[i]
        k = kc[i]
        if never[i]:
            kmax, kmin = np.argmax(u[i]), np.argmin(u[i])
            for q in range(s):
                dc[q] = Emean[q] if u[i, kmax] == u[i, kmin] else 0.5 * (E[kmax, q] + E[kmin, q])
            for q in range(s):
                for r in range(s):
                    Ji[q, r] = k * ((1.0 if q == r else 0.0) - P1[q] * dc[r])
            continue
        V[:] = 0.0
        wraps = 0
        K = 0
        for e in range(n_t):  # the last stuck sample of every run, and the sums of S over the runs
            if st[i, e] and not st[i, e + 1 if e + 1 < n_t else 0]:
                ends[K] = e
                K += 1
                a = anchor[i, e]
                for q in range(L):
                    V[q] += S[e, q] - S[a, q]
                if e < a:
                    wraps += 1
        for q in range(L):
            V[q] += wraps * S[n_t - 1, q]
        for q in range(s):
            for r in range(s):
                e = q * s + r
                Ji[q, r] = c1[e] * V[v1[e]] + c2[e] * V[v2[e]]
        if K:
            C = np.empty((s, K))
            Ea = np.empty((K, s))
            for r in range(K):
                e = ends[r]
                a = anchor[i, e]
                w = 1.0 if e < a else 0.0
                for q in range(s):
                    C[q, r] = CP[e, q] - CP[a, q] + w * CP[n_t - 1, q]
                    Ea[r, q] = E[a, q]
            G = C @ Ea  # BLAS, as numpy's product of the stacks
            for q in range(s):
                for r in range(s):
                    Ji[q, r] -= G[q, r]
        for q in range(s):
            for r in range(s):
                Ji[q, r] *= k
    return J


def block_factor(B: Array, c: float, k: int, row0: bool) -> tuple[Array, Array, Array, int]:
    """``balance.BlockTridiagonal(B, c, k, row0)``: ``(inv_d, inv_v, inv, bad)``, the diagonals and
    first rows of the first k pivots' inverses, the others' inverses, and the first singular block
    (-1 if none)."""
    n, s, _ = B.shape
    inv_d = np.empty((k, s))
    inv_v = np.zeros((k, s))
    inv = np.empty((n - k, s, s))
    c2 = c * c
    for i in range(k):
        for q in range(s):
            di = B[i, q, q] - c2 * inv_d[i - 1, q] if i else B[0, q, q]
            if di == 0.0:
                return inv_d, inv_v, inv, i
            inv_d[i, q] = 1.0 / di
        if row0:
            for q in range(1, s):
                wi = B[i, 0, q] - c2 * inv_v[i - 1, q] if i else B[0, 0, q]
                inv_v[i, q] = -wi * inv_d[i, q] * inv_d[i, 0]
    for i in range(k, n):
        Ci = B[i].copy()
        if i == k and k:
            for q in range(s):
                Ci[q, q] -= c2 * inv_d[k - 1, q]
            if row0:
                for q in range(1, s):
                    Ci[0, q] -= c2 * inv_v[k - 1, q]
        elif i:
            Ci -= c2 * inv[i - 1 - k]
        if not np.all(np.isfinite(Ci)):  # NaN in, NaN out (the caller's checks catch it)
            inv[i - k] = np.nan
            continue
        try:
            Ri = np.linalg.inv(Ci)  # LAPACK's dgetrf and dgetri, as the numpy path
        except Exception:  # singular
            return inv_d, inv_v, inv, i
        for q in range(s):  # (copied element by element, as in ``residual``)
            for r in range(s):
                inv[i - k, q, r] = Ri[q, r]
    return inv_d, inv_v, inv, -1


def coupled_factor(J: Array, lin: Array, c: Array, k: int, row0: bool, scaled: bool) -> tuple:
    """``coupled.Coupled``'s block elimination of the Jacobian blocks ``J[:-1]`` with the linear part
    ``lin[:-1]`` on their diagonals (``with_diagonal``), each row divided by its coupling ``c`` where ``scaled``:
    ``block_factor`` of those blocks with the coupling 1 (else ``c[0]``), the same operations."""
    n, s = J.shape[0] - 1, J.shape[1]
    B = np.empty((n, s, s))
    for i in range(n):
        for q in range(s):
            for r in range(s):
                v = J[i, q, r]
                if q == r:
                    v += lin[i, q]
                B[i, q, r] = v / c[q] if scaled else v
    return _block_factor_c(B, 1.0 if scaled else c[0], k, row0)


def newton(U: Array, R: Array, res: float, T: Array, u: Array, st: Array, an: Array, nv: Array, J: Array, X: Array,
           lin: Array, c: Array, kc: Array, p: Array, ET: Array, PT: Array, half: bool, E: Array, P1: Array,
           mean: Array, S: Array, CP: Array, I1: Array, I2: Array, coefs: Array, tol: float, exact: float,
           max_iter: int, row0: bool, derivatives: bool) -> tuple:
    """``solve.FixedBar.newton`` from the evaluation ``(U, R, res, T, (u, st, an, nv), J)`` (its Jacobian
    given) where the blocks are eliminated one by one: the same steps, tests and operations (``residual``,
    ``jacobians``, ``same_pattern``, ``coupled_factor``, ``block_solve``).  Returns the last evaluation, whether its
    Jacobian is known (``has_J``) and the last factorisation (``has_fac``; ``bad`` its first singular block or -1),
    the iterations and whether ``res <= tol``:
    ``(U, R, res, T, u, st, an, nv, J, has_J, inv_d, inv_v, inv, has_fac, bad, it, converged)``."""
    scaled = c.size < 0  # False, typed as a bool (not the literal False): one signature of coupled_factor
    for q in range(c.size):
        if c[q] != c[0]:
            scaled = True
    has_J = True
    version, p_version, fac_version = 0, 0, -1  # which Jacobian: the start's 0, each one evaluated the next number
    inv_d, inv_v, inv = np.empty((0, 1)), np.empty((0, 1)), np.empty((0, 1, 1))
    has_fac, bad = False, -1
    pJ, pu, pst, pan, pnv = J, u, st, an, nv
    it = 0
    for it in range(max_iter + 1):
        done = res <= (tol if it else exact) or it == max_iter or not np.isfinite(res)
        if done and not derivatives:
            break
        if not has_J:  # an accepted trial: its predecessor's Jacobian for the same pattern
            if _same_c(pu, pst, pan, pnv, u, st, an, nv):
                J, version = pJ, p_version
            else:
                J, version = _jacobians_c(u, st, an, nv, kc, E, P1, mean, S, CP, I1, I2, coefs), p_version + 1
            has_J = True
        if version != fac_version:
            n = nv.size - 1
            k = n
            for i in range(n):
                if not nv[i]:
                    k = i
                    break
            inv_d, inv_v, inv, bad = _coupled_c(J, lin, c, k, row0, scaled)
            fac_version, has_fac = version, True
            if bad >= 0:
                break
        if done:
            break
        r = R / c if scaled else R.copy()
        dU = -_block_solve_c(inv_d, inv_v, inv, 1.0 if scaled else c[0], r, row0)
        t = 1.0
        for _ in range(30):  # the Jacobian only for the trial accepted
            tU = U + t * dU
            tR, tres, tT, tu, tst, tan, tnv = _residual_c(tU, X, lin, c, kc, p, ET, PT, half)
            if tres <= (1.0 - 1e-4 * t) * res:
                break
            t *= 0.5
        pJ, pu, pst, pan, pnv, p_version = J, u, st, an, nv, version
        U, R, res, T, u, st, an, nv = tU, tR, tres, tT, tu, tst, tan, tnv
        has_J = False
    return U, R, res, T, u, st, an, nv, J, has_J, inv_d, inv_v, inv, has_fac, bad, it, res <= tol


def block_solve(inv_d: Array, inv_v: Array, inv: Array, c: float, r: Array, row0: bool) -> Array:
    """``balance.BlockTridiagonal.solve`` for r of shape (n, s) or (n, s, q)."""
    k = inv_d.shape[0]
    n = k + inv.shape[0]
    s = inv_d.shape[1]
    y = r.copy()
    for i in range(1, n):
        if i <= k:
            z = y[i - 1].copy()
            for q in range(s):
                z[q] = inv_d[i - 1, q] * y[i - 1, q]
            if row0:
                z[0] += inv_v[i - 1, 1:] @ y[i - 1, 1:]
            yi = y[i]  # in place on the row, as numpy's y[i] -= ... (whose assignment back numba would compile)
            yi -= c * z
        else:
            yi = y[i]
            yi -= c * (inv[i - 1 - k] @ y[i - 1])
    x = np.empty_like(y)
    for i in range(n - 1, -1, -1):
        z = y[i] - c * x[i + 1] if i < n - 1 else y[i].copy()
        if i < k:
            for q in range(s):
                x[i, q] = inv_d[i, q] * z[q]
            if row0:
                x[i, 0] += inv_v[i, 1:] @ z[1:]
        else:
            np.dot(inv[i - k], z, x[i])  # the call of numba's inv @ z, into the row (as ``rows_kernel``)
    return x


def thomas(diag: Array, off: float, last: Array) -> Array:
    """``balance.scalar_tridiagonal``: column by column, the same operations."""
    n, s = diag.shape
    U = np.empty((n, s))
    cp = np.empty(n)
    y = np.empty(n)
    for j in range(s):
        cp[0] = diag[0, j]
        y[0] = last[j] if n == 1 else 0.0
        for i in range(1, n):
            w = off / cp[i - 1]
            cp[i] = diag[i, j] - w * off
            y[i] = (last[j] if i == n - 1 else 0.0) - w * y[i - 1]
        U[n - 1, j] = y[n - 1] / cp[n - 1]
        for i in range(n - 2, -1, -1):
            U[i, j] = (y[i] - off * U[i + 1, j]) / cp[i]
    return U
