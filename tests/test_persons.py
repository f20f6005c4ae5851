"""The persons axis: multi-person records, packed datasets, files and batches ``[B, P, T, J, 3]``."""

import json

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxmotion.data import Motion, MotionDataset, pack
from jaxmotion.data.motion import to_dataset
from jaxmotion.data.pipeline import BatchSpec, make_batch_fn
from jaxmotion.geometry import SMPL24, axis_angle_to_matrix, forward_kinematics

LENGTHS = (30, 12, 50, 7, 41)
PERSONS = 2
HIPS = (SMPL24.index("left_hip"), SMPL24.index("right_hip"))


def _fk(rotations, translation):
    return np.asarray(forward_kinematics(axis_angle_to_matrix(jnp.asarray(rotations)), jnp.asarray(translation),
                                         SMPL24.offsets, SMPL24.parents))


def _motions():
    rng = np.random.default_rng(1)
    out = []
    for i, t in enumerate(LENGTHS):
        rot = (0.3 * rng.normal(size=(PERSONS, t, 24, 3))).astype(np.float32)
        rot[:, :, 0, 1] += rng.uniform(-3, 3, size=(PERSONS, 1))  # each person's own heading
        trans = (np.cumsum(0.02 * rng.normal(size=(PERSONS, t, 3)), axis=1)
                 + rng.normal(size=(PERSONS, 1, 3))).astype(np.float32)
        out.append(Motion(_fk(rot, trans), trans, rot, action=i % 2, mode=0, subject=i, name=f"clip{i}"))
    return out


@pytest.fixture(scope="module")
def dataset():
    return pack(_motions(), name="pairs", split="train", class_names=("a", "b"), skeleton=SMPL24, fps=30,
                persons=PERSONS)


def test_records_round_trip_through_the_packed_dataset(dataset):
    assert dataset.persons == PERSONS and dataset.joints.shape == (sum(LENGTHS), PERSONS, 24, 3)
    assert dataset.translation.shape == (sum(LENGTHS), PERSONS, 3)
    for original, stored in zip(_motions(), dataset, strict=True):
        assert stored.persons == PERSONS and stored.num_frames == original.num_frames
        for field in ("joints", "translation", "rotations"):
            np.testing.assert_array_equal(getattr(stored, field), getattr(original, field))
    sub = dataset.subset([3, 0])
    np.testing.assert_array_equal(sub[0].joints, dataset[3].joints)
    assert sub.persons == PERSONS


def test_files_keep_the_persons_and_one_person_files_without_the_field_still_load(dataset, tmp_path):
    dataset.save(tmp_path / "pairs.npz")
    back = MotionDataset.load(tmp_path / "pairs.npz")
    assert back.persons == PERSONS
    np.testing.assert_array_equal(back.joints, dataset.joints)
    # a one-person file written before the persons axis existed: its header has no "persons"
    single = dataset.subset([0])
    single = pack([Motion(m.joints[0], m.translation[0], m.rotations[0], m.action, name=m.name) for m in single],
                  name="one", split="train", class_names=("a", "b"), skeleton=SMPL24, fps=30)
    single.save(tmp_path / "one.npz")
    with np.load(tmp_path / "one.npz") as f:
        arrays = dict(f)
    header = json.loads(str(arrays.pop("header")))
    del header["persons"]
    np.savez(tmp_path / "old.npz", header=np.array(json.dumps(header)), **arrays)
    old = MotionDataset.load(tmp_path / "old.npz")
    assert old.persons == 1 and old.joints.shape == (LENGTHS[0], 24, 3)


