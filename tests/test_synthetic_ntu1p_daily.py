"""NTU-120's daily one-person actions A001-A049 (:mod:`jaxmotion.data.synthetic.ntu1p_daily`): names, order
and reuse, and the signatures that tell the near pairs apart, read off the Kinect markers as a recogniser sees
them (limits, floor and distinctness over all 94 classes: ``test_synthetic_ntu1p.py``)."""

import numpy as np

from jaxmotion.data.formats.ntu120 import ACTION_NAMES
from jaxmotion.data.synthetic import humanact12, ntu1p_daily, ntu13
from ntu1p_clips import NTU, clips, forward, hands

CLASSES = ntu1p_daily.CLASSES


def _hand_gap(j):
    return np.linalg.norm(j[:, NTU["left_hand"]] - j[:, NTU["right_hand"]], axis=-1)


def _nearest_hand(j, joint):
    """``[T]`` distance from the nearer hand marker to ``joint``."""
    return np.minimum(*(np.linalg.norm(j[:, NTU[f"{s}_hand"]] - j[:, NTU[joint]], axis=-1) for s in ("left", "right")))


def _minima(x, below):
    """How many separate runs of ``x < below`` there are."""
    on = (x < below).astype(int)
    return int(on[0] + np.sum(np.diff(on) == 1))


def test_forty_nine_classes_in_ntu_order_with_their_names():
    assert tuple(c.name for c in CLASSES) == tuple(ACTION_NAMES[i] for i in range(1, 50))
    assert all(2 <= len(c.modes) <= 4 and len(set(c.modes)) == len(c.modes) for c in CLASSES)


def test_actions_of_other_stand_ins_are_their_functions_not_copies():
    by_id = dict(zip(range(1, 50), CLASSES))
    for action_id, perform in ((1, humanact12.drink), (2, humanact12.eat), (6, ntu13.pickup), (7, humanact12.throw),
                               (9, ntu13.standing_up), (22, ntu13.cheer_up), (23, ntu13.hand_waving),
                               (24, ntu13.kicking_something), (28, humanact12.phone), (38, ntu13.salute)):
        assert by_id[action_id].perform is perform, action_id


def test_clapping_parts_the_hands_again_and_again_palms_together_hold_them_and_rubbing_never_parts():
    for mode, _, j in clips(10):  # clapping
        gap = _hand_gap(j)
        assert _minima(gap, 0.09) >= 3 and gap.max() > 0.15, (mode, _minima(gap, 0.09), gap.max())
    for action_id in (34, 39):  # rub two hands, put the palms together: together once, for a while
        for mode, _, j in clips(action_id):
            together = _hand_gap(j) < 0.15
            assert together.sum() >= 25 and _minima(_hand_gap(j), 0.15) == 1, (action_id, mode, together.sum())
            if action_id == 34:  # rubbing moves the hands along each other while together
                left = j[together, NTU["left_hand"]] - j[together, NTU["spine_shoulder"]]
                assert np.ptp(left, axis=0).max() > 0.03, mode
            else:  # pressed together, fingers up
                for s in ("left", "right"):
                    assert np.mean(j[together, NTU[f"{s}_hand_tip"], 1] - j[together, NTU[f"{s}_wrist"], 1]) > 0.06


def test_cross_hands_in_front_takes_each_wrist_past_the_midline_and_clapping_never_does():
    def crossed(j):
        across = j[:, NTU["left_shoulder"]] - j[:, NTU["right_shoulder"]]
        across /= np.linalg.norm(across, axis=-1, keepdims=True)
        mid = j[:, NTU["spine_shoulder"]]
        left = ((j[:, NTU["left_wrist"]] - mid) * across).sum(-1)
        right = ((j[:, NTU["right_wrist"]] - mid) * across).sum(-1)
        return (left < -0.02) & (right > 0.02)

    for mode, _, j in clips(40):
        assert crossed(j).sum() >= 20, mode  # two thirds of a second or more
    for mode, _, j in clips(10):
        assert not crossed(j).any(), mode


def test_glasses_stay_at_eye_height_and_hats_go_over_the_head():
    for action_id, over in ((18, False), (19, False), (20, True), (21, True)):
        for mode, _, j in clips(action_id):
            top = max(j[:, NTU[f"{s}_hand"], 1].max() for s in hands(mode)) - j[:, NTU["head"], 1].max()
            assert _nearest_hand(j, "head").min() < 0.2, (action_id, mode)
            assert (top > 0.15) if over else (top < 0.1), (action_id, mode, top)


