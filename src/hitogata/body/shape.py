"""Shape parameters → MakeHuman macro-target weights → vertex positions.

MakeHuman's combination rule (documented in ../shared/reference/makehuman-assets.md):
a target's weight is the product of the factors its file name names. Every
factor is piecewise linear in its parameter, so for fixed sex, age, muscle and
proportions the vertices are bilinear in (weight, height) — or in (muscle,
height) for fixed weight — inside each quadrant split at 0.5: `BilinearShape`
uses that to evaluate bodies cheaply while solving for stature and mass.

Modifiers follow MakeHuman's modifier convention: `measure-bust-circ` at value
v in −1..1 weighs its `-decr` target by max(0, −v) and its `-incr` target by
max(0, v), whatever the macro parameters; vertices are linear in v on each side of 0.
"""

from __future__ import annotations

import math
from collections import OrderedDict
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, replace
from functools import cache
from typing import Any

import numpy as np

from hitogata.body.assets import Assets, load_child_targets
from hitogata.errors import HitogataError
from hitogata.options import RACES

# MakeHuman's age axis: "baby" is 1 year, "child" 10 years (age value 0.1875 with
# MakeHuman 1.1's 1–25 years over 0–0.5), "young" 25 years (0.5), "old" 90 years (1.0).
# hitogata reaches the young shape at 18 rather than 25, so that its adults (18 and
# over) keep the adult shape the survey-calibrated solver was built on: baby → child
# from 1 to 10 years, child → young from 10 to 18, young → old from 25 to 90.
BABY_YEARS = 1.0
CHILD_YEARS = 10.0
ADULT_YEARS = 18.0
YOUNG_YEARS = 25.0
OLD_YEARS = 90.0
MIN_AGE_YEARS = BABY_YEARS

# Weight beyond MakeHuman's slider (1): its max-weight targets extrapolated linearly, as far
# as the skin stays closed, outward and free of new self-intersections (docs/decisions:
# children and plus sizes). Reaches BMI 50 for adults of 155–190 cm and the 99.9th
# percentile of mass for age of the growth references.
WEIGHT_MAX = 2.0

# MakeHuman's measure modifiers (each a decr and an incr target in the data file), value −1..1.
MODIFIER_NAMES = (
    "measure-neck-circ", "measure-neck-height", "measure-upperarm-circ", "measure-upperarm-length",
    "measure-lowerarm-length", "measure-wrist-circ", "measure-frontchest-dist", "measure-bust-circ",
    "measure-underbust-circ", "measure-waist-circ", "measure-napetowaist-dist", "measure-waisttohip-dist",
    "measure-shoulder-dist", "measure-hips-circ", "measure-upperleg-height", "measure-lowerleg-height",
    "measure-thigh-circ", "measure-knee-circ", "measure-calf-circ", "measure-ankle-circ",
)
Modifiers = tuple[tuple[str, float], ...]


