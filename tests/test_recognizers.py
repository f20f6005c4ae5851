"""Evaluators trained on the embedded data: inputs, invariances, training, caching, the experiment."""

import dataclasses
import json
import pickle
import subprocess
import sys
import time

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.config import replace_paths
from jaxmotion.data.datasets import load_dataset
from jaxmotion.data.pipeline import BatchSpec, epoch_windows
from jaxmotion.evaluation import recognizers
from jaxmotion.evaluation.recognizers import cache_folder, trained_recognizer
from jaxmotion.recipes.evaluators import EVALUATORS, evaluator_spec
from jaxmotion.files import folder_lock
from jaxmotion.geometry.rotations import axis_angle_to_matrix, matrix_to_axis_angle
from jaxmotion.geometry.skeletons import SMPL24
from jaxmotion.models.recognition import (
    Recognizer,
    RecognizerConfig,
    init_gru_recognizer,
    init_recognizer,
    load_a2m_params,
    recognizer_inputs,
)

SMALL_GRU = RecognizerConfig(hidden=16, layers=2, feature_dim=8)
SMALL_STGCN = RecognizerConfig(architecture="stgcn", inputs="rot6d", channels=(8, 16), strides=(1, 2))
SMALL_TRANSFORMER = RecognizerConfig(architecture="transformer", inputs="rot6d+translation", hidden=16, layers=1,
                                     heads=2, feature_dim=8, dropout=0.1)


@pytest.fixture(scope="module")
def windows():
    data = load_dataset("synth-humanact12", count=24)
    return epoch_windows(data, jax.random.key(0), BatchSpec(batch_size=1, window=30, canonical=False), 12)


def _untrained(config):
    variables = init_recognizer(jax.random.key(1), config, SMPL24, 12, frames=30)
    return Recognizer(config, SMPL24, tuple(f"class {i}" for i in range(12)), variables)


def test_scoring_a_dataset_of_other_classes_is_refused():
    """A 12-class evaluator on UESTC's 40 classes would give a plausible accuracy near 0 without a word."""
    with pytest.raises(ValueError, match=r"evaluator: it recognises 12 classes, but the real set 'train' "
                                         r"\(synth-uestc\) has 40"):
        recognizers.evaluate_recognizer(_untrained(SMALL_GRU), load_dataset("synth-uestc", count=40),
                                        jax.random.key(0), window=30)


def _turn_and_move(motions, angle, shift):
    """The same motions, turned about the vertical by ``angle`` and moved by ``shift`` (a new placement)."""
    c, s = np.cos(angle), np.sin(angle)
    rot = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]], np.float32)
    root = np.asarray(matrix_to_axis_angle(jnp.einsum("ij,btjk->btik", rot, axis_angle_to_matrix(motions["rotations"][:, :, 0]))))
    rotations = motions["rotations"].copy()
    rotations[:, :, 0] = root
    return {"joints": motions["joints"] @ rot.T + shift, "translation": motions["translation"] @ rot.T + shift,
            "rotations": rotations}


@pytest.mark.parametrize("config", [SMALL_GRU, SMALL_STGCN, SMALL_TRANSFORMER],
                         ids=["gru-joints", "stgcn-rot6d", "transformer-rot6d+translation"])
def test_recognizer_output_does_not_depend_on_placement_or_heading(windows, config):
    recognizer = _untrained(config)
    logits, features = recognizer(windows)
    moved_logits, moved_features = recognizer(_turn_and_move(windows, 2.1, np.array([3.0, 0.0, -1.5], np.float32)))
    assert features.shape == (12, config.features) and logits.shape == (12, 12)
    np.testing.assert_allclose(np.asarray(moved_features), np.asarray(features), atol=2e-4)
    np.testing.assert_allclose(np.asarray(moved_logits), np.asarray(logits), atol=2e-4)


