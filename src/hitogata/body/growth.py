"""Growth references for children: stature and mass for age and sex, by the LMS method.

The shipped table `data/growth/growth_references.csv` holds the LMS parameters of
WHO's child growth standards (2006, 1–5 years), WHO's growth reference (2007,
stature 5–19 years, mass 5–10 years) and CDC's growth charts (2000, mass over 10
years), and WHO's BMI-for-age (2006 and 2007) for sampling populations, as published
(its header names the tables). A value X at z-score z is
M (1 + L S z)^(1/L) (Cole 1990); between tabulated months the parameters are
interpolated linearly. Statures below 24 months are WHO's recumbent lengths less
0.7 cm, WHO's own conversion to standing height; BMI below 24 months is on recumbent
length, as WHO defines it (`mass_of_bmi`).

SI at this module's edge: stature in metres, mass in kilograms, age in years.
"""

from __future__ import annotations

import csv
import math
from functools import cache
from importlib import resources
from statistics import NormalDist
from typing import Any

import numpy as np

from hitogata.errors import HitogataError
from hitogata.units import shown

TABLE = ("growth", "growth_references.csv")
FIRST_YEAR, LAST_YEAR = 1.0, 18.0  # the ages hitogata takes from these references (below its adults' 18)
LENGTH_TO_HEIGHT_CM = 0.7  # WHO 2006: standing height is on average 0.7 cm less than recumbent length
OUTER_PERCENTILES = (0.1, 99.9)  # requests outside these percentiles for age and sex are refused
UNITS = {"stature": 0.01, "mass": 1.0, "bmi": 1.0}  # table unit (cm, kg, kg/m²) → SI
LENGTH_MONTHS = 24.0  # below this age WHO measures recumbent length (and BMI on it)
SEXES = ("female", "male")


@cache
def _tables() -> dict[tuple[str, str], np.ndarray]:
    """(quantity, sex) → rows (age in months, L, M, S), ascending in age, stature as standing height."""
    rows: dict[tuple[str, str], list[list[float]]] = {}
    text = resources.files("hitogata").joinpath("data", *TABLE).read_text()
    for row in csv.DictReader(line for line in text.splitlines() if not line.startswith("#")):
        lms = [float(row["age_months"]), float(row["L"]), float(row["M"]), float(row["S"])]
        if row["quantity"] == "stature" and row["measure"] == "length":  # normal (L = 1): the shift keeps the SD, M S
            months, box_cox, median, cv = lms
            height = median - LENGTH_TO_HEIGHT_CM
            lms = [months, box_cox, height, cv * median / height]
        rows.setdefault((row["quantity"], row["sex"]), []).append(lms)
    return {key: np.array(sorted(value)) for key, value in rows.items()}


def _lms(quantity: str, sex: str, age: float) -> tuple[float, float, float]:
    table = _tables()[quantity, sex]
    months = age * 12.0
    return tuple(float(np.interp(months, table[:, 0], table[:, k])) for k in (1, 2, 3))  # type: ignore[return-value]


def _value_at_z(lms: tuple[float, float, float], z: Any) -> Any:
    """The value at z-score `z` (a number or an array)."""
    box_cox, median, cv = lms
    if abs(box_cox) < 1e-9:
        return median * np.exp(cv * z)
    return median * (1.0 + box_cox * cv * z) ** (1.0 / box_cox)


def _z_of_value(lms: tuple[float, float, float], value: float) -> float:
    box_cox, median, cv = lms
    if abs(box_cox) < 1e-9:
        return math.log(value / median) / cv
    return ((value / median) ** box_cox - 1.0) / (box_cox * cv)


def covers(age: float) -> bool:
    """Whether the references give the stature and mass of this age (1 up to 18 years)."""
    return FIRST_YEAR <= age < LAST_YEAR


def _check_age(age: float) -> None:
    if not covers(age):
        raise HitogataError(f"age {age!r} years: the growth references cover {FIRST_YEAR:g} up to {LAST_YEAR:g} years")


def at_percentile(quantity: str, sex: float, age: float, percentile: float) -> float:
    """The `quantity` ("stature" m, "mass" kg, "bmi" kg/m²) at a percentile (0–100) for age
    (years) and sex (0 female … 1 male; a blend interpolates the two references)."""
    _check_age(age)
    z = NormalDist().inv_cdf(percentile / 100.0)
    values = [_value_at_z(_lms(quantity, s, age), z) for s in SEXES]
    return float((1.0 - sex) * values[0] + sex * values[1]) * UNITS[quantity]