@dataclass(frozen=True)
class ShapeParameters:
    """MakeHuman macro parameters of a body.

    sex: 0 = female … 1 = male (blends allowed); age in years (1–90; below 18 the
    baby and child targets of `hitogata.body.assets.load_child_targets` blend in);
    muscle, weight, height, proportions, cup, firmness in 0..1 with 0.5 = average (weight up
    to `WEIGHT_MAX`: beyond 1 MakeHuman's max-weight targets are extrapolated linearly);
    race: weights of (african, asian, caucasian), normalised to sum 1;
    modifiers: (name, value) pairs of MODIFIER_NAMES, value −1..1 (0 = none), given as
    pairs or a mapping, kept sorted by name without the zero ones.
    """

    sex: float = 0.0
    age: float = 30.0
    muscle: float = 0.5
    weight: float = 0.5
    height: float = 0.5
    proportions: float = 0.5
    cup: float = 0.5
    firmness: float = 0.5
    race: tuple[float, float, float] = field(default=(1 / 3, 1 / 3, 1 / 3))
    modifiers: Modifiers = ()

    def __post_init__(self) -> None:
        unit = ("sex", "muscle", "weight", "height", "proportions", "cup", "firmness")
        for name in unit:
            value = getattr(self, name)
            top = WEIGHT_MAX if name == "weight" else 1.0
            if not (isinstance(value, (int, float)) and 0.0 <= value <= top):
                raise HitogataError(f"shape parameter {name}={value!r}: allowed 0..{top:g}")
        if not (isinstance(self.age, (int, float)) and MIN_AGE_YEARS <= self.age <= OLD_YEARS):
            raise HitogataError(
                f"age {self.age!r} years: allowed {MIN_AGE_YEARS:g}..{OLD_YEARS:g}"
            )
        race = np.asarray(self.race, dtype=float)
        if race.shape != (3,) or not np.all(np.isfinite(race)) or race.min() < 0 or race.sum() <= 0:
            raise HitogataError(f"race {self.race!r}: allowed three non-negative weights, not all zero")
        object.__setattr__(self, "modifiers", _checked_modifiers(self.modifiers))

    def with_(self, **changes: Any) -> "ShapeParameters":
        """A copy with some parameters changed."""
        return replace(self, **changes)


def _checked_modifiers(given: Mapping[str, float] | Iterable[Iterable[Any]]) -> Modifiers:
    """Modifier (name, value) pairs, sorted and without zeros; a one-line error for a bad one."""
    try:
        pairs = list(given.items()) if isinstance(given, Mapping) else [tuple(pair) for pair in given]
    except TypeError:
        raise HitogataError(f"modifiers {given!r}: allowed (name, value) pairs") from None
    out = {}
    for pair in pairs:
        if len(pair) != 2 or pair[0] not in MODIFIER_NAMES:
            raise HitogataError(f"modifier {pair!r}: allowed (name, value) with a name of {', '.join(MODIFIER_NAMES)}")
        name, value = pair
        if not (isinstance(value, (int, float)) and -1.0 <= value <= 1.0):
            raise HitogataError(f"modifier {name}={value!r}: allowed −1..1")
        if value:
            out[name] = float(value)
    return tuple(sorted(out.items()))


def _levels(value: float) -> dict[str, float]:
    """min/average/max factors of a 0..1 parameter whose neutral value is 0.5."""
    low = max(0.0, 1.0 - 2.0 * value)
    high = max(0.0, 2.0 * value - 1.0)
    return {"min": low, "average": 1.0 - low - high, "max": high}


def age_factors(years: float) -> dict[str, float]:
    """Weights of MakeHuman's baby, child, young and old targets at an age (module note on ages)."""
    ramps = ((BABY_YEARS, "baby"), (CHILD_YEARS, "child"), (ADULT_YEARS, "young"), (YOUNG_YEARS, "young"),
             (OLD_YEARS, "old"))
    out = {"baby": 0.0, "child": 0.0, "young": 0.0, "old": 0.0}
    for (a0, w0), (a1, w1) in zip(ramps[:-1], ramps[1:]):
        if a0 <= years <= a1:
            t = (years - a0) / (a1 - a0)
            out[w0] += 1.0 - t
            out[w1] += t
            return out
    out["baby" if years < BABY_YEARS else "old"] = 1.0
    return out


def factors(params: ShapeParameters) -> dict[str, float]:
    """The factor each word of a target's file name stands for."""
    race = np.asarray(params.race, dtype=float) / float(np.sum(params.race))
    out = {"female": 1.0 - params.sex, "male": params.sex, **age_factors(params.age)}
    out.update(zip(RACES, race.tolist()))
    for word in ("muscle", "weight", "height", "cup", "firmness"):
        for level, f in _levels(getattr(params, word)).items():
            out[level + word] = f
    levels = _levels(params.proportions)
    out["uncommonproportions"], out["idealproportions"] = levels["min"], levels["max"]
    out["universal"] = 1.0
    return out


