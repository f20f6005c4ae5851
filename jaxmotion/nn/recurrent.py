"""Recurrent layers as pure functions over explicit parameter pytrees, unrolled with ``lax.scan``.

Gate layouts follow PyTorch's, so released PyTorch weights load without reshuffling:
``w_ih [3H, D]``, ``w_hh [3H, H]``, ``b_ih [3H]``, ``b_hh [3H]`` with row blocks (reset, update, new), and

    r = σ(W_ir x + b_ir + W_hr h + b_hr)
    z = σ(W_iz x + b_iz + W_hz h + b_hz)
    n = tanh(W_in x + b_in + r ⊙ (W_hn h + b_hn))
    h' = (1 − z) ⊙ n + z ⊙ h
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp

from jaxmotion.nn.core import torch_uniform


class GRUParams(NamedTuple):
    w_ih: jax.Array  # [3H, D]
    w_hh: jax.Array  # [3H, H]
    b_ih: jax.Array  # [3H]
    b_hh: jax.Array  # [3H]


def gru_cell(p: GRUParams, h: jax.Array, x: jax.Array) -> jax.Array:
    """One step: ``h [B, H]``, ``x [B, D]`` -> ``h' [B, H]``."""
    gi = x @ p.w_ih.T + p.b_ih
    gh = h @ p.w_hh.T + p.b_hh
    i_r, i_z, i_n = jnp.split(gi, 3, axis=-1)
    h_r, h_z, h_n = jnp.split(gh, 3, axis=-1)
    r = jax.nn.sigmoid(i_r + h_r)
    z = jax.nn.sigmoid(i_z + h_z)
    n = jnp.tanh(i_n + r * h_n)
    return (1.0 - z) * n + z * h


def init_gru(key: jax.Array, input_dim: int, hidden: int) -> GRUParams:
    """PyTorch's default GRU initialisation: all four tensors uniform in ±1/sqrt(H) (fan_in = H)."""
    shapes = ((3 * hidden, input_dim), (3 * hidden, hidden), (3 * hidden,), (3 * hidden,))
    keys = jax.random.split(key, 4)
    return GRUParams(*(torch_uniform(k, shape, hidden) for k, shape in zip(keys, shapes, strict=True)))


def gru_stack(layers: tuple[GRUParams, ...], xs: jax.Array, h0: tuple[jax.Array, ...]) -> jax.Array:
    """A multi-layer GRU over time: ``xs [T, B, D]``, one ``h0 [B, H]`` per layer -> top outputs ``[T, B, H]``.

    All layers advance in one ``lax.scan`` step per frame (layer l reads layer l-1's new state), which
    halves the loop trips of running the layers one after another; the result is the same.
    """
    if len(layers) != len(h0) or not layers:
        raise ValueError(f"h0: expected one initial state per layer ({len(layers)}), got {len(h0)}")

    def step(hs, x):
        new = []
        for p, h in zip(layers, hs, strict=True):
            x = gru_cell(p, h, x)
            new.append(x)
        return tuple(new), x

    return jax.lax.scan(step, tuple(h0), xs)[1]
