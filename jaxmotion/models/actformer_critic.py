"""ActFormer's critic (the authors' ``net_D.py`` with ``use_graph_conv: false``): graph convolutions over a
skeleton that is coarsened twice, conditioned on the action by projection.

Input: the motion ``[B, T, V, C]`` (several persons: their channels stacked, person-major, as the code stacks
them) and, with ``motion_flow``, its frame differences (zero at frame 0) as C more channels. Layers
(``time_kernel`` 4, stride 2, padding 1 unless said; LeakyReLU 0.2 after each):

* ``conv0``: V -> V nodes, 32 channels, time kernel 5, stride 1, padding 2, with bias;
* ``down1`` V -> L1 nodes, 64; ``down2`` L1 -> L2, 128; ``down3`` L2 -> L2, 256 (no biases);
* ``conv4``: a plain convolution whose kernel spans all L2 nodes and 4 frames: 512 channels, one node;
* the sum over nodes and frames gives ``h [B, 512]``; the score is ``Linear(h) + <E[y], h>`` (projection
  conditioning, ``E`` an ``Embedding(K, 512)``).

Each graph layer is node-specific (the code's ``use_graph_conv: false``): input node ``v`` has its own temporal
convolution into ``c·k`` channels (the code's grouped convolution, one group per node), and output node ``w`` sums
``A[k, w, v] · f_{k,v}(x_v)`` over the hop kernels ``k`` (self, 1-hop) and input nodes; ``A`` and the coarse node
sets come from :mod:`jaxmotion.nn.graph_coarsening` (the caller passes them as :class:`CriticGraphs`).
Spectral normalisation on every layer, the embedding included (each grouped convolution is one matrix
``[V·c·k, C_in·kernel]``, as PyTorch views it).

Table 4's alternatives (``pooling``): instead of one critic on the stacked persons (``"concat"``, the code),
the same critic body runs on each person alone (C channels) and its per-person features ``h [B, P, 512]`` are
pooled over the persons before the score: ``"avg"``, ``"max"``, or ``"attention"`` (one single-head
self-attention over the persons with a residual, then the mean; the paper does not detail its module, so it is
the plainest symmetric one, spectrally normalised like every other layer).

Init: PyTorch's defaults (FACTS 5: the code's ``weights_init`` does not reach spectrally normalised layers), the
biases zeroed, the embedding orthogonal.

Axes: B batch, T frames, V / W input / output nodes, C channels, K hop kernels.
"""

from __future__ import annotations

import dataclasses
from typing import Literal, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.config import check_at_least
from jaxmotion.nn.core import LinearParams, init_linear, linear, torch_uniform
from jaxmotion.nn.spectral_norm import SpectralState, init_spectral_state, spectral_normalize

_HIGHEST = jax.lax.Precision.HIGHEST
_SLOPE = 0.2  # LeakyReLU


class CriticGraphs(NamedTuple):
    """The four layers' normalised adjacencies ``[K, W, V]``: conv0 (V -> V), down1 (V -> L1), down2 (L1 -> L2),
    down3 (L2 -> L2)."""

    conv0: np.ndarray
    down1: np.ndarray
    down2: np.ndarray
    down3: np.ndarray


@dataclasses.dataclass(frozen=True)
class CriticConfig:
    """The critic at the authors' settings (``config/generator/*``: base 32, skeleton kernel 2, time kernel 4,
    motion flow, spectral norm). ``channels``: per-frame channels of one node of the input (persons x C)."""

    num_classes: int
    joints: int = 25
    channels: int = 3
    base_channels: int = 32
    time_kernel: int = 4
    motion_flow: bool = True
    spectral_norm: bool = True
    pooling: Literal["concat", "avg", "max", "attention"] = "concat"

    def __post_init__(self):
        check_at_least(self, 1, "num_classes", "joints", "channels", "base_channels", "time_kernel")
        if self.pooling not in ("concat", "avg", "max", "attention"):
            raise ValueError(f"CriticConfig.pooling: expected concat, avg, max or attention, got {self.pooling!r}")

    @property
    def widths(self) -> tuple[int, int, int, int, int]:
        return tuple(self.base_channels * m for m in (1, 2, 4, 8, 16))

    @property
    def in_channels(self) -> int:
        return self.channels * (2 if self.motion_flow else 1)


