"""Write hitogata's default skeleton list, `src/hitogata/data/skeleton.toml`, from its sources.

The list (65 parts, 140 degrees of freedom) is data a person may edit by hand;
this script records how the shipped file was made, and re-running it
reproduces that file byte for byte (a test checks it). It needs nothing but
numpy.

    python tools/generate_skeleton_toml.py                 # rewrites the shipped file
    python tools/generate_skeleton_toml.py --out /tmp/skeleton.toml

Sources (repeated in the file's header):
- limb ranges of motion: AAOS averages (Greene & Heckman, The Clinical Measurement
  of Joint Motion, AAOS 1994; as tabulated in Norkin & White, Measurement of Joint
  Motion); shoulder elevation shared 2 : 1 between the glenohumeral joint and the
  scapula (Inman, Saunders & Abbott, JBJS 1944); girdle ranges after Kapandji;
- vertebral segments: the AAOS regional ranges shared among the segments in
  proportion to White & Panjabi's representative segmental ranges (Clinical
  Biomechanics of the Spine, 2nd ed., 1990, ch. 2), the table `SEGMENT_ROM` below;
- vertebral joint centres: Gray's proportions (cervical 12.5 cm, thoracic 28 cm,
  lumbar 18 cm), ANSUR II heights for L5/S1, vertebral body heights after
  Panjabi et al. (Spine 1991) for the thoracic segments;
- rest angles: measured on the default female and male bodies (MakeHuman A-pose).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

OUT = Path(__file__).resolve().parents[1] / "src" / "hitogata" / "data" / "skeleton.toml"

# White & Panjabi 1990, representative segmental ranges (degrees):
# flexion + extension combined, lateral bending to one side, axial rotation to one side.
SEGMENT_ROM = {
    "C0/C1": (25, 5, 5), "C1/C2": (20, 5, 40), "C2/C3": (10, 10, 3), "C3/C4": (15, 11, 7), "C4/C5": (20, 11, 7),
    "C5/C6": (20, 8, 7), "C6/C7": (17, 7, 6), "C7/T1": (9, 4, 2),
    "T1/T2": (4, 6, 9), "T2/T3": (4, 6, 8), "T3/T4": (4, 6, 8), "T4/T5": (4, 6, 8), "T5/T6": (4, 6, 8),
    "T6/T7": (5, 6, 8), "T7/T8": (6, 6, 8), "T8/T9": (6, 6, 7), "T9/T10": (6, 6, 4), "T10/T11": (9, 7, 2),
    "T11/T12": (12, 9, 2), "T12/L1": (12, 8, 2), "L1/L2": (12, 6, 2), "L2/L3": (14, 6, 2), "L3/L4": (15, 8, 2),
    "L4/L5": (16, 6, 2), "L5/S1": (17, 3, 1),
}
# AAOS regional ranges (degrees): flexion, extension, lateral bending and rotation to each side.
REGION_ROM = {"cervical": (45, 45, 45, 60), "thoracolumbar": (80, 25, 35, 45)}

LUMBAR = [f"L{k}" for k in range(5, 0, -1)]
THORACIC = [f"T{k}" for k in range(12, 0, -1)]
CERVICAL = [f"C{k}" for k in range(7, 0, -1)]

L5_S1_FRACTION = 0.18  # of the rig's spine chain (pelvis joint → neck joint): see the header
LUMBAR_CM, THORACIC_CM = 18.0, 28.0
CERVICAL_CM = {"C7": 1.9, "C6": 1.9, "C5": 1.9, "C4": 1.9, "C3": 1.9, "C2": 2.0, "C1": 1.0}  # shares, C7/T1 upward

MIRROR = {"x": "x", "X": "X", "hinge": "hinge", "y": "-y", "Y": "-Y", "z": "-z", "Z": "-Z", "long": "-long"}  # left-side axis → right side

HEADER = """\
# The default skeleton of hitogata: 65 parts, pelvis at the root (the paper's §2.1).
#
# One [[part]] per part. Keys:
#   name, parent        the part and the part it hangs from (the root has no parent)
#   joint               its joint centre on the MakeHuman rig:
#                         { bone = "b" }  head of a rig bone ({ bone = "b", at = "tail" } for its tail)
#                         { bones = ["a", "b"], at = "head" }  the mean of several bone ends
#                         { between = ["a", "b"], at = f }  arc-length fraction f along the rig's
#                           chain of bone heads from bone a's head to bone b's head
#   tail                its far end (same forms, or { part = "p" }: that part's joint centre);
#                       default: the joint centre of its only child
#   frame               "bone" (default): y along the part (joint -> tail), z the body's front made
#                       perpendicular to it, x perpendicular to both towards the body's left;
#                       "world": the body's axes (x left, y up, z front)
#   bones               MakeHuman bones whose skinning weights this part takes; a bone listed nowhere
#                       goes with its nearest listed ancestor (face -> head, tongue -> jaw)
#   dof                 the joint's degrees of freedom, applied in list order (intrinsic):
#                       name; axis in the part's frame: x, y, z, or in the body's: X, Y, Z;
#                       long (the part's own axis), hinge (normal to the parent's and the
#                       part's axes, towards the body's left),
#                       each optionally negated ("-z"); min, max = clinical range of motion in
#                       degrees (0 = anatomical position); rest = the clinical angle of the rest pose
#                       (default 0; "measured" for a hinge: the bend between the part and its parent).
# [[shared]] lists rig bones whose weights are shared along a chain of parts by where each
# vertex lies along the chain (the rig's 5 spine and 3 neck bones cover 24 vertebrae).
#
# Sign conventions (positive direction): flexion forward, lateral bending to the body's left,
# rotation turning the face to the left; limbs: flexion, abduction, internal rotation, pronation.
# Right-side axes mirror the left: x, X and hinge keep their sign, y, Y, z, Z and long flip.
#
# Sources. Limb ranges: AAOS averages (Greene & Heckman, The Clinical Measurement of Joint
# Motion, AAOS 1994; as tabulated in Norkin & White, Measurement of Joint Motion).
# Vertebral segments: the AAOS regional ranges (cervical: flexion 45, extension 45, lateral
# bending 45, rotation 60; thoracolumbar: 80, 25, 35, 45) shared among the segments in
# proportion to White & Panjabi's representative segmental values (Clinical Biomechanics of
# the Spine, 2nd ed., 1990, ch. 2), e.g. L4/L5 flexion-extension 16, lateral 6, rotation 2.
# Shoulder: the AAOS elevation of 180° is shared 2 : 1 between the glenohumeral joint and the
# scapula (scapulohumeral rhythm: Inman, Saunders & Abbott, JBJS 1944); girdle ranges approximate,
# after Kapandji (The Physiology of the Joints, vol. 1).
# Rest angles: measured on the default female and male bodies (MakeHuman A-pose).
#
# Vertebral joint centres (proportions of Gray's Anatomy: cervical 12.5 cm, thoracic 28 cm,
# lumbar 18 cm): L5/S1 sits 18 % of the way up the rig's spine chain from the pelvis joint
# (hip-joint level) to the neck joint (C7/T1) -- the iliac crests (the supracristal plane, L4/L5)
# stand about 0.60 of stature high against 0.52 for the hip joints and 0.85 for C7 (ANSUR II
# iliocristale, trochanterion and cervicale heights), one lumbar segment lower gives 0.18.
# Above it the lumbar segments are equal, the thoracic ones grow linearly from T1 to T12
# (1 : 1.5, vertebral body heights after Panjabi et al., Spine 1991); the cervical chain runs
# from the neck joint to the head joint with C3-C7 1.9, C2 2.0 and C1 1.0 cm shares.
"""


def segment(vertebra: str) -> str:
    """The motion segment a vertebra's joint is: with the vertebra below ('C0' is the occiput)."""
    below = {"L5": "S1", "T12": "L1", "C7": "T1", "C0": "C1"}
    number = int(vertebra[1:])
    return f"{vertebra}/{below.get(vertebra, f'{vertebra[0]}{number + 1}')}"


