"""The comparison table: each row's measurement beside hitogata's answers, in units of the measurement's SD.

Rows become `Comparison`s (error z = (model − mean) / SD per surface); the
summary gives, per kind and surface, the share of rows within 1 and 2 SD.
Written as CSV (one line a row), JSON (rows, summary, sources) and a
Markdown page for the docs, all from the same figures.
"""

from __future__ import annotations

import csv
import io
import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from hitogata.validation.answers import SURFACES, RowAnswers
from hitogata.validation.dataset import KINDS, POSTURED, Dataset, Row


@dataclass(frozen=True)
class Comparison:
    """One row: the measurement, the model's value (None: undefined, with the reason) and z per surface."""

    row: Row
    values: Mapping[str, float | None]
    reasons: Mapping[str, str]

    def z(self, surface: str) -> float | None:
        """(model − mean) / SD; None where the model has no answer or the study no spread."""
        value = self.values.get(surface)
        if value is None or self.row.sd <= 0:
            return None
        return (value - self.row.mean) / self.row.sd


@dataclass(frozen=True)
class Share:
    """How many rows of a kind have an answer on a surface, and how many lie within 1 and 2 SD."""

    kind: str
    surface: str
    answered: int
    within_1sd: int
    within_2sd: int
    undefined: int

    @property
    def share_2sd(self) -> float | None:
        return self.within_2sd / self.answered if self.answered else None

    @property
    def share_1sd(self) -> float | None:
        return self.within_1sd / self.answered if self.answered else None


def compare(answers: Sequence[RowAnswers]) -> list[Comparison]:
    """Each row's measurement beside the model's answers (`answer_dataset`'s), with z per surface."""
    return [Comparison(a.row, {s: a.answers[s].value for s in a.answers},
                       {s: a.answers[s].reason for s in a.answers if a.answers[s].value is None}) for a in answers]


def with_surface(comparisons: Sequence[Comparison], others: Sequence[Comparison], surface: str,
                 name: str) -> list[Comparison]:
    """`comparisons` with `others`' answers on `surface` added as the surface `name` (the same rows, in order:
    the elastic surface answered again with other materials, say)."""
    if [c.row.id for c in comparisons] != [c.row.id for c in others]:
        raise ValueError("the two comparisons hold different rows")
    out = []
    for mine, other in zip(comparisons, others, strict=True):
        values, reasons = dict(mine.values), dict(mine.reasons)
        if surface in other.values:
            values[name] = other.values[surface]
        if surface in other.reasons:
            reasons[name] = other.reasons[surface]
        out.append(Comparison(mine.row, values, reasons))
    return out


def surfaces_of(comparisons: Sequence[Comparison]) -> tuple[str, ...]:
    """The surfaces answered: the skinned and the elastic, then any added (`with_surface`), in order."""
    extra = dict.fromkeys(s for c in comparisons for s in c.values if s not in SURFACES)
    return (*SURFACES, *extra)


def summary(comparisons: Sequence[Comparison]) -> list[Share]:
    """Per kind (and 'all') and surface: rows answered, within 1 SD, within 2 SD, undefined. Rows whose
    study reported no spread (`sd_of = "guessed"`) are left out: an error in units of an assumed SD
    says nothing."""
    out = []
    reported = [c for c in comparisons if c.row.sd_of != "guessed"]
    for kind in (*KINDS, "all"):
        mine = [c for c in reported if kind in ("all", c.row.kind)]
        if not mine:
            continue
        for surface in surfaces_of(comparisons):
            zs = [c.z(surface) for c in mine if surface in c.values]
            answered = [abs(z) for z in zs if z is not None]
            if not zs:
                continue
            out.append(Share(kind, surface, len(answered), sum(z <= 1 for z in answered),
                             sum(z <= 2 for z in answered), len(zs) - len(answered)))
    return out


def headline(shares: Sequence[Share]) -> dict[str, float | None]:
    """The share of all rows within 2 SD, by surface (the elastic surface includes the material rows)."""
    return {s.surface: s.share_2sd for s in shares if s.kind == "all"}


@dataclass(frozen=True)
class PressureErrors:
    """The pressure rows both Laplace (skinned column) and the contact (elastic column) answer: how many,
    and the mean |z| of each (None without such rows). Rows with an assumed spread count too: the two
    methods are compared on the same rows and the same SD."""

    rows: int
    laplace: float | None
    contact: float | None


def pressure_errors(comparisons: Sequence[Comparison]) -> PressureErrors:
    """Laplace's and the contact's mean |error| in SD on the same pressure rows."""
    both = [(c.z("skinned"), c.z("elastic")) for c in comparisons if c.row.kind == "pressure"]
    pairs = [(abs(a), abs(b)) for a, b in both if a is not None and b is not None]
    if not pairs:
        return PressureErrors(0, None, None)
    return PressureErrors(len(pairs), sum(a for a, _ in pairs) / len(pairs), sum(b for _, b in pairs) / len(pairs))


