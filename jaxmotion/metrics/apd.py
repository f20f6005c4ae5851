"""Average pairwise distance (APD) of motion sets, ODMO's n-APD and its mode-homogeneity.

ODMO (P-OD, Sec. 4.2.2 and 4.3.1):

* **APD** of a set ``A = {m(1), ..., m(N)}``:
  ``APD(A) = 1/(N(N-1)) Σ_i Σ_{j≠i} (Σ_t ‖m_t(i) − m_t(j)‖²)^½``, i.e. the Euclidean distance between
  whole motions flattened to ``T·J·3`` vectors, averaged over ordered pairs of distinct samples. ODMO's
  ``calculate_apd.py`` computes exactly this (sklearn ``pairwise_distances`` on the flattened motions,
  summed and divided by ``N(N−1)``).
* **n-APD** of a model: ``100 · mean_c APD(generated_c) / APD(real_c)``. The paper's formula has no
  factor 100; ODMO's script multiplies by 100 when it prints, and Tables 1-2 report real motions at 100.0,
  so the factor is kept here.
* **mode-homogeneity** (no ODMO script): for class c, with its real motions ``G_c`` split into modes
  ``G(c, k)`` by a GMM over the latent codes,
  ``mode-APD(G_c) = 1/|G_c| Σ_k |G(c, k)| APD(G(c, k))`` and
  ``mode-homogeneity = 100 · 1/|C| Σ_c (APD(G_c) − mode-APD(G_c)) / APD(G_c)``.

Choices where the sources are silent:

* APD of a set with fewer than 2 samples is NaN (there is no pair; ODMO's code would return 0 for one
  sample, which makes the n-APD ratio 0 or a division by zero).
* In mode-APD a mode with a single sample contributes 0 (no pair, and ODMO's ``compute_APD`` gives 0 for
  one sample); an empty mode contributes nothing.
* Class means are plain means, as ODMO's script takes them (``np.mean``): a NaN class (fewer than two
  samples, or a zero real APD) makes the aggregate NaN instead of being skipped; ``apd_per_class`` gives
  the per-class values.
* A label or mode outside its range makes every output NaN: a jittable function cannot raise on values,
  and dropping the sample silently would change the metric.

Numerics: distances come from the Gram matrix after centring each class on its own mean. Distances within
a class are unchanged by that shift, the float32 cancellation in ``|a|² + |b|² − 2a·b`` is then relative
to the class's spread rather than to the motions' absolute coordinates, and one ``[N, N]`` matmul
replaces an ``[N, N, T·J·3]`` difference tensor. Cross-class entries are computed and masked, so memory
is O(N²) (8 000 samples: 256 MB).

Units: APD is in the unit of the input (metres); n-APD and mode-homogeneity are percentages.

Axes: N samples, T frames, J joints, C classes, K modes per class.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

from jaxmotion.data.labels import ids_in_range

_HIGHEST = jax.lax.Precision.HIGHEST


def _check_motions(name: str, motions: jax.Array) -> jax.Array:
    motions = jnp.asarray(motions)
    if motions.ndim != 4 or motions.shape[-1] != 3:
        raise ValueError(f"{name}: expected [N, T, J, 3], got {tuple(motions.shape)}")
    return motions.astype(jnp.promote_types(motions.dtype, jnp.float32))


def _check_ids(name: str, ids: jax.Array, num_samples: int) -> jax.Array:
    ids = jnp.asarray(ids)
    if ids.shape != (num_samples,) or not jnp.issubdtype(ids.dtype, jnp.integer):
        raise ValueError(f"{name}: expected integer [N] = ({num_samples},), got {ids.dtype} {tuple(ids.shape)}")
    return ids


def _within_class_distances(motions: jax.Array, labels: jax.Array, num_classes: int) -> jax.Array:
    """``[N, T, J, 3], [N] -> [N, N]``: distance of flattened motions of one class; 0 across classes and i = j."""
    flat = motions.reshape(motions.shape[0], -1)
    onehot = jax.nn.one_hot(labels, num_classes, dtype=flat.dtype)
    counts = onehot.sum(axis=0)
    means = jnp.matmul(onehot.T, flat, precision=_HIGHEST) / jnp.maximum(counts, 1.0)[:, None]
    centred = flat - jnp.matmul(onehot, means, precision=_HIGHEST)
    squares = jnp.sum(centred**2, axis=-1)
    gram = jnp.matmul(centred, centred.T, precision=_HIGHEST)
    # Rounding can take the squared distance of near-identical motions slightly below zero.
    distances = jnp.sqrt(jnp.maximum(squares[:, None] + squares[None, :] - 2.0 * gram, 0.0))
    same_class = (labels[:, None] == labels[None, :]) & ~jnp.eye(flat.shape[0], dtype=bool)
    return jnp.where(same_class, distances, 0.0)


def _group_sums(values: jax.Array, groups: jax.Array, num_groups: int) -> tuple[jax.Array, jax.Array]:
    """Per-group sum of ``values [N]`` and per-group count, ``[G]`` each (out-of-range ids are dropped)."""
    onehot = jax.nn.one_hot(groups, num_groups, dtype=values.dtype)
    return jnp.matmul(values, onehot, precision=_HIGHEST), onehot.sum(axis=0)


def _apd_from_sums(pair_sums: jax.Array, counts: jax.Array) -> jax.Array:
    pairs = counts * (counts - 1.0)
    return jnp.where(counts >= 2, pair_sums / jnp.where(counts >= 2, pairs, 1.0), jnp.nan)


@jax.jit(static_argnames='num_classes')
def apd_per_class(motions: jax.Array, labels: jax.Array, num_classes: int) -> jax.Array:
    """APD of each class's motions: ``motions [N, T, J, 3]``, ``labels [N]`` int -> ``[C]`` (input unit).

    ``num_classes`` is static. A class with fewer than two samples is NaN; any label outside
    ``[0, num_classes)`` makes every class NaN.
    """
    motions = _check_motions("motions", motions)
    labels = _check_ids("labels", labels, motions.shape[0])
    distances = _within_class_distances(motions, labels, num_classes)
    per_class = _apd_from_sums(*_group_sums(distances.sum(axis=1), labels, num_classes))
    return jnp.where(ids_in_range(labels, num_classes), per_class, jnp.nan)


@jax.jit
def apd(motions: jax.Array) -> jax.Array:
    """APD of one set of motions ``[N, T, J, 3]`` -> scalar (input unit); NaN when N < 2."""
    motions = _check_motions("motions", motions)
    return apd_per_class(motions, jnp.zeros(motions.shape[0], jnp.int32), 1)[0]


@jax.jit(static_argnames='num_classes')
def n_apd(
    generated: jax.Array, generated_labels: jax.Array, real: jax.Array, real_labels: jax.Array, num_classes: int
) -> jax.Array:
    """ODMO's n-APD (percent): ``100 · mean_c APD(generated_c) / APD(real_c)`` -> scalar.

    Args:
      generated: ``[N, T, J, 3]`` generated motions.
      generated_labels: ``[N]`` int class of each generated motion.
      real: ``[M, T', J', 3]`` real motions (ODMO pairs generated set i with real file i).
      real_labels: ``[M]`` int class of each real motion.
      num_classes: static number of classes C; every class enters the mean.

    Returns NaN when any class has fewer than two samples in either set or a real APD of 0.
    """
    generated, real = _check_motions("generated", generated), _check_motions("real", real)
    generated_labels = _check_ids("generated_labels", generated_labels, generated.shape[0])
    real_labels = _check_ids("real_labels", real_labels, real.shape[0])
    generated_apd = apd_per_class(generated, generated_labels, num_classes)
    real_apd = apd_per_class(real, real_labels, num_classes)
    ratio = jnp.where(real_apd > 0, generated_apd / jnp.where(real_apd > 0, real_apd, 1.0), jnp.nan)
    return 100.0 * ratio.mean()


@jax.jit(static_argnames=('num_classes', 'num_modes'))
def mode_homogeneity(
    motions: jax.Array, labels: jax.Array, modes: jax.Array, num_classes: int, num_modes: int
) -> jax.Array:
    """ODMO's mode-homogeneity (percent): mean relative drop of APD when each class is split into modes.

    Args:
      motions: ``[N, T, J, 3]`` real motions.
      labels: ``[N]`` int class of each motion.
      modes: ``[N]`` int mode of each motion within its class, in ``[0, num_modes)`` (the GMM component
        of its latent code); mode ids are per class, so mode 0 of two classes are different modes.
      num_classes: static C.
      num_modes: static K, at least the largest number of modes of any class.

    Returns ``100 · mean_c (APD_c − mode-APD_c) / APD_c`` -> scalar: 0 when every class is one mode,
    100 when every mode is a single motion. NaN when a class has fewer than two motions or an APD of 0.
    """
    motions = _check_motions("motions", motions)
    labels = _check_ids("labels", labels, motions.shape[0])
    modes = _check_ids("modes", modes, motions.shape[0])
    distances = _within_class_distances(motions, labels, num_classes)
    class_sums, class_counts = _group_sums(distances.sum(axis=1), labels, num_classes)
    class_apd = _apd_from_sums(class_sums, class_counts)

    same_mode = modes[:, None] == modes[None, :]
    mode_sums, mode_counts = _group_sums(
        jnp.where(same_mode, distances, 0.0).sum(axis=1), labels * num_modes + modes, num_classes * num_modes
    )
    # |G(c,k)| · APD(G(c,k)) = pair sum / (|G(c,k)| − 1); a one-motion mode has a pair sum of 0.
    weighted = mode_sums / jnp.maximum(mode_counts - 1.0, 1.0)
    mode_apd = weighted.reshape(num_classes, num_modes).sum(axis=1) / jnp.maximum(class_counts, 1.0)

    homogeneity = 100.0 * ((class_apd - mode_apd) / class_apd).mean()
    valid = ids_in_range(labels, num_classes) & ids_in_range(modes, num_modes)
    return jnp.where(valid, homogeneity, jnp.nan)
