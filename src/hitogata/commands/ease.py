"""`hitogata ease`: dynamic ease and zone stretch of a body through mobility motions — tables (CSV, JSON), a plot."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

from hitogata import units
from hitogata.commands.args import add_body_arguments, add_cache_argument, add_materials_argument
from hitogata.commands.body import body_from_args
from hitogata.commands.paths import add_output
from hitogata.elastic.materials import load_materials
from hitogata.motion.scenario import Scenario, load_scenario, shipped_scenarios
from hitogata.errors import HitogataError
from hitogata.export.atomic import write_bytes_atomically
from hitogata.garment.ease import (HEIGHTS, ease_csv, ease_json, elastic_surface, overall, sampled_frames,
                                  skinned_surface)
from hitogata.garment.fabric import Fabric, read_fabric_csv
from hitogata.garment.fit import FitAnswers, fit_answers
from hitogata.garment.pressure import Garment
from hitogata.garment.pressure_motion import pressure_csv
from hitogata.garment.stretch import stretch_csv
from hitogata.motion.clip import scenario_clip
from hitogata.options import SKINNING, SURFACE_SOURCES
from hitogata.posing.pose import poser_for

if TYPE_CHECKING:
    from hitogata.body.model import Body

DEFAULT_MOTIONS = "reach_forward,arms_crossed,arms_overhead,sit,deep_squat,stride,toe_touch,trunk_twist"


def scenario_path(name: str) -> Path:
    """A shipped scenario by name (with or without 'mobility_'), a short name that starts one word of
    exactly one mobility motion's name ('reach', 'squat', 'cross'), or a scenario file."""
    shipped = shipped_scenarios()
    for candidate in (name, f"mobility_{name}"):
        if candidate in shipped:
            return shipped[candidate]
    if Path(name).suffix == ".toml":
        return Path(name)
    mobility = sorted(n.removeprefix("mobility_") for n in shipped if n.startswith("mobility_"))
    short = [m for m in mobility if name and any(word.startswith(name) for word in m.split("_"))]
    if len(short) == 1:
        return shipped[f"mobility_{short[0]}"]
    why = f" (stands for {' and '.join(short)})" if short else ""
    raise HitogataError(f"--motions: {name!r}{why}; allowed a scenario file (.toml) or {', '.join(mobility)}")


def motion_name(path: Path) -> str:
    """The name a motion goes by in the tables: the scenario file's stem without 'mobility_'."""
    return path.stem.removeprefix("mobility_")


def load_motions(text: str) -> dict[str, Scenario]:
    """The scenarios of a comma-separated --motions, all loaded (and so checked) before any long work."""
    names = [n.strip() for n in text.split(",") if n.strip()]
    if not names:
        raise HitogataError(f"--motions {text!r}: allowed comma-separated motion names or scenario files")
    return {motion_name(path): load_scenario(path) for path in map(scenario_path, names)}


def check_rate(rate: float, scenarios: dict[str, Scenario]) -> None:
    """--rate: frames per second > 0, at most the motions' own."""
    fastest = min(s.rate for s in scenarios.values())
    if not 0 < rate <= fastest:
        raise HitogataError(f"--rate {rate:g}: allowed frames per second > 0 and at most {fastest:g} "
                            "(the motions' own frame rate)")


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


def checked_inputs(args: argparse.Namespace) -> tuple[dict[str, Scenario], tuple[Garment, Fabric] | None]:
    """The motions and the garment of the shared options, checked before any long work."""
    scenarios = load_motions(args.motions)
    check_rate(args.rate, scenarios)
    if args.surface == "elastic" and args.skinning != "dqs":
        raise HitogataError(f"--surface elastic: the elastic body stands on dual-quaternion skinning; "
                            f"drop --skinning {args.skinning}")
    if args.materials is not None:
        if args.surface != "elastic" and getattr(args, "garment", None) is None:  # fit-report's soft limb takes them
            raise HitogataError("--materials: the tissue materials are those of the elastic body; add --surface elastic")
        load_materials(args.materials)  # a bad file is said before any long work
    return scenarios, garment_from_args(args)


def compute(args: argparse.Namespace, body: Body, scenarios: dict[str, Scenario],
            garment: tuple[Garment, Fabric] | None) -> FitAnswers:
    """The fit answers of `body` through the scenarios' motions, with the options' surface and rate."""
    poser = poser_for(body)
    clips = {name: scenario_clip(s, poser) for name, s in scenarios.items()}
    if args.surface == "elastic":
        frames = sum(len(sampled_frames(clip, args.rate)) for clip in clips.values())
        print(f"elastic whole body: {frames} frames to hold, each with its skin's self-contact resolved "
              "(a few seconds each)", flush=True)
        materials = None if args.materials is None else load_materials(args.materials)
        surface = elastic_surface(body, workers=None, materials=materials)  # on the cores free of other work
    else:
        surface = skinned_surface(body, args.skinning)
    return fit_answers(body, clips, surface, args.rate, garment)


