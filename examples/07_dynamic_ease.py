"""Dynamic ease: how much each girth and length of a body grows and shrinks through mobility motions.

    python examples/07_dynamic_ease.py [OUT_FOLDER]

A garment needs at least the largest increase of each measurement as ease to let the wearer move
(docs/garment.md). The motions are shipped scenarios (`hitogata ease --motions ...` names them);
here two of them, measured on the skinned body at 2 frames per second to keep the run short
(the command's default is eight motions at 5 frames per second).
"""

import sys
import tempfile
from pathlib import Path

import hitogata as hg
from hitogata.garment.ease import dynamic_ease, ease_csv, overall  # the functions behind `hitogata ease`
from hitogata.motion.clip import scenario_clip

out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp(prefix="hitogata-07-"))
out.mkdir(parents=True, exist_ok=True)

body = hg.Body.from_measurements(sex="male", stature=1.78, mass=78.0)
shipped = hg.shipped_scenarios()
motions = {name: scenario_clip(hg.load_scenario(shipped[f"mobility_{name}"]), hg.poser_for(body))
           for name in ("reach_forward", "deep_squat")}
results = dynamic_ease(body, motions, rate=2.0)

print(f"{'measurement':20s} standing   largest increase (motion)    largest decrease (motion)")
for row in overall(results):
    if row["measurement"] in ("stature", "inside_leg"):  # heights, not what a garment wraps
        continue
    if row["increase_cm"] is None:  # no meaning in any frame: the reason instead of a number
        print(f"{row['measurement']:20s} undefined: {row['undefined']}")
        continue
    if row["increase_cm"] > 0.5 or row["decrease_cm"] < -0.5:  # the measurements that move by 5 mm or more
        grows, shrinks = f"({row['increase_in']})", f"({row['decrease_in']})"
        print(f"{row['measurement']:20s} {row['standing_cm']:6.1f} cm  +{row['increase_cm']:4.1f} cm {grows:15s}  "
              f"{row['decrease_cm']:5.1f} cm {shrinks}")

(out / "ease.csv").write_text(ease_csv(results), encoding="utf-8")  # every measurement at every frame
print(f"wrote {out / 'ease.csv'}")
