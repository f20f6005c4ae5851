"""NTU-120's single-person additions A061-A105 (:mod:`jaxmotion.data.synthetic.ntu1p_extended`): names and
order, every mode within the joint limits and on the floor, every class apart from every other, and the
signatures that tell the near pairs apart, read off the Kinect markers as a recogniser sees them."""

import numpy as np
import pytest

from jaxmotion.data.formats.ntu120 import ACTION_NAMES
from jaxmotion.data.synthetic import anatomy, engine, ntu1p_extended
from jaxmotion.data.synthetic.engine import Split, Variant
from jaxmotion.geometry import rotations
from jaxmotion.geometry.markers import NTU25_ON_SMPL24, markers_from_rotations
from jaxmotion.geometry.skeletons import NTU25, SMPL24

CLASSES = ntu1p_extended.CLASSES
PER_CLASS = 4  # sequences per class in the generated sample: every mode at least once
_NTU = {name: k for k, name in enumerate(NTU25.joint_names)}
_ELBOW_PRON = anatomy.channel("left_elbow.pron")[1]


def _variant(per_class: int, subjects=tuple(range(40))) -> Variant:
    """NTU's rate and clip lengths (30 fps, 2-5 s) over this module's classes."""
    return Variant(name="synth-ntu1p-extended-test", classes=CLASSES, fps=30.0, lengths=(60, 150),
                   splits={"train": Split(num_sequences=len(CLASSES) * per_class, subjects=subjects)})


@pytest.fixture(scope="module")
def sample():
    """``(data, ntu)``: the generated SMPL-24 sample and its NTU-25 markers ``[F, 25, 3]`` (clean)."""
    variant = _variant(PER_CLASS)
    data = engine.generate_split(variant, "train", seed=0)
    offsets = np.stack([engine.subject(variant, int(s), 0).offsets for s in data.subjects])
    per_frame = np.repeat(offsets, data.lengths, axis=0)
    ntu = markers_from_rotations(NTU25_ON_SMPL24, data.rotations[:, None], data.translation[:, None], per_frame)
    return data, np.asarray(ntu)[:, 0]


def _clips(sample, action_id: int):
    """``(mode name, SMPL motion, NTU joints [T, 25, 3])`` of every clip of NTU action ``action_id``."""
    data, ntu = sample
    c = action_id - 61
    for i in np.flatnonzero(data.actions == c):
        yield CLASSES[c].modes[data.modes[i]], data[int(i)], ntu[data.starts[i]:data.starts[i + 1]]


def _hands(mode: str) -> tuple[str, ...]:
    return ("left", "right") if mode.startswith("both") else ("left",) if mode.startswith("left") else ("right",)


def _raised(j: np.ndarray, sides, tolerance: float = 0.02) -> np.ndarray:
    """``[T]`` frames where every named wrist is within ``tolerance`` m of its highest point: the hold."""
    keep = np.ones(len(j), bool)
    for side in sides:
        y = j[:, _NTU[f"{side}_wrist"], 1]
        keep &= y >= y.max() - tolerance
    return keep


def _forward(j: np.ndarray) -> np.ndarray:
    """``[T, 3]`` the horizontal direction the hips face, per frame."""
    across = j[:, _NTU["left_hip"]] - j[:, _NTU["right_hip"]]
    f = np.cross(across, np.array([0.0, 1.0, 0.0]))
    f[:, 1] = 0.0
    return f / np.linalg.norm(f, axis=-1, keepdims=True)


def test_forty_five_classes_in_ntu_order_with_their_names():
    assert ntu1p_extended.ACTION_IDS == tuple(range(61, 106))
    assert tuple(c.name for c in CLASSES) == tuple(ACTION_NAMES[i] for i in range(61, 106))
    assert all(2 <= len(c.modes) <= 3 and len(set(c.modes)) == len(c.modes) for c in CLASSES)


