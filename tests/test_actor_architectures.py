"""ACTOR's Table 2 architectures (transformer, GRU, FC, autoregressive Transformer): shapes, masking,
determinism, causality, parameter counts and one training step each."""

import functools

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.geometry.skeletons import SMPL24
from jaxmotion.losses.actor import ActorLossWeights, actor_loss
from jaxmotion.models.actor import (
    ARCHITECTURES,
    ActorConfig,
    autoencode,
    decode,
    encode,
    generate,
    init_actor,
    length_mask,
)

FRAMES = 8
X = jax.random.normal(jax.random.key(1), (2, FRAMES, 25, 6))
ACTIONS = jnp.array([0, 2])
MASK = length_mask(jnp.array([FRAMES, 5]), FRAMES)  # row 1 has 3 padded frames


@functools.cache
def config(architecture: str, dropout: float = 0.0) -> ActorConfig:
    # Dropout off by default; test_autoregressive_dropout_runs_only_with_a_key and test_actor.py cover it.
    return ActorConfig(num_classes=3, width=16, ff=32, layers=2, heads=4, dropout=dropout,
                       architecture=architecture, frames=FRAMES)


@functools.cache
def params(architecture: str):
    return init_actor(jax.random.key(0), config(architecture))


# Jitted once per architecture and shared by the tests: compilation dominates their time.
@functools.cache
def jitted_training_step(architecture: str):
    """``(params, key) -> ((loss, autoencode's outputs), grads)`` on (X, ACTIONS, MASK), train=True."""
    cfg = config(architecture)

    def loss_fn(p, key):
        out = autoencode(cfg, p, X, ACTIONS, MASK, key=key, train=True)
        loss, _ = actor_loss(out["output"], X, MASK, out["mu"], out["logvar"], rep="rot6d",
                             weights=ActorLossWeights(), skeleton=SMPL24)
        return loss, out

    return jax.jit(jax.value_and_grad(loss_fn, has_aux=True))


@functools.cache
def jitted_decode(architecture: str):
    return jax.jit(lambda p, z, a, m, target: decode(config(architecture), p, z, a, m, target=target))


@functools.cache
def jitted_generate(architecture: str):
    return jax.jit(lambda p, k, a, d: generate(config(architecture), p, a, d, FRAMES, key=k))


def parameter_count(tree) -> int:
    return sum(int(np.prod(leaf.shape)) for leaf in jax.tree.leaves(tree))


@pytest.mark.parametrize("architecture", ARCHITECTURES)
def test_reconstruction_has_the_input_shape_zero_padding_and_depends_only_on_the_key(architecture):
    key = jax.random.key(2)
    (_, out), _ = jitted_training_step(architecture)(params(architecture), key)
    (_, again), _ = jitted_training_step(architecture)(params(architecture), key)
    output = np.asarray(out["output"])
    assert output.shape == X.shape and np.isfinite(output).all()
    assert np.abs(output[1, 5:]).max() == 0.0 and np.abs(output[1, :5]).max() > 0.0
    np.testing.assert_array_equal(output, np.asarray(again["output"]))


@pytest.mark.parametrize("architecture", ARCHITECTURES)
def test_generation_has_the_requested_shape_and_mask_and_depends_only_on_the_key(architecture):
    durations = jnp.array([5, FRAMES])
    a, mask = jitted_generate(architecture)(params(architecture), jax.random.key(3), ACTIONS, durations)
    b, _ = jitted_generate(architecture)(params(architecture), jax.random.key(3), ACTIONS, durations)
    c, _ = jitted_generate(architecture)(params(architecture), jax.random.key(4), ACTIONS, durations)
    assert a.shape == (2, FRAMES, 25, 6) and np.isfinite(np.asarray(a)).all()
    np.testing.assert_array_equal(np.asarray(mask.sum(1)), [5, FRAMES])
    assert float(jnp.abs(a[0, 5:]).max()) == 0.0
    np.testing.assert_array_equal(np.asarray(a), np.asarray(b))
    assert not np.allclose(np.asarray(a), np.asarray(c))


def test_gru_encoder_ignores_padded_frames():
    p, cfg = params("gru"), config("gru")
    mu, logvar = encode(cfg, p, X, ACTIONS, MASK)
    mu2, logvar2 = encode(cfg, p, X.at[1, 5:].set(100.0), ACTIONS, MASK)
    np.testing.assert_array_equal(np.asarray(mu2), np.asarray(mu))
    np.testing.assert_array_equal(np.asarray(logvar2), np.asarray(logvar))
    mu3, _ = encode(cfg, p, X.at[1, 4].set(100.0), ACTIONS, MASK)  # the last real frame does count
    assert not np.allclose(np.asarray(mu3[1]), np.asarray(mu[1]))


