"""The embedded procedural dataset: determinism, layout, kinematic consistency, physical plausibility."""

import numpy as np
import pytest

from jaxmotion.data import synthetic
from jaxmotion.data.synthetic import anatomy
from jaxmotion.data.synthetic.grounding import foot_skate
from jaxmotion.geometry import rotations
from jaxmotion.geometry.kinematics import bone_lengths, forward_kinematics
from jaxmotion.geometry.skeletons import SMPL24

NAME = "synth-humanact12"
PER_MODE = 3  # sequences per (class, mode) in the shared sample
_TOES = (SMPL24.index("left_foot"), SMPL24.index("right_foot"))


@pytest.fixture(scope="module")
def sample():
    variant = synthetic.VARIANTS[NAME]
    count = PER_MODE * sum(len(c.modes) for c in variant.classes)
    return synthetic.generate(NAME, seed=0, count=count)


def _class(data, name):
    return data.class_names.index(name)


def test_same_seed_gives_identical_bytes_and_other_seed_differs():
    a = synthetic.generate(NAME, seed=3, count=6)
    b = synthetic.generate(NAME, seed=3, count=6)
    c = synthetic.generate(NAME, seed=4, count=6)
    for field in ("rotations", "translation", "joints", "starts", "actions", "modes", "subjects"):
        assert getattr(a, field).tobytes() == getattr(b, field).tobytes(), field
    assert a.rotations.shape != c.rotations.shape or not np.array_equal(a.rotations, c.rotations)


def test_prefix_is_order_independent(sample):
    small = synthetic.generate(NAME, seed=0, count=4)
    assert np.array_equal(small.rotations, sample.rotations[: small.starts[-1]])


def test_shapes_dtypes_and_label_ranges(sample):
    variant = synthetic.VARIANTS[NAME]
    frames = sample.starts[-1]
    assert sample.rotations.shape == sample.joints.shape == (frames, 24, 3)
    assert sample.translation.shape == (frames, 3)
    assert sample.rotations.dtype == sample.joints.dtype == sample.translation.dtype == np.float32
    assert sample.num_classes == 12 and sample.class_names == variant.class_names
    assert sample.fps == 20.0
    for c in range(sample.num_classes):
        modes = sample.modes[sample.actions == c]
        assert set(modes.tolist()) == set(range(len(variant.classes[c].modes)))
    assert set(sample.subjects.tolist()) <= set(variant.splits["train"].subjects)
    lo, hi = variant.lengths
    assert sample.lengths.min() >= lo and sample.lengths.max() <= hi


def test_full_split_is_about_balanced():
    actions, _ = synthetic.engine.schedule(synthetic.VARIANTS[NAME], "train")
    counts = np.bincount(actions)
    assert len(actions) == 1200 and counts.min() >= 80 and counts.max() <= 120


def test_joints_are_fk_of_stored_rotations(sample):
    offsets = np.stack([synthetic.subject_offsets(NAME, int(s)) for s in sample.subjects])
    per_frame = np.repeat(offsets, sample.lengths, axis=0)
    joints = forward_kinematics(rotations.axis_angle_to_matrix(sample.rotations), sample.translation,
                                per_frame, SMPL24.parents)
    np.testing.assert_allclose(np.asarray(joints), sample.joints, atol=1e-5)


def test_every_pose_within_joint_limits(sample):
    angles = anatomy.rotmats_to_angles(np.asarray(rotations.axis_angle_to_matrix(sample.rotations), float))
    tolerance = 0.05  # degrees: float32 storage
    assert np.all(angles >= anatomy.LIMITS[:, :, 0] - tolerance)
    assert np.all(angles <= anatomy.LIMITS[:, :, 1] + tolerance)


def test_angle_conversion_round_trips():
    rng = np.random.default_rng(0)
    limits = np.clip(anatomy.LIMITS, -170, 170)
    angles = rng.uniform(limits[..., 0], limits[..., 1], size=(200, 24, 3))
    back = anatomy.rotmats_to_angles(anatomy.angles_to_rotmats(angles))
    np.testing.assert_allclose(back, angles, atol=1e-6)


def test_feet_never_below_the_floor(sample):
    assert sample.joints[..., 1].min() > -0.01


def test_foot_sliding_in_locomotion_below_tolerance(sample):
    speeds = []
    for c in (_class(sample, "walk"), _class(sample, "run")):
        for i in np.flatnonzero(sample.actions == c):
            speeds.append(foot_skate(sample[int(i)].joints, _TOES, sample.fps))
    speeds = np.concatenate(speeds)
    assert len(speeds) > 100
    assert speeds.mean() < synthetic.FOOT_SKATE_TOLERANCE


