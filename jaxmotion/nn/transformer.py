"""Transformer layers as pure functions over explicit parameter pytrees, stacked with ``lax.scan``.

Where it is used:

* **ACTOR's transformer VAE** (``src/models/architectures/transformer.py``): torch 1.7
  ``nn.TransformerEncoderLayer`` / ``nn.TransformerDecoderLayer`` with d=256, 4 heads, FF 1024, dropout 0.1,
  GELU; post-norm, no final norm; sinusoidal positions (:func:`sinusoidal_encoding`).
* **ACTOR's autoregressive baseline** (``autotrans.py``, layers from joeynmt): pre-norm decoder layers
  (LayerNorm eps 1e-6 before each sublayer, ReLU FF), causal self-attention; the caller applies the final
  LayerNorm. Same functions with ``TransformerOptions(norm_first=True, activation="relu", layer_norm_eps=1e-6,
  causal=True)``; generation decodes one frame at a time through a key/value cache (below).

Layout is batch first, ``[B, T, D]`` (torch 1.7 is sequence first: transpose axes 0 and 1). Masks are
boolean with **True = real token** (torch's ``key_padding_mask`` is the negation). Every function is
jittable. A stack's settings (heads, activation, norm placement, LayerNorm eps, dropout rate, causal
self-attention, unrolled layer loop) are one frozen :class:`TransformerOptions`, a static (hashable) value
under ``jit``; what changes per call (masks, memory, dropout key) stays an argument.

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
  with ``lax.scan``, so compile time does not grow with depth (``options.unroll`` traces them unrolled); the
  dropout key is split into one per layer. An encoder stack's ``num_queries`` limits its last layer to the
  outputs the caller reads.
* **Cached decoding** (generation, eval mode): :func:`init_decoder_cache` preallocates the self-attention
  keys and values of every layer for ``T`` positions and computes the memory's cross-attention keys and
  values once; :func:`decoder_stack_step` decodes position ``t`` (a traced index, so a ``lax.scan`` over
  frames compiles once) from its input token, writes its keys and values at ``t`` and attends over
  positions ``≤ t``. It shares the attention, residual and FF code of :func:`decoder_layer`, so it equals
  the full causal pass frame by frame (``tests/test_transformer.py``). No dropout: a step takes no key.
* **Initialisation** is PyTorch's default: ``Linear`` and LayerNorm as in :mod:`jaxmotion.nn.core`;
  ``MultiheadAttention`` ``in_proj_weight`` xavier-uniform over ``[3D, D]``, zero ``in_proj_bias`` and
  ``out_proj.bias``, ``out_proj.weight`` as a ``Linear``. torch's ``nn.TransformerEncoder`` /
  ``nn.TransformerDecoder`` deep-copy one layer, so all layers start identical (``clone=True``, ACTOR's
  case); joeynmt builds each layer separately and its q / k / v / output projections are plain ``Linear``
  layers with biases (``clone=False, separate_projections=True``).
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Sequence
from typing import Literal, NamedTuple

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

# -------------------------------------------------------------------------------------------------- options


@dataclasses.dataclass(frozen=True)
class TransformerOptions:
    """The settings a layer or stack runs with, static under ``jit``. Defaults are torch 1.7's layers
    (post-norm, GELU, eps 1e-5, no dropout, no causal mask); ACTOR's autoregressive decoder (joeynmt) is
    ``TransformerOptions(heads, activation="relu", norm_first=True, layer_norm_eps=1e-6, causal=True)``.

    ``dropout_rate`` applies only when a call passes a ``dropout_key`` (no key = eval mode). ``causal``:
    self-attention position ``t`` sees positions ``≤ t`` only. ``unroll``: stacks trace their layer loop
    unrolled (same result; compiles slower, and on CPU differentiates faster).
    """

    num_heads: int
    activation: Literal["gelu", "relu"] = "gelu"
    norm_first: bool = False
    layer_norm_eps: float = 1e-5
    dropout_rate: float = 0.0
    causal: bool = False
    unroll: bool = False

    def __post_init__(self):
        if not isinstance(self.num_heads, int) or self.num_heads < 1:
            raise ValueError(f"TransformerOptions.num_heads: expected an int >= 1, got {self.num_heads!r}")
        if self.activation not in ("gelu", "relu"):
            raise ValueError(f"TransformerOptions.activation: expected 'gelu' or 'relu', got {self.activation!r}")
        if not self.layer_norm_eps > 0:
            raise ValueError(f"TransformerOptions.layer_norm_eps: expected > 0, got {self.layer_norm_eps}")
        if not 0.0 <= self.dropout_rate < 1.0:
            raise ValueError(f"TransformerOptions.dropout_rate: expected in [0, 1), got {self.dropout_rate}")


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


def _project(p: AttentionParams, x: jax.Array, part: int, num_heads: int) -> jax.Array:
    """``x [B, T, D]`` through the query (``part`` 0), key (1) or value (2) rows of ``in_proj``, split into
    heads, heads first: ``[B, H, T, D/H]`` (the layout of the attention products, and of the cache)."""
    batch, length, dim = x.shape
    rows = slice(part * dim, (part + 1) * dim)
    heads = (x @ p.in_proj_weight[rows].T + p.in_proj_bias[rows]).reshape(batch, length, num_heads, dim // num_heads)
    return heads.transpose(0, 2, 1, 3)


def _attend(
    out_proj: LinearParams,
    q: jax.Array,
    k: jax.Array,
    v: jax.Array,
    allowed: jax.Array,
    dropout_rate: float,
    dropout_key: jax.Array | None,
) -> jax.Array:
    """Heads ``q [B, H, Tq, e]`` over ``k, v [B, H, Tk, e]`` where ``allowed`` (broadcasting to
    ``[B, H, Tq, Tk]``) -> ``out_proj(context) [B, Tq, H·e]``: softmax of scaled scores over the allowed
    keys, zero weights for a query that sees none, dropout on the weights."""
    batch, num_heads, len_q, head_dim = q.shape
    scores = jnp.einsum("bhqd,bhkd->bhqk", q * (1.0 / math.sqrt(head_dim)), k)
    # A finite fill (not −inf) keeps fully masked rows NaN-free; their weights are then zeroed.
    scores = jnp.where(allowed, scores, jnp.finfo(scores.dtype).min)
    weights = jax.nn.softmax(scores, axis=-1) * allowed.any(-1, keepdims=True)
    weights = dropout(weights, dropout_rate, dropout_key)
    context = jnp.einsum("bhqk,bhkd->bqhd", weights, v).reshape(batch, len_q, num_heads * head_dim)
    return linear(out_proj, context)


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

    if len_k == 1:
        # One key (ACTOR's decoder reads a single memory token): its softmax weight is exactly 1 (0 when
        # padded), whatever the query, so the query and key projections are skipped and out_proj is applied
        # once per head and sequence: ~15% of a decoder layer's products. Same dropout mask as _attend's.
        allowed = jnp.ones((batch, 1), bool) if key_padding_mask is None else key_padding_mask.astype(bool)
        weights = jnp.broadcast_to(allowed[:, None, :], (batch, num_heads, len_q)).astype(query.dtype)
        weights = dropout(weights[..., None], dropout_rate, dropout_key)[..., 0]  # [B, H, Tq]
        v = _project(p, key_value, 2, num_heads)[:, :, 0]  # [B, H, D/H]
        per_head = jnp.einsum("bhe,dhe->bhd", v, p.out_proj.weight.reshape(dim, num_heads, dim // num_heads))
        return jnp.einsum("bhq,bhd->bqd", weights, per_head) + p.out_proj.bias

    allowed = jnp.ones((1, 1, len_q, len_k), bool)
    if key_padding_mask is not None:
        allowed = allowed & key_padding_mask.astype(bool)[:, None, None, :]
    if causal:
        allowed = allowed & jnp.tril(jnp.ones((len_q, len_k), bool))
    q, k, v = (_project(p, x, part, num_heads) for part, x in enumerate((query, key_value, key_value)))
    return _attend(p.out_proj, q, k, v, allowed, dropout_rate, dropout_key)


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


def _layer_feed_forward(p: EncoderLayerParams | DecoderLayerParams, h: jax.Array, options: TransformerOptions,
                        dropout_key: jax.Array | None) -> jax.Array:
    return feed_forward(p.linear1, p.linear2, h, activation=options.activation, dropout_rate=options.dropout_rate,
                        dropout_key=dropout_key)


def _sublayer_input(x: jax.Array, norm: LayerNormParams, options: TransformerOptions) -> jax.Array:
    """What a residual block's sublayer reads: ``LN(x)`` (pre-norm) or ``x`` (post-norm)."""
    return layer_norm(norm, x, options.layer_norm_eps) if options.norm_first else x


