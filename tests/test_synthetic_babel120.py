"""synth-babel120's procedural classes: BABEL's 120 categories in order, long-tailed shares, every class
generating within the joint limits and above the floor, classes telling apart, and a few class-specific
properties."""

import dataclasses

import numpy as np
import pytest

from jaxmotion.data.formats.babel import CATEGORIES
from jaxmotion.data.synthetic import anatomy, babel120
from jaxmotion.data.synthetic.body import sample_subject
from jaxmotion.data.synthetic.engine import Split, Variant, generate_split, schedule
from jaxmotion.data.synthetic.take import Take, finish
from jaxmotion.geometry import rotations
from jaxmotion.geometry.skeletons import SMPL24

FPS = 30.0
_HIPS = (SMPL24.index("left_hip"), SMPL24.index("right_hip"))
_WRISTS = (SMPL24.index("left_wrist"), SMPL24.index("right_wrist"))
_SHOULDERS = (SMPL24.index("left_shoulder"), SMPL24.index("right_shoulder"))
_HANDS = (SMPL24.index("left_hand"), SMPL24.index("right_hand"))


def _variant(classes, count, lengths, *, equal=True):
    if equal:
        classes = tuple(dataclasses.replace(c, weight=1.0) for c in classes)
    return Variant(name="test-babel120", classes=tuple(classes), fps=FPS, lengths=lengths,
                   splits={"train": Split(num_sequences=count, subjects=tuple(range(6)))})


def _generate(names, per_class, lengths, seed=0):
    classes = [c for c in babel120.CLASSES if c.name in names]
    return generate_split(_variant(classes, per_class * len(classes), lengths), "train", seed)


def _clips(data, name):
    c = data.class_names.index(name)
    return [data[int(i)] for i in np.flatnonzero(data.actions == c)]


def _facing(joints):
    """``[T, 2]`` unit horizontal facing (x, z) per frame, from the hip axis."""
    across = joints[:, _HIPS[0]] - joints[:, _HIPS[1]]
    facing = np.stack([-across[:, 2], across[:, 0]], -1)  # the subject's left turned 90 degrees: forward
    return facing / np.linalg.norm(facing, axis=-1, keepdims=True)


@pytest.fixture(scope="module")
def sample():
    """4 clips of every class (equal shares), 1-8 s."""
    variant = _variant(babel120.CLASSES, 4 * len(babel120.CLASSES), (30, 240))
    return generate_split(variant, "train", 0)


def test_classes_are_babels_categories_in_order_with_named_modes():
    assert len(babel120.CLASSES) == 120
    assert tuple(c.name for c in babel120.CLASSES) == CATEGORIES
    for c in babel120.CLASSES:
        assert 2 <= len(c.modes) <= 3 and len(set(c.modes)) == len(c.modes), c.name


def test_weights_are_long_tailed_and_the_schedule_follows_them():
    weights = np.array([c.weight for c in babel120.CLASSES])
    assert np.all(np.diff(weights) <= 0)  # most frequent first, as BABEL's index
    assert weights.max() / weights.min() >= 50
    n = 20000
    actions, _ = schedule(_variant(babel120.CLASSES, n, (30, 240), equal=False), "train")
    counts = np.bincount(actions, minlength=120)
    assert counts.sum() == n
    np.testing.assert_allclose(counts, n * weights / weights.sum(), atol=1.0)
    assert counts.max() / counts.min() >= 50


def test_every_class_and_mode_performs_on_short_and_long_clips():
    subject = sample_subject(0, np.random.default_rng(0))
    for k, c in enumerate(babel120.CLASSES):
        for mode in c.modes:
            for frames in (30, 240):
                take = Take(frames, FPS, np.random.default_rng([k, frames]), subject, mode)
                c.perform(take)
                angles = finish(take)
                assert take.mode == mode
                assert np.isfinite(angles).all() and angles.shape == (frames, 24, 3), (c.name, mode)
                assert np.isfinite(take.contact).all() and take.contact.min() >= 0.0, (c.name, mode)
                assert np.isfinite(take.ground).all(), (c.name, mode)


def test_generated_clips_within_joint_limits_and_above_the_floor(sample):
    assert set(sample.actions.tolist()) == set(range(120))
    assert sample.lengths.min() >= 30 and sample.lengths.max() <= 240
    angles = anatomy.rotmats_to_angles(np.asarray(rotations.axis_angle_to_matrix(sample.rotations), float))
    assert np.all(angles >= anatomy.LIMITS[:, :, 0] - 0.05)
    assert np.all(angles <= anatomy.LIMITS[:, :, 1] + 0.05)
    for i in range(len(sample)):
        assert sample[i].joints[..., 1].min() > -0.01, sample.class_names[sample.actions[i]]


