"""`hitogata skeleton`: a picture of the posed skeleton, front and side (the paper's Fig. 3(a))."""

from __future__ import annotations

import argparse
from pathlib import Path

from hitogata.commands.args import add_body_arguments
from hitogata.commands.paths import add_output
from hitogata.commands.pose_args import add_pose_arguments
from hitogata.commands.pose_summary import pose_summary
from hitogata.commands.posing import pose_from_args
from hitogata.errors import HitogataError
from hitogata.options import MUSCLE_LINES
from hitogata.render import VIEWS, ensure_offscreen_gl, render_views, save_png, side_by_side
from hitogata.render.figures import skeleton_items

GAP = 12  # pixels between the views


def pixels(text: str) -> int:
    """The picture's height in pixels, 64..4096."""
    if not text.strip().isdigit() or not 64 <= int(text) <= 4096:
        raise HitogataError(f"--height {text!r}: allowed a whole number of pixels, 64..4096")
    return int(text)


def view_names(text: str) -> list[str]:
    """'front,side' → ['front', 'side']."""
    names = [v.strip() for v in text.split(",") if v.strip()]
    bad = [v for v in names if v not in VIEWS]
    if not names or bad:
        raise HitogataError(f"--views {text!r}: allowed a comma-separated list of {', '.join(VIEWS)}")
    return names


def run(args: argparse.Namespace) -> None:
    out = Path(args.out)
    height, views = pixels(args.height), view_names(args.views)
    ensure_offscreen_gl()  # before the body is built: a missing library fails fast
    _, request, posed = pose_from_args(args)
    given = [*request.contractions, *request.lengths] if args.muscle_lines != "none" else []
    items = skeleton_items(posed, skin=args.skin, muscles=given, other_muscles=args.muscle_lines == "all")
    images = render_views(items, views=views, size=(None, height), labels=True)
    picture = side_by_side(images, gap=GAP)
    save_png(out, picture)
    print(f"{out}: {', '.join(views)} views, {picture.shape[1]}×{picture.shape[0]} px")
    print("\n".join(pose_summary(request, posed)))


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser(
        "skeleton",
        help="draw the posed 65-part skeleton, front and side, optionally in its skin",
        description="Draw the skeleton (bones as capsules, joints as spheres) posed by muscles or angles, "
        "from the front and the side, optionally with muscle lines and inside the translucent skin.",
    )
    add_body_arguments(parser)
    add_pose_arguments(parser)
    parser.add_argument("--skin", action="store_true", help="draw the skin, translucent, around the skeleton")
    parser.add_argument(
        "--muscle-lines", choices=MUSCLE_LINES, default="given",
        help="muscles drawn origin to insertion: none, given (those in --muscle; default) or all",
    )
    parser.add_argument(
        "--views", default="front,side", help=f"comma-separated, of {', '.join(VIEWS)}; default front,side"
    )
    parser.add_argument("--height", default="900", help="picture height in pixels; each view is as wide as it needs")
    add_output(parser, "file", "output picture, .png", (".png",))
    parser.set_defaults(run=run)