def test_the_transformer_recogniser_reads_only_the_real_frames_and_trains_with_dropout(windows):
    from jaxmotion.models.recognition import apply_recognizer

    recognizer = _untrained(SMALL_TRANSFORMER)
    x = recognizer_inputs(SMALL_TRANSFORMER, SMPL24, windows)  # [B, T, J + 1, 6]
    lengths = np.full(12, 20)

    def logits(inputs, key=None):
        return apply_recognizer(SMALL_TRANSFORMER, SMPL24, 12, {"params": recognizer.variables["params"]}, inputs,
                                lengths, train=key is not None, key=key)[0][0]

    garbage = x.at[:, 20:].set(7.0)  # past every length: never read
    np.testing.assert_allclose(np.asarray(logits(garbage)), np.asarray(logits(x)), atol=1e-5)

    def loss(params, key):
        out = apply_recognizer(SMALL_TRANSFORMER, SMPL24, 12, {"params": params}, x, train=True, key=key)
        return out[0][0].sum()

    grads = jax.grad(loss)(recognizer.variables["params"], jax.random.key(1))
    assert all(np.isfinite(np.asarray(g)).all() for g in jax.tree.leaves(grads))
    assert float(logits(x, jax.random.key(1)).sum()) != float(logits(x, jax.random.key(2)).sum())  # dropout


def test_rot6d_recognizer_refuses_joint_only_motions(windows):
    with pytest.raises(ValueError, match=r"motions\['rotations'\].*\[B, T, 24, 3\]"):
        recognizer_inputs(SMALL_STGCN, SMPL24, {"joints": windows["joints"]})
    with pytest.raises(ValueError, match=r"motions\['joints'\]: expected \[B, T, 24, 3\]"):
        recognizer_inputs(SMALL_GRU, SMPL24, {"joints": windows["joints"][..., :20, :]})


def test_chunked_calls_equal_one_call(windows):
    config = SMALL_GRU
    one = _untrained(config)
    chunked = dataclasses.replace(one, chunk=5)
    np.testing.assert_allclose(np.asarray(chunked(windows)[1]), np.asarray(one(windows)[1]), atol=1e-6)


def test_fresh_gru_has_the_released_action2motion_layout(shared_dir):
    released = load_a2m_params(shared_dir / "a2m" / "humanact12_gru_classifier.npz")
    fresh = init_gru_recognizer(jax.random.key(0), 72, 12)
    assert jax.tree.map(jnp.shape, fresh) == jax.tree.map(jnp.shape, released)


@pytest.mark.parametrize("profile", ["smoke", "cpu", "paper"])
def test_every_standard_evaluator_has_a_spec_in_every_profile(profile):
    specs = [evaluator_spec(name, profile) for name in EVALUATORS]
    assert [s.name for s in specs] == list(EVALUATORS)
    assert specs[3].recognizer.inputs == "rot6d" and specs[4].recognizer.architecture == "gru"
    if profile != "smoke":
        assert specs[4].recognizer.hidden == 256 and specs[4].recognizer.layers == 3  # ODMO's UESTC GRU
    with pytest.raises(ValueError, match="unknown evaluator"):
        evaluator_spec("synth-uestc/transformer", profile)
    # only the embedded-data ST-GCN is trained with input noise; the paper profile keeps the reference recipe
    noisy = profile != "paper"
    assert [s.input_noise > 0 for s in specs] == ([False, False, False, noisy] + [False] * 7
                                                  + [noisy, False, noisy, False, False, False])
    if profile == "cpu":  # the 94 and 120 classes of NTU-1P and BABEL-120 get twice the steps
        assert [s.loop.steps for s in specs[5:]] == [3000, 3000, 1500, 3000, 1500, 3000, 3000, 1500, 3000, 3000,
                                                     3000, 3000]
    # ActFormer's: its representations, trained on the other split; the pair stacked on channels, permuted
    actformer = specs[9:15]
    assert [s.recognizer.inputs for s in actformer] == ["limbs", "limbs", "rot6d+translation", "limbs",
                                                        "rot6d+translation", "limbs"]
    assert [s.recognizer.graph_center for s in actformer] == [9, 20, 0, 20, 0, 0]
    assert [s.recognizer.topology for s in actformer] == ["own"] * 5 + ["joints15"]  # GTA Combat's FID_a
    assert all(s.trains_on == "held_out" and s.recognizer.dropout == 0.5 and not s.recognizer.canonical
               for s in actformer)
    assert [(s.recognizer.persons, s.permute_persons, s.window) for s in actformer] == (
        [("average", False, 64)] * 3 + [("channels", True, 60)] + [("average", False, 64)] * 2)
    if profile == "paper":
        assert all(s.optimizer == "sgd" and s.learning_rate == 0.1 for s in actformer)
    # Neural Marionette's: a Transformer on synth-mag's actions, trained on its train split
    marionette, revision = specs[15:]
    assert (marionette.dataset, marionette.recognizer.architecture, marionette.trains_on) == (
        "synth-mag", "transformer", "train")
    # Action Revision's classifier: the same recipe, trained apart (another seed, so another cache entry)
    assert dataclasses.replace(revision, seed=marionette.seed) == marionette and revision.seed != marionette.seed
    assert cache_folder(revision) != cache_folder(marionette)


