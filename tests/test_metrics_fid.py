"""FID kernels: properties, analytical cases, and agreement with Action2Motion's scipy formulation."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from jaxmotion.metrics import (
    aggregate_persons,
    fid,
    fid_class_mean,
    fid_per_class,
    frechet_distance,
    gaussian_stats,
)

scipy_linalg = pytest.importorskip("scipy.linalg")


def reference_fid(a: np.ndarray, b: np.ndarray) -> float:
    """Action2Motion's fid.py in float64: np.cov, scipy sqrtm, real part."""
    a, b = a.astype(np.float64), b.astype(np.float64)
    s1, s2 = np.cov(a, rowvar=False), np.cov(b, rowvar=False)
    covmean = scipy_linalg.sqrtm(s1 @ s2)
    if not np.isfinite(covmean).all():
        eps = 1e-6 * np.eye(s1.shape[0])
        covmean = scipy_linalg.sqrtm((s1 + eps) @ (s2 + eps))
    diff = a.mean(0) - b.mean(0)
    return float(diff @ diff + np.trace(s1) + np.trace(s2) - 2 * np.trace(covmean.real))


def feature_sets(seed: int, n: int = 400, m: int = 300, d: int = 30):
    """Correlated, tanh-squashed features like the recognisers' (not isotropic)."""
    rng = np.random.default_rng(seed)
    mix_a, mix_b = rng.normal(size=(d, d)) / np.sqrt(d), rng.normal(size=(d, d)) / np.sqrt(d)
    a = np.tanh(rng.normal(size=(n, d)) @ mix_a + 0.3)
    b = np.tanh(rng.normal(size=(m, d)) @ mix_b * 1.2)
    return a.astype(np.float32), b.astype(np.float32)


@pytest.mark.parametrize("seed", range(5))
def test_fid_matches_float64_scipy_reference(seed):
    a, b = feature_sets(seed)
    assert float(fid(a, b)) == pytest.approx(reference_fid(a, b), rel=1e-3)


def test_fid_matches_reference_at_paper_size():
    a, b = feature_sets(11, n=3000, m=3000)
    assert float(fid(a, b)) == pytest.approx(reference_fid(a, b), rel=1e-3)


def test_fid_matches_reference_for_close_sets():
    # two draws from one distribution: the small FID values the "Real" rows report
    rng = np.random.default_rng(3)
    mix = rng.normal(size=(30, 30)) / 6
    a = np.tanh(rng.normal(size=(1000, 30)) @ mix).astype(np.float32)
    b = np.tanh(rng.normal(size=(1000, 30)) @ mix).astype(np.float32)
    expected = reference_fid(a, b)
    assert 0 < expected < 0.2
    assert float(fid(a, b)) == pytest.approx(expected, rel=1e-2, abs=1e-4)


def test_fid_of_identical_sets_is_zero():
    a, _ = feature_sets(1)
    assert abs(float(fid(a, a))) < 1e-4


@settings(max_examples=10, deadline=None)
@given(st.integers(0, 2**31 - 1))
def test_fid_is_symmetric(seed):
    a, b = feature_sets(seed, n=120, m=90, d=8)
    assert float(fid(a, b)) == pytest.approx(float(fid(b, a)), rel=1e-4, abs=1e-5)


@settings(max_examples=10, deadline=None)
@given(st.integers(0, 2**31 - 1))
def test_fid_is_invariant_to_translation_and_rotation_of_feature_space(seed):
    a, b = feature_sets(seed, n=120, m=90, d=8)
    rng = np.random.default_rng(seed)
    q, _ = np.linalg.qr(rng.normal(size=(8, 8)))
    shift = rng.normal(size=8)
    moved = fid((a @ q + shift).astype(np.float32), (b @ q + shift).astype(np.float32))
    assert float(moved) == pytest.approx(float(fid(a, b)), rel=1e-3, abs=1e-4)


