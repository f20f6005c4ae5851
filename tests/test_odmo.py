"""ODMO's model and loss: parameter counts against a hand count, the authors' state-dict names, the pieces'
invariants (root-relative encoder input, trajectory integration, the class-code outer product, causal
teacher forcing, BatchNorm per pair half), the loss terms on analytical cases and the code-vs-paper switches.

Parity with the authors' PyTorch code at the same weights (outputs 8e-7, losses 2e-7, gradients 6e-6
relative, BatchNorm running statistics 3e-7) was checked outside the suite; the README's ODMO section says how.
"""

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.data.motion import MotionDataset
from jaxmotion.losses.odmo import (
    ODMOLossConfig,
    contrastive_loss,
    pair_loss,
    prior_kl,
    trajectory_loss,
    weighted_frame_error,
)
from jaxmotion.models import odmo
from jaxmotion.nn.core import count_parameters
from jaxmotion.train.odmo import TeacherForcing, validation_split

TINY = odmo.ODMOConfig(num_joints=4, num_classes=3, num_frames=8, code_dim=5, encoder_hidden=6, encoder_width=7,
                       trajectory_hidden=8, motion_hidden=9)


def _lstm(d, h, layers):
    return sum(4 * h * ((d if i == 0 else h) + h) + 8 * h for i in range(layers))


def _linear(i, o):
    return i * o + o


def _hand_count(j, c, t, z=20):
    f, cond = 3 * j, c * z
    encoder = _lstm(f, 64, 1) + _linear(64, 256) + 2 * 256 + 1 + _linear(256, 256) + 2 * 256 + 1 + _linear(256, 2 * z)
    d = cond + 3
    trajectory = _linear(d, d * (t - 1)) + _linear(d, 128) + _lstm(128, 128, 2) + 3 * _linear(128, 128) + \
        _linear(128, 3) + 1
    motion = _linear(3, 128) + _lstm(128, 128, 2) + _linear(f + cond + 1, 128) + _lstm(128, 128, 2) + \
        _linear(128, f) + 1
    return encoder + trajectory + motion


@pytest.mark.parametrize("sizes,decoder_input", [("humanact12", 313), ("uestc", 855), ("mocap", 201)])
def test_parameter_counts_match_a_hand_count_of_the_authors_layers(sizes, decoder_input):
    config = getattr(odmo.ODMOConfig, sizes)()
    assert config.decoder_input == decoder_input
    params, _ = jax.eval_shape(lambda: odmo.init_odmo(jax.random.key(0), config))
    expected = _hand_count(config.num_joints, config.num_classes, config.num_frames)
    assert count_parameters(params) == expected
    if sizes == "humanact12":
        assert expected == 4_551_019  # the authors' Ensemble, counted in torch


def test_state_dict_uses_the_authors_names_and_round_trips():
    params, stats = odmo.init_odmo(jax.random.key(0), TINY)
    stats = jax.tree.map(lambda x: x + 0.5, stats)
    arrays = odmo.state_dict(params, stats)
    for name in ("tgenerator.expand.weight", "tgenerator.rnn.weight_hh_l1", "tgenerator.activation_fun.weight",
                 "LMPencoder.encoder.bias_ih_l0", "LMPencoder.fc.4.running_var", "LMPencoder.fc.5.weight",
                 "mgenerator.encoder_rnn.weight_ih_l0", "mgenerator.relu.weight", "mgenerator.out_fc.bias"):
        assert name in arrays
    assert arrays["tgenerator.expand.weight"].shape == (TINY.trajectory_input * 7, TINY.trajectory_input)
    back = odmo.load_state_dict(arrays, TINY)
    for a, b in zip(jax.tree.leaves((params, stats)), jax.tree.leaves(back), strict=True):
        np.testing.assert_array_equal(a, b)
    with pytest.raises(ValueError, match="missing 1 arrays"):
        odmo.load_state_dict({k: v for k, v in arrays.items() if k != "mgenerator.relu.weight"}, TINY)
    with pytest.raises(ValueError, match=r"mgenerator.out_fc.bias has shape \(3,\), expected \(12,\)"):
        odmo.load_state_dict({**arrays, "mgenerator.out_fc.bias": np.zeros(3)}, TINY)


