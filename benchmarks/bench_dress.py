"""Dressing benchmark: a legging (−20 % ease) put on the default female's soft leg, cold, in a fresh process,
then through the first frames of the stride at 5 frames a second, each solved from the last (warm).

Goals: ≤ 60 s on the 2-core machine cold; one motion frame ≤ 5 s warm. Prints the wall and CPU time of
each stage (imports, the body and garment file, the contact solve with the garment's placement, the
answers and their exact checks, the stride's postures, its first frame, a warm frame with its placement,
tissue and solve, its answers), Newton's iterations, the least garment–skin distance, the exact checks
and, for the motion frame, whether its warm start was taken.

"now" is the code as it is (a Newton step by conjugate gradients preconditioned with the last factored
step's factors where they serve, else factored by `equilibrium.factor_method`: PARDISO where pypardiso is
installed, else SuperLU, the default install's); "before" the same run with every step factored by the
project's SuperLU (`equilibrium.FACTOR = "auto"`, `equilibrium.REUSE_ITERATIONS = 0`), in the same process
after it: the figures side by side, their CPU ratio, each level's pressure and
indentation by both with their difference (the answers must agree within 1 %), and the ratio of each time
to its goal. Read CPU seconds where the machine is
shared (the wall clock then counts the other processes' turns). "now" runs first, so it alone pays the
imports and the caches a fresh process fills (its "cold" total); "before" is timed from its contact
solve on.

    PYTHONPATH=src python benchmarks/bench_dress.py [--now-only]
"""

from __future__ import annotations

import argparse
import importlib
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

Clock = tuple[float, float]
GOAL_COLD, GOAL_FRAME = 60.0, 5.0  # s wall on 2 idle cores


def clock() -> Clock:
    return time.perf_counter(), time.process_time()


@dataclass
class Run:
    """One pass: each stage's (name, wall s, CPU s), the standing and moved answers, Newton's iterations."""

    stages: list[tuple[str, float, float]] = field(default_factory=list)
    answers: dict[str, Any] = field(default_factory=dict)

    def timed(self, name: str, work: Callable[[], Any]) -> Any:
        start = clock()
        out = work()
        now = clock()
        self.stages.append((name, now[0] - start[0], now[1] - start[1]))
        return out

    def total(self, names: tuple[str, ...]) -> Clock:
        chosen = [(wall, cpu) for name, wall, cpu in self.stages if name in names]
        return sum(w for w, _ in chosen), sum(c for _, c in chosen)


COLD = ("imports", "body and garment file", "contact solve (prepare + Newton)", "answers and exact checks")
FRAME = ("one warm motion frame",)
MODULES = ("hitogata.body", "hitogata.garment.contact.answers", "hitogata.garment.contact.motion", "hitogata.pose",
           "hitogata.motion.scenario")


def dress_run(run: Run) -> None:
    """The cold dressing and the stride's first two frames, timed stage by stage into `run`."""
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
    run.answers["standing"] = run.timed("answers and exact checks", lambda: garment_contact(dressing))
    clip = scenario_clip(load_scenario(shipped_scenarios()["mobility_stride"]), poser_for(body))
    times, frames = run.timed("stride's postures", lambda: postures(body, clip, 5.0))
    first, _ = run.timed("its first frame (standing again)", lambda: dress_frame(dressing, frames[0]))
    second, warm = run.timed("one warm motion frame", lambda: dress_frame(first, frames[1]))
    run.answers["moved"] = run.timed("its answers and exact checks", lambda: garment_contact(second, laplace=False))
    run.answers.update(time=float(times[1]), warm=warm, iterations=(dressing.iterations, second.iterations))


def main(baseline: bool) -> None:
    now = Run()
    now.timed("imports", lambda: [importlib.import_module(name) for name in MODULES])
    dress_run(now)
    before = None
    if baseline:
        from hitogata.garment.contact import equilibrium

        saved = equilibrium.FACTOR, equilibrium.REUSE_ITERATIONS
        equilibrium.FACTOR, equilibrium.REUSE_ITERATIONS = "auto", 0
        try:
            before = Run()
            dress_run(before)
        finally:
            equilibrium.FACTOR, equilibrium.REUSE_ITERATIONS = saved
    print(f"{'stage':>36} | {'now wall s':>10} | {'now CPU s':>9}" + (" | before wall s | before CPU s | CPU ratio"
                                                                       if before else ""))
    for name, wall, cpu in now.stages:
        line = f"{name:>36} | {wall:10.2f} | {cpu:9.2f}"
        if before is not None and name != "imports":
            _, wall0, cpu0 = next(stage for stage in before.stages if stage[0] == name)
            line += f" | {wall0:13.2f} | {cpu0:12.2f} | {cpu0 / max(cpu, 1e-9):9.2f}"
        print(line)
    for label, names, goal in (("cold dressing, total", COLD, GOAL_COLD), ("one warm frame", FRAME, GOAL_FRAME)):
        wall, cpu = now.total(names)
        line = f"{label}: now wall {wall:.1f} s, CPU {cpu:.1f} s (goal ≤ {goal:.0f} s: CPU / goal {cpu / goal:.2f})"
        if before is not None:
            wall0, cpu0 = before.total(names)
            if names is COLD:  # "before" paid no imports: the same import time added
                wall0, cpu0 = wall0 + now.stages[0][1], cpu0 + now.stages[0][2]
            line += f"; before wall {wall0:.1f} s, CPU {cpu0:.1f} s; CPU before / now {cpu0 / cpu:.2f}"
        print(line)
    for name, run in (("now", now), ("before", before)):
        if run is None:
            continue
        standing, moved = run.answers["standing"], run.answers["moved"]
        print(f"{name}: Newton iterations cold {run.answers['iterations'][0]}, frame {run.answers['iterations'][1]} "
              f"({'warm' if run.answers['warm'] else 'started cold'}); least distance {1e3 * standing.min_distance:.3f}"
              f" / {1e3 * moved.min_distance:.3f} mm; inside {standing.inside} / {moved.inside}; crossing "
              f"{standing.crossing} / {moved.crossing}")
    print(f"levels (standing, then the frame at {now.answers['time']:.1f} s): pressure mmHg and indentation mm, "
          "now" + (" | before | now / before − 1" if before else ""))
    for which in ("standing", "moved"):
        rows = now.answers[which].levels
        old = before.answers[which].levels if before else [None] * len(rows)
        for row, row0 in zip(rows, old):
            line = f"  {which:>8} {row.level:>6}: {row.pressure / 133.322:6.2f} mmHg {1e3 * row.indentation:5.3f} mm"
            if row0 is not None:
                line += (f" | {row0.pressure / 133.322:6.2f} mmHg {1e3 * row0.indentation:5.3f} mm | pressure "
                         f"{100 * (row.pressure / row0.pressure - 1):+.2f} %, indentation "
                         f"{100 * (row.indentation / row0.indentation - 1):+.2f} %")
            print(line)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--now-only", action="store_true", help="skip the run with every Newton step factored by SuperLU")
    main(not parser.parse_args().now_only)
