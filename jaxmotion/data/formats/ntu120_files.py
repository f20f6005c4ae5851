"""NTU RGB+D 120 as ActFormer reads it: the Kinect ``.skeleton`` files, and ActFormer's prepared ``.h5`` files.

**Raw files** (the ``--src_path`` of ActFormer's ``datasets/ntu120/prepare_ntu_data.py``)::

    <data_root>/skeletons/SsssCcccPpppRrrrAaaa.skeleton
    <data_root>/ntu_rgb120_missings.txt    NTU's list of samples with missing skeletons, one name per line

A ``.skeleton`` file is text: a line ``numFrame``; per frame a line ``numBody``; per body a line of 10 values
(``bodyID``, then clipedEdges, handLeftConfidence, handLeftState, handRightConfidence, handRightState,
isResticted, leanX, leanY, trackingState), a line ``numJoint`` (25), and per joint a line of 12 values (x y z,
the Kinect camera-space position in metres; depthX depthY; colorX colorY; orientation W X Y Z; trackingState).
:func:`read_skeleton` reads one, :func:`prepare_skeleton` repeats ActFormer's preparation of it:

  * bodies are told apart by ``bodyID``; the 1 (one-person classes) or 2 (two-person classes) bodies detected in
    the most frames are kept (ties: the one seen first), listed in order of first appearance; a clip with fewer
    bodies is skipped;
  * each kept body's undetected frames are filled by :func:`~jaxmotion.data.formats.ntu120.fill_missing`
    (``rule="code"`` by default: what ActFormer's code does; ``"linear"``: what it means to do);
  * each body is smoothed in time by :func:`~jaxmotion.data.formats.ntu120.gaussian_smooth` (sigma 3).

The loaders keep the smoothed joint positions (absolute, with each performer's own bone lengths); ActFormer's
next step, root minus the clip's mean root and unit limb vectors, is
:func:`~jaxmotion.geometry.representations.skeleton_features`. File names ``SsssCcccPpppRrrrAaaa`` give the
setup, camera, performer (the subject), replication and action. Files named in the missing-skeletons list are
skipped, as are files of the other person count; a clip with too few bodies is skipped with a warning.

**Prepared files** (ActFormer's ``datasets/ntu120`` folder after ``split_train_test.py``)::

    <data_root>/data1p/{xsub,xview}.{train,test}.h5    one-person set
    <data_root>/data2p/{xsub,xview}.{train,test}.h5    two-person set
    <data_root>/ntu_adjacency.h5                       optional: ``avglength``, the average bone lengths

Each key of an ``.h5`` is one clip, float32 ``(3P, 25, T)``: channel ``3p + c`` of person p, joint 0 the root
position minus the mean root over the clip's frames and persons, joint j > 0 the unit vector from its parent
(ActFormer divides by the length + 1e-4). The label is the 3 digits after the key's last ``A``, minus 1
(ActFormer's ``feeder/feeder.py``); the key is the clip's name, with ActFormer's relabelled action field (a
one-person ``A061`` clip is stored as ``A050``). Joints are rebuilt from the root by
:func:`~jaxmotion.geometry.representations.joints_from_limb_vectors` with ``avglength`` of
``ntu_adjacency.h5`` when present, else :data:`NTU_AVGLENGTH` (the same numbers, from ActFormer's file), so
every rebuilt body has the dataset's average proportions. The two-person files also hold a ``<key>-flip`` copy
of each clip with the persons swapped (``split_train_test.py --two_person``): they are kept as stored, as
separate clips.

**Labels**: the one-person set has the 94 actions of
:data:`~jaxmotion.data.formats.ntu120.SINGLE_ACTIONS`, the two-person set the 26 of
:data:`~jaxmotion.data.formats.ntu120.MUTUAL_ACTIONS`, in ActFormer's orders. **Splits**: cross-subject
(``xsub``, the default: train = the 53 performers of
:data:`~jaxmotion.data.formats.ntu120.XSUB_TRAIN_SUBJECTS`) or cross-view (``xview``: train = cameras 2 and 3),
``"train"`` or ``"test"``.

**Frame**: Kinect camera space has y up and z the depth away from the sensor, so a person facing the sensor
faces -Z (with their left at -X). :data:`KINECT_TO_LIBRARY`, the 180-degree turn about Y, ``(x, y, z) ->
(-x, y, -z)``, takes it to the library frame: that person faces +Z, their left at +X, up +Y, in metres.
Positions (raw) and limb vectors (prepared) are turned alike. 30 fps. Skeleton :data:`NTU25`, no rotations,
translation = joint 0.

Reading ``.h5`` files needs h5py, an optional extra: ``pip install -e ".[h5]"``. The helpers :func:`open_h5`,
:func:`read_h5_clips`, :func:`read_avglength` and :func:`limb_clips_to_joints` are shared with the other
ActFormer-data loaders (GTA Combat, BABEL, NTURecon).
"""

