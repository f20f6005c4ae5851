"""Forward kinematics, bone measurements, canonicalisation and the HumanAct12 frame conversion.

Compilation dominates the run time on a CPU (about a second per skeleton for FK), so:
  * FK shapes are fixed per skeleton ([2, 3] poses: 2 bodies x 3 frames), and every skeleton compiles
    once; hypothesis draws the seeds, and sizes only where a tiny tree or a cheap function compiles;
  * random arrays are cut from one ``jax.random`` draw of a fixed size (random-bit generation is costly
    to compile, once per shape);
  * the non-jitted library functions are called through ``jax.jit`` (one compilation per shape rather
    than one per operation, which also checks that they are jittable).
"""

import math
import re

import jax
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from jaxmotion.geometry.kinematics import (
    apply_transform,
    bone_lengths,
    canonicalize,
    canonicalize_transform,
    forward_kinematics,
    forward_kinematics_transforms,
    heading_transform,
    humanact12_to_library_frame,
    inverse_transform,
    library_to_humanact12_frame,
    root_relative,
    root_trajectory,
    transform_ground_path,
    transform_root,
)
from jaxmotion.geometry.rotations import axis_angle_to_matrix
from jaxmotion.geometry.skeletons import CMU_MOCAP20, NTU25, SMPL24, UESTC18

SKELETONS = {s.name: s for s in (SMPL24, CMU_MOCAP20, UESTC18, NTU25)}
BATCH = (2, 3)  # [bodies, frames]
# A tiny branching tree whose parents are not topologically ordered (joint 1 hangs from joint 3).
TINY_TREE = (-1, 3, 0, 0)
ATOL = 1e-5

seeds = st.integers(0, 2**31 - 1)
skeleton_names = st.sampled_from(sorted(SKELETONS))

_normal_pool = jax.jit(lambda key: jax.random.normal(key, (1024,)))
jit_axis_angle_to_matrix = jax.jit(axis_angle_to_matrix)


def normals(seed, *shapes):
    """Independent standard-normal float32 arrays of the given shapes, from one ``jax.random`` draw."""
    sizes = [math.prod(shape) for shape in shapes]
    pool = np.asarray(_normal_pool(jax.random.PRNGKey(seed)))
    chunks = np.split(pool[: sum(sizes)], np.cumsum(sizes)[:-1])
    return [chunk.reshape(shape) for chunk, shape in zip(chunks, shapes, strict=True)]


def random_inputs(seed, batch, num_joints):
    """Random local rotations, root translation and offsets; the root's offset is random too (FK ignores it)."""
    shapes = (*batch, num_joints, 3), (*batch, 3), (num_joints, 3)
    axis_angles, root_translation, offsets = normals(seed, *shapes)
    return np.asarray(jit_axis_angle_to_matrix(2.0 * axis_angles)), root_translation, 0.3 * offsets


def random_motion(seed, num_frames):
    """[2, T, 6, 3] random joints; joints 1 and 2 act as the left and right hip."""
    return normals(seed, (2, num_frames, 6, 3))[0]


jit_bone_lengths = jax.jit(bone_lengths, static_argnames="parents")
jit_root_relative_and_trajectory = jax.jit(lambda joints: (root_relative(joints), root_trajectory(joints)))
jit_frame_conversions = jax.jit(lambda x: (library_to_humanact12_frame(x), humanact12_to_library_frame(x)))
jit_canonicalize = jax.jit(canonicalize, static_argnames=("left_hip", "right_hip", "up_axis"))
jit_canonicalize_transform = jax.jit(
    canonicalize_transform, static_argnames=("left_hip", "right_hip", "up_axis")
)


def reference_fk(local_rotmats, root_translation, offsets, parents):
    """FK by its definition, walking from each joint up to the root (numpy, recursive)."""
    local_rotmats, root_translation, offsets = map(np.asarray, (local_rotmats, root_translation, offsets))

    def transform(joint):
        if parents[joint] < 0:
            return local_rotmats[..., joint, :, :], root_translation
        parent_rotation, parent_position = transform(parents[joint])
        rotation = parent_rotation @ local_rotmats[..., joint, :, :]
        return rotation, parent_position + parent_rotation @ offsets[joint]

    rotations, positions = zip(*(transform(j) for j in range(len(parents))))
    return np.stack(rotations, axis=-3), np.stack(positions, axis=-2)


