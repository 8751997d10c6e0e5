"""Dressing benchmark: a legging (−20 % ease) put on the default female's soft leg, cold, then through the
stride at 5 frames a second, its first frame (the standing posture again) and the next `--frames` (default
3: 0.2, 0.4 and 0.6 s), each solved from the last (warm where it can); the code as it is ("now") and a
baseline commit's ("before", default `main`), each in a fresh process, in the same run.

Goals: ≤ 60 s on the 2-core machine cold; one motion frame ≤ 5 s warm. Prints the wall and CPU time of
each stage (imports, the body and garment file, the contact solve with the garment's placement, the
answers and their exact checks, the stride's postures, each frame with its placement, tissue and solve,
its answers) for both, the CPU ratio before / now, the cold total and the 0.2 s frame against their goals;
for each frame whether it started warm (from the last frame's equilibrium) or cold, Newton's iterations,
its CPU, the least garment–skin distance, the exact checks and the barrier's κ of its answer; and each
level's pressure (mmHg) and indentation (mm, mean and deepest), standing and at each frame, by both with
their differences.

"before" runs this same script (`--pass`) in a subprocess on a `git archive` of the baseline's `src`
(PYTHONPATH), "now" on this tree's `src`; each process pays its own imports and caches. Read CPU seconds
where the machine is shared (the wall clock then counts the other processes' turns).

    PYTHONPATH=src python benchmarks/bench_dress.py [--baseline main] [--now-only] [--frames N]
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
GOAL_COLD, GOAL_FRAME = 60.0, 5.0  # s wall on 2 idle cores
MMHG = 133.322  # Pa
COLD = ("imports", "body and garment file", "contact solve (prepare + Newton)", "answers and exact checks")
FRAME = ("frame at 0.2 s",)
MODULES = ("hitogata.body", "hitogata.garment.contact.answers", "hitogata.garment.contact.motion", "hitogata.pose",
           "hitogata.motion.scenario")


@dataclass
class Run:
    """One pass: each stage's (name, wall s, CPU s) and its answers."""

    stages: list[tuple[str, float, float]] = field(default_factory=list)
    answers: dict[str, Any] = field(default_factory=dict)

    def timed(self, name: str, work: Callable[[], Any]) -> Any:
        wall, cpu = time.perf_counter(), time.process_time()
        out = work()
        self.stages.append((name, time.perf_counter() - wall, time.process_time() - cpu))
        return out

    def total(self, names: tuple[str, ...]) -> tuple[float, float]:
        chosen = [(wall, cpu) for name, wall, cpu in self.stages if name in names]
        return sum(w for w, _ in chosen), sum(c for _, c in chosen)


def levels(contact: Any) -> list[tuple[str, float, float, float]]:
    """Each level's name, pressure (Pa), mean and deepest indentation (m)."""
    return [(row.level, row.pressure, row.indentation, row.deepest) for row in contact.levels]


def dress_pass(frames: int) -> Run:
    """The cold dressing and the stride's first frame, then its next `frames` frames (0.2 s apart), each from
    the last, in this process, timed stage by stage."""
    run = Run()
    run.timed("imports", lambda: [importlib.import_module(name) for name in MODULES])
    from hitogata.body import default_body
    from hitogata.garment.contact.answers import garment_contact
    from hitogata.garment.contact.dressing import dress
    from hitogata.garment.contact.motion import dress_frame, postures
    from hitogata.garment.contact.spec import load_garment
    from hitogata.motion.clip import scenario_clip
    from hitogata.motion.scenario import load_scenario, shipped_scenarios
    from hitogata.posing import poser_for

    body, spec = run.timed("body and garment file", lambda: (default_body("female"), load_garment("legging")))
    dressing = run.timed("contact solve (prepare + Newton)", lambda: dress(body, spec))
    standing = run.timed("answers and exact checks", lambda: garment_contact(dressing))
    clip = scenario_clip(load_scenario(shipped_scenarios()["mobility_stride"]), poser_for(body))
    times, postured = run.timed("stride's postures", lambda: postures(body, clip, 5.0))
    last, _ = run.timed("its first frame (standing again)", lambda: dress_frame(dressing, postured[0]))
    answers: dict[str, Any] = {"standing": levels(standing), "iterations": [dressing.iterations],
                               "least": [standing.min_distance], "inside": [standing.inside],
                               "crossing": [standing.crossing], "frames": []}
    for k in range(1, min(frames, len(postured) - 1) + 1):
        at = float(times[k])
        last, warm = run.timed(f"frame at {at:.1f} s", partial(dress_frame, last, postured[k]))
        moved = run.timed(f"its answers ({at:.1f} s)", partial(garment_contact, last, laplace=False))
        answers["frames"].append({"time": at, "warm": warm, "iterations": last.iterations,
                                  "least": moved.min_distance, "inside": moved.inside, "crossing": moved.crossing,
                                  "levels": levels(moved), "stiffness": last.barrier_stiffness})
    answers["stiffness"] = dressing.barrier_stiffness
    run.answers = answers
    return run


