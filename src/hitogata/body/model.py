"""A human body: skin surface, rig and skinning weights, from parameters or real units.

`Body.from_measurements` solves MakeHuman's weight and height parameters so that
the body has the asked stature and mass; mass is the skin's enclosed volume
times a whole-body density (`WHOLE_BODY_DENSITY`). Asked for tape measurements
too (chest, waist, ...), it solves the shape by least squares on them
(`hitogata.made_to_measure`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property, partial
from typing import Callable, TypeVar, cast

import numpy as np
import scipy.sparse as sp

from hitogata.body import growth
from hitogata.body.assets import Assets, load_assets, skin_points
from hitogata.body.rig import Rig, place_rig
from hitogata.body.shape import WEIGHT_MAX, BilinearShape, ShapeParameters, blend
from hitogata.errors import HitogataError, excerpt
from hitogata.geometry.mesh_checks import enclosed_volume
from hitogata.units import shown

Prepared = TypeVar("Prepared")

# Whole-body density with the lungs' air inside the skin, kg/m³. Lean tissue and fat
# give 1.03–1.07 g/cm³ once lung gas is removed (Siri 1961, Brožek et al. 1963);
# the skin also encloses the thoracic gas at rest (functional residual capacity,
# about 3 L in an adult: ICRP Publication 89, 2002), which brings a 70 L body to
# about 1.00 g/cm³ — the near-neutral buoyancy of a person in water.
WHOLE_BODY_DENSITY = 1000.0
# Densities a body may have, kg/m³: from fat (0.90 g/cm³) to fat-free tissue (1.10 g/cm³), the two
# compartments of every body composition model (Siri 1961; Brožek et al. 1963); a whole body, with
# its lung gas, lies between them.
DENSITY_RANGE = (900.0, 1100.0)

# Statures a body may be asked for: the MakeHuman height targets reach further
# (1.22–2.45 m) but distort the body far outside the range of adult surveys.
STATURE_RANGE = (1.40, 2.10)

# The heaviest adult a body may be asked for: BMI 50, the top of the plus-size range (WHO class III
# obesity starts at 40); MakeHuman's weight targets are extrapolated beyond their slider to reach it.
ADULT_BMI_MAX = 50.0

SEX_WORDS = {"female": 0.0, "f": 0.0, "woman": 0.0, "male": 1.0, "m": 1.0, "man": 1.0}

AVERAGE = 0.5  # MakeHuman's neutral value of a 0..1 parameter
STATURE_TOLERANCE = 1e-4  # m: the solver stops well inside the 2 mm promise
MASS_TOLERANCE = 2e-4  # relative: well inside the 2 % promise
# solves of the build path at most: the first, and again asking for the volume a heavy body's rest
# contact took (`_touching`), until the mass is within TOUCHING_MASS_TOLERANCE (relative); the skin held
# back moves in steps, so the mass there is not a smooth function of the weight and no closer is sought
MASS_ROUNDS = 4
TOUCHING_MASS_TOLERANCE = 1e-3


def sex_value(sex: float | str) -> float:
    """0 (female) … 1 (male) from a number or a word."""
    if isinstance(sex, str):
        word = sex.strip().lower()
        if word in SEX_WORDS:
            return SEX_WORDS[word]
        try:
            sex = float(word)
        except ValueError:
            raise HitogataError(
                f"sex {sex!r}: allowed 'female', 'male' or a number 0 (female) … 1 (male)"
            ) from None
    if not (isinstance(sex, (int, float)) and 0.0 <= sex <= 1.0):
        raise HitogataError(f"sex {sex!r}: allowed 'female', 'male' or a number 0 (female) … 1 (male)")
    return float(sex)


@dataclass(frozen=True, eq=False)
class Body:
    """One body at rest, in metres, in the frame of DESIGN.md §4 (+Y up, +Z front, +X left).

    `all_vertices` holds the skin vertices followed by the joint cubes and helper
    vertices that place the rig; `vertices` and `faces` are the closed skin surface.
    """

    params: ShapeParameters
    all_vertices: np.ndarray
    density: float = WHOLE_BODY_DENSITY

    def __post_init__(self) -> None:
        check_density(self.density, "density")

    @classmethod
    def from_parameters(cls, params: ShapeParameters, density: float = WHOLE_BODY_DENSITY) -> "Body":
        """The body of MakeHuman shape parameters, standing on the floor; beyond MakeHuman's weight slider
        (weight above 1) with its skin touching where it meets itself, not passing through
        (`hitogata.body.rest_contact`)."""
        assets = load_assets()
        vertices = _stand(assets, blend(assets, params))
        if params.weight > 1.0:
            vertices = _touching(assets, params, vertices)
        return cls(params, vertices, density)

    @classmethod
    def from_measurements(
        cls,
        sex: float | str,
        age: float = 30.0,
        stature: float | None = None,
        mass: float | None = None,
        *,
        muscle: float | None = None,
        proportions: float | None = None,
        density: float = WHOLE_BODY_DENSITY,
        **measurements: float,
    ) -> "Body":
        """The body of a given stature (m) and mass (kg), and of any other measurements `measure`
        reports (m; e.g. chest=0.92, waist=0.74, hip=1.0, inside_leg=0.76).

        Stature and mass alone: MakeHuman's shape parameters solved, stature met within
        0.1 mm and mass within 0.02 % (0.1 % past MakeHuman's weight slider, where the skin meeting
        itself is resolved: `from_parameters`); a missing one is the default body's (its stature,
        its BMI; for a child of 1 up to 18 years the growth references' medians for age and
        sex, and a request outside their 0.1–99.9 percentiles is refused: `hitogata.body.growth`). With `muscle` given, only weight and height are solved; without it,
        the mass follows MakeHuman's build path (see `_build_path`). A target outside
        what the data supports for that sex and age raises a one-line error stating the
        range. With other measurements, `hitogata.made_to_measure.body_to_measure`
        solves the shape (its report of asked against made is there).
        """
        check_density(density, "density")
        if measurements:
            from hitogata.made_to_measure.solve import body_to_measure

            asked = {**measurements, **({} if stature is None else {"stature": stature}),
                     **({} if mass is None else {"mass": mass})}
            return body_to_measure(sex, asked, age=age, muscle=muscle, proportions=proportions,
                                   density=density).body
        params = ShapeParameters(
            sex=sex_value(sex), age=age, muscle=AVERAGE if muscle is None else muscle,
            proportions=AVERAGE if proportions is None else proportions,
        )
        if stature is None or mass is None:
            default_stature, default_mass = default_measurements(sex, age)
            stature = default_stature if stature is None else stature
            mass = default_mass / default_stature**2 * stature**2 if mass is None else mass
        check_stature_mass(params.sex, age, stature, mass)
        sought = mass
        for _ in range(MASS_ROUNDS):  # a heavy body's skin held back where it folds gives up a little volume
            solved = _solve_build(params, stature, sought, density, free_muscle=muscle is None)
            assert isinstance(solved, ShapeParameters)
            body = cls.from_parameters(solved, density)
            if abs(body.mass / mass - 1.0) <= TOUCHING_MASS_TOLERANCE:
                break
            sought *= mass / body.mass
        return body

    @cached_property
    def vertices(self) -> np.ndarray:
        """(V, 3) skin vertices, metres."""
        return skin_points(load_assets(), self.all_vertices)

    @property
    def faces(self) -> np.ndarray:
        """(F, 3) skin triangles, outward-oriented."""
        return load_assets().triangles

    @cached_property
    def rig(self) -> Rig:
        """The MakeHuman default rig placed on this body."""
        return place_rig(load_assets(), self.all_vertices)

    @property
    def skin_weights(self) -> sp.csr_matrix:
        """(V, B) skinning weights of the skin vertices over the rig's bones."""
        return load_assets().skin_weights

    def prepared(self, build: Callable[[Body], Prepared]) -> Prepared:
        """What a layer above finds once per body on its rest shape (its poser, landmarks, zones, fine
        skin ...): `build(self)` on first use, then kept with the body under `build`. The owner of each
        preparation is the module defining `build` (`hitogata.posing.pose.poser_for`, `hitogata.measure.landmarks
        .body_landmarks`, ...); the body holds them without knowing what they are."""
        store: dict[Callable[[Body], object], object] = self.__dict__.setdefault("_prepared", {})
        if build not in store:
            store[build] = build(self)
        return cast("Prepared", store[build])

    @property
    def stature(self) -> float:
        """Floor to the top of the head, m."""
        return float(self.vertices[:, 1].max())

    @cached_property
    def volume(self) -> float:
        """Volume enclosed by the skin, m³."""
        return enclosed_volume(self.vertices, self.faces)

    @property
    def mass(self) -> float:
        """Volume × density, kg."""
        return self.volume * self.density

    @property
    def bmi(self) -> float:
        """Body mass index, kg/m²."""
        return self.mass / self.stature**2


