"""Neural Marionette's generation in the world frame: equivariant to where the context stands and faces, paths
followed in that frame, durations masked, inputs checked."""

import jax
import numpy as np
import pytest

from jaxmotion.geometry import SMPL24, axis_angle_to_matrix, forward_kinematics
from jaxmotion.geometry.rotations import matrix_to_axis_angle
from jaxmotion.models.marionet import MarionetConfig, init_marionet
from jaxmotion.pipelines.marionette import generate_actions

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
    with pytest.raises(ValueError, match=r"paths: expected \[B, T, 2\] = \(2, 8, 2\) finite ground points"):
        generate_actions(params, CONFIG, rotations, translation, tags, tags, durations, paths[:, :7])
    with pytest.raises(ValueError, match="context: expected finite"):
        generate_actions(params, CONFIG, rotations * np.nan, translation, tags, tags, durations)
