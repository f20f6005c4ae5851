"""MANN, test-sized: shapes and masking, padding that changes nothing, scan generation equal to teacher forcing on
its own poses, a gate that blends, a steering path, and a few deterministic steps of training."""

import dataclasses
import json

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.data import synthetic
from jaxmotion.models import mann as mm
from jaxmotion.train.loop import LoopConfig
from jaxmotion.train.mann import MannTraining, train_mann

CONFIG = mm.MannConfig.tiny()
B, T, C = 3, 8, 31
NAMES = ("context", "tags", "next_tags", "path", "mask")


def _inputs(seed, frames=T, lengths=(8, 5, 3)):
    rng = np.random.default_rng(seed)
    tags = np.zeros((B, C), np.float32)
    tags[np.arange(B), [0, 7, 24]] = 1.0
    tags[2, 28] = 1.0  # a state with a body part
    mask = np.arange(frames)[None] < np.array(lengths)[:, None]
    path = np.cumsum(0.05 * rng.normal(size=(B, frames, 2)), axis=1) * mask[..., None]
    return {"context": jnp.asarray(0.3 * rng.normal(size=(B, mm.CONTEXT, 135)), jnp.float32),
            "tags": jnp.asarray(tags), "next_tags": jnp.asarray(np.roll(tags, 1, axis=0)),
            "path": jnp.asarray(path, jnp.float32), "mask": jnp.asarray(mask)}


@pytest.fixture(scope="module")
def params():
    return jax.jit(mm.init_mann, static_argnums=1)(jax.random.key(0), CONFIG)


_continue = jax.jit(mm.mann_continue, static_argnums=1)
_forward = jax.jit(mm.mann_forward, static_argnums=1)
_teacher_forced = jax.jit(mm.teacher_forced, static_argnums=1)


def test_generation_by_scan_equals_teacher_forcing_on_its_own_poses(params):
    x = _inputs(1)
    poses = _continue(params, CONFIG, *(x[k] for k in NAMES))
    assert poses.shape == (B, T, 135)
    again = _forward(params, CONFIG, x["context"], x["tags"], x["next_tags"], x["path"], poses, x["mask"])
    np.testing.assert_allclose(np.asarray(again), np.asarray(poses), atol=1e-5)
    np.testing.assert_array_equal(np.asarray(poses)[1, 5:], 0.0)  # padding
    np.testing.assert_array_equal(np.asarray(poses)[2, 3:], 0.0)
    assert np.abs(np.asarray(poses[0] - x["context"][0, -1])).max() > 1e-3  # it moves
    keyed = _continue(params, CONFIG, *(x[k] for k in NAMES), jax.random.key(3))
    np.testing.assert_array_equal(np.asarray(keyed), np.asarray(poses))  # deterministic: the key is unused


def test_an_action_does_not_depend_on_how_far_its_batch_is_padded(params):
    x = _inputs(2)
    wide = {**x, "path": jnp.pad(x["path"], ((0, 0), (0, 4), (0, 0))), "mask": jnp.pad(x["mask"], ((0, 0), (0, 4)))}
    short = _continue(params, CONFIG, *(x[k] for k in NAMES))
    long = _continue(params, CONFIG, *(wide[k] for k in NAMES))
    np.testing.assert_allclose(np.asarray(long[:, :T]), np.asarray(short), atol=1e-6)
    target = jax.random.normal(jax.random.key(1), (B, T, 135))
    garbage = jnp.where(x["mask"][..., None], target, 1e3)  # what padding holds is never read
    padded = jnp.pad(garbage, ((0, 0), (0, 4), (0, 0)), constant_values=-1e3)
    a = _forward(params, CONFIG, x["context"], x["tags"], x["next_tags"], x["path"], target, x["mask"])
    b = _forward(params, CONFIG, x["context"], x["tags"], x["next_tags"], wide["path"], padded, wide["mask"])
    np.testing.assert_allclose(np.asarray(b[:, :T]), np.asarray(a), atol=1e-6)
    np.testing.assert_array_equal(np.asarray(b)[~np.asarray(wide["mask"])], 0.0)


def test_teacher_forcing_reads_the_six_true_poses_before_each_frame_and_drops_out_with_a_key(params):
    x = _inputs(3)
    target = jax.random.normal(jax.random.key(1), (B, T, 135))
    out = _forward(params, CONFIG, x["context"], x["tags"], x["next_tags"], x["path"], target, x["mask"])
    changed = _forward(params, CONFIG, x["context"], x["tags"], x["next_tags"], x["path"], target.at[:, 0].add(1.0),
                       x["mask"])
    moved = np.abs(np.asarray(changed - out)).max(axis=(0, 2))  # frame 0 is read by frames 1..6 only
    assert moved[0] == 0.0 and (moved[1:7] > 1e-5).all() and moved[7] == 0.0
    dropped = _forward(params, CONFIG, x["context"], x["tags"], x["next_tags"], x["path"], target, x["mask"],
                       jax.random.key(2))
    assert np.abs(np.asarray(dropped - out)).max() > 1e-4


