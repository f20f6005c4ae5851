"""UESTC RGB-D varying-view actions as ACTOR prepared them: VIBE SMPL estimates (ACTOR ``src/datasets/uestc.py``).

Layout of the dataset folder (ACTOR's ``data/uestc``):

  * ``info/names.txt``: one video per line, ``a{action}_d{view}_p{subject:03d}_c{side}_color.avi``
    (25,600 lines); line i describes entry i of every per-video list below.
  * ``info/num_frames_min.txt``: one integer per line, the usable frame count of each video.
  * ``info/action_classes.txt`` (optional): the 40 class names, one per line, in label order. Without it,
    the names of ODMO's ``src/param/data_params.py`` ``uestc_class_names`` are used (not verified against
    ACTOR's file).
  * ``vibe_cache_refined.pkl``: a dict of per-video lists; read here: ``pose`` ``[T, 72]`` SMPL axis-angle and
    ``joints3d`` ``[T, 49, 3]`` VIBE joints (``orig_cam``, ``pred_cam``, ``betas``, ``bboxes``, ``frame_ids``
    are not needed).
  * ``globtrans_usez.pkl``: a list of ``[T, 3]`` camera translations relative to frame 0 (ACTOR computes it
    from ``orig_cam`` when the file is absent; here it is required).

What ACTOR does, and this loader repeats:
  * labels are the ``a`` field (0..39), subjects the ``p`` field (1..118);
  * split by subject: train = the 51 subjects of :data:`TRAIN_SUBJECTS` (from ACTOR's code), test = the rest;
  * a clip has ``min(num_frames_min, T)`` frames: the frames past that are never read;
  * videos with ``side != 1`` and ``view == 8`` are dropped; the other ``side != 1`` videos are turned to the
    front view: global orientation, joints and translation by ``R_y(-view * pi / 4)``;
  * train keeps clips of at least ``min_train_frames`` frames (ACTOR: 3/4 of its 60-frame crops, 45);
    test is not filtered.

Translation is ACTOR's: joint 0 of its 18 VIBE joints (MidHip, VIBE index 8) plus ``globtrans``. Joint positions
are forward kinematics of the SMPL rotations with the project template ``SMPL24.offsets`` from that
translation (no SMPL body model ships with the library), so joints and rotations agree exactly.

Frame: VIBE's camera frame has y down and the subject facing -Z (ACTOR's ``src/visualize/anim.py`` negates y
and z before plotting), so after ACTOR's view rotation the global orientation and translation go through
:data:`~jaxmotion.data.formats._common.CAMERA_TO_LIBRARY`. Frame rate: the Kinect v2 videos' 30 fps (ACTOR does
not resample).
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from jaxmotion.data.formats._common import (
    CAMERA_TO_LIBRARY,
    check_array,
    check_label,
    check_sequence,
    check_split,
    check_unique,
    field,
    read_lines,
    read_pickle,
    require_file,
    smpl_clips_to_library,
)
from jaxmotion.data.formats.ntu13 import VIBE18_INDICES
from jaxmotion.data.motion import Motion, MotionDataset, pack
from jaxmotion.geometry.skeletons import SMPL24

#: ACTOR's 51 training subjects (``_tr_subjects`` in ``src/datasets/uestc.py``); the other 67 of 118 are test.
TRAIN_SUBJECTS = frozenset({
    1, 2, 6, 12, 13, 16, 21, 24, 28, 29, 30, 31, 33, 35, 39, 41, 42, 45, 47, 50, 52, 54, 55, 57, 59, 61, 63, 64,
    67, 69, 70, 71, 73, 77, 81, 84, 86, 87, 88, 90, 91, 93, 96, 99, 102, 103, 104, 107, 108, 112, 113,
})
NUM_SUBJECTS = 118
#: Class names when ``info/action_classes.txt`` is absent (ODMO's ``uestc_class_names``).
CLASS_NAMES = (
    "punching-and-knee-lifting", "marking-time-and-knee-lifting", "jumping-jack", "squatting", "forward-lunging",
    "left-lunging", "left-stretching", "raising-hand-and-jumping", "left-kicking", "rotation-clapping",
    "front-raising", "pulling-chest-expanders", "punching", "wrist-circling", "single-dumbbell-raising",
    "shoulder-raising", "elbow-circling", "dumbbell-one-arm-shoulder-pressing", "arm-circling",
    "dumbbell-shrugging", "pinching-back", "head-anticlockwise-circling", "shoulder-abduction",
    "deltoid-muscle-stretching", "straight-forward-flexion", "spinal-stretching", "dumbbell-side-bend",
    "standing-opposite-elbow-to-knee-crunch", "standing-rotation", "overhead-stretching", "upper-back-stretching",
    "knee-to-chest", "knee-circling", "alternate-knee-lifting", "bent-over-twist", "rope-skipping",
    "standing-toe-touches", "standing-gastrocnemius-calf", "single-leg-lateral-hopping", "high-knees-running",
)
FPS = 30.0
#: ACTOR's training length filter: 3/4 of its 60-frame crops.
MIN_TRAIN_FRAMES = 45
_NAME = re.compile(r"a(?P<action>\d+)_d(?P<view>\d+)_p(?P<subject>\d+)_c(?P<side>\d+)")
_DROPPED_VIEW = 8  # ACTOR skips view 8 of the side != 1 recordings
_TRANS_WHAT = "UESTC translations (globtrans_usez.pkl)"


def _front_view_rotation(view: int, side: int) -> np.ndarray:
    """ACTOR's turn to the front view, in VIBE's camera frame: ``R_y(-view * pi / 4)`` for ``side != 1``."""
    if side == 1:
        return np.eye(3)
    c, s = math.cos(-view * math.pi / 4), math.sin(-view * math.pi / 4)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def _class_names(path: Path) -> tuple[str, ...]:
    if not path.is_file():
        return CLASS_NAMES
    names = tuple(read_lines(path, "UESTC class names"))
    if len(names) != len(CLASS_NAMES) or not all(names):
        raise ValueError(f"{path}: expected {len(CLASS_NAMES)} non-empty class names, one per line, "
                         f"got {len(names)} lines")
    return names


def _frame_counts(path: Path, count: int) -> list[int]:
    lines = read_lines(path, "UESTC per-video frame counts")
    if len(lines) != count:
        raise ValueError(f"{path}: expected {count} lines (one per video of names.txt), got {len(lines)}")
    try:
        counts = [int(line) for line in lines]
    except ValueError as err:
        raise ValueError(f"{path}: expected one integer frame count per line: {err}") from None
    if min(counts, default=0) < 0:
        raise ValueError(f"{path}: frame counts must be >= 0, got {min(counts)}")
    return counts


def load_uestc(root: str | Path, split: str = "train", *, min_train_frames: int = MIN_TRAIN_FRAMES) -> MotionDataset:
    """ACTOR's UESTC (SMPL rotations, template joints, 40 classes). ``root``: the dataset folder (ACTOR's
    ``data/uestc``); ``split``: ``"train"`` or ``"test"`` (cross-subject)."""
    check_split(split, ("train", "test"), "uestc")
    root = Path(root)
    names_path = root / "info" / "names.txt"
    names = read_lines(names_path, "UESTC video names")
    check_unique(names, [f"line {n}" for n in range(1, len(names) + 1)], file=names_path, what="video")
    frame_counts = _frame_counts(root / "info" / "num_frames_min.txt", len(names))
    class_names = _class_names(root / "info" / "action_classes.txt")
    vibe_path = root / "vibe_cache_refined.pkl"
    trans_path = root / "globtrans_usez.pkl"
    require_file(trans_path, _TRANS_WHAT)  # fail before reading the large VIBE pickle
    vibe = read_pickle(vibe_path, "UESTC VIBE estimates (vibe_cache_refined.pkl)")
    poses = field(vibe, "pose", file=vibe_path, length=len(names))
    vibe_joints = field(vibe, "joints3d", file=vibe_path, length=len(names))
    globtrans = check_sequence(read_pickle(trans_path, _TRANS_WHAT), len(names), file=trans_path,
                               key="translation list")

    clip_poses, to_library, translations, records = [], [], [], []
    for index, video in enumerate(names):
        match = _NAME.match(video)
        if match is None:
            raise ValueError(f"{names_path}: line {index + 1}: expected a{{action}}_d{{view}}_p{{subject}}_c{{side}}"
                             f"_color.avi, got {video!r}")
        action, view, subject, side = (int(match[k]) for k in ("action", "view", "subject", "side"))
        if side != 1 and view == _DROPPED_VIEW:
            continue
        if not 1 <= subject <= NUM_SUBJECTS or not (side == 1 or 0 <= view < _DROPPED_VIEW):
            raise ValueError(f"{names_path}: line {index + 1}: {video!r}: expected subject in 1..{NUM_SUBJECTS} "
                             f"and, for side != 1, view in 0..{_DROPPED_VIEW}")
        if (subject in TRAIN_SUBJECTS) != (split == "train"):
            continue
        key = f"[{index}] ({video})"
        pose = check_array(poses[index], ("T", 72), file=vibe_path, key=f"pose{key}")
        frames = pose.shape[0]
        joints = check_array(vibe_joints[index], (frames, 49, 3), file=vibe_path, key=f"joints3d{key}")
        trans = check_array(globtrans[index], (frames, 3), file=trans_path, key=f"globtrans{key}")
        used = min(frame_counts[index], frames)
        if split == "train" and used < min_train_frames:
            continue
        if used == 0:
            raise ValueError(f"{root / 'info' / 'num_frames_min.txt'}: line {index + 1}: test video {video!r} "
                             "has 0 usable frames")
        matrix = CAMERA_TO_LIBRARY @ _front_view_rotation(view, side)
        clip_poses.append(pose[:used].reshape(used, 24, 3))
        to_library.append(matrix)
        translations.append((joints[:used, VIBE18_INDICES[0]] + trans[:used]) @ matrix.T)
        records.append((check_label(action, len(class_names), file=names_path, key=f"line {index + 1}: action"),
                        subject, video))

    rotations, joints = smpl_clips_to_library(clip_poses, to_library, translations)
    motions = [
        Motion(joints=j, translation=t.astype(np.float32), rotations=r, action=action, subject=subject,
               name=video)
        for r, j, t, (action, subject, video) in zip(rotations, joints, translations, records)
    ]
    return pack(motions, name="uestc", split=split, class_names=class_names, skeleton=SMPL24, fps=FPS)