from __future__ import annotations

import contextlib
import dataclasses
import re
import warnings
from collections.abc import Iterator
from pathlib import Path
from typing import Literal, NamedTuple

import numpy as np

from jaxmotion.data.formats._common import check_array, check_label, check_split, read_lines, require_file
from jaxmotion.data.formats.ntu120 import (
    FPS,
    MUTUAL_ACTIONS,
    MUTUAL_CLASS_NAMES,
    SINGLE_ACTIONS,
    SINGLE_CLASS_NAMES,
    SMOOTHING_SIGMA,
    XSUB_TRAIN_SUBJECTS,
    GapFill,
    fill_missing,
    gaussian_smooth,
)
from jaxmotion.data.motion import Motion, MotionDataset, pack
from jaxmotion.geometry.representations import joints_from_limb_vectors
from jaxmotion.geometry.skeletons import NTU25, Skeleton

#: Kinect camera space (y up, a person facing the sensor faces -Z) -> library frame: the 180-degree turn about
#: Y, acting on column vectors (``p_library = KINECT_TO_LIBRARY @ p_kinect``).
KINECT_TO_LIBRARY = np.diag([-1.0, 1.0, -1.0])
#: ActFormer's average NTU-25 bone lengths in metres, one per child joint (0 for the root): ``avglength`` of
#: ``datasets/ntu120/ntu_adjacency.h5`` in Szy-Young/ActFormer (commit 0d62a8d), read from that file at full
#: float32 precision (FACTS 1.3 lists them rounded to 4 decimals).
NTU_AVGLENGTH = (
    0.0, 0.28051090240478516, 0.06936009973287582, 0.12543989717960358, 0.15821120142936707,
    0.23542866110801697, 0.22375081479549408, 0.0666295513510704, 0.1579355001449585, 0.23291495442390442,
    0.2226639837026596, 0.06841236352920532, 0.07034452259540558, 0.33721819519996643, 0.3436765670776367,
    0.10623186826705933, 0.07056058943271637, 0.33705782890319824, 0.3437376618385315, 0.10665354132652283,
    0.20882093906402588, 0.05633103847503662, 0.038765739649534225, 0.056338898837566376, 0.03832982853055,
)
#: ActFormer's cross-view training cameras (``split_train_test.py``); the test split is camera 1.
XVIEW_TRAIN_CAMERAS = frozenset({2, 3})
SKELETON_DIR = "skeletons"
MISSING_FILE = "ntu_rgb120_missings.txt"
ADJACENCY_FILE = "ntu_adjacency.h5"
NUM_JOINTS = 25
#: Values per joint line and per body-info line of a ``.skeleton`` file.
JOINT_VALUES, BODY_INFO_VALUES = 12, 10

Benchmark = Literal["xsub", "xview"]
_NAME = re.compile(r"S(\d{3})C(\d{3})P(\d{3})R(\d{3})A(\d{3})")
_SUBJECT = re.compile(r"P(\d{3})")
_H5_HINT = 'pip install -e ".[h5]"'


# --- h5 helpers shared by the ActFormer-data loaders ------------------------------------------------------


def require_h5py():
    """The ``h5py`` module, imported on first use; an ``ImportError`` saying how to install it if it is absent."""
    try:
        import h5py
    except ImportError as err:
        raise ImportError(f"reading ActFormer's .h5 dataset files needs h5py, an optional extra: {_H5_HINT} "
                          "(or pip install h5py)") from err
    return h5py


