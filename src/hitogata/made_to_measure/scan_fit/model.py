"""The body the fit moves: MakeHuman shape parameters and the joint angles a scan shows, as one vector each.

Shape: the macro parameters of `ShapeParameters` except sex (given) and race
(kept), each in its 0..1 range; age as a fraction of MakeHuman's adult span
(25 → 90 years; younger bodies share the 25-year shape). Pose (`POSE_SPEC`):
the thoracolumbar spine's and the neck's flexion, lateral bending and rotation
(each a region's angle shared among its vertebrae, `skeleton.stretches`); the
shoulder complex's clinical flexion and abduction (`hitogata.skeleton.shoulder`:
the girdle follows); the upper arm's turn, the elbow's flexion, the forearm's
pronation, the wrist's flexion and deviation, each finger's and the thumb's
joints; the hips' flexion, abduction and turn, the knees, the ankles and toes —
all but the shoulders relative to the rest pose, each in three stages from the
trunk out (`POSE_STAGES`). The posed surface is the body's own (`poser_for`, LBS).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from hitogata.body.model import Body
from hitogata.body.shape import OLD_YEARS, YOUNG_YEARS, ShapeParameters
from hitogata.muscles.activation import MuscleLimitWarning
from hitogata.muscles.geometry import MuscleGeometryWarning
from hitogata.posing.pose import Poser, poser_for
from hitogata.posing.skinning import Skin, linear_blend
from hitogata.skeleton.stretches import spread

SHAPE_NAMES = ("weight", "muscle", "height", "proportions", "cup", "firmness", "age")
TRUNK, LIMBS, DISTAL = 0, 1, 2  # the stages of the pose, coarse to fine (`register.STAGE_FROM`)


def _sides(*entries: tuple[str, tuple[float, float], float, int]) -> tuple[tuple[str, tuple[float, float], float, int], ...]:
    """Each '{s}' entry for the left and the right side."""
    return tuple((name.format(s=s), bounds, start, stage) for name, bounds, start, stage in entries for s in "lr")


FINGERS = ("index", "middle", "ring", "little")
# (name, bounds in degrees, start in degrees, stage). shoulder_* are clinical (the girdle follows),
# spine.* and neck.* a region's angle shared among its vertebrae (`skeleton.stretches`), the others
# single DOFs relative to the rest pose. The bounds lie within the skeleton's ranges of motion, for a
# person standing to be scanned: the trunk bent or turned a little, the head turned, the arms anywhere
# from hanging to a T, the hands and fingers as they fall or are held.
POSE_SPEC = (
    ("spine.flexion", (-20.0, 40.0), 0.0, TRUNK),
    ("spine.lateral_bending", (-20.0, 20.0), 0.0, TRUNK),
    ("spine.rotation", (-25.0, 25.0), 0.0, TRUNK),
    *_sides(("shoulder_{s}.abduction", (0.0, 120.0), 42.0, TRUNK),
            ("shoulder_{s}.flexion", (-30.0, 60.0), 0.0, TRUNK),
            ("thigh_{s}.abduction", (-15.0, 30.0), 0.0, TRUNK),
            ("thigh_{s}.flexion", (-20.0, 40.0), 0.0, TRUNK)),
    ("neck.flexion", (-30.0, 30.0), 0.0, LIMBS),
    ("neck.lateral_bending", (-25.0, 25.0), 0.0, LIMBS),
    ("neck.rotation", (-60.0, 60.0), 0.0, LIMBS),
    *_sides(("upper_arm_{s}.internal_rotation", (-60.0, 60.0), 0.0, LIMBS),
            ("forearm_{s}.flexion", (-38.0, 60.0), 0.0, LIMBS),
            ("forearm_{s}.pronation", (-80.0, 80.0), 0.0, LIMBS),
            ("thigh_{s}.internal_rotation", (-30.0, 30.0), 0.0, LIMBS),
            ("shank_{s}.flexion", (-9.0, 60.0), 0.0, LIMBS)),
    *_sides(("hand_{s}.flexion", (-70.0, 80.0), 0.0, LIMBS),
            ("hand_{s}.radial_deviation", (-30.0, 20.0), 0.0, LIMBS),
            ("thumb_metacarpal_{s}.flexion", (-20.0, 15.0), 0.0, DISTAL),
            ("thumb_metacarpal_{s}.abduction", (0.0, 60.0), 0.0, DISTAL),
            ("thumb_phalanges_{s}.flexion", (-25.0, 20.0), 0.0, DISTAL),
            *((f"{f}_proximal_{{s}}.flexion", (-15.0, 60.0), 0.0, DISTAL) for f in FINGERS),
            *((f"{f}_proximal_{{s}}.abduction", (-15.0, 15.0), 0.0, DISTAL) for f in FINGERS),
            *((f"{f}_distal_{{s}}.flexion", (-10.0, 60.0), 0.0, DISTAL) for f in FINGERS),
            ("foot_{s}.dorsiflexion", (-30.0, 20.0), 0.0, DISTAL),
            ("foot_{s}.inversion", (-15.0, 20.0), 0.0, DISTAL),
            ("toes_{s}.flexion", (-30.0, 30.0), 0.0, DISTAL)),
)
POSE_NAMES = tuple(name for name, _, _, _ in POSE_SPEC)
POSE_STAGES = np.array([stage for *_, stage in POSE_SPEC])
STRETCH_CHANNELS = ("spine", "neck")  # pose names 'spine.flexion', 'neck.rotation', …: a region's angle
# Entries whose joints take no part in the shoulder complex or a combined limit (`skeleton.combined`:
# the spine as a whole, the two hips): a change of one moves its own DOFs and nothing else.
ALONE = ("neck.", "upper_arm_", "forearm_", "shank_", "hand_", "thumb_", *(f"{f}_" for f in FINGERS), "foot_", "toes_")
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
        return (np.radians([b[0] for _, b, _, _ in POSE_SPEC]), np.radians([b[1] for _, b, _, _ in POSE_SPEC]))

    def shape_start(self) -> np.ndarray:
        return self.shape_vector(self.base)

    @staticmethod
    def pose_start() -> np.ndarray:
        return np.radians([start for _, _, start, _ in POSE_SPEC])

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

    def poser(self, shape: np.ndarray) -> Poser:
        """The body's poser (`poser_for`); the solver's passing bodies' muscle notes are not the user's."""
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", MuscleGeometryWarning)
            return poser_for(self.body(shape))

    @classmethod
    def rest_complex(cls, poser: Poser) -> np.ndarray:
        """(D,) the shoulder complex's angles at the rest pose (`angles`' `rest`)."""
        return cls._complex(poser, cls.pose_start())

    @classmethod
    def angles(cls, poser: Poser, pose: np.ndarray, rest: np.ndarray | None = None) -> np.ndarray:
        """(D,) rest-relative joint angles of a pose vector (clamped onto the ranges of motion, silently).

        MakeHuman's rest pose holds the arms at 42° with the shoulder girdle at 0,
        where the scapulohumeral rhythm would have raised it a little: the complex's
        angles at the rest pose's own values are taken off, in full there and fading
        out by a T-pose, so that the rest pose is one the fit can reach exactly.
        `rest`: the complex's angles at the rest pose, if known (`_complex` of `pose_start`).
        """
        q = cls._complex(poser, pose)
        if rest is None:
            rest = cls.rest_complex(poser)
        names = poser.skeleton.dof_names
        for side in ("l", "r"):
            k = POSE_NAMES.index(f"shoulder_{side}.abduction")
            fade = np.clip((T_POSE - pose[k]) / (T_POSE - cls.pose_start()[k]), 0.0, 1.0)
            mine = np.array([f"_{side}." in name for name in names])
            q[mine] -= fade * rest[mine]
        return q

    @staticmethod
    def _own(poser: Poser, name: str, value: float) -> dict[str, float]:
        """The rest-relative DOF angles one pose entry (not a shoulder's) sets."""
        region, _, dof = name.partition(".")
        if region in STRETCH_CHANNELS:
            return spread(poser.skeleton, region, dof, value, f"pose {name}")
        return {name: value}

    def _probe_angles(self, poser: Poser, pose: np.ndarray, probes: list[tuple[int, float]]) -> np.ndarray:
        """(1 + n, D) joint angles of the pose and of each probe (entry, step). An entry of `ALONE` moves its
        own DOFs only, so its probe is the pose's angles with those changed; the others go through the
        shoulder complex and the combined limits again."""
        rest = self.rest_complex(poser)
        q0 = self.angles(poser, pose, rest)
        out = [q0]
        for j, step in probes:
            moved = pose.copy()
            moved[j] += step
            alone = POSE_NAMES[j].startswith(ALONE)
            out.append(self.moved_angles(poser, pose, q0, moved) if alone else self.angles(poser, moved, rest))
        return np.stack(out)

    @classmethod
    def moved_angles(cls, poser: Poser, pose: np.ndarray, q: np.ndarray, moved: np.ndarray) -> np.ndarray:
        """(D,) the joint angles of `moved`, a pose that differs from `pose` (angles `q`) in `ALONE` entries only."""
        out = q.copy()
        for j in np.flatnonzero(moved != pose):
            name = POSE_NAMES[j]
            before, after = cls._own(poser, name, float(pose[j])), cls._own(poser, name, float(moved[j]))
            for dof, value in after.items():
                out[poser.skeleton.dof_index(dof)] += value - before[dof]
        return out

    @classmethod
    def _complex(cls, poser: Poser, pose: np.ndarray) -> np.ndarray:
        clinical = {n: float(v) for n, v in zip(POSE_NAMES, pose) if n.startswith("shoulder_")}
        relative: dict[str, float] = {}
        for name, value in zip(POSE_NAMES, pose):
            if not name.startswith("shoulder_"):
                relative |= cls._own(poser, name, float(value))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", MuscleLimitWarning)
            return poser.angles(angles=relative, clinical=clinical, on_limit="clamp")

    def posed(self, poser: Poser, pose: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The skin vertices (V, 3) and rig joint centres (B, 3) of `poser`'s body in the pose."""
        q = self.angles(poser, pose)
        kin = poser.kinematics.pose(q)
        vertices = poser.pose_many(q[None])[0]
        return vertices, poser.rig_joints(kin.rotations[0], kin.translations[0])

    def jacobian(self, shape: np.ndarray, pose: np.ndarray, moving: np.ndarray | None = None,
                 poser: Poser | None = None) -> tuple[Body, Poser, np.ndarray, np.ndarray]:
        """The body, its poser, the posed skin (V, 3) and d(posed skin)/d(shape, pose) (V, 3, S + Q).

        Pose columns are finite differences of the skinned surface, for the joint
        angles `moving` (Q,) allows (all when None; the others' columns are zero).
        Shape columns are finite differences of the rest surface carried by each
        vertex's blended rotation (LBS's linear part): the joints' own move with the
        shape is left to the next iteration, which rebuilds the body.
        `poser`: the shape's poser (`poser`), if the caller has it.
        """
        poser = self.poser(shape) if poser is None else poser
        body = poser.body
        lo, hi = self.pose_bounds
        columns = np.flatnonzero(np.ones(len(pose), bool) if moving is None else moving)
        steps = np.array([POSE_STEP if pose[j] + POSE_STEP <= hi[j] else -POSE_STEP for j in columns])
        kin = poser.kinematics.pose(self._probe_angles(poser, pose, list(zip(columns, steps))))
        posed, changes = probe_changes(poser.skin, kin.rotations, kin.translations)
        n_shape = len(shape)
        jac = np.zeros((len(posed), 3, n_shape + len(pose)))
        for members, rows, moved in changes:
            jac[np.ix_(rows, np.arange(3), n_shape + columns[members])] = (
                moved / steps[members, None, None]).transpose(1, 2, 0)
        linear = (poser.skin.weights @ kin.rotations[0].reshape(-1, 9)).reshape(-1, 3, 3)
        for j in range(n_shape):
            # central differences within 0..1: every parameter's targets switch at 0.5 (MakeHuman's
            # min/average/max), where a one-sided slope would hold the solver on the side it started
            lo_probe, hi_probe = shape.copy(), shape.copy()
            lo_probe[j], hi_probe[j] = max(shape[j] - SHAPE_STEP, 0.0), min(shape[j] + SHAPE_STEP, 1.0)
            change = self.body(hi_probe).vertices - self.body(lo_probe).vertices
            jac[:, :, j] = np.einsum("vij,vj->vi", linear, change / (hi_probe[j] - lo_probe[j]))
        return body, poser, posed, jac


def probe_changes(skin: Skin, rotations: np.ndarray, translations: np.ndarray
                  ) -> tuple[np.ndarray, list[tuple[np.ndarray, np.ndarray, np.ndarray]]]:
    """The skin (V, 3) in the first of the part transforms (1 + n, N, ...), and where the others move it:
    (probes, vertices, their change (probes, vertices, 3)), by LBS, exactly as the whole skin posed in
    each would give them; every vertex not listed for a probe is where the first put it.

    A probe moves few parts (a finger's joint its finger): only the vertices weighted to a part whose
    transform differs from the first's are posed again, the probes that move the same parts together.
    """
    posed = linear_blend(skin, rotations[:1], translations[:1])[0]
    changed = ((rotations[1:] != rotations[:1]).any(axis=(2, 3))
               | (translations[1:] != translations[:1]).any(axis=2))  # (n, N)
    patterns, group = np.unique(changed, axis=0, return_inverse=True)
    # each weight's vertex and part, read off the arrays (scipy's arithmetic on the matrix would sort its
    # rows in place, and the skin's later sums would round otherwise)
    w = skin.weights
    weighted = w.data != 0
    vertex, part = np.repeat(np.arange(w.shape[0]), np.diff(w.indptr))[weighted], w.indices[weighted]
    out = []
    for k, pattern in enumerate(patterns):
        rows = np.unique(vertex[pattern[part]])
        if len(rows):
            members = np.flatnonzero(group.ravel() == k)
            moved = linear_blend(skin.part(rows), rotations[1 + members], translations[1 + members])
            out.append((members, rows, moved - posed[rows]))
    return posed, out
