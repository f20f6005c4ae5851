"""The released Action2Motion recogniser, ported: parity with the PyTorch reference outputs."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.metrics import accuracy, confusion_matrix
from jaxmotion.models.recognition import load_a2m_params, load_a2m_recognizer


@pytest.fixture(scope="module")
def a2m(shared_dir):
    return shared_dir / "a2m"


def test_parity_with_the_pytorch_reference_outputs(a2m):
    recognize = load_a2m_recognizer(a2m / "humanact12_gru_classifier.npz")
    motions = np.load(a2m / "humanact12_a2m_generated_joints.npy")[:4]
    reference = np.load(a2m / "humanact12_reference_first4.npz")
    logits, features = recognize(motions)
    np.testing.assert_allclose(np.asarray(features), reference["features"], atol=1e-4)
    np.testing.assert_allclose(np.asarray(logits), reference["logits"], atol=1e-4)


def test_lengths_read_the_last_real_frame(a2m):
    recognize = load_a2m_recognizer(a2m / "humanact12_gru_classifier.npz")
    motions = np.load(a2m / "humanact12_a2m_generated_joints.npy")[:3]
    _, short_features = recognize(motions[:, :40])
    padded = np.concatenate([motions[:, :40], np.zeros_like(motions[:, :20])], axis=1)
    _, features = recognize(padded, lengths=np.array([40, 40, 40]))
    np.testing.assert_allclose(np.asarray(features), np.asarray(short_features), atol=1e-6)


def test_random_start_is_keyed_and_differs_from_zero_start(a2m):
    recognize = load_a2m_recognizer(a2m / "humanact12_gru_classifier.npz")
    motions = np.load(a2m / "humanact12_a2m_generated_joints.npy")[:2]
    a = recognize(motions, key=jax.random.key(0))[1]
    b = recognize(motions, key=jax.random.key(0))[1]
    np.testing.assert_array_equal(np.asarray(a), np.asarray(b))
    assert not np.allclose(np.asarray(a), np.asarray(recognize(motions)[1]))


@pytest.mark.parametrize("name, features", [("cmu_mocap_gru_classifier.npz", 60),
                                            ("ntu13_vibe_gru_classifier.npz", 54),
                                            ("humanact12_fine_gru_classifier.npz", 72)])
def test_every_released_recogniser_loads(a2m, name, features):
    params = load_a2m_params(a2m / name)
    assert params.layers[0].w_ih.shape == (384, features)


def test_bad_inputs_name_the_problem(a2m, tmp_path):
    recognize = load_a2m_recognizer(a2m / "humanact12_gru_classifier.npz")
    with pytest.raises(ValueError, match=r"motions: expected shape \[B, T, 72\]"):
        recognize(np.zeros((2, 10, 60), np.float32))
    with pytest.raises(FileNotFoundError, match="not found"):
        load_a2m_params(tmp_path / "missing.npz")
    np.savez(tmp_path / "broken.npz", **{"recurrent.weight_ih_l0": np.zeros((384, 72))})
    with pytest.raises(ValueError, match="missing array 'recurrent.weight_hh_l0'"):
        load_a2m_params(tmp_path / "broken.npz")


def test_released_recogniser_accuracy_on_action2motion_generated_motions(a2m):
    # the known value for the 20 motions in shared/a2m, zero initial state: 15 of 20 recognised
    recognize = load_a2m_recognizer(a2m / "humanact12_gru_classifier.npz")
    motions = np.load(a2m / "humanact12_a2m_generated_joints.npy")
    labels = np.load(a2m / "humanact12_a2m_generated_labels.npy")
    logits, _ = recognize(motions)
    confusion = confusion_matrix(jnp.asarray(labels), jnp.argmax(logits, -1), num_classes=12)
    assert int(confusion.sum()) == 20
    assert float(accuracy(confusion)) == pytest.approx(0.75)
