"""Recurrent layers as pure functions over explicit parameter pytrees, unrolled with ``lax.scan``.

Gate layouts follow PyTorch's (``torch.nn.GRU`` / ``torch.nn.LSTM``), so released PyTorch weights load
without reshuffling. Per layer ``w_ih [G·H, D]``, ``w_hh [G·H, H]``, ``b_ih [G·H]``, ``b_hh [G·H]``:

* **GRU**, G = 3, row blocks (reset, update, new)::

    r = σ(W_ir x + b_ir + W_hr h + b_hr)
    z = σ(W_iz x + b_iz + W_hz h + b_hz)
    n = tanh(W_in x + b_in + r ⊙ (W_hn h + b_hn))
    h' = (1 − z) ⊙ n + z ⊙ h

* **LSTM**, G = 4, row blocks (input, forget, cell, output)::

    i, f, o = σ(W_i· x + b_i· + W_h· h + b_h·)       g = tanh(W_ig x + b_ig + W_hg h + b_hg)
    c' = f ⊙ c + i ⊙ g                                h' = o ⊙ tanh(c')

A stack runs its layers in one ``lax.scan`` step per frame (layer l reads layer l−1's new output), which
halves the loop trips of running the layers one after another and gives the same numbers. On a CPU the LSTM
stack's step is recomputed in the backward pass rather than stored (:func:`recompute_on_cpu`). The stacked
step functions (:func:`gru_stack_step`, :func:`lstm_stack_step`) serve autoregressive decoders, which feed
each output back as the next input.

Axes: T frames, B batch, D inputs, H hidden, L layers.
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


class LSTMParams(NamedTuple):
    w_ih: jax.Array  # [4H, D]
    w_hh: jax.Array  # [4H, H]
    b_ih: jax.Array  # [4H]
    b_hh: jax.Array  # [4H]


class LSTMState(NamedTuple):
    """Hidden and cell states of every layer of a stack, as ``torch.nn.LSTM``'s ``(h_n, c_n)``."""

    h: jax.Array  # [L, B, H]
    c: jax.Array  # [L, B, H]


def _init_gates(key: jax.Array, gates: int, input_dim: int, hidden: int):
    shapes = ((gates * hidden, input_dim), (gates * hidden, hidden), (gates * hidden,), (gates * hidden,))
    keys = jax.random.split(key, 4)
    return tuple(torch_uniform(k, shape, hidden) for k, shape in zip(keys, shapes, strict=True))


def init_gru(key: jax.Array, input_dim: int, hidden: int) -> GRUParams:
    """PyTorch's default GRU initialisation: all four tensors uniform in ±1/sqrt(H) (fan_in = H)."""
    return GRUParams(*_init_gates(key, 3, input_dim, hidden))


def init_lstm(key: jax.Array, input_dim: int, hidden: int) -> LSTMParams:
    """PyTorch's default LSTM initialisation: all four tensors uniform in ±1/sqrt(H) (fan_in = H)."""
    return LSTMParams(*_init_gates(key, 4, input_dim, hidden))


def init_lstm_stack(key: jax.Array, input_dim: int, hidden: int, layers: int) -> tuple[LSTMParams, ...]:
    """``layers`` LSTM layers, the first reading ``input_dim`` features, the others ``hidden``
    (``torch.nn.LSTM(input_dim, hidden, layers)``'s ``*_l0``, ``*_l1``, ...)."""
    keys = jax.random.split(key, layers)
    return tuple(init_lstm(k, input_dim if i == 0 else hidden, hidden) for i, k in enumerate(keys))


def recompute_on_cpu(step):
    """A ``lax.scan`` step whose activations, on a CPU, are recomputed in the backward pass instead of stored
    per frame (``jax.checkpoint``): there, writing and reading every frame's gates costs more than computing
    them again (measured on 2 cores: a 2 x 128 LSTM over 1 024 x 60, forward + backward, 835 -> 715 ms; an
    ODMO training step of 512 pairs 5.3 -> 2.8 s). The values are the same. Other backends keep XLA's
    default (not measured)."""
    return jax.checkpoint(step) if jax.default_backend() == "cpu" else step


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