def test_the_gate_gives_each_frame_a_blend_of_the_experts(params):
    x = _inputs(4)
    target = jax.random.normal(jax.random.key(1), (B, T, 135))
    _, blend = _teacher_forced(params, CONFIG, x["context"], x["tags"], x["next_tags"], x["path"], target, x["mask"])
    blend = np.asarray(blend)
    assert blend.shape == (B, T, CONFIG.experts) and (blend > 0).all()
    np.testing.assert_allclose(blend.sum(-1), 1.0, atol=1e-6)
    # one expert is the MLP alone: blending K copies of it changes nothing
    one = mm.MannConfig.tiny(experts=1)
    single = mm.init_mann(jax.random.key(5), one)
    copies = single._replace(experts=tuple(layer._replace(weight=jnp.repeat(layer.weight, 2, 0),
                                                          bias=jnp.repeat(layer.bias, 2, 0))
                                           for layer in single.experts),
                             gating=params.gating)
    a = _forward(single, one, x["context"], x["tags"], x["next_tags"], x["path"], target, x["mask"])
    b = _forward(copies, CONFIG, x["context"], x["tags"], x["next_tags"], x["path"], target, x["mask"])
    np.testing.assert_allclose(np.asarray(b), np.asarray(a), atol=1e-5)


def test_the_path_ahead_is_clamped_to_the_action_and_read_relative_to_the_root(params):
    x = _inputs(5)
    ahead, time_code = mm.frame_schedule(CONFIG, x["path"], x["mask"])
    assert ahead.shape == (B, T, 3, 2) and time_code.shape == (B, T, 2)
    np.testing.assert_allclose(np.asarray(ahead[1, 2, 1]), np.asarray(x["path"][1, 4]))  # t + 10 -> last frame 4
    np.testing.assert_allclose(np.asarray(time_code[1, :5, 0]), [1.0, 0.8, 0.6, 0.4, 0.2], atol=1e-6)
    # moving the whole motion and path on the ground changes no input of the networks
    shift = jnp.zeros(135).at[132].set(1.5).at[134].set(-0.7)
    window = x["context"]
    inputs = mm.frame_inputs(window, x["tags"], x["next_tags"], ahead[:, 0], time_code[:, 0])
    moved = mm.frame_inputs(window + shift, x["tags"], x["next_tags"], ahead[:, 0] + jnp.array([1.5, -0.7]),
                            time_code[:, 0])
    np.testing.assert_allclose(np.asarray(moved.motion), np.asarray(inputs.motion), atol=1e-5)
    np.testing.assert_allclose(np.asarray(moved.gating), np.asarray(inputs.gating), atol=1e-5)
    assert inputs.motion.shape == (B, CONFIG.motion_inputs) and inputs.gating.shape == (B, CONFIG.gating_inputs)


def test_pose_output_and_wrong_shapes(params):
    x = _inputs(6)
    pose_config = dataclasses.replace(CONFIG, output="pose")
    poses = mm.mann_continue(params, pose_config, *(x[k] for k in NAMES))
    assert poses.shape == (B, T, 135) and np.isfinite(np.asarray(poses)).all()
    with pytest.raises(ValueError, match=r"path: expected shape \[3, 8, 2\]"):
        mm.mann_continue(params, CONFIG, x["context"], x["tags"], x["next_tags"], x["path"][:, :4], x["mask"])


@pytest.mark.parametrize("changes, field", [({"experts": 0}, "experts"), ({"hidden": 0}, "hidden"),
                                            ({"gating_hidden": 0}, "gating_hidden"), ({"dropout": 1.0}, "dropout"),
                                            ({"path_ahead": ()}, "path_ahead"), ({"path_ahead": (0, -1)}, "path_ahead"),
                                            ({"output": "velocity"}, "output")])
def test_config_errors_name_the_field(changes, field):
    with pytest.raises(ValueError, match=f"MannConfig.{field}:"):
        mm.MannConfig(**changes)


@pytest.fixture(scope="module")
def takes():
    return synthetic.generate("synth-mag", "test", seed=0, count=6, progress=False)


def test_training_refuses_data_it_cannot_read(takes):
    training = MannTraining(mm.MannConfig.tiny(num_tags=12), LoopConfig(steps=1))
    with pytest.raises(ValueError, match="num_tags: 12, but synth-mag has 31 tags"):
        train_mann(takes, training, jax.random.key(0))


def test_training_config_errors_name_the_field():
    loop = LoopConfig(steps=1)
    with pytest.raises(ValueError, match="MannTraining.batch_size:"):
        MannTraining(CONFIG, loop, batch_size=0)
    with pytest.raises(ValueError, match="MannTraining.learning_rate:"):
        MannTraining(CONFIG, loop, learning_rate=0.0)


@pytest.mark.smoke
def test_a_few_steps_of_training_are_deterministic_and_log_finite_losses(takes, tmp_path):
    """In two length buckets (the batches' windows differ; the step compiles once for each)."""
    training = MannTraining(CONFIG, LoopConfig(steps=4, log_every=2, checkpoint_every=0), batch_size=4,
                            length_buckets=2)
    params = train_mann(takes, training, jax.random.key(5), tmp_path / "a", progress=False)
    again = train_mann(takes, training, jax.random.key(5), progress=False)
    for leaf, other in zip(jax.tree.leaves(params), jax.tree.leaves(again)):
        np.testing.assert_array_equal(np.asarray(leaf), np.asarray(other))
    assert all(np.isfinite(np.asarray(leaf)).all() for leaf in jax.tree.leaves(params))
    start = mm.init_mann(jax.random.split(jax.random.key(5), 3)[0], CONFIG)  # fit's init key
    assert any(np.abs(np.asarray(a) - np.asarray(b)).max() > 0 for a, b in
               zip(jax.tree.leaves(params), jax.tree.leaves(start)))
    log = [json.loads(line) for line in (tmp_path / "a" / "metrics.jsonl").read_text().splitlines()]
    assert [record["step"] for record in log] == [2, 4]
    for key in ("loss", "rotations", "translation", "joints"):
        assert np.isfinite(log[-1][key])
