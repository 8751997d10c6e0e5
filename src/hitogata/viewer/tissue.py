"""Tissue-region surfaces of the volume model, carried along by the posed skeleton.

Drawn as the paper draws them: nested boundary surfaces, from the inside
out — bone, then everything up to the viscera, then everything up to the
muscle layer — each the outside of the union of the regions within it, so
each is one shell that semi-transparency can show without sorting artefacts
(a region's own inner shell would be drawn twice). Regions are labelled per
tetrahedron, so the shells are staircases of lattice faces; for display only
they are smoothed (Taubin's λ|μ filter, which does not shrink them); the
volume model is unchanged. The shells' nodes take the part weights of their
nearest skin vertex and are skinned like the skin, so they follow the pose
without re-meshing (the elastic correction is not drawn yet). The skin+fat
region's outside is the skin itself, which is drawn already.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from hitogata.geometry.shells import region_boundary, taubin_smooth
from hitogata.skeleton.kinematics import Pose
from hitogata.posing.skinning import Skin, prepare_skin, skin_vertices
from hitogata.volume import VolumeModel

SHOWN_REGIONS = ("bone", "viscera", "muscle")  # from the inside out
REGION_COLOURS = {"bone": (235, 225, 200), "viscera": (200, 110, 90), "muscle": (170, 45, 60)}
REGION_OPACITY = {"bone": 0.9, "viscera": 0.45, "muscle": 0.25}  # inner shells more opaque, to show through
SMOOTHING = 10  # Taubin λ|μ passes (`geometry.shells.taubin_smooth`)


@dataclass(frozen=True, eq=False)
class TissueSurface:
    """One shell, the outside of `region` and the regions within: rest vertices (n, 3) and outward faces (f, 3), prepared for skinning."""

    region: str
    faces: np.ndarray
    skin: Skin

    @property
    def rest(self) -> np.ndarray:
        return self.skin.rest

    def posed(self, pose: Pose) -> np.ndarray:
        """(n, 3) vertices in the pose (P = 1)."""
        return skin_vertices(self.skin, pose.rotations, pose.translations)[0]


def tissue_surfaces(model: VolumeModel, body_skin: Skin) -> tuple[TissueSurface, ...]:
    """The nested shells (bone, up to viscera, up to muscle), each node weighted like its nearest skin vertex.

    body_skin: the body's skin prepared for skinning (`Poser.skin`: rest surface and part weights).
    """
    nearest = cKDTree(body_skin.rest).query(model.nodes)[1]
    out = []
    for k, region in enumerate(SHOWN_REGIONS):
        # bones held outside the mesh: the soft tissue's faces on them are the bone shell
        faces = region_boundary(model.tets, model.region, model.region_names, SHOWN_REGIONS[: k + 1],
                                model.bone_surface)
        if not len(faces):
            continue
        used, compact = np.unique(faces, return_inverse=True)
        compact = compact.reshape(-1, 3)
        weights = body_skin.weights[nearest[used]]
        skin = prepare_skin(taubin_smooth(model.nodes[used], compact, SMOOTHING), weights, body_skin.parents)
        out.append(TissueSurface(region, compact, skin))
    return tuple(out)
