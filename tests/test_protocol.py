"""The evaluation protocol: rows over repetitions, the Real row, samplers scored against shared draws."""

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.data import Motion, pack
from jaxmotion.data.datasets import load_dataset
from jaxmotion.data.pipeline import BatchSpec, gather_windows, tiled_windows
from jaxmotion.evaluation.protocol import (ProtocolConfig, evaluate, generate, person_features, reference_features,
                                           score)
from jaxmotion.metrics.classification import accuracy, confusion_matrix, mean_class_recall
from jaxmotion.geometry.skeletons import SMPL24
from jaxmotion.models.recognition import Recognizer, RecognizerConfig, init_recognizer
from jaxmotion.progress import ENV_AFTER, ENV_EVERY

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


def test_evaluate_reports_every_pass_when_the_threshold_is_zero_and_its_numbers_stay_the_same(
        data, recognizer, capsys, monkeypatch):
    samplers = {"replay": replay_sampler(data["train"])}
    monkeypatch.setenv(ENV_AFTER, "inf")
    quiet = evaluate(jax.random.key(2), samplers, recognizer, data, CONFIG)
    assert capsys.readouterr().err == ""
    monkeypatch.setenv(ENV_AFTER, "0")
    monkeypatch.setenv(ENV_EVERY, "0")
    shown = evaluate(jax.random.key(2), samplers, recognizer, data, CONFIG)
    lines = capsys.readouterr().err.splitlines()
    assert shown == quiet
    assert all(line.startswith("[eval] pass ") for line in lines)
    # per repetition: the two real sets' features, the generation, the Real row's and replay's scoring
    assert [line.split(" | ")[1] for line in lines] == [
        f"rep {r}/2 {what}" for r in (1, 2)
        for what in ("train reference", "test reference", "replay generating", "Real scoring", "replay scoring")
        for _ in range(3 if what == "replay generating" else 1)]  # 48 clips in chunks of 20
    assert lines[-1].startswith("[eval] pass 10/10 100% | ")


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


# --- ActFormer's protocol: fixed tiled reference, class-mean accuracy and FID, FID_a over persons ----------

ACTFORMER = dataclasses.replace(ProtocolConfig.actformer(repetitions=2), per_class=3, duration=30,
                                reference_window=30, diversity_pairs=20, multimodality_pairs=2, chunk=40)


def fixed_sampler(dataset):
    """A generator that ignores its key: the first 30 frames of a class's first clip for every label."""
    first = {c: int(np.flatnonzero(dataset.actions == c)[0]) for c in range(dataset.num_classes)}

    def sample(key, actions, durations):
        ids = np.array([first[int(a)] for a in np.asarray(actions)])
        frames = dataset.starts[ids][:, None] + np.arange(int(durations[0]))  # [N, T] from each clip's start
        arrays = {k: getattr(dataset, k)[frames] for k in ("joints", "translation", "rotations")}
        if dataset.persons > 1:
            arrays = {k: np.moveaxis(v, 2, 1) for k, v in arrays.items()}
        return {**arrays, "lengths": np.asarray(durations), "actions": np.asarray(actions)}

    return sample


def test_actformer_protocol_scores_every_repetition_against_the_same_tiles(data, recognizer):
    sampler = {"fixed": fixed_sampler(data["train"])}
    rows = evaluate(jax.random.key(4), sampler, recognizer, {"train": data["train"]}, ACTFORMER)
    assert set(rows["fixed"]) == {"accuracy", "FID_train", "FIDm_train", "diversity", "multimodality"}
    for metric in ("FID_train", "FIDm_train", "accuracy"):  # same motions, same reference
        assert rows["fixed"][metric][0] == rows["fixed"][metric][1]
    assert rows["Real"]["FID_train"][0] != rows["Real"]["FID_train"][1]  # the Real row redraws its windows
    drawn = evaluate(jax.random.key(4), sampler, recognizer, {"train": data["train"]},
                     dataclasses.replace(ACTFORMER, reference="draw"))
    assert drawn["fixed"]["FID_train"][0] != drawn["fixed"]["FID_train"][1]  # a redrawn reference moves it
    assert rows["fixed"]["FIDm_train"][0] > rows["Real"]["FIDm_train"][0]  # one clip per class is no distribution


def test_class_mean_accuracy_weighs_every_class_equally(data, recognizer):
    batch = gather_windows(data["train"], np.arange(31), jax.random.key(0), BatchSpec(batch_size=1, window=30))
    actions = np.asarray(batch["actions"])
    reference = {"train": reference_features(recognizer, batch)}
    logits, _ = recognizer(batch)
    confusion = confusion_matrix(jnp.asarray(actions), jnp.argmax(logits, -1), 12)
    for rule, expected in (("overall", accuracy(confusion)), ("class_mean", mean_class_recall(confusion))):
        config = dataclasses.replace(CONFIG, accuracy=rule)
        got = score(jax.random.key(1), recognizer, batch, actions, reference, config)["accuracy"]
        assert got == pytest.approx(float(expected), rel=1e-6)
    assert np.bincount(actions, minlength=12).std() > 0  # unbalanced, so the two rules can differ


