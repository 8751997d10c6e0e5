"""`hitogata body --size-chart chart.csv --out sizes/`: one body per size of a size chart.

The CSV has one row per size: a `size` column (the size's name, which names its
file), then one column per measurement, its unit in the header: `stature_cm`,
`chest_girth_cm` (or `chest_cm`), `inside_leg_mm`, `mass_kg`, ... An empty cell
leaves that measurement out for that size. An `age_years` column gives each size its
own age (a children's chart, where sizes are statures and ages follow them); without
it, or in an empty cell, the size takes `--age`. The whole file is checked before any
body is made; each mistake is one line naming the file, the row, the column and
the value. The folder gets `<size>.glb` per size and `sizes.csv` (asked against
made, cm and kg), written in a staging folder and renamed when all are done.
A shipped example chart is named by its short name (`shipped_size_charts`).
"""

from __future__ import annotations

import argparse
import csv
import io
import re
from pathlib import Path

from importlib import resources

from hitogata import units
from hitogata.commands.args import BODY_DEFAULTS
from hitogata.errors import HitogataError, excerpt
from hitogata.export.atomic import write_bytes_atomically
from hitogata.body.shape import MIN_AGE_YEARS, OLD_YEARS

SIZE_COLUMN = "size"
AGE_COLUMN = "age_years"  # optional: the age of each size's body
MAX_BYTES = 2**20  # a size chart is a few kilobytes: a row per size
MAX_ROWS = 1001  # the header and up to 1000 sizes
SIZE_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._+-]{0,39}$")  # a size's name is also its file's name
UNITS = {**{u: (units.LENGTH_UNITS, "a length") for u in units.LENGTH_UNITS},
         **{u: (units.MASS_UNITS, "a mass") for u in units.MASS_UNITS}}

Chart = list[tuple[str, dict[str, float], float | None]]  # size, measurements (m, kg), age (years) or None


def shipped_size_charts() -> dict[str, Path]:
    """The example size charts shipped with the package, by name (e.g. `women_example`)."""
    folder = resources.files("hitogata") / "data" / "size_charts"
    return {p.name.removesuffix(".csv"): Path(str(p)) for p in folder.iterdir() if p.name.endswith(".csv")}


def read_size_chart(path: Path) -> Chart:
    """(size, measurements in m and kg) per row, or a one-line error naming file, row, column, value."""
    from hitogata.measure.values import aliases

    try:
        if path.stat().st_size > MAX_BYTES:
            raise HitogataError(f"{path}: {path.stat().st_size / 2**20:.1f} MiB; allowed a size chart of at most "
                                f"{MAX_BYTES / 2**20:.0f} MiB")
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as err:
        raise HitogataError(f"{path}: cannot be read as UTF-8 text ({type(err).__name__})") from None
    reader = csv.reader(io.StringIO(text))
    try:
        rows = list(reader)
    except csv.Error as err:
        raise HitogataError(f"{path}: row {reader.line_num}: not CSV ({err}); allowed cells of at most "
                            f"{csv.field_size_limit():,} characters") from None
    if len(rows) > MAX_ROWS:
        raise HitogataError(f"{path}: {len(rows) - 1} sizes; allowed at most {MAX_ROWS - 1}")
    rows = [row for row in rows if any(cell.strip() for cell in row)]
    if not rows:
        raise HitogataError(f"{path}: empty; allowed a header 'size,<measurement>_<unit>,...' and one row per size")
    header = [cell.strip() for cell in rows[0]]
    if not header or header[0] != SIZE_COLUMN:
        raise HitogataError(f"{path}: first column {excerpt(header[0] if header else '')}; allowed '{SIZE_COLUMN}'")
    known = {**aliases(), "mass": "mass"}
    columns: list[tuple[str, float]] = []
    for column in header[1:]:
        if column == AGE_COLUMN:
            columns.append((AGE_COLUMN, 1.0))
            continue
        name, _, unit = column.rpartition("_")
        if name not in known or unit not in UNITS or (name == "mass") != (UNITS[unit][1] == "a mass"):
            allowed = ", ".join(sorted({n for n in known.values() if n != "mass"}))
            raise HitogataError(f"{path}: column {excerpt(column)}: allowed <measurement>_<unit> with a measurement of "
                                f"{allowed} and unit m, cm or mm, or mass_kg / mass_g")
        columns.append((known[name], UNITS[unit][0][unit]))
    named = [name for name, _ in columns]
    twice = next((n for n in named if named.count(n) > 1), None)
    if twice:
        raise HitogataError(f"{path}: {twice} is in two columns; allowed once")
    if len(rows) < 2:
        raise HitogataError(f"{path}: no sizes; allowed one row per size under the header")
    chart: Chart = []
    for number, row in enumerate(rows[1:], start=2):
        chart.append(_size_row(path, number, header, row, columns, [size for size, _, _ in chart]))
    return chart