@contextlib.contextmanager
def open_h5(path: Path, what: str) -> Iterator[object]:
    """``path`` opened read-only with h5py; a missing file is a ``FileNotFoundError``, one that is not HDF5
    (truncated, corrupt) a ``ValueError``, both naming it and ``what`` it should hold."""
    h5py = require_h5py()
    require_file(path, what)
    try:
        handle = h5py.File(path, "r")
    except OSError as err:
        raise ValueError(f"{path}: cannot read {what} as HDF5 (truncated or corrupt?): {err}") from err
    with handle:
        yield handle


def read_h5_clips(path: Path, what: str, shape: tuple[int, int]) -> list[tuple[str, np.ndarray]]:
    """Every key of an ActFormer ``.h5`` file as ``(key, float64 [C, V, T])``, in the file's key order (the
    order ActFormer's feeder reads); each must be a finite numeric dataset of ``shape`` ``(C, V)`` and T >= 1
    frames, else a ``ValueError`` naming the file and the key."""
    h5py = require_h5py()
    clips = []
    with open_h5(path, what) as f:
        for key in f.keys():
            item = f[key]
            if not isinstance(item, h5py.Dataset):
                raise ValueError(f"{path}: {key!r}: expected a dataset of shape [{shape[0]}, {shape[1]}, T], "
                                 f"got a {type(item).__name__}")
            clips.append((key, check_array(item[()], (*shape, "T"), file=path, key=repr(key))))
    return clips


def read_avglength(path: Path, skeleton: Skeleton, what: str) -> np.ndarray:
    """``avglength`` ``[J]`` of an ActFormer adjacency file (``ntu_adjacency.h5``, ``gta_adjacency.h5``), as
    float64. When the file also has ``parent`` (``[p, c] = 1``, the root its own parent), its tree must be
    ``skeleton``'s; a missing key, a wrong shape, a negative length or another tree is a ``ValueError``."""
    j = skeleton.num_joints
    with open_h5(path, what) as f:
        if "avglength" not in f:
            raise ValueError(f"{path}: missing key 'avglength' (found: {sorted(f.keys())})")
        lengths = check_array(f["avglength"][()], (j,), file=path, key="'avglength'")
        parent = check_array(f["parent"][()], (j, j), file=path, key="'parent'") if "parent" in f else None
    if np.any(lengths[1:] <= 0):
        child = 1 + int(np.flatnonzero(lengths[1:] <= 0)[0])
        raise ValueError(f"{path}: 'avglength': expected a positive bone length for every joint but the root, got "
                         f"{lengths[child]} at joint {child} ({skeleton.joint_names[child]})")
    if parent is not None:
        for child in range(1, j):
            found = [p for p in np.flatnonzero(parent[:, child] == 1) if p != child]
            if found != [skeleton.parents[child]]:
                raise ValueError(f"{path}: 'parent': joint {child}: expected parent {skeleton.parents[child]} "
                                 f"(the {skeleton.name} tree), got {found}")
    return lengths


# A prepared limb vector is d / (|d| + 1e-4): its norm is 1 within 0.05 for every bone of 2 mm or more.
_UNIT_TOLERANCE = 0.05


def _check_unit_limbs(vectors: np.ndarray, key: str, skeleton: Skeleton, file: Path) -> None:
    """``vectors [P, T, J, 3]``: joint 0 the root position, the others unit limb vectors, else a ``ValueError``
    naming the file, the clip and the first bad vector (a zero or a long vector builds no skeleton)."""
    norms = np.linalg.norm(vectors[..., 1:, :], axis=-1)
    bad = np.abs(norms - 1) > _UNIT_TOLERANCE
    if bad.any():
        person, frame, limb = (int(i) for i in np.argwhere(bad)[0])
        raise ValueError(
            f"{file}: {key!r}: {int(bad.sum())} limb vectors are not unit vectors; the first, person {person}, "
            f"frame {frame}, joint {limb + 1} ({skeleton.joint_names[limb + 1]}), has norm "
            f"{norms[person, frame, limb]:.4g}: expected ActFormer's prepared (x_c - x_parent) / (|x_c - x_parent| "
            f"+ 1e-4), of norm 1 within {_UNIT_TOLERANCE} (a bone of 2 mm or more)")


