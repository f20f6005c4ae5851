"""ACTOR: the action-conditioned Transformer VAE (Petrovich et al. 2021) and its Table 2 baselines, as pure
functions.

The model on one screen (ACTOR's ``src/models/architectures/transformer.py``; paper §3.1):

* **Input** ``x [B, T, J, C]``: per frame the 24 joint rotations in ``rep`` (C = 6 for rot6d) and one extra
  "joint" holding the root translation relative to frame 0 (:func:`to_features`),
  with ``mask [B, T]`` marking real frames (a prefix of each row).
* **Encoder**: each frame is embedded by one linear layer (J·C -> d); the per-action distribution tokens
  ``mu_query[a]`` and ``sigma_query[a]`` are prepended; sinusoidal positional encodings (positions 0..T+1)
  are added; a post-norm Transformer encoder runs over the T + 2 tokens with padded frames masked; its
  outputs at the two tokens are μ and log σ².
* **Latent**: ``z = μ + exp(logvar / 2) · ε`` (training, denoising) or ``z ~ N(0, I)`` (generation).
* **Decoder**: the memory is one token, ``z + action_bias[a]``; the queries are the T positional encodings
  (zeros + PE(0..T-1)), padded queries masked; a post-norm Transformer decoder, then one linear layer
  (d -> J·C); padded frames are zeroed.

Table 2 ablations of the Transformer are switches of :class:`ActorConfig`: ``distribution_tokens=False``
(μ, logvar from two linear layers on the mean encoder output, ACTOR's ``average_encoder``),
``bias_token=False`` (the one-hot action concatenated to z, then a linear layer: ``zandtime``).

Table 2's other rows are ``ActorConfig.architecture`` (ACTOR's ``gru.py``, ``fc.py``, ``autotrans.py``).
Below, ``a`` is the one-hot action [K] and ``τ_t = t / (len − 1)`` the time channel (0 on padded frames),
both repeated per frame:

* ``"gru"``: encoder ``Linear(concat(x_t, a, τ_t)) -> d``, a ``layers``-deep GRU(d), its output at the last
  real frame ``len − 1``, two linear layers to μ / logvar; decoder ``Linear(concat(z, a, τ_t)) -> d``, a GRU,
  ``Linear(d -> J·C)``. No dropout (ACTOR's ``nn.GRU`` has none).
* ``"fc"``: fixed length ``T = config.frames``. Encoder ``(J·C·T + K) -> 2d -> d`` with GELU, then linear
  layers to μ / logvar; decoder ``(d + K) -> d -> 2d -> J·C·T`` with GELU after every layer, **the output
  included** (see :func:`_decode_fc`). The widths follow ``width``: the paper's d = 256 gives its 512 / 256.
  No dropout (ACTOR's ``fc.py`` has none).
* ``"autoregressive"``: ACTOR's Transformer encoder above (``autotrans.py`` imports it, distribution tokens
  included); decoder of joeynmt pre-norm layers (LayerNorm eps 1e-6, ReLU FF, causal self-attention),
  memory ``Linear(concat(z, a, τ_t))`` for every frame, target ``Linear(concat(x_{t−1}, a, τ_t)) + PE(t)``
  with ``x_{−1} = 0``, final LayerNorm, ``Linear(d -> J·C)`` without bias. ``autoencode(train=True)`` and
  :func:`decode` with a ``target`` use teacher forcing (the ground-truth previous frame); :func:`generate`,
  :func:`decode` without a target and ``autoencode(train=False)`` decode frame by frame, feeding each output
  back in, as ACTOR does outside training; they do it through a key/value cache
  (:func:`jaxmotion.nn.transformer.decoder_stack_step`), which gives the frames of re-running the causal pass
  for every frame at the cost of one pass.

Layers, heads, widths and dropout are fields; the rotation representation is the input's C. Parameters are
pytrees of NamedTuples in PyTorch's layout (``jaxmotion.nn.transformer``; field names follow ACTOR's modules);
every function is pure and jittable; dropout runs only when a key is given.

Axes: B batch, T frames, J joints (+1 translation row), C channels per joint, d model width, K classes,
L layers.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from typing import Literal, NamedTuple

import jax
import jax.numpy as jnp

from jaxmotion.config import check_at_least
from jaxmotion.geometry.kinematics import forward_kinematics
from jaxmotion.geometry.representations import rotation_features, split_rotation_features
from jaxmotion.geometry.rotations import REPRESENTATIONS, axis_angle_to_matrix
from jaxmotion.geometry.skeletons import Skeleton
from jaxmotion.data.labels import check_actions, check_durations
from jaxmotion.nn.core import (
    LayerNormParams,
    LinearParams,
    dropout,
    init_layer_norm,
    init_linear,
    layer_norm,
    linear,
    torch_uniform,
)
from jaxmotion.nn.recurrent import GRUParams, gru_stack, init_gru
from jaxmotion.nn.transformer import (
    DecoderLayerParams,
    EncoderLayerParams,
    TransformerOptions,
    decoder_stack,
    decoder_stack_step,
    encoder_stack,
    init_decoder_cache,
    init_decoder_stack,
    init_encoder_stack,
    sinusoidal_encoding,
)

Architecture = Literal["transformer", "gru", "fc", "autoregressive"]
ARCHITECTURES: tuple[str, ...] = ("transformer", "gru", "fc", "autoregressive")


@dataclasses.dataclass(frozen=True)
class ActorConfig:
    """ACTOR's architecture. Defaults are the paper's (d 256, 8 layers, 4 heads, FF 1024, dropout 0.1, GELU).

    ``rep``: the rotation representation of the input and output tensor (its channels C per joint); ``width``:
    d, the model width, which is also the size of z. ``architecture`` picks a Table 2 row (module docstring);
    ``distribution_tokens`` and ``bias_token`` are
    the Transformer's own ablations; ``frames`` is the fixed clip length of the ``"fc"`` variant (its input
    is J·C·T wide) and is ignored by the others. ``ff``, ``heads`` and ``activation`` are unused by ``"gru"``
    and ``"fc"``; the autoregressive decoder's FF is ReLU whatever ``activation`` says (joeynmt's layer).
    """

    num_classes: int
    num_joints: int = 25
    rep: Literal["axis_angle", "quaternion", "matrix", "rot6d"] = "rot6d"
    width: int = 256
    ff: int = 1024
    layers: int = 8
    heads: int = 4
    dropout: float = 0.1
    activation: Literal["gelu", "relu"] = "gelu"
    distribution_tokens: bool = True
    bias_token: bool = True
    architecture: Architecture = "transformer"
    frames: int = 60

    def __post_init__(self):
        if self.architecture not in ARCHITECTURES:
            raise ValueError(f"ActorConfig.architecture: expected one of {ARCHITECTURES}, got {self.architecture!r}")
        check_at_least(self, 1, "num_classes", "num_joints", "width", "ff", "layers", "heads", "frames")
        if self.architecture in ("transformer", "autoregressive") and self.width % self.heads:
            raise ValueError(f"ActorConfig: width ({self.width}) must be a multiple of heads ({self.heads})")
        if self.architecture != "transformer" and not (self.distribution_tokens and self.bias_token):
            raise ValueError(f"ActorConfig.distribution_tokens / bias_token: the token ablations apply to "
                             f"architecture 'transformer' only; leave both True for {self.architecture!r}")
        if not 0.0 <= self.dropout < 1.0:
            raise ValueError(f"ActorConfig.dropout must be in [0, 1), got {self.dropout}")

    @property
    def channels(self) -> int:
        """C: the numbers per joint of ``rep`` (6 for rot6d)."""
        return math.prod(REPRESENTATIONS[self.rep])

    @property
    def features(self) -> int:
        return self.num_joints * self.channels


# ----------------------------------------------------------------------------------------------- parameters


class ActorEncoderParams(NamedTuple):
    skel_embedding: LinearParams  # [d, J·C]
    mu_query: jax.Array | None  # [K, d], None without distribution tokens
    sigma_query: jax.Array | None  # [K, d]
    mu_layer: LinearParams | None  # [d, d], only without distribution tokens
    sigma_layer: LinearParams | None
    layers: EncoderLayerParams  # stacked on a leading axis L


class ActorDecoderParams(NamedTuple):
    action_biases: jax.Array | None  # [K, d], None without the bias token
    z_action_linear: LinearParams | None  # [d, d + K], only without the bias token
    layers: DecoderLayerParams  # stacked on a leading axis L
    final_layer: LinearParams  # [J·C, d]


class ActorParams(NamedTuple):
    """``architecture="transformer"``."""

    encoder: ActorEncoderParams
    decoder: ActorDecoderParams


class GruEncoderParams(NamedTuple):
    feats_embedding: LinearParams  # [d, J·C + K + 1]
    gru: tuple[GRUParams, ...]  # L layers of GRU(d, d); torch gru.weight_ih_l{i} = gru[i].w_ih, ...
    mu: LinearParams  # [d, d]
    var: LinearParams  # [d, d], gives logvar (ACTOR's name)


class GruDecoderParams(NamedTuple):
    feats_embedding: LinearParams  # [d, d + K + 1]
    gru: tuple[GRUParams, ...]
    final_layer: LinearParams  # [J·C, d]


class GruActorParams(NamedTuple):
    """``architecture="gru"``."""

    encoder: GruEncoderParams
    decoder: GruDecoderParams


class FcEncoderParams(NamedTuple):
    hidden1: LinearParams  # [2d, J·C·T + K], torch fully_connected.0
    hidden2: LinearParams  # [d, 2d], fully_connected.2
    mu: LinearParams  # [d, d]
    var: LinearParams  # [d, d], gives logvar


class FcDecoderParams(NamedTuple):
    hidden1: LinearParams  # [d, d + K], fully_connected.0
    hidden2: LinearParams  # [2d, d], fully_connected.2
    output: LinearParams  # [J·C·T, 2d], fully_connected.4


class FcActorParams(NamedTuple):
    """``architecture="fc"``."""

    encoder: FcEncoderParams
    decoder: FcDecoderParams


class BiaslessLinearParams(NamedTuple):
    weight: jax.Array  # [out, in]


class AutoregressiveDecoderParams(NamedTuple):
    embedding: LinearParams  # [d, d + K + 1], memory from (z, a, τ)
    embedding_x: LinearParams  # [d, J·C + K + 1], target from (previous frame, a, τ)
    layers: DecoderLayerParams  # joeynmt pre-norm layers, stacked on a leading axis L
    layer_norm: LayerNormParams  # [d], final, eps 1e-6
    output_layer: BiaslessLinearParams  # [J·C, d]


class AutoregressiveActorParams(NamedTuple):
    """``architecture="autoregressive"``: ACTOR's Transformer encoder (distribution tokens) and an
    autoregressive decoder."""

    encoder: ActorEncoderParams
    decoder: AutoregressiveDecoderParams


AnyActorParams = ActorParams | GruActorParams | FcActorParams | AutoregressiveActorParams


# ------------------------------------------------------------------------------------------ initialisation


def _init_transformer_encoder(keys: jax.Array, config: ActorConfig) -> ActorEncoderParams:
    """``keys``: 4 keys."""
    d, k = config.width, config.num_classes
    tokens = config.distribution_tokens
    return ActorEncoderParams(
        skel_embedding=init_linear(keys[0], config.features, d),
        mu_query=jax.random.normal(keys[1], (k, d)) if tokens else None,
        sigma_query=jax.random.normal(keys[2], (k, d)) if tokens else None,
        mu_layer=None if tokens else init_linear(keys[1], d, d),
        sigma_layer=None if tokens else init_linear(keys[2], d, d),
        layers=init_encoder_stack(keys[3], config.layers, d, config.ff),
    )


def _init_transformer(key: jax.Array, config: ActorConfig) -> ActorParams:
    keys = jax.random.split(key, 9)
    d, k = config.width, config.num_classes
    decoder = ActorDecoderParams(
        action_biases=jax.random.normal(keys[4], (k, d)) if config.bias_token else None,
        z_action_linear=None if config.bias_token else init_linear(keys[5], d + k, d),
        layers=init_decoder_stack(keys[6], config.layers, d, config.ff),
        final_layer=init_linear(keys[7], d, config.features),
    )
    return ActorParams(_init_transformer_encoder(keys[:4], config), decoder)


def _init_gru_layers(key: jax.Array, config: ActorConfig) -> tuple[GRUParams, ...]:
    return tuple(init_gru(k, config.width, config.width) for k in jax.random.split(key, config.layers))


def _init_gru(key: jax.Array, config: ActorConfig) -> GruActorParams:
    keys = jax.random.split(key, 7)
    d, k = config.width, config.num_classes
    encoder = GruEncoderParams(
        feats_embedding=init_linear(keys[0], config.features + k + 1, d),
        gru=_init_gru_layers(keys[1], config),
        mu=init_linear(keys[2], d, d),
        var=init_linear(keys[3], d, d),
    )
    decoder = GruDecoderParams(
        feats_embedding=init_linear(keys[4], d + k + 1, d),
        gru=_init_gru_layers(keys[5], config),
        final_layer=init_linear(keys[6], d, config.features),
    )
    return GruActorParams(encoder, decoder)


def _init_fc(key: jax.Array, config: ActorConfig) -> FcActorParams:
    keys = jax.random.split(key, 7)
    d, k = config.width, config.num_classes
    flat = config.features * config.frames
    encoder = FcEncoderParams(
        hidden1=init_linear(keys[0], flat + k, 2 * d),
        hidden2=init_linear(keys[1], 2 * d, d),
        mu=init_linear(keys[2], d, d),
        var=init_linear(keys[3], d, d),
    )
    decoder = FcDecoderParams(
        hidden1=init_linear(keys[4], d + k, d),
        hidden2=init_linear(keys[5], d, 2 * d),
        output=init_linear(keys[6], 2 * d, flat),
    )
    return FcActorParams(encoder, decoder)


def _init_autoregressive(key: jax.Array, config: ActorConfig) -> AutoregressiveActorParams:
    keys = jax.random.split(key, 8)
    d, k = config.width, config.num_classes
    # torch's default Linear init for the bias-free output layer: U(±1/√d)
    output_weight = torch_uniform(keys[7], (config.features, d), d)
    decoder = AutoregressiveDecoderParams(
        embedding=init_linear(keys[4], d + k + 1, d),
        embedding_x=init_linear(keys[5], config.features + k + 1, d),
        # joeynmt builds every layer separately, with four biased nn.Linear attention projections
        layers=init_decoder_stack(keys[6], config.layers, d, config.ff, clone=False, separate_projections=True),
        layer_norm=init_layer_norm(d),
        output_layer=BiaslessLinearParams(output_weight),
    )
    return AutoregressiveActorParams(_init_transformer_encoder(keys[:4], config), decoder)


# ------------------------------------------------------------------------------------------------ helpers


def _check_motion(config: ActorConfig, x: jax.Array, actions: jax.Array, mask: jax.Array) -> None:
    expected = f"[B, T, {config.num_joints}, {config.channels}]"
    if x.ndim != 4 or x.shape[2:] != (config.num_joints, config.channels):
        raise ValueError(f"x: expected {expected}, got {tuple(x.shape)}")
    if actions.shape != x.shape[:1]:
        raise ValueError(f"actions: expected [B] = ({x.shape[0]},), got {tuple(actions.shape)}")
    if mask.shape != x.shape[:2]:
        raise ValueError(f"mask: expected [B, T] = {tuple(x.shape[:2])}, got {tuple(mask.shape)}")
    check_actions(actions, config.num_classes)


def _check_fc_frames(config: ActorConfig, frames: int) -> None:
    if config.architecture == "fc" and frames != config.frames:
        raise ValueError(f"T: architecture 'fc' takes exactly ActorConfig.frames = {config.frames} frames "
                         f"([B, {config.frames}, J, C] and mask [B, {config.frames}]), got T = {frames}")


def _transformer_options(config: ActorConfig, key: jax.Array | None) -> TransformerOptions:
    """The VAE's torch 1.7 stacks (post-norm, eps 1e-5)."""
    # A key means training: unrolled layer loops make a CPU training step ~20% faster (XLA schedules the
    # backward pass of a scan poorly there); inference keeps the scan, which runs as fast and compiles faster.
    return TransformerOptions(num_heads=config.heads, activation=config.activation, dropout_rate=config.dropout,
                              unroll=key is not None)


