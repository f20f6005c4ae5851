"""Keyed clustering in pure JAX: k-means++ seeding, Lloyd's k-means, full-covariance Gaussian-mixture EM,
the silhouette score and ODMO's adaptive choice of the number of modes.

Every kernel is written for one problem ``x [N, D]`` with a validity ``mask [N]`` and is jittable and
vmappable, so many independent problems (all classes of a dataset, each padded to the same N) fit in one
call. K is static (a Python int); iteration counts, tolerances and the covariance floor are traced.
Iterations are ``lax.while_loop`` s with a convergence flag: under ``vmap`` the loop runs until the last
problem converges and a converged problem's state is held fixed, so each problem gets the iterations it
would get alone.

The algorithms are scikit-learn's (``KMeans``, ``GaussianMixture(covariance_type="full")``,
``metrics.silhouette_score``), which the ODMO authors call:

* **k-means++** is sklearn's greedy variant: each new center is the best, by the inertia it leaves, of
  ``2 + ⌊ln K⌋`` candidates drawn with probability ∝ squared distance to the nearest chosen center. Draws
  are inverse-CDF look-ups of uniforms in the cumulative weights, as sklearn's, which makes them blind to
  masked rows: padding moves no draw.
* **Lloyd** iterations as sklearn's: stop when no label changes or when the squared center shift summed
  over centers is ``≤ tol · mean_d var(x_d)`` (``tol`` is relative to the mean per-feature variance of
  the valid samples); an empty cluster takes the valid sample farthest from its center, as sklearn
  relocates. Labels are those of the final centers. Distances are computed on the data centred on its
  mean (sklearn centres too), which keeps float32 cancellation in ``|x|² − 2x·c + |c|²`` small.
* **EM** as sklearn's: ``nk = Σ resp + 10·eps``, ``reg_covar`` added to each covariance's diagonal in the
  M-step, Cholesky factors of the covariances and their inverses ``P`` by triangular solves
  (log-determinants from the factors), Mahalanobis terms as ``x P − μ P``, log-sum-exp
  responsibilities. The fit runs on the data centred on their mean (EM is translation-equivariant), so
  float32 cancellation is relative to the data's spread, not their offset. Iteration i runs an E-step (its mean log-likelihood is
  the lower bound) then an M-step, and stops once ``|Δ lower bound| < tol``; so, as sklearn's
  ``lower_bound_``, the returned lower bound is that of the parameters one M-step before the returned
  ones. ``init="kmeans"`` starts from the M-step of a one-restart k-means fit's one-hot labels (sklearn's
  default), ``"random"`` from uniform random responsibilities normalised per sample.
* **Restarts** (``n_init``) are vmapped in :func:`kmeans` and :func:`fit_gmm`; restart i reads row i of one uniform draw ``[R, ...]`` made from
  the key, so under JAX's default (partitionable) threefry the restarts of ``n_init = m`` are the first m
  of any larger ``n_init`` and the best result can only improve with it. k-means keeps the lowest
  inertia, EM the highest lower bound (the first on ties, as sklearn).
* **Silhouette**: Euclidean; the mean intra-cluster distance excludes the sample itself, a sample alone in
  its cluster scores 0, as does one with both distances 0, and empty clusters are left out of the
  nearest-other-cluster minimum (sklearn re-encodes labels, so unused labels never count).

Where these differ from sklearn:

* Random draws come from JAX keys, so results match sklearn's in distribution, not number for number;
  from the same starting parameters (:func:`gmm_em`) the two agree to float32 rounding.
* Values cannot raise inside ``jit``: a restart whose Cholesky fails (NaN) loses to every finite one, and
  a silhouette over fewer than 2 or more than ``n_valid − 1`` non-empty clusters (where sklearn raises) or
  with a valid label outside ``[0, K)`` is NaN. Checks that need values (fewer valid samples than K) run
  on the host when the mask is concrete, i.e. outside ``jit`` and ``vmap``.
* Masked samples (``mask`` False) carry no weight anywhere: not in seeding, centers, means, covariances,
  weights, lower bounds or silhouettes; their rows may hold anything (NaN included) and their labels are
  -1. ``init="random"`` draws one uniform per row, padding included, so only the k-means init is blind to
  padding.

ODMO's number of modes (:func:`choose_k`; FACTS §7, code vs paper) from the silhouettes ``S_k`` of GMMs
(k-means init, ``n_init`` 5) over the class's latent codes, each scored on its own predicted labels:

* ``rule="code"`` (default; ODMO's ``sample_code_multimodal``): k = 3..9, stop at the first k with
  ``S_k < 0.95 · S_{k−1}`` and use k − 1; 9 when nothing breaks.
* ``rule="paper"`` (supplement, Sec. 2.2): k = 3..11, the first i with ``S_i > 0.95 · S_{i+1}``; 11 when
  none.

:func:`discover_modes_batched` fits all problems with k components in one call of one compiled kernel,
the same for every k (``max(ks)`` component slots of which the first k take part, k traced; the k-means
starts vmapped over problems and restarts; the EM runs share a pool of slots that take the next pending
run when theirs converges, so the few slow runs do not hold up the many fast ones), for k = 3, 4, ... until
every problem's rule has broken: like the authors' loop, it never fits the ks past the break, which are
the costly ones (EM with many components converges slowly); a problem whose rule has broken takes no
more EM slots. The two ``discover_modes`` functions are host-side drivers (the choice of k is Python) and
jit that kernel themselves; everything else is jittable, not jitted.

Dropping small components before sampling (ODMO: ≤ 10 codes in the code, < 10 in the paper) is the
caller's: give them a count of 0 in :func:`sample_components`.

Axes: N samples, D features, K components (slots), C independent problems (classes), R restarts,
T k-means++ candidates per center.
"""

from __future__ import annotations

import functools
import math
import operator
from collections.abc import Mapping, Sequence
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.progress import phase

_HIGHEST = jax.lax.Precision.HIGHEST

MODE_KS = {"code": range(3, 10), "paper": range(3, 12)}
"""The k each of ODMO's rules tries."""

_RATIO = 0.95  # ODMO's silhouette ratio, in both rules
_KMEANS_INIT = (300, 1e-4)  # max_iter and tol of the KMeans that sklearn's GaussianMixture starts from
_POOL_SHARE = 16  # EM runs per pool slot in mode discovery (12 classes × 5 restarts on 2 CPU cores, summed
# over k = 3..9: 4 runs a slot 2.28 s, 8 2.14 s, 16 2.12 s, 32 2.11 s, all 60 in one slot 2.37 s)