def segment_ranges() -> dict[str, tuple[float, float, float, float]]:
    """(flexion, extension, lateral bending, rotation) per segment: regional ranges shared by White & Panjabi."""
    out = {}
    groups = (
        ("thoracolumbar", [segment(v) for v in LUMBAR + THORACIC]),
        ("cervical", [segment(v) for v in CERVICAL + ["C0"]]),
    )
    for region, names in groups:
        fl, ex, lat, rot = REGION_ROM[region]
        fe, lb, ar = (np.array([SEGMENT_ROM[n][c] for n in names], float) for c in range(3))
        for i, n in enumerate(names):
            out[n] = (fl * fe[i] / fe.sum(), ex * fe[i] / fe.sum(), lat * lb[i] / lb.sum(), rot * ar[i] / ar.sum())
    return out


def joint_fractions() -> dict[str, float]:
    """Each vertebra's joint as an arc-length fraction along its rig chain (see the header)."""
    pos = {}
    lumbar_share = (1 - L5_S1_FRACTION) * LUMBAR_CM / (LUMBAR_CM + THORACIC_CM)
    for k, v in enumerate(LUMBAR):
        pos[v] = L5_S1_FRACTION + lumbar_share * k / 5
    weights = np.array([1 + 0.5 * (k - 1) / 11 for k in range(12, 0, -1)])  # T12 … T1: 1.5 … 1
    cumulative = np.concatenate([[0], np.cumsum(weights)]) / weights.sum()
    for k, v in enumerate(THORACIC):
        pos[v] = L5_S1_FRACTION + lumbar_share + (1 - L5_S1_FRACTION - lumbar_share) * cumulative[k]
    total, acc = sum(CERVICAL_CM.values()), 0.0
    for v in CERVICAL:
        pos[v] = acc / total
        acc += CERVICAL_CM[v]
    return pos


