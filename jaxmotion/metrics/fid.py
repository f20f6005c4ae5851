"""Fréchet distance between feature sets (FID and the papers' variants).

``FID(a, b) = ‖μ_a − μ_b‖² + Tr(Σ_a + Σ_b − 2 (Σ_a Σ_b)^½)`` with the unbiased covariances (``np.cov``,
N − 1) of the recogniser features, as Action2Motion's ``fid.py`` computes it. Action2Motion takes the
matrix square root with ``scipy.linalg.sqrtm`` (Schur form, can return small imaginary parts that are then
dropped); here only its trace is needed, and ``Tr (Σ_a Σ_b)^½ = Σ_i √λ_i(S Σ_b S)`` with ``S = Σ_a^½``:
the eigenvalues of ``Σ_a Σ_b`` equal those of the symmetric positive semi-definite ``S Σ_b S``, so two
symmetric eigendecompositions give the trace exactly, with no complex arithmetic, and rounding below zero
is clipped instead of turning into NaN.

Variants (ActFormer, ODMO, ACTOR): ``FID_w`` = the whole generated set against the whole real set (the
plain :func:`fid`), ``FID_m`` = the mean over classes of the per-class FID (:func:`fid_per_class`),
``FID_tr`` / ``FID_test`` = against features of the training / test split (the protocol picks the
sets), ``FID_a`` = multi-person features reduced by a channel-wise max over persons before the FID
(:func:`aggregate_persons`).

Axes: N, M samples; D feature channels; C classes; P persons.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

from jaxmotion.data.labels import ids_in_range

_HIGHEST = jax.lax.Precision.HIGHEST


def _check_features(name: str, x: jax.Array) -> None:
    if x.ndim != 2:
        raise ValueError(f"{name}: expected features [N, D], got shape {tuple(x.shape)}")


def gaussian_stats(features: jax.Array, weights: jax.Array | None = None) -> tuple[jax.Array, jax.Array]:
    """Mean ``[D]`` and unbiased covariance ``[D, D]`` of ``features [N, D]``.

    ``weights [N]`` (0/1) selects a subset without changing shapes (per-class statistics under jit);
    the covariance divides by (count − 1), like ``np.cov``, so fewer than two selected rows give NaN.
    """
    _check_features("features", features)
    x = features.astype(jnp.float32)
    w = jnp.ones(x.shape[:1], x.dtype) if weights is None else weights.astype(x.dtype)
    if w.shape != x.shape[:1]:
        raise ValueError(f"weights: expected shape [N] = ({x.shape[0]},), got {tuple(w.shape)}")
    count = w.sum()
    mu = (w @ x) / count
    centred = (x - mu) * w[:, None]
    sigma = jnp.matmul(centred.T, centred, precision=_HIGHEST) / (count - 1.0)
    return mu, sigma


def _sqrt_psd(sigma: jax.Array) -> jax.Array:
    """Symmetric square root of a positive semi-definite ``[D, D]`` matrix."""
    vals, vecs = jnp.linalg.eigh(sigma)
    return jnp.matmul(vecs * jnp.sqrt(jnp.clip(vals, 0.0)), vecs.T, precision=_HIGHEST)


def frechet_distance(mu_a: jax.Array, sigma_a: jax.Array, mu_b: jax.Array, sigma_b: jax.Array) -> jax.Array:
    """Fréchet distance between N(μ_a, Σ_a) and N(μ_b, Σ_b): ``μ [D]``, ``Σ [D, D]`` -> scalar."""
    for name, mu, sigma in (("a", mu_a, sigma_a), ("b", mu_b, sigma_b)):
        if mu.ndim != 1 or sigma.shape != (mu.shape[0], mu.shape[0]):
            raise ValueError(f"frechet_distance: expected mu_{name} [D] and sigma_{name} [D, D], got "
                             f"{tuple(mu.shape)} and {tuple(sigma.shape)}")
    if mu_a.shape != mu_b.shape:
        raise ValueError(f"frechet_distance: feature sizes differ, {mu_a.shape[0]} vs {mu_b.shape[0]}")
    root_a = _sqrt_psd(sigma_a)
    inner = jnp.matmul(jnp.matmul(root_a, sigma_b, precision=_HIGHEST), root_a, precision=_HIGHEST)
    inner = 0.5 * (inner + inner.T)  # exact symmetry for eigh
    trace_sqrt = jnp.sqrt(jnp.clip(jnp.linalg.eigvalsh(inner), 0.0)).sum()
    diff = mu_a - mu_b
    return diff @ diff + jnp.trace(sigma_a) + jnp.trace(sigma_b) - 2.0 * trace_sqrt


@jax.jit
def fid(features_a: jax.Array, features_b: jax.Array) -> jax.Array:
    """FID between two feature sets ``[N, D]`` and ``[M, D]`` -> scalar (also FID_w, FID_tr, FID_test)."""
    _check_features("features_a", features_a)
    _check_features("features_b", features_b)
    if features_a.shape[1] != features_b.shape[1]:
        raise ValueError(f"fid: features_a has D = {features_a.shape[1]} channels, features_b "
                         f"{features_b.shape[1]}")
    return frechet_distance(*gaussian_stats(features_a), *gaussian_stats(features_b))


def _per_class(features_a, labels_a, features_b, labels_b, num_classes):
    def one(c):
        stats_a = gaussian_stats(features_a, labels_a == c)
        stats_b = gaussian_stats(features_b, labels_b == c)
        return frechet_distance(*stats_a, *stats_b)

    return jax.vmap(one)(jnp.arange(num_classes))


def _check_labels(name: str, labels: jax.Array, features: jax.Array) -> None:
    if labels.shape != features.shape[:1] or not jnp.issubdtype(labels.dtype, jnp.integer):
        raise ValueError(f"{name}: expected integer labels [N] = ({features.shape[0]},), got {labels.dtype} "
                         f"{tuple(labels.shape)}")


@jax.jit(static_argnames="num_classes")
def fid_per_class(features_a: jax.Array, labels_a: jax.Array, features_b: jax.Array, labels_b: jax.Array,
                  num_classes: int) -> jax.Array:
    """FID of each class, ``[C]``: class c's rows of ``features_a [N, D]`` against those of ``features_b
    [M, D]`` (labels ``[N]``, ``[M]``). A class with fewer than two samples on either side is NaN; a label
    outside ``[0, num_classes)`` on either side makes every class NaN (a jittable function cannot raise on
    values, and leaving the sample out would change the metric)."""
    _check_features("features_a", features_a)
    _check_features("features_b", features_b)
    _check_labels("labels_a", labels_a, features_a)
    _check_labels("labels_b", labels_b, features_b)
    in_range = ids_in_range(labels_a, num_classes) & ids_in_range(labels_b, num_classes)
    return jnp.where(in_range, _per_class(features_a, labels_a, features_b, labels_b, num_classes), jnp.nan)


def fid_class_mean(features_a: jax.Array, labels_a: jax.Array, features_b: jax.Array, labels_b: jax.Array,
                   num_classes: int) -> jax.Array:
    """FID_m (ActFormer): the mean of :func:`fid_per_class` over the classes where it is defined."""
    return jnp.nanmean(fid_per_class(features_a, labels_a, features_b, labels_b, num_classes))


def aggregate_persons(features: jax.Array) -> jax.Array:
    """FID_a's multi-person feature (ActFormer): ``[N, P, D]`` per-person recogniser features -> ``[N, D]``
    channel-wise maximum over persons, so the result does not depend on the order of persons."""
    if features.ndim != 3:
        raise ValueError(f"features: expected per-person features [N, P, D], got shape {tuple(features.shape)}")
    return features.max(axis=1)
