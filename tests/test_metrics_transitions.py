"""Neural Marionette's Δpose, Δvel and qualification ratios: properties, hand-computed cases, numpy reference.

Every kernel runs eagerly and under ``jax.jit`` (the ``compile`` fixture). To keep compilation cheap, the
gap tests share one motion shape [T, J] = [20, 4] with three transitions, and the QR tests one [M, A].
"""


import jax
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from jaxmotion.metrics.transitions import (
    action_qr,
    mean_transition_gaps,
    motion_qr,
    qualification_ratio_curves,
    transition_gaps,
)

T, J = 20, 4
BOUNDARIES = np.array([4, 9, 15])  # actions of 4, 5, 6 and 5 frames
RTOL = 1e-4


def motion(seed, batch=()):
    return np.random.default_rng(seed).normal(scale=0.3, size=(*batch, T, J, 3)).astype(np.float32)


def reference_gaps(x, boundaries):
    """Float64 loops over transitions and joints; metres in, cm and cm/frame out."""
    x = np.asarray(x, np.float64)
    pose, velocity = [], []
    for b in boundaries:
        pose.append(np.mean([np.linalg.norm(x[b, j] - x[b - 1, j]) for j in range(x.shape[1])]))
        end_velocity = x[b - 1] - x[b - 2]  # last two frames of the previous action
        start_velocity = x[b + 1] - x[b]  # first two frames of the current action
        velocity.append(np.mean([np.linalg.norm(start_velocity[j] - end_velocity[j]) for j in range(x.shape[1])]))
    return 100.0 * np.array(pose), 100.0 * np.array(velocity)


def random_rotation(seed):
    q, r = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return (q * np.linalg.det(q)).astype(np.float32)  # det +1


# --- Δpose and Δvel ----------------------------------------------------------------------------------


def test_transition_gaps_match_numpy_reference(compile):
    x = motion(0)
    pose, velocity = compile(transition_gaps)(x, BOUNDARIES)
    expected_pose, expected_velocity = reference_gaps(x, BOUNDARIES)
    np.testing.assert_allclose(pose, expected_pose, rtol=RTOL)
    np.testing.assert_allclose(velocity, expected_velocity, rtol=RTOL)


def test_mean_transition_gaps_average_every_transition_of_every_motion(compile):
    x = motion(1, batch=(3,))
    boundaries = np.array([[4, 9, 15], [2, 10, 18], [5, 7, 12]])
    pose, velocity = compile(mean_transition_gaps)(x, boundaries)
    expected = [reference_gaps(m, b) for m, b in zip(x, boundaries, strict=True)]
    np.testing.assert_allclose(pose, np.mean([p for p, _ in expected]), rtol=RTOL)
    np.testing.assert_allclose(velocity, np.mean([v for _, v in expected]), rtol=RTOL)


def test_gaps_are_zero_for_a_static_pose(compile):
    x = np.broadcast_to(motion(2)[:1], (T, J, 3))
    pose, velocity = compile(transition_gaps)(x, BOUNDARIES)
    np.testing.assert_allclose(pose, 0.0, atol=1e-6)
    np.testing.assert_allclose(velocity, 0.0, atol=1e-6)


def test_constant_velocity_has_no_velocity_gap_and_a_pose_gap_of_one_step(compile):
    velocities = np.array([[0.01, 0.0, 0.0], [0.0, 0.03, 0.04], [0.0, 0.0, 0.0], [0.02, 0.0, 0.0]], np.float32)
    x = motion(3)[0] + np.arange(T, dtype=np.float32)[:, None, None] * velocities
    pose, velocity = compile(transition_gaps)(x, BOUNDARIES)
    np.testing.assert_allclose(pose, 100.0 * np.mean([0.01, 0.05, 0.0, 0.02]), rtol=RTOL)  # cm per frame step
    np.testing.assert_allclose(velocity, 0.0, atol=1e-4)


def test_gaps_are_in_centimetres(compile):
    # Static poses with a 1 cm jump of every joint at frame 9: Δpose 1 cm there; the velocities on both
    # sides are zero, so Δvel is 0 everywhere.
    x = np.zeros((T, J, 3), np.float32)
    x[9:, :, 1] = 0.01
    pose, velocity = compile(transition_gaps)(x, BOUNDARIES)
    np.testing.assert_allclose(pose, [0.0, 1.0, 0.0], atol=1e-5)
    np.testing.assert_allclose(velocity, 0.0, atol=1e-5)


