"""A body made to measure: the shape that has the asked tape measurements.

Unknowns: MakeHuman's macro parameters (height, weight, muscle, proportions and,
for a female body, the breast's cup and firmness), each in 0..1, and the 20
`measure-*` modifiers (`hitogata.body.shape.MODIFIER_NAMES`), each in −1..1 — the
ranges MakeHuman's own sliders allow, so the shape stays a body MakeHuman makes.
They are solved by bounded least squares (`scipy.optimize.least_squares`, trust
region reflective) on the measurements `hitogata.measure.measure` reports, taken
by name: residuals in tenths of each measurement's allowance (`allowance`), plus a
weak pull of every unknown towards a plain body, which picks the plainest of the
bodies that fit. The plain body is the one of the asked stature and mass; without
a mass, the build (macro parameters alone) that best fits the measurements.

The Jacobian is not found by differencing the measurements (one full measurement
per unknown, too slow): each tape and surface length is a polyline on the skin
(`measurement_paths`), whose length changes, to first order, by the skin's motion
at its points along the polyline's own directions; heights follow their landmark
and the lowest skin point; the mass follows the enclosed volume's gradient. The
skin's motion per unknown is exact for the modifiers (their targets) and a finite
difference of the blend for the macro parameters. Residuals are always the
measured values, so the Jacobian only steers.

What cannot be met within `allowance` is named: beyond `IMPOSSIBLE` allowances a
one-line error, else a warning with the residuals.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cache

import numpy as np
from scipy.optimize import least_squares

from hitogata.body import growth
from hitogata.body.assets import Assets, load_assets
from hitogata.body.model import (
    AVERAGE,
    STATURE_RANGE,
    WHOLE_BODY_DENSITY,
    Body,
    default_measurements,
    sex_value,
)
from hitogata.body.shape import MODIFIER_NAMES, ShapeParameters, blend
from hitogata.errors import HitogataError
from hitogata.made_to_measure.measurement_rates import measurement_rows
from hitogata.measure.measurements import measure
from hitogata.measure.values import MEASUREMENT_NAMES, aliases
from hitogata.units import shown

# ISO 20685-1 allowed errors, m: girths 9 mm, small girths 4 mm, lengths and heights 5 mm.
GIRTH_ALLOWANCE, SMALL_GIRTH_ALLOWANCE, LENGTH_ALLOWANCE = 0.009, 0.004, 0.005
SMALL_GIRTHS = ("neck", "wrist", "ankle")  # name prefixes of the small girths
MASS_ALLOWANCE = 0.01  # relative: 1 % of the asked mass
# Ratios of asked measurements no adult has, checked before the search: an adult's waist-to-hip ratio lies in
# 0.65–1.15 and waist-to-height ratio in 0.38–0.8 (WHO 2008, "Waist circumference and waist-hip ratio",
# Ashwell & Hsieh 2005); the bounds are wider still, so only a request no person could have is refused
# here, and the search judges the rest (`judge`).
PROPORTIONS = {
    ("waist_girth", "hip_girth"): (0.55, 1.3),
    ("waist_girth", "stature"): (0.3, 1.0),
    ("hip_girth", "stature"): (0.4, 1.1),
    ("chest_girth", "stature"): (0.4, 1.0),
    ("chest_girth", "waist_girth"): (0.65, 2.0),
}
IMPOSSIBLE = 3.0  # allowances: a residual beyond this is an error, between 1 and this a warning
REGULARISATION = 3.0  # residual units per unit of a parameter's distance from the plain body
# Without an asked stature, the default body's is asked softly: a miss of this much (m) counts as
# one residual unit, so the stature moves only where asked lengths need it. With girths alone the
# height parameter stays the default body's too: a girth is met by the build, not by growing taller.
SOFT_STATURE = 0.03
RESIDUAL_UNIT = 0.1  # residuals are counted in tenths of an allowance
MET = 1.0  # residual units: the solve stops once every measurement is this close (a tenth of its allowance)
MAX_EVALUATIONS = 30  # bodies measured at most in the full solve
BUILD_EVALUATIONS = 5  # ... in the first solve, of the build alone
TOLERANCE, BUILD_TOLERANCE = 1e-4, 1e-2  # least_squares' ftol and xtol in each
MACRO_STEP = 1e-3  # finite-difference step of the macro parameters
JACOBIAN_REACH = 0.05  # parameter units: a Jacobian found this close is used again
NEGLIGIBLE = 1e-6  # a modifier value this small is none
MACROS = ("height", "weight", "muscle", "proportions")
BREAST = ("cup", "firmness")


class _Met(Exception):
    """Raised from inside the solver to stop it at x: every measurement is met (`MET`)."""

    def __init__(self, x: np.ndarray) -> None:
        super().__init__()
        self.x = np.array(x)


class MeasurementWarning(UserWarning):
    """Some asked measurements are met only roughly (outside their allowance, within `IMPOSSIBLE`)."""


def allowance(name: str, value: float = 0.0) -> float:
    """The error allowed on a measurement (m; for the mass, kg), ISO 20685-1."""
    if name == "mass":
        return MASS_ALLOWANCE * value
    if name.endswith("_girth"):
        return SMALL_GIRTH_ALLOWANCE if name.startswith(SMALL_GIRTHS) else GIRTH_ALLOWANCE
    return LENGTH_ALLOWANCE


def measurement_name(given: str) -> str:
    """The measurement a name asks for, or a one-line error listing the allowed names."""
    known = aliases()
    if given not in known:
        raise HitogataError(f"measurement {given!r}: allowed {', '.join(MEASUREMENT_NAMES)} (or a girth without "
                            "'_girth', e.g. chest), or mass")
    return known[given]


@dataclass(frozen=True, eq=False)
class MadeToMeasure:
    """A body solved for measurements: the body, what was asked and what it has (m; mass kg)."""

    body: Body
    requested: dict[str, float]
    achieved: dict[str, float]

    @property
    def residuals(self) -> dict[str, float]:
        """Achieved minus requested, per measurement."""
        return {name: self.achieved[name] - value for name, value in self.requested.items()}

    def outside(self, factor: float = 1.0) -> dict[str, float]:
        """The residuals larger than `factor` allowances."""
        return {name: r for name, r in self.residuals.items()
                if abs(r) > factor * allowance(name, self.requested[name])}

    def lines(self) -> list[str]:
        """One line per measurement: requested, achieved, difference (cm; kg for the mass)."""
        out = []
        for name, value in self.requested.items():
            scale, unit = (1.0, "kg") if name == "mass" else (100.0, "cm")
            got, diff = self.achieved[name] * scale, (self.achieved[name] - value) * scale
            flag = "" if abs(diff) <= allowance(name, value) * scale else "  (outside the allowance)"
            out.append(f"{name:<20} asked {value * scale:7.1f} {unit}  made {got:7.1f} {unit}  {diff:+6.2f}{flag}")
        return out


def body_to_measure(
    sex: float | str,
    measurements: Mapping[str, float],
    *,
    age: float = 30.0,
    muscle: float | None = None,
    proportions: float | None = None,
    density: float = WHOLE_BODY_DENSITY,
) -> MadeToMeasure:
    """The body with the asked measurements (metres; `mass` in kg), any subset of those `measure`
    reports (girths also without `_girth`). See the module note."""
    requested = checked_request(measurements, sex, age)
    problem = _Problem(ShapeParameters(sex=sex_value(sex), age=age), requested, density, muscle, proportions)
    x = problem.solve()
    body = problem.body(x)
    made = problem.values_of(body)
    fit = MadeToMeasure(body, requested, {name: made[name] for name in requested})
    judge(fit, problem.limits_reached())
    return fit


def checked_request(measurements: Mapping[str, float], sex: float | str = 0.0, age: float = 30.0) -> dict[str, float]:
    """Asked measurements by their `measure` names in `measure`'s order (the mass last), each a
    positive finite number; stature in range (a child's stature and mass: within the growth
    references' percentiles for the age and sex)."""
    requested: dict[str, float] = {}
    for given, value in measurements.items():
        name = "mass" if given == "mass" else measurement_name(given)
        unit = "kg" if name == "mass" else "m"
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            raise HitogataError(f"{given} {value!r} {unit}: allowed a finite positive number")
        if name in requested:
            raise HitogataError(f"{given}: {name} asked twice")
        requested[name] = float(value)
    if not requested:
        raise HitogataError("no measurement asked: give at least one of " + ", ".join(MEASUREMENT_NAMES))
    order = [*MEASUREMENT_NAMES, "mass"]
    requested = dict(sorted(requested.items(), key=lambda item: order.index(item[0])))
    lo, hi = STATURE_RANGE
    if growth.covers(age):
        for quantity in ("stature", "mass"):
            if quantity in requested:
                growth.check_within(quantity, sex_value(sex), age, requested[quantity])
    elif "stature" in requested and not lo <= requested["stature"] <= hi:
        raise HitogataError(f"stature {shown(requested['stature'] * 100)} cm: allowed {lo * 100:.0f}–{hi * 100:.0f} cm")
    for (a, b), (low, high) in PROPORTIONS.items():  # no person is shaped so: said before the long search
        if a in requested and b in requested and not low <= requested[a] / requested[b] <= high:
            raise HitogataError(f"{_quantity(a, requested[a])} with {_quantity(b, requested[b])}: {a} "
                                f"{requested[a] / requested[b]:.2f} times the {b}; allowed {low:g}–{high:g} "
                                "(beyond every adult's proportions)")
    return requested


def judge(fit: MadeToMeasure, limits: list[str] | tuple[str, ...] = ()) -> None:
    """Raise a one-line error naming what cannot be met together (beyond `IMPOSSIBLE` allowances)
    and the unknowns at their `limits`; warn with the residuals of what is met only roughly."""
    far = fit.outside(IMPOSSIBLE)
    if far:
        asked = ", ".join(_quantity(n, fit.requested[n]) for n in fit.requested)
        nearest = ", ".join(_quantity(n, fit.achieved[n]) for n in far)
        raise HitogataError(f"{asked}: cannot be met together; the nearest body has {nearest}" + _at_limits(limits))
    near = fit.outside()
    if near:
        text = ", ".join(f"{n} {r * (1 if n == 'mass' else 100):+.1f} {'kg' if n == 'mass' else 'cm'}"
                         for n, r in near.items())
        warnings.warn(MeasurementWarning(f"met outside the allowance: {text}"), stacklevel=3)


def _at_limits(limits: list[str] | tuple[str, ...]) -> str:
    """' (at the limit of weight, muscle and 3 of the 20 shape modifiers)': the build parameters by name,
    MakeHuman's `measure-*` modifiers counted (their target names mean nothing to a user)."""
    named = [n for n in limits if n not in MODIFIER_NAMES]
    modifiers = len(limits) - len(named)
    if modifiers:
        named.append(f"{modifiers} of the {len(MODIFIER_NAMES)} shape modifiers")
    if not named:
        return ""
    return f" (at the limit of {', '.join(named[:-1]) + ' and ' + named[-1] if len(named) > 1 else named[0]})"


def _quantity(name: str, value: float) -> str:
    return f"mass {value:.1f} kg" if name == "mass" else f"{name} {value * 100:.1f} cm"


def _start(sex: ShapeParameters, requested: dict[str, float], density: float, muscle: float | None,
           proportions: float | None) -> ShapeParameters:
    """The plain body the solve starts from and is pulled towards: the asked stature and mass, or
    the default body's stature and build (BMI)."""
    stature, mass = default_measurements(sex.sex, sex.age)
    bmi = mass / stature**2
    stature = requested.get("stature", stature)
    mass = requested.get("mass", bmi * stature**2)
    body = Body.from_measurements(sex.sex, sex.age, stature, mass, muscle=muscle,
                                  proportions=AVERAGE if proportions is None else proportions, density=density)
    return body.params


class _Problem:
    """The least-squares problem: unknowns ↔ shape parameters, residuals, Jacobian."""

    def __init__(self, base: ShapeParameters, requested: dict[str, float], density: float,
                 muscle: float | None, proportions: float | None) -> None:
        self.requested = requested
        self.density = density
        start = _start(base, requested, density, muscle, proportions)
        fixed = {"muscle": muscle, "proportions": proportions}
        if not any(not name.endswith("_girth") and name != "mass" for name in requested):
            fixed["height"] = start.height  # girths alone: the default stature's height (SOFT_STATURE)
        self.macros = [m for m in MACROS if fixed.get(m) is None] + (list(BREAST) if start.sex < 1.0 else [])
        self.start = start
        self.prior = np.array([getattr(start, m) for m in self.macros] + [0.0] * len(MODIFIER_NAMES))
        n = len(self.macros)
        self.lower = np.r_[np.zeros(n), -np.ones(len(MODIFIER_NAMES))]
        # weight past MakeHuman's slider only where the plain body of the asked mass already is (plus sizes)
        self.upper = np.r_[[max(1.0, start.weight) if m == "weight" else 1.0 for m in self.macros],
                           np.ones(len(MODIFIER_NAMES))]
        self.pull = np.full(len(self.prior), REGULARISATION)
        self.kinks = np.r_[np.full(n, AVERAGE), np.zeros(len(MODIFIER_NAMES))]  # where the blend's slope changes
        targets = {**requested}
        scale = [RESIDUAL_UNIT * allowance(k, v) for k, v in requested.items()]
        if "stature" not in requested:
            targets["stature"] = default_measurements(base.sex, base.age)[0]
            scale.append(SOFT_STATURE)
        self.names = list(targets)
        self.scale = np.array(scale)
        self.goal = np.array(list(targets.values()))
        self._bodies: dict[bytes, Body] = {}
        self._measured: dict[int, dict[str, float]] = {}
        self._jacobian: tuple[np.ndarray, np.ndarray] | None = None

    # unknowns ↔ bodies
    def params(self, x: np.ndarray) -> ShapeParameters:
        n = len(self.macros)
        macros = {m: float(np.clip(v, 0.0, 1.0)) for m, v in zip(self.macros, x[:n])}
        modifiers = tuple((name, float(np.clip(v, -1.0, 1.0))) for name, v in zip(MODIFIER_NAMES, x[n:])
                          if abs(v) > NEGLIGIBLE)
        return self.start.with_(**macros, modifiers=modifiers)

    def body(self, x: np.ndarray) -> Body:
        key = np.asarray(x, dtype=float).tobytes()
        if key not in self._bodies:
            if len(self._bodies) > 4:
                self._bodies.pop(next(iter(self._bodies)))
            self._bodies[key] = Body.from_parameters(self.params(x), self.density)
        return self._bodies[key]

    def measured(self, body: Body) -> dict[str, float]:
        """All measurements of a body (kept for the bodies kept)."""
        if id(body) not in self._measured:
            self._measured = {k: v for k, v in self._measured.items() if k in map(id, self._bodies.values())}
            self._measured[id(body)] = measure(body).as_dict()
        return self._measured[id(body)]

    def values_of(self, body: Body) -> dict[str, float]:
        values = self.measured(body)
        return {name: body.mass if name == "mass" else values[name] for name in self.names}

    # least squares
    def residuals(self, x: np.ndarray) -> np.ndarray:
        """Measurement residuals (RESIDUAL_UNIT allowances; the soft stature's in SOFT_STATURE) and
        the pull towards the plain body; `_Met` once every asked measurement is within a tenth of
        its allowance."""
        got = np.array(list(self.values_of(self.body(x)).values()))
        if not np.all(np.isfinite(got)):
            lost = [n for n, v in zip(self.names, got) if not math.isfinite(v)]
            raise HitogataError(f"{', '.join(lost)}: not measurable on the body the solver reached")
        misses = (got - self.goal) / self.scale
        if np.all(np.abs(misses[: len(self.requested)]) <= MET):
            raise _Met(x)
        return np.r_[misses, self.pull * (x - self.prior)]

    def jacobian(self, x: np.ndarray) -> np.ndarray:
        """The steering Jacobian; the last one again while x stays within JACOBIAN_REACH of where it
        was found and on the same side of every kink (it only steers, and finding it costs a second
        pass over the tapes)."""
        if self._jacobian is not None:
            last, jacobian = self._jacobian
            same_side = np.array_equal(np.sign(x - self.kinks), np.sign(last - self.kinks))
            if same_side and np.abs(x - last).max() <= JACOBIAN_REACH:
                return jacobian
        body = self.body(x)
        motion = self.skin_motion(x)  # (V, 3, K)
        rows = measurement_rows(body, self.measured(body), self.names, motion, self.density)
        for m in np.flatnonzero(np.isnan(rows[:, 0])):
            rows[m] = self.differenced_row(x, self.names[m])
        jacobian = np.vstack([rows / self.scale[:, None], np.diag(self.pull)])
        self._jacobian = (np.array(x), jacobian)
        return jacobian

    def differenced_row(self, x: np.ndarray, name: str) -> np.ndarray:
        """A measurement's Jacobian row by differences of whole bodies' measurements (one per unknown):
        the slow way, for a measurement that is neither a path on the skin nor a landmark's height."""
        here = self.measured(self.body(x))[name]
        row = np.empty(len(x))
        for k in range(len(x)):
            step = MACRO_STEP * 10 if x[k] + MACRO_STEP * 10 <= self.upper[k] else -MACRO_STEP * 10
            probe = np.array(x)
            probe[k] += step
            row[k] = (measure(Body.from_parameters(self.params(probe), self.density)).get(name) - here) / step
        return row

    def solve(self) -> np.ndarray:
        """Without a mass, the build first (macro parameters alone, modifiers at 0), which then
        becomes the plain body (but for its height) the modifiers are pulled towards; then
        everything. Either stops once all is met."""
        n = len(self.macros)
        x = np.clip(self.prior, self.lower, self.upper)
        try:
            if "mass" not in self.requested:  # (with the mass, the start has the build already)
                x = self._least_squares(x, np.arange(n), BUILD_EVALUATIONS, BUILD_TOLERANCE)
                build = [k for k, name in enumerate(self.macros) if name != "height"]
                self.prior[build] = x[build]
            return self._least_squares(x, np.arange(len(x)), MAX_EVALUATIONS, TOLERANCE)
        except _Met as met:
            return met.x

    def _least_squares(self, x0: np.ndarray, free: np.ndarray, evaluations: int, tolerance: float) -> np.ndarray:
        """x0 with its `free` unknowns solved by least squares within their bounds."""
        def full(sub: np.ndarray) -> np.ndarray:
            x = np.array(x0)
            x[free] = sub
            return x

        result = least_squares(lambda sub: self.residuals(full(sub)), x0[free],
                               jac=lambda sub: self.jacobian(full(sub))[:, free],
                               bounds=(self.lower[free], self.upper[free]), method="trf", ftol=tolerance,
                               xtol=tolerance, gtol=1e-6, max_nfev=evaluations)
        return full(np.asarray(result.x))

    def skin_motion(self, x: np.ndarray) -> np.ndarray:
        """(V, 3, K): how each skin point moves per unit of each unknown at x."""
        assets = load_assets()
        n = len(self.macros)
        params = self.params(x)
        here = blend(assets, params)
        columns = []
        for k, name in enumerate(self.macros):
            step = MACRO_STEP if x[k] + MACRO_STEP <= 1.0 else -MACRO_STEP
            moved = blend(assets, params.with_(**{name: float(x[k] + step)}))
            columns.append((moved - here) / step)
        for name, value in zip(MODIFIER_NAMES, x[n:]):
            columns.append(_modifier_motion(assets, name, float(value)))
        motion = np.stack(columns, axis=-1)  # (N, 3, K)
        caps = _cap_matrix(assets)
        return np.concatenate([motion[: assets.n_surface], np.einsum("cn,nik->cik", caps, motion)])

    def limits_reached(self) -> list[str]:
        """The unknowns at a bound in the last body solved (for the error)."""
        x = np.frombuffer(next(reversed(self._bodies)), dtype=float) if self._bodies else self.prior
        at = (np.isclose(x, self.lower, atol=1e-3) & (self.lower != self.prior)) | np.isclose(x, self.upper, atol=1e-3)
        labels = self.macros + list(MODIFIER_NAMES)
        return [label for label, hit in zip(labels, at) if hit]


def _modifier_motion(assets: Assets, name: str, value: float) -> np.ndarray:
    """(N, 3) motion per unit of a modifier: its incr target above 0, minus its decr target below,
    their mean at 0 (the kink)."""
    incr, decr = _target(assets, f"{name}-incr"), _target(assets, f"{name}-decr")
    if value > 0:
        return incr
    if value < 0:
        return -decr
    return 0.5 * (incr - decr)


@cache
def _target(assets: Assets, name: str) -> np.ndarray:
    column = assets.targets[:, assets.target_names.index(name)]
    return np.asarray(column.todense()).reshape(-1, 3)


@cache
def _cap_matrix(assets: Assets) -> np.ndarray:
    """(C, N) dense: each pocket cap centre as the mean of its loop."""
    caps = np.zeros((len(assets.cap_loops), assets.n_vertices))
    for row, loop in enumerate(assets.cap_loops):
        caps[row, loop] = 1.0 / len(loop)
    return caps
