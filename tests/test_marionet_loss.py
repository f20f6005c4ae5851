"""Neural Marionette's loss: zero on the target, the velocity terms, padding ignored, joints by forward kinematics,
the two passes weighted."""

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.geometry import SMPL24, axis_angle_to_matrix, forward_kinematics
from jaxmotion.geometry.representations import pose135
from jaxmotion.losses.core import masked_velocity_mse
from jaxmotion.losses.marionet import MarionetLossWeights, local_joints, marionet_loss, reconstruction

WEIGHTS = MarionetLossWeights()


def _poses(seed, batch=2, frames=6):
    rng = np.random.default_rng(seed)
    rotations = jnp.asarray(0.3 * rng.normal(size=(batch, frames, 24, 3)), jnp.float32)
    translation = jnp.asarray(rng.normal(size=(batch, frames, 3)), jnp.float32)
    return pose135(rotations, translation), rotations


def test_the_loss_is_zero_on_the_target_and_ignores_padded_frames():
    target, _ = _poses(0)
    mask = jnp.array([[True] * 6, [True] * 4 + [False] * 2])
    mu, log_variance = jnp.zeros((2, 8)), jnp.zeros((2, 8))
    loss, terms = marionet_loss(target, None, target, mask, mu, log_variance, weights=WEIGHTS, skeleton=SMPL24)
    assert float(loss) == 0.0 and float(terms["kl"]) == 0.0
    garbage = target.at[1, 4:].set(9.0)  # only on the padded frames
    again, _ = marionet_loss(garbage, None, target, mask, mu, log_variance, weights=WEIGHTS, skeleton=SMPL24)
    assert float(again) == 0.0


def test_a_constant_offset_costs_position_but_no_velocity():
    target, _ = _poses(1)
    mask = jnp.ones((2, 6), bool)
    shifted = target.at[..., 132:].add(0.5)  # the translation moved by 0.5 everywhere
    _, terms = reconstruction(shifted, target, mask, WEIGHTS, SMPL24)
    np.testing.assert_allclose(terms["translation"], 0.25, rtol=1e-6)  # mean of 0.5², no velocity part
    assert float(terms["rotations"]) == 0.0 and float(terms["joints"]) == 0.0
    np.testing.assert_allclose(masked_velocity_mse(shifted, target, mask), 0.0, atol=1e-12)


def test_local_joints_are_forward_kinematics_of_the_rotations_about_the_root():
    poses, rotations = _poses(2)
    joints = local_joints(poses, SMPL24)
    rotmats = axis_angle_to_matrix(rotations.at[..., 22:, :].set(0.0))
    expected = forward_kinematics(rotmats, jnp.zeros((2, 6, 3)), SMPL24.offsets, SMPL24.parents)
    np.testing.assert_allclose(joints, expected, atol=1e-5)
    np.testing.assert_allclose(joints[..., 0, :], 0.0)


def test_the_second_pass_and_the_kl_enter_with_their_weights():
    target, _ = _poses(3)
    first, second = target + 0.1, target + 0.2
    mask = jnp.ones((2, 6), bool)
    mu, log_variance = jnp.ones((2, 8)), jnp.zeros((2, 8))
    recon_first, _ = reconstruction(first, target, mask, WEIGHTS, SMPL24)
    recon_second, second_terms = reconstruction(second, target, mask, WEIGHTS, SMPL24)
    loss, terms = jax.jit(lambda *a: marionet_loss(*a, weights=WEIGHTS, skeleton=SMPL24, first_weight=0.1,
                                                   second_weight=0.9))(first, (recon_second, second_terms), target,
                                                                       mask, mu, log_variance)
    np.testing.assert_allclose(terms["kl"], 0.5 * 16)  # sum of mu²/2 over 2 x 8
    np.testing.assert_allclose(loss, 0.1 * recon_first + 0.9 * recon_second + 1e-8 * 8.0, rtol=1e-6)
    np.testing.assert_allclose(terms["joints (second pass)"], second_terms["joints"])