def limb_clips_to_joints(clips: list[tuple[str, np.ndarray]], skeleton: Skeleton, lengths: np.ndarray,
                         to_library: np.ndarray, *, file: Path) -> list[np.ndarray]:
    """Per clip ``(key, [P, T, J, 3])``, root + unit limb vectors in the source frame, checked -> ``[P, T, J, 3]``
    float32 library-frame joints, rebuilt with ``lengths`` ``[J]``; every frame in one call (one compiled
    shape). ``file``, the clips' file, names it in errors."""
    if not clips:
        return []
    for key, vectors in clips:
        _check_unit_limbs(vectors, key, skeleton, file)
    vectors = np.concatenate([v for _, v in clips], axis=1) @ np.asarray(to_library).T  # [P, F, J, 3]
    joints = np.asarray(joints_from_limb_vectors(vectors.astype(np.float32), skeleton.parents,
                                                 lengths.astype(np.float32)))
    return np.split(joints, np.cumsum([v.shape[1] for _, v in clips])[:-1], axis=1)


def actformer_label(key: str, num_classes: int, *, file: Path) -> int:
    """ActFormer's label of an h5 key: the 3 digits after its last ``A``, minus 1 (``feeder/feeder.py``)."""
    at = key.rfind("A")
    digits = key[at + 1:at + 4] if at >= 0 else ""
    if len(digits) != 3 or not digits.isdigit():
        raise ValueError(f"{file}: key {key!r}: expected 'A' and 3 digits (the class id, from 001) in the key, "
                         f"got {digits or 'no A'!r}")
    return check_label(int(digits) - 1, num_classes, file=file, key=f"key {key!r}: class id {digits} minus 1")


def key_subject(key: str) -> int:
    """The performer (``P`` field) of an NTU clip name, ``-1`` when it has none."""
    match = _SUBJECT.search(key)
    return int(match[1]) if match else -1


# --- the .skeleton files ------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True, eq=False)
class SkeletonBody:
    """One ``bodyID`` of a ``.skeleton`` file.

    Attributes:
      body_id: the ``bodyID`` as written (a large integer, kept as text).
      frames: ``[n]`` int64 increasing indices of the frames the body is detected in.
      joints: ``[n, 25, 12]`` float64 the joint lines of those frames (x y z first).
      info: ``[n, 9]`` float64 the body-info values after ``bodyID``.
    """

    body_id: str
    frames: np.ndarray
    joints: np.ndarray
    info: np.ndarray

    @property
    def xyz(self) -> np.ndarray:
        """``[n, 25, 3]`` camera-space positions, metres."""
        return self.joints[..., :3]


@dataclasses.dataclass(frozen=True, eq=False)
class SkeletonFile:
    """A ``.skeleton`` file: its ``num_frames`` and its bodies, in order of first appearance."""

    path: Path
    num_frames: int
    bodies: tuple[SkeletonBody, ...]


class _Cursor:
    """Lines of a ``.skeleton`` file read in order; every error names the file, the line and the field."""

    def __init__(self, path: Path, lines: list[str]):
        self.path, self.lines, self.at = path, lines, 0

    def _where(self, offset: int = 0) -> str:
        return f"{self.path}: line {self.at + 1 + offset}"

    def _need(self, count: int, field: str) -> None:
        if self.at + count > len(self.lines):
            raise ValueError(f"{self._where()}: {field}: expected {count} more line(s), got the end of the file "
                             "(truncated?)")

    def integer(self, field: str, low: int = 0) -> int:
        self._need(1, field)
        text = self.lines[self.at].strip()
        try:
            value = int(text)
        except ValueError:
            value = None
        if value is None or value < low:
            raise ValueError(f"{self._where()}: {field}: expected an integer >= {low}, got {text!r}")
        self.at += 1
        return value

    def values(self, count: int, field: str) -> list[str]:
        self._need(1, field)
        values = self.lines[self.at].split()
        if len(values) != count:
            raise ValueError(f"{self._where()}: {field}: expected {count} values, got {len(values)}")
        self.at += 1
        return values

    def floats(self, rows: int, count: int, field: str) -> np.ndarray:
        self._need(rows, field)
        split = [line.split() for line in self.lines[self.at:self.at + rows]]
        for k, values in enumerate(split):
            if len(values) != count:
                raise ValueError(f"{self._where(k)}: {field} (line {k + 1} of {rows}): expected {count} values, "
                                 f"got {len(values)}")
        try:
            array = np.array(split, dtype=np.float64)
        except ValueError as err:
            raise ValueError(f"{self._where()}: {field}: expected numbers: {err}") from None
        self.at += rows
        return array