class KMeans(NamedTuple):
    centers: jax.Array  # [K, D]
    labels: jax.Array  # [N] int32, -1 where masked
    inertia: jax.Array  # [] sum of squared distances of valid samples to their centers
    n_iter: jax.Array  # [] int32 Lloyd iterations run


class GaussianMixture(NamedTuple):
    weights: jax.Array  # [K]
    means: jax.Array  # [K, D]
    covariances: jax.Array  # [K, D, D]
    lower_bound: jax.Array | float = float("nan")  # [] mean log-likelihood per valid sample (sklearn's)
    converged: jax.Array | bool = False  # []
    n_iter: jax.Array | int = 0  # [] EM iterations run


class Modes(NamedTuple):
    """One problem's modes: the chosen K, the mixture fitted with it, its labels, ``S_k`` of every k in
    ks (NaN past the rule's break, where no fit ran)."""

    k: int
    gmm: GaussianMixture  # K = k components
    labels: jax.Array  # [N] int32, -1 where masked
    silhouettes: dict[int, float]


class ModesBatch(NamedTuple):
    """C problems' modes. ``gmm`` has ``max(ks)`` component slots; those past a problem's k have weight 0
    (mean 0, covariance ``reg_covar · I``), which every function over a mixture treats as absent."""

    k: np.ndarray  # [C] int
    gmm: GaussianMixture  # weights [C, K], means [C, K, D], covariances [C, K, D, D], the rest [C]
    labels: jax.Array  # [C, N] int32, -1 where masked
    silhouettes: np.ndarray  # [C, len(ks)], NaN for the ks a problem never fitted (past its break)
    ks: tuple[int, ...]


# ------------------------------------------------------------------------------------------------ checks


def _has_value(a) -> bool:
    """False for a traced value (inside ``jit`` or ``vmap``), where checks on values cannot run."""
    return not isinstance(a, jax.core.Tracer)


def _check_k(k: int) -> int:
    try:
        k = operator.index(k)
    except TypeError:
        raise ValueError(f"k: expected a Python int (static), got {k!r}") from None
    if k < 1:
        raise ValueError(f"k: expected at least 1 component, got {k}")
    return k


def _check_data(x: jax.Array, mask: jax.Array | None, k: int | None = None) -> tuple[jax.Array, jax.Array]:
    """``x [N, D]`` as float (masked rows zeroed) and ``mask [N]`` bool (all True when None)."""
    x = jnp.asarray(x)
    if x.ndim != 2:
        raise ValueError(f"x: expected [N, D], got {tuple(x.shape)}")
    x = x.astype(jnp.promote_types(x.dtype, jnp.float32))
    n = x.shape[0]
    if mask is None:
        mask = jnp.ones((n,), bool)
    else:
        mask = jnp.asarray(mask)
        if mask.shape != (n,) or mask.dtype != bool:
            raise ValueError(f"mask: expected bool [N] = ({n},), got {mask.dtype} {tuple(mask.shape)}")
    if k is not None:
        if k > n:
            raise ValueError(f"k: {k} components but x has only N = {n} samples")
        if _has_value(mask) and (n_valid := int(mask.sum())) < k:
            raise ValueError(f"mask: {n_valid} valid samples, fewer than k = {k}")
    return jnp.where(mask[:, None], x, 0.0), mask


def _check_mixture(weights, means, covariances) -> tuple[jax.Array, jax.Array, jax.Array]:
    means = jnp.asarray(means)
    if means.ndim != 2:
        raise ValueError(f"means: expected [K, D], got {tuple(means.shape)}")
    k, d = means.shape
    weights, covariances = jnp.asarray(weights), jnp.asarray(covariances)
    if weights.shape != (k,):
        raise ValueError(f"weights: expected [K] = ({k},), got {tuple(weights.shape)}")
    if covariances.shape != (k, d, d):
        raise ValueError(f"covariances: expected [K, D, D] = ({k}, {d}, {d}), got {tuple(covariances.shape)}")
    dtype = jnp.promote_types(means.dtype, jnp.float32)
    return weights.astype(dtype), means.astype(dtype), covariances.astype(dtype)


def _check_features(x: jax.Array, gmm: GaussianMixture) -> jax.Array:
    x = jnp.asarray(x)
    d = gmm.means.shape[-1]
    if x.ndim != 2 or x.shape[1] != d:
        raise ValueError(f"x: expected [N, D] = [N, {d}], got {tuple(x.shape)}")
    return x.astype(jnp.promote_types(x.dtype, jnp.float32))


# --------------------------------------------------------------------------------------------- k-means


def _active(slots: int, k=None) -> jax.Array:
    """``[slots]`` bool: True for the first ``k`` (default all; may be traced) component slots."""
    return jnp.ones((slots,), bool) if k is None else jnp.arange(slots) < k


def _center(x: jax.Array, w: jax.Array) -> tuple[jax.Array, jax.Array]:
    """``x [N, D]`` minus the mean of its valid rows (masked rows 0), and that mean ``[D]``."""
    mean = (w @ x) / w.sum()
    return (x - mean) * w[:, None], mean


def _n_trials(k: int) -> int:
    """sklearn's k-means++ candidates per center."""
    return 2 + int(math.log(k))


def _weighted_choice(u: jax.Array, weights: jax.Array) -> jax.Array:
    """Indices drawn with probability ∝ ``weights [N]`` (≥ 0, not all 0) for uniforms ``u [...]`` in
    [0, 1), by inverse CDF as sklearn.

    ``1 − u ∈ (0, 1]`` times the total lands strictly above a zero-weight row's cumulative step, so a row
    of weight 0 is never drawn, wherever it sits.
    """
    cumulative = jnp.cumsum(weights)
    targets = (1.0 - u) * cumulative[-1]
    return jnp.minimum(jnp.searchsorted(cumulative, targets, method="compare_all"), weights.shape[0] - 1)


