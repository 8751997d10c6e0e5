"""Write a `Body` to a file whose format follows the suffix."""

from __future__ import annotations

import os
from dataclasses import asdict
from pathlib import Path

import numpy as np

from hitogata.body.model import WHOLE_BODY_DENSITY, Body, check_density
from hitogata.errors import HitogataError, excerpt
from hitogata.export.atomic import write_bytes_atomically
from hitogata.export.meshfiles import MESH_SUFFIXES, write_mesh
from hitogata.body.shape import ShapeParameters

DETAIL_KEY = "detail_offsets_0.01mm"  # a fitted body's per-skin-vertex offsets along the rest normals


def body_figures(body: Body) -> dict[str, float]:
    """The body's headline figures in the units a person reads (cm, kg, L, kg/m²)."""
    return {
        "stature_cm": round(body.stature * 100, 2),
        "mass_kg": round(body.mass, 2),
        "bmi": round(body.bmi, 2),
        "volume_l": round(body.volume * 1000, 2),
    }


def shape_extras(params: ShapeParameters) -> dict[str, object]:
    """The shape parameters as JSON-able extras, enough to rebuild the body exactly."""
    return {**asdict(params), "race": list(params.race)}


def detail_extras(body: Body) -> dict[str, object]:
    """A fitted body's per-vertex detail (`hitogata.made_to_measure.scan_fit.detail`) as extras, in 0.01 mm;
    empty for a model body."""
    from hitogata.made_to_measure.scan_fit.detail import detail_offsets

    offsets = detail_offsets(body)
    return {} if offsets is None else {DETAIL_KEY: np.round(offsets * 1e5).astype(int).tolist()}


def body_from_extras(path: Path, extras: dict) -> Body:
    """The body a hitogata GLB was written from (its extras hold the shape parameters, and the
    per-vertex detail of a body fitted to a scan)."""
    shape = extras.get("shape")
    if not isinstance(shape, dict):
        raise HitogataError(f"{path}: no hitogata shape in the file's extras; allowed: a .glb written by hitogata")
    try:
        params = ShapeParameters(**{**shape, "race": tuple(shape.get("race", (1 / 3,) * 3))})
    except TypeError as err:
        raise HitogataError(f"{path}: extras 'shape' {excerpt(shape)}: {err}") from None
    density = check_density(extras.get("density", WHOLE_BODY_DENSITY), f"{path}: extras 'density'")
    if DETAIL_KEY not in extras:
        return Body.from_parameters(params, density)
    from hitogata.made_to_measure.scan_fit.detail import detailed_body

    try:
        offsets = np.asarray(extras[DETAIL_KEY], dtype=np.float64) * 1e-5
    except (TypeError, ValueError):
        raise HitogataError(f"{path}: extras '{DETAIL_KEY}': allowed a list of integers (0.01 mm)") from None
    try:
        return detailed_body(params, offsets, density)
    except HitogataError as err:
        raise HitogataError(f"{path}: {err}") from None


def check_body_path(path: str | os.PathLike) -> Path:
    """The path, if its suffix names a format a body can be written in."""
    path = Path(path)
    if path.suffix.lower() not in MESH_SUFFIXES:
        raise HitogataError(f"{path}: unknown file suffix {path.suffix!r}; allowed: {', '.join(MESH_SUFFIXES)}")
    return path


def write_body(path: str | os.PathLike, body: Body) -> Path:
    """GLB with the MakeHuman rig and skin weights, or a plain OBJ/PLY surface."""
    path = check_body_path(path)
    if path.suffix.lower() != ".glb":
        return write_mesh(path, body.vertices, body.faces)
    return write_bytes_atomically(path, body_glb_bytes(body))


def body_glb_bytes(body: Body) -> bytes:
    """The body's GLB (rig, skin weights, shape, density, figures, detail), as `write_body` writes it."""
    from hitogata.export.gltf import GlbBuilder, add_skinned_mesh  # pygltflib: only to write a GLB

    builder = GlbBuilder()
    add_skinned_mesh(
        builder,
        body.vertices,
        body.faces,
        joint_names=body.rig.names,
        joint_parents=body.rig.parents,
        joint_positions=body.rig.heads,
        skin_weights=body.skin_weights,
        name="hitogata body",
        extras={"shape": shape_extras(body.params), "density": body.density, **body_figures(body),
                **detail_extras(body)},
    )
    return builder.to_bytes()
