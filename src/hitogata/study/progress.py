"""Progress of a study on the terminal: tasks done, failed, rate and time left.

On a terminal one line is rewritten in place (at most a few times a
second); elsewhere (a log file, a pipe) a line is printed every tenth of the
study or every minute, whichever comes first, so a log is not flooded.
"""

from __future__ import annotations

import sys
import time
from typing import TextIO

from hitogata.study.runner import RunSummary


class ProgressLine:
    """A callable for the runner's `progress` hook."""

    def __init__(self, stream: TextIO = sys.stderr, interval: float | None = None) -> None:
        self.stream = stream
        self.tty = stream.isatty()
        self.interval = interval if interval is not None else (0.25 if self.tty else 60.0)
        self.last_time = -float("inf")
        self.last_tenth = 0

    def __call__(self, s: RunSummary) -> None:
        finished = s.done + s.failed
        todo = s.total - s.skipped
        now = time.monotonic()
        tenth = 10 * finished // max(todo, 1)
        final = finished >= todo
        if not final and now - self.last_time < self.interval and (self.tty or tenth == self.last_tenth):
            return
        self.last_time, self.last_tenth = now, tenth
        self.stream.write(("\r" if self.tty else "") + line(s) + ("\n" if final or not self.tty else ""))
        self.stream.flush()


def line(s: RunSummary) -> str:
    """'37/120 tasks (12 done before), 2 failed, 14.2 tasks/min, 5 min 51 s left'."""
    finished = s.done + s.failed
    todo = s.total - s.skipped
    rate = s.rate_per_minute
    left = (todo - finished) / rate * 60.0 if rate > 0 else float("nan")
    text = f"{finished + s.skipped}/{s.total} tasks"
    if s.skipped:
        text += f" ({s.skipped} done before)"
    text += f", {s.failed} failed, {rate:.1f} tasks/min"
    if finished < todo and left == left:
        text += f", {int(left // 60)} min {int(left % 60):02d} s left"
    return text
