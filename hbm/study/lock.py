"""One study at a time in a folder: a lock file holding the PID of the process that writes there.

:func:`hold` creates ``study.lock`` in the folder with ``os.open(O_CREAT | O_EXCL)`` (atomic: of
several processes only one creates it) and writes its PID into it; a second study into the same
folder is refused at once with :class:`FolderInUse`, naming the folder and that PID.  A lock whose
process is gone (``os.kill(pid, 0)`` fails; killed: SIGKILL, a power cut), or whose PID is now
another process's (on Linux the file also holds the process's start time), is stale: it is
moved aside with ``os.rename`` (atomic: of several processes only one moves a given file) and
the lock created anew, as above.  A lock written on another host (a folder shared between
machines) cannot be checked and is never taken for stale.  The lock is removed when the study
ends, however it ends (an error, Ctrl-C, SIGTERM).
"""

from __future__ import annotations

import contextlib
import os
import socket
import time
from pathlib import Path
from typing import Iterator

from .._validation import InputError

#: The lock file's name in a study's folder.
LOCK = "study.lock"


class FolderInUse(InputError):
    """Another live process is writing a study into the folder.

    Attributes
    ----------
    folder : pathlib.Path
        The folder.
    pid : int
        The PID of the process that holds its lock.
    """

    def __init__(self, folder: Path, pid: int, host: str = "") -> None:
        self.folder, self.pid = Path(folder), pid
        on = f" on {host}" if host and host != socket.gethostname() else ""
        super().__init__(f"the folder {self.folder} is in use by another study (process {pid}{on} holds "
                         f"{self.folder / LOCK}): wait for it to end, or write into another folder (--out)")


_HELD: set = set()  # the locks this process holds (a lock of its PID not here is a reused PID's)


#: A takeover guard older than this (s) was left by a process that died holding it.
GUARD_STALE = 5.0


def _stat(pid: int) -> list | None:
    """The fields of ``/proc/PID/stat`` after the command's name (state first); None without."""
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except (OSError, IndexError):
        return None


def _started(pid: int) -> str:
    """When ``pid`` started (clock ticks after boot, ``/proc``), or "" where unknown."""
    fields = _stat(pid)
    return fields[19] if fields is not None and len(fields) > 19 else ""


def holder(path: str | Path) -> int | None:
    """The PID written in the lock file ``path``; None if it is missing, empty or not a PID."""
    return _read(path)[0]


def _read(path: str | Path) -> tuple:
    """``(pid, started, host)`` of a lock file (its words: the PID, the start time or "-", the
    host name); ``(None, "", "")`` without a PID."""
    try:
        words = [w.decode("utf-8", "replace") for w in Path(path).read_bytes().split()]
        pid = int(words[0])
    except (OSError, IndexError, ValueError):
        return None, "", ""
    started = words[1] if len(words) > 1 and words[1] != "-" else ""
    return (pid if pid > 0 else None), started, (words[2] if len(words) > 2 else "")


def alive(pid: int, started: str = "") -> bool:
    """Whether the process ``pid`` runs (``os.kill(pid, 0)``): not if it is a zombie (dead, not
    yet reaped by its parent), nor if it started at another time than ``started`` (when given
    and known: its PID was reused)."""
    if pid == os.getpid():
        return True
    if os.name == "nt":  # there os.kill(pid, 0) would send Ctrl-C (0 is CTRL_C_EVENT)
        return _alive_windows(pid)
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's process
        return True
    except OSError:
        return False
    fields = _stat(pid)
    if fields is None:  # no /proc: not Linux, or gone since
        return True
    if fields[0] in ("Z", "X"):
        return False
    return not (started and _started(pid) and _started(pid) != started)


def _alive_windows(pid: int) -> bool:
    import ctypes  # only on Windows, where os.kill(pid, 0) would send Ctrl-C

    kernel32 = ctypes.windll.kernel32  # type: ignore[attr-defined]
    handle = kernel32.OpenProcess(0x1000, False, pid)  # PROCESS_QUERY_LIMITED_INFORMATION
    if not handle:
        return ctypes.GetLastError() == 5  # type: ignore[attr-defined]  # access denied: it exists
    try:
        code = ctypes.c_ulong()
        return not kernel32.GetExitCodeProcess(handle, ctypes.byref(code)) or code.value == 259  # STILL_ACTIVE
    finally:
        kernel32.CloseHandle(handle)


