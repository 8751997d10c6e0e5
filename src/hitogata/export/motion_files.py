"""What a simulated motion is written as: GLB animation, VTU series, pictures, GIF, summary.

- GLB: the skin surface and the tissue regions' boundary surfaces, each with
  one morph target per frame, and an animation of the morph weights (one-hot,
  linear in between), so three.js and Blender play it as a shape-key
  animation; checked by the Khronos validator in the tests.
- VTU + PVD: the FE mesh per frame (quadratic tets as VTK's tetra10) with
  displacement, elastic displacement and the tissue (`export.tissue_data`:
  per-sample labels, fractions, materials), a time series for ParaView.
- PNG: front and side views of the region boundary surfaces, translucent,
  with the skeleton inside (the paper's Fig. 3(b)), at chosen times: every
  region's own closed surface over the whole body (`volume.region_surfaces`),
  carried as the tissue moves (`dynamics.carried_surfaces`).
- GIF: the same views over time (pillow).
Every file is written whole or not at all.
"""

from __future__ import annotations

import io
import json
import os
from pathlib import Path
from typing import Any, Self
from xml.sax.saxutils import quoteattr

import meshio
import numpy as np
import pygltflib as gl

from hitogata.body.model import WHOLE_BODY_DENSITY, Body
from hitogata.dynamics.carried_surfaces import CarriedSurface
from hitogata.dynamics.motion import Motion
from hitogata.errors import HitogataError
from hitogata.export.atomic import write_bytes_atomically
from hitogata.export.npz_read import read_npz
from hitogata.export.body_files import DETAIL_KEY, body_from_extras, detail_extras, shape_extras
from hitogata.export.gltf import GlbBuilder, add_material, named_node
from hitogata.geometry.normals import vertex_normals
from hitogata.export.tissue_data import tissue_cell_data, tissue_field_data
from hitogata.export.vtu import write_vtu

SKIN_OPACITY = 0.35  # the skin over the regions in the motion GLB: see-through, so the tissue shows
SUPERSAMPLE = 2  # snapshots: rendered at twice the size and averaged (smooth edges)
# GIF frames: at their size (a 256-colour animation's edges gain little; 2.6x cheaper per frame on
# software OpenGL, and the GIF's frames are most of the pictures' time)
GIF_SUPERSAMPLE = 1
MAX_TARGETS = 120  # morph targets in a GLB: frames beyond are subsampled evenly
REGION_STYLE = {  # colour, opacity: translucent nested surfaces as in the paper's figure
    "skin": ("#e3b899", 0.22),
    "muscle": ("#b5473a", 0.30),
    "viscera": ("#d9a52b", 0.45),
    "bone": ("#efe9dc", 0.55),  # the bones fill the limbs' capsules: the skeleton's lines show through them
}


def frame_subset(n_frames: int, most: int) -> np.ndarray:
    """Indices of at most `most` frames spread evenly, first and last included."""
    return np.unique(np.round(np.linspace(0, n_frames - 1, min(n_frames, most))).astype(int))


