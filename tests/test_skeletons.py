"""Skeleton definitions: joint counts, tree validation, topological order, the SMPL-24 template."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from jaxmotion.geometry.skeletons import (
    CMU_MOCAP20,
    GTA22,
    JOINTS15,
    NTU25,
    SMPL24,
    UESTC18,
    VIBE18,
    Skeleton,
    bones,
    joints15_indices,
    topological_order,
)

ALL_SKELETONS = [SMPL24, CMU_MOCAP20, UESTC18, NTU25, GTA22]


@pytest.mark.parametrize(
    ("skeleton", "num_joints"),
    [(SMPL24, 24), (CMU_MOCAP20, 20), (UESTC18, 18), (NTU25, 25), (GTA22, 22)],
    ids=["smpl", "cmu", "uestc", "ntu", "gta"],
)
def test_skeletons_have_the_right_joint_counts(skeleton, num_joints):
    assert skeleton.num_joints == len(skeleton.parents) == len(skeleton.joint_names) == num_joints
    assert len(skeleton.bones) == num_joints - 1
    assert sum(len(c) for c in skeleton.children) == num_joints - 1


def test_vibe18_is_the_uestc18_layout():
    assert VIBE18 is UESTC18
    assert UESTC18.joint_names[UESTC18.parents[UESTC18.index("HeadTop")]] == "Nose"


def test_ntu25_is_not_topologically_ordered_but_is_a_valid_tree():
    assert any(parent > joint for joint, parent in enumerate(NTU25.parents))
    assert NTU25.joint_names[NTU25.parents[NTU25.index("neck")]] == "spine_shoulder"


@pytest.mark.parametrize("skeleton", ALL_SKELETONS, ids=lambda s: s.name)
def test_topological_order_puts_every_parent_before_its_children(skeleton):
    order = topological_order(skeleton.parents)
    assert sorted(order) == list(range(skeleton.num_joints))
    position = {joint: i for i, joint in enumerate(order)}
    assert all(position[parent] < position[child] for parent, child in skeleton.bones)


@given(data=st.data(), num_joints=st.integers(1, 30))
def test_topological_order_of_any_relabelled_tree_is_valid(data, num_joints):
    # A tree with parent < child, then joints 1.. relabelled at random: parents can follow children.
    ordered_parents = [-1] + [data.draw(st.integers(0, j - 1)) for j in range(1, num_joints)]
    label = [0] + data.draw(st.permutations(range(1, num_joints)))
    parents = [0] * num_joints
    for joint, parent in enumerate(ordered_parents):
        parents[label[joint]] = -1 if parent < 0 else label[parent]
    parents = tuple(parents)
    order = topological_order(parents)
    position = {joint: i for i, joint in enumerate(order)}
    assert sorted(order) == list(range(num_joints))
    assert all(position[parents[j]] < position[j] for j in range(1, num_joints))
    assert bones(parents) == tuple((parents[j], j) for j in range(1, num_joints))


@pytest.mark.parametrize(
    ("parents", "message"),
    [
        ((), "parents"),
        ((0, -1), r"parents\[0\] == -1"),
        ((-1, -1), "only joint 0 may be the root"),
        ((-1, 5), r"in \[0, 2\)"),
        ((-1, 1), "parent 1"),
        ((-1, 2, 1), "cycle"),
    ],
    ids=["empty", "root-not-first", "two-roots", "out-of-range", "self-parent", "cycle"],
)
def test_skeleton_validation_rejects_bad_parents(parents, message):
    with pytest.raises(ValueError, match=message):
        topological_order(parents)
    with pytest.raises(ValueError, match=message):
        Skeleton("bad", tuple(f"j{i}" for i in range(len(parents))), parents, None)


def test_skeleton_validation_rejects_mismatched_names_and_offsets():
    parents = (-1, 0, 1)
    with pytest.raises(ValueError, match="joint_names: expected 3 names"):
        Skeleton("bad", ("a", "b"), parents, None)
    with pytest.raises(ValueError, match="unique"):
        Skeleton("bad", ("a", "b", "a"), parents, None)
    with pytest.raises(ValueError, match=r"offsets: expected shape \(3, 3\), got \(2, 3\)"):
        Skeleton("bad", ("a", "b", "c"), parents, np.zeros((2, 3)))
    with pytest.raises(ValueError, match="parents: expected a tuple"):
        Skeleton("bad", ("a", "b", "c"), [-1, 0, 1], None)
    with pytest.raises(ValueError, match="joint_name"):
        SMPL24.index("tail")


def test_offsets_are_a_read_only_float32_copy():
    source = np.zeros((3, 3))
    skeleton = Skeleton("chain", ("a", "b", "c"), (-1, 0, 1), source)
    assert skeleton.offsets.dtype == np.float32
    with pytest.raises(ValueError):
        skeleton.offsets[1, 0] = 1.0
    source[1, 0] = 1.0
    assert skeleton.offsets[1, 0] == 0.0
    assert SMPL24.offsets is not None and not SMPL24.offsets.flags.writeable


def test_smpl_offsets_are_left_right_mirror_symmetric():
    offsets = SMPL24.offsets
    mirror = np.array([-1.0, 1.0, 1.0], dtype=np.float32)
    pairs = [(name, "right_" + name[5:]) for name in SMPL24.joint_names if name.startswith("left_")]
    assert len(pairs) == 9
    for left, right in pairs:
        np.testing.assert_array_equal(offsets[SMPL24.index(right)], offsets[SMPL24.index(left)] * mirror)
    midline = [SMPL24.index(n) for n in SMPL24.joint_names if not n.startswith(("left_", "right_"))]
    np.testing.assert_array_equal(offsets[midline, 0], 0.0)
    np.testing.assert_array_equal(offsets[0], 0.0)


def test_smpl_template_is_in_the_library_frame():
    # Rest positions by walking up the tree: left is +x, up is +y, the feet point forward (+z).
    def rest(joint):
        parent = SMPL24.parents[joint]
        return np.zeros(3) if parent < 0 else rest(parent) + SMPL24.offsets[joint]

    position = {name: rest(SMPL24.index(name)) for name in SMPL24.joint_names}
    assert position["left_hip"][0] > 0 > position["right_hip"][0]
    assert position["left_hand"][0] > 0.6 and position["right_hand"][0] < -0.6
    assert position["head"][1] > 0.5 and position["left_ankle"][1] < -0.8
    assert position["left_foot"][2] > position["left_ankle"][2]
    # Adult proportions: pelvis-to-head plus pelvis-to-ankle is within a plausible standing height.
    assert 1.3 < position["head"][1] - position["left_ankle"][1] < 1.7


@pytest.mark.parametrize("skeleton", [NTU25, GTA22])
def test_joints15_takes_each_common_joint_so_that_every_bone_follows_the_source_tree(skeleton):
    indices = joints15_indices(skeleton)
    assert indices[0] == 0 and len(set(indices)) == 15  # root to root: the translation stays the translation
    for joint, parent in enumerate(JOINTS15.parents[1:], start=1):
        ancestors, node = set(), indices[joint]
        while node >= 0:
            node = skeleton.parents[node]
            ancestors.add(node)
        assert indices[parent] in ancestors, (skeleton.name, JOINTS15.joint_names[joint])
    for joint, name in enumerate(JOINTS15.joint_names):  # sides and limb joints keep their names
        if name.startswith(("left_", "right_")):
            assert skeleton.joint_names[indices[joint]] == name
    assert joints15_indices(JOINTS15) == tuple(range(15))
    with pytest.raises(ValueError, match="no mapping onto the 15-joint topology"):
        joints15_indices(SMPL24)
