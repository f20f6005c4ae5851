"""synth-ntu1p and synth-ntu1p-smpl, NTU-120's 94 one-person classes: the registered variants (names, order,
skeleton, capture, cross-subject split, the SMPL stand-in performing the same takes, determinism through the
capture model), every class and mode within the joint limits and on the floor, and every class apart from every
other."""

import numpy as np

from jaxmotion.data import synthetic
from jaxmotion.data.formats.ntu120 import SINGLE_CLASS_NAMES, XSUB_TRAIN_SUBJECTS
from jaxmotion.data.synthetic import anatomy, engine
from jaxmotion.data.synthetic.engine import Split, Variant
from jaxmotion.data.synthetic.noise import EstimateNoise, KinectNoise
from jaxmotion.geometry import rotations
from jaxmotion.geometry.skeletons import NTU25
from ntu1p_clips import CLASSES, sample


def test_the_variants_hold_ntus_94_one_person_classes_in_label_order_split_by_subject():
    kinect, smpl = synthetic.VARIANTS["synth-ntu1p"], synthetic.VARIANTS["synth-ntu1p-smpl"]
    assert tuple(c.name for c in kinect.classes) == SINGLE_CLASS_NAMES and len(SINGLE_CLASS_NAMES) == 94
    assert smpl.classes == kinect.classes and smpl.stream == "synth-ntu1p"
    assert isinstance(kinect.joint_noise, KinectNoise) and isinstance(smpl.noise, EstimateNoise)
    for v in (kinect, smpl):
        assert set(v.splits["train"].subjects) == XSUB_TRAIN_SUBJECTS
        assert not set(v.splits["test"].subjects) & XSUB_TRAIN_SUBJECTS
        assert all(s.num_sequences >= 60 * 94 for s in v.splits.values())
        assert v.fps == 30.0


def test_the_kinect_and_smpl_stand_ins_store_the_same_takes():
    kinect = synthetic.generate("synth-ntu1p", "test", count=94)
    smpl = synthetic.generate("synth-ntu1p-smpl", "test", count=94)
    assert kinect.skeleton == NTU25 and kinect.rotations is None and smpl.rotations is not None
    for field in ("actions", "modes", "subjects", "lengths"):
        np.testing.assert_array_equal(getattr(kinect, field), getattr(smpl, field))
    assert set(kinect.actions.tolist()) == set(range(94))
    # the same bodies moving: pelvis paths agree to the capture noises (Kinect spine base vs SMPL pelvis)
    gap = np.linalg.norm(kinect.joints[:, 0, [0, 2]] - smpl.joints[:, 0, [0, 2]], axis=-1)
    assert np.median(gap) < 0.08, np.median(gap)


def test_every_class_and_mode_generates_within_the_joint_limits_on_the_floor():
    data, ntu = sample()
    for c, cls in enumerate(CLASSES):
        assert set(data.modes[data.actions == c].tolist()) == set(range(len(cls.modes))), cls.name
    assert data.lengths.min() >= 60 and data.lengths.max() <= 150
    angles = anatomy.rotmats_to_angles(np.asarray(rotations.axis_angle_to_matrix(data.rotations), float))
    assert np.all(angles >= anatomy.LIMITS[:, :, 0] - 0.05) and np.all(angles <= anatomy.LIMITS[:, :, 1] + 0.05)
    assert data.joints[..., 1].min() > -0.01 and ntu[..., 1].min() > -0.03
    assert np.isfinite(ntu).all()


# --- every class apart from every other ----------------------------------------------------------------

def _posed(split: str, per_class: int) -> dict:
    """``{(class, k): angles [T, J, 3]}``: the k-th take of every class posed (no kinematics), k's mode
    ``k % modes``. Take k of every class draws the same random stream, subject and length."""
    variant = Variant(name="synth-ntu1p-test", classes=CLASSES, fps=30.0, lengths=(60, 150),
                      splits={"a": Split(1, tuple(range(20))), "b": Split(1, tuple(range(20, 40)))})
    bodies = {s: engine.subject(variant, s, 0) for s in range(40)}
    return {(c, k): engine._perform(variant, split, 0, k, c, k % len(cls.modes), bodies).angles
            for c, cls in enumerate(CLASSES) for k in range(per_class)}


def _angle_features(angles: np.ndarray) -> np.ndarray:
    """Mean, spread and mean speed of every anatomical channel over the clip."""
    return np.concatenate([angles.mean(0).ravel(), angles.std(0).ravel(),
                           3.0 * np.abs(np.diff(angles, axis=0)).mean(0).ravel()])


def test_no_two_classes_move_alike_on_the_same_random_stream():
    """Take k of every class has the same subject, length and random stream, so two identical classes would
    pose identically: every pair differs at some joint by tens of degrees (RMS over the clip). The closest
    pair is nod head/bow vs shake head (~22 degrees: the head pitches or turns)."""
    posed = _posed("a", 3)
    n = len(CLASSES)
    gap = np.full((n, n), np.inf)
    for a in range(n):
        for b in range(a + 1, n):
            gap[a, b] = np.mean([np.sqrt(((posed[a, k] - posed[b, k]) ** 2).sum(-1).mean(0)).max() for k in range(3)])
    worst = np.unravel_index(np.argmin(gap), gap.shape)
    assert gap.min() > 15.0, (CLASSES[worst[0]].name, CLASSES[worst[1]].name, gap.min())


def test_held_out_takes_are_nearest_their_own_class():
    """Nearest class-mode centroid of the joint-angle features (standardised), trained on 20 subjects and
    tested on 20 others: each class keeps most of its takes; two identical classes would split theirs."""
    train, test = _posed("a", 8), _posed("b", 6)
    keys = [(c, k % len(CLASSES[c].modes)) for c, k in train]
    x = np.stack([_angle_features(a) for a in train.values()])
    mu, sd = x.mean(0), x.std(0) + 1e-6
    z = (x - mu) / sd
    groups = sorted(set(keys))
    centroids = np.stack([z[[key == g for key in keys]].mean(0) for g in groups])
    owner = np.array([g[0] for g in groups])
    y = np.array([c for c, _ in test])
    zt = (np.stack([_angle_features(a) for a in test.values()]) - mu) / sd
    predicted = owner[np.argmin(((zt[:, None] - centroids[None]) ** 2).sum(-1), axis=1)]
    per_class = np.array([np.mean(predicted[y == c] == c) for c in range(len(CLASSES))])
    assert np.mean(predicted == y) > 0.9
    assert per_class.min() >= 0.5, [CLASSES[c].name for c in np.flatnonzero(per_class < 0.5)]


def test_same_seed_same_bytes_through_the_kinect_capture():
    a, b = (synthetic.generate("synth-ntu1p", "train", count=12) for _ in range(2))
    np.testing.assert_array_equal(a.joints, b.joints)
    other = synthetic.generate("synth-ntu1p", "train", seed=1, count=12)
    assert not np.allclose(other.joints[:50], a.joints[:50])
