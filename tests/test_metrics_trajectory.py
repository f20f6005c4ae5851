"""ΔTraj and ΔJPE (Neural Marionette) and dist_e / end-point hit rate (ODMO): properties, hand cases, numpy reference.

Every kernel runs eagerly and under ``jax.jit`` (the ``compile`` fixture); the tests share one motion
shape [N, T, J] = [9, 6, 3] so that each function compiles about once.
"""


import jax
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from jaxmotion.metrics.trajectory import (
    end_point_error,
    end_point_hit_rate,
    end_point_squared_error,
    joint_position_error,
    joint_position_error_per_sample,
    trajectory_error,
    trajectory_error_per_sample,
)

N, T, J = 9, 6, 3
LABELS = np.array([0, 2, 1, 0, 0, 2, 0, 1, 0])  # unequal classes: class means differ from the pooled mean
LENGTHS = np.array([6, 3, 1, 5, 6, 2, 4, 6, 3])
RTOL = 1e-4




def motions(seed):
    return np.random.default_rng(seed).normal(size=(N, T, J, 3)).astype(np.float32)


def ground(x):
    """(x, z) of the root: the ground plane of the library frame (+Y up)."""
    return np.ascontiguousarray(x[:, :, 0, [0, 2]])


# --- float64 references, from the papers' sentences and ODMO's procedure -----------------------------


def reference_trajectory_error(x, trajectories, lengths):
    per_action = []
    for motion, trajectory, length in zip(np.asarray(x, np.float64), trajectories, lengths, strict=True):
        distances = [np.hypot(motion[t, 0, 0] - trajectory[t, 0], motion[t, 0, 2] - trajectory[t, 1])
                     for t in range(length)]
        per_action.append(sum(distances) / length)
    return np.array(per_action)


def reference_class_mean(values, labels, num_classes):
    return np.mean([np.mean([v for v, c in zip(values, labels, strict=True) if c == k]) for k in range(num_classes)])


def reference_squared_errors(x, targets):
    x = np.asarray(x, np.float64)
    return np.array([sum((targets[i, d] - x[i, -1, 0, d]) ** 2 for d in range(3)) for i in range(len(x))])


# --- ΔTraj -------------------------------------------------------------------------------------------


def test_trajectory_error_matches_numpy_reference(compile):
    x = motions(0)
    trajectories = np.random.default_rng(1).normal(size=(N, T, 2)).astype(np.float32)
    per_sample = compile(trajectory_error_per_sample)(x, trajectories, LENGTHS)
    expected = reference_trajectory_error(x, trajectories, LENGTHS)
    np.testing.assert_allclose(per_sample, expected, rtol=RTOL)
    np.testing.assert_allclose(compile(trajectory_error)(x, trajectories, LENGTHS), expected.mean(), rtol=RTOL)


def test_trajectory_error_is_zero_when_the_root_follows_the_trajectory(compile):
    x = motions(2)
    np.testing.assert_allclose(compile(trajectory_error)(x, ground(x)), 0.0, atol=1e-7)


def test_trajectory_error_ignores_height_and_non_root_joints(compile):
    x = motions(3)
    trajectories = np.random.default_rng(4).normal(size=(N, T, 2)).astype(np.float32)
    moved = x.copy()
    moved[:, :, 0, 1] += 5.0  # root height
    moved[:, :, 1:] = 0.0  # every other joint
    fn = compile(trajectory_error_per_sample)
    np.testing.assert_allclose(fn(moved, trajectories, LENGTHS), fn(x, trajectories, LENGTHS), rtol=RTOL)


def test_trajectory_error_of_a_constant_offset_is_its_length(compile):
    x = motions(5)
    offset = np.array([3.0, 4.0], np.float32)  # 5 on the ground plane, whatever the lengths
    np.testing.assert_allclose(compile(trajectory_error_per_sample)(x, ground(x) + offset, LENGTHS), 5.0, rtol=RTOL)


def test_trajectory_error_never_reads_frames_past_the_length(compile):
    x = motions(6)
    trajectories = ground(x) + 1.0
    padded = x.copy()
    for i, length in enumerate(LENGTHS):
        padded[i, length:] = np.nan
    got = compile(trajectory_error_per_sample)(padded, trajectories, LENGTHS)
    np.testing.assert_allclose(got, np.sqrt(2.0), rtol=RTOL)


@given(seed=st.integers(0, 2**16), shift=st.lists(st.floats(-20, 20), min_size=2, max_size=2))
def test_trajectory_error_is_invariant_to_a_common_ground_translation(seed, shift):
    x = motions(seed)
    trajectories = ground(motions(seed + 1))
    shift = np.asarray(shift, np.float32)
    moved = x.copy()
    moved[..., [0, 2]] += shift
    fn = jax.jit(trajectory_error_per_sample)
    np.testing.assert_allclose(
        fn(moved, trajectories + shift, LENGTHS), fn(x, trajectories, LENGTHS), rtol=1e-3, atol=1e-4
    )


@pytest.mark.parametrize("bad_length", [0, T + 1, -2])
def test_trajectory_error_is_nan_for_a_length_outside_1_to_t(compile, bad_length):
    lengths = LENGTHS.copy()
    lengths[4] = bad_length
    x = motions(7)
    got = np.asarray(compile(trajectory_error_per_sample)(x, ground(x), lengths))
    assert np.isnan(got[4]) and np.isfinite(np.delete(got, 4)).all()


# --- dist_e and hit rate -----------------------------------------------------------------------------


