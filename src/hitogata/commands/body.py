"""`hitogata body`: build one body from real units, or one per size of a size chart, and write it.

Besides sex, age, stature and mass, any measurement `hitogata measure` reports may
be asked for (`--chest-girth 92cm`, or `--chest 92cm` for a girth): the shape is
then solved to measure (`hitogata.made_to_measure`) and asked against made is printed.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from typing import TYPE_CHECKING, Any

from hitogata import units
from hitogata.commands.args import add_body_arguments
from hitogata.commands.paths import Output, add_output, input_path
from hitogata.commands.size_chart import write_size_chart
from hitogata.errors import HitogataError
from hitogata.export.body_files import body_figures, write_body
from hitogata.export.meshfiles import MESH_SUFFIXES
from hitogata.made_to_measure.size_chart import shipped_size_charts

if TYPE_CHECKING:
    from hitogata.body.model import Body
    from hitogata.made_to_measure.solve import MadeToMeasure


def figures_line(label: str, body: Body) -> str:
    """One line of the body's headline figures."""
    f = body_figures(body)
    return (
        f"{label}: stature {f['stature_cm']:.1f} cm, mass {f['mass_kg']:.1f} kg, "
        f"BMI {f['bmi']:.1f}, volume {f['volume_l']:.1f} L"
    )


def measurement_options() -> dict[str, tuple[str, ...]]:
    """Measurement name → its options: `--name-with-dashes`, and for a girth also the short name
    (`--chest`). The stature has its own option among the body options."""
    from hitogata.measure.values import aliases

    options: dict[str, list[str]] = {}
    for alias, name in aliases().items():
        if name != "stature":
            options.setdefault(name, []).append("--" + alias.replace("_", "-"))
    return {name: tuple(sorted(found, key=lambda o: -len(o))) for name, found in options.items()}


def asked_measurements(args: argparse.Namespace) -> dict[str, float]:
    """The measurements given as options (m), each checked: a length with its unit (none for a
    command without the measurement options)."""
    asked = {}
    for name, options in getattr(args, "measurement_options", {}).items():
        text = getattr(args, name, None)
        if text is not None:
            value = units.length(text, options[-1])
            if value <= 0:
                raise HitogataError(f"{options[-1]} {text}: allowed a positive length, e.g. 80cm")
            asked[name] = value
    return asked


def body_from_args(args: argparse.Namespace) -> Body:
    """The body the --sex/--age/--stature/--mass/... arguments describe (stature and mass not
    given: the default body's of that sex, `hitogata.body.default_measurements`)."""
    return solve_from_args(args, asked_measurements(args))[0]


def solve_from_args(args: argparse.Namespace, asked: dict[str, float]) -> tuple[Body, MadeToMeasure | None]:
    """The body of the body options and the asked measurements, and when measurements were asked
    the report of asked against made (warnings printed as notes)."""
    from hitogata.body.model import Body, default_measurements

    stature, mass = default_measurements(args.sex, args.age) if args.stature is None or args.mass is None else (0.0, 0.0)
    given = (("--stature", args.stature, units.length, "165cm"), ("--mass", args.mass, units.mass, "58kg"))
    values: list[float | None] = []
    for (option, text, parse, example), default in zip(given, (stature, mass)):
        value = (None if asked else default) if text is None else parse(text, option)
        if value is not None and value <= 0:
            raise HitogataError(f"{option} {text}: allowed a positive {option[2:]}, e.g. {example}")
        values.append(value)
    if not asked:
        body = Body.from_measurements(sex=args.sex, age=args.age, stature=values[0], mass=values[1],
                                      muscle=args.muscle_tone, proportions=args.proportions)
        return body, None
    from hitogata.made_to_measure.solve import MeasurementWarning, body_to_measure

    request = {**{k: v for k, v in zip(("stature", "mass"), values) if v is not None}, **asked}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", MeasurementWarning)
        fit = body_to_measure(args.sex, request, age=args.age, muscle=args.muscle_tone,
                              proportions=args.proportions)
    for warning in caught:
        print(f"hitogata: note: {warning.message}", file=sys.stderr)
    return fit.body, fit


def run(args: argparse.Namespace) -> None:
    if args.size_chart is not None:
        write_size_chart(args)
        return
    body, fit = solve_from_args(args, asked_measurements(args))
    path = write_body(args.out, body)
    print(figures_line(str(path), body))
    if fit is not None:
        print("\n".join(fit.lines()))
    if args.measure:
        from hitogata.measure import measure
        from hitogata.report.measurements import measurement_table

        print(measurement_table(measure(body)))


class SizeChart(argparse.Action):
    """--size-chart: the output becomes a folder (one body per size)."""

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace, values: Any,
                 option_string: str | None = None) -> None:
        setattr(namespace, self.dest, values)
        namespace.output = Output("folder")


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("body", help="build a body from sex, age, stature, mass and any measurements, "
                            "or one per size of a size chart, and write it")
    add_body_arguments(parser)
    add_output(parser, "file", "output file: .glb (skinned, with rig), .obj or .ply; with --size-chart a "
               "folder (one .glb per size and sizes.csv)", MESH_SUFFIXES)
    parser.add_argument("--measure", action="store_true", help="also print the ISO 8559-1 measurements (cm)")
    parser.add_argument("--size-chart", action=SizeChart, metavar="CSV",
                        type=input_path("file", suffixes=(".csv",), names=shipped_size_charts),
                        help="a CSV with one row per size: a 'size' column, then measurements with their unit "
                        "in the header (e.g. stature_cm, chest_girth_cm, mass_kg); or a shipped example: "
                        "women_example, children_example (sizes 92–176 by stature, an age_years column)")
    group = parser.add_argument_group("measurements (any of those `hitogata measure` reports; the shape is "
                                      "solved to meet them)")
    options = measurement_options()
    for name, names in options.items():
        group.add_argument(*names, dest=name, metavar="LENGTH", help=f"{name} with its unit (m, cm, mm)")
    parser.set_defaults(run=run, measurement_options=options)