def _plusplus(u: jax.Array, x: jax.Array, w: jax.Array, k=None) -> jax.Array:
    """Greedy k-means++ seeds of ``x [N, D]`` with sample weights ``w [N]`` -> ``[K, D]``.

    ``u [K, T]`` uniforms: ``u[0, 0]`` picks the first center, ``u[c]`` the T candidates of center c. Only the
    first ``k`` (default K; may be traced) slots get centers, the others stay 0.
    """
    k = u.shape[0] if k is None else k
    first = x[_weighted_choice(u[0, 0], w)]
    closest = jnp.sum((x - first) ** 2, axis=-1)

    def add_center(c, carry):
        centers, closest = carry
        # All valid samples already on a center (duplicates): any valid sample will do.
        p = jnp.where(closest @ w > 0, w * closest, w)
        candidates = x[_weighted_choice(u[c], p)]  # [T, D]
        dist = jnp.minimum(closest, jnp.sum((candidates[:, None] - x[None]) ** 2, axis=-1))  # [T, N]
        best = jnp.argmin(dist @ w)
        return centers.at[c].set(candidates[best]), dist[best]

    centers = jnp.zeros((u.shape[0], x.shape[1]), x.dtype).at[0].set(first)
    return jax.lax.fori_loop(1, k, add_center, (centers, closest))[0]


def kmeans_plusplus(key: jax.Array, x: jax.Array, k: int, mask: jax.Array | None = None) -> jax.Array:
    """k-means++ seeds ``[K, D]`` of ``x [N, D]``: sklearn's greedy variant (best of ``2 + ⌊ln K⌋``
    candidates per center by the inertia it leaves), drawn only from valid rows of ``mask [N]``."""
    k = _check_k(k)
    x, mask = _check_data(x, mask, k)
    u = jax.random.uniform(key, (k, _n_trials(k)), x.dtype)
    return _plusplus(u, x, mask.astype(x.dtype))


def _assign(x: jax.Array, centers: jax.Array, active: jax.Array) -> jax.Array:
    """Nearest active center (``active [K]``) of each row of centred ``x [N, D]`` -> ``[N]`` (``|x|²`` is
    common to a row)."""
    scores = jnp.sum(centers**2, axis=-1) - 2.0 * jnp.matmul(x, centers.T, precision=_HIGHEST)
    scores = jnp.where(active, scores, jnp.inf)
    return jnp.argmin(scores, axis=-1).astype(jnp.int32)


def _update_centers(x: jax.Array, w: jax.Array, centers: jax.Array, labels: jax.Array,
                    active: jax.Array) -> jax.Array:
    """Lloyd's center update with sklearn's relocation of empty clusters -> new centers ``[K, D]`` (inactive
    slots stay 0)."""
    k = centers.shape[0]
    onehot = jax.nn.one_hot(labels, k, dtype=x.dtype) * w[:, None]
    mass, sums = onehot.sum(axis=0), jnp.matmul(onehot.T, x, precision=_HIGHEST)
    # The j-th empty cluster takes the j-th valid sample farthest from its own center, which leaves its
    # cluster (sklearn's _relocate_empty_clusters_dense).
    empty = (mass == 0) & active
    spread = jnp.where(w > 0, jnp.sum((x - centers[labels]) ** 2, axis=-1), -1.0)
    donors = jax.lax.top_k(spread, k)[1][jnp.cumsum(empty) - 1]  # [K], meaningful where empty
    moved = jnp.where(empty, w[donors], 0.0)
    sums = sums.at[labels[donors]].add(-x[donors] * moved[:, None])
    mass = mass.at[labels[donors]].add(-moved)
    sums = jnp.where(empty[:, None], x[donors] * moved[:, None], sums)
    mass = jnp.where(empty, moved, mass)
    # A cluster left with no weight keeps its (zero) sum as center, as sklearn's _average_centers.
    return jnp.where(mass[:, None] > 0, sums / jnp.where(mass > 0, mass, 1.0)[:, None], sums)


def _lloyd(u: jax.Array, x: jax.Array, w: jax.Array, max_iter, tol, k=None) -> KMeans:
    """One k-means restart on centred ``x [N, D]``, weights ``w [N]``, seeds from ``u [K, T]``, with the
    first ``k`` (default K; may be traced) slots as clusters; ``tol`` is absolute (summed squared center
    shift)."""
    active = _active(u.shape[0], k)

    def step(state):
        centers, labels_old, it, _ = state
        labels = _assign(x, centers, active)
        new = _update_centers(x, w, centers, labels, active)
        unchanged = jnp.all((labels == labels_old) | (w == 0))
        return new, labels, it + 1, unchanged | (jnp.sum((new - centers) ** 2) <= tol)

    state = (_plusplus(u, x, w, k), jnp.full((x.shape[0],), -1, jnp.int32), jnp.int32(0),
             jnp.bool_(False))
    centers, _, n_iter, _ = jax.lax.while_loop(lambda s: ~s[3] & (s[2] < max_iter), step, state)
    labels = _assign(x, centers, active)
    inertia = jnp.sum(w * jnp.sum((x - centers[labels]) ** 2, axis=-1))
    return KMeans(centers, jnp.where(w > 0, labels, -1), inertia, n_iter)


def _absolute_tol(x: jax.Array, w: jax.Array, tol) -> jax.Array:
    """sklearn's k-means tolerance for centred ``x [N, D]``: ``tol`` times the mean per-feature variance
    of the valid rows."""
    return tol * jnp.mean((w @ x**2) / w.sum())


def kmeans(key: jax.Array, x: jax.Array, k: int, *, mask: jax.Array | None = None, n_init: int = 1,
           max_iter: int = 300, tol: float = 1e-4) -> KMeans:
    """Lloyd's k-means of ``x [N, D]`` from k-means++ seeds, best of ``n_init`` (static) restarts.

    Args:
      key: PRNG key; restart i reads row i of ``uniform(key, [n_init, K, 2 + ⌊ln K⌋])``.
      x: ``[N, D]`` samples.
      k: static number of clusters K.
      mask: ``[N]`` bool, True for the samples to cluster (default all).
      n_init: static number of restarts; the lowest inertia wins.
      max_iter: most Lloyd iterations per restart.
      tol: sklearn's relative tolerance: a restart stops when no label changes or the squared center
        shift summed over centers is ``≤ tol · mean_d var(x_d)`` over the valid samples.

    Returns ``KMeans(centers [K, D], labels [N] (-1 where masked), inertia [], n_iter [])``.
    """
    k = _check_k(k)
    x, mask = _check_data(x, mask, k)
    w = mask.astype(x.dtype)
    x, mean = _center(x, w)
    tol = _absolute_tol(x, w, tol)
    u = jax.random.uniform(key, (n_init, k, _n_trials(k)), x.dtype)
    fits = jax.vmap(lambda u_r: _lloyd(u_r, x, w, max_iter, tol))(u)
    best = jax.tree.map(lambda a: a[jnp.argmin(fits.inertia)], fits)
    return best._replace(centers=best.centers + mean)


# ---------------------------------------------------------------------------------- Gaussian mixtures


