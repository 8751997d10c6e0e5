"""The tissue inside each element as VTU arrays, so a reader rebuilds the model's materials from the file.

The elastic model does not give an element one tissue: it takes the tissue
at `fem.elements.MATERIAL_SAMPLES` points inside it (27 for the default
rule) and integrates E, ν and ρ there. The VTU files (`hitogata modes`'
`model.vtu`, `simulate`'s frames) carry what that takes:

- cell data `region_samples` (T, Q) and `muscle_samples` (T, Q): the label
  at each sample point (−1: no named muscle), one component per point;
  `fraction_<region>` (T,): each region's share of the element's volume;
  `region` and `muscle`: the label at the centroid (for colouring);
- field data `sample_barycentric` (Q, 4) and `sample_weights` (Q, summing
  to 1): where the points are and what share of the volume each stands
  for; `material_youngs_modulus_pa`, `material_poissons_ratio` and
  `material_density_kg_m3` (R,): each region's material, by label; and the
  names behind the labels (`region 2: muscle` = [2]).

So an element's modulus is `sample_weights @ material_youngs_modulus_pa[region_samples]`
(the model's `E`), and likewise ν and ρ.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from hitogata.export.vtu import label_arrays
from hitogata.fem.elements import MATERIAL_SAMPLES

if TYPE_CHECKING:
    from hitogata.elastic.model import ElasticModel


def tissue_cell_data(model: ElasticModel) -> dict[str, list[np.ndarray]]:
    """meshio cell data: centroid labels, per-sample labels, each region's volume fraction."""
    volume = model.volume
    fractions = volume.region_fractions
    return {
        "region": [model.region.astype(np.int32)],
        "muscle": [volume.muscle.astype(np.int32)],
        "region_samples": [volume.region_samples.astype(np.int8)],
        "muscle_samples": [volume.muscle_samples.astype(np.int16)],
        **{f"fraction_{name}": [fractions[:, k]] for k, name in enumerate(model.region_names)},
    }


def tissue_field_data(model: ElasticModel) -> dict[str, np.ndarray]:
    """Field data: the sample points and weights, each region's material, the names behind the labels."""
    points, weights = MATERIAL_SAMPLES
    table = model.materials.table(model.region_names)
    materials = [table[k] for k in range(len(model.region_names))]
    return {
        "sample_barycentric": points,
        "sample_weights": weights,
        "material_youngs_modulus_pa": np.array([m.E for m in materials]),
        "material_poissons_ratio": np.array([m.nu for m in materials]),
        "material_density_kg_m3": np.array([m.rho for m in materials]),
        **label_arrays("region", model.region_names),
        **label_arrays("muscle", model.muscle_names),
    }
