"""One place for each geometric idea: each function below is defined once, in its geometry module, and no
other module computes a triangle's normal or a Rodrigues rotation inline (read from the source)."""

from __future__ import annotations

import ast
from functools import cache
from pathlib import Path

import pytest

SOURCE = Path(__file__).resolve().parents[2] / "src"

# idea -> (the owning module, the functions it defines)
OWNERS: dict[str, tuple[str, tuple[str, ...]]] = {
    "normals and areas": ("hitogata.geometry.normals",
                          ("triangle_normals", "triangle_areas", "face_normals", "vertex_normals", "vertex_areas")),
    "closest point on a surface": ("hitogata.geometry.closest",
                                   ("closest_points_on_triangles", "nearest_on_triangles", "barycentric_on_triangles")),
    "broad phase": ("hitogata.geometry.broad_phase", ("box_pairs",)),
    "a triangle's deformation": ("hitogata.geometry.strain", ("deformation", "principal_stretches")),
    "winding number": ("hitogata.geometry.mesh_checks", ("winding_number",)),
    "rotations": ("hitogata.geometry.rotations",
                  ("axis_rotations", "matrix_to_quaternion", "quaternion_matrices", "soa_quaternion_matrices",
                   "shortest_arc", "extract_rotations")),
}


@cache
def definitions() -> dict[str, list[str]]:
    """Function name -> the modules defining it (module level or in a class)."""
    found: dict[str, list[str]] = {}
    for path in sorted((SOURCE / "hitogata").rglob("*.py")):
        module = ".".join(path.relative_to(SOURCE).with_suffix("").parts).removesuffix(".__init__")
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                found.setdefault(node.name, []).append(module)
    return found


@pytest.mark.parametrize("idea", sorted(OWNERS))
def test_each_geometric_idea_is_defined_once_in_its_module(idea: str) -> None:
    owner, names = OWNERS[idea]
    for name in names:
        assert definitions().get(name) == [owner], f"{idea}: {name} defined in {definitions().get(name)}"


def _edge(node: ast.expr, first: int) -> str | None:
    """`x[:, first] - x[:, 0]` -> "x", else None."""
    if not (isinstance(node, ast.BinOp) and isinstance(node.op, ast.Sub)):
        return None
    names = []
    for side, index in ((node.left, first), (node.right, 0)):
        if not (isinstance(side, ast.Subscript) and isinstance(side.slice, ast.Tuple)
                and len(side.slice.elts) == 2 and isinstance(side.slice.elts[1], ast.Constant)
                and side.slice.elts[1].value == index):
            return None
        names.append(ast.unparse(side.value))
    return names[0] if names[0] == names[1] else None


def inline_triangle_normals() -> list[str]:
    """Where `np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])` is written outside geometry.normals."""
    found = []
    for path in sorted((SOURCE / "hitogata").rglob("*.py")):
        if path.match("geometry/normals.py"):
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Call) and ast.unparse(node.func).endswith("cross") and len(node.args) == 2:
                first, second = _edge(node.args[0], 1), _edge(node.args[1], 2)
                if first is not None and first == second:
                    found.append(f"{path.relative_to(SOURCE)}:{node.lineno}")
    return found


def test_no_module_computes_a_triangle_normal_inline() -> None:
    assert inline_triangle_normals() == []


def test_the_normal_scan_finds_the_pattern() -> None:
    code = "import numpy as np\nn = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])\n"
    call = next(node for node in ast.walk(ast.parse(code)) if isinstance(node, ast.Call))
    assert _edge(call.args[0], 1) == "tri" and _edge(call.args[1], 2) == "tri"
