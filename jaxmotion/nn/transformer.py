"""Transformer layers as pure functions over explicit parameter pytrees, stacked with ``lax.scan``.

Where it is used:

* **ACTOR's transformer VAE** (``src/models/architectures/transformer.py``): torch 1.7
  ``nn.TransformerEncoderLayer`` / ``nn.TransformerDecoderLayer`` with d=256, 4 heads, FF 1024, dropout 0.1,
  GELU; post-norm, no final norm; sinusoidal positions (:func:`sinusoidal_encoding`).
* **ACTOR's autoregressive baseline** (``autotrans.py``, layers from joeynmt): pre-norm decoder layers
  (LayerNorm eps 1e-6 before each sublayer, ReLU FF), causal self-attention; the caller applies the final
  LayerNorm. Same functions with ``norm_first=True, activation="relu", layer_norm_eps=1e-6``.

Layout is batch first, ``[B, T, D]`` (torch 1.7 is sequence first: transpose axes 0 and 1). Masks are
boolean with **True = real token** (torch's ``key_padding_mask`` is the negation). Every function is
jittable; ``num_heads``, ``activation``, ``causal``, ``norm_first``, ``dropout_rate`` and
``layer_norm_eps`` are Python values (static under ``jit``).

A layer with post-norm (torch, ``norm_first=False``) and pre-norm (joeynmt, ``norm_first=True``) sublayers:

    post-norm:  x = LN(x + drop(f(x)))          pre-norm:  x = x + drop(f(LN(x)))
    encoder:    f = self-attention, then FF
    decoder:    f = self-attention, then cross-attention on ``memory``, then FF
    FF(x)     = W₂ · drop(act(W₁ x + b₁)) + b₂

(joeynmt's cross-attention reads the normalised query and the raw memory, which is what ``f(LN(x))`` gives.)

Parameters mirror PyTorch state-dict names: nested NamedTuples whose dotted field paths are the keys
(``self_attn.in_proj_weight``, ``self_attn.out_proj.weight``, ``linear1.weight``, ``norm1.bias``, ...), with
PyTorch's shapes (``Linear.weight`` is ``[out, in]``). :func:`state_dict` / :func:`load_state_dict` convert,
including ``layers.{i}.`` stacks. For joeynmt weights: ``in_proj_weight = cat(q_layer, k_layer, v_layer)``,
``out_proj = output_layer``, ``norm1/2/3 = x_layer_norm / dec_layer_norm / feed_forward.layer_norm``,
``linear1/2 = feed_forward.pwff_layer.0 / .3``.

Choices:

* **Fully masked query rows** (every key padded; torch returns NaN) get all-zero attention weights, so the
  attention output there is ``out_proj.bias``: finite, and it receives no gradient from other tokens.
* **Dropout** happens only when a ``dropout_key`` is given (no key = eval mode), in the places torch puts it:
  on the attention weights, after each sublayer before the residual add, and after the FF activation. Masks
  come from :func:`jaxmotion.nn.core.dropout_bits` (a hash of the element index, seeded from the key), not
  threefry.
* **One key** (a single memory token): attention skips the query/key projections, whose softmax weight is 1.
* **Stacks** take parameters stacked on a leading layer axis ``L`` (:func:`stack_layers`) and run the layers
  with ``lax.scan``, so compile time does not grow with depth (``unroll=True`` traces them unrolled); the
  dropout key is split into one per layer. An encoder stack's ``num_queries`` limits its last layer to the
  outputs the caller reads.
* **Initialisation** is PyTorch's default: ``Linear`` and LayerNorm as in :mod:`jaxmotion.nn.core`;
  ``MultiheadAttention`` ``in_proj_weight`` xavier-uniform over ``[3D, D]``, zero ``in_proj_bias`` and
  ``out_proj.bias``, ``out_proj.weight`` as a ``Linear``. torch's ``nn.TransformerEncoder`` /
  ``nn.TransformerDecoder`` deep-copy one layer, so all layers start identical (``clone=True``, ACTOR's
  case); joeynmt builds each layer separately and its q / k / v / output projections are plain ``Linear``
  layers with biases (``clone=False, separate_projections=True``).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.nn.core import (
    LayerNormParams,
    LinearParams,
    dropout,
    init_layer_norm,
    init_linear,
    layer_norm,
    linear,
    split_key,
)

# ----------------------------------------------------------------------------------------------- parameters


class AttentionParams(NamedTuple):
    """torch ``nn.MultiheadAttention`` with equal query / key / value sizes."""

    in_proj_weight: jax.Array  # [3D, D], row blocks (query, key, value)
    in_proj_bias: jax.Array  # [3D]
    out_proj: LinearParams  # [D, D], [D]


class EncoderLayerParams(NamedTuple):
    """torch ``nn.TransformerEncoderLayer``."""

    self_attn: AttentionParams
    linear1: LinearParams  # [F, D], [F]
    linear2: LinearParams  # [D, F], [D]
    norm1: LayerNormParams  # after (post-norm) / before (pre-norm) self-attention
    norm2: LayerNormParams  # FF


class DecoderLayerParams(NamedTuple):
    """torch ``nn.TransformerDecoderLayer``."""

    self_attn: AttentionParams
    multihead_attn: AttentionParams  # cross-attention on the memory
    linear1: LinearParams  # [F, D], [F]
    linear2: LinearParams  # [D, F], [D]
    norm1: LayerNormParams  # self-attention
    norm2: LayerNormParams  # cross-attention
    norm3: LayerNormParams  # FF


# ------------------------------------------------------------------------------------------ initialisation


def init_multi_head_attention(key: jax.Array, dim: int, *, separate_projections: bool = False) -> AttentionParams:
    """Attention parameters for model width ``dim``.

    Default (torch ``nn.MultiheadAttention``): ``in_proj_weight [3D, D]`` xavier-uniform, i.e.
    U(±√(6 / (D + 3D))); zero ``in_proj_bias`` and ``out_proj.bias``; ``out_proj.weight`` U(±1/√D).
    ``separate_projections=True`` (joeynmt): query, key, value and output projections are four independent
    ``nn.Linear(D, D)``, weights and biases U(±1/√D).
    """
    k_in, k_out = jax.random.split(key)
    out_proj = init_linear(k_out, dim, dim)
    if separate_projections:
        qkv = [init_linear(k, dim, dim) for k in jax.random.split(k_in, 3)]
        return AttentionParams(
            jnp.concatenate([p.weight for p in qkv]), jnp.concatenate([p.bias for p in qkv]), out_proj
        )
    bound = math.sqrt(6.0 / (dim + 3 * dim))
    return AttentionParams(
        jax.random.uniform(k_in, (3 * dim, dim), jnp.float32, -bound, bound),
        jnp.zeros((3 * dim,), jnp.float32),
        out_proj._replace(bias=jnp.zeros((dim,), jnp.float32)),
    )


def init_encoder_layer(
    key: jax.Array, dim: int, ff_dim: int, *, separate_projections: bool = False
) -> EncoderLayerParams:
    """One encoder layer of width ``dim`` and FF width ``ff_dim`` (see :func:`init_multi_head_attention`)."""
    k_att, k_1, k_2 = jax.random.split(key, 3)
    return EncoderLayerParams(
        self_attn=init_multi_head_attention(k_att, dim, separate_projections=separate_projections),
        linear1=init_linear(k_1, dim, ff_dim),
        linear2=init_linear(k_2, ff_dim, dim),
        norm1=init_layer_norm(dim),
        norm2=init_layer_norm(dim),
    )


def init_decoder_layer(
    key: jax.Array, dim: int, ff_dim: int, *, separate_projections: bool = False
) -> DecoderLayerParams:
    """One decoder layer of width ``dim`` and FF width ``ff_dim`` (see :func:`init_multi_head_attention`)."""
    k_self, k_cross, k_1, k_2 = jax.random.split(key, 4)
    return DecoderLayerParams(
        self_attn=init_multi_head_attention(k_self, dim, separate_projections=separate_projections),
        multihead_attn=init_multi_head_attention(k_cross, dim, separate_projections=separate_projections),
        linear1=init_linear(k_1, dim, ff_dim),
        linear2=init_linear(k_2, ff_dim, dim),
        norm1=init_layer_norm(dim),
        norm2=init_layer_norm(dim),
        norm3=init_layer_norm(dim),
    )


def stack_layers(layers: Sequence[NamedTuple]) -> NamedTuple:
    """Per-layer parameter trees -> one tree whose leaves have a leading layer axis ``L``."""
    if not layers:
        raise ValueError("layers: expected at least one layer's parameters, got none")
    return jax.tree.map(lambda *leaves: jnp.stack(leaves), *layers)


def unstack_layers(stacked: NamedTuple) -> list[NamedTuple]:
    """Inverse of :func:`stack_layers`."""
    return [jax.tree.map(lambda leaf, i=i: leaf[i], stacked) for i in range(_num_layers(stacked))]


def _init_stack(init_layer, key, num_layers, clone, **kwargs):
    if num_layers < 1:
        raise ValueError(f"num_layers: expected >= 1, got {num_layers}")
    if clone:
        return stack_layers([init_layer(key, **kwargs)] * num_layers)
    return stack_layers([init_layer(k, **kwargs) for k in jax.random.split(key, num_layers)])


def init_encoder_stack(
    key: jax.Array, num_layers: int, dim: int, ff_dim: int, *, clone: bool = True, separate_projections: bool = False
) -> EncoderLayerParams:
    """``num_layers`` encoder layers stacked on a leading axis; ``clone=True`` copies one initial layer, like
    torch's ``nn.TransformerEncoder``, ``clone=False`` draws each layer independently."""
    return _init_stack(
        init_encoder_layer, key, num_layers, clone, dim=dim, ff_dim=ff_dim, separate_projections=separate_projections
    )


