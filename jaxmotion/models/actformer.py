"""ActFormer's generator (Xu et al. 2023): a Transformer that turns a Gaussian-process latent sequence and an
action label into the motion of one or several persons.

One person (the authors' ``net_G.py``): the latent sequence ``z [B, T, Z]`` (:mod:`jaxmotion.nn.gp_prior`) is
projected frame by frame to the width ``D = 8 V`` (``Linear(Z, D)``), an action token (``Embedding(K, D)``,
orthogonal init) is put in front, learnable positional encodings ``[T + 1, D]`` are added, and ``depth``
pre-LN Transformer blocks over time (T-Formers: LayerNorm eps 1e-6, 8 heads, GELU MLP of width
``mlp_ratio · D``, qkv with bias, no dropout) mix the frames. A last LayerNorm and ``Linear(D, V·C)`` give each
frame's joints; the action token's output is dropped.

Several persons (``net_G_multip.py``): the token grid is ``[T + 1, P, D]``, every person starting from the same
embedded latent and action token (the shared z), and each of the ``depth`` blocks is an I-Former (attention over
the P persons of a frame) followed by a T-Former (over the T + 1 tokens of a person). The positional encoding is
one free ``[T + 1, P, D]`` tensor initialised as the concatenation of a temporal ``[T + 1, D/2]`` and a person
``[P, D/2]`` part (``positions="split"``; ``"independent"`` draws the whole tensor at once; ``"fixed"``:
sinusoidal codes, not trained, the class row zero). ``interaction="concat"`` (Table 5's "interaction by
concatenation"): the one-person network whose head gives every person's joints at once (``V·P·C`` per frame,
person-major per joint, as the code's channel layout), no I-Formers.

Output normalisation (``output``): ``skeleton``, for root + limb-vector data (NTU-25, GTA-22): joint 0 is the
raw root position, every other joint ``tanh`` then divided by its norm + 1e-4 (a unit limb direction);
``smpl``, for rot6d + translation (SMPL-25): joints 0..V-2 ``tanh`` then Gram-Schmidt on their two 3-vectors,
joint V-1 the raw translation; ``raw``: as the head gives it.

Spectral normalisation (``spectral_norm``, on by default as in the code): every Linear (input embedding, qkv,
attention output, both MLP layers, head) and the last LayerNorm's gain are divided by their top singular value
(:mod:`jaxmotion.nn.spectral_norm`); the power-iteration vectors are a separate pytree
(:class:`GeneratorSpectral`) that a training call returns moved. The block norms are not normalised (the code's
lines for them are commented out).

Initialisation is what the authors' code trains from, not its stated intent (FACTS 5): their ``weights_init``
runs after ``spectral_norm`` wrapped the Linears, so it writes a derived tensor and every wrapped Linear keeps
PyTorch's default U(±1/√fan_in) weights; biases are zeroed; the block LayerNorm gains N(1, 0.02), the last one
1; positional encodings truncated-normal 0.02. Without spectral normalisation ``weights_init`` does reach the
Linears: N(0, 0.02).

Axes: B batch, P persons, T frames, V joints, C channels per joint, Z latent channels, D width, K classes.
"""

from __future__ import annotations

import dataclasses
import functools
from typing import Literal, NamedTuple

import jax
import jax.numpy as jnp

from jaxmotion.config import check_at_least
from jaxmotion.nn.core import LayerNormParams, LinearParams, init_linear, layer_norm, linear
from jaxmotion.nn.gp_prior import CHANNELS
from jaxmotion.nn.spectral_norm import SpectralState, init_spectral_state, spectral_normalize
from jaxmotion.nn.transformer import (
    AttentionParams,
    EncoderLayerParams,
    TransformerOptions,
    encoder_layer,
    sinusoidal_encoding,
    stack_layers,
)

_EPS = 1e-6  # the blocks' and the last norm's LayerNorm eps