def _size_row(path: Path, number: int, header: list[str], row: list[str], columns: list[tuple[str, float]],
              sizes: list[str]) -> tuple[str, dict[str, float], float | None]:
    where = f"{path}: row {number}"
    if len(row) != len(header):
        raise HitogataError(f"{where}: {len(row)} cells; allowed {len(header)} (one per header column)")
    size = row[0].strip()
    if not SIZE_NAME.match(size):
        raise HitogataError(f"{where}, column {SIZE_COLUMN}: {excerpt(size)}; allowed letters, digits, '.', '_', '+', "
                            "'-' (up to 40)")
    if size in sizes:
        raise HitogataError(f"{where}, column {SIZE_COLUMN}: {size!r} is named twice; allowed once")
    asked = {}
    for column, (name, scale), cell in zip(header[1:], columns, row[1:]):
        if not cell.strip():
            continue
        try:
            value = float(cell) * scale
        except ValueError:
            raise HitogataError(f"{where}, column {column}: {excerpt(cell.strip())}; allowed a number") from None
        if not value > 0 or value == float("inf"):
            raise HitogataError(f"{where}, column {column}: {excerpt(cell.strip())}; allowed a positive number")
        if name == AGE_COLUMN and not MIN_AGE_YEARS <= value <= OLD_YEARS:
            raise HitogataError(f"{where}, column {column}: {excerpt(cell.strip())}; allowed years, "
                                f"{MIN_AGE_YEARS:g}..{OLD_YEARS:g}")
        asked[name] = value
    age = asked.pop(AGE_COLUMN, None)
    if not asked:
        raise HitogataError(f"{where}: size {size!r} has no measurement; allowed at least one")
    return size, asked, age


def write_size_chart(args: argparse.Namespace) -> None:
    """Check the chart and the options, then make, write and report one body per size."""
    from hitogata.commands.body import figures_line, solve_from_args
    from hitogata.export.body_files import write_body
    from hitogata.made_to_measure import checked_request

    given = [options[-1] for name, options in args.measurement_options.items() if getattr(args, name) is not None]
    given += [option for option in ("--stature", "--mass") if getattr(args, BODY_DEFAULTS[option][0]) is not None]
    if given:
        raise HitogataError(f"{given[0]}: does not apply with --size-chart (the chart gives the measurements); "
                            f"leave out {', '.join(given)}")
    chart = read_size_chart(args.size_chart)
    for size, asked, age in chart:  # every size's request checked before the first body is made
        try:
            checked_request(asked, args.sex, args.age if age is None else age)
        except HitogataError as err:
            raise HitogataError(f"{args.size_chart}: size {size}: {err}") from None
    lines = ["size,measurement,asked,made,difference,unit"]
    for size, asked, age in chart:
        try:
            body, fit = solve_from_args(argparse.Namespace(**{**vars(args), "age": args.age if age is None else age}),
                                        asked)
        except HitogataError as err:
            raise HitogataError(f"{args.size_chart}: size {size}: {err}") from None
        path = write_body(args.workdir / f"{size}.glb", body)
        print(figures_line(str(Path(args.out) / path.name), body))
        assert fit is not None
        for name, value in fit.requested.items():
            scale, unit = (1.0, "kg") if name == "mass" else (100.0, "cm")
            made = fit.achieved[name]
            lines.append(f"{size},{name},{value * scale:.2f},{made * scale:.2f},{(made - value) * scale:.2f},{unit}")
    write_bytes_atomically(args.workdir / "sizes.csv", ("\n".join(lines) + "\n").encode())
    print(f"{len(chart)} sizes; wrote {', '.join(f'{s}.glb' for s, _, _ in chart)} and sizes.csv in {Path(args.out)}/")
