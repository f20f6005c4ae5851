"""The packed motion dataset: indexing, subsets, persistence and validation."""

import dataclasses

import numpy as np
import pytest

from jaxmotion.data import Motion, MotionDataset, pack
from jaxmotion.geometry import SMPL24


def _motions(lengths, rotations=True):
    rng = np.random.default_rng(0)
    return [
        Motion(joints=rng.normal(size=(t, 24, 3)).astype(np.float32),
               translation=rng.normal(size=(t, 3)).astype(np.float32),
               rotations=rng.normal(size=(t, 24, 3)).astype(np.float32) if rotations else None,
               action=i % 3, mode=i % 2, subject=i, name=f"clip{i}")
        for i, t in enumerate(lengths)
    ]


def _dataset(lengths=(5, 7, 3, 9), rotations=True):
    return pack(_motions(lengths, rotations), name="toy", split="train", class_names=("a", "b", "c"),
                skeleton=SMPL24, fps=20, mode_names=(("l", "r"),) * 3)


def test_pack_then_index_returns_each_motion():
    motions = _motions((5, 7, 3, 9))
    data = _dataset()
    assert len(data) == 4 and list(data.lengths) == [5, 7, 3, 9]
    for original, back in zip(motions, data, strict=True):
        np.testing.assert_array_equal(original.joints, back.joints)
        np.testing.assert_array_equal(original.rotations, back.rotations)
        assert (original.action, original.mode, original.subject, original.name) == (
            back.action, back.mode, back.subject, back.name)
    assert data[-1].name == "clip3"
    with pytest.raises(IndexError, match="out of range for 4"):
        data[4]


def test_the_digest_is_the_same_for_the_same_data_and_changes_with_any_of_it():
    data = _dataset()
    assert data.digest() == _dataset().digest() and len(data.digest()) == 64
    joints = data.joints.copy()
    joints[3, 5, 1] += 1e-6
    changed = (dataclasses.replace(data, joints=joints), data.subset([0, 1, 2, 3], split="test"),
               dataclasses.replace(data, fps=30.0), _dataset(rotations=False), _dataset(lengths=(5, 7, 3, 8)))
    assert len({data.digest(), *(other.digest() for other in changed)}) == 1 + len(changed)


def test_subset_keeps_order_and_content():
    data = _dataset()
    sub = data.subset([3, 1], split="test")
    assert sub.split == "test" and list(sub.lengths) == [9, 7] and sub.names == ("clip3", "clip1")
    np.testing.assert_array_equal(sub[0].joints, data[3].joints)


@pytest.mark.parametrize("rotations", [True, False])
def test_save_load_round_trip_is_exact(tmp_path, rotations):
    data = _dataset(rotations=rotations)
    data.save(tmp_path / "d.npz")
    back = MotionDataset.load(tmp_path / "d.npz")
    assert (back.name, back.split, back.class_names, back.fps, back.names, back.mode_names) == (
        data.name, data.split, data.class_names, data.fps, data.names, data.mode_names)
    assert back.skeleton is SMPL24
    for field in ("joints", "translation", "starts", "actions", "modes", "subjects"):
        np.testing.assert_array_equal(getattr(back, field), getattr(data, field))
    assert (back.rotations is None) == (not rotations)
    assert not list(tmp_path.glob("*.tmp.npz"))


def test_malformed_datasets_name_the_field():
    data = _dataset()
    import dataclasses

    with pytest.raises(ValueError, match=r"translation: expected shape \[F, 3\]"):
        dataclasses.replace(data, translation=data.translation[:-1])
    with pytest.raises(ValueError, match=r"actions: expected class indices in \[0, 3\)"):
        dataclasses.replace(data, actions=np.array([0, 1, 2, 3], np.int32))
    with pytest.raises(ValueError, match="starts: expected increasing offsets"):
        dataclasses.replace(data, starts=np.array([0, 5, 5, 15, 24]))
    with pytest.raises(ValueError, match="either every motion has rotations or none"):
        pack(_motions((3,)) + _motions((3,), rotations=False), name="x", split="all", class_names=("a",),
             skeleton=SMPL24, fps=20)


def test_concatenate_appends_sequences_in_order():
    from jaxmotion.data import concatenate

    a, b = _dataset((5, 7)), _dataset((3,))
    both = concatenate([a, b], split="all")
    assert both.split == "all" and list(both.lengths) == [5, 7, 3]
    np.testing.assert_array_equal(both[2].joints, b[0].joints)
    other = pack(_motions((2,)), name="x", split="train", class_names=("z",) * 3, skeleton=SMPL24, fps=20)
    with pytest.raises(ValueError, match="differs from toy/train in its classes"):
        concatenate([a, other], split="all")


def test_concatenate_refuses_another_frame_rate_or_missing_rotations():
    import dataclasses

    from jaxmotion.data import concatenate

    a = _dataset((5, 7))
    # the result could hold one rate only; a part without rotations would drop everyone's
    with pytest.raises(ValueError, match=r"in its frame rate \(fps 30 and 20\)"):
        concatenate([a, dataclasses.replace(_dataset((3,)), fps=30.0)], split="all")
    with pytest.raises(ValueError, match="in its rotations"):
        concatenate([a, _dataset((3,), rotations=False)], split="all")
    with pytest.raises(ValueError, match="at least one dataset"):
        concatenate([], split="all")
    assert concatenate([_dataset((2,), rotations=False)] * 2, split="all").rotations is None
