"""`hitogata pose`: pose a body by its muscles or joint angles and write it."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from hitogata.commands.args import add_body_arguments, add_cache_argument, add_materials_argument
from hitogata.commands.body_file import add_body_file, body_of
from hitogata.commands.paths import add_output
from hitogata.commands.pose_args import add_pose_arguments
from hitogata.commands.pose_summary import moved_count, pose_summary
from hitogata.commands.posing import pose_from_args
from hitogata.skin.single_pose import elastic_dynamics, elastic_pose
from hitogata.elastic.materials import load_materials, materials_name
from hitogata.errors import HitogataError
from hitogata.export.body_files import body_figures, detail_extras, shape_extras
from hitogata.export.meshfiles import MESH_SUFFIXES, write_mesh
from hitogata.geometry.offset_limit import HELD
from hitogata.export.pose_files import check_posed_path, write_posed
from hitogata.export.posed_mesh import write_sidecar
from hitogata.posing.pose import Poser
from hitogata.skeleton.shoulder import CHANNEL_RANGES, channel_names
from hitogata.skin.fine_skin import body_fine_skin


def list_names(poser: Poser) -> list[str]:
    """Every muscle (kind, DOF, joints) and every DOF (clinical range, rest angle)."""
    sk, ms = poser.skeleton, poser.muscles
    lines = [f"muscles ({len(ms.names)}; --muscle NAME=VALUE):"]
    for m, name in enumerate(ms.names):
        dofs = [sk.dof_names[d] for d in ms.dofs(m)]
        part, dof = dofs[0].split(".")
        moves = dofs[0] if len(dofs) == 1 else f"{dof} of {len(dofs)} joints {part}…"
        lines.append(f"  {name:40s} {'rotation' if ms.rotation[m] else 'flexion':9s} {moves}")
    lines.append(f"degrees of freedom ({sk.n_dofs}; --angle PART.DOF=ANGLE, clinical range, rest):")
    low, high, rest = (np.degrees(a) for a in (sk.rest + sk.lower, sk.rest + sk.upper, sk.rest))
    for k, name in enumerate(sk.dof_names):
        lines.append(f"  {name:40s} {low[k]:7.1f}° … {high[k]:6.1f}°  rest {rest[k]:6.1f}°")
    channels = channel_names(sk)
    lines.append(f"shoulder complex ({len(channels)}; --angle NAME=ANGLE, clinical range; the girdle follows):")
    for name in channels:
        lo, hi = CHANNEL_RANGES[name.split(".")[1]]
        lines.append(f"  {name:40s} {lo:7.1f}° … {hi:6.1f}°")
    return lines


def run(args: argparse.Namespace) -> None:
    if args.list:
        print("\n".join(list_names(Poser.from_body(body_of(args)))))
        return
    if args.out is None:
        raise HitogataError("--out: give the output file (.glb, .obj or .ply), or --list")
    elastic_mesh = args.elastic and Path(args.out).suffix.lower() != ".glb"  # a GLB holds the skinned pose beside
    if elastic_mesh and args.skinning == "lbs":
        raise HitogataError("--elastic --skinning lbs: the elastic body stands on dual-quaternion skinning; "
                            "leave out --skinning (dqs is taken)")
    args.skinning = args.skinning or ("dqs" if elastic_mesh else "lbs")
    check_posed_path(args.out, args.skinning)
    if args.contact and not args.elastic:
        raise HitogataError("--contact: the skin's self-contact is resolved on the elastic body; add --elastic")
    if args.materials is not None and not args.elastic:
        raise HitogataError("--materials: the tissue materials are those of the elastic body; add --elastic")
    materials = load_materials(args.materials) if args.elastic else None  # a bad file is said before posing
    poser, request, posed = pose_from_args(args)
    extras = {
        "shape": shape_extras(poser.body.params),
        "density": poser.body.density,
        **body_figures(poser.body),
        **detail_extras(poser.body),
        "angles_rad": [float(a) for a in posed.angles],
        "clinical_angles_deg": {
            name: round(float(np.degrees(value)), 4) for name, value in zip(posed.skeleton.dof_names, posed.clinical)
        },
    }
    written = []
    if args.elastic:
        held = elastic_pose(elastic_dynamics(poser.body, materials=materials), clinical=request.clinical, contractions=request.contractions,
                            lengths=request.lengths, on_limit=request.on_limit, contact=args.contact,
                            slide=args.contact)
        mesh = Path(args.out) if Path(args.out).suffix.lower() != ".glb" else Path(args.out).with_name(
            Path(args.out).stem + "_elastic.ply")
        written.append(write_mesh(mesh, held.vertices, held.faces))
        surface = {"skinning": "dqs", "surface": "elastic", "contact": args.contact, "slide": args.contact,
                   "materials": materials_name(materials)}
        if held.slide is not None:  # its fine skin slid on its own: measured from its own file
            fine = mesh.with_name(mesh.stem + "_fine.ply")
            written.append(write_mesh(fine, held.fine_vertices(), body_fine_skin(poser.body).faces))
            surface["fine_skin"] = fine.name
        written.append(write_sidecar(mesh, {**extras, **surface}))
        print(f"elastic body: {held.quality.line()}")
        kept_back = held.held_back > HELD
        print(f"elastic displacement held back where it would fold or cross the skin: {int(kept_back.sum())} "
              f"vertices, at most {held.held_back.max() * 1e3:.1f} mm")
        inside = held.penetrations
        print(f"skin inside another part: {len(inside)} vertices, deepest {inside.deepest * 1e3:.1f} mm"
              + ("" if args.contact else " (--contact resolves them)"))
        if held.slide is not None:
            coarse, fine_slide = held.slide.coarse, held.slide.fine
            print(f"skin slid over the fascia where stretched beyond +95 %: {int(coarse.free.sum())} vertices "
                  f"free, the longest slide {coarse.moved.max() * 1e3:.0f} mm; the fine skin then: "
                  f"{int(fine_slide.free.sum())} vertices free, the longest slide {fine_slide.moved.max() * 1e3:.0f} mm")
    if not (args.elastic and Path(args.out).suffix.lower() != ".glb"):
        written.insert(0, write_posed(args.out, poser, posed, extras))
        if Path(args.out).suffix.lower() != ".glb":
            written.append(write_sidecar(args.out, {**extras, "skinning": request.skinning, "surface": "skinning"}))
    moved = moved_count(posed)
    angles = f"{moved} joint angle{'s' * (moved != 1)}"
    files = ", ".join(str(p) for p in written)
    print(f"{files}: {len(posed.skeleton.names)}-part skeleton, {angles} moved (clinical):")
    print("\n".join(pose_summary(request, posed)))


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser(
        "pose",
        help="pose a body by muscle contractions or joint angles and write it",
        description="Pose a body by its muscles (eq. 1, 2 of the paper) or by clinical joint angles. "
        "A .glb holds the rest skin on the 65-part skeleton with the pose as joint rotations "
        "(re-posable in Blender or three.js); .obj/.ply hold the posed surface.",
    )
    add_body_arguments(parser)
    add_body_file(parser)
    add_pose_arguments(parser)
    parser.add_argument("--list", action="store_true", help="print the muscles and degrees of freedom, and exit")
    add_output(parser, "file", "output file: .glb (skinned, posed, re-posable), .obj or .ply "
               "(with a .json of the pose beside it: `hitogata measure` reads both)", MESH_SUFFIXES, required=False)
    parser.add_argument(
        "--elastic", action="store_true",
        help="also solve the elastic body (whole body, DQS + quasi-statics; about a minute) and write its skin: "
        "to the .obj/.ply given, or beside a .glb as NAME_elastic.ply (+ .json)",
    )
    parser.add_argument(
        "--contact", action="store_true",
        help="with --elastic: resolve the skin's self-contact (elbow, knee, hip creases) as a barrier problem "
        "(IPC), so no part of the skin passes into another, then slide the skin over the fascia where it is "
        "stretched beyond +95 %% (armpit, groin), its fine skin too, written as NAME_fine.ply beside the skin "
        "(`hitogata measure` reads it through the .json); see docs/elastic.md",
    )
    add_materials_argument(parser, "with --elastic: the tissue materials")
    add_cache_argument(parser)
    parser.set_defaults(run=run)
