"""Trained generators load by themselves: a run writes its generator beside its checkpoints, and a fresh process
loading it (no training data, no optimiser, no experiment) generates bitwise the same motions from the same key;
generated motions stand on the floor; a folder without a generator is refused with what is missing."""

import dataclasses
import subprocess
import sys

import jax
import numpy as np
import pytest

import jaxmotion
from jaxmotion.data import synthetic
from jaxmotion.data.datasets import load_dataset
from jaxmotion.data.export import export_motions, load_bvh
from jaxmotion.geometry import axis_angle_to_matrix, forward_kinematics
from jaxmotion.data.motion import on_the_floor, to_dataset
from jaxmotion.geometry.skeletons import SMPL24
from jaxmotion.pipelines.artefacts import ArtefactError, as_key
from jaxmotion.recipes.a2m import a2m_table_training
from jaxmotion.recipes.actformer import actformer_table_training, csgn_table_training
from jaxmotion.recipes.actor import smoke_training
from jaxmotion.recipes.odmo import odmo_table_recipe
from jaxmotion.recipes.tables import fit_generator

ACTIONS, DURATIONS = np.array([0, 3, 3, 1]), None


def _rows():
    actor = dataclasses.replace(smoke_training(12, steps=2), window=16)
    a2m = dataclasses.replace(a2m_table_training("HumanAct12", "smoke"), window=16)
    return {
        "actor": ("synth-humanact12", actor),
        "a2m": ("synth-humanact12", a2m),
        "odmo": ("synth-humanact12", odmo_table_recipe("HumanAct12", "smoke")),
        "actformer-1p": ("synth-ntu13", actformer_table_training("synth-ntu13", "smoke")),
        "actformer-2p": ("synth-ntu2p", actformer_table_training("synth-ntu2p", "smoke")),
        "csgn": ("synth-ntu13", csgn_table_training("synth-ntu13", "smoke")),
    }


LOAD_AND_GENERATE = """
import sys, numpy as np, jaxmotion
generator = jaxmotion.load_generator(sys.argv[1])
motions = generator.generate(7, np.array([0, 3, 3, 1]))
np.savez(sys.argv[2], joints=motions.joints, translation=motions.translation, starts=motions.starts)
"""


@pytest.mark.integration
@pytest.mark.parametrize("name", list(_rows()))
def test_a_loaded_generator_generates_bitwise_what_the_trained_one_does(name, tmp_path):
    dataset, row = _rows()[name]
    data = load_dataset(dataset, count=24) if "ntu" not in dataset else synthetic.generate(dataset, "train", count=16)
    generator = fit_generator(row, data, jax.random.key(0), tmp_path / "run" / "row", progress=False)
    here = generator.generate(7, ACTIONS)
    out = tmp_path / "loaded.npz"
    subprocess.run([sys.executable, "-c", LOAD_AND_GENERATE, str(tmp_path / "run"), str(out)], check=True)
    loaded = np.load(out)
    np.testing.assert_array_equal(loaded["joints"], here.joints)
    np.testing.assert_array_equal(loaded["translation"], here.translation)
    np.testing.assert_array_equal(loaded["starts"], here.starts)
    assert np.ptp(here.joints[here.starts[1]:here.starts[2]], axis=0).max() > 0  # it moves
    # on the floor: each motion's lowest joint at its first frame touches y = 0
    firsts = here.joints[here.starts[:-1]]
    np.testing.assert_allclose(firsts[..., 1].reshape(len(ACTIONS), -1).min(axis=1), 0.0, atol=1e-5)


@pytest.mark.smoke
def test_an_exported_bvh_of_a_trained_model_stands_on_the_floor(tmp_path):
    data = load_dataset("synth-humanact12", count=24)
    row = dataclasses.replace(smoke_training(12, steps=2), window=16)
    fit_generator(row, data, jax.random.key(0), tmp_path / "run", progress=False)
    motions = jaxmotion.load_generator(tmp_path / "run").generate(jax.random.key(1), [2, 5], [16, 12])
    paths = export_motions(tmp_path / "export", motions, formats=("bvh",))
    assert len(paths) == 2
    for path in paths:
        bvh = load_bvh(path)
        joints = forward_kinematics(axis_angle_to_matrix(bvh.rotations), bvh.translation, bvh.offsets, tuple(bvh.parents))
        assert abs(float(np.min(joints[0, :, 1]))) < 0.05, path  # BVH: y up


def test_on_the_floor_lifts_each_motion_by_its_lowest_first_frame_joint():
    rng = np.random.default_rng(0)
    joints = rng.normal(size=(2, 3, 24, 3)).astype(np.float32)
    joints[1, 1:, :, 1] = -5.0  # later frames may go lower: only the first frame counts
    batch = {"joints": joints, "translation": joints[:, :, 0].copy(), "lengths": np.array([3, 2]),
             "actions": np.array([0, 1])}
    data = to_dataset(batch, SMPL24, ("a", "b"), 20.0)
    placed = on_the_floor(data)
    firsts = placed.joints[placed.starts[:-1]]
    np.testing.assert_allclose(firsts[..., 1].min(axis=1), [0.0, 0.0], atol=1e-6)
    np.testing.assert_allclose(placed.joints[..., [0, 2]], data.joints[..., [0, 2]])  # only y moves
    lift = placed.joints - data.joints
    np.testing.assert_allclose(lift[:3], np.broadcast_to(lift[0, 0], (3, 24, 3)), atol=1e-6)  # one lift per motion
    np.testing.assert_allclose(placed.translation, placed.joints[:, 0])


def test_keys_and_int_seeds_are_accepted_and_bad_ones_refused():
    assert jax.random.key_data(as_key(3)).tolist() == jax.random.key_data(jax.random.key(3)).tolist()
    assert as_key(jax.random.key(3)) is not None
    with pytest.raises(ValueError, match="seed from 0"):
        as_key(-1)
    with pytest.raises(ValueError, match="key"):
        as_key("3")


def test_a_folder_without_a_generator_names_what_is_missing(tmp_path):
    (tmp_path / "checkpoints").mkdir()
    with pytest.raises(ArtefactError, match="no trained generator"):
        jaxmotion.load_generator(tmp_path)
    (tmp_path / "row" / "generator").mkdir(parents=True)
    (tmp_path / "row" / "generator" / "generator.json").write_text('{"format": 1}')
    with pytest.raises(ArtefactError, match="without arrays.npz"):
        jaxmotion.load_generator(tmp_path)
