"""Retargeting aids for exported BVH: Mixamo-style bone names for the SMPL-24 tree, and an optional foot clean-up.

Conventions: library frame (metres, +Y up, the subject faces +Z at rest, +X is the subject's left); rotations are
local axis-angle ``[T, J, 3]`` with joint 0's global; ``translation [T, 3]`` is joint 0's position. Axes: T frames,
J joints, F feet (legs).

**Bone names.** :data:`MIXAMO_NAMES` maps each SMPL-24 joint (:data:`jaxmotion.geometry.skeletons.SMPL24`) to the
Mixamo bone that starts at it, with the ``mixamorig:`` prefix of Mixamo's exports (a Mixamo BVH in the ``bvh``
package's test data, ``20tab/bvh-python`` ``tests/test_freebvh.bvh``, is named so). Rigs are also met with the
prefix stripped by some tool, and a BVH reader that split names at a colon would misread it, so
:func:`mixamo_names` takes the prefix as a parameter (``prefix=""`` for bare ``Hips``, ``LeftArm``, ...) and
returns the names in SMPL-24's joint order, as ``save_bvh(names=...)`` takes them. The BVH writer accepts a colon
(names must be non-empty, unique, without whitespace or braces). Blender 5.0.1's BVH importer (``bpy`` from PyPI,
run once by hand, not in the suite) kept the prefixed names and put every joint of a 142-frame clip within 3e-6 m
of the library's; MotionBuilder's importer was not tried. A BVH joint names the bone its rotation swings (from it
to its child), and a Mixamo bone starts at the joint of the same place, so the pairs are:

* pelvis -> ``Hips``; SMPL's three spine joints in order -> ``Spine``, ``Spine1``, ``Spine2`` (both trees have
  three bones between the pelvis and the neck; Mixamo numbers from the second); neck -> ``Neck``; head -> ``Head``;
* collar -> ``Shoulder`` (Mixamo's shoulder is the clavicle bone); SMPL's shoulder -> ``Arm`` (upper arm);
  elbow -> ``ForeArm``; wrist -> ``Hand``;
* SMPL's ``hand`` (the end of the hand, 8.5 cm past the wrist in the template, at the knuckles) -> ``HandMiddle1``,
  the first bone of Mixamo's middle finger, which starts at the middle knuckle and runs along the hand's axis.
  A name the target rig has is bound by name-matching retargeters, where an invented ``HandEnd`` would be dropped;
  SMPL bends the fingers as one block about that joint, and on a Mixamo rig only the middle finger follows;
* hip -> ``UpLeg``; knee -> ``Leg``; ankle -> ``Foot``; SMPL's ``foot`` (the toe joint) -> ``ToeBase``.

Sides agree: SMPL's ``left_*`` is the subject's left (+X at rest), as is Mixamo's ``Left*``.

**Rest pose and scale.** The BVH's rest pose (all rotations zero) is the SMPL-24 template's: a T-pose, arms along
±X, +Y up, facing +Z, in metres. The Mixamo BVH cited above has the same axes (``LeftArm`` along +X, ``LeftUpLeg``
at +X, toes toward +Z, +Y up) in centimetres (its hips 98 units above the floor), with its own proportions.
Blender's BVH importer defaults (``Forward -Z``, ``Up Y``) read a +Y-up file as such; its ``Scale`` (default 1)
should be 100 when the target rig's units are centimetres. A retargeter that copies rotations bone by bone assumes
the two rest poses match: both are T-poses, but their bones point differently (between that file and the SMPL-24
template, bone by bone: 2-7 degrees for the thighs, shins, upper arms, forearms and lower spine, 13-32 for the others:
hips, upper spine, neck, head, collars, shoulders, hands, toes), so use the retargeter's rest-pose matching (or align
the rest poses) before copying rotations.

**Foot clean-up** (optional, :func:`clean_feet`). Generated motions slide their feet while standing on them. A foot
is in contact where its ankle is within ``max_height`` of the clip's floor (the lowest ankle height over the clip
and both feet) and slower than ``max_speed``. The ankle alone decides, as it is the point held: while only the toes
bear weight (heel off) the ankle turns about them and must not be held. Contact runs shorter than ``min_frames``
are dropped (a swing passes a low, slow frame at its turning point without standing). Within each run the ankle is
held at the run's mean position (all three coordinates: the foot is not pushed onto the floor) by turning the hip
and the knee (:func:`jaxmotion.geometry.ik.two_bone_pose`), the ankle's local rotation being recomputed so that the
foot keeps its orientation in the world. Over ``blend_frames`` frames either side of a run the hold fades out with
a raised cosine, so legs do not pop. Nothing else changes: not the root, the toes' local rotations, the upper body,
nor frames farther from a contact than the blend. The thresholds are ours, set with margin from the embedded walks
(``synth-humanact12``, ``synth-mag``): there a standing ankle stays within 4 cm of the floor height at a median
speed under 0.05 m/s, while low ankles outside the stances move at a median 0.65-1.1 m/s.
"""

