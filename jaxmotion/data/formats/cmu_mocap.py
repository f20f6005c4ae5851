"""CMU motion capture as Action2Motion prepared it: 20 joint positions per frame (no rotations).

Layout of the dataset folder (Action2Motion ``dataProcessing/dataset.py`` ``MotionFolderDatasetMocap``;
ODMO ``src/param/param_mocap.py``, ``dataset/mocap``):

  * ``mocap_3djoints/<motion>.npy``: ``[T, 20, 3]`` joint positions, the ``CMU_MOCAP20`` layout;
  * ``pose_clip.csv``: columns ``motion`` (the ``.npy`` name without extension) and ``action_type`` (a class
    name); rows whose fields are all empty are ignored (Action2Motion reads it with pandas and drops them);
  * ``pose_clip_7class.csv``: ODMO's 7-class list, the same without the Wash clips.

Classes: the 8 of :data:`CLASS_NAMES` in Action2Motion's order (its released ``label_enc_rev_mocap.txt``;
Action2Motion numbers the names in order of first appearance in the CSV, which gives this order on the full
file, fixed here so that any subset keeps the same indices); ODMO's 7 of :data:`CLASS_NAMES_7` drop Wash
(``mocap_class_names`` in ``src/param/data_params.py``). A name outside the list is an error (ODMO's
encoder would silently make it class 0). Subjects come from CMU's ``<subject>_<trial>`` motion names
(``-1`` otherwise). Both codes train on every listed clip: ``train`` and ``all`` are the same clips, and
there is no test split.

Scale and frame: coordinates are divided by 20, as both codes do (:data:`SCALE`: 0.05 m per unit, against
the 0.0564 m of CMU's ASF length unit, so if the files hold ASF units bodies come out about 11% small;
unverified). The data is already y up: Action2Motion's ``mocap_raw_offsets`` point the spine at +y and the
legs at -y, ODMO plots it with y from -1 to 3, and both plot it with the opposite azimuth to their y-down
HumanAct12/VIBE data; so no axis is changed. Heading is the capture's own (neither code turns clips to face
+Z). Translation is joint 0 (hips); joints keep it. Frame rate: 12 fps (the 120 Hz captures downsampled,
Action2Motion's project page).
"""

from __future__ import annotations

import csv
import re
from pathlib import Path

from jaxmotion.data.formats._common import check_array, check_split, check_unique, read_npy, require_file
from jaxmotion.data.motion import Motion, MotionDataset, pack
from jaxmotion.geometry.skeletons import CMU_MOCAP20

CLASS_NAMES = ("Walk", "Wash", "Run", "Jump", "Animal Behavior", "Dance", "Step", "Climb")
CLASS_NAMES_7 = tuple(name for name in CLASS_NAMES if name != "Wash")
SCALE = 1.0 / 20.0
FPS = 12.0
JOINTS_DIR = "mocap_3djoints"
CLIPS_CSV = "pose_clip.csv"
CLIPS_CSV_7 = "pose_clip_7class.csv"
_COLUMNS = ("motion", "action_type")
_SUBJECT = re.compile(r"(\d+)_\d+")


def _read_clip_table(path: Path) -> list[tuple[int, str, str]]:
    """``(row number, motion, action_type)`` of each non-empty CSV row, in file order."""
    with require_file(path, "CMU mocap clip list (CSV with columns motion, action_type)").open(
            newline="", encoding="utf-8") as f:
        reader = csv.DictReader(f)
        missing = [c for c in _COLUMNS if c not in (reader.fieldnames or ())]
        if missing:
            raise ValueError(f"{path}: missing column(s) {missing}; expected columns {list(_COLUMNS)}, "
                             f"got {reader.fieldnames}")
        rows = []
        for number, row in enumerate(reader, start=2):  # row 1 is the header
            if not any(row.values()):
                continue
            values = [row[c] or "" for c in _COLUMNS]
            if not all(values):
                raise ValueError(f"{path}: row {number}: expected a motion and an action_type, got {values}")
            rows.append((number, *values))
    check_unique([motion for _, motion, _ in rows], [f"row {number}" for number, _, _ in rows], file=path,
                 what="motion")
    return rows


def _load(root: str | Path, split: str, csv_name: str, class_names: tuple[str, ...], dataset: str) -> MotionDataset:
    check_split(split, ("train", "all"), dataset, "the CMU mocap set has no test split: every clip is train")
    root = Path(root)
    csv_path = root / csv_name
    motions = []
    for number, motion, action_type in _read_clip_table(csv_path):
        if action_type not in class_names:
            raise ValueError(f"{csv_path}: row {number}: action_type {action_type!r}: expected one of {class_names}")
        path = root / JOINTS_DIR / f"{motion}.npy"
        raw = read_npy(path, f"CMU mocap joint clip (listed in {csv_name}, row {number})")
        joints = (check_array(raw, ("T", 20, 3), file=path, key="joints") * SCALE).astype("float32")
        subject = _SUBJECT.fullmatch(motion)
        motions.append(Motion(joints=joints, translation=joints[:, 0], rotations=None,
                              action=class_names.index(action_type), subject=int(subject[1]) if subject else -1,
                              name=motion))
    return pack(motions, name=dataset, split=split, class_names=class_names, skeleton=CMU_MOCAP20, fps=FPS)


def load_cmu_mocap(root: str | Path, split: str = "train") -> MotionDataset:
    """Action2Motion's 8-class CMU mocap (``pose_clip.csv``). ``root``: the folder holding
    ``mocap_3djoints/`` and the CSV; ``split``: ``"train"`` or ``"all"`` (the same clips)."""
    return _load(root, split, CLIPS_CSV, CLASS_NAMES, "cmu")


def load_cmu_mocap7(root: str | Path, split: str = "train") -> MotionDataset:
    """ODMO's 7-class CMU mocap (``pose_clip_7class.csv``, no Wash). Arguments as :func:`load_cmu_mocap`."""
    return _load(root, split, CLIPS_CSV_7, CLASS_NAMES_7, "cmu7")
