"""A body scan as the fit takes it: points in metres (and triangles, when a mesh), its unit decided.

Scans come in millimetres or metres. A standing person's largest extent (stature,
or the arm span of a T-pose) lies in `BODY_EXTENT`; the unit whose reading puts
it there is the scan's, and a scan that fits neither is an error unless the
unit is given.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hitogata.errors import HitogataError
from hitogata.geometry.normals import triangle_areas

UNITS = {"mm": 1e-3, "m": 1.0}
BODY_EXTENT = (1.0, 2.6)  # m: a standing adult's stature (1.4–2.1 m) or arm span, with margin
MIN_POINTS = 2000  # fewer cannot pin down a body's shape
MAX_DEPTH_RATIO = 0.5  # a person's smallest principal extent over the largest (0.15–0.3), with margin
MIN_WIDTH_RATIO = 0.1  # the middle one (shoulders or hips: 0.2–0.3; arm span in a T-pose: about 1)


@dataclass(frozen=True)
class Scan:
    """Scan points (P, 3) in metres in the scan's own frame; faces (F, 3) when it was a triangle mesh."""

    points: np.ndarray
    faces: np.ndarray | None
    unit: str  # the file's unit, "mm" or "m"
    source: str = "scan"

    def sample(self, count: int, seed: int = 0) -> np.ndarray:
        """About `count` points spread evenly over the scan: area-uniform on a mesh, a random subset of a cloud."""
        rng = np.random.default_rng(seed)
        if self.faces is None or len(self.faces) == 0:
            if len(self.points) <= count:
                return self.points
            return self.points[rng.choice(len(self.points), count, replace=False)]
        tri = self.points[self.faces]
        area = triangle_areas(tri)
        chosen = rng.choice(len(tri), count, p=area / area.sum())
        r1, r2 = np.sqrt(rng.random(count)), rng.random(count)
        a, b, c = tri[chosen, 0], tri[chosen, 1], tri[chosen, 2]
        return (1 - r1)[:, None] * a + (r1 * (1 - r2))[:, None] * b + (r1 * r2)[:, None] * c


def scan_unit(points: np.ndarray, source: str, unit: str | None = None) -> str:
    """The scan's unit: `unit` if given (its reading must make the scan a person's size), else the one
    that makes its largest extent a person's."""
    extent = float(np.ptp(points, axis=0).max())
    lo, hi = BODY_EXTENT
    if unit is not None:
        if unit not in UNITS:
            raise HitogataError(f"--units {unit!r}: allowed {', '.join(UNITS)}")
        metres = extent * UNITS[unit]
        if not lo <= metres <= hi:
            other = next((n for n, m in UNITS.items() if lo <= extent * m <= hi), None)
            hint = f"; is the file in {other}?" if other else ""
            raise HitogataError(f"{source}: --units {unit}: the scan spans {metres:.4g} m; a standing person spans "
                                f"{lo:g}–{hi:g} m{hint}")
        return unit
    for name, metres in UNITS.items():
        if lo <= extent * metres <= hi:
            return name
    raise HitogataError(
        f"{source}: largest extent {extent:g} in the file's unit: unit unclear (a standing person spans "
        f"{lo:g}–{hi:g} m or {lo * 1000:g}–{hi * 1000:g} mm); give --units mm or --units m"
    )


def make_scan(points: np.ndarray, faces: np.ndarray | None, source: str, unit: str | None = None) -> Scan:
    """A checked scan in metres: enough finite points, the unit decided (`scan_unit`)."""
    points = np.asarray(points, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] != 3:
        raise HitogataError(f"{source}: points of shape {points.shape}; allowed (P, 3)")
    finite = np.isfinite(points).all(axis=1)
    if faces is not None and len(faces) and not finite.all():
        faces = faces[finite[faces].all(axis=1)]
    if not finite.all():
        if faces is not None and len(faces):
            keep = np.flatnonzero(finite)
            remap = np.full(len(points), -1)
            remap[keep] = np.arange(len(keep))
            faces = remap[faces]
        points = points[finite]
    if len(points) < MIN_POINTS:
        raise HitogataError(f"{source}: {len(points)} points; allowed a scan of at least {MIN_POINTS} points")
    unit = scan_unit(points, source, unit)
    check_person_shape(points, source)
    faces = None if faces is None or len(faces) == 0 else np.asarray(faces, dtype=np.int64)
    return Scan(points * UNITS[unit], faces, unit, source)


def check_person_shape(points: np.ndarray, source: str) -> None:
    """One line before the fit if the points are not shaped like a standing person.

    Along its principal axes a standing person is long and shallow: the depth (front to back,
    0.2–0.5 m) is at most about a third of the stature or arm span (1.4–2.1 m) — 0.15 for a slim
    adult, 0.3 for a very large one. A ball, a cube or a flat sheet is not a person.
    """
    centred = points - points.mean(axis=0)
    axes = np.linalg.svd(centred[:: max(len(centred) // 20000, 1)], full_matrices=False)[2]
    extents = np.sort(np.ptp(centred @ axes.T, axis=0))[::-1]
    depth, width, length = extents[2] / extents[0], extents[1] / extents[0], extents[0]
    if depth > MAX_DEPTH_RATIO or width < MIN_WIDTH_RATIO:
        raise HitogataError(f"{source}: not shaped like a standing person: along its principal axes it measures "
                            f"{extents[0] / length:.2f} : {width:.2f} : {depth:.2f}; allowed a depth of at most "
                            f"{MAX_DEPTH_RATIO:g} and a width of at least {MIN_WIDTH_RATIO:g} of its length")
