"""k-means++, k-means, Gaussian-mixture EM, silhouette and ODMO's adaptive K (jaxmotion.mixtures).

scikit-learn and scipy are float64 references (skipped when absent); the rest are properties. Compilation
dominates on a CPU, so the tests share a few shapes (N = 90 samples of D = 3 features, K = 3) and jitted
functions are built once per static-argument set at module level.
"""

import functools
import warnings

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from jaxmotion import mixtures as mx

N, D, K = 90, 3, 3
PAD = 10

gmm_em = jax.jit(mx.gmm_em)
fit_gmm = jax.jit(functools.partial(mx.fit_gmm, k=K, n_init=2))
kmeans_1 = jax.jit(functools.partial(mx.kmeans, k=5, n_init=1))
kmeans_4 = jax.jit(functools.partial(mx.kmeans, k=5, n_init=4))
silhouette = jax.jit(mx.silhouette_score, static_argnames="k")
plusplus = jax.jit(mx.kmeans_plusplus, static_argnums=2)
sample_components = jax.jit(mx.sample_components, static_argnums=3)


def blobs(seed, n_per=N // 3, spread=1.0, distance=10.0):
    """Three Gaussian blobs ``[3·n_per, D]`` (corners of a triangle, ``distance`` apart) and their ids."""
    rng = np.random.default_rng(seed)
    centers = distance * np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 0.9, 0.0]])
    ids = np.repeat(np.arange(3), n_per)
    return (centers[ids] + spread * rng.normal(size=(len(ids), D))).astype(np.float32), ids


def same_partition(a, b):
    """True when the labellings ``a`` and ``b`` differ only by a permutation of label names."""
    a, b = np.asarray(a), np.asarray(b)
    pairs = set(zip(a.tolist(), b.tolist()))
    return len(pairs) == len(set(a.tolist())) == len(set(b.tolist()))


def start_params(x, seed=0):
    """EM starting point for ``x``: three samples as means, equal weights, unit covariances."""
    rng = np.random.default_rng(seed)
    means = x[rng.choice(len(x), K, replace=False)].astype(np.float64)
    return np.full(K, 1.0 / K), means, np.stack([np.eye(D)] * K)


def padded(x):
    """``x`` with PAD garbage rows (huge values and a NaN) appended and the mask that hides them."""
    garbage = np.full((PAD, x.shape[1]), 1e6, np.float32)
    garbage[0, 0] = np.nan
    return np.concatenate([x, garbage]), np.concatenate([np.ones(len(x), bool), np.zeros(PAD, bool)])


def overlapping():
    """Blobs that overlap enough for EM to take several iterations."""
    return blobs(3, distance=3.0)[0]


# --- scikit-learn and scipy references ---------------------------------------------------------------


def sklearn_gmm(x, weights, means, covariances, max_iter):
    mixture = pytest.importorskip("sklearn.mixture")
    exceptions = pytest.importorskip("sklearn.exceptions")
    model = mixture.GaussianMixture(K, covariance_type="full", weights_init=weights, means_init=means,
                                    precisions_init=np.linalg.inv(covariances), reg_covar=1e-6, tol=1e-3,
                                    max_iter=max_iter)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", exceptions.ConvergenceWarning)
        return model.fit(np.asarray(x, np.float64))


def test_em_from_same_start_matches_sklearn():
    x = overlapping()
    start = start_params(x)
    ours = gmm_em(x, *start, max_iter=100, tol=1e-3, reg_covar=1e-6)
    ref = sklearn_gmm(x, *start, max_iter=100)
    assert bool(ours.converged) and ref.converged_
    assert int(ours.n_iter) == ref.n_iter_ > 3
    np.testing.assert_allclose(float(ours.lower_bound), ref.lower_bound_, rtol=1e-5)
    np.testing.assert_allclose(ours.weights, ref.weights_, atol=1e-4)
    np.testing.assert_allclose(ours.means, ref.means_, atol=1e-3)
    np.testing.assert_allclose(ours.covariances, ref.covariances_, atol=1e-3)


