"""The `hitogata` command: thin shells over the library calls.

A user's mistake prints one line (`hitogata: error: …`) and exits with status 2;
nothing is written.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Callable, Sequence

from hitogata import units
from hitogata.body import Body, default_body
from hitogata.errors import HitogataError
from hitogata.export.atomic import write_bytes_atomically
from hitogata.export.body_files import body_figures, check_body_path, write_body


def _figures_line(label: str, body: Body) -> str:
    f = body_figures(body)
    return (
        f"{label}: stature {f['stature_cm']:.1f} cm, mass {f['mass_kg']:.1f} kg, "
        f"BMI {f['bmi']:.1f}, volume {f['volume_l']:.1f} L"
    )


def cmd_body(args: argparse.Namespace) -> None:
    """Build one body from real units and write it."""
    check_body_path(args.out)
    body = Body.from_measurements(
        sex=args.sex,
        age=args.age,
        stature=units.length(args.stature, "--stature"),
        mass=units.mass(args.mass, "--mass"),
        muscle=args.muscle,
        proportions=args.proportions,
    )
    path = write_body(args.out, body)
    print(_figures_line(str(path), body))


def cmd_demo(args: argparse.Namespace) -> None:
    """Build the default female and male bodies, export them and their figures."""
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    summary = {}
    for sex in ("female", "male"):
        body = default_body(sex)
        for suffix in (".glb", ".obj"):
            write_body(out / f"default_{sex}{suffix}", body)
        summary[sex] = {"age_years": body.params.age, **body_figures(body)}
        print(_figures_line(f"default {sex}", body))
    write_bytes_atomically(out / "summary.json", json.dumps(summary, indent=2).encode())
    print(f"wrote {out}/")


def _age(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"age {text!r}: allowed a number of years, 18–90") from None


def _unit_fraction(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: allowed a number 0..1") from None


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="hitogata", description="A posable human body model for apparel design.")
    sub = parser.add_subparsers(dest="command", required=True)

    body = sub.add_parser("body", help="build a body from sex, age, stature and mass, and write it")
    body.add_argument("--sex", default="female", help="female, male, or 0 (female) … 1 (male); default female")
    body.add_argument("--age", type=_age, default=30.0, help="years, 18–90; default 30")
    body.add_argument("--stature", default="165cm", help="e.g. 165cm, 1.65m; default 165cm")
    body.add_argument("--mass", default="60kg", help="e.g. 58kg; default 60kg")
    body.add_argument("--muscle", type=_unit_fraction, default=None,
                      help="0..1, 0.5 = average; default: follows the mass (MakeHuman's build path)")
    body.add_argument("--proportions", type=_unit_fraction, default=0.5, help="0..1, 0.5 = average")
    body.add_argument("--out", required=True, help="output file: .glb (skinned, with rig), .obj or .ply")
    body.set_defaults(run=cmd_body)

    demo = sub.add_parser("demo", help="run the main job on the built-in default bodies")
    demo.add_argument("--out", default="demo", help="output folder; default ./demo")
    demo.set_defaults(run=cmd_demo)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    run: Callable[[argparse.Namespace], None] = args.run
    try:
        run(args)
    except HitogataError as err:
        print(f"hitogata: error: {err}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
