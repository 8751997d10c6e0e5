"""The one configuration reader: TOML files → checked values, one failure style.

Used by the skeleton and muscle lists, the materials, the scenarios and the
viewer's keyframe files. Every failure is a one-line `HitogataError` that
names the file, the entry (and key), the value as written and what is
allowed; a file that cannot be read (missing, a folder, not UTF-8, not TOML)
is one line too, with the line number where the reader stopped.
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Iterable
from pathlib import Path
from typing import Any, NoReturn, TypeVar, overload

from hitogata import units
from hitogata.errors import HitogataError, excerpt

Option = TypeVar("Option", bound=str)  # one of a Literal alias's words (hitogata.options)


MAX_BYTES = 128 * 2**20  # the largest TOML read: a scenario of BVH keyframes takes about 2.5 kB a frame


def read_toml(path: str | Path) -> tuple[str, dict[str, Any]]:
    """(source, document) of a TOML file; anything that keeps it from being read is a one-line error."""
    source = str(path)
    try:
        size = Path(path).stat().st_size
        if size > MAX_BYTES:
            raise HitogataError(f"{source}: {size / 2**20:.0f} MiB; allowed a TOML file of at most "
                                f"{MAX_BYTES / 2**20:.0f} MiB")
        data = Path(path).read_bytes()
    except FileNotFoundError:
        raise HitogataError(f"{source}: no such file") from None
    except IsADirectoryError:
        raise HitogataError(f"{source}: is a folder; allowed a TOML file") from None
    except OSError as err:
        raise HitogataError(f"{source}: cannot be read ({err.strerror or err})") from None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as err:
        line = data[: err.start].count(b"\n") + 1
        raise HitogataError(f"{source}: line {line}: not UTF-8 text (byte {data[err.start]:#04x}); "
                            "allowed a TOML file in UTF-8") from None
    try:
        return source, tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise HitogataError(f"{source}: not valid TOML: {err}") from None  # tomllib names line and column
    except RecursionError:
        raise HitogataError(f"{source}: not valid TOML: arrays or tables nested too deep") from None
    except ValueError as err:  # an integer of more than 4300 digits (Python's limit on reading one)
        raise HitogataError(f"{source}: not a usable TOML file ({excerpt(str(err), 60)})") from None


class Entry:
    """Typed access to one TOML table, with errors that name the file and entry."""

    def __init__(self, source: str, where: str, table: Any, allowed: Iterable[str]):
        self.source, self.where = source, where
        allowed = tuple(sorted(allowed) if isinstance(allowed, (set, frozenset)) else allowed)
        if not isinstance(table, dict):
            self.fail(f"expected a table, got {table!r}")
        unknown = sorted(set(table) - set(allowed), key=str)
        if unknown:
            self.fail(f"unknown key {unknown[0]!r}; allowed: {', '.join(allowed)}")
        self.table = table

    def error(self, message: str, key: str | None = None) -> HitogataError:
        """The one-line error for this entry (or one of its keys)."""
        where = self.where if key is None else f"{self.where}.{key}"
        return HitogataError(f"{self.source}: {where}: {message}")

    def fail(self, message: str, key: str | None = None) -> NoReturn:
        raise self.error(message, key)

    def has(self, key: str) -> bool:
        return key in self.table

    def get(self, key: str, kind: type | tuple[type, ...], default: Any = ...) -> Any:
        if key not in self.table:
            if default is ...:
                self.fail(f"missing key {key!r}")
            return default
        value = self.table[key]
        kinds = kind if isinstance(kind, tuple) else (kind,)
        if float in kinds and isinstance(value, int) and not isinstance(value, bool):
            value = float(value)
        if not isinstance(value, kinds) or isinstance(value, bool) and bool not in kinds:
            self.fail(f"{key} = {value!r}: expected {_kind_name(kind)}")
        return value

    def names(self, key: str, default: Any = ...) -> tuple[str, ...]:
        value = self.get(key, list, default)
        if not all(isinstance(v, str) and v for v in value):
            self.fail(f"{key} = {value!r}: expected a list of names")
        return tuple(value)

    def number(self, key: str, default: Any = ...) -> float:
        value = self.get(key, float, default)
        if not math.isfinite(value):
            self.fail(f"{key} = {value!r}: expected a finite number")
        return value

    @overload
    def quantity(self, key: str, table: dict[str, float], default: float, low: float = ...,
                 high: float = ..., what: str = ...) -> float: ...

    @overload
    def quantity(self, key: str, table: dict[str, float], default: float | None, low: float = ...,
                 high: float = ..., what: str = ...) -> float | None: ...

    def quantity(self, key: str, table: dict[str, float], default: float | None, low: float = -math.inf,
                 high: float = math.inf, what: str = "a number") -> float | None:
        """A number with a unit of `table` (SI), within low..high; `what` says what is allowed."""
        if key not in self.table:
            return default
        value = self.table[key]
        if isinstance(value, bool):
            self.fail(f"{value!r} is not {what}", key)
        try:
            number = units.parse_quantity(value, table, what)
        except HitogataError:
            self.fail(f"{value!r} is not {what}", key)
        if not low <= number <= high:
            self.fail(f"{value!r} is out of range; allowed {what}", key)
        return number

    def choice(self, key: str, options: tuple[Option, ...], default: Option) -> Option:
        value = self.table.get(key, default)
        if value not in options:
            self.fail(f"{value!r}; allowed {', '.join(options)}", key)
        return value

    def integer(self, key: str, default: int, low: int, high: int) -> int:
        value = self.table.get(key, default)
        if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
            self.fail(f"{value!r}; allowed a whole number {low}..{high}", key)
        return value


def _kind_name(kind: type | tuple[type, ...]) -> str:
    kinds = kind if isinstance(kind, tuple) else (kind,)
    words = {str: "a string", float: "a number", list: "a list", dict: "a table", bool: "true or false"}
    return " or ".join(words.get(k, k.__name__) for k in kinds)
