"""Write a file all at once or not at all.

Exports go to a temporary file in the target's directory and are then renamed
over the target (``os.replace``, atomic on POSIX and Windows), so a crash or
error mid-write never leaves a truncated file that a viewer or batch job
would trip over later.
"""

from __future__ import annotations

import os
import secrets
from collections.abc import Callable
from pathlib import Path
from typing import BinaryIO

from hitogata.errors import HitogataError


def write_bytes_atomically(path: str | os.PathLike, data: bytes) -> Path:
    """Write ``data`` to ``path`` via a temporary sibling file; return the path."""
    return write_atomically(path, lambda handle: handle.write(data))


def write_atomically(path: str | os.PathLike, write: Callable[[BinaryIO], object]) -> Path:
    """Call ``write(handle)`` on a temporary sibling of ``path``, flushed to disk, then rename it over
    ``path``; return the path. Two writers of one path each rename a whole file: the last one stays."""
    path = Path(path)
    if not path.parent.is_dir():
        raise HitogataError(f"{path}: cannot write, directory {path.parent} does not exist")
    temporary = path.with_name(f".{path.name}.{secrets.token_hex(4)}.tmp")
    try:
        # os.open with mode 0o666 lets the umask decide permissions, as open() would.
        fd = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0), 0o666)
        with os.fdopen(fd, "wb") as handle:
            write(handle)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(temporary, path)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise
    return path
