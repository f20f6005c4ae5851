"""Accuracy, confusion matrix, diversity and multimodality (Action2Motion's definitions)."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.metrics import (
    accuracy,
    confusion_matrix,
    diversity,
    mean_class_recall,
    multimodality,
)


def test_confusion_matrix_counts_each_pair_and_accuracy_is_its_trace_share():
    labels = jnp.array([0, 0, 1, 1, 1, 2])
    predicted = jnp.array([0, 1, 1, 1, 2, 2])
    conf = confusion_matrix(labels, predicted, num_classes=3)
    np.testing.assert_array_equal(conf, [[1, 1, 0], [0, 2, 1], [0, 0, 1]])
    assert float(accuracy(conf)) == pytest.approx(4 / 6)
    assert float(mean_class_recall(conf)) == pytest.approx((1 / 2 + 2 / 3 + 1) / 3)


def test_mean_class_recall_skips_absent_classes_and_equals_accuracy_when_balanced():
    rng = np.random.default_rng(0)
    labels = np.repeat(np.arange(4), 25)
    predicted = np.where(rng.random(100) < 0.7, labels, rng.integers(0, 4, 100))
    conf = confusion_matrix(jnp.asarray(labels), jnp.asarray(predicted), num_classes=5)
    assert float(mean_class_recall(conf)) == pytest.approx(float(accuracy(conf)), rel=1e-6)


def _expected_pair_distance(features):
    """E‖f_i − f_j‖ for i, j independent uniform (i = j allowed), the quantity both metrics estimate."""
    d = np.linalg.norm(features[:, None] - features[None], axis=-1)
    return d.mean()


def _a2m_multimodality(features, labels, num_classes, pairs, rng):
    """Action2Motion's loop, verbatim in behaviour: quota per label, partner redrawn until labels match."""
    quota = np.full(num_classes, pairs)
    total = 0.0
    while np.any(quota > 0):
        i = rng.integers(0, len(labels))
        if not quota[labels[i]]:
            continue
        j = rng.integers(0, len(labels))
        while labels[j] != labels[i]:
            j = rng.integers(0, len(labels))
        quota[labels[i]] -= 1
        total += np.linalg.norm(features[i] - features[j])
    return total / (pairs * num_classes)


def test_diversity_estimates_the_mean_pairwise_distance():
    features = np.asarray(jax.random.normal(jax.random.key(1), (60, 5)))
    estimate = float(diversity(jax.random.key(2), features, pairs=40_000))
    assert estimate == pytest.approx(_expected_pair_distance(features), rel=0.02)


def test_diversity_with_paper_pair_count_uses_the_drawn_pairs():
    features = jax.random.normal(jax.random.key(3), (30, 4))
    key = jax.random.key(4)
    k1, k2 = jax.random.split(key)
    first, second = jax.random.randint(k1, (200,), 0, 30), jax.random.randint(k2, (200,), 0, 30)
    f = np.asarray(features, np.float64)
    expected = np.mean([np.linalg.norm(f[i] - f[j]) for i, j in zip(np.asarray(first), np.asarray(second))])
    assert float(diversity(key, features)) == pytest.approx(expected, rel=1e-5)


def test_multimodality_agrees_with_action2motion_loop_and_exact_expectation():
    rng = np.random.default_rng(5)
    labels = rng.integers(0, 4, 200)
    features = rng.normal(size=(200, 6)) * (1 + labels[:, None])  # class spreads differ
    exact = np.mean([_expected_pair_distance(features[labels == c]) for c in range(4)])
    ours = float(multimodality(jax.random.key(0), features.astype(np.float32), labels, 4, pairs=20_000))
    theirs = _a2m_multimodality(features, labels, 4, 5_000, np.random.default_rng(6))
    assert ours == pytest.approx(exact, rel=0.02)
    assert theirs == pytest.approx(exact, rel=0.03)


def test_multimodality_is_zero_when_each_class_collapses_to_one_point():
    labels = jnp.array([0, 0, 1, 1, 2, 2])
    features = jnp.repeat(jnp.eye(3), 2, axis=0)
    assert float(multimodality(jax.random.key(0), features, labels, 3)) == 0.0
    assert float(diversity(jax.random.key(0), features)) > 0.0


def test_multimodality_ignores_absent_classes():
    labels = jnp.array([0, 0, 0, 2, 2, 2])
    features = jax.random.normal(jax.random.key(7), (6, 3))
    key = jax.random.key(8)
    with_gap = multimodality(key, features, labels, 3)
    assert np.isfinite(float(with_gap))


def test_same_key_same_value_and_keys_matter():
    features = jax.random.normal(jax.random.key(9), (50, 8))
    labels = jnp.arange(50) % 5
    a = multimodality(jax.random.key(1), features, labels, 5)
    assert float(a) == float(multimodality(jax.random.key(1), features, labels, 5))
    assert float(a) != float(multimodality(jax.random.key(2), features, labels, 5))


def test_bad_shapes_name_the_argument():
    with pytest.raises(ValueError, match=r"labels: expected integer \[N\]"):
        multimodality(jax.random.key(0), jnp.zeros((5, 3)), jnp.zeros(4, jnp.int32), 2)
    with pytest.raises(ValueError, match=r"features: expected \[N, D\]"):
        diversity(jax.random.key(0), jnp.zeros((5,)))


@pytest.mark.parametrize("bad", [-1, 3])
def test_a_label_outside_the_classes_makes_multimodality_nan(bad):
    features = jax.random.normal(jax.random.key(3), (12, 4))
    labels = jnp.arange(12) % 3
    assert np.isfinite(float(multimodality(jax.random.key(0), features, labels, 3)))
    assert np.isnan(float(multimodality(jax.random.key(0), features, labels.at[5].set(bad), 3)))


def test_diversity_of_one_sample_is_refused_not_zero():
    with pytest.raises(ValueError, match="at least 2 samples, got N = 1"):
        diversity(jax.random.key(0), jnp.ones((1, 3)))
    with pytest.raises(ValueError, match=r"labels: expected integer \[N\]"):
        multimodality(jax.random.key(0), jnp.zeros((4, 3)), jnp.zeros(4), 2)
