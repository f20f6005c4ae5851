"""Transformer layers: sinusoidal codes, attention and post-/pre-norm layers against float64 numpy references,
masking and causality properties, dropout modes, scanned stacks, cached decoding against the full causal pass,
options, PyTorch initialisation, sizes and names."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.nn.transformer import (
    AttentionParams,
    TransformerOptions,
    decoder_layer,
    decoder_stack,
    decoder_stack_step,
    encoder_layer,
    encoder_stack,
    init_decoder_cache,
    init_decoder_layer,
    init_decoder_stack,
    init_encoder_layer,
    init_encoder_stack,
    init_multi_head_attention,
    load_state_dict,
    multi_head_attention,
    sinusoidal_encoding,
    stack_layers,
    state_dict,
    unstack_layers,
)

D, H, F = 16, 4, 32
OPTIONS = TransformerOptions(num_heads=H)  # torch 1.7's layers
JOEYNMT = TransformerOptions(num_heads=H, activation="relu", norm_first=True, layer_norm_eps=1e-6, causal=True)


def _random_params(init, seed, *args):
    """Parameters with ``init``'s structure and random values (numpy-drawn, so nothing is compiled): LayerNorm
    scales near 1, everything else N(0, 0.3²), so zero biases or unit scales cannot hide mistakes."""
    rng = np.random.default_rng(seed)

    def draw(path, leaf):
        value = 0.3 * rng.standard_normal(leaf.shape)
        if "norm" in jax.tree_util.keystr(path) and jax.tree_util.keystr(path).endswith(".weight"):
            value += 1.0
        return jnp.asarray(value, jnp.float32)

    return jax.tree_util.tree_map_with_path(draw, jax.eval_shape(lambda key: init(key, *args), jax.random.key(0)))


def _inputs(seed, *shape):
    return jnp.asarray(np.random.default_rng(seed).standard_normal(shape), jnp.float32)


# ------------------------------------------------------------------------------- float64 numpy references


def _np(tree):
    return jax.tree.map(lambda a: np.asarray(a, np.float64), tree)


def ref_attention(p, q_in, kv_in, num_heads, key_mask=None, causal=False):
    q_in, kv_in = np.asarray(q_in, np.float64), np.asarray(kv_in, np.float64)
    b, tq, d = q_in.shape
    tk, hd = kv_in.shape[1], d // num_heads
    w, bias = p.in_proj_weight, p.in_proj_bias
    q = (q_in @ w[:d].T + bias[:d]).reshape(b, tq, num_heads, hd)
    k = (kv_in @ w[d : 2 * d].T + bias[d : 2 * d]).reshape(b, tk, num_heads, hd)
    v = (kv_in @ w[2 * d :].T + bias[2 * d :]).reshape(b, tk, num_heads, hd)
    out = np.zeros((b, tq, num_heads, hd))
    for i in range(b):
        for h in range(num_heads):
            for t in range(tq):
                ok = np.ones(tk, bool) if key_mask is None else np.asarray(key_mask[i], bool).copy()
                if causal:
                    ok[t + 1 :] = False
                if not ok.any():
                    continue
                s = k[i, ok, h] @ q[i, t, h] / math.sqrt(hd)
                a = np.exp(s - s.max())
                out[i, t, h] = (a / a.sum()) @ v[i, ok, h]
    return out.reshape(b, tq, d) @ p.out_proj.weight.T + p.out_proj.bias


def ref_ln(p, x, eps):
    mu, var = x.mean(-1, keepdims=True), x.var(-1, keepdims=True)
    return (x - mu) / np.sqrt(var + eps) * p.weight + p.bias


def ref_ff(p, x, activation):
    h = x @ p.linear1.weight.T + p.linear1.bias
    if activation == "gelu":
        h = 0.5 * h * (1 + np.vectorize(math.erf)(h / math.sqrt(2)))
    else:
        h = np.maximum(h, 0)
    return h @ p.linear2.weight.T + p.linear2.bias


def _ref_block(x, norm, f, norm_first, eps):
    return x + f(ref_ln(norm, x, eps)) if norm_first else ref_ln(norm, x + f(x), eps)


def ref_encoder(p, x, mask, activation="gelu", norm_first=False, eps=1e-5):
    p, x = _np(p), np.asarray(x, np.float64)
    x = _ref_block(x, p.norm1, lambda h: ref_attention(p.self_attn, h, h, H, mask), norm_first, eps)
    return _ref_block(x, p.norm2, lambda h: ref_ff(p, h, activation), norm_first, eps)


def ref_decoder(p, tgt, memory, tgt_mask, mem_mask, causal, activation="gelu", norm_first=False, eps=1e-5):
    p, x, m = _np(p), np.asarray(tgt, np.float64), np.asarray(memory, np.float64)
    x = _ref_block(x, p.norm1, lambda h: ref_attention(p.self_attn, h, h, H, tgt_mask, causal), norm_first, eps)
    x = _ref_block(x, p.norm2, lambda h: ref_attention(p.multihead_attn, h, m, H, mem_mask), norm_first, eps)
    return _ref_block(x, p.norm3, lambda h: ref_ff(p, h, activation), norm_first, eps)


MASK_3x6 = np.array([[1, 1, 1, 1, 1, 1], [1, 1, 1, 0, 0, 0], [1, 0, 0, 0, 0, 0]], bool)


@pytest.fixture(scope="module")
def attn():
    return _random_params(init_multi_head_attention, 1, D)


@pytest.fixture(scope="module")
def enc():
    return _random_params(init_encoder_layer, 3, D, F)


@pytest.fixture(scope="module")
def dec():
    return _random_params(init_decoder_layer, 5, D, F)


# ----------------------------------------------------------------------------------------------- encoding


def test_sinusoidal_encoding_known_values_and_shape():
    pe = np.asarray(sinusoidal_encoding(jnp.arange(5), 8))
    assert pe.shape == (5, 8) and pe.dtype == np.float32
    np.testing.assert_allclose(pe[0], [0, 1, 0, 1, 0, 1, 0, 1], atol=1e-7)
    # Position 3, columns 2 (sin) and 3 (cos) share the frequency 10000^(-2/8) = 0.1.
    np.testing.assert_allclose(pe[3, 2:4], [math.sin(0.3), math.cos(0.3)], rtol=1e-6)
    np.testing.assert_allclose(pe[3, 0:2], [math.sin(3.0), math.cos(3.0)], rtol=1e-6)
    np.testing.assert_allclose(sinusoidal_encoding(jnp.array([3.0]), 8)[0], pe[3], rtol=1e-6)  # float positions
    with pytest.raises(ValueError, match="positions"):
        sinusoidal_encoding(jnp.zeros((2, 3)), 8)


# ---------------------------------------------------------------------------------------------- attention


@pytest.mark.parametrize("masked", [False, True])
@pytest.mark.parametrize("causal", [False, True])
def test_attention_matches_numpy_reference(attn, masked, causal):
    x = _inputs(0, 3, 6, D)
    mask = MASK_3x6 if masked else None
    out = multi_head_attention(attn, x, x, num_heads=H, key_padding_mask=mask, causal=causal)
    np.testing.assert_allclose(out, ref_attention(_np(attn), x, x, H, mask, causal), atol=1e-5)


def test_cross_attention_with_other_length_matches_reference(attn):
    q, kv = _inputs(1, 2, 3, D), _inputs(2, 2, 5, D)
    mask = np.array([[1, 1, 1, 1, 1], [1, 1, 0, 0, 0]], bool)
    out = multi_head_attention(attn, q, kv, num_heads=H, key_padding_mask=mask)
    assert out.shape == (2, 3, D)
    np.testing.assert_allclose(out, ref_attention(_np(attn), q, kv, H, mask), atol=1e-5)


@pytest.mark.parametrize("masked", [False, True])
def test_single_key_attention_matches_reference(attn, masked):
    q, kv = _inputs(23, 2, 5, D), _inputs(24, 2, 1, D)
    mask = np.array([[True], [False]]) if masked else None
    out = multi_head_attention(attn, q, kv, num_heads=H, key_padding_mask=mask)
    np.testing.assert_allclose(out, ref_attention(_np(attn), q, kv, H, mask), atol=1e-5)


def test_single_key_attention_dropout_keeps_or_drops_whole_heads(attn):
    q, kv, rate = _inputs(25, 3, 40, D), _inputs(26, 3, 1, D), 0.25
    out = multi_head_attention(attn, q, kv, num_heads=H, dropout_rate=rate, dropout_key=jax.random.key(5))
    a = _np(attn)
    # undo out_proj: the per-head context of each query is either the value or zero
    context = np.linalg.solve(a.out_proj.weight, (np.asarray(out, np.float64) - a.out_proj.bias)[..., None])[..., 0]
    value = np.asarray(kv, np.float64)[:, 0] @ a.in_proj_weight[2 * D:].T + a.in_proj_bias[2 * D:]  # [B, D]
    context, value = context.reshape(3, 40, H, D // H), value.reshape(3, 1, H, D // H) / (1 - rate)
    kept = np.abs(context - value).max(-1) < 1e-3
    dropped = np.abs(context).max(-1) < 1e-3
    assert np.all(kept ^ dropped)
    assert 0.1 < dropped.mean() < 0.4  # 480 head-queries at rate 0.25


def test_padded_keys_have_no_influence(attn):
    q, kv = _inputs(3, 3, 4, D), _inputs(4, 3, 6, D)
    changed = jnp.where(MASK_3x6[..., None], kv, 100.0 * _inputs(5, 3, 6, D))
    run = lambda k: multi_head_attention(attn, q, k, num_heads=H, key_padding_mask=MASK_3x6)
    np.testing.assert_allclose(run(kv), run(changed), atol=1e-6)


def test_causal_output_does_not_depend_on_later_inputs(attn):
    x = _inputs(6, 2, 6, D)
    later_changed = x.at[:, 4:].set(_inputs(7, 2, 2, D))
    run = lambda z: multi_head_attention(attn, z, z, num_heads=H, causal=True)
    a, b = run(x), run(later_changed)
    np.testing.assert_allclose(a[:, :4], b[:, :4], atol=1e-6)
    assert not np.allclose(a[:, 4:], b[:, 4:])


def test_fully_masked_rows_are_finite_with_finite_gradients(attn):
    x = _inputs(8, 2, 4, D)
    mask = np.array([[0, 0, 0, 0], [1, 1, 0, 0]], bool)
    out = multi_head_attention(attn, x, x, num_heads=H, key_padding_mask=mask)
    assert np.isfinite(out).all()
    np.testing.assert_allclose(out[0], np.broadcast_to(attn.out_proj.bias, (4, D)), atol=1e-6)
    grad = jax.grad(lambda z: multi_head_attention(attn, z, z, num_heads=H, key_padding_mask=mask).sum())(x)
    assert np.isfinite(grad).all()


def test_attention_validates_shapes(attn):
    x = _inputs(9, 2, 4, D)
    with pytest.raises(ValueError, match="key_padding_mask"):
        multi_head_attention(attn, x, x, num_heads=H, key_padding_mask=np.ones((2, 5), bool))
    with pytest.raises(ValueError, match="key_value"):
        multi_head_attention(attn, x, x[..., :8], num_heads=H)
    with pytest.raises(ValueError, match="query"):
        multi_head_attention(attn, x[0], x, num_heads=H)
    with pytest.raises(ValueError, match="num_heads"):
        multi_head_attention(attn, x, x, num_heads=3)
    with pytest.raises(ValueError, match="causal"):
        multi_head_attention(attn, x, x[:, :3], num_heads=H, causal=True)


# ------------------------------------------------------------------------------------------------- layers


@pytest.mark.parametrize("masked", [False, True])
def test_post_norm_encoder_layer_matches_numpy_reference(enc, masked):
    x = _inputs(10, 3, 6, D)
    mask = MASK_3x6 if masked else None
    out = encoder_layer(enc, x, OPTIONS, key_padding_mask=mask)
    np.testing.assert_allclose(out, ref_encoder(enc, x, mask), atol=1e-4)


@pytest.mark.parametrize("causal", [False, True])
def test_post_norm_decoder_layer_matches_numpy_reference(dec, causal):
    tgt, memory = _inputs(11, 3, 6, D), _inputs(12, 3, 2, D)
    mem_mask = np.array([[1, 1], [1, 0], [1, 1]], bool)
    out = decoder_layer(dec, tgt, memory, TransformerOptions(num_heads=H, causal=causal),
                        tgt_key_padding_mask=MASK_3x6, memory_key_padding_mask=mem_mask)
    np.testing.assert_allclose(out, ref_decoder(dec, tgt, memory, MASK_3x6, mem_mask, causal), atol=1e-4)


def test_pre_norm_relu_decoder_layer_matches_numpy_reference(dec):
    """joeynmt's layer as ACTOR's autoregressive baseline uses it: pre-norm, ReLU, eps 1e-6, causal."""
    tgt, memory = _inputs(13, 3, 6, D), _inputs(14, 3, 6, D)
    out = decoder_layer(dec, tgt, memory, JOEYNMT, tgt_key_padding_mask=MASK_3x6, memory_key_padding_mask=MASK_3x6)
    expected = ref_decoder(dec, tgt, memory, MASK_3x6, MASK_3x6, True, "relu", norm_first=True, eps=1e-6)
    np.testing.assert_allclose(out, expected, atol=1e-4)


def test_encoder_layer_is_permutation_equivariant(enc):
    x = _inputs(15, 2, 7, D)
    perm = np.array([3, 0, 6, 1, 5, 2, 4])
    permuted_in = encoder_layer(enc, x[:, perm], OPTIONS)
    np.testing.assert_allclose(permuted_in, encoder_layer(enc, x, OPTIONS)[:, perm], atol=1e-5)


@pytest.mark.parametrize("norm_first", [False, True])
def test_causal_decoder_output_does_not_depend_on_later_targets(dec, norm_first):
    tgt, memory = _inputs(16, 2, 6, D), _inputs(17, 2, 3, D)
    later_changed = tgt.at[:, 3:].set(_inputs(18, 2, 3, D))
    options = TransformerOptions(num_heads=H, causal=True, norm_first=norm_first)
    run = lambda t: decoder_layer(dec, t, memory, options)
    np.testing.assert_allclose(run(tgt)[:, :3], run(later_changed)[:, :3], atol=1e-5)


def test_dropout_only_with_a_key_and_reproducible(enc):
    x = _inputs(19, 2, 5, D)
    run = lambda key: encoder_layer(enc, x, TransformerOptions(num_heads=H, dropout_rate=0.3), dropout_key=key)
    eval_out = encoder_layer(enc, x, OPTIONS)
    np.testing.assert_array_equal(run(None), eval_out)
    a, b = run(jax.random.key(0)), run(jax.random.key(1))
    assert not np.allclose(a, b) and not np.allclose(a, eval_out)
    np.testing.assert_array_equal(a, run(jax.random.key(0)))
    zero_rate = encoder_layer(enc, x, OPTIONS, dropout_key=jax.random.key(0))
    np.testing.assert_array_equal(zero_rate, eval_out)


# ------------------------------------------------------------------------------------------------- stacks


def test_encoder_stack_equals_layers_one_by_one():
    layers = [_random_params(init_encoder_layer, 10 + i, D, F) for i in range(3)]
    x, key = _inputs(20, 3, 6, D), jax.random.key(7)
    options = TransformerOptions(num_heads=H, dropout_rate=0.2)
    run = jax.jit(lambda p, x, k: encoder_stack(p, x, options, key_padding_mask=MASK_3x6, dropout_key=k))
    stack = run(stack_layers(layers), x, key)
    h = x
    for layer, k in zip(layers, jax.random.split(key, 3)):
        h = encoder_layer(layer, h, options, key_padding_mask=MASK_3x6, dropout_key=k)
    np.testing.assert_allclose(stack, h, atol=1e-5)


@pytest.mark.parametrize("num_layers", [1, 3])
@pytest.mark.parametrize("norm_first", [False, True])
def test_encoder_stack_with_num_queries_gives_the_first_outputs_of_the_full_stack(num_layers, norm_first):
    stack = stack_layers([_random_params(init_encoder_layer, 30 + i, D, F) for i in range(num_layers)])
    x = _inputs(31, 3, 6, D)
    options = TransformerOptions(num_heads=H, norm_first=norm_first)
    full = encoder_stack(stack, x, options, key_padding_mask=MASK_3x6)
    first = encoder_stack(stack, x, options, key_padding_mask=MASK_3x6, num_queries=2)
    assert first.shape == (3, 2, D)
    np.testing.assert_allclose(first, full[:, :2], atol=1e-5)
    with pytest.raises(ValueError, match="num_queries"):
        encoder_stack(stack, x, TransformerOptions(num_heads=H, causal=True), num_queries=2)


def test_unrolled_stacks_equal_scanned_ones():
    enc = stack_layers([_random_params(init_encoder_layer, 40 + i, D, F) for i in range(2)])
    dec = stack_layers([_random_params(init_decoder_layer, 42 + i, D, F) for i in range(2)])
    x, memory, key = _inputs(43, 3, 6, D), _inputs(44, 3, 1, D), jax.random.key(9)
    def run(unroll):
        options = TransformerOptions(num_heads=H, dropout_rate=0.2, unroll=unroll)
        return (encoder_stack(enc, x, options, key_padding_mask=MASK_3x6, dropout_key=key),
                decoder_stack(dec, x, memory, options, tgt_key_padding_mask=MASK_3x6, dropout_key=key))

    for a, b in zip(run(True), run(False), strict=True):
        np.testing.assert_allclose(a, b, atol=1e-5)


def test_decoder_stack_equals_layers_one_by_one():
    layers = [_random_params(init_decoder_layer, 20 + i, D, F) for i in range(2)]
    tgt, memory = _inputs(21, 2, 5, D), _inputs(22, 2, 1, D)
    options, kwargs = TransformerOptions(num_heads=H, causal=True), {"tgt_key_padding_mask": MASK_3x6[1:, :5]}
    stack = decoder_stack(stack_layers(layers), tgt, memory, options, **kwargs)
    h = tgt
    for layer in layers:
        h = decoder_layer(layer, h, memory, options, **kwargs)
    np.testing.assert_allclose(stack, h, atol=1e-5)


# ---------------------------------------------------------------------------------------- cached decoding


def _cached_pass(p, tgt, memory, tgt_mask, memory_mask, options):
    """``tgt [B, T, D]`` decoded one position at a time through the cache, positions traced in a scan."""
    cache = init_decoder_cache(p, memory, tgt.shape[1], options, tgt_key_padding_mask=tgt_mask,
                               memory_key_padding_mask=memory_mask)

    def step(cache, t):
        out, cache = decoder_stack_step(p, cache, tgt[:, t], t, options)
        return cache, out

    return jax.lax.scan(step, cache, jnp.arange(tgt.shape[1]))[1].swapaxes(0, 1)


@pytest.mark.parametrize("batch", [1, 32])
@pytest.mark.parametrize("options", [TransformerOptions(num_heads=H, causal=True), JOEYNMT],
                         ids=["post-norm-gelu", "joeynmt-pre-norm-relu"])
def test_cached_decoding_equals_full_causal_pass_at_every_frame(compile, batch, options):
    frames, memory_frames = 7, 5
    p = stack_layers([_random_params(init_decoder_layer, 50 + i, D, F) for i in range(3)])
    rng = np.random.default_rng(batch)
    tgt, memory = _inputs(51, batch, frames, D), _inputs(52, batch, memory_frames, D)
    # padded target and memory positions, as ACTOR's generation has them (padded frames get outputs too)
    tgt_mask = np.arange(frames) < rng.integers(1, frames + 1, (batch, 1))
    memory_mask = np.arange(memory_frames) < rng.integers(1, memory_frames + 1, (batch, 1))
    cached = compile(_cached_pass, static=("options",))(p, tgt, memory, tgt_mask, memory_mask, options=options)
    full = decoder_stack(p, tgt, memory, options, tgt_key_padding_mask=tgt_mask, memory_key_padding_mask=memory_mask)
    assert cached.shape == (batch, frames, D)
    np.testing.assert_allclose(cached, full, atol=1e-5, rtol=0)


def test_decoder_stack_step_reads_only_the_cache_and_its_token():
    # Stepping position 2 after positions 0 and 1 gives the full pass's output there, whatever later tokens hold
    # (the full pass sees them but masks them); concrete positions, eagerly.
    p = stack_layers([_random_params(init_decoder_layer, 60 + i, D, F) for i in range(2)])
    tgt, memory = _inputs(61, 2, 4, D), _inputs(62, 2, 3, D)
    cache = init_decoder_cache(p, memory, 4, JOEYNMT)
    for t in range(3):
        out, cache = decoder_stack_step(p, cache, tgt[:, t], t, JOEYNMT)
    changed = tgt.at[:, 3].set(100.0)
    np.testing.assert_allclose(out, decoder_stack(p, changed, memory, JOEYNMT)[:, 2], atol=1e-5, rtol=0)
    written = np.any(np.asarray(cache.keys) != 0, axis=(2, 4))  # [L, B, T]
    assert written[..., :3].all() and not written[..., 3].any()


def test_cached_decoding_rejects_positions_past_the_cache_and_mismatched_inputs():
    p = stack_layers([_random_params(init_decoder_layer, 70 + i, D, F) for i in range(2)])
    memory, token = _inputs(71, 2, 3, D), _inputs(72, 2, D)
    cache = init_decoder_cache(p, memory, 4, JOEYNMT)
    with pytest.raises(ValueError, match=r"position: expected 0 <= position < 4 \(the cache's length\), got 4"):
        decoder_stack_step(p, cache, token, 4, JOEYNMT)
    with pytest.raises(ValueError, match=r"position: expected 0 <= position < 4"):
        decoder_stack_step(p, cache, token, jnp.int32(-1), JOEYNMT)
    with pytest.raises(ValueError, match=r"token: expected \[B, D\] = \(2, 16\)"):
        decoder_stack_step(p, cache, token[:, None], 0, JOEYNMT)
    with pytest.raises(ValueError, match=r"cache: built for 2 layers of 4 heads"):
        decoder_stack_step(p, cache, token, 0, TransformerOptions(num_heads=2, causal=True))
    with pytest.raises(ValueError, match=r"options.causal: cached decoding reproduces causal self-attention"):
        init_decoder_cache(p, memory, 4, OPTIONS)
    with pytest.raises(ValueError, match=r"tgt_key_padding_mask: expected shape \[B, T\] = \(2, 4\)"):
        init_decoder_cache(p, memory, 4, JOEYNMT, tgt_key_padding_mask=np.ones((2, 3), bool))
    with pytest.raises(ValueError, match=r"length: expected a Python int >= 1"):
        init_decoder_cache(p, memory, 0, JOEYNMT)


def test_transformer_options_name_the_bad_field():
    with pytest.raises(ValueError, match=r"TransformerOptions.activation: expected 'gelu' or 'relu', got 'tanh'"):
        TransformerOptions(num_heads=H, activation="tanh")
    with pytest.raises(ValueError, match=r"TransformerOptions.num_heads: expected an int >= 1, got 0"):
        TransformerOptions(num_heads=0)
    with pytest.raises(ValueError, match=r"TransformerOptions.dropout_rate: expected in \[0, 1\), got 1.0"):
        TransformerOptions(num_heads=H, dropout_rate=1.0)
    assert hash(JOEYNMT) == hash(TransformerOptions(H, "relu", True, 1e-6, 0.0, True))  # static under jit


# ----------------------------------------------------------------------------------- init, sizes and names


def test_actor_size_encoder_layer_has_torchs_parameter_count():
    d, f = 256, 1024
    params = jax.eval_shape(lambda key: init_encoder_layer(key, d, f), jax.random.key(0))
    attention = 4 * d * d + 4 * d  # in_proj [3D, D] + [3D], out_proj [D, D] + [D]
    ff = 2 * d * f + f + d
    norms = 2 * 2 * d
    assert sum(leaf.size for leaf in jax.tree.leaves(params)) == attention + ff + norms == 789_760


def test_initialisation_follows_torch_defaults():
    p = init_encoder_layer(jax.random.key(0), 64, 128)
    xavier = math.sqrt(6 / (64 + 3 * 64))
    w = np.asarray(p.self_attn.in_proj_weight)
    assert np.abs(w).max() <= xavier and np.abs(w).max() > 0.9 * xavier
    assert not np.any(p.self_attn.in_proj_bias) and not np.any(p.self_attn.out_proj.bias)
    linears = [(p.self_attn.out_proj.weight, 64), *((leaf, 64) for leaf in p.linear1)]
    for leaf, fan_in in [*linears, *((leaf, 128) for leaf in p.linear2)]:
        assert 0.9 / math.sqrt(fan_in) < np.abs(leaf).max() <= 1 / math.sqrt(fan_in)
    np.testing.assert_array_equal(p.norm1.weight, 1.0)
    np.testing.assert_array_equal(p.norm2.bias, 0.0)
    joey = init_multi_head_attention(jax.random.key(1), 64, separate_projections=True)
    assert 0.9 / 8 < np.abs(joey.in_proj_bias).max() <= 1 / 8 and np.abs(joey.in_proj_weight).max() <= 1 / 8


def test_stack_init_clones_like_torch_or_draws_each_layer():
    cloned = init_encoder_stack(jax.random.key(0), 3, D, F)
    assert cloned.linear1.weight.shape == (3, F, D)
    first, *rest = unstack_layers(cloned)
    for layer in rest:
        jax.tree.map(np.testing.assert_array_equal, layer, first)
    separate = init_decoder_stack(jax.random.key(0), 2, D, F, clone=False)
    assert not np.allclose(separate.self_attn.in_proj_weight[0], separate.self_attn.in_proj_weight[1])


def test_state_dict_names_match_torch_and_round_trip():
    layer = init_decoder_layer(jax.random.key(0), D, F)
    sd = state_dict(layer)
    attn_keys = ["in_proj_weight", "in_proj_bias", "out_proj.weight", "out_proj.bias"]
    expected = {f"{a}.{k}" for a in ("self_attn", "multihead_attn") for k in attn_keys}
    expected |= {f"{m}.{k}" for m in ("linear1", "linear2", "norm1", "norm2", "norm3") for k in ("weight", "bias")}
    assert set(sd) == expected
    assert sd["linear1.weight"].shape == (F, D) and sd["self_attn.in_proj_weight"].shape == (3 * D, D)

    stacked = init_encoder_stack(jax.random.key(1), 2, D, F, clone=False)
    sd = state_dict(stacked, "seqTransEncoder.", stacked=True)
    assert "seqTransEncoder.layers.1.self_attn.out_proj.weight" in sd
    template = init_encoder_stack(jax.random.key(2), 2, D, F)
    loaded = load_state_dict(template, sd, "seqTransEncoder.", stacked=True)
    jax.tree.map(np.testing.assert_array_equal, loaded, stacked)
    del sd["seqTransEncoder.layers.0.norm2.bias"]
    with pytest.raises(ValueError, match="norm2.bias"):
        load_state_dict(template, sd, "seqTransEncoder.", stacked=True)


def test_layers_are_jittable_with_masks_as_arguments(enc):
    x = _inputs(23, 3, 6, D)
    fn = jax.jit(lambda p, x, m: encoder_layer(p, x, OPTIONS, key_padding_mask=m))
    eager = encoder_layer(enc, x, OPTIONS, key_padding_mask=MASK_3x6)
    np.testing.assert_allclose(fn(enc, x, MASK_3x6), eager, atol=1e-6)
    assert isinstance(enc.self_attn, AttentionParams)
