"""Primitives every layer of :mod:`jaxmotion.nn` and every model builds on: PyTorch's default
initialisation, ``Linear``, ``PReLU``, ``LayerNorm``, ``BatchNorm`` and dropout, as pure functions over
NamedTuple parameter pytrees.

Parameters mirror PyTorch: field names are its state-dict names (``weight``, ``bias``, ``running_mean``,
``running_var``) and shapes are its shapes (``Linear.weight`` is ``[out, in]``), so released weights load
without reshuffling. Everything is jittable; sizes, rates and modes are Python values (static under ``jit``).

Choices:

* **PReLU** is ``torch.nn.PReLU``: ``max(0, x) + a · min(0, x)`` with ``a`` learned, one value (the
  default) or one per channel, starting at 0.25. The channel axis is the last one (PyTorch's is axis 1;
  the two agree for the ``[B, C]`` inputs the models give it).
* **Initialisation** is PyTorch's default for ``Linear`` and ``Conv``: weights (``kaiming_uniform(a=√5)``)
  and biases alike U(±1/√fan_in) (:func:`torch_uniform`), with ``fan_in`` the inputs of one output
  (``in`` for a ``Linear``, ``in · kernel size`` for a conv, the hidden size for a GRU). Norms start at
  scale 1, shift 0; BatchNorm's running mean at 0 and variance at 1.
* **BatchNorm** is split into trained parameters and running statistics (:class:`BatchNormStats`), a
  separate pytree that train mode returns updated, as ``torch.nn.BatchNorm*`` with its defaults: momentum
  0.1 (``running = 0.9 · running + 0.1 · batch``), eps 1e-5, the biased batch variance for normalising
  and the unbiased one for the running estimate.
* **Dropout** masks come from :func:`dropout_bits`, a hash of the element index seeded from the key, not
  threefry (reasons there); no key means no dropout (eval mode).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import jax
import jax.numpy as jnp

# ----------------------------------------------------------------------------------------- initialisation


def torch_uniform(key: jax.Array, shape: tuple[int, ...], fan_in: int) -> jax.Array:
    """PyTorch's default ``Linear`` / ``Conv`` / ``GRU`` weight and bias init: float32 U(±1/√fan_in)."""
    bound = 1.0 / math.sqrt(fan_in)
    return jax.random.uniform(key, shape, jnp.float32, -bound, bound)


def count_parameters(params) -> int:
    """Number of scalars in a parameter tree (works on ``jax.eval_shape`` output too): pass the trained
    parameters only, not running statistics or power-iteration vectors."""
    return sum(math.prod(leaf.shape) for leaf in jax.tree.leaves(params))


# ------------------------------------------------------------------------------------------------ linear


class LinearParams(NamedTuple):
    weight: jax.Array  # [out, in]
    bias: jax.Array  # [out]


def init_linear(key: jax.Array, in_dim: int, out_dim: int) -> LinearParams:
    """torch ``nn.Linear`` default: weight ``[out_dim, in_dim]`` and bias ``[out_dim]`` U(±1/√in_dim)."""
    k_w, k_b = jax.random.split(key)
    return LinearParams(torch_uniform(k_w, (out_dim, in_dim), in_dim), torch_uniform(k_b, (out_dim,), in_dim))


def linear(p: LinearParams, x: jax.Array) -> jax.Array:
    """``x [..., in]`` -> ``[..., out]``."""
    return x @ p.weight.T + p.bias


# ------------------------------------------------------------------------------------------------ PReLU


class PReLUParams(NamedTuple):
    weight: jax.Array  # [1] or [C]: the slope of negative inputs


def init_prelu(channels: int = 1, init: float = 0.25) -> PReLUParams:
    """``torch.nn.PReLU(channels, init)``: slopes ``[channels]`` at ``init``."""
    return PReLUParams(jnp.full((channels,), init, jnp.float32))


def prelu(p: PReLUParams, x: jax.Array) -> jax.Array:
    """``x [..., C]`` (any trailing size when the slope is shared) -> same shape."""
    return jnp.where(x >= 0, x, p.weight * x)


# ----------------------------------------------------------------------------------------------- norms


class LayerNormParams(NamedTuple):
    weight: jax.Array  # [D]
    bias: jax.Array  # [D]


def init_layer_norm(dim: int) -> LayerNormParams:
    """LayerNorm over ``dim`` features: scale ones, shift zeros."""
    return LayerNormParams(jnp.ones((dim,), jnp.float32), jnp.zeros((dim,), jnp.float32))


def layer_norm(p: LayerNormParams, x: jax.Array, eps: float = 1e-5) -> jax.Array:
    """LayerNorm over the last axis (biased variance, like torch)."""
    mean = x.mean(-1, keepdims=True)
    var = jnp.square(x - mean).mean(-1, keepdims=True)
    return (x - mean) * jax.lax.rsqrt(var + eps) * p.weight + p.bias


