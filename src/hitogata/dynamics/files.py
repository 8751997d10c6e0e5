"""What a simulated motion is written as: GLB animation, VTU series, pictures, GIF, summary.

- GLB: the skin surface and the tissue regions' boundary surfaces, each with
  one morph target per frame, and an animation of the morph weights (one-hot,
  linear in between), so three.js and Blender play it as a shape-key
  animation; checked by the Khronos validator in the tests.
- VTU + PVD: the FE mesh per frame (quadratic tets as VTK's tetra10) with
  displacement, elastic displacement and region, a time series for ParaView.
- PNG: front and side views of the region boundary surfaces, translucent,
  with the skeleton inside (the paper's Fig. 3(b)), at chosen times.
- GIF: the same views over time (pillow).
Every file is written whole or not at all.
"""

from __future__ import annotations

import io
import json
import os
import zipfile
from pathlib import Path
from xml.sax.saxutils import quoteattr

import meshio
import numpy as np
import pygltflib as gl

from hitogata.dynamics.motion import Motion
from hitogata.export.atomic import write_bytes_atomically
from hitogata.body import Body
from hitogata.errors import HitogataError
from hitogata.export.body_files import body_from_extras, shape_extras
from hitogata.export.gltf import GlbBuilder, add_material, named_node, vertex_normals
from hitogata.export.vtu import label_arrays, write_vtu
from hitogata.geometry.shells import region_boundary, taubin_smooth

SMOOTHING = 4  # Taubin steps on the pictures' region surfaces
SKIN_OPACITY = 0.35  # the skin over the regions in the motion GLB: see-through, so the tissue shows
MAX_TARGETS = 120  # morph targets in a GLB: frames beyond are subsampled evenly
REGION_STYLE = {  # colour, opacity: translucent nested surfaces as in the paper's figure
    "skin": ("#e3b899", 0.22),
    "muscle": ("#b5473a", 0.30),
    "viscera": ("#d9a52b", 0.45),
    "bone": ("#efe9dc", 0.95),
}


def frame_subset(n_frames: int, most: int) -> np.ndarray:
    """Indices of at most `most` frames spread evenly, first and last included."""
    return np.unique(np.round(np.linspace(0, n_frames - 1, min(n_frames, most))).astype(int))


def write_motion_glb(path: str | os.PathLike, motion: Motion) -> Path:
    """The skin and the tissue regions' boundary surfaces as one morph-target animation.

    Each surface is a mesh with one morph target per frame (frames subsampled
    to `MAX_TARGETS`); one set of one-hot weight keys drives them all. The
    skin is the whole body's, translucent (material "skin"); the regions (the
    elastic model's corner mesh, nodes and materials "region_<name>") are
    translucent in the colours of the pictures, nested inside it. Each mesh
    has smooth vertex normals at rest; node names are safe for three.js.
    """
    pick = frame_subset(len(motion.times), MAX_TARGETS)
    body = motion.dynamics.poser.body
    builder = GlbBuilder()
    names = [f"t={motion.times[k]:.3f}s" for k in pick]
    skin = add_material(builder, "skin", (*_rgb(REGION_STYLE["skin"][0]), SKIN_OPACITY))
    nodes = [_add_morphing_mesh(builder, "skin", body.faces, body.vertices, motion.skin[pick], names, skin)]
    points = motion.dynamics.model.points
    for name, faces in region_surfaces(motion).items():
        used, local = np.unique(faces, return_inverse=True)
        colour, opacity = REGION_STYLE[name]
        material = add_material(builder, f"region_{name}", (*_rgb(colour), opacity))
        nodes.append(_add_morphing_mesh(builder, f"region_{name}", local.reshape(faces.shape), points[used],
                                        motion.nodes[np.ix_(pick, used)], names, material=material))
    times = builder.add_accessor(motion.times[pick].astype(np.float32), gl.SCALAR, with_bounds=True)
    weights = builder.add_accessor(np.eye(len(pick), dtype=np.float32).reshape(-1), gl.SCALAR)
    builder.gltf.animations.append(gl.Animation(
        name="motion",
        samplers=[gl.AnimationSampler(input=times, output=weights, interpolation="LINEAR")],
        channels=[gl.AnimationChannel(sampler=0, target=gl.AnimationChannelTarget(node=node, path="weights"))
                  for node in nodes],
    ))
    return write_bytes_atomically(path, builder.to_bytes())


def _rgb(colour: str) -> tuple[float, float, float]:
    return tuple(int(colour[i:i + 2], 16) / 255.0 for i in (1, 3, 5))  # type: ignore[return-value]