def test_gru_decoder_rows_do_not_depend_on_their_batch_neighbours():
    z = jax.random.normal(jax.random.key(5), (2, 16))
    out = jitted_decode("gru")(params("gru"), z, ACTIONS, MASK, None)
    other = jitted_decode("gru")(params("gru"), z.at[0].set(5.0), ACTIONS.at[0].set(1), MASK, None)
    np.testing.assert_array_equal(np.asarray(other[1]), np.asarray(out[1]))
    assert not np.allclose(np.asarray(other[0]), np.asarray(out[0]))


def test_autoregressive_teacher_forced_frame_t_depends_only_on_target_frames_before_t():
    # The decoder reads the target shifted by one frame, so output t sees target[:, :t]: perturbing the
    # target from frame 3 on leaves outputs 0..3 unchanged and changes output 4.
    z = jax.random.normal(jax.random.key(6), (2, 16))
    p = params("autoregressive")
    out = jitted_decode("autoregressive")(p, z, ACTIONS, MASK, X)
    perturbed = jitted_decode("autoregressive")(p, z, ACTIONS, MASK, X.at[:, 3:].add(1.0))
    np.testing.assert_allclose(np.asarray(perturbed[:, :4]), np.asarray(out[:, :4]), atol=1e-6)
    assert not np.allclose(np.asarray(perturbed[:, 4]), np.asarray(out[:, 4]), atol=1e-3)


def test_autoregressive_frame_by_frame_decoding_equals_teacher_forcing_on_its_own_output():
    z = jax.random.normal(jax.random.key(7), (2, 16))
    p = params("autoregressive")
    free = jitted_decode("autoregressive")(p, z, ACTIONS, MASK, None)
    forced = jitted_decode("autoregressive")(p, z, ACTIONS, MASK, free)
    assert float(jnp.abs(free).max()) > 0.0
    np.testing.assert_allclose(np.asarray(forced), np.asarray(free), atol=1e-5)