def _autoregressive_options(config: ActorConfig) -> TransformerOptions:
    """The autoregressive decoder's joeynmt layers: pre-norm, LayerNorm eps 1e-6, ReLU FF, causal."""
    return TransformerOptions(num_heads=config.heads, activation="relu", norm_first=True, layer_norm_eps=1e-6,
                              dropout_rate=config.dropout, causal=True)


def _split(key: jax.Array | None) -> tuple[jax.Array | None, jax.Array | None]:
    return tuple(jax.random.split(key)) if key is not None else (None, None)


def _action_and_time(actions: jax.Array, mask: jax.Array, num_classes: int) -> jax.Array:
    """``actions [B]``, ``mask [B, T]`` -> ``[B, T, K + 1]``: the one-hot action, then ACTOR's time channel
    ``t / (len − 1)`` on real frames and 0 on padded ones."""
    batch, frames = mask.shape
    onehot = jax.nn.one_hot(actions, num_classes, dtype=jnp.float32)
    # ACTOR divides by len − 1 unguarded (inf / NaN for one-frame clips); max(·, 1) gives τ = 0 there
    span = jnp.maximum(mask.sum(axis=1) - 1, 1).astype(jnp.float32)
    time = jnp.where(mask, jnp.arange(frames, dtype=jnp.float32)[None, :] / span[:, None], 0.0)
    return jnp.concatenate([jnp.broadcast_to(onehot[:, None], (batch, frames, num_classes)), time[..., None]], -1)