def read_skeleton(path: str | Path) -> SkeletonFile:
    """Read one NTU RGB+D ``.skeleton`` file (layout in the module docstring).

    A truncated or malformed file is a ``ValueError`` naming the file, the line and the field (``numFrame``,
    ``numBody``, ``body info``, ``numJoint``, ``joints``) with what was expected and what was found. A body
    listed twice in one frame keeps its last entry.
    """
    path = Path(path)
    require_file(path, "NTU skeleton file")
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except UnicodeDecodeError as err:
        raise ValueError(f"{path}: cannot read the NTU skeleton file as text (corrupt?): {err}") from None
    while lines and not lines[-1].strip():
        lines.pop()
    cursor = _Cursor(path, lines)
    num_frames = cursor.integer("numFrame")
    seen: dict[str, dict[int, tuple[np.ndarray, np.ndarray]]] = {}  # bodyID -> frame -> (joints, info)
    for t in range(num_frames):
        for b in range(cursor.integer(f"numBody of frame {t}")):
            where = f"body {b} of frame {t}"
            info = cursor.values(BODY_INFO_VALUES, f"body info of {where}")
            try:
                values = np.array(info[1:], dtype=np.float64)
            except ValueError:
                raise ValueError(f"{cursor._where(-1)}: body info of {where}: expected bodyID and 9 numbers, "
                                 f"got {' '.join(info)!r}") from None
            at = cursor.at
            joints = cursor.integer(f"numJoint of {where}")
            if joints != NUM_JOINTS:
                raise ValueError(f"{path}: line {at + 1}: numJoint of {where}: expected {NUM_JOINTS}, got {joints}")
            xyz = cursor.floats(NUM_JOINTS, JOINT_VALUES, f"joints of {where}")
            seen.setdefault(info[0], {})[t] = (xyz, values)
    if cursor.at != len(lines):
        raise ValueError(f"{cursor._where()}: expected the end of the file after numFrame = {num_frames} frames, "
                         f"got more lines")
    bodies = tuple(
        SkeletonBody(body_id=body_id, frames=np.array(sorted(frames), np.int64),
                     joints=np.stack([frames[t][0] for t in sorted(frames)]),
                     info=np.stack([frames[t][1] for t in sorted(frames)]))
        for body_id, frames in seen.items()
    )
    return SkeletonFile(path=path, num_frames=num_frames, bodies=bodies)


def prepare_skeleton(skeleton: SkeletonFile, bodies: int, rule: GapFill = "code",
                     sigma: float | None = SMOOTHING_SIGMA) -> np.ndarray | None:
    """ActFormer's preparation of one clip (``prepare_ntu_data.py``): ``[P, T, 25, 3]`` float64 camera-space
    joints of the ``bodies`` (P) bodies kept, or ``None`` when the clip has fewer bodies (ActFormer skips it).

    Kept: the ``bodies`` bodies detected in the most frames (ties: the one seen first), in order of first
    appearance. Each is gap-filled by :func:`~jaxmotion.data.formats.ntu120.fill_missing` with ``rule``
    (``"code"``, ActFormer's; ``"linear"``, its intent) and smoothed in time by
    :func:`~jaxmotion.data.formats.ntu120.gaussian_smooth` with ``sigma`` (ActFormer: 3; ``None`` skips the
    smoothing, to inspect the filled frames).
    """
    found = skeleton.bodies
    if len(found) < bodies:
        return None
    # sorted() is stable: among bodies with as many detections, the one seen first ranks first
    keep = sorted(sorted(range(len(found)), key=lambda i: -len(found[i].frames))[:bodies])
    out = []
    for i in keep:
        body = found[i]
        joints = np.zeros((skeleton.num_frames, NUM_JOINTS, 3))
        detected = np.zeros(skeleton.num_frames, bool)
        joints[body.frames], detected[body.frames] = body.xyz, True
        filled = fill_missing(joints, detected, rule)
        out.append(filled if sigma is None else gaussian_smooth(filled, sigma, axis=0))
    return np.stack(out)


class NtuName(NamedTuple):
    """The fields of an NTU clip name ``SsssCcccPpppRrrrAaaa``."""

    setup: int
    camera: int
    performer: int
    replication: int
    action: int


