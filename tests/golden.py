"""Regression figures kept in golden files, one per test module: `tests/golden/<package>/<module>.json`.

A test states what it computed and the tolerance its method allows, `golden.check("female.hip_girth", value,
abs=5e-5)`; the figure it is compared with lives in the module's golden file, not in the test's source. When a
change moves figures on purpose, `make repin TESTS=tests/...` (pytest `--repin`) runs the tests writing what they
compute into their golden files instead, and prints every figure that moved, old and new; `git diff tests/golden`
then shows the same for review, and the change explains each in CHANGELOG.md or its decision.
"""

from __future__ import annotations

import json
import math
import os
import tempfile
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pytest

TESTS = Path(__file__).resolve().parent
FOLDER = TESTS / "golden"
DIGITS = 7  # significant digits kept: far finer than any tolerance a test states


def plain(value: Any) -> Any:
    """A figure as JSON holds it: numbers (numpy's too) rounded to DIGITS significant digits, sequences as lists,
    mappings as dicts with their keys as text; None, booleans and text as they are."""
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, Mapping):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, Sequence) or hasattr(value, "tolist"):
        listed = value.tolist() if hasattr(value, "tolist") else value
        return [plain(v) for v in listed] if isinstance(listed, list) else plain(listed)
    number = float(value)
    if not math.isfinite(number) or number == 0.0:
        return number
    rounded = float(f"{number:.{DIGITS}g}")
    return int(rounded) if isinstance(value, int) else rounded


@dataclass
class GoldenFile:
    """One test module's golden figures: compared against (`check`), or written anew with `--repin`."""

    path: Path
    repin: bool
    figures: dict[str, Any] = field(default_factory=dict)
    moved: dict[str, tuple[Any, Any]] = field(default_factory=dict)  # key → (old, new), when repinning

    def __post_init__(self) -> None:
        if self.path.exists():
            self.figures = json.loads(self.path.read_text())

    @property
    def name(self) -> str:
        """The file's path as a message names it: under the checkout where it is there."""
        return str(self.path.relative_to(TESTS.parent)) if self.path.is_relative_to(TESTS.parent) else str(self.path)

    def check(self, key: str, value: Any, *, rel: float | None = None, abs: float | None = None) -> None:
        """Assert `value` is the golden figure `key` within `rel`/`abs` (as `pytest.approx`); with `--repin`,
        keep `value` as the new golden figure instead."""
        new = plain(value)
        if self.repin:
            old = self.figures.get(key)
            if old != new:
                self.moved[key] = (old, new)
                self.figures[key] = new
            return
        if key not in self.figures:
            pytest.fail(f"{self.name} has no figure {key!r}: make repin TESTS=<this test>")
        assert new == pytest.approx(self.figures[key], rel=rel, abs=abs), (
            f"{key} moved from its golden figure ({self.name}); "
            "if on purpose: make repin TESTS=<this test>")

    def write(self) -> None:
        """The figures, written whole (a temporary file renamed over the old one)."""
        self.path.parent.mkdir(parents=True, exist_ok=True)
        text = json.dumps(dict(sorted(self.figures.items())), indent=1) + "\n"
        handle, temporary = tempfile.mkstemp(dir=self.path.parent, prefix=f".{self.path.name}.")
        with os.fdopen(handle, "w") as out:
            out.write(text)
        os.replace(temporary, self.path)


def golden_path(module_file: str | Path) -> Path:
    """The golden file of a test module: tests/golden/<its path under tests/>.json."""
    return FOLDER / Path(module_file).resolve().relative_to(TESTS).with_suffix(".json")
