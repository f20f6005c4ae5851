"""Recognition accuracy of generated motions: confusion matrix, accuracy, mean per-class recall.

ACTOR, ODMO and Action2Motion report ``accuracy`` = trace / total of the confusion matrix; ActFormer
reports the mean per-class recall (:func:`mean_class_recall`), which equals accuracy when every class has
the same number of samples (its protocol generates 100 per class).

Axes: N samples, C classes.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

from jaxmotion.data.labels import check_actions


def confusion_matrix(labels: jax.Array, predictions: jax.Array, num_classes: int) -> jax.Array:
    """``[C, C]`` counts (int32): row = true class, column = predicted class; ``labels``, ``predictions [N]``,
    class ids in ``[0, C)`` (checked where the values are concrete: bincount would count -1 as class 0 and
    drop an id >= C)."""
    labels, predictions = jnp.asarray(labels), jnp.asarray(predictions)
    if labels.ndim != 1 or predictions.shape != labels.shape:
        raise ValueError(f"confusion_matrix: expected labels [N] and predictions [N], got "
                         f"{tuple(labels.shape)} and {tuple(predictions.shape)}")
    check_actions(labels, num_classes, where="confusion_matrix: labels")
    check_actions(predictions, num_classes, where="confusion_matrix: predictions")
    return _confusion(labels, predictions, num_classes)


@jax.jit(static_argnames="num_classes")
def _confusion(labels: jax.Array, predictions: jax.Array, num_classes: int) -> jax.Array:
    flat = labels.astype(jnp.int32) * num_classes + predictions.astype(jnp.int32)
    return jnp.bincount(flat, length=num_classes * num_classes).reshape(num_classes, num_classes)


def accuracy(confusion: jax.Array) -> jax.Array:
    """Fraction of correct predictions, ``trace / total`` of a ``[C, C]`` confusion matrix (ACTOR, ODMO)."""
    return jnp.trace(confusion) / confusion.sum()


def mean_class_recall(confusion: jax.Array) -> jax.Array:
    """Mean over classes with samples of the per-class recall (ActFormer's "Acc")."""
    support = confusion.sum(axis=1)
    recall = jnp.diagonal(confusion) / jnp.where(support > 0, support, 1)
    present = support > 0
    return jnp.where(present, recall, 0.0).sum() / present.sum()