def number(x: float) -> str:
    """Degrees as written in the file: an integer, or one decimal."""
    return f"{x:.1f}".rstrip("0").rstrip(".") if abs(x - round(x)) > 1e-9 else f"{int(round(x))}"


def dof(name: str, axis: str, lo: float, hi: float, rest: float | str = 0.0, comment: str = "") -> str:
    """One `dof = [...]` entry line."""
    line = f'  {{ name = "{name}", axis = "{axis}", min = {number(lo)}, max = {number(hi)}'
    if rest:
        line += ', rest = "measured"' if rest == "measured" else f", rest = {number(rest)}"
    line += " },"
    return line + (f"  # {comment}" if comment else "")


def part(
    name: str,
    parent: str | None = None,
    *,
    joint: str,
    tail: str | None = None,
    frame: str | None = None,
    bones: list[str] | None = None,
    dofs: list[str] | tuple[str, ...] = (),
    comment: str | None = None,
) -> list[str]:
    """The lines of one [[part]] entry, after a blank line."""
    lines = [""] + ([f"# {comment}"] if comment else []) + ["[[part]]", f'name = "{name}"']
    lines += [f'parent = "{parent}"'] if parent else []
    lines.append(f"joint = {joint}")
    lines += [f"tail = {tail}"] if tail else []
    lines += [f'frame = "{frame}"'] if frame else []
    lines += ["bones = [" + ", ".join(f'"{b}"' for b in bones) + "]"] if bones else []
    if dofs:
        lines += ["dof = [", *dofs, "]"]
    return lines


def spine_dofs(name: str, ranges: dict[str, tuple[float, float, float, float]]) -> list[str]:
    fl, ex, lat, rot = ranges[name]
    return [
        dof("flexion", "x", -ex, fl, comment=name),
        dof("lateral_bending", "-z", -lat, lat),
        dof("rotation", "y", -rot, rot),
    ]


def axial() -> list[str]:
    """Pelvis, 24 vertebrae, head and jaw."""
    ranges, pos = segment_ranges(), joint_fractions()
    out = ["", "# ---- axial skeleton ----"]
    out += part("pelvis", joint=head_of("spine05"), tail='{ part = "lumbar_5" }', frame="world",
                bones=["root", "pelvis.L", "pelvis.R"],
                comment="the root: MakeHuman's pelvis joint, at hip-joint level")
    previous = "pelvis"
    for v in LUMBAR + THORACIC:
        name = ("lumbar_" if v[0] == "L" else "thoracic_") + v[1:]
        out += part(name, previous, joint=f'{{ between = ["spine05", "neck01"], at = {pos[v]:.4f} }}',
                    dofs=spine_dofs(segment(v), ranges), tail='{ part = "thoracic_1" }' if v == "T2" else None)
        previous = name
    for v in CERVICAL:
        name = "cervical_" + v[1:]
        out += part(name, previous, joint=f'{{ between = ["neck01", "head"], at = {pos[v]:.4f} }}',
                    dofs=spine_dofs(segment(v), ranges))
        previous = name
    out += part("head", previous, joint=head_of("head"), tail=tail_of("head"), bones=["head"],
                dofs=spine_dofs("C0/C1", ranges),
                comment="joint C0/C1 (atlanto-occipital); the face bones follow the head")
    out += part("jaw", "head", joint=head_of("jaw"), tail=tail_of("jaw"), bones=["jaw"],
                dofs=[dof("depression", "x", 0, 30,
                          comment="mouth opening as a hinge: about 30° of condylar rotation")])
    return out


