"""A disk cache of built models, as plain arrays, shared by every process of a user.

What takes tens of seconds to build and depends only on its inputs (the whole-body
elastic model of a body) is kept as one numpy `.npz` file per entry, named by a
digest of its key (everything it was built from). An entry holds arrays only
(loaded with `allow_pickle=False`: no code is ever read back), and its key, which
is compared on reading. It is written to a temporary file in the same folder and
renamed into place: a reader never sees half an entry. A process about to build
an entry holds the entry's lock file (`building`) while it builds, so a second
process or Dask worker asking for the same entry waits and then reads it instead
of building it again; a builder that dies releases its lock with its process. An
entry that cannot be read whole (truncated, corrupt, another key) is removed with
a one-line note and built again, never used. Members a reader names `deferred` (a model's
stiffness and mass matrices, which a held posture never uses: four fifths of a whole-body
entry) are read, their checksums checked, only when first asked for, from the file as it
was opened (`Entry`).

Where: `$HITOGATA_CACHE`, else the platform's user cache folder (`~/.cache/hitogata`
on Linux). Size: at most `$HITOGATA_CACHE_LIMIT` megabytes (default `DEFAULT_LIMIT_MB`);
beyond it the entries used longest ago go (reading an entry marks it used).
Off: `HITOGATA_NO_CACHE=1`, or the commands' `--no-cache`.
"""

from __future__ import annotations

import hashlib
import json
import os
import sys
import threading
import time
import zipfile
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

import numpy as np
from filelock import FileLock, Timeout

from hitogata.errors import HitogataError
from hitogata.export.atomic import write_atomically

T = TypeVar("T")

CACHE_ENV = "HITOGATA_CACHE"
NO_CACHE_ENV = "HITOGATA_NO_CACHE"
LIMIT_ENV = "HITOGATA_CACHE_LIMIT"
DEFAULT_LIMIT_MB = 2000.0  # a default body's whole-body elastic model is ~90 MB
STALE_WRITE = 3600.0  # s: a temporary file this old was left by a writer that died
KEY = "__key__"  # the array holding the entry's key (JSON), checked on reading
SUFFIX = ".npz"
LOCK_SUFFIX = ".lock"


def note(text: str) -> None:
    """One line on stderr: the cache never stops the work, it only says what it could not do."""
    print(f"hitogata: note: {text}", file=sys.stderr)


def cache_dir() -> Path:
    """The cache's folder: `$HITOGATA_CACHE`, else the platform's user cache folder for hitogata."""
    where = os.environ.get(CACHE_ENV)
    if where:
        return Path(where).expanduser()
    from platformdirs import user_cache_dir

    return Path(user_cache_dir("hitogata", appauthor=False))


def enabled(cache: bool | None = None) -> bool:
    """Whether to use the cache: `cache` if given, else on unless `HITOGATA_NO_CACHE` is set (not 0/empty)."""
    if cache is not None:
        return cache
    return os.environ.get(NO_CACHE_ENV, "").strip().lower() in ("", "0", "false", "no")


def limit_bytes() -> int:
    """The cache's size limit in bytes (`$HITOGATA_CACHE_LIMIT` megabytes, default DEFAULT_LIMIT_MB)."""
    text = os.environ.get(LIMIT_ENV, "").strip()
    try:
        megabytes = float(text) if text else DEFAULT_LIMIT_MB
    except ValueError:
        megabytes = -1.0
    if not (megabytes >= 0 and np.isfinite(megabytes)):
        raise HitogataError(f"{LIMIT_ENV}={text!r}: allowed a number of megabytes >= 0")
    return int(megabytes * 1e6)


def digest(key: Mapping) -> str:
    """A short hex digest naming the entry of `key` (JSON of plain values, keys sorted)."""
    return hashlib.sha256(_key_text(key).encode()).hexdigest()[:32]


def entry_path(kind: str, key: Mapping) -> Path:
    """Where the entry of `kind` ("dynamics", "elastic-model", ...) and `key` lives."""
    return cache_dir() / f"{kind}-{digest(key)}{SUFFIX}"