class GraphConvParams(NamedTuple):
    weight: jax.Array  # [V·c·k, C_in, kernel] (one temporal convolution per input node)
    bias: jax.Array | None  # [V·c·k]


class CriticParams(NamedTuple):
    conv0: GraphConvParams
    down1: GraphConvParams
    down2: GraphConvParams
    down3: GraphConvParams
    conv4_weight: jax.Array  # [512, 256, L2, kernel]
    conv4_bias: jax.Array  # [512]
    conv5: LinearParams  # [1, 512]
    embedding: jax.Array  # [K, 512]
    attention: tuple[LinearParams, ...] | None = None  # pooling="attention": q, k, v, out [512, 512]


class CriticSpectral(NamedTuple):
    conv0: SpectralState
    down1: SpectralState
    down2: SpectralState
    down3: SpectralState
    conv4: SpectralState
    conv5: SpectralState
    embedding: SpectralState
    attention: tuple[SpectralState, ...] | None = None


def _check_graphs(graphs: CriticGraphs, joints: int) -> None:
    chain = [(graphs.conv0, "conv0"), (graphs.down1, "down1"), (graphs.down2, "down2"), (graphs.down3, "down3")]
    inputs = joints
    for a, name in chain:
        if a.ndim != 3 or a.shape[2] != inputs:
            raise ValueError(f"graphs.{name}: expected [K, W, {inputs}] (its input nodes are the previous layer's "
                             f"outputs), got {tuple(a.shape)}")
        inputs = a.shape[1]


def init_graph_conv(key: jax.Array, adjacency: np.ndarray, c_in: int, c_out: int, kernel: int,
                     bias: bool) -> GraphConvParams:
    hops, _, nodes = adjacency.shape
    fan_in = c_in * kernel
    weight = torch_uniform(key, (nodes * c_out * hops, c_in, kernel), fan_in)
    return GraphConvParams(weight, jnp.zeros((nodes * c_out * hops,)) if bias else None)


def init_critic(key: jax.Array, config: CriticConfig, graphs: CriticGraphs) -> tuple[CriticParams, CriticSpectral | None]:
    """Fresh parameters and (with ``spectral_norm``) power-iteration vectors for ``graphs``."""
    _check_graphs(graphs, config.joints)
    c1, c2, c3, c4, c5 = config.widths
    kt = config.time_kernel
    keys = jax.random.split(key, 10)
    coarse = graphs.down3.shape[1]
    attention = (tuple(init_linear(k, c5, c5)._replace(bias=jnp.zeros((c5,))) for k in jax.random.split(keys[8], 4))
                 if config.pooling == "attention" else None)
    params = CriticParams(
        conv0=init_graph_conv(keys[0], graphs.conv0, config.in_channels, c1, 5, True),
        down1=init_graph_conv(keys[1], graphs.down1, c1, c2, kt, False),
        down2=init_graph_conv(keys[2], graphs.down2, c2, c3, kt, False),
        down3=init_graph_conv(keys[3], graphs.down3, c3, c4, kt, False),
        conv4_weight=torch_uniform(keys[4], (c5, c4, coarse, kt), c4 * coarse * kt),
        conv4_bias=jnp.zeros((c5,)),
        conv5=init_linear(keys[5], c5, 1)._replace(bias=jnp.zeros((1,))),
        embedding=jax.nn.initializers.orthogonal()(keys[6], (config.num_classes, c5), jnp.float32),
        attention=attention,
    )
    if not config.spectral_norm:
        return params, None
    weights = (params.conv0.weight, params.down1.weight, params.down2.weight, params.down3.weight,
               params.conv4_weight, params.conv5.weight, params.embedding)
    states = CriticSpectral(*(init_spectral_state(k, w) for k, w in zip(jax.random.split(keys[7], 7), weights)))
    if attention is not None:
        states = states._replace(attention=tuple(init_spectral_state(k, layer.weight) for k, layer in
                                                 zip(jax.random.split(keys[9], 4), attention)))
    return params, states




