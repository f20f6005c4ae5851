"""The training sets of ACTOR's recognition use case: the batched latent interpolation."""

import jax
import numpy as np
import pytest
from smooth_motions import MODEL, WINDOW, smooth_dataset

from jaxmotion.data.pipeline import BatchSpec, gather_windows
from jaxmotion.models.actor import init_actor
from jaxmotion.pipelines.actor import denoise, interpolated_set


@pytest.fixture(scope="module")
def setup():
    return smooth_dataset(), jax.jit(init_actor, static_argnums=1)(jax.random.key(0), MODEL)


def test_interpolants_stay_within_their_action_and_between_its_lengths(setup):
    data, params = setup
    out = interpolated_set(params, MODEL, data, jax.random.key(1), 9, window=WINDOW)
    assert len(out) == 9 and out.class_names == data.class_names and out.skeleton is data.skeleton
    for action in set(out.actions.tolist()):
        lengths = data.lengths[data.actions == action]  # all shorter than the window: whole clips
        mine = out.lengths[out.actions == action]
        assert lengths.min() <= mine.min() and mine.max() <= lengths.max()


def test_a_clip_alone_in_its_class_interpolates_to_its_denoised_window(setup):
    """With one clip per action both ends of every pair are that clip, so each interpolant decodes its
    posterior mean: the deterministic denoising of its canonical window."""
    data, params = setup
    single = data.subset([0, 1])  # actions 0 and 1
    out = interpolated_set(params, MODEL, single, jax.random.key(2), 4, window=WINDOW)
    windows = gather_windows(single, np.arange(2), jax.random.key(3), BatchSpec(batch_size=1, window=WINDOW))
    reference = denoise(params, MODEL, windows, single.skeleton)
    for motion in out:
        n = motion.num_frames
        assert n == single.lengths[motion.action]
        np.testing.assert_allclose(motion.rotations, reference["rotations"][motion.action, :n], atol=1e-4)
        np.testing.assert_allclose(motion.joints, reference["joints"][motion.action, :n], atol=1e-4)


def test_interpolants_do_not_depend_on_the_chunk_size(setup):
    data, params = setup
    whole = interpolated_set(params, MODEL, data, jax.random.key(4), 7, window=WINDOW)
    parts = interpolated_set(params, MODEL, data, jax.random.key(4), 7, window=WINDOW, chunk=3)
    np.testing.assert_array_equal(whole.starts, parts.starts)
    np.testing.assert_allclose(whole.joints, parts.joints, atol=1e-5)


@pytest.mark.parametrize("count", [0, -1])
def test_count_must_be_positive(setup, count):
    data, params = setup
    with pytest.raises(ValueError, match="count"):
        interpolated_set(params, MODEL, data, jax.random.key(0), count, window=WINDOW)
