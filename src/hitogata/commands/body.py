"""`hitogata body`: build one body from real units and write it."""

from __future__ import annotations

import argparse

from hitogata import units
from hitogata.body import Body, default_measurements
from hitogata.commands.args import add_body_arguments
from hitogata.export.body_files import body_figures, check_body_path, write_body
from hitogata.measure import measure
from hitogata.report.measurements import measurement_table


def figures_line(label: str, body: Body) -> str:
    """One line of the body's headline figures."""
    f = body_figures(body)
    return (
        f"{label}: stature {f['stature_cm']:.1f} cm, mass {f['mass_kg']:.1f} kg, "
        f"BMI {f['bmi']:.1f}, volume {f['volume_l']:.1f} L"
    )


def body_from_args(args: argparse.Namespace) -> Body:
    """The body the --sex/--age/--stature/--mass/... arguments describe (stature and mass not
    given: the default body's of that sex, `hitogata.body.default_measurements`)."""
    stature, mass = default_measurements(args.sex) if args.stature is None or args.mass is None else (0.0, 0.0)
    return Body.from_measurements(
        sex=args.sex,
        age=args.age,
        stature=stature if args.stature is None else units.length(args.stature, "--stature"),
        mass=mass if args.mass is None else units.mass(args.mass, "--mass"),
        muscle=args.muscle_tone,
        proportions=args.proportions,
    )


def run(args: argparse.Namespace) -> None:
    check_body_path(args.out)
    body = body_from_args(args)
    path = write_body(args.out, body)
    print(figures_line(str(path), body))
    if args.measure:
        print(measurement_table(measure(body)))


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("body", help="build a body from sex, age, stature and mass, and write it")
    add_body_arguments(parser)
    parser.add_argument("--out", required=True, help="output file: .glb (skinned, with rig), .obj or .ply")
    parser.add_argument("--measure", action="store_true", help="also print the ISO 8559-1 measurements (cm)")
    parser.set_defaults(run=run)