def _precision_cholesky(covariances: jax.Array) -> jax.Array:
    """``[K, D, D]`` covariances -> ``L⁻ᵀ`` (upper, ``P Pᵀ = Σ⁻¹``) from their Cholesky factors ``L``."""
    chol = jnp.linalg.cholesky(covariances)
    eye = jnp.broadcast_to(jnp.eye(covariances.shape[-1], dtype=covariances.dtype), covariances.shape)
    return jnp.swapaxes(jax.lax.linalg.triangular_solve(chol, eye, left_side=True, lower=True), -1, -2)


def _log_gaussians(x: jax.Array, means: jax.Array, prec_chol: jax.Array) -> jax.Array:
    """``log N(x_n | μ_k, Σ_k)`` -> ``[N, K]`` for ``x [N, D]``, ``means [K, D]``, ``prec_chol [K, D, D]``.

    sklearn's form ``x P − μ P``: one ``[N, D] × [D, K·D]`` product instead of K products of ``x − μ_k``
    (callers centre x, so the cancellation is relative to the data's spread).
    """
    d = x.shape[-1]
    y = (jnp.einsum("nd,kde->nke", x, prec_chol, precision=_HIGHEST)
         - jnp.einsum("kd,kde->ke", means, prec_chol, precision=_HIGHEST))
    log_det = jnp.sum(jnp.log(jnp.diagonal(prec_chol, axis1=-2, axis2=-1)), axis=-1)  # = −½ log|Σ|
    return -0.5 * (d * math.log(2.0 * math.pi) + jnp.sum(y**2, axis=-1)) + log_det


def _weighted_log_prob(weights, means, prec_chol, x) -> jax.Array:
    """``log w_k + log N(x_n | μ_k, Σ_k)`` -> ``[N, K]``; ``-inf`` for a component of weight 0."""
    return _log_gaussians(x, means, prec_chol) + jnp.log(weights)


def _m_step(x: jax.Array, resp: jax.Array, reg_covar, active: jax.Array):
    """sklearn's M-step from responsibilities ``resp [N, K]`` (0 on masked rows and inactive slots) ->
    weights, means, covariances (``reg_covar`` on the diagonal); inactive slots (``active [K]`` False) get
    weight 0, mean 0 and covariance ``reg_covar · I``."""
    nk = jnp.where(active, resp.sum(axis=0) + 10.0 * jnp.finfo(x.dtype).eps, 0.0)
    divisor = jnp.where(active, nk, 1.0)
    means = jnp.matmul(resp.T, x, precision=_HIGHEST) / divisor[:, None]
    # Deviations from each mean, not the second moment about the origin: a covariance made of weighted
    # outer products stays positive semi-definite whatever the float32 rounding.
    diff = x[None] - means[:, None]  # [K, N, D]
    cov = jnp.einsum("knd,kne->kde", resp.T[:, :, None] * diff, diff, precision=_HIGHEST)
    cov = cov / divisor[:, None, None] + reg_covar * jnp.eye(x.shape[-1], dtype=x.dtype)
    return nk / nk.sum(), means, cov


class _EMState(NamedTuple):
    weights: jax.Array  # [K]
    means: jax.Array  # [K, D]
    covariances: jax.Array  # [K, D, D]
    prec_chol: jax.Array  # [K, D, D]
    lower_bound: jax.Array  # [] of the E-step before the M-step that gave these parameters
    n_iter: jax.Array  # [] int32
    converged: jax.Array  # [] bool


def _em_start(weights, means, covariances) -> _EMState:
    bound = jnp.full(weights.shape[:-1], -jnp.inf, weights.dtype)
    return _EMState(weights, means, covariances, _precision_cholesky(covariances), bound,
                    jnp.zeros(bound.shape, jnp.int32), jnp.zeros(bound.shape, bool))


def _em_running(s: _EMState, max_iter) -> jax.Array:
    return ~s.converged & (s.n_iter < max_iter)


def _em_step(x, w, tol, reg_covar, active, s: _EMState) -> _EMState:
    """One E-step (whose mean log-likelihood is the new lower bound) and M-step on ``x [N, D]`` over the
    ``active [K]`` slots."""
    log_prob = _weighted_log_prob(s.weights, s.means, s.prec_chol, x)
    norm = jax.nn.logsumexp(log_prob, axis=-1)
    bound = (w @ norm) / w.sum()
    weights, means, cov = _m_step(x, jnp.exp(log_prob - norm[:, None]) * w[:, None], reg_covar, active)
    return _EMState(weights, means, cov, _precision_cholesky(cov), bound, s.n_iter + 1,
                    jnp.abs(bound - s.lower_bound) < tol)


def _em_result(s: _EMState) -> GaussianMixture:
    return GaussianMixture(s.weights, s.means, s.covariances, s.lower_bound, s.converged, s.n_iter)


def _em(x, w, weights, means, covariances, max_iter, tol, reg_covar) -> GaussianMixture:
    """EM on ``x [N, D]`` (masked rows 0, weights ``w [N]``) from the given parameters."""
    step = functools.partial(_em_step, x, w, tol, reg_covar, _active(weights.shape[-1]))
    start = _em_start(weights, means, covariances)
    return _em_result(jax.lax.while_loop(lambda s: _em_running(s, max_iter), step, start))


def _em_pool(x, w, owner, start: _EMState, max_iter, tol, reg_covar, width: int,
             count: jax.Array | None = None, k=None) -> GaussianMixture:
    """EM for B problems ``start`` (leaves ``[B, ...]``) on the data ``x [C, N, D]``, ``w [C, N]`` of
    their problem ``owner [B]``, ``width`` (static) at a time; only the first ``count`` (traced, default
    B) are fitted, the others keep their start; the first ``k`` (traced, default all) slots are components.

    A vmapped ``while_loop`` runs every problem as long as the slowest (EM from k-means starts on
    ODMO-sized problems: a median of 2 iterations, a mean of 5, a tail of 30). Here ``width`` slots each
    hold one problem and take the next pending one when theirs stops, so the work is the problems' own
    iterations plus one tail; every problem gets exactly the iterations it would get alone.
    """
    b = owner.shape[0]
    count = b if count is None else count
    step = jax.vmap(_em_step, in_axes=(0, 0, None, None, None, 0))
    active = _active(start.weights.shape[-1], k)

    def body(carry):
        states, slots, pending = carry
        live = slots < count
        index = jnp.minimum(slots, b - 1)
        current = jax.tree.map(lambda a: a[index], states)
        run = live & _em_running(current, max_iter)
        new = step(x[owner[index]], w[owner[index]], tol, reg_covar, active, current)
        new = jax.tree.map(lambda n, c: jnp.where(run.reshape((-1,) + (1,) * (n.ndim - 1)), n, c), new, current)
        states = jax.tree.map(lambda a, n: a.at[jnp.where(live, slots, b)].set(n, mode="drop"), states, new)
        free = ~live | ~_em_running(new, max_iter)
        slots = jnp.where(free, pending + jnp.cumsum(free) - 1, slots)
        return states, slots, pending + free.sum()

    width = min(width, b)
    carry = (start, jnp.arange(width), jnp.int32(width))
    return _em_result(jax.lax.while_loop(lambda c: jnp.any(c[1] < count), body, carry)[0])


