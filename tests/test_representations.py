"""Motion representations: rotations + translation row (ACTOR, ActFormer SMPL) and root + unit limb vectors
(ActFormer NTU-25 / GTA-22): round trips, centring, lengths, errors."""

import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.geometry import GTA22, NTU25, SMPL24, axis_angle_to_matrix, forward_kinematics
from jaxmotion.geometry.markers import NTU25_ON_SMPL24, markers_from_rotations
from jaxmotion.geometry.representations import (
    from_pose135,
    joints_from_limb_vectors,
    limb_vectors,
    mean_bone_lengths,
    pose135,
    rotation_features,
    skeleton_features,
    split_rotation_features,
)


def _motion(seed, lead=(2, 3), frames=10):
    rng = np.random.default_rng(seed)
    rot = (0.4 * rng.normal(size=(*lead, frames, 24, 3))).astype(np.float32)
    trans = np.cumsum(0.05 * rng.normal(size=(*lead, frames, 3)), axis=-2).astype(np.float32) + 1.0
    return jnp.asarray(rot), jnp.asarray(trans)


@pytest.mark.parametrize("rep", ["rot6d", "quaternion", "matrix", "axis_angle"])
@pytest.mark.parametrize("origin", ["first", "mean"])
def test_rotation_features_round_trip_on_persons_axes(rep, origin):
    rot, trans = _motion(0)  # [B=2, P=3, T, 24, 3]
    feats = rotation_features(rot, trans, rep, origin)
    channels = {"rot6d": 6, "quaternion": 4, "matrix": 9, "axis_angle": 3}[rep]
    assert feats.shape == (2, 3, 10, 25, channels)
    back_rot, back_trans = split_rotation_features(feats, rep)
    np.testing.assert_allclose(np.asarray(axis_angle_to_matrix(back_rot)), np.asarray(axis_angle_to_matrix(rot)),
                               atol=2e-5)
    origin_point = trans[..., :1, :] if origin == "first" else trans.mean(axis=-2, keepdims=True)
    np.testing.assert_allclose(np.asarray(back_trans), np.asarray(trans - origin_point), atol=1e-6)
    if origin == "mean":
        np.testing.assert_allclose(np.asarray(back_trans).mean(axis=-2), 0.0, atol=1e-6)
    np.testing.assert_array_equal(np.asarray(feats[..., -1, 3:]), 0.0)  # the translation row's padding


def test_rotation_features_name_the_bad_field():
    rot, trans = _motion(1)
    with pytest.raises(ValueError, match="translation: expected shape"):
        rotation_features(rot, trans[..., :5, :], "rot6d")
    with pytest.raises(ValueError, match="origin: expected 'first' or 'mean'"):
        rotation_features(rot, trans, "rot6d", origin="last")
    with pytest.raises(ValueError, match=r"features: expected shape \[..., T, J \+ 1, 6\]"):
        split_rotation_features(jnp.zeros((2, 10, 25, 4)), "rot6d")


@pytest.mark.parametrize("skeleton", [NTU25, GTA22, SMPL24], ids=["ntu25", "gta22", "smpl24"])
def test_limb_vectors_are_units_and_rebuild_joints_with_the_true_lengths(skeleton):
    rng = np.random.default_rng(2)
    joints = jnp.asarray(rng.normal(size=(4, 7, skeleton.num_joints, 3)).astype(np.float32))
    vectors = limb_vectors(joints, skeleton.parents)
    norms = np.linalg.norm(np.asarray(vectors)[..., 1:, :], axis=-1)
    np.testing.assert_allclose(norms, 1.0, atol=1e-3)  # 1 - 1e-4/|d|
    np.testing.assert_array_equal(np.asarray(vectors[..., 0, :]), np.asarray(joints[..., 0, :]))
    # with each frame's own bone lengths, the rebuild is exact up to the 1e-4 guard
    parent = np.array([max(p, 0) for p in skeleton.parents])
    lengths = np.linalg.norm(np.asarray(joints - joints[..., parent, :]), axis=-1)  # [4, 7, J]
    one = joints_from_limb_vectors(vectors[0, 0], skeleton.parents, lengths[0, 0])
    np.testing.assert_allclose(np.asarray(one), np.asarray(joints[0, 0]), atol=2e-3)
    # and limb vectors of rebuilt joints are the same vectors
    again = limb_vectors(joints_from_limb_vectors(vectors, skeleton.parents, mean_bone_lengths(joints, skeleton.parents)),
                         skeleton.parents)
    np.testing.assert_allclose(np.asarray(again), np.asarray(vectors), atol=1e-3)  # the guard, on short bones


