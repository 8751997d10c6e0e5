"""The tissue constants identified from measured people: bounded least squares on validation rows.

The paper leaves the physical constants open; this answers it with a method.
The unknowns are each soft region's Young's modulus (skin-and-fat, muscle,
viscera), the soft tissue's Poisson's ratio, each region's density and the
Rayleigh damping (α, β), each bounded by the range the literature gives
(`PARAMETERS`). The rows that pin them: in-vivo stiffness (the region's
modulus itself), soft-tissue resonance frequencies and damping (the elastic
whole body's region resonance, `elastic.resonance`). Residuals are in units
of each row's SD; `scipy.optimize.least_squares` (trust region reflective,
bounds) minimises their squares.

A resonance needs the modes at every trial: the whole body's 60 lowest modes
at a reference point span the trial's (Rayleigh–Ritz, with the stiffness and
mass changes of each region projected onto them: exact at the reference);
each outer round re-solves the full model at the last fit until the
constants move by less than `TOLERANCE`, so the answer is the full model's.
The report gives the fit, each row's residual, which constant each row pins
(sensitivity: SD per +10 % of the constant), 95 % intervals from the
Jacobian, constants the rows cannot pin (left at their start), and the error
of each row predicted by a fit without its source (leave one source out).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np
import scipy.linalg
import scipy.sparse as sp
from scipy.optimize import least_squares

from hitogata.body.model import Body
from hitogata.elastic.materials import Materials
from hitogata.errors import HitogataError
from hitogata.fem import Material, mass_matrix, sparsity, stiffness_matrix
from hitogata.elastic.resonance import weighted_response
from hitogata.validation.answers import (
    MODEL_ELEMENT_SIZE,
    RESONANCE_MODES,
    BodyCache,
    sexes,
    stiffness_region,
    stiffness_value,
    unresolved_region,
)
from hitogata.validation.dataset import Dataset, Row

IDENTIFIABLE = ("stiffness", "frequency", "damping")
SOFT = ("viscera", "muscle", "skin")
TOLERANCE = 0.002  # outer rounds stop when no constant moves by more than 0.2 % (of its range for linear ones)
MAX_ROUNDS = 5
PINNED = 0.05  # a constant that moves no row by this many SD per +10 % is not pinned by the rows
TINY = 1e-9  # a region's own matrices: the other regions' tissue at this fraction (the checks refuse 0)


@dataclass(frozen=True)
class Parameter:
    """One constant: its name, the literature's bounds (SI), fitted on a log scale or not, and why the bounds."""

    name: str
    low: float
    high: float
    log: bool
    bounds_from: str


PARAMETERS = (
    Parameter("skin.youngs_modulus", 1e3, 30e3, True,
              "subcutaneous fat 1-10 kPa at small strain (Samani et al. 2007; Alkhouli et al. 2013), the dermis "
              "stiffer: a skin-and-fat layer up to 30 kPa"),
    Parameter("muscle.youngs_modulus", 5e3, 100e3, True,
              "passive muscle: shear modulus 2-15 kPa by elastography (E = 3 mu: 6-45 kPa); indentation and "
              "resting tone up to ~100 kPa"),
    Parameter("viscera.youngs_modulus", 1e3, 20e3, True, "liver, spleen, intestines by MR elastography: E 2-20 kPa"),
    Parameter("soft.poissons_ratio", 0.45, 0.499, False, "soft tissue is nearly incompressible (0.45-0.5)"),
    Parameter("skin.density", 900.0, 1000.0, False, "fat 900, dermis 1,100 kg/m3 (ICRP 89)"),
    Parameter("muscle.density", 1040.0, 1090.0, False, "skeletal muscle 1,040-1,090 kg/m3 (Mendez & Keys 1960)"),
    Parameter("viscera.density", 800.0, 1060.0, False, "soft organs 1,030-1,060, the lungs' air lowers the cavity's"),
    Parameter("damping.alpha", 0.0, 60.0, False, "mass-proportional damping 0-60 1/s (zeta 0.5 at 10 Hz)"),
    Parameter("damping.beta", 0.0, 0.02, False, "stiffness-proportional damping 0-0.02 s (zeta 0.6 at 10 Hz)"),
)
NAMES = tuple(p.name for p in PARAMETERS)