class BatchNormParams(NamedTuple):
    weight: jax.Array  # [*F], scale
    bias: jax.Array  # [*F], shift


class BatchNormStats(NamedTuple):
    running_mean: jax.Array  # [*F]
    running_var: jax.Array  # [*F], unbiased


def init_batch_norm(features: tuple[int, ...]) -> tuple[BatchNormParams, BatchNormStats]:
    """BatchNorm over trailing feature axes of shape ``features``: scale ones, shift zeros; running mean
    zeros, running variance ones. Every leaf is its own buffer, so a train state holding both pytrees can
    be donated."""
    return (BatchNormParams(jnp.ones(features, jnp.float32), jnp.zeros(features, jnp.float32)),
            BatchNormStats(jnp.zeros(features, jnp.float32), jnp.ones(features, jnp.float32)))


def batch_norm(p: BatchNormParams, stats: BatchNormStats, x: jax.Array, *, train: bool, momentum: float = 0.1,
               eps: float = 1e-5) -> tuple[jax.Array, BatchNormStats]:
    """``x [..., *F]`` normalised per feature over all leading axes -> ``(y [..., *F], stats)``.

    ``train``: normalise with the batch's mean and biased variance and return the running statistics moved
    ``momentum`` of the way to the batch's mean and unbiased variance (torch's update); otherwise normalise
    with the running statistics and return them unchanged.
    """
    features = p.weight.shape
    if x.shape[x.ndim - len(features):] != features:
        raise ValueError(f"x: expected trailing feature axes {features}, got shape {tuple(x.shape)}")
    if not train:
        mean, var = stats.running_mean, stats.running_var
    else:
        axes = tuple(range(x.ndim - len(features)))
        count = math.prod(x.shape[: len(axes)])
        if count < 2:
            raise ValueError(f"x: train-mode BatchNorm needs more than one value per feature, got shape {x.shape}")
        mean = x.mean(axes)
        var = jnp.square(x - mean).mean(axes)
        stats = BatchNormStats((1.0 - momentum) * stats.running_mean + momentum * mean,
                               (1.0 - momentum) * stats.running_var + momentum * var * (count / (count - 1)))
    return (x - mean) * (jax.lax.rsqrt(var + eps) * p.weight) + p.bias, stats


# ---------------------------------------------------------------------------------------------- dropout


def _mix32(h: jax.Array) -> jax.Array:
    """Wellons' "lowbias32" integer finaliser: a bijection of ``uint32`` with good avalanche."""
    h = (h ^ (h >> 16)) * jnp.uint32(0x7FEB352D)
    h = (h ^ (h >> 15)) * jnp.uint32(0x846CA68B)
    return h ^ (h >> 16)


def dropout_bits(key: jax.Array, shape: tuple[int, ...]) -> jax.Array:
    """Uniform ``uint32`` bits of ``shape`` for dropout masks: two 32-bit seeds drawn from ``key``, mixed
    into a hash of each element's index.

    Why not ``jax.random.bits``: threefry costs ~30 integer rounds per element, more than all the matrix
    products of an ACTOR training step on a CPU (XLA's RngBitGenerator is no cheaper there); the two hash
    rounds are ~15x cheaper and their bits pass as independent fair coins for masking
    (``tests/test_nn_core.py``). The second seed enters after the first round, so two keys do not give
    shifted copies of one sequence. Same key, same mask.
    """
    size = math.prod(shape)
    if size >= 2**32:
        raise ValueError(f"dropout_bits: shape {shape} has more than 2**32 elements")
    seeds = jax.random.bits(key, (2,), jnp.uint32)
    index = jax.lax.iota(jnp.uint32, size).reshape(shape)
    return _mix32(_mix32(index * jnp.uint32(0x9E3779B9) + seeds[0]) ^ seeds[1])


def split_key(key: jax.Array | None, num: int) -> list[jax.Array | None]:
    """``num`` keys split from ``key``, or ``num`` Nones without one (eval mode stays eval mode)."""
    return [None] * num if key is None else list(jax.random.split(key, num))


def dropout(x: jax.Array, rate: float, key: jax.Array | None) -> jax.Array:
    """Inverted dropout (kept values scaled by ``1 / (1 − rate)``); the identity when ``key`` is None.
    A value is dropped when its :func:`dropout_bits` fall below ``rate · 2³²``."""
    if key is None or rate == 0.0:
        return x
    if not 0.0 <= rate < 1.0:
        raise ValueError(f"dropout_rate: expected in [0, 1), got {rate}")
    keep = dropout_bits(key, x.shape) >= jnp.uint32(round(rate * 2**32))
    return jnp.where(keep, x / (1.0 - rate), jnp.zeros_like(x))