def test_locomotion_travels_and_standing_actions_stay(sample):
    def travel(c):  # mean horizontal root speed along the path, m/s
        idx = np.flatnonzero(sample.actions == _class(sample, c))
        paths = [sample[int(i)].translation[:, [0, 2]] for i in idx]
        return np.array([np.linalg.norm(np.diff(p, axis=0), axis=-1).mean() * sample.fps for p in paths])

    assert np.all(travel("walk") > 0.5) and np.all(travel("walk") < 2.0)  # m/s
    assert np.all(travel("run") > 1.5)
    assert np.all(travel("drink") < 0.15) and np.all(travel("phone") < 0.15)
    assert _net_travel(sample, "jump", "in place").max() < 0.15  # metres: the feet land where they took off


def _features(motion):
    """Mode-defining summary: mean and spread of root-relative joints, and mean joint speed."""
    rel = motion.joints - motion.joints[:, :1]
    speed = np.linalg.norm(np.diff(motion.joints, axis=0), axis=-1).mean(axis=0)
    root_speed = np.linalg.norm(np.diff(motion.translation[:, [0, 2]], axis=0), axis=-1).mean()
    return np.concatenate([rel.mean(0).ravel(), rel.std(0).ravel(), 5 * speed, [5 * root_speed]])


def test_modes_are_distinct(sample):
    for c in range(sample.num_classes):
        idx = np.flatnonzero(sample.actions == c)
        feats = np.stack([_features(sample[int(i)]) for i in idx])
        modes = sample.modes[idx]
        dist = np.linalg.norm(feats[:, None] - feats[None], axis=-1)
        same = modes[:, None] == modes[None]
        off_diagonal = ~np.eye(len(idx), dtype=bool)
        within, between = dist[same & off_diagonal].mean(), dist[~same].mean()
        assert between > within, (sample.class_names[c], within, between)


def test_bone_lengths_vary_across_subjects_within_ten_percent():
    template = np.asarray(bone_lengths(_rest_joints(SMPL24.offsets), SMPL24.parents))
    ratios = []
    for s in synthetic.VARIANTS[NAME].subjects:
        ratios.append(np.asarray(bone_lengths(_rest_joints(synthetic.subject_offsets(NAME, s)), SMPL24.parents))
                      / template)
    ratios = np.stack(ratios)
    assert np.all(np.abs(ratios - 1.0) <= 0.1 + 1e-6)
    assert ratios.std(axis=0).min() > 0.01  # every bone varies across subjects


def _rest_joints(offsets):
    return np.asarray(forward_kinematics(np.broadcast_to(np.eye(3, dtype=np.float32), (24, 3, 3)),
                                         np.zeros(3, np.float32), offsets, SMPL24.parents))


def test_cache_round_trip(tmp_path, monkeypatch):
    calls = []
    real = synthetic.generate
    monkeypatch.setattr(synthetic, "generate", lambda *a, **k: calls.append(1) or real(*a, **k))
    first = synthetic.load(NAME, seed=1, cache_dir=tmp_path, count=5)
    second = synthetic.load(NAME, seed=1, cache_dir=tmp_path, count=5)
    assert len(calls) == 1
    path = synthetic.cache_path(NAME, seed=1, cache_dir=tmp_path, count=5)
    assert path.exists() and str(synthetic.GENERATOR_VERSION) in path.name
    for field in ("rotations", "translation", "joints", "starts", "actions", "modes", "subjects"):
        assert np.array_equal(getattr(first, field), getattr(second, field))
    assert second.mode_names == first.mode_names


def test_unknown_variant_lists_valid_names():
    with pytest.raises(ValueError, match="synth-humanact12"):
        synthetic.generate("synth-nope")
    with pytest.raises(ValueError, match="splits"):
        synthetic.generate(NAME, "test")


@pytest.mark.parametrize("args, message", [
    (["synth-nothing"], "jaxmotion.viz.preview: unknown synthetic variant 'synth-nothing'"),
    (["synth-humanact12", "--count", "12", "--classes", "0,12"],
     r"jaxmotion.viz.preview: classes: expected class indices of synth-humanact12 in \[0, 12\), got \[12\]"),
])
def test_preview_command_refuses_what_it_cannot_draw_in_one_line(tmp_path, args, message):
    from jaxmotion.viz import preview

    with pytest.raises(SystemExit, match=message):
        preview.main([*args, "--png", "--out", str(tmp_path / "grid.png")])


