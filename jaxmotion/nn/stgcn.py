"""ST-GCN, the spatial-temporal graph convolutional action recogniser (Yan et al. 2018).

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

Inputs are ``[B, T, V, C]`` or ``[B, M, T, V, C]``; ACTOR's ``batch["x"]`` ``(B, V, C, T)`` is
``x.transpose(0, 3, 1, 2)`` and ActFormer's ``(N, C, T, V, M)`` is ``x.transpose(0, 4, 2, 3, 1)``.

Layout: channels last, ``[N, T, V, C]`` (``N`` = batch × persons), so the 1×1 convolutions are plain
matrix products over the last axis and the temporal convolution is an ordinary NHWC conv, the layouts
XLA's CPU backend is fastest with. Parameter shapes map one-to-one onto the reference state dict: the
graph conv kernel ``[C_in, K·C_out]`` is ordered subset-major like the reference's ``view(n, K, C, t, v)``,
``data_bn`` is ``[V, C]`` for the reference's ``V·C`` channels (joint-major).

Choices where the reference is ambiguous or differs between the two codebases:

* **Spatial partition with truncated distances.** The reference measures each joint's distance to the
  centre with the same hop matrix it builds for the neighbourhood, which stops at ``max_hop``; joints
  farther than that are all "infinitely" far and compare equal. So only edges with an end within ``max_hop``
  of the centre are split by direction; every deeper edge falls, both ways, in the "same or farther"
  subset (on SMPL with ``max_hop = 1``: just the six edges 0-1, 0-2, 0-3, 1-4, 2-5, 3-6 are split). Reproduced as is, because evaluator weights trained on that graph expect it.
* **Dropout in every block.** ACTOR strips the dropout argument from block 1, ActFormer passes it to all
  blocks; ActFormer is followed (ACTOR uses no dropout, so nothing changes for it).
* **Initialisation** is PyTorch's default (weights and biases uniform in ±1/√fan_in, BN scale 1, shift 0),
  which is what ACTOR trains from. ActFormer's trainer re-initialises (conv weights N(0, 0.02), zero biases,
  BN scales N(1, 0.02)); that belongs to a trainer, not to this module.
* **BatchNorm** uses PyTorch's momentum 0.1 (flax ``momentum=0.9``) and eps 1e-5. Flax updates the running
  variance with the biased batch variance where PyTorch uses the unbiased one; over N·T·V values per channel
  the difference is negligible. Persons share the input BatchNorm (ActFormer's ``person_bn`` is off).
* **Persons** are folded into the batch for every layer, so in train mode batch statistics pool all persons,
  as in the reference.
"""

from __future__ import annotations

import functools
import math

import flax.linen as nn
import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.geometry.skeletons import bones

# PyTorch's BatchNorm defaults: running = 0.9 · running + 0.1 · batch, eps 1e-5.
_BatchNorm = functools.partial(nn.BatchNorm, momentum=0.9, epsilon=1e-5)
# PyTorch's default conv/linear weight init, kaiming_uniform(a=√5), is uniform in ±1/√fan_in.
_torch_kernel_init = nn.initializers.variance_scaling(1.0 / 3.0, "fan_in", "uniform")


def _torch_bias_init(fan_in: int) -> nn.initializers.Initializer:
    """PyTorch's default bias init: uniform in ±1/√fan_in of the layer's weight."""
    bound = 1.0 / math.sqrt(fan_in)

    def init(key, shape, dtype=jnp.float32):
        return jax.random.uniform(key, shape, dtype, -bound, bound)

    return init


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


