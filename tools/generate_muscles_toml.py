"""Write hitogata's default muscle list, `src/hitogata/data/muscles.toml`: design the attachment points.

For each of the 57 muscle pairs the table `muscles()` gives its anatomy (the
joints and the degree of freedom it moves, which way, its moment arm or its
cylinder) and the script places its origin and insertion on the default
female body's skeleton (placed from `src/hitogata/data/skeleton.toml`) so that
the paper's equations cover the joint's whole clinical range:

- flexion (eq. 1): origin and insertion lie in the joint's plane, on the
  proximal and distal side, at the muscle's moment arm from the bones (d1, d2 =
  arm / sin β, capped at 0.8 of the bones' lengths), turned so that the
  triangle's rest angle sits mid-way in the window eq. 1 can span (0…180°)
  given the range of motion; a muscle off the midline is shifted along the
  axis by its `lateral` offset, which keeps the triangle;
- rotation (eq. 2): a helix on a cylinder of the given radius round the axis,
  from `heights[0]` below the joint to `heights[1]` above it, wound by the
  range of motion in its direction plus 40°.

Points are written in the part's frame, in part lengths (see the file's header,
`MUSCLES_HEADER`). Re-running the script reproduces the shipped file byte for
byte (a test checks it): it reads the shipped skeleton list and the body data
through hitogata, so run it with hitogata importable (the repo's .venv).

    python tools/generate_muscles_toml.py                 # rewrites the shipped file
    python tools/generate_muscles_toml.py --out /tmp/muscles.toml

Sources: origins and insertions as in the comments, after standard anatomy
texts (Gray's Anatomy; Kapandji, The Physiology of the Joints); moment arms
are round values of the published ranges (biceps 3.5 cm, quadriceps 4.5 cm,
rectus abdominis 9 cm, ...).
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from hitogata.body import default_body
from hitogata.skeleton.kinematics import axis_rotations
from hitogata.skeleton.placement import Skeleton, place_skeleton
from hitogata.skeleton.spec import load_skeleton_spec

OUT = Path(__file__).resolve().parents[1] / "src" / "hitogata" / "data" / "muscles.toml"

TRUNK = [f"lumbar_{k}" for k in range(5, 0, -1)] + [f"thoracic_{k}" for k in range(12, 0, -1)]
LUMBAR_QL = [f"lumbar_{k}" for k in range(5, 0, -1)] + ["thoracic_12"]
THORAX_IC = [f"thoracic_{k}" for k in range(11, 0, -1)]
NECK = [f"cervical_{k}" for k in range(7, 0, -1)] + ["head"]
FINGERS = ["index", "middle", "ring", "little"]
CAP = 0.8  # attachment distance from the joint, at most this fraction of the bone's length
MARGIN_DEG = 40  # rotation muscles wind this much beyond their range of motion

MUSCLES_HEADER = """\
# The default muscles of hitogata (the paper's §2.2): the active organ that poses the skeleton.
#
# One [[muscle]] per muscle. Keys:
#   name          anatomical name, _l / _r for the body's left / right
#   kind          "flexion": eq. 1, the law of cosines in the joint's plane;
#                 "rotation": eq. 2, a helix round a cylindrical bone
#   joints, dof   the parts whose joint it moves and which degree of freedom (see skeleton.toml)
#   distribution  for several joints: "range" (default; serial joints such as vertebrae share the
#                 muscle's angle in proportion to their ranges of motion in that direction, so they
#                 reach their limits together), "same" (parallel joints such as the four fingers
#                 each turn by the whole angle) or a list of shares summing to 1
#   origin        { part, at }: a point fixed in a part, in that part's frame (x the body's left,
#   insertion     y along the part, z its front; or the world axes for frame = "world" parts),
#                 in units of the part's length; the origin is on the proximal side of the joints
#   radius        rotation only: radius of the cylinder it winds round, metres
#   handedness    rotation only: "right" or "left", the sense of the helix from origin to insertion
#                 (mirror images: a left muscle and its right twin have opposite handedness)
#   antagonist    the muscle that moves the same joints the other way
#
# How the points were placed. The paper's triangle (eq. 1) is straight, while real muscles wrap
# over bones and pulleys; anatomical attachment points would collapse the triangle before the
# joint reaches its clinical range (a biceps at the radial tuberosity could not flex the elbow
# to 150°). So each flexion muscle's origin and insertion lie in its joint's plane, on its side
# of the joint, at about the muscle's moment arm from the bones (biceps 3.5 cm, quadriceps
# 4.5 cm, rectus abdominis 9 cm ...), turned so that the triangle spans the joint's whole range
# of motion with a margin; each rotation muscle winds round its cylinder by its joint's range
# plus 40°. Positions were computed on the default female body and are checked on both default
# bodies by the tests. The comments name each muscle's anatomical origin and insertion.
# Muscles spanning several joints in reality (biceps, hamstrings, gastrocnemius) span one
# joint here; trunk and neck muscles span the vertebral joints they move.
"""


@dataclass(frozen=True)
class Design:
    """One muscle's anatomy and design parameters.

    sense: +1 if contracting it turns the DOF positive. Flexion: `arm` (m), `lateral`
    offset along the axis (m). Rotation: `radius` (m), `heights` below / above the
    joint (m), `start` the direction (body frame) the helix starts from.
    """

    name: str
    kind: str
    joints: list[str]
    dof: str
    sense: int
    origin: str
    insertion: str
    antagonist: str
    comment: str
    arm: float = 0.0
    lateral: float = 0.0
    distribution: str = "range"
    radius: float = 0.0
    heights: tuple[float, float] = (0.0, 0.0)
    start: list[float] = field(default_factory=lambda: [0.0, 0.0, 1.0])


def muscles() -> list[Design]:
    """The table: both sides of every muscle, in the order they were designed."""
    out: list[Design] = []
    for s, S in (("l", 1), ("r", -1)):
        o = "r" if s == "l" else "l"

        def add(name: str, kind: str, joints: list[str], dof: str, sense: int, origin: str, insertion: str,
                antagonist: str, comment: str, **kw) -> None:
            out.append(Design(name, kind, joints, dof, sense, origin, insertion, antagonist, comment, **kw))

        # trunk
        add(f"rectus_abdominis_{s}", "flexion", TRUNK, "flexion", +1, "pelvis", "thoracic_1", f"erector_spinae_{s}",
            "pubic crest -> xiphoid and costal cartilages 5-7 (the rib cage carries its pull to the upper thoracic spine)",
            lateral=0.04, arm=0.09)
        add(f"erector_spinae_{s}", "flexion", TRUNK, "flexion", -1, "pelvis", "thoracic_1", f"rectus_abdominis_{s}",
            "sacrum, iliac crest -> ribs and thoracic spinous processes (longissimus, spinalis)", lateral=0.04, arm=0.05)
        add(f"quadratus_lumborum_{s}", "flexion", LUMBAR_QL, "lateral_bending", S, "pelvis", "thoracic_12",
            f"quadratus_lumborum_{o}", "iliac crest -> rib 12 and the L1-L4 transverse processes", arm=0.06)
        add(f"iliocostalis_thoracis_{s}", "flexion", THORAX_IC, "lateral_bending", S, "thoracic_12", "thoracic_1",
            f"iliocostalis_thoracis_{o}", "ribs 7-12 -> ribs 1-6: bends the thorax to its side", arm=0.07)
        add(f"external_oblique_{s}", "rotation", TRUNK, "rotation", -S, "pelvis", "thoracic_1", f"external_oblique_{o}",
            "ribs 5-12 -> iliac crest and linea alba: turns the trunk to the other side",
            radius=0.12, heights=(0.12, 0.12), start=[S, 0, 1])
        # neck
        add(f"longus_colli_{s}", "flexion", NECK, "flexion", +1, "thoracic_1", "head", f"semispinalis_capitis_{s}",
            "T1-T3 and cervical bodies -> atlas and occiput (with longus capitis)", lateral=0.01, arm=0.02)
        add(f"semispinalis_capitis_{s}", "flexion", NECK, "flexion", -1, "thoracic_1", "head", f"longus_colli_{s}",
            "C4-T6 transverse processes -> occiput: extends head and neck", lateral=0.02, arm=0.04)
        add(f"splenius_capitis_{s}", "flexion", NECK, "lateral_bending", S, "thoracic_1", "head", f"splenius_capitis_{o}",
            "ligamentum nuchae, C7-T3 spinous processes -> mastoid: bends the neck to its side", arm=0.04)
        add(f"sternocleidomastoid_{s}", "rotation", NECK, "rotation", -S, "thoracic_2", "head", f"sternocleidomastoid_{o}",
            "manubrium and medial clavicle -> mastoid: winds round the neck, turns the face to the other side",
            radius=0.05, heights=(0.11, 0.03), start=[0.3 * S, 0, 1])
        add(f"masseter_{s}", "flexion", ["jaw"], "depression", -1, "head", "jaw", f"digastric_{s}",
            "zygomatic arch -> angle of the mandible: closes the mouth", lateral=0.05, arm=0.025)
        add(f"digastric_{s}", "flexion", ["jaw"], "depression", +1, "head", "jaw", f"masseter_{s}",
            "mastoid notch -> digastric fossa of the mandible: opens the mouth", lateral=0.02, arm=0.02)
        # shoulder girdle
        add(f"trapezius_upper_{s}", "flexion", [f"clavicle_{s}"], "elevation", +1, "thoracic_2", f"clavicle_{s}",
            f"subclavius_{s}", "occiput and ligamentum nuchae -> lateral third of the clavicle: elevates the girdle",
            arm=0.04)
        add(f"subclavius_{s}", "flexion", [f"clavicle_{s}"], "elevation", -1, "thoracic_2", f"clavicle_{s}",
            f"trapezius_upper_{s}", "first rib -> underside of the clavicle: depresses it", arm=0.02)
        add(f"serratus_anterior_{s}", "flexion", [f"clavicle_{s}"], "protraction", +1, "thoracic_2", f"clavicle_{s}",
            f"rhomboid_major_{s}", "ribs 1-8 -> medial border of the scapula: protracts the girdle", arm=0.04)
        add(f"rhomboid_major_{s}", "flexion", [f"clavicle_{s}"], "protraction", -1, "thoracic_2", f"clavicle_{s}",
            f"serratus_anterior_{s}", "T2-T5 spinous processes -> medial border of the scapula: retracts it", arm=0.04)
        add(f"trapezius_lower_{s}", "flexion", [f"scapula_{s}"], "upward_rotation", +1, f"clavicle_{s}", f"scapula_{s}",
            f"levator_scapulae_{s}", "T4-T12 spinous processes -> spine of the scapula: rotates it upwards", arm=0.03)
        add(f"levator_scapulae_{s}", "flexion", [f"scapula_{s}"], "upward_rotation", -1, f"clavicle_{s}", f"scapula_{s}",
            f"trapezius_lower_{s}", "C1-C4 transverse processes -> superior angle of the scapula: rotates it downwards",
            arm=0.03)
        # shoulder
        arm_ = [f"upper_arm_{s}"]
        add(f"pectoralis_major_{s}", "flexion", arm_, "flexion", +1, f"scapula_{s}", f"upper_arm_{s}",
            f"latissimus_dorsi_{s}",
            "clavicle and sternum -> lateral lip of the bicipital groove (the clavicular head flexes)", arm=0.04)
        add(f"latissimus_dorsi_{s}", "flexion", arm_, "flexion", -1, f"scapula_{s}", f"upper_arm_{s}",
            f"pectoralis_major_{s}",
            "T7-L5 spinous processes, iliac crest -> floor of the bicipital groove: extends the arm", arm=0.04)
        add(f"deltoid_{s}", "flexion", arm_, "abduction", +1, f"scapula_{s}", f"upper_arm_{s}", f"teres_major_{s}",
            "acromion and spine of the scapula -> deltoid tuberosity: abducts the arm", arm=0.035)
        add(f"teres_major_{s}", "flexion", arm_, "abduction", -1, f"scapula_{s}", f"upper_arm_{s}", f"deltoid_{s}",
            "inferior angle of the scapula -> medial lip of the bicipital groove: adducts the arm", arm=0.035)
        add(f"subscapularis_{s}", "rotation", arm_, "internal_rotation", +1, f"scapula_{s}", f"upper_arm_{s}",
            f"infraspinatus_{s}", "subscapular fossa -> lesser tubercle, winding round the front of the humeral head",
            radius=0.025, heights=(0.03, 0.04), start=[0, 0, 1])
        add(f"infraspinatus_{s}", "rotation", arm_, "internal_rotation", -1, f"scapula_{s}", f"upper_arm_{s}",
            f"subscapularis_{s}", "infraspinous fossa -> greater tubercle, round the back of the humeral head",
            radius=0.025, heights=(0.03, 0.04), start=[0, 0, -1])
        # elbow and forearm
        fore = [f"forearm_{s}"]
        add(f"biceps_brachii_{s}", "flexion", fore, "flexion", +1, f"upper_arm_{s}", f"forearm_{s}",
            f"triceps_brachii_{s}",
            "supraglenoid tubercle and coracoid -> radial tuberosity (the model spans the elbow only)", arm=0.035)
        add(f"triceps_brachii_{s}", "flexion", fore, "flexion", -1, f"upper_arm_{s}", f"forearm_{s}",
            f"biceps_brachii_{s}", "infraglenoid tubercle and back of the humerus -> olecranon", arm=0.02)
        add(f"pronator_teres_{s}", "rotation", fore, "pronation", +1, f"upper_arm_{s}", f"forearm_{s}", f"supinator_{s}",
            "medial epicondyle -> lateral surface of the radius, across the front of the forearm",
            radius=0.015, heights=(0.02, 0.10), start=[-S, 0, 0])
        add(f"supinator_{s}", "rotation", fore, "pronation", -1, f"upper_arm_{s}", f"forearm_{s}", f"pronator_teres_{s}",
            "lateral epicondyle -> radius, wound round its neck from behind",
            radius=0.015, heights=(0.02, 0.06), start=[S, 0, 0])
        # wrist
        hand = [f"hand_{s}"]
        add(f"flexor_carpi_radialis_{s}", "flexion", hand, "flexion", +1, f"forearm_{s}", f"hand_{s}",
            f"extensor_carpi_radialis_brevis_{s}", "medial epicondyle -> base of the 2nd metacarpal", arm=0.015)
        add(f"extensor_carpi_radialis_brevis_{s}", "flexion", hand, "flexion", -1, f"forearm_{s}", f"hand_{s}",
            f"flexor_carpi_radialis_{s}", "lateral epicondyle -> base of the 3rd metacarpal", arm=0.015)
        add(f"extensor_carpi_radialis_longus_{s}", "flexion", hand, "radial_deviation", +1, f"forearm_{s}", f"hand_{s}",
            f"flexor_carpi_ulnaris_{s}",
            "lateral supracondylar ridge -> base of the 2nd metacarpal: deviates the hand radially", arm=0.015)
        add(f"flexor_carpi_ulnaris_{s}", "flexion", hand, "radial_deviation", -1, f"forearm_{s}", f"hand_{s}",
            f"extensor_carpi_radialis_longus_{s}",
            "medial epicondyle, olecranon -> pisiform, hamate, 5th metacarpal: deviates it ulnarly", arm=0.015)
        # thumb
        cmc, thumb = [f"thumb_metacarpal_{s}"], f"thumb_metacarpal_{s}"
        add(f"flexor_pollicis_brevis_{s}", "flexion", cmc, "flexion", +1, f"hand_{s}", thumb,
            f"extensor_pollicis_brevis_{s}", "flexor retinaculum, trapezium -> base of the thumb's proximal phalanx",
            arm=0.01)
        add(f"extensor_pollicis_brevis_{s}", "flexion", cmc, "flexion", -1, f"hand_{s}", thumb,
            f"flexor_pollicis_brevis_{s}", "radius, interosseous membrane -> base of the thumb's proximal phalanx",
            arm=0.01)
        add(f"abductor_pollicis_longus_{s}", "flexion", cmc, "abduction", +1, f"hand_{s}", thumb,
            f"adductor_pollicis_{s}", "ulna, radius, interosseous membrane -> base of the 1st metacarpal", arm=0.01)
        add(f"adductor_pollicis_{s}", "flexion", cmc, "abduction", -1, f"hand_{s}", thumb,
            f"abductor_pollicis_longus_{s}",
            "capitate, 2nd and 3rd metacarpals -> base of the thumb's proximal phalanx", arm=0.01)
        mcp, phalanges = [f"thumb_phalanges_{s}"], f"thumb_phalanges_{s}"
        add(f"flexor_pollicis_longus_{s}", "flexion", mcp, "flexion", +1, thumb, phalanges,
            f"extensor_pollicis_longus_{s}", "radius -> base of the thumb's distal phalanx", arm=0.008)
        add(f"extensor_pollicis_longus_{s}", "flexion", mcp, "flexion", -1, thumb, phalanges,
            f"flexor_pollicis_longus_{s}", "ulna -> base of the thumb's distal phalanx", arm=0.008)
        # fingers (one tendon per finger, each finger turning alike)
        prox = [f"{f}_proximal_{s}" for f in FINGERS]
        dist = [f"{f}_distal_{s}" for f in FINGERS]
        index_p, index_d = f"index_proximal_{s}", f"index_distal_{s}"
        add(f"flexor_digitorum_superficialis_{s}", "flexion", prox, "flexion", +1, f"hand_{s}", index_p,
            f"extensor_digitorum_{s}", "medial epicondyle, radius -> middle phalanges: flexes the knuckles",
            arm=0.01, distribution="same")
        add(f"extensor_digitorum_{s}", "flexion", prox, "flexion", -1, f"hand_{s}", index_p,
            f"flexor_digitorum_superficialis_{s}", "lateral epicondyle -> extensor expansions of the four fingers",
            arm=0.01, distribution="same")
        add(f"dorsal_interossei_{s}", "flexion", prox, "abduction", +1, f"hand_{s}", index_p, f"palmar_interossei_{s}",
            "between the metacarpals -> proximal phalanges: spread the fingers (with abductor digiti minimi)",
            arm=0.008, distribution="same")
        add(f"palmar_interossei_{s}", "flexion", prox, "abduction", -1, f"hand_{s}", index_p, f"dorsal_interossei_{s}",
            "2nd, 4th, 5th metacarpals -> proximal phalanges: close the fingers", arm=0.008, distribution="same")
        add(f"flexor_digitorum_profundus_{s}", "flexion", dist, "flexion", +1, index_p, index_d, f"lumbricals_{s}",
            "ulna -> distal phalanges: flexes the interphalangeal joints", arm=0.008, distribution="same")
        add(f"lumbricals_{s}", "flexion", dist, "flexion", -1, index_p, index_d, f"flexor_digitorum_profundus_{s}",
            "profundus tendons -> extensor expansions: straighten the interphalangeal joints",
            arm=0.006, distribution="same")
        # hip
        hip = [f"thigh_{s}"]
        add(f"iliopsoas_{s}", "flexion", hip, "flexion", +1, "pelvis", f"thigh_{s}", f"gluteus_maximus_{s}",
            "T12-L4 vertebrae and iliac fossa -> lesser trochanter", arm=0.05)
        add(f"gluteus_maximus_{s}", "flexion", hip, "flexion", -1, "pelvis", f"thigh_{s}", f"iliopsoas_{s}",
            "ilium, sacrum, coccyx -> gluteal tuberosity and iliotibial tract", arm=0.06)
        add(f"gluteus_medius_{s}", "flexion", hip, "abduction", +1, "pelvis", f"thigh_{s}", f"adductor_magnus_{s}",
            "outer ilium -> greater trochanter: abducts the thigh", arm=0.05)
        add(f"adductor_magnus_{s}", "flexion", hip, "abduction", -1, "pelvis", f"thigh_{s}", f"gluteus_medius_{s}",
            "ischiopubic ramus, ischial tuberosity -> linea aspera, adductor tubercle (with the other adductors)",
            arm=0.05)
        add(f"gluteus_minimus_{s}", "rotation", hip, "internal_rotation", +1, "pelvis", f"thigh_{s}", f"piriformis_{s}",
            "outer ilium -> front of the greater trochanter: turns the thigh inwards",
            radius=0.04, heights=(0.06, 0.06), start=[S, 0, 0])
        add(f"piriformis_{s}", "rotation", hip, "internal_rotation", -1, "pelvis", f"thigh_{s}", f"gluteus_minimus_{s}",
            "front of the sacrum -> greater trochanter (with the deep rotators): turns the thigh outwards",
            radius=0.04, heights=(0.06, 0.06), start=[0, 0, -1])
        # knee
        knee = [f"shank_{s}"]
        add(f"hamstrings_{s}", "flexion", knee, "flexion", +1, f"thigh_{s}", f"shank_{s}", f"quadriceps_{s}",
            "ischial tuberosity -> tibia and fibula heads (the model spans the knee only)", arm=0.03)
        add(f"quadriceps_{s}", "flexion", knee, "flexion", -1, f"thigh_{s}", f"shank_{s}", f"hamstrings_{s}",
            "ilium and femur -> patella -> tibial tuberosity", arm=0.045)
        # ankle and foot
        ankle, toes = [f"foot_{s}"], [f"toes_{s}"]
        add(f"tibialis_anterior_{s}", "flexion", ankle, "dorsiflexion", +1, f"shank_{s}", f"foot_{s}",
            f"gastrocnemius_{s}", "lateral tibia -> medial cuneiform, 1st metatarsal: lifts the foot", arm=0.035)
        add(f"gastrocnemius_{s}", "flexion", ankle, "dorsiflexion", -1, f"shank_{s}", f"foot_{s}",
            f"tibialis_anterior_{s}", "femoral condyles -> calcaneus by the Achilles tendon (with soleus)", arm=0.05)
        add(f"tibialis_posterior_{s}", "flexion", ankle, "inversion", +1, f"shank_{s}", f"foot_{s}",
            f"fibularis_longus_{s}", "back of tibia and fibula -> navicular and cuneiforms: inverts the foot", arm=0.025)
        add(f"fibularis_longus_{s}", "flexion", ankle, "inversion", -1, f"shank_{s}", f"foot_{s}",
            f"tibialis_posterior_{s}",
            "fibula -> medial cuneiform, 1st metatarsal, under the sole: everts the foot", arm=0.025)
        add(f"flexor_digitorum_longus_{s}", "flexion", toes, "flexion", +1, f"foot_{s}", f"toes_{s}",
            f"extensor_digitorum_longus_{s}",
            "back of the tibia -> distal phalanges of toes 2-5 (with flexor hallucis longus)", arm=0.012)
        add(f"extensor_digitorum_longus_{s}", "flexion", toes, "flexion", -1, f"foot_{s}", f"toes_{s}",
            f"flexor_digitorum_longus_{s}",
            "tibia, fibula -> dorsal expansions of toes 2-5 (with extensor hallucis longus)", arm=0.012)
    return out


def unit(v: np.ndarray) -> np.ndarray:
    n = np.linalg.norm(v)
    if n < 1e-9:
        raise ValueError(f"cannot normalise {v}")
    return v / n


def perp(v: np.ndarray, u: np.ndarray) -> np.ndarray:
    """v without its component along the unit vector u."""
    return v - (v @ u) * u


def rotate(u: np.ndarray, angle: float, v: np.ndarray) -> np.ndarray:
    return axis_rotations(u[None], np.array([angle]))[0] @ v


def signed(a: np.ndarray, b: np.ndarray, u: np.ndarray) -> float:
    """The angle from a to b about u."""
    return float(np.arctan2(u @ np.cross(a, b), a @ b))


def wrap(x: float) -> float:
    return (x + np.pi) % (2 * np.pi) - np.pi


class Designer:
    """Places muscles on one skeleton."""

    def __init__(self, sk: Skeleton):
        self.sk = sk

    def equivalent(self, m: Design) -> tuple[np.ndarray, np.ndarray, float, float, np.ndarray]:
        """The muscle's equivalent joint: centre, axis, range (rest-relative) and the DOFs' parts."""
        sk = self.sk
        dofs = np.array([sk.dof_index(f"{j}.{m.dof}") for j in m.joints])
        lo, hi = sk.lower[dofs], sk.upper[dofs]
        parts = sk.dof_parts[dofs]
        if m.distribution == "same":
            w, low, high = np.eye(len(m.joints))[0], lo.max(), hi.min()
        else:
            w, low, high = (hi - lo) / (hi - lo).sum(), lo.sum(), hi.sum()
        return w @ sk.joints[parts], unit(w @ sk.dof_axes[dofs]), low, high, parts

    def to_part(self, part: str, p: np.ndarray) -> np.ndarray:
        """A point in a part's frame, in part lengths."""
        i = self.sk.index(part)
        return np.linalg.solve(self.sk.bases[i], p - self.sk.joints[i])

    def directions(
        self, m: Design, u: np.ndarray, a: np.ndarray, parts: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, float, float]:
        """Unit proximal and distal directions in the joint's plane, and the bone lengths along them."""
        sk = self.sk
        if len(m.joints) > 1 and m.joints[0] != m.joints[-1]:
            prox_point, dist_point = sk.joints[sk.index(m.origin)], sk.tails[sk.index(m.insertion)]
        else:
            prox_point, dist_point = sk.joints[sk.parents[parts[0]]], sk.tails[parts[0]]
        c, c_len = perp(dist_point - a, u), np.linalg.norm(dist_point - a)
        pv, p_len = perp(prox_point - a, u), np.linalg.norm(prox_point - a)
        if np.linalg.norm(c) < 0.3 * c_len:  # the DOF turns the part about its own axis
            c = -pv
        c = unit(c)
        if np.linalg.norm(pv) < 0.3 * p_len or p_len < 1e-6:
            pv, p_len = -c, max(p_len, c_len)
        return unit(pv), c, p_len, c_len

    def flexion(self, m: Design) -> tuple[np.ndarray, np.ndarray, str | None]:
        """Origin and insertion of a flexion muscle (eq. 1)."""
        a, u, low, high, parts = self.equivalent(m)
        p, c, p_len, c_len = self.directions(m, u, a, parts)
        window, sign = ((high, np.pi + low), -1) if m.sense > 0 else ((-low, np.pi - high), +1)
        if window[1] <= window[0]:
            raise ValueError(f"{m.name}: eq. 1 cannot span the range {np.degrees(window)}")
        alpha0 = sign * (window[0] + 0.5 * (window[1] - window[0]))  # rest angle mid-way in the window
        beta = wrap(signed(p, c, u) - alpha0) / 2
        d1 = min(m.arm / abs(np.sin(beta)), CAP * p_len)
        d2 = min(m.arm / abs(np.sin(beta)), CAP * c_len)
        d, e = a + d1 * rotate(u, beta, p), a + d2 * rotate(u, -beta, c)
        side = np.sign(u[0]) * m.lateral * (1 if m.name.endswith("_l") else -1)
        return d + side * u, e + side * u, None

    def rotation(self, m: Design) -> tuple[np.ndarray, np.ndarray, str | None]:
        """Origin, insertion and handedness of a rotation muscle (eq. 2)."""
        a, u, low, high, parts = self.equivalent(m)
        sd = np.sign(u @ (self.sk.tails[parts[-1]] - a))
        z_o, z_i = -m.heights[0] * sd, m.heights[1] * sd
        rise = z_i - z_o
        phi0 = (high if m.sense > 0 else -low) + np.radians(MARGIN_DEG)
        if phi0 >= 2 * np.pi - 0.1:
            raise ValueError(f"{m.name}: the helix would wind a full turn ({np.degrees(phi0):.0f}°)")
        h = -m.sense * np.sign(rise)
        n0 = unit(perp(np.array(m.start, dtype=float), u))
        o = a + z_o * u + m.radius * n0
        i = a + z_i * u + m.radius * rotate(u, h * np.sign(rise) * phi0, n0)
        return o, i, "right" if h > 0 else "left"


