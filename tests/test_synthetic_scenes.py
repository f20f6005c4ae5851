"""Scenes of several persons (synth-ntu2p's interactions): determinism, layout, contact where the class implies
it and nowhere else, reactions after hits, distances that walking changes.

Bodies are capsules around their bones (``body_capsules``); "contact" is a surface gap of at most 5 cm, and
outside the touching limbs the persons' surfaces never overlap by more than 5 cm (the radii are rough
estimates of flesh, which two bodies pressed together also compress).
"""

import dataclasses
from types import MappingProxyType

import jax.numpy as jnp
import numpy as np
import pytest

from body_capsules import all_points, limbs, part_points, surface_gap
from jaxmotion.data.synthetic import ntu2p
from jaxmotion.data.synthetic.anatomy import LIMITS, rotmats_to_angles
from jaxmotion.data.synthetic.engine import Split, Variant, generate_split
from jaxmotion.geometry import SMPL24, axis_angle_to_matrix, forward_kinematics, forward_kinematics_transforms

PER_CLASS = 2
CONTACT = 0.05
NAMES = [c.name for c in ntu2p.CLASSES]


def _variant(count=26 * PER_CLASS, **changes):
    base = Variant("test-ntu2p", ntu2p.CLASSES, 30.0, (60, 150),
                   MappingProxyType({"train": Split(count, tuple(range(1, 21)))}), persons=2)
    return dataclasses.replace(base, **changes)


@pytest.fixture(scope="module")
def scenes():
    return generate_split(_variant(), "train", seed=0)


def _clips(data, name):
    c = NAMES.index(name)
    return [data[int(i)] for i in np.flatnonzero(data.actions == c)]


def test_same_seed_same_bytes_and_swapped_copies_reverse_the_persons(scenes):
    again = generate_split(_variant(8), "train", seed=0)
    np.testing.assert_array_equal(again.joints, scenes.subset(range(8)).joints)
    flipped = generate_split(_variant(4, swapped_copies=True), "train", seed=0)
    assert len(flipped) == 8 and flipped.names[1] == flipped.names[0] + "-flip"
    np.testing.assert_array_equal(flipped[1].joints, flipped[0].joints[::-1])
    np.testing.assert_array_equal(flipped[1].rotations, flipped[0].rotations[::-1])
    assert flipped.actions[1] == flipped.actions[0]


def test_layout_fk_and_joint_limits(scenes):
    assert scenes.persons == 2 and scenes.joints.shape[1:] == (2, 24, 3) and scenes.rotations.shape[1:] == (2, 24, 3)
    assert sorted(set(scenes.actions.tolist())) == list(range(26))
    for m in (scenes[0],):
        # joints are FK of the stored rotations on one rigid body per person: the rest offsets read back
        # through each frame's parent rotations are the same on every frame, and FK with them gives the joints
        global_rot, _ = forward_kinematics_transforms(axis_angle_to_matrix(jnp.asarray(m.rotations)),
                                                      jnp.asarray(m.translation), SMPL24.offsets, SMPL24.parents)
        parents = np.array(SMPL24.parents[1:])
        offsets = np.einsum("ptjba,ptjb->ptja", np.asarray(global_rot)[:, :, parents],
                            m.joints[:, :, 1:] - m.joints[:, :, parents])
        np.testing.assert_allclose(offsets, np.broadcast_to(offsets[:, :1], offsets.shape), atol=2e-4)
        body = np.concatenate([np.zeros((2, 1, 3)), offsets[:, 0]], axis=1)
        for p in range(2):
            fk = forward_kinematics(axis_angle_to_matrix(jnp.asarray(m.rotations[p])), jnp.asarray(m.translation[p]),
                                    body[p], SMPL24.parents)
            np.testing.assert_allclose(np.asarray(fk), m.joints[p], atol=3e-4)
    angles = rotmats_to_angles(np.asarray(axis_angle_to_matrix(jnp.asarray(scenes.rotations[::23]))))
    assert np.all(angles >= LIMITS[..., 0] - 0.5) and np.all(angles <= LIMITS[..., 1] + 0.5)
    assert np.all(scenes.joints[..., 1].min(axis=-1) > -0.03)  # nobody sinks into the floor