def _with_latent(z: jax.Array, actions: jax.Array, mask: jax.Array, num_classes: int) -> jax.Array:
    """ACTOR's ``augment_z``: ``concat(z, a, τ_t)`` for every frame, ``[B, T, d + K + 1]``."""
    batch, frames = mask.shape
    tiled = jnp.broadcast_to(z[:, None], (batch, frames, z.shape[-1]))
    return jnp.concatenate([tiled, _action_and_time(actions, mask, num_classes)], axis=-1)


def _gru(layers: tuple[GRUParams, ...], h: jax.Array) -> jax.Array:
    """A GRU stack from zero states over ``h [B, T, d]`` -> top outputs ``[B, T, d]``."""
    h0 = tuple(jnp.zeros((h.shape[0], p.w_hh.shape[1]), h.dtype) for p in layers)
    return gru_stack(layers, h.swapaxes(0, 1), h0).swapaxes(0, 1)


def _gelu(x: jax.Array) -> jax.Array:
    return jax.nn.gelu(x, approximate=False)  # torch nn.GELU(): exact, erf-based


def _frames_out(flat: jax.Array, config: ActorConfig, mask: jax.Array) -> jax.Array:
    """``[B, T, J·C]`` -> ``[B, T, J, C]`` with padded frames zeroed."""
    x = flat.reshape(*mask.shape, config.num_joints, config.channels)
    return jnp.where(mask[:, :, None, None], x, 0.0)


