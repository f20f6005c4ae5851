"""Shared primitives: PyTorch's default initialisation (bounds and moments), Linear and LayerNorm, BatchNorm's
train and eval modes and running-statistics update against a float64 numpy reference of torch's, and dropout
(keep rate, scaling, the hashed mask bits)."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.nn.core import (
    BatchNormStats,
    batch_norm,
    dropout,
    dropout_bits,
    init_batch_norm,
    init_layer_norm,
    init_linear,
    init_prelu,
    layer_norm,
    linear,
    prelu,
    torch_uniform,
)
from jaxmotion.nn.recurrent import init_gru


def _inputs(seed, *shape, scale=1.0, shift=0.0):
    return jnp.asarray(shift + scale * np.random.default_rng(seed).standard_normal(shape), jnp.float32)


# ----------------------------------------------------------------------------------------- initialisation


@pytest.mark.parametrize("fan_in", [1, 7, 64, 1000])
def test_torch_uniform_fills_the_bounds_with_uniform_moments(fan_in):
    bound = 1 / math.sqrt(fan_in)
    w = torch_uniform(jax.random.key(fan_in), (200, 100), fan_in)
    assert w.dtype == jnp.float32
    w, n = np.asarray(w, np.float64), w.size
    assert np.abs(w).max() <= bound and np.abs(w).max() > 0.999 * bound
    # U(-b, b): mean 0 (sd b/√(3n)), variance b²/3 (sd of the estimate b²·√(4/45n))
    assert abs(w.mean()) < 5 * bound / math.sqrt(3 * n)
    assert abs(w.var() - bound**2 / 3) < 5 * bound**2 * math.sqrt(4 / (45 * n))


def test_init_linear_has_torchs_shapes_and_bound_for_weight_and_bias():
    p = init_linear(jax.random.key(0), 300, 400)
    assert p.weight.shape == (400, 300) and p.bias.shape == (400,) and p.weight.dtype == jnp.float32
    bound = 1 / math.sqrt(300)
    for leaf in p:
        assert 0.99 * bound < np.abs(leaf).max() <= bound
    assert not np.allclose(p.weight[:, 0], p.bias)  # weight and bias from different keys


def test_init_gru_uses_the_hidden_size_as_fan_in():
    p = init_gru(jax.random.key(0), 10, 64)
    for leaf in p:
        assert 0.9 / 8 < np.abs(leaf).max() <= 1 / 8


def test_linear_and_layer_norm_match_numpy():
    p = init_linear(jax.random.key(1), 5, 3)
    x = _inputs(0, 4, 2, 5)
    np.testing.assert_allclose(linear(p, x), np.asarray(x) @ np.asarray(p.weight).T + p.bias, rtol=1e-5, atol=1e-6)
    norm = init_layer_norm(5)._replace(weight=_inputs(1, 5, shift=1.0), bias=_inputs(2, 5))
    x64 = np.asarray(x, np.float64)
    expected = (x64 - x64.mean(-1, keepdims=True)) / np.sqrt(x64.var(-1, keepdims=True) + 1e-5)
    np.testing.assert_allclose(layer_norm(norm, x), expected * norm.weight + norm.bias, rtol=1e-5, atol=1e-5)


# --------------------------------------------------------------------------------------------- batch norm


def _ref_batch_norm(p, stats, x, train, momentum=0.1, eps=1e-5):
    """torch ``BatchNorm`` semantics in float64, features on the trailing axes of ``p.weight``'s shape."""
    x = np.asarray(x, np.float64)
    flat = x.reshape(-1, *p.weight.shape)
    mean, var = stats.running_mean, stats.running_var
    if train:
        mean, var = flat.mean(0), flat.var(0)
        n = flat.shape[0]
        stats = BatchNormStats((1 - momentum) * stats.running_mean + momentum * mean,
                               (1 - momentum) * stats.running_var + momentum * flat.var(0, ddof=1))
        assert np.allclose(flat.var(0, ddof=1), var * n / (n - 1))
    return (x - mean) / np.sqrt(var + eps) * p.weight + p.bias, stats


