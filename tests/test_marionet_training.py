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
from jaxmotion.train.marionet import (MarionetTraining, marionet_inputs, marionet_state, marionet_step, sampling_share,
                                      train_marionet)

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
    """With a gate no first pass can miss and sampling active from the start, the second pass weighs in (the
    shared loop's determinism and resumption are tested once for every trainer, in test_experiment.py)."""
    training = dataclasses.replace(TRAINING, activate=0.0, accomplish=0.5, gate=1e9)
    params = train_marionet(takes, training, jax.random.key(5), tmp_path, progress=False)
    assert all(np.isfinite(np.asarray(leaf)).all() for leaf in jax.tree.leaves(params))
    log = [json.loads(line) for line in (tmp_path / "metrics.jsonl").read_text().splitlines()]
    assert [record["step"] for record in log] == [2, 4]
    # xi = step / 2 (accomplished at half of 4 steps), the log's mean over its steps: (0 + 0.5) / 2, then 1
    assert [record["sampled share"] for record in log] == [0.25, 1.0]
    assert np.isfinite(log[-1]["loss"]) and log[-1]["rotations (second pass)"] > 0 and log[-1]["second pass"] == 1


def test_a_second_pass_that_weighs_nothing_is_not_run(takes):
    """Before the gate opens the step skips the second pass: the same update as teacher forcing alone, the pass's
    terms logged as zeros."""
    items = takes.action_items(CONTEXT)
    spec, labels = action_item_batches(items, batch_size=4)
    batch = make_batch_fn(items.data, jax.random.key(0), spec, labels)(0)
    closed = dataclasses.replace(TRAINING, activate=0.0, gate=1e-12)
    updates = {}
    for name, training in {"gate closed": closed, "teacher forcing": dataclasses.replace(
            closed, scheduled_sampling=False)}.items():
        state = marionet_state(training, jax.random.key(1))
        updates[name] = jax.jit(marionet_step(training, root_tag_mask(takes.class_names)))(state, batch,
                                                                                           jax.random.key(2))
    (state, terms), (reference, reference_terms) = updates["gate closed"], updates["teacher forcing"]
    assert terms["second pass"] == 0 and terms["rotations (second pass)"] == 0 and terms["sampled share"] == 0
    np.testing.assert_allclose(terms["loss"], reference_terms["loss"], rtol=1e-6)
    for leaf, expected in zip(jax.tree.leaves(state.params), jax.tree.leaves(reference.params)):
        np.testing.assert_allclose(leaf, expected, rtol=1e-5, atol=1e-7)


def test_training_refuses_data_it_cannot_read(takes):
    with pytest.raises(ValueError, match="num_tags: 12, but synth-mag has 31 tags"):
        train_marionet(takes, dataclasses.replace(TRAINING, model=MarionetConfig.tiny(num_tags=12)),
                       jax.random.key(0))
    with pytest.raises(ValueError, match="class_names: expected BABEL-MAG's tags; 'walk' is not one"):
        root_tag_mask(("walk", "run"))
