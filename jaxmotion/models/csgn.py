"""A conditional graph-convolution GAN generator in the style of CSGN (Yan et al., ICCV 2019, "Convolutional
Sequence Generation for Skeleton-Based Action Synthesis") as the ActFormer paper (Xu et al. 2023) uses it:

* ``temporal="conv"``: the CSGN baseline, extended to conditional generation by conditional BatchNorm in the
  generator (the projection in the discriminator is the ActFormer critic's,
  :mod:`jaxmotion.models.actformer_critic`, not part of this module);
* ``temporal="transformer"``: ActFormer's Table 3 row (2), "GraphConv. in Gen.": the skeleton topology modelled
  by the same graph convolutions and graph upsampling, the temporal correlations by T-Formers.

The API is the ActFormer generator's (:mod:`jaxmotion.models.actformer`), so a trainer can use either:
``init_generator(key, config) -> (params, buffers)`` and ``generate(config, params, buffers, z, labels, *,
train) -> (motion, buffers)``; ``buffers`` (:class:`CSGNBuffers`, never None) holds the BatchNorm running
statistics and, with ``spectral_norm``, the power-iteration vectors.

Network (per frame ``t``, nodes on the rows; ``L2 < L1 < V`` the node counts of the skeleton's coarsening
pyramid, :func:`jaxmotion.nn.graph_coarsening.graph_pyramid`, e.g. NTU-25: 5 < 11 < 25)::

    z [B, T, Z] --Linear(Z, L2·w0)--> [B, T, L2, w0] --CBN, act-->
      up3: L2 -> L2 nodes, w1 channels --CBN, act--> (T-Former)
      up2: L2 -> L1 nodes, w2 channels --CBN, act--> (T-Former)
      up1: L1 -> V  nodes, w3 channels --CBN, act--> (T-Former)
      out: V  -> V  nodes, P·C channels (bias) -> [B, T, V, P, C] -> normalize_output

The graph layers are the transposes of the ActFormer critic's (:func:`~jaxmotion.nn.graph_coarsening
.critic_adjacency`: conv0 V -> V, down1 V -> L1, down2 L1 -> L2, down3 L2 -> L2; its conv4, all L2 nodes -> one
node, is mirrored by the input Linear), so the generator is the critic run backwards. A downsampling layer with
normalised hop kernels ``A [K, W, V]`` (K = 2: the node itself, its 1-hop neighbours) gives coarse node ``w``
``sum_k sum_v A[k, w, v] f_{k,v}(x_v)``, ``f_{k,v}`` input node ``v``'s own temporal convolution
(:func:`~jaxmotion.models.actformer_critic.graph_conv`). Its upsampling counterpart (:func:`graph_upsample`)
gives fine node ``v`` ``sum_k sum_w A[k, w, v] g_{k,w}(x_w)``: the same function called with ``A``
transposed to ``[K, V, W]``, ``g_{k,w}`` coarse node ``w``'s own temporal convolution. With node-shared
weights and unit temporal kernels it is the adjoint of the downsampling (``tests/test_csgn.py`` checks
``<down(x), y> = <x, up(y)>``). This is the idea of the authors' ``GraphConvTranspose``, which takes the
matching convolution's kernel as its "computation kernel".

Which parts follow CSGN (as ActFormer's paper describes its use of it), which are this project's reading:

* CSGN: a GP latent sequence as input (here the ActFormer GP prior, :mod:`jaxmotion.nn.gp_prior`, shared by
  the persons); a generator that starts from a single node and grows the skeleton by graph upsampling over a
  coarsened skeleton graph, with BatchNorm and a nonlinearity after every hidden layer. ActFormer's extension:
  conditional BatchNorm. Row (2): graph convolution and graph upsampling "like in CSGN", T-Formers over time.
* This project's reading:
  - the one-node start followed by a first upsampling from that node to the L2 coarse nodes is one per-frame
    ``Linear(Z, L2·w0)`` (the most general map from one node to L2 nodes; it mirrors the critic's conv4);
  - the graph pyramid, hop kernels and node-specific layers are the ActFormer critic's (``use_graph_conv:
    false``), one layer per critic layer, rather than CSGN's own coarsening;
  - **no temporal upsampling** (CSGN grows the sequence in time as well as on the graph): every layer runs at
    the full frame rate (stride 1, 'same' padding, ``time_kernel`` frames, odd); the GP prior already
    correlates the frames, and a constant rate keeps the T-Former variant's sequence length and positions
    fixed. ``temporal="transformer"`` uses temporal kernel 1
    in every graph layer, and after each of the three upsampling stages one pre-LN T-Former block (the
    ActFormer generator's: GELU MLP of ``mlp_ratio · w``, LayerNorm eps 1e-6, ``heads`` heads) over the T
    frames of each node's feature sequence, a learnable ``[T, w]`` temporal positional encoding (ActFormer's truncated
    normal, std 0.02) added before it; the nodes of a stage share the block;
  - conditional BatchNorm: per channel over (batch, frames, nodes), PyTorch's statistics (momentum 0.1, eps
    1e-5, unbiased running variance; :func:`jaxmotion.nn.core.batch_norm`), no affine of its own; the class
    embeddings ``E_g``, ``E_b [K, w]`` give gain ``1 + E_g[y]`` and shift ``E_b[y]``, both zero at init, so the
    layer starts as plain BatchNorm;
  - LeakyReLU with ``negative_slope`` 0.2 (0: ReLU); no biases in layers that a BatchNorm follows, except the
    input Linear's (a per-node bias, not removed by a per-channel norm); a bias in the output layer;
  - several persons: the output layer writes every person's channels on each node, person-major
    (``p·C + c``: "concatenating multi-person motions as a whole in each frame"), then
    :func:`~jaxmotion.models.actformer.normalize_output` per person;
  - initialisation: PyTorch's defaults (U(±1/√fan_in) weights; the T-Former as
    :func:`jaxmotion.nn.transformer.init_encoder_layer`), zero graph-layer bias, zero CBN embeddings;
  - ``spectral_norm`` (default off: CSGN's generator normalises with BatchNorm) divides the input Linear, every
    graph layer (viewed ``[W·c·k, C_in·kernel]`` as the critic does) and the T-Formers' qkv / out / MLP weights
    by their top singular value, the vectors kept in ``buffers.spectral``.

Widths: ``widths = (w0, w1, w2, w3)`` channels at the coarse input, after up3 (coarse), up2 (middle) and up1
(fine); default (128, 128, 64, 32): about 1.0 M parameters at NTU-25, one person, 94 classes with
``temporal="conv"`` (0.63 M with ``"transformer"``), the order of ActFormer's one-person generator (0.72 M).

Axes: B batch, P persons, T frames, V fine nodes (``joints``), L1 / L2 middle / coarse nodes, W a layer's input
nodes, C channels per joint and person, Z latent channels, K classes (hop kernels in adjacencies).
"""