def test_negative_input_noise_is_refused():
    with pytest.raises(ValueError, match="input_noise"):
        dataclasses.replace(evaluator_spec("synth-uestc/stgcn", "smoke"), input_noise=-0.1)


def test_cache_folder_changes_with_every_field_of_the_spec(tmp_path):
    spec = evaluator_spec("synth-humanact12/gru", "smoke")
    folders = {cache_folder(spec, tmp_path), cache_folder(replace_paths(spec, {"loop.steps": 21}), tmp_path),
               cache_folder(dataclasses.replace(spec, seed=1), tmp_path),
               cache_folder(dataclasses.replace(spec, recognizer=SMALL_GRU), tmp_path),
               cache_folder(dataclasses.replace(spec, input_noise=0.01), tmp_path)}
    assert len(folders) == 5


def _humanact12_folder(folder, clips=(30, 40, 35, 50)):
    """A tiny HumanAct12 folder in the authors' pickle layout (every clip train; no test split)."""
    rng = np.random.default_rng(0)
    folder.mkdir(parents=True, exist_ok=True)
    data = {"poses": [0.1 * rng.normal(size=(t, 72)) for t in clips],
            "joints3D": [rng.normal(size=(t, 24, 3)) for t in clips], "y": [i % 12 for i in range(len(clips))],
            "oldposes": []}
    (folder / "humanact12poses.pkl").write_bytes(pickle.dumps(data))
    return folder


def test_a_real_data_evaluator_is_keyed_by_the_resolved_folder_and_its_files(tmp_path, monkeypatch):
    spec = dataclasses.replace(evaluator_spec("synth-humanact12/gru", "smoke"), dataset="humanact12")
    for name in ("a", "b"):
        _humanact12_folder(tmp_path / name / "data")
    monkeypatch.chdir(tmp_path / "a")
    in_a = cache_folder(spec, tmp_path, data_root="data")
    assert cache_folder(spec, tmp_path, data_root=str(tmp_path / "a" / "data")) == in_a  # two spellings, one folder
    monkeypatch.chdir(tmp_path / "b")
    assert cache_folder(spec, tmp_path, data_root="data") != in_a  # one spelling, two folders
    in_b = cache_folder(spec, tmp_path, data_root="data")
    (tmp_path / "b" / "data" / "extra.npy").write_bytes(b"1")
    assert cache_folder(spec, tmp_path, data_root="data") != in_b  # the files changed


def test_the_evaluator_cache_key_holds_the_usable_cpu_cores(tmp_path, monkeypatch):
    spec = evaluator_spec("synth-humanact12/gru", "smoke")
    two = cache_folder(spec, tmp_path)
    monkeypatch.setattr(recognizers, "usable_cpus", lambda: 1)  # e.g. under taskset -c 0
    assert cache_folder(spec, tmp_path) != two
    assert recognizers.training_machine()["cpu_threads"] == 1


