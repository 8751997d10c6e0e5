"""Dressing benchmark: a legging (−20 % ease) put on the default female's soft leg, cold, in a fresh process,
then through the first frames of the stride at 5 frames a second, each solved from the last (warm).

Goals: ≤ 60 s on the 2-core machine cold; one motion frame ≤ 5 s warm. Prints the wall and CPU time of
each stage (the body, the garment against it, the contact solve, the answers and their exact checks, a
warm motion frame's placement, tissue and solve, its answers) and Newton's iterations, the least
garment–skin distance and, for the motion frame, whether its warm start was taken.
"""

from __future__ import annotations

import time

STAGES: list[tuple[str, float, float]] = []


def stage(name: str, start: tuple[float, float]) -> tuple[float, float]:
    now = (time.perf_counter(), time.process_time())
    STAGES.append((name, now[0] - start[0], now[1] - start[1]))
    return now


def main() -> None:
    begin = mark = (time.perf_counter(), time.process_time())
    from hitogata.body import default_body
    from hitogata.garment.contact.answers import garment_contact
    from hitogata.garment.contact.dressing import dress, prepare
    from hitogata.garment.contact.spec import load_garment

    mark = stage("imports", mark)
    body = default_body("female")
    spec = load_garment("legging")
    mark = stage("body and garment file", mark)
    _, tube, _, _, _, _ = prepare(body, spec)
    mark = stage("garment against the body", mark)
    dressing = dress(body, spec)
    mark = stage("contact solve (prepare again + Newton)", mark)
    result = garment_contact(dressing)
    mark = stage("answers and exact checks", mark)
    cold = (time.perf_counter() - begin[0], time.process_time() - begin[1])
    from hitogata.garment.contact.motion import dress_frame, postures
    from hitogata.motion.clip import scenario_clip
    from hitogata.motion.scenario import load_scenario, shipped_scenarios
    from hitogata.posing import poser_for

    clip = scenario_clip(load_scenario(shipped_scenarios()["mobility_stride"]), poser_for(body))
    times, frames = postures(body, clip, 5.0)
    first, _ = dress_frame(dressing, frames[0])  # the stride's first frame: the standing body again
    mark = stage("stride's postures, its first frame", mark)
    second, warm = dress_frame(first, frames[1])
    mark = stage(f"one warm motion frame ({times[1]:.1f} s)", mark)
    moved = garment_contact(second, laplace=False)
    stage("its answers and exact checks", mark)
    for name, wall, cpu in STAGES:
        print(f"{name:>40}: wall {wall:6.2f} s  cpu {cpu:6.2f} s")
    print(f"{'total, cold':>40}: wall {cold[0]:6.2f} s  cpu {cold[1]:6.2f} s (goal ≤ 60 s wall)")
    print(f"garment: {tube.n_rings} rings × {tube.per_ring}; Newton iterations {result.iterations}; least "
          f"distance {1e3 * result.min_distance:.3f} mm; inside {result.inside}; crossing {result.crossing}")
    print(f"motion frame at {times[1]:.1f} s: {'warm' if warm else 'cold (the warm start crossed the skin)'}, "
          f"Newton iterations {second.iterations}; inside {moved.inside}; crossing {moved.crossing} (goal ≤ 5 s wall)")
    for level, standing in zip(moved.levels, result.levels):
        print(f"  {level.level:>6}: {standing.pressure / 133.322:5.1f} → {level.pressure / 133.322:5.1f} mmHg, "
              f"indentation {1e3 * standing.indentation:4.2f} → {1e3 * level.indentation:4.2f} mm")


if __name__ == "__main__":
    main()