def point(v: np.ndarray) -> str:
    return "[" + ", ".join(f"{x:.4f}".rstrip("0").rstrip(".") if abs(x) > 5e-5 else "0" for x in v) + "]"


def entry(designer: Designer, m: Design) -> list[str]:
    """The lines of one [[muscle]] entry, after a blank line."""
    o, i, handed = designer.flexion(m) if m.kind == "flexion" else designer.rotation(m)
    lines = ["", f"# {m.comment}", "[[muscle]]", f'name = "{m.name}"', f'kind = "{m.kind}"',
             "joints = [" + ", ".join(f'"{j}"' for j in m.joints) + "]", f'dof = "{m.dof}"']
    if m.distribution == "same":
        lines.append('distribution = "same"')
    lines.append(f'origin = {{ part = "{m.origin}", at = {point(designer.to_part(m.origin, o))} }}')
    lines.append(f'insertion = {{ part = "{m.insertion}", at = {point(designer.to_part(m.insertion, i))} }}')
    if m.kind == "rotation":
        lines += [f"radius = {m.radius}", f'handedness = "{handed}"']
    return lines + [f'antagonist = "{m.antagonist}"']


def muscles_toml() -> str:
    """The whole file's text: left and right of each muscle next to each other."""
    table = muscles()
    first: dict[str, int] = {}
    for k, m in enumerate(table):
        first.setdefault(m.name[:-2], k)
    order = sorted(range(len(table)), key=lambda k: (first[table[k].name[:-2]], table[k].name[-1] != "l"))
    designer = Designer(place_skeleton(load_skeleton_spec(), default_body("female").rig))
    lines = [MUSCLES_HEADER.rstrip("\n")]
    for k in order:
        lines += entry(designer, table[k])
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=OUT, help=f"default: {OUT}")
    args = parser.parse_args()
    args.out.write_text(muscles_toml(), encoding="utf-8")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