def gmm_em(x: jax.Array, weights: jax.Array, means: jax.Array, covariances: jax.Array, *,
           mask: jax.Array | None = None, max_iter: int = 100, tol: float = 1e-3,
           reg_covar: float = 1e-6) -> GaussianMixture:
    """EM for a full-covariance Gaussian mixture from given parameters (sklearn's ``weights_init``,
    ``means_init``, ``precisions_init = Σ⁻¹``).

    Args:
      x: ``[N, D]`` samples; mask: ``[N]`` bool, True for the samples to fit (default all).
      weights, means, covariances: ``[K]``, ``[K, D]``, ``[K, D, D]`` starting parameters, used as given
        (``reg_covar`` enters from the first M-step on, as in sklearn).
      max_iter: most EM iterations; tol: stop once ``|Δ lower bound| < tol``.
      reg_covar: added to the diagonal of every estimated covariance.

    Returns the fitted :class:`GaussianMixture`; its ``lower_bound`` is the mean log-likelihood of the
    parameters one M-step before the returned ones (sklearn's ``lower_bound_``), ``-inf`` when
    ``max_iter`` is 0.
    """
    weights, means, covariances = _check_mixture(weights, means, covariances)
    x, mask = _check_data(x, mask)
    if x.shape[1] != means.shape[1]:
        raise ValueError(f"x: expected [N, D] = [N, {means.shape[1]}], got {tuple(x.shape)}")
    w = mask.astype(x.dtype)
    x, mean = _center(x, w)
    fit = _em(x, w, weights, means - mean, covariances, max_iter, tol, reg_covar)
    return fit._replace(means=fit.means + mean)


def _gmm_starts(u, x, w, init, reg_covar, kmeans_max_iter, kmeans_tol, k=None):
    """The starting parameters of the restarts ``u`` (``[R, K, T]`` k-means++ uniforms for
    ``init="kmeans"``, ``[R, N, K]`` responsibilities for ``"random"``) on centred ``x [N, D]``, with the
    first ``k`` (default K; may be traced) slots as components -> weights ``[R, K]``, means ``[R, K, D]``,
    covariances ``[R, K, D, D]``."""
    slots = u.shape[-1] if init == "random" else u.shape[1]
    active = _active(slots, k)
    kmeans_tol = _absolute_tol(x, w, kmeans_tol)

    def start(u_r):
        if init == "kmeans":
            labels = _lloyd(u_r, x, w, kmeans_max_iter, kmeans_tol, k).labels
            resp = jax.nn.one_hot(labels, slots, dtype=x.dtype)  # -1 (masked) -> a zero row
        else:
            u_r = jnp.where(active, u_r, 0.0)
            resp = u_r / u_r.sum(axis=1, keepdims=True) * w[:, None]
        return _m_step(x, resp, reg_covar, active)

    return jax.vmap(start)(u)


def _best_restart(fits: GaussianMixture) -> GaussianMixture:
    """The restart (leading axis) with the highest lower bound; NaN loses."""
    best = jnp.argmax(jnp.where(jnp.isnan(fits.lower_bound), -jnp.inf, fits.lower_bound))
    return jax.tree.map(lambda a: a[best], fits)


def _restart_shape(init: str, n_init: int, n: int, k: int) -> tuple[int, ...]:
    """The uniforms one fit draws: k-means++ ``[R, K, T]`` or random responsibilities ``[R, N, K]``."""
    return (n_init, k, _n_trials(k)) if init == "kmeans" else (n_init, n, k)


def _check_init(init: str) -> None:
    if init not in ("kmeans", "random"):
        raise ValueError(f"init: expected 'kmeans' or 'random', got {init!r}")


def fit_gmm(key: jax.Array, x: jax.Array, k: int, *, mask: jax.Array | None = None, n_init: int = 1,
            max_iter: int = 100, tol: float = 1e-3, reg_covar: float = 1e-6, init: str = "kmeans",
            kmeans_max_iter: int = _KMEANS_INIT[0], kmeans_tol: float = _KMEANS_INIT[1]) -> GaussianMixture:
    """Full-covariance Gaussian mixture of ``x [N, D]`` with K (static) components, best of ``n_init``
    (static) restarts by lower bound: sklearn's ``GaussianMixture(k, covariance_type="full", ...)``.

    Args:
      key: PRNG key; restart i reads row i of one uniform draw (``[n_init, K, 2 + ⌊ln K⌋]`` k-means++
        uniforms, or ``[n_init, N, K]`` responsibilities for ``init="random"``).
      x: ``[N, D]``; mask: ``[N]`` bool, True for the samples to fit (default all).
      k: static number of components.
      n_init, max_iter, tol, reg_covar: as sklearn (see :func:`gmm_em`).
      init: ``"kmeans"`` (responsibilities = one-hot labels of a one-restart :func:`kmeans` with
        ``kmeans_max_iter`` and ``kmeans_tol``, then an M-step) or ``"random"`` (uniform responsibilities
        normalised per sample, then an M-step).
    """
    k = _check_k(k)
    _check_init(init)
    x, mask = _check_data(x, mask, k)
    w = mask.astype(x.dtype)
    x, mean = _center(x, w)
    u = jax.random.uniform(key, _restart_shape(init, n_init, x.shape[0], k), x.dtype)
    starts = _gmm_starts(u, x, w, init, reg_covar, kmeans_max_iter, kmeans_tol)
    fits = jax.vmap(lambda s: _em(x, w, *s, max_iter, tol, reg_covar))(starts)
    best = _best_restart(fits)
    return best._replace(means=best.means + mean)


