"""Training MARIONET: inputs normalised at the last context pose with paths only for root motion, the scheduled
sampling share, and a few steps of training that are deterministic and turn the second pass on."""

import dataclasses
import json

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.data import synthetic
from jaxmotion.data.mag_tags import KINDS, root_tag_mask
from jaxmotion.data.pipeline import action_item_batches, make_batch_fn
from jaxmotion.geometry.rotations import to_matrix
from jaxmotion.models.marionet import CONTEXT, MarionetConfig
from jaxmotion.train.loop import LoopConfig
from jaxmotion.train.marionet import MarionetTraining, marionet_inputs, sampling_share, train_marionet

TRAINING = MarionetTraining(MarionetConfig.tiny(), LoopConfig(steps=4, log_every=2, checkpoint_every=0),
                            batch_size=4)


@pytest.fixture(scope="module")
def takes():
    return synthetic.generate("synth-mag", "test", seed=0, count=6, progress=False)


def test_inputs_are_normalised_at_the_last_context_pose_with_paths_for_root_motion_only(takes):
    items = takes.action_items(CONTEXT)
    spec, labels = action_item_batches(items, batch_size=len(items))
    batch = make_batch_fn(items.data, jax.random.key(0), spec, labels)(0)
    x = marionet_inputs(batch, jnp.asarray(root_tag_mask(takes.class_names)))
    last = np.asarray(x["context"][:, -1])
    forward = np.asarray(to_matrix(jnp.asarray(last[:, :6]), "rot6d"))[:, :, 2]  # the root's R e_z
    np.testing.assert_allclose(forward[:, 0], 0.0, atol=1e-5)  # facing +Z
    assert (forward[:, 2] > 0).all()
    np.testing.assert_allclose(last[:, [132, 134]], 0.0, atol=1e-5)  # over the origin, the height kept
    assert (last[:, 133] > 0.3).all()
    roots = np.array([any(KINDS[takes.class_names[t]] == "root" for t in np.flatnonzero(row))
                      for row in np.asarray(x["tags"])])
    assert roots.any() and (~roots).any()
    travel = np.abs(np.asarray(x["path"])).sum(axis=(1, 2))
    assert (travel[~roots] == 0).all() and (travel[roots] > 0).all()
    np.testing.assert_array_equal(np.asarray(x["path"])[~np.asarray(x["mask"])], 0.0)


def test_the_sampled_share_rises_linearly_between_activate_and_accomplish():
    training = dataclasses.replace(TRAINING, loop=LoopConfig(steps=1000, log_every=10, checkpoint_every=0))
    shares = [float(sampling_share(training, jnp.int32(s))) for s in (0, 250, 500, 750, 1000)]
    np.testing.assert_allclose(shares, [0.0, 0.0, 0.5, 1.0, 1.0])


@pytest.mark.smoke
def test_a_few_steps_of_training_turn_the_second_pass_on(takes, tmp_path):
    """Before ``activate`` (half of 4 steps) the second pass is not run, its terms logged as zeros; after it, with a
    gate no first pass can miss, it weighs in (the shared loop's determinism and resumption are tested once for
    every trainer, in test_experiment.py)."""
    training = dataclasses.replace(TRAINING, activate=0.5, accomplish=0.75, gate=1e9)
    params = train_marionet(takes, training, jax.random.key(5), tmp_path, progress=False)
    assert all(np.isfinite(np.asarray(leaf)).all() for leaf in jax.tree.leaves(params))
    log = [json.loads(line) for line in (tmp_path / "metrics.jsonl").read_text().splitlines()]
    assert [record["step"] for record in log] == [2, 4]
    off, on = log
    assert off["second pass"] == 0 and off["sampled share"] == 0 and off["rotations (second pass)"] == 0
    # xi = (step / 4 - 0.5) / 0.25 at steps 2 and 3: 0 and 1, both with the pass on; the log's mean: 0.5
    assert on["second pass"] == 1 and on["sampled share"] == 0.5 and on["rotations (second pass)"] > 0
    assert np.isfinite(on["loss"])


def test_training_refuses_data_it_cannot_read(takes):
    with pytest.raises(ValueError, match="num_tags: 12, but synth-mag has 31 tags"):
        train_marionet(takes, dataclasses.replace(TRAINING, model=MarionetConfig.tiny(num_tags=12)),
                       jax.random.key(0))
    with pytest.raises(ValueError, match="class_names: expected BABEL-MAG's tags; 'walk' is not one"):
        root_tag_mask(("walk", "run"))
