"""A BVH file as a scenario's timeline: keyframes of joint angles, one per BVH frame.

`[timeline] bvh = "walk.bvh"` (a path relative to the scenario file) with an
optional `joint_map` (a shipped map's name or a TOML file; default: the map
matching the most joint names) stands in for the `[[keyframe]]` entries. The
retargeted angles (docs/motion.md) become `angles` keyframes, linear between
frames. The root's rigid motion (walking forward, turning) becomes the
scenario's root track: the simulation moves the whole body with it.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from hitogata.motion.scenario import BodySpec, make_body
from hitogata.dynamics.timeline import MAX_RATE, Keyframe, RootTrack
from hitogata.errors import HitogataError, excerpt
from hitogata.motion.bvh import read_bvh
from hitogata.motion.clip import MotionClip
from hitogata.motion.joint_map import choose_joint_map
from hitogata.motion.retarget import Retargeted, retarget
from hitogata.skeleton.child_ranges import with_age_ranges
from hitogata.skeleton.placement import Skeleton, place_skeleton
from hitogata.skeleton.spec import load_skeleton_spec

KEYS = ("bvh", "joint_map")
STILL = math.radians(0.01)  # a DOF that never moves more than this from rest is left out of the keyframes


def body_skeleton(spec: BodySpec) -> Skeleton:
    """The shipped skeleton placed on the scenario's body."""

    body = make_body(spec)
    return with_age_ranges(place_skeleton(load_skeleton_spec(), body.rig), body.params.sex, body.params.age)


def bvh_timeline(source: str, data: dict, body: BodySpec) -> tuple[list[Keyframe], RootTrack]:
    """The keyframes and the root track a scenario's `[timeline] bvh = …` stands for."""
    table = data["timeline"]
    if "keyframe" in data:
        raise HitogataError(f"{source}: [timeline].bvh: give a BVH file or [[keyframe]] entries, not both")
    path = beside(source, "[timeline].bvh", table["bvh"])
    mapping = table.get("joint_map")
    if mapping is not None and not isinstance(mapping, str):
        raise HitogataError(f"{source}: [timeline].joint_map: {excerpt(mapping)}; allowed a map name or a TOML path")
    if mapping is not None and mapping.endswith(".toml"):
        mapping = str(beside(source, "[timeline].joint_map", mapping))
    skeleton = body_skeleton(body)
    bvh = read_bvh(path)
    result = retarget(bvh, skeleton, choose_joint_map(bvh.names, skeleton, mapping, bvh.source))
    return clip_keyframes(result.clip, skeleton), RootTrack(result.clip.times, result.clip.root)


def beside(source: str, entry: str, name: object) -> Path:
    """A file a scenario names: a path relative to the scenario's folder that stays inside it.

    A scenario may come from someone else: it must not make the program read (and quote in
    an error) a file elsewhere on the machine, by an absolute path, `..` or a symbolic link.
    """
    allowed = "allowed a path relative to the scenario's folder, inside it (no absolute path, no '..')"
    if not isinstance(name, str) or not name or Path(name).is_absolute() or ".." in Path(name).parts:
        raise HitogataError(f"{source}: {entry}: {excerpt(name)}; {allowed}")
    folder = Path(source).parent
    if not (folder / name).resolve().is_relative_to(folder.resolve()):
        raise HitogataError(f"{source}: {entry}: {excerpt(name)} leads outside the scenario's folder; {allowed}")
    return folder / name


def clip_keyframes(clip: MotionClip, skeleton: Skeleton) -> list[Keyframe]:
    """One linear keyframe per frame with the rest-relative angle of every DOF that moves."""
    moving = np.flatnonzero(np.abs(clip.angles).max(axis=0) > STILL)
    return [Keyframe(float(t), {("angle", skeleton.dof_names[d]): float(a[d]) for d in moving}, "linear")
            for t, a in zip(clip.times, clip.angles)]


def scenario_text(result: Retargeted, skeleton: Skeleton, body: BodySpec, title: str, origin: str,
                  joint_map: str) -> str:
    """A scenario TOML holding the retargeted motion as keyframes (angles in degrees from rest)."""
    clip = result.clip
    moving = np.flatnonzero(np.abs(clip.angles).max(axis=0) > STILL)
    beyond = (clip.angles < skeleton.lower - 1e-9) | (clip.angles > skeleton.upper + 1e-9)
    outside = [skeleton.dof_names[d] for d in moving if beyond[:, d].any()]
    turn = float(np.degrees(np.arccos(np.clip((np.trace(clip.root[-1, :3, :3]) - 1) / 2, -1, 1))))
    travel = float(np.linalg.norm(clip.root[-1, :3, 3] - clip.root[0, :3, 3]) * 100)
    lines = [f"# Retargeted from {origin} by `hitogata motion import` (docs/motion.md).",
             f"# Joint map {joint_map}; BVH joints used: {', '.join(result.mapped)}.",
             (f"# The file's skeleton stands {result.height:.4g} {result.unit or 'units (unit not recognised)'} "
              "tall (head joint above the lowest joint)."),
             (f"# Root motion (not kept in this file; a scenario with [timeline] bvh = the file moves with it): "
              f"turned {turn:.1f}°, moved {travel:.1f} cm by the last frame."),
             (f"# Joint angles outside the ranges of motion: {', '.join(outside) if outside else 'none'}"
              + (" (on_limit = clamp)" if outside else "")),
             f"title = {_quote(title)}", "", "[body]",
             f"sex = {_quote(body.sex) if isinstance(body.sex, str) else body.sex}", f"age = {body.age:g}"]
    if body.stature is not None:
        lines += [f'stature = "{body.stature * 100:.1f}cm"', f'mass = "{body.mass:.1f}kg"']
    lines += ["", "[model]", 'extent = "body"', "", "[time]", f'duration = "{clip.times[-1]:.6g}s"',
              f"rate = {min(max(round(clip.rate), 1), int(MAX_RATE))}", "", "[timeline]", 'interpolation = "linear"',
              f'on_limit = "{"clamp" if outside else "raise"}"']
    for t, row in zip(clip.times, clip.angles):
        values = ", ".join(f'"{skeleton.dof_names[d]}" = {np.degrees(row[d]):.4f}' for d in moving)
        lines += ["", "[[keyframe]]", f'time = "{t:.6g}s"', f"angles = {{ {values} }}"]
    return "\n".join(lines) + "\n"


def _quote(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'