def default_measurements(sex: float | str = "female", age: float = 30.0) -> tuple[float, float]:
    """Stature (m) and mass (kg) of the default body of a sex (0 female … 1 male, or the word) and age.

    Adults: female 165 cm / 62 kg, male 178 cm / 78 kg, near the adult means of ANSUR II
    (Gordon et al. 2014; women 162.9 cm / 68 kg, men 175.6 cm / 85 kg) and of
    civilian surveys, which weigh less than the army sample. Children (1 up to 18
    years): the growth references' medians for age and sex (`hitogata.body.growth`). The
    command line uses the same figures for a stature or mass not given.
    """
    value = sex_value(sex)
    if isinstance(age, (int, float)) and growth.covers(age):
        return growth.median("stature", value, age), growth.median("mass", value, age)
    return 1.65 + 0.13 * value, 62.0 + 16.0 * value


def default_body(sex: float | str = "female") -> Body:
    """The built-in default body: a 30-year-old of average survey stature and mass (`default_measurements`)."""
    stature, mass = default_measurements(sex)
    return Body.from_measurements(sex_value(sex), 30.0, stature, mass)


def check_density(value: object, where: str) -> float:
    """A whole-body density in kg/m³ (`where`: the file and entry it came from), within `DENSITY_RANGE`."""
    low, high = DENSITY_RANGE
    number = isinstance(value, (int, float, np.number)) and not isinstance(value, bool)
    if not (number and math.isfinite(float(value)) and low <= float(value) <= high):  # type: ignore[arg-type]
        raise HitogataError(f"{where} {excerpt(value)} kg/m³: allowed a whole-body density {low:g}–{high:g} kg/m³ "
                            "(fat 900, fat-free tissue 1100)")
    return float(value)  # type: ignore[arg-type]