def parse_ntu_name(name: str) -> NtuName | None:
    """``SsssCcccPpppRrrrAaaa`` -> its fields, ``None`` if ``name`` is not such a name."""
    match = _NAME.fullmatch(name)
    return NtuName(*(int(g) for g in match.groups())) if match else None


def in_train_split(name: NtuName, benchmark: Benchmark) -> bool:
    """Whether a clip is in ActFormer's training split: ``xsub`` by performer, ``xview`` by camera."""
    if benchmark == "xsub":
        return name.performer in XSUB_TRAIN_SUBJECTS
    if benchmark == "xview":
        return name.camera in XVIEW_TRAIN_CAMERAS
    raise ValueError(f"benchmark: expected 'xsub' or 'xview', got {benchmark!r}")


def _check_options(persons: int, benchmark: str) -> None:
    if persons not in (1, 2):
        raise ValueError(f"persons: expected 1 (the one-person set) or 2 (the two-person set), got {persons!r}")
    if benchmark not in ("xsub", "xview"):
        raise ValueError(f"benchmark: expected 'xsub' or 'xview', got {benchmark!r}")


def _dataset_name(persons: int, benchmark: str, suffix: str = "") -> str:
    return f"ntu{persons}p{suffix}" + ("" if benchmark == "xsub" else "-xview")


def _to_motions(clips: list[np.ndarray], records: list[tuple[str, int, int]], persons: int) -> list[Motion]:
    """Library-frame ``[P, T, J, 3]`` clips -> records (persons axis dropped for one person)."""
    motions = []
    for joints, (name, label, subject) in zip(clips, records):
        joints = joints[0] if persons == 1 else joints
        motions.append(Motion(joints=joints, translation=joints[..., 0, :], rotations=None, action=label,
                              subject=subject, name=name))
    return motions


def load_ntu_skeletons(root: str | Path, split: str = "train", *, persons: int = 1, benchmark: Benchmark = "xsub",
                       rule: GapFill = "code") -> MotionDataset:
    """NTU RGB+D 120 from the raw ``.skeleton`` files, prepared as ActFormer does (module docstring).

    Args:
      root: the folder holding ``skeletons/`` and ``ntu_rgb120_missings.txt``.
      split: ``"train"`` or ``"test"`` of ``benchmark``.
      persons: 1 (the 94 one-person actions) or 2 (the 26 two-person ones).
      benchmark: ``"xsub"`` (cross-subject) or ``"xview"`` (cross-view).
      rule: the gap-filling rule of :func:`prepare_skeleton`.
    """
    _check_options(persons, benchmark)
    name = _dataset_name(persons, benchmark, "-skeletons")
    check_split(split, ("train", "test"), name)
    root = Path(root)
    folder = root / SKELETON_DIR
    if not folder.is_dir():
        raise FileNotFoundError(f"{folder}: folder of NTU .skeleton files not found")
    missing = {line for line in read_lines(root / MISSING_FILE, "NTU list of samples with missing skeletons")
               if line}
    actions = SINGLE_ACTIONS if persons == 1 else MUTUAL_ACTIONS
    clips, records, skipped = [], [], []
    for path in sorted(folder.glob("*.skeleton")):
        stem = path.name[: -len(".skeleton")]
        fields = parse_ntu_name(stem)
        if fields is None or not 1 <= fields.action <= 120:
            raise ValueError(f"{path}: file name: expected SsssCcccPpppRrrrAaaa.skeleton with an action in "
                             f"A001..A120, got {path.name!r}")
        if fields.action not in actions or stem in missing or in_train_split(fields, benchmark) != (split == "train"):
            continue
        clip = prepare_skeleton(read_skeleton(path), persons, rule)
        if clip is None:
            skipped.append(stem)
            continue
        clips.append(clip @ KINECT_TO_LIBRARY.T)
        records.append((stem, actions.index(fields.action), fields.performer))
    if skipped:
        warnings.warn(f"{folder}: skipped {len(skipped)} clips with fewer than {persons} bodies (as ActFormer "
                      f"does): {skipped[:5]}", stacklevel=2)
    class_names = SINGLE_CLASS_NAMES if persons == 1 else MUTUAL_CLASS_NAMES
    return pack(_to_motions(clips, records, persons), name=name, split=split, class_names=class_names,
                skeleton=NTU25, fps=FPS, persons=persons)


