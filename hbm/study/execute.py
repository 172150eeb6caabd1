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

from .._threads import openblas_setters
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
    for path, setter in openblas_setters():
        setter(ctypes.c_int(1))
        done.append(path)
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


#: In a worker of a study with a time limit: the queue on which each run says it started.
_STARTS: Any = None


def _worker_init(starts: Any = None) -> None:
    """A worker process computes on one thread (:func:`single_threaded_blas`), leaves Ctrl-C to
    its parent (which stops it), dies on SIGTERM, and ends on its own when its parent is gone
    (:func:`_watch_parent`).  ``starts``: the queue of a time-limited study (:func:`_started`)."""
    global _STARTS
    _STARTS = starts
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


class RunTimeLimit(Exception):
    """A run of a study took longer than its time limit (``study.time_limit``, ``--time-limit``)."""


def time_limit_message(limit: float) -> str:
    """The message of a run stopped at its time limit."""
    return (f"RunTimeLimit: the run took longer than its time limit of {limit:g} s and was stopped "
            "(study.time_limit, --time-limit)")


def _failed(message: str, elapsed: float) -> dict:
    return {"success": False, "message": message, "peak_omega_rad_s": None, "peak_amplitude_m": None,
            "peak_error_rel": None, "peak_model": None, "nfev": None, "curve": {}, "time_s": elapsed}


def limited(runner: Callable[[Mapping[str, Any]], Any], limit: float | None, point: Mapping[str, Any]) -> dict:
    """``execute(runner, point)`` stopped after ``limit`` seconds (SIGALRM, in the main thread where the
    platform has it): a failed record naming the limit.  ``limit`` None: no limit."""
    if limit is None or not hasattr(signal, "setitimer") or threading.current_thread() is not threading.main_thread():
        return execute(runner, point)

    def alarm(signum: int, frame: Any) -> None:
        raise RunTimeLimit(f"the run took longer than its time limit of {limit:g} s")

    t0 = time.perf_counter()
    previous = signal.signal(signal.SIGALRM, alarm)
    signal.setitimer(signal.ITIMER_REAL, limit)
    try:
        rec = execute(runner, point)  # the alarm inside the runner: a failed record of it
    except RunTimeLimit:  # the alarm between the runner's end and execute's own
        rec = None
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, previous)
    if rec is None or rec["message"].startswith("RunTimeLimit:"):
        rec = _failed(time_limit_message(limit), time.perf_counter() - t0)
    return rec


def _started(runner: Callable[[Mapping[str, Any]], Any], limit: float, task: tuple) -> dict:
    """In a worker: say on the start queue that run ``task[0]`` starts here, then :func:`limited`."""
    index, point = task
    _STARTS.put((index, os.getpid(), time.time()))
    return limited(runner, limit, point)


#: Seconds past its limit the parent gives a run before it kills the worker (a worker that cannot
#: stop itself: stopped by SIGSTOP, or inside a long call of compiled code).
KILL_GRACE_S = 2.0
#: Seconds between two looks of the parent at its runs' time (a study with a time limit).
WATCH_PERIOD_S = 0.1