def write_motion_glb(path: str | os.PathLike, motion: Motion) -> Path:
    """The skin and the tissue regions' boundary surfaces as one morph-target animation.

    Each surface is a mesh with one morph target per frame (frames subsampled
    to `MAX_TARGETS`); one set of one-hot weight keys drives them all. The
    skin is the whole body's, translucent (material "skin"); the regions (the
    whole body's, with fewer triangles than the pictures': `region_surfaces`;
    nodes and materials "region_<name>") are translucent in the colours of
    the pictures, nested inside it. Each mesh
    has smooth vertex normals at rest; node names are safe for three.js.
    """
    pick = frame_subset(len(motion.times), MAX_TARGETS)
    body = motion.dynamics.poser.body
    builder = GlbBuilder()
    names = [f"t={motion.times[k]:.3f}s" for k in pick]
    skin = add_material(builder, "skin", (*_rgb(REGION_STYLE["skin"][0]), SKIN_OPACITY))
    nodes = [_add_morphing_mesh(builder, "skin", body.faces, body.vertices, motion.skin[pick], names, skin)]
    for name, surface in region_surfaces(motion, light=True).items():
        colour, opacity = REGION_STYLE[name]
        material = add_material(builder, f"region_{name}", (*_rgb(colour), opacity))
        nodes.append(_add_morphing_mesh(builder, f"region_{name}", surface.faces, surface.rest,
                                        np.stack([surface.frame(motion, k) for k in pick]), names,
                                        material=material))
    times = builder.add_accessor(motion.times[pick].astype(np.float32), gl.SCALAR, with_bounds=True)
    weights = builder.add_accessor(np.eye(len(pick), dtype=np.float32).reshape(-1), gl.SCALAR)
    builder.gltf.scenes[0].extras = playback_extras(motion.times[pick])
    builder.gltf.animations.append(gl.Animation(
        name="motion",
        samplers=[gl.AnimationSampler(input=times, output=weights, interpolation="LINEAR")],
        channels=[gl.AnimationChannel(sampler=0, target=gl.AnimationChannelTarget(node=node, path="weights"))
                  for node in nodes],
    ))
    return write_bytes_atomically(path, builder.to_bytes())


def playback_extras(times: np.ndarray) -> dict[str, float]:
    """The scene's extras: the animation's time span, for a tool that does not take its playback range
    from the animation. Blender's importer (5.0) leaves the scene at frames 1–250 and copies these onto
    the scene as custom properties; docs/scenarios.md has the line that sets the range from them."""
    return {"animation_start_s": float(times[0]), "animation_end_s": float(times[-1])}


def _rgb(colour: str) -> tuple[float, float, float]:
    return tuple(int(colour[i:i + 2], 16) / 255.0 for i in (1, 3, 5))  # type: ignore[return-value]


def _add_morphing_mesh(builder: GlbBuilder, name: str, faces: np.ndarray, rest: np.ndarray, frames: np.ndarray,
                       target_names: list[str], material: int | None = None) -> int:
    """A root node with a mesh of `faces` at `rest` (V, 3), its rest normals, and a morph target per frame
    (position and normal deltas: the frame's own vertex normals, so a moved limb is lit as it lies)."""
    faces = np.asarray(faces, dtype=np.int64)
    normals = vertex_normals(rest.astype(np.float64), faces).astype(np.float32)
    rest = rest.astype(np.float32)
    position = builder.add_accessor(rest, gl.VEC3, target=gl.ARRAY_BUFFER, with_bounds=True)
    normal = builder.add_accessor(normals, gl.VEC3, target=gl.ARRAY_BUFFER)
    indices = builder.add_accessor(faces.astype(np.uint32).reshape(-1), gl.SCALAR, target=gl.ELEMENT_ARRAY_BUFFER)
    targets = [{"POSITION": builder.add_accessor((frame - rest).astype(np.float32), gl.VEC3,
                                                 target=gl.ARRAY_BUFFER, with_bounds=True),
                "NORMAL": builder.add_accessor(
                    vertex_normals(frame.astype(np.float64), faces).astype(np.float32) - normals, gl.VEC3,
                    target=gl.ARRAY_BUFFER)}
               for frame in frames]
    primitive = gl.Primitive(attributes=gl.Attributes(POSITION=position, NORMAL=normal), indices=indices,
                             targets=targets,
                             material=material)
    builder.gltf.meshes.append(gl.Mesh(name=name, primitives=[primitive], weights=[0.0] * len(frames),
                                       extras={"targetNames": target_names}))
    return builder.add_node(named_node(name, mesh=len(builder.gltf.meshes) - 1), root=True)


