"""Dressing benchmark: a legging (−20 % ease) put on the default female's soft leg, cold, in a fresh process.

Goal: ≤ 60 s on the 2-core machine. Prints the wall and CPU time of each stage (the body, the garment
against it, the contact solve, the answers and their exact checks) and Newton's iterations, contacts at
the end and the least garment–skin distance.
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
    stage("answers and exact checks", mark)
    for name, wall, cpu in STAGES:
        print(f"{name:>40}: wall {wall:6.2f} s  cpu {cpu:6.2f} s")
    wall, cpu = time.perf_counter() - begin[0], time.process_time() - begin[1]
    print(f"{'total, cold':>40}: wall {wall:6.2f} s  cpu {cpu:6.2f} s (goal ≤ 60 s wall)")
    print(f"garment: {tube.n_rings} rings × {tube.per_ring}; Newton iterations {result.iterations}; least "
          f"distance {1e3 * result.min_distance:.3f} mm; inside {result.inside}; crossing {result.crossing}")


if __name__ == "__main__":
    main()