def _mixture_log_prob(gmm: GaussianMixture, x: jax.Array) -> jax.Array:
    """``[N, K]`` weighted log densities, computed about the mixture's mean (``x P − μ P`` cancels less)."""
    center = gmm.weights @ gmm.means
    return _weighted_log_prob(gmm.weights, gmm.means - center, _precision_cholesky(gmm.covariances), x - center)


def gmm_log_prob(gmm: GaussianMixture, x: jax.Array) -> jax.Array:
    """Log density of the mixture at each row of ``x [N, D]`` -> ``[N]`` (sklearn's ``score_samples``)."""
    return jax.nn.logsumexp(_mixture_log_prob(gmm, _check_features(x, gmm)), axis=-1)


def gmm_responsibilities(gmm: GaussianMixture, x: jax.Array) -> jax.Array:
    """Posterior probability of each component for each row of ``x [N, D]`` -> ``[N, K]``
    (sklearn's ``predict_proba``)."""
    return jax.nn.softmax(_mixture_log_prob(gmm, _check_features(x, gmm)), axis=-1)


def gmm_predict(gmm: GaussianMixture, x: jax.Array, mask: jax.Array | None = None) -> jax.Array:
    """Most probable component of each row of ``x [N, D]`` -> ``[N]`` int32, -1 where ``mask [N]`` is
    False."""
    x = _check_features(x, gmm)
    _, mask = _check_data(x, mask)
    labels = jnp.argmax(_mixture_log_prob(gmm, x), axis=-1).astype(jnp.int32)
    return jnp.where(mask, labels, -1)


def _sample_given(key: jax.Array, gmm: GaussianMixture, components: jax.Array) -> jax.Array:
    """One draw of component ``components [n]`` each -> ``[n, D]``."""
    chol = jnp.linalg.cholesky(gmm.covariances)
    z = jax.random.normal(key, components.shape + gmm.means.shape[-1:], gmm.means.dtype)
    return gmm.means[components] + jnp.einsum("nde,ne->nd", chol[components], z, precision=_HIGHEST)


def sample_gmm(key: jax.Array, gmm: GaussianMixture, n: int) -> jax.Array:
    """``n`` (static) i.i.d. samples of the mixture -> ``[n, D]``."""
    k_comp, k_draw = jax.random.split(key)
    components = jax.random.categorical(k_comp, jnp.log(gmm.weights), shape=(n,))
    return _sample_given(k_draw, gmm, components)


def sample_components(key: jax.Array, gmm: GaussianMixture, counts: jax.Array,
                      total: int) -> tuple[jax.Array, jax.Array]:
    """``counts[k]`` samples of each component k (ODMO's mode-preserving sampling) -> ``(samples
    [total, D], component [total])``, sorted by component.

    ``counts [K]`` int ≥ 0 must sum to ``total`` (static); this is checked when ``counts`` has values.
    Under ``jit``, rows past ``sum(counts)`` get component -1 and NaN samples, and counts past ``total``
    are cut.
    """
    k = gmm.weights.shape[-1]
    counts = jnp.asarray(counts)
    if counts.shape != (k,) or not jnp.issubdtype(counts.dtype, jnp.integer):
        raise ValueError(f"counts: expected integer [K] = ({k},), got {counts.dtype} {tuple(counts.shape)}")
    if _has_value(counts):
        if (np.asarray(counts) < 0).any() or int(counts.sum()) != total:
            raise ValueError(f"counts: expected non-negative counts summing to total = {total}, got {counts}")
    components = jnp.searchsorted(jnp.cumsum(counts), jnp.arange(total), side="right").astype(jnp.int32)
    inside = components < k
    samples = _sample_given(key, gmm, jnp.minimum(components, k - 1))
    return jnp.where(inside[:, None], samples, jnp.nan), jnp.where(inside, components, -1)


# ------------------------------------------------------------------------------------------ silhouette


def _silhouette(x: jax.Array, mask: jax.Array, labels: jax.Array, k: int) -> jax.Array:
    """:func:`silhouette_score` of ``x [N, D]`` (masked rows 0) without the argument checks."""
    w = mask.astype(x.dtype)
    n_valid = w.sum()
    centred = (x - (w @ x) / n_valid) * w[:, None]
    squares = jnp.sum(centred**2, axis=-1)
    gram = jnp.matmul(centred, centred.T, precision=_HIGHEST)
    # Rounding can take the squared distance of near-identical samples slightly below zero.
    dist = jnp.sqrt(jnp.maximum(squares[:, None] + squares[None, :] - 2.0 * gram, 0.0))
    dist = jnp.where(jnp.eye(x.shape[0], dtype=bool), 0.0, dist)

    onehot = jax.nn.one_hot(labels, k, dtype=x.dtype) * w[:, None]
    sizes = onehot.sum(axis=0)  # [K]
    to_clusters = jnp.matmul(dist, onehot, precision=_HIGHEST)  # [N, K] summed distance to each cluster
    own = jnp.clip(labels, 0, k - 1)
    own_size = sizes[own]
    intra = jnp.take_along_axis(to_clusters, own[:, None], axis=1)[:, 0] / jnp.maximum(own_size - 1.0, 1.0)
    other = (jnp.arange(k) != own[:, None]) & (sizes > 0)
    inter = jnp.min(jnp.where(other, to_clusters / jnp.maximum(sizes, 1.0), jnp.inf), axis=1)
    scale = jnp.maximum(intra, inter)
    s = jnp.where((own_size > 1) & (scale > 0), (inter - intra) / jnp.where(scale > 0, scale, 1.0), 0.0)
    score = (w @ s) / n_valid

    used = jnp.sum(sizes > 0)
    in_range = jnp.all(~mask | ((labels >= 0) & (labels < k)))
    return jnp.where(in_range & (used >= 2) & (used <= n_valid - 1), score, jnp.nan)


def silhouette_score(x: jax.Array, labels: jax.Array, k: int, *, mask: jax.Array | None = None) -> jax.Array:
    """Mean silhouette of the valid samples of ``x [N, D]`` under ``labels [N]`` in ``[0, k)`` -> ``[]``,
    as ``sklearn.metrics.silhouette_score`` with Euclidean distances.

    ``k`` is static (labels ≥ k are an error, unused labels are ignored). NaN when a valid label is out of
    range or the number of non-empty clusters is outside ``[2, n_valid − 1]`` (sklearn raises). Labels of
    masked rows are ignored.
    """
    k = _check_k(k)
    x, mask = _check_data(x, mask)
    labels = jnp.asarray(labels)
    if labels.shape != (x.shape[0],) or not jnp.issubdtype(labels.dtype, jnp.integer):
        raise ValueError(f"labels: expected integer [N] = ({x.shape[0]},), got {labels.dtype} "
                         f"{tuple(labels.shape)}")
    return _silhouette(x, mask, labels, k)