def write_tables(answers: FitAnswers, folder: Path) -> list[str]:
    """ease.csv, ease.json, stretch.csv and, with a garment, pressure.csv in `folder`; the names written."""
    tables = {"ease.csv": ease_csv(answers.ease), "ease.json": ease_json(answers.ease),
              "stretch.csv": stretch_csv(answers.stretch)}
    if answers.pressure is not None:
        tables["pressure.csv"] = pressure_csv(dict(answers.pressure))
    for name, text in tables.items():
        write_bytes_atomically(folder / name, text.encode())
    return list(tables)


def run(args: argparse.Namespace) -> None:
    from hitogata.garment.ease_plot import ease_plot

    out, folder = Path(args.out), args.workdir  # written into the staging folder, renamed to --out at the end
    scenarios, garment = checked_inputs(args)
    body = body_from_args(args)
    answers = compute(args, body, scenarios, garment)
    written = write_tables(answers, folder)
    write_bytes_atomically(folder / "ease.png", ease_plot(answers.ease, f"dynamic ease: {body.stature * 100:.0f} cm, "
                                                                     f"{body.mass:.0f} kg"))
    print(f"{out}/: {', '.join([*written, 'ease.png'])} ({len(answers.ease)} motions)")
    for row in overall(answers.ease):
        if row["increase_cm"] is None:
            print(f"  {row['measurement']:20s} {row['standing_cm']:6.1f} cm  undefined in motion "
                  f"({'a height' if row['measurement'] in HEIGHTS else row['undefined']})")
        elif row["increase_cm"] > 0.05 or row["decrease_cm"] < -0.05 or "undefined" in row:
            print(f"  {row['measurement']:20s} {row['standing_cm']:6.1f} cm  +{row['increase_cm']:5.1f} "
                  f"({row['increase_in']})  {row['decrease_cm']:6.1f} ({row['decrease_in']})"
                  + ("  over the frames where it is defined (ease.csv says which)" if "undefined" in row else ""))


MOTION_DEFAULTS = {"motions": DEFAULT_MOTIONS, "surface": "skinned", "skinning": "dqs", "rate": 5.0}


def add_motion_arguments(parser: argparse.ArgumentParser, defaults: bool = True) -> None:
    """--motions --surface --skinning --rate --garment-ease --fabric: the motions and the garment, as `ease` takes them.
    `defaults=False`: left None when not given (MOTION_DEFAULTS says what they stand for)."""
    d = {name: value if defaults else None for name, value in MOTION_DEFAULTS.items()}
    parser.add_argument("--motions", default=d["motions"],
                        help="comma-separated shipped motions (short names like reach, squat, cross will do) or "
                             f"scenario files; default {DEFAULT_MOTIONS}")
    parser.add_argument("--surface", choices=SURFACE_SOURCES, default=d["surface"],
                        help="the surface measured: the body skinned onto the posed skeleton, or the elastic whole "
                             "body held at each frame with its skin's self-contact resolved and its creases folded "
                             "(a few seconds a frame: minutes; on dqs); default skinned")
    parser.add_argument("--skinning", choices=SKINNING[::-1], default=d["skinning"],
                        help="the skinning method; default dqs")
    parser.add_argument("--rate", type=float, default=d["rate"], help="frames measured per second of motion; default 5")
    add_materials_argument(parser, "with --surface elastic: the tissue materials")
    add_garment_arguments(parser, "its pressure through the motions (pressure.csv; with --fabric)")


def add_garment_arguments(parser: argparse.ArgumentParser, what: str) -> None:
    """--garment-ease --fabric: a stretch garment (`garment_from_args` reads them); `what` it is for."""
    parser.add_argument("--garment-ease", default=None,
                        help="a stretch garment this much smaller round than the standing body, e.g. --garment-ease=-15%%: "
                             f"{what}")
    parser.add_argument("--fabric", default=None,
                        help="the garment's fabric: a tensile test CSV (docs/garment.md) or a modulus like 400N/m")


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("ease", help="dynamic ease: each girth and length through mobility motions")
    add_body_arguments(parser)
    add_motion_arguments(parser)
    add_output(parser, "folder", "output folder (a new or empty folder); default ./ease", default="ease")
    add_cache_argument(parser)
    parser.set_defaults(run=run)