def _add_residual(kept: jax.Array, out: jax.Array, norm: LayerNormParams, options: TransformerOptions,
                  dropout_key: jax.Array | None) -> jax.Array:
    """A residual block's output from its input ``kept`` and sublayer output ``out``: post-norm
    ``LN(kept + drop(out))`` or pre-norm ``kept + drop(out)``."""
    out = dropout(out, options.dropout_rate, dropout_key)
    return kept + out if options.norm_first else layer_norm(norm, kept + out, options.layer_norm_eps)


def _residual(x, norm, sublayer, options, dropout_key, num_queries=None):
    """One residual block, ``sublayer`` applied to :func:`_sublayer_input`; with ``num_queries``, ``sublayer``
    returns the first ``num_queries`` positions only and so does the block."""
    kept = x if num_queries is None else x[:, :num_queries]
    return _add_residual(kept, sublayer(_sublayer_input(x, norm, options)), norm, options, dropout_key)


def encoder_layer(
    p: EncoderLayerParams,
    x: jax.Array,
    options: TransformerOptions,
    *,
    key_padding_mask: jax.Array | None = None,
    dropout_key: jax.Array | None = None,
    num_queries: int | None = None,
) -> jax.Array:
    """One encoder layer, ``x [B, T, D]`` -> ``[B, T, D]``: self-attention, then FF, each a residual block
    (post-norm like torch 1.7 by default, pre-norm with ``options.norm_first``).

    ``key_padding_mask [B, T]``: True = real token. Padded positions still get outputs (computed from the
    real tokens); the caller ignores them. ``num_queries``: compute only the first ``num_queries`` outputs,
    ``[B, num_queries, D]``, still attending over all of ``x`` (for a last layer whose other outputs are
    never read).
    """
    _check_sequence("x", x)
    if num_queries is not None and (options.causal or not 1 <= num_queries <= x.shape[1]):
        raise ValueError(f"num_queries: expected 1..T = {x.shape[1]} without causal, got {num_queries} "
                         f"(causal={options.causal})")
    k_att, k_drop1, k_ff, k_drop2 = split_key(dropout_key, 4)

    def self_attention(h):
        queries = h if num_queries is None else h[:, :num_queries]
        return multi_head_attention(
            p.self_attn, queries, h, num_heads=options.num_heads, key_padding_mask=key_padding_mask,
            causal=options.causal, dropout_rate=options.dropout_rate, dropout_key=k_att,
        )

    x = _residual(x, p.norm1, self_attention, options, k_drop1, num_queries)
    return _residual(x, p.norm2, lambda h: _layer_feed_forward(p, h, options, k_ff), options, k_drop2)


