"""Spectral normalisation (Miyato et al. 2018) as ``torch.nn.utils.spectral_norm`` computes it.

A weight ``W`` (any shape; viewed as ``[out, rest]`` with its first axis as rows, as PyTorch's ``dim=0``) is
divided by an estimate of its largest singular value, ``sigma = u^T W v``, where ``u [out]`` and ``v [rest]``
are running power-iteration vectors. In training, each call first runs one power iteration from the stored
vectors, ``v = normalise(W^T u)``, ``u = normalise(W v)`` (``normalise(x) = x / max(|x|, eps)``, no gradient
through them), and returns the moved vectors for the caller to keep in its train state; in evaluation the stored
vectors are used as they are. Gradients flow through ``W`` in ``sigma``. A 1-D weight (a LayerNorm gain, as
ActFormer normalises its generator's last norm) is a ``[D, 1]`` matrix, so it is divided by its Euclidean
norm. Start vectors: normal draws, normalised (PyTorch's ``u`` and ``v`` buffers), from an explicit key.
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp

#: PyTorch's default eps of the normalisation.
EPS = 1e-12
_HIGHEST = jax.lax.Precision.HIGHEST


class SpectralState(NamedTuple):
    """The power-iteration vectors of one weight: ``u [out]``, ``v [rest]`` (not trained)."""

    u: jax.Array
    v: jax.Array


def _matrix(weight: jax.Array) -> jax.Array:
    return weight.reshape(weight.shape[0], -1)


def _normalise(x: jax.Array, eps: float) -> jax.Array:
    return x / jnp.maximum(jnp.linalg.norm(x), eps)


def init_spectral_state(key: jax.Array, weight: jax.Array, eps: float = EPS) -> SpectralState:
    """Start vectors for ``weight``: ``u`` and ``v`` drawn normal and normalised."""
    rows, cols = _matrix(weight).shape
    k_u, k_v = jax.random.split(key)
    return SpectralState(_normalise(jax.random.normal(k_u, (rows,), jnp.float32), eps),
                         _normalise(jax.random.normal(k_v, (cols,), jnp.float32), eps))


def spectral_normalize(weight: jax.Array, state: SpectralState, *, train: bool,
                       eps: float = EPS) -> tuple[jax.Array, SpectralState]:
    """``(weight / sigma, state)``: one power iteration first when ``train`` (the returned state moved),
    otherwise the stored vectors (the state returned unchanged)."""
    w = _matrix(weight)
    if state.u.shape != w.shape[:1] or state.v.shape != w.shape[1:]:
        raise ValueError(f"state: expected u [{w.shape[0]}] and v [{w.shape[1]}] for a weight of shape "
                         f"{tuple(weight.shape)}, got {tuple(state.u.shape)} and {tuple(state.v.shape)}")
    u, v = state
    if train:
        w_const = jax.lax.stop_gradient(w)
        v = _normalise(jnp.dot(w_const.T, u, precision=_HIGHEST), eps)
        u = _normalise(jnp.dot(w_const, v, precision=_HIGHEST), eps)
        state = SpectralState(u, v)
    sigma = jnp.dot(u, jnp.dot(w, v, precision=_HIGHEST), precision=_HIGHEST)
    return weight / sigma, state
