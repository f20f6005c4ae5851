"""ActFormer's training step on the embedded data: representation of the real windows, n_critic critic updates
then one generator update, spectral-norm buffers moving, determinism, and both losses."""

import dataclasses

import jax
import numpy as np
import pytest

from jaxmotion.data import synthetic
from jaxmotion.data.pipeline import make_batch_fn
from jaxmotion.geometry.skeletons import NTU25
from jaxmotion.models.actformer import GeneratorConfig
from jaxmotion.pipelines.actformer import ActFormerGenerator, generate_motions
from jaxmotion.train.actformer import ActFormerTraining, critic_graphs, real_batches, train_actformer
from jaxmotion.train.loop import LoopConfig



def _generator(training, state, data):
    return ActFormerGenerator.trained_on(training.model, state.params["generator"], state.buffers["generator"], data)

def _training(persons=2, loss="hinge", steps=2):
    generator = GeneratorConfig(num_classes=26, persons=persons, frames=16, depth=1, width_per_joint=4, heads=4)
    return ActFormerTraining(generator=generator, loop=LoopConfig(steps=steps, log_every=1, checkpoint_every=0),
                             critic_base_channels=16, batch_size=4, n_critic=2, loss=loss)


@pytest.fixture(scope="module")
def pairs():
    return synthetic.generate("synth-ntu2p", "train", count=52)


def test_real_windows_become_root_and_unit_limb_vectors_split_per_critic_update(pairs):
    training = _training()
    batch = make_batch_fn(pairs, jax.random.key(0), training.batch)(0)
    motions, labels = real_batches(training, batch, NTU25.parents)
    assert motions.shape == (2, 4, 2, 16, 25, 3) and labels.shape == (2, 4)
    # |d| / (|d| + 1e-4): within 1% of unit even for the 2-4 cm hand bones
    np.testing.assert_allclose(np.linalg.norm(np.asarray(motions)[..., 1:, :], axis=-1), 1.0, atol=1e-2)
    roots = np.asarray(motions)[..., 0, :]
    np.testing.assert_allclose(roots.mean(axis=(2, 3)), 0.0, atol=1e-5)  # the clip's mean root removed


@pytest.mark.smoke
@pytest.mark.parametrize("loss", ["hinge", "wgan"])
def test_training_is_deterministic_moves_every_set_and_the_buffers(pairs, loss, tmp_path):
    training = _training(loss=loss)
    first = train_actformer(pairs, training, jax.random.key(1), tmp_path / "a", progress=False)
    again = train_actformer(pairs, training, jax.random.key(1), tmp_path / "b", progress=False)
    for a, b in zip(jax.tree.leaves(first), jax.tree.leaves(again)):
        np.testing.assert_array_equal(np.asarray(a), np.asarray(b))
    from jaxmotion.train.actformer import actformer_state

    k_init = jax.random.split(jax.random.key(1), 3)[0]  # fit's initialisation key
    fresh = actformer_state(training, critic_graphs(training, NTU25.parents), k_init)
    for name in ("generator", "critic"):
        assert int(first.opt_states[name][0].count) == (2 if name == "generator" else 4)  # 2 steps x n_critic 2
        paths = jax.tree_util.tree_flatten_with_path(first.params[name])[0]
        still = [jax.tree_util.keystr(path) for (path, a), b in zip(paths, jax.tree.leaves(fresh.params[name]))
                 if np.allclose(np.asarray(a), np.asarray(b))]
        # the score's bias gets no gradient: real and fake scores enter the losses with opposite signs
        assert still == ([] if name == "generator" else [".conv5.bias"]), (name, still)
        assert not np.allclose(np.asarray(first.buffers[name].head.u if name == "generator"
                                          else first.buffers[name].embedding.u),
                               np.asarray(fresh.buffers[name].head.u if name == "generator"
                                          else fresh.buffers[name].embedding.u))
    log = (tmp_path / "a" / "metrics.jsonl").read_text().splitlines()
    assert len(log) == 2 and all("critic_loss" in line and "generator_loss" in line for line in log)
    motions = generate_motions(_generator(training, first, pairs), jax.random.key(2), np.arange(3))
    assert motions["joints"].shape == (3, 2, 16, 25, 3) and np.isfinite(motions["joints"]).all()


def test_mismatched_data_is_refused(pairs):
    training = dataclasses.replace(_training(), generator=GeneratorConfig(num_classes=26, frames=16, depth=1))
    with pytest.raises(ValueError, match="the generator expects 25, 1 and 26"):
        train_actformer(pairs, training, jax.random.key(0), None, progress=False)


@pytest.mark.smoke
def test_the_recipe_trains_the_graph_convolution_generator_with_its_batch_statistics(pairs):
    """CSGN in ActFormer's recipe: the same step, the generator's buffers its BatchNorm statistics (moved by
    every training-mode pass), the critic still spectrally normalised; generation reads the running statistics,
    so a motion does not depend on the others drawn with it."""
    from jaxmotion.models.csgn import CSGNConfig
    from jaxmotion.recipes.actformer import csgn_table_training

    generator = CSGNConfig(num_classes=26, persons=2, frames=16, widths=(8, 8, 8, 8))
    training = dataclasses.replace(_training(), generator=generator)
    assert training.critic.spectral_norm and not generator.spectral_norm
    state = train_actformer(pairs, training, jax.random.key(1), None, progress=False)
    stats = state.buffers["generator"].input_norm
    assert not np.allclose(np.asarray(stats.running_mean), 0.0) and not np.allclose(np.asarray(stats.running_var), 1.0)
    fitted = _generator(training, state, pairs)
    three = generate_motions(fitted, jax.random.key(2), np.arange(3))
    one = generate_motions(fitted, jax.random.key(2), np.arange(1))
    assert three["joints"].shape == (3, 2, 16, 25, 3)
    np.testing.assert_allclose(one["joints"][0], three["joints"][0], atol=1e-5)
    # the table recipe: the dataset's tree (SMPL-25 adds the translation node), everything else ActFormer's
    smpl = csgn_table_training("synth-ntu1p-smpl", "cpu", temporal="transformer")
    assert smpl.generator.parents[-1] == 0 and len(smpl.generator.parents) == 25 and smpl.generator.channels == 6
    assert smpl.loop == csgn_table_training("synth-ntu1p", "cpu").loop and smpl.critic_base_channels == 8