# ------------------------------------------------------------------------------------------------ encoders


def _encode_transformer(p: ActorEncoderParams, config: ActorConfig, x: jax.Array, actions: jax.Array,
                        mask: jax.Array, key: jax.Array | None) -> tuple[jax.Array, jax.Array]:
    batch, frames = x.shape[:2]
    k_pe, k_layers = _split(key)
    h = linear(p.skel_embedding, x.reshape(batch, frames, -1))  # [B, T, d]
    if config.distribution_tokens:
        h = jnp.concatenate([p.mu_query[actions][:, None], p.sigma_query[actions][:, None], h], axis=1)
        mask = jnp.concatenate([jnp.ones((batch, 2), bool), mask], axis=1)
    h = dropout(h + sinusoidal_encoding(jnp.arange(h.shape[1]), config.width), config.dropout, k_pe)
    if config.distribution_tokens:  # only the µ and Σ tokens' outputs are read: the last layer computes those
        out = encoder_stack(p.layers, h, _transformer_options(config, k_layers), key_padding_mask=mask,
                            dropout_key=k_layers, num_queries=2)
        return out[:, 0], out[:, 1]
    out = encoder_stack(p.layers, h, _transformer_options(config, k_layers), key_padding_mask=mask,
                        dropout_key=k_layers)
    # ACTOR's "average_encoder" ablation averages every output, padded frames included.
    pooled = out.mean(axis=1)
    return linear(p.mu_layer, pooled), linear(p.sigma_layer, pooled)