def constants_of(materials: Materials) -> np.ndarray:
    """The parameter vector (SI) of a materials table (its damping, else the model's default)."""
    from hitogata.elastic.model import DEFAULT_DAMPING, _rayleigh

    r = materials.regions
    alpha, beta = materials.rayleigh if materials.rayleigh is not None else _rayleigh(DEFAULT_DAMPING, None)
    return np.array([r["skin"].E, r["muscle"].E, r["viscera"].E, r["muscle"].nu, r["skin"].rho, r["muscle"].rho,
                     r["viscera"].rho, alpha, beta])


def materials_of(theta: np.ndarray, base: Materials, source: str = "identified") -> Materials:
    """A materials table with the constants `theta` (the bone and viscera's Poisson's ratio as in `base`)."""
    values = dict(zip(NAMES, theta))
    regions = dict(base.regions)
    for name in SOFT:
        old = regions[name]
        nu = values["soft.poissons_ratio"] if name != "viscera" else old.nu
        regions[name] = Material(E=float(values[f"{name}.youngs_modulus"]), nu=float(nu),
                                 rho=float(values[f"{name}.density"]), name=name)
    return Materials(source, MappingProxyType(regions), (float(values["damping.alpha"]), float(values["damping.beta"])))


def _to_unit(theta: np.ndarray) -> np.ndarray:
    """Constants → the fit's coordinates: log for moduli, fraction of the range for the others."""
    out = np.empty(len(theta))
    for k, p in enumerate(PARAMETERS):
        out[k] = math.log(theta[k]) if p.log else (theta[k] - p.low) / (p.high - p.low)
    return out


def _from_unit(x: np.ndarray) -> np.ndarray:
    out = np.empty(len(x))
    for k, p in enumerate(PARAMETERS):
        out[k] = math.exp(x[k]) if p.log else p.low + x[k] * (p.high - p.low)
    return out


def _unit_bounds() -> tuple[np.ndarray, np.ndarray]:
    lo = np.array([math.log(p.low) if p.log else 0.0 for p in PARAMETERS])
    hi = np.array([math.log(p.high) if p.log else 1.0 for p in PARAMETERS])
    return lo, hi


def _lame(E: float, nu: float) -> tuple[float, float]:
    return E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))