def _poses(seed, b=4, config=TINY):
    return jax.random.normal(jax.random.key(seed), (b, config.num_frames, config.pose_dim))


def test_encoder_reads_the_motion_relative_to_its_root():
    params, stats = odmo.init_odmo(jax.random.key(1), TINY)
    poses = _poses(2)
    lmp = odmo.local_movement(poses)
    np.testing.assert_array_equal(lmp[..., :3], 0)
    shift = jnp.tile(jax.random.normal(jax.random.key(3), (4, TINY.num_frames, 3)), TINY.num_joints)
    moved = odmo.encode(TINY, params, stats, poses + shift, train=False)
    np.testing.assert_allclose(moved[0], odmo.encode(TINY, params, stats, poses, train=False)[0], atol=1e-5)
    whole = dataclasses.replace(TINY, lmp_input=False)
    assert not np.allclose(odmo.encode(whole, params, stats, poses + shift, train=False)[0],
                           odmo.encode(whole, params, stats, poses, train=False)[0], atol=1e-3)


def test_condition_is_the_class_major_outer_product_and_integration_starts_at_the_origin():
    code = jnp.arange(10.0).reshape(2, 5)
    cond = odmo.condition(jnp.array([2, 0]), code, 3)
    np.testing.assert_array_equal(cond[0, 10:15], code[0])
    np.testing.assert_array_equal(cond[1, :5], code[1])
    assert float(jnp.abs(cond).sum()) == float(jnp.abs(code).sum())
    v = jax.random.normal(jax.random.key(0), (2, 7, 3))
    positions = odmo.integrate(v)
    np.testing.assert_array_equal(positions[:, 0], 0)
    np.testing.assert_allclose(jnp.diff(positions, axis=1), v, atol=1e-6)
    np.testing.assert_allclose(np.asarray(odmo.time_feature(60))[[0, -1]], [1 / 60, 1.0], rtol=1e-6)


def test_teacher_forcing_is_causal_and_off_by_default():
    params, _ = odmo.init_odmo(jax.random.key(4), TINY)
    code, actions = jax.random.normal(jax.random.key(5), (3, 5)), jnp.array([0, 1, 2])
    trajectory, teacher = jax.random.normal(jax.random.key(6), (3, 8, 3)), _poses(7, 3)
    free = odmo.decode_motion(params, code, actions, trajectory, TINY)
    np.testing.assert_array_equal(free, odmo.decode_motion(params, code, actions, trajectory, TINY, teacher=teacher))
    forced = odmo.decode_motion(params, code, actions, trajectory, TINY, teacher=teacher,
                                teacher_mask=jnp.ones(8, bool))
    changed = teacher.at[:, 4:].add(1.0)  # frames from 4 on reach outputs 5, 6, 7 only
    again = odmo.decode_motion(params, code, actions, trajectory, TINY, teacher=changed, teacher_mask=jnp.ones(8, bool))
    np.testing.assert_array_equal(again[:, :5], forced[:, :5])
    assert not np.allclose(again[:, 5:], forced[:, 5:])
    np.testing.assert_array_equal(forced[:, 0], free[:, 0])  # the first step reads zeros either way
    # a per-row mask: row 1 forced, rows 0 and 2 free
    rows = odmo.decode_motion(params, code, actions, trajectory, TINY, teacher=teacher,
                              teacher_mask=jnp.zeros((8, 3), bool).at[:, 1].set(True))
    np.testing.assert_allclose(np.asarray(rows)[[0, 2]], np.asarray(free)[[0, 2]], atol=1e-6)
    np.testing.assert_allclose(rows[1], forced[1], atol=1e-6)


def test_the_end_root_steers_the_trajectory_only_with_use_end():
    params, _ = odmo.init_odmo(jax.random.key(8), TINY)
    code, actions = jax.random.normal(jax.random.key(9), (2, 5)), jnp.array([0, 1])
    ends = [jnp.zeros((2, 3)), jnp.ones((2, 3))]
    with_end = [odmo.trajectory_velocities(params, code, actions, e, TINY) for e in ends]
    assert not np.allclose(*with_end)
    no_end = dataclasses.replace(TINY, use_end=False)
    np.testing.assert_array_equal(*[odmo.trajectory_velocities(params, code, actions, e, no_end) for e in ends])


