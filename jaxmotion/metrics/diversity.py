"""Diversity and multimodality of recogniser features, as Action2Motion defines them.

Action2Motion (``final_evaluation.py``; ACTOR and ODMO use the same code):

* **diversity**: draw ``pairs`` (200) first indices and ``pairs`` second indices uniformly, with
  replacement, from all N samples (an index may pair with itself), and average the Euclidean distances of
  the paired features.
* **multimodality**: for each class, ``pairs`` (20) pairs whose two members are both drawn uniformly, with
  replacement, from that class's samples; the sum of all distances is divided by ``pairs · C``. (The
  original draws a random sample, skips it if its class quota is used up, then redraws the partner until
  the labels match: the same distribution as drawing both members from the class directly, which is what
  this jittable version does.) The original loops forever when a class has no sample; here such a class
  is left out and the division uses the number of classes present.

Degenerate inputs: diversity of fewer than 2 samples is an error (every pair would be a sample with itself,
distance 0, which reads as "no diversity"); a label outside ``[0, C)`` makes multimodality NaN (a jittable
function cannot raise on values, and dropping or miscounting the sample would change the metric).

Pairs are drawn with the explicit key, so a metric value is a function of (features, labels, key).

Axes: N samples, D feature channels, C classes.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

from jaxmotion.data.labels import ids_in_range


def _check(features: jax.Array, labels: jax.Array | None = None) -> None:
    if features.ndim != 2:
        raise ValueError(f"features: expected [N, D], got shape {tuple(features.shape)}")
    if labels is not None and (labels.shape != features.shape[:1] or not jnp.issubdtype(labels.dtype, jnp.integer)):
        raise ValueError(f"labels: expected integer [N] = ({features.shape[0]},), got {labels.dtype} "
                         f"{tuple(labels.shape)}")


@jax.jit(static_argnames="pairs")
def diversity(key: jax.Array, features: jax.Array, pairs: int = 200) -> jax.Array:
    """Mean distance between ``pairs`` random pairs of rows of ``features [N, D]`` (N >= 2) -> scalar."""
    _check(features)
    if features.shape[0] < 2:
        raise ValueError(f"features: diversity needs at least 2 samples, got N = {features.shape[0]}")
    k_first, k_second = jax.random.split(key)
    n = features.shape[0]
    first = jax.random.randint(k_first, (pairs,), 0, n)
    second = jax.random.randint(k_second, (pairs,), 0, n)
    return jnp.linalg.norm(features[first] - features[second], axis=-1).mean()


@jax.jit(static_argnames=("num_classes", "pairs"))
def multimodality(key: jax.Array, features: jax.Array, labels: jax.Array, num_classes: int,
                  pairs: int = 20) -> jax.Array:
    """Mean distance between ``pairs`` random same-class pairs per class: ``features [N, D]``, ``labels [N]``
    in ``[0, num_classes)`` (NaN when one is not)."""
    _check(features, labels)

    def class_sum(k, c):
        members = labels == c
        logits = jnp.where(members, 0.0, -jnp.inf)
        first, second = jax.random.categorical(k, logits, shape=(2, pairs))
        return jnp.linalg.norm(features[first] - features[second], axis=-1).sum(), members.any()

    sums, present = jax.vmap(class_sum)(jax.random.split(key, num_classes), jnp.arange(num_classes))
    return jnp.where(ids_in_range(labels, num_classes), jnp.where(present, sums, 0.0).sum() / (pairs * present.sum()), jnp.nan)