def test_one_em_step_matches_sklearn():
    x = overlapping()
    start = start_params(x, seed=1)
    ours = gmm_em(x, *start, max_iter=1, tol=1e-3, reg_covar=1e-6)
    ref = sklearn_gmm(x, *start, max_iter=1)
    assert int(ours.n_iter) == 1 and not bool(ours.converged)
    np.testing.assert_allclose(float(ours.lower_bound), ref.lower_bound_, rtol=1e-6)
    np.testing.assert_allclose(ours.weights, ref.weights_, atol=1e-6)
    np.testing.assert_allclose(ours.means, ref.means_, atol=1e-5)
    np.testing.assert_allclose(ours.covariances, ref.covariances_, rtol=1e-5, atol=1e-5)


def test_fit_gmm_reaches_sklearn_optimum_on_separated_blobs():
    mixture = pytest.importorskip("sklearn.mixture")
    x, ids = blobs(0)
    ours = fit_gmm(jax.random.key(0), x)
    ref = mixture.GaussianMixture(K, covariance_type="full", n_init=2, random_state=0).fit(x.astype(np.float64))
    np.testing.assert_allclose(float(ours.lower_bound), ref.lower_bound_, rtol=1e-5)
    order = np.argsort(np.asarray(ours.means)[:, 0] + 2 * np.asarray(ours.means)[:, 1])
    ref_order = np.argsort(ref.means_[:, 0] + 2 * ref.means_[:, 1])
    np.testing.assert_allclose(np.asarray(ours.means)[order], ref.means_[ref_order], atol=1e-4)
    np.testing.assert_allclose(np.asarray(ours.weights)[order], ref.weights_[ref_order], atol=1e-5)
    assert same_partition(mx.gmm_predict(ours, x), ids)


def labelled(seed):
    """N samples in 3-D with labels 0..5: label 4 unused, label 5 a single sample."""
    rng = np.random.default_rng(seed)
    x = rng.normal(size=(N, D)).astype(np.float32)
    labels = rng.choice([0, 1, 2, 3], size=N)
    labels[rng.integers(N)] = 5
    return x, labels.astype(np.int32)


@settings(max_examples=10)
@given(seed=st.integers(0, 2**16))
def test_silhouette_matches_sklearn(seed):
    metrics = pytest.importorskip("sklearn.metrics")
    x, labels = labelled(seed)
    ours = float(silhouette(x, labels, k=6))
    np.testing.assert_allclose(ours, metrics.silhouette_score(x.astype(np.float64), labels), atol=1e-5)


def test_log_prob_matches_scipy():
    stats = pytest.importorskip("scipy.stats")
    rng = np.random.default_rng(0)
    a = rng.normal(size=(K, D, D))
    covariances = a @ a.transpose(0, 2, 1) + 0.5 * np.eye(D)
    weights, means = np.array([0.2, 0.3, 0.5]), 3.0 * rng.normal(size=(K, D))
    x = 3.0 * rng.normal(size=(N, D))
    gmm = mx.GaussianMixture(*(jnp.asarray(v, jnp.float32) for v in (weights, means, covariances)))
    density = sum(w * stats.multivariate_normal(m, c).pdf(x) for w, m, c in zip(weights, means, covariances))
    np.testing.assert_allclose(mx.gmm_log_prob(gmm, x.astype(np.float32)), np.log(density), rtol=1e-5)
    np.testing.assert_allclose(mx.gmm_responsibilities(gmm, x.astype(np.float32)).sum(axis=1), 1.0, rtol=1e-6)


# --- properties ------------------------------------------------------------------------------------------