def _summary(take: Take) -> np.ndarray:
    """A performed take summarised: per channel the mean, spread and late-minus-early change of its angles (the
    heading relative to its start), and the feet's support."""
    angles = finish(take).reshape(take.num_frames, -1)
    angles[:, 0] -= angles[0, 0]
    third = max(take.num_frames // 3, 1)
    return np.concatenate([angles.mean(0), angles.std(0), angles[-third:].mean(0) - angles[:third].mean(0),
                           take.contact.mean(0), take.contact.std(0)])


def test_classes_differ_pairwise():
    """Common random numbers: clip k of every class is performed from the same generator seed, subject, length and
    mode index, so two identical classes would give identical clips. For every pair of classes the mean distance
    between their paired clips must be a good part of the spread between different clips of one class (1-8 s)."""
    clips = 8
    subjects = [sample_subject(k, np.random.default_rng([7, k])) for k in range(clips)]
    feats = []
    for c in babel120.CLASSES:
        row = []
        for k in range(clips):
            take = Take(30 + (53 * k) % 211, FPS, np.random.default_rng([2024, k]), subjects[k],
                        c.modes[k % len(c.modes)])
            c.perform(take)
            row.append(_summary(take))
        feats.append(row)
    feats = np.array(feats)  # [class, clip, feature]
    feats = feats / (feats.reshape(-1, feats.shape[-1]).std(0) + 1e-6)
    pairs = np.triu_indices(clips, 1)
    spread = np.linalg.norm(feats[:, pairs[0]] - feats[:, pairs[1]], axis=-1).mean(1)  # [class]
    paired = np.linalg.norm(feats[:, None] - feats[None], axis=-1).mean(-1)  # [class, class]
    ratio = paired / (0.5 * (spread[:, None] + spread[None]))
    np.fill_diagonal(ratio, np.inf)
    i, j = np.unravel_index(np.argmin(ratio), ratio.shape)
    assert ratio[i, j] > 0.4, (CATEGORIES[i], CATEGORIES[j], ratio[i, j])


def test_t_pose_holds_both_wrists_out_sideways_at_shoulder_height():
    data = _generate({"t pose"}, 6, (30, 150))
    for m in _clips(data, "t pose"):
        j = m.joints[-1]
        across = j[_HIPS[0]] - j[_HIPS[1]]
        across = across / np.linalg.norm(across)
        for w, s in zip(_WRISTS, _SHOULDERS):
            assert abs(j[w, 1] - j[s, 1]) < 0.12
            assert abs((j[w] - j[0]) @ across) > 0.5


def test_turn_changes_the_heading_by_at_least_80_degrees():
    data = _generate({"turn"}, 6, (30, 150))
    for m in _clips(data, "turn"):
        f = _facing(m.joints)
        angle = np.degrees(np.arccos(np.clip(f[0] @ f[-1], -1.0, 1.0)))
        assert angle >= 80.0


def test_backwards_movement_travels_backwards():
    data = _generate({"backwards movement"}, 6, (60, 200))
    for m in _clips(data, "backwards movement"):
        f = _facing(m.joints[:1])[0]
        travel = m.translation[-1, [0, 2]] - m.translation[0, [0, 2]]
        assert travel @ f < -0.15


def test_sit_lowers_the_pelvis_by_at_least_30_cm():
    data = _generate({"sit"}, 4, (90, 180))
    for m in _clips(data, "sit"):
        assert m.joints[0, 0, 1] - m.joints[-1, 0, 1] >= 0.3


def test_crawl_keeps_the_pelvis_low_and_the_hands_near_the_floor():
    data = _generate({"crawl"}, 4, (30, 150))
    for m in _clips(data, "crawl"):
        assert m.joints[:, 0, 1].max() < 0.65
        assert m.joints[:, list(_HANDS), 1].min(axis=1).mean() < 0.2
        assert m.joints[..., 1].min() > -0.01


def test_square_root_sampling_flattens_the_long_tail_of_the_registered_variant():
    """ActFormer resamples BABEL-120 by the square root of the class counts: drawn from the registered
    variant's head (which keeps its shares), a class's share of the batches follows sqrt(count), so the head
    class is drawn ~sqrt(ratio) times as often as the rarest instead of ratio times."""
    import jax

    from jaxmotion.data import synthetic
    from jaxmotion.data.pipeline import BatchSpec, make_batch_fn

    data = synthetic.generate("synth-babel120", "train", count=600)
    counts = np.bincount(data.actions, minlength=120)
    assert counts.min() >= 1 and counts.max() / counts.min() >= 50
    batch_fn = make_batch_fn(data, jax.random.key(0), BatchSpec(batch_size=512, window=30, sampling="sqrt"))
    drawn = np.bincount(np.concatenate([np.asarray(batch_fn(step)["actions"]) for step in range(40)]), minlength=120)
    expected = np.sqrt(counts) / np.sqrt(counts).sum()
    share = drawn / drawn.sum()
    head, tail = counts >= 20, counts <= 2  # enough draws in each group to compare
    np.testing.assert_allclose(share[head].sum(), expected[head].sum(), rtol=0.05)
    np.testing.assert_allclose(share[tail].sum(), expected[tail].sum(), rtol=0.1)
    assert drawn[0] / drawn[counts == counts.min()].mean() < 2 * np.sqrt(counts[0] / counts.min())