# ------------------------------------------------------------------------------------ ODMO's adaptive K


def _check_rule(rule: str) -> None:
    if rule not in MODE_KS:
        raise ValueError(f"rule: expected 'code' or 'paper', got {rule!r}")


def choose_k(silhouettes: Mapping[int, float] | Sequence[float], ks: Sequence[int] | None = None, *,
             rule: str = "code") -> int:
    """ODMO's number of modes from the silhouettes ``S_k`` (host-side Python).

    Args:
      silhouettes: ``{k: S_k}``, or ``S_k`` in the order of ``ks``.
      ks: the k of each silhouette (increasing); taken from the mapping when one is given.
      rule: ``"code"``: the k before the first k with ``S_k < 0.95 · S_{k−1}``, else the last k;
        ``"paper"``: the first k with ``S_k > 0.95 · S_{k+1}``, else the last k. A NaN never breaks.
    """
    _check_rule(rule)
    if isinstance(silhouettes, Mapping):
        ks = sorted(silhouettes)
        s = [float(silhouettes[k]) for k in ks]
    else:
        s = [float(v) for v in np.asarray(silhouettes).reshape(-1)]
        if ks is None or len(ks) != len(s):
            raise ValueError(f"ks: expected one k per silhouette ({len(s)}), got {ks!r}")
    if not s:
        raise ValueError("silhouettes: expected at least one value, got none")
    index = _break_index(s, rule)
    return int(ks[len(s) - 1 if index is None else index])


def _break_index(s: Sequence[float], rule: str) -> int | None:
    """The index of the k that ``rule`` chooses at its first break in ``s``, None while it has not broken.
    Either rule decides from a prefix of the silhouettes, so the ks after its break need no fit."""
    if rule == "code":
        return next((j - 1 for j in range(1, len(s)) if s[j] < _RATIO * s[j - 1]), None)
    return next((i for i in range(len(s) - 1) if s[i] > _RATIO * s[i + 1]), None)


def _resolve_ks(ks: Sequence[int] | None, rule: str) -> tuple[int, ...]:
    _check_rule(rule)
    ks = tuple(MODE_KS[rule] if ks is None else (_check_k(k) for k in ks))
    if not ks or list(ks) != sorted(set(ks)):
        raise ValueError(f"ks: expected increasing distinct k, got {ks}")
    return ks


@functools.partial(jax.jit, static_argnames=("k", "slots", "n_init", "n", "init", "dtype"))
def _draws(keys, k: int, slots: int, n_init: int, n: int, init: str, dtype):
    """The uniforms of C problems' fits with k components (problem c: one draw from ``fold_in(keys[c], k)``
    of :func:`_restart_shape`), padded to ``slots`` components -> ``[C, R, slots, 2 + ⌊ln slots⌋]`` or
    ``[C, R, N, slots]``. k-means++ candidates past k's repeat its last one: a copy never beats the candidate
    it repeats (the first of equal inertias wins), so the seeds are those of the unpadded draw."""
    u = jax.vmap(lambda key: jax.random.uniform(jax.random.fold_in(key, k), _restart_shape(init, n_init, n, k),
                                                dtype))(keys)
    if init == "kmeans":
        return jnp.pad(u, ((0, 0), (0, 0), (0, slots - k), (0, _n_trials(slots) - _n_trials(k))), mode="edge")
    return jnp.pad(u, ((0, 0), (0, 0), (0, 0), (0, slots - k)))


