"""A fit report: one self-contained HTML page of a body through motions — ease, fabric stretch per
garment zone, the fit's answers and risks, with pictures (docs/garment.md, "The fit report").

    python examples/08_fit_report.py [OUT_FOLDER]

The page has no front-door function: this script runs the `fit-report` command's Python entry
point, as `hitogata fit-report --sex female --motions reach,squat --rate 2 --out fit_report/` would,
with two motions at 2 frames per second to keep it short (the page opens offline in any browser).
"""

import json
import sys
import tempfile
from pathlib import Path

from hitogata import cli

out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp(prefix="hitogata-08-"))
out.mkdir(parents=True, exist_ok=True)
report = out / "fit_report"

status = cli.main(["fit-report", "--sex", "female", "--stature", "165cm", "--mass", "60kg",
                   "--motions", "reach,squat", "--rate", "2", "--out", str(report), "--force"])
if status != 0:
    sys.exit(status)

# Beside the page: the tables behind it, for a spreadsheet or a script.
ease = json.loads((report / "ease.json").read_text(encoding="utf-8"))
print(f"page: {report / 'fit_report.html'}; tables: {', '.join(sorted(p.name for p in report.glob('*.csv')))}")
print(f"ease.json: {len(ease['motions'])} motions")