@dataclass
class ReducedBody:
    """One body's whole elastic model projected on its lowest modes at a reference, and what each soft
    region adds to its stiffness and mass there (for Rayleigh–Ritz at nearby constants)."""

    reference: np.ndarray  # the constants the basis was solved at
    K0: np.ndarray  # (k, k) Φᵀ K Φ at the reference (diagonal: the eigenvalues)
    Klam: dict[str, np.ndarray]  # region → Φᵀ K_λ Φ (unit Lamé λ in that region)
    Kmu: dict[str, np.ndarray]  # region → Φᵀ K_μ Φ
    Mrho: dict[str, np.ndarray]  # region → Φᵀ M Φ at unit density there
    M0: np.ndarray  # the rest of the mass (bone)
    share: dict[str, dict[str, np.ndarray]]  # soft-tissue region → density region → (k, k) mass in its nodes
    share0: dict[str, np.ndarray]
    base: dict[str, np.ndarray]  # density region → (k, 3) Φᵀ M r (participation in a base step along x, y, z)
    base0: np.ndarray
    viscera_nu: float  # the viscera's Poisson's ratio (not fitted: the cavity holds gas)
    volume: object  # the body's volume model (the mesh does not depend on the constants)
    last_modes: tuple[bytes, np.ndarray, np.ndarray] | None = None  # (constants' key, eigenvalues, vectors)

    def resonance(self, theta: np.ndarray, region: str) -> tuple[float, float]:
        """(frequency Hz, damping ratio) of the region's resonance at constants `theta`."""
        v = dict(zip(NAMES, theta))
        lam, Y = self._modes(theta)
        S = self.share0[region] + sum(v[f"{n}.density"] * self.share[region][n] for n in SOFT)
        B = self.base0 + sum(v[f"{n}.density"] * self.base[n] for n in SOFT)
        energy = ((Y.T @ B) ** 2).sum(axis=1) * np.sum(Y * (S @ Y), axis=0)  # diag(Yᵀ S Y)
        found = weighted_response(region, lam, energy / energy.sum(), v["damping.alpha"], v["damping.beta"])
        return found.frequency, found.damping_ratio

    def _modes(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Eigenvalues and mass-normalised eigenvectors of the reduced problem at `theta`: the last ones kept,
        since every region's rows (and a damping constant's step) ask for the same elastic constants."""
        key = np.delete(theta, [NAMES.index("damping.alpha"), NAMES.index("damping.beta")]).tobytes()
        if self.last_modes is None or self.last_modes[0] != key:
            self.last_modes = (key, *self._solve_modes(theta))
        return self.last_modes[1], self.last_modes[2]

    def _solve_modes(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        v = dict(zip(NAMES, theta))
        r = dict(zip(NAMES, self.reference))
        K = self.K0.copy()
        for name in SOFT:
            nu1 = v["soft.poissons_ratio"] if name != "viscera" else self.viscera_nu
            nu0 = r["soft.poissons_ratio"] if name != "viscera" else self.viscera_nu
            lam1, mu1 = _lame(v[f"{name}.youngs_modulus"], nu1)
            lam0, mu0 = _lame(r[f"{name}.youngs_modulus"], nu0)
            K += (lam1 - lam0) * self.Klam[name] + (mu1 - mu0) * self.Kmu[name]
        M = self.M0 + sum(v[f"{n}.density"] * self.Mrho[n] for n in SOFT)
        lam, Y = scipy.linalg.eigh(0.5 * (K + K.T), 0.5 * (M + M.T))
        return lam, Y


def reduce_body(body: Body, materials: Materials, theta: np.ndarray, volume=None,
                element_size: float = MODEL_ELEMENT_SIZE) -> ReducedBody:
    """The full model at constants `theta`, solved, and its projections (see `ReducedBody`); `volume`: the
    body's volume model already meshed (at `element_size`, mm)."""
    from hitogata.elastic.model import bone_segments, build_elastic_model
    from hitogata.elastic.resonance import REGIONS, region_nodes

    table = materials_of(theta, materials)
    model = build_elastic_model(body, extent="body", element_size=element_size, n_modes=RESONANCE_MODES,
                                materials=table, volume=volume)
    phi = model.modes.vectors
    samples = model.volume.region_samples
    names = model.volume.region_names
    pattern = sparsity(model.elements, len(model.points))
    pts, els = model.points, model.elements

    def project(A: sp.spmatrix) -> np.ndarray:
        return phi.T @ (A @ phi)

    Klam, Kmu, Mrho = {}, {}, {}
    mask = {n: np.where(samples == names.index(n), 1.0, TINY) for n in SOFT}
    masses = {n: mass_matrix(pts, els, mask[n], pattern=pattern) for n in SOFT}
    for n in SOFT:
        k_mu = stiffness_matrix(pts, els, 2.0 * mask[n], 0.0, pattern, model.dilatation)  # λ 0, μ 1
        k_both = stiffness_matrix(pts, els, mask[n], 0.25, pattern, model.dilatation)  # λ 0.4, μ 0.4
        Kmu[n] = project(k_mu)
        Klam[n] = project(k_both) / 0.4 - Kmu[n]
        Mrho[n] = project(masses[n])
    M_full = model.M
    rest_of_mass = sp.csr_matrix(M_full - sum(table.regions[n].rho * masses[n] for n in SOFT))
    M0 = project(rest_of_mass)
    r = np.zeros((M_full.shape[0], 3))
    for axis in range(3):
        r[axis::3, axis] = 1.0
    heads, tails = bone_segments(model.volume, body.rig)
    share: dict[str, dict[str, np.ndarray]] = {}
    share0: dict[str, np.ndarray] = {}
    for region in REGIONS:
        nodes = region_nodes(model.points, model.volume.bone_names, heads, tails, region)
        dofs = (3 * nodes[:, None] + np.arange(3)).ravel()
        part = phi[dofs]
        share[region] = {n: part.T @ (masses[n][dofs][:, dofs] @ part) for n in SOFT}
        share0[region] = part.T @ (rest_of_mass[dofs][:, dofs] @ part)
    base = {n: phi.T @ (masses[n] @ r) for n in SOFT}
    return ReducedBody(theta.copy(), np.diag(model.modes.eigenvalues), Klam, Kmu, Mrho, M0, share, share0, base,
                       phi.T @ (rest_of_mass @ r), materials.regions["viscera"].nu, model.volume)