def check_stature_mass(sex: float | str, age: float, stature: float, mass: float) -> None:
    """A one-line error if a stature (m) and mass (kg) lie outside what hitogata takes for the
    sex and age: a child's growth references' 0.1–99.9 percentiles, an adult's stature range
    and BMI up to `ADULT_BMI_MAX`. The build path may still refuse a shape (`mass_range`)."""
    _check_positive("stature", stature, "m")
    _check_positive("mass", mass, "kg")
    if growth.covers(age):
        growth.check_child(sex_value(sex), age, stature, mass)
    elif not STATURE_RANGE[0] <= stature <= STATURE_RANGE[1]:
        lo, hi = STATURE_RANGE
        raise HitogataError(f"stature {shown(stature * 100)} cm: allowed {lo * 100:.0f}–{hi * 100:.0f} cm")
    elif mass / stature**2 > ADULT_BMI_MAX:
        raise HitogataError(
            f"mass {shown(mass)} kg at stature {shown(stature * 100)} cm: BMI {mass / stature**2:.1f}, "
            f"allowed up to {ADULT_BMI_MAX:g} ({ADULT_BMI_MAX * stature**2:.1f} kg) for adults"
        )


def _check_positive(name: str, value: float, unit: str) -> None:
    if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
        raise HitogataError(f"{name} {value!r} {unit}: allowed a finite positive number")