def _normalized(params: CriticParams, spectral: CriticSpectral | None, train: bool
                ) -> tuple[CriticParams, CriticSpectral | None]:
    if spectral is None:
        return params, None
    out = [spectral_normalize(w, s, train=train) for w, s in zip(
        (params.conv0.weight, params.down1.weight, params.down2.weight, params.down3.weight, params.conv4_weight,
         params.conv5.weight, params.embedding), spectral)]
    w0, w1, w2, w3, w4, w5, emb = (w for w, _ in out)
    moved = CriticSpectral(*(s for _, s in out))
    if params.attention is not None:
        pairs = [spectral_normalize(layer.weight, st, train=train) for layer, st in zip(params.attention,
                                                                                          spectral.attention)]
        params = params._replace(attention=tuple(layer._replace(weight=w) for layer, (w, _) in
                                                 zip(params.attention, pairs)))
        moved = moved._replace(attention=tuple(st for _, st in pairs))
    params = params._replace(conv0=params.conv0._replace(weight=w0), down1=params.down1._replace(weight=w1),
                             down2=params.down2._replace(weight=w2), down3=params.down3._replace(weight=w3),
                             conv4_weight=w4, conv5=params.conv5._replace(weight=w5), embedding=emb)
    return params, (moved if train else spectral)


def time_windows(x: jax.Array, kernel: int, stride: int, padding: int) -> jax.Array:
    """``x [B, T, ...]`` -> ``[B, T', kernel, ...]``: the frames each output frame of a strided temporal
    convolution reads (zero-padded by ``padding`` at both ends), so the convolution becomes one matmul over
    (kernel, channels). XLA's CPU convolutions with one group per node, and its NCHW ones, run several times
    slower than these matmuls."""
    frames = x.shape[1]
    out = (frames + 2 * padding - kernel) // stride + 1
    if out < 1:
        raise ValueError(f"x: {frames} frames are too few for a temporal kernel of {kernel} with padding {padding}")
    padded = jnp.pad(x, [(0, 0), (padding, padding)] + [(0, 0)] * (x.ndim - 2))
    return jnp.stack([padded[:, i:i + stride * (out - 1) + 1:stride] for i in range(kernel)], axis=2)


def graph_conv(p: GraphConvParams, adjacency: np.ndarray, x: jax.Array, *, stride: int, padding: int) -> jax.Array:
    """``x [B, T, V, C_in]`` -> ``[B, T', W, c]``: node ``v``'s own temporal convolution into ``c·k`` channels,
    then ``sum_k sum_v A[k, w, v] f_{k, v}(x_v)``."""
    hops, _, nodes = adjacency.shape
    c_in, kernel = p.weight.shape[1:]
    c = p.weight.shape[0] // (nodes * hops)
    weight = p.weight.reshape(nodes, c * hops, c_in, kernel)  # group v's filters
    y = jnp.einsum("btjvi,voij->btvo", time_windows(x, kernel, stride, padding), weight, precision=_HIGHEST)
    if p.bias is not None:
        y = y + p.bias.reshape(nodes, c * hops)
    y = y.reshape(*y.shape[:3], c, hops)  # channel v·(c·k) + c_i·k + k_i, as the code views it
    return jnp.einsum("kwv,btvck->btwc", jnp.asarray(adjacency, jnp.float32), y, precision=_HIGHEST)


