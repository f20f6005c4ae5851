"""MARIONET (Neural Marionette's single-action generator, Wang et al. 2022, §4.2 and supplement Table 2).

One action from its tags, the 6 poses before it, the next action's tags, a duration T and an optional ground path,
in the normalised frame of its context (the last context pose faces +Z over the origin:
:func:`~jaxmotion.geometry.kinematics.heading_transform`). Poses are the paper's 135 numbers
(:func:`~jaxmotion.geometry.representations.pose135`).

* **Condition encoder.** Tokens: the 6 context poses (the shared pose embedding, 135 -> d), the action's tags and
  the next action's tags (the shared tag embedding, C -> d, multi-hot in); a sinusoidal position code 0..7; a
  2-layer Transformer encoder. The tag token's output regresses mu and log sigma^2 (two FCs); Z = mu + sigma eps.
* **Time unrolling.** A 2-layer Transformer decoder whose queries are a reverse position code (T .. 1: the frames
  left until the action ends) plus the tag embedding (tag injection), and whose memory is Z alone; its outputs are
  projected to d - 32 numbers and joined with the 32-number embedding of the ground path (an FC 2 -> 32, then a
  1-layer, 1-head, 32-wide Transformer over the frames; zeros in for in-place actions) into frame controls c_t.
* **Motion decoder.** A 6-layer causal Transformer decoder over the embedded previous poses (the last context
  pose first) plus a forward position code, cross-attending to the controls; a linear head back to 135 numbers.
  Generation runs it one frame at a time through the key/value cache (:func:`generate`).

Where the paper is silent ([U] in MARIONETTE.md) the choice is a config field, documented on
:class:`MarionetConfig`. Ablations (Table 2): ``time_unrolling=False`` gives every frame the same control
``FC(Z)`` (no unrolling decoder; the motion decoder's own position code still tells the frames apart),
``tag_injection=False`` drops the tag from the unrolling queries, ``next_tag=False`` feeds zeros as the next tag
(as the paper's ablation does). Scheduled sampling is the trainer's.

Axes: B actions, K context frames, T frames (padded to the batch's longest), C tags, D = 135 pose numbers, d width.
"""

from __future__ import annotations

import dataclasses
from typing import Literal, NamedTuple

import jax
import jax.numpy as jnp

from jaxmotion.config import check_at_least
from jaxmotion.data.segments import CONTEXT_FRAMES
from jaxmotion.geometry.kinematics import heading_transform, transform_motion
from jaxmotion.geometry.representations import POSE135_SIZE, pose135
from jaxmotion.geometry.rotations import axis_angle_to_matrix
from jaxmotion.nn.core import LinearParams, dropout, init_linear, linear, split_key
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

#: Context poses MARIONET reads (S§3).
CONTEXT = CONTEXT_FRAMES


@dataclasses.dataclass(frozen=True)
class MarionetConfig:
    """MARIONET's architecture; the defaults are the supplement's Table 2 (the ``paper`` size).

    ``width`` d (256), ``heads`` (8), ``ff`` (1024); ``encoder_layers`` (2), ``unroll_layers`` (2),
    ``decoder_layers`` (6); ``path_width`` (32: d - 32 = 224 numbers of each control come from the unrolling);
    ``path_layers`` (1; 0 leaves the path as its FC embedding). Dropout and activation per block as MARIONETTE.md
    reads the table: encoder 0.1 / GELU, unrolling 0.01 / ReLU, decoder 0.1 / GELU, path 0.001 / ReLU.
    ``max_frames``: the longest action it generates (the position codes are sinusoidal, so it bounds only what
    the callers pad to). Post-norm (torch's default; [U]). The embedding FCs (tags, poses, path, unrolled latents)
    are followed by a ReLU, as Table 2 lists; the heads (mu, log sigma^2, poses) are linear ([I]: a ReLU there
    could not output negative numbers). ``latent``: the encoder regresses ``log_variance`` ([U]; ACTOR's choice).
    """

    num_tags: int = 31
    width: int = 256
    heads: int = 8
    ff: int = 1024
    encoder_layers: int = 2
    unroll_layers: int = 2
    decoder_layers: int = 6
    path_width: int = 32
    path_layers: int = 1
    encoder_dropout: float = 0.1
    unroll_dropout: float = 0.01
    decoder_dropout: float = 0.1
    path_dropout: float = 0.001
    max_frames: int = 120
    latent: Literal["log_variance"] = "log_variance"
    time_unrolling: bool = True
    tag_injection: bool = True
    next_tag: bool = True

    def __post_init__(self):
        check_at_least(self, 1, "num_tags", "width", "heads", "ff", "encoder_layers", "unroll_layers",
                       "decoder_layers", "path_width", "max_frames")
        check_at_least(self, 0, "path_layers")
        if self.width % self.heads:
            raise ValueError(f"MarionetConfig.heads: must divide width {self.width}, got {self.heads}")
        if self.path_width >= self.width:
            raise ValueError(f"MarionetConfig.path_width: expected fewer than width ({self.width}) numbers, got "
                             f"{self.path_width}")
        for name in ("encoder_dropout", "unroll_dropout", "decoder_dropout", "path_dropout"):
            if not 0.0 <= getattr(self, name) < 1.0:
                raise ValueError(f"MarionetConfig.{name}: expected in [0, 1), got {getattr(self, name)}")
        if self.latent != "log_variance":
            raise ValueError(f"MarionetConfig.latent: expected 'log_variance', got {self.latent!r}")

    @classmethod
    def tiny(cls, **changes) -> MarionetConfig:
        """A test-sized model (d 32, 2 heads, one layer each)."""
        return cls(**{"width": 32, "heads": 2, "ff": 64, "encoder_layers": 1, "unroll_layers": 1,
                      "decoder_layers": 1, "path_width": 8, **changes})


