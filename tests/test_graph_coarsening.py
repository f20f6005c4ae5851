"""ActFormer critic's graph coarsening (:mod:`jaxmotion.nn.graph_coarsening`): the reference node sets,
the properties of one coarsening step, the hop-kernel normalisation on hand-worked graphs, bad input."""

from __future__ import annotations

import numpy as np
import pytest

from jaxmotion.geometry.skeletons import GTA22, NTU25, SMPL24
from jaxmotion.models.actformer_critic import CriticGraphs
from jaxmotion.nn.graph_coarsening import (
    coarse_adjacency,
    coarsen,
    critic_adjacency,
    graph_pyramid,
    hop_distances,
    hop_kernels,
    maximal_independent_sets,
    skeleton_adjacency,
)

SMPL25_PARENTS = SMPL24.parents + (0,)  # SMPL-24 plus the translation node under joint 0
PATH5 = skeleton_adjacency((-1, 0, 1, 2, 3))  # 0-1-2-3-4

# Joint indices (of the skeleton) kept after each coarsening, as FACTS 5 records them from the authors' code.
# GTA-22's sets (FACTS gives only the sizes 10 and 4) were checked against the authors' selection run on
# python-igraph.
REFERENCE_SETS = {
    "ntu25": (NTU25.parents, [[0, 3, 5, 7, 9, 11, 13, 15, 17, 19, 20], [7, 11, 13, 17, 20], [20]]),
    "smpl25": (SMPL25_PARENTS, [[1, 2, 3, 7, 8, 9, 15, 16, 17, 20, 21, 24], [1, 8, 9, 20, 21]]),
    "gta22": (GTA22.parents, [[0, 1, 3, 5, 7, 9, 11, 13, 17, 20], [0, 5, 9, 11]]),
}


def _joint_sets(pyramid) -> list[list[int]]:
    """Kept sets as skeleton joint indices (each level's ``kept`` indexes the previous level's nodes)."""
    joints, out = np.arange(pyramid.adjacency[0].shape[0]), []
    for kept in pyramid.kept:
        joints = joints[kept]
        out.append(joints.tolist())
    return out


@pytest.mark.parametrize("name", sorted(REFERENCE_SETS))
def test_coarsening_reproduces_reference_node_sets(name):
    parents, expected = REFERENCE_SETS[name]
    pyramid = graph_pyramid(parents, levels=len(expected))
    assert _joint_sets(pyramid) == expected
    assert [a.shape[0] for a in pyramid.adjacency] == [len(parents)] + [len(s) for s in expected]


@pytest.mark.parametrize("name", sorted(REFERENCE_SETS))
def test_kept_set_is_maximal_independent_and_coarse_graph_links_within_three_hops(name):
    pyramid = graph_pyramid(REFERENCE_SETS[name][0], levels=2)
    for kept, fine, coarse in zip(pyramid.kept, pyramid.adjacency, pyramid.adjacency[1:]):
        assert (np.diff(kept) > 0).all()  # sorted, distinct
        assert not fine[np.ix_(kept, kept)].any()  # independent
        dropped = np.setdiff1d(np.arange(fine.shape[0]), kept)
        assert fine[np.ix_(dropped, kept)].any(axis=1).all()  # maximal: every dropped node touches a kept one
        assert (coarse == coarse.T).all() and not coarse.diagonal().any()
        distance = hop_distances(fine)[np.ix_(kept, kept)]
        np.testing.assert_array_equal(coarse, (distance <= 3) & (distance > 0))


def test_critic_adjacency_chains_the_four_layers_and_normalises_per_kernel():
    graphs = CriticGraphs(*critic_adjacency(NTU25.parents))
    assert [a.shape for a in graphs] == [(2, 25, 25), (2, 11, 25), (2, 5, 11), (2, 5, 5)]
    for a in graphs:
        mask = a > 0
        expected = mask / np.sqrt(np.maximum(mask.sum(2, keepdims=True) * mask.sum(1, keepdims=True), 1))
        np.testing.assert_allclose(a, expected, rtol=1e-6)
    np.testing.assert_array_equal(graphs.conv0[0], np.eye(25))  # self kernel: one entry per row and column
    np.testing.assert_array_equal(graphs.down1[0] > 0, np.eye(25)[REFERENCE_SETS["ntu25"][1][0]] > 0)
    np.testing.assert_array_equal(graphs.conv0[1] > 0, skeleton_adjacency(NTU25.parents) > 0)


