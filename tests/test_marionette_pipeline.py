"""Neural Marionette's generation in the world frame: equivariant to where the context stands and faces, paths
followed in that frame, durations masked, inputs checked; context-free motions placed after a context; a trained
generator saved, loaded and generating one action in one call, its bad inputs named."""

import jax
import numpy as np
import pytest

from jaxmotion.data import synthetic
from jaxmotion.geometry import SMPL24, axis_angle_to_matrix, forward_kinematics
from jaxmotion.geometry.rotations import matrix_to_axis_angle
from jaxmotion.models.marionet import MarionetConfig, init_marionet
from jaxmotion.pipelines.artefacts import DataFacts
from jaxmotion.pipelines.load import load_generator
from jaxmotion.pipelines.marionette import ContextGenerator, generate_actions, place_after, start_bank

CONFIG = MarionetConfig.tiny(max_frames=10)


@pytest.fixture(scope="module")
def params():
    return jax.jit(init_marionet, static_argnums=1)(jax.random.key(0), CONFIG)


def _inputs(seed):
    rng = np.random.default_rng(seed)
    rotations = (0.2 * rng.normal(size=(2, 6, 24, 3))).astype(np.float32)
    translation = np.cumsum(0.03 * rng.normal(size=(2, 6, 3)), axis=1).astype(np.float32) + [0.5, 0.9, -1.0]
    tags = np.zeros((2, 31), bool)
    tags[[0, 1], [0, 24]] = True
    paths = np.cumsum(np.full((2, 8, 2), 0.04), axis=1).astype(np.float32) + translation[:, -1:, [0, 2]]
    return rotations, translation, tags, paths


def _turned(rotations, translation, paths, angle, shift):
    c, s = np.cos(angle), np.sin(angle)
    turn = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]], np.float32)
    roots = np.einsum("ij,btjk->btik", turn, np.asarray(axis_angle_to_matrix(rotations[:, :, 0])))
    rotations = rotations.copy()
    rotations[:, :, 0] = np.asarray(matrix_to_axis_angle(roots))
    ground = np.stack([paths[..., 0], np.zeros_like(paths[..., 0]), paths[..., 1]], -1) @ turn.T + shift
    return rotations, translation @ turn.T + shift, ground[..., [0, 2]].astype(np.float32), turn


def test_a_turned_and_moved_context_gives_the_same_action_turned_and_moved(params):
    rotations, translation, tags, paths = _inputs(0)
    durations = np.array([8, 5])
    follow = np.array([True, False])  # the standing action ignores its path
    out = generate_actions(params, CONFIG, rotations, translation, tags, tags, durations, paths, follow)
    shift = np.array([2.0, 0.0, -3.0], np.float32)
    moved_rot, moved_trans, moved_paths, turn = _turned(rotations, translation, paths, 1.1, shift)
    again = generate_actions(params, CONFIG, moved_rot, moved_trans, tags, tags, durations, moved_paths, follow)
    mask = out["mask"]
    np.testing.assert_allclose(again["joints"][mask], (out["joints"] @ turn.T + shift)[mask], atol=2e-4)
    np.testing.assert_array_equal(out["joints"][1, 5:], 0.0)
    other = generate_actions(params, CONFIG, rotations, translation, tags, tags, durations, paths + 1.0, follow)
    assert np.abs(other["joints"][0] - out["joints"][0]).max() > 1e-3  # the first follows its path
    np.testing.assert_array_equal(other["joints"][1], out["joints"][1])  # the second does not
    joints = forward_kinematics(axis_angle_to_matrix(out["rotations"]), out["translation"], SMPL24.offsets,
                                SMPL24.parents)
    np.testing.assert_allclose(np.asarray(joints)[mask], out["joints"][mask], atol=1e-5)


def test_bad_inputs_name_the_field(params):
    rotations, translation, tags, paths = _inputs(1)
    durations = np.array([8, 5])
    with pytest.raises(ValueError, match=r"durations: expected \[B\] = \(2,\) frame counts in \[1, 10\]"):
        generate_actions(params, CONFIG, rotations, translation, tags, tags, np.array([8, 11]))
    with pytest.raises(ValueError, match=r"context: expected rotations \[B, 6, 24, 3\]"):
        generate_actions(params, CONFIG, rotations[:, :5], translation[:, :5], tags, tags, durations)
    with pytest.raises(ValueError, match=r"paths: expected \[B, T, 2\] = \(2, T >= 8, 2\) finite ground points"):
        generate_actions(params, CONFIG, rotations, translation, tags, tags, durations, paths[:, :7])
    with pytest.raises(ValueError, match="context: expected finite"):
        generate_actions(params, CONFIG, rotations * np.nan, translation, tags, tags, durations)


