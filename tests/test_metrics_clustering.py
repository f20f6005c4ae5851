"""The adjusted Rand index: known values, invariances, masks, and agreement with scikit-learn's."""

import jax
import numpy as np
import pytest

from jaxmotion.metrics.clustering import adjusted_rand_index


def test_identical_partitions_score_one_whatever_the_names():
    labels = np.array([0, 0, 1, 1, 2, 2, 2])
    assert float(adjusted_rand_index(labels, labels, 3, 3)) == pytest.approx(1.0)
    assert float(adjusted_rand_index(labels, (labels + 1) % 3, 3, 4)) == pytest.approx(1.0)
    # both one cluster: degenerate, 1 as scikit-learn
    assert float(adjusted_rand_index(np.zeros(5, int), np.zeros(5, int), 1, 1)) == 1.0


def test_a_known_value_and_independent_labelings_near_zero():
    # Hubert & Arabie's example as scikit-learn documents it: [0, 0, 1, 1] vs [0, 0, 1, 2] -> 0.5714...
    assert float(adjusted_rand_index(np.array([0, 0, 1, 1]), np.array([0, 0, 1, 2]), 2, 3)) == pytest.approx(4 / 7)
    rng = np.random.default_rng(0)
    a, b = rng.integers(0, 3, 3000), rng.integers(0, 4, 3000)
    assert abs(float(adjusted_rand_index(a, b, 3, 4))) < 0.01


def test_masked_samples_take_no_part_and_bad_labels_give_nan():
    a = np.array([0, 0, 1, 1, 0, 1])
    b = np.array([1, 1, 0, 0, 0, 0])
    mask = np.array([True, True, True, True, False, False])
    assert float(adjusted_rand_index(a, b, 2, 2, mask)) == pytest.approx(1.0)
    assert np.isnan(float(adjusted_rand_index(a, np.array([0, 0, 1, 1, 0, 5]), 2, 2)))
    assert float(adjusted_rand_index(a, np.array([0, 0, 1, 1, 0, 5]), 2, 2, mask)) == pytest.approx(1.0)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_matches_scikit_learn(seed):
    metrics = pytest.importorskip("sklearn.metrics")
    rng = np.random.default_rng(seed)
    a = rng.integers(0, 4, 200)
    b = np.where(rng.random(200) < 0.6, a, rng.integers(0, 5, 200))
    expected = metrics.adjusted_rand_score(a, b)
    assert float(jax.jit(adjusted_rand_index, static_argnums=(2, 3))(a, b, 4, 5)) == pytest.approx(expected, abs=1e-5)