def _stand(assets: Assets, vertices: np.ndarray) -> np.ndarray:
    """Translate a body so it stands on the floor (y = 0) with the origin between its ankles."""
    skin = vertices[: assets.n_surface]
    rig = place_rig(assets, vertices)
    ankles = rig.heads[[rig.index("foot.L"), rig.index("foot.R")]].mean(axis=0)
    return vertices - np.array([ankles[0], skin[:, 1].min(), ankles[2]])


def _touching(assets: Assets, params: ShapeParameters, vertices: np.ndarray) -> np.ndarray:
    """A body's vertices (all of them, standing) beyond weight 1 with the skin touching where it meets
    itself: reached along weights from 1 (`hitogata.body.rest_contact`)."""
    from hitogata.body.rest_contact import (  # here: bodies within the slider load no contact code
        WEIGHT_STEP,
        contact_groups,
        touching_skin,
    )

    steps = math.ceil((params.weight - 1.0) / WEIGHT_STEP)
    path = [_stand(assets, blend(assets, params.with_(weight=float(w)))) for w in np.linspace(1.0, params.weight,
                                                                                             steps + 1)[:-1]]
    path.append(vertices)
    groups, folding = contact_groups(place_rig(assets, path[0]), assets.skin_weights)
    skin = touching_skin([skin_points(assets, v) for v in path], assets.triangles, groups, folding)
    out = vertices.copy()
    out[: assets.n_surface] = skin[: assets.n_surface]
    return out


def _stature(assets: Assets, vertices: np.ndarray) -> float:
    """Height of the skin (the pocket caps lie inside the head and do not matter)."""
    return float(np.ptp(vertices[: assets.n_surface, 1]))


def _stature_and_volume(assets: Assets, vertices: np.ndarray) -> tuple[float, float]:
    skin = skin_points(assets, vertices)
    return _stature(assets, vertices), enclosed_volume(skin, assets.triangles)


def _build_path(params: ShapeParameters, free_muscle: bool) -> list[BilinearShape]:
    """The segments, lightest first, along which mass is sought.

    With the muscle fixed: weight 0 → 1. Otherwise MakeHuman's own extremes
    extend it: leaner than weight 0 by lowering muscle tone at weight 0, heavier
    than weight 1 by lowering it at weight 1 (MakeHuman's heaviest body is the
    min-muscle, max-weight one), and heavier still by extrapolating that body's
    weight from 1 to `WEIGHT_MAX` (plus sizes, and toddlers heavier than
    MakeHuman's baby at weight 1).
    """
    assets = load_assets()
    middle = BilinearShape(assets, params, axis="weight")
    if not free_muscle:
        return [middle]
    lean = BilinearShape(assets, params.with_(weight=0.0), axis="muscle")
    heavy = BilinearShape(assets, params.with_(weight=1.0), axis="muscle")
    heavier = BilinearShape(assets, params.with_(muscle=0.0), axis="weight")
    return [lean, middle, heavy, heavier]


def mass_range(
    sex: float | str, age: float, stature: float, *, muscle: float | None = None, proportions: float | None = None,
    density: float = WHOLE_BODY_DENSITY,
) -> tuple[float, float]:
    """The lightest and heaviest mass (kg) `Body.from_measurements` builds at a stature (m) for a sex
    and age: the ends of the build path, without the checks against the surveys (adults' BMI 50,
    children's growth references) that narrow it further."""
    params = ShapeParameters(
        sex=sex_value(sex), age=age, muscle=AVERAGE if muscle is None else muscle,
        proportions=AVERAGE if proportions is None else proportions,
    )
    ends = _solve_build(params, stature, None, check_density(density, "density"), free_muscle=muscle is None)
    assert isinstance(ends, tuple)
    return ends


