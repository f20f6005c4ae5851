"""Kinematic trees of the skeletons the paper experiments use.

A skeleton is a tree of J joints given by a static ``parents`` tuple (``-1`` marks the root, which is
always joint 0). Parents need not precede their children (NTU-25 lists ``spine_shoulder`` last), so
code that walks the tree uses :func:`topological_order` rather than joint order.

Library frame: metres, +Y up, the subject faces +Z in the rest pose, +X is the subject's left (SMPL).
"""

from __future__ import annotations

import dataclasses
import functools

import numpy as np


@functools.lru_cache(maxsize=None)
def topological_order(parents: tuple[int, ...]) -> tuple[int, ...]:
    """Joint indices ordered so that every parent comes before its children (breadth-first from the root).

    Also validates ``parents``: joint 0 is the only root (``-1``), every other entry is a joint index, and
    every joint is reachable from the root (i.e. the graph is a tree, with no cycle). Cached, so
    validating a static ``parents`` tuple at trace time costs nothing after the first call.

    Raises:
      ValueError: if ``parents`` does not describe a tree rooted at joint 0.
    """
    num_joints = len(parents)
    if num_joints == 0 or parents[0] != -1:
        raise ValueError(f"parents: expected parents[0] == -1 (joint 0 is the root), got {parents}")
    for joint, parent in enumerate(parents[1:], start=1):
        if not 0 <= parent < num_joints or parent == joint:
            raise ValueError(
                f"parents: joint {joint} has parent {parent}; expected another joint index in "
                f"[0, {num_joints}) (only joint 0 may be the root), got {parents}"
            )
    order = [0]
    for joint in order:  # the list grows while iterated: a breadth-first walk
        order.extend(child for child in range(1, num_joints) if parents[child] == joint)
    if len(order) != num_joints:
        unreachable = sorted(set(range(num_joints)) - set(order))
        raise ValueError(f"parents: joints {unreachable} lie on a cycle, not under the root; got {parents}")
    return tuple(order)


@functools.lru_cache(maxsize=None)
def bones(parents: tuple[int, ...]) -> tuple[tuple[int, int], ...]:
    """The (parent, child) pair of every non-root joint, in joint order: J - 1 pairs."""
    topological_order(parents)  # validates
    return tuple((parent, child) for child, parent in enumerate(parents) if parent >= 0)


@dataclasses.dataclass(frozen=True, eq=False)
class Skeleton:
    """A named kinematic tree, with optional rest offsets.

    Attributes:
      name: human-readable name.
      joint_names: one unique name per joint.
      parents: parent index per joint, ``-1`` for the root (joint 0); any order that forms a tree.
      offsets: ``[J, 3]`` float32 rest vectors from parent to child in the parent's rest frame (metres,
        library frame; FK ignores the root row, zero in the templates), or ``None`` for skeletons used only
        as joint layouts. Stored read-only.

    ``eq=False`` keeps identity equality and hashing: a numpy field has no usable ``==``/hash, and jitted
    code takes the hashable ``skeleton.parents`` tuple as its static argument, not the skeleton.
    """

    name: str
    joint_names: tuple[str, ...]
    parents: tuple[int, ...]
    offsets: np.ndarray | None = None

    def __post_init__(self) -> None:
        # Tuples are required so that ``parents`` can be a jit static argument and names stay immutable.
        if not isinstance(self.parents, tuple) or not all(isinstance(p, int) for p in self.parents):
            raise ValueError(f"parents: expected a tuple of ints, got {self.parents!r}")
        if not isinstance(self.joint_names, tuple):
            raise ValueError(f"joint_names: expected a tuple of str, got {type(self.joint_names).__name__}")
        topological_order(self.parents)
        num_joints = len(self.parents)
        if len(self.joint_names) != num_joints:
            raise ValueError(
                f"joint_names: expected {num_joints} names (one per parent entry), got {len(self.joint_names)}"
            )
        if len(set(self.joint_names)) != num_joints:
            raise ValueError(f"joint_names: expected unique names, got {self.joint_names}")
        if self.offsets is not None:
            offsets = np.array(self.offsets, dtype=np.float32)  # a private copy, so read-only is real
            if offsets.shape != (num_joints, 3):
                raise ValueError(f"offsets: expected shape ({num_joints}, 3), got {offsets.shape}")
            offsets.flags.writeable = False
            object.__setattr__(self, "offsets", offsets)

    @property
    def num_joints(self) -> int:
        return len(self.parents)

    @property
    def children(self) -> tuple[tuple[int, ...], ...]:
        """Children of each joint, in joint order."""
        return tuple(
            tuple(child for child, parent in enumerate(self.parents) if parent == joint)
            for joint in range(self.num_joints)
        )

    @property
    def bones(self) -> tuple[tuple[int, int], ...]:
        """(parent, child) pairs of the non-root joints, in joint order."""
        return bones(self.parents)

    def index(self, joint_name: str) -> int:
        """Index of a joint by name, e.g. the hips that :func:`jaxmotion.geometry.kinematics.canonicalize` takes."""
        try:
            return self.joint_names.index(joint_name)
        except ValueError:
            raise ValueError(f"joint_name: {joint_name!r} is not a joint of {self.name}") from None