def _add_morphing_mesh(builder: GlbBuilder, name: str, faces: np.ndarray, rest: np.ndarray, frames: np.ndarray,
                       target_names: list[str], material: int | None = None) -> int:
    """A root node with a mesh of `faces` at `rest` (V, 3), its rest normals, and a morph target per frame."""
    normals = vertex_normals(rest.astype(np.float64), np.asarray(faces, dtype=np.int64)).astype(np.float32)
    rest = rest.astype(np.float32)
    position = builder.add_accessor(rest, gl.VEC3, target=gl.ARRAY_BUFFER, with_bounds=True)
    normal = builder.add_accessor(normals, gl.VEC3, target=gl.ARRAY_BUFFER)
    indices = builder.add_accessor(np.asarray(faces, dtype=np.uint32).reshape(-1), gl.SCALAR,
                                   target=gl.ELEMENT_ARRAY_BUFFER)
    targets = [{"POSITION": builder.add_accessor((frame - rest).astype(np.float32), gl.VEC3,
                                                 target=gl.ARRAY_BUFFER, with_bounds=True)} for frame in frames]
    primitive = gl.Primitive(attributes=gl.Attributes(POSITION=position, NORMAL=normal), indices=indices,
                             targets=targets,
                             material=material)
    builder.gltf.meshes.append(gl.Mesh(name=name, primitives=[primitive], weights=[0.0] * len(frames),
                                       extras={"targetNames": target_names}))
    return builder.add_node(named_node(name, mesh=len(builder.gltf.meshes) - 1), root=True)


def write_pvd(folder: str | os.PathLike, motion: Motion, name: str = "motion") -> Path:
    """`name.pvd` and `name/frame_NNNN.vtu` in folder: the FE body at every frame."""
    folder = Path(folder)
    frames = folder / name
    frames.mkdir(parents=True, exist_ok=True)
    model = motion.dynamics.model
    cell = "tetra10" if model.elements.shape[1] == 10 else "tetra"
    skinned = motion.nodes - motion.elastic
    entries = []
    for k, t in enumerate(motion.times):
        mesh = meshio.Mesh(
            motion.nodes[k].astype(np.float64), [(cell, model.elements)],
            point_data={"displacement": (motion.nodes[k] - model.points).astype(np.float64),
                        "elastic": motion.elastic[k].astype(np.float64),
                        "skinned": skinned[k].astype(np.float64)},
            cell_data={"region": [model.region.astype(np.int32)]},
        )
        file = frames / f"frame_{k:04d}.vtu"
        write_vtu(file, mesh, {"time_s": np.array([t]), **label_arrays("region", model.region_names)})
        entries.append(f'    <DataSet timestep="{t:.6f}" part="0" file={quoteattr(f"{name}/{file.name}")}/>')
    xml = ('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n'
           + "\n".join(entries) + "\n  </Collection>\n</VTKFile>\n")
    return write_bytes_atomically(folder / f"{name}.pvd", xml.encode())


def region_surfaces(motion: Motion) -> dict[str, np.ndarray]:
    """Outward boundary triangles (F, 3) of each tissue region's corner tets; for bones held outside
    the mesh, the soft tissue's boundary on them."""
    model = motion.dynamics.model
    surfaces = {name: region_boundary(model.elements, model.region, model.region_names, [name],
                                      model.volume.bone_surface) for name in model.region_names}
    return {name: faces for name, faces in surfaces.items() if len(faces)}


def frame_items(motion: Motion, k: int, surfaces: dict[str, np.ndarray], bounds: np.ndarray,
                colour_by_elastic: bool = False) -> list:
    """Render items of frame k: the skeleton, translucent region surfaces (or the skin coloured by the
    elastic displacement in mm), and invisible bounds that fix the framing over frames."""
    from hitogata.render import Layer, Lines, Points

    pose = motion.dynamics.poser.kinematics.pose(motion.angles[k])
    bones = np.stack([pose.joints[0], pose.tails[0]], axis=1)
    items = [Lines(bones, color="#4a4a4a", radius=0.005), Points(pose.joints[0], color="#8e2f25", radius=0.008)]
    nodes = motion.nodes[k].astype(np.float64)
    if colour_by_elastic:
        model = motion.dynamics.model
        outer = model.volume.boundary_faces[model.volume.boundary_on_skin]
        mm = np.linalg.norm(motion.elastic[k], axis=1).astype(np.float64) * 1e3
        top = float(np.linalg.norm(motion.elastic, axis=2).max() * 1e3)
        items.append(Layer(nodes, outer, scalars=mm, colormap="viridis", clim=(0.0, max(top, 1e-3)),
                           scalar_title="elastic displacement (mm)", opacity=1.0))
    else:
        for name in ("bone", "viscera", "muscle", "skin"):
            if name in surfaces:
                color, opacity = REGION_STYLE[name]
                items.append(Layer(taubin_smooth(nodes, surfaces[name], SMOOTHING), surfaces[name], color=color, opacity=opacity))
    items.append(Points(bounds, color="white", size=1.0, opacity=0.0))
    return items