def test_preview_renders_a_still_grid_a_gif_and_a_filmstrip(tmp_path):
    from jaxmotion.viz import motion as pictures

    data = synthetic.generate("synth-humanact12", count=36)
    pictures.render_grid(data, [0, 1], str(tmp_path / "grid.png"), still=True)
    pictures.render_grid(data, [3], str(tmp_path / "grid.gif"), max_frames=3)
    pictures.filmstrip(data[0], data.skeleton, str(tmp_path / "strip.png"), frames=3)
    for name in ("grid.png", "grid.gif", "strip.png"):
        assert (tmp_path / name).stat().st_size > 1000


# --- synth-ntu13 and synth-cmu -------------------------------------------------------------------------

NTU13_CLASSES = ("pickup", "throw", "sitting down", "standing up", "cheer up", "hand waving", "kicking something",
                 "salute", "squat down", "shake fist", "running on the spot", "butt kicks", "side kick")
CMU_CLASSES = ("Walk", "Run", "Jump", "Animal Behavior", "Dance", "Step", "Climb")


@pytest.fixture(scope="module", params=[("synth-ntu13", 102), ("synth-cmu", 80)], ids=lambda p: p[0])
def other_sample(request):
    """A prefix of each new variant with at least two sequences of every mode (three for NTU-13)."""
    name, count = request.param
    return synthetic.generate(name, count=count)


def test_ntu13_and_cmu_layout():
    ntu, cmu = synthetic.VARIANTS["synth-ntu13"], synthetic.VARIANTS["synth-cmu"]
    assert ntu.class_names == NTU13_CLASSES and cmu.class_names == CMU_CLASSES
    assert (ntu.fps, ntu.lengths, cmu.fps, cmu.lengths) == (20.0, (40, 150), 12.0, (100, 100))
    assert tuple(ntu.splits) == tuple(cmu.splits) == ("train",)
    assert ntu.splits["train"].num_sequences == 3900 and cmu.splits["train"].num_sequences == 970
    assert all(2 <= len(c.modes) <= 4 for c in ntu.classes + cmu.classes)
    counts = np.bincount(synthetic.engine.schedule(ntu, "train")[0])
    assert len(counts) == 13 and counts.min() == counts.max() == 300


def test_new_variants_every_mode_present_fk_and_limits(other_sample):
    variant = synthetic.VARIANTS[other_sample.name]
    for c, cls in enumerate(variant.classes):
        assert set(other_sample.modes[other_sample.actions == c].tolist()) == set(range(len(cls.modes))), cls.name
    offsets = np.stack([synthetic.subject_offsets(other_sample.name, int(s)) for s in other_sample.subjects])
    joints = forward_kinematics(rotations.axis_angle_to_matrix(other_sample.rotations), other_sample.translation,
                                np.repeat(offsets, other_sample.lengths, axis=0), SMPL24.parents)
    np.testing.assert_allclose(np.asarray(joints), other_sample.joints, atol=1e-5)
    angles = anatomy.rotmats_to_angles(np.asarray(rotations.axis_angle_to_matrix(other_sample.rotations), float))
    assert np.all(angles >= anatomy.LIMITS[:, :, 0] - 0.05) and np.all(angles <= anatomy.LIMITS[:, :, 1] + 0.05)
    assert other_sample.joints[..., 1].min() > -0.01


def test_new_variants_modes_are_distinct(other_sample):
    borrowed = {"throw", "sitting down"}  # the HumanAct12 classes' own code, checked on that variant above
    for c in range(other_sample.num_classes):
        if other_sample.class_names[c] in borrowed:
            continue
        idx = np.flatnonzero(other_sample.actions == c)
        feats = np.stack([_features(other_sample[int(i)]) for i in idx])
        modes = other_sample.modes[idx]
        dist = np.linalg.norm(feats[:, None] - feats[None], axis=-1)
        same = (modes[:, None] == modes[None]) & ~np.eye(len(idx), dtype=bool)
        assert dist[~same & (modes[:, None] != modes[None])].mean() > dist[same].mean(), other_sample.class_names[c]


def _paths(data, name):
    """Root path length (m, horizontal) of every sequence of class ``name``."""
    idx = np.flatnonzero(data.actions == data.class_names.index(name))
    return np.array([np.linalg.norm(np.diff(data[int(i)].translation[:, [0, 2]], axis=0), axis=-1).sum()
                     for i in idx])