def row_value(row: Row, theta: np.ndarray, reduced: Sequence[ReducedBody]) -> float:
    """The model's value for an identifiable row at constants `theta` (reduced bodies: the row's, one per sex)."""
    v = dict(zip(NAMES, theta))
    if row.kind == "stiffness":
        region = stiffness_region(row)
        assert region is not None, row.id  # `identifiable` leaves out the rows of no model region
        return stiffness_value(row, v[f"{region}.youngs_modulus"], v["soft.poissons_ratio"])
    answers = [body.resonance(theta, row.quantity) for body in reduced]
    f = float(np.mean([a[0] for a in answers]))
    zeta = float(np.mean([a[1] for a in answers]))
    if row.kind == "frequency":
        return f
    return zeta if row.unit == "1" else zeta * 2 * math.pi * f


@dataclass(frozen=True)
class Identification:
    """The fit: constants (SI), their 95 % intervals (None: not pinned), rows' residuals and sensitivities."""

    names: tuple[str, ...]
    start: np.ndarray
    constants: np.ndarray
    interval: tuple[tuple[float, float] | None, ...]
    pinned: tuple[bool, ...]
    rows: tuple[Row, ...]
    fitted: np.ndarray  # model value per row at the fit
    z: np.ndarray  # (model − mean) / SD per row at the fit
    z_start: np.ndarray
    cross_validated: np.ndarray  # z per row from a fit without its source (NaN: no other source to fit)
    sensitivity: np.ndarray  # (rows, constants) SD per +10 % of each constant (of its range for linear ones)
    rounds: int
    held_out: tuple[Row, ...] = ()
    z_held_out: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def materials(self, base: Materials, source: str = "identified") -> Materials:
        return materials_of(self.constants, base, source)


def identifiable(dataset: Dataset) -> Dataset:
    """The rows identification can use: a selection holding another kind is a one-line error; the rows whose
    answer the model does not compute (`hitogata validate` reports them undefined) are left out: a local probe's
    tap (a myometer's: the model's resonance is the segment's) and the dermis alone (no region of the model).
    None left: an error."""
    other = [r for r in dataset.rows if r.kind not in IDENTIFIABLE]
    if other:
        raise HitogataError(f"{dataset.path}: row {other[0].id!r} is a {other[0].kind} row; identification uses "
                            f"{', '.join(IDENTIFIABLE)} rows (select them with --kinds or --rows)")
    fitted = tuple(r for r in dataset.rows if computed(r))
    if not fitted:
        first = dataset.rows[0]
        what = f"a {first.probe} tap" if first.probe else "the dermis alone, no region of the model"
        raise HitogataError(f"{dataset.path}: row {first.id!r} is {what}, which the model does not "
                            f"compute; identification fits a segment's resonance, stiffness rows or both")
    return Dataset(dataset.path, dataset.sources, fitted)


def computed(row: Row) -> bool:
    """Whether the model computes the row's answer: not a local probe's tap, not the dermis alone."""
    return not row.probe and (row.kind != "stiffness" or stiffness_region(row) is not None)


