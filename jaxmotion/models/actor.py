"""ACTOR: the action-conditioned Transformer VAE (Petrovich et al. 2021), as pure functions.

The whole model on one screen (FACTS.md §3; paper §3.1):

* **Input** ``x [B, T, J, C]``: per frame the 24 joint rotations in ``rep`` (C = 6 for rot6d) and one extra
  "joint" holding the root translation relative to frame 0 (``jaxmotion.data.pipeline.to_actor_features``),
  with ``mask [B, T]`` marking real frames.
* **Encoder**: each frame is embedded by one linear layer (J·C -> d); the per-action distribution tokens
  ``mu_query[a]`` and ``sigma_query[a]`` are prepended; sinusoidal positional encodings (positions 0..T+1)
  are added; a post-norm Transformer encoder runs over the T + 2 tokens with padded frames masked; its
  outputs at the two tokens are μ and log σ².
* **Latent**: ``z = μ + exp(logvar / 2) · ε`` (training, denoising) or ``z ~ N(0, I)`` (generation).
* **Decoder**: the memory is one token, ``z + action_bias[a]``; the queries are the T positional encodings
  (zeros + PE(0..T-1)), padded queries masked; a post-norm Transformer decoder, then one linear layer
  (d -> J·C); padded frames are zeroed.

Table 2 ablations are switches of :class:`ActorConfig`: ``distribution_tokens=False`` (μ, logvar from two
linear layers on the mean encoder output, ACTOR's ``average_encoder``), ``bias_token=False`` (the one-hot
action concatenated to z, then a linear layer: ``zandtime``). Layers, heads, widths and dropout are
fields; the rotation representation is the input's C.

Parameters are a pytree of NamedTuples in PyTorch's layout (``jaxmotion.nn.transformer``); every function
is pure and jittable; dropout runs only when a key is given.

Axes: B batch, T frames, J joints (+1 translation row), C channels per joint, d model width, K classes.
"""

from __future__ import annotations

import dataclasses
from typing import Literal, NamedTuple

import jax
import jax.numpy as jnp

from jaxmotion.nn.transformer import (
    DecoderLayerParams,
    EncoderLayerParams,
    LinearParams,
    decoder_stack,
    dropout,
    encoder_stack,
    init_decoder_stack,
    init_encoder_stack,
    init_linear,
    linear,
    sinusoidal_encoding,
)


@dataclasses.dataclass(frozen=True)
class ActorConfig:
    """ACTOR's architecture. Defaults are the paper's (d 256, 8 layers, 4 heads, FF 1024, dropout 0.1, GELU)."""

    num_classes: int
    num_joints: int = 25
    channels: int = 6
    latent: int = 256
    ff: int = 1024
    layers: int = 8
    heads: int = 4
    dropout: float = 0.1
    activation: Literal["gelu", "relu"] = "gelu"
    distribution_tokens: bool = True
    bias_token: bool = True

    def __post_init__(self):
        if self.latent % self.heads:
            raise ValueError(f"ActorConfig: latent ({self.latent}) must be a multiple of heads ({self.heads})")
        for name in ("num_classes", "num_joints", "channels", "latent", "ff", "layers", "heads"):
            if getattr(self, name) < 1:
                raise ValueError(f"ActorConfig.{name} must be >= 1, got {getattr(self, name)}")
        if not 0.0 <= self.dropout < 1.0:
            raise ValueError(f"ActorConfig.dropout must be in [0, 1), got {self.dropout}")

    @property
    def features(self) -> int:
        return self.num_joints * self.channels


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
    encoder: ActorEncoderParams
    decoder: ActorDecoderParams


def init_actor(key: jax.Array, config: ActorConfig) -> ActorParams:
    """Fresh parameters: PyTorch's initialisation (tokens and biases N(0, 1), as ``torch.randn``)."""
    keys = jax.random.split(key, 9)
    d, k = config.latent, config.num_classes
    tokens = config.distribution_tokens
    encoder = ActorEncoderParams(
        skel_embedding=init_linear(keys[0], config.features, d),
        mu_query=jax.random.normal(keys[1], (k, d)) if tokens else None,
        sigma_query=jax.random.normal(keys[2], (k, d)) if tokens else None,
        mu_layer=None if tokens else init_linear(keys[1], d, d),
        sigma_layer=None if tokens else init_linear(keys[2], d, d),
        layers=init_encoder_stack(keys[3], config.layers, d, config.ff),
    )
    decoder = ActorDecoderParams(
        action_biases=jax.random.normal(keys[4], (k, d)) if config.bias_token else None,
        z_action_linear=None if config.bias_token else init_linear(keys[5], d + k, d),
        layers=init_decoder_stack(keys[6], config.layers, d, config.ff),
        final_layer=init_linear(keys[7], d, config.features),
    )
    return ActorParams(encoder, decoder)


def _check_motion(config: ActorConfig, x: jax.Array, actions: jax.Array, mask: jax.Array) -> None:
    expected = f"[B, T, {config.num_joints}, {config.channels}]"
    if x.ndim != 4 or x.shape[2:] != (config.num_joints, config.channels):
        raise ValueError(f"x: expected {expected}, got {tuple(x.shape)}")
    if actions.shape != x.shape[:1]:
        raise ValueError(f"actions: expected [B] = ({x.shape[0]},), got {tuple(actions.shape)}")
    if mask.shape != x.shape[:2]:
        raise ValueError(f"mask: expected [B, T] = {tuple(x.shape[:2])}, got {tuple(mask.shape)}")


