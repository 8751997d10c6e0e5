"""Scan-fit benchmark: `fit_scan` on the test suite's scans, this tree's code ("now") beside a baseline
commit's ("before", default `main`), each in a fresh process, in the same run.

The scans are the ones tests/made_to_measure/test_fit_scan.py, test_fit_pose.py and examples/03_scan_fit.py
fit, made by those files' own recipes (`scan_of`, `posed_scan`: bodies of known shape, posed or at rest,
sampled as clouds or re-triangulated, with 1.5 mm noise, holes, a rigid offset, in millimetres). They are
made once here and handed to both runs, so both fit the very same points.

Per scan, for both: wall and CPU seconds (user + system of the fit alone: read CPU where the machine is
shared), the CPU ratio before / now; the fit's median scan → body distance (mm, the fitted body's); the
fitted girths less the known body's (the largest, mm); and the largest distance between the two fitted
bodies' vertices (mm: the change the new code makes to the answer). "before" runs this same script
(`--pass`) in a subprocess on a `git archive` of the baseline's `src` (PYTHONPATH).

    PYTHONPATH=src nice -n 5 python benchmarks/bench_fit_scan.py [--baseline main] [--now-only] [--scans a,b]
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
RECIPES = (ROOT / "tests", ROOT / "tests" / "made_to_measure")  # where the scans' recipes live


def scans() -> dict[str, tuple[Any, Any, str, bool]]:
    """name → (known body, scan, sex, detail), as the tests and the example make them."""
    for folder in RECIPES:
        sys.path.insert(0, str(folder))
    import test_fit_pose as pose_tests
    import test_fit_scan as scan_tests

    from hitogata.body import Body
    from hitogata.made_to_measure.scan_fit import make_scan
    from hitogata.made_to_measure.scan_fit.synthetic import Perturbation, synthetic_scan
    from hitogata.posing import poser_for

    out: dict[str, tuple[Any, Any, str, bool]] = {}
    woman, man = Body.from_parameters(scan_tests.WOMAN), Body.from_parameters(scan_tests.MAN)
    out["woman cloud"] = (woman, scan_tests.scan_of(woman, woman.vertices, woman.rig.heads, 100_000), "female", True)
    posed = poser_for(man).pose(clinical=scan_tests.T_POSE)
    out["man T-pose mesh"] = (man, scan_tests.scan_of(man, posed.vertices, posed.rig_joints, None, seed=1), "male",
                              True)
    ends = {"female 1.50 m BMI 33 z-up": ("female", 1.50, 33.0, scan_tests.Z_UP),
            "female 2.00 m BMI 19": ("female", 2.00, 19.0, Perturbation.rotation),
            "male 1.45 m BMI 35": ("male", 1.45, 35.0, Perturbation.rotation),
            "male 1.95 m BMI 18 facing away": ("male", 1.95, 18.0, scan_tests.FACING_AWAY)}
    for name, (sex, stature, bmi, rotation) in ends.items():
        truth = Body.from_measurements(sex, 30.0, stature, bmi * stature**2)
        out[name] = (truth, scan_tests.scan_of(truth, truth.vertices, truth.rig.heads, 60_000, rotation=rotation),
                     sex, True)
    out["woman, left arm 20 % thicker"] = (woman, scan_tests.thick_arm_scan(woman), "female", True)
    cloud, _ = synthetic_scan(man, man.vertices, man.rig.heads, Perturbation(), points=30_000)
    out["man 30k cloud (the CLI's)"] = (man, make_scan(cloud, None, "scan"), "male", True)
    d = np.radians
    out["woman posed, 30k cloud"] = (
        Body.from_parameters(pose_tests.WOMAN),
        pose_tests.posed_scan(pose_tests.WOMAN, pose_tests.WOMAN_POSE,
                              {"spine.flexion": d(15), "neck.rotation": d(30)}, 30_000, 2), "female", False)
    stretches = {"spine.lateral_bending": d(8), "spine.rotation": d(10), "neck.flexion": d(15),
                 "neck.lateral_bending": d(-10)}
    out["other man posed, mesh"] = (Body.from_parameters(pose_tests.OTHER_MAN),
                                    pose_tests.posed_scan(pose_tests.OTHER_MAN, pose_tests.MAN_POSE, stretches, None, 3),
                                    "male", False)
    truth = Body.from_measurements(sex="male", age=40, stature=1.78, mass=80.0)
    cloud, faces = synthetic_scan(truth, truth.vertices, truth.rig.heads, points=30_000)
    out["example 03 man"] = (truth, make_scan(cloud, faces, "synthetic scan"), "male", False)
    return out


def cpu_seconds() -> float:
    """User + system seconds of this process so far."""
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def fit_pass(stored: Path, out: Path) -> list[dict[str, Any]]:
    """Fit each stored scan in this process; each fit's figures, the fitted bodies' vertices to `out`."""
    from hitogata.made_to_measure.scan_fit import fit_scan
    from hitogata.made_to_measure.scan_fit.scan import Scan
    from hitogata.measure.measurements import GIRTHS

    with np.load(stored, allow_pickle=False) as data:
        recipe = json.loads(str(data["recipe"]))
        arrays = {key: data[key] for key in data.files}
    rows, bodies = [], {}
    for k, (name, sex, detail) in enumerate(recipe):
        faces = arrays[f"faces{k}"] if f"faces{k}" in arrays else None
        scan = Scan(arrays[f"points{k}"], faces, "mm", name)
        wall, cpu = time.perf_counter(), cpu_seconds()
        fit = fit_scan(scan, sex, detail=detail)
        wall, cpu = time.perf_counter() - wall, cpu_seconds() - cpu
        bodies[f"body{k}"] = fit.body.vertices
        girths = {g: fit.measurements.get(g) for g in GIRTHS}
        rows.append({"name": name, "wall": wall, "cpu": cpu, "median": fit.error.median,
                     "girths": {g: v for g, v in girths.items() if np.isfinite(v)}})
    np.savez(out, **bodies)
    return rows


def child_pass(src: Path, stored: Path, out: Path) -> list[dict[str, Any]]:
    """`fit_pass` in a fresh process on the package at `src`."""
    done = subprocess.run([sys.executable, __file__, "--pass", str(stored), str(out)],
                          env={**os.environ, "PYTHONPATH": str(src)}, check=True, capture_output=True, text=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def store_scans(chosen: list[str] | None, path: Path) -> dict[str, dict[str, float]]:
    """The scans written to `path` for both runs; each known body's girths (m), by scan."""
    from hitogata.measure import measure
    from hitogata.measure.measurements import GIRTHS

    made = scans()
    names = list(made) if chosen is None else chosen
    arrays: dict[str, np.ndarray] = {}
    recipe, known = [], {}
    for k, name in enumerate(names):
        truth, scan, sex, detail = made[name]
        arrays[f"points{k}"] = scan.points
        if scan.faces is not None:
            arrays[f"faces{k}"] = scan.faces
        recipe.append((name, sex, detail))
        measured = measure(truth)
        known[name] = {g: measured.get(g) for g in GIRTHS}
    np.savez(path, recipe=np.array(json.dumps(recipe)), **arrays)
    return known


