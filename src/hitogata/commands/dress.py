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
    from hitogata.body import Body
    from hitogata.elastic.materials import Materials
    from hitogata.garment.contact.answers import GarmentContact
    from hitogata.garment.contact.spec import GarmentSpec


def run(args: argparse.Namespace) -> None:
    from hitogata.elastic.materials import load_materials
    from hitogata.garment.contact.dressing import prepare
    from hitogata.garment.contact.files import write_dressing
    from hitogata.garment.contact.spec import load_garment
    from hitogata.render import ensure_offscreen_gl

    spec = load_garment(args.garment)
    materials = None if args.materials is None else load_materials(args.materials)
    body = body_of(args)
    ensure_offscreen_gl()  # the picture needs it: a missing library is one line before the long work
    prepare(body, spec)  # the garment against this body (its levels, its fabric's range), before the solve
    result = checked_contact(body, spec, materials)
    written = write_dressing(args.workdir, result)
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


def checked_contact(body: Body, spec: GarmentSpec, materials: Materials | None = None) -> GarmentContact:
    """The garment solved on the body (a limb's tissue of `materials`), refused (one line, nothing written)
    unless Newton converged and the exact checks after the solve hold."""
    from hitogata.garment.contact.answers import dress_garment

    result = dress_garment(body, spec, materials=materials)
    if not result.converged:
        raise HitogataError(f"{spec.source}: the contact solve did not converge in {result.iterations} Newton "
                            "iterations; nothing written")
    if result.inside or result.crossing:
        raise HitogataError(f"{spec.source}: the solve left {result.inside} garment vertices inside the body"
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
                                 "pressure.png (a new or empty folder)")
    add_materials_argument(parser, "the soft limb's tissue under the garment")
    parser.set_defaults(run=run)