def identify(dataset: Dataset, materials: Materials, held_out: Dataset | None = None,
             progress: Callable[[str], None] | None = None, element_size: float = MODEL_ELEMENT_SIZE) -> Identification:
    """Fit the constants to the dataset's rows (all identifiable), starting from `materials`; `held_out`
    rows (identifiable, kept apart) are predicted with the fit. `element_size` (mm): the whole body's
    lattice, as `answer_dataset`'s."""
    dataset = identifiable(dataset)
    if held_out is not None:  # the rows the model does not compute are neither fitted nor predicted
        held_out = Dataset(held_out.path, held_out.sources, tuple(r for r in held_out.rows if computed(r)))
    say = progress or (lambda _: None)
    rows = dataset.rows
    theta0 = constants_of(materials)
    _check_start(theta0)
    cache = BodyCache(materials, element_size)
    keys = {r.id: [(s, dataset.source_of(r).subjects) for s in sexes(dataset.source_of(r).subjects)]
            for r in rows if r.kind != "stiffness"}
    bodies = {key: cache.body(*key) for ks in keys.values() for key in ks}
    theta = theta0.copy()
    lo, hi = _unit_bounds()
    free = np.ones(len(theta), dtype=bool)
    reduced: dict = {}
    rounds = 0
    for rounds in range(1, MAX_ROUNDS + 1):
        for key, body in bodies.items():
            say(f"round {rounds}: solving the whole body of {key[0]} subjects at the current constants")
            reduced[key] = reduce_body(body, materials, theta, reduced[key].volume if key in reduced else None,
                                       element_size)
        if rounds == 1:  # the tissue meshes are made: a region they do not model is neither fitted nor predicted
            rows = tuple(r for r in rows if _resolved(r, [(reduced[k].volume, bodies[k]) for k in keys.get(r.id, [])],
                                                      element_size, say))
            if not rows:
                raise HitogataError(f"{dataset.path}: no row left to fit: the elastic model does not resolve the "
                                    "regions of its resonance rows")
            keys = {r.id: keys[r.id] for r in rows if r.id in keys}  # the later rounds solve the bodies still asked
            bodies = {key: bodies[key] for ks in keys.values() for key in ks}
        residual = _residuals(rows, keys, reduced)
        J = _jacobian(residual, _to_unit(theta))
        free = _pinned(J)
        x = _to_unit(theta)
        new = _from_unit(_fit(residual, x, free, lo, hi))
        moved = np.abs(_to_unit(new) - x)
        theta = new
        say(f"round {rounds}: largest change {moved.max():.2%}")
        if moved.max() < TOLERANCE:
            break
    residual = _residuals(rows, keys, reduced)
    x = _to_unit(theta)
    J = _jacobian(residual, x)
    z = residual(x)
    interval = _intervals(J, x, free)
    cv = _leave_one_source_out(rows, dataset, keys, reduced, x, free, lo, hi)
    z_held = np.zeros(0)
    if held_out is not None and held_out.rows:
        extra = _bodies_for(held_out, cache, materials, theta, element_size)
        kept = held_out

        def meshes(r: Row) -> list:
            subjects = kept.source_of(r).subjects
            return [(reduced_body.volume, cache.body(sex, subjects))
                    for sex, reduced_body in zip(sexes(subjects), extra.get(r.id, []))]

        held_out = Dataset(held_out.path, held_out.sources,
                           tuple(r for r in held_out.rows if _resolved(r, meshes(r), element_size, say)))
        z_held = np.array([(row_value(r, theta, extra.get(r.id, [])) - r.mean) / r.sd for r in held_out.rows])
    fitted = np.array([row_value(r, theta, [reduced[k] for k in keys.get(r.id, [])]) for r in rows])
    start_residual = np.array([(row_value(r, theta0, [reduced[k] for k in keys.get(r.id, [])]) - r.mean) / r.sd
                               for r in rows])
    return Identification(NAMES, theta0, theta, interval, tuple(bool(f) for f in free), rows, fitted, z,
                          start_residual, cv, _per_ten_percent(J), rounds,
                          () if held_out is None else held_out.rows, z_held)


def _resolved(row: Row, meshes: Sequence[tuple], element_size: float, say: Callable[[str], None]) -> bool:
    """Whether the row's region is modelled on each of its bodies (`meshes`: (volume model, body) pairs, none
    for a stiffness row; `answers.unresolved_region`); a row that is not is said and left out, as the table
    reports it undefined."""
    for volume, body in meshes:
        why = unresolved_region(row, volume, body, element_size)
        if why:
            say(f"row {row.id!r} left out: {why}")
            return False
    return True


def _check_start(theta: np.ndarray) -> None:
    for p, value in zip(PARAMETERS, theta):
        if not p.low <= value <= p.high:
            raise HitogataError(f"starting materials: {p.name} = {value:.4g} lies outside the literature's range "
                                f"{p.low:.4g}..{p.high:.4g} ({p.bounds_from})")