def test_a_real_dataset_without_a_test_split_fails_before_training(tmp_path):
    spec = dataclasses.replace(evaluator_spec("synth-humanact12/gru", "smoke"), dataset="humanact12", count=None)
    root = _humanact12_folder(tmp_path / "HumanAct12Poses")
    with pytest.raises(ValueError, match="no split 'test'"):
        trained_recognizer(spec, cache_dir=tmp_path / "cache", data_root=str(root), progress=False)
    assert not (cache_folder(spec, tmp_path / "cache", data_root=str(root)) / "checkpoints").exists()


@pytest.mark.integration
def test_a_second_process_wanting_an_evaluator_in_training_waits_and_reads_it(tmp_path):
    spec = replace_paths(evaluator_spec("synth-humanact12/gru", "smoke"), {"window": 30, "loop.steps": 10})
    probe = ("import sys; from jaxmotion.evaluation.recognizers import trained_recognizer\n"
             "from jaxmotion.recipes.evaluators import evaluator_spec\n"
             "from jaxmotion.config import replace_paths\n"
             "spec = replace_paths(evaluator_spec('synth-humanact12/gru', 'smoke'), {'window': 30, 'loop.steps': 10})\n"
             f"_, record = trained_recognizer(spec, cache_dir={str(tmp_path)!r})\nprint(record['held_out']['accuracy'])")
    log = tmp_path / "other.log"
    with folder_lock(cache_folder(spec, tmp_path), what="evaluator cache"), log.open("w") as err:
        other = subprocess.Popen([sys.executable, "-c", probe], stdout=subprocess.PIPE, stderr=err, text=True)
        deadline = time.monotonic() + 120
        while "waiting for" not in log.read_text():
            assert other.poll() is None and time.monotonic() < deadline, log.read_text()
            time.sleep(0.05)
        _, record = trained_recognizer(spec, cache_dir=tmp_path, progress=False)
    out, _ = other.communicate(timeout=300)
    assert other.returncode == 0, log.read_text()
    assert float(out) == record["held_out"]["accuracy"] and "[evaluator] training" not in log.read_text()


@pytest.mark.smoke
def test_trained_evaluator_is_cached_and_read_back_identically(tmp_path, windows):
    spec = replace_paths(evaluator_spec("synth-humanact12/gru", "smoke"), {"window": 30, "loop.steps": 10})
    first, record = trained_recognizer(spec, cache_dir=tmp_path, progress=False)
    folder = cache_folder(spec, tmp_path)
    assert json.loads((folder / "recognizer.json").read_text())["held_out"] == record["held_out"]
    # the record holds what the trained evaluator scores on its held-out split
    assert record["held_out"] == recognizers.evaluate_recognizer(
        first, recognizers.held_out_data(spec), jax.random.key(spec.seed + 1), window=spec.window,
        count=spec.test_count)
    again, record_again = trained_recognizer(spec, cache_dir=tmp_path)
    assert record_again == record
    np.testing.assert_array_equal(np.asarray(again(windows)[1]), np.asarray(first(windows)[1]))


@pytest.mark.smoke
def test_recognition_experiment_smoke_writes_its_table(tmp_path, monkeypatch):
    from experiments import recognition

    monkeypatch.setenv("JAXMOTION_CACHE", str(tmp_path / "cache"))
    result = recognition.main(["--profile", "smoke", "--out", str(tmp_path / "out"),
                               "--set", 'only=["synth-cmu/gru"]'])
    row = result["rows"]["synth-cmu/gru"]
    assert set(row) == {"held-out accuracy (%)", "train accuracy (%)", "held-out clips"}
    record = json.loads((cache_folder(evaluator_spec("synth-cmu/gru", "smoke"), tmp_path / "cache")
                         / "recognizer.json").read_text())
    assert row["held-out accuracy (%)"] == 100 * record["held_out"]["accuracy"]  # the cached evaluator's
    assert row["held-out clips"] == record["held_out"]["clips"] == evaluator_spec("synth-cmu/gru", "smoke").test_count
    assert (tmp_path / "out" / "recognition" / "smoke" / "seed-0" / "table.md").exists()
    # The same run with its evaluator cached and another one the config names beside it: the same metrics.json,
    # byte for byte (it records the evaluators the run used, nothing read from other cache entries).
    other = cache_folder(evaluator_spec("synth-humanact12/gru", "smoke"), tmp_path / "cache")
    other.mkdir(parents=True)
    (other / "recognizer.json").write_text(json.dumps({**record, "held_out": {**record["held_out"], "accuracy": 0.5}}))
    recognition.main(["--profile", "smoke", "--out", str(tmp_path / "again"), "--set", 'only=["synth-cmu/gru"]'])
    assert ((tmp_path / "again" / "recognition" / "smoke" / "seed-0" / "metrics.json").read_bytes()
            == (tmp_path / "out" / "recognition" / "smoke" / "seed-0" / "metrics.json").read_bytes())