from __future__ import annotations

import functools
import math
import re
from collections.abc import Sequence
from types import MappingProxyType
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.data.arrays import bucket, checked, padded
from jaxmotion.geometry.ik import two_bone_pose
from jaxmotion.geometry.kinematics import forward_kinematics_transforms
from jaxmotion.geometry.rotations import axis_angle_to_matrix, matrix_to_axis_angle
from jaxmotion.geometry.skeletons import SMPL24, topological_order

__all__ = [
    "MIXAMO_NAMES", "MIXAMO_PREFIX", "SMPL24_LEGS", "FootCleanup", "Leg", "clean_feet", "foot_contacts",
    "foot_skating", "mixamo_names",
]

#: The prefix of Mixamo's bone names in its own exports.
MIXAMO_PREFIX = "mixamorig:"

# SMPL-24 joint -> Mixamo bone, unprefixed; the module docstring says why each pair.
_MIXAMO_BONES = (
    ("pelvis", "Hips"), ("left_hip", "LeftUpLeg"), ("right_hip", "RightUpLeg"), ("spine1", "Spine"),
    ("left_knee", "LeftLeg"), ("right_knee", "RightLeg"), ("spine2", "Spine1"), ("left_ankle", "LeftFoot"),
    ("right_ankle", "RightFoot"), ("spine3", "Spine2"), ("left_foot", "LeftToeBase"),
    ("right_foot", "RightToeBase"), ("neck", "Neck"), ("left_collar", "LeftShoulder"),
    ("right_collar", "RightShoulder"), ("head", "Head"), ("left_shoulder", "LeftArm"),
    ("right_shoulder", "RightArm"), ("left_elbow", "LeftForeArm"), ("right_elbow", "RightForeArm"),
    ("left_wrist", "LeftHand"), ("right_wrist", "RightHand"), ("left_hand", "LeftHandMiddle1"),
    ("right_hand", "RightHandMiddle1"),
)

#: Every SMPL-24 joint name -> its Mixamo bone name with :data:`MIXAMO_PREFIX` (read-only; see the module docstring).
MIXAMO_NAMES = MappingProxyType({joint: MIXAMO_PREFIX + bone for joint, bone in _MIXAMO_BONES})


def mixamo_names(prefix: str = MIXAMO_PREFIX) -> tuple[str, ...]:
    """The Mixamo bone names in SMPL-24's joint order, each with ``prefix`` (``""``: bare names), for
    ``save_bvh(..., names=mixamo_names())``.

    Raises:
      ValueError: if ``prefix`` is not a string or holds whitespace or braces (BVH names cannot).
    """
    if not isinstance(prefix, str) or re.search(r"[\s{}]", prefix):
        raise ValueError(f"prefix: expected a string without whitespace or braces, got {prefix!r}")
    bones = dict(_MIXAMO_BONES)
    return tuple(prefix + bones[joint] for joint in SMPL24.joint_names)


class Leg(NamedTuple):
    """Joint indices of one leg: the hip (the chain's root), the knee and the ankle (the point held)."""

    hip: int
    knee: int
    ankle: int


#: SMPL-24's legs, left then right.
SMPL24_LEGS = tuple(Leg(*(SMPL24.index(f"{side}_{joint}") for joint in ("hip", "knee", "ankle")))
                    for side in ("left", "right"))