def init_decoder_stack(
    key: jax.Array, num_layers: int, dim: int, ff_dim: int, *, clone: bool = True, separate_projections: bool = False
) -> DecoderLayerParams:
    """``num_layers`` decoder layers stacked on a leading axis (``clone`` as in :func:`init_encoder_stack`)."""
    return _init_stack(
        init_decoder_layer, key, num_layers, clone, dim=dim, ff_dim=ff_dim, separate_projections=separate_projections
    )


# ------------------------------------------------------------------------------------- PyTorch state dicts


def _named_leaves(tree, prefix: str):
    if isinstance(tree, tuple) and hasattr(tree, "_fields"):
        for name in tree._fields:
            yield from _named_leaves(getattr(tree, name), f"{prefix}{name}.")
    else:
        yield prefix[:-1], tree


def state_dict(params: NamedTuple, prefix: str = "", *, stacked: bool = False) -> dict[str, np.ndarray]:
    """Parameters as a PyTorch-style flat dict of numpy arrays keyed by dotted names.

    ``stacked=True``: ``params`` carries a leading layer axis and the keys are ``{prefix}layers.{i}.{name}``,
    as in torch's ``nn.TransformerEncoder`` / ``nn.TransformerDecoder``.
    """
    if stacked:
        out = {}
        for i, layer in enumerate(unstack_layers(params)):
            out.update(state_dict(layer, f"{prefix}layers.{i}."))
        return out
    return {name: np.asarray(leaf) for name, leaf in _named_leaves(params, prefix)}