def test_discover_modes_finds_three_separated_blobs():
    x, ids = blobs(0)
    modes = mx.discover_modes(jax.random.key(0), x, ks=range(3, 6))
    # Three clear blobs: S_3 is high and splitting any blob (k = 4) drops it below 0.95 · S_3.
    assert modes.silhouettes[4] < 0.95 * modes.silhouettes[3]
    assert modes.k == 3 and modes.gmm.means.shape == (3, D)
    assert same_partition(modes.labels, ids)


def test_discover_batched_equals_per_problem_calls():
    (x_a, _), (x_b, _) = blobs(1), blobs(2, spread=2.0)
    x_pad, mask_a = padded(x_a[:-PAD])
    x = np.stack([x_pad, x_b])
    mask = np.stack([mask_a, np.ones(N, bool)])
    key = jax.random.key(3)
    batch = mx.discover_modes_batched(key, x, mask, ks=range(3, 6))
    for c, key_c in enumerate(jax.random.split(key, 2)):
        one = mx.discover_modes(key_c, x[c], mask=mask[c], ks=range(3, 6))
        assert one.k == batch.k[c]
        np.testing.assert_array_equal(one.labels, batch.labels[c])
        np.testing.assert_allclose(list(one.silhouettes.values()), batch.silhouettes[c], rtol=1e-5)
        np.testing.assert_allclose(one.gmm.means, batch.gmm.means[c, :one.k], rtol=1e-4, atol=1e-4)
        assert (np.asarray(batch.gmm.weights[c, one.k:]) == 0).all()
    assert (np.asarray(batch.labels[0, -PAD:]) == -1).all()


def _every_k(key, x, ks, slots=None):
    """Every problem of ``x [C, N, D]`` fitted with every k of ``ks`` (no break): the discovery kernel with all
    problems live and ``slots`` (default ``max(ks)``) component slots -> one (gmm, labels, silhouettes) per k."""
    keys, live, mask = jax.random.split(key, len(x)), jnp.ones(len(x), bool), jnp.ones(x.shape[:2], bool)
    return [mx._fit_k_kernel()(mx._draws(keys, k, slots or ks[-1], 5, x.shape[1], "kmeans", jnp.float32),
                               jnp.asarray(x), mask, live, jnp.int32(k), 100, 1e-3, 1e-6, "kmeans") for k in ks]


def test_discovery_stops_at_every_break_and_chooses_as_the_full_sweep():
    # Three blobs break at k = 4, five at k = 6: each problem's fits stop there, and the sweep after k = 6.
    rng = np.random.default_rng(5)
    angles = 2 * np.pi * np.arange(5) / 5
    five = 10.0 * np.stack([np.cos(angles), np.sin(angles), np.zeros(5)], axis=1)[np.arange(N) % 5]
    x = np.stack([blobs(8)[0], (five + rng.normal(size=(N, D))).astype(np.float32)])
    key, ks = jax.random.key(4), range(3, 9)
    batch = mx.discover_modes_batched(key, x, ks=ks)
    # Each k's fit reads the same draws (fold_in of the problem's key by k) whichever ks ran before it.
    alone = _every_k(key, x, ks)
    full = np.stack([silhouettes for _, _, silhouettes in alone], axis=1)
    assert list(batch.k) == [3, 5]
    assert [mx.choose_k(row, list(ks)) for row in full] == [3, 5]
    for c, fitted in enumerate([2, 4]):  # k = 3..4 and 3..6
        np.testing.assert_allclose(batch.silhouettes[c, :fitted], full[c, :fitted], rtol=1e-6)
        assert np.isnan(batch.silhouettes[c, fitted:]).all()
    for c, k in enumerate(batch.k):
        gmm, labels, _ = alone[k - 3]
        np.testing.assert_array_equal(batch.labels[c], labels[c])
        np.testing.assert_allclose(batch.gmm.means[c], gmm.means[c], rtol=1e-6)
        assert (np.asarray(batch.gmm.weights[c, k:]) == 0).all() and batch.gmm.means.shape[1] == 8