def test_putting_on_ends_with_empty_hands_down_and_taking_off_ends_holding_it():
    """Glasses and hats: taking off ends with a hand held in front of the body (the object), putting on with
    the hands hanging at the sides."""
    for on, off in ((18, 19), (20, 21)):
        for action_id, holding in ((on, False), (off, True)):
            for mode, _, j in clips(action_id):
                end, ahead_of = j[-1], forward(j)[-1]
                ahead = max((end[NTU[f"{s}_wrist"]] - end[NTU["spine_base"]]) @ ahead_of for s in ("left", "right"))
                assert (ahead > 0.15) if holding else (ahead < 0.08), (action_id, mode, ahead)


def test_the_aches_put_a_hand_where_it_hurts():
    """Each held for a second or more: headache at the head, chest pain on the chest (below the collarbones)
    or the belly (below the spine's middle), both in front of the trunk; backache behind the lower back,
    neckache behind the neck."""
    for mode, _, j in clips(44):
        assert (_nearest_hand(j, "head") < 0.17).sum() >= 30, mode  # the head marker is mid-head
    spots = {"hand on heart": ("spine_shoulder", 1.0, 0.3), "hands on stomach": ("spine_mid", 1.0, 0.22)}
    for action_id in (45, 46, 47):
        for mode, _, j in clips(action_id):
            joint, side_of_body, most = spots[mode] if action_id == 45 else (
                ("spine_mid", -1.0, 0.3) if action_id == 46 else ("neck", -1.0, 0.15))
            acting = ("left", "right") if action_id == 45 else hands(mode)
            near = [np.linalg.norm(j[:, NTU[f"{s}_hand"]] - j[:, NTU[joint]], axis=-1) for s in acting]
            k = int(np.argmin([d.min() for d in near]))
            on = near[k] < most
            assert on.sum() >= 30, (action_id, mode, near[k].min())
            offset = j[on, NTU[f"{acting[k]}_hand"]] - j[on, NTU[joint]]
            depth = (offset * forward(j)[on]).sum(-1)
            assert side_of_body * np.median(depth) > 0.0, (action_id, mode, np.median(depth))
            if action_id == 45:
                assert np.median(offset[:, 1]) < 0.0, (mode, np.median(offset[:, 1]))


def test_falling_ends_on_the_floor_and_staggering_stays_up():
    for mode, motion, j in clips(43):
        pelvis = j[-15:, NTU["spine_base"], 1]
        assert pelvis.max() < 0.45, (mode, pelvis.max())
        if mode == "forward":  # lying on the front: the shoulders as low as the hips
            assert j[-1, NTU["spine_shoulder"], 1] < j[-1, NTU["spine_base"], 1] + 0.25
        else:  # seated, leaning back on the hands
            assert j[-1, NTU["spine_shoulder"], 1] > j[-1, NTU["spine_base"], 1] + 0.3
    for mode, motion, j in clips(42):
        assert j[:, NTU["spine_base"], 1].min() > 0.7, mode
        travel = np.linalg.norm(motion.joints[-1, 0, [0, 2]] - motion.joints[0, 0, [0, 2]])
        assert travel > 0.3, (mode, travel)


def test_hopping_keeps_one_foot_up_and_jump_up_lifts_both():
    for mode, _, j in clips(26):
        free = "right" if mode.startswith("left") else "left"
        standing = "left" if free == "right" else "right"
        lift = j[:, NTU[f"{free}_ankle"], 1] - j[:, NTU[f"{standing}_ankle"], 1]
        assert np.mean(lift > 0.1) > 0.6, (mode, np.mean(lift > 0.1))
        pelvis = j[:, NTU["spine_base"], 1]
        assert _minima(pelvis - pelvis.min(), 0.01) >= 2, mode  # repeated hops
    for mode, _, j in clips(27):
        both_up = np.minimum(j[:, NTU["left_foot"], 1], j[:, NTU["right_foot"], 1]) - j[0, NTU["left_foot"], 1]
        assert both_up.max() > 0.1, (mode, both_up.max())


def test_nodding_pitches_the_head_and_shaking_turns_it():
    def head_on_neck(j):
        d = j[:, NTU["head"]] - j[:, NTU["neck"]]
        return d / np.linalg.norm(d, axis=-1, keepdims=True)

    for mode, _, j in clips(35):
        if mode == "nod":
            ahead = (head_on_neck(j) * forward(j)).sum(-1)
            assert np.ptp(ahead) > 0.2, (mode, np.ptp(ahead))
    for mode, _, j in clips(36):
        d = j[:, NTU["head"]] - j[:, NTU["neck"]]
        across = np.cross(forward(j), np.array([0.0, 1.0, 0.0]))
        assert np.ptp((d * across).sum(-1)) > 0.015, mode  # the head marker shifts side to side as it turns
