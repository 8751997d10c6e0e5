"""Convergence of the trunk's 40 lowest frequencies: the evidence behind the default element and size.

Two studies on the default female trunk (shipped materials, bone rigid, cuts attached):

1. Fixed geometry. The lattice at one size is split 1 -> 8 (`hitogata.elastic.refine`),
   which keeps the regions (here labelled by centroid), the bone nodes and the cuts
   exactly; P1 and P2 on the mesh (P1r: P1 on the split mesh, the same nodes as P2)
   against P2 on the split mesh, with the volumetric term in full and on the mean
   dilatation ("P2m", the default). This is the discretisation error alone.
2. Lattice sequence. The whole model at several lattice sizes against the finest
   default run: P2 on the mean dilatation with the tissue sampled inside the
   elements (the default), P2 in full, and P1: discretisation plus the geometry
   the lattice resolves (the bone capsules' surface, a polyhedron of the
   lattice's resolution).

Eigen-solves use our default solver; times are wall-clock on a shared machine.
Runs ~15-25 minutes (the references have ~200k dof). docs/elastic.md quotes its output.

Run:  python benchmarks/convergence_elastic.py [--fixed 40] [--p2 50,45,40,35,30,25,20] [--p2-full 40,30,25,20]
                                              [--p1 40,30,25,20,15,12]
"""

from __future__ import annotations

import argparse
import json
import os
import time

import numpy as np

from hitogata.body import default_body
from hitogata.elastic import load_materials
from hitogata.elastic.model import EIGEN_TOLERANCE, assemble_system
from hitogata.elastic.refine import refine
from hitogata.fem import lift_node_set, mass_matrix, p2_mesh, region_materials, solve_modes, sparsity, stiffness_matrix
from hitogata.volume import build_volume_model

N_MODES = 40


def trunk(body, size: float):
    return build_volume_model(body.vertices, body.faces, body.rig, body.skin_weights, bmi=body.bmi,
                              sex=body.params.sex, extent="trunk", element_size=size)


def modes_of(points, tets, region, fixed, order: int, table, dilatation: str = "full"
             ) -> tuple[np.ndarray, int, float]:
    """Frequencies, free dof and solve time of a labelled P1 mesh solved with P1 or P2 elements."""
    if order == 2:
        points, tets = p2_mesh(points, tets)
        fixed = lift_node_set(tets, fixed)
    E, nu, rho = region_materials(region, table)
    pattern = sparsity(tets, len(points))
    K = stiffness_matrix(points, tets, E, nu, pattern, dilatation)
    M = mass_matrix(points, tets, rho, pattern=pattern)
    start = time.perf_counter()
    modes = solve_modes(K, M, N_MODES, fixed, tol=EIGEN_TOLERANCE)
    return modes.frequencies, 3 * (len(points) - len(fixed)), time.perf_counter() - start


def errors(f: np.ndarray, ref: np.ndarray) -> str:
    e = f / ref - 1.0
    return f"f1 {100 * e[0]:+5.1f}%  mean |e| {100 * np.abs(e).mean():4.1f}%  max |e| {100 * np.abs(e).max():4.1f}%"


def fixed_geometry(body, size: float) -> dict:
    volume = trunk(body, size)
    table = load_materials().table(volume.region_names)
    fixed = assemble_system(volume, body.rig, element="P1").fixed_nodes  # bone + cut nodes
    fine = refine(volume.nodes, volume.tets, volume.region, fixed)
    runs = {
        "P1": modes_of(volume.nodes, volume.tets, volume.region, fixed, 1, table),
        "P1r": modes_of(*fine, 1, table),
        "P2": modes_of(volume.nodes, volume.tets, volume.region, fixed, 2, table),
        "P2r": modes_of(*fine, 2, table),
        "P2m": modes_of(volume.nodes, volume.tets, volume.region, fixed, 2, table, "mean"),
        "P2mr": modes_of(*fine, 2, table, "mean"),
    }
    ref = runs["P2mr"][0]
    print(f"\n1. fixed geometry, lattice {size:g} mm; reference P2mr ({runs['P2mr'][1]} dof): "
          f"f1 {ref[0]:.3f} Hz, f40 {ref[-1]:.3f} Hz")
    for name, (f, dof, seconds) in runs.items():
        print(f"  {name:4}{dof:>8} dof {seconds:>7.1f} s  {errors(f, ref)}", flush=True)
    return {name: {"dof": dof, "seconds": s, "f": f.tolist()} for name, (f, dof, s) in runs.items()}


def lattice(body, p2_sizes: list[float], p2_full_sizes: list[float], p1_sizes: list[float]) -> dict:
    runs = {}
    for name, element, dilatation, sizes in (("P2", "P2", "mean", p2_sizes), ("P2full", "P2", "full", p2_full_sizes),
                                             ("P1", "P1", "full", p1_sizes)):
        for size in sizes:
            volume = trunk(body, size)
            system = assemble_system(volume, body.rig, element=element, dilatation=dilatation)
            start = time.perf_counter()
            f = solve_modes(system.K, system.M, N_MODES, system.fixed_nodes, tol=EIGEN_TOLERANCE).frequencies
            runs[f"{name}@{size:g}"] = {"dof": 3 * (len(system.points) - len(system.fixed_nodes)),
                                        "seconds": time.perf_counter() - start, "f": f.tolist(),
                                        "bone_l": volume.quality.region_volumes["bone"] * 1e3}
            print(f"  ({name} {size:g} mm solved)", flush=True)
    ref_key = f"P2@{min(p2_sizes):g}"
    ref = np.array(runs[ref_key]["f"])
    print(f"\n2. lattice sequence; reference {ref_key}: f1 {ref[0]:.3f} Hz, f40 {ref[-1]:.3f} Hz")
    for key, run in runs.items():
        f = np.array(run["f"])
        print(f"  {key:10}{run['dof']:>8} dof {run['seconds']:>7.1f} s  bone {run['bone_l']:.2f} L  "
              f"{errors(f, ref)}  within 1 %: {int((np.abs(f / ref - 1) < 0.01).sum())}/{N_MODES}")
    return runs


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fixed", type=float, default=40.0, help="lattice size of the fixed-geometry study, mm")
    parser.add_argument("--p2", default="50,45,40,35,30,25,20",
                        help="P2 lattice sizes, mm (the smallest is the reference)")
    parser.add_argument("--p2-full", default="40,30,25,20",
                        help="lattice sizes of P2 with the volumetric term in full, mm")
    parser.add_argument("--p1", default="40,30,25,20,15,12", help="P1 lattice sizes, mm")
    parser.add_argument("--json", default=None, help="also write the frequencies to this JSON file")
    args = parser.parse_args()
    print(f"start: load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    body = default_body("female")
    out = {"fixed": fixed_geometry(body, args.fixed),
           "lattice": lattice(body, *([float(s) for s in sizes.split(",")] if sizes else []
                                      for sizes in (args.p2, args.p2_full, args.p1)))}
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(out, fh)
    print(f"end: load average {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
