"""The fit report: one self-contained HTML page and the tables behind it (docs/garment.md).

For a body through motions (`garment.fit.FitAnswers`): the body and its
measurements; per motion the snapshots, the dynamic-ease table and plot,
the zone-stretch table and map (front and back, zones outlined), the lines
of non-extension on the rest body, and with a
stretch garment its pressure table and map; a summary paragraph naming where
the garment is most at risk, with numbers (`garment.fit.risks`). For a
population study's results (`hitogata study`): per motion the percentile
tables (P5/P50/P95 per size or body cluster) of each girth's and length's
dynamic ease and each zone's required stretch, and the band plots. Either
part alone, or both.

`write_fit_report` writes into an existing folder, each file atomically:
`fit_report.html`, `summary.json` and, as the parts need them,
`measurements.csv`, `non_extension.csv` and `.json` (the lines of
non-extension per motion, `garment.non_extension`) and `percentiles.csv`; the motion tables (ease, stretch,
pressure) are the command's, written by `hitogata.commands.ease.write_tables`.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hitogata.errors import HitogataError
from hitogata.export.atomic import write_bytes_atomically
from hitogata.export.body_files import body_figures
from hitogata.garment.contact.answers import RAL_LETTERS, GarmentContact
from hitogata.export.garment_files import levels_csv
from hitogata.garment.ease import HEIGHTS, NAMES, MotionEase, overall
from hitogata.garment.ease_plot import ease_over_time, ease_plot
from hitogata.garment.fit import FitAnswers, peak_frames, posture, risks
from hitogata.garment.non_extension import Line, lines_csv, lines_json, non_extension_lines
from hitogata.garment.pressure import MMHG
from hitogata.garment.stretch import ZoneStretch
from hitogata.report import html_page as h
from hitogata.report.fit_pictures import FitPictures, zone_colours
from hitogata.study.plots import motion_plot
from hitogata.study.results import Band, bands_csv, percentile_table, read_failures, read_rows

PAGE = "fit_report.html"


@dataclass(frozen=True)
class Population:
    """A study's results: its folder, percentile bands, failed tasks."""

    folder: Path
    bands: list[Band]
    failures: list[dict]


def read_population(folder: str | os.PathLike) -> Population:
    """A `hitogata study` results folder's percentile bands; a one-line error if it is not one."""
    folder = Path(folder)
    if not any((folder / "rows").glob("motion=*/*.parquet")):
        raise HitogataError(f"--study {folder}: no task rows (rows/motion=*/*.parquet); allowed the --out folder "
                            "of `hitogata study` with at least one finished task")
    return Population(folder, percentile_table(read_rows(folder)), read_failures(folder))


def label(name: str) -> str:
    return name.replace("_", " ")


def _signed(x: float | None) -> str:
    return "undefined" if x is None else f"{round(x, 1) + 0.0:+.1f}"  # + 0.0: no "-0.0"


def _fixed(x: float | None) -> str:
    return "undefined" if x is None else f"{round(x, 1) + 0.0:.1f}"


def _at(x: float | None) -> str:
    return "—" if x is None else f"{x:.2f}"


def ease_rows(ease: MotionEase) -> list[list[object]]:
    """One motion's ease table: standing, largest increase and decrease (cm, %, when)."""
    return [[label(r["measurement"]), _fixed(r["standing_cm"]), _signed(r["increase_cm"]),
             _fixed(r["increase_pct"]), _at(r["increase_at_s"]), _signed(r["decrease_cm"]),
             _fixed(r["decrease_pct"]), _at(r["decrease_at_s"])] for r in ease.largest()]


EASE_COLUMNS = ("measurement", "standing cm", "largest increase cm", "%", "at s", "largest decrease cm", "%", "at s")
STRETCH_COLUMNS = ("zone", "lengthwise %", "crosswise %", "principal %", "least lengthwise %", "least crosswise %")
PRESSURE_COLUMNS = ("level", "largest strain %", "largest mean mmHg", "largest peak mmHg", "peak at s")


NON_EXTENSION_NOTE = ("Lines of non-extension: the skin's directions that keep their length at the frame of most "
                      "stretch, where it stretches one way and shortens the other (Iberall 1964), drawn on the rest "
                      "body; seams or stiff tapes laid along them do not hinder the motion. Black and green: the two "
                      "families. The polylines are in non_extension.csv and .json (rest body, mm).")


def stretch_rows(stretch: ZoneStretch) -> list[list[object]]:
    colours = zone_colours()
    return [[h.swatch(colours[r["zone"]], label(r["zone"])), _fixed(r["lengthwise_pct"]), _fixed(r["crosswise_pct"]),
             _fixed(r["principal_pct"]), _fixed(r["lengthwise_min_pct"]), _fixed(r["crosswise_min_pct"])]
            for r in stretch.rows()]


