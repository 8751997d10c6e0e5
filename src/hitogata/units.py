"""Quantities as a person writes them ("165cm", "1.65m", "58kg", "90deg") → SI numbers.

Used at the user's edge only (CLI, TOML files); everything inside is SI.
"""

from __future__ import annotations

import math
import re

from hitogata.errors import HitogataError

LENGTH_UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001}
MASS_UNITS = {"kg": 1.0, "g": 0.001}
ANGLE_UNITS = {"deg": math.pi / 180.0, "°": math.pi / 180.0, "rad": 1.0}
FRACTION_UNITS = {"": 1.0, "%": 0.01}

_QUANTITY = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([^\d\s]*)\s*$")


def parse_quantity(text: str | float, units: dict[str, float], what: str) -> float:
    """The SI value of `text` (a number followed by one of `units`), or a one-line error.

    A bare number is accepted only where the unit table has the empty unit.
    """
    allowed = ", ".join(f"'{u}'" for u in units if u) or "a plain number"
    example = next((u for u in units if u), "")
    if isinstance(text, (int, float)) and not isinstance(text, bool):
        text = repr(text)
    match = _QUANTITY.match(str(text))
    unit = match.group(2).lower() if match else None
    if match is None or unit not in units:
        raise HitogataError(f"{what} {text!r}: write a number with a unit ({allowed}), e.g. 1.5{example}")
    value = float(match.group(1)) * units[unit]
    if not math.isfinite(value):
        raise HitogataError(f"{what} {text!r}: allowed a finite number")
    return value


def length(text: str | float, what: str = "length") -> float:
    """Metres from '165cm', '1.65m' or '1650mm'."""
    return parse_quantity(text, LENGTH_UNITS, what)


def mass(text: str | float, what: str = "mass") -> float:
    """Kilograms from '58kg' or '58000g'."""
    return parse_quantity(text, MASS_UNITS, what)


def angle(text: str | float, what: str = "angle") -> float:
    """Radians from '90deg', '90°' or '1.57rad'."""
    return parse_quantity(text, ANGLE_UNITS, what)


def shown(value: float, decimals: int = 1) -> str:
    """A value as a message quotes it: fixed decimals for a person's figures, 3 significant digits beyond."""
    return f"{value:.{decimals}f}" if abs(value) < 1e6 else f"{value:.3g}"