def _fit_k(u, x, mask, live, k, max_iter, tol, reg_covar, init, pool_share=_POOL_SHARE):
    """For C problems ``x [C, N, D]`` (masked rows 0), ``mask [C, N]``: the GMM with ``k`` (traced)
    components in the K component slots of the restarts' uniforms ``u [C, R, ...]`` (:func:`_draws`), its
    labels and their silhouette -> leaves ``[C, ...]``; the slots past k have weight 0, mean 0 and
    covariance ``reg_covar · I``. One compiled kernel serves every k.

    The EM runs of the problems that are ``live [C]`` share one pool of ``⌈C · R / pool_share⌉`` slots
    (:func:`_em_pool`), the others' are skipped (their results are meaningless; their silhouettes NaN).
    """
    c, n_init = u.shape[:2]
    slots = u.shape[-1] if init == "random" else u.shape[2]
    w = mask.astype(x.dtype)
    x, mean = jax.vmap(_center)(x, w)
    starts = jax.vmap(lambda u_c, x_c, w_c: _gmm_starts(u_c, x_c, w_c, init, reg_covar, *_KMEANS_INIT, k))(u, x, w)
    runs = c * n_init
    owner = jnp.repeat(jnp.arange(c), n_init)
    order = jnp.argsort(~live[owner], stable=True)  # the live problems' runs first, for the pool to take
    flat = jax.tree.map(lambda a: a.reshape(runs, *a.shape[2:])[order], starts)
    fits = _em_pool(x, w, owner[order], _em_start(*flat), max_iter, tol, reg_covar, -(-runs // pool_share),
                    live[owner].sum(), k)
    fits = jax.tree.map(lambda a: a[jnp.argsort(order)].reshape(c, n_init, *a.shape[1:]), fits)
    gmm = jax.vmap(_best_restart)(fits)

    def score(gmm_c, x_c, mask_c):
        labels = jnp.where(mask_c, jnp.argmax(_mixture_log_prob(gmm_c, x_c), axis=-1).astype(jnp.int32), -1)
        return labels, _silhouette(x_c, mask_c, labels, slots)

    labels, silhouettes = jax.vmap(score)(gmm, x, mask)
    means = jnp.where(_active(slots, k)[:, None], gmm.means + mean[:, None], 0.0)
    return gmm._replace(means=means), labels, jnp.where(live, silhouettes, jnp.nan)


_STATIC = ("init", "pool_share")
# On a CPU, LLVM at -O1 instead of XLA's default -O2 compiles the kernel in ~60 % of the time and runs it
# as fast (measured on the kernel that fitted every k at once: 12 s against 19 s of compile CPU time).
_fit_k_cpu = jax.jit(_fit_k, static_argnames=_STATIC, compiler_options={"xla_backend_optimization_level": 1})
_fit_k_any = jax.jit(_fit_k, static_argnames=_STATIC)


def _fit_k_kernel():
    """:func:`_fit_k` jitted for the default backend."""
    return _fit_k_cpu if jax.default_backend() == "cpu" else _fit_k_any


def _discover(keys, x, mask, ks, rule, n_init, max_iter, tol, reg_covar, init) -> ModesBatch:
    """The modes of ``x [C, N, D]`` (masked rows 0), ``mask [C, N]`` (validated) with problem keys ``[C]``.

    Fits k = ks[0], ks[1], ... one kernel call per k (one kernel for all, with ``max(ks)`` component slots),
    each problem until its rule has broken (:func:`_break_index`), as the authors' loop stops at its break;
    silhouettes of the ks a problem never fitted are NaN.
    """
    fit_k = _fit_k_kernel()
    silhouettes = np.full((x.shape[0], len(ks)), np.nan)
    live = np.ones(x.shape[0], bool)
    fits = []
    with phase("[modes]", len(ks), unit="k") as bar:
        for j, k in enumerate(ks):
            u = _draws(keys, k, ks[-1], n_init, x.shape[1], init, x.dtype)
            gmm, labels, scores = fit_k(u, x, mask, jnp.asarray(live), jnp.int32(k), max_iter, tol, reg_covar, init)
            fits.append((gmm, labels))
            silhouettes[live, j] = np.asarray(scores, np.float64)[live]
            bar.advance(note=f"k={k} fitted for {int(live.sum())} of {x.shape[0]} problems")
            live = np.array([_break_index(row[:j + 1], rule) is None for row in silhouettes])
            if not live.any():
                break
    if (blank := np.flatnonzero(np.isnan(silhouettes).all(axis=1))).size:
        raise ValueError(f"x: problem {blank[0]} has no silhouette at any k in {list(ks)} (its valid samples sit on "
                         "fewer than 2 distinct points, or in one cluster at every k): no number of modes to choose")
    index = np.array([ks.index(choose_k(row, ks, rule=rule)) for row in silhouettes])
    problems = np.arange(x.shape[0])
    gmm, labels = jax.tree.map(lambda *a: jnp.stack(a)[index, problems], *fits)
    return ModesBatch(np.asarray(ks)[index], gmm, labels, silhouettes, ks)


def discover_modes_batched(key: jax.Array, x: jax.Array, mask: jax.Array | None = None, *,
                           ks: Sequence[int] | None = None, rule: str = "code", n_init: int = 5,
                           max_iter: int = 100, tol: float = 1e-3, reg_covar: float = 1e-6,
                           init: str = "kmeans") -> ModesBatch:
    """ODMO's mode discovery for C independent problems (e.g. each class's latent codes) at once.

    Args:
      key: PRNG key; problem c uses ``split(key, C)[c]`` exactly as :func:`discover_modes` would.
      x: ``[C, N, D]`` samples, each problem padded to N; mask: ``[C, N]`` bool, True for real samples.
      ks: the k to try, increasing (default the rule's: ``MODE_KS[rule]``).
      rule: ``"code"`` or ``"paper"`` (:func:`choose_k`).
      n_init, max_iter, tol, reg_covar, init: the GMM fits (:func:`fit_gmm`; ODMO: k-means init, 5).

    One call per k of one compiled kernel fits every problem with k components (k-means starts vmapped over
    problems and restarts, EM runs in a shared pool) and scores each fit's predicted labels; the ks run in increasing
    order until every problem's rule has broken, as the authors' loop stops at its break, so the chosen k
    is the one a sweep over every k would choose. Silhouettes of the ks a problem never fitted are NaN. Problem c's
    fit with k components reads one uniform draw from ``fold_in(split(key, C)[c], k)``, whichever ks run
    before it, so it differs in its draws (not in distribution) from a :func:`fit_gmm` call. Raises
    ValueError when a problem has fewer valid samples than the largest k, or no silhouette at any k (identical
    samples: scikit-learn's silhouette raises there too). Returns a :class:`ModesBatch`.
    """
    ks = _resolve_ks(ks, rule)
    _check_init(init)
    x = jnp.asarray(x)
    if x.ndim != 3:
        raise ValueError(f"x: expected [C, N, D], got {tuple(x.shape)}")
    c, n, _ = x.shape
    if ks[-1] > n:
        raise ValueError(f"ks: up to k = {ks[-1]} components but x has only N = {n} samples")
    mask = jnp.ones((c, n), bool) if mask is None else jnp.asarray(mask)
    if mask.shape != (c, n) or mask.dtype != bool:
        raise ValueError(f"mask: expected bool [C, N] = ({c}, {n}), got {mask.dtype} {tuple(mask.shape)}")
    if _has_value(mask):
        n_valid = np.asarray(mask.sum(axis=1))
        if (short := np.flatnonzero(n_valid < ks[-1])).size:
            raise ValueError(f"mask: problem {short[0]} has {n_valid[short[0]]} valid samples, fewer than "
                             f"k = {ks[-1]} (the largest of ks)")
    x = jnp.where(mask[..., None], x.astype(jnp.promote_types(x.dtype, jnp.float32)), 0.0)
    return _discover(jax.random.split(key, c), x, mask, ks, rule, n_init, max_iter, tol, reg_covar, init)


def discover_modes(key: jax.Array, x: jax.Array, *, mask: jax.Array | None = None,
                   ks: Sequence[int] | None = None, rule: str = "code", n_init: int = 5, max_iter: int = 100,
                   tol: float = 1e-3, reg_covar: float = 1e-6, init: str = "kmeans") -> Modes:
    """ODMO's mode discovery for one problem ``x [N, D]`` (``mask [N]``): fit a GMM for k = ks[0],
    ks[1], ... until ``rule`` breaks, score each one's predicted labels with :func:`silhouette_score`,
    choose k by ``rule``.

    Arguments as :func:`discover_modes_batched`, whose problem c this is when called with
    ``split(key, C)[c]``. Returns :class:`Modes` with the mixture at the chosen k (k components).
    """
    ks = _resolve_ks(ks, rule)
    _check_init(init)
    x, mask = _check_data(x, mask, ks[-1])
    batch = _discover(key[None], x[None], mask[None], ks, rule, n_init, max_iter, tol, reg_covar, init)
    k = int(batch.k[0])
    gmm = jax.tree.map(lambda a: a[0], batch.gmm)
    gmm = gmm._replace(weights=gmm.weights[:k], means=gmm.means[:k], covariances=gmm.covariances[:k])
    return Modes(k, gmm, batch.labels[0], dict(zip(batch.ks, batch.silhouettes[0].tolist())))