@pytest.fixture(scope="module")
def bn():
    """BatchNorm over ``[V, C] = [3, 4]`` features with non-trivial parameters and running statistics."""
    p, stats = init_batch_norm((3, 4))
    p = p._replace(weight=_inputs(1, 3, 4, scale=0.3, shift=1.0), bias=_inputs(2, 3, 4))
    stats = BatchNormStats(_inputs(3, 3, 4), jnp.abs(_inputs(4, 3, 4)) + 0.5)
    return p, stats


def test_batch_norm_starts_at_identity_scale_and_unit_running_variance():
    p, stats = init_batch_norm((6,))
    np.testing.assert_array_equal(p.weight, 1.0)
    np.testing.assert_array_equal(p.bias, 0.0)
    np.testing.assert_array_equal(stats.running_mean, 0.0)
    np.testing.assert_array_equal(stats.running_var, 1.0)


def test_batch_norm_parameters_and_statistics_can_be_donated_together():
    # a train state holds both; XLA refuses to donate one buffer twice
    state = init_batch_norm((6,))
    jax.jit(lambda s: jax.tree.map(lambda a: a + 1, s), donate_argnums=0)(state)


@pytest.mark.parametrize("train", [True, False], ids=["train", "eval"])
def test_batch_norm_matches_torch_semantics(bn, train):
    p, stats = bn
    x = _inputs(5, 2, 7, 3, 4, scale=2.0, shift=0.5)  # [N, T, V, C]: statistics over N and T
    y, new = batch_norm(p, stats, x, train=train)
    ref_y, ref_stats = _ref_batch_norm(p, stats, x, train)
    np.testing.assert_allclose(y, ref_y, rtol=1e-5, atol=1e-5)
    for got, want in zip(new, ref_stats, strict=True):
        np.testing.assert_allclose(got, want, rtol=1e-5, atol=1e-6)
    if not train:
        jax.tree.map(np.testing.assert_array_equal, new, stats)


def test_batch_norm_train_mode_normalises_each_feature_of_the_batch(bn):
    p, stats = bn
    x = _inputs(6, 5, 9, 3, 4, scale=3.0, shift=-2.0)
    y, _ = batch_norm(p._replace(weight=jnp.ones((3, 4)), bias=jnp.zeros((3, 4))), stats, x, train=True)
    np.testing.assert_allclose(y.mean(axis=(0, 1)), 0.0, atol=1e-5)
    np.testing.assert_allclose(y.var(axis=(0, 1)), 1.0, rtol=1e-4)


def test_batch_norm_eval_mode_treats_samples_independently_and_train_mode_does_not(bn):
    p, stats = bn
    x = _inputs(7, 4, 3, 4)
    other = x.at[2:].set(10.0)
    np.testing.assert_allclose(batch_norm(p, stats, other, train=False)[0][:2],
                               batch_norm(p, stats, x, train=False)[0][:2], rtol=1e-6)
    assert not np.allclose(batch_norm(p, stats, other, train=True)[0][:2],
                           batch_norm(p, stats, x, train=True)[0][:2], atol=1e-2)


def test_batch_norm_running_statistics_converge_to_the_unbiased_estimates(bn):
    p, stats = bn
    x = _inputs(8, 6, 3, 4, scale=2.0, shift=1.0)
    step = jax.jit(lambda s: batch_norm(p, s, x, train=True)[1])
    for _ in range(200):  # 0.9^200 of the start is left
        stats = step(stats)
    flat = np.asarray(x, np.float64)
    np.testing.assert_allclose(stats.running_mean, flat.mean(0), rtol=1e-4, atol=1e-5)
    np.testing.assert_allclose(stats.running_var, flat.var(0, ddof=1), rtol=1e-4)


def test_batch_norm_refuses_mismatched_features_and_single_values(bn):
    p, stats = bn
    with pytest.raises(ValueError, match=r"x: expected trailing feature axes \(3, 4\), got shape \(2, 4, 3\)"):
        batch_norm(p, stats, jnp.zeros((2, 4, 3)), train=False)
    with pytest.raises(ValueError, match="more than one value per feature"):
        batch_norm(p, stats, jnp.zeros((1, 3, 4)), train=True)
    batch_norm(p, stats, jnp.zeros((1, 3, 4)), train=False)  # eval mode needs no batch