def _pairs(dataset):
    """Two-person scenes from one-person clips: each clip and the next one, moved 1.5 m aside."""
    records = []
    for i in range(len(dataset)):
        j = (i + 1) % len(dataset)
        n = int(min(dataset.lengths[i], dataset.lengths[j]))
        clips = [dataset[k] for k in (i, j)]
        shift = np.array([[0.0, 0.0, 0.0], [1.5, 0.0, 0.0]], np.float32)
        records.append(Motion(np.stack([c.joints[:n] for c in clips]) + shift[:, None, None],
                              np.stack([c.translation[:n] for c in clips]) + shift[:, None],
                              np.stack([c.rotations[:n] for c in clips]), action=clips[0].action, mode=0,
                              subject=i, name=f"pair{i}"))
    return pack(records, name="pairs", split="train", class_names=dataset.class_names, skeleton=dataset.skeleton,
                fps=dataset.fps, persons=2)


def test_fid_a_pools_one_person_features_over_the_persons_in_any_order(data, recognizer):
    pairs = _pairs(data["train"])
    two = tiled_windows(pairs, 30)
    pooled = np.asarray(person_features(recognizer, two))
    each = [np.asarray(recognizer({k: v[:, p] for k, v in two.items() if k in ("joints", "translation", "rotations")}
                                  )[1]) for p in range(2)]
    np.testing.assert_allclose(pooled, np.maximum(*each), rtol=1e-5, atol=1e-6)
    swapped = {k: (v[:, ::-1] if k in ("joints", "translation", "rotations") else v) for k, v in two.items()}
    np.testing.assert_allclose(np.asarray(person_features(recognizer, swapped)), pooled, rtol=1e-5, atol=1e-6)
    with pytest.raises(ValueError, match=r"several persons \[N, P, T, J, 3\]"):
        person_features(recognizer, tiled_windows(data["train"], 30))

    pair_recognizer = Recognizer(recognizer.config, SMPL24, recognizer.class_names,
                                 init_recognizer(jax.random.key(5), recognizer.config, SMPL24, 12, frames=30, persons=2))

    def swapping(key, actions, durations):
        motions = fixed_sampler(pairs)(key, actions, durations)
        return {k: (v[:, ::-1] if k in ("joints", "translation", "rotations") else v) for k, v in motions.items()}

    samplers = {"fixed": fixed_sampler(pairs), "swapped": swapping}
    config = dataclasses.replace(ACTFORMER, repetitions=1)
    rows = evaluate(jax.random.key(6), samplers, pair_recognizer, {"train": pairs}, config,
                    person_recognizer=recognizer)
    assert {"FIDa_train", "FIDam_train"} <= set(rows["fixed"])
    assert rows["swapped"]["FIDa_train"][0] == pytest.approx(rows["fixed"]["FIDa_train"][0], rel=1e-4)
    assert rows["swapped"]["FIDam_train"][0] == pytest.approx(rows["fixed"]["FIDam_train"][0], rel=1e-4)
    plain = evaluate(jax.random.key(6), samplers, pair_recognizer, {"train": pairs}, config)
    assert "FIDa_train" not in plain["fixed"]


def test_actformer_protocol_settings_are_checked():
    with pytest.raises(ValueError, match="reference: 'tiles' generates per class"):
        ProtocolConfig(reference="tiles")
    with pytest.raises(ValueError, match=r"ProtocolConfig.accuracy: expected one of"):
        ProtocolConfig(accuracy="balanced")
    with pytest.raises(ValueError, match="reference_window: expected >= 1"):
        ProtocolConfig(reference_window=0)


def test_without_a_recogniser_of_its_own_a_set_is_scored_by_fid_a_alone(data, recognizer):
    """GTA Combat's case: one class no recogniser knows; the one-person recogniser's pooled features only."""
    pairs = _pairs(data["train"])
    config = dataclasses.replace(ACTFORMER, repetitions=1)
    pair_recognizer = Recognizer(recognizer.config, SMPL24, recognizer.class_names,
                                 init_recognizer(jax.random.key(5), recognizer.config, SMPL24, 12, frames=30, persons=2))
    with_own = evaluate(jax.random.key(6), {"fixed": fixed_sampler(pairs)}, pair_recognizer, {"train": pairs}, config,
                        person_recognizer=recognizer)
    alone = evaluate(jax.random.key(6), {"fixed": fixed_sampler(pairs)}, None, {"train": pairs}, config,
                     person_recognizer=recognizer)
    for row in ("fixed", "Real"):
        assert set(alone[row]) == {"FIDa_train", "FIDam_train"}
        for metric in ("FIDa_train", "FIDam_train"):
            assert alone[row][metric] == pytest.approx(with_own[row][metric], rel=1e-6)
    with pytest.raises(ValueError, match="expected a recogniser, or a person_recognizer"):
        evaluate(jax.random.key(6), {"fixed": fixed_sampler(pairs)}, None, {"train": pairs}, config)
