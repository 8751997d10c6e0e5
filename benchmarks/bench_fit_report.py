"""Fit-report benchmark: a body and 4 mobility motions, end to end and by part.

End to end: `hitogata fit-report` in a fresh process (a user's run: start-up, body, motions, pictures,
page), default female, reach, sit, squat, overhead at the default 5 frames per second, a −15 %
garment of a 400 N/m fabric. Then the same work by part in this process: the body, the motions'
clips, dynamic ease, zone stretch, pressure, the page (pictures, plots, HTML). Goal (issue 16): the
whole report ≤ 3 min on this machine.

    PYTHONPATH=src python benchmarks/bench_fit_report.py
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

MOTIONS = "reach,sit,squat,overhead"
GARMENT = ["--garment-ease=-15%", "--fabric", "400N/m"]
RATE = 5.0


def main() -> None:
    with tempfile.TemporaryDirectory(prefix="hitogata-fit-bench-") as folder:
        start = time.perf_counter()
        subprocess.run([sys.executable, "-m", "hitogata.cli", "fit-report", "--motions", MOTIONS, *GARMENT,
                        "--out", str(Path(folder) / "cli")], check=True, stdout=subprocess.DEVNULL,
                       env=os.environ.copy())
        total = time.perf_counter() - start
        size = (Path(folder) / "cli" / "fit_report.html").stat().st_size
        print(f"hitogata fit-report, female, {MOTIONS} at {RATE:g} frames/s, with a garment: {total:.1f} s "
              f"(goal ≤ 180 s); page {size / 1e6:.1f} MB")
        parts(Path(folder))


def parts(folder: Path) -> None:
    from hitogata.body import Body
    from hitogata.commands.ease import load_motions
    from hitogata.garment.ease import dynamic_ease, skinned_surface
    from hitogata.garment.fabric import Fabric
    from hitogata.garment.fit import FitAnswers
    from hitogata.garment.pressure import Garment
    from hitogata.garment.pressure_motion import pressure_series
    from hitogata.garment.stretch import stretch_table
    from hitogata.motion.clip import scenario_clip
    from hitogata.posing import poser_for
    from hitogata.report.fit_report import write_fit_report

    times: dict[str, float] = {}

    def step(name: str, fn):
        start = time.perf_counter()
        out = fn()
        times[name] = time.perf_counter() - start
        return out

    scenarios = load_motions(MOTIONS)
    body = step("body", lambda: Body.from_measurements(sex="female", age=30.0, stature=1.65, mass=62.0))
    clips = step("clips", lambda: {n: scenario_clip(s, poser_for(body)) for n, s in scenarios.items()})
    surface = skinned_surface(body)
    garment = (Garment(ease=-0.15), Fabric.linear(400.0))
    ease = step("dynamic ease", lambda: dynamic_ease(body, clips, surface, RATE))
    stretch = step("zone stretch", lambda: stretch_table(body, clips, surface, RATE))
    pressure = step("pressure", lambda: {n: pressure_series(body, *garment, c, surface, RATE) for n, c in clips.items()})
    answers = FitAnswers(body, clips, surface, RATE, ease, stretch, garment, pressure)
    (folder / "parts").mkdir()
    step("page (pictures, plots, HTML)", lambda: write_fit_report(folder / "parts", answers))
    frames = sum(len(e.times) for e in ease)
    print(f"by part, in this process ({frames} sampled frames over {len(clips)} motions):")
    for name, seconds in times.items():
        print(f"  {name:30s} {seconds:6.1f} s")
    print(f"  {'sum':30s} {sum(times.values()):6.1f} s")


if __name__ == "__main__":
    main()
