"""The command line's progress line for a running scene or study (``python3 -m hbm run``).

On a terminal, one line rewritten in place (carriage return), once the run has taken longer than
``SHOW_AFTER`` seconds and at most every ``INTERVAL`` seconds.  Off a terminal (stderr piped into a
file or another program, ``plain=True``), a plain line ending in a newline, no carriage return, at
most every ``PLAIN_INTERVAL`` seconds and first after that long, so a log shows the run is alive
without filling up.  Nothing at all when disabled (``--quiet``).  It is a callback for ``hbm.scenes.run_scene(progress=...)`` and
``hbm.study.run_study(progress=...)``: it draws ``p.line()`` (a ``hbm.scenes.Progress`` or a
``hbm.study.StudyProgress``) and counts ``p.points``.  A computation that reports no progress of
its own for seconds (the main job's solve, ``--model auto``'s refined windows) runs under
:func:`ticking`, which draws :class:`Elapsed` (what runs, the points so far, the time) from a
timer thread.
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Callable, TextIO

if TYPE_CHECKING:  # only named in annotations: the main job draws its line without importing scenes or studies
    from ..scenes.running import Progress
    from ..study import StudyProgress

__all__ = ["ProgressLine", "Elapsed", "ticking", "duration", "SHOW_AFTER", "INTERVAL", "PLAIN_INTERVAL", "TICK"]


def __getattr__(name: str) -> Any:
    """``duration`` (``hbm.scenes.running.duration``, named here as before), imported when it is asked for."""
    if name == "duration":
        from ..scenes.running import duration  # lazily: the main job imports no scene module

        return duration
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


#: Seconds after which the line appears (shorter sweeps print nothing).
SHOW_AFTER = 1.0
#: Least seconds between two redraws.
INTERVAL = 0.1
#: Seconds between two plain lines off a terminal (and before the first one).
PLAIN_INTERVAL = 5.0
#: Seconds between two looks of :func:`ticking`'s timer at a computation that reports nothing itself.
TICK = 0.5


class ProgressLine:
    """``line(progress)`` redraws ``progress.line()`` on ``stream``: for a scene
    ``run i/n label: omega ... rad/s (xx %), N points, t s, about T left`` (runs numbered from 1,
    as in the CSV and the summary; T from the time so far), for a study
    ``run i/n (f failed, r reused), t s, about T left``.

    ``plain=True`` (the stream is not a terminal): the same text as whole lines, one at most every
    ``PLAIN_INTERVAL`` seconds.  ``clock`` gives the time in seconds (``time.monotonic``).
    """

    def __init__(self, stream: TextIO, *, enabled: bool, plain: bool = False,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.stream = stream
        self.enabled = enabled
        self.plain = plain
        self.points = 0  #: points (a study: runs) finished so far (also counted when disabled)
        self._clock = clock
        self._last: float | None = None
        self._width = 0

    def __call__(self, p: Progress | StudyProgress) -> None:
        self.points = p.points
        if not self.enabled:
            return
        if self.plain:
            self._plain(p)
            return
        if p.elapsed < SHOW_AFTER:
            return
        now = self._clock()
        if self._last is not None and now - self._last < INTERVAL:
            return
        self._last = now
        text = p.line()
        self.stream.write("\r" + text.ljust(self._width))
        self.stream.flush()
        self._width = len(text)

    def _plain(self, p: Progress | StudyProgress) -> None:
        now = self._clock()
        if self._last is None:  # the run started p.elapsed s ago: the first line PLAIN_INTERVAL s after that
            self._last = now - p.elapsed
        if now - self._last < PLAIN_INTERVAL:
            return
        self._last = now
        self.stream.write(p.line() + "\n")
        self.stream.flush()

    def clear(self) -> None:
        """Erase the line (before the summary is printed)."""
        if self._width:
            self.stream.write("\r" + " " * self._width + "\r")
            self.stream.flush()
            self._width = 0



@dataclass
class Elapsed:
    """The progress of a computation that says only what it is and how far it got: ``what``, the
    points accepted so far (``points``, 0 while none is reported) with the last frequency
    (``omega``, rad/s, or None), and ``elapsed`` s.

    Examples
    --------
    >>> Elapsed("the main job (--model auto)", 7.2, points=120, omega=38000.0).line()
    'the main job (--model auto): 120 points, omega = 38000 rad/s, 7 s'
    >>> Elapsed("the main job (--model auto)", 2.6).line()
    'the main job (--model auto): 3 s'
    """

    what: str
    elapsed: float
    points: int = 0
    omega: float | None = None

    def line(self) -> str:
        got = f"{self.points} points, omega = {self.omega:.6g} rad/s, " if self.points and self.omega is not None else ""
        return f"{self.what}: {got}{self.elapsed:.0f} s"


def ticking(line: ProgressLine, what: str, compute: Callable[[Elapsed], Any],
            clock: Callable[[], float] = time.monotonic) -> Any:
    """``compute(state)`` with ``line`` drawing ``state`` (an :class:`Elapsed`, whose ``points``
    and ``omega`` ``compute`` may update, e.g. from ``frequency_response``'s ``callback``) every
    :data:`TICK` s from a timer thread, until it returns (or raises); the line then stays for the
    caller to clear.  ``line`` keeps its own rules: nothing before ``SHOW_AFTER`` s on a terminal,
    a plain line every ``PLAIN_INTERVAL`` s off one."""
    t0 = clock()
    state = Elapsed(what, 0.0)
    done = threading.Event()

    def tick() -> None:
        while not done.wait(TICK):
            state.elapsed = clock() - t0
            line(state)

    timer = threading.Thread(target=tick, name="progress", daemon=True)
    timer.start()
    try:
        return compute(state)
    finally:
        done.set()
        timer.join()