def mirror(axis: str) -> str:
    """A left-side axis name for the right side."""
    negated, base = axis.startswith("-"), axis.lstrip("-")
    m = MIRROR[base]
    return (m[1:] if m.startswith("-") else "-" + m) if negated else m


def head_of(bone: str) -> str:
    return f'{{ bone = "{bone}" }}'


def tail_of(bone: str) -> str:
    return f'{{ bone = "{bone}", at = "tail" }}'


def limbs(s: str) -> list[str]:
    """One side's upper and lower limb ('l' or 'r'); axes are written for the left and mirrored."""
    S = s.upper()

    def d(name: str, axis: str, lo: float, hi: float, rest: float | str = 0.0, comment: str = "") -> str:
        return dof(name, axis if s == "l" else mirror(axis), lo, hi, rest, comment)

    side = "left" if s == "l" else "right"
    out = ["", f"# ---- {side} upper limb ----"]
    out += part(
        f"clavicle_{s}", "thoracic_2", joint=head_of(f"clavicle.{S}"), tail=tail_of(f"clavicle.{S}"), frame="world",
        bones=[f"clavicle.{S}"],
        dofs=[d("elevation", "z", -10, 40, comment="sternoclavicular joint; the manubrium is at the T2/T3 level"),
              d("protraction", "-y", -20, 15)])
    out += part(
        f"scapula_{s}", f"clavicle_{s}", joint=head_of(f"shoulder01.{S}"), tail=tail_of(f"shoulder01.{S}"),
        bones=[f"shoulder01.{S}"],
        dofs=[d("upward_rotation", "z", -10, 50, comment="acromion to glenoid: the scapula's third of arm elevation")])
    out += part(
        f"upper_arm_{s}", f"scapula_{s}", joint=head_of(f"upperarm01.{S}"), bones=[f"upperarm01.{S}", f"upperarm02.{S}"],
        dofs=[d("flexion", "-X", -40, 120,
                comment="glenohumeral: 2/3 of the AAOS elevation (180), scapulohumeral rhythm;"
                        " in the body's sagittal plane after abduction"),
              d("abduction", "Z", 0, 120, 42, "in the body's frontal plane; the rest pose is abducted"),
              d("internal_rotation", "long", -90, 70)])
    out += part(
        f"forearm_{s}", f"upper_arm_{s}", joint=head_of(f"lowerarm01.{S}"), bones=[f"lowerarm01.{S}", f"lowerarm02.{S}"],
        dofs=[d("flexion", "-hinge", 0, 150, "measured", "elbow; rest: the bend measured on the body (about 40°)"),
              d("pronation", "y", -80, 80, comment="radio-ulnar; 0 = thumb forward, as in the rest pose")])
    out += part(
        f"hand_{s}", f"forearm_{s}", joint=head_of(f"wrist.{S}"), tail=head_of(f"finger3-1.{S}"),
        bones=[f"wrist.{S}"] + [f"metacarpal{k}.{S}" for k in range(1, 5)],
        dofs=[d("flexion", "-z", -70, 80, comment="wrist; the palm faces the thigh"),
              d("radial_deviation", "-x", -30, 20)])
    out += part(
        f"thumb_metacarpal_{s}", f"hand_{s}", joint=head_of(f"finger1-1.{S}"), bones=[f"finger1-1.{S}"],
        dofs=[d("flexion", "z", -20, 15, comment="carpometacarpal; axes approximate (the thumb is oblique)"),
              d("abduction", "x", 0, 70)])
    out += part(
        f"thumb_phalanges_{s}", f"thumb_metacarpal_{s}", joint=head_of(f"finger1-2.{S}"), tail=tail_of(f"finger1-3.{S}"),
        bones=[f"finger1-2.{S}", f"finger1-3.{S}"],
        dofs=[d("flexion", "hinge", 0, 50, "measured",
                "metacarpophalangeal; the interphalangeal joint is not modelled")])
    rests = {"index": (15, 15), "middle": (20, 10), "ring": (25, 10), "little": (20, 10)}  # MCP, PIP (degrees)
    spread = {"index": "-x", "middle": "-x", "ring": "x", "little": "x"}
    for k, finger in enumerate(["index", "middle", "ring", "little"], start=2):
        mcp, pip = rests[finger]
        first = k == 2
        out += part(
            f"{finger}_proximal_{s}", f"hand_{s}", joint=head_of(f"finger{k}-1.{S}"), bones=[f"finger{k}-1.{S}"],
            dofs=[d("flexion", "-z", -45, 90, mcp, "metacarpophalangeal" if first else ""),
                  d("abduction", spread[finger], -15, 20,
                    comment="away from the middle finger's axis (middle: radially)" if first else "")])
        out += part(
            f"{finger}_distal_{s}", f"{finger}_proximal_{s}", joint=head_of(f"finger{k}-2.{S}"),
            tail=tail_of(f"finger{k}-3.{S}"), bones=[f"finger{k}-2.{S}", f"finger{k}-3.{S}"],
            dofs=[d("flexion", "-z", 0, 100, pip,
                    "proximal interphalangeal; middle and distal phalanges as one part" if first else "")])
    out += ["", f"# ---- {side} lower limb ----"]
    out += part(
        f"thigh_{s}", "pelvis", joint=head_of(f"upperleg01.{S}"), bones=[f"upperleg01.{S}", f"upperleg02.{S}"],
        dofs=[d("flexion", "-x", -30, 120, 5, "hip"), d("abduction", "z", -30, 45, 6),
              d("internal_rotation", "y", -45, 45)])
    out += part(
        f"shank_{s}", f"thigh_{s}", joint=head_of(f"lowerleg01.{S}"), bones=[f"lowerleg01.{S}", f"lowerleg02.{S}"],
        dofs=[d("flexion", "x", 0, 135, 9, "knee")])
    toe_heads = ", ".join(f'"toe{k}-1.{S}"' for k in range(1, 6))
    toe_tails = ", ".join(f'"toe{k}-{2 if k == 1 else 3}.{S}"' for k in range(1, 6))
    out += part(
        f"foot_{s}", f"shank_{s}", joint=head_of(f"foot.{S}"), frame="world", tail=f"{{ bones = [{toe_heads}] }}",
        bones=[f"foot.{S}"],
        dofs=[d("dorsiflexion", "-x", -50, 20, comment="ankle (talocrural) and subtalar joints at one centre"),
              d("inversion", "-long", -15, 35)])
    out += part(
        f"toes_{s}", f"foot_{s}", joint=f"{{ bones = [{toe_heads}] }}", tail=f'{{ bones = [{toe_tails}], at = "tail" }}',
        frame="world", bones=[f"toe{k}-1.{S}" for k in range(1, 6)],
        dofs=[d("flexion", "x", -70, 45, comment="metatarsophalangeal (the great toe's ranges)")])
    return out


def shared() -> list[str]:
    """The rig's spine, neck and breast bones, shared along pelvis, vertebrae and head."""
    chain = (["pelvis"] + [("lumbar_" if v[0] == "L" else "thoracic_") + v[1:] for v in LUMBAR + THORACIC]
             + ["cervical_" + v[1:] for v in CERVICAL] + ["head"])
    bones = ["spine05", "spine04", "spine03", "spine02", "spine01", "neck01", "neck02", "neck03", "breast.L", "breast.R"]
    out = ["", "# The rig's spine, neck and breast bones: their weights go to the pelvis, vertebrae and head by position.",
           "[[shared]]", "bones = [" + ", ".join(f'"{b}"' for b in bones) + "]", "parts = ["]
    out += ["  " + ", ".join(f'"{c}"' for c in chain[i:i + 6]) + "," for i in range(0, len(chain), 6)]
    return out + ["]"]


def skeleton_toml() -> str:
    """The whole file's text."""
    return "\n".join([HEADER, *axial(), *limbs("l"), *limbs("r"), *shared()]) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=OUT, help=f"default: {OUT}")
    args = parser.parse_args()
    args.out.write_text(skeleton_toml(), encoding="utf-8")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
