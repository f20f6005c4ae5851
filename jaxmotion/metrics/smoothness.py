"""Jitter of joint trajectories: the mean magnitude of their second difference (acceleration per frame²).

Used by ACTOR's denoising use case (encode-decode lowers the jitter of noisy monocular estimates) and to
calibrate the embedded UESTC noise against VIBE's published acceleration error.

Axes: N sequences, T frames, J joints.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp


@jax.jit
def mean_acceleration(joints: jax.Array, mask: jax.Array | None = None) -> jax.Array:
    """Mean over sequences, interior frames and joints of ``‖x[t+1] − 2 x[t] + x[t−1]‖``, in the input unit
    per frame²: ``joints [N, T, J, 3]``, ``mask [N, T]`` (real frames; a frame counts when it and both
    neighbours are real) -> scalar. NaN when no frame qualifies (T < 3)."""
    if joints.ndim != 4 or joints.shape[-1] != 3:
        raise ValueError(f"joints: expected [N, T, J, 3], got {tuple(joints.shape)}")
    if mask is None:
        mask = jnp.ones(joints.shape[:2], bool)
    elif mask.shape != joints.shape[:2]:
        raise ValueError(f"mask: expected [N, T] = {tuple(joints.shape[:2])}, got {tuple(mask.shape)}")
    accel = jnp.linalg.norm(joints[:, 2:] - 2.0 * joints[:, 1:-1] + joints[:, :-2], axis=-1).mean(axis=-1)
    valid = mask[:, 2:] & mask[:, 1:-1] & mask[:, :-2]
    return jnp.sum(jnp.where(valid, accel, 0.0)) / valid.sum()