def _net_travel(data, name, mode=None):
    """Horizontal distance (m) from the first to the last root position of every sequence of class ``name``
    (of ``mode`` only, if given)."""
    c = data.class_names.index(name)
    hit = data.actions == c
    if mode is not None:
        hit &= data.modes == data.mode_names[c].index(mode)
    return np.array([np.linalg.norm(data[int(i)].translation[-1, [0, 2]] - data[int(i)].translation[0, [0, 2]])
                     for i in np.flatnonzero(hit)])


def test_new_variants_foot_sliding_and_travel(other_sample):
    gaits = {"synth-ntu13": ("running on the spot", "butt kicks"), "synth-cmu": ("Walk", "Run")}[other_sample.name]
    speeds = np.concatenate([foot_skate(other_sample[int(i)].joints, _TOES, other_sample.fps)
                             for c in gaits for i in np.flatnonzero(other_sample.actions == _class(other_sample, c))])
    assert len(speeds) > 100 and speeds.mean() < synthetic.FOOT_SKATE_TOLERANCE
    if other_sample.name == "synth-cmu":
        assert np.all(other_sample.lengths == 100)
        assert _paths(other_sample, "Walk").min() > 5.0 and _paths(other_sample, "Run").min() > 10.0  # metres
        assert np.median(_paths(other_sample, "Walk")) > 3.0 * np.median(_paths(other_sample, "Dance"))
        assert _net_travel(other_sample, "Jump", "in place").max() < 0.15  # metres, over ~8 s of jumps
    else:  # on the spot: the feet land where they stood, so the body stays where it started
        assert max(_net_travel(other_sample, c).max() for c in gaits) < 0.6  # metres, over up to 7.5 s


def test_cmu_step_and_climb_rise_onto_their_supports():
    """Stairs (Step, high steps) and Climb go up: the root rises with the support under the feet; a foot
    bearing all the weight rests on its support (a step, rung or the floor), and none bearing any is under it."""
    variant = synthetic.VARIANTS["synth-cmu"]
    data = synthetic.generate(variant.name, count=80)
    bodies = {s: synthetic.engine.subject(variant, s, 0) for s in variant.splits["train"].subjects}
    ankles = [SMPL24.index("left_ankle"), SMPL24.index("right_ankle")]
    up = 0
    for i in np.flatnonzero(np.isin(data.actions, [_class(data, "Step"), _class(data, "Climb")])):
        posed = synthetic.engine._perform(variant, "train", 0, int(i), int(data.actions[i]), int(data.modes[i]), bodies)
        joints = data[int(i)].joints
        drop = -posed.subject.offsets[_TOES[0], 1]  # the toe joint's rest height above the heel's
        sole = np.minimum(joints[:, _TOES, 1], joints[:, ankles, 1] - drop)  # [T, 2] lowest point of each foot
        gap = sole - posed.ground
        assert np.abs(gap[posed.contact > 0.99]).max() < 0.05 and gap[posed.contact > 0.01].min() > -0.01
        rise = joints[-1, 0, 1] - joints[0, 0, 1]
        if data.mode_names[data.actions[i]][data.modes[i]] == "side steps":  # level ground
            assert not posed.ground.any() and abs(rise) < 0.05
            continue
        support = posed.contact[-1] @ posed.ground[-1] / posed.contact[-1].sum()
        assert support > 0.8 and abs(rise - support) < 0.3  # metres: several steps, the body on top of them
        up += 1
    assert up >= 4


# --- synth-uestc ---------------------------------------------------------------------------------------

UESTC = "synth-uestc"
UESTC_PER_CLASS = 8  # sequences per class in the shared pair: every mode at least twice


@pytest.fixture(scope="module")
def uestc_pair():
    """A prefix of synth-uestc's train split as stored (noisy) and from the same generator without noise."""
    import dataclasses

    variant = synthetic.VARIANTS[UESTC]
    count = UESTC_PER_CLASS * len(variant.classes)
    clean = synthetic.engine.generate_split(dataclasses.replace(variant, noise=None), "train", 0, count)
    return synthetic.generate(UESTC, count=count), clean


