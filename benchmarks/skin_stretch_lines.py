"""Skin stretch on lines drawn on the skin, for the extreme poses, by skinning and by the elastic body.

For both default bodies and each pose of issue 12 (elbow 150°, knee 135°,
hip flexion 120°, seated, hip adduction 30°, shoulder flexion 180°, shoulder
abduction 170°, neck flexion 45°, trunk flexion 80°, trunk rotation 45°):
the change of length (%) of the lines of `hitogata.measure.body_lines`
(left side), measured on the fine skin (`hitogata.skin.fine_skin`) posed
by linear blend skinning, by dual-quaternion skinning, by the elastic
body (DQS + the quasi-static correction, `hitogata.skin.single_pose`)
by the elastic body with its self-contact resolved (`contact=True`) and
with its skin then slid over the fascia (`slide=True`, `skin.skin_slide`);
with the fine skin's area stretched beyond +100 % (λ1 > 2, and area ratio
> 2) and its 99.9th percentile (by area) of λ1 − 1, and the elastic body's
inverted elements and largest tissue-region volume change. Prints a Markdown table
(docs/measurements.md). Slow: the whole-body model per body, a quasi-static
solve per pose.

    PYTHONPATH=src python benchmarks/skin_stretch_lines.py [female|male ...] [--poses "elbow 150°,knee 135°"]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from hitogata.body import default_body
from hitogata.skin.single_pose import elastic_dynamics, elastic_pose
from hitogata.skin.skin_slide import slide_posed_skin
from hitogata.measure.body_lines import LINE_NAMES, body_lines
from hitogata.measure.strain import skin_strain
from hitogata.skeleton.extreme_poses import extreme_poses
from hitogata.skin.fine_skin import body_fine_skinning

SHORT = {
    "elbow_posterior": "elbow post.", "elbow_anterior": "elbow ant.", "elbow_circumference": "elbow circ.",
    "knee_anterior": "knee ant.",
    "knee_posterior": "knee post.", "knee_circumference": "knee circ.", "back_width": "back width",
    "seat_vertical": "seat vert.",
}


def stretch_peaks(strain) -> str:
    """Skin stretched beyond +100 % (cm², by λ1 and by area) and the 99.9th percentile (by area) of λ1 − 1."""
    ok = np.isfinite(strain.stretch_max)
    area, lam, ratio = strain.rest_area[ok], strain.stretch_max[ok], strain.area_ratio[ok]
    order = np.argsort(lam)
    p999 = lam[order][np.searchsorted(np.cumsum(area[order]) / area.sum(), 0.999)]
    return f"{area[lam > 2].sum() * 1e4:.0f} | {area[ratio > 2].sum() * 1e4:.0f} | {p999 - 1:+.0%}"


def main(sexes: list[str], names: list[str] | None = None) -> None:
    print("| body | pose | surface | " + " | ".join(SHORT[n] for n in LINE_NAMES)
          + " | λ1 > 2 cm² | area > 2 cm² | λ1 p99.9 | inverted | volume |")
    print("|---|---|---|" + "---:|" * (len(LINE_NAMES) + 5))
    for sex in sexes:
        body = default_body(sex)
        start = time.perf_counter()
        dynamics = elastic_dynamics(body)
        print(f"<!-- {sex}: whole-body model in {time.perf_counter() - start:.0f} s -->", flush=True)
        poser = dynamics.poser
        fine = body_fine_skinning(body)
        lines = body_lines(body, fine.fine.vertices, fine.fine.faces)
        rest = {n: lines[n].length(fine.fine.vertices) for n in LINE_NAMES}
        for pose, clinical in extreme_poses(poser.skeleton).items():
            if names and pose not in names:
                continue
            start = time.perf_counter()
            held = elastic_pose(dynamics, clinical=clinical)
            seconds = time.perf_counter() - start
            start = time.perf_counter()
            touching = elastic_pose(dynamics, clinical=clinical, contact=True)
            with_contact = time.perf_counter() - start
            start = time.perf_counter()  # the slide of the contact's skin, as elastic_pose(..., slide=True) does it
            slid = slide_posed_skin(fine, touching.posed.pose, "dqs", body.vertices, touching.vertices, body.faces)
            sliding = time.perf_counter() - start
            lbs = poser.pose(clinical=clinical, skinning="lbs")
            surfaces = {
                "LBS": (fine.surface(lbs.pose, "lbs"), None),
                "DQS": (fine.surface(held.posed.pose, "dqs"), None),
                "elastic": (held.fine_vertices(), held.quality),
                "elastic + contact": (touching.fine_vertices(), touching.quality),
                "elastic + contact + slide": (slid.fine.vertices, touching.quality),
            }
            for name, (v, quality) in surfaces.items():
                cells = [f"{(lines[n].length(v) / rest[n] - 1) * 100:+.0f}" for n in LINE_NAMES]
                worst = max(quality.region_change.values(), key=abs) if quality else 0.0
                extra = f"{quality.inverted} | {worst * 100:+.2f}%" if quality else "|"
                peaks = stretch_peaks(skin_strain(fine.fine.vertices, v, fine.fine.faces))
                print(f"| {sex} | {pose} | {name} | " + " | ".join(cells) + f" | {peaks} | {extra} |", flush=True)
            print(f"<!-- {sex} {pose}: elastic pose in {seconds:.1f} s, with contact {with_contact:.1f} s, the slide "
                  f"{sliding:.1f} s (coarse: {int(slid.coarse.free.sum())} vertices free, the longest slide "
                  f"{slid.coarse.moved.max() * 1e3:.0f} mm; fine: {int(slid.fine.free.sum())} free, the longest "
                  f"{slid.fine.moved.max() * 1e3:.0f} mm) -->", flush=True)


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("sexes", nargs="*", default=["female", "male"])
    parser.add_argument("--poses", default=None, help="comma-separated pose names; default all")
    args = parser.parse_args()
    main(args.sexes, args.poses.split(",") if args.poses else None)