@pytest.mark.parametrize("cls", [c for c in ntu2p.CLASSES if c.touches], ids=lambda c: c.name[:24])
def test_contact_classes_touch_where_the_class_says(scenes, cls):
    for m in _clips(scenes, cls.name):
        j = m.joints
        touch = min(surface_gap(part_points(j[pa], ja), part_points(j[pb], jb)).min() for (pa, ja), (pb, jb) in cls.touches)
        assert touch <= CONTACT, f"{cls.name} ({m.name}): the touching parts stay {touch:.3f} m apart"
        excluded = {0: set(), 1: set()}
        for (pa, ja), (pb, jb) in cls.touches:
            excluded[pa] |= limbs(ja)
            excluded[pb] |= limbs(jb)
        rest = surface_gap(all_points(j[0], excluded[0]), all_points(j[1], excluded[1])).min()
        assert rest > -CONTACT, f"{cls.name} ({m.name}): bodies overlap by {-rest:.3f} m outside the contact"


@pytest.mark.parametrize("cls", [c for c in ntu2p.CLASSES if not c.touches], ids=lambda c: c.name[:24])
def test_classes_without_contact_never_touch(scenes, cls):
    for m in _clips(scenes, cls.name):
        gap = surface_gap(all_points(m.joints[0]), all_points(m.joints[1])).min()
        assert gap > CONTACT, f"{cls.name} ({m.name}): the persons come within {gap:.3f} m"


def _away(m):
    """``[T]`` how far the receiver's pelvis has moved away from the actor's start, since frame 0."""
    d = (m.joints[1, 0, 0] - m.joints[0, 0, 0]) * np.array([1.0, 0.0, 1.0])
    d /= np.linalg.norm(d)
    return (m.joints[1, :, 0] - m.joints[1, 0, 0]) @ d


@pytest.mark.parametrize("name", ["punching/slapping other person", "kicking other person", "pushing other person",
                                  "knock over other person (hit with body)"])
def test_hits_come_first_and_the_receiver_then_gives_way(scenes, name):
    cls = ntu2p.CLASSES[NAMES.index(name)]
    for m in _clips(scenes, name):
        j = m.joints
        (pa, ja), (pb, jb) = cls.touches[0] if len(cls.touches) == 1 else min(
            cls.touches, key=lambda t: surface_gap(part_points(j[t[0][0]], t[0][1]), part_points(j[t[1][0]], t[1][1])).min())
        gap = surface_gap(part_points(j[pa], ja), part_points(j[pb], jb))
        hit = int(np.flatnonzero(gap <= CONTACT)[0])
        away = _away(m)
        assert abs(away[hit]) < 0.05, f"{m.name}: the receiver moved {away[hit]:.2f} m before the hit"
        assert away[hit:].max() > 0.1, f"{m.name}: the receiver does not step back after the hit"


def test_walking_changes_the_distance_as_the_class_says(scenes):
    def gap(m):
        return np.linalg.norm((m.joints[0, :, 0] - m.joints[1, :, 0])[:, [0, 2]], axis=-1)

    for m in _clips(scenes, "walking towards each other"):
        g = gap(m)
        assert g[0] - g[-1] > 1.0 and g[-1] > 0.6
    for m in _clips(scenes, "walking apart from each other"):
        g = gap(m)
        assert g[-1] - g[0] > 1.0
    for m in _clips(scenes, "follow other person"):
        g, travel = gap(m), np.linalg.norm(m.joints[:, -1, 0] - m.joints[:, 0, 0], axis=-1)
        assert np.all(travel > 1.0) and np.ptp(g) < 0.8