def load_state_dict(template: NamedTuple, weights, prefix: str = "", *, stacked: bool = False) -> NamedTuple:
    """Fill ``template``'s structure from a flat dict of arrays (torch tensors: pass ``t.numpy()``).

    ``template`` gives the structure and shapes (e.g. from an ``init_*`` function); every leaf must be present
    in ``weights`` under its dotted name with the template's shape, else ``ValueError``.
    """
    if stacked:
        layers = [
            load_state_dict(layer, weights, f"{prefix}layers.{i}.") for i, layer in enumerate(unstack_layers(template))
        ]
        return stack_layers(layers)
    names = [name for name, _ in _named_leaves(template, prefix)]
    leaves, treedef = jax.tree.flatten(template)
    loaded = []
    for name, leaf in zip(names, leaves):
        if name not in weights:
            raise ValueError(f"weights: missing key {name!r}")
        value = jnp.asarray(np.asarray(weights[name]), dtype=leaf.dtype)
        if value.shape != leaf.shape:
            raise ValueError(f"weights[{name!r}]: expected shape {leaf.shape}, got {value.shape}")
        loaded.append(value)
    return jax.tree.unflatten(treedef, loaded)


# ------------------------------------------------------------------------------------------------- layers


def sinusoidal_encoding(positions: jax.Array, dim: int) -> jax.Array:
    """Sinusoidal position codes: ``positions [T]`` (int or float) -> ``[T, dim]`` float32.

    Column ``2i`` is ``sin(p / 10000^(2i/dim))`` and column ``2i+1`` is ``cos`` of the same angle (ACTOR's
    ``PositionalEncoding``; add ``sinusoidal_encoding(jnp.arange(T), D)`` to a ``[B, T, D]`` sequence).
    """
    positions = jnp.asarray(positions)
    if positions.ndim != 1:
        raise ValueError(f"positions: expected shape [T], got {positions.shape}")
    if dim < 1:
        raise ValueError(f"dim: expected >= 1, got {dim}")
    column = np.arange(dim)
    inv_freq = jnp.asarray(np.exp((column - column % 2) * (-math.log(10000.0) / dim)), jnp.float32)  # [D]
    angle = positions.astype(jnp.float32)[:, None] * inv_freq
    return jnp.where(column % 2 == 0, jnp.sin(angle), jnp.cos(angle))


