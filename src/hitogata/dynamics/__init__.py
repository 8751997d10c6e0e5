"""Posture-driven dynamics of the elastic body and the paper's experiment (§2.4, §4).

Typical use::

    from hitogata.body.model import default_body
    from hitogata.elastic import build_elastic_model
    from hitogata.dynamics import BodyDynamics, Keyframe, Timeline, simulate

    body = default_body("female")
    dyn = BodyDynamics.build(body, build_elastic_model(body))         # trunk, P2, 40 modes
    timeline = Timeline.from_keyframes([
        Keyframe(0.0, {}),
        Keyframe(0.8, {("contraction", "rectus_abdominis_l"): -0.08}),  # stretch: a negative contraction
        Keyframe(1.1, {("contraction", "rectus_abdominis_l"): 0.0}, "linear"),
    ])
    motion = simulate(dyn, timeline, duration=2.5, rate=30, on_limit="clamp")
    motion.skin, motion.nodes, motion.elastic     # (F, V, 3), (F, N, 3), (F, N, 3) per output frame

A scenario file's motion (`hitogata simulate s.toml --out results/`; format in docs/scenarios.md) is
read and run by `hitogata.motion` (`load_scenario`, `run_scenario`), and its files are written by
`hitogata.export.motion_files`: this package holds the physics and writes no file. The skin's
self-contact, creases and slide, and the elastic pose of a held posture, are the layer above
(`hitogata.skin`): a motion with contact is `hitogata.simulate(..., contact=True)`
(`hitogata.skin.motion_contact.simulate`), which hands its frames' contact in (`FrameContact`).

Modules: `rigging` (skinning weights at the FE nodes), `rotations`,
`volumes` (tet volumes and their gradients, fast), `quasistatic` (the
tissue's rotation-invariant equilibrium on one prefactored matrix, warm-started
by a `WarmStart` its caller hands on), `untangle`, `motion` (coupling and
modal dynamics), `timeline`, `quality` (inversions, volumes, distortion vs skinning),
`model_cache` (the elastic dynamics kept on disk).
"""

from hitogata.dynamics.motion import BodyDynamics, Motion, simulate
from hitogata.dynamics.quality import PoseQuality, compare_pose
from hitogata.dynamics.timeline import Channel, Keyframe, Timeline

__all__ = ["BodyDynamics", "Channel", "Keyframe", "Motion", "PoseQuality", "Timeline", "compare_pose", "simulate"]