_SMPL24_NAMES = (
    "pelvis", "left_hip", "right_hip", "spine1", "left_knee", "right_knee", "spine2", "left_ankle",
    "right_ankle", "spine3", "left_foot", "right_foot", "neck", "left_collar", "right_collar", "head",
    "left_shoulder", "right_shoulder", "left_elbow", "right_elbow", "left_wrist", "right_wrist",
    "left_hand", "right_hand",
)


def _smpl24_offsets() -> np.ndarray:
    """SMPL neutral template, rounded; project-defined.

    Rest vectors child minus parent of the SMPL neutral model at beta = 0 (adult proportions), rounded to
    millimetres. Left/right pairs are exact mirror images (x negated), and the few millimetres of x on
    the midline joints are zeroed, so the whole rest pose is mirror-symmetric about x = 0: left/right
    flip augmentation then maps the template onto itself.
    """
    midline = {  # joint: offset from its parent
        "spine1": (0.0, 0.109, -0.027),
        "spine2": (0.0, 0.135, 0.001),
        "spine3": (0.0, 0.053, 0.025),
        "neck": (0.0, 0.214, -0.043),
        "head": (0.0, 0.065, 0.051),
    }
    left = {  # left side (+x); the right side is its mirror image
        "hip": (0.069, -0.091, -0.006),
        "knee": (0.036, -0.379, -0.007),
        "ankle": (-0.015, -0.398, -0.043),
        "foot": (0.026, -0.052, 0.121),
        "collar": (0.080, 0.120, -0.036),
        "shoulder": (0.093, 0.031, -0.009),
        "elbow": (0.257, -0.013, -0.024),
        "wrist": (0.252, 0.008, -0.003),
        "hand": (0.085, -0.010, -0.014),
    }
    rows = dict(midline, pelvis=(0.0, 0.0, 0.0))
    for part, (x, y, z) in left.items():
        rows[f"left_{part}"] = (x, y, z)
        rows[f"right_{part}"] = (-x, y, z)
    return np.array([rows[name] for name in _SMPL24_NAMES], dtype=np.float32)


SMPL24 = Skeleton(
    name="SMPL-24 (HumanAct12)",
    joint_names=_SMPL24_NAMES,
    parents=(-1, 0, 0, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 9, 9, 12, 13, 14, 16, 17, 18, 19, 20, 21),
    offsets=_smpl24_offsets(),
)

# Action2Motion's 20-joint CMU mocap set publishes no joint names: these are inferred from the tree
# (root -> thorax -> neck -> head; two 4-joint arms off the thorax; two 4-joint legs off the root), with
# the first chain of each pair taken as the left one, following the CMU ASF's left-before-right order.
CMU_MOCAP20 = Skeleton(
    name="CMU mocap 20 (Action2Motion)",
    joint_names=(
        "hips", "thorax", "neck", "head",
        "left_collar", "left_shoulder", "left_elbow", "left_wrist",
        "right_collar", "right_shoulder", "right_elbow", "right_wrist",
        "left_hip", "left_knee", "left_ankle", "left_toe",
        "right_hip", "right_knee", "right_ankle", "right_toe",
    ),
    parents=(-1, 0, 1, 2, 1, 4, 5, 6, 1, 8, 9, 10, 0, 12, 13, 14, 0, 16, 17, 18),
)

# The VIBE 18-joint set (OpenPose-style names) used for NTU-13 and ODMO's UESTC xyz data.
UESTC18 = Skeleton(
    name="VIBE-18 (NTU-13, UESTC)",
    joint_names=(
        "MidHip", "Neck", "RShoulder", "RElbow", "RWrist", "LShoulder", "LElbow", "LWrist", "Nose",
        "RHip", "RKnee", "RAnkle", "LHip", "LKnee", "LAnkle", "LHeel", "RHeel", "HeadTop",
    ),
    parents=(-1, 0, 1, 2, 3, 1, 5, 6, 1, 0, 9, 10, 0, 12, 13, 14, 11, 8),
)
VIBE18 = UESTC18

