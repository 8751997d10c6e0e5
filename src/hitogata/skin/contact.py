"""The body's skin split into contact groups, for its self-contact test (`hitogata.geometry.contact`).

A contact group is a set of skeleton parts whose skin is held in shape by
its bones (an upper arm, a forearm, a thigh, the chest): it never meets
itself, and meets every other group. The groups part at every joint where
a garment's crease forms: elbow (upper arm | forearm), knee (thigh |
shank), hip (pelvis, abdomen | thigh), armpit (upper arm | shoulder, chest),
neck (head | neck | chest), the trunk folding (chest | abdomen | pelvis), and
the two legs. A skin vertex belongs to the group holding most of its
skinning weight. The groups' parts are named with every other split of the
body in `hitogata.posing.body_split`.
"""

from __future__ import annotations

import weakref
from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from hitogata.geometry.contact import PENETRATION_DEFAULTS, PenetrationSettings, SelfContact
from hitogata.geometry.strain import principal_stretches
from hitogata.posing.body_split import SPLITS, owning_parts
from hitogata.posing.body_split import part_groups as split_groups
from hitogata.skin.settings import SKIN_DEFAULTS, CreaseSettings, SkinSettings

if TYPE_CHECKING:
    from hitogata.dynamics.motion import BodyDynamics
    from hitogata.geometry.offset_limit import OffsetLimiter
    from hitogata.options import Skinning
    from hitogata.posing.pose import Poser

# the groups and their parts: `hitogata.posing.body_split.SPLITS["contact groups"]`
CONTACT = "contact groups"
GROUPS: Mapping[str, tuple[str, ...]] = SPLITS[CONTACT].groups
# groups whose skin may fold onto itself (a crease: skin far apart at rest meets); a hand's, a foot's and
# the head's small triangles lie close everywhere and stay held in shape by their bones
FOLDING = tuple(g for g, name in enumerate(GROUPS) if not name.startswith(("hand", "foot", "head")))


def part_groups(names: tuple[str, ...]) -> np.ndarray:
    """(parts,) the contact group of each skeleton part (index into GROUPS); every part must have one."""
    out = split_groups(CONTACT, names)
    missing = [n for n, g in zip(names, out) if g < 0]
    if missing:
        raise ValueError(f"skeleton parts without a contact group: {', '.join(missing)}")
    return out


def vertex_groups(weights: sp.csr_matrix, names: tuple[str, ...]) -> np.ndarray:
    """(V,) each skin vertex's contact group: the group holding most of its skinning weight."""
    groups = part_groups(names)
    onto = sp.csr_matrix((np.ones(len(names)), (np.arange(len(names)), groups)), shape=(len(names), len(GROUPS)))
    return owning_parts(weights @ onto)


# each poser's self-contact tests by their settings, made on first use and kept while the poser lives
_TESTS: weakref.WeakKeyDictionary[Poser, dict[PenetrationSettings, SelfContact]] = weakref.WeakKeyDictionary()


def skin_contact(poser: Poser, settings: PenetrationSettings = PENETRATION_DEFAULTS) -> SelfContact:
    """The self-contact test of a poser's body skin counting penetrations as `settings` say, made once per
    poser and settings (its rest search is a whole test of the skin) and kept while the poser lives: the
    dynamics of one body, whatever their modes, share it."""
    tests = _TESTS.setdefault(poser, {})
    test = tests.get(settings)
    if test is None:
        body = poser.body
        test = tests[settings] = SelfContact(body.vertices, body.faces,
                                             vertex_groups(poser.skin.weights, poser.skeleton.names), settings)
    return test


def skin_limiter(dynamics: BodyDynamics, settings: SkinSettings = SKIN_DEFAULTS) -> OffsetLimiter:
    """The dynamics' skin limiter (`BodyDynamics.skin_limiter`) holding back as `settings.offset_limit` say."""
    return dynamics.skin_limiter.with_settings(settings.offset_limit)