def test_uestc_classes_modes_and_splits():
    from jaxmotion.data.formats import uestc as uestc_format

    variant = synthetic.VARIANTS[UESTC]
    assert variant.class_names == uestc_format.CLASS_NAMES and len(variant.classes) == 40
    assert (variant.fps, variant.lengths) == (20.0, (40, 150))
    assert all(2 <= len(c.modes) <= 4 and len(set(c.modes)) == len(c.modes) for c in variant.classes)
    seated = [i for i, c in enumerate(variant.classes) if any("seated" in m for m in c.modes)]
    assert len(seated) == 15 and min(seated) >= 10  # 15 of actions 10-39 were done seated by half the subjects
    assert tuple(variant.class_names[i] for i in seated) == synthetic.uestc.SEATED_CAPABLE  # the documented list
    train, test = variant.splits["train"], variant.splits["test"]
    assert (train.num_sequences, test.num_sequences) == (10650, 13350)
    assert set(train.subjects) == set(uestc_format.TRAIN_SUBJECTS) and len(test.subjects) == 67
    assert not set(train.subjects) & set(test.subjects)
    assert set(train.subjects) | set(test.subjects) == set(range(1, 119))
    small = synthetic.generate(UESTC, "test", count=40)
    assert set(small.subjects.tolist()) <= set(test.subjects) and small.split == "test"


def test_uestc_every_mode_present_and_distinct(uestc_pair):
    data, _ = uestc_pair
    variant = synthetic.VARIANTS[UESTC]
    for c, cls in enumerate(variant.classes):
        idx = np.flatnonzero(data.actions == c)
        modes = data.modes[idx]
        assert all(np.sum(modes == m) >= 2 for m in range(len(cls.modes))), cls.name
        feats = np.stack([_features(data[int(i)]) for i in idx])
        dist = np.linalg.norm(feats[:, None] - feats[None], axis=-1)
        same = (modes[:, None] == modes[None]) & ~np.eye(len(idx), dtype=bool)
        assert dist[modes[:, None] != modes[None]].mean() > dist[same].mean(), cls.name


def _accel_mm(joints):
    """Per joint and frame, |second difference| of root-relative joints, mm/frame^2."""
    rel = joints - joints[:, :1]
    return 1000.0 * np.linalg.norm(rel[2:] - 2 * rel[1:-1] + rel[:-2], axis=-1)


def test_uestc_noise_is_vibe_like(uestc_pair):
    noisy, clean = uestc_pair
    assert np.array_equal(noisy.starts, clean.starts) and np.array_equal(noisy.subjects, clean.subjects)
    error = np.concatenate([_accel_mm(noisy[i].joints - clean[i].joints + clean[i].joints[:, :1]).ravel()
                            for i in range(len(noisy))])
    assert 15.8 < error.mean() < 31.6  # VIBE's acceleration error, H36M to AIST++ (noise.py: ~23 on 3DPW)
    raw = [np.concatenate([_accel_mm(d[i].joints).ravel() for i in range(len(d))]).mean() for d in (noisy, clean)]
    assert raw[0] > 2.0 * raw[1]
    # Depth from the box height: the body seems farther from the camera (-Z) the lower it folds.
    squat = noisy.class_names.index("squatting")
    deep = noisy.modes != noisy.mode_names[squat].index("half squat")
    for i in np.flatnonzero((noisy.actions == squat) & deep):
        extent = np.ptp(clean[int(i)].joints[..., 1], axis=1)
        depth = clean[int(i)].translation[:, 2] - noisy[int(i)].translation[:, 2]
        assert np.corrcoef(extent, depth)[0, 1] < -0.5


def test_uestc_fk_consistency_and_joint_limits_after_noise(uestc_pair):
    data, _ = uestc_pair
    offsets = np.stack([synthetic.subject_offsets(UESTC, int(s)) for s in data.subjects])
    joints = forward_kinematics(rotations.axis_angle_to_matrix(data.rotations), data.translation,
                                np.repeat(offsets, data.lengths, axis=0), SMPL24.parents)
    np.testing.assert_allclose(np.asarray(joints), data.joints, atol=1e-5)
    angles = anatomy.rotmats_to_angles(np.asarray(rotations.axis_angle_to_matrix(data.rotations), float))
    assert np.all(angles >= anatomy.LIMITS[:, :, 0] - 0.05) and np.all(angles <= anatomy.LIMITS[:, :, 1] + 0.05)
    assert data.joints[..., 1].min() > -0.08  # estimates dip a few centimetres into the floor, no more


def test_engine_rotations_match_anatomy():
    rng = np.random.default_rng(0)
    limits = np.clip(anatomy.LIMITS, -170, 170)
    angles = rng.uniform(limits[..., 0], limits[..., 1], size=(synthetic.engine._CHUNK_FRAMES, 24, 3))
    ours = np.asarray(anatomy.angles_to_rotmats_f32(angles.astype(np.float32)))
    np.testing.assert_allclose(ours, anatomy.angles_to_rotmats(angles), atol=2e-6)
