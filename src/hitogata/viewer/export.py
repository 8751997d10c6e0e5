"""Exports of what the viewer shows: the current pose as a skinned GLB, the scene as static HTML.

The GLB binds the shown (posed) surface to the MakeHuman rig placed at the
posed joint centres, so the file opens in that pose and stays riggable; the
HTML is viser's self-contained snapshot of the scene (no sliders), which
opens from a file without a server.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from hitogata.body.model import Body
from hitogata.export.body_files import body_figures
from hitogata.export.gltf import GlbBuilder, add_skinned_mesh
from hitogata.viewer.frame import Frame

if TYPE_CHECKING:
    import viser


def pose_glb(body: Body, frame: Frame) -> bytes:
    """GLB bytes of the frame's surface bound to the rig at the frame's joint centres."""
    builder = GlbBuilder()
    add_skinned_mesh(
        builder,
        frame.vertices,
        body.faces,
        joint_names=body.rig.names,
        joint_parents=body.rig.parents,
        joint_positions=frame.rig_joints,
        skin_weights=body.skin_weights,
        name="hitogata body (posed)",
        extras={"sex": body.params.sex, "age_years": body.params.age, "posed": True, **body_figures(body)},
    )
    return builder.to_bytes()


def snapshot_html(server: "viser.ViserServer") -> str:
    """A self-contained HTML page of the current scene (static: no GUI, no server)."""
    return server.scene.as_html()

