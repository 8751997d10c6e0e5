"""A population study: bodies sampled from survey statistics, each through a motion, computed on a
Dask cluster of local processes, summarised as percentile tables (docs/study.md).

    python examples/09_study.py [OUT_FOLDER]

A tiny study (six bodies, one motion, three frames) on one worker, so that it runs in well under a
minute; the shipped `hitogata study example` samples 200 bodies through two motions. The study has
no front-door function: this script runs the `study` command's Python entry point.
"""

import csv
import sys
import tempfile
from pathlib import Path

from hitogata import cli

STUDY = """\
title = "six women reaching forward"
seed = 7
motions = ["mobility_reach_forward"]   # shipped scenarios, or scenario files beside this one
outputs = ["measurements", "dynamic_ease"]

[bodies]
sampled = 6
female = "100%"
clusters = 1            # groups of similar stature and mass for the tables

[bodies.women]          # stature and mass jointly normal, with where the figures come from
stature_mean = "162.9cm"
stature_sd = "6.4cm"
mass_mean = "67.8kg"
mass_sd = "11.1kg"
correlation = 0.53
source = "ANSUR II 2012 women (Gordon et al. 2014, NATICK/TR-15/007)"

[model]
posing = "skinning"     # or "elastic": each motion on the elastic body (minutes a body)
frames = 3
"""


def main() -> None:
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp(prefix="hitogata-09-"))
    out.mkdir(parents=True, exist_ok=True)
    study = out / "tiny.toml"
    study.write_text(STUDY, encoding="utf-8")

    results = out / "results"
    status = cli.main(["study", str(study), "--out", str(results), "--workers", "1", "--quiet"])
    if status != 0:
        sys.exit(status)

    # percentiles.csv: per group, motion, measurement and quantity, the number of bodies n and P5/P50/P95.
    with open(results / "percentiles.csv", newline="", encoding="utf-8") as f:
        rows = [r for r in csv.DictReader(f) if r["group"] == "all" and r["quantity"] == "dynamic_ease"]
    for row in rows:
        if row["name"] in ("across_back_width", "shoulder_width", "chest_girth"):
            print(f"dynamic ease of {row['name']:18s} over {row['n']} bodies: "
                  f"P5 {row['p5']} P50 {row['p50']} P95 {row['p95']} {row['unit']}")
    # A body the model cannot build (a draw outside the supported stature and mass) is a failed task
    # with its one-line error, not the end of the study.
    failed = (results / "failed.csv").read_text(encoding="utf-8").splitlines()[1:]
    print(f"{len(failed)} failed task(s)" + "".join(f"\n  {line}" for line in failed))


if __name__ == "__main__":  # Dask starts its worker processes by importing this file again
    main()
