"""The elastic skin of one pose: a library call for a posture to measure, draw or write.

`elastic_pose` poses the skeleton (muscles and/or angles, as `Poser.pose`),
skins the FE nodes (the dynamics' skinning, DQS by default), solves the
tissue's quasi-static equilibrium about them from rest (no loads, no
dynamics: a posture held), and carries the nodes' elastic displacement to the
skin as a simulation frame does (`BodyDynamics.frame`). With `contact`, the
skin's self-contact is then resolved as a barrier problem
(`hitogata.geometry.barrier_contact`, IPC) along a path of postures: the rest
skin, the skin skinned at even fractions of the joint angles (the same
skinning: `skin.contact.approach`), the elastic skin, its creases tied back
towards skinning's fold (`skin.creases`: the 40 mm tissue mesh
bows out where the skin of a flexed joint creases). With `slide`, the skin then
slides over the fascia where its fine skin is stretched beyond what skin takes
(`hitogata.skin.skin_slide`). `elastic_dynamics` builds and caches the
whole-body model it needs, once per body and size.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from hitogata.body.model import Body
from hitogata.skin.contact import approach, skin_contact, skin_limiter
from hitogata.skin.creases import solve_creased
from hitogata.dynamics.motion import BodyDynamics
from hitogata.elastic.materials import Materials
from hitogata.elastic.model import EIGEN_TOLERANCE
from hitogata.fem.modes import solve_modes
from hitogata.dynamics.quality import STATIC_ITERATIONS, PoseQuality, pose_quality
from hitogata.dynamics.quasistatic import HELD, rotate
from hitogata.geometry.barrier_contact import BarrierResult, contact_regions
from hitogata.geometry.contact import Penetrations
from hitogata.skin.skin_slide import SkinSlide, slide_posed_skin
from hitogata.options import OnLimit
from hitogata.posing.pose import PosedBody
from hitogata.skin.fine_skin import FineSkinning, body_fine_skinning, keep_fine_skin
from hitogata.skin.settings import SKIN_DEFAULTS, SkinSettings

ELEMENT_SIZE = 40.0  # mm: the whole body's lattice for a held posture (as the large-motion tests)


def held_dynamics(body: Body) -> dict[tuple[float, str], BodyDynamics]:
    """The whole-body elastic dynamics built for the body's held postures, by element size (mm) and the
    materials' values (JSON): filled by `elastic_dynamics`, which builds each once."""
    return {}


def elastic_dynamics(body: Body, element_size: float = ELEMENT_SIZE, materials: Materials | None = None,
                     n_modes: int = 0, cache: bool | None = None) -> BodyDynamics:
    """The whole body's elastic model ready for posing, built once per body, element size and materials
    (kept with the body, `held_dynamics`, and on disk: `dynamics.model_cache`; `cache` False: not read
    nor written there, None: as `HITOGATA_NO_CACHE` says; `materials` None: the shipped presets).
    A held posture needs no modes (none by default: their factor is half the build); a motion's dynamics
    asks for its `n_modes`, solved then on the model already built, which then serves every call asking
    for as many or fewer."""
    from hitogata.dynamics.model_cache import cached_dynamics
    from hitogata.elastic import load_materials
    from hitogata.elastic.cache import materials_values

    table = load_materials() if materials is None else materials
    key = (element_size, json.dumps(materials_values(table)))  # by value: a file's name is not its materials
    built = body.prepared(held_dynamics)
    cached = built.get(key)
    if cached is None:
        built[key] = cached = cached_dynamics(body, cache=cache, extent="body", element_size=element_size,
                                              n_modes=n_modes, materials=table)
    elif len(cached.model.modes.eigenvalues) < n_modes:
        model = cached.model
        built[key] = cached = cached.with_modes(
            solve_modes(model.K, model.M, n_modes, model.fixed_nodes, tol=EIGEN_TOLERANCE))
    return cached


@dataclass(frozen=True, eq=False)
class ElasticPose:
    """One held posture: the pose, its skinned and elastic skins (coarse), the FE nodes and their figures."""

    posed: PosedBody  # the skeleton's pose; its vertices are skinned by the dynamics' method
    vertices: np.ndarray  # (V, 3) the elastic skin
    nodes: np.ndarray  # (N, 3) the FE nodes, elastic
    dynamics: BodyDynamics
    held_back: np.ndarray  # (V,) m: elastic displacement held back to keep the skin whole (`geometry.offset_limit`)
    barrier: BarrierResult | None = None  # the barrier's figures (free skin, Newton steps) when contact was resolved
    slide: SkinSlide | None = None  # the skin's slide over the fascia (coarse, then fine), when it slid
    settings: SkinSettings = SKIN_DEFAULTS  # the contact's constants it was held with (and its penetrations counted)

    @property
    def faces(self) -> np.ndarray:
        return self.posed.faces

    @cached_property
    def quality(self) -> PoseQuality:
        """Inversions, region volumes and distortion of the elastic body (figured when first asked for)."""
        return pose_quality(self.dynamics.model, self.nodes, "elastic")

    @property
    def penetrations(self) -> Penetrations:
        """The skin's vertices inside another part (`hitogata.geometry.contact`), beyond the rest body's."""
        return skin_contact(self.dynamics.poser, self.settings.penetration).penetrations(self.vertices)

    @property
    def skinned(self) -> np.ndarray:
        """(V, 3) the skin by skinning alone, the same method."""
        return self.posed.vertices

    def fine_vertices(self) -> np.ndarray:
        """(Vf, 3) the fine skin (`hitogata.skin.fine_skin`) carried by the same skinning and elastic field,
        or, when the skin slid, as it slid."""
        if self.slide is not None:
            return self.slide.fine.vertices
        poser = self.dynamics.poser
        return _held_fine_skinning(poser.body).surface(self.posed.pose, self.dynamics.rig.method, self.vertices)