def _check_sequence(name: str, x: jax.Array, dim: int | None = None, batch: int | None = None) -> None:
    expected = f"[{'B' if batch is None else batch}, T, {'D' if dim is None else dim}]"
    if x.ndim != 3 or (dim is not None and x.shape[2] != dim) or (batch is not None and x.shape[0] != batch):
        raise ValueError(f"{name}: expected shape {expected}, got {x.shape}")


def _check_mask(name: str, mask: jax.Array | None, batch: int, length: int) -> None:
    if mask is not None and mask.shape != (batch, length):
        raise ValueError(f"{name}: expected shape [B, T] = {(batch, length)} (True = real token), got {mask.shape}")


def multi_head_attention(
    p: AttentionParams,
    query: jax.Array,
    key_value: jax.Array,
    *,
    num_heads: int,
    key_padding_mask: jax.Array | None = None,
    causal: bool = False,
    dropout_rate: float = 0.0,
    dropout_key: jax.Array | None = None,
) -> jax.Array:
    """Scaled dot-product attention of ``query [B, Tq, D]`` over ``key_value [B, Tk, D]`` -> ``[B, Tq, D]``.

    torch ``nn.MultiheadAttention(query, key_value, key_value)``: project with ``in_proj``, split ``D`` into
    ``num_heads`` contiguous heads of ``D / num_heads``, ``softmax(q kᵀ / √(D / num_heads))`` over allowed
    keys, dropout on those weights (only with ``dropout_key``), weighted sum of values, ``out_proj``.

    ``key_padding_mask [B, Tk]``: True = real key; padded keys get zero weight. ``causal``: query ``t`` sees
    keys ``≤ t`` only (needs ``Tq == Tk``). A query that sees no key at all gets zero weights, so its output
    is ``out_proj.bias`` (torch gives NaN there).
    """
    _check_sequence("query", query)
    batch, len_q, dim = query.shape
    _check_sequence("key_value", key_value, dim=dim, batch=batch)
    len_k = key_value.shape[1]
    if dim % num_heads:
        raise ValueError(f"num_heads: must divide the model width D={dim}, got {num_heads}")
    if p.in_proj_weight.shape != (3 * dim, dim):
        raise ValueError(f"p.in_proj_weight: expected shape [3D, D] = {(3 * dim, dim)}, got {p.in_proj_weight.shape}")
    _check_mask("key_padding_mask", key_padding_mask, batch, len_k)
    if causal and len_q != len_k:
        raise ValueError(f"causal: needs as many queries as keys, got Tq={len_q}, Tk={len_k}")

    w_q, w_k, w_v = jnp.split(p.in_proj_weight, 3)
    b_q, b_k, b_v = jnp.split(p.in_proj_bias, 3)
    head_dim = dim // num_heads

    def heads(x, w, b):  # [B, T, D] -> [B, T, H, D/H]
        return (x @ w.T + b).reshape(*x.shape[:2], num_heads, head_dim)

    if len_k == 1:
        # One key (ACTOR's decoder reads a single memory token): its softmax weight is exactly 1 (0 when
        # padded), whatever the query, so the query and key projections are skipped and out_proj is applied
        # once per head and sequence: ~15% of a decoder layer's products. Same dropout mask as below.
        allowed = jnp.ones((batch, 1), bool) if key_padding_mask is None else key_padding_mask.astype(bool)
        weights = jnp.broadcast_to(allowed[:, None, :], (batch, num_heads, len_q)).astype(query.dtype)
        weights = dropout(weights[..., None], dropout_rate, dropout_key)[..., 0]  # [B, H, Tq]
        v = heads(key_value, w_v, b_v)[:, 0]  # [B, H, D/H]
        per_head = jnp.einsum("bhe,dhe->bhd", v, p.out_proj.weight.reshape(dim, num_heads, head_dim))
        return jnp.einsum("bhq,bhd->bqd", weights, per_head) + p.out_proj.bias

    q = heads(query, w_q, b_q) * (1.0 / math.sqrt(head_dim))
    k = heads(key_value, w_k, b_k)
    v = heads(key_value, w_v, b_v)
    scores = jnp.einsum("bqhd,bkhd->bhqk", q, k)

    allowed = jnp.ones((1, 1, len_q, len_k), bool)
    if key_padding_mask is not None:
        allowed = allowed & key_padding_mask.astype(bool)[:, None, None, :]
    if causal:
        allowed = allowed & jnp.tril(jnp.ones((len_q, len_k), bool))
    # A finite fill (not −inf) keeps fully masked rows NaN-free; their weights are then zeroed.
    scores = jnp.where(allowed, scores, jnp.finfo(scores.dtype).min)
    weights = jax.nn.softmax(scores, axis=-1) * allowed.any(-1, keepdims=True)
    weights = dropout(weights, dropout_rate, dropout_key)
    context = jnp.einsum("bhqk,bkhd->bqhd", weights, v).reshape(batch, len_q, dim)
    return linear(p.out_proj, context)