def test_paths_longer_than_the_longest_duration_set_the_frames(params):
    rotations, translation, tags, paths = _inputs(2)
    out = generate_actions(params, CONFIG, rotations, translation, tags, tags, np.array([4, 3]), paths, key=None)
    assert out["joints"].shape[1] == 8 and out["mask"].sum(axis=1).tolist() == [4, 3]
    short = generate_actions(params, CONFIG, rotations, translation, tags, tags, np.array([4, 3]), paths[:, :4])
    np.testing.assert_allclose(out["joints"][:, :4], short["joints"], atol=1e-5)


def test_a_motion_in_the_canonical_frame_is_placed_where_its_context_ends():
    rotations, translation, _, _ = _inputs(3)
    turned, moved, _, turn = _turned(rotations, translation, np.zeros((2, 1, 2), np.float32), 0.7,
                                     np.array([1.0, 0.0, 2.0], np.float32))
    steps = np.zeros((2, 4, 3), np.float32)
    steps[:, :, 2] = np.arange(4) * 0.1  # straight ahead (+Z in the canonical frame), the root at the floor
    motion = np.zeros((2, 4, 24, 3), np.float32)
    _, placed = place_after(turned, moved, motion, steps)
    placed = np.asarray(placed)
    np.testing.assert_allclose(placed[:, 0], moved[:, -1], atol=1e-5)  # over the last context root, at its height
    heading = np.asarray(axis_angle_to_matrix(turned[:, -1, 0]))[:, :, 2] * [1, 0, 1]
    heading /= np.linalg.norm(heading, axis=-1, keepdims=True)
    np.testing.assert_allclose(placed[:, 3] - placed[:, 0], 0.3 * heading, atol=1e-5)  # along its heading


@pytest.fixture(scope="module")
def generator(params):
    takes = synthetic.generate("synth-mag", "test", seed=0, count=4, progress=False)
    bank = start_bank(takes, per_tag=2)
    return ContextGenerator(CONFIG, params, DataFacts.of(takes), bank, frames=8, max_frames=10), takes


def test_a_trained_generator_saves_loads_and_acts_in_one_call(generator, tmp_path):
    generator, takes = generator
    assert generator.starts.counts.max() == 2 and generator.starts.paths.shape[:2] == (31, 2)
    loaded = load_generator(generator.save(tmp_path / "generator"))
    assert isinstance(loaded, ContextGenerator) and loaded.method == "marionet"
    walk = loaded.action(0, "Walk", 9, mean=True)
    again = generator.action(0, ["Walk"], 9, mean=True)
    assert len(walk) == 1 and walk.lengths.tolist() == [9] and walk.class_names[walk.actions[0]] == "Walk"
    np.testing.assert_array_equal(walk.joints, again.joints)
    rotations, translation, _, _ = _inputs(4)
    path = np.cumsum(np.full((9, 2), 0.05, np.float32), axis=0)  # 9 frames as above: one compilation
    given = loaded.action(1, "Walk", 9, context=(rotations[0], translation[0]), path=path, next_tags="Stand")
    assert np.abs(given.translation[0] - translation[0, -1]).max() < 1.0  # it continues the given context
    motions = loaded.generate(0, [0, 24], [9, 5])
    assert motions.lengths.tolist() == [9, 5] and np.isfinite(motions.joints).all()
    contexts = [(rotations[0], translation[0]), (rotations[1], translation[1])]
    both = loaded.actions(2, ["Walk", "Kick"], [5, 9], contexts=contexts, mean=True)  # one generation, two rows
    kick = loaded.action(3, "Kick", 9, context=contexts[1], mean=True)
    np.testing.assert_allclose(both.joints[5:], kick.joints, atol=1e-5)
    with pytest.raises(ValueError, match=r"durations: expected one per action \(2\), got 1"):
        loaded.actions(2, ["Walk", "Kick"], [6])


def test_one_call_generation_names_the_bad_field(generator):
    generator, _ = generator
    rotations, translation, _, _ = _inputs(5)
    with pytest.raises(ValueError, match="tags: 'Dance' is not one of the model's tags: Walk, "):
        generator.action(0, "Dance", 8)
    with pytest.raises(ValueError, match="next_tags: 99 is not one of the model's tags"):
        generator.action(0, "Walk", 8, next_tags=99)
    with pytest.raises(ValueError, match="duration: expected frames from 1 to 10"):
        generator.action(0, "Walk", 11)
    with pytest.raises(ValueError, match=r"context: expected the 6 frames before the action.*got \(5, 24, 3\)"):
        generator.action(0, "Walk", 8, context=(rotations[0, :5], translation[0, :5]))
    with pytest.raises(ValueError, match="context: expected finite"):
        generator.action(0, "Walk", 8, context=(rotations[0] * np.nan, translation[0]))
    with pytest.raises(ValueError, match=r"path: expected \[duration, 2\] = \(8, 2\) finite .* got shape \(9, 2\)"):
        generator.action(0, "Walk", 8, path=np.zeros((9, 2)))