def test_component_slots_past_k_change_nothing():
    # One kernel serves every k: k = 3 of 8 slots (8 has one k-means++ candidate more than 3) fits as 3 of 3.
    x = np.stack([blobs(8)[0], overlapping()])
    key, k = jax.random.key(2), 3
    (narrow, narrow_labels, narrow_s), = _every_k(key, x, [k])
    (wide, wide_labels, wide_s), = _every_k(key, x, [k], slots=8)
    np.testing.assert_array_equal(wide_labels, narrow_labels)
    np.testing.assert_allclose(wide_s, narrow_s, rtol=1e-6)
    for a, b in zip(narrow[:3], wide[:3]):
        np.testing.assert_allclose(b[:, :k], a, rtol=1e-5, atol=1e-6)
    assert (np.asarray(wide.weights[:, k:]) == 0).all() and (np.asarray(wide.means[:, k:]) == 0).all()
    np.testing.assert_array_equal(wide.covariances[:, k:], np.broadcast_to(np.float32(1e-6) * np.eye(D, dtype=np.float32), (2, 5, D, D)))


def test_silhouette_is_invariant_to_sample_order():
    x, labels = blobs(4)
    perm = np.random.default_rng(0).permutation(N)
    np.testing.assert_allclose(silhouette(x[perm], labels[perm], k=K), silhouette(x, labels, k=K), rtol=1e-6)


def test_em_is_invariant_to_sample_order():
    x = overlapping()
    start = start_params(x)
    perm = np.random.default_rng(1).permutation(N)
    fit, shuffled = gmm_em(x, *start), gmm_em(x[perm], *start)
    assert int(fit.n_iter) == int(shuffled.n_iter)
    for a, b in zip(fit[:4], shuffled[:4]):
        np.testing.assert_allclose(a, b, rtol=1e-5, atol=1e-5)


def test_masked_rows_change_nothing():
    x = blobs(5)[0]
    x_pad, mask = padded(x)
    fit = fit_gmm(jax.random.key(1), x)
    labels, labels_pad = mx.gmm_predict(fit, x), mx.gmm_predict(fit, x_pad, mask)
    np.testing.assert_array_equal(labels_pad, np.concatenate([labels, np.full(PAD, -1)]))
    np.testing.assert_allclose(silhouette(x_pad, labels_pad, k=K, mask=mask), silhouette(x, labels, k=K),
                               rtol=1e-5)
    seeds = plusplus(jax.random.key(1), x_pad, K, mask)
    assert np.isin(np.asarray(seeds), x).all(axis=1).all()


def test_same_key_same_result_and_new_key_new_restarts():
    x = overlapping()
    a, b = fit_gmm(jax.random.key(7), x), fit_gmm(jax.random.key(7), x)
    for leaf_a, leaf_b in zip(a, b):
        np.testing.assert_array_equal(leaf_a, leaf_b)
    x_pad, mask = padded(x)
    seeds = [np.asarray(plusplus(jax.random.key(s), x_pad, K, mask)) for s in range(3)]
    assert not all(np.array_equal(seeds[0], s) for s in seeds[1:])


def test_vmapped_fit_on_padded_problems_equals_per_problem_fits():
    # Each problem padded with masked garbage rows (huge values, a NaN): padding moves no draw and no sum.
    problems = blobs(6)[0], overlapping()
    x, mask = map(np.stack, zip(*map(padded, problems)))
    keys = jax.random.split(jax.random.key(2), 2)
    batch = jax.jit(jax.vmap(functools.partial(mx.fit_gmm, k=K, n_init=2)))(keys, x, mask=mask)
    for c, problem in enumerate(problems):
        one = fit_gmm(keys[c], problem)
        assert int(one.n_iter) == int(batch.n_iter[c])
        for a, b in zip(one, batch):
            np.testing.assert_allclose(a, b[c], rtol=1e-5, atol=1e-5)


