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


def gru_layer(p: GRUParams, xs: jax.Array, h0: jax.Array) -> jax.Array:
    """Run a GRU over time: ``xs [T, B, D]``, ``h0 [B, H]`` -> outputs ``[T, B, H]``."""

    def step(h, x):
        h = gru_cell(p, h, x)
        return h, h

    return jax.lax.scan(step, h0, xs)[1]
