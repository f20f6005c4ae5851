"""Jitter (mean joint acceleration): analytical cases and masking."""

import numpy as np
import pytest

from jaxmotion.metrics import mean_acceleration


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