def _run_processes_limited(runner: Callable, tasks: Sequence[tuple[int, Mapping[str, Any]]],
                           on_done: Callable[[int, dict], None], workers: int | None, limit: float,
                           start: Callable[[], None]) -> list[tuple[int, str]]:
    """``run_tasks`` on worker processes with a time limit per run: each run stops itself at
    ``limit`` (:func:`limited`); a worker still on it ``KILL_GRACE_S`` later is killed (SIGKILL: a
    stopped process too), its run recorded as failed at its limit, and the runs the broken pool lost
    computed again on a new one."""
    import multiprocessing

    todo = dict(tasks)
    lost: list = []
    started = False
    while todo:
        starts = multiprocessing.get_context().SimpleQueue()
        n = workers or min(cores(), len(todo))
        with _sigint_blocked():
            pool = cf.ProcessPoolExecutor(max_workers=n, initializer=_worker_init, initargs=(starts,))
            futures = {pool.submit(_started, runner, limit, (i, p)): i for i, p in list(todo.items())[:n]}
        if not started:
            start()
            started = True
        for i, p in list(todo.items())[n:]:
            futures[pool.submit(_started, runner, limit, (i, p))] = i
        running: dict = {}  # index -> (pid, start time)
        killed: set = set()
        broken = False
        try:
            pending = set(futures)
            while pending:
                done, pending = cf.wait(pending, timeout=WATCH_PERIOD_S, return_when=cf.FIRST_COMPLETED)
                for fut in done:
                    i = futures[fut]
                    exc = fut.exception()
                    if exc is None:
                        todo.pop(i, None)
                        running.pop(i, None)
                        on_done(i, fut.result())
                    elif isinstance(exc, cf.process.BrokenProcessPool) and (killed or broken):
                        broken = True  # lost with the killed worker's pool: computed again
                    else:
                        todo.pop(i, None)
                        lost.append((i, f"{type(exc).__name__}: {exc}".rstrip(": ")))
                while not starts.empty():
                    i, pid, t = starts.get()
                    running[i] = (pid, t)
                now = time.time()
                for i, (pid, t) in list(running.items()):
                    if i in todo and i not in killed and now - t > limit + KILL_GRACE_S:
                        with contextlib.suppress(OSError):
                            os.kill(pid, signal.SIGKILL)
                        killed.add(i)
                        todo.pop(i)
                        on_done(i, _failed(time_limit_message(limit), now - t))
                if killed:
                    broken = True
                    break
        except BaseException:
            with _sigint_deferred():
                _stop(pool)
            raise
        _end(pool)
    return sorted(lost)


def _end(pool: cf.ProcessPoolExecutor) -> None:
    """Shut ``pool`` down without waiting on a worker that cannot end (stopped by SIGSTOP): each gets
    ``KILL_GRACE_S`` to exit, then SIGKILL."""
    procs = list((getattr(pool, "_processes", None) or {}).values())
    pool.shutdown(wait=False, cancel_futures=True)
    for proc in procs:
        proc.join(KILL_GRACE_S)
        if proc.is_alive():
            proc.kill()
            proc.join(KILL_GRACE_S)


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
              scheduler: str | None = None, on_start: Callable[[], None] | None = None,
              time_limit: float | None = None) -> list[tuple[int, str]]:
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
    time_limit : float, optional
        Seconds a run may take (default None: no limit).  A run over it becomes a failed record naming
        the limit; on worker processes one that does not stop (a worker stopped by SIGSTOP) is killed
        ``KILL_GRACE_S`` later and the runs that shared its pool are computed again.  Serial and worker
        runs stop themselves by SIGALRM; a Dask cluster's runs are not limited.

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
    if time_limit is not None and (isinstance(time_limit, bool) or not isinstance(time_limit, (int, float))
                                   or not 0.0 < time_limit < float("inf")):
        raise InputError(f"time_limit must be a number of seconds > 0 or None, got time_limit={time_limit!r}")
    fn = functools.partial(execute, runner) if time_limit is None else functools.partial(limited, runner, time_limit)
    start = on_start if on_start is not None else (lambda: None)
    if executor == "serial" or (executor == "processes" and workers == 1):
        start()
        for index, point in tasks:
            on_done(index, fn(point))
        return []
    if not tasks:
        start()
        return []
    if executor == "processes" and time_limit is not None:
        return _run_processes_limited(runner, tasks, on_done, workers, float(time_limit), start)
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


__all__ = ["EXECUTORS", "DASK_MISSING", "DASK_CONNECT_TIMEOUT", "RunTimeLimit", "KILL_GRACE_S", "limited", "PARENT_CHECK_S", "BLAS_THREAD_VARIABLES", "single_threaded_blas", "cores", "signals_held", "check_executor", "dask_executor", "run_tasks"]
