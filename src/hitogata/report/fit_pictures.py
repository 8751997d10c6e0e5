"""The fit report's pictures of the moving body, drawn by the render layer (`hitogata.render`).

- snapshots: the skinned body at a motion's frames, front and side;
- the stretch map: the largest principal skin strain (%) at a frame, front
  and back, on one scale for every motion (±MAP_RANGE), with each garment
  zone (`garment.stretch`) outlined in its colour;
- the lines of non-extension (`garment.non_extension`) of a frame, drawn on
  the rest body coloured by that frame's stretch, front and back;
- the pressure map: a stretch garment's pressure (mmHg, `garment.pressure_map`)
  on the skin it covers at a frame, front, right side and back.

One offscreen window (a `render.Renderer`) serves every picture of a report;
each picture is PNG bytes.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import matplotlib
import numpy as np
from matplotlib.colors import to_hex

from hitogata.export.gltf import vertex_normals
from hitogata.garment.fit import FitAnswers, posture
from hitogata.garment.non_extension import Line
from hitogata.garment.pressure import MMHG
from hitogata.garment.pressure_map import pressure_map
from hitogata.garment.stretch import GARMENT_ZONES, MAP_RANGE
from hitogata.geometry.mesh_checks import boundary_edges
from hitogata.measure.strain import skin_strain
from hitogata.garment.stretch import garment_zones

if TYPE_CHECKING:
    from hitogata.render import Renderer

SKIN = "#d9b59c"
HEIGHT = 460  # pixels per view
MAP_WIDTH = 340  # pixels per view of a map: room for its colour bar
OUTLINE_LIFT = 0.003  # m: zone outlines drawn this far outside the skin, so the surface does not hide them
OUTLINE_PIXELS = 2.5
LINES_HEIGHT = 720  # pixels per view of the lines of non-extension: thin lines need room
FAMILY_COLOURS = ("#111111", "#1b7837")  # lines of non-extension at +θ and −θ from the most stretch


def zone_colours() -> dict[str, str]:
    """Each garment zone's outline colour (matplotlib's tab10, in the zones' order)."""
    palette = matplotlib.colormaps["tab10"].colors
    return {zone: to_hex(palette[k % len(palette)]) for k, zone in enumerate(GARMENT_ZONES)}


class FitPictures:
    """The pictures of one report's motions, drawn in one live offscreen window (a `render.Renderer`)."""

    def __init__(self, answers: FitAnswers, renderer: Renderer) -> None:
        self.answers = answers
        self._renderer = renderer

    def _picture(self, items: list, views: tuple[str, ...], caption: str, width: int | None = None,
                 height: int = HEIGHT) -> np.ndarray:
        from hitogata.render import side_by_side, titled

        images = self._renderer.render(items, views=views, size=(width, height), labels=True)
        return titled(side_by_side(images, gap=8), caption)

    def snapshots(self, motion: str, frames: list[int]) -> bytes:
        """The body at each frame (front and side), left to right, each titled with its time."""
        from hitogata.render import Layer, png_bytes, side_by_side

        body, clip = self.answers.body, self.answers.clips[motion]
        pictures = [self._picture([Layer(posture(self.answers, motion, k)[0], body.faces, color=SKIN)],
                                  ("front", "side"), f"t = {clip.times[k]:.2f} s") for k in frames]
        return png_bytes(side_by_side(pictures, gap=24))

    def stretch_map(self, motion: str, frame: int) -> bytes:
        """The largest principal strain (%) at `frame`, front and back, the garment zones outlined."""
        from hitogata.render import Layer, Lines, png_bytes

        body, clip = self.answers.body, self.answers.clips[motion]
        vertices = posture(self.answers, motion, frame)[0]
        values = skin_strain(body.vertices, vertices, body.faces).strain_max_percent
        items: list = [Layer(vertices, body.faces, scalars=np.clip(np.nan_to_num(values), -MAP_RANGE, MAP_RANGE),
                             colormap="RdBu_r", clim=(-MAP_RANGE, MAP_RANGE),
                             scalar_title="largest principal strain (%)")]
        lifted = vertices + OUTLINE_LIFT * vertex_normals(vertices, body.faces)
        colours = zone_colours()
        for zone, faces in garment_zones(body)[0].items():
            edges = boundary_edges(body.faces[faces])
            if len(edges):
                items.append(Lines(lifted[edges], color=colours[zone], width=OUTLINE_PIXELS))
        caption = f"skin stretch at t = {clip.times[frame]:.2f} s (colours saturate beyond ±{MAP_RANGE:.0f} %)"
        return png_bytes(self._picture(items, ("front", "back"), caption, MAP_WIDTH))

    def non_extension_map(self, motion: str, frame: int, lines: list[Line]) -> bytes:
        """The lines of non-extension of `frame` on the rest body, coloured by that frame's principal strain."""
        from scipy.spatial import cKDTree

        from hitogata.render import Layer, Lines, png_bytes

        body, clip = self.answers.body, self.answers.clips[motion]
        values = skin_strain(body.vertices, posture(self.answers, motion, frame)[0], body.faces).strain_max_percent
        items: list = [Layer(body.vertices, body.faces, colormap="RdBu_r", clim=(-MAP_RANGE, MAP_RANGE),
                             scalars=np.clip(np.nan_to_num(values), -MAP_RANGE, MAP_RANGE),
                             scalar_title="largest principal strain (%)")]
        normals = vertex_normals(body.vertices, body.faces)
        tree = cKDTree(body.vertices)
        for family, colour in enumerate(FAMILY_COLOURS):
            chosen = [line.points for line in lines if line.family == family]
            if chosen:
                segments = np.concatenate([np.stack([p[:-1], p[1:]], axis=1) for p in chosen])
                lifted = segments + OUTLINE_LIFT * normals[tree.query(segments)[1]]
                items.append(Lines(lifted, color=colour, width=OUTLINE_PIXELS))
        caption = (f"lines of non-extension at t = {clip.times[frame]:.2f} s on the rest body "
                   f"({len(lines)} lines, {sum(line.length for line in lines):.1f} m)")
        return png_bytes(self._picture(items, ("front", "back"), caption, LINES_HEIGHT * MAP_WIDTH // HEIGHT,
                                       LINES_HEIGHT))

    def pressure_map(self, motion: str, frame: int) -> bytes:
        """The garment's pressure (mmHg) at `frame` on the skin it covers, front, right side and back."""
        from hitogata.render import Layer, png_bytes

        answers = self.answers
        assert answers.garment is not None, "a pressure map needs a garment"
        body, clip = answers.body, answers.clips[motion]
        vertices, joints = posture(answers, motion, frame)
        mmhg = pressure_map(body, *answers.garment, vertices, joints).pressure / MMHG
        covered = np.isfinite(mmhg)[body.faces].all(axis=1)
        top = float(np.nanmax(mmhg)) if covered.any() else 1.0
        items: list = []
        if covered.any():
            items.append(Layer(vertices, body.faces[covered], scalars=np.nan_to_num(mmhg), colormap="viridis",
                               clim=(0.0, max(top, 1e-3)), scalar_title="pressure (mmHg)"))
        if (~covered).any():
            items.append(Layer(vertices, body.faces[~covered], color=SKIN))
        caption = f"garment pressure at t = {clip.times[frame]:.2f} s"
        return png_bytes(self._picture(items, ("front", "right", "back"), caption, MAP_WIDTH))
