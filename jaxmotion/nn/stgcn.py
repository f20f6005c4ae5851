"""ST-GCN, the spatial-temporal graph convolutional action recogniser (Yan et al. 2018), as pure functions
over NamedTuple parameter and BatchNorm-statistics pytrees.

Where it is used:

* **ACTOR's UESTC evaluator** (``src/recognition/models/stgcn.py``): input the 6-d rotations of the 24
  SMPL joints without the translation row, ``[B, T, 24, 6]``; SMPL tree with centre joint 0; 40 classes;
  the 256-d globally pooled vector is the feature behind FID, diversity and multimodality; no dropout.
* **ActFormer's recogniser** (``net/st_gcn/st_gcn.py``) for all its datasets: the same network with
  dropout 0.5, one or two persons, features averaged over persons.

Network: a BatchNorm over the joint-by-channel input channels, then one block per entry of ``channels``
(reference: 64, 64, 64, 64, 128, 128, 128, 256, 256, 256 with temporal stride 2 at the 5th and 8th), then the
mean over frames, joints and persons (the feature) and a linear classifier. A block maps ``x`` to

    y[w] = Σ_k Σ_v graph[k, v, w] · (W_k x[v] + b_k)       graph conv: one 1×1 conv to K·C_out channels
    out  = relu(dropout(BN(conv_t(relu(BN(y))))) + residual(x))

with ``conv_t`` a temporal convolution (kernel 9, "same" padding, the block's stride) and ``residual``
absent in the first block, the identity when channels and length are unchanged, else a strided 1×1 conv
and BN. ``graph`` is ``spatial_partition(parents, center)`` scaled by a learnt per-block edge importance
(initialised to ones).

Use: ``graph = spatial_partition(parents, center)``; ``params, stats = init_stgcn(key, graph, C, classes,
channels=..., strides=...)``; ``(logits, features), stats = stgcn(params, stats, x, graph, strides=...,
train=...)``. Train mode normalises with batch statistics and returns the moved running statistics; eval
mode uses (and returns) the running ones.

Inputs are ``[B, T, V, C]`` or ``[B, M, T, V, C]``; ACTOR's ``batch["x"]`` ``(B, V, C, T)`` is
``x.transpose(0, 3, 1, 2)`` and ActFormer's ``(N, C, T, V, M)`` is ``x.transpose(0, 4, 2, 3, 1)``.

Layout: channels last, ``[N, T, V, C]`` (``N`` = batch × persons), so the 1×1 convolutions are plain
matrix products over the last axis and the temporal convolution is an ordinary NHWC conv, the layouts
XLA's CPU backend is fastest with. Parameters map one-to-one onto the reference state dict, with PyTorch's
shapes less the unit kernel axes of the 1×1 and ``(9, 1)`` convolutions:

    data_bn                               -> data_bn             [V, C] for the reference's V·C channels
    st_gcn_networks.{i}.gcn.conv          -> blocks[i].gcn       weight [K·C_out, C_in], subset-major as
                                                                  the reference's view(n, K, C, t, v)
    st_gcn_networks.{i}.tcn.0 / .2 / .3   -> blocks[i].tcn_bn_in / tcn_conv [C_out, C_out, 9] / tcn_bn_out
    st_gcn_networks.{i}.residual.0 / .1   -> blocks[i].residual_conv [C_out, C_in] / residual_bn
    edge_importance.{i}                   -> blocks[i].edge_importance [K, V, V]
    fcn                                   -> fcn                 weight [classes, C_last]

with BatchNorm ``weight`` / ``bias`` in the parameters and ``running_mean`` / ``running_var`` in the
statistics (``data_bn``'s joint-major channels reshape to ``[V, C]``).

Choices where the reference is ambiguous or differs between the two codebases:

* **Spatial partition with truncated distances.** The reference measures each joint's distance to the
  centre with the same hop matrix it builds for the neighbourhood, which stops at ``max_hop``; joints
  farther than that are all "infinitely" far and compare equal. So only edges with an end within ``max_hop``
  of the centre are split by direction; every deeper edge falls, both ways, in the "same or farther"
  subset (on SMPL with ``max_hop = 1``: just the six edges 0-1, 0-2, 0-3, 1-4, 2-5, 3-6 are split).
  Reproduced as is, because evaluator weights trained on that graph expect it.
* **Dropout in every block.** ACTOR strips the dropout argument from block 1, ActFormer passes it to all
  blocks; ActFormer is followed (ACTOR uses no dropout, so nothing changes for it). Masks are
  :func:`jaxmotion.nn.core.dropout`'s, one key per block split from ``dropout_key``.
* **Initialisation** is PyTorch's default (weights and biases uniform in ±1/√fan_in, BN scale 1, shift 0),
  which is what ACTOR trains from. ActFormer's trainer re-initialises (conv weights N(0, 0.02), zero biases,
  BN scales N(1, 0.02)); that belongs to a trainer, not to this module.
* **BatchNorm** is PyTorch's (:func:`jaxmotion.nn.core.batch_norm`: momentum 0.1, eps 1e-5, unbiased
  running variance). Persons share the input BatchNorm (ActFormer's ``person_bn`` is off).
* **Persons** are folded into the batch for every layer, so in train mode batch statistics pool all persons,
  as in the reference.
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.geometry.skeletons import bones
from jaxmotion.nn.core import (
    BatchNormParams,
    BatchNormStats,
    LinearParams,
    batch_norm,
    dropout,
    init_batch_norm,
    init_linear,
    linear,
    split_key,
    torch_uniform,
)

REFERENCE_CHANNELS = (64, 64, 64, 64, 128, 128, 128, 256, 256, 256)
REFERENCE_STRIDES = (1, 1, 1, 1, 2, 1, 1, 2, 1, 1)

# ----------------------------------------------------------------------------------------------- parameters


class TemporalConvParams(NamedTuple):
    """torch ``Conv2d(C_in, C_out, (kt, 1))`` less its unit kernel axis."""

    weight: jax.Array  # [C_out, C_in, kt]
    bias: jax.Array  # [C_out]


class BlockParams(NamedTuple):
    edge_importance: jax.Array | None  # [K, V, V]; None without edge importance
    gcn: LinearParams  # [K·C_out, C_in], [K·C_out], subset-major
    tcn_bn_in: BatchNormParams  # [C_out]
    tcn_conv: TemporalConvParams  # [C_out, C_out, kt], [C_out]
    tcn_bn_out: BatchNormParams  # [C_out]
    residual_conv: LinearParams | None  # [C_out, C_in], [C_out]; only where channels or length change
    residual_bn: BatchNormParams | None  # [C_out]; with residual_conv


class BlockStats(NamedTuple):
    tcn_bn_in: BatchNormStats  # [C_out]
    tcn_bn_out: BatchNormStats  # [C_out]
    residual_bn: BatchNormStats | None  # [C_out]; with residual_conv


class STGCNParams(NamedTuple):
    data_bn: BatchNormParams  # [V, C]
    blocks: tuple[BlockParams, ...]
    fcn: LinearParams  # [classes, C_last], [classes]


class STGCNStats(NamedTuple):
    """BatchNorm running statistics, the non-trained state (Flax's ``batch_stats``)."""

    data_bn: BatchNormStats  # [V, C]
    blocks: tuple[BlockStats, ...]


# ------------------------------------------------------------------------------------------------- graph


def _hop_distances(parents: tuple[int, ...], max_hop: int) -> np.ndarray:
    """``[V, V]`` hop count between joints of the tree, ``inf`` beyond ``max_hop`` (as the reference)."""
    num_joints = len(parents)
    linked = np.eye(num_joints, dtype=bool)
    for parent, child in bones(parents):  # validates the tree
        linked[parent, child] = linked[child, parent] = True
    reached = np.eye(num_joints, dtype=bool)
    distance = np.where(reached, 0.0, np.inf)
    for hop in range(1, max_hop + 1):
        reached = (reached.astype(np.int64) @ linked.astype(np.int64)) > 0
        distance[reached & np.isinf(distance)] = hop
    return distance


def spatial_partition(parents: tuple[int, ...], center: int, max_hop: int = 1) -> np.ndarray:
    """ST-GCN's "spatial" graph for a kinematic tree: ``[K, V, V]`` with ``K = 1 + 2·max_hop``.

    ``graph[k, v, w]`` weights what joint ``w`` gathers from joint ``v`` in subset ``k``: subset 0 is the
    joint itself; then per hop ``h = 1..max_hop`` one subset of the ``h``-hop neighbours ``v`` at the same or a
    greater distance from ``center`` than ``w``, and one of those nearer to it. Every non-zero in column ``w``
    is ``1 / deg(w)``, ``deg(w)`` counting ``w`` and its neighbours within ``max_hop`` (the reference's A·D⁻¹
    normalisation), so the subsets sum to the column-normalised neighbourhood and each column sums to 1.
    Distances to the centre are truncated at ``max_hop`` as in the reference (module docstring).
    """
    if not 0 <= center < len(parents):
        raise ValueError(f"center: expected a joint index in [0, {len(parents)}), got {center}")
    if max_hop < 1:
        raise ValueError(f"max_hop: expected at least 1, got {max_hop}")
    distance = _hop_distances(parents, max_hop)
    within = np.isfinite(distance)
    normalized = within / within.sum(axis=0, keepdims=True)  # A·D⁻¹: divide column w by deg(w)
    from_centre = distance[:, center]
    source_not_nearer = from_centre[:, None] >= from_centre[None, :]  # [v, w]; inf >= inf holds
    subsets = [np.where(distance == 0, normalized, 0.0)]
    for hop in range(1, max_hop + 1):
        at_hop = np.where(distance == hop, normalized, 0.0)
        subsets += [np.where(source_not_nearer, at_hop, 0.0), np.where(source_not_nearer, 0.0, at_hop)]
    return np.stack(subsets).astype(np.float32)


def graph_aggregate(y: jax.Array, graph: jax.Array) -> jax.Array:
    """``y [N, T, V, K, C]`` (per-subset features), ``graph [K, V, W]`` -> ``[N, T, W, C]``:
    joint ``w`` sums subset ``k`` of every joint ``v`` weighted by ``graph[k, v, w]``."""
    return jnp.einsum("ntvkc,kvw->ntwc", y, graph)


def _fold_persons(x: jax.Array, num_joints: int) -> tuple[jax.Array, int]:
    """``x [B, T, V, C]`` or ``[B, M, T, V, C]`` -> ``([B·M, T, V, C], M)``, validating the shape."""
    if x.ndim not in (4, 5) or x.shape[-2] != num_joints:
        raise ValueError(f"x: expected shape [B, T, V, C] or [B, M, T, V, C] with V = {num_joints} joints, "
                         f"got {tuple(x.shape)}")
    persons = x.shape[1] if x.ndim == 5 else 1
    return x.reshape(-1, *x.shape[-3:]), persons


# ------------------------------------------------------------------------------------------ initialisation


def _check_graph(graph: np.ndarray) -> None:
    if graph.ndim != 3 or graph.shape[1] != graph.shape[2]:
        raise ValueError(f"graph: expected shape [K, V, V] (from spatial_partition), got {tuple(graph.shape)}")


def init_temporal_conv(key: jax.Array, in_features: int, out_features: int, kernel: int) -> TemporalConvParams:
    """torch ``Conv2d((kernel, 1))`` default: weight and bias U(±1/√(in_features · kernel))."""
    k_w, k_b = jax.random.split(key)
    fan_in = in_features * kernel
    return TemporalConvParams(torch_uniform(k_w, (out_features, in_features, kernel), fan_in),
                              torch_uniform(k_b, (out_features,), fan_in))


def init_stgcn_block(key: jax.Array, graph: np.ndarray, in_features: int, features: int, *, stride: int = 1,
                     temporal_kernel: int = 9, residual: bool = True,
                     edge_importance: bool = True) -> tuple[BlockParams, BlockStats]:
    """One block's parameters and statistics (PyTorch's default initialisation); ``graph [K, V, V]`` gives
    the edge-importance shape. A residual conv is made where ``residual`` needs one (channels or length
    change)."""
    _check_graph(graph)
    if temporal_kernel % 2 != 1:
        raise ValueError(f"temporal_kernel: expected an odd size, got {temporal_kernel}")
    k_gcn, k_tcn, k_res = jax.random.split(key, 3)
    bn_in, stats_in = init_batch_norm((features,))
    bn_out, stats_out = init_batch_norm((features,))
    res_conv = res_bn = res_stats = None
    if residual and (in_features != features or stride != 1):
        res_conv = init_linear(k_res, in_features, features)
        res_bn, res_stats = init_batch_norm((features,))
    params = BlockParams(
        edge_importance=jnp.ones(graph.shape, jnp.float32) if edge_importance else None,
        gcn=init_linear(k_gcn, in_features, graph.shape[0] * features),
        tcn_bn_in=bn_in,
        tcn_conv=init_temporal_conv(k_tcn, features, features, temporal_kernel),
        tcn_bn_out=bn_out,
        residual_conv=res_conv,
        residual_bn=res_bn,
    )
    return params, BlockStats(stats_in, stats_out, res_stats)


def init_stgcn(key: jax.Array, graph: np.ndarray, in_features: int, num_classes: int, *,
               channels: tuple[int, ...] = REFERENCE_CHANNELS, strides: tuple[int, ...] = REFERENCE_STRIDES,
               temporal_kernel: int = 9, edge_importance: bool = True) -> tuple[STGCNParams, STGCNStats]:
    """ST-GCN parameters and BatchNorm statistics for ``in_features`` input channels over the joints of
    ``graph [K, V, V]``; defaults are the reference architecture (module docstring)."""
    if len(channels) != len(strides) or not channels:
        raise ValueError(f"channels, strides: expected equal non-zero lengths, got {len(channels)} "
                         f"and {len(strides)}")
    _check_graph(graph)
    keys = jax.random.split(key, len(channels) + 1)
    data_bn, data_stats = init_batch_norm((graph.shape[1], in_features))
    blocks = [
        init_stgcn_block(k, graph, c_in, c_out, stride=stride, temporal_kernel=temporal_kernel, residual=i > 0,
                         edge_importance=edge_importance)
        for i, (k, c_in, c_out, stride) in enumerate(zip(keys, (in_features, *channels), channels, strides))
    ]
    params = STGCNParams(data_bn, tuple(p for p, _ in blocks), init_linear(keys[-1], channels[-1], num_classes))
    return params, STGCNStats(data_stats, tuple(s for _, s in blocks))


# ------------------------------------------------------------------------------------------------ layers


def temporal_conv(p: TemporalConvParams, x: jax.Array, stride: int = 1) -> jax.Array:
    """"Same"-padded convolution over frames, each joint apart: ``x [N, T, V, C_in]`` ->
    ``[N, ceil(T / stride), V, C_out]`` (odd kernel)."""
    pad = (p.weight.shape[-1] - 1) // 2
    y = jax.lax.conv_general_dilated(x, p.weight[..., None], window_strides=(stride, 1),
                                     padding=((pad, pad), (0, 0)), dimension_numbers=("NHWC", "OIHW", "NHWC"))
    return y + p.bias


def stgcn_block(p: BlockParams, stats: BlockStats, x: jax.Array, graph: np.ndarray, *, stride: int = 1,
                residual: bool = True, train: bool, dropout_rate: float = 0.0,
                dropout_key: jax.Array | None = None) -> tuple[jax.Array, BlockStats]:
    """One graph-conv + temporal-conv block: ``x [N, T, V, C_in]``, ``graph [K, V, V]`` (from
    :func:`spatial_partition`) -> ``([N, ceil(T / stride), V, C_out], stats)``. Dropout only with a
    ``dropout_key``; ``stride`` and ``residual`` as at :func:`init_stgcn_block`."""
    subsets, features = graph.shape[0], p.tcn_bn_in.weight.shape[0]
    if p.edge_importance is not None:
        graph = graph * p.edge_importance
    y = linear(p.gcn, x)
    y = graph_aggregate(y.reshape(*y.shape[:-1], subsets, features), graph)
    y, stats_in = batch_norm(p.tcn_bn_in, stats.tcn_bn_in, y, train=train)
    y = temporal_conv(p.tcn_conv, jax.nn.relu(y), stride)
    y, stats_out = batch_norm(p.tcn_bn_out, stats.tcn_bn_out, y, train=train)
    y = dropout(y, dropout_rate, dropout_key)
    if not residual:
        return jax.nn.relu(y), BlockStats(stats_in, stats_out, None)
    if p.residual_conv is None:
        if x.shape[-1] != features or stride != 1:
            raise ValueError(f"stride: the block has no residual conv, so needs stride 1 and C_in = C_out = "
                             f"{features}; got stride {stride}, C_in {x.shape[-1]} (strides differ from init?)")
        return jax.nn.relu(y + x), BlockStats(stats_in, stats_out, None)
    res, stats_res = batch_norm(p.residual_bn, stats.residual_bn, linear(p.residual_conv, x[:, ::stride]),
                                train=train)
    return jax.nn.relu(y + res), BlockStats(stats_in, stats_out, stats_res)


def stgcn(params: STGCNParams, stats: STGCNStats, x: jax.Array, graph: np.ndarray, *, strides: tuple[int, ...],
          train: bool, dropout_rate: float = 0.0,
          dropout_key: jax.Array | None = None) -> tuple[tuple[jax.Array, jax.Array], STGCNStats]:
    """The recogniser (module docstring): ``x [B, T, V, C]`` or ``[B, M, T, V, C]`` (``M`` persons) ->
    ``((logits [B, classes], features [B, C_last]), stats)``; features are the mean over frames, joints
    and persons.

    ``graph [K, V, V]`` and ``strides`` as at :func:`init_stgcn` (``REFERENCE_STRIDES`` for the
    reference). ``train``: BatchNorm from batch
    statistics, returning the moved running statistics, and dropout at ``dropout_rate`` when a
    ``dropout_key`` is given (one key per block); otherwise running statistics and no dropout.
    """
    if len(strides) != len(params.blocks):
        raise ValueError(f"strides: expected one per block ({len(params.blocks)}), got {len(strides)}")
    _check_graph(graph)
    x, persons = _fold_persons(x, graph.shape[1])
    x, data_stats = batch_norm(params.data_bn, stats.data_bn, x, train=train)  # per (joint, channel)
    keys = split_key(dropout_key if train else None, len(params.blocks))
    block_stats = []
    for i, (p, s, stride, key) in enumerate(zip(params.blocks, stats.blocks, strides, keys, strict=True)):
        x, s = stgcn_block(p, s, x, graph, stride=stride, residual=i > 0, train=train, dropout_rate=dropout_rate,
                           dropout_key=key)
        block_stats.append(s)
    pooled = x.mean(axis=(1, 2))  # [B·M, C]
    features = pooled.reshape(-1, persons, pooled.shape[-1]).mean(axis=1)
    return (linear(params.fcn, features), features), STGCNStats(data_stats, tuple(block_stats))
