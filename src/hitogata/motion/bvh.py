"""BVH motion files: read, check, write, and the skeleton's world motion in the file's own frame.

BVH (Biovision Hierarchy) is a joint tree with rest offsets (HIERARCHY) and
one line of channel values per frame (MOTION). Each joint's rotation is the
product of its rotation channels in the order listed (R = R_c1 R_c2 R_c3,
intrinsic: 'Zrotation Xrotation Yrotation' is ZXY), in degrees; positions in
the file's length unit. At rest (all channels zero) every joint's frame is
the file's world frame. A joint with position channels sits where they say
in its parent's frame (the root: in the world), its OFFSET being its rest
place (Blender's reading). Every mistake is one line naming the file and line.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from hitogata.dynamics.timeline import MAX_DURATION, MAX_RATE
from hitogata.errors import HitogataError, excerpt

CHANNELS = ("Xposition", "Yposition", "Zposition", "Xrotation", "Yrotation", "Zrotation")
MAX_FRAMES = int(MAX_DURATION * MAX_RATE)  # the longest motion at the fastest scenario rate
MAX_BYTES = 512 * 2**20  # a file of MAX_FRAMES frames of a 65-joint skeleton is about 300 MiB
MAX_DEPTH = 64  # nesting: a human skeleton with fingers is about 25 deep
MAX_JOINTS = 1000
MAX_NAME = 100  # characters of a joint name
MAX_OFFSET = 1e5  # |OFFSET| in file units: 100 m in mm


@dataclass(frozen=True)
class BvhJoint:
    """One joint: name, parent index (-1: root), rest offset from the parent, channels, end-site offset."""

    name: str
    parent: int
    offset: np.ndarray  # (3,)
    channels: tuple[str, ...]
    end_site: np.ndarray | None = None


@dataclass(frozen=True)
class Bvh:
    """A BVH file: joints (parents before children), frame time (s), values (F, C) in file units/degrees."""

    source: str
    joints: tuple[BvhJoint, ...]
    frame_time: float
    values: np.ndarray

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(j.name for j in self.joints)

    @property
    def frames(self) -> int:
        return len(self.values)

    def rest_positions(self) -> np.ndarray:
        """(J, 3) joint positions at rest (all channels zero), file units, root at its offset."""
        out = np.zeros((len(self.joints), 3))
        for k, j in enumerate(self.joints):
            out[k] = j.offset + (out[j.parent] if j.parent >= 0 else 0.0)
        return out

    def world(self) -> tuple[np.ndarray, np.ndarray]:
        """(F, J, 3, 3) world rotations and (F, J, 3) positions of every joint in every frame."""
        n_frames, n = self.frames, len(self.joints)
        rotations = np.zeros((n_frames, n, 3, 3))
        positions = np.zeros((n_frames, n, 3))
        column = 0
        for k, j in enumerate(self.joints):
            values = self.values[:, column:column + len(j.channels)]
            column += len(j.channels)
            local = _local_rotation(j.channels, values)
            has_position = any(c.endswith("position") for c in j.channels)
            moved = (_local_translation(j.channels, values) if has_position
                     else np.broadcast_to(j.offset, (n_frames, 3)))
            if j.parent < 0:
                rotations[:, k], positions[:, k] = local, moved
            else:
                rotations[:, k] = rotations[:, j.parent] @ local
                positions[:, k] = positions[:, j.parent] + np.einsum("fij,fj->fi", rotations[:, j.parent], moved)
        return rotations, positions


def _local_rotation(channels: tuple[str, ...], values: np.ndarray) -> np.ndarray:
    order = "".join(c[0] for c in channels if c.endswith("rotation"))
    angles = values[:, [i for i, c in enumerate(channels) if c.endswith("rotation")]]
    if not order:
        return np.broadcast_to(np.eye(3), (len(values), 3, 3)).copy()
    return Rotation.from_euler(order.upper(), angles, degrees=True).as_matrix().reshape(-1, 3, 3)


def _local_translation(channels: tuple[str, ...], values: np.ndarray) -> np.ndarray:
    out = np.zeros((len(values), 3))
    for i, c in enumerate(channels):
        if c.endswith("position"):
            out[:, "XYZ".index(c[0])] = values[:, i]
    return out


class _Tokens:
    """Whitespace tokens with their line numbers, split line by line as they are asked for (one-line errors).

    Only the hierarchy is read word by word; the motion's lines are taken whole (`rest`), so a long
    file is refused by its frame count before its values are read.
    """

    def __init__(self, source: str, text: str) -> None:
        self.source = source
        self.lines = text.splitlines()
        self.row = 0  # lines split so far
        self.pending: list[tuple[str, int]] = []  # the current line's words not yet taken, last first
        self.line = 1  # the line of the word taken last

    def _fill(self) -> bool:
        while not self.pending and self.row < len(self.lines):
            self.row += 1
            self.pending = [(word, self.row) for word in reversed(self.lines[self.row - 1].split())]
        return bool(self.pending)

    def fail(self, message: str, line: int | None = None) -> HitogataError:
        return HitogataError(f"{self.source}: line {self.line if line is None else line}: {message}")

    def next(self, what: str) -> tuple[str, int]:
        if not self._fill():
            raise HitogataError(f"{self.source}: line {max(len(self.lines), 1)}: the file ends where {what} "
                                "was expected")
        word, self.line = self.pending.pop()
        return word, self.line

    def expect(self, word: str) -> int:
        got, line = self.next(f"{word!r}")
        if got != word:
            raise self.fail(f"expected {word!r}, found {excerpt(got)}", line)
        return line

    def number(self, what: str) -> float:
        got, line = self.next(what)
        try:
            value = float(got)
        except ValueError:
            value = float("nan")
        if not np.isfinite(value):
            raise self.fail(f"{what}: {excerpt(got)}; allowed a finite number", line)
        return value

    def peek(self) -> str | None:
        return self.pending[-1][0] if self._fill() else None

    def rest(self) -> list[tuple[int, list[str]]]:
        """The lines not yet read, as (line number, words), empty lines left out."""
        out = [(self.line, [w for w, _ in reversed(self.pending)])] if self.pending else []
        self.pending = []
        out += [(k, words) for k in range(self.row + 1, len(self.lines) + 1) if (words := self.lines[k - 1].split())]
        self.row = len(self.lines)
        return out


def read_bvh(path: str | Path) -> Bvh:
    """Read and check a BVH file."""
    path = Path(path)
    try:
        size = path.stat().st_size
        if size > MAX_BYTES:
            raise HitogataError(f"{path}: {size / 2**20:.0f} MiB; allowed a BVH file of at most "
                                f"{MAX_BYTES / 2**20:.0f} MiB ({MAX_DURATION:g} s of motion)")
        text = path.read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise HitogataError(f"{path}: no such BVH file") from None
    except (UnicodeDecodeError, IsADirectoryError) as err:
        raise HitogataError(f"{path}: not a text BVH file ({err.__class__.__name__})") from None
    return parse_bvh(text, str(path))


def parse_bvh(text: str, source: str = "<bvh>") -> Bvh:
    """Parse BVH text (HIERARCHY, then MOTION)."""
    tokens = _Tokens(source, text)
    if tokens.peek() != "HIERARCHY":  # not a BVH file: nothing of it is quoted
        raise tokens.fail("not a BVH file; allowed a file beginning with HIERARCHY")
    tokens.expect("HIERARCHY")
    tokens.expect("ROOT")
    joints: list[BvhJoint] = []
    _joint(tokens, joints, -1)
    if tokens.peek() in ("ROOT", "JOINT"):
        raise tokens.fail("a second root; allowed one skeleton per file")
    tokens.expect("MOTION")
    tokens.expect("Frames:")
    frames = tokens.number("the frame count")
    if frames != int(frames) or not 1 <= frames <= MAX_FRAMES:
        raise tokens.fail(f"frame count {frames:g}; allowed a whole number 1..{MAX_FRAMES}")
    tokens.expect("Frame")
    tokens.expect("Time:")
    frame_time = tokens.number("the frame time")
    if not 1e-4 <= frame_time <= 10.0:
        raise tokens.fail(f"frame time {frame_time:g} s; allowed 0.0001..10 s")
    if (int(frames) - 1) * frame_time > MAX_DURATION:
        raise tokens.fail(f"{int(frames)} frames of {frame_time:g} s = {(int(frames) - 1) * frame_time:.0f} s of "
                          f"motion; allowed at most {MAX_DURATION:g} s (the longest scenario `simulate` runs)")
    width = sum(len(j.channels) for j in joints)
    data = tokens.rest()
    count = sum(len(words) for _, words in data)
    if count != int(frames) * width:
        line = data[-1][0] if data else max(len(tokens.lines), 1)
        raise tokens.fail(f"{count} channel values for {int(frames)} frames of {width} channels; "
                          f"allowed {int(frames) * width}", line)
    wrong = [(line, len(words)) for line, words in data if len(words) != width]
    try:
        values = np.array([w for _, words in data for w in words], dtype=float)
    except ValueError:
        values = None
    if values is None or not np.isfinite(values).all():
        for line, words in data:
            for word in words:
                try:
                    ok = np.isfinite(float(word))
                except ValueError:
                    ok = False
                if not ok:
                    raise tokens.fail(f"channel value {excerpt(word)}; allowed a finite number", line)
    if wrong:  # one frame per line, as every BVH writer does
        raise tokens.fail(f"{wrong[0][1]} values on this frame line; allowed {width} (one frame per line)",
                          wrong[0][0])
    assert values is not None  # every word was a finite number (the loop above)
    return Bvh(source, tuple(joints), frame_time, values.reshape(int(frames), width))


def _joint(tokens: _Tokens, joints: list[BvhJoint], parent: int, depth: int = 1) -> None:
    name, line = tokens.next("a joint name")
    if name in ("{", "}"):
        raise tokens.fail(f"expected a joint name, found {excerpt(name)}", line)
    if len(name) > MAX_NAME or not name.isprintable():
        raise tokens.fail(f"joint name {excerpt(name)}; allowed up to {MAX_NAME} printable characters", line)
    if any(j.name == name for j in joints):
        raise tokens.fail(f"joint {excerpt(name)} named twice; allowed unique names", line)
    if depth > MAX_DEPTH or len(joints) >= MAX_JOINTS:
        raise tokens.fail(f"joint {name!r}: {'nested ' + str(depth) + ' deep' if depth > MAX_DEPTH else 'one joint too many'}"
                          f"; allowed at most {MAX_DEPTH} levels and {MAX_JOINTS} joints", line)
    tokens.expect("{")
    tokens.expect("OFFSET")
    offset = _offset(tokens, f"{name} OFFSET")
    tokens.expect("CHANNELS")
    count = tokens.number(f"{name} channel count")
    if count != int(count) or not 0 <= count <= 6:
        raise tokens.fail(f"{name}: {count:g} channels; allowed 0..6")
    channels = []
    for _ in range(int(count)):
        word, at = tokens.next("a channel name")
        word = word.capitalize()  # 'zrotation' and 'ZROTATION' are seen in the wild
        if word not in CHANNELS or word in channels:
            raise tokens.fail(f"{name}: channel {excerpt(word)}; allowed each of {', '.join(CHANNELS)} at most once",
                              at)
        channels.append(word)
    index = len(joints)
    joints.append(BvhJoint(name, parent, offset, tuple(channels)))
    end_site = None
    while True:
        word, at = tokens.next("JOINT, End Site or '}'")
        if word == "}":
            break
        if word == "JOINT":
            _joint(tokens, joints, index, depth + 1)
        elif word == "End":
            tokens.expect("Site")
            tokens.expect("{")
            tokens.expect("OFFSET")
            end_site = _offset(tokens, f"{name} End Site OFFSET")
            tokens.expect("}")
        else:
            raise tokens.fail(f"expected JOINT, End Site or '}}', found {excerpt(word)}", at)
    if end_site is not None:
        j = joints[index]
        joints[index] = BvhJoint(j.name, j.parent, j.offset, j.channels, end_site)


def _offset(tokens: _Tokens, what: str) -> np.ndarray:
    """Three finite numbers within ±MAX_OFFSET (a person in any length unit, mm included)."""
    offset = np.array([tokens.number(what) for _ in range(3)])
    if np.abs(offset).max() > MAX_OFFSET:
        raise tokens.fail(f"{what}: {' '.join(f'{x:g}' for x in offset)}; allowed values within "
                          f"±{MAX_OFFSET:g} (file units)")
    return offset


def write_bvh(bvh: Bvh) -> str:
    """BVH text of a Bvh (offsets and values as given; 6 decimals)."""
    children: dict[int, list[int]] = {k: [] for k in range(-1, len(bvh.joints))}
    for k, j in enumerate(bvh.joints):
        children[j.parent].append(k)
    lines = ["HIERARCHY"]

    def emit(k: int, depth: int) -> None:
        j, pad = bvh.joints[k], "  " * depth
        lines.append(f"{pad}{'ROOT' if j.parent < 0 else 'JOINT'} {j.name}")
        lines.append(f"{pad}{{")
        lines.append(f"{pad}  OFFSET " + " ".join(f"{x:.6f}" for x in j.offset))
        lines.append(f"{pad}  CHANNELS {len(j.channels)} " + " ".join(j.channels))
        for c in children[k]:
            emit(c, depth + 1)
        if j.end_site is not None:
            site = " ".join(f"{x:.6f}" for x in j.end_site)
            lines.extend([f"{pad}  End Site", f"{pad}  {{", f"{pad}    OFFSET {site}", f"{pad}  }}"])
        lines.append(f"{pad}}}")

    for root in children[-1]:
        emit(root, 0)
    lines += ["MOTION", f"Frames: {bvh.frames}", f"Frame Time: {bvh.frame_time:.8f}"]
    lines += [" ".join(f"{x:.6f}" for x in row) for row in bvh.values]
    return "\n".join(lines) + "\n"
