"""Agreement between two partitions: the adjusted Rand index (Hubert & Arabie 1985), used to score the modes
a model discovers against the embedded data's ground-truth style modes (no paper could: their datasets
have no mode labels).

``ARI = (Σ_ij C(n_ij, 2) − E) / (½ (Σ_i C(a_i, 2) + Σ_j C(b_j, 2)) − E)`` with ``E = Σ_i C(a_i, 2) Σ_j C(b_j, 2)
/ C(n, 2)``, from the contingency table ``n_ij`` of the two labelings (row sums ``a_i``, column sums
``b_j``): 1 for identical partitions (up to renaming), about 0 for independent ones, negative when worse
than chance. As scikit-learn's ``adjusted_rand_score``, a degenerate table (both labelings one cluster, or
both all singletons: the denominator is 0) scores 1.

Masked samples (``mask`` False) take no part; labels outside their range make the result NaN (a jittable
function cannot raise on values). Axes: N samples, K and L label counts.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp


def _pairs(n: jax.Array) -> jax.Array:
    return n * (n - 1.0) / 2.0


@jax.jit(static_argnames=("num_true", "num_pred"))
def adjusted_rand_index(labels_true: jax.Array, labels_pred: jax.Array, num_true: int, num_pred: int,
                        mask: jax.Array | None = None) -> jax.Array:
    """ARI of ``labels_pred [N]`` (in ``[0, num_pred)``) against ``labels_true [N]`` (in ``[0, num_true)``) ->
    scalar; ``mask [N]`` bool selects the samples (default all)."""
    labels_true, labels_pred = jnp.asarray(labels_true), jnp.asarray(labels_pred)
    if labels_true.ndim != 1 or labels_pred.shape != labels_true.shape:
        raise ValueError(f"labels_true, labels_pred: expected two [N] arrays, got {labels_true.shape} and "
                         f"{labels_pred.shape}")
    mask = jnp.ones(labels_true.shape, bool) if mask is None else jnp.asarray(mask, bool)
    w = mask.astype(jnp.float32)
    table = jnp.einsum("n,nk,nl->kl", w, jax.nn.one_hot(labels_true, num_true), jax.nn.one_hot(labels_pred, num_pred))
    index = _pairs(table).sum()
    rows, cols = _pairs(table.sum(1)).sum(), _pairs(table.sum(0)).sum()
    expected = rows * cols / jnp.maximum(_pairs(w.sum()), 1.0)
    denominator = 0.5 * (rows + cols) - expected
    ari = jnp.where(denominator == 0, 1.0, (index - expected) / jnp.where(denominator == 0, 1.0, denominator))
    valid = jnp.all(~mask | ((labels_true >= 0) & (labels_true < num_true) & (labels_pred >= 0)
                             & (labels_pred < num_pred)))
    return jnp.where(valid, ari, jnp.nan)
