"""The 3-D scene: skin, strain-coloured skin, skeleton and tissue surfaces as viser nodes.

Nodes are made once and then updated in place (new vertex positions only,
no re-sent faces), which keeps a slider move to one small message per layer.
Hidden layers are not updated; they catch up with the shown frame when they
are turned on again. The strain-coloured skin is a GLB (viser meshes have no
per-vertex colours), re-sent when the strain is recomputed.
"""

from __future__ import annotations

import io
from typing import TYPE_CHECKING

import numpy as np
import trimesh

from hitogata.viewer.frame import Frame, bone_reach
from hitogata.viewer.tissue import REGION_COLOURS, REGION_OPACITY, TissueSurface

if TYPE_CHECKING:
    import viser

    from hitogata.skeleton.placement import Skeleton

SKIN_COLOUR = (225, 190, 165)
BONE_LINE_COLOUR = (30, 30, 60)
BONE_LINE_THICKNESS = 0.004  # m; a line ends half of it under the skin (`frame.bone_reach`)


def coloured_glb(vertices: np.ndarray, faces: np.ndarray, colours: np.ndarray) -> bytes:
    """A GLB of a surface with per-vertex colours (V, 3) uint8 and smooth normals."""
    mesh = trimesh.Trimesh(vertices, faces, vertex_colors=colours, process=False)
    with io.BytesIO() as buffer:
        mesh.export(buffer, file_type="glb", include_normals=True)
        return buffer.getvalue()


class SceneView:
    """The scene nodes of one body; `show` moves them to a frame."""

    def __init__(self, scene: "viser.SceneApi", faces: np.ndarray, frame: Frame, skin_opacity: float) -> None:
        self.scene, self.faces = scene, faces
        self.layers = {"skin": True, "skeleton": True, "tissue": False, "strain": False}
        self.frame = frame
        self.reach: np.ndarray | None = None  # (N,) the share of each part drawn (`fit_bones`)
        scene.set_up_direction("+y")
        scene.add_grid("/floor", width=2.0, height=2.0, plane="xz", cell_size=0.1, section_size=0.5)
        self.skin = scene.add_mesh_simple(
            "/body/skin", frame.vertices, faces, color=SKIN_COLOUR, opacity=skin_opacity, side="front"
        )
        self.skeleton = scene.add_line_segments(
            "/body/skeleton", self._bones(frame), colors=BONE_LINE_COLOUR, thickness=BONE_LINE_THICKNESS
        )
        self.strain: viser.GlbHandle | None = None
        self.strain_colours: np.ndarray | None = None  # (V, 3) uint8: the colours last shown
        self.tissue: list[tuple[TissueSurface, viser.MeshHandle]] = []

    def _bones(self, frame: Frame) -> np.ndarray:
        bones = frame.bones(self.reach)
        return np.zeros((1, 2, 3)) if bones is None else bones

    def fit_bones(self, skeleton: Skeleton, rest_vertices: np.ndarray) -> None:
        """Draw each part only as far as it lies under this body's skin (fingertips, toes, chin, crown),
        and redraw the skeleton."""
        self.reach = bone_reach(skeleton, rest_vertices, self.faces, clearance=BONE_LINE_THICKNESS / 2)
        if self.skeleton.visible:
            self.skeleton.points = self._bones(self.frame)

    def show(self, frame: Frame) -> None:
        """Move every shown layer to the frame (vertex positions only)."""
        skeleton_known = (frame.pose is None) != (self.frame.pose is None)
        self.frame = frame
        if skeleton_known:
            self._apply_layers()
        if self.skin.visible:
            self.skin.vertices = frame.vertices
        if self.skeleton.visible:
            self.skeleton.points = self._bones(frame)
        if self.layers["tissue"] and frame.pose is not None:
            for surface, handle in self.tissue:
                handle.vertices = surface.posed(frame.pose)

    def set_layer(self, layer: str, on: bool) -> None:
        """Turn a layer on or off, and bring it up to the shown frame."""
        self.layers[layer] = on
        self._apply_layers()
        self.show(self.frame)

    def _apply_layers(self) -> None:
        """Visibility from the layer switches; strain colours replace the plain skin, and the
        skeleton and tissue need the frame's pose (a sequence may have none)."""
        surface, strain, posed = self.layers["skin"], self.layers["strain"], self.frame.pose is not None
        self.skin.visible = surface and not strain
        if self.strain is not None:
            self.strain.visible = surface and strain
        self.skeleton.visible = self.layers["skeleton"] and posed
        for _, handle in self.tissue:
            handle.visible = self.layers["tissue"] and posed

    def set_skin_opacity(self, opacity: float) -> None:
        self.skin.opacity = float(opacity)

    def show_strain(self, vertices: np.ndarray, colours: np.ndarray) -> None:
        """Show the colour-mapped surface (a GLB, re-sent whole)."""
        self.strain_colours = colours
        data = coloured_glb(vertices, self.faces, colours)
        visible = self.layers["skin"] and self.layers["strain"]
        if self.strain is None:
            self.strain = self.scene.add_glb("/body/strain", data, visible=visible)
        else:
            self.strain.glb_data = data
            self.strain.visible = visible

    def set_tissue(self, surfaces: tuple[TissueSurface, ...]) -> None:
        """Replace the tissue surfaces (after a (re)build), posed like the current frame."""
        self.clear_tissue()
        pose = self.frame.pose
        for surface in surfaces:
            vertices = surface.posed(pose) if pose is not None else surface.rest
            handle = self.scene.add_mesh_simple(
                f"/body/tissue/{surface.region}", vertices, surface.faces,
                color=REGION_COLOURS[surface.region], opacity=REGION_OPACITY[surface.region], side="front",
                visible=self.layers["tissue"] and pose is not None, cast_shadow=False, receive_shadow=False,
            )
            self.tissue.append((surface, handle))

    def clear_tissue(self) -> None:
        for _, handle in self.tissue:
            handle.remove()
        self.tissue = []
