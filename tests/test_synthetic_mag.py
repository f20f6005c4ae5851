"""synth-mag: BABEL-MAG's tags and counts, multi-action takes whose actions carry their real context and next tags,
continuous joins, body parts that move, and a sparse transition matrix."""

import numpy as np
import pytest

from jaxmotion.data import synthetic, transition_counts
from jaxmotion.data.segments import CONTEXT_FRAMES
from jaxmotion.data.synthetic import mag
from jaxmotion.data.synthetic.engine import plan_segments
from jaxmotion.data.synthetic.grounding import foot_skate
from jaxmotion.geometry.skeletons import SMPL24

NAME = "synth-mag"
TAKES = 10  # the shared sample: the first takes of the test split
_TOES = (SMPL24.index("left_foot"), SMPL24.index("right_foot"))


@pytest.fixture(scope="module")
def sample():
    return synthetic.generate(NAME, "test", seed=0, count=TAKES, progress=False)


@pytest.fixture(scope="module")
def plans():
    return {split: mag.plan_takes(split, 0) for split in ("train", "test")}


def test_the_31_tags_are_the_papers_with_its_counts():
    """Supplement Table 1: ids, kinds and segment numbers; intention and state actions make the 7,643 actions, the
    body-part tags ride on state actions (8,924 tags in all)."""
    assert len(mag.TAGS) == 31 and mag.TAG_NAMES[0] == "Walk" and mag.TAG_NAMES[7] == "Turn"
    assert mag.TAG_NAMES[22:24] == ("Using Object and Sit", "Step and Touch Body Part")
    by_kind = {kind: sum(t.count for t in mag.TAGS if t.kind == kind) for kind in ("root", "in place", "state",
                                                                                    "body part")}
    assert by_kind == {"root": 2809, "in place": 3606, "state": 1228, "body part": 1281}
    assert sum(by_kind.values()) == 8924 and by_kind["root"] + by_kind["in place"] + by_kind["state"] == 7643


def test_each_split_holds_its_share_of_every_tag(plans):
    for split, takes in plans.items():
        segments = plan_segments(takes, len(mag.TAGS))
        counts = dict(zip(mag.TAG_NAMES, segments.tags.sum(axis=0).tolist()))
        assert counts == mag.split_counts(split), split
    test, train = mag.split_counts("test"), mag.split_counts("train")
    for tag in mag.TAGS:
        assert test[tag.name] == min(round(0.2 * tag.count), 100) and test[tag.name] + train[tag.name] == tag.count


def test_tags_combine_as_in_babel_mag(plans):
    """An intention action has one tag; a state action one state and zero or more body parts; leg and waist
    movements only while standing, never together."""
    segments = plan_segments(plans["train"], len(mag.TAGS))
    kinds = np.array([t.kind for t in mag.TAGS])
    for row in segments.tags:
        names = [mag.TAG_NAMES[i] for i in np.flatnonzero(row)]
        leading = [n for n in names if kinds[mag.TAG_NAMES.index(n)] != "body part"]
        assert len(leading) == 1
        if len(names) > 1:
            assert kinds[mag.TAG_NAMES.index(leading[0])] == "state"
        if {"Leg Movement", "Waist Movement"} & set(names):
            assert leading == ["Stand"] and not {"Leg Movement", "Waist Movement"} <= set(names)


def test_the_transition_matrix_is_sparse_skewed_and_plausible(plans):
    """S-Fig. 1: a few pairs (turn-walk) are frequent, most are rare or absent; nothing implausible occurs."""
    counts = transition_counts(plan_segments(plans["train"], len(mag.TAGS)))
    walk, turn, sit_down, run, stand_up = (mag.TAG_NAMES.index(n) for n in ("Walk", "Turn", "Sit Down", "Run",
                                                                           "Stand Up"))
    assert (counts > 0).mean() < 0.4  # most of the 961 pairs never occur
    assert (counts[counts > 0] < 10).mean() > 0.4  # and many that do occur are rare
    top = np.sort(counts.ravel())[::-1]
    assert top[:10].sum() > 0.25 * counts.sum()  # the ten largest pairs carry a quarter of all transitions
    assert counts[turn, walk] >= top[2] and counts[walk, turn] >= top[2]
    assert counts[sit_down, run] == 0 and counts[run, stand_up] == 0
    seated_next = {mag.TAG_NAMES.index(n) for n in mag.STARTS_SEATED}
    assert set(np.flatnonzero(counts[sit_down])) <= seated_next | {mag.TAG_NAMES.index(n) for n in (
        "Head Movement", "Arm Movement")}