class STGCNBlock(nn.Module):
    """One graph-conv + temporal-conv block: ``x [N, T, V, C_in]``, ``graph [K, V, V]`` (from
    :func:`spatial_partition`) -> ``[N, ceil(T / stride), V, features]``."""

    features: int
    stride: int = 1
    temporal_kernel: int = 9
    residual: bool = True
    dropout: float = 0.0
    edge_importance: bool = True

    @nn.compact
    def __call__(self, x: jax.Array, graph: np.ndarray, *, train: bool) -> jax.Array:
        subsets = graph.shape[0]
        in_features = x.shape[-1]
        if self.edge_importance:
            graph = graph * self.param("edge_importance", nn.initializers.ones, graph.shape)
        y = nn.Dense(subsets * self.features, kernel_init=_torch_kernel_init,
                     bias_init=_torch_bias_init(in_features), name="gcn")(x)
        y = graph_aggregate(y.reshape(*y.shape[:-1], subsets, self.features), graph)

        pad = (self.temporal_kernel - 1) // 2
        y = nn.relu(_BatchNorm(use_running_average=not train, name="tcn_bn_in")(y))
        y = nn.Conv(self.features, (self.temporal_kernel, 1), strides=(self.stride, 1),
                    padding=((pad, pad), (0, 0)), kernel_init=_torch_kernel_init,
                    bias_init=_torch_bias_init(self.features * self.temporal_kernel), name="tcn_conv")(y)
        y = _BatchNorm(use_running_average=not train, name="tcn_bn_out")(y)
        y = nn.Dropout(self.dropout, deterministic=not train)(y)

        if not self.residual:
            return nn.relu(y)
        if in_features == self.features and self.stride == 1:
            return nn.relu(y + x)
        res = nn.Conv(self.features, (1, 1), strides=(self.stride, 1), kernel_init=_torch_kernel_init,
                      bias_init=_torch_bias_init(in_features), name="residual_conv")(x)
        res = _BatchNorm(use_running_average=not train, name="residual_bn")(res)
        return nn.relu(y + res)


class STGCN(nn.Module):
    """ST-GCN recogniser (module docstring). Defaults are the reference architecture.

    Call ``apply(variables, x, train=...)``; in train mode pass ``mutable=["batch_stats"]`` and, when
    ``dropout > 0``, an rng named ``"dropout"``.
    """

    num_classes: int
    parents: tuple[int, ...]
    center: int
    channels: tuple[int, ...] = (64, 64, 64, 64, 128, 128, 128, 256, 256, 256)
    strides: tuple[int, ...] = (1, 1, 1, 1, 2, 1, 1, 2, 1, 1)
    temporal_kernel: int = 9
    dropout: float = 0.0
    edge_importance: bool = True

    @nn.compact
    def __call__(self, x: jax.Array, *, train: bool) -> tuple[jax.Array, jax.Array]:
        """``x [B, T, V, C]`` or ``[B, M, T, V, C]`` (``M`` persons) -> ``(logits [B, num_classes],
        features [B, channels[-1]])``; features are the mean over frames, joints and persons."""
        if len(self.channels) != len(self.strides) or not self.channels:
            raise ValueError(f"channels, strides: expected equal non-zero lengths, got {len(self.channels)} "
                             f"and {len(self.strides)}")
        if self.temporal_kernel % 2 != 1:
            raise ValueError(f"temporal_kernel: expected an odd size, got {self.temporal_kernel}")
        x, persons = _fold_persons(x, len(self.parents))
        graph = spatial_partition(self.parents, self.center)
        x = _BatchNorm(use_running_average=not train, axis=(-2, -1), name="data_bn")(x)  # per (joint, channel)
        for i, (features, stride) in enumerate(zip(self.channels, self.strides, strict=True)):
            x = STGCNBlock(features, stride, self.temporal_kernel, residual=i > 0, dropout=self.dropout,
                           edge_importance=self.edge_importance, name=f"block{i}")(x, graph, train=train)
        pooled = x.mean(axis=(1, 2))  # [B·M, C]
        features = pooled.reshape(-1, persons, pooled.shape[-1]).mean(axis=1)
        logits = nn.Dense(self.num_classes, kernel_init=_torch_kernel_init,
                          bias_init=_torch_bias_init(pooled.shape[-1]), name="fcn")(features)
        return logits, features