# ------------------------------------------------------------------------------------------------ dropout


@pytest.mark.parametrize("rate", [0.1, 0.5, 0.9])
def test_dropout_keeps_one_minus_rate_and_scales_the_kept_values(rate):
    n = 1 << 16
    x = _inputs(9, 4, n // 4, shift=3.0)
    y = np.asarray(dropout(x, rate, jax.random.key(0)))
    kept = y != 0
    assert abs(kept.mean() - (1 - rate)) < 5 * math.sqrt(rate * (1 - rate) / n)
    np.testing.assert_allclose(y[kept], np.asarray(x)[kept] / (1 - rate), rtol=1e-6)
    assert abs(y.mean() / np.asarray(x).mean() - 1) < 0.05  # the expectation is kept


def test_dropout_is_the_identity_without_a_key_or_at_rate_zero_and_refuses_bad_rates():
    x = _inputs(10, 3, 5)
    np.testing.assert_array_equal(dropout(x, 0.5, None), x)
    np.testing.assert_array_equal(dropout(x, 0.0, jax.random.key(0)), x)
    with pytest.raises(ValueError, match=r"dropout_rate: expected in \[0, 1\), got 1.0"):
        dropout(x, 1.0, jax.random.key(0))


def test_dropout_masks_are_the_pinned_hash_of_the_key():
    # Values from before the move to nn.core: same key, same bits and masks, so trained models reproduce.
    bits = np.asarray(dropout_bits(jax.random.key(0), (2, 3))).ravel().tolist()
    assert bits == [2302592709, 397945886, 1273672552, 52932118, 110484487, 3591225784]
    mask = np.asarray(dropout(jnp.ones((2, 8)), 0.5, jax.random.key(0)))
    np.testing.assert_array_equal(mask, [[2, 0, 0, 0, 0, 2, 0, 0], [2, 2, 0, 2, 0, 2, 2, 0]])


def test_dropout_bits_behave_like_independent_fair_coins():
    n = 1 << 16
    bits = np.asarray(dropout_bits(jax.random.key(3), (4, n // 4))).ravel()
    other = np.asarray(dropout_bits(jax.random.key(4), (4, n // 4))).ravel()
    per_bit = ((bits[:, None] >> np.arange(32, dtype=np.uint32)) & 1).mean(0)
    tolerance = 5 * 0.5 / np.sqrt(n)  # five standard errors of a fair coin's frequency
    assert np.all(np.abs(per_bit - 0.5) < tolerance), per_bit
    keep = bits >= np.uint32(round(0.1 * 2**32))
    assert abs(keep.mean() - 0.9) < 5 * np.sqrt(0.09 / n)
    # neighbours (the hash's input counter differs by one) and another key: no more agreement than chance
    for a, b in ((keep[1:], keep[:-1]), (keep, other >= np.uint32(round(0.1 * 2**32)))):
        assert abs((a == b).mean() - 0.82) < 5 * np.sqrt(0.82 * 0.18 / n)
    np.testing.assert_array_equal(bits, np.asarray(dropout_bits(jax.random.key(3), (4, n // 4))).ravel())


# ------------------------------------------------------------------------------------------------- PReLU


def test_prelu_scales_negative_inputs_by_its_slope_only():
    x = jnp.array([[-2.0, -0.5, 0.0, 1.5]])
    np.testing.assert_allclose(prelu(init_prelu(), x), [[-0.5, -0.125, 0.0, 1.5]])
    per_channel = init_prelu(4)._replace(weight=jnp.array([0.0, 1.0, 2.0, 3.0]))
    np.testing.assert_allclose(prelu(per_channel, x), [[0.0, -0.5, 0.0, 1.5]])
    # the slope's gradient is the sum of the negative inputs
    grad = jax.grad(lambda p: prelu(p, x).sum())(init_prelu())
    np.testing.assert_allclose(grad.weight, [-2.5])