@pytest.fixture(scope="module")
def two_person_windows():
    data = load_dataset("synth-ntu2p", count=26)
    return epoch_windows(data, jax.random.key(0), BatchSpec(batch_size=1, window=30, canonical=False), 8)


def _untrained_ntu(config, persons):
    from jaxmotion.geometry.skeletons import NTU25

    variables = init_recognizer(jax.random.key(1), config, NTU25, 26, frames=30, persons=persons)
    return Recognizer(config, NTU25, tuple(f"class {i}" for i in range(26)), variables)


def test_two_person_motions_are_read_together_and_placed_by_the_first_person(two_person_windows):
    """The GRU reads both persons in their order, the ST-GCN averages them (order-free); both see the pair in
    the first person's canonical frame, so moving the pair together changes nothing."""
    w = two_person_windows
    assert w["joints"].shape[:3] == (8, 2, 30)
    swapped = {k: w[k][:, ::-1] for k in ("joints", "translation")}
    c, s = np.cos(0.7), np.sin(0.7)
    rot = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]], np.float32)
    moved = {k: w[k] @ rot.T + np.array([1.0, 0.0, 2.0], np.float32) for k in ("joints", "translation")}
    joints_stgcn = RecognizerConfig(architecture="stgcn", inputs="joints", channels=(8, 16), strides=(1, 2))
    for config in (SMALL_GRU, joints_stgcn):
        recognizer = _untrained_ntu(config, persons=2)
        logits, _ = recognizer(w)
        assert logits.shape == (8, 26)
        np.testing.assert_allclose(np.asarray(recognizer(moved)[0]), np.asarray(logits), atol=2e-4)
        first_as_frame = {k: np.ascontiguousarray(v) for k, v in swapped.items()}
        if config.architecture == "stgcn":  # averaged persons: only the canonical frame's owner changes
            plain = dataclasses.replace(config, canonical=False)
            order_free = _untrained_ntu(plain, persons=2)
            np.testing.assert_allclose(np.asarray(order_free(first_as_frame)[0]), np.asarray(order_free(w)[0]),
                                       atol=2e-4)
        else:  # the GRU's input order is the persons' order
            assert not np.allclose(np.asarray(recognizer(first_as_frame)[0]), np.asarray(logits), atol=1e-3)


def test_one_person_on_a_persons_axis_reads_as_without_it(windows):
    recognizer = _untrained(SMALL_GRU)
    with_axis = {k: windows[k][:, None] for k in ("joints", "translation", "rotations")}
    np.testing.assert_allclose(np.asarray(recognizer(with_axis)[0]), np.asarray(recognizer(windows)[0]), atol=1e-6)


def test_a_two_person_evaluator_is_cached_with_its_persons(tmp_path, two_person_windows):
    spec = replace_paths(evaluator_spec("synth-humanact12/gru", "smoke"),
                         {"dataset": "synth-ntu2p", "window": 30, "loop.steps": 5, "count": 52, "test_count": 20})
    first, record = trained_recognizer(spec, cache_dir=tmp_path, progress=False)
    assert record["persons"] == 2 and len(record["class_names"]) == 26
    again, _ = trained_recognizer(spec, cache_dir=tmp_path)
    np.testing.assert_array_equal(np.asarray(again(two_person_windows)[0]), np.asarray(first(two_person_windows)[0]))


