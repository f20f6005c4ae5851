"""The evaluation protocol: rows over repetitions, the Real row, samplers scored against shared draws."""

import jax
import numpy as np
import pytest

from jaxmotion.data.datasets import load_dataset
from jaxmotion.data.pipeline import BatchSpec, gather_windows
from jaxmotion.evaluation.protocol import ProtocolConfig, evaluate, generate
from jaxmotion.geometry.skeletons import SMPL24
from jaxmotion.models.recognition import Recognizer, RecognizerConfig, init_recognizer

CONFIG = ProtocolConfig(repetitions=2, max_real=48, duration=30, diversity_pairs=50, multimodality_pairs=5, chunk=20)


@pytest.fixture(scope="module")
def data():
    return {"train": load_dataset("synth-humanact12", count=96),
            "test": load_dataset("synth-humanact12", seed=1, count=48)}


@pytest.fixture(scope="module")
def recognizer():
    config = RecognizerConfig(hidden=16, layers=1, feature_dim=8)
    variables = init_recognizer(jax.random.key(0), config, SMPL24, 12, frames=30)
    return Recognizer(config, SMPL24, tuple(str(i) for i in range(12)), variables)


def replay_sampler(dataset):
    """A perfect generator: a real clip of the requested class for each label."""
    members = [np.flatnonzero(dataset.actions == c) for c in range(dataset.num_classes)]

    def sample(key, actions, durations):
        k_pick, k_window = jax.random.split(key)
        picks = np.asarray(jax.random.randint(k_pick, actions.shape, 0, 1 << 30))
        ids = np.array([members[a][p % len(members[a])] for a, p in zip(np.asarray(actions), picks)])
        return gather_windows(dataset, ids, k_window, BatchSpec(batch_size=1, window=int(durations[0])))

    return sample


def frozen_sampler(dataset):
    """A collapsed generator: crops of one real clip whatever the label."""
    def sample(key, actions, durations):
        ids = np.zeros(actions.shape[0], np.int32)
        return gather_windows(dataset, ids, key, BatchSpec(batch_size=1, window=int(durations[0])))

    return sample


def test_rows_hold_one_value_per_repetition_for_every_metric(data, recognizer):
    rows = evaluate(jax.random.key(0), {"replay": replay_sampler(data["train"])}, recognizer, data, CONFIG)
    assert list(rows) == ["Real", "replay"]
    for cells in rows.values():
        assert set(cells) == {"accuracy", "FID_train", "FID_test", "diversity", "multimodality"}
        assert all(len(v) == CONFIG.repetitions and np.isfinite(v).all() for v in cells.values())


def test_a_perfect_generator_scores_like_the_real_row_and_a_collapsed_one_does_not(data, recognizer):
    samplers = {"replay": replay_sampler(data["train"]), "frozen": frozen_sampler(data["train"])}
    rows = evaluate(jax.random.key(1), samplers, recognizer, {"train": data["train"]}, CONFIG)
    mean = {name: {k: np.mean(v) for k, v in cells.items()} for name, cells in rows.items()}
    assert mean["replay"]["FID_train"] < 3 * mean["Real"]["FID_train"] + 1e-3
    assert mean["frozen"]["FID_train"] > 10 * mean["replay"]["FID_train"]
    assert mean["frozen"]["diversity"] < 0.5 * mean["replay"]["diversity"]
    assert mean["replay"]["diversity"] == pytest.approx(mean["Real"]["diversity"], rel=0.3)


def test_same_key_same_rows(data, recognizer):
    samplers = {"replay": replay_sampler(data["train"])}
    a = evaluate(jax.random.key(2), samplers, recognizer, {"train": data["train"]}, CONFIG)
    b = evaluate(jax.random.key(2), samplers, recognizer, {"train": data["train"]}, CONFIG)
    assert a == b


def test_per_class_protocol_asks_each_class_equally(data, recognizer):
    asked = []

    def counting(key, actions, durations):
        asked.append(np.asarray(actions))
        return replay_sampler(data["train"])(key, actions, durations)

    config = ProtocolConfig(repetitions=1, sampling="per_class", per_class=4, duration=30, chunk=1000)
    rows = evaluate(jax.random.key(3), {"g": counting}, recognizer, {"train": data["train"]}, config)
    np.testing.assert_array_equal(np.bincount(np.concatenate(asked), minlength=12), np.full(12, 4))
    assert len(rows["g"]["accuracy"]) == 1


def test_generate_pads_the_last_chunk_and_keeps_exactly_the_requested_motions(data):
    shapes = []

    def sampler(key, actions, durations):
        shapes.append(actions.shape)
        return replay_sampler(data["train"])(key, actions, durations)

    out = generate(sampler, jax.random.key(0), np.arange(25) % 12, 30, chunk=10)
    assert shapes == [(10,), (10,), (10,)]
    assert out["joints"].shape == (25, 30, 24, 3)
    np.testing.assert_array_equal(out["actions"], np.arange(25) % 12)


def test_bad_samplers_and_names_are_refused(data, recognizer):
    with pytest.raises(ValueError, match="'joints'"):
        generate(lambda k, a, d: {"poses": np.zeros((len(a), 30, 24, 3))}, jax.random.key(0), np.arange(3), 30, 10)
    with pytest.raises(ValueError, match="Real"):
        evaluate(jax.random.key(0), {"Real": replay_sampler(data["train"])}, recognizer, data, CONFIG)