def test_frechet_distance_is_exact_for_diagonal_gaussians():
    # Tr((Σa Σb)^½) = Σ √(σa σb) for diagonal covariances, so FID = ‖Δμ‖² + Σ (√σa − √σb)²
    var_a = jnp.array([0.5, 2.0, 1.0, 0.1])
    var_b = jnp.array([1.5, 0.5, 1.0, 0.4])
    mu_a, mu_b = jnp.array([0.0, 1.0, -2.0, 0.5]), jnp.array([1.0, 1.0, 0.0, 0.5])
    expected = float(((mu_a - mu_b) ** 2).sum() + ((jnp.sqrt(var_a) - jnp.sqrt(var_b)) ** 2).sum())
    got = frechet_distance(mu_a, jnp.diag(var_a), mu_b, jnp.diag(var_b))
    assert float(got) == pytest.approx(expected, rel=1e-5)


def test_frechet_distance_tolerates_singular_covariances():
    # rank-deficient sets (fewer samples than channels) are where scipy's sqrtm needs its epsilon
    rng = np.random.default_rng(0)
    a, b = rng.normal(size=(5, 30)).astype(np.float32), rng.normal(size=(6, 30)).astype(np.float32)
    value = float(fid(a, b))
    assert np.isfinite(value)
    assert value == pytest.approx(reference_fid(a, b), rel=1e-2)


def test_gaussian_stats_match_numpy_cov_and_weights_select_rows():
    a, _ = feature_sets(2, n=50, d=6)
    mu, sigma = gaussian_stats(a)
    np.testing.assert_allclose(mu, a.mean(0), atol=1e-6)
    np.testing.assert_allclose(sigma, np.cov(a, rowvar=False), atol=1e-5)
    keep = np.arange(50) % 3 == 0
    mu_w, sigma_w = gaussian_stats(a, jnp.asarray(keep))
    np.testing.assert_allclose(mu_w, a[keep].mean(0), atol=1e-6)
    np.testing.assert_allclose(sigma_w, np.cov(a[keep], rowvar=False), atol=1e-5)


def test_fid_per_class_equals_fid_of_each_class_subset():
    a, b = feature_sets(4, n=300, m=240, d=6)
    rng = np.random.default_rng(4)
    la, lb = rng.integers(0, 3, 300), rng.integers(0, 3, 240)
    lb[lb == 2] = 1  # class 2 absent from b: undefined
    per_class = np.asarray(fid_per_class(a, la, b, lb, num_classes=4))
    for c in range(2):
        assert per_class[c] == pytest.approx(reference_fid(a[la == c], b[lb == c]), rel=1e-3)
    assert np.isnan(per_class[2]) and np.isnan(per_class[3])
    assert float(fid_class_mean(a, la, b, lb, 4)) == pytest.approx(per_class[:2].mean(), rel=1e-6)


def test_aggregate_persons_is_channelwise_max_and_order_free():
    x = jax.random.normal(jax.random.key(0), (7, 3, 5))
    out = aggregate_persons(x)
    np.testing.assert_array_equal(out, np.max(np.asarray(x), axis=1))
    np.testing.assert_array_equal(out, aggregate_persons(x[:, ::-1]))


@pytest.mark.parametrize(("a", "b", "match"), [
    ((10, 4), (10, 5), "channels"),
    ((10,), (10, 4), r"features_a: expected features \[N, D\]"),
    ((10, 4), (2, 10, 4), r"features_b: expected features \[N, D\]"),
])
def test_fid_rejects_bad_shapes_naming_the_argument(a, b, match):
    with pytest.raises(ValueError, match=match):
        fid(np.zeros(a, np.float32), np.zeros(b, np.float32))


@pytest.mark.parametrize("side", ["a", "b"])
@pytest.mark.parametrize("bad", [-1, 3])
def test_a_label_outside_the_classes_makes_every_class_fid_nan(side, bad):
    a, b = feature_sets(5, n=60, m=60, d=4)
    la, lb = np.arange(60) % 3, np.arange(60) % 3
    (la if side == "a" else lb)[7] = bad  # dropped or counted as another class, it would move a plausible number
    assert np.isnan(np.asarray(fid_per_class(a, la, b, lb, num_classes=3))).all()
    assert np.isnan(float(fid_class_mean(a, la, b, lb, 3)))
    with pytest.raises(ValueError, match="labels_a: expected integer labels"):
        fid_per_class(a, la.astype(np.float32), b, lb, num_classes=3)