def write_pvd(folder: str | os.PathLike, motion: Motion, name: str = "motion") -> Path:
    """`name.pvd` and `name/frame_NNNN.vtu` in folder: the FE body at every frame, with its tissue
    (`export.tissue_data`)."""
    folder = Path(folder)
    frames = folder / name
    frames.mkdir(parents=True, exist_ok=True)
    model = motion.dynamics.model
    cell = "tetra10" if model.elements.shape[1] == 10 else "tetra"
    skinned = motion.nodes - motion.elastic
    tissue, about = tissue_cell_data(model), tissue_field_data(model)
    entries = []
    for k, t in enumerate(motion.times):
        mesh = meshio.Mesh(
            motion.nodes[k].astype(np.float64), [(cell, model.elements)],
            point_data={"displacement": (motion.nodes[k] - model.points).astype(np.float64),
                        "elastic": motion.elastic[k].astype(np.float64),
                        "skinned": skinned[k].astype(np.float64)},
            cell_data=tissue,
        )
        file = frames / f"frame_{k:04d}.vtu"
        write_vtu(file, mesh, {"time_s": np.array([t]), **about})
        entries.append(f'    <DataSet timestep="{t:.6f}" part="0" file={quoteattr(f"{name}/{file.name}")}/>')
    xml = ('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n'
           + "\n".join(entries) + "\n  </Collection>\n</VTKFile>\n")
    return write_bytes_atomically(folder / f"{name}.pvd", xml.encode())


def region_surfaces(motion: Motion, light: bool = False) -> dict[str, CarriedSurface]:
    """The whole body's tissue regions' closed surfaces, carried through the motion as its tissue moves
    (`dynamics.carried_surfaces`); `light`: with fewer triangles, as the GLB has them."""
    dynamics = motion.dynamics
    return {s.name: s for s in (dynamics.light_region_surfaces if light else dynamics.region_surfaces)}


class MotionPictures:
    """The pictures of one motion, all from one live offscreen window, each frame at each size once.

    Frame k (`frame(k)`): the skeleton and the translucent region surfaces
    (the paper's Fig. 3(b)); `elastic()`: the body's skin at the frame of
    its largest elastic displacement, coloured by it in mm on a scale that
    ends at that largest value (the figure the run's summary prints). Every
    picture is titled with `title` and its time; all share one framing (the
    box of the whole motion). `size` is per view; a frame asked for again
    at the same size is not rendered again. (A GIF frame is rendered at
    the GIF's size without supersampling, not scaled down from a
    snapshot's: software OpenGL's cost goes with the pixels, so that is
    cheaper than sharing the few frames that coincide.) Close it (or use `with`).
    """

    def __init__(self, motion: Motion, views, size, title: str = "") -> None:
        from hitogata.render import Renderer

        self.motion, self.views, self.size, self.title = motion, tuple(views), tuple(size), title
        self.surfaces = region_surfaces(motion)
        self.bounds = motion_bounds(motion)
        self._renderer = Renderer()
        self._frames: dict[tuple[int, tuple[int, int], int], np.ndarray] = {}

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *_: object) -> None:
        self.close()

    def close(self) -> None:
        self._renderer.close()

    def _caption(self, k: int) -> str:
        time = f"t = {self.motion.times[k]:.2f} s"
        return f"{self.title}, {time}" if self.title else time

    def _render(self, items: list, k: int, size: tuple[int, int], supersample: int = SUPERSAMPLE) -> np.ndarray:
        from hitogata.render import side_by_side, titled
        from hitogata.render.images import TITLE_PIXELS

        views = self._renderer.render(items, views=self.views, size=(size[0], size[1] - TITLE_PIXELS),
                                      supersample=supersample)
        return titled(side_by_side(views), self._caption(k))

    def _skeleton(self, k: int) -> list:
        from hitogata.render import Lines, Points

        pose = self.motion.dynamics.poser.kinematics.pose(self.motion.angles[k])
        bones = np.stack([pose.joints[0], pose.tails[0]], axis=1)
        return [Lines(bones, color="#4a4a4a", radius=0.005), Points(pose.joints[0], color="#8e2f25", radius=0.008),
                Points(self.bounds, color="white", size=1.0, opacity=0.0)]  # fixes the framing over frames

    def frame(self, k: int, size: tuple[int, int] | None = None, supersample: int = SUPERSAMPLE) -> np.ndarray:
        """(H, W, 3) RGB: frame k's views side by side, region surfaces translucent, skeleton inside;
        `size` per view (default: the pictures'), `supersample` as in `render.Renderer.render`."""
        size = self.size if size is None else (size[0], size[1])  # a list given becomes a key
        if (k, size, supersample) not in self._frames:
            from hitogata.render import Layer

            items = self._skeleton(k)
            for name in ("bone", "viscera", "muscle", "skin"):
                if name in self.surfaces:
                    color, opacity = REGION_STYLE[name]
                    surface = self.surfaces[name]
                    items.append(Layer(surface.frame(self.motion, k), surface.faces, color=color, opacity=opacity))
            self._frames[k, size, supersample] = self._render(items, k, size, supersample)
        return self._frames[k, size, supersample]

    def elastic(self) -> np.ndarray:
        """(H, W, 3) RGB: the skin coloured by its elastic displacement (mm) at the frame of its largest."""
        from hitogata.render import Layer

        motion = self.motion
        mm = np.linalg.norm(motion.skin - motion.skinned_skin, axis=2) * 1e3  # (F, V), as the summary's
        k = int(np.argmax(mm.max(axis=1)))
        top = float(mm[k].max())
        body = motion.dynamics.poser.body
        items = self._skeleton(k) + [Layer(motion.skin[k].astype(np.float64), body.faces, scalars=mm[k].astype(float),
                                           colormap="viridis", clim=(0.0, max(top, 1e-3)), opacity=1.0,
                                           scalar_title="elastic displacement (mm)")]
        return self._render(items, k, self.size)


