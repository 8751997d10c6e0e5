"""The body the fit moves: MakeHuman shape parameters and a few joint angles, as one vector each.

Shape: the macro parameters of `ShapeParameters` except sex (given) and race
(kept), each in its 0..1 range; age as a fraction of MakeHuman's adult span
(25 → 90 years; younger bodies share the 25-year shape). Pose: the shoulder
complex's clinical flexion and abduction (`hitogata.skeleton.shoulder`: the
girdle follows), the elbows' flexion and the hips' abduction, the last two
relative to the rest pose — what tells an A-pose scan from a T-pose one and
from the rest pose. The posed surface is the body's own (`poser_for`, LBS).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from hitogata.body import Body
from hitogata.muscles.activation import MuscleLimitWarning
from hitogata.muscles.geometry import MuscleGeometryWarning
from hitogata.pose import Poser
from hitogata.shape import OLD_YEARS, YOUNG_YEARS, ShapeParameters
from hitogata.pose import poser_for

SHAPE_NAMES = ("weight", "muscle", "height", "proportions", "cup", "firmness", "age")
# (name, bounds in degrees, start in degrees); shoulder_* are clinical, the others rest-relative.
POSE_SPEC = (
    ("shoulder_l.abduction", (0.0, 120.0), 42.0),
    ("shoulder_r.abduction", (0.0, 120.0), 42.0),
    ("shoulder_l.flexion", (-30.0, 60.0), 0.0),
    ("shoulder_r.flexion", (-30.0, 60.0), 0.0),
    ("forearm_l.flexion", (-38.0, 60.0), 0.0),
    ("forearm_r.flexion", (-38.0, 60.0), 0.0),
    ("thigh_l.abduction", (-15.0, 30.0), 0.0),
    ("thigh_r.abduction", (-15.0, 30.0), 0.0),
)
POSE_NAMES = tuple(name for name, _, _ in POSE_SPEC)
T_POSE = np.radians(90.0)  # shoulder abduction of a T-pose
SHAPE_STEP = 0.01  # finite-difference steps: parameter units
POSE_STEP = np.radians(0.5)


@dataclass(frozen=True)
class BodyModel:
    """Shape vector ↔ `ShapeParameters` (sex, race and density fixed) and pose vector ↔ joint angles."""

    base: ShapeParameters
    density: float

    @property
    def shape_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        return np.zeros(len(SHAPE_NAMES)), np.ones(len(SHAPE_NAMES))

    @property
    def pose_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        return (np.radians([b[0] for _, b, _ in POSE_SPEC]), np.radians([b[1] for _, b, _ in POSE_SPEC]))

    def shape_start(self) -> np.ndarray:
        return self.shape_vector(self.base)

    @staticmethod
    def pose_start() -> np.ndarray:
        return np.radians([start for _, _, start in POSE_SPEC])

    @staticmethod
    def shape_vector(params: ShapeParameters) -> np.ndarray:
        age = min(max((params.age - YOUNG_YEARS) / (OLD_YEARS - YOUNG_YEARS), 0.0), 1.0)
        return np.array([*(getattr(params, n) for n in SHAPE_NAMES[:-1]), age])

    def params(self, shape: np.ndarray) -> ShapeParameters:
        s = np.clip(shape, 0.0, 1.0)
        values = {n: float(v) for n, v in zip(SHAPE_NAMES[:-1], s[:-1])}
        return self.base.with_(**values, age=YOUNG_YEARS + float(s[-1]) * (OLD_YEARS - YOUNG_YEARS))

    def body(self, shape: np.ndarray) -> Body:
        return Body.from_parameters(self.params(shape), self.density)

    @classmethod
    def angles(cls, poser: Poser, pose: np.ndarray) -> np.ndarray:
        """(D,) rest-relative joint angles of a pose vector (clamped onto the ranges of motion, silently).

        MakeHuman's rest pose holds the arms at 42° with the shoulder girdle at 0,
        where the scapulohumeral rhythm would have raised it a little: the complex's
        angles at the rest pose's own values are taken off, in full there and fading
        out by a T-pose, so that the rest pose is one the fit can reach exactly.
        """
        q = cls._complex(poser, pose)
        rest = cls._complex(poser, cls.pose_start())
        names = poser.skeleton.dof_names
        for side in ("l", "r"):
            k = POSE_NAMES.index(f"shoulder_{side}.abduction")
            fade = np.clip((T_POSE - pose[k]) / (T_POSE - cls.pose_start()[k]), 0.0, 1.0)
            mine = np.array([f"_{side}." in name for name in names])
            q[mine] -= fade * rest[mine]
        return q

    @staticmethod
    def _complex(poser: Poser, pose: np.ndarray) -> np.ndarray:
        clinical = {n: float(v) for n, v in zip(POSE_NAMES, pose) if n.startswith("shoulder_")}
        relative = {n: float(v) for n, v in zip(POSE_NAMES, pose) if not n.startswith("shoulder_")}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", MuscleLimitWarning)
            return poser.angles(angles=relative, clinical=clinical, on_limit="clamp")

    def posed(self, poser: Poser, pose: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The skin vertices (V, 3) and rig joint centres (B, 3) of `poser`'s body in the pose."""
        q = self.angles(poser, pose)
        kin = poser.kinematics.pose(q)
        vertices = poser.pose_many(q[None])[0]
        return vertices, poser.rig_joints(kin.rotations[0], kin.translations[0])

    def jacobian(self, shape: np.ndarray, pose: np.ndarray) -> tuple[Body, Poser, np.ndarray, np.ndarray]:
        """The body, its poser, the posed skin (V, 3) and d(posed skin)/d(shape, pose) (V, 3, S + Q).

        Pose columns are finite differences of the skinned surface. Shape columns are
        finite differences of the rest surface carried by each vertex's blended rotation
        (LBS's linear part): the joints' own move with the shape is left to the next
        iteration, which rebuilds the body.
        """
        body = self.body(shape)
        with warnings.catch_warnings():  # the solver's passing bodies: their muscle notes are not the user's
            warnings.simplefilter("ignore", MuscleGeometryWarning)
            poser = poser_for(body)
        lo, hi = self.pose_bounds
        probes = [pose]
        steps = []
        for j in range(len(pose)):
            step = POSE_STEP if pose[j] + POSE_STEP <= hi[j] else -POSE_STEP
            probe = pose.copy()
            probe[j] += step
            probes.append(probe)
            steps.append(step)
        q = np.stack([self.angles(poser, p) for p in probes])
        surfaces = poser.pose_many(q)
        posed = surfaces[0]
        pose_cols = (surfaces[1:] - posed) / np.asarray(steps)[:, None, None]
        kin = poser.kinematics.pose(q[:1])
        linear = (poser.skin.weights @ kin.rotations[0].reshape(-1, 9)).reshape(-1, 3, 3)
        shape_cols = []
        for j in range(len(shape)):
            # central differences within 0..1: every parameter's targets switch at 0.5 (MakeHuman's
            # min/average/max), where a one-sided slope would hold the solver on the side it started
            lo_probe, hi_probe = shape.copy(), shape.copy()
            lo_probe[j], hi_probe[j] = max(shape[j] - SHAPE_STEP, 0.0), min(shape[j] + SHAPE_STEP, 1.0)
            change = self.body(hi_probe).vertices - self.body(lo_probe).vertices
            shape_cols.append(np.einsum("vij,vj->vi", linear, change / (hi_probe[j] - lo_probe[j])))
        jac = np.concatenate([np.stack(shape_cols, axis=2), pose_cols.transpose(1, 2, 0)], axis=2)
        return body, poser, posed, jac