# Kinect v2 joint order; spine_shoulder (20) is listed after its children, so this tree is not
# topologically ordered.
NTU25 = Skeleton(
    name="NTU-25 (Kinect v2)",
    joint_names=(
        "spine_base", "spine_mid", "neck", "head", "left_shoulder", "left_elbow", "left_wrist",
        "left_hand", "right_shoulder", "right_elbow", "right_wrist", "right_hand", "left_hip",
        "left_knee", "left_ankle", "left_foot", "right_hip", "right_knee", "right_ankle", "right_foot",
        "spine_shoulder", "left_hand_tip", "left_thumb", "right_hand_tip", "right_thumb",
    ),
    parents=(-1, 0, 20, 2, 20, 4, 5, 6, 20, 8, 9, 10, 0, 12, 13, 14, 0, 16, 17, 18, 1, 7, 7, 11, 11),
)

# GTA Combat's 22 joints (ActFormer's gta_adjacency.h5 parents, FACTS 1.4). ActFormer publishes no names:
# the tree is JTA's 22-joint GTA-V layout (head top, head centre, neck, right then left clavicle-shoulder-
# elbow-wrist, spine0 (top) .. spine4 (pelvis), right then left hip-knee-ankle) with spine4 and head_top
# swapped so that the pelvis is joint 0 (its head joint, 15, is then the head top); sides follow JTA.
GTA22 = Skeleton(
    name="GTA-22 (GTA Combat)",
    joint_names=(
        "pelvis", "head_center", "neck", "right_clavicle", "right_shoulder", "right_elbow", "right_wrist",
        "left_clavicle", "left_shoulder", "left_elbow", "left_wrist", "spine0", "spine1", "spine2", "spine3",
        "head_top", "right_hip", "right_knee", "right_ankle", "left_hip", "left_knee", "left_ankle",
    ),
    parents=(-1, 2, 11, 2, 3, 4, 5, 2, 7, 8, 9, 12, 13, 14, 0, 1, 0, 16, 17, 0, 19, 20),
)

# The 15 joints NTU-25 and GTA-22 share, in the order of the authors' ST-GCN ``joints15`` layout (pelvis; neck;
# head; one arm's shoulder-elbow-wrist, the other's; one leg's hip-knee-ankle, the other's). ActFormer measures
# GTA Combat's FID_a with an NTU-1P recogniser on this topology; its conversion is unpublished (FACTS 1.3), so
# which joint of each skeleton stands for each of the 15 is this project's reading of the names: NTU's spine
# base and GTA's pelvis are the root, NTU's spine shoulder and GTA's neck the neck, NTU's head and GTA's head
# centre the head, the shoulders are the upper-arm joints (not GTA's clavicles); the layout's sides are
# unnamed, the left limbs are put first.
JOINTS15 = Skeleton(
    name="joints15 (NTU / GTA common)",
    joint_names=(
        "pelvis", "neck", "head", "left_shoulder", "left_elbow", "left_wrist", "right_shoulder", "right_elbow",
        "right_wrist", "left_hip", "left_knee", "left_ankle", "right_hip", "right_knee", "right_ankle",
    ),
    parents=(-1, 0, 1, 1, 3, 4, 1, 6, 7, 0, 9, 10, 0, 12, 13),
)

#: Each skeleton that maps onto :data:`JOINTS15`: its joint standing for each of the 15, by name.
JOINTS15_SOURCES = {
    NTU25.name: ("spine_base", "spine_shoulder", "head", "left_shoulder", "left_elbow", "left_wrist",
                 "right_shoulder", "right_elbow", "right_wrist", "left_hip", "left_knee", "left_ankle", "right_hip",
                 "right_knee", "right_ankle"),
    GTA22.name: ("pelvis", "neck", "head_center", "left_shoulder", "left_elbow", "left_wrist", "right_shoulder",
                 "right_elbow", "right_wrist", "left_hip", "left_knee", "left_ankle", "right_hip", "right_knee",
                 "right_ankle"),
}


def joints15_indices(skeleton: Skeleton) -> tuple[int, ...]:
    """``skeleton``'s joint for each of :data:`JOINTS15`'s (gather ``joints[..., indices, :]``); the root maps
    to the root, so a motion's translation stays its translation."""
    if skeleton.name == JOINTS15.name:
        return tuple(range(JOINTS15.num_joints))
    if skeleton.name not in JOINTS15_SOURCES:
        raise ValueError(f"skeleton: {skeleton.name} has no mapping onto the 15-joint topology; known: "
                         f"{sorted(JOINTS15_SOURCES)}")
    return tuple(skeleton.index(name) for name in JOINTS15_SOURCES[skeleton.name])