def test_em_pool_gives_every_run_its_own_iterations():
    # The engine of discover_modes_batched: 6 runs on two data sets through 2 slots, against each run alone.
    data = np.stack([overlapping(), blobs(7)[0]])
    owner = np.array([0, 1, 0, 1, 0, 0])
    starts = [start_params(data[o], seed=i) for i, o in enumerate(owner)]
    weights, means, covariances = (np.stack(p).astype(np.float32) for p in zip(*starts))
    pooled = jax.jit(mx._em_pool, static_argnums=7)(
        jnp.asarray(data), jnp.ones((2, N)), jnp.asarray(owner),
        mx._em_start(jnp.asarray(weights), jnp.asarray(means), jnp.asarray(covariances)), 100, 1e-3, 1e-6, 2)
    for i, o in enumerate(owner):
        alone = gmm_em(data[o], *starts[i])
        assert int(pooled.n_iter[i]) == int(alone.n_iter)
        for a, b in zip(alone[:4], pooled[:4]):
            np.testing.assert_allclose(b[i], a, rtol=1e-4, atol=1e-4)


def test_kmeans_inertia_never_increases_with_n_init():
    # Five blobs in a row: k-means++ starts often end in a local optimum that merges two of them.
    rng = np.random.default_rng(0)
    x = np.repeat(np.arange(5.0), 18)[:, None] * np.array([4.0, 0, 0]) + rng.normal(size=(N, D))
    x = x.astype(np.float32)
    gains = []
    for seed in range(6):
        one, four = kmeans_1(jax.random.key(seed), x), kmeans_4(jax.random.key(seed), x)
        assert float(four.inertia) <= float(one.inertia) * (1 + 1e-6)
        gains.append(float(one.inertia) - float(four.inertia))
        assert float(four.inertia) == pytest.approx(float(jnp.sum((x - four.centers[four.labels]) ** 2)), rel=1e-5)
    assert max(gains) > 0  # restarts do find better optima here


def test_sample_gmm_moments_approach_the_mixture():
    weights = jnp.array([0.3, 0.7])
    means = jnp.array([[0.0, 0.0], [4.0, 1.0]])
    covariances = jnp.array([[[1.0, 0.5], [0.5, 2.0]], [[0.5, -0.2], [-0.2, 0.3]]])
    gmm = mx.GaussianMixture(weights, means, covariances)
    samples = np.asarray(jax.jit(mx.sample_gmm, static_argnums=2)(jax.random.key(0), gmm, 40_000), np.float64)
    mean = np.asarray(weights @ means)
    second = np.einsum("k,kde->de", weights, covariances + means[:, :, None] * means[:, None, :])
    np.testing.assert_allclose(samples.mean(0), mean, atol=0.03)
    np.testing.assert_allclose(np.cov(samples.T, bias=True), second - np.outer(mean, mean), atol=0.05)


def test_sample_components_draws_each_component_its_count():
    gmm = mx.GaussianMixture(jnp.array([0.5, 0.2, 0.3]), jnp.array([[0.0], [10.0], [-10.0]]),
                             jnp.full((3, 1, 1), 0.01))
    counts = np.array([3000, 0, 2000], np.int32)
    samples, components = sample_components(jax.random.key(0), gmm, counts, 5000)
    np.testing.assert_array_equal(components, np.repeat(np.arange(3), counts))
    np.testing.assert_allclose(samples[:3000].mean(), 0.0, atol=0.01)
    np.testing.assert_allclose(samples[3000:].mean(), -10.0, atol=0.01)
    # Under jit counts cannot be checked: rows past their sum are marked, not silently drawn.
    short, ids = sample_components(jax.random.key(0), gmm, counts - np.array([3, 0, 0], np.int32), 5000)
    assert (np.asarray(ids[-3:]) == -1).all() and np.isnan(np.asarray(short[-3:])).all()


