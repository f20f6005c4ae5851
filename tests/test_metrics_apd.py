"""APD, n-APD and mode-homogeneity (ODMO): properties, hand-computed cases and a float64 numpy reference.

Every kernel runs eagerly and under ``jax.jit`` (the ``compile`` fixture). Compilation dominates on a CPU
(eager mode compiles each operation once per shape), so almost every test uses the same N = 13 motions of
[T, J] = [4, 3], and jitted functions are built once per static-argument set.
"""


import jax
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from jaxmotion.metrics.apd import apd, apd_per_class, mode_homogeneity, n_apd

T, J = 4, 3
RTOL = 1e-4




def motions(seed, n=13, offset=0.0):
    return (np.random.default_rng(seed).normal(size=(n, T, J, 3)) + offset).astype(np.float32)


# --- float64 reference, written from the paper's formula ---------------------------------------------


def reference_apd(x):
    flat = np.asarray(x, np.float64).reshape(len(x), -1)
    n = len(flat)
    if n < 2:
        return np.nan
    total = 0.0
    for i in range(n):
        for j in range(n):
            if i != j:
                total += np.sqrt(np.sum((flat[i] - flat[j]) ** 2))
    return total / (n * (n - 1))


def reference_apd_per_class(x, labels, num_classes):
    return np.array([reference_apd(x[labels == c]) for c in range(num_classes)])


def reference_mode_homogeneity(x, labels, modes, num_classes):
    drops = []
    for c in range(num_classes):
        members = x[labels == c]
        member_modes = modes[labels == c]
        mode_apd = 0.0
        for k in np.unique(member_modes):
            group = members[member_modes == k]
            if len(group) > 1:  # a one-motion mode has no pair: it contributes 0
                mode_apd += len(group) * reference_apd(group)
        mode_apd /= len(members)
        class_apd = reference_apd(members)
        drops.append((class_apd - mode_apd) / class_apd)
    return 100.0 * np.mean(drops)


# Unequal class sizes, shuffled order, and a large per-class offset (the centring must cancel it).
LABELS = np.array([2, 0, 1, 0, 2, 2, 1, 0, 0, 2, 1, 0, 2])
OFFSETS = np.array([0.0, 100.0, -30.0])
RANK = np.array([np.sum(LABELS[:i] == label) for i, label in enumerate(LABELS)])  # index within its class
K = RANK.max() + 1  # num_modes for every mode-homogeneity test: one compilation


def labelled_motions(seed):
    return motions(seed, len(LABELS)) + OFFSETS[LABELS][:, None, None, None].astype(np.float32)


# --- APD ---------------------------------------------------------------------------------------------


def test_apd_per_class_matches_numpy_reference(compile):
    x = labelled_motions(0)
    got = compile(apd_per_class, "num_classes")(x, LABELS, 3)
    np.testing.assert_allclose(got, reference_apd_per_class(x, LABELS, 3), rtol=RTOL)


def test_apd_matches_numpy_reference(compile):
    x = motions(1, offset=5.0)
    np.testing.assert_allclose(compile(apd)(x), reference_apd(x), rtol=RTOL)


def test_apd_of_two_motions_is_their_distance(compile):
    x = labelled_motions(1)
    pair = np.flatnonzero(LABELS == 1)[:2]
    labels = np.where(np.isin(np.arange(len(LABELS)), pair), 1, 0)
    x[pair] = 0.0
    x[pair[1], 0, 0] = [3.0, 0.0, 4.0]  # one coordinate triple differs: distance 5
    x[pair[1], 2, 1, 1] = 12.0  # sqrt(25 + 144) = 13
    np.testing.assert_allclose(compile(apd_per_class, "num_classes")(x, labels, 3)[1], 13.0, rtol=RTOL)


def test_apd_is_zero_for_identical_motions(compile):
    x = np.repeat(motions(2, 1, offset=3.0), len(LABELS), axis=0)
    np.testing.assert_allclose(compile(apd)(x), 0.0, atol=1e-6)


@given(seed=st.integers(0, 2**16), shift=st.lists(st.floats(-50, 50), min_size=3, max_size=3))
def test_apd_is_invariant_to_translation_and_sample_order(seed, shift):
    x = labelled_motions(seed)
    order = np.random.default_rng(seed).permutation(len(LABELS))
    moved = x[order] + np.asarray(shift, np.float32)
    jitted = jax.jit(apd_per_class, static_argnames="num_classes")
    np.testing.assert_allclose(jitted(moved, LABELS[order], 3), jitted(x, LABELS, 3), rtol=RTOL)


@pytest.mark.parametrize("scale", [0.5, -2.0, 10.0])
def test_apd_scales_with_the_absolute_scale_factor(compile, scale):
    x = motions(3)
    np.testing.assert_allclose(compile(apd)(scale * x), abs(scale) * compile(apd)(x), rtol=RTOL)


def test_apd_per_class_is_nan_for_classes_with_fewer_than_two_samples(compile):
    labels = np.zeros(len(LABELS), int)
    labels[5] = 1
    got = compile(apd_per_class, "num_classes")(motions(4), labels, 3)
    assert np.isfinite(got[0]) and np.isnan(got[1]) and np.isnan(got[2])


@pytest.mark.parametrize("bad_label", [-1, 3])
def test_out_of_range_label_makes_every_class_nan(compile, bad_label):
    labels = LABELS.copy()
    labels[4] = bad_label
    assert np.isnan(compile(apd_per_class, "num_classes")(labelled_motions(5), labels, 3)).all()