def _held_by_other(path: Path) -> int | None:
    """The PID of the live process, not this one, that holds the lock ``path``; None if stale."""
    pid, started, host = _read(path)
    if pid is None:
        return None
    if host and host != socket.gethostname():  # a folder shared between machines: cannot look
        return pid
    if pid == os.getpid():
        return pid if path in _HELD else None
    return pid if alive(pid, started) else None


def _move_stale(path: Path, pid: int | None, *, young: float = 2.0) -> None:
    """Remove the stale lock ``path`` (of ``pid``; None: empty or no PID) so that the next
    ``O_EXCL`` create wins.

    Under a guard file made with ``O_EXCL`` (one process at a time): the lock is read again and
    removed only if it is still the stale one seen (the same PID, not held by a live process, an
    empty one no longer young), so a lock that another process created meanwhile is never taken
    away.  A guard older than ``GUARD_STALE`` seconds was left by a process that died holding it.
    """
    guard = path.with_name(path.name + ".takeover")
    try:
        fd = os.open(guard, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
    except FileExistsError:
        with contextlib.suppress(FileNotFoundError):
            if time.time() - guard.stat().st_mtime > GUARD_STALE:
                os.unlink(guard)
        time.sleep(0.005)  # another process is taking the stale lock over: look again after it
        return
    try:
        os.close(fd)
        now = _read(path)[0]
        with contextlib.suppress(FileNotFoundError):
            fresh = now is None and time.time() - path.stat().st_mtime < young
            if now == pid and not fresh and _held_by_other(path) is None:
                os.unlink(path)
    finally:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(guard)


def acquire(folder: str | Path, *, wait_for_pid: float = 2.0) -> Path:
    """Create the lock of ``folder`` (which exists) for this process; its path.

    Raises :class:`FolderInUse` if a live process holds it.  An empty lock file is taken for
    one being written, for up to ``wait_for_pid`` seconds after it was made; after that, or if
    it holds no PID, or if its process is gone, it is stale and replaced.
    """
    folder = Path(folder)
    path = Path(os.path.abspath(folder)) / LOCK
    t0 = time.monotonic()
    while True:
        try:
            fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
        except FileExistsError:
            live = _held_by_other(path)
            if live is not None:
                raise FolderInUse(folder, live, _read(path)[2]) from None
            pid = holder(path)
            if pid is None:
                try:
                    st = path.stat()
                except FileNotFoundError:
                    continue
                young = time.time() - st.st_mtime < wait_for_pid and time.monotonic() - t0 < wait_for_pid
                if st.st_size == 0 and young:
                    time.sleep(0.01)  # its creator is writing its PID
                    continue
            _move_stale(path, pid, young=wait_for_pid)
            if time.monotonic() - t0 > 10.0 * wait_for_pid:  # never seen: contention that does not settle
                raise FolderInUse(folder, pid or 0) from None
            continue
        with os.fdopen(fd, "w") as fh:
            fh.write(f"{os.getpid()}\n{_started(os.getpid()) or '-'}\n{socket.gethostname()}\n")
        _HELD.add(path)
        return path


def release(path: str | Path) -> None:
    """Remove the lock ``path`` if this process holds it."""
    path = Path(os.path.abspath(path))
    if path in _HELD:
        _HELD.discard(path)
        if holder(path) == os.getpid():
            with contextlib.suppress(OSError):
                path.unlink()


@contextlib.contextmanager
def hold(folder: str | Path) -> Iterator[Path]:
    """``with hold(folder):`` this process alone writes a study there (:func:`acquire`,
    :func:`release`).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> with hold(folder) as lock:
    ...     holder(lock) == os.getpid()
    True
    >>> lock.exists()
    False
    """
    path = acquire(folder)
    try:
        yield path
    finally:
        release(path)


__all__ = ["LOCK", "FolderInUse", "holder", "alive", "acquire", "release", "hold"]