def test_hop_kernels_count_columns_over_kept_rows_on_a_path():
    # Path 0-1-2-3-4, rows [0, 2]. Self kernel: one entry per kept row, value 1. Neighbour kernel: row 0 has
    # {1}, row 2 has {1, 3}; among the kept rows column 1 has 2 entries, column 3 one (node 4 is not kept), so
    # [0, 1] = 1/√(1·2), [1, 1] = 1/√(2·2), [1, 3] = 1/√(2·1).
    s = 1 / np.sqrt(2)
    expected = np.array([[[1, 0, 0, 0, 0], [0, 0, 1, 0, 0]],
                         [[0, s, 0, 0, 0], [0, 0.5, 0, s, 0]]])
    np.testing.assert_allclose(hop_kernels(PATH5, np.array([0, 2])), expected, rtol=1e-6)
    # All rows: every neighbour-kernel entry of edge (v, w) is 1/√(deg v · deg w).
    degree = PATH5.sum(1)
    np.testing.assert_allclose(hop_kernels(PATH5)[1], PATH5 / np.sqrt(np.outer(degree, degree)), rtol=1e-6)


def test_selection_criteria_in_order_on_hand_worked_graphs():
    # P5: {0,2,4} and {1,3} tie on degree sum 4; betweenness means 4/3 < 3, so {1,3}.
    np.testing.assert_array_equal(coarsen(PATH5), [1, 3])
    np.testing.assert_array_equal(coarse_adjacency(PATH5, np.array([1, 3])), [[0, 1], [1, 0]])
    # P4 0-1-2-3: {0,2} and {1,3} tie on degree (3), betweenness (1), closeness (5/8), eccentricity (5/2) and
    # size, then the smaller index sum wins; {0,3} has degree sum 2.
    path4 = skeleton_adjacency((-1, 0, 1, 2))
    assert maximal_independent_sets(path4) == [(0, 2), (0, 3), (1, 3)]
    np.testing.assert_array_equal(coarsen(path4), [0, 2])
    # A star: {centre} and {leaves} tie on degree sum; the centre carries all the betweenness.
    np.testing.assert_array_equal(coarsen(skeleton_adjacency((-1, 0, 0, 0))), [0])
    np.testing.assert_array_equal(coarsen(np.zeros((1, 1), dtype=int)), [0])


def test_equal_means_compare_exactly():
    # Edges 0-1, 1-2, 1-3, 3-4, 2-5. {1,4,5} and {0,2,3} have degree sum 5 and betweenness means 8/3
    # ([8, 0, 0] and [0, 4, 4]; the authors' float running means differ in the last bit); closeness means
    # 45/91 < 155/297 then pick {0,2,3}.
    np.testing.assert_array_equal(coarsen(skeleton_adjacency((-1, 0, 1, 1, 3, 2))), [0, 2, 3])


@pytest.mark.parametrize("adjacency, match", [
    (np.zeros((2, 3)), r"adjacency: expected a square \[V, V\]"),
    (np.array([[0, 2], [2, 0]]), "adjacency: expected 0/1 entries"),
    (np.array([[0, 1], [0, 0]]), "adjacency: expected a symmetric"),
    (np.array([[1, 1], [1, 0]]), "adjacency: expected a zero diagonal"),
    (np.zeros((3, 3)), "adjacency: expected a connected graph"),
    (skeleton_adjacency(tuple(range(-1, 50))), "adjacency: expected at most 50 nodes"),
])
def test_bad_adjacency_raises(adjacency, match):
    with pytest.raises(ValueError, match=match):
        coarsen(adjacency)


def test_bad_rows_and_parents_raise():
    with pytest.raises(ValueError, match=r"kept: expected distinct node indices in \[0, 5\)"):
        coarse_adjacency(PATH5, np.array([0, 5]))
    with pytest.raises(ValueError, match=r"rows: expected a non-empty \[W\] integer index array"):
        hop_kernels(PATH5, np.array([[0, 2]]))
    with pytest.raises(ValueError, match="hops: expected at least 1"):
        coarse_adjacency(PATH5, np.array([0, 2]), hops=0)
    with pytest.raises(ValueError, match="parents"):
        graph_pyramid((0, 0, 1))
    with pytest.raises(ValueError, match="levels: expected at least 0"):
        graph_pyramid(NTU25.parents, levels=-1)
