"""Wrong labels, classes and durations are errors, where they enter, naming what is wrong."""

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.data.datasets import load_dataset
from jaxmotion.evaluation.protocol import ProtocolConfig, evaluate
from jaxmotion.evaluation.recognizers import RecognizerTraining
from jaxmotion.recipes.evaluators import evaluator_spec
from jaxmotion.evaluation.tables import TableData
from jaxmotion.geometry.skeletons import SMPL24
from jaxmotion.metrics.classification import accuracy, confusion_matrix
from jaxmotion.models import actor
from jaxmotion.models.a2m import A2MVAEConfig, a2m_generate, init_a2m_vae
from jaxmotion.models.recognition import Recognizer, RecognizerConfig, init_recognizer
from jaxmotion.pipelines.a2m import a2m_sampler
from jaxmotion.pipelines.actor import actor_sampler, generate_motions

ACTOR = actor.ActorConfig(num_classes=12, num_joints=25, width=16, ff=32, layers=1, heads=2)
A2M = A2MVAEConfig(pose_dim=72, num_classes=12, hidden=16, latent=4, kl_weight=1e-2)


@pytest.fixture(scope="module")
def actor_params():
    return actor.init_actor(jax.random.key(0), ACTOR)


@pytest.fixture(scope="module")
def a2m_params():
    return init_a2m_vae(jax.random.key(0), A2M)


@pytest.mark.parametrize("labels, message", [([0, -1, 2], r"labels: expected class ids in \[0, 3\).*\[-1\]"),
                                             ([0, 3, 2], r"labels: expected class ids in \[0, 3\).*\[3\]")])
def test_confusion_matrix_rejects_labels_outside_the_classes(labels, message):
    predictions = jnp.array([0, 1, 2])
    with pytest.raises(ValueError, match=message):
        confusion_matrix(jnp.array(labels), predictions, 3)
    with pytest.raises(ValueError, match="predictions: expected class ids"):
        confusion_matrix(predictions, jnp.array(labels), 3)
    # in range: the known value
    assert float(accuracy(confusion_matrix(jnp.array([0, 1, 2, 2]), jnp.array([0, 1, 2, 0]), 3))) == 0.75


@pytest.mark.parametrize("action", [12, 99, -1])
def test_every_actor_generator_rejects_an_action_outside_the_classes(actor_params, action):
    actions, durations = np.array([0, action]), np.array([20, 20])
    match = r"actions: expected class ids in \[0, 12\)"
    with pytest.raises(ValueError, match=match):
        actor.generate(ACTOR, actor_params, actions, durations, 20, key=jax.random.key(1))
    with pytest.raises(ValueError, match=match):
        generate_motions(actor_params, ACTOR, jax.random.key(1), actions, durations, SMPL24)
    with pytest.raises(ValueError, match=match):
        actor_sampler(actor_params, ACTOR, SMPL24)(jax.random.key(1), actions, durations)


@pytest.mark.parametrize("duration", [0, -3])
def test_actor_samplers_reject_durations_below_one(actor_params, duration):
    with pytest.raises(ValueError, match=r"durations: expected frame counts in \[1"):
        actor_sampler(actor_params, ACTOR, SMPL24)(jax.random.key(1), np.array([0, 1]), np.array([20, duration]))
    with pytest.raises(ValueError, match=r"durations: expected frame counts in \[1"):
        generate_motions(actor_params, ACTOR, jax.random.key(1), np.array([0, 1]), np.array([20, duration]), SMPL24)


def test_actor_generate_rejects_durations_beyond_its_frames(actor_params):
    with pytest.raises(ValueError, match=r"durations: expected frame counts in \[1, 20\], got values from 5 to 30"):
        actor.generate(ACTOR, actor_params, np.array([0, 1]), np.array([5, 30]), 20, key=jax.random.key(1))


def test_a2m_generators_reject_actions_and_durations_outside_their_range(a2m_params):
    with pytest.raises(ValueError, match=r"actions: expected class ids in \[0, 12\)"):
        a2m_generate(A2M, a2m_params, jnp.array([0, 12]), 10, key=jax.random.key(1))
    sampler = a2m_sampler(a2m_params, A2M, SMPL24)
    with pytest.raises(ValueError, match=r"actions: expected class ids in \[0, 12\)"):
        sampler(jax.random.key(1), np.array([-1, 0]), np.array([10, 10]))
    with pytest.raises(ValueError, match=r"durations: expected frame counts in \[1"):
        sampler(jax.random.key(1), np.array([1, 0]), np.array([10, 0]))


def _recognizer(num_classes):
    config = RecognizerConfig(hidden=8, layers=1, feature_dim=4)
    variables = init_recognizer(jax.random.key(0), config, SMPL24, num_classes, frames=20)
    return Recognizer(config, SMPL24, tuple(str(i) for i in range(num_classes)), variables)


def test_the_protocol_refuses_an_evaluator_of_other_classes():
    uestc = load_dataset("synth-uestc", count=40)  # 40 classes
    with pytest.raises(ValueError, match=r"evaluator: it recognises 12 classes, but the real set 'train' "
                                         r"\(synth-uestc\) has 40"):
        evaluate(jax.random.key(0), {}, _recognizer(12), {"train": uestc}, ProtocolConfig(repetitions=1, duration=20))


def test_the_protocol_refuses_a_duration_longer_than_every_clip():
    data = load_dataset("synth-humanact12", count=12)
    longest = int(data.lengths.max())
    with pytest.raises(ValueError, match=f"protocol.duration: {longest + 1} frames is longer than every clip.*"
                                         f"the longest has {longest}"):
        evaluate(jax.random.key(0), {}, _recognizer(12), {"train": data},
                 ProtocolConfig(repetitions=1, duration=longest + 1))


def test_unknown_dataset_names_fail_when_the_config_is_made():
    with pytest.raises(ValueError, match="TableData.name: unknown dataset 'uestcc'; embedded: .*synth-uestc"):
        TableData("uestcc")
    with pytest.raises(ValueError, match="RecognizerTraining.dataset: unknown dataset 'ntu'; .*real .*ntu13"):
        dataclasses.replace(evaluator_spec("synth-ntu13/gru", "smoke"), dataset="ntu")
    assert isinstance(TableData("uestc"), TableData) and isinstance(evaluator_spec("synth-cmu/gru", "cpu"),
                                                                    RecognizerTraining)


def test_an_unknown_dataset_name_from_the_command_line_fails_at_parse_time(tmp_path):
    from experiments import actor_uestc

    with pytest.raises(SystemExit, match="TableData.name: unknown dataset 'uestcc'"):
        actor_uestc.main(["--profile", "smoke", "--out", str(tmp_path), "--set", "table.data.name=uestcc"])
    assert not any(tmp_path.iterdir())  # nothing was started


def test_a_table_with_a_duration_longer_than_every_clip_fails_before_anything_trains(tmp_path, monkeypatch):
    from jaxmotion.recipes.tables import run_table, table_dataset

    monkeypatch.setenv("JAXMOTION_CACHE", str(tmp_path / "cache"))
    table = table_dataset("HumanAct12", "smoke")
    table = dataclasses.replace(table, protocol=dataclasses.replace(table.protocol, duration=10_000))
    with pytest.raises(ValueError, match="protocol.duration: 10000 frames is longer than every clip"):
        run_table({}, table, workdir=tmp_path / "run", train_key=jax.random.key(0), eval_key=jax.random.key(1))
    assert not (tmp_path / "cache" / "recognizers").exists() and not (tmp_path / "run").exists()