def test_pair_halves_are_normalised_apart_as_two_passes():
    params, stats = odmo.init_odmo(jax.random.key(10), TINY)
    first, second = _poses(11), _poses(12)
    mu_1, _, stats_1 = odmo.encode(TINY, params, stats, first, train=True)
    mu_2, _, stats_2 = odmo.encode(TINY, params, stats_1, second, train=True)
    mu, _, together = odmo.encode(TINY, params, stats, jnp.concatenate([first, second]), train=True, groups=2)
    np.testing.assert_allclose(mu, jnp.concatenate([mu_1, mu_2]), atol=1e-5)
    for a, b in zip(jax.tree.leaves(together), jax.tree.leaves(stats_2), strict=True):
        np.testing.assert_allclose(a, b, atol=1e-6)
    # eval mode: each sequence's code does not depend on the rest of the batch
    alone = odmo.encode(TINY, params, stats_2, first[:1], train=False)[0]
    np.testing.assert_allclose(alone, odmo.encode(TINY, params, stats_2, first, train=False)[0][:1], atol=1e-6)


def test_forward_and_generate_name_the_field_of_bad_input():
    params, stats = odmo.init_odmo(jax.random.key(0), TINY)
    with pytest.raises(ValueError, match=r"poses: expected \[B, 8, 12\]"):
        odmo.forward(TINY, params, stats, jnp.zeros((2, 7, 12)), jnp.zeros(2, jnp.int32), key=jax.random.key(0),
                     train=False)
    with pytest.raises(ValueError, match="actions"):
        odmo.generate(TINY, params, jnp.zeros((2, 5)), jnp.array([0, 3]), jnp.zeros((2, 3)))
    with pytest.raises(ValueError, match=r"end: expected \[2, 3\]"):
        odmo.generate(TINY, params, jnp.zeros((2, 5)), jnp.array([0, 1]), jnp.zeros((2, 2)))
    with pytest.raises(ValueError, match=r"code: expected \[B, 5\]"):
        odmo.generate(TINY, params, jnp.zeros((2, 4)), jnp.array([0, 1]), jnp.zeros((2, 3)))


# ----------------------------------------------------------------------------------------------- losses


def test_kl_vanishes_at_the_prior_spread_and_the_prior_switch_reads_the_scale_as_std_or_variance():
    code_std = ODMOLossConfig()
    paper = ODMOLossConfig(prior="variance")
    assert code_std.prior_std == 0.05 and paper.prior_std == pytest.approx(0.05 ** 0.5)
    at_prior = jnp.full((1, 20), 2 * np.log(0.05))
    np.testing.assert_allclose(prior_kl(at_prior, code_std.prior_std), 0, atol=1e-5)
    assert float(prior_kl(at_prior, paper.prior_std)[0]) > 1.0
    # KL(N(0, s²) ‖ N(0, p²)) = log(p/s) + s²/(2p²) − ½ per dimension
    s, p = 0.3, 0.1
    np.testing.assert_allclose(prior_kl(jnp.full((1, 2), 2 * np.log(s)), p), 2 * (np.log(p / s) + s**2 / (2 * p**2) - 0.5),
                               rtol=1e-5)


def test_contrastive_loss_on_hand_made_pairs():
    config = ODMOLossConfig()
    mu_1 = jnp.zeros((4, 2))
    mu_2 = jnp.array([[1.0, 0.0], [0.3, 0.0], [3.0, 0.0], [6.0, 0.0]])
    same = jnp.array([True, True, False, False])
    np.testing.assert_allclose(contrastive_loss(mu_1, mu_2, same, config), [0.5 * 0.75, 0.0, 0.5 * 4.0, 0.0],
                               rtol=1e-5, atol=1e-7)
    paper = ODMOLossConfig(same_class="squared")
    np.testing.assert_allclose(contrastive_loss(mu_1, mu_2, same, paper)[:2], [0.5, 0.5 * 0.09], rtol=1e-5)