def test_velocity_gap_of_a_reversal_is_twice_the_speed(compile):
    # Joints move +1 cm/frame along x until frame 8, then -1 cm/frame: the velocity jumps by 2 cm/frame.
    t = np.arange(T, dtype=np.float32)
    x = np.zeros((T, J, 3), np.float32)
    x[:, :, 0] = (0.01 * np.where(t <= 8, t, 16 - t))[:, None]
    pose, velocity = compile(transition_gaps)(x, BOUNDARIES)
    np.testing.assert_allclose(velocity, [0.0, 2.0, 0.0], atol=1e-5)
    np.testing.assert_allclose(pose, 1.0, atol=1e-5)


@given(seed=st.integers(0, 2**16), shift=st.lists(st.floats(-10, 10), min_size=3, max_size=3))
def test_gaps_are_invariant_to_rigid_motion_of_the_whole_scene(seed, shift):
    x = motion(seed)
    moved = x @ random_rotation(seed).T + np.asarray(shift, np.float32)
    gaps = jax.jit(transition_gaps)
    for got, expected in zip(gaps(moved, BOUNDARIES), gaps(x, BOUNDARIES), strict=True):
        np.testing.assert_allclose(got, expected, rtol=1e-3, atol=1e-3)


@pytest.mark.parametrize(
    "boundaries, bad",
    [
        ([1, 9, 15], [0]),  # first action has one frame
        ([4, 5, 15], [0, 1]),  # second action has one frame
        ([4, 9, 19], [2]),  # last action has one frame
        ([4, 15, 9], [1, 2]),  # out of order
        ([4, 9, 25], [2]),  # past the end
    ],
)
def test_transition_with_a_one_frame_or_misplaced_action_is_nan(compile, boundaries, bad):
    pose, velocity = compile(transition_gaps)(motion(4), np.array(boundaries))
    for gap in (np.asarray(pose), np.asarray(velocity)):
        assert np.isnan(gap[bad]).all() and np.isfinite(np.delete(gap, bad)).all()


# --- qualification ratios ----------------------------------------------------------------------------

M, A = 6, 5


def reference_qrs(correct):
    per_motion = [sum(row) / len(row) for row in correct]
    qualified = [all(row) for row in correct]
    return sum(per_motion) / len(correct), sum(qualified) / len(correct)


def test_action_qr_of_the_papers_example_is_60_percent(compile):
    correct = np.zeros((M, A), bool)
    correct[:, :3] = True  # 3 accurate actions among 5, in every motion
    np.testing.assert_allclose(compile(action_qr)(correct), 0.6, rtol=RTOL)
    assert compile(motion_qr)(correct) == 0.0


def test_motion_qr_counts_motions_with_every_action_correct(compile):
    correct = np.ones((M, A), bool)
    correct[1, 4] = correct[3, 0] = correct[3, 2] = False
    np.testing.assert_allclose(compile(motion_qr)(correct), 4 / 6, rtol=RTOL)


@given(bits=st.lists(st.booleans(), min_size=M * A, max_size=M * A))
def test_qrs_match_python_reference(bits):
    correct = np.array(bits).reshape(M, A)
    expected_action, expected_motion = reference_qrs(correct.tolist())
    np.testing.assert_allclose(jax.jit(action_qr)(correct), expected_action, rtol=RTOL)
    np.testing.assert_allclose(jax.jit(motion_qr)(correct), expected_motion, rtol=RTOL)


def test_qr_curves_are_the_qrs_of_the_first_n_actions(compile):
    correct = np.random.default_rng(5).random((M, A)) < 0.8
    action_curve, motion_curve = compile(qualification_ratio_curves)(correct)
    expected = np.array([reference_qrs(correct[:, :n].tolist()) for n in range(1, A + 1)])
    np.testing.assert_allclose(action_curve, expected[:, 0], rtol=RTOL)
    np.testing.assert_allclose(motion_curve, expected[:, 1], rtol=RTOL)
    assert np.all(np.diff(motion_curve) <= 0)  # a motion, once disqualified, stays so


# --- input validation --------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: transition_gaps(np.zeros((T, J)), BOUNDARIES), r"motion: expected \[T, J, 3\], got \(20, 4\)"),
        (lambda: transition_gaps(np.zeros((T, J, 3)), BOUNDARIES.astype(float)), r"boundaries: expected integer \[B\]"),
        (lambda: transition_gaps(np.zeros((T, J, 3)), np.zeros(0, int)), r"boundaries: expected integer \[B\]"),
        (lambda: mean_transition_gaps(np.zeros((2, T, J, 3)), BOUNDARIES[None]),
         r"boundaries: expected integer \[M, B\] with M = 2"),
        (lambda: mean_transition_gaps(np.zeros((T, J, 3)), BOUNDARIES), r"motions: expected \[M, T, J, 3\]"),
        (lambda: action_qr(np.ones(A, bool)), r"correct: expected bool \[M, A\]"),
        (lambda: motion_qr(np.ones((M, A), int)), r"correct: expected bool \[M, A\]"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(call, message):
    with pytest.raises(ValueError, match=message):
        call()
