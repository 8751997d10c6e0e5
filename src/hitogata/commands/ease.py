"""`hitogata ease`: dynamic ease and zone stretch of a body through mobility motions — tables (CSV, JSON), a plot."""

from __future__ import annotations

import argparse
from pathlib import Path

from hitogata import units
from hitogata.commands.args import add_body_arguments
from hitogata.commands.body import body_from_args
from hitogata.dynamics.scenario import load_scenario, shipped_scenarios
from hitogata.errors import HitogataError
from hitogata.export.atomic import write_bytes_atomically
from hitogata.garment.ease import dynamic_ease, ease_csv, ease_json, overall, skinned_surface
from hitogata.garment.fabric import Fabric, read_fabric_csv
from hitogata.garment.pressure import Garment
from hitogata.garment.pressure_motion import pressure_csv, pressure_series
from hitogata.garment.stretch import stretch_csv, stretch_table
from hitogata.motion.clip import scenario_clip
from hitogata.pose import poser_for

DEFAULT_MOTIONS = "reach_forward,arms_crossed,arms_overhead,sit,deep_squat,stride,toe_touch,trunk_twist"


def scenario_path(name: str) -> Path:
    """A shipped scenario by name (with or without 'mobility_') or a scenario file."""
    shipped = shipped_scenarios()
    for candidate in (name, f"mobility_{name}"):
        if candidate in shipped:
            return shipped[candidate]
    if Path(name).suffix == ".toml":
        return Path(name)
    mobility = sorted(n.removeprefix("mobility_") for n in shipped if n.startswith("mobility_"))
    raise HitogataError(f"--motions: {name!r}; allowed a scenario file (.toml) or {', '.join(mobility)}")


def garment_from_args(args: argparse.Namespace) -> tuple[Garment, Fabric] | None:
    """The stretch garment of --garment-ease and --fabric, or None when neither is given."""
    if args.garment_ease is None and args.fabric is None:
        return None
    if args.garment_ease is None or args.fabric is None:
        raise HitogataError("--garment-ease and --fabric: give both (e.g. --garment-ease -15% --fabric 400N/m)")
    ease = units.parse_quantity(args.garment_ease, units.FRACTION_UNITS, "--garment-ease")
    if args.fabric.endswith(".csv"):
        fabric = read_fabric_csv(args.fabric)
    else:
        fabric = Fabric.linear(units.parse_quantity(args.fabric, {"n/m": 1.0, "n/cm": 100.0}, "--fabric modulus"))
    return Garment(ease=ease), fabric


def run(args: argparse.Namespace) -> None:
    from hitogata.garment.ease_plot import ease_plot

    out = Path(args.out)
    names = [n.strip() for n in args.motions.split(",") if n.strip()]
    paths = {Path(n).stem.removeprefix("mobility_"): scenario_path(n) for n in names}
    scenarios = {name: load_scenario(path) for name, path in paths.items()}  # all checked before the long work
    if not (args.rate > 0):
        raise HitogataError(f"--rate {args.rate}: allowed frames per second > 0")
    garment = garment_from_args(args)
    out.mkdir(parents=True, exist_ok=True)
    body = body_from_args(args)
    poser = poser_for(body)
    clips = {name: scenario_clip(s, poser) for name, s in scenarios.items()}
    surface = skinned_surface(body, args.skinning)
    results = dynamic_ease(body, clips, surface, args.rate)
    stretch = stretch_table(body, clips, surface, args.rate)
    write_bytes_atomically(out / "ease.csv", ease_csv(results).encode())
    write_bytes_atomically(out / "ease.json", ease_json(results).encode())
    write_bytes_atomically(out / "ease.png", ease_plot(results, f"dynamic ease: {body.stature * 100:.0f} cm, "
                                                                 f"{body.mass:.0f} kg"))
    write_bytes_atomically(out / "stretch.csv", stretch_csv(stretch).encode())
    written = "ease.csv, ease.json, ease.png, stretch.csv"
    if garment is not None:
        series = {name: pressure_series(body, *garment, clip, surface, args.rate) for name, clip in clips.items()}
        write_bytes_atomically(out / "pressure.csv", pressure_csv(series).encode())
        written += ", pressure.csv"
    print(f"{out}/: {written} ({len(results)} motions)")
    for row in overall(results):
        if row["increase_cm"] > 0.05 or row["decrease_cm"] < -0.05:
            print(f"  {row['measurement']:20s} {row['standing_cm']:6.1f} cm  +{row['increase_cm']:5.1f} "
                  f"({row['increase_in']})  {row['decrease_cm']:6.1f} ({row['decrease_in']})")


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("ease", help="dynamic ease: each girth and length through mobility motions")
    add_body_arguments(parser)
    parser.add_argument("--motions", default=DEFAULT_MOTIONS,
                        help=f"comma-separated shipped motions or scenario files; default {DEFAULT_MOTIONS}")
    parser.add_argument("--skinning", choices=("dqs", "lbs"), default="dqs", help="the surface's source; default dqs")
    parser.add_argument("--rate", type=float, default=5.0, help="frames measured per second of motion; default 5")
    parser.add_argument("--garment-ease", default=None,
                        help="a stretch garment this much smaller round than the standing body, e.g. --garment-ease=-15%%: "
                             "its pressure through the motions (pressure.csv; with --fabric)")
    parser.add_argument("--fabric", default=None,
                        help="the garment's fabric: a tensile test CSV (docs/garment.md) or a modulus like 400N/m")
    parser.add_argument("--out", default="ease", help="output folder; default ./ease")
    parser.set_defaults(run=run)
