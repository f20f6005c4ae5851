"""MARIONET, test-sized: shapes, cached frame-by-frame generation against the uncached loop, padding that changes
nothing, the ablation switches, finite gradients."""

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.models import marionet as mn

CONFIG = mn.MarionetConfig.tiny()
B, T, C = 3, 8, 31


def _inputs(seed, frames=T, lengths=(8, 5, 3)):
    rng = np.random.default_rng(seed)
    tags = np.zeros((B, C), np.float32)
    tags[np.arange(B), [0, 7, 24]] = 1.0
    tags[2, 28] = 1.0  # a state with a body part
    next_tags = np.roll(tags, 1, axis=0)
    mask = np.arange(frames)[None] < np.array(lengths)[:, None]
    path = np.cumsum(0.05 * rng.normal(size=(B, frames, 2)), axis=1) * mask[..., None]
    return dict(context=jnp.asarray(0.3 * rng.normal(size=(B, mn.CONTEXT, 135)), jnp.float32),
                tags=jnp.asarray(tags), next_tags=jnp.asarray(next_tags),
                path=jnp.asarray(path, jnp.float32), mask=jnp.asarray(mask))


@pytest.fixture(scope="module")
def params():
    return jax.jit(mn.init_marionet, static_argnums=1)(jax.random.key(0), CONFIG)


_generate = jax.jit(mn.generate, static_argnums=1)
_decode = jax.jit(mn.decode, static_argnums=1)
_forward = jax.jit(mn.forward, static_argnums=1)


def test_generation_through_the_cache_equals_the_uncached_frame_by_frame_loop(params):
    """The paper decodes one frame at a time by re-running the decoder on everything so far; the cache must give
    the same poses."""
    x = _inputs(1)
    poses = np.asarray(_generate(params, CONFIG, x["context"], x["tags"], x["next_tags"], x["path"], x["mask"]))
    assert poses.shape == (B, T, 135)
    mu, _ = mn.encode(params, CONFIG, x["context"], x["tags"], x["next_tags"])
    frame_controls = mn.controls(params, CONFIG, mu, x["tags"], x["path"], x["mask"])
    made = np.zeros((B, T, 135), np.float32)
    for t in range(T):  # each frame from a full causal pass over the poses made so far
        previous = np.concatenate([np.asarray(x["context"][:, -1:]), made[:, :-1]], axis=1)
        made[:, t] = np.asarray(_decode(params, CONFIG, frame_controls, jnp.asarray(previous), x["mask"]))[:, t]
    np.testing.assert_allclose(poses, made, atol=1e-5)
    np.testing.assert_array_equal(poses[1, 5:], 0.0)  # padding
    assert np.abs(poses[0]).max() > 0.01


def test_an_action_does_not_depend_on_how_far_its_batch_is_padded(params):
    x = _inputs(2)
    wide = {**x, "path": jnp.pad(x["path"], ((0, 0), (0, 4), (0, 0))), "mask": jnp.pad(x["mask"], ((0, 0), (0, 4)))}
    short = _generate(params, CONFIG, **{k: x[k] for k in ("context", "tags", "next_tags", "path", "mask")})
    long = _generate(params, CONFIG, **{k: wide[k] for k in ("context", "tags", "next_tags", "path", "mask")})
    np.testing.assert_allclose(long[:, :T], short, atol=1e-5)


def test_a_teacher_forced_pass_reads_each_previous_true_pose_and_samples_z_with_a_key(params):
    x = _inputs(3)
    target = jax.random.normal(jax.random.key(1), (B, T, 135))
    out = _forward(params, CONFIG, x["context"], x["tags"], x["next_tags"], x["path"], target, x["mask"])
    assert out.poses.shape == (B, T, 135) and out.mu.shape == out.log_variance.shape == (B, CONFIG.width)
    changed = target.at[:, 4].add(1.0)  # frame 4 is read by frame 5 and later only (causal)
    again = _forward(params, CONFIG, x["context"], x["tags"], x["next_tags"], x["path"], changed, x["mask"])
    np.testing.assert_allclose(again.poses[:, :5], out.poses[:, :5], atol=1e-6)
    assert np.abs(np.asarray(again.poses[0, 5:] - out.poses[0, 5:])).max() > 1e-4
    sampled = _forward(params, CONFIG, x["context"], x["tags"], x["next_tags"], x["path"], target, x["mask"],
                       jax.random.key(2))
    assert np.abs(np.asarray(sampled.poses - out.poses)).max() > 1e-4  # Z drawn, dropout on


def test_ablation_switches_remove_what_they_name(params):
    x = _inputs(4)
    other_next = jnp.roll(x["next_tags"], 1, axis=0)
    plain = dataclasses.replace(CONFIG, next_tag=False)
    mu, _ = mn.encode(params, plain, x["context"], x["tags"], x["next_tags"])
    mu_other, _ = mn.encode(params, plain, x["context"], x["tags"], other_next)
    np.testing.assert_array_equal(mu, mu_other)  # no next tag: zeros in, whatever it is
    z = jnp.ones((B, CONFIG.width))
    flat = mn.controls(params, dataclasses.replace(CONFIG, time_unrolling=False), z, x["tags"], x["path"], x["mask"])
    np.testing.assert_allclose(flat[:, 0, :-CONFIG.path_width], flat[:, 3, :-CONFIG.path_width])  # one control
    injected = mn.controls(params, CONFIG, z, x["tags"], x["path"], x["mask"])
    bare = mn.controls(params, dataclasses.replace(CONFIG, tag_injection=False), z, x["tags"], x["path"], x["mask"])
    other_tags = mn.controls(params, dataclasses.replace(CONFIG, tag_injection=False), z, jnp.roll(x["tags"], 1, 0),
                             x["path"], x["mask"])
    np.testing.assert_array_equal(bare, other_tags)  # without tag injection the tags do not reach the unrolling
    assert np.abs(np.asarray(injected - bare)).max() > 1e-4


def test_gradients_of_a_training_pass_are_finite(params):
    x = _inputs(5)
    target = jax.random.normal(jax.random.key(3), (B, T, 135))

    def loss(p):
        out = mn.forward(p, CONFIG, x["context"], x["tags"], x["next_tags"], x["path"], target, x["mask"],
                         jax.random.key(4))
        return jnp.mean((out.poses - target) ** 2) + jnp.mean(out.mu ** 2)

    grads = jax.jit(jax.grad(loss))(params)
    leaves = jax.tree.leaves(grads)
    assert all(np.isfinite(np.asarray(g)).all() for g in leaves)
    assert sum(float(jnp.abs(g).sum()) for g in leaves) > 0


def test_configs_refuse_what_they_cannot_build():
    with pytest.raises(ValueError, match="MarionetConfig.heads: must divide width 32, got 3"):
        mn.MarionetConfig.tiny(heads=3)
    with pytest.raises(ValueError, match=r"MarionetConfig.path_width: expected fewer than width \(32\)"):
        mn.MarionetConfig.tiny(path_width=32)
