"""`hitogata fit-report`: one self-contained HTML page of a body through motions (and a study's population).

The motions run through the same path as `hitogata ease` (`commands.ease`:
the same options, checks and tables); the page is `report.fit_report`'s.
Everything given is checked before the long work; the folder is written
through a staging folder (`commands.paths`), so a mistake or Ctrl-C leaves
nothing behind.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from hitogata.commands.args import add_body_arguments, body_options_given, refuse_body_options, add_cache_argument
from hitogata.commands.body import body_from_args
from hitogata.elastic.materials import load_materials, materials_name
from hitogata.commands.ease import MOTION_DEFAULTS, add_motion_arguments, checked_inputs, compute, write_tables
from hitogata.commands.paths import add_output, input_path


def wants_body(args: argparse.Namespace) -> bool:
    """The body part is reported unless only a study is given (no body, body or motion option)."""
    return (args.study is None or args.body is not None or bool(body_options_given(args))
            or any(getattr(args, name) is not None for name in (*MOTION_DEFAULTS, "garment_ease", "fabric",
                                                                 "materials", "garment")))


def settings(args: argparse.Namespace) -> str:
    """How the motions were measured, in words, for the page."""
    if args.surface == "elastic":
        surface = ("the elastic whole body held at each frame (DQS and quasi-statics; its skin's self-contact "
                   "resolved and its creases folded, docs/garment.md; tissue materials: "
                   f"{materials_name(None if args.materials is None else load_materials(args.materials))})")
    else:
        surface = (f"the body skinned onto the posed skeleton ({args.skinning.upper()}; strains at the joints are "
                   "skinning's, docs/garment.md)")
    text = f"Surface: {surface}; {args.rate:g} frames measured per second of motion"
    if args.garment_ease is not None:
        text += f"; garment: ease {args.garment_ease} against the standing girths, fabric {args.fabric}"
    return text + "."


def run(args: argparse.Namespace) -> None:
    from hitogata.report.fit_report import read_population, summary_text, write_fit_report

    population = None if args.study is None else read_population(args.study)
    answers, contact = None, None
    spec = None
    if args.garment is not None:
        from hitogata.garment.contact.spec import load_garment

        spec = load_garment(args.garment)
    if wants_body(args):
        for name, value in MOTION_DEFAULTS.items():
            if getattr(args, name) is None:
                setattr(args, name, value)
        if args.body is not None:
            refuse_body_options(args, f"the body comes from {args.body}")
        scenarios, garment = checked_inputs(args)
        if args.body is not None:
            from hitogata.commands.measure import body_from_file

            body = body_from_file(args.body)[0]
        else:
            body = body_from_args(args)
        from hitogata.render import ensure_offscreen_gl

        ensure_offscreen_gl()  # the pictures need it: a missing library is one line before the long work
        if spec is not None:
            from hitogata.commands.dress import checked_contact
            from hitogata.garment.contact.dressing import prepare

            prepare(body, spec)  # the garment against this body, before the long work
        answers = compute(args, body, scenarios, garment)
        contact = None if spec is None else checked_contact(
            body, spec, None if args.materials is None else load_materials(args.materials))
    written = [] if answers is None else write_tables(answers, args.workdir)
    title = "fit report" if args.body is None else f"fit report: {args.body.name}"
    written += write_fit_report(args.workdir, answers, population, title, "" if answers is None else settings(args),
                                contact)
    print(f"{Path(args.out)}/: {', '.join(sorted(set(written)))}")
    if answers is not None:
        print(summary_text(answers))


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("fit-report", help="a self-contained HTML fit report: ease, stretch, pressure, population")
    parser.add_argument("--body", default=None, type=input_path("file", suffixes=(".glb",)),
                        help="a .glb written by `hitogata body` (its shape; a pose in it is not used); "
                             "or the body options")
    add_body_arguments(parser)
    add_motion_arguments(parser, defaults=False)
    parser.add_argument("--garment", default=None,
                        help="a garment file (TOML) or a shipped garment (as `hitogata dress`): its contact answers "
                             "beside Laplace's quick estimate")
    parser.add_argument("--study", default=None, type=input_path("folder"),
                        help="a `hitogata study` results folder: adds the population's percentile tables and bands")
    add_output(parser, "folder", "report folder: fit_report.html and its tables (a new or empty folder)")
    add_cache_argument(parser)
    parser.set_defaults(run=run)
