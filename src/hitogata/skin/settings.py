"""The skin's contact settings: every tuning constant of the contact, the creases and the slide, in one frozen
dataclass with its unit and its reason (SI: m, radians).

`SkinSettings()` (`SKIN_DEFAULTS`) is the library's answer; the entry points that run the skin's contact take
`settings=` and hand it down: `single_pose.elastic_pose`, `held_frames.HeldFrames`, `motion_contact.simulate`
and `resolve_frames`, `skin_slide.slide_posed_skin`, `slide_skin` and `slide_fine_skin`. A study of one
constant is a `dataclasses.replace` of the defaults:

    from dataclasses import replace
    from hitogata.skin import SKIN_DEFAULTS
    wider = replace(SKIN_DEFAULTS, barrier=replace(SKIN_DEFAULTS.barrier, dhat=3e-3))
    elastic_pose(dynamics, angles=..., contact=True, settings=wider)

The mesh algorithms below the body keep their own settings in `hitogata.geometry` (they know nothing of a
body), held here as fields: the barrier (`geometry.barrier_contact.BarrierSettings`), the offset limit
(`geometry.offset_limit.OffsetLimitSettings`) and the penetration test (`geometry.contact.PenetrationSettings`).
Every value is checked when the settings are made: a bad one is refused in one line naming the field.
The defaults and where each comes from: docs/decisions/0046-skin-settings.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from hitogata.errors import require, require_above, require_whole
from hitogata.geometry.barrier_contact import BARRIER_DEFAULTS, BarrierSettings
from hitogata.geometry.contact import PENETRATION_DEFAULTS, PenetrationSettings
from hitogata.geometry.offset_limit import OFFSET_LIMIT_DEFAULTS, OffsetLimitSettings


def _share(where: str, value: object, lowest_open: bool = True) -> None:
    """Refuse anything but a number in (0, 1] (`lowest_open` False: [0, 1])."""
    ok = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value) \
        and (0 < value <= 1 if lowest_open else 0 <= value <= 1)
    require(ok, where, value, "a share above 0 and at most 1" if lowest_open else "a share from 0 to 1")


@dataclass(frozen=True)
class CreaseSettings:
    """A crease (`skin.contact.crease_tether`, `skin.creases`): where skin folds rather than carries a
    compression, how much of the tissue's elastic offset it gives up, how that share is spread and let go."""

    stretch: tuple[float, float] = (0.7, 0.4)
    """the skin's smallest principal stretch under skinning where it starts to fold (tethered 0) and where it
    is folded (1): skin is a thin sheet that folds rather than carry a compression."""
    angles: tuple[float, float] = (math.radians(30.0), math.radians(60.0))
    """radians: the angle between the parts a vertex is skinned to where a joint starts to fold the skin and
    where it folds it (a spine segment, a shoulder following the chest turn a few degrees: no crease)."""
    fold_weight: float = 0.05
    """a part holding less of a vertex's skinning weight does not fold it."""
    share: float = 0.5
    """the share of the tissue's elastic offset a crease's skin gives up: the skin is tied to the fascia, the
    fat under it still bulges; all of it takes skinning's shear beside the fold too (male seated: 22 -> 123 cm²
    of the fine skin beyond +100 %), half keeps that within 1.7x (decision 0005, docs/elastic.md "Creases")."""
    levels: int = 8
    """a crease's tether is spread over the skin in steps of 1/levels (one surface distance search each)."""
    releases: int = 2
    """most times a crease is let go where its skin crosses and the barrier solved again."""

    def __post_init__(self) -> None:
        (s0, s1), (a0, a1) = self.stretch, self.angles
        require(0 < s1 < s0, "CreaseSettings.stretch", self.stretch, "two stretches s0 > s1 > 0 (folding, folded)")
        require(0 <= a0 < a1 <= math.pi, "CreaseSettings.angles", self.angles,
                "two angles 0 <= a0 < a1 <= pi radians (folding, folded)")
        _share("CreaseSettings.fold_weight", self.fold_weight)
        _share("CreaseSettings.share", self.share, lowest_open=False)
        require_whole("CreaseSettings.levels", self.levels, 1)
        require_whole("CreaseSettings.releases", self.releases, 0)


@dataclass(frozen=True)
class SlideLevel:
    """How one skin slides (the coarse skin, then the fine one on its own): the cosines of the turning allowed
    its triangles (the first, then, where that crosses other skin, the next), the share of its area a triangle
    may shrink to, the tether's reach, and how skin whose slide crosses other skin is held."""

    tilts: tuple[float, ...]
    """cosines: a slid triangle turns at most this far (from how it lay, or for the fine skin from the smooth
    surface under it); the next where a slide at the one before crosses other skin."""
    shrink: float
    """nor shrinks below this share of its area (as it lay or at rest, whichever is less)."""
    falloff: float
    """m: the tether's reach (the fascia's): a slide dies away over about this distance."""
    stiffening: float | None
    """skin whose slide crosses other skin: its tether this many times stiffer each round (None: held whole)."""

    def __post_init__(self) -> None:
        require(len(self.tilts) > 0 and all(-1 <= t <= 1 for t in self.tilts), "SlideLevel.tilts", self.tilts,
                "one or more cosines from -1 to 1")
        _share("SlideLevel.shrink", self.shrink, lowest_open=False)
        require_above("SlideLevel.falloff", self.falloff, what="a distance (m)")
        if self.stiffening is not None:
            require_above("SlideLevel.stiffening", self.stiffening, 1.0, "None or a factor")


