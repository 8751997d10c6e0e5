"""Children's ranges of motion: a placed skeleton's limits widened where children's measured ranges
exceed adults'.

The figures and their sources are in `data/child_joint_ranges.toml` (Soucie et al. 2011, normal
passive range of motion by age group and sex). For a body inside the file's age group each listed
DOF's limit becomes the child's (the adult limit moved by the child-minus-adult difference, or the
child's mean itself), never narrower than the adult's; outside it the skeleton is returned as it is,
so an adult's limits are the skeleton list's to the bit.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from functools import cache
from importlib import resources
from pathlib import Path

from hitogata.config import Entry, read_toml
from hitogata.skeleton.placement import Skeleton

SHIPPED_FILE = "child_joint_ranges.toml"
SIDES = ("l", "r")


@dataclass(frozen=True)
class ChildRange:
    """One DOF's range end for children, degrees as in the file (magnitudes for a `min` bound)."""

    part: str
    dof: str
    bound: str  # "max" | "min"
    female: float
    male: float
    adult_female: float | None
    adult_male: float | None
    share: float

    def change(self, sex: float, adult_limit: float) -> float:
        """The child's clinical limit (radians) for a sex 0 (female) … 1 (male), given the adult's."""
        child = (1.0 - sex) * self.female + sex * self.male
        sign = 1.0 if self.bound == "max" else -1.0
        if self.adult_female is None or self.adult_male is None:
            wanted = sign * math.radians(child)
        else:
            adult = (1.0 - sex) * self.adult_female + sex * self.adult_male
            wanted = adult_limit + sign * self.share * math.radians(child - adult)
        return max(adult_limit, wanted) if self.bound == "max" else min(adult_limit, wanted)


@dataclass(frozen=True)
class ChildRanges:
    """The ages the ranges apply to (from_age ≤ age < below_age) and the ranges."""

    from_age: float
    below_age: float
    ranges: tuple[ChildRange, ...]

    def applies(self, age: float) -> bool:
        return self.from_age <= age < self.below_age


def shipped_path() -> Path:
    return Path(str(resources.files("hitogata").joinpath("data", SHIPPED_FILE)))


@cache
def load_child_ranges(path: str | Path | None = None) -> ChildRanges:
    """Read and check a children's ranges file (the shipped one when `path` is None)."""
    source, doc = read_toml(shipped_path() if path is None else path)
    top = Entry(source, "top level", doc, ("group", "range"))
    group = Entry(source, "group", top.get("group", dict), ("from_age", "below_age"))
    from_age, below_age = group.number("from_age"), group.number("below_age")
    if not from_age < below_age:
        group.fail(f"from_age {from_age:g} >= below_age {below_age:g}; allowed from_age < below_age")
    ranges = []
    for k, raw in enumerate(top.get("range", list)):
        entry = Entry(source, f"range {k}", raw, ("part", "dof", "bound", "female", "male",
                                                   "adult_female", "adult_male", "share"))
        bound = entry.choice("bound", ("max", "min"), "max")
        adults = tuple(entry.number(key) if entry.has(key) else None for key in ("adult_female", "adult_male"))
        if (adults[0] is None) != (adults[1] is None):
            entry.fail("give both adult_female and adult_male, or neither")
        share = entry.number("share", 1.0)
        if not 0.0 < share <= 1.0:
            entry.fail(f"share {share:g}; allowed 0 < share <= 1", "share")
        ranges.append(ChildRange(entry.get("part", str), entry.get("dof", str), bound, entry.number("female"),
                                 entry.number("male"), adults[0], adults[1], share))
    return ChildRanges(from_age, below_age, tuple(ranges))


def with_age_ranges(skeleton: Skeleton, sex: float, age: float) -> Skeleton:
    """The skeleton with children's ranges for a body of this sex (0 … 1) and age (years); the same
    skeleton when the age is outside the children's group. DOFs the skeleton lacks are left out."""
    table = load_child_ranges()
    if not table.applies(age):
        return skeleton
    lower, upper = skeleton.lower.copy(), skeleton.upper.copy()
    names = {name: k for k, name in enumerate(skeleton.dof_names)}
    for r in table.ranges:
        for side in SIDES:
            d = names.get(f"{r.part}_{side}.{r.dof}")
            if d is None:
                continue
            limits = upper if r.bound == "max" else lower
            rest = skeleton.rest[d]
            limits[d] = r.change(sex, float(limits[d] + rest)) - rest
    return dataclasses.replace(skeleton, lower=lower, upper=upper)

