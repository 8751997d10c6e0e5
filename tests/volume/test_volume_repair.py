"""The repair of a stuffed mesh: held pinch points split, other pinches and unheld pieces removed."""

import numpy as np

from hitogata.volume.integrity import hold_width, mesh_integrity
from hitogata.volume.lattice import TetMesh
from hitogata.volume.repair import repair

H = 0.04  # m: an element of the default size


def _mesh(nodes, tets, held) -> TetMesh:
    part = np.full(len(nodes), -1)
    part[held] = 1
    return TetMesh(nodes=np.asarray(nodes, dtype=float) * H, tets=np.asarray(tets), node_part=part)


def test_held_pinch_vertex_is_split_and_both_pieces_stay():
    # Two tets meeting at node 0 only; node 0 and two more of each tet are held.
    nodes = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [-1, 0, 0], [0, -1, 0], [0, 0, -1]]
    mesh = _mesh(nodes, [[0, 1, 2, 3], [0, 4, 6, 5]], [0, 1, 2, 4, 5])
    fixed, report = repair(mesh, np.flatnonzero(mesh.node_part == 1))
    assert (report.split, report.pinched, report.unheld) == (1, 0, 0)
    assert len(fixed.tets) == 2 and len(fixed.nodes) == 8  # node 0 copied
    assert np.allclose(fixed.nodes[fixed.tets[0, 0]], fixed.nodes[fixed.tets[1, 0]])
    m = mesh_integrity(fixed.nodes, fixed.tets, np.flatnonzero(fixed.node_part == 1))
    assert m.ok and m.n_pieces == 2 and m.pinched_vertices == 0


def test_free_pinch_edge_keeps_one_side_and_unheld_pieces_go():
    # Tets 0 and 1 share the free edge 0-1 only; tet 2 is glued to tet 0 by a face. Tet 1
    # is held on a line (nodes 4, 5 and node 0 do not span 10 mm off their line): it goes.
    nodes = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, -1, 0.5], [1.5, 0, -1], [1, 1, 1]]
    mesh = _mesh(nodes, [[0, 1, 2, 3], [0, 1, 4, 5], [1, 2, 3, 6]], [2, 3, 6])
    fixed, report = repair(mesh, np.flatnonzero(mesh.node_part == 1))
    assert report.pinched + report.unheld == 1 and report.removed_volume > 0
    assert len(fixed.tets) == 2
    m = mesh_integrity(fixed.nodes, fixed.tets, np.flatnonzero(fixed.node_part == 1))
    assert m.ok and m.n_pieces == 1 and m.non_manifold_edges == 0


def test_hold_width_is_the_smallest_height_in_millimetres():
    assert hold_width(np.array([[0, 0, 0], [0.1, 0, 0]])) == 0.0  # two points: a line
    line = np.array([[0, 0, 0], [0.1, 0, 0], [0.05, 1e-4, 0]])
    assert np.isclose(hold_width(line), 1e-4)  # three nearly collinear nodes, 0.1 mm off: a hinge
    square = np.array([[0, 0, 0], [0.04, 0, 0], [0, 0.04, 0], [0.04, 0.04, 0]])
    assert np.isclose(hold_width(square), 0.04 / np.sqrt(2))