def test_end_point_error_matches_numpy_reference(compile):
    x = motions(8)
    targets = np.random.default_rng(9).normal(size=(N, 3)).astype(np.float32)
    got = compile(end_point_error, "num_classes")(x, targets, LABELS, 3)
    expected = reference_class_mean(reference_squared_errors(x, targets), LABELS, 3)
    np.testing.assert_allclose(got, expected, rtol=RTOL)


def test_end_point_error_is_zero_when_every_end_is_reached(compile):
    x = motions(10)
    np.testing.assert_allclose(compile(end_point_error, "num_classes")(x, x[:, -1, 0], LABELS, 3), 0.0, atol=1e-7)


def test_end_point_error_is_the_squared_distance_of_the_final_root(compile):
    x = motions(11)
    targets = x[:, -1, 0] + np.array([0.0, 0.3, 0.4], np.float32)  # 0.5 away: squared error 0.25
    x[:, :-1] = 100.0  # earlier frames and
    x[:, -1, 1:] = 100.0  # other joints play no part
    np.testing.assert_allclose(compile(end_point_squared_error)(x, targets), 0.25, rtol=RTOL)


@pytest.mark.parametrize("scale", [2.0, 0.5])
def test_end_point_error_scales_with_the_square_of_the_miss(compile, scale):
    x = motions(12)
    miss = np.random.default_rng(13).normal(size=(N, 3)).astype(np.float32)
    fn = compile(end_point_error, "num_classes")
    np.testing.assert_allclose(
        fn(x, x[:, -1, 0] + scale * miss, LABELS, 3), scale**2 * fn(x, x[:, -1, 0] + miss, LABELS, 3), rtol=RTOL
    )


def test_hit_rate_counts_ends_within_the_tolerance(compile):
    x = np.zeros((N, T, J, 3), np.float32)
    targets = np.tile(np.array([[0.0, 0.0, 2.0]], np.float32), (N, 1))  # ‖end‖ = 2: tolerance 0.2
    misses = np.array([0.1, 0.3, 0.19, 0.0, 0.21, 0.5, 0.05, 0.15, 1.0])  # along x
    x[:, -1, 0] = targets + misses[:, None] * np.array([1.0, 0.0, 0.0], np.float32)
    hits = misses < 0.2
    got = compile(end_point_hit_rate, "num_classes")(x, targets, LABELS, 3, 0.1)
    np.testing.assert_allclose(got, reference_class_mean(hits, LABELS, 3), rtol=RTOL)


def test_hit_rate_matches_numpy_reference(compile):
    x = motions(14)
    targets = x[:, -1, 0] + np.random.default_rng(15).normal(scale=0.3, size=(N, 3)).astype(np.float32)
    squared = reference_squared_errors(x, targets)
    for tolerance in (0.1, 0.5):
        hits = squared < tolerance**2 * np.sum(np.asarray(targets, np.float64) ** 2, axis=1)
        got = compile(end_point_hit_rate, "num_classes")(x, targets, LABELS, 3, tolerance)
        np.testing.assert_allclose(got, reference_class_mean(hits, LABELS, 3), rtol=RTOL)


def test_an_empty_class_or_a_bad_label_makes_the_class_mean_nan(compile):
    x = motions(16)
    fn = compile(end_point_error, "num_classes")
    assert np.isnan(fn(x, x[:, -1, 0], LABELS, 4))  # class 3 has no sample
    bad = LABELS.copy()
    bad[0] = 3
    assert np.isnan(fn(x, x[:, -1, 0], bad, 3))


# --- input validation --------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: trajectory_error(np.zeros((N, T, J)), np.zeros((N, T, 2))),
         r"motions: expected \[N, T, J, 3\], got \(9, 6, 3\)"),
        (lambda: trajectory_error(np.zeros((N, T, J, 3)), np.zeros((N, T, 3))),
         r"trajectories: expected \[N, T, 2\] = \(9, 6, 2\), got \(9, 6, 3\)"),
        (lambda: trajectory_error(np.zeros((N, T, J, 3)), np.zeros((N, T, 2)), np.full(N, 3.0)),
         r"lengths: expected integer \[N\]"),
        (lambda: end_point_error(np.zeros((N, T, J, 3)), np.zeros((N, 2)), LABELS, 3),
         r"targets: expected \[N, 3\] = \(9, 3\), got \(9, 2\)"),
        (lambda: end_point_hit_rate(np.zeros((N, T, J, 3)), np.zeros((N, 3)), LABELS[:-1], 3),
         r"labels: expected integer \[N\] = \(9,\)"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_joint_position_error_is_the_mean_joint_distance_over_each_actions_frames(compile):
    generated, truth = motions(11), motions(12)
    expected = np.array([np.linalg.norm(generated[i, :n] - truth[i, :n], axis=-1).mean()
                         for i, n in enumerate(LENGTHS)])
    np.testing.assert_allclose(compile(joint_position_error_per_sample)(generated, truth, LENGTHS), expected,
                               rtol=RTOL)
    np.testing.assert_allclose(compile(joint_position_error)(generated, truth, LENGTHS), expected.mean(), rtol=RTOL)
    shifted = truth + np.array([0.0, 0.1, 0.0], np.float32)  # every joint 10 cm up
    np.testing.assert_allclose(compile(joint_position_error)(shifted, truth), 0.1, rtol=RTOL)
    padded = generated.copy()
    padded[1, 3:] = np.nan  # past action 1's length: never read
    assert np.isfinite(compile(joint_position_error_per_sample)(padded, truth, LENGTHS)).all()
    bad = compile(joint_position_error_per_sample)(generated, truth, LENGTHS * 0)
    assert np.isnan(bad).all()