class FootCleanup(NamedTuple):
    """What :func:`clean_feet` returns.

    Attributes:
      rotations: ``[T, J, 3]`` float32 local axis-angle, the input's except the legs' hips, knees and ankles near
        contacts.
      contacts: ``[T, F]`` bool, where each foot was found standing (:func:`foot_contacts`).
      targets: ``[T, F, 3]`` float32, where the leg's ankle was sent: the held position during a contact, the
        input ankle where ``weights`` is 0, a blend of the two in between.
      weights: ``[T, F]`` float32 in [0, 1], how much of the hold applies (1 during contacts).
    """

    rotations: np.ndarray
    contacts: np.ndarray
    targets: np.ndarray
    weights: np.ndarray


def _float32(value, field: str, expected: tuple, named: str) -> np.ndarray:
    return checked(value, field, expected, named).astype(np.float32)


def _positive(value, field: str) -> float:
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = math.nan
    if not (number > 0 and math.isfinite(number)):
        raise ValueError(f"{field}: expected a positive finite number, got {value!r}")
    return number


def _count(value, field: str, smallest: int) -> int:
    if not isinstance(value, (int, np.integer)) or isinstance(value, bool) or value < smallest:
        raise ValueError(f"{field}: expected an integer >= {smallest}, got {value!r}")
    return int(value)


def _checked_legs(legs: Sequence[Sequence[int]], parents: tuple[int, ...]) -> tuple[Leg, ...]:
    """``legs`` as :class:`Leg` tuples: at least one, each a hip-knee-ankle chain, none hanging from another."""
    chains = [tuple(leg) for leg in legs]
    if not chains or any(len(chain) != 3 or not all(isinstance(j, (int, np.integer)) and 0 <= j < len(parents)
                                                    for j in chain) for chain in chains):
        raise ValueError(f"legs: expected (hip, knee, ankle) joint indices in [0, {len(parents)}), got {chains}")
    checked = tuple(Leg(*(int(j) for j in chain)) for chain in chains)
    for index, leg in enumerate(checked):
        if parents[leg.knee] != leg.hip or parents[leg.ankle] != leg.knee:
            raise ValueError(f"legs: expected each leg's joints to be the parent of the next, got {tuple(leg)} "
                             f"with parents {tuple(parents[j] for j in leg)}")
        above, joint = set(), leg.hip  # the hip and its ancestors: no other leg may turn them
        while joint >= 0:
            above.add(joint)
            joint = parents[joint]
        if any(set(other) & above for k, other in enumerate(checked) if k != index):
            raise ValueError(f"legs: expected legs that do not hang from one another, got {chains}")
    return checked