def elastic_pose(
    dynamics: BodyDynamics,
    angles: Mapping[str, float] | np.ndarray | None = None,
    clinical: Mapping[str, float] | None = None,
    contractions: Mapping[str, float] | None = None,
    lengths: Mapping[str, float] | None = None,
    on_limit: OnLimit = "raise",
    iterations: int = STATIC_ITERATIONS,
    contact: bool = False,
    slide: bool = False,
    settings: SkinSettings = SKIN_DEFAULTS,
) -> ElasticPose:
    """The elastic skin of one posture (names and units as `Poser.pose`), solved from rest;
    contact: no part of the skin passing into another (the barrier along the path of skinned
    postures, see the module's text and docs/elastic.md); without it, the elastic displacement is
    held back where it would fold or cross the skin beyond skinning's (`BodyDynamics.frame`); slide: the
    skin then slides within the posed surface until no fine triangle is stretched beyond +95 % (or no
    further without crossing other skin: `skin.skin_slide`, docs/elastic.md); settings: the constants of the
    offset limit, the contact, the creases and the slide (`skin.settings.SkinSettings`)."""
    poser = dynamics.poser
    posed = poser.pose(contractions, lengths, angles, clinical, dynamics.rig.method, on_limit)
    g, r = dynamics.rig.pose(posed.pose.rotations, posed.pose.translations)
    delta, _ = dynamics.quasi_static(g[0], r[0], None, None, iterations,  # warm=None: from rest
                                     acceleration=HELD)
    at_rest = np.zeros(len(dynamics.eigenvalues))
    resolved = None
    if contact:  # the barrier takes the whole elastic skin: nothing need be held back
        _, plain, offset = dynamics.skin_offset(posed.pose.rotations[0], posed.pose.translations[0], r[0], delta,
                                                at_rest)
        resolved, skin, held = _resolve(dynamics, posed, plain, offset, settings)
    else:
        _, skin, _, held = dynamics.frame(posed.pose.rotations[0], posed.pose.translations[0], r[0], delta, at_rest,
                                          skin_limiter(dynamics, settings))
    nodes = g[0] + rotate(r[0], delta)
    slid = slide_posed_skin(_held_fine_skinning(poser.body), posed.pose, dynamics.rig.method, poser.body.vertices, skin,
                            posed.faces, settings) if slide else None
    skin = skin if slid is None else slid.coarse.vertices
    return ElasticPose(posed, skin.astype(float), nodes, dynamics, held.astype(float), resolved, slid, settings)


def _held_fine_skinning(body: Body) -> FineSkinning:
    """The body's fine skin ready for skinning, kept on disk for the next process posing it (`keep_fine_skin`)."""
    fine = body_fine_skinning(body)
    keep_fine_skin(body)
    return fine


def _resolve(dynamics: BodyDynamics, posed: PosedBody, plain: np.ndarray, offset: np.ndarray, settings: SkinSettings
             ) -> tuple[BarrierResult, np.ndarray, np.ndarray]:
    """The elastic skin of `posed` (`plain` skinned + the elastic `offset`, (V, 3)) with its self-contact
    resolved, reached from the rest skin through skinned postures on the way (`skin.contact.approach`),
    its creases tied back towards skinning (`skin.creases`). Returns the barrier's result, the skin
    (V, 3) and how far each vertex was held back (V,)."""
    path = approach(dynamics.poser, posed.angles, dynamics.rig.method, settings=settings)
    free = contact_regions([*path[1:], np.asarray(plain + offset, dtype=float)],
                           skin_contact(dynamics.poser, settings.penetration), settings.barrier.reach,
                           settings.barrier.rings)
    free[-2] = free[-1]  # the posture skinned and its elastic skin: one set of unknowns (not built twice)
    solved = solve_creased(dynamics, path, plain, offset, posed.pose.rotations[0], free, settings=settings)
    return solved.barrier, solved.skin, solved.held