def child_pass(src: Path, frames: int) -> Run:
    """`dress_pass` in a fresh process on the package at `src`."""
    out = subprocess.run([sys.executable, __file__, "--pass", "--frames", str(frames)], env={**os.environ, "PYTHONPATH": str(src)},
                         check=True, capture_output=True, text=True)
    found = json.loads(out.stdout.strip().splitlines()[-1])
    return Run([tuple(stage) for stage in found["stages"]], found["answers"])  # type: ignore[misc]


def baseline_pass(commit: str, frames: int) -> Run:
    """`dress_pass` on a `git archive` of `commit`'s src."""
    with tempfile.TemporaryDirectory() as tree:
        archive = subprocess.run(["git", "archive", commit, "src"], cwd=ROOT, capture_output=True, check=True)
        subprocess.run(["tar", "-x", "-C", tree], input=archive.stdout, check=True)
        return child_pass(Path(tree) / "src", frames)


def report(now: Run, before: Run | None, baseline: str) -> None:
    print(f"{'stage':>36} | {'now wall s':>10} | {'now CPU s':>9}"
          + (f" | {baseline} wall s | {baseline} CPU s | CPU {baseline} / now" if before else ""))
    for name, wall, cpu in now.stages:
        line = f"{name:>36} | {wall:10.2f} | {cpu:9.2f}"
        if before is not None:
            _, wall0, cpu0 = next(stage for stage in before.stages if stage[0] == name)
            line += f" | {wall0:13.2f} | {cpu0:12.2f} | {cpu0 / max(cpu, 1e-9):9.2f}"
        print(line)
    for label, names, goal in (("cold dressing, total", COLD, GOAL_COLD), ("one warm frame", FRAME, GOAL_FRAME)):
        wall, cpu = now.total(names)
        line = f"{label}: now wall {wall:.1f} s, CPU {cpu:.1f} s (goal ≤ {goal:.0f} s: CPU / goal {cpu / goal:.2f})"
        if before is not None:
            wall0, cpu0 = before.total(names)
            line += f"; {baseline} wall {wall0:.1f} s, CPU {cpu0:.1f} s; CPU {baseline} / now {cpu0 / cpu:.2f}"
        print(line)
    for name, run in (("now", now), (baseline, before)):
        if run is None:
            continue
        a = run.answers
        print(f"{name}: cold dressing {a['iterations'][0]} Newton iterations, least distance "
              f"{1e3 * a['least'][0]:.3f} mm, inside {a['inside'][0]}, crossing {a['crossing'][0]}, κ {a['stiffness']:.3g}")
        for frame in a["frames"]:
            cpu = next(stage[2] for stage in run.stages if stage[0] == f"frame at {frame['time']:.1f} s")
            print(f"{name}: frame at {frame['time']:.1f} s {'warm' if frame['warm'] else 'STARTED COLD'}, "
                  f"{frame['iterations']} Newton iterations, {cpu:.1f} s CPU, least distance "
                  f"{1e3 * frame['least']:.3f} mm, inside {frame['inside']}, crossing {frame['crossing']}, "
                  f"κ {frame['stiffness']:.3g}")
    print("levels (standing, then each frame): pressure mmHg, indentation mean / deepest mm, now"
          + (f" | {baseline} | now − {baseline}" if before else ""))
    tables = [("standing", now.answers["standing"], before.answers["standing"] if before else None)]
    for k, frame in enumerate(now.answers["frames"]):
        old = before.answers["frames"][k]["levels"] if before and k < len(before.answers["frames"]) else None
        tables.append((f"{frame['time']:.1f} s", frame["levels"], old))
    for which, rows, old_rows in tables:
        for index, (level, p, mean, deepest) in enumerate(rows):
            line = f"  {which:>8} {level:>6}: {p / MMHG:6.2f} mmHg {1e3 * mean:6.3f} / {1e3 * deepest:6.3f} mm"
            if old_rows is not None:
                _, p0, mean0, deepest0 = old_rows[index]
                line += (f" | {p0 / MMHG:6.2f} mmHg {1e3 * mean0:6.3f} / {1e3 * deepest0:6.3f} mm | "
                         f"{(p - p0) / MMHG:+.3f} mmHg, {1e3 * (mean - mean0):+.4f} / {1e3 * (deepest - deepest0):+.4f} mm")
            print(line)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", default="main", help="the commit whose code runs as 'before' (default main)")
    parser.add_argument("--now-only", action="store_true", help="skip the baseline's run")
    parser.add_argument("--pass", dest="one_pass", action="store_true",
                        help="one pass in this process, its figures as a JSON line (what each run's process does)")
    parser.add_argument("--frames", type=int, default=3,
                        help="the stride's frames after its first, each from the last (default 3: 0.2, 0.4, 0.6 s)")
    args = parser.parse_args()
    if args.one_pass:
        run = dress_pass(args.frames)
        print(json.dumps({"stages": run.stages, "answers": run.answers}))
        return
    now = child_pass(ROOT / "src", args.frames)
    before = None
    if not args.now_only:
        try:
            before = baseline_pass(args.baseline, args.frames)
        except subprocess.CalledProcessError as err:  # no such commit here (a shallow clone), or its code failed
            print(f"{args.baseline}: not run ({' '.join(map(str, err.cmd))[:80]} exited {err.returncode})")
    report(now, before, args.baseline)


if __name__ == "__main__":
    main()