from __future__ import annotations

import dataclasses
import functools
from typing import Literal, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.geometry.skeletons import NTU25, topological_order
from jaxmotion.models.actformer import BlockSpectral, normalize_output, normalized_block, trunc_normal
from jaxmotion.models.actformer_critic import GraphConvParams, init_graph_conv, graph_conv
from jaxmotion.nn.core import BatchNormParams, BatchNormStats, LinearParams, batch_norm, init_linear, linear
from jaxmotion.nn.gp_prior import CHANNELS
from jaxmotion.nn.graph_coarsening import critic_adjacency
from jaxmotion.nn.spectral_norm import SpectralState, init_spectral_state, spectral_normalize
from jaxmotion.nn.transformer import EncoderLayerParams, TransformerOptions, encoder_layer, init_encoder_layer

BN_EPS = 1e-5  # BatchNorm eps (PyTorch's)
BN_MOMENTUM = 0.1  # running = (1 - momentum) · running + momentum · batch (PyTorch's)
_LN_EPS = 1e-6  # the T-Formers' LayerNorm eps (ActFormer's)


@dataclasses.dataclass(frozen=True)
class CSGNConfig:
    """CSGN-style generator. Shared fields mean what :class:`~jaxmotion.models.actformer.GeneratorConfig`'s
    do; ``parents``: the parent list of the ``joints`` generator nodes (SMPL-25: SMPL-24's plus ``(0,)``)."""

    num_classes: int
    joints: int = 25
    channels: int = 3
    persons: int = 1
    frames: int = 60
    latent: int = CHANNELS
    spectral_norm: bool = False
    output: Literal["skeleton", "smpl", "raw"] = "skeleton"
    parents: tuple[int, ...] = NTU25.parents
    temporal: Literal["conv", "transformer"] = "conv"
    widths: tuple[int, int, int, int] = (128, 128, 64, 32)
    time_kernel: int = 3
    heads: int = 4
    mlp_ratio: float = 2.0
    negative_slope: float = 0.2

    def __post_init__(self):
        for name in ("num_classes", "joints", "channels", "persons", "frames", "latent", "time_kernel", "heads"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < 1:
                raise ValueError(f"CSGNConfig.{name}: expected an int >= 1, got {value!r}")
        if self.temporal not in ("conv", "transformer"):
            raise ValueError(f"CSGNConfig.temporal: expected 'conv' or 'transformer', got {self.temporal!r}")
        if self.output not in ("skeleton", "smpl", "raw"):
            raise ValueError(f"CSGNConfig.output: expected 'skeleton', 'smpl' or 'raw', got {self.output!r}")
        if self.output == "skeleton" and self.channels != 3:
            raise ValueError(f"CSGNConfig.output: 'skeleton' normalises 3-vectors, channels is {self.channels}")
        if self.output == "smpl" and self.channels != 6:
            raise ValueError(f"CSGNConfig.output: 'smpl' normalises rot6d (6 channels), channels is {self.channels}")
        if (not isinstance(self.widths, tuple) or len(self.widths) != 4
                or not all(isinstance(w, int) and not isinstance(w, bool) and w >= 1 for w in self.widths)):
            raise ValueError(f"CSGNConfig.widths: expected a tuple of 4 ints >= 1 (coarse input, coarse, middle, "
                             f"fine), got {self.widths!r}")
        if self.time_kernel % 2 == 0:
            raise ValueError(f"CSGNConfig.time_kernel: expected an odd size ('same' padding), got {self.time_kernel}")
        if self.temporal == "transformer" and any(w % self.heads for w in self.widths[1:]):
            raise ValueError(f"CSGNConfig.heads: must divide the T-Former widths {self.widths[1:]}, got {self.heads}")
        if not self.mlp_ratio > 0:
            raise ValueError(f"CSGNConfig.mlp_ratio: expected > 0, got {self.mlp_ratio}")
        if not self.negative_slope >= 0:
            raise ValueError(f"CSGNConfig.negative_slope: expected >= 0, got {self.negative_slope}")
        if not isinstance(self.parents, tuple) or not all(isinstance(p, int) for p in self.parents):
            raise ValueError(f"CSGNConfig.parents: expected a tuple of ints (hashable), got {self.parents!r}")
        if len(self.parents) != self.joints:
            raise ValueError(f"CSGNConfig.parents: expected one parent per generator node ({self.joints} = joints), "
                             f"got {len(self.parents)}")
        try:
            topological_order(self.parents)
        except ValueError as error:
            raise ValueError(f"CSGNConfig.{error}") from None

    @property
    def kernel(self) -> int:
        """Temporal kernel of the graph layers: ``time_kernel``, or 1 with T-Formers."""
        return self.time_kernel if self.temporal == "conv" else 1


# --- parameters --------------------------------------------------------------------------------------------


class CondBatchNormParams(NamedTuple):
    """Class embeddings of a conditional BatchNorm: gain ``1 + gain[y]``, shift ``bias[y]``."""

    gain: jax.Array  # [K, C]
    bias: jax.Array  # [K, C]


class StageParams(NamedTuple):
    """One upsampling stage: graph layer, conditional BatchNorm and (``temporal="transformer"``) a T-Former."""

    conv: GraphConvParams  # weight [W·c·2, C_in, kernel], bias None
    norm: CondBatchNormParams  # [K, c]
    positions: jax.Array | None  # [T, c]
    block: EncoderLayerParams | None  # width c


class CSGNParams(NamedTuple):
    input: LinearParams  # [L2·w0, Z], [L2·w0] (node-major)
    input_norm: CondBatchNormParams  # [K, w0]
    stages: tuple[StageParams, StageParams, StageParams]  # up3 (L2 -> L2), up2 (L2 -> L1), up1 (L1 -> V)
    output: GraphConvParams  # weight [V·P·C·2, w3, kernel], bias [V·P·C·2]


class StageSpectral(NamedTuple):
    conv: SpectralState
    block: BlockSpectral | None


class CSGNSpectral(NamedTuple):
    input: SpectralState
    stages: tuple[StageSpectral, StageSpectral, StageSpectral]
    output: SpectralState


class CSGNBuffers(NamedTuple):
    """What a training call returns moved: running statistics of every BatchNorm, power-iteration vectors."""

    input_norm: BatchNormStats  # [w0]
    stages: tuple[BatchNormStats, BatchNormStats, BatchNormStats]  # [w1], [w2], [w3]
    spectral: CSGNSpectral | None


class CSGNGraphs(NamedTuple):
    """The matching *downsampling* adjacencies ``[K, W, V]`` (coarse rows, fine columns) of the generator's layers,
    i.e. the critic's: each generator layer uses its transpose."""

    out: np.ndarray  # [2, V, V] (critic conv0)
    up1: np.ndarray  # [2, L1, V] (critic down1)
    up2: np.ndarray  # [2, L2, L1] (critic down2)
    up3: np.ndarray  # [2, L2, L2] (critic down3)


@functools.lru_cache(maxsize=16)
def generator_graphs(parents: tuple[int, ...]) -> CSGNGraphs:
    """The adjacencies for the skeleton ``parents`` (cached; the arrays are read-only)."""
    conv0, down1, down2, down3 = critic_adjacency(tuple(parents))
    for a in (conv0, down1, down2, down3):
        a.setflags(write=False)
    return CSGNGraphs(out=conv0, up1=down1, up2=down2, up3=down3)


def _stage_graphs(graphs: CSGNGraphs) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return graphs.up3, graphs.up2, graphs.up1


def _init_cbn(num_classes: int, width: int) -> tuple[CondBatchNormParams, BatchNormStats]:
    zeros = jnp.zeros((num_classes, width), jnp.float32)
    return CondBatchNormParams(zeros, zeros.copy()), BatchNormStats(jnp.zeros((width,)), jnp.ones((width,)))


def init_generator(key: jax.Array, config: CSGNConfig) -> tuple[CSGNParams, CSGNBuffers]:
    """Fresh parameters and buffers (running means 0, variances 1; spectral vectors with ``spectral_norm``)."""
    c = config
    graphs = generator_graphs(c.parents)
    coarse = graphs.up3.shape[1]
    k_in, k_out, k_sn, *k_stages = jax.random.split(key, 6)
    input_norm, input_stats = _init_cbn(c.num_classes, c.widths[0])
    stages, stats = [], []
    for k_stage, down, c_in, c_out in zip(k_stages, _stage_graphs(graphs), c.widths[:3], c.widths[1:]):
        k_conv, k_pos, k_block = jax.random.split(k_stage, 3)
        up = np.swapaxes(down, 1, 2)  # [K, fine, coarse]: input nodes are the coarse ones
        norm, stat = _init_cbn(c.num_classes, c_out)
        transformer = c.temporal == "transformer"
        stages.append(StageParams(
            conv=init_graph_conv(k_conv, up, c_in, c_out, c.kernel, False), norm=norm,
            positions=trunc_normal(k_pos, (c.frames, c_out)) if transformer else None,
            block=init_encoder_layer(k_block, c_out, int(c_out * c.mlp_ratio)) if transformer else None))
        stats.append(stat)
    params = CSGNParams(
        input=init_linear(k_in, c.latent, coarse * c.widths[0]),
        input_norm=input_norm,
        stages=tuple(stages),
        output=init_graph_conv(k_out, graphs.out, c.widths[3], c.persons * c.channels, c.kernel, True),
    )
    buffers = CSGNBuffers(input_stats, tuple(stats), _init_spectral(k_sn, params) if c.spectral_norm else None)
    return params, buffers


# --- spectral normalisation --------------------------------------------------------------------------------


def _block_weights(block: EncoderLayerParams) -> tuple[jax.Array, ...]:
    return (block.self_attn.in_proj_weight, block.self_attn.out_proj.weight, block.linear1.weight,
            block.linear2.weight)


def _init_spectral(key: jax.Array, params: CSGNParams) -> CSGNSpectral:
    k_in, k_out, *k_stages = jax.random.split(key, 2 + len(params.stages))
    stages = []
    for k, stage in zip(k_stages, params.stages):
        k_conv, *k_block = jax.random.split(k, 5)
        block = (None if stage.block is None else
                 BlockSpectral(*(init_spectral_state(kb, w) for kb, w in zip(k_block, _block_weights(stage.block)))))
        stages.append(StageSpectral(init_spectral_state(k_conv, stage.conv.weight), block))
    return CSGNSpectral(init_spectral_state(k_in, params.input.weight), tuple(stages),
                        init_spectral_state(k_out, params.output.weight))


def _normalized(params: CSGNParams, spectral: CSGNSpectral | None, train: bool
                ) -> tuple[CSGNParams, CSGNSpectral | None]:
    """The parameters with every normalised weight divided by its sigma, and the (in training, moved) vectors."""
    if spectral is None:
        return params, None
    sn = functools.partial(spectral_normalize, train=train)
    w_in, s_in = sn(params.input.weight, spectral.input)
    w_out, s_out = sn(params.output.weight, spectral.output)
    stages, states = [], []
    for stage, state in zip(params.stages, spectral.stages):
        w_conv, s_conv = sn(stage.conv.weight, state.conv)
        stage = stage._replace(conv=stage.conv._replace(weight=w_conv))
        s_block = None
        if stage.block is not None:
            block, s_block = normalized_block(stage.block, state.block, train)
            stage = stage._replace(block=block)
        stages.append(stage)
        states.append(StageSpectral(s_conv, s_block))
    params = params._replace(input=params.input._replace(weight=w_in), stages=tuple(stages),
                             output=params.output._replace(weight=w_out))
    return params, (CSGNSpectral(s_in, tuple(states), s_out) if train else spectral)


# --- layers ------------------------------------------------------------------------------------------------


def graph_upsample(p: GraphConvParams, adjacency: np.ndarray, x: jax.Array, *, padding: int) -> jax.Array:
    """Transposed graph convolution: ``x [B, T, W, C_in]`` on the coarse nodes -> ``[B, T, V, c]`` on the fine
    ones, for ``adjacency [K, W, V]`` the matching downsampling's: fine node ``v`` gets ``sum_k sum_w
    A[k, w, v] g_{k,w}(x_w)``, ``g_{k,w}`` coarse node ``w``'s own temporal convolution (stride 1) into
    ``c·k`` channels (``p.weight [W·c·K, C_in, kernel]``)."""
    if adjacency.ndim != 3 or x.ndim != 4 or x.shape[2] != adjacency.shape[1]:
        raise ValueError(f"x: expected [B, T, {adjacency.shape[1]}, C] (the coarse nodes of an adjacency "
                         f"[K, W, V] of shape {tuple(adjacency.shape)}), got {tuple(x.shape)}")
    return graph_conv(p, np.swapaxes(adjacency, 1, 2), x, stride=1, padding=padding)


def conditional_batch_norm(p: CondBatchNormParams, stats: BatchNormStats, x: jax.Array, labels: jax.Array, *,
                           train: bool) -> tuple[jax.Array, BatchNormStats]:
    """``x [B, T, N, C]`` normalised per channel over (batch, frames, nodes) (batch statistics and moved running
    ones in training, the running ones otherwise), then scaled by ``1 + p.gain[labels]`` and shifted by
    ``p.bias[labels]`` per row -> ``(y [B, T, N, C], stats)``."""
    width = x.shape[-1]
    plain = BatchNormParams(jnp.ones((width,), x.dtype), jnp.zeros((width,), x.dtype))
    y, stats = batch_norm(plain, stats, x, train=train, momentum=BN_MOMENTUM, eps=BN_EPS)
    gain, shift = 1.0 + p.gain[labels], p.bias[labels]  # [B, C]
    return y * gain[:, None, None] + shift[:, None, None], stats


def _t_former(stage: StageParams, x: jax.Array, heads: int) -> jax.Array:
    """One pre-LN block over the frames of each node: ``x [B, T, N, c]`` -> same shape."""
    batch, frames, nodes, width = x.shape
    seq = jnp.swapaxes(x, 1, 2).reshape(batch * nodes, frames, width) + stage.positions  # [B·N, T, c]
    seq = encoder_layer(stage.block, seq, TransformerOptions(num_heads=heads, norm_first=True, layer_norm_eps=_LN_EPS))
    return jnp.swapaxes(seq.reshape(batch, nodes, frames, width), 1, 2)


def generate(config: CSGNConfig, params: CSGNParams, buffers: CSGNBuffers, z: jax.Array, labels: jax.Array, *,
             train: bool = False) -> tuple[jax.Array, CSGNBuffers]:
    """``(motion, buffers)`` from latent sequences ``z [B, T, Z]`` (shared by the persons) and action labels
    ``labels [B]`` (int). ``motion``: ``[B, T, V, C]`` for one person, ``[B, P, T, V, C]`` for several.

    ``train``: BatchNorm normalises with the batch's statistics (every row then depends on the batch) and the
    returned buffers carry the running statistics moved by momentum 0.1 (and the spectral vectors moved by one
    power iteration); otherwise the running statistics are used, each row depends only on its own latent and
    label, and ``buffers`` is returned as given.
    """
    c = config
    if z.ndim != 3 or z.shape[1:] != (c.frames, c.latent):
        raise ValueError(f"z: expected [B, {c.frames}, {c.latent}] (one latent sequence per clip, shared by the "
                         f"persons), got {tuple(z.shape)}")
    if labels.shape != z.shape[:1] or not jnp.issubdtype(labels.dtype, jnp.integer):
        raise ValueError(f"labels: expected [B] = [{z.shape[0]}] integer class indices, got shape "
                         f"{tuple(labels.shape)} and dtype {labels.dtype}")
    if not isinstance(buffers, CSGNBuffers) or (buffers.spectral is None) == c.spectral_norm:
        raise ValueError(f"buffers: expected the CSGNBuffers of init_generator for this config (spectral_norm="
                         f"{c.spectral_norm}), got {type(buffers).__name__}")
    graphs = generator_graphs(c.parents)
    p, spectral = _normalized(params, buffers.spectral, train)
    act = lambda h: jax.nn.leaky_relu(h, c.negative_slope)  # noqa: E731
    pad = (c.kernel - 1) // 2
    batch = z.shape[0]

    x = linear(p.input, z).reshape(batch, c.frames, -1, c.widths[0])  # [B, T, L2, w0]
    x, input_stats = conditional_batch_norm(p.input_norm, buffers.input_norm, x, labels, train=train)
    x = act(x)
    stats = []
    for stage, stat, down in zip(p.stages, buffers.stages, _stage_graphs(graphs)):
        x = graph_upsample(stage.conv, down, x, padding=pad)  # [B, T, fine nodes, c]
        x, stat = conditional_batch_norm(stage.norm, stat, x, labels, train=train)
        x = act(x)
        if stage.block is not None:
            x = _t_former(stage, x, c.heads)
        stats.append(stat)
    x = graph_upsample(p.output, graphs.out, x, padding=pad)  # [B, T, V, P·C], person-major
    x = x.reshape(batch, c.frames, c.joints, c.persons, c.channels)
    x = x[:, :, :, 0] if c.persons == 1 else jnp.moveaxis(x, 3, 1)  # [B, T, V, C] or [B, P, T, V, C]
    motion = normalize_output(x, c.output)
    if not train:
        return motion, buffers
    return motion, CSGNBuffers(input_stats, tuple(stats), spectral)
