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
outliers count for little. The pose comes coarse to fine (`STAGE_FROM`): the
trunk, shoulders and hips first, then the neck, elbows, forearms' and upper
arms' turn and knees, then the wrists, fingers and feet, each stage joining
once the one before has brought its parts near their scan points. A weak prior
(`POSE_PRIOR`) keeps joint angles the surface hardly shows near rest.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import lsq_linear
from scipy.spatial import cKDTree
from threadpoolctl import threadpool_limits

from hitogata.geometry.normals import vertex_normals
from hitogata.made_to_measure.scan_fit.closest import SurfaceQuery, face_normals
from hitogata.made_to_measure.scan_fit.hands import search_hands
from hitogata.made_to_measure.scan_fit.model import DISTAL, LIMBS, POSE_NAMES, POSE_STAGES, BodyModel

BODY_TO_SCAN = 0.5  # weight of the body → scan rows against the scan → body rows
TRUST = {"rotation": np.radians(5.0), "translation": 0.03, "shape": 0.15, "pose": np.radians(12.0)}
SIGMA = (0.03, 0.003)  # m: the Cauchy scale, first and last
SIGMA_DECAY = 0.75
# A weak pull of the joint angles towards the rest pose (all but the shoulders' abduction: A- or
# T-pose is the scan's to say), as if every scan point the angle moves (`MOVES`) were 0.1 mm off per
# 10° away: it settles the angles the surface hardly sees (flexion of an arm held out sideways turns
# it about its own axis) without moving what the scan shows, and weighs as little against a finger's
# few points as against the trunk's many. The data rows it stands against are Cauchy-weighted and
# the prior's are not: at 1 mm per 10° it held a trunk bent 15° at 13° and a forearm turned 40° at 18°.
POSE_PRIOR = 0.0001 / np.radians(10.0)
MOVES = 0.01  # m per radian: a scan point moves with a joint angle whose turn carries its body point this fast
# The iteration from which each stage of the pose (`model.POSE_STAGES`: trunk, limbs, distal) is solved.
STAGE_FROM = (0, 3, 6)
CLIP = 0.05  # m: distances are clipped here in the fit's score (a mean that still sees feet turned backwards)


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
    first: int = 0,
    sigma: tuple[float, float] = SIGMA,
) -> tuple[Registration, float]:
    """Refine `start` (rigid motion, shape and pose) on the scan points (P, 3); `first`: the
    iteration to start at (the Cauchy scale follows the iteration count).

    Returns the registration and the score (`score`) of the last iteration.
    """
    with threadpool_limits(1, user_api="blas"):  # small products and solves: a second BLAS thread only spins
        return _register(model, points, start, iterations, first, sigma)


def _register(model: BodyModel, points: np.ndarray, start: Registration, iterations: int, first: int,
              sigma: tuple[float, float]) -> tuple[Registration, float]:
    state = start
    score = np.inf
    for k in range(first, first + iterations):
        poser = model.poser(state.shape)
        if k in (STAGE_FROM[LIMBS], STAGE_FROM[DISTAL]):
            state = replace(state, pose=search_hands(model, poser, state.pose, state.place(points), CLIP,
                                                     fingers=k == STAGE_FROM[DISTAL]))
        moving = POSE_STAGES <= max(stage for stage, at in enumerate(STAGE_FROM) if k >= at)
        body, _, posed, jac = model.jacobian(state.shape, state.pose, moving, poser)
        s = max(sigma[1], sigma[0] * SIGMA_DECAY**k)
        state, score = gauss_newton_step(model, points, state, Surface.of(posed, body.faces), s, jac, moving)
    return state, score


def score(distance: np.ndarray) -> float:
    """How far a scan is from the body: the mean scan → body distance, each clipped at `CLIP` (m)."""
    return float(np.minimum(distance, CLIP).mean())


def gauss_newton_step(
    model: BodyModel,
    points: np.ndarray,
    state: Registration,
    surface: Surface,
    sigma: float,
    jac: np.ndarray | None = None,
    moving: np.ndarray | None = None,
) -> tuple[Registration, float]:
    """One step from `state` on the posed surface; `jac` (V, 3, S + Q) its Jacobian there, None: rigid only;
    `moving` (Q,): the joint angles the step may change (all when None).

    Returns the new registration and the score (`score`) before the step.
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
        at_points = np.einsum("pk,pkic->pic", near.bary, jac[faces[near.face]])  # (P, 3, S + Q)
        a1 = np.concatenate([a1, np.einsum("pi,pic->pc", fn, at_points)], axis=1)
        a2 = np.concatenate([a2, np.einsum("vi,vic->vc", vn, jac[rows])], axis=1)
    w1, w2 = cauchy(r1, sigma), BODY_TO_SCAN * np.sqrt(len(r1) / len(r2)) * cauchy(r2, sigma)
    a = np.concatenate([a1 * w1[:, None], a2 * w2[:, None]])
    b = -np.concatenate([r1 * w1, r2 * w2])
    if jac is not None:  # the prior on the pose: rows for (pose − rest pose) but the arms' abduction
        n_pose = len(state.pose)
        free = np.array([n.startswith("shoulder_") and n.endswith(".abduction") for n in POSE_NAMES])
        moved = np.count_nonzero(np.linalg.norm(at_points[:, :, -n_pose:], axis=1) > MOVES, axis=0)
        weight = POSE_PRIOR * np.sqrt(np.maximum(moved, 1)) * ~free
        prior = np.zeros((n_pose, a.shape[1]))
        prior[:, -n_pose:] = np.diag(weight)
        a = np.concatenate([a, prior])
        b = np.concatenate([b, -weight * (state.pose - model.pose_start())])
    lower, upper = _step_bounds(model, state, moving)
    r, qtb = _small_factor(a, b)
    step = np.zeros(len(lower))
    if jac is None:
        step[:6] = np.clip(np.linalg.solve(r, qtb), lower[:6], upper[:6])
    else:
        step = lsq_linear(r, qtb, bounds=(lower, upper), method="bvls").x
    return _apply(state, step, centre), score(near.distance)


def _small_factor(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(R, c) with ‖a x − b‖² = ‖R x − c‖² + const, R square (Cholesky of the normal equations): the
    bounded solve then runs on S + Q + 6 rows instead of ~18,000. A column the data does not move
    (cup on a male body) gets a tiny ridge, so R stays regular."""
    normal = a.T @ a
    normal[np.diag_indices_from(normal)] += 1e-9 * np.trace(normal) / len(normal) + 1e-15
    upper = np.linalg.cholesky(normal).T
    return upper, np.linalg.solve(upper.T, a.T @ b)


def _step_bounds(model: BodyModel, state: Registration,
                 moving: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    """The step's box: each parameter's own bounds within the trust box; joint angles not `moving` held."""
    rigid = np.array([TRUST["rotation"]] * 3 + [TRUST["translation"]] * 3)
    s_lo, s_hi = model.shape_bounds
    p_lo, p_hi = model.pose_bounds
    held = np.zeros(len(state.pose), bool) if moving is None else ~moving
    tiny = 1e-12  # lsq_linear wants lower < upper even for a parameter at its bound
    lower = np.concatenate([-rigid, np.maximum(s_lo - state.shape, -TRUST["shape"]) - tiny,
                            np.where(held, 0.0, np.maximum(p_lo - state.pose, -TRUST["pose"])) - tiny])
    upper = np.concatenate([rigid, np.minimum(s_hi - state.shape, TRUST["shape"]) + tiny,
                            np.where(held, 0.0, np.minimum(p_hi - state.pose, TRUST["pose"])) + tiny])
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
