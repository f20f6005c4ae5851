"""Action recognisers used as evaluators.

**Action2Motion's GRU classifier** (Guo et al. 2020, ``MotionDiscriminator``; the weights in
``shared/a2m/`` are the released ones ACTOR and ODMO evaluated with): a 2-layer GRU (hidden 128) reads the
motion frame by frame, the top layer's output at the last real frame goes through ``linear1`` (128 -> 30)
and ``tanh`` to give the 30-d feature used by FID, diversity and multimodality, and ``linear2`` (30 -> C)
gives the class logits. Input: joints flattened per frame, ``[B, T, J·3]`` (joint-major), in the dataset's
own frame (HumanAct12: y down, root of frame 0 at the origin).

The original starts the GRU from a random normal hidden state on every call, which makes its features
random; here the start is zero by default (deterministic; the reference outputs in ``shared/a2m`` were made
that way), and the random start is available by passing a key.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.nn.recurrent import GRUParams, gru_layer


class A2MRecognizerParams(NamedTuple):
    layers: tuple[GRUParams, ...]
    linear1: tuple[jax.Array, jax.Array]  # weight [30, H], bias [30]
    linear2: tuple[jax.Array, jax.Array]  # weight [C, 30], bias [C]


def load_a2m_params(npz_path: str | Path) -> A2MRecognizerParams:
    """Read Action2Motion classifier weights saved as PyTorch state-dict names in an ``.npz``."""
    path = Path(npz_path)
    if not path.is_file():
        raise FileNotFoundError(f"Action2Motion recogniser weights not found: {path}")
    with np.load(path) as data:
        arrays = {k: jnp.asarray(data[k], jnp.float32) for k in data.files}

    def take(name: str) -> jax.Array:
        if name not in arrays:
            raise ValueError(f"{path}: missing array {name!r} (found: {sorted(arrays)})")
        return arrays[name]

    num_layers = sum(1 for k in arrays if k.startswith("recurrent.weight_ih_l"))
    if num_layers == 0:
        raise ValueError(f"{path}: no GRU weights 'recurrent.weight_ih_l0' (found: {sorted(arrays)})")
    layers = tuple(
        GRUParams(*(take(f"recurrent.{n}_l{i}") for n in ("weight_ih", "weight_hh", "bias_ih", "bias_hh")))
        for i in range(num_layers)
    )
    hidden = layers[0].w_hh.shape[1]
    for i, layer in enumerate(layers):
        expected_in = layers[i - 1].w_hh.shape[1] if i else layer.w_ih.shape[1]
        if layer.w_ih.shape != (3 * hidden, expected_in) or layer.w_hh.shape != (3 * hidden, hidden):
            raise ValueError(f"{path}: GRU layer {i} has weight_ih {layer.w_ih.shape}, weight_hh {layer.w_hh.shape}; "
                             f"expected [{3 * hidden}, {expected_in}] and [{3 * hidden}, {hidden}]")
    return A2MRecognizerParams(layers, (take("linear1.weight"), take("linear1.bias")),
                               (take("linear2.weight"), take("linear2.bias")))


def a2m_recognize(params: A2MRecognizerParams, motions: jax.Array, lengths: jax.Array | None = None,
                  key: jax.Array | None = None) -> tuple[jax.Array, jax.Array]:
    """``motions [B, T, F]`` -> ``(logits [B, C], features [B, 30])``.

    ``lengths [B]``: read each sequence at its last real frame (default: frame T - 1). ``key``: start from
    a standard-normal hidden state drawn from it, as the original code does (default: zeros).
    """
    in_dim = params.layers[0].w_ih.shape[1]
    if motions.ndim != 3 or motions.shape[-1] != in_dim:
        raise ValueError(f"motions: expected shape [B, T, {in_dim}], got {tuple(motions.shape)}")
    batch, frames = motions.shape[:2]
    hidden = params.layers[0].w_hh.shape[1]
    if key is None:
        starts = [jnp.zeros((batch, hidden), motions.dtype)] * len(params.layers)
    else:
        starts = list(jax.random.normal(key, (len(params.layers), batch, hidden), motions.dtype))
    xs = jnp.swapaxes(motions, 0, 1)  # [T, B, F]
    for layer, h0 in zip(params.layers, starts, strict=True):
        xs = gru_layer(layer, xs, h0)
    last = jnp.full((batch,), frames - 1) if lengths is None else jnp.asarray(lengths) - 1
    top = xs[last, jnp.arange(batch)]  # [B, H]
    features = jnp.tanh(top @ params.linear1[0].T + params.linear1[1])
    return features @ params.linear2[0].T + params.linear2[1], features


def load_a2m_recognizer(npz_path: str | Path) -> Callable[..., tuple[jax.Array, jax.Array]]:
    """The released recogniser as a jitted callable ``(motions [B, T, F], lengths=None, key=None) ->
    (logits [B, C], features [B, 30])``."""
    params = load_a2m_params(npz_path)
    apply = jax.jit(a2m_recognize)

    def recognize(motions, lengths=None, key=None):
        return apply(params, jnp.asarray(motions, jnp.float32), lengths, key)

    return recognize
