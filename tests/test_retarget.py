"""Retargeting aids: the SMPL-24 -> Mixamo name map, analytic two-bone IK, and the foot clean-up.

The IK kernels run jitted (one compilation per shape, which also checks that they are jittable); hypothesis draws
seeds, and the arrays come from one ``jax.random`` draw per seed. The clean-up is checked on a hand-built walk
(one foot standing while the root moves on, plus a drift: a sliding stance), on motions without a contact, and on
the embedded HumanAct12-like walks, whose foot skating it must reduce.
"""

import math
import re

import jax
import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from jaxmotion.data.export import load_bvh, rest_offsets, save_bvh
from jaxmotion.data.retarget import (
    MIXAMO_NAMES,
    MIXAMO_PREFIX,
    SMPL24_LEGS,
    clean_feet,
    foot_contacts,
    foot_skating,
    mixamo_names,
)
from jaxmotion.data.synthetic import generate
from jaxmotion.geometry.ik import two_bone_ik, two_bone_pose
from jaxmotion.geometry.kinematics import bone_lengths, forward_kinematics_transforms
from jaxmotion.geometry.rotations import axis_angle_to_matrix, matrix_to_axis_angle
from jaxmotion.geometry.skeletons import SMPL24

ATOL = 1e-5
FPS = 30.0
PARENTS = SMPL24.parents
LEFT, RIGHT = SMPL24_LEGS
seeds = st.integers(0, 2**31 - 1)

_normal_pool = jax.jit(lambda key: jax.random.normal(key, (160,)))
jit_ik = jax.jit(two_bone_ik)
jit_pose = jax.jit(two_bone_pose, static_argnames=("parents", "chain"))


def normals(seed: int, count: int) -> np.ndarray:
    """``count`` standard-normal float32 values from one ``jax.random`` draw."""
    return np.asarray(_normal_pool(jax.random.PRNGKey(seed)))[:count]


def unit(vector: np.ndarray) -> np.ndarray:
    return vector / np.linalg.norm(vector)


def fk(rotations: np.ndarray, translation: np.ndarray, offsets=SMPL24.offsets) -> tuple[np.ndarray, np.ndarray]:
    """Global rotations ``[T, J, 3, 3]`` and joints ``[T, J, 3]`` of an axis-angle motion."""
    global_rotmats, joints = forward_kinematics_transforms(axis_angle_to_matrix(rotations), translation, offsets,
                                                           PARENTS)
    return np.asarray(global_rotmats), np.asarray(joints)


# --- names -------------------------------------------------------------------------------------------------


def test_mixamo_map_names_every_smpl24_joint_once_with_unique_bvh_names():
    assert tuple(MIXAMO_NAMES) == SMPL24.joint_names
    names = list(MIXAMO_NAMES.values())
    assert len(set(names)) == len(names) == 24
    assert all(name.startswith(MIXAMO_PREFIX) and not re.search(r"[\s{}]", name) for name in names)
    assert MIXAMO_NAMES["pelvis"] == "mixamorig:Hips"
    assert [MIXAMO_NAMES[f"spine{i}"] for i in (1, 2, 3)] == ["mixamorig:Spine", "mixamorig:Spine1",
                                                              "mixamorig:Spine2"]
    with pytest.raises(TypeError):
        MIXAMO_NAMES["pelvis"] = "Root"  # read-only


def test_mixamo_names_follow_smpl24_order_with_any_prefix():
    assert mixamo_names() == tuple(MIXAMO_NAMES[joint] for joint in SMPL24.joint_names)
    bare = mixamo_names("")
    assert bare == tuple(name.removeprefix(MIXAMO_PREFIX) for name in mixamo_names())
    assert bare[SMPL24.index("left_collar")] == "LeftShoulder" and bare[SMPL24.index("left_foot")] == "LeftToeBase"
    for side, mixamo_side in (("left", "Left"), ("right", "Right")):  # SMPL's left is the subject's, as Mixamo's
        assert all(name.startswith(mixamo_side) for joint, name in zip(SMPL24.joint_names, bare)
                   if joint.startswith(side))
    for prefix in ("mixamo rig:", "a{", None):
        with pytest.raises(ValueError, match="prefix"):
            mixamo_names(prefix)


