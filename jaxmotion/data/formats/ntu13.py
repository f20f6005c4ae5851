"""NTU-13, Action2Motion's VIBE re-estimation of 13 NTU RGB+D actions (no longer distributed).

Layout of the dataset folder (ACTOR's ``data/ntu13``; Action2Motion ``dataProcessing/dataset.py``
``MotionFolderDatasetNtuVIBE``, ACTOR ``src/datasets/ntu13.py``):

  * ``ntu_vibe_list.txt``: one VIBE output file per line, relative to the folder, named after the NTU clip
    (``SsssCcccPpppRrrrAaaa.pkl``);
  * each listed file: VIBE's output as saved by joblib, a dict keyed by track id; track ``1`` holds
    ``pose`` ``[T, 72]`` SMPL axis-angle and ``joints3d`` ``[T, 49, 3]`` VIBE joints.

The action is the number after the first ``A`` of the file name, up to the extension (ACTOR and
Action2Motion read it from the listed path; the file name is used here, the same for paths whose folders have
no ``A``); it must be one of :data:`NTU_ACTIONS`, whose order gives labels 0..12. The subject is the ``P``
field when the name has one, else ``-1``. Both codes use the same clips for training and testing, so the
``train``, ``test`` and ``all`` splits are identical.

Files without a track 1 carrying the needed keys are skipped, as the authors' code does (Action2Motion needs
``joints3d``, ACTOR also ``pose``); a warning reports them.

joblib is not a dependency: a listed file is read with joblib when it is installed, and with ``pickle``
otherwise, which works for plain pickles; joblib's own containers (compressed, or with arrays stored
outside the pickle stream) raise ``ImportError`` asking for ``pip install joblib``.

Two views of the same clips, since a ``MotionDataset`` has one skeleton for joints and rotations:
  * :func:`load_ntu13` (``"ntu13"``): Action2Motion's 18 joints (:data:`VIBE18_INDICES` into the 49, the
    ``UESTC18``/VIBE-18 layout), ``rotations=None``: what the Action2Motion NTU classifier reads.
  * :func:`load_ntu13_smpl` (``"ntu13-smpl"``): ACTOR's input, the SMPL rotations on ``SMPL24``, joints by
    forward kinematics of the project template from the translation (joint 0 of the 18 joints, MidHip,
    as ACTOR takes it).

Frame: VIBE's camera frame (y down, the subject facing -Z; Action2Motion's ``vibe_raw_offsets`` put the neck
at -y from the hips and ACTOR's ``src/visualize/anim.py`` negates y and z before plotting) is turned into the
library frame by the 180-degree turn about X, on joints and on the global orientation. VIBE's joints are
body-centred, so there is no camera translation: translation is joint 0's motion. Frame rate: NTU's 30 fps.
"""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np

from jaxmotion.data.formats._common import (
    CAMERA_TO_LIBRARY,
    camera_points_to_library,
    check_array,
    check_split,
    check_unique,
    read_lines,
    read_pickle,
    require_file,
    smpl_clips_to_library,
)
from jaxmotion.data.motion import Motion, MotionDataset, pack
from jaxmotion.geometry.skeletons import SMPL24, UESTC18

#: NTU action ids of the 13 classes, in label order.
NTU_ACTIONS = (6, 7, 8, 9, 22, 23, 24, 38, 80, 93, 99, 100, 102)
CLASS_NAMES = (
    "pickup", "throw", "sitting down", "standing up (from sitting position)", "cheer up", "hand waving",
    "kicking something", "salute", "squat down", "shake fist", "running on the spot", "butt kicks (kick backward)",
    "side kick",
)
#: VIBE joint of each of Action2Motion's 18 joints (MidHip first, Nose at 8).
VIBE18_INDICES = (8, 1, 2, 3, 4, 5, 6, 7, 0, 9, 10, 11, 12, 13, 14, 21, 24, 38)
LIST_FILE = "ntu_vibe_list.txt"
FPS = 30.0
_TRACK = 1
_SPLITS = ("train", "test", "all")
# First bytes of joblib's compressed containers (zlib, gzip, bz2, xz, lz4, and joblib's old "ZF" format).
_COMPRESSED = (b"\x78", b"\x1f\x8b", b"BZh", b"\xfd7zXZ", b"\x04\x22\x4d\x18", b"ZF")
_SUBJECT = re.compile(r"P(\d+)")


def _read_vibe_output(path: Path) -> object:
    what = "VIBE output (a file listed in ntu_vibe_list.txt)"
    try:
        import joblib  # optional: only joblib reads its own containers
    except ImportError:
        joblib = None
    if joblib is None:
        with require_file(path, what).open("rb") as f:
            if f.read(6).startswith(_COMPRESSED):
                raise ImportError(f"{path}: {what} is a compressed joblib file; reading it needs joblib: "
                                  "pip install joblib")
        return read_pickle(path, what)
    require_file(path, what)
    try:
        return joblib.load(path)
    except Exception as err:  # joblib raises many kinds on a corrupt file
        raise ValueError(f"{path}: cannot unpickle {what} with joblib (truncated or corrupt?): {err!r}") from err