def critic(config: CriticConfig, graphs: CriticGraphs, params: CriticParams, buffers: CriticSpectral | None,
           motion: jax.Array, labels: jax.Array, *, train: bool = False) -> tuple[jax.Array, CriticSpectral | None]:
    """``(scores [B], buffers)`` (``buffers``: the spectral-norm vectors) for ``motion`` ``[B, T, V, C]`` or ``[B, P, T, V, C]`` (``pooling="concat"``:
    persons stacked on the channels, person-major; otherwise each person alone, then pooled) and ``labels [B]``;
    ``train`` moves the power iterations."""
    pooled = config.pooling != "concat"
    if pooled and (motion.ndim != 5 or motion.shape[3:] != (config.joints, config.channels)):
        raise ValueError(f"motion: pooling {config.pooling!r} scores persons one by one: expected [B, P, T, "
                         f"{config.joints}, {config.channels}], got {tuple(motion.shape)}")
    persons = motion.shape[1] if pooled else 1
    if pooled:
        motion = motion.reshape(-1, *motion.shape[2:])  # [B·P, T, V, C]
    elif motion.ndim == 5:
        motion = jnp.moveaxis(motion, 1, 3).reshape(*motion.shape[0:1], *motion.shape[2:4], -1)
    if motion.ndim != 4 or motion.shape[2:] != (config.joints, config.channels):
        raise ValueError(f"motion: expected [B, T, {config.joints}, {config.channels}] (or [B, P, T, "
                         f"{config.joints}, C] with P·C = {config.channels}), got {tuple(motion.shape)}")
    if labels.shape != (motion.shape[0] // persons,):
        raise ValueError(f"labels: expected [B] = [{motion.shape[0] // persons}] class indices, got "
                         f"{tuple(labels.shape)}")
    p, buffers = _normalized(params, buffers, train)
    x = motion
    if config.motion_flow:
        flow = jnp.concatenate([jnp.zeros_like(x[:, :1]), x[:, 1:] - x[:, :-1]], 1)
        x = jnp.concatenate([x, flow], -1)
    act = lambda h: jax.nn.leaky_relu(h, _SLOPE)  # noqa: E731
    pad = (config.time_kernel - 2) // 2
    x = act(graph_conv(p.conv0, graphs.conv0, x, stride=1, padding=2))
    for layer, adjacency in ((p.down1, graphs.down1), (p.down2, graphs.down2), (p.down3, graphs.down3)):
        x = act(graph_conv(layer, adjacency, x, stride=2, padding=pad))
    # conv4: a convolution over (nodes, frames) whose kernel spans every node: [B, T, W, C] -> [B, T', 512]
    y = jnp.einsum("btjwc,ocwj->bto", time_windows(x, config.time_kernel, 2, pad), p.conv4_weight,
                   precision=_HIGHEST)
    h = act(y + p.conv4_bias).sum(axis=1)  # [B, 512] (pooled: [B·P, 512])
    if pooled:
        h = pool_persons(config.pooling, h.reshape(-1, persons, h.shape[-1]), p.attention)
    score = linear(p.conv5, h)[:, 0] + jnp.sum(p.embedding[labels] * h, -1)
    return score, buffers


def pool_persons(pooling: str, h: jax.Array, attention: tuple[LinearParams, ...] | None = None) -> jax.Array:
    """Per-person critic features ``h [B, P, D]`` -> ``[B, D]``, symmetric in the persons: their mean, their
    channel-wise max, or one single-head self-attention with a residual (``attention``: q, k, v, out), then
    the mean."""
    if pooling == "avg":
        return jnp.mean(h, 1)
    if pooling == "max":
        return jnp.max(h, 1)
    if pooling == "attention":
        q, k, v = (linear(layer, h) for layer in attention[:3])
        out = attention[3]
        weights = jax.nn.softmax(jnp.einsum("bpd,bqd->bpq", q, k, precision=_HIGHEST) / np.sqrt(h.shape[-1]), -1)
        return jnp.mean(h + linear(out, jnp.einsum("bpq,bqd->bpd", weights, v, precision=_HIGHEST)), 1)
    raise ValueError(f"pooling: expected avg, max or attention, got {pooling!r}")