def test_batches_carry_the_persons_axis_and_keep_their_placement(dataset):
    batch = make_batch_fn(dataset, jax.random.key(0), BatchSpec(batch_size=4, window=20))(3)
    joints = np.asarray(batch["joints"])
    assert joints.shape == (4, PERSONS, 20, 24, 3) and batch["translation"].shape == (4, PERSONS, 20, 3)
    assert batch["rotations"].shape == (4, PERSONS, 20, 24, 3) and batch["mask"].shape == (4, 20)
    # the first person sets the canonical frame: root at the origin, facing +Z at frame 0
    np.testing.assert_allclose(joints[:, 0, 0, 0], 0.0, atol=1e-5)
    left = joints[:, 0, 0, HIPS[0]] - joints[:, 0, 0, HIPS[1]]
    np.testing.assert_allclose(np.cross(left, [0.0, 1.0, 0.0])[:, 0], 0.0, atol=1e-5)
    # one rigid map for both persons: their distances are the data's, and FK still holds for each
    for b in range(4):
        real = int(batch["lengths"][b])
        seq = dataset[int(batch["subjects"][b])]
        gap = np.linalg.norm(joints[b, 0, :real, 0] - joints[b, 1, :real, 0], axis=-1)
        data_gap = np.linalg.norm(seq.joints[0, :, 0] - seq.joints[1, :, 0], axis=-1)
        assert any(np.allclose(gap, data_gap[s:s + real], atol=1e-5) for s in range(seq.num_frames - real + 1))
    np.testing.assert_allclose(_fk(batch["rotations"], batch["translation"]), joints, atol=3e-5)


def test_person_permutation_reorders_persons_only_and_is_deterministic(dataset):
    # not canonical: then only a shift by the first person's root separates the two orders
    plain = make_batch_fn(dataset, jax.random.key(7), BatchSpec(batch_size=5, window=16, sampling="uniform",
                                                                canonical=False))
    spec = BatchSpec(batch_size=5, window=16, sampling="uniform", canonical=False, permute_persons=True)
    permuted, again = make_batch_fn(dataset, jax.random.key(7), spec), make_batch_fn(dataset, jax.random.key(7), spec)
    swaps = []
    for step in range(6):
        a, b = plain(step), permuted(step)
        np.testing.assert_array_equal(np.asarray(b["joints"]), np.asarray(again(step)["joints"]))
        np.testing.assert_array_equal(np.asarray(a["subjects"]), np.asarray(b["subjects"]))
        # the same crops; each window holds the same two persons, in one order or the other
        trans_a, trans_b = np.asarray(a["translation"]), np.asarray(b["translation"])
        for w in range(5):
            relative = lambda t: t - t[:, :1]  # noqa: E731  (each person's path from its start)
            same = np.allclose(relative(trans_a[w]), relative(trans_b[w]), atol=1e-4)
            swapped = np.allclose(relative(trans_a[w]), relative(trans_b[w])[::-1], atol=1e-4)
            assert same or swapped
            swaps.append(swapped and not same)
    assert 0 < sum(swaps) < len(swaps)


def test_multi_person_batches_pack_back_into_a_dataset(dataset):
    batch = make_batch_fn(dataset, jax.random.key(2), BatchSpec(batch_size=3, window=25, canonical=False))(0)
    back = to_dataset(batch, SMPL24, dataset.class_names, dataset.fps, name="back")
    assert back.persons == PERSONS and len(back) == 3
    for i in range(3):
        real = int(batch["lengths"][i])
        np.testing.assert_array_equal(back[i].joints, np.asarray(batch["joints"][i, :, :real]))


def test_wrong_shapes_and_mixed_persons_name_the_field(dataset):
    with pytest.raises(ValueError, match=r"joints: expected shape \[F, 3, 24, 3\]"):
        MotionDataset(**{**{f: getattr(dataset, f) for f in MotionDataset.__dataclass_fields__}, "persons": 3})
    one = Motion(dataset[0].joints[0], dataset[0].translation[0], dataset[0].rotations[0], 0, name="single")
    with pytest.raises(ValueError, match="'single' has 1 persons, expected 2"):
        pack([dataset[0], one], name="x", split="train", class_names=("a", "b"), skeleton=SMPL24, fps=30,
             persons=2)
    with pytest.raises(ValueError, match="permute_persons: x/train has one person"):
        make_batch_fn(pack([one], name="x", split="train", class_names=("a", "b"), skeleton=SMPL24, fps=30),
                      jax.random.key(0), BatchSpec(batch_size=1, window=8, permute_persons=True))