def _runs(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Starts and (exclusive) stops of the runs of True in ``mask [T]``."""
    edges = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    return np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)


def foot_contacts(ankles, fps: float, *, max_height: float = 0.05, max_speed: float = 0.2,
                  min_frames: int = 3) -> np.ndarray:
    """Where each foot stands: ``ankles [T, F, 3]`` -> ``[T, F]`` bool.

    A frame is a contact where the ankle is at most ``max_height`` metres above the clip's floor (the lowest ankle
    height over all frames and feet) and moves at most ``max_speed`` m/s (central differences, one-sided at the
    ends; a one-frame clip has speed 0); runs of contact shorter than ``min_frames`` frames are dropped.
    """
    ankles = checked(ankles, "ankles", (None, None, 3), "[T, F, 3]").astype(np.float64)
    fps, max_height, max_speed = (_positive(v, f) for v, f in ((fps, "fps"), (max_height, "max_height"),
                                                               (max_speed, "max_speed")))
    min_frames = _count(min_frames, "min_frames", 1)
    heights = ankles[..., 1] - ankles[..., 1].min()
    if len(ankles) > 1:
        speeds = np.linalg.norm(np.gradient(ankles, axis=0), axis=-1) * fps
    else:
        speeds = np.zeros(ankles.shape[:2])
    contacts = (heights <= max_height) & (speeds <= max_speed)
    for foot in range(contacts.shape[1]):
        for start, stop in zip(*_runs(contacts[:, foot])):
            if stop - start < min_frames:
                contacts[start:stop, foot] = False
    return contacts


def foot_skating(ankles, contacts, fps: float) -> float:
    """Mean horizontal (x, z) ankle speed in m/s over pairs of consecutive frames in which a foot is in contact:
    ``ankles [T, F, 3]``, ``contacts [T, F]``; NaN where no foot stands for two frames in a row."""
    ankles = checked(ankles, "ankles", (None, None, 3), "[T, F, 3]").astype(np.float64)
    contacts = np.asarray(contacts, bool)
    if contacts.shape != ankles.shape[:2]:
        raise ValueError(f"contacts: expected shape {ankles.shape[:2]} ([T, F], as ankles), got {contacts.shape}")
    fps = _positive(fps, "fps")
    steps = np.linalg.norm(np.diff(ankles[..., [0, 2]], axis=0), axis=-1) * fps  # [T - 1, F]
    standing = contacts[1:] & contacts[:-1]
    return float(steps[standing].mean()) if standing.any() else float("nan")


def _holds(ankles: np.ndarray, contacts: np.ndarray, blend_frames: int) -> tuple[np.ndarray, np.ndarray]:
    """Ankle targets ``[T, F, 3]`` and hold weights ``[T, F]`` from the contacts.

    Each run holds its mean ankle position with weight 1 and fades with a raised cosine over ``blend_frames``
    frames either side. Where two runs' fades overlap, their held positions are averaged by weight (and the
    weights summed, at most 1), so the target moves continuously between them.
    """
    frames = np.arange(len(ankles))
    weights, targets = np.zeros(contacts.shape), ankles.copy()
    for foot in range(contacts.shape[1]):
        total, pulled, runs = np.zeros(len(frames)), np.zeros((len(frames), 3)), []
        for start, stop in zip(*_runs(contacts[:, foot])):
            held = ankles[start:stop, foot].mean(axis=0)
            gap = np.maximum(np.maximum(start - frames, frames - (stop - 1)), 0)
            fade = np.where(gap <= blend_frames, 0.5 * (1.0 + np.cos(np.pi * gap / (blend_frames + 1))), 0.0)
            total += fade
            pulled += fade[:, None] * held
            runs.append((start, stop, held))
        weight = np.minimum(total, 1.0)
        locked = pulled / np.maximum(total, 1e-12)[:, None]
        for start, stop, held in runs:  # a contact frame holds its own run's position, whatever fades nearby
            weight[start:stop], locked[start:stop] = 1.0, held
        weights[:, foot] = weight
        targets[:, foot] = (1.0 - weight[:, None]) * ankles[:, foot] + weight[:, None] * locked
    return targets, weights


@functools.partial(jax.jit, static_argnames="parents")
def _transforms(rotations, translation, offsets, parents):
    """``[T, J, 3]`` axis-angle, ``[T, 3]``, ``[J, 3]`` -> (global rotations ``[T, J, 3, 3]``, joints ``[T, J, 3]``)."""
    return forward_kinematics_transforms(axis_angle_to_matrix(rotations), translation, offsets, parents)


@functools.partial(jax.jit, static_argnames=("parents", "legs"))
def _solve_legs(rotations, global_rotmats, joints, targets, moving, knee_hinge, parents, legs):
    """Each leg's ankle sent to its target ``[T, F, 3]`` where ``moving [T, F]``: ``[T, J, 3]`` new axis-angle.

    Every leg is solved on the input pose's forward kinematics: legs do not hang from one another (checked by
    the caller), so turning one moves nothing another's solution reads.
    """
    local = axis_angle_to_matrix(rotations)
    for foot, leg in enumerate(legs):
        solve = functools.partial(two_bone_pose, parents=parents, chain=tuple(leg), hinge=knee_hinge)
        posed = jax.vmap(lambda *pose: solve(*pose[:3], target=pose[3]))(local, global_rotmats, joints,
                                                                          targets[:, foot])
        local = jnp.where(moving[:, foot, None, None, None], posed, local)
    return matrix_to_axis_angle(local)


def clean_feet(rotations, translation, offsets, parents: tuple[int, ...], *, fps: float,
               legs: Sequence[Leg] = SMPL24_LEGS, max_height: float = 0.05, max_speed: float = 0.2,
               min_frames: int = 3, blend_frames: int = 4, knee_hinge: Sequence[float] = (1.0, 0.0, 0.0),
               ) -> FootCleanup:
    """Hold each foot still while it stands (see the module docstring): contacts by :func:`foot_contacts`, the leg
    moved by two-bone IK, the foot's world orientation kept.

    Args:
      rotations: ``[T, J, 3]`` local axis-angle, joint 0 global.
      translation: ``[T, 3]`` root positions (not changed).
      offsets: ``[J, 3]`` rest offsets the motion is posed with (e.g. ``jaxmotion.data.export.rest_offsets``).
      parents: static parent tuple (``-1`` for joint 0).
      fps: frames per second (for the speeds).
      legs: the legs to clean, as :class:`Leg` joint indices of ``parents`` (default: SMPL-24's two).
      max_height, max_speed, min_frames: the contact thresholds of :func:`foot_contacts` (metres above the
        clip's lowest ankle: 0.05; m/s: 0.2; frames: 3).
      blend_frames: frames either side of a contact run over which the hold fades out (default 4; 0: none).
      knee_hinge: the knees' bend axis in their own frames, used only where a leg is straight (SMPL: +X).

    Returns:
      A :class:`FootCleanup`: the new rotations, the contacts ``[T, F]``, the ankle targets ``[T, F, 3]`` and the
      hold weights ``[T, F]``. Where a target is out of the leg's reach (the root moved too far), the leg is
      straightened toward it and the ankle stops short.

    Raises:
      ValueError: on shapes that do not match the above, non-finite values, a leg whose joints are not a
        hip-knee-ankle chain of ``parents``, or a threshold out of range.
    """
    parents = tuple(int(p) for p in parents)
    topological_order(parents)
    num_joints = len(parents)
    rotations = _float32(rotations, "rotations", (None, num_joints, 3), f"[T, {num_joints}, 3]")
    frames = len(rotations)
    translation = _float32(translation, "translation", (frames, 3), f"[T, 3] = ({frames}, 3)")
    offsets = _float32(offsets, "offsets", (num_joints, 3), f"[{num_joints}, 3]")
    knee_hinge = _float32(knee_hinge, "knee_hinge", (3,), "[3]")
    if not np.linalg.norm(knee_hinge) > 0:
        raise ValueError("knee_hinge: expected a non-zero axis")
    legs = _checked_legs(legs, parents)
    blend_frames = _count(blend_frames, "blend_frames", 0)

    # Compiled once per power-of-two clip length (and skeleton), not once per length: clips are padded with
    # copies of their last frame, which the IK leaves unused.
    grow = functools.partial(padded, size=bucket(frames, 16))
    global_rotmats, joints = _transforms(grow(rotations), grow(translation), offsets, parents)
    ankles = np.asarray(joints)[:frames, [leg.ankle for leg in legs]].astype(np.float64)
    contacts = foot_contacts(ankles, fps, max_height=max_height, max_speed=max_speed, min_frames=min_frames)
    targets, weights = _holds(ankles, contacts, blend_frames)
    moving = weights > 0  # [T, F]
    if not moving.any():
        return FootCleanup(rotations=rotations, contacts=contacts, targets=targets.astype(np.float32),
                           weights=weights.astype(np.float32))
    solved = np.asarray(_solve_legs(grow(rotations), global_rotmats, joints, grow(targets.astype(np.float32)),
                                    grow(moving), knee_hinge, parents, legs))[:frames]
    changed = np.zeros((frames, num_joints), bool)
    for foot, leg in enumerate(legs):
        changed[np.ix_(moving[:, foot], list(leg))] = True
    # Only the joints the IK turned are taken from it, so every other value is the input's, bit for bit.
    cleaned = np.where(changed[..., None], solved, rotations)
    return FootCleanup(rotations=cleaned.astype(np.float32), contacts=contacts,
                       targets=targets.astype(np.float32), weights=weights.astype(np.float32))