def _encode_gru(p: GruEncoderParams, config: ActorConfig, x: jax.Array, actions: jax.Array, mask: jax.Array,
                key: jax.Array | None) -> tuple[jax.Array, jax.Array]:
    del key  # no dropout in ACTOR's GRU
    batch, frames = mask.shape
    inputs = jnp.concatenate([x.reshape(batch, frames, -1), _action_and_time(actions, mask, config.num_classes)], -1)
    h = _gru(p.gru, linear(p.feats_embedding, inputs))  # [B, T, d]
    # the state after the last real frame: later (padded) frames cannot reach it, the GRU being causal
    last = h[jnp.arange(batch), jnp.maximum(mask.sum(axis=1) - 1, 0)]  # [B, d]
    return linear(p.mu, last), linear(p.var, last)


def _encode_fc(p: FcEncoderParams, config: ActorConfig, x: jax.Array, actions: jax.Array, mask: jax.Array,
               key: jax.Array | None) -> tuple[jax.Array, jax.Array]:
    del key  # no dropout in ACTOR's FC
    _check_fc_frames(config, x.shape[1])
    # Padded frames are zeroed so that only real ones reach the latent (ACTOR's FC sees only full clips);
    # flattened in ACTOR's (J, C, T) order so its weights load unchanged.
    flat = jnp.where(mask[:, :, None, None], x, 0.0).transpose(0, 2, 3, 1).reshape(x.shape[0], -1)
    onehot = jax.nn.one_hot(actions, config.num_classes, dtype=flat.dtype)
    h = _gelu(linear(p.hidden2, _gelu(linear(p.hidden1, jnp.concatenate([flat, onehot], axis=-1)))))
    return linear(p.mu, h), linear(p.var, h)


# ------------------------------------------------------------------------------------------------ decoders


