"""The command line's progress line for a running scene or study (``python -m hbm run``).

On a terminal, one line rewritten in place (carriage return), once the run has taken longer than
``SHOW_AFTER`` seconds and at most every ``INTERVAL`` seconds.  Off a terminal (stderr piped into a
file or another program, ``plain=True``), a plain line ending in a newline, no carriage return, at
most every ``PLAIN_INTERVAL`` seconds and first after that long, so a log shows the run is alive
without filling up.  Nothing at all when disabled (``--quiet``).  It is a callback for ``hbm.scenes.run_scene(progress=...)`` and
``hbm.study.run_study(progress=...)``: it draws ``p.line()`` (a ``hbm.scenes.Progress`` or a
``hbm.study.StudyProgress``) and counts ``p.points``.
"""

from __future__ import annotations

import time
from typing import Callable, TextIO

from ..scenes.running import Progress, duration
from ..study import StudyProgress

__all__ = ["ProgressLine", "duration", "SHOW_AFTER", "INTERVAL", "PLAIN_INTERVAL"]

#: Seconds after which the line appears (shorter sweeps print nothing).
SHOW_AFTER = 1.0
#: Least seconds between two redraws.
INTERVAL = 0.1
#: Seconds between two plain lines off a terminal (and before the first one).
PLAIN_INTERVAL = 5.0


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

