"""ActFormer's Gaussian-process latent prior: a smooth random sequence per latent channel.

ActFormer's generator reads a latent *sequence* ``[T, Z]`` instead of one code: each channel ``c`` is an
independent zero-mean Gaussian process over the time steps with the squared-exponential kernel
``K_c(i, j) = exp(-(|i - j| / l_c)^2)`` (no factor 2), and the length-scales grow linearly over the channels,
``l_c = max_scale * (c + 1) / Z`` (the code: Z = 120 channels, max_scale 100, T = 60 steps). Slow channels are
nearly constant over a clip, fast ones vary within it, so the sequence carries both a clip-wide identity and
its timing. The same sequence drives every person of a multi-person clip (a separate one per person is an
ablation).

Sampling: for T = 60 and l_c up to 100 the kernels are numerically singular (eigenvalues down to 1e-17 and
below zero in floating point), so a Cholesky factor does not exist. The authors draw with numpy's
``multivariate_normal``, which factors through an SVD; here the factor is the symmetric eigendecomposition
``K = U diag(lambda) U^T`` with the negative round-off eigenvalues set to 0, ``F = U diag(sqrt(lambda))``, and a
sample is ``F @ n`` with ``n ~ N(0, I)``: the same distribution, computed once in float64 per (T, scales) and
applied in float32 under ``jit``. Keys are explicit; a Gaussian (white) prior, the ablation, is the identity
factor.

Axes: B batch, T time steps, Z latent channels.
"""

from __future__ import annotations

import functools

import jax
import jax.numpy as jnp
import numpy as np

#: ActFormer's latent channels, time steps and largest length-scale (steps).
CHANNELS, STEPS, MAX_SCALE = 120, 60, 100.0


def length_scales(channels: int = CHANNELS, max_scale: float = MAX_SCALE) -> np.ndarray:
    """``[Z]`` ActFormer's per-channel length-scales (time steps): ``max_scale * (c + 1) / channels``."""
    if channels < 1 or max_scale <= 0:
        raise ValueError(f"length_scales: channels must be >= 1 and max_scale > 0, got {channels}, {max_scale}")
    return max_scale * np.arange(1, channels + 1, dtype=np.float64) / channels


def rbf_kernel(steps: int, scales: np.ndarray) -> np.ndarray:
    """``[Z, T, T]`` the kernels ``exp(-(|i - j| / l_z)^2)`` for the length-scales ``scales [Z]``, float64."""
    scales = np.asarray(scales, np.float64)
    if scales.ndim != 1 or np.any(scales <= 0):
        raise ValueError(f"scales: expected a [Z] array of positive length-scales, got shape {scales.shape}")
    lag = np.abs(np.arange(steps)[:, None] - np.arange(steps)[None, :])
    return np.exp(-(lag[None] / scales[:, None, None]) ** 2)


@functools.lru_cache(maxsize=16)
def _factors(steps: int, scales: tuple[float, ...]) -> np.ndarray:
    values, vectors = np.linalg.eigh(rbf_kernel(steps, np.array(scales)))
    return (vectors * np.sqrt(np.clip(values, 0.0, None))[:, None, :]).astype(np.float32)


def gp_factors(steps: int = STEPS, scales: np.ndarray | None = None) -> np.ndarray:
    """``[Z, T, T]`` float32 factors ``F_z`` with ``F_z F_z^T = K_z`` (to float32 rounding), for
    :func:`sample_gp`; ``scales`` default :func:`length_scales`. Cached per (steps, scales)."""
    scales = length_scales() if scales is None else np.asarray(scales, np.float64)
    return _factors(int(steps), tuple(float(s) for s in scales))


def white_factors(steps: int = STEPS, channels: int = CHANNELS) -> np.ndarray:
    """``[Z, T, T]`` identity factors: the Gaussian prior (independent steps), the "w/o GP" ablation."""
    return np.broadcast_to(np.eye(steps, dtype=np.float32), (channels, steps, steps)).copy()


def sample_gp(key: jax.Array, factors: jax.Array, batch: int) -> jax.Array:
    """``batch`` latent sequences ``[B, T, Z]`` from the factors ``[Z, T, T]`` (:func:`gp_factors`)."""
    if factors.ndim != 3 or factors.shape[1] != factors.shape[2]:
        raise ValueError(f"factors: expected [Z, T, T] (from gp_factors), got {tuple(factors.shape)}")
    channels, steps = factors.shape[0], factors.shape[1]
    noise = jax.random.normal(key, (batch, channels, steps), jnp.float32)
    return jnp.einsum("zts,bzs->btz", jnp.asarray(factors), noise, precision=jax.lax.Precision.HIGHEST)
