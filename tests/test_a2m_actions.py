"""Neural Marionette's adapted A2M: one code path with the original (class ids = their one-hot condition, a zero
first pose = the original's), generation with MARIONET's contract (shape, zero padding, independence of the batch's
longest action, determinism with and without a key), a few deterministic training steps on action items, and
errors that name the field."""

import dataclasses
import json

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.data import synthetic
from jaxmotion.models.a2m import A2MVAEConfig, a2m_continue, a2m_generate, a2m_vae_forward, a2m_vae_loss, init_a2m_vae
from jaxmotion.train.a2m import A2MActionTraining, train_a2m_actions
from jaxmotion.train.loop import LoopConfig

F, C, B, T, K = 9, 4, 3, 6, 6
CFG = A2MVAEConfig(pose_dim=F, num_classes=C, kl_weight=1e-2, hidden=8, latent=4)
CONTINUE = jax.jit(a2m_continue, static_argnums=1)


@pytest.fixture(scope="module")
def params():
    return init_a2m_vae(jax.random.key(0), CFG)


def _inputs(seed=0, b=B, t=T):
    rng = np.random.default_rng(seed)
    poses = jnp.asarray(rng.standard_normal((b, t, F)), jnp.float32)
    context = jnp.asarray(rng.standard_normal((b, K, F)), jnp.float32)
    tags = jnp.asarray(rng.random((b, C)) < 0.5)
    return poses, context, tags


def test_class_ids_equal_their_one_hot_condition_and_zero_first_pose_equals_the_original(params):
    poses, _, _ = _inputs()
    ids = jnp.array([0, 3, 1])
    one_hot = jax.nn.one_hot(ids, C)
    key = jax.random.key(1)
    mask = jnp.asarray(np.arange(T)[None] < np.array([[4], [T], [2]]))
    original, _ = a2m_vae_loss(CFG, params, poses, ids, key=key, mask=mask)
    for condition, first in ((one_hot, None), (one_hot > 0, None), (ids, jnp.zeros((B, F)))):
        loss, _ = a2m_vae_loss(CFG, params, poses, condition, key=key, mask=mask, first_pose=first)
        assert float(loss) == float(original)
    np.testing.assert_array_equal(a2m_generate(CFG, params, one_hot, 5, key=key, first_pose=jnp.zeros((B, F))),
                                  a2m_generate(CFG, params, ids, 5, key=key))
    # A first pose reaches frame 0's decoding in training and in generation.
    first = jnp.ones((B, F))
    out = a2m_vae_forward(CFG, params, poses, ids, key=key, first_pose=first)["recon"]
    assert not np.allclose(out[:, 0], a2m_vae_forward(CFG, params, poses, ids, key=key)["recon"][:, 0])
    assert not np.allclose(a2m_generate(CFG, params, ids, 2, key=key, first_pose=first),
                           a2m_generate(CFG, params, ids, 2, key=key))


def test_continue_shape_zero_padding_and_first_pose_is_the_last_context_pose(params):
    _, context, tags = _inputs(2)
    durations = np.array([4, T, 1])
    mask = jnp.asarray(np.arange(T)[None] < durations[:, None])
    path = jnp.ones((B, T, 2))
    out = CONTINUE(params, CFG, context, tags, tags, path, mask, jax.random.key(3))
    assert out.shape == (B, T, F)
    np.testing.assert_array_equal(np.asarray(out)[~np.asarray(mask)], 0.0)
    assert (np.abs(np.asarray(out)[np.asarray(mask)]).sum(-1) > 0).all()
    # a2m_generate with the last context pose first and each row's own duration gives the same frames.
    for row, duration in enumerate(durations):
        alone = a2m_generate(CFG, params, tags[row:row + 1], int(duration), key=None, first_pose=context[row:row + 1, -1])
        np.testing.assert_allclose(CONTINUE(params, CFG, context, tags, tags, path, mask, None)[row, :duration],
                                   alone[0], rtol=1e-6, atol=1e-6)
    # next_tags, path and the context before its last pose are not read.
    other = CONTINUE(params, CFG, context.at[:, :-1].set(5.0), tags, ~tags, -path, mask, jax.random.key(3))
    np.testing.assert_array_equal(out, other)


def test_an_actions_frames_do_not_depend_on_the_batchs_longest(params):
    _, context, tags = _inputs(4)
    durations = np.array([3, 5, 2])
    for key in (None, jax.random.key(5)):
        short = CONTINUE(params, CFG, context, tags, tags, jnp.zeros((B, 5, 2)),
                         jnp.asarray(np.arange(5)[None] < durations[:, None]), key)
        long = CONTINUE(params, CFG, context, tags, tags, jnp.zeros((B, 11, 2)),
                        jnp.asarray(np.arange(11)[None] < durations[:, None]), key)
        np.testing.assert_allclose(long[:, :5], short, rtol=1e-6, atol=1e-6)
        np.testing.assert_array_equal(np.asarray(long)[:, 5:], 0.0)