def motion_bounds(motion: Motion) -> np.ndarray:
    """(2, 3) corners of the box holding the nodes, the skin and the joints over all frames."""
    joints = motion.dynamics.poser.kinematics.pose(motion.angles).joints
    pts = np.concatenate([motion.nodes.reshape(-1, 3), motion.skin.reshape(-1, 3), joints.reshape(-1, 3)])
    return np.stack([pts.min(axis=0), pts.max(axis=0)]).astype(np.float64)


def nearest_frame(motion: Motion, t: float) -> int:
    """Index of the output frame nearest time t."""
    return int(np.argmin(np.abs(motion.times - t)))


def write_pictures(folder: str | os.PathLike, motion: Motion, times, views, size, name: str = "motion",
                   title: str = "", pictures: MotionPictures | None = None) -> list[Path]:
    """PNG of the views at the frames nearest each time (`<name>_<t>s.png`), and of the frame of
    largest elastic skin displacement with the skin coloured by it (`<name>_elastic.png`).

    pictures: a `MotionPictures` of this motion at `size` to render with (and to share frames with
    the GIF); by default one of its own, titled `title`."""
    from hitogata.render import save_png

    own = pictures is None
    if pictures is None:
        pictures = MotionPictures(motion, views, size, title)
    try:
        out = []
        for t in times:
            k = nearest_frame(motion, t)
            out.append(save_png(Path(folder) / f"{name}_{motion.times[k]:.2f}s.png", pictures.frame(k)))
        out.append(save_png(Path(folder) / f"{name}_elastic.png", pictures.elastic()))
        return out
    finally:
        if own:
            pictures.close()


def write_gif(path: str | os.PathLike, motion: Motion, views, size, rate: float, progress=None, title: str = "",
              pictures: MotionPictures | None = None) -> Path:
    """An animated GIF of the views at `rate` frames per second (looping), each frame `size` per view.

    pictures: a `MotionPictures` of this motion to render with (its window reused); by default its own."""
    from PIL import Image

    own = pictures is None
    if pictures is None:
        pictures = MotionPictures(motion, views, size, title)
    span = motion.times[-1] - motion.times[0]
    count = max(2, round(span * rate) + 1)
    picks = np.unique([nearest_frame(motion, t) for t in np.linspace(motion.times[0], motion.times[-1], count)])
    images = []
    try:
        for i, k in enumerate(picks):
            images.append(Image.fromarray(pictures.frame(int(k), size, GIF_SUPERSAMPLE)))
            if progress is not None:
                progress(i + 1, len(picks))
    finally:
        if own:
            pictures.close()
    buffer = io.BytesIO()
    step = 1000.0 * span / max(len(picks) - 1, 1)
    images[0].save(buffer, format="GIF", save_all=True, append_images=images[1:], duration=round(step), loop=0)
    return write_bytes_atomically(path, buffer.getvalue())


