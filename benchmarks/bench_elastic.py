"""Elastic body timings and accuracy: the default trunk model end to end, then mesh sizes against scipy's default.

Part 1, the default trunk model (`build_elastic_model(body)`: P2 tets, 40 modes)
of the default female and male bodies, end to end: meshing, assembly, the 40
lowest modes, the skin map; goal <= 10 s.

Part 2, the female trunk at several lattice sizes: P2 (our default element)
and P1 (scipy's default path: linear tets, `eigsh(K, 40, M, sigma=0)` with
SuperLU/COLAMD, tol 0, as a user calls it). Each row gives the mesh,
assembly and eigen-solve times, and how far its 40 frequencies are from a
reference (P2 at a finer lattice, `--reference`): mean and largest relative
difference. Where a size allows, scipy's eigsh also runs on our P2 matrices
(the solver ratio, as in the FEM baseline). The summary compares our default
with the fastest scipy-default P1 run that is at least as accurate.

The CPU is shared with other jobs: times are wall-clock (part 1 also gives
the process's CPU time, less sensitive to the load; the mesher and the
assembly use two BLAS threads, so on an idle machine CPU time exceeds wall
time), and the load average is printed at the start and the end.

Run:  python benchmarks/bench_elastic.py [--sizes 50,40,35] [--p1-sizes 20,15] [--reference 25]
                                         [--no-scipy-above 70000]
"""

from __future__ import annotations

import argparse
import os
import platform
import time

import numpy as np
import scipy

from hitogata.body import default_body
from hitogata.elastic import DEFAULT_ELEMENT_SIZES, build_elastic_model
from hitogata.elastic.model import EIGEN_TOLERANCE, assemble_system
from hitogata.fem import available_methods, solve_modes
from hitogata.volume import build_volume_model

N_MODES = 40
GOAL_SECONDS = 10.0


def load() -> str:
    one, five, fifteen = os.getloadavg()
    return f"load average {one:.2f}, {five:.2f}, {fifteen:.2f} on {os.cpu_count()} cores"


def timed(fn, *args, **kwargs):
    start = time.perf_counter()
    out = fn(*args, **kwargs)
    return out, time.perf_counter() - start


def part_default() -> None:
    print(f"\n1. default trunk model end to end (P2 at {DEFAULT_ELEMENT_SIZES['P2']:g} mm, {N_MODES} modes)")
    print(f"{'body':8}{'tets':>8}{'free dof':>10}{'mesh':>7}{'assembly':>10}{'modes':>7}{'skin map':>10}"
          f"{'total':>8}{'(CPU)':>8}  goal   f1 .. f40 (Hz)")
    for sex in ("female", "male"):
        body = default_body(sex)
        cpu = time.process_time()
        model, total = timed(build_elastic_model, body)
        cpu = time.process_time() - cpu
        t = model.timings
        dof = 3 * (len(model.points) - len(model.fixed_nodes))
        verdict = "ok" if total <= GOAL_SECONDS else "MISS"
        f = model.frequencies
        lowest = f"{f[0]:.2f} {f[1]:.2f} {f[2]:.2f} .. {f[-1]:.2f}"
        print(f"{sex:8}{len(model.elements):>8}{dof:>10}{t['mesh']:>6.1f}s{t['assembly']:>9.1f}s{t['modes']:>6.1f}s"
              f"{t['skin_map']:>9.1f}s{total:>7.1f}s{cpu:>7.1f}s  {verdict:5}  {lowest}")


def run_size(body, element: str, size: float, ours: bool, scipy_limit: int | None = 0) -> dict:
    """Mesh, assemble and solve one lattice size with our solver and/or scipy's default eigsh
    (the latter up to `scipy_limit` free dof; None: always, 0: never)."""
    volume, t_mesh = timed(build_volume_model, body.vertices, body.faces, body.rig, body.skin_weights,
                           bmi=body.bmi, sex=body.params.sex, extent="trunk", element_size=size)
    system, t_asm = timed(assemble_system, volume, body.rig, element=element)
    row = {"element": element, "size": size, "dof": 3 * (len(system.points) - len(system.fixed_nodes)),
           "mesh": t_mesh, "assembly": t_asm}
    if ours:
        modes, row["ours"] = timed(solve_modes, system.K, system.M, N_MODES, system.fixed_nodes, tol=EIGEN_TOLERANCE)
        row["f"] = modes.frequencies
    if scipy_limit is None or row["dof"] <= scipy_limit:
        modes, row["scipy"] = timed(solve_modes, system.K, system.M, N_MODES, system.fixed_nodes, solver="scipy",
                                    tol=0.0, blas_threads=None)
        if "f" in row:
            row["agree"] = float(np.max(np.abs(modes.frequencies / row["f"] - 1.0)))
        row["f"] = modes.frequencies
    return row


