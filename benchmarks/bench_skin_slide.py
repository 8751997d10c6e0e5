"""The skin's slide (coarse, then fine) against a baseline commit's, on the same inputs, measured in the same run.

Each held pose with `slide=True` spends most of its time in the slide's local/global steps
(`skin.skin_slide._relax`): each step projects the slid vertices back onto the surface near where they lay
(the closest point of every triangle within two rings: `geometry.closest`) and solves the tangent-space
normal equations (SuperLU). The baseline is commit `--base`'s `skin_slide.py` and `closest.py`, the rest of
the package today's.

For each body and extreme pose: `elastic_pose(..., contact=True, slide=True)` runs once, the inputs of its
coarse and fine slides are kept, and each slide runs on them with the baseline's code and with this tree's,
alternately `--repeat` times: the least CPU seconds of each (this machine's timings wander by ±15 % from run to
run) and the largest distance between their slid skins (mm; 0 when the answers are the same to the last bit).

    PYTHONPATH=src python benchmarks/bench_skin_slide.py [--base b24d721] [--repeat 3] [--large]
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
import types
from pathlib import Path

import numpy as np

import hitogata.skin.skin_slide as today
from hitogata.body import Body, default_body
from hitogata.skeleton.extreme_poses import extreme_poses
from hitogata.skin.single_pose import elastic_dynamics, elastic_pose

ROOT = Path(__file__).resolve().parents[1]
POSES = ("hip flexion 120°", "seated 90/90", "shoulder flexion 180°")


def module_at(base: str, path: str, name: str, replace: dict | None = None) -> types.ModuleType:
    """The module at `path` as commit `base` has it (the rest of the package today's), its names in
    `replace` set after it is run."""
    source = subprocess.run(["git", "show", f"{base}:{path}"], cwd=ROOT, capture_output=True, text=True,
                            check=True).stdout
    module = types.ModuleType(name)
    sys.modules[name] = module
    exec(compile(source, f"{base}:{path}", "exec"), module.__dict__)
    module.__dict__.update(replace or {})
    return module


def captured_slides(body: Body, pose: str) -> dict[str, tuple[tuple, dict]]:
    """The arguments `elastic_pose` gives the coarse and the fine slide at the extreme pose `pose`."""
    kept: dict[str, tuple[tuple, dict]] = {}
    originals = today.slide_skin, today.slide_fine_skin

    def keep(name, function):
        def run(*args, **kwargs):
            kept[name] = (args, kwargs)
            return function(*args, **kwargs)
        return run

    today.slide_skin, today.slide_fine_skin = keep("coarse", originals[0]), keep("fine", originals[1])
    try:
        dynamics = elastic_dynamics(body)
        elastic_pose(dynamics, clinical=extreme_poses(dynamics.poser.skeleton)[pose], contact=True, slide=True)
    finally:
        today.slide_skin, today.slide_fine_skin = originals
    return kept


def timed(function, args: tuple, kwargs: dict) -> tuple[float, np.ndarray]:
    start = time.process_time()
    result = function(*args, **kwargs)
    return time.process_time() - start, result.vertices


def least_of(functions: tuple, args: tuple, kwargs: dict, repeat: int) -> list[tuple[float, np.ndarray]]:
    """Each function's least CPU seconds over `repeat` alternating runs, and its answer."""
    runs = [[timed(f, args, kwargs) for f in functions] for _ in range(repeat)]
    return [(min(run[k][0] for run in runs), runs[-1][k][1]) for k in range(len(functions))]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", default="b24d721", help="the baseline commit (default: %(default)s)")
    parser.add_argument("--repeat", type=int, default=3, help="runs of each slide, alternating (default: %(default)s)")
    parser.add_argument("--large", action="store_true",
                        help="also the largest male (195 cm, BMI 35) at hip flexion 120°: its groin's fine slide")
    args = parser.parse_args()
    closest = module_at(args.base, "src/hitogata/geometry/closest.py", "baseline_closest")
    base = module_at(args.base, "src/hitogata/skin/skin_slide.py", "baseline_skin_slide",
                     {"closest_points_on_triangles": closest.closest_points_on_triangles})
    cases = [(sex, default_body(sex), pose) for sex in ("female", "male") for pose in POSES]
    if args.large:
        cases.append(("male 195 cm BMI 35", Body.from_measurements("male", stature=1.95, mass=35.0 * 1.95**2),
                      "hip flexion 120°"))
    print(f"baseline {args.base}; least CPU s of {args.repeat} runs of each slide on the same inputs, the skins' "
          "largest distance (mm)")
    print(f"{'body':<20} {'pose':<24} {'slide':<7} {'base s':>7} {'now s':>7} {'ratio':>6} {'apart mm':>9}")
    totals = np.zeros(2)
    for label, body, pose in cases:
        for level, (call_args, call_kwargs) in captured_slides(body, pose).items():
            function = "slide_skin" if level == "coarse" else "slide_fine_skin"
            (before, x0), (after, x1) = least_of((getattr(base, function), getattr(today, function)), call_args,
                                                 call_kwargs, args.repeat)
            totals += (before, after)
            apart = float(np.abs(x1 - x0).max(initial=0.0)) * 1e3
            print(f"{label:<20} {pose:<24} {level:<7} {before:7.2f} {after:7.2f} {before / after:6.2f} {apart:9.2g}",
                  flush=True)
    print(f"{'all':<20} {'':<24} {'':<7} {totals[0]:7.2f} {totals[1]:7.2f} {totals[0] / totals[1]:6.2f}")


if __name__ == "__main__":
    main()