def test_ntu13_and_uestc_actions_are_their_functions_not_copies():
    from jaxmotion.data.synthetic import ntu13, uestc

    by_id = dict(zip(ntu1p_extended.ACTION_IDS, CLASSES))
    for action_id, name in ((80, "squat down"), (93, "shake fist"), (99, "running on the spot"),
                            (100, "butt kicks"), (102, "side kick")):
        theirs = next(c for c in ntu13.CLASSES if c.name == name)
        assert by_id[action_id].perform is theirs.perform and by_id[action_id].modes == theirs.modes
    assert by_id[97].perform is uestc.arm_circling


def test_every_class_and_mode_generates_within_the_joint_limits_on_the_floor(sample):
    data, ntu = sample
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
    variant = Variant(name="synth-ntu1p-extended-test", classes=CLASSES, fps=30.0, lengths=(60, 150),
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
    pose identically: every pair differs at some joint by tens of degrees (RMS over the clip)."""
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


# --- signatures of the near pairs -----------------------------------------------------------------------

def test_thumb_up_points_the_thumb_marker_up_and_thumb_down_down(sample):
    for action_id, sign in ((69, 1.0), (70, -1.0)):
        for mode, _, j in _clips(sample, action_id):
            sides = _hands(mode)
            held = _raised(j, sides)
            for side in sides:
                rise = (j[held, _NTU[f"{side}_thumb"], 1] - j[held, _NTU[f"{side}_hand"], 1]).mean()
                assert sign * rise > 0.015, (action_id, mode, side, rise)


def test_ok_sign_is_shown_in_front_below_the_face_and_victory_beside_the_face(sample):
    """Both hands upright (the tip marker well above the wrist); OK well in front of the face and below it
    (the hand at shoulder height), victory out to the side of the face at its height, in its plane."""
    for action_id in (71, 72):
        for mode, _, j in _clips(sample, action_id):
            side = _hands(mode)[0]
            held = _raised(j, (side,))
            wrist, tip, head = (j[held, _NTU[name]] for name in (f"{side}_wrist", f"{side}_hand_tip", "head"))
            ahead = ((wrist - head) * _forward(j)[held]).sum(-1).mean()
            below = (head[:, 1] - wrist[:, 1]).mean()
            assert (tip[:, 1] - wrist[:, 1]).mean() > 0.08, (action_id, mode)
            if action_id == 71:
                assert ahead > 0.15 and below > 0.18, (mode, ahead, below)
            else:
                assert ahead < 0.12 and below < 0.14, (mode, ahead, below)
                assert np.linalg.norm((wrist - head)[:, [0, 2]], axis=-1).mean() > 0.15  # out to the side


def test_hands_up_holds_both_wrists_above_the_head(sample):
    for mode, _, j in _clips(sample, 95):
        held = _raised(j, ("left", "right"))
        assert held.sum() >= 15, mode  # held for half a second or more
        for side in ("left", "right"):
            assert np.all(j[held, _NTU[f"{side}_wrist"], 1] > j[held, _NTU["head"], 1] + 0.02), (mode, side)


def test_cross_arms_folds_each_wrist_onto_the_other_elbow(sample):
    for mode, _, j in _clips(sample, 96):
        f = len(j) // 2  # folded through the middle of the clip
        across = j[f, _NTU["left_shoulder"]] - j[f, _NTU["right_shoulder"]]
        across /= np.linalg.norm(across)
        middle = j[f, _NTU["spine_shoulder"]]
        for side, opposite, sign in (("left", "right", 1.0), ("right", "left", -1.0)):
            wrist = j[f, _NTU[f"{side}_wrist"]]
            gap = np.linalg.norm(wrist - j[f, _NTU[f"{opposite}_elbow"]])
            assert gap < 0.2, (mode, side, gap)  # the elbows themselves are ~0.3 m apart
            assert sign * (wrist - middle) @ across < -0.03, (mode, side)  # past the midline


def test_move_heavy_objects_lowers_the_pelvis_and_the_carry_travels(sample):
    for mode, motion, j in _clips(sample, 92):
        root = motion.joints[:, 0]
        travel = np.linalg.norm(root[-1, [0, 2]] - root[0, [0, 2]])
        if mode == "push":
            assert travel > 0.2, travel
            continue
        low = np.argmin(root[:, 1])
        assert root[0, 1] - root[low, 1] > 0.2, (mode, root[0, 1] - root[low, 1])
        assert max(j[low, _NTU["left_wrist"], 1], j[low, _NTU["right_wrist"], 1]) < 0.65  # hands at the load
        if mode == "lift and carry":
            assert travel > 0.2, travel


def test_headphones_both_reach_the_ears_and_only_taking_off_ends_holding_them_in_front(sample):
    for action_id in (61, 62):
        for mode, _, j in _clips(sample, action_id):
            head = j[:, _NTU["head"]]
            at_ears = np.maximum(*(np.linalg.norm(j[:, _NTU[f"{s}_hand"]] - head, axis=-1) for s in ("left", "right")))
            assert at_ears.min() < 0.16, (action_id, mode, at_ears.min())
            forward = _forward(j)[-1]
            ahead = max(((j[-1, _NTU[f"{s}_wrist"]] - j[-1, _NTU["spine_base"]]) @ forward) for s in ("left", "right"))
            if action_id == 61:
                assert ahead < 0.1, (mode, ahead)  # the hands left the ears downward and hang
            else:
                assert ahead > 0.14, (mode, ahead)  # one hand holds the headphones low in front


def test_hush_holds_a_fingertip_upright_at_the_mouth_with_the_head_still(sample):
    for mode, _, j in _clips(sample, 67):
        side = _hands(mode)[0]
        tip, wrist, head = j[:, _NTU[f"{side}_hand_tip"]], j[:, _NTU[f"{side}_wrist"]], j[:, _NTU["head"]]
        mouth = head + 0.095 * _forward(j) - np.array([0.0, 0.055, 0.0])  # est. from the head marker (mid-head)
        on_lips = np.linalg.norm(tip - mouth, axis=-1) < 0.05
        assert on_lips.sum() >= 20, (mode, on_lips.sum())  # held two thirds of a second or more
        assert np.all(tip[on_lips, 1] - wrist[on_lips, 1] > 0.05)  # the finger points up
        head_on_body = head[on_lips] - j[on_lips, _NTU["spine_base"]]
        assert np.ptp(head_on_body, axis=0).max() < 0.04


def test_open_bottle_twists_one_forearm_back_and_forth_while_the_other_holds(sample):
    for mode, motion, _ in _clips(sample, 78):
        twisting = "left" if mode.startswith("left") else "right"
        holding = "right" if twisting == "left" else "left"
        angles = anatomy.rotmats_to_angles(np.asarray(rotations.axis_angle_to_matrix(motion.rotations), float))
        pron = {s: angles[:, SMPL24.index(f"{s}_elbow"), _ELBOW_PRON] for s in (twisting, holding)}
        turns = np.sum(np.diff(np.sign(np.diff(pron[twisting]))) != 0)  # direction changes
        assert np.ptp(pron[twisting]) > 45.0 and turns >= 4, (mode, np.ptp(pron[twisting]), turns)
        assert np.ptp(pron[holding]) < np.ptp(pron[twisting]) / 2


def test_bag_on_ends_at_the_shoulder_and_bag_off_bends_down_to_the_floor(sample):
    for mode, motion, j in _clips(sample, 87):
        top = max(j[-1, _NTU[f"{s}_wrist"], 1] - j[-1, _NTU[f"{s}_shoulder"], 1] for s in ("left", "right"))
        assert top > -0.2, (mode, top)  # a hand on the strap in front of the shoulder
    for mode, motion, j in _clips(sample, 88):
        root = motion.joints[:, 0, 1]
        assert root[0] - root.min() > 0.15, mode  # the bag set down on the floor
        assert min(j[:, _NTU[f"{s}_wrist"], 1].min() for s in ("left", "right")) < 0.75