def part_sizes(sizes: list[float], p1_sizes: list[float], reference: float, scipy_limit: int) -> None:
    body = default_body("female")
    print(f"\n2. female trunk, {N_MODES} modes, against a reference: P2 at {reference:g} mm (our solver)")
    ref = run_size(body, "P2", reference, ours=True)
    print(f"reference: {ref['dof']} free dof, eigen-solve {ref['ours']:.1f} s; f1 {ref['f'][0]:.3f} Hz, "
          f"f40 {ref['f'][-1]:.3f} Hz")
    print(f"{'':4}{'size':>6}{'free dof':>10}{'mesh':>7}{'assembly':>10}{'ours':>8}{'scipy eigsh':>13}"
          f"{'ratio':>7}{'total ours':>12}{'total scipy':>13}{'mean err':>10}{'max err':>9}")
    rows = []
    for element, size in [("P2", s) for s in sizes] + [("P1", s) for s in p1_sizes]:
        row = run_size(body, element, size, ours=(element == "P2"),
                       scipy_limit=scipy_limit if element == "P2" else None)
        error = np.abs(row["f"] / ref["f"] - 1.0)
        row["mean_err"], row["max_err"] = float(error.mean()), float(error.max())
        rows.append(row)
        base = row["mesh"] + row["assembly"]
        ours = f"{row['ours']:>7.1f}s" if "ours" in row else f"{'–':>8}"
        sci = f"{row['scipy']:>12.1f}s" if "scipy" in row else f"{'skipped':>13}"
        ratio = f"{row['scipy'] / row['ours']:>6.1f}x" if "ours" in row and "scipy" in row else f"{'':>7}"
        total_ours = f"{base + row['ours']:>11.1f}s" if "ours" in row else f"{'':>12}"
        total_sci = f"{base + row['scipy']:>12.1f}s" if "scipy" in row else f"{'':>13}"
        print(f"{element:4}{size:>4g}mm{row['dof']:>10}{row['mesh']:>6.1f}s{row['assembly']:>9.1f}s{ours}{sci}{ratio}"
              f"{total_ours}{total_sci}{100 * row['mean_err']:>9.1f}%{100 * row['max_err']:>8.1f}%", flush=True)
        if "agree" in row:
            assert row["agree"] < 1e-6, f"solvers disagree by {row['agree']:.2e}"

    default = next((r for r in rows if r["element"] == "P2" and r["size"] == DEFAULT_ELEMENT_SIZES["P2"]), None)
    if default is None:
        return
    total = default["mesh"] + default["assembly"] + default["ours"]
    as_good = [r for r in rows if r["element"] == "P1" and "scipy" in r
               and r["mean_err"] <= default["mean_err"] and r["max_err"] <= default["max_err"]]
    print(f"\ndefault (P2 {default['size']:g} mm): {total:.1f} s to the modes, "
          f"mean error {100 * default['mean_err']:.1f}%, max {100 * default['max_err']:.1f}% vs the reference")
    if as_good:
        best = min(as_good, key=lambda r: r["mesh"] + r["assembly"] + r["scipy"])
        scipy_total = best["mesh"] + best["assembly"] + best["scipy"]
        print(f"scipy-default P1 path at least as accurate: {best['size']:g} mm, {scipy_total:.1f} s "
              f"-> ours is {scipy_total / total:.1f}x faster")
        return
    p1 = [r for r in rows if r["element"] == "P1" and "scipy" in r]
    if p1:
        best = min(p1, key=lambda r: r["mean_err"])
        scipy_total = best["mesh"] + best["assembly"] + best["scipy"]
        print(f"no scipy-default P1 run is as accurate; the most accurate, {best['size']:g} mm "
              f"(mean {100 * best['mean_err']:.1f}%, max {100 * best['max_err']:.1f}%), took {scipy_total:.1f} s "
              f"-> ours is more than {scipy_total / total:.1f}x faster at equal accuracy")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="50,40,35", help="P2 lattice sizes, mm")
    parser.add_argument("--p1-sizes", default="20,15", help="P1 lattice sizes for scipy's default path, mm")
    parser.add_argument("--reference", type=float, default=25.0, help="reference P2 lattice size, mm")
    parser.add_argument("--no-scipy-above", type=int, default=70000,
                        help="skip scipy's eigsh on our P2 matrices above this many free dof")
    args = parser.parse_args()
    print(f"hitogata elastic benchmark — Python {platform.python_version()}, numpy {np.__version__}, "
          f"scipy {scipy.__version__}; factorizations: {', '.join(available_methods())}")
    print(f"start: {load()}")
    part_default()
    part_sizes([float(s) for s in args.sizes.split(",")], [float(s) for s in args.p1_sizes.split(",")],
               args.reference, args.no_scipy_above)
    print(f"\nend: {load()}")


if __name__ == "__main__":
    main()