def feed_forward(
    linear1: LinearParams,
    linear2: LinearParams,
    x: jax.Array,
    *,
    activation: str = "gelu",
    dropout_rate: float = 0.0,
    dropout_key: jax.Array | None = None,
) -> jax.Array:
    """``linear2(drop(act(linear1(x))))``: ``x [..., D]`` -> ``[..., D]``; ``activation`` ``"gelu"`` (exact,
    erf-based, as torch) or ``"relu"``."""
    if activation == "gelu":
        act = jax.nn.gelu(linear(linear1, x), approximate=False)
    elif activation == "relu":
        act = jax.nn.relu(linear(linear1, x))
    else:
        raise ValueError(f"activation: expected 'gelu' or 'relu', got {activation!r}")
    return linear(linear2, dropout(act, dropout_rate, dropout_key))


def _residual(x, norm, sublayer, *, norm_first, eps, dropout_rate, dropout_key, num_queries=None):
    """One residual block: post-norm ``LN(x + drop(f(x)))`` or pre-norm ``x + drop(f(LN(x)))``; with
    ``num_queries``, ``f`` returns the first ``num_queries`` positions only and so does the block."""
    kept = x if num_queries is None else x[:, :num_queries]
    if norm_first:
        return kept + dropout(sublayer(layer_norm(norm, x, eps)), dropout_rate, dropout_key)
    return layer_norm(norm, kept + dropout(sublayer(x), dropout_rate, dropout_key), eps)


