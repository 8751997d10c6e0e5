"""The same answers: `hitogata pose --elastic --contact` at a few postures on the default female and male, run
from a baseline source tree and from ours, each on a model cache of its own; prints for each posture whether the
GLB files are byte for byte the same and the largest distance between the elastic skins (x_elastic.ply) and
between the fine skins (x_elastic_fine.ply). Speed is not measured here (`bench_elastic_cache.py` does).

Run:  nice -n 5 python benchmarks/compare_elastic_pose.py --baseline-src /path/to/main/src [--cache-base DIR
      --cache-ours DIR] (the caches: folders of your own; default empty ones in a temporary folder)
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
POSTURES = {"knee 135°": "knee_r.flexion=135deg", "shoulder flexion 180°": "shoulder_r.flexion=180deg",
            "hip flexion 120°": "thigh_r.flexion=120deg"}
SEXES = ("female", "male")


def run(src: Path, cache: Path, out: Path, sex: str, angle: str) -> None:
    """`hitogata pose --elastic --contact` of one posture with `src` first on the path, into `out` (.glb)."""
    env = {**os.environ, "PYTHONPATH": str(src), "HITOGATA_CACHE": str(cache)}
    subprocess.run([sys.executable, "-m", "hitogata.cli", "pose", "--elastic", "--contact", "--sex", sex, "--angle",
                    angle, "--out", str(out), "--force"], env=env, check=True, stdout=subprocess.DEVNULL)


def vertices(path: Path) -> np.ndarray:
    import trimesh

    return np.asarray(trimesh.load(path, process=False).vertices)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline-src", type=Path, required=True, help="the baseline's source folder")
    parser.add_argument("--cache-base", type=Path, default=None, help="the baseline's model cache folder")
    parser.add_argument("--cache-ours", type=Path, default=None, help="our model cache folder")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as scratch:
        root = Path(scratch)
        caches = {"base": args.cache_base or root / "cache_base", "ours": args.cache_ours or root / "cache_ours"}
        sources = {"base": args.baseline_src, "ours": REPO / "src"}
        worst = 0.0
        print(f"{'body, posture':34s} {'GLB':>9s} {'elastic skin Δ m':>16s} {'fine skin Δ m':>14s}")
        for sex in SEXES:
            for title, angle in POSTURES.items():
                outs = {label: root / f"{label}.glb" for label in sources}
                for label, src in sources.items():
                    run(src, caches[label], outs[label], sex, angle)
                same = outs["base"].read_bytes() == outs["ours"].read_bytes()
                gaps = [np.abs(vertices(outs["ours"].with_name(f"ours{tail}"))
                               - vertices(outs["base"].with_name(f"base{tail}"))).max()
                        for tail in ("_elastic.ply", "_elastic_fine.ply")]
                worst = max(worst, *gaps)
                print(f"{sex + ', ' + title:34s} {'same' if same else 'differs':>9s} {gaps[0]:16.3g} {gaps[1]:14.3g}")
        print(f"largest difference: {worst:.3g} m (goal: ≤ 1e-9 m)")


if __name__ == "__main__":
    main()