def _residuals(rows: Sequence[Row], keys: dict, reduced: dict) -> Callable[[np.ndarray], np.ndarray]:
    def residual(x: np.ndarray) -> np.ndarray:
        theta = _from_unit(x)
        return np.array([(row_value(r, theta, [reduced[k] for k in keys.get(r.id, [])]) - r.mean) / max(r.sd, 1e-12)
                         for r in rows])
    return residual


def _jacobian(residual: Callable[[np.ndarray], np.ndarray], x: np.ndarray, step: float = 1e-4) -> np.ndarray:
    """Central differences in the fit's coordinates (the resonance picks a mode: no analytic derivative)."""
    J = np.empty((len(residual(x)), len(x)))
    for k in range(len(x)):
        e = np.zeros(len(x))
        e[k] = step
        J[:, k] = (residual(x + e) - residual(x - e)) / (2 * step)
    return J


def _per_ten_percent(J: np.ndarray) -> np.ndarray:
    """SD per +10 % of each constant: of its value for a modulus (log scale), of its range for the others."""
    return J * np.array([math.log(1.1) if p.log else 0.1 for p in PARAMETERS])


def _pinned(J: np.ndarray) -> np.ndarray:
    """The constants some row responds to by at least `PINNED` SD per +10 %."""
    return np.abs(_per_ten_percent(J)).max(axis=0) >= PINNED


def _fit(residual: Callable[[np.ndarray], np.ndarray], x: np.ndarray, free: np.ndarray, lo: np.ndarray,
         hi: np.ndarray, rows: np.ndarray | None = None) -> np.ndarray:
    """The bounded least-squares fit of the free constants (of `rows` only, if given), from `x`."""
    keep = slice(None) if rows is None else rows
    fit = least_squares(lambda y: residual(_merge(x, y, free))[keep], x[free], bounds=(lo[free], hi[free]),
                        x_scale="jac", method="trf", xtol=1e-12, ftol=1e-12, gtol=1e-12)
    return _merge(x, fit.x, free)


def _merge(x: np.ndarray, y: np.ndarray, free: np.ndarray) -> np.ndarray:
    out = x.copy()
    out[free] = y
    return out


def _intervals(J: np.ndarray, x: np.ndarray, free: np.ndarray) -> tuple[tuple[float, float] | None, ...]:
    """95 % intervals from the Gauss–Newton covariance (JᵀJ)⁻¹ of the free constants (residuals in SD), cut
    at the literature's bounds."""
    out: list[tuple[float, float] | None] = [None] * len(x)
    lo, hi = _unit_bounds()
    Jf = J[:, free]
    if Jf.size == 0:
        return tuple(out)
    cov = np.linalg.pinv(Jf.T @ Jf)
    half = 1.96 * np.sqrt(np.maximum(np.diag(cov), 0.0))
    for k, h in zip(np.flatnonzero(free), half):
        p = PARAMETERS[k]
        a, b = max(x[k] - h, lo[k]), min(x[k] + h, hi[k])  # within the literature's range, as the fit is
        out[k] = ((math.exp(a), math.exp(b)) if p.log else (p.low + a * (p.high - p.low), p.low + b * (p.high - p.low)))
    return tuple(out)


def _leave_one_source_out(rows, dataset: Dataset, keys, reduced, x, free, lo, hi) -> np.ndarray:
    """Each row's z from a fit on the other sources' rows (reduced bodies at the fit: no new solves)."""
    out = np.full(len(rows), np.nan)
    residual = _residuals(rows, keys, reduced)
    for source in sorted({r.source for r in rows}):
        keep = np.array([r.source != source for r in rows])
        if not keep.any():
            continue
        out[~keep] = residual(_fit(residual, x, free, lo, hi, keep))[~keep]
    return out


def _bodies_for(held_out: Dataset, cache: BodyCache, materials: Materials, theta: np.ndarray,
                element_size: float) -> dict:
    """Reduced bodies at the fit for held-out resonance rows (one per sex of each row's subjects)."""
    out: dict = {}
    built: dict = {}
    for r in held_out.rows:
        if r.kind == "stiffness":
            continue
        subjects = held_out.source_of(r).subjects
        out[r.id] = []
        for sex in sexes(subjects):
            key = (sex, subjects)
            if key not in built:
                built[key] = reduce_body(cache.body(sex, subjects), materials, theta, None, element_size)
            out[r.id].append(built[key])
    return out
