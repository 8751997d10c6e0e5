"""Fit adults' waist, hip and upper-arm girths on BMI and stature from NHANES body measures, and write
`src/hitogata/data/nhanes_adult_girths.toml`, the reference heavy bodies are checked against.

Input: NHANES 2017–March 2020 pre-pandemic body measures (P_BMX; CDC/NCHS, public domain,
https://wwwn.cdc.gov/Nchs/Nhanes/2017-2018/P_BMX.htm), adults of 18 years and over with every measure
present, one CSV per sex with CDC's column names BMXWT (kg), BMXHT (cm), BMXARMC, BMXHIP, BMXWAIST (cm);
lines starting with # are skipped. Such files are made from P_BMX.XPT and P_DEMO.XPT (RIDAGEYR >= 18,
RIAGENDR) with any XPT reader, e.g. `pandas.read_sas`.

    python tools/fit_nhanes_adult_girths.py --female female.csv --male male.csv

Each girth is fitted per sex by ordinary least squares, girth = a + b BMI + c BMI² + d stature (cm),
unweighted (NHANES's sample weights are not applied: the fit is a description of measured people of a
given build, not a national estimate). The scatter about it grows with BMI, so its standard deviation is
written per BMI band, with the band's number of people.
"""

from __future__ import annotations

import argparse
import hashlib
from pathlib import Path

import numpy as np

OUT = Path(__file__).resolve().parents[1] / "src" / "hitogata" / "data" / "nhanes_adult_girths.toml"
GIRTHS = {"waist": "BMXWAIST", "hip": "BMXHIP", "upper_arm": "BMXARMC"}
BANDS = (18.5, 25.0, 30.0, 35.0, 40.0, 45.0, 50.0, 70.0)  # BMI band edges, kg/m²


def read(path: Path) -> dict[str, np.ndarray]:
    lines = [line for line in path.read_text().splitlines() if line and not line.startswith("#")]
    header = [name.strip('"') for name in lines[0].split(",")]
    values = np.array([[float(v) if v not in ("", "NA") else np.nan for v in line.split(",")] for line in lines[1:]])
    values = values[~np.isnan(values).any(axis=1)]
    return {name: values[:, k] for k, name in enumerate(header)}


def fit(columns: dict[str, np.ndarray], girth: str) -> tuple[np.ndarray, list[tuple[float, float, float, int]]]:
    bmi = columns["BMXWT"] / (columns["BMXHT"] / 100.0) ** 2
    design = np.column_stack([np.ones_like(bmi), bmi, bmi**2, columns["BMXHT"]])
    measured = columns[GIRTHS[girth]]
    coefficients, *_ = np.linalg.lstsq(design, measured, rcond=None)
    residual = measured - design @ coefficients
    bands = []
    for low, high in zip(BANDS[:-1], BANDS[1:]):
        inside = (bmi >= low) & (bmi < high)
        bands.append((low, high, float(residual[inside].std(ddof=4)), int(inside.sum())))
    return coefficients, bands


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--female", type=Path, required=True)
    parser.add_argument("--male", type=Path, required=True)
    args = parser.parse_args()
    lines = ["# Adults' girths on BMI and stature, fitted to NHANES 2017-March 2020 body measures (P_BMX; CDC/NCHS,",
             "# public domain): written by tools/fit_nhanes_adult_girths.py, which says how; do not edit by hand.",
             "# girth (cm) = intercept + bmi * BMI + bmi2 * BMI^2 + stature * stature (cm); `sd` (cm) is the scatter of",
             "# measured people about the fit in each BMI band [from, to), `n` the people in it. NHANES takes the",
             "# waist just above the uppermost lateral border of the right ilium, the hip at the buttocks' greatest",
             "# protrusion, the upper arm midway between acromion and olecranon.", ""]
    for sex in ("female", "male"):
        path = getattr(args, sex)
        columns = read(path)
        lines += [f"[{sex}]", f"people = {len(columns['BMXWT'])}",
                  f'input_sha256 = "{hashlib.sha256(path.read_bytes()).hexdigest()}"', ""]
        for girth in GIRTHS:
            coefficients, bands = fit(columns, girth)
            lines += [f"[{sex}.{girth}]"]
            lines += [f"{name} = {value:.6g}" for name, value in zip(("intercept", "bmi", "bmi2", "stature"), coefficients)]
            lines += ["bands = ["] + [f"  {{ from = {low:g}, to = {high:g}, sd = {sd:.2f}, n = {n} }},"
                                       for low, high, sd, n in bands] + ["]", ""]
    OUT.write_text("\n".join(lines))
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
