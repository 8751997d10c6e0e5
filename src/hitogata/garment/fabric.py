"""A stretch fabric's tension against strain: from a tensile test's CSV or a linear modulus.

Tension is force per unit width of fabric (N/m) in the direction the garment
stretches round the body (its course, for a knit worn crosswise); strain is
the engineering strain, 0.2 = 20 % longer than relaxed. Inside, SI only: the
CSV's header says its units and they are converted here, once.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hitogata.errors import HitogataError

STRAIN_COLUMNS = {"strain": 1.0, "strain_%": 0.01, "strain_pct": 0.01, "strain_percent": 0.01}
TENSION_COLUMNS = {"tension_n/m": 1.0, "tension_n/cm": 100.0, "tension_n/mm": 1000.0}


@dataclass(frozen=True)
class Fabric:
    """Tension (N/m) at strain: piecewise linear through the test's points, the last
    segment's slope beyond them; no tension in compression (a fabric buckles)."""

    strains: tuple[float, ...]
    tensions: tuple[float, ...]
    source: str = "linear"

    @classmethod
    def linear(cls, modulus: float) -> Fabric:
        """A fabric whose tension is `modulus` (N/m per unit strain) × strain."""
        if not (math.isfinite(modulus) and modulus > 0):
            raise HitogataError(f"fabric modulus {modulus!r} N/m: allowed a finite number > 0")
        return cls((0.0, 1.0), (0.0, float(modulus)), f"linear {modulus:g} N/m")

    def tension(self, strain: np.ndarray | float) -> np.ndarray:
        """Tension (N/m) at engineering strain (any shape); zero at and below zero strain."""
        e = np.asarray(strain, dtype=float)
        x, y = np.asarray(self.strains), np.asarray(self.tensions)
        t = np.interp(e, x, y)
        slope = (y[-1] - y[-2]) / (x[-1] - x[-2])
        t = np.where(e > x[-1], y[-1] + slope * (e - x[-1]), t)
        return np.where(e <= 0.0, 0.0, np.maximum(t, 0.0))

    @property
    def tested_strain(self) -> float:
        """The largest strain the curve was measured to (beyond it: extrapolated)."""
        return self.strains[-1]


def read_fabric_csv(path: str | Path) -> Fabric:
    """A tensile test's curve: two columns with their units in the header.

    Strain: `strain` (a fraction) or `strain_%`; tension: `tension_N/m`,
    `tension_N/cm` or `tension_N/mm`. Lines starting with '#' are comments.
    Strains strictly increasing from 0 or more, tensions finite and ≥ 0.
    Every mistake is one line naming the file, line and value.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise HitogataError(f"{path}: no such fabric file") from None
    except (UnicodeDecodeError, IsADirectoryError) as err:
        raise HitogataError(f"{path}: not a text CSV file ({err.__class__.__name__})") from None
    rows = [(k, row) for k, row in enumerate(csv.reader(text.splitlines()), start=1)
            if row and any(c.strip() for c in row) and not row[0].lstrip().startswith("#")]
    if not rows:
        raise HitogataError(f"{path}: empty; allowed a header like 'strain_%,tension_N/m' and rows of numbers")
    line, header = rows[0]
    names = [h.strip().lower().replace(" ", "") for h in header]
    strain_col = _column(path, line, names, STRAIN_COLUMNS, "strain")
    tension_col = _column(path, line, names, TENSION_COLUMNS, "tension")
    strains: list[float] = []
    tensions: list[float] = []
    for line, row in rows[1:]:
        if len(row) != len(names):
            raise HitogataError(f"{path}: line {line}: {len(row)} values; allowed {len(names)} (as the header)")
        e = _number(path, line, row[strain_col], header[strain_col]) * STRAIN_COLUMNS[names[strain_col]]
        t = _number(path, line, row[tension_col], header[tension_col]) * TENSION_COLUMNS[names[tension_col]]
        if e < 0 or t < 0:
            bad = row[strain_col] if e < 0 else row[tension_col]
            raise HitogataError(f"{path}: line {line}: value {bad.strip()!r} is negative; allowed ≥ 0")
        if strains and e <= strains[-1]:
            raise HitogataError(f"{path}: line {line}: strain {row[strain_col].strip()!r} is not above the "
                                f"previous line's; allowed strictly increasing strains")
        strains.append(e)
        tensions.append(t)
    if len(strains) < 2:
        raise HitogataError(f"{path}: {len(strains)} data line(s); allowed at least two (strain, tension) points")
    if strains[0] > 0:
        strains.insert(0, 0.0)
        tensions.insert(0, 0.0)
    return Fabric(tuple(strains), tuple(tensions), str(path))


def _column(path: Path, line: int, names: list[str], allowed: dict[str, float], what: str) -> int:
    found = [k for k, n in enumerate(names) if n in allowed]
    if len(found) != 1:
        given = ",".join(names)
        raise HitogataError(f"{path}: line {line}: header {given!r} has {len(found)} {what} columns; "
                            f"allowed exactly one of {', '.join(allowed)} (case-insensitive)")
    return found[0]


def _number(path: Path, line: int, text: str, column: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise HitogataError(f"{path}: line {line}: {column.strip()} value {text.strip()!r}; allowed a finite number")
    return value
