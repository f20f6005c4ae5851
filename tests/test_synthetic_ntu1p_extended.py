"""NTU-120's single-person additions A061-A105 (:mod:`jaxmotion.data.synthetic.ntu1p_extended`): names, order
and reuse, and the signatures that tell the near pairs apart, read off the Kinect markers as a recogniser sees
them (limits, floor and distinctness over all 94 classes: ``test_synthetic_ntu1p.py``)."""

import numpy as np

from jaxmotion.data.formats.ntu120 import ACTION_NAMES
from jaxmotion.data.synthetic import anatomy, ntu1p_extended
from jaxmotion.geometry import rotations
from jaxmotion.geometry.skeletons import SMPL24
from ntu1p_clips import NTU, clips, forward, hands, raised

CLASSES = ntu1p_extended.CLASSES
_ELBOW_PRON = anatomy.channel("left_elbow.pron")[1]


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


# --- signatures of the near pairs -----------------------------------------------------------------------

def test_thumb_up_points_the_thumb_marker_up_and_thumb_down_down():
    for action_id, sign in ((69, 1.0), (70, -1.0)):
        for mode, _, j in clips(action_id):
            sides = hands(mode)
            held = raised(j, sides)
            for side in sides:
                rise = (j[held, NTU[f"{side}_thumb"], 1] - j[held, NTU[f"{side}_hand"], 1]).mean()
                assert sign * rise > 0.015, (action_id, mode, side, rise)


def test_ok_sign_is_shown_in_front_below_the_face_and_victory_beside_the_face():
    """Both hands upright (the tip marker well above the wrist); OK well in front of the face and below it
    (the hand at shoulder height), victory out to the side of the face at its height, in its plane."""
    for action_id in (71, 72):
        for mode, _, j in clips(action_id):
            side = hands(mode)[0]
            held = raised(j, (side,))
            wrist, tip, head = (j[held, NTU[name]] for name in (f"{side}_wrist", f"{side}_hand_tip", "head"))
            ahead = ((wrist - head) * forward(j)[held]).sum(-1).mean()
            below = (head[:, 1] - wrist[:, 1]).mean()
            assert (tip[:, 1] - wrist[:, 1]).mean() > 0.08, (action_id, mode)
            if action_id == 71:
                assert ahead > 0.15 and below > 0.18, (mode, ahead, below)
            else:
                assert ahead < 0.12 and below < 0.14, (mode, ahead, below)
                assert np.linalg.norm((wrist - head)[:, [0, 2]], axis=-1).mean() > 0.15  # out to the side


def test_hands_up_holds_both_wrists_above_the_head():
    for mode, _, j in clips(95):
        held = raised(j, ("left", "right"))
        assert held.sum() >= 15, mode  # held for half a second or more
        for side in ("left", "right"):
            assert np.all(j[held, NTU[f"{side}_wrist"], 1] > j[held, NTU["head"], 1] + 0.02), (mode, side)


def test_cross_arms_folds_each_wrist_onto_the_other_elbow():
    for mode, _, j in clips(96):
        f = len(j) // 2  # folded through the middle of the clip
        across = j[f, NTU["left_shoulder"]] - j[f, NTU["right_shoulder"]]
        across /= np.linalg.norm(across)
        middle = j[f, NTU["spine_shoulder"]]
        for side, opposite, sign in (("left", "right", 1.0), ("right", "left", -1.0)):
            wrist = j[f, NTU[f"{side}_wrist"]]
            gap = np.linalg.norm(wrist - j[f, NTU[f"{opposite}_elbow"]])
            assert gap < 0.2, (mode, side, gap)  # the elbows themselves are ~0.3 m apart
            assert sign * (wrist - middle) @ across < -0.03, (mode, side)  # past the midline


