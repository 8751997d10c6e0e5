"""Children's statures and masses drawn from the growth references for an age and sex.

Stature is drawn from WHO's height-for-age and BMI from WHO's BMI-for-age (`hitogata.body.growth`),
each by its own LMS curve at a standard normal z-score, the two independently; the mass is
the BMI times the stature squared. A draw is kept only where every figure lies within the
references' 0.1–99.9 percentiles for the age (stature, BMI and the resulting mass against
weight-for-age) and the shape's build path reaches the mass at that stature
(`body.mass_range`); the others are drawn again, so the sample is the references' joint
distribution truncated to what hitogata builds, and the share drawn again is reported.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hitogata.body import growth
from hitogata.errors import HitogataError
from hitogata.study.sampling import SEXES

REACH_GRID = 9  # statures at which the build path's mass range is solved, interpolated between
REACH_MARGIN = 0.01  # kept inside the interpolated reach by this share of the mass
MIN_KEPT = 0.05  # below this share of draws kept, the age and sex is refused as unreachable


@dataclass(frozen=True)
class ChildSample:
    """(N, 2) statures (m) and masses (kg) of one sex, and the share of draws kept (0–1)."""

    values: np.ndarray
    kept_share: float


def _reach(sex: str, age: float, low: float, high: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Statures (m) from `low` to `high` and the lightest and heaviest mass the shape builds at each."""
    from hitogata.body.model import mass_range

    statures = np.linspace(low, high, REACH_GRID)
    ends = np.array([mass_range(sex, age, float(s)) for s in statures])
    return statures, ends[:, 0], ends[:, 1]


def sample_children(sex: str, age: float, count: int, seed: int) -> ChildSample:
    """`count` children of one sex and age (years, 1 up to 18), reproducible from the seed.

    The stream is the one the adults' sampling uses for the sex, so the two sexes draw apart.
    """
    stream = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(SEXES.index(sex),)))
    z_low, z_high = growth.outer_z()
    stature_bounds = growth.at_z("stature", sex, age, np.array([z_low, z_high]))
    mass_low, mass_high = growth.at_z("mass", sex, age, np.array([z_low, z_high]))
    statures, lightest, heaviest = _reach(sex, age, *stature_bounds)
    kept: list[np.ndarray] = []
    draws = have = 0
    while have < count:
        batch = max(64, 2 * (count - have))
        z = stream.standard_normal((batch, 2))
        stature = growth.at_z("stature", sex, age, z[:, 0])
        mass = growth.mass_of_bmi(growth.at_z("bmi", sex, age, z[:, 1]), stature, age)
        low = np.interp(stature, statures, lightest) * (1.0 + REACH_MARGIN)
        high = np.interp(stature, statures, heaviest) * (1.0 - REACH_MARGIN)
        ok = ((z >= z_low) & (z <= z_high)).all(axis=1) & (mass >= mass_low) & (mass <= mass_high)
        ok &= (mass >= low) & (mass <= high)
        draws += batch
        good = np.column_stack([stature, mass])[ok]
        kept.append(good)
        have += len(good)
        if draws >= 1000 and have < MIN_KEPT * draws:
            raise HitogataError(
                f"{sex} children aged {age:g}: only {have} of {draws} bodies drawn from the growth references "
                "lie within hitogata's reach; allowed an age where the build path covers the references"
            )
    return ChildSample(np.concatenate(kept)[:count], have / draws)