def test_rigid_bodies_round_trip_through_skeleton_features():
    rot, trans = _motion(3, lead=(2, 2), frames=12)  # two clips of two persons, one body
    joints = forward_kinematics(axis_angle_to_matrix(rot), trans, SMPL24.offsets, SMPL24.parents)  # rigid bones
    feats = skeleton_features(joints, SMPL24.parents)
    np.testing.assert_allclose(np.asarray(feats[..., 0, :]).mean(axis=(1, 2)), 0.0, atol=1e-5)  # centred per clip
    lengths = mean_bone_lengths(joints, SMPL24.parents)
    assert float(lengths[0]) == 0.0
    np.testing.assert_allclose(np.asarray(lengths[1:]), np.linalg.norm(SMPL24.offsets[1:], axis=-1), atol=1e-5)
    rebuilt = joints_from_limb_vectors(feats, SMPL24.parents, lengths)
    centre = np.asarray(joints[..., 0, :]).mean(axis=(1, 2))[:, None, None, None]
    np.testing.assert_allclose(np.asarray(rebuilt), np.asarray(joints) - centre, atol=1e-3)


def test_ntu_markers_rebuilt_from_average_lengths_stay_near_the_body():
    # Kinect-like bones are not rigid on an SMPL body (spine_mid to spine_shoulder spans a spine joint): the
    # rebuild with average lengths is close, not exact
    rot, trans = _motion(5, lead=(1, 1), frames=40)
    rot = rot * 0.3  # everyday joint angles
    joints = markers_from_rotations(NTU25_ON_SMPL24, rot, trans, SMPL24.offsets)
    rebuilt = joints_from_limb_vectors(skeleton_features(joints, NTU25.parents), NTU25.parents,
                                       mean_bone_lengths(joints, NTU25.parents))
    centre = np.asarray(joints[..., 0, :]).mean(axis=(1, 2))[:, None, None, None]
    error = np.linalg.norm(np.asarray(rebuilt) - (np.asarray(joints) - centre), axis=-1)
    assert error.mean() < 0.01 and error.max() < 0.05


def test_the_smpl_rotation_row_layout_drives_forward_kinematics():
    rot, trans = _motion(4, lead=(3,))
    back_rot, back_trans = split_rotation_features(rotation_features(rot, trans, "rot6d", "mean"), "rot6d")
    a = forward_kinematics(axis_angle_to_matrix(rot), trans - trans.mean(axis=-2, keepdims=True), SMPL24.offsets,
                           SMPL24.parents)
    b = forward_kinematics(axis_angle_to_matrix(back_rot), back_trans, SMPL24.offsets, SMPL24.parents)
    np.testing.assert_allclose(np.asarray(a), np.asarray(b), atol=3e-5)


def test_skeleton_features_need_a_persons_axis():
    with pytest.raises(ValueError, match=r"joints: expected shape \[..., P, T, 25, 3\]"):
        skeleton_features(jnp.zeros((10, 25, 3)), NTU25.parents)
    with pytest.raises(ValueError, match=r"lengths: expected shape \[J\] = \(25,\)"):
        joints_from_limb_vectors(jnp.zeros((10, 25, 3)), NTU25.parents, jnp.zeros(24))


def test_the_135_number_pose_holds_22_joints_in_rot6d_and_the_translation_and_round_trips():
    rot, trans = _motion(3)  # [2, 3, T, 24, 3]
    pose = pose135(rot, trans)
    assert pose.shape == (2, 3, 10, 135)
    np.testing.assert_allclose(pose[..., 132:], trans)
    first = np.asarray(axis_angle_to_matrix(rot[..., 0, :]))[..., :2, :].reshape(2, 3, 10, 6)
    np.testing.assert_allclose(pose[..., :6], first, atol=1e-6)  # joint 0 first, the matrix's first two rows
    back_rot, back_trans = from_pose135(pose)
    np.testing.assert_allclose(axis_angle_to_matrix(back_rot[..., :22, :]), axis_angle_to_matrix(rot[..., :22, :]),
                               atol=1e-5)
    np.testing.assert_array_equal(back_rot[..., 22:, :], 0.0)  # the hands: identity
    np.testing.assert_array_equal(back_trans, trans)
    with pytest.raises(ValueError, match=r"pose: expected shape \[..., T, 135\], got \(10, 134\)"):
        from_pose135(pose[0, 0, :, :134])
    with pytest.raises(ValueError, match=r"rotations: expected shape \[..., T, 24, 3\] \(SMPL-24\)"):
        pose135(rot[..., :22, :], trans)