def _decode_transformer(p: ActorDecoderParams, config: ActorConfig, z: jax.Array, actions: jax.Array,
                        mask: jax.Array, key: jax.Array | None) -> jax.Array:
    batch, frames = mask.shape
    k_pe, k_layers = _split(key)
    if config.bias_token:
        memory = z + p.action_biases[actions]
    else:
        onehot = jax.nn.one_hot(actions, config.num_classes, dtype=z.dtype)
        memory = linear(p.z_action_linear, jnp.concatenate([z, onehot], axis=-1))
    queries = jnp.broadcast_to(sinusoidal_encoding(jnp.arange(frames), config.width), (batch, frames, config.width))
    queries = dropout(queries, config.dropout, k_pe)
    out = decoder_stack(p.layers, queries, memory[:, None], _transformer_options(config, k_layers),
                        tgt_key_padding_mask=mask, dropout_key=k_layers)
    return _frames_out(linear(p.final_layer, out), config, mask)


def _decode_gru(p: GruDecoderParams, config: ActorConfig, z: jax.Array, actions: jax.Array, mask: jax.Array,
                key: jax.Array | None) -> jax.Array:
    del key  # no dropout in ACTOR's GRU
    h = _gru(p.gru, linear(p.feats_embedding, _with_latent(z, actions, mask, config.num_classes)))
    return _frames_out(linear(p.final_layer, h), config, mask)


def _decode_fc(p: FcDecoderParams, config: ActorConfig, z: jax.Array, actions: jax.Array, mask: jax.Array,
               key: jax.Array | None) -> jax.Array:
    del key  # no dropout in ACTOR's FC
    _check_fc_frames(config, mask.shape[1])
    onehot = jax.nn.one_hot(actions, config.num_classes, dtype=z.dtype)
    h = _gelu(linear(p.hidden2, _gelu(linear(p.hidden1, jnp.concatenate([z, onehot], axis=-1)))))
    # ACTOR's fc.py ends its decoder with a GELU too, so no output can fall below GELU's minimum ≈ −0.17
    # (rot6d and translation values often do): a quirk of the baseline, kept so Table 2's row is reproduced.
    flat = _gelu(linear(p.output, h))
    x = flat.reshape(z.shape[0], config.num_joints, config.channels, config.frames).transpose(0, 3, 1, 2)
    return jnp.where(mask[:, :, None, None], x, 0.0)


def _autoregressive_target(p: AutoregressiveDecoderParams, config: ActorConfig, previous: jax.Array,
                           conditioning: jax.Array, positions: jax.Array) -> jax.Array:
    """The decoder's input: ``Linear(concat(x_{t−1}, a, τ_t)) + PE(t)``. ``previous [..., J·C]`` and
    ``conditioning [..., K + 1]`` for all frames (``[B, T, ·]``, ``positions [T]``) or one (``[B, ·]``,
    ``positions [1]``) -> ``[..., d]``."""
    target = linear(p.embedding_x, jnp.concatenate([previous, conditioning], axis=-1))
    return target + sinusoidal_encoding(positions, config.width)


def _autoregressive_frames(p: AutoregressiveDecoderParams, out: jax.Array, mask: jax.Array) -> jax.Array:
    """Decoder outputs ``[..., d]`` -> frames ``[..., J·C]`` (final LayerNorm, bias-free output layer), zero
    where ``mask [...]`` is False."""
    frames = layer_norm(p.layer_norm, out, 1e-6) @ p.output_layer.weight.T
    return jnp.where(mask[..., None], frames, 0.0)


def _decode_autoregressive(p: AutoregressiveDecoderParams, config: ActorConfig, z: jax.Array, actions: jax.Array,
                           mask: jax.Array, key: jax.Array | None, target: jax.Array | None) -> jax.Array:
    """``z [B, d]`` -> ``[B, T, J, C]``, teacher-forced by ``target [B, T, J, C]`` (one causal pass, dropout
    with a key) or, without it, frame by frame on its own outputs (eval mode, through the key/value cache)."""
    batch, frames = mask.shape
    conditioning = _action_and_time(actions, mask, config.num_classes)  # [B, T, K + 1]
    memory = linear(p.embedding, _with_latent(z, actions, mask, config.num_classes))  # [B, T, d]
    options = _autoregressive_options(config)

    if target is not None:  # teacher forcing: frame t reads target frame t − 1 (zeros before frame 0)
        k_emb, k_layers = _split(key)
        previous = jnp.pad(target.reshape(batch, frames, -1)[:, :-1], ((0, 0), (1, 0), (0, 0)))
        h = _autoregressive_target(p, config, previous, conditioning, jnp.arange(frames))
        out = decoder_stack(p.layers, dropout(h, config.dropout, k_emb), memory, options,
                            tgt_key_padding_mask=mask, memory_key_padding_mask=mask, dropout_key=k_layers)
        return _frames_out(_autoregressive_frames(p, out, mask), config, mask)

    # Frame by frame: step t embeds frame t − 1 (already zero when padded, as the causal pass reads it),
    # decodes position t from the cached keys and values of positions < t and the memory's, computed once.
    cache = init_decoder_cache(p.layers, memory, frames, options, tgt_key_padding_mask=mask,
                               memory_key_padding_mask=mask)

    def step(carry, t):
        cache, previous = carry  # previous [B, J·C]
        h = _autoregressive_target(p, config, previous, conditioning[:, t], t[None])
        out, cache = decoder_stack_step(p.layers, cache, h, t, options)
        frame = _autoregressive_frames(p, out, mask[:, t])
        return (cache, frame), frame

    first = jnp.zeros((batch, config.features), z.dtype)
    _, out = jax.lax.scan(step, (cache, first), jnp.arange(frames))  # [T, B, J·C]
    return _frames_out(out.swapaxes(0, 1), config, mask)