def lstm_cell(p: LSTMParams, h: jax.Array, c: jax.Array, x: jax.Array) -> tuple[jax.Array, jax.Array]:
    """One step: ``h, c [B, H]``, ``x [B, D]`` -> ``(h', c') [B, H]``."""
    gates = x @ p.w_ih.T + p.b_ih + h @ p.w_hh.T + p.b_hh
    i, f, g, o = jnp.split(gates, 4, axis=-1)
    c = jax.nn.sigmoid(f) * c + jax.nn.sigmoid(i) * jnp.tanh(g)
    return jax.nn.sigmoid(o) * jnp.tanh(c), c


def gru_stack_step(layers: tuple[GRUParams, ...], hs: tuple[jax.Array, ...], x: jax.Array
                   ) -> tuple[tuple[jax.Array, ...], jax.Array]:
    """One frame through stacked GRU layers: ``hs`` one ``[B, H]`` per layer, ``x [B, D]`` -> (new states,
    the top layer's output ``[B, H]``)."""
    new = []
    for p, h in zip(layers, hs, strict=True):
        x = gru_cell(p, h, x)
        new.append(x)
    return tuple(new), x


def lstm_stack_step(layers: tuple[LSTMParams, ...], state: LSTMState, x: jax.Array) -> tuple[LSTMState, jax.Array]:
    """One frame through stacked LSTM layers: ``state`` ``[L, B, H]`` twice, ``x [B, D]`` -> (new state, the
    top layer's output ``[B, H]``)."""
    hs, cs = [], []
    for layer, p in enumerate(layers):
        h, c = lstm_cell(p, state.h[layer], state.c[layer], x)
        hs.append(h)
        cs.append(c)
        x = h
    return LSTMState(jnp.stack(hs), jnp.stack(cs)), x


def gru_stack(layers: tuple[GRUParams, ...], xs: jax.Array, h0: tuple[jax.Array, ...]) -> jax.Array:
    """A multi-layer GRU over time: ``xs [T, B, D]``, one ``h0 [B, H]`` per layer -> top outputs ``[T, B, H]``."""
    if len(layers) != len(h0) or not layers:
        raise ValueError(f"h0: expected one initial state per layer ({len(layers)}), got {len(h0)}")
    return jax.lax.scan(lambda hs, x: gru_stack_step(layers, hs, x), tuple(h0), xs)[1]


def lstm_zero_state(layers: tuple[LSTMParams, ...], batch: int) -> LSTMState:
    """``torch.nn.LSTM``'s default initial state: zeros ``[L, B, H]``."""
    shape = (len(layers), batch, layers[0].w_hh.shape[1])
    return LSTMState(jnp.zeros(shape, jnp.float32), jnp.zeros(shape, jnp.float32))


def lstm_stack(layers: tuple[LSTMParams, ...], xs: jax.Array, state: LSTMState | None = None
               ) -> tuple[jax.Array, LSTMState]:
    """A multi-layer LSTM over time, as ``torch.nn.LSTM(xs, (h0, c0))``: ``xs [T, B, D]``, ``state`` ``[L, B, H]``
    twice (None: zeros) -> (top outputs ``[T, B, H]``, final state ``[L, B, H]`` twice)."""
    if not layers:
        raise ValueError("layers: expected at least one LSTM layer")
    if xs.ndim != 3 or xs.shape[-1] != layers[0].w_ih.shape[1]:
        raise ValueError(f"xs: expected [T, B, {layers[0].w_ih.shape[1]}] (T, B, D), got {tuple(xs.shape)}")
    if state is None:
        state = lstm_zero_state(layers, xs.shape[1])
    expected = (len(layers), xs.shape[1], layers[0].w_hh.shape[1])
    if state.h.shape != expected or state.c.shape != expected:
        raise ValueError(f"state: expected h and c of shape {list(expected)} (L, B, H), got "
                         f"{tuple(state.h.shape)} and {tuple(state.c.shape)}")
    final, outputs = jax.lax.scan(recompute_on_cpu(lambda s, x: lstm_stack_step(layers, s, x)), state, xs)
    return outputs, final