def yaw(angle):
    """Rotation by ``angle`` about +Y (numpy)."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]], dtype=np.float32)


# --- forward kinematics -------------------------------------------------------------------------------


@given(seed=seeds, name=skeleton_names)
def test_identity_rotations_and_zero_translation_give_the_rest_pose(seed, name):
    skeleton = SKELETONS[name]
    _, _, offsets = random_inputs(seed, BATCH, skeleton.num_joints)
    if skeleton.offsets is not None and seed % 2:  # half the SMPL examples use the project's template
        offsets = skeleton.offsets
    identity = np.broadcast_to(np.eye(3, dtype=np.float32), (*BATCH, skeleton.num_joints, 3, 3))
    zero = np.zeros((*BATCH, 3), np.float32)
    rotations, joints = forward_kinematics_transforms(identity, zero, offsets, skeleton.parents)

    # Rest pose: the sum of the offsets along the path from the root (whose own offset is ignored).
    def rest(joint):
        parent = skeleton.parents[joint]
        return np.zeros(3) if parent < 0 else rest(parent) + offsets[joint]

    expected = np.stack([rest(j) for j in range(skeleton.num_joints)])
    np.testing.assert_allclose(joints, np.broadcast_to(expected, joints.shape), atol=ATOL)
    np.testing.assert_array_equal(rotations, identity)


@given(seed=seeds, name=skeleton_names)
def test_fk_matches_its_recursive_definition_on_every_skeleton(seed, name):
    # NTU-25 is included: its parents are not topologically ordered.
    skeleton = SKELETONS[name]
    inputs = random_inputs(seed, BATCH, skeleton.num_joints)
    rotations, joints = forward_kinematics_transforms(*inputs, skeleton.parents)
    expected_rotations, expected_joints = reference_fk(*inputs, skeleton.parents)
    np.testing.assert_allclose(rotations, expected_rotations, atol=ATOL)
    np.testing.assert_allclose(joints, expected_joints, atol=ATOL)


@given(seed=seeds, name=skeleton_names)
def test_bone_lengths_are_preserved_under_arbitrary_rotations(seed, name):
    skeleton = SKELETONS[name]
    local_rotmats, root_translation, offsets = random_inputs(seed, BATCH, skeleton.num_joints)
    _, joints = forward_kinematics_transforms(local_rotmats, root_translation, offsets, skeleton.parents)
    lengths = jit_bone_lengths(joints, parents=skeleton.parents)
    assert lengths.shape == (*BATCH, skeleton.num_joints - 1)
    expected = np.linalg.norm(offsets[1:], axis=-1)  # non-root joints, in joint order
    np.testing.assert_allclose(lengths, np.broadcast_to(expected, lengths.shape), atol=ATOL)


@given(seed=seeds)
def test_rigid_motion_of_the_root_moves_all_joints_rigidly(seed):
    local_rotmats, root_translation, _ = random_inputs(seed, BATCH, SMPL24.num_joints)
    # One rigid motion per body, applied to all its frames: a root rotation and translation of another seed.
    rigid_rotations, rigid_translations, _ = random_inputs(seed + 1, BATCH, SMPL24.num_joints)
    rotation, translation = rigid_rotations[:, 0, 0], rigid_translations[:, 0]

    moved_root = np.einsum("bij,btjk->btik", rotation, local_rotmats[..., 0, :, :])
    moved_translation = np.einsum("bij,btj->bti", rotation, root_translation) + translation[:, None, :]
    root, new_translation = transform_root(rotation, translation, local_rotmats[..., 0, :, :], root_translation)
    np.testing.assert_allclose(root, moved_root, atol=ATOL)
    np.testing.assert_allclose(new_translation, moved_translation, atol=ATOL)
    moved_rotmats = local_rotmats.copy()
    moved_rotmats[..., 0, :, :] = moved_root
    _, moved = forward_kinematics_transforms(moved_rotmats, moved_translation, SMPL24.offsets, SMPL24.parents)
    _, joints = forward_kinematics_transforms(local_rotmats, root_translation, SMPL24.offsets, SMPL24.parents)
    expected = np.einsum("bij,btkj->btki", rotation, joints) + translation[:, None, None, :]
    np.testing.assert_allclose(moved, expected, atol=ATOL)


def test_two_bone_chain_matches_hand_computation():
    quarter_turn_z = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # x -> y, y -> -x
    local_rotmats = np.stack([quarter_turn_z, quarter_turn_z, np.eye(3)])
    root = np.array([0.1, 0.2, 0.3])
    offsets = np.array([[5.0, 5.0, 5.0], [1.0, 0.0, 0.0], [0.5, 0.0, 0.0]])  # the root row is ignored
    rotations, joints = forward_kinematics_transforms(local_rotmats, root, offsets, (-1, 0, 1))
    # Joint 1: root + Rz90 (1, 0, 0) = root + (0, 1, 0).
    # Joint 2: joint 1 + Rz90 Rz90 (0.5, 0, 0) = joint 1 + Rz180 (0.5, 0, 0) = joint 1 - (0.5, 0, 0).
    half_turn_z = np.diag([-1.0, -1.0, 1.0])
    np.testing.assert_allclose(joints, [[0.1, 0.2, 0.3], [0.1, 1.2, 0.3], [-0.4, 1.2, 0.3]], atol=1e-6)
    np.testing.assert_allclose(rotations, np.stack([quarter_turn_z, half_turn_z, half_turn_z]), atol=1e-6)


@given(seed=seeds)
def test_eager_and_jit_agree(seed):
    # One fixed shape: eager mode compiles every operation separately, per shape.
    inputs = random_inputs(seed, (2,), len(TINY_TREE))
    jitted = forward_kinematics(*inputs, TINY_TREE)
    with jax.disable_jit():
        eager = forward_kinematics(*inputs, TINY_TREE)
    np.testing.assert_allclose(jitted, eager, atol=ATOL)
    np.testing.assert_array_equal(jitted, forward_kinematics_transforms(*inputs, TINY_TREE)[1])


@given(seed=seeds, num_bodies=st.integers(1, 2))
def test_per_body_offsets_equal_a_loop_over_bodies(seed, num_bodies):
    local_rotmats, root_translation, _ = random_inputs(seed, (num_bodies, 3), len(TINY_TREE))
    # Bodies of different proportions: each body's offsets scaled by its own factor.
    scale = 1.0 + np.arange(num_bodies, dtype=np.float32)
    offsets = normals(seed + 1, (len(TINY_TREE), 3))[0] * scale[:, None, None]
    joints = forward_kinematics(local_rotmats, root_translation, offsets, TINY_TREE)
    for body in range(num_bodies):
        np.testing.assert_allclose(
            joints[body],
            forward_kinematics(local_rotmats[body], root_translation[body], offsets[body], TINY_TREE),
            atol=ATOL,
        )


J = SMPL24.num_joints
SHAPE_ERRORS = {
    "rotations-joints": (
        lambda: forward_kinematics(np.zeros((2, J - 1, 3, 3)), np.zeros((2, 3)), SMPL24.offsets, SMPL24.parents),
        f"local_rotmats: expected shape [..., {J}, 3, 3], got (2, {J - 1}, 3, 3)",
    ),
    "rotations-not-3x3": (
        lambda: forward_kinematics(np.zeros((2, J, 4)), np.zeros((2, 3)), SMPL24.offsets, SMPL24.parents),
        f"local_rotmats: expected shape [..., {J}, 3, 3], got (2, {J}, 4)",
    ),
    "translation-batch": (
        lambda: forward_kinematics(np.zeros((2, J, 3, 3)), np.zeros((3,)), SMPL24.offsets, SMPL24.parents),
        "root_translation: expected shape [2, 3], got (3,)",
    ),
    "offsets-joints": (
        lambda: forward_kinematics(
            np.zeros((2, J, 3, 3)), np.zeros((2, 3)), np.zeros((J - 1, 3)), SMPL24.parents
        ),
        f"offsets: expected shape [{J}, 3] or [*B, {J}, 3] with B a prefix of [2], got ({J - 1}, 3)",
    ),
    "offsets-not-a-prefix": (
        lambda: forward_kinematics_transforms(
            np.zeros((2, 5, J, 3, 3)), np.zeros((2, 5, 3)), np.zeros((5, J, 3)), SMPL24.parents
        ),
        f"offsets: expected shape [{J}, 3] or [*B, {J}, 3] with B a prefix of [2, 5], got (5, {J}, 3)",
    ),
    "bone-lengths": (
        lambda: bone_lengths(np.zeros((4, J - 1, 3)), SMPL24.parents),
        f"joints: expected shape [..., {J}, 3], got (4, {J - 1}, 3)",
    ),
    "root-relative": (lambda: root_relative(np.zeros((4, 2))), "joints: expected shape [..., J, 3], got (4, 2)"),
    "root-trajectory": (lambda: root_trajectory(np.zeros((3,))), "joints: expected shape [..., J, 3], got (3,)"),
    "canonicalize-no-time-axis": (
        lambda: canonicalize(np.zeros((J, 3)), 1, 2),
        f"joints: expected shape [..., T, J, 3], got ({J}, 3)",
    ),
    "transform-root-translation": (
        lambda: transform_root(np.eye(3), np.zeros((2, 3)), np.zeros((4, 3, 3)), np.zeros((4, 3))),
        "translation: expected shape [3], got (2, 3)",
    ),
    "transform-root-frames": (
        lambda: transform_root(np.eye(3), np.zeros(3), np.zeros((3, 3)), np.zeros((4, 3))),
        "root_rotmats: expected shape ['T', 3, 3], got (3, 3)",
    ),
    "frame-points": (
        lambda: library_to_humanact12_frame(np.zeros((4, 2))),
        "points: expected shape [..., 3], got (4, 2)",
    ),
}


@pytest.mark.parametrize("case", sorted(SHAPE_ERRORS))
def test_shape_errors_name_the_argument_and_the_expected_shape(case):
    call, message = SHAPE_ERRORS[case]
    with pytest.raises(ValueError, match=re.escape(message)):
        call()


def test_invalid_parents_and_hip_indices_raise_value_error():
    with pytest.raises(ValueError, match="parents"):
        forward_kinematics(np.zeros((3, 3, 3)), np.zeros(3), np.zeros((3, 3)), (-1, 2, 1))
    with pytest.raises(ValueError, match="left_hip, right_hip"):
        canonicalize(np.zeros((2, 4, 3)), 1, 1)
    with pytest.raises(ValueError, match="up_axis"):
        canonicalize(np.zeros((2, 4, 3)), 1, 2, up_axis=3)


# --- root helpers and canonicalisation ----------------------------------------------------------------


@given(seed=seeds, num_frames=st.integers(1, 3))
def test_root_relative_plus_root_trajectory_restores_the_joints(seed, num_frames):
    joints = random_motion(seed, num_frames)
    relative, trajectory = jit_root_relative_and_trajectory(joints)
    np.testing.assert_array_equal(relative[..., 0, :], 0.0)
    assert trajectory.shape == (2, num_frames, 3)
    np.testing.assert_allclose(np.asarray(relative) + np.asarray(trajectory)[..., None, :], joints, atol=1e-6)


@given(seed=seeds, num_frames=st.integers(1, 3))
def test_canonicalize_puts_frame_zero_root_at_origin_facing_plus_z(seed, num_frames):
    joints = random_motion(seed, num_frames)
    rotation, _ = jit_canonicalize_transform(joints, left_hip=1, right_hip=2)
    out = np.asarray(jit_canonicalize(joints, left_hip=1, right_hip=2))
    np.testing.assert_allclose(out[:, 0, 0], 0.0, atol=ATOL)
    facing = np.cross(out[:, 0, 1] - out[:, 0, 2], [0.0, 1.0, 0.0])
    np.testing.assert_allclose(facing[:, 0], 0.0, atol=ATOL)
    assert np.all(facing[:, 2] > 0)
    # A rotation about the vertical only: heights are kept (relative to the root's), and R is proper.
    np.testing.assert_allclose(out[..., 1], joints[..., 1] - joints[:, :1, :1, 1], atol=ATOL)
    np.testing.assert_allclose(np.linalg.det(rotation), 1.0, atol=ATOL)


@given(seed=seeds, num_frames=st.integers(1, 3), angle=st.floats(-np.pi, np.pi))
def test_canonicalize_is_invariant_to_a_prior_yaw_and_translation(seed, num_frames, angle):
    joints = random_motion(seed, num_frames)
    shift = random_motion(seed + 1, 1)[0, 0, 0]
    moved = np.einsum("ij,btkj->btki", yaw(angle), joints) + shift
    np.testing.assert_allclose(
        jit_canonicalize(moved, left_hip=1, right_hip=2),
        jit_canonicalize(joints, left_hip=1, right_hip=2),
        atol=1e-4,
    )


@given(seed=seeds)
def test_canonicalize_commutes_with_a_cyclic_relabelling_of_the_axes(seed):
    # (left, up, forward) = (x, y, z) relabelled as (y, z, x): the same motion stored z-up.
    joints = random_motion(seed, 2)
    z_up = np.roll(joints, 1, axis=-1)
    np.testing.assert_allclose(
        jit_canonicalize(z_up, left_hip=1, right_hip=2, up_axis=2),
        np.roll(jit_canonicalize(joints, left_hip=1, right_hip=2), 1, axis=-1),
        atol=ATOL,
    )


@given(seed=seeds)
def test_canonicalizing_the_root_of_a_rotation_motion_canonicalizes_its_joints(seed):
    local_rotmats, root_translation, _ = random_inputs(seed, BATCH, SMPL24.num_joints)
    _, joints = forward_kinematics_transforms(local_rotmats, root_translation, SMPL24.offsets, SMPL24.parents)
    hips = {"left_hip": SMPL24.index("left_hip"), "right_hip": SMPL24.index("right_hip")}
    rotation, translation = jit_canonicalize_transform(joints, **hips)
    root, new_translation = transform_root(rotation, translation, local_rotmats[..., 0, :, :], root_translation)
    moved_rotmats = local_rotmats.copy()
    moved_rotmats[..., 0, :, :] = root
    _, moved = forward_kinematics_transforms(moved_rotmats, new_translation, SMPL24.offsets, SMPL24.parents)
    np.testing.assert_allclose(moved, jit_canonicalize(joints, **hips), atol=1e-4)


# --- frame conversion ---------------------------------------------------------------------------------


@given(seed=seeds, num_frames=st.integers(1, 3))
def test_humanact12_frame_conversion_is_an_involution(seed, num_frames):
    points = random_motion(seed, num_frames)
    converted, _ = jit_frame_conversions(points)
    back_by_the_same_map, back = jit_frame_conversions(converted)
    np.testing.assert_array_equal(back_by_the_same_map, points)
    np.testing.assert_array_equal(back, points)


def test_humanact12_frame_conversion_is_a_proper_rotation_turning_up_down_and_forward_back():
    # Columns: the images of e_x, e_y, e_z.
    matrix = np.asarray(library_to_humanact12_frame(np.eye(3, dtype=np.float32))).T
    np.testing.assert_allclose(matrix @ matrix.T, np.eye(3))
    assert np.linalg.det(matrix) == pytest.approx(1.0)
    np.testing.assert_array_equal(matrix, np.diag([1.0, -1.0, -1.0]))


def test_fk_refuses_a_concrete_scaled_or_mirrored_joint_rotation_but_not_under_jit():
    rotmats = np.tile(np.eye(3, dtype=np.float32), (2, SMPL24.num_joints, 1, 1))
    rotmats[1, 5] *= 1.1  # would stretch every bone below joint 5
    args = (rotmats, np.zeros((2, 3), np.float32), SMPL24.offsets)
    for fk, name in ((forward_kinematics, "forward_kinematics"),
                     (forward_kinematics_transforms, "forward_kinematics_transforms")):
        with pytest.raises(ValueError, match=re.escape(f"{name}: local_rotmats: 1 of 48 matrices are not rotations; "
                                                       f"the first, at index (1, 5), is scaled or sheared")):
            fk(*args, SMPL24.parents)
    stretched = np.asarray(forward_kinematics(*args, SMPL24.parents, check=False))
    np.testing.assert_allclose(stretched, jax.jit(forward_kinematics, static_argnums=3)(*args, SMPL24.parents),
                               atol=1e-6)
    lengths = bone_lengths(stretched, SMPL24.parents)
    assert (lengths[1] > lengths[0] + 1e-4).any() and np.allclose(lengths[0], bone_lengths(
        forward_kinematics(*(a[:1] for a in args[:2]), SMPL24.offsets, SMPL24.parents), SMPL24.parents)[0])


def test_transform_root_refuses_a_reflection():
    with pytest.raises(ValueError, match=re.escape("transform_root: rotation: 1 of 1 matrices are not rotations; "
                                                   "the first, at index (), is a reflection")):
        transform_root(np.diag([-1.0, 1.0, 1.0]), np.zeros(3), np.tile(np.eye(3), (4, 1, 1)), np.zeros((4, 3)))


# --- Marionette's heading normalisation ---------------------------------------------------------------

_heading = jax.jit(heading_transform)


def _normalised(rotmats, translation, frame):
    """A motion ``[T, 24, 3, 3]``, ``[T, 3]`` in the heading frame of ``frame``: its root rotations, translation,
    joints, and the transform."""
    rotation, shift = _heading(rotmats[frame, 0], translation[frame])
    roots, moved = transform_root(rotation, shift, rotmats[:, 0], translation)
    rotmats = np.concatenate([np.asarray(roots)[:, None], rotmats[:, 1:]], axis=1)
    return rotmats, np.asarray(moved), (rotation, shift)


@given(seeds, st.floats(-np.pi, np.pi), st.floats(-3.0, 3.0), st.floats(-3.0, 3.0))
def test_heading_normalisation_removes_the_ground_rotation_and_position_and_restores_them(seed, angle, dx, dz):
    axis_angles, translation = normals(seed, (5, 24, 3), (5, 3))
    rotmats = np.asarray(jit_axis_angle_to_matrix(0.7 * axis_angles))
    frame = 3
    norm_rotmats, norm_translation, (rotation, shift) = _normalised(rotmats, translation, frame)
    forward = norm_rotmats[frame, 0] @ np.array([0.0, 0.0, 1.0])
    assert abs(forward[0]) < 1e-5 and forward[2] > 0  # facing +Z
    np.testing.assert_allclose(norm_translation[frame], [0.0, translation[frame, 1], 0.0], atol=1e-5)  # height kept
    # FK commutes with the transform
    offsets = SMPL24.offsets
    joints = forward_kinematics(rotmats, translation, offsets, SMPL24.parents)
    np.testing.assert_allclose(forward_kinematics(norm_rotmats, norm_translation, offsets, SMPL24.parents),
                               apply_transform(rotation, shift, joints), atol=1e-5)
    # the inverse restores the motion to float32 rounding
    back_roots, back_translation = transform_root(*inverse_transform(rotation, shift), norm_rotmats[:, 0],
                                                  norm_translation)
    np.testing.assert_allclose(back_roots, rotmats[:, 0], atol=1e-5)
    np.testing.assert_allclose(back_translation, translation, atol=1e-5)
    # the same motion turned about +Y and moved on the ground normalises to the same thing
    turned_roots, turned_translation = transform_root(yaw(angle), np.array([dx, 0.0, dz], np.float32),
                                                      rotmats[:, 0], translation)
    turned = np.concatenate([np.asarray(turned_roots)[:, None], rotmats[:, 1:]], axis=1)
    again_rotmats, again_translation, _ = _normalised(turned, np.asarray(turned_translation), frame)
    np.testing.assert_allclose(again_rotmats[:, 0], norm_rotmats[:, 0], atol=1e-4)
    np.testing.assert_allclose(again_translation, norm_translation, atol=1e-4)


def test_a_ground_path_moves_with_the_transform_and_stays_on_the_ground():
    # a quarter turn about +Y (x -> -z, z -> x), then 1 m along x: (1, 0) -> (0, -1) -> (1, -1); (0, 2) -> (3, 0)
    path = np.array([[[1.0, 0.0], [0.0, 2.0]]], np.float32)  # [B, N, 2] (x, z)
    moved = transform_ground_path(yaw(np.pi / 2)[None], np.array([[1.0, 0.5, 0.0]], np.float32), path)
    np.testing.assert_allclose(moved, [[[1.0, -1.0], [3.0, 0.0]]], atol=1e-6)  # the height shift leaves the ground
    lifted = np.stack([path[..., 0], np.zeros_like(path[..., 0]), path[..., 1]], -1)
    rotation, shift = heading_transform(jit_axis_angle_to_matrix(np.array([[0.3, 1.1, -0.2]], np.float32)),
                                        np.array([[0.4, 0.9, -1.3]], np.float32))
    np.testing.assert_allclose(transform_ground_path(rotation, shift, path),
                               np.asarray(apply_transform(rotation, shift, lifted))[..., [0, 2]], atol=1e-6)
