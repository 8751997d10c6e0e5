"""The tissue regions' surfaces of the motion pictures (`volume.region_surfaces`, carried by
`dynamics.carried_surfaces`): what they cost and how continuous they stay.

Per default body: the time to build the surfaces (the 8 mm grid, its marching cubes and the two
simplifications), their vertex counts and volumes at each level against the whole-body elastic model's
region volumes; then, on the body's whole-body model (40 mm) through a shipped scenario (default
`mobility_arms_overhead`) at a given rate: the time to bind them, to carry them a frame, and the carriers'
mismatch, as the largest lengthening (mm) and stretch of an edge between two vertices bound differently,
with the bindings blended (`BLEND_STEPS`) and without, against the edges within one carrier.

    PYTHONPATH=src python benchmarks/region_surfaces.py [female|male ...] [--rate 5] [--scenario NAME]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from hitogata.body import default_body
from hitogata.dynamics import carried_surfaces
from hitogata.dynamics.motion import simulate
from hitogata.geometry.mesh_checks import enclosed_volume
from hitogata.motion.scenario import load_scenario, shipped_scenarios
from hitogata.skin.single_pose import elastic_dynamics
from hitogata.volume import region_surfaces

MIN_EDGE = 2e-3  # m: marching cubes' slivers are left out of the stretch ratios


def edges(faces: np.ndarray) -> np.ndarray:
    return np.unique(np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1), axis=0)


def mismatch(surfaces, motion) -> dict[str, tuple[float, float, float, float]]:
    """Per surface over the frames: (lengthening mm, stretch) at the edges where carriers meet, then elsewhere."""
    out = {}
    for s in surfaces:
        e = edges(s.faces)
        rest = np.linalg.norm(s.rest[e[:, 0]] - s.rest[e[:, 1]], axis=1)
        meet, long = s.carried_by[e[:, 0]] != s.carried_by[e[:, 1]], rest >= MIN_EDGE
        worst = np.zeros(4)
        for k in range(len(motion.times)):
            x = s.frame(motion, k)
            now = np.linalg.norm(x[e[:, 0]] - x[e[:, 1]], axis=1)
            ratio = now / np.maximum(rest, 1e-12)
            worst = np.maximum(worst, [(now - rest)[meet].max(initial=0) * 1e3, ratio[meet & long].max(initial=1),
                                       (now - rest)[~meet].max() * 1e3, ratio[~meet & long].max()])
        out[s.name] = tuple(worst)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sexes", nargs="*", default=["female", "male"])
    parser.add_argument("--rate", type=float, default=5.0)
    parser.add_argument("--scenario", default="mobility_arms_overhead")
    args = parser.parse_args()
    scenario = load_scenario(shipped_scenarios()[args.scenario])
    for sex in args.sexes:
        body = default_body(sex)
        start = time.perf_counter()
        fine = region_surfaces.build_region_surfaces(body.vertices, body.faces, body.rig, body.skin_weights,
                                                     bmi=body.bmi, sex=body.params.sex)
        grid = time.perf_counter() - start
        start = time.perf_counter()
        picture = region_surfaces.body_region_surfaces(body)  # builds the grid again, then simplifies
        built = time.perf_counter() - start
        start = time.perf_counter()
        light = region_surfaces.body_region_surfaces(body, light=True)
        lighter = time.perf_counter() - start
        print(f"{sex}: grid {region_surfaces.GRID_SPACING * 1e3:.0f} mm and marching cubes {grid:.1f} s; "
              f"picture surfaces {built:.1f} s, light {lighter:.1f} s")
        dynamics = elastic_dynamics(body)
        held = dynamics.model.volume.quality.region_volumes
        for levels in zip(fine, picture, light):
            name = levels[0].name
            print(f"  {name:8s} vertices {' / '.join(str(len(s.vertices)) for s in levels)} (fine / picture / light); "
                  f"volume {' / '.join(f'{enclosed_volume(s.vertices, s.faces) * 1e3:.2f}' for s in levels)} L; "
                  f"the 40 mm model's {held[name] * 1e3:.2f} L")
        motion = simulate(dynamics, scenario.timeline, scenario.duration, args.rate, on_limit="clamp")
        for steps in (carried_surfaces.BLEND_STEPS, 0):
            kept, carried_surfaces.BLEND_STEPS = carried_surfaces.BLEND_STEPS, steps
            start = time.perf_counter()
            surfaces = carried_surfaces.carried_region_surfaces(dynamics)
            bind = time.perf_counter() - start
            carried_surfaces.BLEND_STEPS = kept
            start = time.perf_counter()
            for s in surfaces:
                s.frame(motion, len(motion.times) // 2)
            print(f"  {args.scenario}, bindings blended over {steps} steps: bound in {bind:.1f} s, "
                  f"a frame carried in {time.perf_counter() - start:.2f} s")
            for name, (meet_mm, meet_ratio, other_mm, other_ratio) in mismatch(surfaces, motion).items():
                print(f"    {name:8s} where carriers meet: +{meet_mm:.1f} mm, x{meet_ratio:.2f}; "
                      f"elsewhere +{other_mm:.1f} mm, x{other_ratio:.2f}")


if __name__ == "__main__":
    main()
