"""ActFormer's generated representations back to the library's motions, and its protocol sampler: round trips
through the representations, row keys independent of the chunking, bad requests refused."""

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.data import synthetic
from jaxmotion.data.pipeline import BatchSpec, epoch_windows
from jaxmotion.geometry.kinematics import forward_kinematics
from jaxmotion.geometry.representations import actformer_features, limb_vectors
from jaxmotion.geometry.rotations import axis_angle_to_matrix
from jaxmotion.models.actformer import GeneratorConfig, normalize_output
from jaxmotion.pipelines.actformer import ActFormerGenerator, generate_motions, to_motions
from jaxmotion.pipelines.artefacts import DataFacts
from jaxmotion.train.actformer import ActFormerTraining, actformer_state, critic_graphs
from jaxmotion.train.loop import LoopConfig


def _training(**generator):
    config = GeneratorConfig(**{"num_classes": 26, "frames": 16, "depth": 1, "width_per_joint": 4, "heads": 4,
                                **generator})
    return ActFormerTraining(generator=config, loop=LoopConfig(steps=1), critic_base_channels=8, batch_size=2)


def _fresh(training, data):
    state = actformer_state(training, critic_graphs(training, data.skeleton.parents), jax.random.key(0))
    return ActFormerGenerator.trained_on(training.model, state.params["generator"], state.buffers["generator"], data)


@pytest.fixture(scope="module")
def pairs():
    return synthetic.generate("synth-ntu2p", "train", count=8)


@pytest.fixture(scope="module")
def smpl():
    return synthetic.generate("synth-ntu1p-smpl", "train", count=4)


def test_skeleton_output_rebuilds_joints_whose_limbs_are_the_generated_unit_vectors(pairs):
    parents = pairs.skeleton.parents
    raw = jax.random.normal(jax.random.key(1), (3, 2, 16, 25, 3))
    motion = normalize_output(raw, "skeleton")
    lengths = _fresh(_training(persons=2), pairs).bone_lengths
    joints = to_motions(motion, "skeleton", pairs.skeleton, lengths)["joints"]
    np.testing.assert_allclose(np.asarray(joints[..., 0, :]), np.asarray(motion[..., 0, :]))
    bones = np.linalg.norm(np.asarray(joints - joints[..., np.maximum(np.array(parents), 0), :]), axis=-1)
    units = np.linalg.norm(np.asarray(motion)[..., 1:, :], axis=-1)  # |tanh| / (|tanh| + 1e-4): just under 1
    np.testing.assert_allclose(bones[..., 1:], lengths[1:] * units, rtol=1e-5)
    # what a 'limbs' recogniser reads again: the unit vectors, to ActFormer's 1e-4 guard over 2-50 cm bones
    np.testing.assert_allclose(np.asarray(limb_vectors(joints, parents))[..., 1:, :], np.asarray(motion)[..., 1:, :],
                               atol=5e-3)
    assert np.all(lengths[1:] > 0.01) and lengths[0] == 0


def test_smpl_output_of_real_features_gives_back_the_real_rotations_and_the_path_about_its_mean(smpl):
    windows = epoch_windows(smpl, jax.random.key(0), BatchSpec(batch_size=1, window=16, canonical=False), 4)
    features = actformer_features("rot6d+translation", smpl.skeleton.parents, windows["joints"],
                                  windows["translation"], windows["rotations"])
    lengths = _fresh(_training(joints=25, channels=6, output="smpl"), smpl).bone_lengths
    out = to_motions(features, "smpl", smpl.skeleton, lengths)
    np.testing.assert_allclose(np.asarray(axis_angle_to_matrix(out["rotations"])),
                               np.asarray(axis_angle_to_matrix(jnp.asarray(windows["rotations"]))), atol=1e-5)
    centred = np.asarray(windows["translation"]) - np.asarray(windows["translation"]).mean(axis=1, keepdims=True)
    np.testing.assert_allclose(np.asarray(out["translation"]), centred, atol=1e-5)
    # joints on the template's rest offsets (the embedded bodies have their own proportions): the root on the path
    np.testing.assert_allclose(np.asarray(out["joints"][..., 0, :]), centred, atol=1e-5)
    expected = forward_kinematics(axis_angle_to_matrix(jnp.asarray(windows["rotations"])), jnp.asarray(centred),
                                  jnp.asarray(smpl.skeleton.offsets), smpl.skeleton.parents)
    np.testing.assert_allclose(np.asarray(out["joints"]), np.asarray(expected), atol=1e-5)


def test_motions_are_lifted_by_the_data_s_mean_root_height(pairs):
    fitted = _fresh(_training(persons=2), pairs)
    np.testing.assert_allclose(fitted.root_height, pairs.joints[..., 0, 1].mean(), rtol=1e-6)
    assert 0.5 < fitted.root_height < 1.5  # a standing pelvis, metres
    motion = normalize_output(jax.random.normal(jax.random.key(3), (2, 16, 25, 3)), "skeleton")
    flat = to_motions(motion, "skeleton", pairs.skeleton, fitted.bone_lengths)["joints"]
    lifted = to_motions(motion, "skeleton", pairs.skeleton, fitted.bone_lengths, fitted.root_height)["joints"]
    np.testing.assert_allclose(np.asarray(lifted - flat), np.broadcast_to([0, fitted.root_height, 0], flat.shape),
                               atol=1e-5)


def test_row_n_depends_on_its_key_only_not_on_the_chunking_or_the_other_rows(pairs):
    training = _training(persons=2)
    trained = _fresh(training, pairs)
    actions = np.array([3, 0, 25, 7, 3])
    whole = generate_motions(trained, jax.random.key(5), actions, chunk=5)
    parts = generate_motions(trained, jax.random.key(5), actions, chunk=2)
    first = generate_motions(trained, jax.random.key(5), actions[:3])
    assert whole["joints"].shape == (5, 2, 16, 25, 3) and whole["lengths"].tolist() == [16] * 5
    scale = 1e-5 * np.abs(whole["joints"]).max()  # float32 sums in other batch shapes (untrained roots are large)
    np.testing.assert_allclose(whole["joints"], parts["joints"], rtol=1e-4, atol=scale)
    np.testing.assert_allclose(whole["joints"][:3], first["joints"], rtol=1e-4, atol=scale)
    assert not np.allclose(whole["joints"][0], whole["joints"][4])  # same class, own latent


def test_the_sampler_refuses_other_durations_skeletons_and_classes(pairs, smpl):
    training = _training(persons=2)
    trained = _fresh(training, pairs)
    sampler = trained.sampler()
    assert sampler(jax.random.key(0), jnp.arange(2), jnp.full(2, 16))["joints"].shape == (2, 2, 16, 25, 3)
    with pytest.raises(ValueError, match="generates 16 frames"):
        sampler(jax.random.key(0), jnp.arange(2), jnp.full(2, 60))
    with pytest.raises(ValueError, match="actions"):
        sampler(jax.random.key(0), jnp.array([26]), jnp.full(1, 16))
    with pytest.raises(ValueError, match="writes 25 joints"):
        dataclasses.replace(trained, facts=DataFacts.of(smpl))
    raw = dataclasses.replace(training, generator=dataclasses.replace(training.generator, output="raw"))
    with pytest.raises(ValueError, match="'raw' output"):
        dataclasses.replace(trained, model=raw.model)
