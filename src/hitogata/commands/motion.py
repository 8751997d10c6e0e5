"""`hitogata motion import|export`: BVH motion files in and out (docs/motion.md)."""

from __future__ import annotations

import argparse
from pathlib import Path

from hitogata import units
from hitogata.commands.paths import add_output, input_path
from hitogata.config import MAX_BYTES as MAX_TOML_BYTES
from hitogata.motion.scenario import BodySpec, load_scenario, shipped_scenarios
from hitogata.errors import HitogataError
from hitogata.export.atomic import write_bytes_atomically
from hitogata.motion.bvh import read_bvh, write_bvh
from hitogata.motion.clip import scenario_clip
from hitogata.motion.joint_map import choose_joint_map
from hitogata.motion.retarget import UNITS, export_bvh, retarget
from hitogata.motion.timeline import body_skeleton, scenario_text


def run_import(args: argparse.Namespace) -> None:
    out = Path(args.out)
    if (args.stature is None) != (args.mass is None):
        raise HitogataError("--stature and --mass: give both or neither (the default body)")
    body = BodySpec(args.sex, 30.0, None if args.stature is None else units.length(args.stature, "--stature"),
                    None if args.mass is None else units.mass(args.mass, "--mass"))
    if args.sex not in ("female", "male"):
        raise HitogataError(f"--sex {args.sex!r}: allowed female or male")
    bvh = read_bvh(args.bvh)
    skeleton = body_skeleton(body)
    joint_map = choose_joint_map(bvh.names, skeleton, args.map, bvh.source)
    result = retarget(bvh, skeleton, joint_map, args.units)
    text = scenario_text(result, skeleton, body, Path(args.bvh).stem, Path(args.bvh).name, Path(joint_map.source).stem)
    if len(text.encode()) > MAX_TOML_BYTES:  # `simulate` would not read it
        raise HitogataError(f"{args.bvh}: {bvh.frames} frames make a scenario of {len(text.encode()) / 2**20:.0f} MiB; "
                            f"allowed at most {MAX_TOML_BYTES / 2**20:.0f} MiB (the largest scenario read); "
                            "nothing written")
    write_bytes_atomically(out, text.encode())
    print(f"{out}: {bvh.frames} frames at {1 / bvh.frame_time:.4g} /s, {len(result.mapped)} BVH joints mapped "
          f"({Path(joint_map.source).stem}), skeleton {result.height:.4g} {result.unit or '(unit unknown)'} tall; "
          f"largest fit error {result.fit_error * 57.29578:.2f}°")


def run_export(args: argparse.Namespace) -> None:
    from hitogata.motion.scenario import make_body
    from hitogata.posing.pose import poser_for

    out = Path(args.out)
    scenario = load_scenario(args.scenario)
    poser = poser_for(make_body(scenario.body))
    clip = scenario_clip(scenario, poser, args.rate)
    write_bytes_atomically(out, write_bvh(export_bvh(poser.skeleton, clip, str(out))).encode())
    print(f"{out}: {len(clip.times)} frames at {clip.rate:.4g} /s, {len(poser.skeleton.names)} joints, centimetres")


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("motion", help="BVH motion files: import onto the skeleton, export a scenario's motion")
    verbs = parser.add_subparsers(dest="verb", required=True)
    imp = verbs.add_parser("import", help="retarget a BVH file onto the 65-part skeleton and write a scenario")
    imp.add_argument("bvh", type=input_path("file", suffixes=(".bvh",)), help="a .bvh file")
    add_output(imp, "file", "the scenario to write (.toml)", (".toml",))
    imp.add_argument("--map", default=None,
                     help="joint map: cmu, mixamo, hitogata or a TOML file; default: the one matching the most names")
    imp.add_argument("--units", choices=tuple(UNITS), default=None,
                     help="the file's length unit; default: detected from the skeleton's height")
    imp.add_argument("--sex", default="female", help="the body the motion is put on: female or male")
    imp.add_argument("--stature", default=None, help="e.g. 172cm, with --mass; default: the default body")
    imp.add_argument("--mass", default=None, help="e.g. 65kg, with --stature")
    imp.set_defaults(run=run_import)
    exp = verbs.add_parser("export", help="write a scenario's skeleton motion as BVH")
    exp.add_argument("scenario", type=input_path("file", suffixes=(".toml",), names=shipped_scenarios),
                     help=f"a scenario file or a shipped one ({', '.join(sorted(shipped_scenarios()))})")
    add_output(exp, "file", "the .bvh file to write", (".bvh",))
    exp.add_argument("--rate", type=float, default=None, help="frames per second; default: the scenario's")
    exp.set_defaults(run=run_export)