@pytest.mark.parametrize("batch", [2, 32])
def test_autoregressive_cached_generation_equals_recomputing_the_causal_pass_for_every_frame(batch):
    # The decoding before the key/value cache: for every frame t, one full causal pass (teacher forcing on the
    # frames decoded so far, zeros after) whose frame t is kept. Row 1 has padded frames.
    z = jax.random.normal(jax.random.key(12), (batch, 16))
    actions = jnp.arange(batch) % 3
    mask = length_mask(jnp.array([FRAMES, 5] * (batch // 2)), FRAMES)
    p = params("autoregressive")
    recomputed = jnp.zeros((batch, FRAMES, 25, 6))
    for t in range(FRAMES):
        recomputed = recomputed.at[:, t].set(jitted_decode("autoregressive")(p, z, actions, mask, recomputed)[:, t])
    cached = jitted_decode("autoregressive")(p, z, actions, mask, None)
    assert float(jnp.abs(cached[1, :5]).min()) > 0.0 and float(jnp.abs(cached[1, 5:]).max()) == 0.0
    np.testing.assert_allclose(np.asarray(cached), np.asarray(recomputed), atol=1e-5, rtol=0)


def test_autoregressive_frame_by_frame_decoding_takes_no_dropout_key():
    z = jnp.zeros((2, 16))
    with pytest.raises(ValueError, match=r"key: frame-by-frame autoregressive decoding \(no target\) runs in eval"):
        decode(config("autoregressive"), params("autoregressive"), z, ACTIONS, MASK, key=jax.random.key(0))


def test_autoregressive_dropout_runs_only_with_a_key():
    cfg = config("autoregressive", dropout=0.1)
    p, z = init_actor(jax.random.key(0), cfg), jax.random.normal(jax.random.key(10), (2, 16))
    run = jax.jit(lambda key: decode(cfg, p, z, ACTIONS, MASK, key=key, target=X))
    key = jax.random.key(11)
    np.testing.assert_array_equal(np.asarray(run(key)), np.asarray(run(key)))
    off = decode(cfg, p, z, ACTIONS, MASK, target=X)
    np.testing.assert_array_equal(np.asarray(off), np.asarray(decode(cfg, p, z, ACTIONS, MASK, target=X)))
    assert not np.allclose(np.asarray(run(key)), np.asarray(off))


def test_fc_rejects_a_clip_length_other_than_config_frames():
    p, cfg = params("fc"), config("fc")
    short_mask = MASK[:, :6]
    with pytest.raises(ValueError, match=r"T: architecture 'fc' takes exactly ActorConfig.frames = 8 .* got T = 6"):
        encode(cfg, p, X[:, :6], ACTIONS, short_mask)
    with pytest.raises(ValueError, match=r"ActorConfig.frames = 8"):
        decode(cfg, p, jnp.zeros((2, 16)), ACTIONS, short_mask)
    with pytest.raises(ValueError, match=r"ActorConfig.frames = 8"):
        generate(cfg, p, ACTIONS, jnp.array([6, 6]), 6, key=jax.random.key(0))


def test_fc_outputs_never_fall_below_gelu_minimum():
    # ACTOR's FC decoder applies GELU to its output layer too; exact GELU's minimum is -0.16997 (at x ≈ -0.75),
    # so even latents far out in the tails cannot produce a real frame value below it.
    z = 10.0 * jax.random.normal(jax.random.key(8), (2, 16))
    out = np.asarray(jitted_decode("fc")(params("fc"), z, ACTIONS, MASK, None))
    assert out.min() >= -0.17 and (out < -0.05).any()


def test_gru_parameter_count_matches_a_hand_count():
    d, k, feats, layers = 16, 3, 25 * 6, 2
    gru_layer = 3 * d * d + 3 * d * d + 3 * d + 3 * d  # w_ih, w_hh, b_ih, b_hh (input width d)
    encoder = (feats + k + 1) * d + d + layers * gru_layer + 2 * (d * d + d)  # embedding, GRU, mu / var
    decoder = (d + k + 1) * d + d + layers * gru_layer + (d * feats + feats)  # embedding, GRU, final layer
    assert parameter_count(params("gru")) == encoder + decoder == 12438


def test_fc_parameter_count_matches_a_hand_count():
    d, k, flat = 16, 3, 25 * 6 * FRAMES
    encoder = (flat + k) * 2 * d + 2 * d + (2 * d * d + d) + 2 * (d * d + d)  # -> 2d -> d, then mu / logvar
    decoder = (d + k) * d + d + (d * 2 * d + 2 * d) + (2 * d * flat + flat)  # -> d -> 2d -> J·C·T
    assert parameter_count(params("fc")) == encoder + decoder == 80064


@pytest.mark.parametrize("architecture", ARCHITECTURES)
def test_one_jitted_training_step_gives_finite_nonzero_gradients_for_every_parameter(architecture):
    (loss, _), grads = jitted_training_step(architecture)(params(architecture), jax.random.key(9))
    assert np.isfinite(float(loss))
    named = jax.tree_util.tree_leaves_with_path(grads)
    assert len(named) == len(jax.tree.leaves(params(architecture)))
    for path, grad in named:
        name = jax.tree_util.keystr(path)
        assert np.isfinite(np.asarray(grad)).all(), name
        assert np.abs(np.asarray(grad)).max() > 0.0, f"{name} gets no gradient"


def test_config_names_the_field_for_unknown_architectures_and_misplaced_switches():
    with pytest.raises(ValueError, match=r"ActorConfig.architecture: expected one of"):
        ActorConfig(num_classes=3, architecture="lstm")
    with pytest.raises(ValueError, match=r"ActorConfig.distribution_tokens / bias_token: .* 'gru'"):
        ActorConfig(num_classes=3, architecture="gru", bias_token=False)
    with pytest.raises(ValueError, match=r"ActorConfig.frames: expected >= 1"):
        ActorConfig(num_classes=3, architecture="fc", frames=0)
    ActorConfig(num_classes=3, width=10, architecture="gru")  # heads must divide width for attention only


def test_parameters_of_another_architecture_and_stray_targets_are_rejected():
    z = jnp.zeros((2, 16))
    with pytest.raises(TypeError, match=r"params: architecture 'gru' expects GruActorParams, got FcActorParams"):
        decode(config("gru"), params("fc"), z, ACTIONS, MASK)
    with pytest.raises(ValueError, match=r"target: teacher forcing exists for architecture 'autoregressive' only"):
        decode(config("gru"), params("gru"), z, ACTIONS, MASK, target=X)
    with pytest.raises(ValueError, match=r"target: expected \[B, T, J, C\]"):
        decode(config("autoregressive"), params("autoregressive"), z, ACTIONS, MASK, target=X[:, :5])
