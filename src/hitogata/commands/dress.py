"""`hitogata dress`: a stretch garment put on the body, its contact with the skin solved (IPC).

The garment (a shipped name or a TOML file) and the body are checked before the long work, and the
output folder is written through a staging folder (`commands.paths`): a mistake or Ctrl-C leaves nothing.
"""

from __future__ import annotations

import argparse
import math
from typing import TYPE_CHECKING

from hitogata.commands.args import add_body_arguments, add_materials_argument
from hitogata.commands.body_file import add_body_file, body_of
from hitogata.commands.paths import add_output
from hitogata.errors import HitogataError

if TYPE_CHECKING:
    from hitogata.body.model import Body
    from hitogata.garment.contact.dressing import Dressing
    from hitogata.garment.contact.motion import MotionContact
    from hitogata.motion.scenario import Scenario
    from hitogata.elastic.materials import Materials
    from hitogata.garment.contact.answers import GarmentContact
    from hitogata.garment.contact.spec import GarmentSpec


def run(args: argparse.Namespace) -> None:
    from hitogata.commands.ease import check_rate, load_motions
    from hitogata.elastic.materials import load_materials
    from hitogata.garment.contact.answers import garment_contact
    from hitogata.garment.contact.dressing import dress, prepare
    from hitogata.export.garment_files import write_dressing
    from hitogata.garment.contact.spec import load_garment
    from hitogata.garment.pressure import MMHG
    from hitogata.render import ensure_offscreen_gl

    spec = load_garment(args.garment)
    scenarios = {} if args.motions is None else load_motions(args.motions)
    if scenarios:
        check_rate(args.rate, scenarios)
    materials = None if args.materials is None else load_materials(args.materials)
    body = body_of(args)
    ensure_offscreen_gl()  # the picture needs it: a missing library is one line before the long work
    prepare(body, spec)  # the garment against this body (its levels, its fabric's range), before the solve
    dressing = dress(body, spec, materials=materials)
    result = checked(garment_contact(dressing), spec)
    motions = through_motions(dressing, scenarios, args.rate, materials)
    written = write_dressing(args.workdir, result, motions)
    print(f"{args.out}/: {', '.join(sorted(written))}")
    body_kind = "the soft limb" if any(math.isfinite(level.indentation) for level in result.levels) \
        else "the rigid skin"
    print(f"{result.title}: contact pressure (mmHg) on {body_kind} beside Laplace's quick estimate")
    for level in result.levels:
        row = level.as_row()
        soft = f"  indentation {row['indentation_mm']:4.2f} mm (deepest {row['deepest_mm']:4.2f})" \
            if math.isfinite(level.indentation) else ""
        print(f"  {level.level:>9} {row['ral_level'] or ' '}  {row['pressure_mmHg']:6.1f}  Laplace "
              f"{row['laplace_mmHg']:6.1f}  course strain {row['course_strain_pct']:5.1f} %{soft}")
    if result.compression_class is not None:
        print(f"  RAL-GZ 387/1 class at the ankle (B): {result.compression_class}")
    for name, motion in motions.items():
        print(f"  through {name} ({len(motion.times)} frames, {sum(motion.warm)} from the last frame): contact "
              "pressure (mmHg) least … most")
        for k, level in enumerate(result.levels):
            series = [frame.levels[k].pressure / MMHG for frame in motion.frames]
            print(f"  {level.level:>9}    {min(series):6.1f} … {max(series):6.1f}")


def through_motions(dressing: Dressing, scenarios: dict[str, Scenario], rate: float,
                    materials: Materials | None) -> dict[str, MotionContact]:
    """The dressed garment through each motion, each frame checked as the standing solve is."""
    from hitogata.garment.contact.motion import dress_through
    from hitogata.motion.clip import scenario_clip
    from hitogata.posing.pose import poser_for

    out = {}
    for name, scenario in scenarios.items():
        motion = dress_through(dressing, scenario_clip(scenario, poser_for(dressing.body)), rate, materials)
        for time, frame in zip(motion.times, motion.frames):
            checked(frame, dressing.spec, f" through {name} at {time:.2f} s")
        out[name] = motion
    return out


def checked_contact(body: Body, spec: GarmentSpec, materials: Materials | None = None) -> GarmentContact:
    """The garment solved on the body (a limb's tissue of `materials`), refused (one line, nothing written)
    unless Newton converged and the exact checks after the solve hold."""
    from hitogata.garment.contact.answers import dress_garment

    return checked(dress_garment(body, spec, materials=materials), spec)


def checked(result: GarmentContact, spec: GarmentSpec, when: str = "") -> GarmentContact:
    """A solved garment's answers, refused (one line, nothing written) unless Newton converged and the exact
    checks after the solve hold; `when`: the motion's frame, for the message."""
    if not result.converged:
        raise HitogataError(f"{spec.source}: the contact solve{when} did not converge in {result.iterations} "
                            "Newton iterations; nothing written")
    if result.inside or result.crossing:
        raise HitogataError(f"{spec.source}: the solve{when} left {result.inside} garment vertices inside the body"
                            f"{' and garment crossing the skin' if result.crossing else ''}; nothing written")
    return result


def register(sub: argparse._SubParsersAction) -> None:
    from hitogata.garment.contact.spec import shipped_garments

    parser = sub.add_parser("dress", help="put a stretch garment on the body: contact pressure at the levels, "
                                          "a pressure map, the dressed body (GLB)")
    parser.add_argument("--garment", required=True,
                        help=f"a garment file (TOML) or a shipped garment: {', '.join(sorted(shipped_garments()))}")
    add_body_file(parser)
    add_body_arguments(parser)
    add_output(parser, "folder", "output folder: pressure.csv, skin_pressure.csv, garment_strain.csv, dressed.glb, "
                                 "pressure.png, with --motions pressure_motion.csv (a new or empty folder)")
    add_materials_argument(parser, "the soft limb's tissue under the garment")
    parser.add_argument("--motions", default=None,
                        help="comma-separated shipped motions (short names like stride, squat, sit will do) or "
                             "scenario files: the garment through each, every sampled frame solved from the last "
                             "one (pressure_motion.csv); default none")
    parser.add_argument("--rate", type=float, default=5.0,
                        help="with --motions: frames solved per second of motion; default 5")
    parser.set_defaults(run=run)