def _decoder_blocks(p: DecoderLayerParams, tgt: jax.Array, options: TransformerOptions, self_attention,
                    cross_attention, dropout_key: jax.Array | None):
    """A decoder layer's three residual blocks around ``self_attention(h, key) -> (out, state)`` and
    ``cross_attention(h, key) -> out``: ``(tgt [B, T, D], state)``. The full pass (:func:`decoder_layer`)
    and the cached step (:func:`decoder_stack_step`) differ only in those two functions."""
    k_self, k_drop1, k_cross, k_drop2, k_ff, k_drop3 = split_key(dropout_key, 6)
    attended, state = self_attention(_sublayer_input(tgt, p.norm1, options), k_self)
    tgt = _add_residual(tgt, attended, p.norm1, options, k_drop1)
    tgt = _residual(tgt, p.norm2, lambda h: cross_attention(h, k_cross), options, k_drop2)
    return _residual(tgt, p.norm3, lambda h: _layer_feed_forward(p, h, options, k_ff), options, k_drop3), state


def decoder_layer(
    p: DecoderLayerParams,
    tgt: jax.Array,
    memory: jax.Array,
    options: TransformerOptions,
    *,
    tgt_key_padding_mask: jax.Array | None = None,
    memory_key_padding_mask: jax.Array | None = None,
    dropout_key: jax.Array | None = None,
) -> jax.Array:
    """One decoder layer, ``tgt [B, T, D]`` attending to ``memory [B, S, D]`` -> ``[B, T, D]``.

    Self-attention over ``tgt`` (``tgt_key_padding_mask [B, T]``, causal with ``options.causal``),
    cross-attention on ``memory`` (``memory_key_padding_mask [B, S]``), FF; each a residual block
    (post-norm like torch 1.7 by default; joeynmt's layer with the options in :class:`TransformerOptions`).
    """
    _check_sequence("tgt", tgt)
    _check_sequence("memory", memory, dim=tgt.shape[2], batch=tgt.shape[0])
    attention = functools.partial(multi_head_attention, num_heads=options.num_heads,
                                  dropout_rate=options.dropout_rate)

    def self_attention(h, key):
        out = attention(p.self_attn, h, h, key_padding_mask=tgt_key_padding_mask, causal=options.causal,
                        dropout_key=key)
        return out, None

    def cross_attention(h, key):
        return attention(p.multihead_attn, h, memory, key_padding_mask=memory_key_padding_mask, dropout_key=key)

    return _decoder_blocks(p, tgt, options, self_attention, cross_attention, dropout_key)[0]


