"""`hitogata body`: build one body from real units and write it."""

from __future__ import annotations

import argparse

from typing import TYPE_CHECKING

from hitogata import units
from hitogata.commands.args import add_body_arguments
from hitogata.commands.paths import add_output
from hitogata.errors import HitogataError
from hitogata.export.body_files import body_figures, write_body
from hitogata.export.meshfiles import MESH_SUFFIXES

if TYPE_CHECKING:
    from hitogata.body import Body


def figures_line(label: str, body: Body) -> str:
    """One line of the body's headline figures."""
    f = body_figures(body)
    return (
        f"{label}: stature {f['stature_cm']:.1f} cm, mass {f['mass_kg']:.1f} kg, "
        f"BMI {f['bmi']:.1f}, volume {f['volume_l']:.1f} L"
    )


def body_from_args(args: argparse.Namespace) -> Body:
    """The body the --sex/--age/--stature/--mass/... arguments describe."""
    from hitogata.body import Body

    stature, mass = units.length(args.stature, "--stature"), units.mass(args.mass, "--mass")
    given = (("--stature", args.stature, stature, "165cm"), ("--mass", args.mass, mass, "58kg"))
    for option, text, value, example in given:
        if value <= 0:
            raise HitogataError(f"{option} {text}: allowed a positive {option[2:]}, e.g. {example}")
    return Body.from_measurements(
        sex=args.sex,
        age=args.age,
        stature=stature,
        mass=mass,
        muscle=args.muscle_tone,
        proportions=args.proportions,
    )


def run(args: argparse.Namespace) -> None:
    body = body_from_args(args)
    path = write_body(args.out, body)
    print(figures_line(str(path), body))
    if args.measure:
        from hitogata.measure import measure
        from hitogata.measure.cli_support import measurement_table

        print(measurement_table(measure(body)))


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("body", help="build a body from sex, age, stature and mass, and write it")
    add_body_arguments(parser)
    add_output(parser, "file", "output file: .glb (skinned, with rig), .obj or .ply", MESH_SUFFIXES)
    parser.add_argument("--measure", action="store_true", help="also print the ISO 8559-1 measurements (cm)")
    parser.set_defaults(run=run)