def ntu_bone_lengths(root: Path) -> np.ndarray:
    """``avglength`` of ``root/ntu_adjacency.h5`` when the file is there, else :data:`NTU_AVGLENGTH`."""
    path = root / ADJACENCY_FILE
    if path.is_file():
        return read_avglength(path, NTU25, "ActFormer's NTU skeleton file (ntu_adjacency.h5)")
    return np.array(NTU_AVGLENGTH)


def load_ntu_prepared(root: str | Path, split: str = "train", *, persons: int = 1,
                      benchmark: Benchmark = "xsub") -> MotionDataset:
    """ActFormer's prepared NTU RGB+D 120 (``data{1,2}p/{xsub,xview}.{train,test}.h5``, module docstring).

    Args:
      root: ActFormer's ``datasets/ntu120`` folder (``data1p/``, ``data2p/``, optional ``ntu_adjacency.h5``).
      split: ``"train"`` or ``"test"``.
      persons: 1 (``data1p``, 94 classes) or 2 (``data2p``, 26 classes; ``-flip`` copies kept as stored).
      benchmark: ``"xsub"`` or ``"xview"``: which of ActFormer's files.
    """
    _check_options(persons, benchmark)
    name = _dataset_name(persons, benchmark)
    require_h5py()  # first: without it, say so before anything else
    check_split(split, ("train", "test"), name)
    root = Path(root)
    path = root / f"data{persons}p" / f"{benchmark}.{split}.h5"
    lengths = ntu_bone_lengths(root)
    class_names = SINGLE_CLASS_NAMES if persons == 1 else MUTUAL_CLASS_NAMES
    clips = read_h5_clips(path, f"ActFormer's prepared NTU {persons}P clips", (3 * persons, NUM_JOINTS))
    records = [(key, actformer_label(key, len(class_names), file=path), key_subject(key)) for key, _ in clips]
    # (3P, V, T) -> (P, T, V, 3)
    vectors = [(key, a.reshape(persons, 3, NUM_JOINTS, -1).transpose(0, 3, 2, 1)) for key, a in clips]
    joints = limb_clips_to_joints(vectors, NTU25, lengths, KINECT_TO_LIBRARY, file=path)
    return pack(_to_motions(joints, records, persons), name=name, split=split, class_names=class_names,
                skeleton=NTU25, fps=FPS, persons=persons)


def load_ntu1p(root: str | Path, split: str = "train") -> MotionDataset:
    """``ntu1p``: ActFormer's prepared one-person NTU-120, cross-subject (:func:`load_ntu_prepared`)."""
    return load_ntu_prepared(root, split, persons=1)


def load_ntu2p(root: str | Path, split: str = "train") -> MotionDataset:
    """``ntu2p``: ActFormer's prepared two-person NTU-120, cross-subject (:func:`load_ntu_prepared`)."""
    return load_ntu_prepared(root, split, persons=2)


def load_ntu1p_xview(root: str | Path, split: str = "train") -> MotionDataset:
    """``ntu1p-xview``: ActFormer's prepared one-person NTU-120, cross-view (:func:`load_ntu_prepared`)."""
    return load_ntu_prepared(root, split, persons=1, benchmark="xview")


def load_ntu2p_xview(root: str | Path, split: str = "train") -> MotionDataset:
    """``ntu2p-xview``: ActFormer's prepared two-person NTU-120, cross-view (:func:`load_ntu_prepared`)."""
    return load_ntu_prepared(root, split, persons=2, benchmark="xview")


def load_ntu1p_skeletons(root: str | Path, split: str = "train") -> MotionDataset:
    """``ntu1p-skeletons``: one-person NTU-120 from the ``.skeleton`` files, cross-subject
    (:func:`load_ntu_skeletons`)."""
    return load_ntu_skeletons(root, split, persons=1)


def load_ntu2p_skeletons(root: str | Path, split: str = "train") -> MotionDataset:
    """``ntu2p-skeletons``: two-person NTU-120 from the ``.skeleton`` files, cross-subject
    (:func:`load_ntu_skeletons`)."""
    return load_ntu_skeletons(root, split, persons=2)
