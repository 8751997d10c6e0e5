"""Fit the body to a scan: align, solve shape and pose, add the detail, and say how well it fits.

The steps (docs/body.md, "A body from a scan"): a rigid start in any orientation
(`align.initial_alignment`); rigid motion, MakeHuman shape parameters and the
scan's whole pose together, coarse to fine (`register.register`, with the hands'
grid search `hands.search_hands`); optional per-vertex detail along the
normals (`detail.solve_detail`). The result is a `Body` like any other — rig,
skin weights, skeleton and muscles placed on it — at rest, with the scan's pose
beside it; and the scan → body distances of the shape model alone (per region:
where the scan leaves the model's space) and of the fitted body.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from hitogata.body.model import WHOLE_BODY_DENSITY, Body, sex_value
from hitogata.body.shape import ShapeParameters
from hitogata.made_to_measure.scan_fit.align import initial_alignments
from hitogata.made_to_measure.scan_fit.closest import signed_closest
from hitogata.made_to_measure.scan_fit.detail import detailed_body, solve_detail
from hitogata.made_to_measure.scan_fit.girths import scan_girths
from hitogata.made_to_measure.scan_fit.model import POSE_NAMES, SHAPE_NAMES, BodyModel
from hitogata.made_to_measure.scan_fit.regions import RegionResidual, cannot_follow, region_residuals, vertex_regions
from hitogata.made_to_measure.scan_fit.register import Registration, register
from hitogata.made_to_measure.scan_fit.scan import Scan
from hitogata.measure import Measurements, measure
from hitogata.posing.pose import poser_for

FIT_POINTS = 6000  # scan points the shape and pose are solved on
DETAIL_POINTS = 60_000  # scan points the detail is solved on
ITERATIONS = 30  # Gauss-Newton iterations in all
TRIED, TRIAL = 2, 6  # the best rigid starts, each given this many iterations before the better goes on
# Muscle tone and weight trade against each other (MakeHuman's lean bodies are low in both): the
# fit is restarted from low and from high muscle tone, RESTART iterations each (the Cauchy scale at its
# floor), and the best kept.
MUSCLE_RESTARTS = (0.2, 0.8)
RESTART = 8


@dataclass(frozen=True)
class Distances:
    """Scan → body distances, m."""

    median: float
    p95: float
    max: float

    @classmethod
    def of(cls, d: np.ndarray) -> "Distances":
        return cls(float(np.median(d)), float(np.percentile(d, 95)), float(d.max()))


@dataclass(frozen=True, eq=False)
class ScanFit:
    """A fitted body and how well it fits its scan."""

    body: Body  # at rest, with the detail
    registration: Registration
    pose: dict[str, float]  # the scan's pose, POSE_NAMES → radians
    offsets: np.ndarray | None  # (n_surface,) m along the rest normals
    model_error: Distances  # the shape parameters alone
    error: Distances  # the fitted body
    regions: list[RegionResidual]  # the shape parameters alone, per region
    not_followed: list[str]  # regions the shape model cannot follow
    measurements: Measurements  # the fitted body at rest
    posed_measurements: Measurements  # the fitted body in the scan's pose
    scan_girths: dict[str, float]  # taken on the scan (NaN: not measurable there)


def _distances(posed: np.ndarray, faces: np.ndarray, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Distance, signed distance (positive: point outside) and nearest corner of each point."""
    near, signed = signed_closest(posed, faces, points)
    corner = faces[near.face, near.bary.argmax(axis=1)]
    return near.distance, signed, corner


def fit_scan(scan: Scan, sex: float | str, *, detail: bool = True, density: float = WHOLE_BODY_DENSITY,
             iterations: int = ITERATIONS, seed: int = 0) -> ScanFit:
    """The body of sex `sex` fitted to the scan (see the module note)."""
    model = BodyModel(ShapeParameters(sex=sex_value(sex)), density)
    sample = scan.sample(FIT_POINTS, seed)
    tried = [register(model, sample, start, TRIAL) for start in initial_alignments(model, scan.points, seed)[:TRIED]]
    reg, score = register(model, sample, min(tried, key=lambda t: t[1])[0], iterations - TRIAL, first=TRIAL)
    for value in MUSCLE_RESTARTS:  # lean-and-muscular against lean-and-slight: a second opinion from each side
        shape = reg.shape.copy()
        shape[SHAPE_NAMES.index("muscle")] = value
        other, other_score = register(model, sample, replace(reg, shape=shape), RESTART, first=iterations)
        if other_score < score:
            reg, score = other, other_score
    params = model.params(reg.shape)
    plain = model.body(reg.shape)
    posed, _ = model.posed(poser_for(plain), reg.pose)
    placed = reg.place(scan.points)
    distance, signed, corner = _distances(posed, plain.faces, placed)
    regions = region_residuals(vertex_regions(plain)[corner], distance, signed)
    offsets = solve_detail(posed, plain.faces, reg.place(scan.sample(DETAIL_POINTS, seed + 1))) if detail else None
    body = detailed_body(params, offsets, density)
    fitted, joints = model.posed(poser_for(body), reg.pose)
    final = _distances(fitted, body.faces, placed)[0]
    return ScanFit(
        body=body,
        registration=reg,
        pose=dict(zip(POSE_NAMES, reg.pose.tolist())),
        offsets=offsets,
        model_error=Distances.of(distance),
        error=Distances.of(final),
        regions=regions,
        not_followed=cannot_follow(regions, float(np.median(distance))),
        measurements=measure(body),
        posed_measurements=measure(body, vertices=fitted, joints=joints),
        scan_girths=scan_girths(placed, scan.faces, body, fitted, joints),
    )
