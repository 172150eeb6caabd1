"""Executors of a study: serial, local processes (``concurrent.futures``) and Dask distributed.

Every executor calls the same pure function, :func:`hbm.study.runs.execute`, on the same points
(drawn beforehand in the calling process), so the records agree to the last bit whichever runs
them.  Records come back to the calling process one by one as runs finish, and are handed to
``on_done`` there (which writes them).  A worker process that dies breaks a process pool: the
runs not finished by then are reported as lost, never recorded, and a rerun computes them (Dask
retries a dead worker's runs on the others first).
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import ctypes
import functools
import os
import signal
import threading
import time
from typing import Any, Callable, Iterator, Mapping, Sequence

from .._validation import InputError
from .runs import execute
from .lock import alive

#: Executors by name; an instance of ``concurrent.futures.Executor`` is accepted too.
EXECUTORS = ("processes", "serial", "dask")
#: The message when Dask is asked for and not installed.
DASK_MISSING = ('executor "dask" needs the packages dask and distributed, which are not installed: '
                'pip install "frictiondamp[dask]"')


def cores() -> int:
    """The cores this process may use (``os.sched_getaffinity`` where available).

    Returns
    -------
    int
        The number of cores (>= 1): the default number of workers of a study.
    """
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def check_executor(executor: Any, workers: int | None, scheduler: str | None) -> None:
    """Refuse unknown executors and worker counts by name (``ValueError``)."""
    if not (isinstance(executor, cf.Executor) or executor in EXECUTORS):
        raise ValueError(f"executor must be one of {', '.join(map(repr, EXECUTORS))} or a "
                         f"concurrent.futures.Executor, got executor={executor!r}")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise ValueError(f"workers must be an integer >= 1 or None (every core), got workers={workers!r}")
    if scheduler is not None and (executor != "dask" or not isinstance(scheduler, str) or not scheduler):
        raise ValueError(f"scheduler (a Dask scheduler's address) needs executor='dask', got "
                         f"scheduler={scheduler!r} with executor={executor!r}")


#: Seconds between two looks of a worker process at its parent (it ends when the parent is gone).
PARENT_CHECK_S = 0.2


#: Environment variables that set the threads of the BLAS / OpenMP libraries a process loads.
BLAS_THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS",
                         "VECLIB_MAXIMUM_THREADS", "NUMEXPR_NUM_THREADS")


def single_threaded_blas() -> list[str]:
    """Make this process's linear algebra single-threaded: a study's workers already use every core.

    Sets :data:`BLAS_THREAD_VARIABLES` to 1 (for libraries loaded from now on) and, on Linux, calls
    ``set_num_threads(1)`` of every OpenBLAS already loaded (numpy's and scipy's, inherited from
    the parent by a forked worker, whose thread count the variables no longer change).  Without
    it two workers on two cores each run BLAS on two threads, which wait on each other.

    Returns
    -------
    list of str
        The OpenBLAS libraries set to one thread (empty where none is found or not on Linux).
    """
    for name in BLAS_THREAD_VARIABLES:
        os.environ[name] = "1"
    done = []
    try:
        with open("/proc/self/maps") as maps:
            paths = sorted({line.split()[-1] for line in maps if "openblas" in line.lower() and ".so" in line})
    except OSError:  # not Linux: the environment variables only
        return done
    for path in paths:
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            continue
        for fn in ("openblas_set_num_threads", "openblas_set_num_threads64_", "scipy_openblas_set_num_threads",
                   "scipy_openblas_set_num_threads64_"):
            if hasattr(lib, fn):
                getattr(lib, fn)(ctypes.c_int(1))
                done.append(path)
                break
    return done


def _worker_init() -> None:
    """A worker process computes on one thread (:func:`single_threaded_blas`), leaves Ctrl-C to
    its parent (which stops it), dies on SIGTERM, and ends on its own when its parent is gone
    (:func:`_watch_parent`)."""
    single_threaded_blas()
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    if hasattr(signal, "pthread_sigmask"):  # blocked by the parent while it started us (_sigint_blocked)
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
    _watch_parent()


def _watch_parent(period: float = PARENT_CHECK_S) -> threading.Thread:
    """Start a daemon thread that ends this process as soon as its parent is gone.

    A parent killed by SIGKILL cannot stop its workers, and a worker blocked reading its next
    task from the pool's pipe never sees the pipe close (its siblings hold the other end).  The
    kernel gives an orphan a new parent, so ``os.getppid()`` changes: the thread then ends the
    process with ``os._exit`` (nothing is left to hand a result to)."""

    parent = os.getppid()
    windows = os.name == "nt"  # no new parent there: ask whether the old one still runs

    def watch() -> None:
        while True:
            time.sleep(period)
            if os.getppid() != parent or (windows and not alive(parent)):
                os._exit(1)

    thread = threading.Thread(target=watch, name="hbm-study-parent-watch", daemon=True)
    thread.start()
    return thread


@contextlib.contextmanager
def _sigint_blocked() -> Iterator[None]:
    """Hold Ctrl-C back (``pthread_sigmask``) while worker processes start: a process started
    now inherits the mask and ignores Ctrl-C before unblocking it (:func:`_worker_init`), so a
    Ctrl-C at the start prints no worker's traceback; this process gets it once unblocked."""
    if not hasattr(signal, "pthread_sigmask") or threading.current_thread() is not threading.main_thread():
        yield
        return
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


