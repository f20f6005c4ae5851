"""Training ACTOR with the minimal loop, and its sampler for the evaluation protocol."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.data.datasets import load_dataset
from jaxmotion.models.actor import ActorConfig
from jaxmotion.pipelines.actor import actor_sampler
from jaxmotion.train.actor import ActorTraining, train_actor
from jaxmotion.train.loop import LoopConfig

TINY = ActorTraining(ActorConfig(num_classes=12, width=16, ff=32, layers=1, heads=2),
                     LoopConfig(4, log_every=2, checkpoint_every=2), batch_size=8, window=20)


@pytest.mark.smoke
def test_training_resumes_and_the_sampler_returns_library_motions(tmp_path):
    data = load_dataset("synth-humanact12", count=24)
    params = train_actor(data, TINY, jax.random.key(0), str(tmp_path), progress=False)
    again = train_actor(data, TINY, jax.random.key(0), str(tmp_path), progress=False)  # all steps done: restored
    for a, b in zip(jax.tree.leaves(params), jax.tree.leaves(again), strict=True):
        np.testing.assert_array_equal(np.asarray(a), np.asarray(b))

    sampler = actor_sampler(params, TINY.model, data.skeleton)
    motions = sampler(jax.random.key(1), jnp.array([0, 5, 11]), jnp.array([12, 8, 12]))
    assert motions["joints"].shape == (3, 12, 24, 3) and motions["rotations"].shape == (3, 12, 24, 3)
    np.testing.assert_array_equal(np.asarray(motions["lengths"]), [12, 8, 12])
    # padding repeats the last real frame, like the real windows the recogniser was trained on
    np.testing.assert_array_equal(np.asarray(motions["joints"][1, 8:]),
                                  np.broadcast_to(np.asarray(motions["joints"][1, 7]), (4, 24, 3)))
    assert np.isfinite(np.asarray(motions["joints"])).all()


def test_the_model_config_carries_its_representation_and_channels():
    assert ActorConfig(num_classes=12, rep="quaternion").channels == 4
    assert ActorConfig(num_classes=12).features == 25 * 6

