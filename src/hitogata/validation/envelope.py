"""The changes with posture that measured people allow: a girth or length's plausible range, from the rows.

Where the validation set measured a girth or length in some posture, no posture changes it, either way,
by more than the largest of those rows' |mean| + 2 SD (the most any measured posture moved it). A row
whose spread was guessed (`sd_of = "guessed"`: its study gave a mean alone) bounds nothing, as it counts
in no headline share: its 2 SD is nobody's measurement. Where the set holds no measured row of that
measurement, the skin sets the bound: a surface length or girth cannot stretch or shrink more than the
skin along it does, so the largest skin stretch and shrink the set's skin-strain rows report (mean ± 2 SD)
bound it, either way.
"""

from __future__ import annotations

from dataclasses import dataclass

from hitogata.validation.dataset import Dataset


@dataclass(frozen=True)
class Allowed:
    """A change's plausible range in metres for a measurement of `standing` metres, and what set it."""

    low: float
    high: float
    basis: str

    def holds(self, change: float) -> bool:
        return self.low <= change <= self.high


def allowed_change(dataset: Dataset, name: str, standing: float) -> Allowed:
    """The range of `name`'s change from standing (m) that the validation rows allow (module text)."""
    spans = []
    for row in dataset.rows:
        if row.kind == "posture_change" and row.quantity == name and row.sd_of != "guessed":
            scale = 0.01 if row.unit == "cm" else standing / 100.0
            spans.append(((row.mean - 2 * row.sd) * scale, (row.mean + 2 * row.sd) * scale, row.id))
    if spans:
        most = max(max(abs(s[0]), abs(s[1])) for s in spans)
        return Allowed(-most, most, "posture rows " + ", ".join(s[2] for s in spans))
    skin = [r for r in dataset.rows if r.kind == "skin_strain" and not r.quantity.endswith(".area")]
    most = max(max(abs(r.mean - 2 * r.sd), abs(r.mean + 2 * r.sd)) for r in skin) / 100.0
    return Allowed(-most * standing, most * standing, "the skin's measured stretch")