def test_takes_are_deterministic_and_carry_their_segments(sample):
    again = synthetic.generate(NAME, "test", seed=0, count=3, progress=False)
    assert again.joints.tobytes() == sample.subset(range(3)).joints.tobytes()
    seg = sample.segments
    assert seg is not None and len(sample) == TAKES and sample.fps == 30.0
    assert sample.class_names == mag.TAG_NAMES and seg.num_classes == 31
    np.testing.assert_array_equal(sample.actions, [seg.primary[seg.sequence == i][0] for i in range(TAKES)])
    # every action is preceded by at least the lead-in: real context for each
    assert seg.start.min() >= mag.LEAD_IN_FRAMES[0] > CONTEXT_FRAMES
    # next tags: the following action's in the take, the action's own for the last one
    for i in range(TAKES):
        rows = np.flatnonzero(seg.sequence == i)
        np.testing.assert_array_equal(seg.next_tags[rows[:-1]], seg.tags[rows[1:]])
        np.testing.assert_array_equal(seg.next_tags[rows[-1]], seg.tags[rows[-1]])
        np.testing.assert_array_equal(seg.start[rows[1:]], seg.end[rows[:-1]])  # back to back
        assert seg.end[rows[-1]] == sample.lengths[i]


def test_action_items_hold_the_frames_before_each_action_as_context(sample):
    items = sample.action_items(CONTEXT_FRAMES)
    seg = sample.segments
    assert len(items) == len(seg) and items.dropped == 0
    np.testing.assert_array_equal(items.durations, seg.end - seg.start)
    for row in range(len(seg)):
        take = sample[int(seg.sequence[row])]
        item = items.data[row]
        frames = slice(int(seg.start[row]) - CONTEXT_FRAMES, int(seg.end[row]))
        np.testing.assert_array_equal(item.rotations, take.rotations[frames])
        np.testing.assert_array_equal(item.joints, take.joints[frames])
        assert item.action == seg.primary[row]
    paths = items.ground_paths()
    assert [len(p) for p in paths] == items.durations.tolist() and paths[0].shape[1] == 2


def _accelerations(joints):
    """``[T - 2]`` the largest joint acceleration (m/frame²) per frame of a take."""
    return np.linalg.norm(np.diff(joints, n=2, axis=0), axis=-1).max(axis=-1)


def test_joins_are_as_smooth_as_the_actions_themselves(sample):
    """The largest joint acceleration at the frames around a boundary is no larger than within actions."""
    seg = sample.segments
    at_joins, within = [], []
    for i in range(TAKES):
        accel = _accelerations(sample[i].joints)  # accel[t] is centred on frame t + 1
        rows = np.flatnonzero(seg.sequence == i)
        join = np.zeros(len(accel), bool)
        for start in seg.start[rows[1:]]:
            join[start - 3:start + 1] = True  # the frames whose second difference spans the boundary
        at_joins.append(accel[join])
        within.append(accel[~join])
    at_joins, within = np.concatenate(at_joins), np.concatenate(within)
    assert np.median(at_joins) <= 1.5 * np.median(within)
    assert np.percentile(at_joins, 90) <= np.percentile(within, 95)


def test_body_part_actions_move_their_body_part_most(sample):
    """Arm movements move the wrists (about the pelvis) more than the ankles; head movements turn the head more
    than the standing actions without body parts do."""
    seg, items = sample.segments, sample.action_items(0)
    arm, head = mag.TAG_NAMES.index("Arm Movement"), mag.TAG_NAMES.index("Head Movement")
    wrists = [SMPL24.index("left_wrist"), SMPL24.index("right_wrist")]
    ankles = [SMPL24.index("left_ankle"), SMPL24.index("right_ankle")]

    def speed(item, joints):
        local = item.joints[:, joints] - item.joints[:, :1]
        return np.linalg.norm(np.diff(local, axis=0), axis=-1).mean()

    arm_rows = np.flatnonzero(seg.tags[:, arm])
    assert len(arm_rows) >= 2
    for row in arm_rows:
        assert speed(items.data[int(row)], wrists) > speed(items.data[int(row)], ankles)
    head_rows = np.flatnonzero(seg.tags[:, head])
    plain = np.flatnonzero((seg.tags.sum(axis=1) == 1) & seg.tags[:, mag.TAG_NAMES.index("Stand")])
    assert len(head_rows) and len(plain)
    turn = (lambda rows: np.mean([np.abs(np.diff(items.data[int(r)].rotations[:, SMPL24.index("head")],
                                                 axis=0)).mean() for r in rows]))
    assert turn(head_rows) > turn(plain)