@cache
def _name_words(names: tuple[str, ...]) -> tuple[tuple[str, ...], ...]:
    return tuple(tuple(name.split("-")) for name in names)


def modifier_weights(params: ShapeParameters) -> dict[str, float]:
    """Weight of each decr/incr modifier target the parameters use (module note)."""
    out = {}
    for name, value in params.modifiers:
        out[f"{name}-{'incr' if value > 0 else 'decr'}"] = abs(value)
    return out


def target_weights(names: tuple[str, ...], params: ShapeParameters) -> np.ndarray:
    """Weight of each named target: the product of the factors in its name (macro targets),
    or its modifier's weight (`modifier_weights`)."""
    f = factors(params)
    modifiers = modifier_weights(params)
    return np.array([
        modifiers.get(name, 0.0) if name.startswith("measure-") else math.prod(f[word] for word in words)
        for name, words in zip(names, _name_words(names))
    ])


def blend(assets: Assets, params: ShapeParameters) -> np.ndarray:
    """All vertices (N, 3) of the body the parameters describe, in metres."""
    offsets = _blended(assets.target_names, assets.targets, params)
    if params.age < ADULT_YEARS:
        offsets = offsets + _blended(*load_child_targets(), params)
    return assets.base_vertices + offsets.reshape(-1, 3)


def _blended(names: tuple[str, ...], targets: Any, params: ShapeParameters) -> np.ndarray:
    weights = target_weights(names, params)
    used = np.flatnonzero(weights)
    return np.asarray(_used_columns(targets, used) @ weights[used])


USED_KEPT = 4  # the last few target sets' columns kept (a fit's or a solve's nearby shapes use the same)
_used: OrderedDict[tuple[int, bytes], tuple[Any, Any]] = OrderedDict()


def _used_columns(targets: Any, used: np.ndarray) -> Any:
    """`targets[:, used]`, kept for the last `USED_KEPT` sets: nearby shapes (a solver's probes) weight the
    same targets, and taking the columns costs more than the product."""
    key = (id(targets), used.tobytes())
    found = _used.get(key)
    if found is None or found[0] is not targets:
        found = _used[key] = (targets, targets[:, used])  # the matrix kept with them: its id stays its own
        while len(_used) > USED_KEPT:
            _used.popitem(last=False)
    _used.move_to_end(key)
    return found[1]


class BilinearShape:
    """Vertices as an exact bilinear function of (`axis`, height), the other parameters fixed.

    `axis` is "weight" or "muscle". Each quadrant of the (axis, height) square split
    at 0.5 is evaluated at its four corners once; inside it, bilinear interpolation
    of the corners is exact because every target weight is linear there.
    """

    def __init__(self, assets: Assets, params: ShapeParameters, axis: str = "weight") -> None:
        self._assets = assets
        self._params = params
        self._axis = axis
        self._corners: dict[tuple[int, int], tuple[np.ndarray, ...]] = {}

    @property
    def params(self) -> ShapeParameters:
        return self._params

    def at(self, x: float, height: float) -> ShapeParameters:
        """The shape parameters of the point (x, height)."""
        return self._params.with_(**{self._axis: x, "height": height})

    def vertices(self, x: float, height: float) -> np.ndarray:
        qx, qh = int(x > 0.5), int(height > 0.5)
        if (qx, qh) not in self._corners:
            x0, h0 = 0.5 * qx, 0.5 * qh
            self._corners[qx, qh] = tuple(
                blend(self._assets, self.at(x0 + dx, h0 + dh))
                for dx, dh in ((0, 0), (0.5, 0), (0, 0.5), (0.5, 0.5))
            )
        v00, v10, v01, v11 = self._corners[qx, qh]
        s, t = 2.0 * x - qx, 2.0 * height - qh
        return (1 - s) * (1 - t) * v00 + s * (1 - t) * v10 + (1 - s) * t * v01 + s * t * v11
