"""Files of an elastic model: frequencies (CSV), the mesh with mode shapes (VTU), mode pictures (PNG).

The VTU file holds quadratic `tetra10` cells for P2 models (VTK's node order
equals ours: corners, then edges 01, 12, 02, 03, 13, 23), `tetra` for P1;
ParaView draws the quadratic cells curved-capable and interpolates mode
shapes quadratically. All writes are atomic.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import io
import os
from pathlib import Path

import meshio
import numpy as np
from matplotlib.figure import Figure

from hitogata.elastic.model import ElasticModel
from hitogata.export.atomic import write_bytes_atomically
from hitogata.export.tissue_data import tissue_cell_data, tissue_field_data
from hitogata.export.vtu import write_vtu as write_mesh_vtu
from hitogata.render import Layer, render_views

if TYPE_CHECKING:
    from hitogata.body.model import Body

PICTURE_AMPLITUDE = 0.03  # m: the largest skin displacement drawn in a mode picture


def frequency_table(model: ElasticModel) -> str:
    """CSV text: mode number, frequency (Hz), eigenvalue ((rad/s)^2), damping ratio."""
    lines = ["mode,frequency_hz,eigenvalue_rad2_s2,damping_ratio"]
    for k, (f, lam, zeta) in enumerate(zip(model.frequencies, model.modes.eigenvalues, model.damping_ratios), 1):
        lines.append(f"{k},{f:.6f},{lam:.6e},{zeta:.4f}")
    return "\n".join(lines) + "\n"


def write_frequencies(path: str | os.PathLike, model: ElasticModel) -> Path:
    """Write the frequency table (see `frequency_table`)."""
    return write_bytes_atomically(path, frequency_table(model).encode())


def vtu_mesh(model: ElasticModel, n_shapes: int | None = None) -> meshio.Mesh:
    """The FE mesh with its tissue (cell data: `tissue_data.tissue_cell_data`, and the element means
    of the sampled tissue: youngs_modulus in Pa, density in kg/m³) and the first mode shapes (point data).

    Point data: `mode_01`... (N, 3) shapes scaled so that each one's largest
    displacement is `PICTURE_AMPLITUDE` (3 cm: ParaView's Warp By Vector at its
    default scale factor 1 shows a visible, not exploded, shape), `fixed` (1
    on nodes that follow the skeleton), `bone` (the rig bone they follow, -1).
    """
    n_shapes = model.modes.vectors.shape[1] if n_shapes is None else min(n_shapes, model.modes.vectors.shape[1])
    cell_type = "tetra10" if model.elements.shape[1] == 10 else "tetra"
    n = len(model.points)
    fixed = np.zeros(n, dtype=np.int8)
    fixed[model.fixed_nodes] = 1
    bone = np.full(n, -1, dtype=np.int32)
    bone[model.fixed_nodes] = model.fixed_bone
    point_data = {"fixed": fixed, "bone": bone}
    for k in range(n_shapes):
        point_data[f"mode_{k + 1:02d}"] = model.modes.vectors[:, k].reshape(n, 3) * mode_scales(model)[k]
    cell_data = {**tissue_cell_data(model), "youngs_modulus": [model.E], "density": [model.rho]}
    return meshio.Mesh(model.points, [(cell_type, model.elements)], point_data=point_data, cell_data=cell_data)


def mode_scales(model: ElasticModel) -> np.ndarray:
    """(M,) the factor from each mass-normalised mode shape to one whose largest node displacement is 3 cm."""
    n = len(model.points)
    largest = np.linalg.norm(model.modes.vectors.T.reshape(-1, n, 3), axis=2).max(axis=1)
    return PICTURE_AMPLITUDE / np.maximum(largest, 1e-300)


def vtu_field_data(model: ElasticModel) -> dict[str, np.ndarray]:
    """What the VTU says about itself: frequencies, the mode scaling and warp hint, the tissue
    (`tissue_data.tissue_field_data`: sample points, materials, the label names)."""
    return {
        "frequencies_hz": np.asarray(model.frequencies, dtype=float),
        "mode_largest_displacement_m": np.array([PICTURE_AMPLITUDE]),
        "mode_to_mass_normalised": 1.0 / mode_scales(model),  # multiply a mode_NN by this: mass-normalised
        "warp_scale_factor": np.array([1.0]),  # Warp By Vector on mode_NN at 1: its largest displacement is 3 cm
        **tissue_field_data(model),
    }


def write_vtu(path: str | os.PathLike, model: ElasticModel, n_shapes: int | None = None) -> Path:
    """Write the model as a VTU file for ParaView (see `vtu_mesh`, `vtu_field_data`)."""
    return write_mesh_vtu(path, vtu_mesh(model, n_shapes), vtu_field_data(model))


def mode_picture(model: ElasticModel, body: Body, mode: int, size: tuple[int, int] = (360, 540)) -> bytes:
    """PNG of one mode on the body's skin, front and side, coloured by displacement.

    The shape is scaled so that its largest skin displacement is `PICTURE_AMPLITUDE`.
    """
    u = model.skin_displacement(model.modes.vectors[:, mode])
    magnitude = np.linalg.norm(u, axis=1)
    scale = PICTURE_AMPLITUDE / max(float(magnitude.max()), 1e-300)
    skin = Layer(body.vertices + scale * u, body.faces, scalars=scale * magnitude * 1e3, colormap="viridis",
                 clim=(0.0, PICTURE_AMPLITUDE * 1e3), scalar_title="mm")
    figure = Figure(figsize=(2 * size[0] / 100, size[1] / 100 + 0.4), dpi=100)
    for k, image in enumerate(render_views([skin], views=("front", "side"), size=size)):
        axes = figure.add_subplot(1, 2, k + 1)
        axes.imshow(image)
        axes.set_axis_off()
    figure.suptitle(f"mode {mode + 1}: {model.frequencies[mode]:.2f} Hz")
    figure.tight_layout()
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png")
    return buffer.getvalue()


def write_mode_pictures(folder: str | os.PathLike, model: ElasticModel, body: Body, count: int) -> list[Path]:
    """`mode_01.png`... for the first `count` modes (see `mode_picture`)."""
    folder = Path(folder)
    return [write_bytes_atomically(folder / f"mode_{k + 1:02d}.png", mode_picture(model, body, k))
            for k in range(min(count, model.modes.vectors.shape[1]))]