@dataclasses.dataclass(frozen=True)
class GeneratorConfig:
    """ActFormer's generator; defaults are the authors' NTU configs (``config/generator/ntu120_*``)."""

    num_classes: int
    joints: int = 25
    channels: int = 3
    persons: int = 1
    frames: int = 60
    latent: int = CHANNELS
    width_per_joint: int = 8
    depth: int = 2
    heads: int = 8
    mlp_ratio: float = 2.0
    spectral_norm: bool = True
    output: Literal["skeleton", "smpl", "raw"] = "skeleton"
    positions: Literal["split", "independent", "fixed"] = "split"
    interaction: Literal["iformer", "concat"] = "iformer"

    def __post_init__(self):
        check_at_least(self, 1, "num_classes", "joints", "channels", "persons", "frames", "latent", "width_per_joint",
                       "depth", "heads")
        if self.width % self.heads:
            raise ValueError(f"GeneratorConfig.heads: must divide the width {self.width} (= width_per_joint · joints)")
        if self.output == "skeleton" and self.channels != 3:
            raise ValueError(f"GeneratorConfig.output: 'skeleton' normalises 3-vectors, channels is {self.channels}")
        if self.output == "smpl" and self.channels != 6:
            raise ValueError(f"GeneratorConfig.output: 'smpl' normalises rot6d (6 channels), channels is {self.channels}")
        if self.output not in ("skeleton", "smpl", "raw") or self.positions not in ("split", "independent", "fixed"):
            raise ValueError(f"GeneratorConfig: output {self.output!r} / positions {self.positions!r} unknown")
        if self.interaction not in ("iformer", "concat"):
            raise ValueError(f"GeneratorConfig.interaction: expected 'iformer' or 'concat', got {self.interaction!r}")
        if self.positions == "fixed" and self.width % 4:
            raise ValueError(f"GeneratorConfig.positions: 'fixed' needs a width divisible by 4, got {self.width}")

    @property
    def width(self) -> int:
        return self.width_per_joint * self.joints

    @property
    def tokens_per_person(self) -> bool:
        """Whether each person has its own tokens (I-Formers); otherwise one token sequence for the clip."""
        return self.persons > 1 and self.interaction == "iformer"

    @property
    def num_blocks(self) -> int:
        """Transformer layers: ``depth`` T-Formers, or ``depth`` (I-Former, T-Former) pairs."""
        return 2 * self.depth if self.tokens_per_person else self.depth


class GeneratorParams(NamedTuple):
    input_embedding: LinearParams  # [D, Z], [D]
    class_embedding: jax.Array  # [K, D]
    positions: jax.Array | None  # [T + 1, D] (one person) or [T + 1, P, D]; None when fixed
    blocks: EncoderLayerParams  # stacked on a leading axis of num_blocks (I- and T-Formers alternating)
    final_norm: LayerNormParams  # [D]
    head: LinearParams  # [V·C, D], [V·C]


class BlockSpectral(NamedTuple):
    qkv: SpectralState
    proj: SpectralState
    fc1: SpectralState
    fc2: SpectralState


class GeneratorSpectral(NamedTuple):
    """Power-iteration vectors of every spectrally normalised weight (block ones stacked like the blocks)."""

    input_embedding: SpectralState
    blocks: BlockSpectral
    final_norm: SpectralState
    head: SpectralState


# --- initialisation ----------------------------------------------------------------------------------------


def _init_linear(key: jax.Array, in_dim: int, out_dim: int, spectral_norm: bool) -> LinearParams:
    """A Linear as the code trains it: PyTorch's default weight (wrapped) or N(0, 0.02), zero bias."""
    p = init_linear(key, in_dim, out_dim)
    weight = p.weight if spectral_norm else 0.02 * jax.random.normal(key, p.weight.shape)
    return LinearParams(weight, jnp.zeros_like(p.bias))


def _init_norm(key: jax.Array, dim: int) -> LayerNormParams:
    return LayerNormParams(1.0 + 0.02 * jax.random.normal(key, (dim,)), jnp.zeros((dim,)))


def _init_block(key: jax.Array, config: GeneratorConfig) -> EncoderLayerParams:
    d, hidden, sn = config.width, int(config.width * config.mlp_ratio), config.spectral_norm
    k_qkv, k_proj, k_1, k_2, k_n1, k_n2 = jax.random.split(key, 6)
    qkv = _init_linear(k_qkv, d, 3 * d, sn)
    return EncoderLayerParams(self_attn=AttentionParams(qkv.weight, qkv.bias, _init_linear(k_proj, d, d, sn)),
                              linear1=_init_linear(k_1, d, hidden, sn), linear2=_init_linear(k_2, hidden, d, sn),
                              norm1=_init_norm(k_n1, d), norm2=_init_norm(k_n2, d))


def trunc_normal(key: jax.Array, shape: tuple[int, ...]) -> jax.Array:
    """The code's ``trunc_normal_(std=0.02)``: cut at ±2 absolute, i.e. ±100 standard deviations."""
    return 0.02 * jax.random.truncated_normal(key, -100.0, 100.0, shape)


