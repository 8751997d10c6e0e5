"""`hitogata validate`: every row of the validation set beside hitogata's answers — CSV, JSON and a docs page."""

from __future__ import annotations

import argparse
import re
import time
from pathlib import Path

from hitogata.commands.args import add_cache_argument, add_materials_argument
from hitogata.commands.paths import add_output, input_path
from hitogata.errors import HitogataError
from hitogata.export.atomic import write_bytes_atomically

SURFACE_CHOICES = ("both", "skinned", "elastic")


def names(text: str | None, what: str) -> tuple[str, ...]:
    """A comma-separated list of names ('' or None: none)."""
    out = tuple(n.strip() for n in (text or "").split(",") if n.strip())
    if text is not None and not out:
        raise HitogataError(f"{what} {text!r}: allowed comma-separated names")
    return out


def run(args: argparse.Namespace) -> None:
    from hitogata.body.model import default_body
    from hitogata.elastic.materials import load_materials
    from hitogata.validation import answer_dataset, compare, headline, load_dataset, summary
    from hitogata.validation.answers import reachable
    from hitogata.validation.table import surface_label, table_csv, table_json, table_markdown, with_surface

    dataset = load_dataset(args.data).select(names(args.rows, "--rows"), names(args.kinds, "--kinds"))
    materials = load_materials(None if args.materials is None else str(args.materials))
    other = None if args.also_materials is None else load_materials(str(args.also_materials))
    if other is not None and args.surface == "skinned":
        raise HitogataError("--also-materials: answers the elastic surface again; allowed with --surface both or "
                            "elastic, not skinned")
    if other is not None and other.regions == materials.regions and other.rayleigh == materials.rayleigh:
        raise HitogataError(f"--also-materials {args.also_materials}: the same constants as --materials "
                            f"({_shown(materials.source)}); allowed: other materials to answer the elastic surface again")
    reachable(dataset, default_body("female"))  # every posture checked before any long work
    surfaces = ("skinned", "elastic") if args.surface == "both" else (args.surface,)
    start = time.perf_counter()

    def progress(done: int, total: int, row) -> None:
        if not args.quiet:
            print(f"[{done}/{total}] {row.id} ({time.perf_counter() - start:.0f} s)", flush=True)

    comparisons = compare(answer_dataset(dataset, materials, surfaces, progress))
    also: dict[str, str] = {}
    if other is not None:
        surface = added_surface(other.source)
        again = compare(answer_dataset(dataset, other, ("elastic",), progress))
        comparisons, also = with_surface(comparisons, again, "elastic", surface), {surface: _shown(other.source)}
    elapsed = time.perf_counter() - start
    command = _command(args)
    out, work = Path(args.out), args.workdir
    write_bytes_atomically(work / "validation.csv", table_csv(comparisons, dataset).encode())
    write_bytes_atomically(work / "validation.json",
                           table_json(comparisons, dataset, materials.source, also).encode())
    write_bytes_atomically(work / "validation.md",
                           table_markdown(comparisons, dataset, _shown(materials.source), command, also).encode())
    shares = summary(comparisons)
    print(f"{len(comparisons)} rows from {len({c.row.source for c in comparisons})} sources in {elapsed:.0f} s")
    for s in shares:
        if s.kind == "all" or s.answered:
            share = "—" if s.share_2sd is None else f"{100 * s.share_2sd:.0f} %"
            print(f"  {s.kind:15s} {surface_label(s.surface):8s} within 2 SD: {s.within_2sd}/{s.answered} "
                  f"({share}), {s.undefined} undefined")
    head = headline(shares)
    print("within 2 SD of the measurement: " +
          ", ".join(f"{surface_label(k)} {'—' if v is None else f'{100 * v:.0f} %'}" for k, v in head.items()))
    print(f"wrote {out}/: validation.csv, validation.json, validation.md")


def added_surface(source: str) -> str:
    """The name of the elastic surface answered again with other materials: 'elastic_calibrated' for a shipped
    preset, 'elastic_<file stem>' for a file."""
    from hitogata.elastic.materials import source_name

    return "elastic_" + re.sub(r"\W+", "-", Path(source_name(source)).stem)


def _command(args: argparse.Namespace) -> str:
    """The command line that made the page (the options that were given; the output folder as DIR)."""
    from hitogata.elastic.materials import source_name

    given = [(k, getattr(args, k)) for k in ("data", "rows", "kinds", "materials", "also_materials")]
    parts = [f"--{k.replace('_', '-')} {source_name(v) if 'materials' in k else v}" for k, v in given if v is not None]
    if args.surface != "both":
        parts.append(f"--surface {args.surface}")
    return " ".join(["hitogata validate", *parts, "--out DIR"])


def _shown(source: str) -> str:
    """A materials file as the page shows it: the shipped one by its package path, a user's as given."""
    path = Path(source)
    return f"hitogata/data/{path.name}" if path.parent.name == "data" and path.parent.parent.name == "hitogata" \
        else source


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("validate", help="every published measurement of the validation set beside the model's "
                                             "answer: a table (CSV, JSON) and a docs page")
    parser.add_argument("--data", type=input_path("file", suffixes=(".toml",)), default=None,
                        help="a validation file (TOML, schema: data/validation/SCHEMA.md); default the shipped set")
    parser.add_argument("--rows", default=None, help="only these row ids (comma-separated)")
    parser.add_argument("--kinds", default=None,
                        help="only rows of these kinds (comma-separated): posture_change, skin_strain, frequency, "
                             "damping, stiffness, pressure")
    parser.add_argument("--surface", choices=SURFACE_CHOICES, default="both",
                        help="the surface the posture rows are measured on; default both")
    add_materials_argument(parser, "the tissue materials")
    add_materials_argument(parser, "the elastic surface answered again with other tissue materials, shown beside "
                                   "the first (e.g. calibrated: the constants hitogata identify finds)",
                           option="--also-materials", default_text="none")
    parser.add_argument("--quiet", action="store_true", help="no progress lines")
    add_output(parser, "folder", "output folder: validation.csv, validation.json, validation.md")
    add_cache_argument(parser)
    parser.set_defaults(run=run)