def motion_bounds(motion: Motion) -> np.ndarray:
    """(2, 3) corners of the box holding the nodes and joints over all frames."""
    joints = motion.dynamics.poser.kinematics.pose(motion.angles).joints
    pts = np.concatenate([motion.nodes.reshape(-1, 3), joints.reshape(-1, 3)])
    return np.stack([pts.min(axis=0), pts.max(axis=0)]).astype(np.float64)


def render_frame(motion: Motion, k: int, views, size, surfaces=None, bounds=None,
                 colour_by_elastic: bool = False) -> np.ndarray:
    """One RGB image (H, W, 3): the views of frame k side by side."""
    from hitogata.render import render_views, side_by_side

    surfaces = region_surfaces(motion) if surfaces is None else surfaces
    bounds = motion_bounds(motion) if bounds is None else bounds
    items = frame_items(motion, k, surfaces, bounds, colour_by_elastic)
    return side_by_side(render_views(items, views=views, size=size))


def write_pictures(folder: str | os.PathLike, motion: Motion, times, views, size, name: str = "motion") -> list[Path]:
    """PNG of the views at the frames nearest each time (`<name>_<t>s.png`), and of the frame of
    largest elastic motion with the skin coloured by it (`<name>_elastic.png`)."""
    from hitogata.render import save_png

    surfaces, bounds = region_surfaces(motion), motion_bounds(motion)
    out = []
    for t in times:
        k = int(np.argmin(np.abs(motion.times - t)))
        out.append(save_png(Path(folder) / f"{name}_{motion.times[k]:.2f}s.png",
                            render_frame(motion, k, views, size, surfaces, bounds)))
    peak = int(np.argmax(np.linalg.norm(motion.elastic, axis=2).max(axis=1)))
    out.append(save_png(Path(folder) / f"{name}_elastic.png",
                        render_frame(motion, peak, views, size, surfaces, bounds, colour_by_elastic=True)))
    return out


def write_gif(path: str | os.PathLike, motion: Motion, views, size, rate: float, progress=None) -> Path:
    """An animated GIF of the views at `rate` frames per second (looping)."""
    from PIL import Image

    surfaces, bounds = region_surfaces(motion), motion_bounds(motion)
    span = motion.times[-1] - motion.times[0]
    count = max(2, int(round(span * rate)) + 1)
    wanted = np.linspace(motion.times[0], motion.times[-1], count)
    picks = np.unique([int(np.argmin(np.abs(motion.times - t))) for t in wanted])
    images = []
    for i, k in enumerate(picks):
        images.append(Image.fromarray(render_frame(motion, k, views, size, surfaces, bounds)))
        if progress is not None:
            progress(i + 1, len(picks))
    buffer = io.BytesIO()
    step = 1000.0 * span / max(len(picks) - 1, 1)
    images[0].save(buffer, format="GIF", save_all=True, append_images=images[1:], duration=int(round(step)), loop=0)
    return write_bytes_atomically(path, buffer.getvalue())


SEQUENCE_SUFFIX = "_sequence.npz"


def write_sequence(path: str | os.PathLike, motion: Motion) -> Path:
    """The motion as plain arrays: what `hitogata measure` and the viewer's player read.

    `times` (F,) s, `vertices` (F, V, 3) float32 skin, `angles` (F, D) rest-relative
    radians, `joints` (F, B, 3) the rig's joint centres, and `shape` (the body's shape
    parameters as JSON) with `density`, so the body can be rebuilt exactly.
    """
    poser = motion.dynamics.poser
    body = poser.body
    joints = motion.rig_joints
    buffer = io.BytesIO()
    np.savez_compressed(
        buffer, times=motion.times, vertices=motion.skin.astype(np.float32), angles=motion.angles,
        joints=joints, shape=np.array(json.dumps(shape_extras(body.params))), density=np.array(body.density),
    )
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
    try:
        with np.load(path, allow_pickle=False) as data:
            arrays = {k: data[k] for k in data.files}
    except (OSError, ValueError, zipfile.BadZipFile, EOFError) as exc:
        raise HitogataError(f"{path}: not a readable .npz file ({exc})") from None
    missing = [k for k in ("times", "vertices", "joints", "shape") if k not in arrays]
    if missing:
        raise HitogataError(f"{path}: no array {missing[0]!r}; allowed a sequence written by `hitogata simulate`")
    extras = {"shape": json.loads(str(arrays.pop("shape"))), "density": float(arrays.pop("density", 1000.0))}
    return body_from_extras(path, extras), arrays