# ------------------------------------------------------------------------------------------------- stacks


def _num_layers(stacked: NamedTuple) -> int:
    leaves = jax.tree.leaves(stacked)
    if not leaves or any(leaf.ndim == 0 or leaf.shape[0] != leaves[0].shape[0] for leaf in leaves):
        raise ValueError("p: expected layer parameters stacked on a leading axis L (see stack_layers)")
    return leaves[0].shape[0]


def _scan_layers(layer_fn, carry, per_layer, unroll, last_layer_fn=None):
    """``carry = layer_fn(carry, layer)`` for each slice ``layer`` of ``per_layer`` (a pytree whose leaves
    have a leading layer axis ``L``) with ``lax.scan`` (traced unrolled with ``unroll``);
    ``last_layer_fn``, when given, runs the last slice instead."""

    def step(c, layer):
        return layer_fn(c, layer), None

    if last_layer_fn is None:
        return jax.lax.scan(step, carry, per_layer, unroll=unroll)[0]
    carry = jax.lax.scan(step, carry, jax.tree.map(lambda a: a[:-1], per_layer), unroll=unroll)[0]
    return last_layer_fn(carry, jax.tree.map(lambda a: a[-1], per_layer))


def _with_layer_keys(p: NamedTuple, dropout_key: jax.Array | None) -> tuple:
    """``(p, keys)`` to scan over: layer ``i`` gets ``jax.random.split(dropout_key, L)[i]`` (None: no keys)."""
    return p, None if dropout_key is None else jax.random.split(dropout_key, _num_layers(p))


def encoder_stack(
    p: EncoderLayerParams,
    x: jax.Array,
    options: TransformerOptions,
    *,
    key_padding_mask: jax.Array | None = None,
    dropout_key: jax.Array | None = None,
    num_queries: int | None = None,
) -> jax.Array:
    """``L`` encoder layers (parameters stacked on a leading axis ``L``) run with ``lax.scan``:
    ``x [B, T, D]`` -> ``[B, T, D]``, no final norm (torch ``nn.TransformerEncoder(norm=None)``). Layer ``i``
    gets ``jax.random.split(dropout_key, L)[i]``. ``num_queries``: the last layer computes only the first
    ``num_queries`` outputs (``[B, num_queries, D]``); other arguments as :func:`encoder_layer`."""

    def layer(h, layer_and_key, queries=None):
        lp, key = layer_and_key
        return encoder_layer(lp, h, options, key_padding_mask=key_padding_mask, dropout_key=key,
                             num_queries=queries)

    last = None if num_queries is None else functools.partial(layer, queries=num_queries)
    return _scan_layers(layer, x, _with_layer_keys(p, dropout_key), options.unroll, last)