def approach(poser: Poser, angles: np.ndarray, skinning: Skinning, root: np.ndarray | None = None,
             settings: SkinSettings = SKIN_DEFAULTS) -> list[np.ndarray]:
    """A path from the rest skin to a posture for the contact barrier (`geometry.barrier_contact`): the
    rest skin (free of crossings), then the skin skinned at `settings.approach_steps` even fractions of the joint
    angles (D,) (`root`: the whole body's (4, 4) transform, at every fraction), each step short enough
    for the barrier's continuous collision detection to follow."""
    steps = settings.approach_steps
    fractions = np.arange(1, steps + 1)[:, None] / steps
    return [poser.body.vertices, *poser.pose_many(fractions * angles, skinning, root)]


def hold_back_crossings(dynamics: BodyDynamics, skin: np.ndarray, start: np.ndarray,
                        settings: SkinSettings = SKIN_DEFAULTS) -> tuple[np.ndarray, np.ndarray]:
    """The barrier's `skin` (V, 3) held back towards `start` (V, 3, a skin free of crossings beyond the rest
    body's: the last step's start, or a motion's previous frame) where it crosses skin the barrier does not
    hold apart (skin of one group near at rest: a breast's fold as the arm rises, the elbow crease's sides;
    skin not free), and how far (m) each vertex was held back (V,). Only crossings: a fold held back towards
    a start that crosses nearby would bring that crossing back."""
    step = skin - start
    held, kept = skin_limiter(dynamics, settings).hold_crossings(start, step)
    return held, (1.0 - kept) * np.linalg.norm(step, axis=1)


def fold_angles(weights: sp.csr_matrix, rotations: np.ndarray, least: float = SKIN_DEFAULTS.creases.fold_weight
                ) -> np.ndarray:
    """(V,) radians: how far a posture folds the skin at each vertex, the largest angle between the
    rotation of the part holding most of its skinning weight and another part holding at least `least`
    of it (`rotations`: the parts' (parts, 3, 3)). 0 within one part."""
    w = sp.csr_matrix(weights)
    rows = np.repeat(np.arange(w.shape[0]), np.diff(w.indptr))
    heaviest = np.lexsort((-w.data, rows))[w.indptr[:-1]]  # each row's largest entry (scipy's argmax: 10× slower)
    main = w.indices[heaviest]
    keep = w.data >= least
    a, b = rotations[main[rows[keep]]], rotations[w.indices[keep]]
    cosine = np.clip(0.5 * (np.einsum("kij,kij->k", a, b) - 1.0), -1.0, 1.0)
    out = np.zeros(w.shape[0])
    np.maximum.at(out, rows[keep], np.arccos(cosine))
    return out


def _smoothstep(u: np.ndarray) -> np.ndarray:
    u = np.clip(u, 0.0, 1.0)
    return u * u * (3.0 - 2.0 * u)


def crease_tether(rest: np.ndarray, skinned: np.ndarray, faces: np.ndarray, folded: np.ndarray, free: np.ndarray,
                  settings: CreaseSettings = SKIN_DEFAULTS.creases) -> np.ndarray:
    """(V,) 0…`settings.share`: the share of the tissue's elastic offset each skin vertex of a crease gives up.

    A flexion crease (elbow, knee, groin, the seat's fold) is skin bound to the deep fascia by fibrous
    septa: it folds in with the joint while the tissue beside it bulges. The 40 mm tissue mesh has no
    such fold: its surface layer, squeezed, bows out (the back of the knee at 135°: 30-57 mm, the line
    there +29 % where skinning gives -21 %). A crease is skin that a joint folds (`folded` (V,), radians,
    `fold_angles`: from `settings.angles[0]` to [1]) and that skinning squeezes (its smallest principal
    stretch, the least over a vertex's triangles, from `settings.stretch[0]` to [1]), on the `free` skin (V,)
    bool of the contact barrier, where skin meets skin and the barrier gives the tissue's volume back
    as a swelling round the fold; each factor rises smoothly from 0 to 1, times `settings.share`."""
    near = np.asarray(faces)[free[faces].any(axis=1)]  # every triangle of the free skin's vertices
    stretch = principal_stretches(rest, skinned, near)[1]  # the smallest
    least = np.full(len(rest), np.inf)
    np.fmin.at(least, near.ravel(), np.repeat(stretch, 3))
    (s0, s1), (a0, a1) = settings.stretch, settings.angles
    squeezed = _smoothstep((s0 - least) / (s0 - s1))
    bent = _smoothstep((folded - a0) / (a1 - a0))
    return np.where(free, settings.share * squeezed * bent, 0.0)
