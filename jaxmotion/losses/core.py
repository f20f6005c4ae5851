"""Loss kernels every generator's loss shares: masked mean squared errors and the Gaussian KL.

Axes: B batch, T frames, d latent size.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp


def masked_mse(prediction: jax.Array, target: jax.Array, mask: jax.Array) -> jax.Array:
    """Mean squared error over the real frames: ``[B, T, ...]`` twice and ``mask [B, T]`` -> scalar."""
    if prediction.shape != target.shape or mask.shape != prediction.shape[:2]:
        raise ValueError(f"masked_mse: expected prediction and target of one shape [B, T, ...] and mask [B, T], "
                         f"got {tuple(prediction.shape)}, {tuple(target.shape)}, {tuple(mask.shape)}")
    squared = ((prediction - target) ** 2).reshape(*mask.shape, -1)
    per_frame = squared.shape[-1]
    return jnp.sum(squared * mask[..., None]) / (jnp.maximum(mask.sum(), 1) * per_frame)


def masked_velocity_mse(prediction: jax.Array, target: jax.Array, mask: jax.Array) -> jax.Array:
    """:func:`masked_mse` of the frame-to-frame differences, over the pairs of consecutive real frames."""
    pairs = mask[:, 1:] & mask[:, :-1]
    return masked_mse(jnp.diff(prediction, axis=1), jnp.diff(target, axis=1), pairs)


def kl_to_standard_normal(mu: jax.Array, logvar: jax.Array) -> jax.Array:
    """``KL(N(mu, exp(logvar)) || N(0, I))`` summed over batch and dimensions: ``[B, d]`` twice -> scalar."""
    return -0.5 * jnp.sum(1.0 + logvar - mu**2 - jnp.exp(logvar))
