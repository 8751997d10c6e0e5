"""Posture-driven dynamics of the elastic body (the paper's §2.4 and §4).

At every time step: muscle contractions and joint angles → joint angles
(eq. 1, 2) → part transforms (forward kinematics) → the elastic body:

1. gross motion: the FE nodes skinned by the parts (`rigging`), bone nodes
   exactly with their part, and a rotation R_n per node;
2. quasi-statics: the tissue's equilibrium about that skeleton, with the
   muscles' eigenstrain loads and the change of gravity in the rotated
   parts (`quasistatic`: rotation-invariant, one prefactored matrix):
   x_qs = g + R δ_qs, the correction δ_qs in the nodes' local frames;
3. dynamics about it, through the modes (mode-acceleration form): with
   s = Φᵀ M δ_qs the modal coordinates of the quasi-static answer and the
   bones' accelerations a pulled into the local frames,

       q̈ + (α + β λ) q̇ + λ q = λ s − Φᵀ M Rᵀ a,     δ = δ_qs + Φ (q − s),

   integrated exactly per mode (loads linear in each step). When the
   skeleton stops, q → s and δ → δ_qs at the rates the modal damping ratios
   give; at rest with no load every term is zero: the rest shape exactly.
4. the posed body: nodes x = g + R δ; skin vertices = their own skinning +
   the nodes' elastic displacement x − g interpolated (`NodeRig.skin_map`),
   faded out towards the cut faces of a trunk model (neck, hips, arms),
   beyond which the body moves by skinning alone, and held back where it
   would fold or cross the skin where skinning does not (a 40 mm mesh does
   not resolve a crease: `geometry.offset_limit`).
5. with a `frame_contact` handed in by the skin layer: every frame's skin with
   its self-contact resolved, each frame's barrier problem started from the
   last one's answer (IPC in time: `hitogata.skin.motion_contact`, whose
   `simulate` is the front door's `hitogata.simulate(..., contact=True)`).

Fictitious forces of the rotating frames on δ itself (Coriolis,
centrifugal) are left out: δ is millimetres against metres of gross motion.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from functools import cached_property
from typing import TYPE_CHECKING, Protocol

import numpy as np
from scipy.spatial import cKDTree

from hitogata.dynamics.quasistatic import FRAME, Acceleration, QuasiStatic, WarmStart, rotate, unrotate
from hitogata.dynamics.rigging import NodeRig, anchored, joint_nodes, node_rig
from hitogata.dynamics.timeline import MAX_DURATION, MAX_RATE, MAX_SUBSTEPS, RootTrack, Timeline
from hitogata.errors import HitogataError
from hitogata.machine import require_memory
from hitogata.fem import advance, lumped_masses, modal_step
from hitogata.fem.elements import P2_EDGES
from hitogata.geometry.offset_limit import OffsetLimiter
from hitogata.options import OnLimit, Skinning
from hitogata.posing.pose import Poser, poser_for
from hitogata.posing.skinning import skin_vertices

if TYPE_CHECKING:
    from hitogata.body.model import Body
    from hitogata.dynamics.carried_surfaces import CarriedSurface
    from hitogata.elastic import ElasticModel
    from hitogata.fem.modes import Modes

CARTILAGE = 10.0
CUT_FADE = 4.0  # elements: the skin's elastic displacement fades in over this distance from a trunk's cuts
MIN_FREQUENCY = 0.05  # Hz: modes below are rigid-body motions of loose mesh pieces, not vibrations
GRAVITY = np.array([0.0, -9.81, 0.0])
SOFT_REGIONS = ("viscera", "muscle", "skin")
# m/s: the fastest a motion holds back or gives back a skin vertex's elastic displacement (a quarter
# of `run.JUMP_SPEED`, the speed of a tear; soft tissue wobbling at 3 Hz, 2 cm, moves 0.4 m/s)
RELEASE_SPEED = 0.25
ITERATIONS = 6  # most local/global steps per time step, warm-started from the previous step
TOLERANCE = 1e-5  # m: a quasi-static answer is converged when a step moves no node further


@dataclass(frozen=True, eq=False)
class BodyDynamics:
    """A body's skeleton and elastic model with everything precomputed for simulation."""

    poser: Poser
    model: ElasticModel
    rig: NodeRig
    statics: QuasiStatic
    unit_loads: dict[str, np.ndarray]  # FE muscle region → (N, 3) nodal forces per unit contraction
    node_mass: np.ndarray  # (N,) lumped
    vectors: np.ndarray  # (N, 3, k) mass-normalised modes
    vectors32: np.ndarray  # (3N, k) the same in float32, for the per-frame superposition (half the traffic)
    projector: np.ndarray  # (k, 3N) Φᵀ M
    eigenvalues: np.ndarray  # (k,)
    skin_fade: np.ndarray  # (V,) share of the elastic displacement a skin vertex takes (0 at a cut)

    @classmethod
    def build(cls, body: Body, model: ElasticModel, skinning: Skinning = "dqs", poser: Poser | None = None,
              solver: type[QuasiStatic] = QuasiStatic, rig: NodeRig | None = None,
              unit_loads: Mapping[str, np.ndarray] | None = None,
              skin_crossings: np.ndarray | None = None) -> BodyDynamics:
        """Prepare a body and its elastic model (`hitogata.elastic.build_elastic_model`).

        solver: the quasi-statics' class (its constructor's); another is for comparisons
        (`benchmarks/bench_dynamics.py` runs a baseline solver this way); rig, unit_loads: the node rig
        and the muscles' unit loads of this body and model already made (`dynamics.model_cache` reads
        them from disk), else made here; skin_crossings: the skin limiter's crossings at rest found before
        (`OffsetLimiter.crossing_at_rest`, read from disk too), else found when the limiter is first used."""
        poser = poser or poser_for(body)
        rig = rig or node_rig(poser, model, skinning)
        held = anchored(np.setdiff1d(model.fixed_nodes, joint_nodes(rig.weights, model.elements, model.fixed_nodes)),
                        model.fixed_nodes, model.elements[:, :4])
        soft = tuple(model.region_names.index(r) for r in SOFT_REGIONS if r in model.region_names)
        soft = tuple(r for r in soft if np.any(model.region == r))
        corners = len(model.volume.nodes)
        # Bone elements matter here only at the joints, whose nodes settle between the bones: there
        # they act as cartilage, so no stiffer than CARTILAGE x the stiffest soft tissue (GPa bone
        # against kPa tissue would stall the iteration).
        E = np.minimum(model.E, CARTILAGE * model.E[np.isin(model.region, soft)].max())
        statics = solver(model.points[:corners], model.elements[:, :4], E, model.nu, held[held < corners],
                         model.region, soft)
        loads = dict(unit_loads) if unit_loads is not None else {
            name: model.muscle_load(name, 1.0).reshape(-1, 3) for name in model.muscle_names
            if len(model.muscle_elements(name))}
        mass = lumped_masses(model.points, model.elements, model.rho)[::3]
        dynamics = cls(poser, model, rig, statics, loads, mass, *_modal_basis(model), cut_fade(body.vertices, model))
        if skin_crossings is not None:  # `skin_limiter` made now, its one costly part known
            dynamics.__dict__["skin_limiter"] = OffsetLimiter(body.vertices, body.faces,
                                                              crossing_at_rest=skin_crossings)
        return dynamics

    def with_modes(self, modes: Modes) -> BodyDynamics:
        """The same dynamics with the model's modes replaced by `modes` (of the same K and M): a body built
        for held postures, which need none, given the modes a motion's dynamics superposes."""
        model = replace(self.model, modes=modes)
        vectors, vectors32, projector, eigenvalues = _modal_basis(model)
        return replace(self, model=model, vectors=vectors, vectors32=vectors32, projector=projector,
                       eigenvalues=eigenvalues)

    @property
    def n_nodes(self) -> int:
        """Number of FE nodes (corners and mid-edge nodes) of the elastic model."""
        return len(self.model.points)

    def region_of(self, muscle: str) -> str | None:
        """The FE muscle region a skeleton muscle loads: its own name, or without the side (one band)."""
        for name in (muscle, muscle.rsplit("_", 1)[0]):
            if name in self.unit_loads:
                return name
        return None

    def modal(self, delta: np.ndarray) -> np.ndarray:
        """Modal coordinates Φᵀ M δ (k,) of a local displacement field (N, 3)."""
        return self.projector @ delta.ravel()

    def superpose(self, q: np.ndarray) -> np.ndarray:
        """Φ q as (N, 3)."""
        return self.vectors @ q

    @cached_property
    def skin_limiter(self) -> OffsetLimiter:
        """Holds the skin's elastic displacement back where it would fold or cross the skin (made on first use)."""
        body = self.poser.body
        return OffsetLimiter(body.vertices, body.faces)

    @cached_property
    def region_surfaces(self) -> tuple[CarriedSurface, ...]:
        """The whole body's tissue regions' surfaces bound to this model and skeleton, for pictures
        (`dynamics.carried_surfaces`; made on first use)."""
        from hitogata.dynamics.carried_surfaces import carried_region_surfaces

        return carried_region_surfaces(self)

    @cached_property
    def light_region_surfaces(self) -> tuple[CarriedSurface, ...]:
        """The same with fewer triangles, for an animation file (`volume.region_surfaces.LIGHT_REDUCTION`)."""
        from hitogata.dynamics.carried_surfaces import carried_region_surfaces

        return carried_region_surfaces(self, light=True)

    def skin_offset(self, rotations: np.ndarray, translations: np.ndarray, node_rotations: np.ndarray,
                    delta_qs: np.ndarray, dynamic: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The elastic displacement of the nodes (N, 3), the skin by skinning alone (V, 3) and the
        elastic offset its vertices take (V, 3), float32, before any is held back.

        rotations/translations: the parts' (parts, 3, 3), (parts, 3); node_rotations (N, 3, 3);
        delta_qs (N, 3) the quasi-static correction; dynamic (k,) = q − s.
        """
        local = delta_qs.astype(np.float32) + (self.vectors32 @ dynamic.astype(np.float32)).reshape(-1, 3)
        elastic = rotate(node_rotations.astype(np.float32), local)
        plain = skin_vertices(self.poser.skin, rotations[None], translations[None], self.rig.method)[0]
        offset = self.skin_fade[:, None] * (self.rig.skin_map @ elastic)
        return elastic, plain.astype(np.float32), offset.astype(np.float32)

    def frame(self, rotations: np.ndarray, translations: np.ndarray, node_rotations: np.ndarray,
              delta_qs: np.ndarray, dynamic: np.ndarray, limiter: OffsetLimiter | None = None
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """One posture's elastic update (`skin_offset`): the nodes' elastic displacement (N, 3), the
        skin (V, 3), the skin by skinning alone (V, 3), float32, and how far (m) each skin vertex's
        elastic displacement was held back to keep the skin whole (V,) (by `limiter`, None: `skin_limiter`)."""
        elastic, plain, offset = self.skin_offset(rotations, translations, node_rotations, delta_qs, dynamic)
        skin, kept = (self.skin_limiter if limiter is None else limiter)(plain, offset)
        return elastic, skin, plain, ((1.0 - kept) * np.linalg.norm(offset, axis=1)).astype(np.float32)

    def loads(self, node_rotations: np.ndarray, contractions: dict[str, float], gravity: bool) -> np.ndarray:
        """World nodal forces (N, 3): muscle eigenstrains turned with the nodes, and gravity's change.

        The rest shape already stands under gravity; a rotated part feels it
        from a new direction, so the load is m (g − R g).
        """
        local = np.zeros((self.n_nodes, 3))
        for muscle, c in contractions.items():
            region = self.region_of(muscle)
            if region is not None and c:
                local += c * self.unit_loads[region]
        world = rotate(node_rotations, local)
        if gravity:
            world += self.node_mass[:, None] * (GRAVITY - rotate(node_rotations, np.broadcast_to(GRAVITY, world.shape)))
        return world

    def quasi_static(self, skinned: np.ndarray, node_rotations: np.ndarray, loads: np.ndarray | None,
                     start: np.ndarray | None = None, iterations: int = ITERATIONS,
                     warm: WarmStart | None = None,
                     acceleration: Acceleration = FRAME) -> tuple[np.ndarray, float]:
        """Local correction δ_qs (N, 3) of the equilibrium about the skinned nodes, and the last step (m).

        Solved on the corner nodes from a previous δ (`start`) and the previous solve's rotations
        (`warm`, from `statics.warm_start()`, updated in place; None for both: from rest), lifted
        to mid-edge nodes as their edge's mean; acceleration: the steps' (`QuasiStatic.solve`).
        """
        c = len(self.statics.points)
        g, R = skinned[:c], node_rotations[:c]
        x = g if start is None else g + rotate(R, start[:c])
        x, size = self.statics.solve(x, None if loads is None else loads[:c], iterations, warm=warm,
                                     acceleration=acceleration)
        delta = np.zeros((self.n_nodes, 3))
        delta[:c] = unrotate(R, x - g)
        elements = self.model.elements
        if elements.shape[1] == 10:
            delta[elements[:, 4:]] = 0.5 * (delta[elements[:, P2_EDGES[:, 0]]] + delta[elements[:, P2_EDGES[:, 1]]])
        return delta, size


def _modal_basis(model: ElasticModel) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The model's stiff modes as the dynamics superposes them: shapes (N, 3, k), the same (3N, k) in float32,
    the projector Φᵀ M (k, 3N) and the eigenvalues (k,). A mode without stiffness (a piece of mesh hinged
    at one node) has no equilibrium to return to: its motion is left to the quasi-statics."""
    stiff = np.asarray(model.modes.eigenvalues) > (2.0 * np.pi * MIN_FREQUENCY) ** 2
    phi = model.modes.vectors[:, stiff]
    # no modes (a held posture's model): no product with M, which then stays unread (`elastic.stored.DeferredMatrix`)
    projector = np.ascontiguousarray((model.M @ phi).T) if phi.shape[1] else np.zeros((0, len(phi)))
    return (phi.reshape(len(model.points), 3, -1), np.ascontiguousarray(phi, dtype=np.float32), projector,
            np.asarray(model.modes.eigenvalues)[stiff])


def cut_fade(vertices: np.ndarray, model: ElasticModel) -> np.ndarray:
    """(V,) 0 → 1 over CUT_FADE elements from the model's cut faces (neck, hips, arms of a trunk), else 1.

    Beyond a cut the skin moves by skinning alone; fading the elastic
    displacement in over four elements keeps the skin surface whole there: at
    a free arm cut the trunk's elasticity pulls the arm's tissue back (132 mm
    at the armpit with the arms raised); faded over one element that folded
    128 neighbouring triangle pairs at the shoulders, over four 6 (docs/scenarios.md).
    """
    cut = np.unique(model.volume.cut_faces)
    if not len(cut):
        return np.ones(len(vertices))
    distance, _ = cKDTree(model.points[cut]).query(vertices)
    u = np.clip(distance / (CUT_FADE * model.volume.element_size), 0.0, 1.0)
    return u * u * (3.0 - 2.0 * u)


@dataclass(frozen=True)
class MotionContact:
    """What resolving a motion's self-contact took, per frame (F,)."""

    free: np.ndarray  # free skin vertices (0: nothing near a contact, the frame's skin as it was)
    iterations: np.ndarray  # Newton iterations, all steps of the frame's path
    seconds: np.ndarray  # wall time of the frame's contact
    from_rest: np.ndarray  # bool: reached from the rest skin (the first frame, or a restart)
    min_distance: np.ndarray  # m: the smallest gap left between skin that may meet (DHAT where none is near)


class FrameContact(Protocol):
    """Resolves the self-contact of a motion's frames, handed to `simulate` by the layer that owns the skin's
    contact (`hitogata.skin.motion_contact.resolve_frames`): the frames' skins (F, V, 3) float32 with it
    resolved, and what it took.

    skins: (F, V, 3) the frames' skins as the motion computes them; skinned: (F, V, 3) the same by skinning
    alone; rotations: (F, parts, 3, 3) the parts' rotations; angles: (F, D) the joint angles; roots: (F, 4, 4)
    the whole body's transform per frame (None: it stands where it is); progress(frames done) after each
    frame."""

    def __call__(self, dynamics: BodyDynamics, skins: np.ndarray, skinned: np.ndarray, rotations: np.ndarray,
                 angles: np.ndarray, roots: np.ndarray | None = None,
                 progress: Callable[[int], None] | None = None) -> tuple[np.ndarray, MotionContact]: ...


@dataclass(frozen=True, eq=False)
class Motion:
    """The simulated body at the output times."""

    dynamics: BodyDynamics
    times: np.ndarray  # (F,) s
    angles: np.ndarray  # (F, D) rest-relative radians
    rotations: np.ndarray  # (F, parts, 3, 3)
    translations: np.ndarray  # (F, parts, 3)
    nodes: np.ndarray  # (F, N, 3) float32, deformed FE nodes
    elastic: np.ndarray  # (F, N, 3) float32, x − g: the elastic body's displacement from the skinning
    skin: np.ndarray  # (F, V, 3) float32, the body's skin surface (contact-resolved when `contact` is)
    skinned_skin: np.ndarray  # (F, V, 3) float32, the same skin by skinning alone
    held_back: np.ndarray  # (F, V) float32 m: elastic displacement held back to keep the skin whole
    q: np.ndarray  # (F, k) modal coordinates
    s: np.ndarray  # (F, k) their quasi-static values
    qd: np.ndarray  # (F, k) modal velocities
    contact: MotionContact | None = None  # what resolving the skin's self-contact took, when it was

    @property
    def frequencies(self) -> np.ndarray:
        """Natural frequencies (Hz) of the modes."""
        return self.dynamics.model.modes.frequencies

    @property
    def rig_joints(self) -> np.ndarray:
        """(F, B, 3) the MakeHuman rig's joint centres per frame: with `skin`, what `measure` takes."""
        return self.dynamics.poser.rig_joints(self.rotations, self.translations)


def simulate(dynamics: BodyDynamics, timeline: Timeline, duration: float, rate: float, substeps: int = 1,
             gravity: bool = True, on_limit: OnLimit = "raise", iterations: int = ITERATIONS,
             progress: Callable[[int, int], None] | None = None, root: RootTrack | None = None,
             frame_contact: FrameContact | None = None, skin_limiter: OffsetLimiter | None = None) -> Motion:
    """Run a timeline for `duration` seconds; outputs at `rate` frames per second, `substeps` steps per frame;
    progress(done, total) is called after each step (and each frame's contact); root: the whole body's
    rigid motion (None: it stands where it is); frame_contact: resolves every frame's self-contact after the
    dynamics (`FrameContact`; `hitogata.simulate(..., contact=True)`, the skin layer's `simulate`, hands in
    `hitogata.skin.motion_contact.resolve_frames`); skin_limiter: holds the frames' elastic offsets back
    (None: the dynamics' own, `BodyDynamics.skin_limiter`)."""
    if not (np.isfinite(duration) and 0 < duration <= MAX_DURATION and np.isfinite(rate) and 0 < rate <= MAX_RATE):
        raise HitogataError(f"duration {duration!r} s and rate {rate!r}/s: allowed a duration up to "
                            f"{MAX_DURATION:g} s and a rate up to {MAX_RATE:g} frames/s")
    if int(substeps) != substeps or not 1 <= substeps <= MAX_SUBSTEPS:
        raise HitogataError(f"substeps {substeps!r}: allowed a whole number 1..{MAX_SUBSTEPS}")
    n_frames = int(round(duration * rate)) + 1
    h = 1.0 / (rate * substeps)
    n_steps = (n_frames - 1) * substeps + 1
    per_frame, per_step = dynamics.n_nodes * 15, len(dynamics.eigenvalues) * 2 + 3 * len(dynamics.poser.skeleton.names)
    require_memory(8.0 * (n_frames * per_frame + n_steps * per_step),
                   f"duration {duration:g} s at {rate:g} frames/s, {substeps} substeps")
    total = n_steps + (n_frames if frame_contact is not None else 0)  # progress: the steps, then each frame's contact
    t = np.arange(n_steps) * h
    sk = dynamics.poser.skeleton
    rest = {("clinical", c.name): float(sk.rest[sk.dof_names.index(c.name)]) for c in timeline.channels
            if c.kind == "clinical" and c.name in sk.dof_names}
    channels = timeline.sample(t, rest)
    angles = _angles(dynamics.poser, channels, n_steps, on_limit)
    roots = None if root is None else root.sample(t)
    pose = dynamics.poser.kinematics.pose(angles, root=roots)
    contractions = channels["contraction"]

    k = len(dynamics.eigenvalues)
    lam = dynamics.eigenvalues
    s_all, p_all = np.zeros((n_steps, k)), np.zeros((n_steps, k))
    frames = np.arange(0, n_steps, substeps)
    keep = {int(f): i for i, f in enumerate(frames)}
    n_nodes = dynamics.n_nodes
    g_out = np.zeros((n_frames, n_nodes, 3))
    r_out = np.zeros((n_frames, n_nodes, 3, 3))
    dqs_out = np.zeros((n_frames, n_nodes, 3))
    delta, s_now, previous, size = None, None, None, np.inf
    warm = dynamics.statics.warm_start()  # this run's own: each pose starts from the previous one's answer

    def skinned(n: int) -> tuple[np.ndarray, np.ndarray]:
        n = min(n, n_steps - 1)  # the skeleton holds still after the end (and before 0)
        g, R = dynamics.rig.pose(pose.rotations[n:n + 1], pose.translations[n:n + 1])
        return g[0], R[0]

    g_prev = g_now = None
    g_next, r_next = skinned(0)
    for n in range(n_steps):
        g_now, r_now = g_next, r_next
        g_prev = g_now if g_prev is None else g_prev
        g_next, r_next = skinned(n + 1)
        c_now = {m: float(v[n]) for m, v in contractions.items()}
        state = (angles[n].tobytes(), tuple(sorted(c_now.items())))
        if not angles[n].any() and not any(c_now.values()):  # the rest pose, unloaded: the rest shape
            delta, size = np.zeros((dynamics.n_nodes, 3)), 0.0
            s_now = np.zeros(k)
        elif state != previous or size > TOLERANCE:  # a held pose and load keep a converged answer
            delta, size = dynamics.quasi_static(g_now, r_now, dynamics.loads(r_now, c_now, gravity), delta,
                                                iterations, warm)
            s_now = dynamics.modal(delta)
        previous = state
        s_all[n] = s_now
        acceleration = (g_next - 2.0 * g_now + g_prev) / (h * h)
        p_all[n] = lam * s_now - dynamics.modal(unrotate(r_now, acceleration))
        if n in keep:
            g_out[keep[n]], r_out[keep[n]], dqs_out[keep[n]] = g_now, r_now, delta
        g_prev = g_now
        if progress is not None:
            progress(n + 1, total)

    step = modal_step(lam, dynamics.model.alpha, dynamics.model.beta, h)
    q, qd = np.zeros((n_steps, k)), np.zeros((n_steps, k))
    q[0] = s_all[0]
    for n in range(n_steps - 1):
        q[n + 1], qd[n + 1] = advance(step, q[n], qd[n], p_all[n], p_all[n + 1])

    motion = _frames(dynamics, t[frames], angles[frames], pose.rotations[frames], pose.translations[frames],
                     g_out, r_out, dqs_out, q[frames], s_all[frames], qd[frames], skin_limiter)
    if frame_contact is None:
        return motion
    skin, took = frame_contact(dynamics, motion.skin, motion.skinned_skin, motion.rotations, motion.angles,
                               None if roots is None else roots[frames],
                               None if progress is None else lambda k: progress(n_steps + k, total))
    return replace(motion, skin=skin, contact=took)


def _angles(poser: Poser, channels: dict[str, dict[str, np.ndarray]], n: int, on_limit: OnLimit) -> np.ndarray:
    """(n, D) joint angles from the sampled channels, one pose at a time (eq. 1, 2)."""
    out = np.zeros((n, poser.skeleton.n_dofs))
    for i in range(n):
        pick = {kind: {name: float(v[i]) for name, v in values.items()} for kind, values in channels.items()}
        out[i] = poser.angles(contractions=pick["contraction"] or None, angles=pick["angle"] or None,
                              clinical=pick["clinical"] or None, on_limit=on_limit)
    return out


def _frames(dynamics: BodyDynamics, times, angles, rotations, translations, skinned, node_rotations,
            delta_qs, q, s, qd, limiter: OffsetLimiter | None = None) -> Motion:
    """Assemble the output frames: elastic displacement, nodes and skin surfaces.

    The skin's elastic offset is held back where it would fold or cross the skin (`skin_limiter`),
    and a motion holds and gives back at RELEASE_SPEED at most: each frame's kept length is
    capped by every other frame's held one plus RELEASE_SPEED x the time between (a crease
    that closes is held from before it closes), and the frames so capped are checked again.
    """
    n = len(times)
    elastic = np.empty((n, dynamics.n_nodes, 3), dtype=np.float32)
    skin = np.empty((n, len(dynamics.poser.body.vertices), 3), dtype=np.float32)
    plain, offset = np.empty_like(skin), np.empty_like(skin)
    limiter = dynamics.skin_limiter if limiter is None else limiter
    candidates, kept = [], np.empty(skin.shape[:2])
    for k in range(n):
        elastic[k], plain[k], offset[k] = dynamics.skin_offset(rotations[k], translations[k], node_rotations[k],
                                                               delta_qs[k], q[k] - s[k])
        candidates.append(limiter.candidates(plain[k], offset[k]))
        skin[k], kept[k] = limiter(plain[k], offset[k], candidates=candidates[k])
    length = np.linalg.norm(offset, axis=2)
    cap = np.where(kept < 1.0, kept * length, np.inf)  # the holds, spread in time below
    for k in range(1, n):
        cap[k] = np.minimum(cap[k], cap[k - 1] + RELEASE_SPEED * (times[k] - times[k - 1]))
    for k in range(n - 2, -1, -1):
        cap[k] = np.minimum(cap[k], cap[k + 1] + RELEASE_SPEED * (times[k + 1] - times[k]))
    for again in np.flatnonzero((cap < kept * length - 1e-9).any(axis=1)):  # held more than its own limit
        skin[again], kept[again] = limiter(plain[again], offset[again],
                                           cap[again] / np.maximum(length[again], 1e-12), candidates[again])
    held = ((1.0 - kept) * length).astype(np.float32)
    nodes = (skinned + elastic).astype(np.float32)
    return Motion(dynamics, times, angles, rotations, translations, nodes, elastic, skin, plain, held, q, s, qd)