def decoder_stack(
    p: DecoderLayerParams,
    tgt: jax.Array,
    memory: jax.Array,
    options: TransformerOptions,
    *,
    tgt_key_padding_mask: jax.Array | None = None,
    memory_key_padding_mask: jax.Array | None = None,
    dropout_key: jax.Array | None = None,
) -> jax.Array:
    """``L`` decoder layers (parameters stacked on a leading axis ``L``) run with ``lax.scan``, every layer
    attending to the same ``memory [B, S, D]``: ``tgt [B, T, D]`` -> ``[B, T, D]``, no final norm. Layer ``i``
    gets ``jax.random.split(dropout_key, L)[i]``; other arguments as :func:`decoder_layer`."""

    def layer(h, layer_and_key):
        lp, key = layer_and_key
        return decoder_layer(lp, h, memory, options, tgt_key_padding_mask=tgt_key_padding_mask,
                             memory_key_padding_mask=memory_key_padding_mask, dropout_key=key)

    return _scan_layers(layer, tgt, _with_layer_keys(p, dropout_key), options.unroll)


# ----------------------------------------------------------------------------------------- cached decoding


class DecoderCache(NamedTuple):
    """What :func:`decoder_stack_step` needs besides the parameters, preallocated for ``T`` positions. One
    array per layer (tuples of ``L``), not one stacked on ``L``: the step's layer loop is unrolled and reads
    each layer's keys and values in place, where slicing a stacked buffer at a traced layer index copies them
    at every step (that doubled the memory traffic of 240-frame decoding on CPU)."""

    keys: tuple[jax.Array, ...]  # L x [B, H, T, D/H] self-attention keys; positions not decoded yet hold zeros
    values: tuple[jax.Array, ...]  # L x [B, H, T, D/H]
    memory_keys: tuple[jax.Array, ...]  # L x [B, H, S, D/H] cross-attention keys of the memory, computed once
    memory_values: tuple[jax.Array, ...]  # L x [B, H, S, D/H]
    target_mask: jax.Array  # [B, T] bool, True = real position (the full pass's tgt_key_padding_mask)
    memory_mask: jax.Array  # [B, S] bool, True = real memory token


