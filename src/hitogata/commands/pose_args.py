"""The pose a user asks for on the command line: --muscle NAME=VALUE, --angle PART.DOF=ANGLE.

Shared by `hitogata pose` and `hitogata skeleton`. Values go through
`hitogata.units` once, here. Names are the skeleton's and muscles' list names,
with two shorthands: no side suffix means both sides (`biceps_brachii=20%`,
`forearm.flexion=90deg`; a midline DOF moved by a left and a right muscle is
driven by the left one, the right one follows), and a joint may be named by
its common name (`elbow_l.flexion` for `forearm_l.flexion`). The shoulder's
flexion and abduction are the shoulder complex's (`shoulder_l.flexion`: the
arm relative to the thorax, 0…180°, the girdle following by the
scapulohumeral rhythm); `upper_arm_l.flexion` is the glenohumeral joint alone.
An unknown name is a one-line error with the closest names.
"""

from __future__ import annotations

import argparse
import difflib
from dataclasses import dataclass, field

from hitogata import units
from hitogata.errors import HitogataError
from hitogata.posing.names import JOINT_NAMES, SIDES, dof_candidates
from hitogata.options import OnLimit, Skinning
from hitogata.posing.pose import ON_LIMIT, Poser
from hitogata.skeleton.shoulder import channel_names
from hitogata.posing.skinning import METHODS

LIST_HINT = "hitogata pose --list shows them all"


@dataclass(frozen=True)
class PoseRequest:
    """Muscle contractions (fractions) and lengths (m), clinical angles (rad), and how to pose."""

    contractions: dict[str, float] = field(default_factory=dict)
    lengths: dict[str, float] = field(default_factory=dict)
    clinical: dict[str, float] = field(default_factory=dict)
    skinning: Skinning = "lbs"
    on_limit: OnLimit = "raise"


def add_pose_arguments(parser: argparse.ArgumentParser) -> None:
    """--muscle (alias --contract), --angle, --skinning, --on-limit."""
    parser.add_argument(
        "--muscle", "--contract", dest="contract", action="append", default=[], metavar="MUSCLE=VALUE",
        help="a muscle's contraction, e.g. biceps_brachii_l=25%% or =0.25 (shorter by a quarter; "
        "negative = stretched), or its length, e.g. =28cm; no _l/_r = both sides; repeatable",
    )
    parser.add_argument(
        "--angle", action="append", default=[], metavar="PART.DOF=ANGLE",
        help="a clinical joint angle (0 = anatomical position), e.g. forearm_l.flexion=90deg or "
        "elbow_l.flexion=1.57rad; joints may be called shoulder, elbow, wrist, hip, knee, ankle; "
        "shoulder_l.flexion/abduction move the whole shoulder complex (0…180°); repeatable",
    )
    parser.add_argument("--skinning", choices=METHODS, default=None,
                        help="skin deformation: lbs or dqs; default lbs (dqs with --elastic, which stands on it)")
    parser.add_argument(
        "--on-limit", choices=ON_LIMIT, default="raise",
        help="beyond a muscle's reach or a joint's range: raise (default, an error) or clamp (with a note)",
    )


def split_entry(text: str, option: str, example: str) -> tuple[str, str]:
    """'NAME=VALUE' → (NAME, VALUE), or a one-line error."""
    name, sep, value = text.partition("=")
    if not sep or not name.strip() or not value.strip():
        raise HitogataError(f"{option} {text!r}: write NAME=VALUE, e.g. {example}")
    return name.strip(), value.strip()


def unknown(kind: str, name: str, option: str, known: list[str], query: str | None = None) -> HitogataError:
    """A one-line error naming the closest known names to `query` (the name as understood)."""
    close = difflib.get_close_matches(query or name, known, n=3, cutoff=0.5)
    hint = f"did you mean {', '.join(close)}?" if close else f"e.g. {', '.join(known[:3])}"
    return HitogataError(f"{option} {name!r}: no {kind} of that name; {hint} ({LIST_HINT})")


def muscle_names(poser: Poser, name: str) -> list[str]:
    """The muscles a name stands for: itself, or both sides' (those moving other DOFs than the first)."""
    ms = poser.muscles
    if name in ms.names:
        return [name]
    sided = [name + s for s in SIDES if name + s in ms.names]
    if not sided:
        known = list(ms.names) + sorted({n[:-2] for n in ms.names if n.endswith(SIDES)})
        raise unknown("muscle", name, "--muscle", known)
    first = set(ms.dofs(ms.index(sided[0])).tolist())
    return sided[:1] + [n for n in sided[1:] if not first & set(ms.dofs(ms.index(n)).tolist())]


def dof_names(poser: Poser, name: str) -> list[str]:
    """The DOFs (or shoulder-complex controls) a 'part.dof' name stands for, joint names and
    side-less names resolved."""
    known = poser.skeleton.dof_names + channel_names(poser.skeleton)
    found = dof_candidates(name, known)
    if not found:
        part, _, dof = name.rpartition(".")
        side = next((s for s in SIDES if part.endswith(s)), "")
        base = part[: len(part) - len(side)]
        short = {n.replace("_l.", ".").replace("_r.", ".") for n in known}
        query = f"{JOINT_NAMES.get(base, base)}{side}.{dof}"
        raise unknown("degree of freedom", name, "--angle", sorted(short | set(known)), query)
    return found


def muscle_value(text: str, where: str) -> tuple[str, float]:
    """('contraction', fraction) from '0.25' or '25%', or ('length', m) from '28cm'."""
    for kind, table in (("contraction", units.FRACTION_UNITS), ("length", units.LENGTH_UNITS)):
        try:
            value = units.parse_quantity(text, table, where)
        except HitogataError:
            continue
        if kind == "contraction" and abs(value) >= 1.0 and not text.strip().endswith("%"):
            raise HitogataError(f"{where} {text!r}: a contraction is a fraction of the rest length, "
                                f"allowed between -1 and 1; did you mean {text.strip()}%?")
        return kind, value
    raise HitogataError(
        f"{where} {text!r}: write a contraction (0.25 or 25%; negative = stretched) or a length (28cm, 0.28m)"
    )


def pose_request(args: argparse.Namespace, poser: Poser) -> PoseRequest:
    """The checked request; every name and value mistake is a one-line error."""
    request = PoseRequest(skinning=args.skinning or "lbs", on_limit=args.on_limit)
    for entry in args.contract:
        name, text = split_entry(entry, "--muscle", "biceps_brachii_l=25%")
        kind, value = muscle_value(text, f"--muscle {name}")
        for muscle in muscle_names(poser, name):
            target = request.contractions if kind == "contraction" else request.lengths
            if muscle in request.contractions or muscle in request.lengths:
                raise HitogataError(f"--muscle {name}: muscle {muscle!r} given twice; give it once")
            target[muscle] = value
    for entry in args.angle:
        name, text = split_entry(entry, "--angle", "forearm_l.flexion=90deg")
        value = units.angle(text, f"--angle {name}")
        for dof in dof_names(poser, name):
            if dof in request.clinical:
                raise HitogataError(f"--angle {name}: {dof} given twice; give it once")
            request.clinical[dof] = value
    return request
