"""HumanAct12 in its two published forms: ACTOR's SMPL poses and Action2Motion's joint files.

**HumanAct12Poses** (ACTOR: ``src/datasets/humanact12poses.py``, written by
``src/preprocess/humanact12_process.py``). One file, ``<dir>/humanact12poses.pkl``: a pickled dict of
per-clip lists, all of the same length N (1191 clips in the release):

  * ``poses``: ``[T, 72]`` SMPL axis-angle (24 joints x 3), global orientation already turned into the
    HumanAct12 camera frame (PHSPD camera ``c2``);
  * ``joints3D``: ``[T, 24, 3]`` the HumanAct12 joints (metres, camera frame: y down, facing -Z);
  * ``y``: coarse class 0..11; ``oldposes``: unused (empty in the release).

Every clip is train (ACTOR has no test split). The pickle carries no clip names and no subjects:
names are ``humanact12poses.pkl#<index>`` and subjects ``-1``.

**HumanAct12 joints** (Action2Motion ``dataProcessing/dataset.py`` ``MotionFolderDatasetHumanAct12``; ODMO's
``dataset/HumanAct12/HumanAct12/``): a folder of ``<name>.npy`` files, ``[T, 24, 3]`` in the same camera frame,
named like ``P01G01R01F0069T0143A0101``: subject after ``P``, action after the first ``A``, whose first two
digits are the coarse class (01..12). Action2Motion numbers the sorted distinct labels it finds; with all 12
present that is ``int(label) - 1``, which is used here so that a partial folder keeps the same indices.
Only ``*.npy`` files are read (ODMO keeps a ``.csv`` beside them), in sorted order.

Frame: joints go through :func:`~jaxmotion.geometry.kinematics.humanact12_to_library_frame` (the 180-degree
turn about X), and the global orientation is left-multiplied by the same matrix, so that forward kinematics
of the rotations matches the joints up to bone lengths. Translation is the converted joint-0 position (the
pickle has no separate translation); joints keep it.

Frame rate: not documented by HumanAct12, Action2Motion or ACTOR (clips are treated as frame sequences);
20 fps is used, the rate at which both ACTOR (``--fps 20``, ``src/parser/visualize.py``) and
Action2Motion (50 ms per frame, ``utils/plot_script.py``) play the clips back.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from jaxmotion.data.formats._common import (
    CAMERA_TO_LIBRARY,
    camera_points_to_library,
    check_array,
    check_label,
    check_split,
    field,
    read_npy,
    read_pickle,
    rotate_roots,
)
from jaxmotion.data.motion import Motion, MotionDataset, pack
from jaxmotion.geometry.skeletons import SMPL24

#: The 12 coarse classes, in label order (ACTOR's ``humanact12_coarse_action_enumerator``).
CLASS_NAMES = (
    "warm_up", "walk", "run", "jump", "drink", "lift_dumbbell", "sit", "eat", "turn steering wheel", "phone",
    "boxing", "throw",
)
FPS = 20.0
POSES_FILE = "humanact12poses.pkl"
_SPLITS = ("train", "all")
_NO_TEST = "HumanAct12 has no test split: every clip is train"


def load_humanact12poses(path_or_root: str | Path, split: str = "all") -> MotionDataset:
    """ACTOR's HumanAct12Poses: ``humanact12poses.pkl``, or the folder holding it (ACTOR's
    ``data/HumanAct12Poses``). ``split``: ``"train"`` or ``"all"`` (the same clips)."""
    check_split(split, _SPLITS, "humanact12", _NO_TEST)
    path = Path(path_or_root)
    path = path / POSES_FILE if path.is_dir() else path
    data = read_pickle(path, "HumanAct12Poses pickle (ACTOR's humanact12poses.pkl)")
    if not isinstance(data, dict):
        raise ValueError(f"{path}: expected a dict with keys poses, joints3D, y; got {type(data).__name__}")
    poses = field(data, "poses", file=path, sequence=True)
    joints3d = field(data, "joints3D", file=path, length=len(poses))
    labels = field(data, "y", file=path, length=len(poses))

    clip_poses, clip_joints, actions = [], [], []
    for i in range(len(poses)):
        pose = check_array(poses[i], ("T", 72), file=path, key=f"poses[{i}]")
        frames = pose.shape[0]
        clip_poses.append(pose.reshape(frames, 24, 3))
        clip_joints.append(check_array(joints3d[i], (frames, 24, 3), file=path, key=f"joints3D[{i}]"))
        actions.append(check_label(labels[i], len(CLASS_NAMES), file=path, key=f"y[{i}]"))

    # One rotation pass over all frames; the split points are the clip boundaries.
    flat = np.concatenate(clip_poses) if clip_poses else np.zeros((0, 24, 3))
    turned = rotate_roots(flat, np.broadcast_to(CAMERA_TO_LIBRARY, (len(flat), 3, 3)))
    rotations = np.split(turned, np.cumsum([len(p) for p in clip_poses])[:-1])
    motions = [
        Motion(joints=joints, translation=joints[:, 0], rotations=rot, action=actions[i], name=f"{POSES_FILE}#{i}")
        for i, (rot, joints) in enumerate(zip(rotations, camera_points_to_library(clip_joints)))
    ]
    return pack(motions, name="humanact12", split=split, class_names=CLASS_NAMES, skeleton=SMPL24, fps=FPS)


_JOINTS_NAME = re.compile(r"(?:P(?P<subject>\d+))?[^A]*A(?P<coarse>\d\d)")


def load_humanact12_joints(root: str | Path, split: str = "all") -> MotionDataset:
    """Action2Motion's / ODMO's HumanAct12 joints: the folder of ``*.npy`` clips (rotations ``None``).
    ``split``: ``"train"`` or ``"all"`` (the same clips)."""
    check_split(split, _SPLITS, "humanact12-joints", _NO_TEST)
    root = Path(root)
    if not root.is_dir():
        raise FileNotFoundError(f"{root}: HumanAct12 joints folder (Action2Motion's *.npy clips) not found")
    files = sorted(root.glob("*.npy"))
    if not files:
        raise FileNotFoundError(f"{root}: no HumanAct12 joint clips (*.npy) in this folder")
    clips, actions, subjects = [], [], []
    for path in files:
        match = _JOINTS_NAME.match(path.stem)
        if match is None:
            raise ValueError(f"{path}: file name: expected HumanAct12's P..A<class>... pattern, e.g. "
                             f"P01G01R01F0069T0143A0101, got {path.stem!r}")
        actions.append(check_label(int(match["coarse"]) - 1, len(CLASS_NAMES), file=path,
                                   key=f"file name: coarse class {match['coarse']} after 'A', minus 1"))
        subjects.append(int(match["subject"]) if match["subject"] else -1)
        clips.append(check_array(read_npy(path, "HumanAct12 joint clip"), ("T", 24, 3), file=path, key="joints"))
    motions = [
        Motion(joints=joints, translation=joints[:, 0], rotations=None, action=action, subject=subject,
               name=path.stem)
        for joints, action, subject, path in zip(camera_points_to_library(clips), actions, subjects, files)
    ]
    return pack(motions, name="humanact12-joints", split=split, class_names=CLASS_NAMES, skeleton=SMPL24,
                fps=FPS)
