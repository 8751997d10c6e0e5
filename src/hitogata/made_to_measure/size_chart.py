"""A size chart: read and checked, one request of measurements per size (`hitogata body --size-chart`
makes a body of each).

The CSV has one row per size: a `size` column (the size's name, which names its
file), then one column per measurement, its unit in the header: `stature_cm`,
`chest_girth_cm` (or `chest_cm`), `inside_leg_mm`, `mass_kg`, ... An empty cell
leaves that measurement out for that size. An `age_years` column gives each size its
own age (a children's chart, where sizes are statures and ages follow them); without
it, or in an empty cell, the size takes `--age`. The whole file is checked before any
body is made; each mistake is one line naming the file, the row, the column and
the value (`read_size_chart`), and each size's request is checked as made-to-measure takes it
(`check_size_chart`) before the first body is made. A shipped example chart is named by its short name (`shipped_size_charts`).
"""

from __future__ import annotations

import csv
import io
import re
from importlib import resources
from pathlib import Path

from hitogata import units
from hitogata.body.shape import MIN_AGE_YEARS, OLD_YEARS
from hitogata.errors import HitogataError, excerpt

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


def check_size_chart(path: Path, chart: Chart, sex: float | str, age: float) -> None:
    """Every size's request checked as `body_to_measure` takes it (`age`: of a size without its own),
    or a one-line error naming the file and the size."""
    from hitogata.made_to_measure.solve import checked_request  # here: reading a chart loads no solver

    for size, asked, own_age in chart:
        try:
            checked_request(asked, sex, age if own_age is None else own_age)
        except HitogataError as err:
            raise HitogataError(f"{path}: size {size}: {err}") from None
