"""Keyframed channels: a muscle's contraction or a joint's angle as a function of time.

A channel is set by the keyframes that name it. Before the first of them it
is at rest — as if a keyframe at t = 0 said so, unless one does: 0 for a
contraction or an angle, the rest pose's own clinical angle for a clinical
channel (the elbow's rest is ~40° flexed, not the anatomical 0°; the
caller, who knows the skeleton, gives it when sampling) — and after the
last it holds. Between two keyframes the value follows the
interpolation the later keyframe names:

- "linear": constant speed; the velocity jumps at keyframes;
- "smoothstep": the cubic Hermite curve with zero velocity at both ends,
  s(u) = 3u² − 2u³, so a motion starts and stops gently.

Channel kinds: "contraction" (fraction of rest length, 0.1 = 10 % shorter),
"angle" (radians from the rest pose) and "clinical" (radians from the
anatomical position).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from hitogata.errors import HitogataError, excerpt
from hitogata.options import CHANNEL_KINDS as KINDS, Interpolation, INTERPOLATIONS

MAX_DURATION = 600.0  # s: the longest motion simulated (a scenario's duration, a BVH timeline, the API)
MAX_RATE = 240.0  # frames per second
MAX_SUBSTEPS = 100  # time steps per frame



def ease(u: np.ndarray, interpolation: str) -> np.ndarray:
    """Progress 0..1 along a segment for the fraction u (0..1) of its time."""
    if interpolation == "linear":
        return u
    if interpolation == "smoothstep":
        return u * u * (3.0 - 2.0 * u)
    raise HitogataError(f"interpolation {interpolation!r}: allowed {', '.join(INTERPOLATIONS)}")


@dataclass(frozen=True)
class Channel:
    """One keyframed value: times (K,) strictly increasing from 0, values (K,), how each is reached."""

    kind: str
    name: str
    times: tuple[float, ...]
    values: tuple[float, ...]
    interpolations: tuple[str, ...]  # how keyframe k is reached from k − 1 (entry 0 unused)
    rest_start: bool = False  # entry 0 is the implicit rest at t = 0, its value given when called

    def __call__(self, t: np.ndarray, rest: float = 0.0) -> np.ndarray:
        """Values at times t (any shape); `rest`: the channel's rest value, for an implicit start."""
        t = np.asarray(t, dtype=float)
        times, values = np.asarray(self.times), np.array(self.values)
        if self.rest_start:
            values[0] = rest
        out = np.full(t.shape, values[-1])
        out[t <= times[0]] = values[0]
        for k in range(1, len(times)):
            inside = (t > times[k - 1]) & (t <= times[k])
            u = (t[inside] - times[k - 1]) / (times[k] - times[k - 1])
            out[inside] = values[k - 1] + (values[k] - values[k - 1]) * ease(u, self.interpolations[k])
        return out


@dataclass(frozen=True)
class Keyframe:
    """Values of some channels at one time, reached by one interpolation."""

    time: float
    values: dict[tuple[str, str], float]  # (kind, name) -> value (SI)
    interpolation: Interpolation = "smoothstep"


@dataclass(frozen=True)
class Timeline:
    """Channels built from keyframes; `sample` evaluates all of them at many times."""

    channels: tuple[Channel, ...]

    @classmethod
    def from_keyframes(cls, keyframes: list[Keyframe]) -> Timeline:
        """Group keyframes (in time order) into channels, each starting at rest at t = 0."""
        times = [k.time for k in keyframes]
        for i, when in enumerate(times, start=1):
            if not isinstance(when, (int, float)) or isinstance(when, bool) or not 0 <= when <= MAX_DURATION:
                raise HitogataError(f"keyframe {i}: time {excerpt(when)}; allowed a number of seconds "
                                    f"0..{MAX_DURATION:g}")
        if any(b <= a for a, b in zip(times, times[1:])):
            at = next(i for i, (a, b) in enumerate(zip(times, times[1:]), start=2) if b <= a)
            raise HitogataError(f"keyframe {at}: time {times[at - 1]:g} s after {times[at - 2]:g} s; "
                                "allowed strictly increasing times from 0 s")
        series: dict[tuple[str, str], list[tuple[float, float, str]]] = {}
        for i, k in enumerate(keyframes, start=1):
            for key, value in k.values.items():
                if key[0] not in KINDS:
                    raise HitogataError(f"channel kind {excerpt(key[0])}: allowed {', '.join(KINDS)}")
                if not isinstance(value, (int, float, np.number)) or isinstance(value, bool) or not np.isfinite(value):
                    raise HitogataError(f"keyframe {i}: {key[0]} {excerpt(key[1])} = {excerpt(value)}; "
                                        "allowed a finite number (SI: radians, a fraction)")
                series.setdefault(key, []).append((k.time, float(value), k.interpolation))
        channels = []
        for (kind, name), points in series.items():
            implicit = points[0][0] > 0
            if implicit:
                points.insert(0, (0.0, 0.0, "linear"))
            t, v, how = zip(*points)
            channels.append(Channel(kind, name, t, v, how, implicit))
        return cls(tuple(channels))

    def sample(self, t: np.ndarray, rest: Mapping[tuple[str, str], float] | None = None
               ) -> dict[str, dict[str, np.ndarray]]:
        """{kind: {name: values at t}} for every channel; rest: (kind, name) -> the value a channel
        starts from when no keyframe at t = 0 names it (default 0)."""
        rest = rest or {}
        out: dict[str, dict[str, np.ndarray]] = {kind: {} for kind in KINDS}
        for c in self.channels:
            out[c.kind][c.name] = c(t, rest.get((c.kind, c.name), 0.0))
        return out

    @property
    def end(self) -> float:
        """Time of the last keyframe (s)."""
        return max((c.times[-1] for c in self.channels), default=0.0)


@dataclass(frozen=True)
class RootTrack:
    """The whole body's rigid motion over time (a BVH's root): times (K,) s and transforms (K, 4, 4),
    rest → posed, applied to the whole skeleton. Between samples the translation is linear and the
    rotation turns at constant speed about one axis (slerp); before the first and after the last
    it holds."""

    times: np.ndarray
    transforms: np.ndarray

    def sample(self, t: np.ndarray) -> np.ndarray:
        """(T, 4, 4) the transform at times t (s)."""
        from scipy.spatial.transform import Rotation, Slerp

        t = np.clip(np.asarray(t, dtype=float), self.times[0], self.times[-1])
        out = np.broadcast_to(np.eye(4), (len(t), 4, 4)).copy()
        for axis in range(3):
            out[:, axis, 3] = np.interp(t, self.times, self.transforms[:, axis, 3])
        if len(self.times) > 1:
            out[:, :3, :3] = Slerp(self.times, Rotation.from_matrix(self.transforms[:, :3, :3]))(t).as_matrix()
        else:
            out[:, :3, :3] = self.transforms[0, :3, :3]
        return out
