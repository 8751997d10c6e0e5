"""The one exception type a user's mistake raises, and the short quote of an input it may carry.

Every message is a single line that names the file or the entry, the value
given and what is allowed, so the CLI can print it as-is instead of a traceback.
Whatever a message quotes from a file or an argument is escaped and cut short
(`excerpt`), and the message as a whole is one line of at most `MAX_MESSAGE`
characters: a file of zeros or a private file named as input is never echoed
in full.
"""

from __future__ import annotations

import math
import sys
import warnings
from typing import TextIO

MAX_MESSAGE = 280  # the message; with "hitogata: error: " a printed line stays within 300 characters
EXCERPT = 40  # characters of an input quoted in a message


def excerpt(value: object, limit: int = EXCERPT) -> str:
    """`value` quoted as Python writes it (escaped, so control characters show), cut to `limit` characters."""
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) >= 10**limit:
        return f"an integer of {len(str(abs(value))) if abs(value) < 10**4000 else 'over 4000'} digits"
    if not isinstance(value, str):
        text = repr(value)
        return text if len(text) <= limit else f"{text[:limit]}… ({len(text):,} characters)"
    if len(value) <= limit:
        return repr(value)
    return repr(value[:limit]) + f"… ({len(value):,} characters)"


def one_line(message: str, limit: int = MAX_MESSAGE) -> str:
    """`message` on one line (control characters escaped) of at most `limit` characters, its middle cut."""
    if len(message) > 4 * limit:  # escape only what can be shown: a message may quote a huge input
        message = message[:2 * limit] + message[-limit:]
    text = "".join(c if c.isprintable() else repr(c)[1:-1] for c in " ".join(message.splitlines()))
    if len(text) <= limit:
        return text
    tail = limit // 3
    return f"{text[:limit - tail - 3]} … {text[-tail:]}"


class HitogataError(ValueError):
    """A user-facing error with a one-line message (escaped, at most `MAX_MESSAGE` characters)."""

    def __init__(self, message: object = "", *rest: object) -> None:
        super().__init__(one_line(str(message)), *rest)


def require(ok: bool, where: str, value: object, allowed: str) -> None:
    """Refuse a value that is not `ok` in one line naming where it was set, the value and what is allowed
    (a settings dataclass's field checked in its `__post_init__`)."""
    if not ok:
        raise HitogataError(f"{where} = {excerpt(value)}: allowed {allowed}")


def require_above(where: str, value: object, least: float = 0.0, what: str = "a number") -> None:
    """Refuse anything but a finite real number above `least` (`what`: how the message names it)."""
    ok = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value) and value > least
    require(ok, where, value, f"{what} above {least:g}")


def require_whole(where: str, value: object, least: int) -> None:
    """Refuse anything but a whole number (an int) of at least `least`."""
    ok = isinstance(value, int) and not isinstance(value, bool) and value >= least
    require(ok, where, value, f"a whole number at least {least}")


def warnings_as_lines(stream: TextIO | None = None) -> None:
    """Show each distinct warning once, as one line `hitogata: warning: …` (no Python source line).

    For the command line and a study's worker processes: the same warning raised for every body of
    a run is said once, and a user sees what happened, not where in the code. Which warnings are
    shown is left to the filters (Python's defaults hide the developers' ones).
    """
    said: set[tuple[type[Warning], str]] = set()

    def show(message: Warning | str, category: type[Warning], filename: str, lineno: int,
             file: TextIO | None = None, line: str | None = None) -> None:
        text = one_line(str(message))
        if (category, text) not in said:
            said.add((category, text))
            print(f"hitogata: warning: {text}", file=file or stream or sys.stderr)

    warnings.showwarning = show
