"""NTU-25 and GTA-22 joints placed on SMPL-24 bodies: rigid attachment, equivariance, scale, plausible bones."""

import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.geometry import SMPL24, axis_angle_to_matrix, forward_kinematics, matrix_to_axis_angle
from jaxmotion.geometry.markers import GTA22_ON_SMPL24, NTU25_ON_SMPL24, body_scale, markers_from_rotations

SETS = pytest.mark.parametrize("markers", [NTU25_ON_SMPL24, GTA22_ON_SMPL24], ids=["ntu25", "gta22"])
# ActFormer's average NTU-25 bone lengths (ntu_adjacency.h5 avglength, FACTS 1.3), per child joint
NTU_AVERAGE_BONES = np.array([0, .2805, .0694, .1254, .1582, .2354, .2238, .0666, .1579, .2329, .2227, .0684, .0703,
                              .3372, .3437, .1062, .0706, .3371, .3437, .1067, .2088, .0563, .0388, .0563, .0383])


def _poses(seed, frames=16):
    rng = np.random.default_rng(seed)
    rot = (0.5 * rng.normal(size=(frames, 24, 3))).astype(np.float32)
    return jnp.asarray(rot), jnp.asarray(rng.normal(size=(frames, 3)).astype(np.float32))


def _bones(joints, parents):
    return np.stack([np.linalg.norm(joints[..., c, :] - joints[..., p, :], axis=-1)
                     for c, p in enumerate(parents) if p >= 0], axis=-1)


@SETS
def test_markers_ride_their_bones_rigidly(markers):
    rot, trans = _poses(0)
    placed = np.asarray(markers_from_rotations(markers, rot, trans, SMPL24.offsets))
    rest = np.asarray(markers_from_rotations(markers, jnp.zeros((1, 24, 3)), jnp.zeros((1, 3)), SMPL24.offsets))
    # a marker keeps its rest distance to the joint it is attached to, whatever the pose
    smpl = np.asarray(forward_kinematics(axis_angle_to_matrix(rot), trans, SMPL24.offsets, SMPL24.parents))
    smpl_rest = np.asarray(forward_kinematics(jnp.eye(3)[None, None].repeat(24, 1), jnp.zeros((1, 3)),
                                              SMPL24.offsets, SMPL24.parents))
    src = np.asarray(markers.sources)
    np.testing.assert_allclose(np.linalg.norm(placed - smpl[:, src], axis=-1),
                               np.broadcast_to(np.linalg.norm(rest[0] - smpl_rest[0, src], axis=-1), placed.shape[:2]),
                               atol=1e-5)


@SETS
def test_markers_move_with_the_body(markers):
    rot, trans = _poses(1)
    turn = jnp.array([0.3, -1.1, 0.4])
    turned_root = axis_angle_to_matrix(turn) @ axis_angle_to_matrix(rot[:, 0])
    moved_rot = rot.at[:, 0].set(matrix_to_axis_angle(turned_root))
    shift = jnp.array([1.0, 0.2, -2.0])
    moved_trans = trans @ axis_angle_to_matrix(turn).T + shift
    a = np.asarray(markers_from_rotations(markers, rot, trans, SMPL24.offsets))
    b = np.asarray(markers_from_rotations(markers, moved_rot, moved_trans, SMPL24.offsets))
    np.testing.assert_allclose(b, a @ np.asarray(axis_angle_to_matrix(turn)).T + np.asarray(shift), atol=2e-5)


@SETS
def test_a_larger_body_carries_proportionally_larger_markers(markers):
    zero = jnp.zeros((1, 24, 3))
    offsets = jnp.asarray(SMPL24.offsets)
    assert float(body_scale(offsets)) == pytest.approx(1.0)
    assert float(body_scale(1.1 * offsets)) == pytest.approx(1.1)
    small = np.asarray(markers_from_rotations(markers, zero, jnp.zeros((1, 3)), offsets))
    large = np.asarray(markers_from_rotations(markers, zero, jnp.zeros((1, 3)), 1.1 * offsets))
    np.testing.assert_allclose(large, 1.1 * small, atol=1e-6)
    # per-body offsets [B, 24, 3] with motions [B, T, 24, 3]
    both = markers_from_rotations(markers, jnp.zeros((2, 3, 24, 3)), jnp.zeros((2, 3, 3)), jnp.stack([offsets, 1.1 * offsets]))
    np.testing.assert_allclose(np.asarray(both)[1, 2], large[0], atol=1e-6)
    # per-frame offsets [F, 24, 3] with poses [F, 24, 3] (the generator's packed frames)
    frames = markers_from_rotations(markers, jnp.zeros((2, 24, 3)), jnp.zeros((2, 3)), jnp.stack([offsets, 1.1 * offsets]))
    np.testing.assert_allclose(np.asarray(frames)[1], large[0], atol=1e-6)


@SETS
def test_rest_pose_is_symmetric_and_bones_have_human_lengths(markers):
    sk = markers.skeleton
    rest = np.asarray(markers_from_rotations(markers, jnp.zeros((1, 24, 3)), jnp.zeros((1, 3)), SMPL24.offsets))[0]
    for i, name in enumerate(sk.joint_names):
        for a, b in (("left", "right"), ("right", "left")):
            if name.startswith(a):
                mirror = rest[sk.index(name.replace(a, b, 1))] * np.array([-1, 1, 1])
                np.testing.assert_allclose(rest[i], mirror, atol=1e-6)
                assert (rest[i, 0] > 0) == (a == "left")  # +X is the subject's left
    lengths = _bones(rest, sk.parents)
    assert np.all(lengths > 0.03) and np.all(lengths < 0.45)
    assert rest[sk.index("neck"), 1] > rest[0, 1] and rest[sk.joint_names.index(
        "head" if "head" in sk.joint_names else "head_top"), 1] > rest[sk.index("neck"), 1]


def test_ntu_bones_are_within_the_real_sets_proportions():
    rest = np.asarray(markers_from_rotations(NTU25_ON_SMPL24, jnp.zeros((1, 24, 3)), jnp.zeros((1, 3)),
                                             SMPL24.offsets))[0]
    ours = _bones(rest, NTU25_ON_SMPL24.skeleton.parents)
    real = NTU_AVERAGE_BONES[1:]
    # adult template vs NTU's average performer as Kinect sees them: limbs within 0.8-1.35x, hips wider (1.65x)
    ratio = ours / real
    hips = [NTU25_ON_SMPL24.skeleton.index(f"{s}_hip") - 1 for s in ("left", "right")]
    assert np.all(ratio[hips] < 1.7)
    others = np.delete(ratio, hips)
    assert np.all((others > 0.8) & (others < 1.35)), dict(zip(NTU25_ON_SMPL24.skeleton.joint_names[1:], ratio.round(2)))