class Entry(Mapping[str, np.ndarray]):
    """The arrays of an entry, read whole when it is loaded but for the `deferred` ones: those are read (their
    checksums checked) the first time they are asked for, from the file as it was opened, which is kept open
    until then (a writer renaming a new entry into place, or the cache's pruning, leaves this one's file as
    it was; one thread at a time reads from it). A deferred member found damaged then removes the entry with a
    note and raises `HitogataError`."""

    def __init__(self, path: Path, arrays: dict[str, np.ndarray], stored: Any = None,
                 deferred: frozenset[str] = frozenset()) -> None:
        self.path = path
        self._arrays = arrays
        self._stored = stored  # the open `NpzFile` the deferred members are read from
        self._deferred = set(deferred)
        self._reading = threading.Lock()

    def deferred(self, name: str) -> bool:
        """Whether the member `name` is still to be read."""
        return name in self._deferred

    def __getitem__(self, name: str) -> np.ndarray:
        if name in self._deferred:
            with self._reading:
                if name in self._deferred:  # not read by another thread meanwhile
                    self._read(name)
        return self._arrays[name]

    def _read(self, name: str) -> None:
        try:
            self._arrays[name] = self._stored[name]
        except (OSError, ValueError, EOFError, zipfile.BadZipFile) as err:
            self._close()
            discard(self.path, f"unreadable ({type(err).__name__}: {err})")
            raise HitogataError(f"the model cache entry {self.path} was damaged: removed; run again") from err
        self._deferred.discard(name)
        if not self._deferred:
            self._close()

    def __iter__(self) -> Iterator[str]:
        return iter([*self._arrays, *sorted(self._deferred)])

    def __len__(self) -> int:
        return len(self._arrays) + len(self._deferred)

    def _close(self) -> None:
        if self._stored is not None:
            self._stored.close()
            self._stored = None
        self._deferred.clear()


def load(kind: str, key: Mapping, deferred: Callable[[str], bool] | None = None) -> Entry | None:
    """The arrays of the entry of `key`, or None when there is none; an unreadable one is removed with a note.
    Members whose name `deferred` accepts are read when first asked for (`Entry`)."""
    path = entry_path(kind, key)
    try:
        stored = np.load(path, allow_pickle=False)
    except FileNotFoundError:
        return None
    except (OSError, ValueError, EOFError, zipfile.BadZipFile) as err:
        discard(path, f"unreadable ({type(err).__name__}: {err})")
        return None
    later = frozenset(name for name in stored.files if deferred is not None and name != KEY and deferred(name))
    try:
        arrays = {name: stored[name] for name in stored.files if name not in later}  # read: their CRC checked
    except (OSError, ValueError, EOFError, zipfile.BadZipFile) as err:
        stored.close()
        discard(path, f"unreadable ({type(err).__name__}: {err})")
        return None
    if not later:
        stored.close()
    if KEY not in arrays or str(arrays.pop(KEY)) != _key_text(key):
        stored.close()
        discard(path, "made for another key")
        return None
    try:
        os.utime(path)  # used now: the last to go when the cache is over its limit
    except OSError:
        pass
    return Entry(path, arrays, stored if later else None, later)


@contextmanager
def building(kind: str, key: Mapping) -> Iterator[None]:
    """Held while this process builds the entry of `key`: another process asking for it waits here (on the
    lock's state, however long the build takes) and then finds the entry stored. Where the lock cannot be
    made (a read-only cache folder) the build goes ahead unlocked."""
    path = entry_path(kind, key)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        lock = FileLock(path.with_suffix(LOCK_SUFFIX), timeout=-1)
        lock.acquire()
    except OSError:
        yield
        return
    try:
        yield
    finally:
        lock.release()


def save(kind: str, key: Mapping, arrays: Mapping[str, np.ndarray]) -> Path | None:
    """Store `arrays` as the entry of `key` (written whole, then renamed into place), then keep the cache
    within its limit; returns the entry's path, or None (with a note) when the cache cannot be written."""
    path = entry_path(kind, key)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        named = {KEY: np.array(_key_text(key)), **arrays}
        write_atomically(path, lambda handle: np.savez(handle, **named))  # type: ignore[arg-type]
    except (OSError, HitogataError) as err:
        note(f"the model cache {path.parent} could not be written ({err}); the model is built on every run")
        return None
    prune(keep=path)
    return path