def _solve_build(
    params: ShapeParameters, stature: float, mass: float | None, density: float, free_muscle: bool
) -> ShapeParameters | tuple[float, float]:
    """Shape parameters with the given stature (m) and mass (kg) along the build path; with no mass,
    the lightest and heaviest mass of the path at that stature."""
    from scipy.optimize import brentq  # here: a body rebuilt from its parameters needs no solver

    assets = load_assets()
    segments = _build_path(params, free_muscle)
    # Segment ends, each as (shape, x): muscle runs 0 → average, weight 0 → 1 (→ WEIGHT_MAX).
    ends = {id(segments[0]): (0.0, AVERAGE)} if free_muscle else {}
    if free_muscle:
        ends[id(segments[1])] = (0.0, 1.0)
        ends[id(segments[2])] = (AVERAGE, 0.0)
        ends[id(segments[3])] = (1.0, WEIGHT_MAX)
    else:
        ends[id(segments[0])] = (0.0, 1.0)

    def measure(shape: BilinearShape, x: float, h: float) -> np.ndarray:
        s, v = _stature_and_volume(assets, shape.vertices(x, h))
        return np.array([s, v * density])

    middle = segments[1] if free_muscle else segments[0]
    short, tall = _stature(assets, middle.vertices(0.5, 0.0)), _stature(assets, middle.vertices(0.5, 1.0))
    if not short <= stature <= tall:
        raise HitogataError(
            f"stature {shown(stature * 100)} cm: allowed {short * 100:.1f}–{tall * 100:.1f} cm for this sex and age"
        )
    height = brentq(lambda h: _stature(assets, middle.vertices(0.5, h)) - stature, 0.0, 1.0, xtol=1e-6)
    masses = []
    for shape in segments:
        a, b = ends[id(shape)]
        lo_mass, hi_mass = measure(shape, a, height)[1], measure(shape, b, height)[1]
        masses += [lo_mass, hi_mass]
        if mass is None:
            continue
        if min(lo_mass, hi_mass) <= mass <= max(lo_mass, hi_mass):
            start = np.array([a + (b - a) * (mass - lo_mass) / (hi_mass - lo_mass), height])
            x, h = _newton(partial(measure, shape), np.array([stature, mass]), start, (min(a, b), max(a, b)))
            return shape.at(x, h)
    lightest, heaviest = min(masses), max(masses)
    if mass is None:
        return lightest, heaviest
    raise HitogataError(
        f"mass {shown(mass)} kg at stature {shown(stature * 100)} cm: allowed {lightest:.1f}–{heaviest:.1f} kg "
        f"(BMI {lightest / stature**2:.1f}–{heaviest / stature**2:.1f}) for this sex and age"
    )


def _newton(
    measure: Callable[[float, float], np.ndarray], goal: np.ndarray, x: np.ndarray, x_range: tuple[float, float]
) -> tuple[float, float]:
    """Solve measure(x, h) = goal for x in x_range, h in [0, 1], by Newton's method.

    The Jacobian is a finite difference; the functions are piecewise smooth (kinks
    at 0.5), so each step is clipped to the segment and the iteration is bounded.
    """
    step = 1e-4
    lower, upper = np.array([x_range[0], 0.0]), np.array([x_range[1], 1.0])
    tolerance = np.array([STATURE_TOLERANCE, MASS_TOLERANCE * goal[1]])
    for _ in range(40):
        f = measure(*x)
        r = f - goal
        if np.all(np.abs(r) < tolerance):
            return float(x[0]), float(x[1])
        jac = np.empty((2, 2))
        for k in range(2):
            probe = x.copy()
            probe[k] += step if probe[k] + step <= upper[k] else -step
            jac[:, k] = (measure(*probe) - f) / (probe[k] - x[k])
        x = np.clip(x - np.linalg.solve(jac, r), lower, upper)
    raise HitogataError(f"stature {goal[0] * 100:.1f} cm, mass {goal[1]:.1f} kg: the shape solver did not converge")