def init_decoder_cache(
    p: DecoderLayerParams,
    memory: jax.Array,
    length: int,
    options: TransformerOptions,
    *,
    tgt_key_padding_mask: jax.Array | None = None,
    memory_key_padding_mask: jax.Array | None = None,
) -> DecoderCache:
    """The cache for decoding positions ``0 .. length − 1`` of a causal decoder stack one at a time
    (:func:`decoder_stack_step`): zero self-attention keys and values, and the cross-attention keys and
    values of ``memory [B, S, D]`` for every layer, computed here once per sequence.

    ``tgt_key_padding_mask [B, length]`` and ``memory_key_padding_mask [B, S]`` (True = real) are the masks
    the full pass (:func:`decoder_stack`) would get; ``options`` must be the full pass's, with ``causal``.
    """
    if not options.causal:
        raise ValueError("options.causal: cached decoding reproduces causal self-attention; got causal=False "
                         "(a non-causal pass has to see later positions, which are not decoded yet)")
    _check_sequence("memory", memory)
    batch, len_s, dim = memory.shape
    if dim % options.num_heads:
        raise ValueError(f"options.num_heads: must divide the model width D={dim}, got {options.num_heads}")
    if not isinstance(length, int) or length < 1:
        raise ValueError(f"length: expected a Python int >= 1 (the positions to decode), got {length!r}")
    _check_mask("tgt_key_padding_mask", tgt_key_padding_mask, batch, length)
    _check_mask("memory_key_padding_mask", memory_key_padding_mask, batch, len_s)
    layers = unstack_layers(p)
    memory_keys = tuple(_project(lp.multihead_attn, memory, 1, options.num_heads) for lp in layers)
    memory_values = tuple(_project(lp.multihead_attn, memory, 2, options.num_heads) for lp in layers)
    empty = (jnp.zeros((batch, options.num_heads, length, dim // options.num_heads), memory.dtype),) * len(layers)
    target_mask = jnp.ones((batch, length), bool) if tgt_key_padding_mask is None else tgt_key_padding_mask
    memory_mask = jnp.ones((batch, len_s), bool) if memory_key_padding_mask is None else memory_key_padding_mask
    return DecoderCache(empty, empty, memory_keys, memory_values, target_mask.astype(bool), memory_mask.astype(bool))


def _cached_decoder_layer(lp: DecoderLayerParams, h: jax.Array, keys: jax.Array, values: jax.Array,
                          memory_keys: jax.Array, memory_values: jax.Array, position: jax.Array | int,
                          seen: jax.Array, memory_allowed: jax.Array, options: TransformerOptions):
    """One decoder layer at one position, ``h [B, 1, D]`` -> ``(h, keys, values)``, the layer's self-attention
    ``keys, values [B, H, T, D/H]`` with this position's written; ``seen`` and ``memory_allowed`` are the
    self- and cross-attention masks, broadcasting to ``[B, H, 1, T]`` and ``[B, H, 1, S]``."""
    num_heads = options.num_heads

    def self_attention(x, _):
        k, v = (jax.lax.dynamic_update_slice_in_dim(buffer, _project(lp.self_attn, x, part, num_heads), position, 2)
                for part, buffer in ((1, keys), (2, values)))
        q = _project(lp.self_attn, x, 0, num_heads)
        return _attend(lp.self_attn.out_proj, q, k, v, seen, 0.0, None), (k, v)

    def cross_attention(x, _):
        q = _project(lp.multihead_attn, x, 0, num_heads)
        return _attend(lp.multihead_attn.out_proj, q, memory_keys, memory_values, memory_allowed, 0.0, None)

    h, (keys, values) = _decoder_blocks(lp, h, options, self_attention, cross_attention, None)
    return h, keys, values


def decoder_stack_step(
    p: DecoderLayerParams,
    cache: DecoderCache,
    token: jax.Array,
    position: jax.Array | int,
    options: TransformerOptions,
) -> tuple[jax.Array, DecoderCache]:
    """Decode one position: ``token [B, D]``, the stack's input at ``position`` (a scalar int, may be traced),
    -> ``(out [B, D], cache)``: the output :func:`decoder_stack` gives at ``position`` when positions
    ``0 .. position − 1`` were decoded before with the same cache, and the cache with this position's keys
    and values written. Eval mode (no dropout); ``options`` as for :func:`init_decoder_cache` (the layer loop
    is unrolled whatever ``options.unroll`` says; see :class:`DecoderCache`).

    A concrete ``position`` past the cache is an error; a traced one is not checked (XLA clamps the write),
    so loop over ``jnp.arange(T)`` with ``T`` the cache's length.
    """
    batch, num_heads, length, head_dim = cache.keys[0].shape
    if token.shape != (batch, num_heads * head_dim):
        raise ValueError(f"token: expected [B, D] = {(batch, num_heads * head_dim)} (the cache's batch and width), "
                         f"got {token.shape}")
    if num_heads != options.num_heads or _num_layers(p) != len(cache.keys):
        raise ValueError(f"cache: built for {len(cache.keys)} layers of {num_heads} heads, but p has "
                         f"{_num_layers(p)} layers and options.num_heads = {options.num_heads}")
    if jnp.ndim(position) != 0:
        raise ValueError(f"position: expected a scalar int, got shape {jnp.shape(position)}")
    if not isinstance(position, jax.core.Tracer) and not 0 <= int(position) < length:
        raise ValueError(f"position: expected 0 <= position < {length} (the cache's length), got {int(position)}")
    seen = ((jnp.arange(length) <= position) & cache.target_mask)[:, None, None, :]  # causal and not padded
    memory_allowed = cache.memory_mask[:, None, None, :]

    h, keys, values = token[:, None], [], []  # h [B, 1, D]
    for lp, *layer_cache in zip(unstack_layers(p), cache.keys, cache.values, cache.memory_keys, cache.memory_values):
        h, layer_keys, layer_values = _cached_decoder_layer(lp, h, *layer_cache, position, seen, memory_allowed,
                                                            options)
        keys.append(layer_keys)
        values.append(layer_values)
    return h[:, 0], cache._replace(keys=tuple(keys), values=tuple(values))