def pressure_line(errors: PressureErrors) -> str:
    """The comparison's one line, as the page and the command print it."""
    if not errors.rows:
        return ("No pressure row gives both its garment's size and its fabric's tension: neither Laplace nor "
                "the contact garment answers one, and which of the two errs less against living people is "
                "not measured.")
    return (f"Mean |error| on the {errors.rows} pressure rows both answer: Laplace {errors.laplace:.2f} SD, "
            f"contact {errors.contact:.2f} SD.")


COLUMNS = ("row", "kind", "quantity", "posture", "source", "where", "read_off_plot", "measured_mean", "measured_sd",
           "sd_of", "unit", "skinned", "elastic", "z_skinned", "z_elastic", "undefined_because")


def columns(comparisons: Sequence[Comparison]) -> tuple[str, ...]:
    """The table's columns: `COLUMNS`, then an added surface's answer and z (`with_surface`) before the reasons."""
    extra = surfaces_of(comparisons)[len(SURFACES):]
    return (*COLUMNS[:-1], *(c for s in extra for c in (s, f"z_{s}")), COLUMNS[-1])


def posture_text(row: Row) -> str:
    """'thigh.flexion=90deg …', 'standing' for a postured row at rest, '' for a row without a posture."""
    if row.kind not in POSTURED:
        return ""
    return " ".join(f"{k}={v:g}deg" for k, v in row.posture.items()) or "standing"


def records(comparisons: Sequence[Comparison], dataset: Dataset) -> list[dict]:
    """One dict per row with the table's columns (numbers rounded for reading, None where undefined)."""
    out = []
    extra = surfaces_of(comparisons)[len(SURFACES):]
    for c in comparisons:
        r = c.row
        out.append({
            "row": r.id, "kind": r.kind, "quantity": r.quantity, "posture": posture_text(r),
            "source": dataset.sources[r.source].citation, "where": r.where, "read_off_plot": r.read_off_plot,
            "measured_mean": r.mean, "measured_sd": r.sd, "sd_of": r.sd_of, "unit": r.unit,
            "skinned": _round(c.values.get("skinned")), "elastic": _round(c.values.get("elastic")),
            "z_skinned": _round(c.z("skinned")), "z_elastic": _round(c.z("elastic")),
            **{k: v for s in extra for k, v in ((s, _round(c.values.get(s))), (f"z_{s}", _round(c.z(s))))},
            "undefined_because": "; ".join(f"{s}: {why}" for s, why in c.reasons.items()),
        })
    return out


def _round(value: float | None) -> float | None:
    return None if value is None else float(f"{value:.4g}")


def table_csv(comparisons: Sequence[Comparison], dataset: Dataset) -> str:
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, columns(comparisons), lineterminator="\n")
    writer.writeheader()
    for rec in records(comparisons, dataset):
        writer.writerow({k: "" if v is None else v for k, v in rec.items()})
    return buffer.getvalue()


def table_json(comparisons: Sequence[Comparison], dataset: Dataset, materials: str,
               also: Mapping[str, str] | None = None) -> str:
    """The table as JSON; `also`: each added surface's materials (`with_surface`)."""
    shares = summary(comparisons)
    doc = {
        "validation_set": dataset.path,
        "materials": materials,
        "materials_of_added_surfaces": dict(also or {}),
        "headline_within_2sd": headline(shares),
        "pressure_mean_abs_z": vars(pressure_errors(comparisons)),
        "summary": [{"kind": s.kind, "surface": s.surface, "answered": s.answered, "within_1sd": s.within_1sd,
                     "within_2sd": s.within_2sd, "undefined": s.undefined} for s in shares],
        "rows": records(comparisons, dataset),
        "sources": {k: {"citation": s.citation, "title": s.title, "method": s.method, "n": s.n, "url": s.url,
                        "doi": s.doi, "subjects": vars(s.subjects)} for k, s in dataset.sources.items()},
    }
    return json.dumps(doc, indent=1)


def _cell(value: float | None, unit: str = "") -> str:
    if value is None:
        return "undefined"
    return f"{value:.3g}{unit}"


def _z_cell(z: float | None) -> str:
    if z is None:
        return "—"
    mark = "" if abs(z) <= 2 else " ✗"
    return f"{z:+.1f}{mark}"


PRESSURE_NOTE = [
    "A pressure row whose study gives its garment's size (ease or relaxed circumference) and its fabric's",
    "tension is answered twice: by Laplace's law on the rigid tape (the skinned body's girth, the fabric's",
    "tension at the strain it makes, over the equivalent circle's radius) and by the contact garment (a",
    "tube of the fabric dressed on the body standing, IPC contact, the limb's tissue mesh taking its",
    "load: `docs/garment_contact.md`), its mean pressure round the level.",
    "",
]


def surface_label(surface: str) -> str:
    """How the page names a surface: 'elastic_calibrated' (an added one, `with_surface`) as 'elastic (calibrated)'."""
    base, _, materials = surface.partition("_")
    return f"{base} ({materials})" if materials else surface


