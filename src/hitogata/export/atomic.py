"""Write a file all at once or not at all; several files as one unit.

Exports go to a temporary file in the target's directory and are then renamed
over the target (``os.replace``, atomic on POSIX and Windows), so a crash or
error mid-write never leaves a truncated file that a viewer or batch job
would trip over later. A full disk (or quota, or a file-size limit) is one
line naming the target, with the temporary file removed. Files that belong
together (a body and its sidecar) are renamed into place with Ctrl-C and
SIGTERM held back, so a signal never leaves one without the other.
"""

from __future__ import annotations

import contextlib
import errno
import glob
import os
import secrets
import signal
import threading
from collections.abc import Callable, Iterator, Mapping
from pathlib import Path
from typing import BinaryIO

from hitogata.errors import HitogataError

# errors of the disk, not of the program: one line, not a traceback
DISK_ERRORS = {errno.ENOSPC, errno.EDQUOT, errno.EFBIG, errno.EROFS, errno.EIO}
TEMPORARY_MARK = ".tmp-hitogata"


def temporary_name(path: Path) -> Path:
    """The hidden sibling a file is written to before it is renamed to `path`."""
    return path.with_name(f".{path.name}.{secrets.token_hex(4)}{TEMPORARY_MARK}")


def stale_temporaries(path: Path) -> list[Path]:
    """Temporary siblings of `path` a stopped writer left (removed by the next writer holding the lock)."""
    if not path.parent.is_dir():
        return []
    return [p for p in path.parent.glob(f".{glob.escape(path.name)}.*{TEMPORARY_MARK}") if p.is_file()]


class DiskError(HitogataError):
    """A write the disk refused (full, over quota or a size limit, read-only, failing)."""

    def __init__(self, path: Path, reason: str) -> None:
        super().__init__(f"{path}: cannot write ({reason}); nothing written")
        self.reason = reason


def disk_error(path: Path, err: OSError | DiskError) -> DiskError:
    """One line for a write the disk refused, naming `path`."""
    return DiskError(path, err.reason if isinstance(err, DiskError) else str(err.strerror or err))


def _write_temporary(path: Path, write: Callable[[BinaryIO], object]) -> Path:
    """Call ``write(handle)`` on a new temporary sibling of ``path``, flushed to disk; return its path."""
    if not path.parent.is_dir():
        raise HitogataError(f"{path}: cannot write, directory {path.parent} does not exist")
    temporary = temporary_name(path)
    try:
        # os.open with mode 0o666 lets the umask decide permissions, as open() would.
        fd = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0), 0o666)
        with os.fdopen(fd, "wb") as handle:
            write(handle)
            handle.flush()
            os.fsync(handle.fileno())
    except BaseException as err:
        temporary.unlink(missing_ok=True)
        if isinstance(err, OSError) and err.errno in DISK_ERRORS:
            raise disk_error(path, err) from None
        raise
    return temporary


def write_bytes_atomically(path: str | os.PathLike, data: bytes) -> Path:
    """Write ``data`` to ``path`` via a temporary sibling file; return the path."""
    return write_atomically(path, _writer(data))


def write_atomically(path: str | os.PathLike, write: Callable[[BinaryIO], object]) -> Path:
    """Call ``write(handle)`` on a temporary sibling of ``path``, flushed to disk, then rename it over
    ``path``; return the path. Two writers of one path each rename a whole file: the last one stays."""
    path = Path(path)
    temporary = _write_temporary(path, write)
    try:
        os.replace(temporary, path)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise
    return path


def _writer(data: bytes) -> Callable[[BinaryIO], object]:
    return lambda handle: handle.write(data)


def write_files_together(files: Mapping[Path, bytes]) -> list[Path]:
    """Write several files as one unit: all written to temporaries first, then renamed in with signals held."""
    temporaries: dict[Path, Path] = {}
    try:
        for path, data in files.items():
            temporaries[Path(path)] = _write_temporary(Path(path), _writer(data))
        with signals_held():
            for path, temporary in temporaries.items():
                os.replace(temporary, path)
    except BaseException:
        for temporary in temporaries.values():
            temporary.unlink(missing_ok=True)
        raise
    return list(temporaries)


@contextlib.contextmanager
def signals_held() -> Iterator[None]:
    """Ctrl-C and SIGTERM wait until the block ends (main thread, POSIX; elsewhere nothing is held)."""
    if not hasattr(signal, "pthread_sigmask") or threading.current_thread() is not threading.main_thread():
        yield
        return
    held = {signal.SIGINT, signal.SIGTERM}
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, held)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)