def encoder_layer(
    p: EncoderLayerParams,
    x: jax.Array,
    *,
    num_heads: int,
    key_padding_mask: jax.Array | None = None,
    causal: bool = False,
    activation: str = "gelu",
    norm_first: bool = False,
    layer_norm_eps: float = 1e-5,
    dropout_rate: float = 0.0,
    dropout_key: jax.Array | None = None,
    num_queries: int | None = None,
) -> jax.Array:
    """One encoder layer, ``x [B, T, D]`` -> ``[B, T, D]``: self-attention, then FF, each a residual block
    (post-norm like torch 1.7 by default, pre-norm with ``norm_first``).

    ``key_padding_mask [B, T]``: True = real token. Padded positions still get outputs (computed from the
    real tokens); the caller ignores them. ``num_queries``: compute only the first ``num_queries`` outputs,
    ``[B, num_queries, D]``, still attending over all of ``x`` (for a last layer whose other outputs are
    never read).
    """
    _check_sequence("x", x)
    if num_queries is not None and (causal or not 1 <= num_queries <= x.shape[1]):
        raise ValueError(f"num_queries: expected 1..T = {x.shape[1]} without causal, got {num_queries} "
                         f"(causal={causal})")
    k_att, k_drop1, k_ff, k_drop2 = split_key(dropout_key, 4)
    block = {"norm_first": norm_first, "eps": layer_norm_eps, "dropout_rate": dropout_rate}

    def self_attention(h):
        queries = h if num_queries is None else h[:, :num_queries]
        return multi_head_attention(
            p.self_attn, queries, h, num_heads=num_heads, key_padding_mask=key_padding_mask, causal=causal,
            dropout_rate=dropout_rate, dropout_key=k_att,
        )

    def ff(h):
        return feed_forward(p.linear1, p.linear2, h, activation=activation, dropout_rate=dropout_rate, dropout_key=k_ff)

    x = _residual(x, p.norm1, self_attention, dropout_key=k_drop1, num_queries=num_queries, **block)
    return _residual(x, p.norm2, ff, dropout_key=k_drop2, **block)


def decoder_layer(
    p: DecoderLayerParams,
    tgt: jax.Array,
    memory: jax.Array,
    *,
    num_heads: int,
    tgt_key_padding_mask: jax.Array | None = None,
    memory_key_padding_mask: jax.Array | None = None,
    causal: bool = False,
    activation: str = "gelu",
    norm_first: bool = False,
    layer_norm_eps: float = 1e-5,
    dropout_rate: float = 0.0,
    dropout_key: jax.Array | None = None,
) -> jax.Array:
    """One decoder layer, ``tgt [B, T, D]`` attending to ``memory [B, S, D]`` -> ``[B, T, D]``.

    Self-attention over ``tgt`` (``tgt_key_padding_mask [B, T]``, optional ``causal``), cross-attention
    on ``memory`` (``memory_key_padding_mask [B, S]``), FF; each a residual block (post-norm like torch 1.7
    by default; ``norm_first=True, activation="relu", layer_norm_eps=1e-6`` is joeynmt's layer).
    """
    _check_sequence("tgt", tgt)
    _check_sequence("memory", memory, dim=tgt.shape[2], batch=tgt.shape[0])
    k_self, k_drop1, k_cross, k_drop2, k_ff, k_drop3 = split_key(dropout_key, 6)
    block = {"norm_first": norm_first, "eps": layer_norm_eps, "dropout_rate": dropout_rate}

    def self_attention(h):
        return multi_head_attention(
            p.self_attn, h, h, num_heads=num_heads, key_padding_mask=tgt_key_padding_mask, causal=causal,
            dropout_rate=dropout_rate, dropout_key=k_self,
        )

    def cross_attention(h):
        return multi_head_attention(
            p.multihead_attn, h, memory, num_heads=num_heads, key_padding_mask=memory_key_padding_mask,
            dropout_rate=dropout_rate, dropout_key=k_cross,
        )

    def ff(h):
        return feed_forward(p.linear1, p.linear2, h, activation=activation, dropout_rate=dropout_rate, dropout_key=k_ff)

    tgt = _residual(tgt, p.norm1, self_attention, dropout_key=k_drop1, **block)
    tgt = _residual(tgt, p.norm2, cross_attention, dropout_key=k_drop2, **block)
    return _residual(tgt, p.norm3, ff, dropout_key=k_drop3, **block)


# ------------------------------------------------------------------------------------------------- stacks