def pressure_rows(times: np.ndarray, levels: dict[str, np.ndarray]) -> list[list[object]]:
    rows: list[list[object]] = []
    for level, series in levels.items():
        k = int(np.argmax(series[:, 2]))
        rows.append([level, _fixed(100 * series[:, 0].max()), _fixed(series[:, 1].max() / MMHG),
                     _fixed(series[:, 2].max() / MMHG), f"{times[k]:.2f}"])
    return rows


def summary_text(answers: FitAnswers) -> str:
    """One paragraph: where the garment is most at risk, with numbers."""
    found = risks(answers)
    e, s = found["ease"], found["stretch"]
    motions = ", ".join(label(m.motion) for m in answers.ease)
    text = (f"Through {motions}: the largest ease need is the {label(e['measurement'])}'s, "
            f"+{e['increase_cm']:.1f} cm ({e['increase_pct']:.1f} % of its standing {e['standing_cm']:.1f} cm) in "
            f"{label(e['motion'])} at {e['at_s']:.2f} s — a woven garment needs at least that ease there. "
            f"The zone that must stretch most is the {label(s['zone'])}: {s['stretch_pct']:.1f} % {s['direction']} "
            f"(principal {s['principal_pct']:.1f} %) in {label(s['motion'])}.")
    if "pressure" in found:
        p = found["pressure"]
        text += (f" The garment presses hardest at the {p['level']}: {p['peak_mmHg']:.1f} mmHg peak "
                 f"({p['mean_mmHg']:.1f} mmHg mean, fabric strain {p['strain_pct']:.1f} %) in {label(p['motion'])} "
                 f"at {p['at_s']:.2f} s.")
    return text


def body_section(answers: FitAnswers) -> tuple[str, str]:
    """The body's figures and standing measurements: (HTML, measurements.csv)."""
    figures = body_figures(answers.body)
    standing = answers.ease[0].standing
    rows = [[label(n), _fixed(100 * standing[k])] for k, n in enumerate(NAMES)]
    csv = "measurement,value_cm\n" + "".join(f"{n},{100 * standing[k]:.2f}\n" for k, n in enumerate(NAMES))
    params = answers.body.params
    sex = {0.0: "female", 1.0: "male"}.get(params.sex, f"sex {params.sex:g} (0 female … 1 male)")
    head = h.paragraph(f"{sex}, {params.age:g} years: stature {figures['stature_cm']:.1f} cm, mass "
                       f"{figures['mass_kg']:.1f} kg, BMI {figures['bmi']:.1f}, volume {figures['volume_l']:.1f} L.")
    return head + h.table(("measurement", "standing cm"), rows, id="measurements"), csv


