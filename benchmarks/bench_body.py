"""Body benchmark: time to load the shipped data and to build a body from stature and mass.

Goals (issue 2): data load ≤ 300 ms; one body from real units ≤ 50 ms after loading.
Baseline, measured in the same run: the same solver steps, each blending every
target with one sparse product instead of interpolating the exact bilinear quadrant
corners (`BilinearShape`): the number of evaluations is counted, each is timed.
"""

from __future__ import annotations

import statistics


from timing import timed

from hitogata.body.assets import load_assets, skin_points
from hitogata.body import Body
from hitogata.geometry.mesh_checks import enclosed_volume
from hitogata.body.shape import BilinearShape, blend

CASES = [("female", 1.55, 50.0), ("female", 1.65, 62.0), ("male", 1.78, 78.0), ("male", 1.92, 88.0)]



def main() -> None:
    load_assets.cache_clear()
    load = timed(lambda: (load_assets.cache_clear(), load_assets()), 5)
    print(f"load data: median {1e3 * statistics.median(load):.0f} ms (goal ≤ 300 ms)")

    assets = load_assets()
    Body.from_measurements("female", 30, 1.65, 62.0)  # warm caches (rig regressor)
    build = []
    for sex, stature, mass in CASES:
        build += timed(lambda sex=sex, stature=stature, mass=mass: Body.from_measurements(sex, 30, stature, mass).rig, 3)
    median_build = statistics.median(build)
    print(f"body from stature and mass (+ rig): median {1e3 * median_build:.1f} ms, "
          f"max {1e3 * max(build):.1f} ms (goal ≤ 50 ms)")

    # Baseline: as many full sparse blends (+ volume) as the solver evaluated bodies.
    calls = []
    original = BilinearShape.vertices

    def counted(self, x, h):
        calls.append((self, x, h))
        return original(self, x, h)

    BilinearShape.vertices = counted
    Body.from_measurements("male", 30, 1.78, 78.0)
    BilinearShape.vertices = original
    full = [lambda s=s, x=x, h=h: enclosed_volume(skin_points(assets, blend(assets, s.at(x, h))), assets.triangles)
            for s, x, h in calls]
    baseline = statistics.median(timed(lambda: [f() for f in full], 3))
    print(f"baseline ({len(calls)} full blends per body): {1e3 * baseline:.1f} ms; "
          f"speed-up {baseline / median_build:.1f}×")


if __name__ == "__main__":
    main()