def at_z(quantity: str, sex: str, age: float, z: np.ndarray) -> np.ndarray:
    """The `quantity` (SI) at z-scores `z` (an array) for age (years) and sex ("female", "male")."""
    _check_age(age)
    return _value_at_z(_lms(quantity, sex, age), np.asarray(z, dtype=float)) * UNITS[quantity]


def outer_z() -> tuple[float, float]:
    """The z-scores of the references' outer percentiles (0.1 and 99.9): ±3.09."""
    return NormalDist().inv_cdf(OUTER_PERCENTILES[0] / 100.0), NormalDist().inv_cdf(OUTER_PERCENTILES[1] / 100.0)


def mass_of_bmi(bmi: np.ndarray, stature: np.ndarray, age: float) -> np.ndarray:
    """Mass (kg) of a child of BMI-for-age `bmi` (kg/m²) and standing stature (m): below 24 months
    WHO's BMI is on recumbent length, the stature plus WHO's 0.7 cm."""
    length = stature + (LENGTH_TO_HEIGHT_CM / 100.0 if age * 12.0 < LENGTH_MONTHS else 0.0)
    return np.asarray(bmi) * length**2


def median(quantity: str, sex: float, age: float) -> float:
    """The reference median of `quantity` (stature m, mass kg) for age and sex."""
    return at_percentile(quantity, sex, age, 50.0)


def percentile_of(quantity: str, sex: float, age: float, value: float) -> float:
    """The percentile (0–100) of a value (m or kg) for age and sex (a blend: of the blended z-score)."""
    _check_age(age)
    zs = [_z_of_value(_lms(quantity, s, age), value / UNITS[quantity]) for s in SEXES]
    return 100.0 * NormalDist().cdf((1.0 - sex) * zs[0] + sex * zs[1])


def check_child(sex: float, age: float, stature: float, mass: float) -> None:
    """A one-line error if a child's stature (m) or mass (kg) lies outside the references'
    0.1–99.9 percentiles for the age and sex."""
    check_within("stature", sex, age, stature)
    check_within("mass", sex, age, mass)


def check_within(quantity: str, sex: float, age: float, value: float) -> None:
    """A one-line error if a child's stature (m) or mass (kg) lies outside the references'
    0.1–99.9 percentiles for the age and sex."""
    low, high = OUTER_PERCENTILES
    unit, scale = {"stature": ("cm", 100.0), "mass": ("kg", 1.0)}[quantity]
    lo, hi = (at_percentile(quantity, sex, age, p) for p in (low, high))
    if not lo <= value <= hi:
        raise HitogataError(
            f"{quantity} {shown(value * scale)} {unit} at age {age:g}: allowed {lo * scale:.1f}–{hi * scale:.1f} "
            f"{unit} for this sex and age, the growth references' percentiles {low:g}–{high:g}"
        )


GIRTH_TABLE = ("growth", "nhanes_child_girths.csv")
# The body measurement each NHANES girth is compared with (the table's header says why)
GIRTH_MEASUREMENTS = {"waist": "iliac_crest_waist_girth", "hip": "hip_girth", "upper_arm": "upper_arm_girth"}
P90_Z = NormalDist().inv_cdf(0.9)


@cache
def _girth_rows() -> tuple[dict[str, str], ...]:
    text = resources.files("hitogata").joinpath("data", *GIRTH_TABLE).read_text()
    return tuple(csv.DictReader(line for line in text.splitlines() if not line.startswith("#")))


def girth_z(girth: str, sex: str, age: float, value: float) -> float | None:
    """The z-score of a child's girth (m; "waist", "hip" or "upper_arm") among U.S. children of the
    sex and age group (NHANES 2021–2023), or None where the survey has no figure for that age.

    The survey gives percentiles, not a distribution: the SD below the median is (P50 − P10)/1.2816,
    above it (P90 − P50)/1.2816, so a skewed girth keeps its skew.
    """
    for row in _girth_rows():
        if row["measurement"] == girth and row["sex"] == sex and int(row["age_from"]) <= age < int(row["age_to"]) + 1:
            p10, p50, p90 = (float(row[k]) / 100.0 for k in ("P10", "P50", "P90"))
            spread = (value - p50) / ((p90 - p50) if value > p50 else (p50 - p10))
            return spread * P90_Z
    return None