class MarionetParams(NamedTuple):
    pose_embedding: LinearParams  # 135 -> d, shared by the encoder's context tokens and the decoder's input
    tag_embedding: LinearParams  # C -> d, shared by the tag, the next tag and tag injection
    encoder: EncoderLayerParams
    mu: LinearParams
    log_variance: LinearParams
    unroll: DecoderLayerParams
    unroll_embedding: LinearParams  # d -> d - path_width
    path_embedding: LinearParams  # 2 -> path_width
    path: EncoderLayerParams | None  # path_layers layers, width path_width (None for 0)
    decoder: DecoderLayerParams
    pose_head: LinearParams  # d -> 135


def normalised_poses(rotations: jax.Array, translation: jax.Array, frame: int
                     ) -> tuple[jax.Array, jax.Array, jax.Array]:
    """A motion ``rotations [B, T, 24, 3]`` (axis-angle), ``translation [B, T, 3]`` in the normalised frame of its
    pose at ``frame`` (the last context pose; Eqs. 3-5) -> ``(poses [B, T, 135], turn [B, 3, 3], shift [B, 3])``,
    the rigid map ``x -> turn x + shift`` that took it there (:func:`~jaxmotion.geometry.kinematics.heading_transform`;
    its :func:`~jaxmotion.geometry.kinematics.inverse_transform` takes generated actions back)."""
    turn, shift = heading_transform(axis_angle_to_matrix(rotations[:, frame, 0]), translation[:, frame])
    return pose135(*transform_motion(turn, shift, rotations, translation)), turn, shift


def init_marionet(key: jax.Array, config: MarionetConfig) -> MarionetParams:
    """Fresh parameters (PyTorch's default initialisation, as every model of the library)."""
    keys = jax.random.split(key, 11)
    d, p = config.width, config.path_width
    return MarionetParams(
        pose_embedding=init_linear(keys[0], POSE135_SIZE, d),
        tag_embedding=init_linear(keys[1], config.num_tags, d),
        encoder=init_encoder_stack(keys[2], config.encoder_layers, d, config.ff),
        mu=init_linear(keys[3], d, d),
        log_variance=init_linear(keys[4], d, d),
        unroll=init_decoder_stack(keys[5], config.unroll_layers, d, config.ff),
        unroll_embedding=init_linear(keys[6], d, d - p),
        path_embedding=init_linear(keys[7], 2, p),
        path=init_encoder_stack(keys[8], config.path_layers, p, 2 * p) if config.path_layers else None,
        decoder=init_decoder_stack(keys[9], config.decoder_layers, d, config.ff),
        pose_head=init_linear(keys[10], d, POSE135_SIZE),
    )


