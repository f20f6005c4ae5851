"""Neural Marionette's single-action protocol: the test actions and their conditions, and known values of the
scores (a sampler that returns the real actions scores the real set's accuracy, FID 0, ΔTraj 0, ΔJPE 0)."""

import jax
import numpy as np
import pytest

from jaxmotion.data import synthetic
from jaxmotion.data.mag_tags import root_tag_mask
from jaxmotion.evaluation.actions import ActionProtocol, action_set, evaluate_actions, generate_for
from jaxmotion.geometry.skeletons import SMPL24
from jaxmotion.models.recognition import Recognizer, RecognizerConfig, init_recognizer


@pytest.fixture(scope="module")
def takes():
    return synthetic.generate("synth-mag", "test", seed=0, count=5, progress=False)


@pytest.fixture(scope="module")
def recognizer():
    config = RecognizerConfig(architecture="transformer", inputs="rot6d+translation", hidden=16, layers=1, heads=2)
    variables = init_recognizer(jax.random.key(0), config, SMPL24, 31, frames=30)
    return Recognizer(config, SMPL24, tuple(str(i) for i in range(31)), variables)


def test_the_test_actions_carry_their_context_conditions_and_real_frames(takes):
    actions = action_set(takes, max_frames=100)
    c, real = actions.conditions, actions.real
    items = takes.action_items(6)
    keep = np.flatnonzero(items.durations <= 100)
    assert len(actions) == len(keep) and c["durations"].max() <= 100
    n = 1  # the second kept action: context = the 6 frames before it, then its own frames, padded by its last
    start, duration = items.data.starts[keep[n]], items.durations[keep[n]]
    np.testing.assert_array_equal(c["context_rotations"][n], items.data.rotations[start:start + 6])
    np.testing.assert_array_equal(real["joints"][n, :duration], items.data.joints[start + 6:start + 6 + duration])
    np.testing.assert_array_equal(real["joints"][n, duration:], np.broadcast_to(
        items.data.joints[start + 5 + duration], real["joints"][n, duration:].shape))
    np.testing.assert_array_equal(c["paths"], real["translation"][..., [0, 2]])
    np.testing.assert_array_equal(c["follow"], (c["tags"] & root_tag_mask(takes.class_names)).any(axis=1))
    assert c["follow"].any() and not c["follow"].all()
    np.testing.assert_array_equal(c["tags"], items.tags[keep])
    assert real["actions"].tolist() == items.data.actions[keep].tolist()


def test_a_count_spreads_over_the_split_and_bad_data_is_refused(takes):
    every = action_set(takes)
    some = action_set(takes, count=4)
    assert len(some) == 4
    first, last = (np.flatnonzero((every.conditions["context_rotations"] == some.conditions["context_rotations"][i])
                                  .all(axis=(1, 2, 3)))[0] for i in (0, 3))
    assert first == 0 and last == len(every) - 1
    with pytest.raises(ValueError, match="data: synth-humanact12/train has no segment table"):
        action_set(synthetic.generate("synth-humanact12", "train", seed=0, count=2, progress=False))
    with pytest.raises(ValueError, match="ActionProtocol.repetitions"):
        ActionProtocol(repetitions=0)


def test_the_real_actions_as_a_sampler_score_as_the_real_set(takes, recognizer):
    actions = action_set(takes)

    def truth(key, conditions):  # one chunk holds every action, so the real set lines up with it
        assert len(conditions["durations"]) == len(actions)
        return actions.real

    def still(key, conditions):  # each real action's first frame, held
        return {k: np.repeat(actions.real[k][:, :1], conditions["paths"].shape[1], axis=1)
                for k in ("joints", "translation", "rotations")}

    config = ActionProtocol(repetitions=2, chunk=len(actions), joint_error=True)
    rows = evaluate_actions(jax.random.key(0), {"truth": truth, "still": still}, recognizer, actions, config)
    assert list(rows) == ["Real", "truth", "still"]
    np.testing.assert_allclose(rows["truth"]["accuracy"], rows["Real"]["accuracy"])
    np.testing.assert_allclose(rows["truth"]["FID"], 0.0, atol=1e-4)  # (an untrained evaluator's features)
    assert min(rows["still"]["FID"]) > 100 * max(np.abs(rows["truth"]["FID"]))
    np.testing.assert_allclose(rows["truth"]["trajectory_error"], 0.0, atol=1e-6)
    assert min(rows["still"]["trajectory_error"]) > 0.05  # the walking actions' roots move away from the start
    assert rows["truth"]["joint_error"] == [0.0] and rows["still"]["joint_error"][0] > 5.0  # cm
    assert len(rows["truth"]["diversity"]) == 2 and "FID" not in rows["Real"]
    again = evaluate_actions(jax.random.key(0), {"truth": truth, "still": still}, recognizer, actions, config)
    assert again == rows


def test_a_sampler_that_returns_the_wrong_frames_is_named(takes):
    actions = action_set(takes, count=3)
    short = lambda key, c: {"joints": np.zeros((len(c["durations"]), 2, 24, 3))}  # noqa: E731
    with pytest.raises(ValueError, match=r"sampler output: expected a mapping with 'joints' \[N, T, J, 3\]"):
        generate_for(short, None, actions.conditions, 8)