def girth_gap(found: dict[str, float], truth: dict[str, float]) -> str:
    """The fitted girth furthest from the known body's: its difference (mm) and name."""
    gaps = {g: (v - truth[g]) * 1e3 for g, v in found.items()}
    g = max(gaps, key=lambda n: abs(gaps[n]))
    return f"{gaps[g]:+.1f} {g.removesuffix('_girth')}"


def report(now: list[dict[str, Any]], before: list[dict[str, Any]] | None, baseline: str,
           known: dict[str, dict[str, float]], bodies: tuple[Path, Path | None]) -> None:
    ours = np.load(bodies[0])
    theirs = np.load(bodies[1]) if bodies[1] is not None else None
    head = f"{'scan':32s} {'wall s':>6s} {'CPU s':>6s} {'median mm':>9s} {'girth Δ mm':>10s}"
    if before is not None:
        head += f" | {baseline + ' CPU s':>12s} {'median mm':>9s} {'girth Δ mm':>10s} | {'CPU ratio':>9s} {'body Δ mm':>9s}"
    print(head)
    totals = [0.0, 0.0]
    worst_body = 0.0
    for k, row in enumerate(now):
        name = row["name"]
        line = (f"{name:32s} {row['wall']:6.1f} {row['cpu']:6.1f} {row['median'] * 1e3:9.3f} "
                f"{girth_gap(row['girths'], known[name]):>10s}")
        totals[0] += row["cpu"]
        if before is not None and theirs is not None:
            old = before[k]
            gap = float(np.abs(ours[f"body{k}"] - theirs[f"body{k}"]).max()) * 1e3
            worst_body = max(worst_body, gap)
            totals[1] += old["cpu"]
            line += (f" | {old['cpu']:12.1f} {old['median'] * 1e3:9.3f} {girth_gap(old['girths'], known[name]):>10s} | "
                     f"{old['cpu'] / row['cpu']:9.2f} {gap:9.4f}")
        print(line)
    print("girth Δ: the fitted body's girth less the known body's, the largest of the fit's girths (mm)")
    line = f"all {len(now)} fits: now {totals[0]:.1f} s CPU"
    if before is not None:
        line += (f", {baseline} {totals[1]:.1f} s CPU: {totals[1] / totals[0]:.2f}× faster; the fitted bodies "
                 f"differ by at most {worst_body:.4f} mm")
    print(line)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", default="main", help="the commit whose code runs as 'before' (default main)")
    parser.add_argument("--now-only", action="store_true", help="skip the baseline's run")
    parser.add_argument("--scans", default=None, help="comma-separated scan names (default all; --list shows them)")
    parser.add_argument("--list", action="store_true", help="the scans' names, then stop")
    parser.add_argument("--pass", dest="one_pass", nargs=2, metavar=("SCANS", "OUT"),
                        help="fit the stored scans in this process, figures as a JSON line (what each run does)")
    args = parser.parse_args()
    if args.one_pass:
        print(json.dumps(fit_pass(Path(args.one_pass[0]), Path(args.one_pass[1]))))
        return
    if args.list:
        print("\n".join(scans()))
        return
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs")
    with tempfile.TemporaryDirectory() as scratch:
        work = Path(scratch)
        chosen = None if args.scans is None else [s.strip() for s in args.scans.split(",")]
        known = store_scans(chosen, work / "scans.npz")
        now = child_pass(ROOT / "src", work / "scans.npz", work / "now.npz")
        before, theirs = None, None
        if not args.now_only:
            tree = work / "baseline"
            tree.mkdir()
            try:
                archive = subprocess.run(["git", "archive", args.baseline, "src"], cwd=ROOT, capture_output=True,
                                         check=True)
                subprocess.run(["tar", "-x", "-C", str(tree)], input=archive.stdout, check=True)
                before = child_pass(tree / "src", work / "scans.npz", work / "before.npz")
                theirs = work / "before.npz"
            except subprocess.CalledProcessError as err:  # no such commit here (a shallow clone), or its code failed
                print(f"{args.baseline}: not run ({' '.join(map(str, err.cmd))[:80]} exited {err.returncode})")
        report(now, before, args.baseline, known, (work / "now.npz", theirs))
    print(f"load average {os.getloadavg()[0]:.1f} at the end")


if __name__ == "__main__":
    main()
