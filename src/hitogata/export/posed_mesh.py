"""A posed surface as OBJ/PLY with a JSON sidecar: a posture `hitogata measure` can read back.

An OBJ or PLY holds positions only. `hitogata pose` writes next to it a JSON
file of the same name (`posed.ply` → `posed.json`) with the body's shape, the
pose's rest-relative angles, how the surface was made (`skinning`: lbs/dqs;
`surface`: skinning or elastic); `read_posed_mesh` rebuilds the body, checks
the surface is its skin (vertex count), and gives the posture to measure: the
file's vertices, the rig joints of the pose, and the fine skin
(`hitogata.skin.fine_skin`) posed by the same skinning plus the file's
difference from it (the elastic correction, carried to the fine skin) — or,
where the skin slid over the fascia and its fine skin slid on its own
(`hitogata.skin.skin_slide`), the fine skin's own PLY the sidecar names
(`fine_skin`).
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import numpy as np

from hitogata.body.model import Body
from hitogata.errors import HitogataError
from hitogata.export.atomic import write_bytes_atomically
from hitogata.export.body_files import body_from_extras
from hitogata.options import Skinning
from hitogata.posing.pose import poser_for
from hitogata.posing.skinning import METHODS, skin_vertices
from hitogata.skin.fine_skin import body_fine_skin
from hitogata.skin.fine_skin import body_fine_skinning

SURFACES = ("skinning", "elastic")


def sidecar_path(path: str | os.PathLike) -> Path:
    """The JSON file that describes a posed OBJ/PLY."""
    return Path(path).with_suffix(".json")


def write_sidecar(path: str | os.PathLike, extras: dict[str, Any]) -> Path:
    """Write the sidecar of a posed OBJ/PLY (atomic)."""
    return write_bytes_atomically(sidecar_path(path), (json.dumps(extras, indent=1, allow_nan=False) + "\n").encode())


def posture(body: Body, angles: np.ndarray, skinning: Skinning = "lbs", vertices: np.ndarray | None = None):
    """(skin vertices, rig joints, fine skin vertices) of a pose; `vertices`: a surface made from it
    (e.g. the elastic skin), by default the skinned one."""
    poser = poser_for(body)
    pose = poser.kinematics.pose(np.asarray(angles, dtype=float))  # as written: checked when it was posed
    joints = poser.rig_joints(pose.rotations[0], pose.translations[0])
    v = skin_vertices(poser.skin, pose.rotations, pose.translations, skinning)[0] if vertices is None else vertices
    fine = body_fine_skinning(body).surface(pose, skinning, vertices)
    return v, joints, fine


def read_posed_mesh(path: Path) -> tuple[Body, np.ndarray, np.ndarray, np.ndarray]:
    """Body, skin vertices, rig joints and fine skin vertices of a posed OBJ/PLY with its sidecar."""
    side = sidecar_path(path)
    if not path.is_file():
        raise HitogataError(f"{path}: no such file")
    if not side.is_file():
        raise HitogataError(
            f"{path}: no {side.name} beside it; allowed a .glb written by `hitogata body` or `hitogata pose`, "
            "or an .obj/.ply written by `hitogata pose` with its .json"
        )
    try:
        extras = json.loads(side.read_text())
    except (OSError, ValueError) as err:
        raise HitogataError(f"{side}: not a hitogata pose description ({err})") from None
    if not isinstance(extras, dict):
        raise HitogataError(f"{side}: not a hitogata pose description (expected a JSON object)")
    body = body_from_extras(side, extras)
    angles = extras.get("angles_rad")
    if not isinstance(angles, list) or len(angles) != poser_for(body).skeleton.n_dofs:
        raise HitogataError(f"{side}: angles_rad: allowed {poser_for(body).skeleton.n_dofs} angles in radians")
    skinning = extras.get("skinning", "lbs")
    if skinning not in METHODS:
        raise HitogataError(f"{side}: skinning = {skinning!r}: allowed {', '.join(METHODS)}")
    vertices = _mesh_vertices(path, len(body.vertices), "the hitogata skin")
    v, joints, fine = posture(body, np.asarray(angles, dtype=float), skinning, vertices)
    if "fine_skin" in extras:
        fine = _read_fine_skin(side, extras["fine_skin"], body)
    return body, v, joints, fine


def _mesh_vertices(path: Path, count: int, what: str) -> np.ndarray:
    """The (count, 3) finite vertices of the mesh file `path` (`what` it must be, for the error)."""
    import trimesh  # here: writing a sidecar or posing needs no mesh reader

    try:
        mesh = trimesh.load(path, process=False, force="mesh")
    except Exception as err:  # noqa: BLE001 -- trimesh raises many kinds on a broken file
        raise HitogataError(f"{path}: not a readable mesh ({err})") from None
    vertices = np.asarray(mesh.vertices, dtype=float)
    if vertices.shape != (count, 3) or not np.isfinite(vertices).all():
        raise HitogataError(f"{path}: {len(vertices)} vertices, allowed {count} finite ones ({what})")
    return vertices


def _read_fine_skin(side: Path, name: Any, body: Body) -> np.ndarray:
    """The fine skin's vertices from the PLY the sidecar `side` names (`fine_skin`), beside it."""
    allowed = f"allowed the name of the fine skin's .ply beside {side.name}, written with it by `hitogata pose`"
    if not isinstance(name, str) or Path(name).name != name or not name.lower().endswith(".ply"):
        raise HitogataError(f"{side}: fine_skin = {name!r}: {allowed}")
    path = side.with_name(name)
    if not path.is_file():
        raise HitogataError(f"{side}: fine_skin = {name!r}: no such file; {allowed}")
    return _mesh_vertices(path, len(body_fine_skin(body).vertices), "the hitogata fine skin")
