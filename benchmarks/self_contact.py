"""The skin passing through itself at the extreme poses, by skinning and by the elastic body, with and
without the contact pass (`hitogata.geometry.contact.separate`), and what the pass costs.

For both default bodies and each pose of issue 12 (`skin_stretch_lines.poses`), on the coarse skin:
new self-crossing triangle pairs beyond the rest body's (`geometry.self_intersections`), skin vertices
inside another part (`geometry.contact`: count, deepest in mm, depth up to DETECT), and the change of
the body's enclosed volume; the elastic pose's time without and with contact and their ratio,
measured in this run. Prints a Markdown table (docs/elastic.md).

    PYTHONPATH=src python benchmarks/self_contact.py [female|male ...]
"""

from __future__ import annotations

import sys
import time

from skin_stretch_lines import poses

from hitogata.body import default_body
from hitogata.dynamics.single_pose import elastic_dynamics, elastic_pose
from hitogata.geometry import enclosed_volume, self_intersections


def main(sexes: list[str]) -> None:
    print("| body | pose | surface | new crossing pairs | vertices inside | deepest mm | volume | time s |")
    print("|---|---|---|---:|---:|---:|---:|---:|")
    for sex in sexes:
        body = default_body(sex)
        dynamics = elastic_dynamics(body)
        test = dynamics.contact
        rest_pairs = len(self_intersections(body.vertices, body.faces))
        rest_volume = enclosed_volume(body.vertices, body.faces)
        ratios = []
        for pose, clinical in poses(dynamics.poser.skeleton).items():
            timed = {}
            for contact in (False, True):
                start = time.perf_counter()
                timed[contact] = (elastic_pose(dynamics, clinical=clinical, contact=contact),
                                  time.perf_counter() - start)
            ratios.append(timed[True][1] / timed[False][1])
            plain = timed[False][0]
            surfaces = {"DQS": (plain.skinned, None), "elastic": (plain.vertices, timed[False][1]),
                        "elastic + contact": (timed[True][0].vertices, timed[True][1])}
            for name, (v, seconds) in surfaces.items():
                inside = test.penetrations(v)
                pairs = len(self_intersections(v, body.faces)) - rest_pairs
                volume = enclosed_volume(v, body.faces) / rest_volume - 1.0
                spent = f"{seconds:.2f}" if seconds is not None else ""
                print(f"| {sex} | {pose} | {name} | {pairs} | {len(inside)} | {inside.deepest * 1e3:.1f} | "
                      f"{volume * 100:+.2f}% | {spent} |", flush=True)
        print(f"<!-- {sex}: contact pass costs {min(ratios):.1f}-{max(ratios):.1f}x the elastic pose -->", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:] or ["female", "male"])
