"""Mesh-check benchmark: self-intersection test and point containment on a ~27k-face mesh.

Moved here from the test suite (a test must not depend on the machine's speed).
Goal: ≤ 3 s on this machine (~0.3 s measured idle). Baseline, measured in the
same run: trimesh's ray-casting `Trimesh.contains` on the same points.

Run:  python benchmarks/bench_mesh_checks.py
"""

from __future__ import annotations

import statistics

import numpy as np
import trimesh
from timing import timed

from hitogata.geometry import mesh_checks as mc


def main() -> None:
    mesh = trimesh.creation.capsule(height=1.0, radius=0.2, count=[116, 116])
    points = np.random.default_rng(0).uniform(-0.3, 0.8, size=(300, 3))
    ours_both = timed(lambda: (mc.self_intersections(mesh.vertices, mesh.faces),
                               mc.contains(mesh.vertices, mesh.faces, points)), 3)
    ours_contains = timed(lambda: mc.contains(mesh.vertices, mesh.faces, points), 3)
    baseline = timed(lambda: trimesh.Trimesh(mesh.vertices, mesh.faces, process=False).contains(points), 3)
    both, contains, base = (statistics.median(t) for t in (ours_both, ours_contains, baseline))
    print(f"{len(mesh.faces)} faces, {len(points)} points")
    print(f"self-intersections + contains: median {both:.2f} s (goal ≤ 3 s)")
    print(f"contains: median {contains:.3f} s; trimesh ray casting (baseline) {base:.3f} s; "
          f"ratio {contains / base:.2f}")


if __name__ == "__main__":
    main()