@pytest.mark.parametrize("rule, scores, expected", [
    ("code", [0.5, 0.6, 0.4, 0.8, 0.7, 0.6, 0.5], 4),  # 0.4 < 0.95 · 0.6 at k = 5
    ("code", [0.5, 0.3, 0.8, 0.8, 0.8, 0.8, 0.8], 3),  # breaks at the first step
    ("code", [0.5, 0.49, 0.48, 0.47, 0.46, 0.45, 0.44], 9),  # drops under 5 % never break
    ("code", [0.5, np.nan, 0.3, 0.3, 0.3, 0.3, 0.3], 9),  # NaN never breaks, nor does a value after it
    ("paper", [0.5, 0.6, 0.7, 0.6, 0.9, 1.0, 1.1, 1.2, 1.3], 5),  # 0.7 > 0.95 · 0.6 at k = 5
    ("paper", [0.5, 0.4, 0.9, 0.9, 0.9, 0.9, 0.9, 0.9, 0.9], 3),
    ("paper", [1.1**i for i in range(9)], 11),  # every step gains over 5 %: no break
])
def test_choose_k_rules_on_written_silhouettes(rule, scores, expected):
    ks = list(mx.MODE_KS[rule])
    assert mx.choose_k(scores, ks, rule=rule) == expected
    assert mx.choose_k(dict(zip(ks, scores)), rule=rule) == expected


def test_bad_inputs_raise_naming_the_argument():
    x = np.zeros((5, 2), np.float32)
    with pytest.raises(ValueError, match=r"x: expected \[N, D\], got \(3,\)"):
        mx.fit_gmm(jax.random.key(0), np.zeros(3), 2)
    with pytest.raises(ValueError, match=r"mask: expected bool \[N\] = \(5,\)"):
        mx.kmeans(jax.random.key(0), x, 2, mask=np.ones(4, bool))
    with pytest.raises(ValueError, match="mask: 2 valid samples, fewer than k = 3"):
        mx.fit_gmm(jax.random.key(0), x, 3, mask=np.array([1, 1, 0, 0, 0], bool))
    with pytest.raises(ValueError, match="k: 6 components but x has only N = 5"):
        mx.kmeans_plusplus(jax.random.key(0), x, 6)
    with pytest.raises(ValueError, match=r"covariances: expected \[K, D, D\]"):
        mx.gmm_em(x, np.ones(2) / 2, np.zeros((2, 2)), np.zeros((2, 2)))
    with pytest.raises(ValueError, match=r"labels: expected integer \[N\]"):
        mx.silhouette_score(x, np.zeros(5), 2)
    with pytest.raises(ValueError, match="counts: expected non-negative counts summing to total = 4"):
        mx.sample_components(jax.random.key(0), mx.GaussianMixture(jnp.ones(2) / 2, jnp.zeros((2, 2)),
                                                                  jnp.stack([jnp.eye(2)] * 2)),
                             np.array([1, 2], np.int32), 4)
    with pytest.raises(ValueError, match="rule: expected 'code' or 'paper'"):
        mx.choose_k([0.1, 0.2], [3, 4], rule="papers")
    with pytest.raises(ValueError, match="mask: problem 1 has 4 valid samples, fewer than k = 5"):
        mask = np.ones((2, 6), bool)
        mask[1, :2] = False
        mx.discover_modes_batched(jax.random.key(0), np.zeros((2, 6, 2)), mask, ks=range(3, 6))
    with pytest.raises(ValueError, match="mask: 4 valid samples, fewer than k = 9"):
        mx.discover_modes(jax.random.key(0), np.zeros((12, 2)), mask=np.arange(12) < 4)


def test_identical_samples_have_no_modes_to_choose():
    # Every k puts all samples in one cluster: no silhouette anywhere, so no k is chosen (it used to be the last k).
    x = np.stack([blobs(0)[0], np.ones((N, D), np.float32)])
    with pytest.raises(ValueError, match="problem 1 has no silhouette at any k"):
        mx.discover_modes_batched(jax.random.key(0), x, ks=range(3, 5))