def _num_layers(stacked: NamedTuple) -> int:
    leaves = jax.tree.leaves(stacked)
    if not leaves or any(leaf.ndim == 0 or leaf.shape[0] != leaves[0].shape[0] for leaf in leaves):
        raise ValueError("p: expected layer parameters stacked on a leading axis L (see stack_layers)")
    return leaves[0].shape[0]


def _scan_layers(layer_fn, p, x, dropout_key, last_layer_fn=None, unroll=False):
    """``layer_fn`` over the stacked layers with ``lax.scan`` (traced unrolled with ``unroll``);
    ``last_layer_fn``, when given, runs the last one instead (same parameters and key)."""
    num_layers = _num_layers(p)
    keys = None if dropout_key is None else jax.random.split(dropout_key, num_layers)

    def step(h, layer):
        layer_params, key = layer
        return layer_fn(layer_params, h, key), None

    if last_layer_fn is None:
        return jax.lax.scan(step, x, (p, keys), unroll=unroll)[0]
    h = jax.lax.scan(step, x, jax.tree.map(lambda a: a[:-1], (p, keys)), unroll=unroll)[0]
    return last_layer_fn(jax.tree.map(lambda a: a[-1], p), h, None if keys is None else keys[-1])


def encoder_stack(
    p: EncoderLayerParams,
    x: jax.Array,
    *,
    num_heads: int,
    key_padding_mask: jax.Array | None = None,
    causal: bool = False,
    activation: str = "gelu",
    norm_first: bool = False,
    layer_norm_eps: float = 1e-5,
    dropout_rate: float = 0.0,
    dropout_key: jax.Array | None = None,
    num_queries: int | None = None,
    unroll: bool = False,
) -> jax.Array:
    """``L`` encoder layers (parameters stacked on a leading axis ``L``) run with ``lax.scan``:
    ``x [B, T, D]`` -> ``[B, T, D]``, no final norm (torch ``nn.TransformerEncoder(norm=None)``). Layer ``i``
    gets ``jax.random.split(dropout_key, L)[i]``. ``num_queries``: the last layer computes only the first
    ``num_queries`` outputs (``[B, num_queries, D]``). ``unroll``: trace the layer loop unrolled (same
    result; compiles slower, and on CPU differentiates faster); other arguments as :func:`encoder_layer`."""

    def layer(lp, h, key, queries=None):
        return encoder_layer(
            lp, h, num_heads=num_heads, key_padding_mask=key_padding_mask, causal=causal, activation=activation,
            norm_first=norm_first, layer_norm_eps=layer_norm_eps, dropout_rate=dropout_rate, dropout_key=key,
            num_queries=queries,
        )

    last = None if num_queries is None else functools.partial(layer, queries=num_queries)
    return _scan_layers(layer, p, x, dropout_key, last, unroll)


def decoder_stack(
    p: DecoderLayerParams,
    tgt: jax.Array,
    memory: jax.Array,
    *,
    num_heads: int,
    tgt_key_padding_mask: jax.Array | None = None,
    memory_key_padding_mask: jax.Array | None = None,
    causal: bool = False,
    activation: str = "gelu",
    norm_first: bool = False,
    layer_norm_eps: float = 1e-5,
    dropout_rate: float = 0.0,
    dropout_key: jax.Array | None = None,
    unroll: bool = False,
) -> jax.Array:
    """``L`` decoder layers (parameters stacked on a leading axis ``L``) run with ``lax.scan``, every layer
    attending to the same ``memory [B, S, D]``: ``tgt [B, T, D]`` -> ``[B, T, D]``, no final norm. Layer ``i``
    gets ``jax.random.split(dropout_key, L)[i]``; ``unroll`` as :func:`encoder_stack`; other arguments as
    :func:`decoder_layer`."""

    def layer(lp, h, key):
        return decoder_layer(
            lp, h, memory, num_heads=num_heads, tgt_key_padding_mask=tgt_key_padding_mask,
            memory_key_padding_mask=memory_key_padding_mask, causal=causal, activation=activation,
            norm_first=norm_first, layer_norm_eps=layer_norm_eps, dropout_rate=dropout_rate, dropout_key=key,
        )

    return _scan_layers(layer, p, tgt, dropout_key, unroll=unroll)
