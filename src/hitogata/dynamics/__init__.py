"""Posture-driven dynamics of the elastic body and the paper's experiment (§2.4, §4).

Typical use::

    from hitogata.body import default_body
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

or from a scenario file: `run_scenario(load_scenario("s.toml"), "results/")`
(`hitogata simulate s.toml --out results/`; format in docs/scenarios.md).

Modules: `rigging` (skinning weights at the FE nodes), `rotations`,
`volumes` (tet volumes and their gradients, fast), `quasistatic` (the
tissue's rotation-invariant equilibrium on one prefactored matrix, warm-started
by a `WarmStart` its caller hands on), `untangle`, `motion` (coupling and
modal dynamics), `timeline`,
`scenario`, `quality` (inversions, volumes, distortion vs skinning),
`files` (GLB, VTU/PVD, PNG, GIF), `run`, `demo`.

`files`, `run` and `demo` write files and draw pictures: they are reporting
over the computation, so importing this package does not load them (nor
matplotlib, meshio, pygltflib, pyvista); `run_scenario` imports `run` on first use.
"""

from typing import TYPE_CHECKING, Any

from hitogata.dynamics.motion import BodyDynamics, Motion, simulate
from hitogata.dynamics.quality import PoseQuality, compare_pose
from hitogata.dynamics.scenario import Scenario, load_scenario, shipped_scenarios
from hitogata.dynamics.timeline import Channel, Keyframe, Timeline

if TYPE_CHECKING:
    from hitogata.dynamics.run import run_scenario


def __getattr__(name: str) -> Any:
    """`run_scenario` from `hitogata.dynamics.run`, imported on first use (PEP 562)."""
    if name == "run_scenario":
        from hitogata.dynamics.run import run_scenario

        return run_scenario
    raise AttributeError(f"module 'hitogata.dynamics' has no attribute {name!r}")

__all__ = [
    "BodyDynamics", "Channel", "Keyframe", "Motion", "PoseQuality", "Scenario", "Timeline", "compare_pose",
    "load_scenario", "run_scenario", "shipped_scenarios", "simulate",
]
