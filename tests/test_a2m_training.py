"""Training Action2Motion with the library loop (resume is exact) and its sampler for the protocol."""

import shutil

import jax
import numpy as np
import pytest

from jaxmotion.data.motion import SKELETONS, Motion, pack
from jaxmotion.models.a2m import A2MVAEConfig
from jaxmotion.pipelines.a2m import a2m_sampler
from jaxmotion.train.a2m import A2MTraining, a2m_state, a2m_step, train_a2m
from jaxmotion.train.loop import LoopConfig

SMPL24 = SKELETONS["SMPL-24 (HumanAct12)"]
CLASSES = 3


def _data():
    """A few random clips on the SMPL-24 skeleton, some shorter than the window: generating the embedded
    datasets would take longer than the whole test."""
    rng = np.random.default_rng(0)
    motions = []
    for i, frames in enumerate((9, 14, 6, 12, 10, 8)):
        joints = rng.normal(size=(frames, 24, 3)).astype(np.float32)
        motions.append(Motion(joints=joints, translation=joints[:, 0].copy(), rotations=None, action=i % CLASSES))
    return pack(motions, name="toy", split="train", class_names=("a", "b", "c"), skeleton=SMPL24, fps=20)


def _training(steps):
    # one GRU cell per net: compilation dominates the test's time
    return A2MTraining(A2MVAEConfig(pose_dim=72, num_classes=CLASSES, kl_weight=1e-4, hidden=8, latent=4,
                                    decoder_layers=1),
                       LoopConfig(steps, log_every=2, checkpoint_every=2), batch_size=4, window=10)


@pytest.mark.smoke
def test_resumed_training_equals_an_uninterrupted_run_and_the_sampler_gives_protocol_motions(tmp_path):
    data = _data()
    straight = train_a2m(data, _training(4), jax.random.key(0), str(tmp_path / "straight"), progress=False)
    # an interruption after step 2: the same folder without the last checkpoint (one run fewer to compile)
    shutil.copytree(tmp_path / "straight", tmp_path / "resumed")
    shutil.rmtree(tmp_path / "resumed" / "checkpoints" / "4")
    resumed = train_a2m(data, _training(4), jax.random.key(0), str(tmp_path / "resumed"), progress=False)
    for a, b in zip(jax.tree.leaves(straight), jax.tree.leaves(resumed), strict=True):
        np.testing.assert_array_equal(np.asarray(a), np.asarray(b))

    sampler = a2m_sampler(resumed, _training(4).model, SMPL24)
    motions = sampler(jax.random.key(1), np.array([0, 2, 1]), np.array([7, 5, 7]))
    assert motions["joints"].shape == (3, 7, 24, 3) and motions["translation"].shape == (3, 7, 3)
    assert np.isfinite(motions["joints"]).all()
    np.testing.assert_array_equal(motions["lengths"], [7, 5, 7])
    np.testing.assert_array_equal(motions["translation"], motions["joints"][:, :, 0])
    # frames past a duration repeat the last one, as the protocol's real windows do
    np.testing.assert_array_equal(motions["joints"][1, 5:], np.broadcast_to(motions["joints"][1, 4], (2, 24, 3)))
    # each row is drawn from its own key: a row does not depend on the other rows (same shapes: no recompile)
    other = sampler(jax.random.key(1), np.array([0, 1, 2]), np.array([7, 5, 7]))
    np.testing.assert_allclose(other["joints"][0], motions["joints"][0], rtol=1e-5, atol=1e-6)
    assert not np.allclose(other["joints"][2], motions["joints"][2])


def test_mismatched_model_and_data_raise():
    with pytest.raises(ValueError, match="pose_dim 72"):
        train_a2m(_data(), A2MTraining(A2MVAEConfig(pose_dim=72, num_classes=5, kl_weight=0.0), LoopConfig(1)),
                  jax.random.key(0))
    with pytest.raises(ValueError, match="pose_dim 60"):
        a2m_sampler(None, A2MVAEConfig(pose_dim=60, num_classes=3, kl_weight=0.0), SMPL24)


def test_several_persons_are_one_body_of_their_joints_per_frame_person_major():
    """ActFormer's scaling of the baseline to NTU-2P: P·J joints a frame in training, P persons out."""
    rng = np.random.default_rng(1)
    clips = rng.normal(size=(4, 2, 10, 24, 3)).astype(np.float32)
    pairs = pack([Motion(joints=j, translation=j[:, :, 0].copy(), rotations=None, action=i % CLASSES)
                  for i, j in enumerate(clips)], name="pairs", split="train", class_names=("a", "b", "c"),
                 skeleton=SMPL24, fps=20, persons=2)
    model = A2MVAEConfig(pose_dim=144, num_classes=CLASSES, kl_weight=1e-4, hidden=8, latent=4, decoder_layers=1)
    training = A2MTraining(model, LoopConfig(2, log_every=1, checkpoint_every=0), batch_size=4, window=10,
                           canonical=False)
    params = train_a2m(pairs, training, jax.random.key(0), progress=False)
    motions = a2m_sampler(params, model, SMPL24)(jax.random.key(1), np.array([0, 2]), np.array([10, 10]))
    assert motions["joints"].shape == (2, 2, 10, 24, 3) and motions["translation"].shape == (2, 2, 10, 3)
    np.testing.assert_array_equal(motions["translation"], motions["joints"][..., 0, :])
    # the step reads frame t as person 0's joints then person 1's: the same pairs swapped are other poses
    step = jax.jit(a2m_step(model))
    state = a2m_state(training, jax.random.key(2))
    batch = {"joints": clips, "actions": np.array([0, 1, 2, 0])}
    _, metrics = step(state, batch, jax.random.key(3))
    _, swapped = step(state, {**batch, "joints": clips[:, ::-1]}, jax.random.key(3))
    assert np.isfinite(float(metrics["loss"])) and float(metrics["recon"]) != float(swapped["recon"])
    with pytest.raises(ValueError, match=r"pose_dim 72 and 3 classes; pairs has 48 joints in all persons"):
        train_a2m(pairs, _training(1), jax.random.key(0))