def cached(kind: str, key: Mapping[str, Any], build: Callable[[], T], encode: Callable[[T], dict[str, np.ndarray]],
           decode: Callable[[Mapping[str, np.ndarray]], T], cache: bool | None,
           deferred: Callable[[str], bool] | None = None) -> T:
    """The value of `key`: read from the disk cache, else built and stored (`cache`: see `enabled`).
    One process builds an entry while any other asking for it waits, then reads it (`building`).
    An entry that reads but does not decode is removed with a note and built again. The arrays `deferred`
    names are read when `decode`'s value first uses them (`Entry`)."""
    if not enabled(cache):
        return build()
    stored = read_cached(kind, key, decode, deferred)
    if stored is not None:
        return stored
    with building(kind, key):
        stored = read_cached(kind, key, decode, deferred)  # built by another process while this one waited
        if stored is not None:
            return stored
        value = build()
        save(kind, key, encode(value))
    return value


def read_cached(kind: str, key: Mapping[str, Any], decode: Callable[[Mapping[str, np.ndarray]], T],
                deferred: Callable[[str], bool] | None = None) -> T | None:
    """The entry of `key` decoded, or None when there is none or it does not decode (then removed with a note);
    `deferred`: as `cached`'s."""
    arrays = load(kind, key, deferred)
    if arrays is None:
        return None
    try:
        return decode(arrays)
    except (KeyError, TypeError, ValueError) as err:
        discard(entry_path(kind, key), f"does not decode ({type(err).__name__}: {err})")
        return None


@dataclass(frozen=True)
class CacheInfo:
    """What the cache holds."""

    folder: Path
    entries: int
    size: int  # bytes
    limit: int  # bytes

    def summary(self) -> str:
        return (f"{self.folder}: {self.entries} entries, {self.size / 1e6:.0f} MB "
                f"(limit {self.limit / 1e6:.0f} MB, {LIMIT_ENV}; off: {NO_CACHE_ENV}=1 or --no-cache)")


def _entries(folder: Path) -> list[Path]:
    return sorted(folder.glob(f"*{SUFFIX}")) if folder.is_dir() else []


def info() -> CacheInfo:
    """The cache's folder, its entries and their size."""
    folder = cache_dir()
    entries = _entries(folder)
    return CacheInfo(folder, len(entries), sum(_size(p) for p in entries), limit_bytes())


def clear() -> tuple[int, int]:
    """Remove every entry (and any temporary file a writer left, and the lock files of entries no process is
    building); returns (entries, bytes) removed."""
    folder = cache_dir()
    removed, size = 0, 0
    for path in _entries(folder):
        entry_size = _size(path)
        if _remove(path):
            size += entry_size
            removed += 1
    for path in folder.glob(".*.tmp") if folder.is_dir() else ():
        path.unlink(missing_ok=True)
    for path in folder.glob(f"*{LOCK_SUFFIX}") if folder.is_dir() else ():
        try:
            with FileLock(path, blocking=False):  # an entry being built now keeps its lock
                path.unlink(missing_ok=True)
        except Timeout:
            pass
    return removed, size


def prune(keep: Path | None = None) -> None:
    """Remove the entries used longest ago until the cache is within its limit (never `keep`), and the
    temporary files of writers that died."""
    folder = cache_dir()
    now = time.time()
    for path in folder.glob(".*.tmp"):
        if now - _mtime(path) > STALE_WRITE:
            path.unlink(missing_ok=True)
    entries = sorted(_entries(folder), key=_mtime)
    total, limit = sum(_size(p) for p in entries), limit_bytes()
    for path in entries:
        if total <= limit:
            break
        if path != keep:
            entry_size = _size(path)
            if _remove(path):
                total -= entry_size


def discard(path: Path, why: str) -> None:
    """Remove an entry that cannot be used, with a one-line note saying why."""
    note(f"cache entry {path.name} {why}: removed, built again")
    _remove(path)


def _remove(path: Path) -> bool:
    """Remove an entry's file; False where it cannot be (Windows: a process still reading its deferred
    members holds it open), then it stays for the next prune or clear."""
    try:
        path.unlink(missing_ok=True)
    except OSError:
        return False
    return True


def _key_text(key: Mapping) -> str:
    return json.dumps(key, sort_keys=True, separators=(",", ":"))


def _size(path: Path) -> int:
    try:
        return path.stat().st_size
    except OSError:
        return 0


def _mtime(path: Path) -> float:
    try:
        return path.stat().st_mtime
    except OSError:
        return 0.0