def test_save_bvh_writes_mixamo_names_that_load_bvh_reads_back(tmp_path):
    rotations = 0.3 * normals(1, 2 * 24 * 3).reshape(2, 24, 3)
    translation = np.array([[0.0, 0.9, 0.0], [0.1, 0.9, 0.2]], np.float32)
    names = mixamo_names()
    path = save_bvh(tmp_path / "mixamo.bvh", rotations, translation, SMPL24.offsets, PARENTS, names, fps=FPS)
    loaded = load_bvh(path)
    assert sorted(loaded.names) == sorted(names)
    order = [loaded.names.index(name) for name in names]  # the file is depth-first: back to SMPL-24's order
    parent_names = [loaded.names[p] if p >= 0 else None for p in np.asarray(loaded.parents)[order]]
    assert parent_names == [names[p] if p >= 0 else None for p in PARENTS]
    np.testing.assert_allclose(axis_angle_to_matrix(loaded.rotations[:, order]), axis_angle_to_matrix(rotations),
                               atol=1e-5)


# --- two-bone IK -------------------------------------------------------------------------------------------


def random_chain(seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Root, mid and end positions (bones 0.25 to ~0.5 m) and a random unit direction, from one seed."""
    draws = normals(seed, 12)
    root = draws[:3]
    mid = root + (0.25 + 0.1 * abs(draws[9])) * unit(draws[3:6])
    end = mid + (0.25 + 0.1 * abs(draws[10])) * unit(draws[6:9])
    return root, mid, end, unit(normals(seed + 1, 3))


def moved(root, mid, end, turns) -> tuple[np.ndarray, np.ndarray]:
    """New mid and end positions from :func:`two_bone_ik`'s turns."""
    root_turn, mid_turn = (np.asarray(turn, np.float64) for turn in turns)
    new_mid = root + root_turn @ (mid - root)
    return new_mid, new_mid + mid_turn @ root_turn @ (end - mid)


HINGE = np.array([1.0, 0.0, 0.0], np.float32)


@given(seed=seeds, fraction=st.floats(0.05, 0.95))
def test_two_bone_ik_reaches_a_reachable_target_in_the_pole_plane(seed, fraction):
    root, mid, end, direction = random_chain(seed)
    upper, lower = np.linalg.norm(mid - root), np.linalg.norm(end - mid)
    pole = (mid - root) - np.dot(mid - root, direction) * direction
    # A pole plane exists only where the mid joint is off the root-to-target line, a hinge only where it bends.
    bend = np.linalg.norm(np.cross(mid - root, end - mid))
    assume(np.linalg.norm(pole) > 0.05 * upper and bend > 0.05 * upper * lower)
    distance = abs(upper - lower) + fraction * (upper + lower - abs(upper - lower))
    target = root + distance * direction
    turns = jit_ik(root, mid, end, target, HINGE)
    for turn in turns:  # proper rotations
        np.testing.assert_allclose(turn @ np.asarray(turn).T, np.eye(3), atol=ATOL)
        assert np.linalg.det(turn) == pytest.approx(1.0, abs=ATOL)
    new_mid, new_end = moved(root, mid, end, turns)
    assert np.linalg.norm(new_end - target) < ATOL
    assert np.linalg.norm(new_mid - root) == pytest.approx(upper, abs=ATOL)
    assert np.linalg.norm(new_end - new_mid) == pytest.approx(lower, abs=ATOL)
    # The knee stays in the plane of the root, the target and the old knee, on the old knee's side.
    assert abs(np.dot(new_mid - root, unit(np.cross(direction, pole)))) < ATOL
    assert np.dot(new_mid - root, pole) > 0
    # The mid joint turns about that plane's normal only: a hinge, no twist between the bones.
    mid_axis = np.asarray(matrix_to_axis_angle(turns[1]))
    if np.linalg.norm(mid_axis) > 1e-3:
        assert np.linalg.norm(np.cross(unit(mid_axis), unit(np.cross(direction, pole)))) < 1e-3


@given(seed=seeds, stretch=st.floats(1.05, 3.0))
def test_two_bone_ik_straightens_toward_an_unreachable_target(seed, stretch):
    root, mid, end, direction = random_chain(seed)
    upper, lower = np.linalg.norm(mid - root), np.linalg.norm(end - mid)
    target = root + stretch * (upper + lower) * direction
    new_mid, new_end = moved(root, mid, end, jit_ik(root, mid, end, target, HINGE))
    np.testing.assert_allclose(new_mid, root + upper * direction, atol=ATOL)
    np.testing.assert_allclose(new_end, root + (upper + lower) * direction, atol=ATOL)


@given(seed=seeds)
def test_two_bone_ik_is_the_identity_when_the_target_is_the_current_end(seed):
    root, mid, end, _ = random_chain(seed)
    for turn in jit_ik(root, mid, end, end, HINGE):
        np.testing.assert_allclose(turn, np.eye(3), atol=ATOL)


def test_two_bone_ik_bends_a_straight_chain_about_its_hinge():
    # A straight leg hanging down (-Y), asked to shorten: the positions give no bend plane; the hinge (+X, as an
    # SMPL knee's) makes the knee go forward (+Z) and the lower bone fold back.
    root, mid, end = np.zeros(3, np.float32), np.array([0, -0.4, 0], np.float32), np.array([0, -0.8, 0], np.float32)
    target = np.array([0.0, -0.6, 0.0], np.float32)
    turns = jit_ik(root, mid, end, target, HINGE)
    new_mid, new_end = moved(root, mid, end, turns)
    np.testing.assert_allclose(new_end, target, atol=ATOL)
    assert np.linalg.norm(new_mid - root) == pytest.approx(0.4, abs=ATOL)
    assert new_mid[2] > 0.2 and abs(new_mid[0]) < ATOL
    assert np.asarray(matrix_to_axis_angle(turns[1]))[0] > 0  # the knee flexes about +X


def test_two_bone_pose_moves_the_ankle_and_keeps_the_foot_and_the_rest():
    rotations = 0.2 * normals(3, 24 * 3).reshape(1, 24, 3)
    translation = np.array([[0.1, 0.9, -0.2]], np.float32)
    global_rotmats, joints = fk(rotations, translation)
    leg = tuple(LEFT)
    target = joints[0, LEFT.ankle] + np.array([0.03, 0.04, -0.05], np.float32)
    local = np.asarray(jit_pose(axis_angle_to_matrix(rotations[0]), global_rotmats[0], joints[0], parents=PARENTS,
                                chain=leg, target=target, hinge=HINGE))
    new_global, new_joints = fk(np.asarray(matrix_to_axis_angle(local))[None], translation)
    np.testing.assert_allclose(new_joints[0, LEFT.ankle], target, atol=ATOL)
    np.testing.assert_allclose(new_global[0, LEFT.ankle], global_rotmats[0, LEFT.ankle], atol=ATOL)
    others = [j for j in range(24) if j not in leg]
    np.testing.assert_array_equal(local[others], np.asarray(axis_angle_to_matrix(rotations[0]))[others])
    leg_subtree = {LEFT.hip, LEFT.knee, LEFT.ankle, SMPL24.index("left_foot")}
    still = [j for j in range(24) if j not in leg_subtree]
    np.testing.assert_allclose(new_joints[0, still], joints[0, still], atol=ATOL)


def test_two_bone_pose_rejects_a_chain_that_is_not_parent_to_child():
    local = np.broadcast_to(np.eye(3, dtype=np.float32), (24, 3, 3))
    with pytest.raises(ValueError, match="chain"):
        two_bone_pose(local, local, np.zeros((24, 3), np.float32), PARENTS, (1, 5, 7), np.zeros(3), HINGE)


# --- foot contacts and the clean-up ------------------------------------------------------------------------


def test_foot_contacts_need_low_and_slow_for_min_frames():
    # Standing for frames 0-5, then rising 0.1 m a frame; a one-frame touch at frame 9.
    heights = np.array([0, 0, 0, 0, 0, 0, 0.1, 0.2, 0.1, 0.0, 0.1, 0.2])
    ankles = np.stack([np.zeros_like(heights), heights, np.zeros_like(heights)], -1)[:, None]
    contacts = foot_contacts(ankles, FPS)[:, 0]
    np.testing.assert_array_equal(np.flatnonzero(contacts), [0, 1, 2, 3, 4])  # frame 5's speed: 1.5 m/s
    assert foot_contacts(ankles, FPS, min_frames=1)[9, 0]  # the touch, dropped as a 1-frame run by default
    with pytest.raises(ValueError, match="max_speed"):
        foot_contacts(ankles, FPS, max_speed=-1.0)


def test_foot_skating_is_the_mean_horizontal_speed_while_standing():
    frames = np.arange(10)
    ankles = np.stack([0.5 * frames / FPS, 0.01 * frames, np.zeros(10)], -1)[:, None]  # 0.5 m/s along x
    contacts = (frames < 6)[:, None]
    assert foot_skating(ankles, contacts, FPS) == pytest.approx(0.5)
    assert math.isnan(foot_skating(ankles, np.zeros_like(contacts), FPS))


STANCE = (15, 45)  # frames of the left foot's stance in the hand-built walk


def walk_like(drift: float = 0.03) -> tuple[np.ndarray, np.ndarray]:
    """A 60-frame, 30 fps motion: the root walks along +Z at 0.3 m/s; the left foot stands on frames 15-44 (its leg
    swung back about the hip so that the ankle stays put) but slides forward by ``drift`` metres over them; outside
    the stance it is lifted, and the right leg is lifted throughout. Returns rotations ``[T, 24, 3]`` and
    translation ``[T, 3]``."""
    frames, knee = 60, 0.7
    time = np.arange(frames) / FPS
    translation = np.stack([np.zeros(frames), np.full(frames, 0.9), 0.3 * time], -1).astype(np.float32)
    rotations = np.zeros((frames, 24, 3), np.float32)
    rotations[:, RIGHT.hip, 0], rotations[:, RIGHT.knee, 0] = -0.8, 1.4
    rotations[:, LEFT.hip, 0], rotations[:, LEFT.knee, 0] = -0.9, 1.8  # swing
    # Stance: the hip angle about X that puts the ankle at the planted (and drifting) z.
    start, stop = STANCE
    shin = np.asarray(axis_angle_to_matrix(np.array([knee, 0, 0], np.float32))) @ SMPL24.offsets[LEFT.ankle]
    leg = SMPL24.offsets[LEFT.knee] + shin  # hip to ankle in the hip's frame, hip unturned
    radius, phase = np.hypot(leg[1], leg[2]), np.arctan2(leg[2], leg[1])
    stance = np.arange(start, stop)
    planted = translation[(start + stop) // 2, 2] + drift * (stance - start) / (stop - start)
    wanted = planted - translation[stance, 2] - SMPL24.offsets[LEFT.hip][2]
    hip = np.pi - np.arcsin(wanted / radius) - phase  # the branch with the foot below the hip
    rotations[stance, LEFT.hip, 0] = np.angle(np.exp(1j * hip))
    rotations[stance, LEFT.knee, 0] = knee
    return rotations, translation


def test_clean_feet_holds_a_sliding_stance_still():
    rotations, translation = walk_like()
    out = clean_feet(rotations, translation, SMPL24.offsets, PARENTS, fps=FPS)
    standing = np.flatnonzero(out.contacts[:, 0])
    assert not out.contacts[:, 1].any()
    assert standing.min() >= STANCE[0] and standing.max() < STANCE[1] and len(standing) >= 25
    np.testing.assert_array_equal(np.diff(standing), 1)  # one run
    before_global, before = fk(rotations, translation)
    after_global, after = fk(out.rotations, translation)
    ankle = LEFT.ankle
    assert np.ptp(before[standing, ankle], axis=0).max() > 0.01  # it did slide
    assert np.abs(after[standing, ankle] - after[standing, ankle].mean(axis=0)).max() < 1e-4
    np.testing.assert_allclose(after[:, ankle], out.targets[:, 0], atol=ATOL)  # every target reachable here
    # The foot keeps its world orientation; bones keep their lengths (same offsets).
    np.testing.assert_allclose(after_global[:, ankle], before_global[:, ankle], atol=ATOL)
    np.testing.assert_allclose(bone_lengths(after, PARENTS), bone_lengths(before, PARENTS), atol=ATOL)


def test_clean_feet_changes_only_the_standing_leg_near_its_contacts():
    rotations, translation = walk_like()
    out = clean_feet(rotations, translation, SMPL24.offsets, PARENTS, fps=FPS, blend_frames=4)
    standing = np.flatnonzero(out.contacts[:, 0])
    first, last = standing.min(), standing.max()
    frames = np.arange(len(rotations))
    gap = np.maximum(np.maximum(first - frames, frames - last), 0)
    expected = np.where(gap <= 4, 0.5 * (1 + np.cos(np.pi * gap / 5)), 0.0)  # raised-cosine fade, then nothing
    np.testing.assert_allclose(out.weights[:, 0], expected, atol=1e-6)
    far = out.weights[:, 0] == 0
    assert far.sum() >= 20
    np.testing.assert_array_equal(out.rotations[far], rotations[far])  # exactly
    others = [j for j in range(24) if j not in tuple(LEFT)]
    np.testing.assert_array_equal(out.rotations[:, others], rotations[:, others])
    assert not np.array_equal(out.rotations[standing][:, list(LEFT)], rotations[standing][:, list(LEFT)])


def test_clean_feet_leaves_a_motion_without_contacts_unchanged():
    # Running past at 1.5 m/s with the legs still: the feet are low but never slow.
    rotations, translation = walk_like()
    rotations[:, LEFT.hip, 0], rotations[:, LEFT.knee, 0] = -0.2, 0.3
    translation[:, 2] = 1.5 * np.arange(len(translation)) / FPS
    out = clean_feet(rotations, translation, SMPL24.offsets, PARENTS, fps=FPS)
    assert not out.contacts.any() and not out.weights.any()
    np.testing.assert_array_equal(out.rotations, rotations)
    # Hopping in place: each landing is one slow frame at the bottom, too short for a contact.
    translation = np.zeros_like(translation)
    translation[:, 1] = 0.9 + 0.15 * (1 - np.cos(2 * np.pi * 1.5 * np.arange(len(translation)) / FPS))
    out = clean_feet(rotations, translation, SMPL24.offsets, PARENTS, fps=FPS)
    assert not out.contacts.any()
    np.testing.assert_array_equal(out.rotations, rotations)
    assert clean_feet(rotations, translation, SMPL24.offsets, PARENTS, fps=FPS, min_frames=1).contacts.any()


def test_clean_feet_rejects_bad_legs_and_thresholds():
    rotations, translation = walk_like()
    with pytest.raises(ValueError, match="legs"):
        clean_feet(rotations, translation, SMPL24.offsets, PARENTS, fps=FPS, legs=[(1, 5, 8)])
    with pytest.raises(ValueError, match="legs"):  # the second hangs from the first
        clean_feet(rotations, translation, SMPL24.offsets, PARENTS, fps=FPS, legs=[(0, 1, 4), (1, 4, 7)])
    with pytest.raises(ValueError, match="blend_frames"):
        clean_feet(rotations, translation, SMPL24.offsets, PARENTS, fps=FPS, blend_frames=-1)
    with pytest.raises(ValueError, match="translation"):
        clean_feet(rotations, translation[:-1], SMPL24.offsets, PARENTS, fps=FPS)


def test_clean_feet_reduces_foot_skating_on_the_embedded_walks():
    data = generate("synth-humanact12", "train", seed=0, count=4, progress=False)
    ankles = [LEFT.ankle, RIGHT.ankle]
    measured = []
    for motion in data:
        offsets = rest_offsets(motion.rotations, motion.joints, PARENTS)
        out = clean_feet(motion.rotations, motion.translation, offsets, PARENTS, fps=data.fps)
        before = fk(motion.rotations, motion.translation, offsets)[1][:, ankles]
        after = fk(out.rotations, motion.translation, offsets)[1][:, ankles]
        measured.append((foot_skating(before, out.contacts, data.fps), foot_skating(after, out.contacts, data.fps)))
    print("foot skating (m/s) before -> after, per clip:", [f"{b:.4f} -> {a:.5f}" for b, a in measured])
    assert all(after < 0.1 * before for before, after in measured)