def _options(config: MarionetConfig, block: str, *, training: bool, causal: bool = False) -> TransformerOptions:
    heads = 1 if block == "path" else config.heads
    activation = "gelu" if block in ("encoder", "decoder") else "relu"
    # A training pass unrolls the layer loop (the backward pass of a scan schedules poorly on CPU, as for ACTOR).
    return TransformerOptions(num_heads=heads, activation=activation, causal=causal, unroll=training,
                              dropout_rate=getattr(config, f"{block}_dropout"))


def _embed_tags(params: MarionetParams, tags: jax.Array) -> jax.Array:
    """``[..., C]`` multi-hot -> ``[..., d]``."""
    return jax.nn.relu(linear(params.tag_embedding, tags.astype(jnp.float32)))


def embed_poses(params: MarionetParams, poses: jax.Array) -> jax.Array:
    """The pose embedding shared by the encoder and the decoder: ``[..., 135] -> [..., d]`` (non-negative: ReLU)."""
    return jax.nn.relu(linear(params.pose_embedding, poses))


def encode(params: MarionetParams, config: MarionetConfig, context: jax.Array, tags: jax.Array,
           next_tags: jax.Array, key: jax.Array | None = None) -> tuple[jax.Array, jax.Array]:
    """Condition encoder: ``context [B, K, 135]``, ``tags``, ``next_tags [B, C]`` -> ``(mu, log_variance) [B, d]``;
    dropout with a ``key`` (training)."""
    if not config.next_tag:
        next_tags = jnp.zeros_like(next_tags)
    tokens = jnp.concatenate([embed_poses(params, context), _embed_tags(params, tags)[:, None],
                              _embed_tags(params, next_tags)[:, None]], axis=1)  # [B, K + 2, d]
    tokens = tokens + sinusoidal_encoding(jnp.arange(tokens.shape[1]), config.width)
    k_in, k_layers = split_key(key, 2)
    out = encoder_stack(params.encoder, dropout(tokens, config.encoder_dropout, k_in),
                        _options(config, "encoder", training=key is not None), dropout_key=k_layers)
    pooled = out[:, context.shape[1]]  # the tag token
    return linear(params.mu, pooled), linear(params.log_variance, pooled)


def controls(params: MarionetParams, config: MarionetConfig, z: jax.Array, tags: jax.Array, path: jax.Array,
             mask: jax.Array, key: jax.Array | None = None) -> jax.Array:
    """Time unrolling and the path: ``z [B, d]``, ``tags [B, C]``, ``path [B, T, 2]`` (ground x, z per frame; zeros
    for in-place actions), ``mask [B, T]`` -> frame controls ``[B, T, d]``."""
    batch, frames = mask.shape
    k_unroll, k_path, k_in = split_key(key, 3)
    if config.time_unrolling:
        remaining = jnp.sum(mask, axis=1, keepdims=True) - jnp.arange(frames)  # T .. 1, then <= 0 on padding
        queries = sinusoidal_encoding(remaining.reshape(-1), config.width).reshape(batch, frames, config.width)
        if config.tag_injection:
            queries = queries + _embed_tags(params, tags)[:, None]
        latents = decoder_stack(params.unroll, dropout(queries, config.unroll_dropout, k_in), z[:, None],
                                _options(config, "unroll", training=key is not None),
                                tgt_key_padding_mask=mask, dropout_key=k_unroll)
    else:
        latents = jnp.broadcast_to(z[:, None], (batch, frames, config.width))
    unrolled = jax.nn.relu(linear(params.unroll_embedding, latents))
    steps = jax.nn.relu(linear(params.path_embedding, path))
    if params.path is not None:
        steps = encoder_stack(params.path, steps, _options(config, "path", training=key is not None),
                              key_padding_mask=mask, dropout_key=k_path)
    return jnp.concatenate([unrolled, steps], axis=-1)


def _decoder_input(params: MarionetParams, config: MarionetConfig, previous: jax.Array,
                   positions: jax.Array) -> jax.Array:
    """``previous [..., 135]`` poses at ``positions`` -> the decoder's tokens ``[..., d]``."""
    return _decoder_token(config, embed_poses(params, previous), positions)


def _decoder_token(config: MarionetConfig, embedded: jax.Array, positions: jax.Array) -> jax.Array:
    """Embedded previous poses ``[..., d]`` at ``positions`` -> the decoder's tokens ``[..., d]``."""
    return embedded + sinusoidal_encoding(positions, config.width)