# ------------------------------------------------------------------------------------------------ dispatch


class _Variant(NamedTuple):
    params: type
    init: Callable
    encode: Callable
    decode: Callable


_VARIANTS = {
    "transformer": _Variant(ActorParams, _init_transformer, _encode_transformer, _decode_transformer),
    "gru": _Variant(GruActorParams, _init_gru, _encode_gru, _decode_gru),
    "fc": _Variant(FcActorParams, _init_fc, _encode_fc, _decode_fc),
    "autoregressive": _Variant(AutoregressiveActorParams, _init_autoregressive, _encode_transformer,
                               _decode_autoregressive),
}


def _variant(params: AnyActorParams, config: ActorConfig) -> _Variant:
    variant = _VARIANTS[config.architecture]
    if not isinstance(params, variant.params):
        raise TypeError(f"params: architecture {config.architecture!r} expects {variant.params.__name__}, "
                        f"got {type(params).__name__}")
    return variant


# -------------------------------------------------------------------------------------------------- public


def init_actor(key: jax.Array, config: ActorConfig) -> AnyActorParams:
    """Fresh parameters for ``config.architecture``: PyTorch's initialisation (tokens and biases N(0, 1), as
    ``torch.randn``; ``Linear`` / ``GRU`` uniform)."""
    return _VARIANTS[config.architecture].init(key, config)


def encode(config: ActorConfig, params: AnyActorParams, x: jax.Array, actions: jax.Array, mask: jax.Array, *,
           key: jax.Array | None = None) -> tuple[jax.Array, jax.Array]:
    """``x [B, T, J, C]``, ``actions [B]``, ``mask [B, T]`` -> ``(mu [B, d], logvar [B, d])``. ``"fc"`` needs
    ``T == config.frames``."""
    _check_motion(config, x, actions, mask)
    variant = _variant(params, config)
    return variant.encode(params.encoder, config, x, actions, mask, key)


def decode(config: ActorConfig, params: AnyActorParams, z: jax.Array, actions: jax.Array, mask: jax.Array, *,
           key: jax.Array | None = None, target: jax.Array | None = None) -> jax.Array:
    """``z [B, d]``, ``actions [B]``, ``mask [B, T]`` -> ``x [B, T, J, C]`` (zero on padded frames).

    ``target [B, T, J, C]`` (``"autoregressive"`` only): teacher forcing, frame t is decoded from
    ``target[:, :t]``; without it the autoregressive decoder runs frame by frame on its own outputs, in eval
    mode (no ``key``), through a key/value cache: the same frames as re-running the causal pass for every
    frame, in one pass's work. ``"fc"`` needs ``T == config.frames``.
    """
    if z.ndim != 2 or z.shape[1] != config.width:
        raise ValueError(f"z: expected [B, {config.width}], got {tuple(z.shape)}")
    if actions.shape != z.shape[:1] or mask.ndim != 2 or mask.shape[0] != z.shape[0]:
        raise ValueError(f"actions, mask: expected [B] and [B, T] with B = {z.shape[0]}, got "
                         f"{tuple(actions.shape)} and {tuple(mask.shape)}")
    check_actions(actions, config.num_classes)
    variant = _variant(params, config)
    if config.architecture != "autoregressive":
        if target is not None:
            raise ValueError(f"target: teacher forcing exists for architecture 'autoregressive' only, not "
                             f"{config.architecture!r}; pass target=None")
        return variant.decode(params.decoder, config, z, actions, mask, key)
    expected = (*mask.shape, config.num_joints, config.channels)
    if target is None and key is not None:
        raise ValueError("key: frame-by-frame autoregressive decoding (no target) runs in eval mode, without "
                         "dropout; pass key=None, or a target for teacher-forced decoding with dropout")
    if target is not None and target.shape != expected:
        raise ValueError(f"target: expected [B, T, J, C] = {expected}, got {tuple(target.shape)}")
    return variant.decode(params.decoder, config, z, actions, mask, key, target)