def test_actformer_representations_feed_the_st_gcn(windows, two_person_windows):
    """Limb vectors (NTU-25, centre 20, two persons) and rot6d with the translation as a 25th node (SMPL)."""
    from jaxmotion.geometry.skeletons import NTU25

    limbs = dataclasses.replace(RecognizerConfig.actformer_stgcn("limbs", graph_center=20), channels=(8, 16),
                                strides=(1, 2))
    x = recognizer_inputs(limbs, NTU25, two_person_windows)
    assert x.shape == (8, 2, 30, 25, 3)
    # unit up to |d| / (|d| + 1e-4): a thumb bone of a few mm (Kinect capture) falls 2% short
    np.testing.assert_allclose(np.linalg.norm(np.asarray(x)[..., 1:, :], axis=-1), 1.0, atol=3e-2)
    np.testing.assert_allclose(np.asarray(x)[..., 0, :].mean(axis=(1, 2)), 0.0, atol=1e-5)
    logits, _ = _untrained_ntu(limbs, persons=2)(two_person_windows)
    assert logits.shape == (8, 26)
    smpl = dataclasses.replace(RecognizerConfig.actformer_stgcn("rot6d+translation"), channels=(8, 16), strides=(1, 2))
    x = recognizer_inputs(smpl, SMPL24, windows)
    assert x.shape == (12, 30, 25, 6)
    np.testing.assert_allclose(np.asarray(x)[..., 24, :3].mean(axis=1), 0.0, atol=1e-5)  # de-meaned translation
    np.testing.assert_array_equal(np.asarray(x)[..., 24, 3:], 0.0)
    recognizer = _untrained(smpl)
    assert recognizer(windows)[0].shape == (12, 12)
    with pytest.raises(ValueError, match=r"reads rot6d\+translation and needs axis-angle rotations"):
        recognizer_inputs(smpl, SMPL24, {"joints": windows["joints"]})


def test_stacked_persons_are_read_in_order_and_averaged_ones_are_not(two_person_windows):
    """ActFormer's two-person evaluator stacks the pair's channels (P·C in), so swapping them matters."""
    stacked = RecognizerConfig(architecture="stgcn", inputs="joints", canonical=False, channels=(8, 16),
                               strides=(1, 2), persons="channels")
    recognizer = _untrained_ntu(stacked, persons=2)
    w = two_person_windows
    swapped = {k: np.ascontiguousarray(w[k][:, ::-1]) for k in ("joints", "translation")}
    assert not np.allclose(np.asarray(recognizer(swapped)[0]), np.asarray(recognizer(w)[0]), atol=1e-3)
    averaged = _untrained_ntu(dataclasses.replace(stacked, persons="average"), persons=2)
    np.testing.assert_allclose(np.asarray(averaged(swapped)[0]), np.asarray(averaged(w)[0]), atol=2e-4)
    with pytest.raises(ValueError, match="RecognizerConfig.persons"):
        dataclasses.replace(stacked, persons="max")


def test_an_evaluator_trained_on_the_other_split_is_checked_on_the_train_split():
    spec = dataclasses.replace(evaluator_spec("synth-humanact12/gru", "smoke"), trains_on="held_out")
    train, held_out = recognizers.training_data(spec), recognizers.held_out_data(spec)
    np.testing.assert_array_equal(train.joints, load_dataset("synth-humanact12", seed=1, count=120).joints)
    np.testing.assert_array_equal(held_out.joints, load_dataset("synth-humanact12", count=120).joints)
    with pytest.raises(ValueError, match="trains_on"):
        dataclasses.replace(spec, trains_on="test")