SEQUENCE_SUFFIX = "_sequence.npz"


def write_sequence(path: str | os.PathLike, motion: Motion) -> Path:
    """The motion as plain arrays: what `hitogata measure` and the viewer's player read.

    `times` (F,) s, `vertices` (F, V, 3) float32 skin, `angles` (F, D) rest-relative
    radians, `joints` (F, B, 3) the rig's joint centres, and `shape` (the body's shape
    parameters as JSON) with `density` — and a fitted body's per-vertex detail (`DETAIL_KEY`,
    integers of 0.01 mm) — so the body can be rebuilt exactly.
    """
    poser = motion.dynamics.poser
    body = poser.body
    joints = motion.rig_joints
    # named arrays in one dict: numpy's stubs type **kwargs against savez's own keyword (allow_pickle)
    arrays: dict[str, Any] = {
        "times": motion.times, "vertices": motion.skin.astype(np.float32), "angles": motion.angles,
        "joints": joints, "shape": np.array(json.dumps(shape_extras(body.params))), "density": np.array(body.density),
        **{k: np.asarray(v, dtype=np.int32) for k, v in detail_extras(body).items()},
    }
    buffer = io.BytesIO()
    np.savez_compressed(buffer, **arrays)
    return write_bytes_atomically(path, buffer.getvalue())


def find_sequence(folder: Path) -> Path:
    """The one motion sequence a results folder holds (`sequence.npz` or `<name>_sequence.npz`)."""
    found = sorted(folder.glob("sequence.npz")) or sorted(folder.glob(f"*{SEQUENCE_SUFFIX}"))
    if len(found) != 1:
        names = ", ".join(p.name for p in found) or "none"
        raise HitogataError(
            f"{folder}: a results folder holds one *{SEQUENCE_SUFFIX}; found {names} (name the file instead)"
        )
    return found[0]


def read_sequence_body(path: Path) -> tuple[Body, dict[str, np.ndarray]]:
    """The body a sequence file was simulated on, and its arrays (times, vertices, angles, joints)."""
    arrays = read_npz(path)
    missing = [k for k in ("times", "vertices", "joints", "shape") if k not in arrays]
    if missing:
        raise HitogataError(f"{path}: no array {missing[0]!r}; allowed a sequence written by `hitogata simulate`")
    times, vertices = arrays["times"], arrays["vertices"]
    if times.ndim != 1 or len(times) == 0 or times.dtype.kind not in "iuf" or not np.isfinite(times).all():
        raise HitogataError(f"{path}: 'times' of shape {times.shape}: allowed one or more finite times (s)")
    if vertices.shape[:1] != times.shape or vertices.ndim != 3 or vertices.shape[2] != 3:
        raise HitogataError(f"{path}: 'vertices' of shape {vertices.shape}: allowed ({len(times)}, V, 3)")
    try:
        shape = json.loads(str(arrays.pop("shape")))
    except ValueError:
        raise HitogataError(f"{path}: 'shape': not JSON; allowed a sequence written by `hitogata simulate`") from None
    density = arrays.pop("density", np.array(WHOLE_BODY_DENSITY))
    extras = {"shape": shape, "density": density.item() if density.ndim == 0 else density.tolist()}
    if DETAIL_KEY in arrays:
        extras[DETAIL_KEY] = arrays.pop(DETAIL_KEY).tolist()
    return body_from_extras(path, extras), arrays