@dataclass(frozen=True)
class SlideSettings:
    """The skin sliding over the fascia (`skin.skin_slide`): when skin slides, how far, how the local/global
    steps go and stop, and each level's own (`coarse`, `fine`)."""

    done: float = 1.95
    """principal stretch and area ratio: fine skin stretched beyond this (+95 %) slides; the sliding ends when
    none is (docs/elastic.md, "The skin sliding over the fascia")."""
    limit: float = 1.6
    """principal stretch and area ratio an overstretched triangle is drawn back to."""
    tension: float = 0.01
    """weight of the tension-field membrane against the limit's (spreads stretch beyond the limit's band)."""
    reach: float = 0.15
    """m along the skin's edges: skin this far from skin beyond `done` is free to slide."""
    floor: float = 0.8
    """the smallest principal stretch the sliding may bring a triangle to."""
    iterations: int = 80
    """local/global steps at most."""
    max_move: float = 0.005
    """m: the longest slide of a step (the surface's curvature and the flips stay in view)."""
    stalled: float = 2e-5
    """m: the sliding ends when no vertex moves further in a step."""
    near: int = 2
    """rings of faces around a vertex's face it may slide onto in one step."""
    hold_rounds: int = 3
    """times skin that would cross is held and the rest slid again (and a step's turned triangles held back)."""
    stall: int = 10
    """steps without less fine skin beyond `done`: the sliding is held up (by the flips it may not make)."""
    coarse: SlideLevel = SlideLevel((-0.9, 0.0), 0.2, 0.04, None)
    """the coarse skin: a slid triangle turns at most 154° from how it lay (the armpit's hollow overhead needs
    it), or, if that slide crosses other skin, 90° (the groin's tight creases); shrinks to 20 % of its area at
    most; its slide dies away over 40 mm; skin whose slide crosses is held whole."""
    fine: SlideLevel = SlideLevel((0.0,), 0.02, 0.02, 30.0)
    """the fine skin, after the coarse: its triangles turn at most 90° from the surface under them (more is
    skin folded over itself), may shrink to 2 % of their area (skin takes compression in wrinkles), its slide
    dies away within 2 cm (it spreads what the coarse slide left over a few of its triangles); skin whose slide
    crosses is tied 30 times as hard to where it lay (decision 0007)."""

    def __post_init__(self) -> None:
        for name in ("done", "limit", "tension"):
            require_above(f"SlideSettings.{name}", getattr(self, name))
        for name in ("reach", "max_move"):
            require_above(f"SlideSettings.{name}", getattr(self, name), what="a distance (m)")
        require(isinstance(self.stalled, (int, float)) and math.isfinite(self.stalled) and self.stalled >= 0,
                "SlideSettings.stalled", self.stalled, "a distance (m) at least 0")
        _share("SlideSettings.floor", self.floor)
        for name in ("iterations", "near", "stall"):
            require_whole(f"SlideSettings.{name}", getattr(self, name), 1)
        require_whole("SlideSettings.hold_rounds", self.hold_rounds, 0)
        for name in ("coarse", "fine"):
            require(isinstance(getattr(self, name), SlideLevel), f"SlideSettings.{name}", getattr(self, name),
                    "a SlideLevel")


@dataclass(frozen=True)
class SkinSettings:
    """Every tuning constant of the skin's contact (SI: m, radians), each field with its unit and reason."""

    barrier: BarrierSettings = BARRIER_DEFAULTS
    """the IPC barrier (`geometry.barrier_contact`): its reach, stiffness, free skin and Newton steps."""
    offset_limit: OffsetLimitSettings = OFFSET_LIMIT_DEFAULTS
    """the offset limiter (`geometry.offset_limit`): how a crossing's hold grows and spreads; also the spread
    of a crease's tether and of its release."""
    penetration: PenetrationSettings = PENETRATION_DEFAULTS
    """what the penetration test (`geometry.contact`, `ElasticPose.penetrations`) counts as skin inside
    another part."""
    approach_steps: int = 4
    """skinned postures on the barrier's path from rest to a posture (each step short enough for the
    barrier's continuous collision detection to follow)."""
    creases: CreaseSettings = field(default_factory=CreaseSettings)
    """a crease's fold and tether (`skin.creases`)."""
    slide: SlideSettings = field(default_factory=SlideSettings)
    """the skin's slide over the fascia, coarse then fine (`skin.skin_slide`)."""

    def __post_init__(self) -> None:
        for name, kind in (("barrier", BarrierSettings), ("offset_limit", OffsetLimitSettings),
                           ("penetration", PenetrationSettings), ("creases", CreaseSettings),
                           ("slide", SlideSettings)):
            require(isinstance(getattr(self, name), kind), f"SkinSettings.{name}", getattr(self, name),
                    f"a {kind.__name__}")
        require_whole("SkinSettings.approach_steps", self.approach_steps, 1)


SKIN_DEFAULTS = SkinSettings()