def _init_positions(key: jax.Array, config: GeneratorConfig) -> jax.Array | None:
    steps, persons, d = config.frames + 1, config.persons, config.width
    if config.positions == "fixed":
        return None
    if not config.tokens_per_person:
        return trunc_normal(key, (steps, d))
    if config.positions == "independent":
        return trunc_normal(key, (steps, persons, d))
    k_t, k_p = jax.random.split(key)
    temporal = jnp.broadcast_to(trunc_normal(k_t, (steps, 1, d // 2)), (steps, persons, d // 2))
    person = jnp.broadcast_to(trunc_normal(k_p, (1, persons, d - d // 2)), (steps, persons, d - d // 2))
    return jnp.concatenate([temporal, person], -1)


def fixed_positions(config: GeneratorConfig) -> jax.Array:
    """``[T + 1, D]`` or ``[T + 1, P, D]`` the sinusoidal codes of ``positions="fixed"`` (class row zero; several
    persons: the temporal code in the first half of the width, the person code in the second)."""
    steps, persons, d = config.frames, config.persons, config.width
    if not config.tokens_per_person:
        return jnp.concatenate([jnp.zeros((1, d)), sinusoidal_encoding(jnp.arange(steps), d)])
    temporal = jnp.broadcast_to(sinusoidal_encoding(jnp.arange(steps), d // 2)[:, None], (steps, persons, d // 2))
    person = jnp.broadcast_to(sinusoidal_encoding(jnp.arange(persons), d // 2)[None], (steps, persons, d // 2))
    return jnp.concatenate([jnp.zeros((1, persons, d)), jnp.concatenate([temporal, person], -1)])


def init_generator(key: jax.Array, config: GeneratorConfig) -> tuple[GeneratorParams, GeneratorSpectral | None]:
    """Fresh parameters and (with ``spectral_norm``) power-iteration vectors."""
    k_in, k_cls, k_pos, k_blocks, k_head, k_sn = jax.random.split(key, 6)
    d, sn = config.width, config.spectral_norm
    params = GeneratorParams(
        input_embedding=_init_linear(k_in, config.latent, d, sn),
        class_embedding=jax.nn.initializers.orthogonal()(k_cls, (config.num_classes, d), jnp.float32),
        positions=_init_positions(k_pos, config),
        blocks=stack_layers([_init_block(k, config) for k in jax.random.split(k_blocks, config.num_blocks)]),
        final_norm=LayerNormParams(jnp.ones((d,)), jnp.zeros((d,))),
        head=_init_linear(k_head, d, config.joints * config.channels * (1 if config.tokens_per_person
                                                                        else config.persons), sn),
    )
    if not sn:
        return params, None
    keys = iter(jax.random.split(k_sn, 4 + 4 * config.num_blocks))
    blocks = [BlockSpectral(*(init_spectral_state(next(keys), w) for w in
                              (b.self_attn.in_proj_weight, b.self_attn.out_proj.weight, b.linear1.weight,
                               b.linear2.weight)))
              for b in (jax.tree.map(lambda leaf, i=i: leaf[i], params.blocks) for i in range(config.num_blocks))]
    spectral = GeneratorSpectral(init_spectral_state(next(keys), params.input_embedding.weight),
                                 stack_layers(blocks), init_spectral_state(next(keys), params.final_norm.weight),
                                 init_spectral_state(next(keys), params.head.weight))
    return params, spectral




# --- forward -----------------------------------------------------------------------------------------------


def _normalized(params: GeneratorParams, spectral: GeneratorSpectral | None, train: bool
                ) -> tuple[GeneratorParams, GeneratorSpectral | None]:
    """The parameters with every spectrally normalised weight divided by its sigma, and the moved vectors."""
    if spectral is None:
        return params, None
    sn = functools.partial(spectral_normalize, train=train)
    blocks, s_blocks = jax.vmap(lambda b, s: normalized_block(b, s, train))(params.blocks, spectral.blocks)
    w_in, s_in = sn(params.input_embedding.weight, spectral.input_embedding)
    gain, s_norm = sn(params.final_norm.weight, spectral.final_norm)
    w_head, s_head = sn(params.head.weight, spectral.head)
    params = params._replace(input_embedding=params.input_embedding._replace(weight=w_in), blocks=blocks,
                             final_norm=params.final_norm._replace(weight=gain),
                             head=params.head._replace(weight=w_head))
    if not train:
        return params, spectral
    return params, GeneratorSpectral(s_in, s_blocks, s_norm, s_head)


def normalized_block(block: EncoderLayerParams, spectral: BlockSpectral, train: bool
                     ) -> tuple[EncoderLayerParams, BlockSpectral]:
    """A Transformer block with its qkv, attention-output and MLP weights divided by their top singular values,
    and the power-iteration vectors (moved when ``train``)."""
    a = block.self_attn
    (qkv, s_qkv), (proj, s_proj), (fc1, s_fc1), (fc2, s_fc2) = (
        spectral_normalize(w, s, train=train)
        for w, s in zip((a.in_proj_weight, a.out_proj.weight, block.linear1.weight, block.linear2.weight), spectral))
    block = block._replace(self_attn=a._replace(in_proj_weight=qkv, out_proj=a.out_proj._replace(weight=proj)),
                           linear1=block.linear1._replace(weight=fc1), linear2=block.linear2._replace(weight=fc2))
    return block, BlockSpectral(s_qkv, s_proj, s_fc1, s_fc2)


def _block(p: EncoderLayerParams, x: jax.Array, heads: int) -> jax.Array:
    """One pre-LN block over the middle axis of ``x [N, S, D]``."""
    return encoder_layer(p, x, TransformerOptions(num_heads=heads, norm_first=True, layer_norm_eps=_EPS))


def normalize_output(x: jax.Array, output: str) -> jax.Array:
    """The head's ``[..., V, C]`` -> the representation's constraints (module docstring)."""
    if output == "skeleton":
        limbs = jnp.tanh(x[..., 1:, :])
        limbs = limbs / (jnp.linalg.norm(limbs, axis=-1, keepdims=True) + 1e-4)
        return jnp.concatenate([x[..., :1, :], limbs], -2)
    if output == "smpl":
        a1, a2 = jnp.split(jnp.tanh(x[..., :-1, :]), 2, axis=-1)
        unit = lambda v: v / jnp.maximum(jnp.linalg.norm(v, axis=-1, keepdims=True), 1e-12)  # noqa: E731
        b1 = unit(a1)
        b2 = unit(a2 - jnp.sum(b1 * a2, -1, keepdims=True) * b1)
        return jnp.concatenate([jnp.concatenate([b1, b2], -1), x[..., -1:, :]], -2)
    return x


def generate(config: GeneratorConfig, params: GeneratorParams, buffers: GeneratorSpectral | None, z: jax.Array,
             labels: jax.Array, *, train: bool = False) -> tuple[jax.Array, GeneratorSpectral | None]:
    """``(motion, buffers)`` from latent sequences and action labels; ``buffers``: the spectral-norm vectors
    (None: no spectral normalisation).

    ``z``: ``[B, T, Z]`` (shared by all persons) or ``[B, P, T, Z]`` (one sequence per person, the "w/o
    shared z" ablation); ``labels [B]`` int. ``motion``: ``[B, T, V, C]`` for one person, ``[B, P, T, V, C]``
    for several. ``train``: one power iteration per normalised weight, the moved vectors returned.
    """
    c = config
    shared = z.ndim == 3
    if z.shape[-2:] != (c.frames, c.latent) or not (shared or (z.ndim == 4 and z.shape[1] == c.persons)):
        raise ValueError(f"z: expected [B, {c.frames}, {c.latent}] or [B, {c.persons}, {c.frames}, {c.latent}], "
                         f"got {tuple(z.shape)}")
    if labels.shape != z.shape[:1]:
        raise ValueError(f"labels: expected [B] = [{z.shape[0]}] class indices, got {tuple(labels.shape)}")
    p, buffers = _normalized(params, buffers, train)
    batch, d = z.shape[0], c.width
    x = linear(p.input_embedding, z)  # [B, T, D] or [B, P, T, D]
    token = p.class_embedding[labels]  # [B, D]
    positions = fixed_positions(c) if p.positions is None else p.positions
    if not c.tokens_per_person:
        if not shared:
            raise ValueError("z: one latent sequence per person needs interaction='iformer' (tokens per person)")
        x = jnp.concatenate([token[:, None], x], 1) + positions  # [B, T + 1, D]
        for i in range(c.num_blocks):
            x = _block(jax.tree.map(lambda leaf, i=i: leaf[i], p.blocks), x, c.heads)
    else:
        if shared:
            x = jnp.broadcast_to(x[:, None], (batch, c.persons, c.frames, d))
        x = jnp.concatenate([jnp.broadcast_to(token[:, None, None], (batch, c.persons, 1, d)), x], 2)
        x = jnp.swapaxes(x, 1, 2) + positions  # [B, T + 1, P, D]
        for i in range(c.depth):
            interact = jax.tree.map(lambda leaf, i=i: leaf[2 * i], p.blocks)
            temporal = jax.tree.map(lambda leaf, i=i: leaf[2 * i + 1], p.blocks)
            x = _block(interact, x.reshape(-1, c.persons, d), c.heads).reshape(batch, c.frames + 1, c.persons, d)
            x = jnp.swapaxes(x, 1, 2).reshape(-1, c.frames + 1, d)  # [B·P, T + 1, D]
            x = jnp.swapaxes(_block(temporal, x, c.heads).reshape(batch, c.persons, c.frames + 1, d), 1, 2)
        x = jnp.swapaxes(x, 1, 2)  # [B, P, T + 1, D]
    x = linear(p.head, layer_norm(p.final_norm, x, eps=_EPS))[..., 1:, :]  # the action token dropped
    if c.persons > 1 and not c.tokens_per_person:  # one token per frame holding every person, person-major
        x = jnp.moveaxis(x.reshape(batch, c.frames, c.joints, c.persons, c.channels), 3, 1)
    else:
        x = x.reshape(*x.shape[:-1], c.joints, c.channels)
    return normalize_output(x, c.output), buffers