def _action_label(path: Path) -> int:
    stem = path.stem
    start = stem.find("A")
    try:
        action = int(stem[start + 1:]) if start >= 0 else None
    except ValueError:
        action = None
    if action not in NTU_ACTIONS:
        raise ValueError(f"{path}: file name: expected the NTU action after 'A' to be one of {NTU_ACTIONS}, "
                         f"got {stem[start + 1:] if start >= 0 else 'no A'!r}")
    return NTU_ACTIONS.index(action)


def _read_clips(root: Path, keys: tuple[str, ...]) -> list[tuple[Path, int, int, dict[str, np.ndarray]]]:
    """``(file, label, subject, {key: array})`` of every listed file whose track 1 has ``keys``, in list order."""
    list_path = root / LIST_FILE
    entries = read_lines(list_path, "NTU-13 file list")
    check_unique(entries, [f"line {n}" for n in range(1, len(entries) + 1)], file=list_path, what="file")
    clips, skipped = [], []
    for line, entry in enumerate(entries, start=1):
        if not entry:
            raise ValueError(f"{list_path}: line {line}: expected a file name, got a blank line")
        path = root / entry
        output = _read_vibe_output(path)
        if not isinstance(output, dict):
            raise ValueError(f"{path}: expected VIBE's dict of tracks keyed by track id, got {type(output).__name__}")
        track = output.get(_TRACK)
        if track is not None and not isinstance(track, dict):
            raise ValueError(f"{path}: [{_TRACK}]: expected a dict of VIBE arrays, got {type(track).__name__}")
        if track is None or not all(key in track for key in keys):
            skipped.append(entry)
            continue
        joints3d = check_array(track["joints3d"], ("T", 49, 3), file=path, key=f"[{_TRACK}]['joints3d']")
        arrays = {"joints3d": joints3d}
        if "pose" in keys:
            arrays["pose"] = check_array(track["pose"], (len(joints3d), 72), file=path, key=f"[{_TRACK}]['pose']")
        subject = _SUBJECT.search(path.stem)
        clips.append((path, _action_label(path), int(subject[1]) if subject else -1, arrays))
    if skipped:
        warnings.warn(f"{list_path}: skipped {len(skipped)} of {len(entries)} files without a track {_TRACK} "
                      f"holding {', '.join(keys)} (as the authors' code does): {skipped[:5]}", stacklevel=3)
    return clips


def load_ntu13(root: str | Path, split: str = "train") -> MotionDataset:
    """NTU-13 as Action2Motion's 18 VIBE joints (``rotations=None``). ``root``: the folder holding
    ``ntu_vibe_list.txt``; ``split``: ``"train"``, ``"test"`` or ``"all"`` (the same clips)."""
    check_split(split, _SPLITS, "ntu13")
    clips = _read_clips(Path(root), ("joints3d",))
    # VIBE's camera frame is the one HumanAct12 uses.
    joints = camera_points_to_library([arrays["joints3d"][:, VIBE18_INDICES] for _, _, _, arrays in clips])
    motions = [
        Motion(joints=j, translation=j[:, 0], rotations=None, action=label, subject=subject, name=path.stem)
        for (path, label, subject, _), j in zip(clips, joints)
    ]
    return pack(motions, name="ntu13", split=split, class_names=CLASS_NAMES, skeleton=UESTC18, fps=FPS)


def load_ntu13_smpl(root: str | Path, split: str = "train") -> MotionDataset:
    """NTU-13 as ACTOR reads it: SMPL rotations, template joints. Arguments as :func:`load_ntu13`."""
    check_split(split, _SPLITS, "ntu13-smpl")
    clips = _read_clips(Path(root), ("pose", "joints3d"))
    rotations, joints = smpl_clips_to_library(
        [arrays["pose"].reshape(-1, 24, 3) for _, _, _, arrays in clips],
        [CAMERA_TO_LIBRARY] * len(clips),
        [arrays["joints3d"][:, VIBE18_INDICES[0]] @ CAMERA_TO_LIBRARY.T for _, _, _, arrays in clips],
    )
    motions = [
        Motion(joints=j, translation=j[:, 0], rotations=r, action=label, subject=subject, name=path.stem)
        for (path, label, subject, _), r, j in zip(clips, rotations, joints)
    ]
    return pack(motions, name="ntu13-smpl", split=split, class_names=CLASS_NAMES, skeleton=SMPL24, fps=FPS)