def test_move_heavy_objects_lowers_the_pelvis_and_the_carry_travels():
    for mode, motion, j in clips(92):
        root = motion.joints[:, 0]
        travel = np.linalg.norm(root[-1, [0, 2]] - root[0, [0, 2]])
        if mode == "push":
            assert travel > 0.2, travel
            continue
        low = np.argmin(root[:, 1])
        assert root[0, 1] - root[low, 1] > 0.15, (mode, root[0, 1] - root[low, 1])  # walking bobs ~3 cm
        assert max(j[low, NTU["left_wrist"], 1], j[low, NTU["right_wrist"], 1]) < 0.65  # hands at the load
        if mode == "lift and carry":
            assert travel > 0.2, travel


def test_headphones_both_reach_the_ears_and_only_taking_off_ends_holding_them_in_front():
    for action_id in (61, 62):
        for mode, _, j in clips(action_id):
            head = j[:, NTU["head"]]
            at_ears = np.maximum(*(np.linalg.norm(j[:, NTU[f"{s}_hand"]] - head, axis=-1) for s in ("left", "right")))
            assert at_ears.min() < 0.16, (action_id, mode, at_ears.min())
            ahead_of = forward(j)[-1]
            ahead = max(((j[-1, NTU[f"{s}_wrist"]] - j[-1, NTU["spine_base"]]) @ ahead_of) for s in ("left", "right"))
            if action_id == 61:
                assert ahead < 0.1, (mode, ahead)  # the hands left the ears downward and hang
            else:
                assert ahead > 0.14, (mode, ahead)  # one hand holds the headphones low in front


def test_hush_holds_a_fingertip_upright_at_the_mouth_with_the_head_still():
    for mode, _, j in clips(67):
        side = hands(mode)[0]
        tip, wrist, head = j[:, NTU[f"{side}_hand_tip"]], j[:, NTU[f"{side}_wrist"]], j[:, NTU["head"]]
        mouth = head + 0.095 * forward(j) - np.array([0.0, 0.055, 0.0])  # est. from the head marker (mid-head)
        on_lips = np.linalg.norm(tip - mouth, axis=-1) < 0.05
        assert on_lips.sum() >= 20, (mode, on_lips.sum())  # held two thirds of a second or more
        assert np.all(tip[on_lips, 1] - wrist[on_lips, 1] > 0.05)  # the finger points up
        head_on_body = head[on_lips] - j[on_lips, NTU["spine_base"]]
        assert np.ptp(head_on_body, axis=0).max() < 0.04


def test_open_bottle_twists_one_forearm_back_and_forth_while_the_other_holds():
    for mode, motion, _ in clips(78):
        twisting = "left" if mode.startswith("left") else "right"
        holding = "right" if twisting == "left" else "left"
        angles = anatomy.rotmats_to_angles(np.asarray(rotations.axis_angle_to_matrix(motion.rotations), float))
        pron = {s: angles[:, SMPL24.index(f"{s}_elbow"), _ELBOW_PRON] for s in (twisting, holding)}
        turns = np.sum(np.diff(np.sign(np.diff(pron[twisting]))) != 0)  # direction changes
        assert np.ptp(pron[twisting]) > 45.0 and turns >= 4, (mode, np.ptp(pron[twisting]), turns)
        assert np.ptp(pron[holding]) < np.ptp(pron[twisting]) / 2


def test_bag_on_ends_at_the_shoulder_and_bag_off_bends_down_to_the_floor():
    for mode, motion, j in clips(87):
        top = max(j[-1, NTU[f"{s}_wrist"], 1] - j[-1, NTU[f"{s}_shoulder"], 1] for s in ("left", "right"))
        assert top > -0.2, (mode, top)  # a hand on the strap in front of the shoulder
    for mode, motion, j in clips(88):
        root = motion.joints[:, 0, 1]
        assert root[0] - root.min() > 0.15, mode  # the bag set down on the floor
        assert min(j[:, NTU[f"{s}_wrist"], 1].min() for s in ("left", "right")) < 0.75