def decode(params: MarionetParams, config: MarionetConfig, frame_controls: jax.Array, previous: jax.Array,
           mask: jax.Array, key: jax.Array | None = None) -> jax.Array:
    """Motion decoder, all frames in one causal pass: ``previous [B, T, 135]`` (the pose before each frame: the
    last context pose, then the action's own, true or predicted) -> poses ``[B, T, 135]``, zero on padding."""
    k_in, k_layers = split_key(key, 2)
    tokens = _decoder_input(params, config, previous, jnp.arange(previous.shape[1]))
    out = decoder_stack(params.decoder, dropout(tokens, config.decoder_dropout, k_in), frame_controls,
                        _options(config, "decoder", training=key is not None, causal=True),
                        tgt_key_padding_mask=mask, memory_key_padding_mask=mask, dropout_key=k_layers)
    return jnp.where(mask[..., None], linear(params.pose_head, out), 0.0)


def sample_z(key: jax.Array, mu: jax.Array, log_variance: jax.Array) -> jax.Array:
    """``Z = mu + sigma eps``, ``eps ~ N(0, I)``: ``[B, d]``."""
    return mu + jnp.exp(0.5 * log_variance) * jax.random.normal(key, mu.shape, mu.dtype)


class MarionetOutput(NamedTuple):
    poses: jax.Array  # [B, T, 135]
    mu: jax.Array  # [B, d]
    log_variance: jax.Array  # [B, d]
    controls: jax.Array  # [B, T, d] (a second decoder pass, scheduled sampling's, reuses them)


def forward(params: MarionetParams, config: MarionetConfig, context: jax.Array, tags: jax.Array,
            next_tags: jax.Array, path: jax.Array, target: jax.Array, mask: jax.Array,
            key: jax.Array | None = None) -> MarionetOutput:
    """Teacher-forced pass: ``target [B, T, 135]`` the true poses (frame t reads frame t - 1, the first the last
    context pose) -> :class:`MarionetOutput`. With a ``key``: Z sampled and dropout on (training); without, Z = mu
    and no dropout."""
    k_z, k_enc, k_ctl, k_dec = split_key(key, 4)
    mu, log_variance = encode(params, config, context, tags, next_tags, k_enc)
    z = mu if key is None else sample_z(k_z, mu, log_variance)
    frame_controls = controls(params, config, z, tags, path, mask, k_ctl)
    previous = jnp.concatenate([context[:, -1:], target[:, :-1]], axis=1)
    return MarionetOutput(decode(params, config, frame_controls, previous, mask, k_dec), mu, log_variance,
                          frame_controls)


def generate(params: MarionetParams, config: MarionetConfig, context: jax.Array, tags: jax.Array,
             next_tags: jax.Array, path: jax.Array, mask: jax.Array, key: jax.Array | None = None,
             start: jax.Array | None = None) -> jax.Array:
    """Frame by frame on its own poses (eval mode), through the decoder's key/value cache: ``mask [B, T]`` gives
    each action's duration (its first frames); ``key`` samples Z (None: Z = mu) -> poses ``[B, T, 135]``, zero on
    padding. Equals :func:`decode` run on the poses it produced (``tests/test_marionet.py``).

    ``start [B, d]``: the decoder's first input in place of the embedded last context pose (Shadow Start, §4.3.2:
    the start pose's embedding replaced, the condition encoder still reading the context as it is);
    :func:`embed_poses` of ``context[:, -1]`` gives the same action as None."""
    mu, log_variance = encode(params, config, context, tags, next_tags)
    z = mu if key is None else sample_z(key, mu, log_variance)
    frame_controls = controls(params, config, z, tags, path, mask)
    options = _options(config, "decoder", training=False, causal=True)
    frames = mask.shape[1]
    cache = init_decoder_cache(params.decoder, frame_controls, frames, options, tgt_key_padding_mask=mask,
                               memory_key_padding_mask=mask)

    def step(carry, t):
        cache, previous = carry  # previous [B, 135]
        embedded = embed_poses(params, previous)
        if start is not None:
            embedded = jnp.where(t == 0, start, embedded)
        out, cache = decoder_stack_step(params.decoder, cache, _decoder_token(config, embedded, t[None]), t,
                                        options)
        pose = jnp.where(mask[:, t, None], linear(params.pose_head, out), 0.0)
        return (cache, pose), pose

    _, poses = jax.lax.scan(step, (cache, context[:, -1]), jnp.arange(frames))
    return poses.swapaxes(0, 1)
