"""Fit adults' body heights on stature from the ANSUR II public data, and write
`src/hitogata/data/ansur2_heights.toml`, the line the bodies' landmark heights are checked against.

Input: the ANSUR II public per-subject tables (Gordon CC et al. 2014, 2012 Anthropometric Survey of U.S.
Army Personnel, NATICK/TR-15/007; the released "ANSUR II FEMALE Public.csv" and "ANSUR II MALE Public.csv",
public domain), one CSV per sex with the survey's column names (`stature`, `iliocristaleheight`,
`crotchheight`, all mm).

    python tools/fit_ansur2_heights.py --female "ANSUR II FEMALE Public.csv" --male "ANSUR II MALE Public.csv"

Each height is fitted per sex by ordinary least squares, height = intercept + slope × stature (mm); the
written `sd` is the scatter of measured people about the line (two degrees of freedom taken), beside the
height's own mean and SD and its mean share of stature.
"""

from __future__ import annotations

import argparse
import csv
import hashlib
from pathlib import Path

import numpy as np

OUT = Path(__file__).resolve().parents[1] / "src" / "hitogata" / "data" / "ansur2_heights.toml"
HEIGHTS = {"iliocristale_height": "iliocristaleheight", "crotch_height": "crotchheight"}
HEADER = """# Adults' heights on stature, fitted to the ANSUR II public data (Gordon et al. 2014, NATICK/TR-15/007;
# public domain): written by tools/fit_ansur2_heights.py, which says how; do not edit by hand.
# height (mm) = intercept + slope * stature (mm); `sd` (mm) is the scatter of measured people about the
# line, `mean` and `population_sd` the height's own, `share` its mean share of stature. ANSUR II takes the
# iliocristale height standing, floor to the iliac crest on the midaxillary line; the crotch height
# floor to the crotch.
"""


def fit(path: Path) -> tuple[str, int, dict[str, dict[str, float]]]:
    """The file's SHA-256, its number of people and each height's line and scatter."""
    data = path.read_bytes()
    rows = list(csv.DictReader(data.decode("latin-1").splitlines()))
    stature = np.array([float(r["stature"]) for r in rows])
    out = {}
    for name, column in HEIGHTS.items():
        height = np.array([float(r[column]) for r in rows])
        slope, intercept = np.polyfit(stature, height, 1)
        residual = height - (intercept + slope * stature)
        out[name] = {"intercept": round(float(intercept), 2), "slope": round(float(slope), 5),
                     "sd": round(float(residual.std(ddof=2)), 2), "mean": round(float(height.mean()), 1),
                     "population_sd": round(float(height.std(ddof=1)), 1),
                     "share": round(float((height / stature).mean()), 4)}
    return hashlib.sha256(data).hexdigest(), len(rows), out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--female", type=Path, required=True)
    parser.add_argument("--male", type=Path, required=True)
    args = parser.parse_args()
    lines = [HEADER]
    for sex, path in (("female", args.female), ("male", args.male)):
        digest, people, heights = fit(path)
        lines += [f"[{sex}]", f"people = {people}", f'input_sha256 = "{digest}"', ""]
        for name, values in heights.items():
            lines.append(f"[{sex}.{name}]")
            lines += [f"{key} = {value}" for key, value in values.items()]
            lines.append("")
    OUT.write_text("\n".join(lines).rstrip() + "\n")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
