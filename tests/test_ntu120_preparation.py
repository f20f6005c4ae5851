"""ActFormer's preparation of Kinect skeletons: gap filling (the code's and the intended rule) and smoothing."""

import numpy as np
import pytest

from jaxmotion.data.formats.ntu120 import (
    MUTUAL_ACTIONS,
    SINGLE_ACTIONS,
    XSUB_TRAIN_SUBJECTS,
    fill_missing,
    gaussian_smooth,
)


def test_label_orders_and_split_have_the_real_sizes():
    assert len(SINGLE_ACTIONS) == 94 and len(MUTUAL_ACTIONS) == 26 and len(XSUB_TRAIN_SUBJECTS) == 53
    assert SINGLE_ACTIONS[49] == 61 and MUTUAL_ACTIONS[11] == 106  # A061 -> label 49, A106 -> label 11
    assert not set(SINGLE_ACTIONS) & set(MUTUAL_ACTIONS)


def test_gap_filling_copies_the_ends_and_fills_gaps_by_each_rule():
    joints = np.arange(8, dtype=float)[:, None, None] * np.ones((8, 2, 3))  # frame t holds the value t
    detected = np.array([0, 1, 1, 0, 0, 0, 1, 0], bool)
    code = fill_missing(joints, detected)
    linear = fill_missing(joints, detected, rule="linear")
    np.testing.assert_array_equal(code[:, 0, 0], [1, 1, 2, 3, 0, 0, 6, 6])  # only frame a + 1 is written
    np.testing.assert_array_equal(linear[:, 0, 0], [1, 1, 2, 3, 4, 5, 6, 6])
    np.testing.assert_array_equal(fill_missing(joints, np.ones(8, bool)), joints)


def test_gap_filling_rejects_a_body_never_seen_and_bad_shapes():
    with pytest.raises(ValueError, match="never detected"):
        fill_missing(np.zeros((4, 25, 3)), np.zeros(4, bool))
    with pytest.raises(ValueError, match=r"detected: expected \[T\] = \(4,\)"):
        fill_missing(np.zeros((4, 25, 3)), np.zeros(5, bool))


@pytest.mark.parametrize("frames", [1, 3, 12, 25, 26, 90])
def test_smoothing_matches_scipy(frames):
    ndimage = pytest.importorskip("scipy.ndimage")
    x = np.random.default_rng(frames).normal(size=(frames, 25, 3))
    np.testing.assert_allclose(gaussian_smooth(x), ndimage.gaussian_filter1d(x, 3, axis=0), atol=1e-12)
    np.testing.assert_allclose(gaussian_smooth(x, 1.5, axis=1), ndimage.gaussian_filter1d(x, 1.5, axis=1), atol=1e-12)
