"""Register the body to scan points: rigid motion, shape and pose together, by Gauss–Newton steps.

Each iteration rebuilds the body (`BodyModel.jacobian`), pairs every scan point
with its closest body point and every body vertex with its nearest scan point
(`scipy.spatial.cKDTree`), and solves the linearised, weighted point-to-plane
least squares for a step of all parameters at once with `scipy.optimize.lsq_linear`
— the parameters' own bounds and a trust box as the step's bounds. Both
directions count: scan → body holds the body to the scan where it was seen,
body → scan pulls limbs onto scanned limbs. Holes in the scan (armpits,
crotch) leave body vertices far from any scan point; the Cauchy weights
w = 1 / (1 + (r/σ)²), σ shrinking over the iterations, make those and
outliers count for little.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import lsq_linear
from scipy.spatial import cKDTree

from hitogata.fit.closest import SurfaceQuery, face_normals
from hitogata.fit.model import BodyModel
from hitogata.geometry.normals import vertex_normals

BODY_TO_SCAN = 0.5  # weight of the body → scan rows against the scan → body rows
TRUST = {"rotation": np.radians(5.0), "translation": 0.03, "shape": 0.15, "pose": np.radians(12.0)}
SIGMA = (0.03, 0.003)  # m: the Cauchy scale, first and last
SIGMA_DECAY = 0.75


@dataclass(frozen=True)
class Registration:
    """The scan's rigid motion into the body frame (x ↦ R x + t), the shape and pose vectors."""

    rotation: np.ndarray  # (3, 3)
    translation: np.ndarray  # (3,)
    shape: np.ndarray
    pose: np.ndarray

    def place(self, points: np.ndarray) -> np.ndarray:
        """Scan points in the body frame."""
        return points @ self.rotation.T + self.translation


@dataclass(frozen=True, eq=False)
class Surface:
    """A posed body surface prepared for the steps: closest-point index, vertex normals, face normals."""

    vertices: np.ndarray
    faces: np.ndarray
    query: SurfaceQuery
    vertex_normals: np.ndarray
    face_normals: np.ndarray
    rows: np.ndarray  # the vertices that pull towards the scan (body → scan rows)

    @classmethod
    def of(cls, vertices: np.ndarray, faces: np.ndarray, every: int = 1) -> "Surface":
        """The surface; every `every`-th vertex gives a body → scan row."""
        return cls(vertices, faces, SurfaceQuery(vertices, faces), vertex_normals(vertices, faces),
                   face_normals(vertices, faces), np.arange(0, len(vertices), every))


def rotation_vector(omega: np.ndarray) -> np.ndarray:
    """The rotation matrix of a rotation vector (Rodrigues)."""
    angle = float(np.linalg.norm(omega))
    if angle < 1e-12:
        return np.eye(3)
    k = omega / angle
    cross = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * cross + (1 - np.cos(angle)) * cross @ cross


def cauchy(r: np.ndarray, sigma: float) -> np.ndarray:
    """Square roots of the Cauchy IRLS weights of residuals r."""
    return 1.0 / np.sqrt(1.0 + (r / sigma) ** 2)


def _rows(normals: np.ndarray, placed: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """d(n·(x − q))/d(ω, δt) for scan points q moved by ω × (q − c) + δt: −[(q − c) × n, n]."""
    return -np.concatenate([np.cross(placed - centre, normals), normals], axis=1)


def register(
    model: BodyModel,
    points: np.ndarray,
    start: Registration,
    iterations: int,
    sigma: tuple[float, float] = SIGMA,
) -> tuple[Registration, float]:
    """Refine `start` (rigid motion, shape and pose) on the scan points (P, 3).

    Returns the registration and the median scan → body distance (m) of the last iteration.
    """
    state = start
    s = sigma[0]
    median = np.inf
    for _ in range(iterations):
        body, _, posed, jac = model.jacobian(state.shape, state.pose)
        state, median = gauss_newton_step(model, points, state, Surface.of(posed, body.faces), s, jac)
        s = max(sigma[1], s * SIGMA_DECAY)
    return state, median


def gauss_newton_step(
    model: BodyModel,
    points: np.ndarray,
    state: Registration,
    surface: Surface,
    sigma: float,
    jac: np.ndarray | None = None,
) -> tuple[Registration, float]:
    """One step from `state` on the posed surface; `jac` (V, 3, S + Q) its Jacobian there, None: rigid only.

    Returns the new registration and the median scan → body distance (m) before the step.
    """
    posed, faces = surface.vertices, surface.faces
    placed = state.place(points)
    centre = placed.mean(axis=0)
    near = surface.query.closest(placed)
    fn = surface.face_normals[near.face]
    r1 = np.einsum("ij,ij->i", fn, near.point - placed)
    rows = surface.rows
    vn = surface.vertex_normals[rows]
    _, nearest = cKDTree(placed).query(posed[rows])
    r2 = np.einsum("ij,ij->i", vn, posed[rows] - placed[nearest])
    a1, a2 = _rows(fn, placed, centre), _rows(vn, placed[nearest], centre)
    if jac is not None:
        a1 = np.concatenate([a1, np.einsum("pi,pkic->pc", fn, near.bary[:, :, None, None] * jac[faces[near.face]])],
                            axis=1)
        a2 = np.concatenate([a2, np.einsum("vi,vic->vc", vn, jac[rows])], axis=1)
    w1, w2 = cauchy(r1, sigma), BODY_TO_SCAN * np.sqrt(len(r1) / len(r2)) * cauchy(r2, sigma)
    a = np.concatenate([a1 * w1[:, None], a2 * w2[:, None]])
    b = -np.concatenate([r1 * w1, r2 * w2])
    lower, upper = _step_bounds(model, state)
    if jac is None:
        step = np.zeros(len(lower))
        step[:6] = np.clip(np.linalg.lstsq(a, b, rcond=None)[0], lower[:6], upper[:6])
    else:
        step = lsq_linear(a, b, bounds=(lower, upper), method="bvls").x
    return _apply(state, step, centre), float(np.median(near.distance))


def _step_bounds(model: BodyModel, state: Registration) -> tuple[np.ndarray, np.ndarray]:
    """The step's box: each parameter's own bounds within the trust box."""
    rigid = np.array([TRUST["rotation"]] * 3 + [TRUST["translation"]] * 3)
    s_lo, s_hi = model.shape_bounds
    p_lo, p_hi = model.pose_bounds
    tiny = 1e-12  # lsq_linear wants lower < upper even for a parameter at its bound
    lower = np.concatenate([-rigid, np.maximum(s_lo - state.shape, -TRUST["shape"]) - tiny,
                            np.maximum(p_lo - state.pose, -TRUST["pose"]) - tiny])
    upper = np.concatenate([rigid, np.minimum(s_hi - state.shape, TRUST["shape"]) + tiny,
                            np.minimum(p_hi - state.pose, TRUST["pose"]) + tiny])
    return lower, upper


def _apply(state: Registration, step: np.ndarray, centre: np.ndarray) -> Registration:
    """The registration after a step (ω, δt, δshape, δpose); the rotation turns about the scan's centre."""
    turn = rotation_vector(step[:3])
    n_shape = len(state.shape)
    return replace(
        state,
        rotation=turn @ state.rotation,
        translation=turn @ (state.translation - centre) + centre + step[3:6],
        shape=np.clip(state.shape + step[6:6 + n_shape], 0.0, 1.0),
        pose=state.pose + step[6 + n_shape:],
    )