# --- n-APD -------------------------------------------------------------------------------------------


def test_n_apd_of_real_against_itself_is_100(compile):
    x = labelled_motions(6)
    np.testing.assert_allclose(compile(n_apd, "num_classes")(x, LABELS, x, LABELS, 3), 100.0, rtol=RTOL)


def test_n_apd_is_200_when_generated_motions_are_twice_as_spread(compile):
    x = labelled_motions(7)
    got = compile(n_apd, "num_classes")(2.0 * x, LABELS, x, LABELS, 3)
    np.testing.assert_allclose(got, 200.0, rtol=RTOL)


def test_n_apd_matches_numpy_reference(compile):
    real = labelled_motions(8)
    generated_labels = np.array([0, 1, 2, 1, 0, 2, 1, 2, 1, 1, 0, 2, 2])
    generated = motions(9)
    got = compile(n_apd, "num_classes")(generated, generated_labels, real, LABELS, 3)
    ratio = reference_apd_per_class(generated, generated_labels, 3) / reference_apd_per_class(real, LABELS, 3)
    np.testing.assert_allclose(got, 100.0 * ratio.mean(), rtol=RTOL)


def test_n_apd_is_nan_when_a_class_cannot_form_a_pair(compile):
    x = labelled_motions(10)
    generated_labels = np.zeros(len(LABELS), int)
    generated_labels[0] = 1  # class 1 has one generated sample, class 2 none
    assert np.isnan(compile(n_apd, "num_classes")(x, generated_labels, x, LABELS, 3))


def test_n_apd_is_nan_when_a_real_class_has_no_spread(compile):
    x = labelled_motions(17)
    real = x.copy()
    real[LABELS == 1] = real[LABELS == 1][0]  # class 1: identical real motions, APD 0
    assert np.isnan(compile(n_apd, "num_classes")(x, LABELS, real, LABELS, 3))


# --- mode-homogeneity --------------------------------------------------------------------------------


def test_mode_homogeneity_is_zero_when_each_class_is_one_mode(compile):
    fn = compile(mode_homogeneity, ("num_classes", "num_modes"))
    np.testing.assert_allclose(fn(labelled_motions(11), LABELS, np.zeros_like(LABELS), 3, K), 0.0, atol=1e-4)


def test_mode_homogeneity_is_100_when_every_mode_is_one_motion(compile):
    fn = compile(mode_homogeneity, ("num_classes", "num_modes"))
    np.testing.assert_allclose(fn(labelled_motions(12), LABELS, RANK, 3, K), 100.0, rtol=RTOL)


def test_mode_homogeneity_of_two_tight_clusters_is_near_100(compile):
    # Two modes per class far apart, each with a tiny spread: the within-mode APD is almost nothing.
    x = motions(13) * 1e-3
    modes = RANK % 2
    x[modes == 1] += 1.0
    got = compile(mode_homogeneity, ("num_classes", "num_modes"))(x, LABELS, modes, 3, K)
    assert 99.0 < got <= 100.0


def test_mode_homogeneity_matches_numpy_reference(compile):
    x = labelled_motions(15)
    # Mode ids are per class (0 and 1 recur across classes); class 1 has a one-motion mode.
    modes = np.array([0, 1, 0, 0, 1, 0, 1, 1, 0, 2, 0, 0, 1])
    got = compile(mode_homogeneity, ("num_classes", "num_modes"))(x, LABELS, modes, 3, K)
    np.testing.assert_allclose(got, reference_mode_homogeneity(x, LABELS, modes, 3), rtol=RTOL)


@pytest.mark.parametrize("bad_mode", [-1, K])
def test_out_of_range_mode_makes_mode_homogeneity_nan(compile, bad_mode):
    modes = np.zeros_like(LABELS)
    modes[0] = bad_mode
    assert np.isnan(compile(mode_homogeneity, ("num_classes", "num_modes"))(labelled_motions(16), LABELS, modes, 3, K))


# --- input validation --------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: apd(np.zeros((4, 60, 24))), r"motions: expected \[N, T, J, 3\], got \(4, 60, 24\)"),
        (lambda: apd(np.zeros((4, 60, 24, 2))), r"motions: expected \[N, T, J, 3\]"),
        (lambda: apd_per_class(np.zeros((4, T, J, 3)), np.zeros(3, int), 2), r"labels: expected integer \[N\]"),
        (lambda: apd_per_class(np.zeros((4, T, J, 3)), np.zeros(4), 2), r"labels: expected integer \[N\]"),
        (lambda: n_apd(np.zeros((4, T, J, 3)), np.zeros(4, int), np.zeros((T, J, 3)), np.zeros(4, int), 1),
         r"real: expected \[N, T, J, 3\], got \(4, 3, 3\)"),
        (lambda: n_apd(np.zeros((4, T, J, 3)), np.zeros(5, int), np.zeros((4, T, J, 3)), np.zeros(4, int), 1),
         r"generated_labels: expected integer \[N\] = \(4,\)"),
        (lambda: mode_homogeneity(np.zeros((4, T, J, 3)), np.zeros(4, int), np.zeros((4, 1), int), 1, 1),
         r"modes: expected integer \[N\]"),
    ],
)
def test_bad_shapes_raise_value_error_naming_the_argument(call, message):
    with pytest.raises(ValueError, match=message):
        call()
