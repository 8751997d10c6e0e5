"""Uniform refinement (for convergence studies): same solid, same labels, P1 on it = P2's nodes."""

import numpy as np

from hitogata.elastic.refine import refine
from hitogata.fem import check_mesh, lift_node_set, p2_mesh, tet_geometry
from hitogata.fem.verify import box_mesh
from hitogata.volume.quality import dihedral_angles


def test_refine_keeps_volume_labels_and_node_sets():
    points, tets = box_mesh((0.3, 0.2, 0.1), (3, 2, 2))
    labels = np.arange(len(tets)) % 3
    fixed = np.flatnonzero(points[:, 0] < 1e-9)
    fine_points, fine, fine_labels, fine_fixed = refine(points, tets, labels, fixed)
    check_mesh(fine_points, fine)  # all positively oriented
    _, coarse_vol = tet_geometry(points, tets)
    _, fine_vol = tet_geometry(fine_points, fine)
    assert len(fine) == 8 * len(tets)
    assert np.allclose(fine_vol.reshape(-1, 8).sum(axis=1), coarse_vol)  # children tile their parent
    assert np.array_equal(fine_labels, np.repeat(labels, 8))
    points2, tets2 = p2_mesh(points, tets)
    assert np.array_equal(fine_points, points2)  # the refined nodes are the P2 nodes
    assert np.array_equal(fine_fixed, lift_node_set(tets2, fixed))
    assert np.all(np.abs(fine_points[fine_fixed, 0]) < 1e-12)  # the face stays the face
    # the shortest-diagonal split keeps the children well shaped
    assert np.degrees(dihedral_angles(fine_points, fine)).min() > 0.5 * np.degrees(dihedral_angles(points, tets)).min()