@contextlib.contextmanager
def _sigint_deferred() -> Iterator[None]:
    """Let a further Ctrl-C pass unheeded while an interrupted study stops its workers: the first
    one is already on its way up, and a second must not cut the cleanup short (it would leave
    workers running and print a second traceback)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, lambda signum, frame: None)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


@contextlib.contextmanager
def signals_held() -> Iterator[None]:
    """Hold Ctrl-C and SIGTERM back while the body runs, and act on the first one after it.

    A study writes each finished run to two files (``runs.jsonl`` and the CSV table); a signal
    raised between the two writes left the log a run ahead of the table.  The body runs with
    handlers that only note a signal; the previous handlers come back at its end, and the first
    signal noted is then handed to its own (which raises, as it would have).  Outside the main
    thread, where handlers cannot be set, the body runs as it is.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    noted: list = []
    held = {s: signal.signal(s, lambda signum, frame: noted.append((signum, frame)))
            for s in (signal.SIGINT, signal.SIGTERM) if signal.getsignal(s) is not None}
    try:
        yield
    finally:
        for s, handler in held.items():
            signal.signal(s, handler)
        if noted:
            signum, frame = noted[0]
            handler = held[signum]
            if callable(handler):
                handler(signum, frame)
            elif handler == signal.SIG_DFL:
                signal.raise_signal(signum)


def dask_executor(workers: int | None, scheduler: str | None) -> tuple[cf.Executor, Callable[[], None]]:
    """``(executor, close)`` on a Dask cluster: a ``LocalCluster`` of ``workers`` single-threaded
    worker processes, or the running scheduler at ``scheduler``.  ``ImportError`` saying how to
    install Dask when it is not installed."""
    try:
        from distributed import Client, LocalCluster  # the optional [dask] extra
    except ImportError:
        raise ImportError(DASK_MISSING) from None
    if scheduler is not None:
        try:
            client, cluster = _connect(Client, scheduler, DASK_CONNECT_TIMEOUT), None
        except InputError:
            raise
        except OSError as exc:  # refused, unreachable, timed out
            raise InputError(f"cannot reach the Dask scheduler at scheduler={scheduler!r}: {exc}") from None
        except Exception as exc:  # noqa: BLE001 - something answered that does not speak Dask's protocol
            what = f"{type(exc).__name__}: {exc}"
            raise InputError(f"cannot use the Dask scheduler at scheduler={scheduler!r}: what answers there is "
                             f"not a Dask scheduler (reading its answer failed with {what[:200]})") from None
    else:
        cluster = LocalCluster(n_workers=workers or cores(), threads_per_worker=1, processes=True,
                               dashboard_address=":0")
        client = Client(cluster)

    def close() -> None:
        client.close()
        if cluster is not None:
            cluster.close()

    return client.get_executor(pure=False), close


#: Seconds a study waits for a Dask scheduler to answer (an address that accepts the connection and
#: never answers made Dask's own client wait past 120 s, its timeout notwithstanding).
DASK_CONNECT_TIMEOUT = 30.0


def _connect(Client: Any, scheduler: str, timeout: float) -> Any:
    """``Client(scheduler)``, in a thread given ``timeout`` seconds; ``InputError`` when no answer came."""
    box: dict = {}

    def connect() -> None:
        try:
            box["client"] = Client(scheduler, timeout=timeout)
        except BaseException as exc:  # noqa: BLE001 - handed to the caller
            box["error"] = exc

    thread = threading.Thread(target=connect, name="hbm-dask-connect", daemon=True)
    thread.start()
    thread.join(timeout)
    if thread.is_alive():
        raise InputError(f"the Dask scheduler at scheduler={scheduler!r} did not answer within {timeout:g} s "
                         "(hbm.study.execute.DASK_CONNECT_TIMEOUT): something accepts connections there but does "
                         "not answer as a Dask scheduler; check the address")
    if "error" in box:
        raise box["error"]
    return box["client"]


def _stop(pool: cf.Executor) -> None:
    """Cancel what has not started and end the worker processes now (an interrupted study)."""
    kill = getattr(pool, "terminate_workers", None)  # Python >= 3.14
    if kill is not None:
        kill()
        return
    procs = list((getattr(pool, "_processes", None) or {}).values())  # shutdown forgets them
    pool.shutdown(wait=False, cancel_futures=True)
    for proc in procs:
        proc.terminate()


