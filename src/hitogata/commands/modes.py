"""`hitogata modes`: the elastic body's lowest vibration modes, written as CSV, VTU and pictures."""

from __future__ import annotations

import argparse
import importlib.util
import json
import time
from pathlib import Path

from hitogata import units
from hitogata.commands.args import add_body_arguments, add_cache_argument, add_materials_argument
from hitogata.commands.body import body_from_args
from hitogata.commands.paths import add_output
from hitogata.elastic import BONE_MODES, CUT_MODES, DEFAULT_ELEMENT_SIZES, ELEMENTS, load_materials
from hitogata.elastic.cache import cached_elastic_model
from hitogata.export.elastic_files import write_frequencies, write_mode_pictures, write_vtu
from hitogata.errors import HitogataError
from hitogata.fem.assembly import DILATATIONS
from hitogata.export.atomic import write_bytes_atomically
from hitogata.render import ensure_offscreen_gl
from hitogata.volume.model import EXTENTS


def summary(model) -> dict:
    """The model's headline figures, JSON-ready (SI units, names in the keys)."""
    q = model.volume.quality
    return {
        "element": model.element,
        "dilatation": model.dilatation,
        "element_size_mm": model.volume.element_size * 1e3,
        "nodes": len(model.points),
        "elements": len(model.elements),
        "free_dofs": 3 * (len(model.points) - len(model.fixed_nodes)),
        "fixed_nodes": len(model.fixed_nodes),
        "bone": model.bone,
        "cuts": model.cuts,
        "mass_kg": model.mass,
        "region_names": list(model.region_names),
        "muscle_names": list(model.muscle_names),
        "region_volumes_l": {k: v * 1e3 for k, v in model.region_volumes.items()},
        "min_dihedral_deg": q.min_dihedral,
        "inverted_elements": q.inverted,
        "materials": {k: {"youngs_modulus_pa": m.E, "poissons_ratio": m.nu, "density_kg_m3": m.rho}
                      for k, m in model.materials.regions.items()},
        "materials_file": model.materials.source,
        "rayleigh_alpha_per_s": model.alpha,
        "rayleigh_beta_s": model.beta,
        "frequencies_hz": model.frequencies.tolist(),
        "timings_s": dict(model.timings),
    }


def run(args: argparse.Namespace) -> None:
    size = None if args.element_size is None else units.length(args.element_size, "--element-size") * 1e3
    if args.count < 1:
        raise HitogataError(f"--count {args.count}: allowed a whole number >= 1")
    if args.pictures < 0:
        raise HitogataError(f"--pictures {args.pictures}: allowed a whole number >= 0")
    materials = load_materials(None if args.materials is None else str(args.materials))
    if args.pictures:  # a missing renderer is reported before the work, not after
        if importlib.util.find_spec("pyvista") is None:
            raise HitogataError("mode pictures need pyvista: pip install pyvista, or pass --pictures 0")
        ensure_offscreen_gl()
    body = body_from_args(args)
    start = time.perf_counter()
    model = cached_elastic_model(body, extent=args.region, element_size=size, element=args.element,
                                 n_modes=args.count, materials=materials, bone=args.bone, cuts=args.cuts,
                                 dilatation=args.dilatation)
    built = time.perf_counter() - start

    out, work = Path(args.out), args.workdir
    write_frequencies(work / "frequencies.csv", model)
    write_vtu(work / "model.vtu", model)
    pictures = write_mode_pictures(work, model, body, args.pictures)
    write_bytes_atomically(work / "summary.json", json.dumps(summary(model), indent=2).encode())

    q = model.volume.quality
    f = model.frequencies
    volumes = ", ".join(f"{k} {v * 1e3:.1f} L" for k, v in model.region_volumes.items())
    print(f"{args.region}: {len(model.elements)} {model.element} tets at {model.volume.element_size * 1e3:.0f} mm, "
          f"{len(model.points)} nodes ({len(model.fixed_nodes)} held by the skeleton), {model.mass:.1f} kg; {volumes}")
    print(f"element quality: dihedral {q.min_dihedral:.1f}°–{q.max_dihedral:.1f}°, {q.inverted} inverted")
    print(f"{len(f)} modes: {f[0]:.2f} … {f[-1]:.2f} Hz; lowest: " + ", ".join(f"{x:.2f}" for x in f[:6]) + " Hz")
    t = model.timings
    print(f"built in {built:.1f} s (mesh {t['mesh']:.1f}, assembly {t['assembly']:.1f}, modes {t['modes']:.1f}, "
          f"skin map {t['skin_map']:.1f} s)")
    print(f"wrote {out}/: frequencies.csv, model.vtu ({'tetra10' if model.element == 'P2' else 'tetra'} cells), "
          f"{len(pictures)} mode pictures, summary.json")


def whole_number(text: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: allowed a whole number") from None


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("modes", help="the elastic body's lowest vibration modes: CSV, VTU (ParaView), pictures")
    add_body_arguments(parser)
    parser.add_argument("--region", choices=EXTENTS, default="trunk", help="trunk (the paper's) or body; default trunk")
    parser.add_argument("--count", type=whole_number, default=40, help="number of modes; default 40")
    parser.add_argument("--element", choices=ELEMENTS, default="P2", help="P2 (quadratic, default) or P1 tets")
    parser.add_argument("--element-size", default=None,
                        help="lattice spacing, e.g. 30mm; default " +
                             ", ".join(f"{v:g}mm for {k}" for k, v in DEFAULT_ELEMENT_SIZES.items()))
    add_materials_argument(parser, "the tissue materials")
    parser.add_argument("--bone", choices=BONE_MODES, default="rigid",
                        help="rigid: bone follows the skeleton (default); elastic: bone deforms too")
    parser.add_argument("--cuts", choices=CUT_MODES, default="free",
                        help="free: the trunk's neck, hip and arm cuts are free surfaces (default, the paper's); "
                             "attached: they follow their nearest bone")
    parser.add_argument("--dilatation", choices=DILATATIONS, default="mean",
                        help="mean: the volumetric term on each element's mean dilatation, free of locking in "
                             "nearly incompressible tissue (default); full: the plain displacement element")
    parser.add_argument("--pictures", type=whole_number, default=6, help="mode pictures to draw; default 6")
    add_output(parser, "folder", "output folder (created; a new or empty folder)")
    add_cache_argument(parser)
    parser.set_defaults(run=run)