def test_sgd_recipe_is_nesterov_with_the_decay_in_the_gradient_and_step_drops():
    """Two steps on f(w) = w²/2 (gradient w) by hand, as PyTorch's SGD(nesterov=True, weight_decay)."""
    spec = dataclasses.replace(evaluator_spec("synth-ntu1p/stgcn", "paper"), learning_rate=0.1, weight_decay=0.5,
                               decay_steps=(1,))
    tx = recognizers.recognizer_optimizer(spec)
    w, state = jnp.array(2.0), tx.init(jnp.array(2.0))
    expected, buf = 2.0, 0.0
    for lr in (0.1, 0.01):
        g = expected + 0.5 * expected
        buf = 0.9 * buf + g
        expected -= lr * (g + 0.9 * buf)
        update, state = tx.update(w, state, w)
        w = w + update
        assert float(w) == pytest.approx(expected, rel=1e-6)
    with pytest.raises(ValueError, match="optimizer"):
        dataclasses.replace(spec, optimizer="rmsprop")


def test_the_fields_added_later_leave_older_cache_keys_alone(tmp_path):
    spec = evaluator_spec("synth-humanact12/gru", "smoke")
    assert "trains_on" not in recognizers._cache_spec(spec) and "persons" not in recognizers._cache_spec(spec)["recognizer"]
    assert cache_folder(dataclasses.replace(spec, trains_on="held_out"), tmp_path) != cache_folder(spec, tmp_path)


def test_a_joints15_recogniser_reads_ntu_and_gta_motions_through_their_common_joints(two_person_windows):
    """The same 15 joints give the same logits whichever skeleton holds them; the other joints are ignored."""
    from jaxmotion.geometry.skeletons import GTA22, JOINTS15, NTU25, joints15_indices

    config = RecognizerConfig(architecture="stgcn", inputs="limbs", canonical=False, channels=(8, 16),
                              strides=(1, 2), topology="joints15")
    variables = init_recognizer(jax.random.key(2), config, NTU25, 26, frames=30)
    ntu = Recognizer(config, NTU25, tuple(f"class {i}" for i in range(26)), variables)
    assert variables["params"] is not None and recognizer_inputs(config, NTU25, two_person_windows).shape[-2] == 15
    ntu_joints = np.asarray(two_person_windows["joints"])[:, 0]  # [B, T, 25, 3]
    gta_joints = np.random.default_rng(0).normal(size=(*ntu_joints.shape[:2], 22, 3)).astype(np.float32)
    gta_joints[..., joints15_indices(GTA22), :] = ntu_joints[..., joints15_indices(NTU25), :]
    gta = ntu.reading(GTA22)
    np.testing.assert_allclose(np.asarray(gta({"joints": gta_joints})[0]), np.asarray(ntu({"joints": ntu_joints})[0]),
                               atol=1e-5)
    assert ntu.reading(NTU25) is ntu and ntu.reading(JOINTS15).skeleton is JOINTS15
    with pytest.raises(ValueError, match="reads NTU-25 \\(Kinect v2\\) motions only"):
        _untrained_ntu(dataclasses.replace(config, topology="own"), persons=1).reading(GTA22)
    with pytest.raises(ValueError, match="no mapping onto the 15-joint topology"):
        ntu.reading(SMPL24)
    with pytest.raises(ValueError, match="RecognizerConfig.inputs: the joints15 topology keeps joint positions"):
        RecognizerConfig(architecture="stgcn", inputs="rot6d", topology="joints15")


@pytest.mark.smoke
def test_the_synth_mag_evaluator_reads_actions_labelled_with_their_first_tag(tmp_path):
    spec = evaluator_spec("synth-mag/transformer", "smoke")
    recognizer, record = trained_recognizer(spec, cache_dir=tmp_path, progress=False)
    assert recognizer.class_names == recognizers.training_data(spec).class_names and recognizer.num_classes == 31
    held_out = recognizers.held_out_data(spec)
    assert held_out.segments is None and len(held_out) > 24  # the takes' actions, not the takes
    assert record["held_out"]["clips"] == spec.test_count and 0 < record["held_out"]["accuracy"] <= 1