def test_frame_errors_weight_the_vertical_coordinate_and_sum_over_frames():
    target = jnp.zeros((1, 5, 6))
    np.testing.assert_allclose(weighted_frame_error(target.at[..., 1].set(1.0), target, 5.0), [5 * 5 / 6])
    np.testing.assert_allclose(weighted_frame_error(target.at[..., 3].set(1.0), target, 5.0), [5 / 6])


def _out(seed, b=3, t=6, f=6):
    keys = jax.random.split(jax.random.key(seed), 4)
    velocities = jax.random.normal(keys[0], (b, t - 1, 3))
    return {"velocities": velocities, "trajectory": odmo.integrate(velocities),
            "poses": jax.random.normal(keys[1], (b, t, f)), "mu": jax.random.normal(keys[2], (b, 5)),
            "logvar": jax.random.normal(keys[3], (b, 5))}


def test_trajectory_loss_modes_and_ablation_switches():
    out, poses = _out(0), jax.random.normal(jax.random.key(1), (3, 6, 6))
    exact = {**out, "trajectory": poses[..., :3], "poses": poses}
    np.testing.assert_allclose(trajectory_loss(exact, poses, ODMOLossConfig()), 0, atol=1e-6)
    velocity_target = {**out, "velocities": jnp.diff(poses[..., :3], axis=1)}
    eq2 = ODMOLossConfig(trajectory="velocities", consistency=False)
    np.testing.assert_allclose(trajectory_loss(velocity_target, poses, eq2), 0, atol=1e-6)
    consistency = trajectory_loss(out, poses, ODMOLossConfig()) - trajectory_loss(out, poses, ODMOLossConfig(
        consistency=False))
    np.testing.assert_allclose(consistency, jnp.square(out["poses"][..., :3] - out["trajectory"]).mean(-1).sum(-1),
                               rtol=1e-5)
    other, same = _out(2), jnp.array([True, False, True])
    full, terms = pair_loss(out, other, poses, poses, same, ODMOLossConfig())
    np.testing.assert_allclose(full, terms["motion"] + terms["kl"] + terms["trajectory"] + terms["contrastive"],
                               rtol=1e-6)
    no_es, _ = pair_loss(out, other, poses, poses, same, ODMOLossConfig(contrastive=False))
    no_traj, _ = pair_loss(out, other, poses, poses, same, ODMOLossConfig(trajectory_loss=False))
    np.testing.assert_allclose(no_es, full - terms["contrastive"], rtol=1e-6)
    np.testing.assert_allclose(no_traj, full - terms["trajectory"], rtol=1e-6)


def test_loss_config_rejects_unknown_switch_values():
    with pytest.raises(ValueError, match="ODMOLossConfig.prior"):
        ODMOLossConfig(prior="precision")
    with pytest.raises(ValueError, match="ODMOLossConfig.trajectory"):
        ODMOLossConfig(trajectory="accelerations")


# --------------------------------------------------------------------------------------------- training


def test_teacher_forcing_decays_per_epoch_to_its_floor():
    schedule = TeacherForcing()
    rates = np.asarray([schedule.rate(s) for s in (0, 3, 4, 8000, 16_000, 40_000)])
    np.testing.assert_allclose(rates, [1.0, 1.0, 1 - 0.7 / 4000, 0.65, 0.3, 0.3], rtol=1e-6)


def test_validation_split_is_disjoint_seeded_and_sized_like_the_code():
    class Fake:
        def __len__(self):
            return 95

    fake: MotionDataset = Fake()  # only its length is read
    train, held = validation_split(fake, jax.random.key(0), 0.1)
    assert len(held) == 9 and len(train) == 86 and not set(train) & set(held)
    again = validation_split(fake, jax.random.key(0), 0.1)
    np.testing.assert_array_equal(held, again[1])
    assert len(validation_split(fake, jax.random.key(0), 0.001)[1]) == 1
    assert len(validation_split(fake, jax.random.key(0), 0.0)[1]) == 0