def table_markdown(comparisons: Sequence[Comparison], dataset: Dataset, materials: str, command: str,
                   also: Mapping[str, str] | None = None) -> str:
    """The docs page: headline, summary by kind, every row, the rows outside 2 SD with their reasons, sources.
    `also`: each added surface's materials as the page names them (`with_surface`)."""
    shares = summary(comparisons)
    head = headline(shares)
    extra = surfaces_of(comparisons)[len(SURFACES):]
    also = also or {}
    lines = [
        "# hitogata beside measured people",
        "",
        f"Generated by `{command}`; do not edit by hand. Every figure below is a published measurement of",
        "living people (the validation set, `src/hitogata/data/validation/measured_people.toml`, with its",
        "sources) beside hitogata's answer for a body built to the study's subjects, on the skinned surface",
        "and on the elastic whole body (skin self-contact resolved). A change is measured from standing with",
        "the joints the row moves at their clinical zero (arms hanging, knees straight). z is the error in units of the",
        "study's standard deviation; ✗ marks |z| > 2. Rows whose study reported no spread are shown",
        "with the spread the set assumes, and left out of the shares.",
        "",
        f"Materials: `{materials}`" + "".join(f"; {surface_label(s)}: the elastic surface again with `{also.get(s, s)}`"
                                               for s in extra) + ".",
        "",
        "**Share of rows within 2 SD of the measurement:** "
        + ", ".join(f"{surface_label(s)} {_pct(v)}" for s, v in head.items()) + ".",
        "",
        "| kind | surface | rows answered | within 1 SD | within 2 SD | undefined |",
        "|---|---|---|---|---|---|",
    ]
    for s in shares:
        lines.append(f"| {s.kind} | {surface_label(s.surface)} | {s.answered} | {_pct(s.share_1sd)} | "
                     f"{_pct(s.share_2sd)} | "
                     f"{s.undefined} |")
    for kind in KINDS:
        mine = [c for c in comparisons if c.row.kind == kind]
        if not mine:
            continue
        columns = ("Laplace, rigid tape", "contact, soft body") if kind == "pressure" else ("skinned", "elastic")
        lines += ["", f"## {kind.replace('_', ' ')}", ""]
        if kind == "pressure":
            lines += PRESSURE_NOTE
        added = "".join(f" {surface_label(s)} | z |" for s in extra)
        lines += [f"| row | quantity | posture | measured | {columns[0]} | z | {columns[1]} | z |{added} source |",
                  "|---|---|---|---|---|---|---|---|" + "---|---|" * len(extra) + "---|"]
        for c in mine:
            r = c.row
            plot = (" (plot)" if r.read_off_plot else "") + (" (spread assumed)" if r.sd_of == "guessed" else "")
            lines.append(
                f"| {r.id} | {r.quantity} | {posture_text(r)} | {r.mean:.3g} ± {r.sd:.2g} {r.unit}{plot} | "
                f"{_cell(c.values.get('skinned')) if 'skinned' in c.values else '—'} | {_z_cell(c.z('skinned'))} | "
                f"{_cell(c.values.get('elastic'))} | {_z_cell(c.z('elastic'))} | "
                + "".join(f"{_cell(c.values.get(s)) if s in c.values else '—'} | {_z_cell(c.z(s))} | " for s in extra)
                + f"{dataset.sources[r.source].authors.split(',')[0]} {dataset.sources[r.source].year}, {r.where} |")
        if kind == "pressure":
            lines += ["", pressure_line(pressure_errors(mine))]
    misses = [c for c in comparisons
              if any(z is not None and abs(z) > 2 for z in (c.z(s) for s in surfaces_of(comparisons)))]
    if misses:
        lines += ["", "## Rows outside 2 SD, and why", "",
                  "Each with the study's own caveats as the validation set records them (where the model's posture, "
                  "zone or tissue differs from what the study measured):", ""]
        lines += [f"- **{c.row.id}** ("
                  + "; ".join(f"{surface_label(s)} z {z:+.1f}" for s in surfaces_of(comparisons)
                              if (z := c.z(s)) is not None) + f"): "
                  f"{c.row.note or c.row.definition}" for c in misses]
    undefined = [c for c in comparisons if c.reasons]
    if undefined:
        lines += ["", "## Answers reported as undefined", ""]
        lines += [f"- {c.row.id}: " + "; ".join(f"{surface_label(s)}: {why}" for s, why in c.reasons.items())
                  for c in undefined]
    lines += ["", "## Sources", ""]
    for src in dataset.sources.values():
        who = src.subjects
        subjects = ", ".join(x for x in (who.sex, _opt(who.age, "y"), _opt(who.stature and who.stature * 100, " cm"),
                                          _opt(who.mass, " kg")) if x)
        link = f" <{src.url}>" if src.url else ""
        lines.append(f"- **{src.id}**: {src.authors} ({src.year}). {src.title}. {src.journal}. N = {src.n} "
                     f"({subjects}); {src.method}.{link}")
    return "\n".join(lines) + "\n"


def _opt(value: float | None, unit: str) -> str:
    return "" if value is None or (isinstance(value, float) and math.isnan(value)) else f"{value:.4g}{unit}"


def _pct(share: float | None) -> str:
    return "—" if share is None else f"{100 * share:.0f} %"