def run_tasks(runner: Callable[[Mapping[str, Any]], Any], tasks: Sequence[tuple[int, Mapping[str, Any]]],
              on_done: Callable[[int, dict], None], *, executor: Any = "processes", workers: int | None = None,
              scheduler: str | None = None, on_start: Callable[[], None] | None = None) -> list[tuple[int, str]]:
    """Run ``execute(runner, point)`` for each ``(index, point)`` of ``tasks``; ``on_done(index,
    record)`` in this process as each finishes.  Returns the runs lost (not computed) as
    ``[(index, reason)]``: a worker process that died, a cluster that failed.

    ``executor``: "serial" (here, in order), "processes" (a ``ProcessPoolExecutor`` of ``workers``
    processes, default every core), "dask" (``dask_executor``) or an executor instance (used, not
    shut down).  KeyboardInterrupt (and anything raised by ``on_done``) stops the workers and
    propagates; what ``on_done`` was given is kept; a further Ctrl-C while the workers are
    stopped is ignored.  Worker processes end on their own when this process is killed.

    Parameters
    ----------
    runner : callable
        A picklable function of one point (a dict), as ``Study.runner``.
    tasks : sequence of (int, dict)
        The runs: ``(index, point)``; the index is handed back to ``on_done``.
    on_done : callable
        ``on_done(index, record)``, called in this process once per finished run with the
        record of ``execute``.
    executor : {"processes", "serial", "dask"} or concurrent.futures.Executor, default "processes"
        Where the runs are computed; ``"processes"`` with ``workers=1`` runs serially.
    workers : int, optional
        Worker processes (>= 1); default every core (``cores()``), at most one per task.
    scheduler : str, optional
        Address of a running Dask scheduler; only with ``executor="dask"``.
    on_start : callable, optional
        Called once with no argument when the executor is up, before the first run (also when
        ``tasks`` is empty); not called if the executor cannot start.

    Returns
    -------
    list of (int, str)
        The runs lost, sorted by index, each with the exception that lost it; empty when every
        run was handed to ``on_done``.

    Raises
    ------
    ValueError
        For an unknown ``executor``, ``workers`` not an integer >= 1, a ``scheduler`` without
        ``executor="dask"``, or a Dask scheduler that cannot be reached.
    ImportError
        For ``executor="dask"`` without dask and distributed.

    Examples
    --------
    >>> done = {}
    >>> run_tasks(lambda p: {"peak_amplitude_m": p["x"]}, [(0, {"x": 1.0}), (1, {"x": 2.0})],
    ...           lambda i, rec: done.update({i: rec["peak_amplitude_m"]}), executor="serial")
    []
    >>> done
    {0: 1.0, 1: 2.0}
    """
    check_executor(executor, workers, scheduler)
    fn = functools.partial(execute, runner)
    start = on_start if on_start is not None else (lambda: None)
    if executor == "serial" or (executor == "processes" and workers == 1):
        start()
        for index, point in tasks:
            on_done(index, fn(point))
        return []
    if not tasks:
        start()
        return []
    close = None
    first = 0  # tasks submitted with Ctrl-C held back: those that start the worker processes
    if executor == "processes":
        first = workers or min(cores(), len(tasks))
        pool = cf.ProcessPoolExecutor(max_workers=first, initializer=_worker_init)
    elif executor == "dask":
        pool, close = dask_executor(workers, scheduler)
    else:
        pool = executor
    lost = []
    interrupted = False
    try:
        start()
        futures = {}
        with _sigint_blocked() if first else contextlib.nullcontext():
            for index, point in tasks[:first]:
                futures[pool.submit(fn, point)] = index
        for index, point in tasks[first:]:
            futures[pool.submit(fn, point)] = index
        for fut in cf.as_completed(futures):
            exc = fut.exception()
            if exc is None:
                on_done(futures[fut], fut.result())
            else:
                lost.append((futures[fut], f"{type(exc).__name__}: {exc}".rstrip(": ")))
    except BaseException:
        interrupted = True
        raise
    finally:
        with _sigint_deferred() if interrupted else contextlib.nullcontext():
            if interrupted and executor == "processes":
                _stop(pool)
            if close is not None:
                close()
            elif executor == "processes":
                pool.shutdown(wait=True, cancel_futures=True)
    return sorted(lost)


__all__ = ["EXECUTORS", "DASK_MISSING", "DASK_CONNECT_TIMEOUT", "PARENT_CHECK_S", "BLAS_THREAD_VARIABLES", "single_threaded_blas", "cores", "signals_held", "check_executor", "dask_executor", "run_tasks"]