def sample_posterior(key: jax.Array, mu: jax.Array, logvar: jax.Array) -> jax.Array:
    """Reparameterised ``z = mu + exp(logvar / 2) · ε``: ``[B, d] -> [B, d]``."""
    return mu + jnp.exp(0.5 * logvar) * jax.random.normal(key, mu.shape, mu.dtype)


def length_mask(durations: jax.Array, frames: int) -> jax.Array:
    """``durations [B]`` -> ``mask [B, frames]``, True on the first ``durations[b]`` frames."""
    return jnp.arange(frames)[None, :] < jnp.asarray(durations)[:, None]


def autoencode(config: ActorConfig, params: AnyActorParams, x: jax.Array, actions: jax.Array, mask: jax.Array, *,
               key: jax.Array, train: bool) -> dict[str, jax.Array]:
    """Encode, sample z from the posterior, decode: ``{"output", "mu", "logvar", "z"}``.

    ``train``: dropout on (keys split from ``key``); the autoregressive decoder is teacher-forced with ``x``.
    Outside training ``z`` is still drawn from the posterior, as ACTOR's denoising does (use ``mu`` for a
    deterministic reconstruction), and the autoregressive decoder runs frame by frame, as ACTOR evaluates it.
    """
    k_enc, k_z, k_dec = jax.random.split(key, 3)
    mu, logvar = encode(config, params, x, actions, mask, key=k_enc if train else None)
    z = sample_posterior(k_z, mu, logvar)
    target = x if train and config.architecture == "autoregressive" else None
    output = decode(config, params, z, actions, mask, key=k_dec if train else None, target=target)
    return {"output": output, "mu": mu, "logvar": logvar, "z": z}


def generate(config: ActorConfig, params: AnyActorParams, actions: jax.Array, durations: jax.Array, frames: int, *,
             key: jax.Array) -> tuple[jax.Array, jax.Array]:
    """Sample ``z ~ N(0, I)`` and decode: ``actions [B]``, ``durations [B]`` (each <= ``frames``) ->
    ``(x [B, frames, J, C], mask [B, frames])``; frames past a duration are zero and unmasked. The
    autoregressive decoder runs frame by frame; ``"fc"`` needs ``frames == config.frames``."""
    check_actions(actions, config.num_classes)
    check_durations(durations, jnp.shape(actions)[0], frames)
    actions = jnp.asarray(actions)
    z = jax.random.normal(key, (actions.shape[0], config.width))
    mask = length_mask(durations, frames)
    return decode(config, params, z, actions, mask), mask


# ------------------------------------------------------------------------------------------- feature layout


def to_features(rotations: jax.Array, translation: jax.Array, rep: str = "rot6d") -> jax.Array:
    """ACTOR's input tensor ``[B, T, J + 1, C]``: each joint's rotation in ``rep``, then one extra "joint"
    holding the translation relative to frame 0, zero-padded to C channels (ACTOR's ``rot6d`` layout;
    :func:`jaxmotion.geometry.representations.rotation_features`).

    ``rotations [B, T, J, 3]`` axis-angle, ``translation [B, T, 3]``; C = 6 (rot6d), 4, 3 or 9 (matrix).
    """
    return rotation_features(rotations, translation, rep, origin="first")


def from_features(features: jax.Array, rep: str = "rot6d") -> tuple[jax.Array, jax.Array]:
    """Inverse of :func:`to_features`: ``[B, T, J + 1, C] -> (rotations [B, T, J, 3], translation [B, T, 3])``,
    the translation relative to frame 0."""
    return split_rotation_features(features, rep)


def motions_from_features(x: jax.Array, mask: jax.Array, rep: str, skeleton: Skeleton) -> dict[str, jax.Array]:
    """ACTOR's tensor ``x [B, T, J + 1, C]`` -> the library's batch form: ``rotations [B, T, J, 3]``,
    ``translation [B, T, 3]`` (relative to frame 0), ``joints [B, T, J, 3]`` (forward kinematics on
    ``skeleton``'s rest offsets), ``mask [B, T]`` and ``lengths [B]``."""
    rotations, translation = from_features(x, rep)
    joints = forward_kinematics(axis_angle_to_matrix(rotations), translation, skeleton.offsets, skeleton.parents)
    return {"joints": joints, "rotations": rotations, "translation": translation, "mask": mask,
            "lengths": mask.sum(axis=1)}
