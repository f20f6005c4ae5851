"""Jitter (mean joint acceleration) and the jerk at transitions (FlowMDM's PJ, AUJ): analytical cases and masking."""

import numpy as np
import pytest

from jaxmotion.metrics import mean_acceleration
from jaxmotion.metrics.smoothness import jerk_scores, mean_jerk, transition_jerk


def test_straight_line_at_constant_speed_has_no_acceleration_and_a_parabola_its_constant(compile):
    t = np.arange(10, dtype=np.float32)[None, :, None, None]
    line = np.concatenate([t * 0.1, t * 0.0, t * -0.2], axis=-1) + np.zeros((2, 1, 5, 1), np.float32)
    parabola = line.copy()
    parabola[..., 1] = 0.5 * 0.03 * t[..., 0] ** 2  # y'' = 0.03 per frame²
    assert float(compile(mean_acceleration)(line)) == pytest.approx(0.0, abs=1e-6)
    assert float(compile(mean_acceleration)(parabola)) == pytest.approx(0.03, rel=1e-4)


def test_masked_frames_are_ignored(compile):
    rng = np.random.default_rng(0)
    joints = rng.normal(size=(3, 12, 4, 3)).astype(np.float32)
    mask = np.arange(12)[None, :] < np.array([[12], [7], [5]])
    wild = joints.copy()
    wild[~mask] = 1e3
    assert float(compile(mean_acceleration)(wild, mask)) == pytest.approx(float(mean_acceleration(joints, mask)),
                                                                          rel=1e-6)
    # reference: frames with both neighbours real
    values = [np.linalg.norm(j[t + 1] - 2 * j[t] + j[t - 1], axis=-1).mean()
              for j, n in zip(joints, (12, 7, 5)) for t in range(1, n - 1)]
    assert float(mean_acceleration(joints, mask)) == pytest.approx(np.mean(values), rel=1e-5)


def test_bad_shapes_name_the_argument():
    with pytest.raises(ValueError, match=r"joints: expected \[N, T, J, 3\]"):
        mean_acceleration(np.zeros((2, 5, 3)))
    with pytest.raises(ValueError, match=r"mask: expected \[N, T\]"):
        mean_acceleration(np.zeros((2, 5, 4, 3)), np.ones((2, 4), bool))


def _jump(frames, boundary):
    """One joint that jumps 1 along x at ``boundary``: third differences 1, -2, 1 on the three frames before."""
    joints = np.zeros((1, frames, 2, 3), np.float32)
    joints[0, boundary:, 1, 0] = 1.0
    return joints


def test_a_jump_at_the_transition_peaks_in_the_middle_of_the_window():
    joints, lengths = _jump(40, 20), np.array([40])
    curve = np.asarray(transition_jerk(joints, lengths, np.array([[20]]), window=10))
    expected = np.zeros(10)
    expected[2:5] = [1.0, 2.0, 1.0]  # the frames whose four positions straddle frame 20 (window from frame 15)
    np.testing.assert_allclose(curve, expected, atol=1e-6)
    assert jerk_scores(curve, 0.0) == pytest.approx({"peak_jerk": 2.0, "area_under_jerk": 4.0})
    assert jerk_scores(curve, 0.5)["area_under_jerk"] == pytest.approx(2.5 + 0.5 * 7)
    # a transition whose window leaves the motion does not count; the other's is the curve alone
    two = np.concatenate([joints, _jump(40, 3)])
    both = transition_jerk(two, np.array([40, 40]), np.array([[20], [3]]), window=10)
    np.testing.assert_allclose(np.asarray(both), expected, atol=1e-6)


def test_mean_jerk_of_a_cubic_is_its_constant_third_difference():
    t = np.arange(12, dtype=np.float32)
    joints = np.zeros((2, 12, 3, 3), np.float32)
    joints[:, :, 0, 2] = 0.001 * t ** 3  # third difference 0.006 per frame³
    lengths = np.array([12, 8])
    joints[1, 8:] = 50.0  # past its length: never read
    assert float(mean_jerk(joints, lengths)) == pytest.approx(0.006, rel=1e-3)
    with pytest.raises(ValueError, match="window: expected an even number of frames"):
        transition_jerk(joints, lengths, np.array([[6], [4]]), window=5)
