"""ACTOR's Transformer VAE: shapes, masking, determinism, ablation switches, the paper's parameter count."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.models.actor import ActorConfig, autoencode, decode, encode, generate, init_actor, length_mask

TINY = ActorConfig(num_classes=3, width=16, ff=32, layers=2, heads=4)


@pytest.fixture(scope="module")
def tiny():
    params = init_actor(jax.random.key(0), TINY)
    x = jax.random.normal(jax.random.key(1), (2, 10, 25, 6))
    return params, x, jnp.array([0, 2]), length_mask(jnp.array([10, 7]), 10)


def test_padded_frames_neither_reach_the_latent_nor_leave_the_decoder(tiny):
    params, x, actions, mask = tiny
    mu, logvar = encode(TINY, params, x, actions, mask)
    changed = x.at[1, 7:].set(100.0)
    mu2, logvar2 = encode(TINY, params, changed, actions, mask)
    np.testing.assert_allclose(np.asarray(mu2), np.asarray(mu), atol=1e-5)
    np.testing.assert_allclose(np.asarray(logvar2), np.asarray(logvar), atol=1e-5)
    out = decode(TINY, params, mu, actions, mask)
    assert out.shape == x.shape and float(jnp.abs(out[1, 7:]).max()) == 0.0


def test_each_sequence_is_decoded_independently_of_the_rest_of_the_batch(tiny):
    params, _, actions, mask = tiny
    z = jax.random.normal(jax.random.key(2), (2, TINY.width))
    both = decode(TINY, params, z, actions, mask)
    alone = decode(TINY, params, z[1:], actions[1:], mask[1:])
    np.testing.assert_allclose(np.asarray(alone[0]), np.asarray(both[1]), atol=1e-5)


def test_generation_is_a_function_of_the_key(tiny):
    params, _, actions, _ = tiny
    a, mask = generate(TINY, params, actions, jnp.array([5, 10]), 10, key=jax.random.key(3))
    b, _ = generate(TINY, params, actions, jnp.array([5, 10]), 10, key=jax.random.key(3))
    c, _ = generate(TINY, params, actions, jnp.array([5, 10]), 10, key=jax.random.key(4))
    np.testing.assert_array_equal(np.asarray(a), np.asarray(b))
    assert not np.allclose(np.asarray(a), np.asarray(c))
    np.testing.assert_array_equal(np.asarray(mask.sum(1)), [5, 10])


def test_dropout_only_in_training(tiny):
    params, x, actions, mask = tiny
    key = jax.random.key(5)
    eval_a = autoencode(TINY, params, x, actions, mask, key=key, train=False)["mu"]
    eval_b = autoencode(TINY, params, x, actions, mask, key=key, train=False)["mu"]
    train = autoencode(TINY, params, x, actions, mask, key=key, train=True)["mu"]
    np.testing.assert_array_equal(np.asarray(eval_a), np.asarray(eval_b))
    assert not np.allclose(np.asarray(train), np.asarray(eval_a))


@pytest.mark.parametrize(("tokens", "bias"), [(False, True), (True, False), (False, False)])
def test_table2_ablations_build_and_run(tiny, tokens, bias):
    _, x, actions, mask = tiny
    config = ActorConfig(num_classes=3, width=16, ff=32, layers=2, heads=4, distribution_tokens=tokens,
                         bias_token=bias)
    params = init_actor(jax.random.key(6), config)
    assert (params.encoder.mu_query is None) != tokens and (params.decoder.action_biases is None) != bias
    out = autoencode(config, params, x, actions, mask, key=jax.random.key(7), train=True)
    assert out["output"].shape == x.shape and np.isfinite(np.asarray(out["output"])).all()


def test_paper_configuration_has_the_reference_parameter_count():
    config = ActorConfig(num_classes=40)
    shapes = jax.eval_shape(lambda k: init_actor(k, config), jax.random.key(0))
    count = sum(int(np.prod(leaf.shape)) for leaf in jax.tree.leaves(shapes))
    d, ff, feats, k, layers = 256, 1024, 25 * 6, 40, 8
    attention = 4 * d * d + 4 * d  # in_proj [3d, d] + bias, out_proj [d, d] + bias
    feed_forward = 2 * d * ff + ff + d
    encoder_layer = attention + feed_forward + 2 * 2 * d  # two LayerNorms
    decoder_layer = 2 * attention + feed_forward + 3 * 2 * d
    expected = (feats * d + d) + 2 * k * d + layers * encoder_layer + k * d + layers * decoder_layer + (d * feats + feats)
    assert count == expected


def test_bad_shapes_name_the_argument(tiny):
    params, x, actions, mask = tiny
    with pytest.raises(ValueError, match=r"x: expected \[B, T, 25, 6\]"):
        encode(TINY, params, x[..., :3], actions, mask)
    with pytest.raises(ValueError, match=r"mask: expected \[B, T\]"):
        encode(TINY, params, x, actions, mask[:, :5])
    with pytest.raises(ValueError, match=r"z: expected \[B, 16\]"):
        decode(TINY, params, jnp.zeros((2, 8)), actions, mask)