def test_continue_is_deterministic_given_its_key_and_the_mean_without_one(params):
    _, context, tags = _inputs(6)
    mask, path = jnp.ones((B, T), bool), jnp.zeros((B, T, 2))
    mean = CONTINUE(params, CFG, context, tags, tags, path, mask, None)
    np.testing.assert_array_equal(mean, CONTINUE(params, CFG, context, tags, tags, path, mask, None))
    np.testing.assert_array_equal(mean, a2m_continue(params, CFG, context, tags, tags, path, mask))  # eager = jit
    drawn = CONTINUE(params, CFG, context, tags, tags, path, mask, jax.random.key(7))
    np.testing.assert_array_equal(drawn, CONTINUE(params, CFG, context, tags, tags, path, mask, jax.random.key(7)))
    assert not np.allclose(drawn, CONTINUE(params, CFG, context, tags, tags, path, mask, jax.random.key(8)))
    assert not np.allclose(drawn, mean)


def test_errors_name_the_field(params):
    poses, context, tags = _inputs()
    mask, path = jnp.ones((B, T), bool), jnp.zeros((B, T, 2))
    cases = {
        "context": (context[..., :4], tags, tags, path, mask),
        "tags": (context, tags[:, :2], tags, path, mask),
        "next_tags": (context, tags, tags[:2], path, mask),
        "path": (context, tags, tags, path[:, :-1], mask),
        "mask": (context, tags, tags, path, mask[0]),
    }
    for field, args in cases.items():
        with pytest.raises(ValueError, match=f"^{field}: expected"):
            a2m_continue(params, CFG, *args)
    with pytest.raises(ValueError, match=r"^actions: expected a \[3, 4\] condition"):
        a2m_vae_loss(CFG, params, poses, jnp.ones((B, C + 1)), key=jax.random.key(0))
    with pytest.raises(ValueError, match="^first_pose: expected shape"):
        a2m_vae_loss(CFG, params, poses, tags, key=jax.random.key(0), first_pose=jnp.zeros((B, F + 1)))
    with pytest.raises(ValueError, match="^first_pose: expected shape"):
        a2m_generate(CFG, params, tags, 3, key=None, first_pose=jnp.zeros((1, F)))
    with pytest.raises(ValueError, match="A2MActionTraining.model: expected pose_dim 135"):
        A2MActionTraining(model=CFG)


TRAINING = A2MActionTraining(model=A2MVAEConfig(pose_dim=135, num_classes=31, kl_weight=1e-3, hidden=8, latent=4),
                             loop=LoopConfig(steps=4, log_every=2, checkpoint_every=0), batch_size=4)


@pytest.fixture(scope="module")
def takes():
    return synthetic.generate("synth-mag", "test", seed=0, count=6, progress=False)


def test_a_few_training_steps_on_action_items_are_deterministic_with_finite_losses(takes, tmp_path):
    runs = [train_a2m_actions(takes, TRAINING, jax.random.key(5), tmp_path / name, progress=False)
            for name in ("a", "b")]
    for a, b in zip(jax.tree.leaves(runs[0]), jax.tree.leaves(runs[1]), strict=True):
        np.testing.assert_array_equal(a, b)
    assert all(np.isfinite(np.asarray(leaf)).all() for leaf in jax.tree.leaves(runs[0]))
    logs = [(tmp_path / name / "metrics.jsonl").read_text() for name in ("a", "b")]
    assert logs[0] == logs[1]
    log = [json.loads(line) for line in logs[0].splitlines()]
    assert [record["step"] for record in log] == [2, 4]
    assert all(np.isfinite(record[name]) and record[name] > 0 for record in log for name in ("loss", "recon", "kl"))
    # The trained model continues an action item.
    poses = a2m_continue(runs[0], TRAINING.model, jnp.zeros((1, 6, 135)), jnp.zeros((1, 31)).at[0, 3].set(1.0),
                         jnp.zeros((1, 31)), jnp.zeros((1, 7, 2)), jnp.ones((1, 7), bool))
    assert poses.shape == (1, 7, 135) and np.isfinite(np.asarray(poses)).all()


def test_training_refuses_data_it_cannot_read(takes):
    model = dataclasses.replace(TRAINING.model, num_classes=12)
    with pytest.raises(ValueError, match="A2MActionTraining.model.num_classes: 12, but synth-mag has 31 tags"):
        train_a2m_actions(takes, dataclasses.replace(TRAINING, model=model), jax.random.key(0))