def motion_section(answers: FitAnswers, ease: MotionEase, stretch: ZoneStretch,
                   pictures: FitPictures) -> tuple[str, list[Line]]:
    """One motion's part of the page, and its lines of non-extension (at the frame of most stretch)."""
    motion = ease.motion
    peaks = peak_frames(answers, motion)
    lines = non_extension_lines(answers.body, posture(answers, motion, peaks.stretch)[0])
    parts = [h.image(pictures.snapshots(motion, sorted({peaks.stretch // 2, peaks.stretch})),
                     f"{label(motion)}: snapshots"),
             h.table(EASE_COLUMNS, ease_rows(ease), id=f"ease-{motion}", caption="dynamic ease (over standing)"),
             h.image(ease_over_time(ease), f"{label(motion)}: change of each girth and length over time"),
             h.table(STRETCH_COLUMNS, stretch_rows(stretch), id=f"stretch-{motion}",
                     caption="fabric stretch per garment zone (95th percentile of the zone, largest over the motion)"),
             h.image(pictures.stretch_map(motion, peaks.stretch), f"{label(motion)}: stretch map with the zones"),
             h.paragraph(NON_EXTENSION_NOTE, "note"),
             h.image(pictures.non_extension_map(motion, peaks.stretch, lines),
                     f"{label(motion)}: lines of non-extension")]
    if answers.pressure is not None and peaks.pressure is not None:
        times, levels = answers.pressure[motion]
        parts += [h.table(PRESSURE_COLUMNS, pressure_rows(times, levels), id=f"pressure-{motion}",
                          caption="garment pressure per level (Laplace's law, largest over the motion)"),
                  h.image(pictures.pressure_map(motion, peaks.pressure), f"{label(motion)}: pressure map")]
    return h.section(f"motion-{motion}", label(motion), parts), lines


def overall_section(answers: FitAnswers) -> str:
    rows = [[label(r["measurement"]), _fixed(r["standing_cm"]), _signed(r["increase_cm"]), _fixed(r["increase_pct"]),
             label(r["increase_in"] or "—"), _signed(r["decrease_cm"]), _fixed(r["decrease_pct"]),
             label(r["decrease_in"] or "—")] for r in overall(answers.ease)]
    columns = ("measurement", "standing cm", "largest increase cm", "%", "in", "largest decrease cm", "%", "in")
    note = h.paragraph(f"Heights ({', '.join(map(label, HEIGHTS))}) are undefined in a motion: ISO 8559-1 takes "
                       "them standing upright, and a height has no meaning once the body bends, sits or strides.",
                       "note")
    others = [h.paragraph(f"{label(r['measurement'])}: undefined where it has no meaning"
                          + ("" if r["increase_cm"] is None else ", the figures above are of its other frames")
                          + f" — {r['undefined']}", "note")
              for r in overall(answers.ease) if r["measurement"] not in HEIGHTS and "undefined" in r]
    return h.section("all-motions", "all motions", [
        h.table(columns, rows, id="ease-all", caption="dynamic ease over all motions"),
        note, *others, h.image(ease_plot(answers.ease), "largest change of each girth and length per motion")])


MEASURED_COLUMNS = ("figure in this report", "published measurement", "posture", "mean ± SD", "source")


def measured_section(answers: FitAnswers) -> str:
    """Each figure the report gives, beside the validation rows of measured people that speak to it
    (`hitogata validate` sets the model beside each of them: docs/validation.md)."""
    from hitogata.validation import load_dataset
    from hitogata.validation.table import posture_text

    data = load_dataset()
    asked = [("posture_change", r["measurement"]) for r in overall(answers.ease) if r["increase_cm"] is not None]
    asked += [("skin_strain", z) for z in (answers.stretch[0].zones if answers.stretch else ())]
    if answers.garment is not None:
        asked += [("pressure", level) for level in answers.garment[0].covered]
    rows: list[list[object]] = []
    unmatched = []
    for kind, name in asked:
        found = data.supporting(kind, name)
        if not found:
            unmatched.append(label(name))
        for r in found:
            source = data.sources[r.source]
            rows.append([label(name), f"{r.id}: {r.definition}", posture_text(r) or "—",
                         f"{r.mean:.3g} ± {r.sd:.2g} {r.unit}", f"{source.authors.split(',')[0]} {source.year}"])
    parts = [h.paragraph("The published measurements of living people that speak to this report's figures; "
                         "hitogata validate sets the model's answer beside each (docs/validation.md)."),
             h.table(MEASURED_COLUMNS, rows, id="measured-people", caption="figures beside measured people")]
    if unmatched:
        parts.append(h.paragraph("No published measurement in the validation set yet for: " + ", ".join(unmatched)
                                 + ".", "note"))
    return h.section("measured-people", "beside measured people", parts)


CONTACT_COLUMNS = ["level", "RAL-GZ 387", "contact: mean (mmHg)", "contact: peak (mmHg)",
                   "Laplace, the quick estimate (mmHg)", "indentation: mean / deepest (mm)",
                   "girth: standing → under the garment (cm)", "course strain (%)", "friction needed"]


def contact_section(contact: GarmentContact) -> str:
    """The garment solved in contact with the body (`hitogata dress`'s answers) beside Laplace's quick
    estimate at each level; the indentation and the girth under the garment where the body was soft."""
    rows: list[list[object]] = []
    for level in contact.levels:
        soft = np.isfinite(level.indentation)
        rows.append([label(level.level), RAL_LETTERS.get(level.level, "—"), _fixed(level.pressure / MMHG),
                     _fixed(level.peak / MMHG) if np.isfinite(level.peak) else "—",
                     _fixed(level.laplace / MMHG) if np.isfinite(level.laplace) else "—",
                     f"{1000 * level.indentation:.2f} / {1000 * level.deepest:.2f}" if soft else "— (rigid body)",
                     f"{100 * level.girth:.1f} → {100 * level.girth_under:.1f}" if soft else f"{100 * level.girth:.1f}",
                     _fixed(100 * level.course_strain), f"{level.hold:.2f}"])
    body = "the soft limb (its tissue solved with the garment)" if any(np.isfinite(lv.indentation)
                                                                       for lv in contact.levels) else "the rigid skin"
    parts = [h.paragraph(f"{contact.title}: the garment's contact with {body} (docs/garment_contact.md): the mean "
                         "pressure round each level and its peak, beside Laplace's law on the standing girth (the "
                         "quick estimate)."),
             h.table(CONTACT_COLUMNS, rows, id="garment-contact", caption="the garment in contact, beside Laplace")]
    if contact.compression_class is not None:
        parts.append(h.paragraph(f"RAL-GZ 387/1 class at the ankle (B): {contact.compression_class}.", "note"))
    return h.section("garment-contact", "the garment in contact", parts)


def population_section(population: Population) -> str:
    """Per motion: the P5/P50/P95 table of dynamic ease and required stretch per group, and the band plot."""
    bands, parts = population.bands, []
    groups = list(dict.fromkeys(b.group for b in bands))
    n_bodies = max((b.n for b in bands if b.group == "all"), default=0)
    parts.append(h.paragraph(f"{population.folder}: {n_bodies} bodies in {len(groups) - 1} groups, "
                             f"{len(population.failures)} failed tasks. Per group (size or body cluster; 'all' pools "
                             "them): the 5th, 50th and 95th percentiles over the bodies."))
    for motion in dict.fromkeys(b.motion for b in bands):
        chosen = [b for b in bands if b.motion == motion and b.quantity in ("dynamic_ease", "required_stretch")]
        columns = ["quantity", "name", "unit"] + [f"{g} P{p}" for g in groups for p in (5, 50, 95)]
        index = {(b.quantity, b.name, b.group): b for b in chosen}
        rows = []
        for quantity, name in dict.fromkeys((b.quantity, b.name) for b in chosen):
            unit = next(b.unit for b in chosen if b.quantity == quantity and b.name == name)
            row: list[object] = [label(quantity), label(name), unit]
            for g in groups:
                b = index.get((quantity, name, g))
                row += ["–"] * 3 if b is None else [_fixed(b.p5), _fixed(b.p50), _fixed(b.p95)]
            rows.append(row)
        parts.append(h.section(f"population-{motion}", label(motion), [
            h.table(columns, rows, id=f"percentiles-{motion}"),
            h.image(motion_plot(bands, motion, population.folder.name), f"{label(motion)}: percentile bands")], 3))
    return h.section("population", "population", parts)


def write_fit_report(folder: str | os.PathLike, answers: FitAnswers | None = None,
                     population: Population | None = None, title: str = "fit report", settings: str = "",
                     contact: GarmentContact | None = None) -> list[str]:
    """Write the page and its tables into an existing folder; return the names written.
    `settings`: how the answers were computed, in words (shown under the summary); `contact`: a garment
    solved in contact with the body (its section and `garment_contact.csv`)."""
    folder = Path(folder)
    if answers is None and population is None:
        raise HitogataError("fit report: nothing to report; give a body with motions, a study's results, or both")
    tables: dict[str, str] = {}
    intro: list[str] = []
    sections: list[tuple[str, str, str]] = []
    summary: dict = {}
    if answers is not None:
        text = summary_text(answers)
        intro.append(h.paragraph(text, "summary"))
        if settings:
            intro.append(h.paragraph(settings, "note"))
        summary.update(body=body_figures(answers.body), risks=risks(answers), summary=text, settings=settings,
                       rate=answers.rate, motions=[e.motion for e in answers.ease])
        body_html, tables["measurements.csv"] = body_section(answers)
        sections.append(("body", "body", h.section("body", "the body", [body_html])))
        sections.append(("all-motions", "all motions", overall_section(answers)))
        sections.append(("measured-people", "beside measured people", measured_section(answers)))
        if contact is not None:
            sections.append(("garment-contact", "the garment in contact", contact_section(contact)))
            tables["garment_contact.csv"] = levels_csv(contact).decode("utf-8")
        from hitogata.render import Renderer

        lines: dict[str, list[Line]] = {}
        with Renderer() as renderer:
            pictures = FitPictures(answers, renderer)
            for ease, stretch in zip(answers.ease, answers.stretch):
                html, lines[ease.motion] = motion_section(answers, ease, stretch, pictures)
                sections.append((f"motion-{ease.motion}", label(ease.motion), html))
        tables["non_extension.csv"] = lines_csv(lines)
        tables["non_extension.json"] = json.dumps(lines_json(lines)) + "\n"
    if population is not None:
        tables["percentiles.csv"] = bands_csv(population.bands)
        summary["population"] = {"study": str(population.folder), "failed_tasks": len(population.failures)}
        sections.append(("population", "population", population_section(population)))
    tables["summary.json"] = json.dumps(summary, indent=1) + "\n"
    write_bytes_atomically(folder / PAGE, h.page(title, intro, sections).encode())
    for name, text in tables.items():
        write_bytes_atomically(folder / name, text.encode())
    return [PAGE, *tables]