def _stack_kwargs(config: ActorConfig, key: jax.Array | None) -> dict:
    return {"num_heads": config.heads, "activation": config.activation, "dropout_rate": config.dropout,
            "dropout_key": key}


def encode(params: ActorParams, config: ActorConfig, x: jax.Array, actions: jax.Array, mask: jax.Array,
           key: jax.Array | None = None) -> tuple[jax.Array, jax.Array]:
    """``x [B, T, J, C]``, ``actions [B]``, ``mask [B, T]`` -> ``(mu [B, d], logvar [B, d])``."""
    _check_motion(config, x, actions, mask)
    p = params.encoder
    batch, frames = x.shape[:2]
    k_pe, k_layers = jax.random.split(key) if key is not None else (None, None)
    h = linear(p.skel_embedding, x.reshape(batch, frames, -1))  # [B, T, d]
    if config.distribution_tokens:
        h = jnp.concatenate([p.mu_query[actions][:, None], p.sigma_query[actions][:, None], h], axis=1)
        mask = jnp.concatenate([jnp.ones((batch, 2), bool), mask], axis=1)
    h = dropout(h + sinusoidal_encoding(jnp.arange(h.shape[1]), config.latent), config.dropout, k_pe)
    out = encoder_stack(p.layers, h, key_padding_mask=mask, **_stack_kwargs(config, k_layers))
    if config.distribution_tokens:
        return out[:, 0], out[:, 1]
    # ACTOR's "average_encoder" ablation averages every output, padded frames included.
    pooled = out.mean(axis=1)
    return linear(p.mu_layer, pooled), linear(p.sigma_layer, pooled)


def decode(params: ActorParams, config: ActorConfig, z: jax.Array, actions: jax.Array, mask: jax.Array,
           key: jax.Array | None = None) -> jax.Array:
    """``z [B, d]``, ``actions [B]``, ``mask [B, T]`` -> ``x [B, T, J, C]`` (zero on padded frames)."""
    if z.ndim != 2 or z.shape[1] != config.latent:
        raise ValueError(f"z: expected [B, {config.latent}], got {tuple(z.shape)}")
    if actions.shape != z.shape[:1] or mask.ndim != 2 or mask.shape[0] != z.shape[0]:
        raise ValueError(f"actions, mask: expected [B] and [B, T] with B = {z.shape[0]}, got "
                         f"{tuple(actions.shape)} and {tuple(mask.shape)}")
    p = params.decoder
    batch, frames = mask.shape
    k_pe, k_layers = jax.random.split(key) if key is not None else (None, None)
    if config.bias_token:
        memory = z + p.action_biases[actions]
    else:
        onehot = jax.nn.one_hot(actions, config.num_classes, dtype=z.dtype)
        memory = linear(p.z_action_linear, jnp.concatenate([z, onehot], axis=-1))
    queries = jnp.broadcast_to(sinusoidal_encoding(jnp.arange(frames), config.latent), (batch, frames, config.latent))
    queries = dropout(queries, config.dropout, k_pe)
    out = decoder_stack(p.layers, queries, memory[:, None], tgt_key_padding_mask=mask,
                        **_stack_kwargs(config, k_layers))
    x = linear(p.final_layer, out).reshape(batch, frames, config.num_joints, config.channels)
    return jnp.where(mask[:, :, None, None], x, 0.0)


def sample_posterior(key: jax.Array, mu: jax.Array, logvar: jax.Array) -> jax.Array:
    """Reparameterised ``z = mu + exp(logvar / 2) · ε``: ``[B, d] -> [B, d]``."""
    return mu + jnp.exp(0.5 * logvar) * jax.random.normal(key, mu.shape, mu.dtype)


def length_mask(durations: jax.Array, frames: int) -> jax.Array:
    """``durations [B]`` -> ``mask [B, frames]``, True on the first ``durations[b]`` frames."""
    return jnp.arange(frames)[None, :] < jnp.asarray(durations)[:, None]


def autoencode(params: ActorParams, config: ActorConfig, key: jax.Array, x: jax.Array, actions: jax.Array,
               mask: jax.Array, *, train: bool) -> dict[str, jax.Array]:
    """Encode, sample z from the posterior, decode: ``{"output", "mu", "logvar", "z"}``.

    ``train``: dropout on (keys split from ``key``). Outside training ``z`` is still drawn from the
    posterior, as ACTOR's denoising does; use ``mu`` for a deterministic reconstruction.
    """
    k_enc, k_z, k_dec = jax.random.split(key, 3)
    mu, logvar = encode(params, config, x, actions, mask, k_enc if train else None)
    z = sample_posterior(k_z, mu, logvar)
    output = decode(params, config, z, actions, mask, k_dec if train else None)
    return {"output": output, "mu": mu, "logvar": logvar, "z": z}


def generate(params: ActorParams, config: ActorConfig, key: jax.Array, actions: jax.Array, durations: jax.Array,
             frames: int) -> tuple[jax.Array, jax.Array]:
    """Sample ``z ~ N(0, I)`` and decode: ``actions [B]``, ``durations [B]`` (each <= ``frames``) ->
    ``(x [B, frames, J, C], mask [B, frames])``; frames past a duration are zero and unmasked."""
    actions = jnp.asarray(actions)
    z = jax.random.normal(key, (actions.shape[0], config.latent))
    mask = length_mask(durations, frames)
    return decode(params, config, z, actions, mask), mask
