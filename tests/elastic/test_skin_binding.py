"""The skin's binding to the elastic body: only tissue that exists, is face-connected and moves with the vertex."""

import numpy as np
import pytest

from hitogata.elastic.mapping import body_piece, face_pieces, skin_vertex_map
from hitogata.fem.verify.box_mesh import box_mesh


def two_legs():
    """Two 0.1 m legs joined at the top, 2 cm of air between them below y = 0.1 m (one piece)."""
    points, tets = box_mesh((0.22, 0.2, 0.1), (11, 10, 5))
    c = points[tets].mean(axis=1)
    return points, tets[~((c[:, 0] > 0.1) & (c[:, 0] < 0.12) & (c[:, 1] < 0.1))]


def test_pieces_join_through_faces_only():
    points, tets = box_mesh((0.1, 0.1, 0.1), (2, 2, 2))
    # a tet hanging on by one edge of the block (it shares two nodes, no face)
    edge = tets[0][:2]
    extra = np.array([[edge[0], edge[1], len(points), len(points) + 1]])
    pts = np.concatenate([points, points[edge].mean(axis=0) + [[-0.03, 0.0, 0.01], [-0.03, 0.02, -0.01]]])
    all_tets = np.concatenate([tets, extra])
    piece = face_pieces(all_tets)
    assert len(np.unique(piece)) == 2 and piece[-1] != piece[0]
    assert body_piece(all_tets).sum() == len(tets)
    # a vertex inside the hanging tet is bound to the block (its closest point there), never to the tet
    inside = pts[extra[0]].mean(axis=0)
    W = skin_vertex_map(inside[None], pts, all_tets, reach=0.05)
    used = W.indices
    assert W.sum() == pytest.approx(1.0) and not np.isin(used, extra[0][2:]).any()


def test_far_vertices_fade_and_rows_reproduce_a_translation():
    points, tets = box_mesh((0.1, 0.1, 0.1), (2, 2, 2))
    vertices = np.array([[0.05, 0.05, 0.05], [0.05, 0.05, 0.105], [0.05, 0.05, 0.1 + 0.005 + 0.025],
                         [0.05, 0.05, 0.5]])
    W = skin_vertex_map(vertices, points, tets, reach=0.005, fade=0.05)
    rows = np.asarray(W.sum(axis=1)).ravel()
    assert rows[0] == pytest.approx(1.0) and rows[1] == pytest.approx(1.0)  # inside, and within reach
    assert rows[2] == pytest.approx(0.5)  # halfway through the fade
    assert rows[3] == 0.0  # out of reach: skinning alone
    shift = np.array([0.01, -0.02, 0.03])
    assert np.allclose(W @ np.tile(shift, (len(points), 1)), rows[:, None] * shift)


def test_a_vertex_binds_to_tissue_of_its_own_part_not_across_a_gap():
    points, tets = two_legs()
    parts = np.zeros((len(points), 2))
    parts[points[:, 0] < 0.11, 0] = 1.0  # leg A: part 0
    parts[points[:, 0] >= 0.11, 1] = 1.0  # leg B: part 1
    # a skin vertex of part 0 in the gap, nearer leg B (3 mm) than leg A (17 mm)
    vertex = np.array([[0.117, 0.05, 0.05]])
    own = np.array([[1.0, 0.0]])
    geometric = skin_vertex_map(vertex, points, tets, reach=0.02)
    aware = skin_vertex_map(vertex, points, tets, reach=0.02, vertex_weights=own, node_weights=parts)
    assert set(geometric.indices) <= set(np.flatnonzero(parts[:, 1]))  # the nearest tissue is the other limb's
    assert set(aware.indices) <= set(np.flatnonzero(parts[:, 0]))  # its own limb's, at 17 mm: within reach
    assert aware.sum() == pytest.approx(1.0)
    # a vertex of neither part binds to nothing
    stranger = skin_vertex_map(vertex, points, tets, reach=0.02, vertex_weights=np.array([[0.1, 0.1]]),
                               node_weights=parts)
    assert stranger.nnz == 0