def test_feet_do_not_slide_while_they_bear_weight(sample):
    speeds = np.concatenate([foot_skate(motion.joints, _TOES, sample.fps) for motion in sample])
    assert len(speeds) > 100 and speeds.mean() < synthetic.FOOT_SKATE_TOLERANCE


def test_preview_draws_a_take_with_its_timeline_and_the_transition_matrix(sample, tmp_path):
    from PIL import Image

    from jaxmotion.data import Motion, pack
    from jaxmotion.viz import motion as pictures

    pictures.take_strip(sample, 1, str(tmp_path / "take.png"), frames=6)
    pictures.transition_heatmap(sample, str(tmp_path / "transitions.png"))
    # the animation on a short take cut from the sample (a whole take renders for a minute)
    whole = sample[1]
    rows = whole.segments.select([0])
    short = Motion(whole.joints[:24], whole.translation[:24], whole.rotations[:24], whole.action, name="short",
                   segments=type(rows)(rows.sequence[:2], np.array([8, 16], np.int32), np.array([16, 24], np.int32),
                                       rows.tags[:2], rows.next_tags[:2], rows.modes[:2]))
    data = pack([short], name=NAME, split="test", class_names=sample.class_names, skeleton=SMPL24, fps=30)
    pictures.take_animation(data, 0, str(tmp_path / "take.gif"))
    with Image.open(tmp_path / "take.gif") as gif:
        assert gif.n_frames == 24
    for name in ("take.png", "transitions.png"):
        with Image.open(tmp_path / name) as image:
            assert image.size[0] > 300
    with pytest.raises(ValueError, match="take: expected an index in \\[0, 1\\)"):
        pictures.take_strip(data, 1, str(tmp_path / "none.png"))


def test_action_items_batch_whole_with_their_tags_and_padding_masks(sample):
    import jax

    from jaxmotion.data.pipeline import action_item_batches, make_batch_fn

    items = sample.action_items(CONTEXT_FRAMES)
    batch = make_batch_fn(items.data, jax.random.key(0), *action_item_batches(items, batch_size=4))(0)
    longest = int(items.data.lengths.max())
    assert batch["joints"].shape == (4, longest, 24, 3) and batch["tags"].shape == (4, 31)
    for row in range(4):
        # which item is it: the one whose tags, length and first frames it holds
        n = int(batch["lengths"][row])
        match = [i for i in range(len(items)) if items.data.lengths[i] == n and np.array_equal(
            items.data[i].joints, np.asarray(batch["joints"][row, :n]))]
        assert len(match) == 1
        i = match[0]
        np.testing.assert_array_equal(batch["tags"][row], items.tags[i])
        np.testing.assert_array_equal(batch["next_tags"][row], items.next_tags[i])
        assert int(batch["durations"][row]) == items.durations[i] == n - CONTEXT_FRAMES
        np.testing.assert_array_equal(batch["mask"][row], np.arange(longest) < n)


def test_root_motion_tags_travel_and_in_place_tags_stay_near_a_spot(sample):
    from jaxmotion.data.mag_tags import KINDS

    items = sample.action_items(0)
    travel = np.array([np.linalg.norm(p[-1] - p[0]) for p in items.ground_paths()])
    kinds = np.array([KINDS[mag.TAG_NAMES[t]] for t in sample.segments.primary])
    root, still = travel[kinds == "root"], travel[np.isin(kinds, ("in place", "state"))]
    assert len(root) >= 5 and len(still) >= 10
    assert np.median(root) > 1.0 and np.median(still) < 0.3
