"""The command line's progress line for a running scene or study (``python -m hbm run``).

One line on a terminal, rewritten in place (carriage return), once the run has taken longer than
``SHOW_AFTER`` seconds and at most every ``INTERVAL`` seconds; nothing at all when disabled (not a
terminal, or ``--quiet``).  It is a callback for ``hbm.scenes.run_scene(progress=...)`` and
``hbm.study.run_study(progress=...)``: it draws ``p.line()`` (a ``hbm.scenes.Progress`` or a
``hbm.study.StudyProgress``) and counts ``p.points``.
"""

from __future__ import annotations

import time
from typing import TextIO

from ..scenes.running import Progress, duration
from ..study import StudyProgress

__all__ = ["ProgressLine", "duration", "SHOW_AFTER", "INTERVAL"]

#: Seconds after which the line appears (shorter sweeps print nothing).
SHOW_AFTER = 1.0
#: Least seconds between two redraws.
INTERVAL = 0.1


class ProgressLine:
    """``line(progress)`` redraws ``progress.line()`` on ``stream``: for a scene
    ``run i/n label: omega ... rad/s (xx %), N points, t s, about T left`` (runs numbered from 1,
    as in the CSV and the summary; T from the time so far), for a study
    ``run i/n (f failed, r reused), t s, about T left``."""

    def __init__(self, stream: TextIO, *, enabled: bool) -> None:
        self.stream = stream
        self.enabled = enabled
        self.points = 0  #: points (a study: runs) finished so far (also counted when disabled)
        self._last = -1.0
        self._width = 0

    def __call__(self, p: Progress | StudyProgress) -> None:
        self.points = p.points
        if not self.enabled or p.elapsed < SHOW_AFTER:
            return
        now = time.monotonic()
        if now - self._last < INTERVAL:
            return
        self._last = now
        text = p.line()
        self.stream.write("\r" + text.ljust(self._width))
        self.stream.flush()
        self._width = len(text)

    def clear(self) -> None:
        """Erase the line (before the summary is printed)."""
        if self._width:
            self.stream.write("\r" + " " * self._width + "\r")
            self.stream.flush()
            self._width = 0

