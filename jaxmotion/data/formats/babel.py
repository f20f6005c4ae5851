"""BABEL-120, ActFormer's action segments of AMASS: from the AMASS and BABEL files, and ActFormer's prepared h5.

**Categories.** ActFormer's ``datasets/babel/prepare_data.py`` reads ``datasets/babel/action_label_2_idx.json``,
which its repository does not ship: it is BABEL's own category index (``action_recognition/data/
action_label_2_idx.json`` of BABEL's repository, abhinanda-punnakkal/BABEL), a JSON object from category name
(``act_cat``) to index, 150 categories ordered by frequency. ActFormer keeps the categories of index 0..119 (id =
index + 1 <= 120), so class i is the category of index i. :data:`CATEGORIES` holds those 120 names; a
``action_label_2_idx.json`` under ``data_root`` (or ``label_map=``) is read instead when present.

**Raw files** (:func:`load_babel120_amass`; ActFormer's ``--src_path``)::

    <data_root>/amass/rawdata/<feat_p without its first folder>    AMASS .npz: poses, trans, mocap_framerate
    <data_root>/babel_v1.0_release/{train,val}.json               BABEL annotations
    <data_root>/action_label_2_idx.json                           optional: the category index (or ``label_map=``)

What ActFormer does, and this loader repeats, per BABEL sequence (in the json's order):
  * pose = the SMPL-H ``poses[:, :66]`` (root + 21 body joints) + 6 zeros (SMPL's two hand joints): 24 joints;
  * ``poses`` (still axis-angle, component-wise) and ``trans`` resampled from ``mocap_framerate`` to 30 fps with
    ``scipy.ndimage.zoom`` (cubic), to ``round(T * 30 / fps)`` frames: :func:`resample_cubic`, in numpy;
  * segments: with ``frame_ann``, each label's ``[int(start_t * 30), int(end_t * 30))`` clipped to the
    sequence (empty ones dropped); without, ``seq_ann``'s labels, each the whole sequence. A label with several
    categories gives one segment per category (sorted, duplicates once), named
    ``<seg_id>_l<label index:02d>_A<id:03d>``; labels without categories and categories outside the 120 are
    dropped;
  * each segment's translation is de-meaned over its frames. ActFormer de-means a view of the sequence, in
    place, so a segment overlapping an earlier one starts from that one's de-meaned frames (its translation has
    a step where the earlier segment ended); ``overlap="code"`` (the default) repeats this, ``"independent"``
    de-means each segment from the original translation. Segments that do not overlap are the same either way.

Segments are returned in key order, the order ActFormer's feeder reads its h5, so the two loaders agree.
Splits: ``"train"`` reads ``train.json``; ``"val"`` and ``"test"`` read ``val.json`` (BABEL's test labels are
not public; ActFormer trains its evaluation classifier on ``val120``).

**Resampling** (:func:`resample_cubic`): ``scipy.ndimage.zoom(x, [scale, 1])`` with its defaults (order 3,
``mode="constant"``, ``grid_mode=False``) interpolates each channel with the cubic B-spline through the samples
(its prefilter's boundary is the whole-sample mirror) at positions ``i (n - 1) / (m - 1)``. The numpy version
builds the same spline: the exact prefilter, ``sqrt(3) * z^|k|`` with ``z = sqrt(3) - 2``, truncated at 40 taps
per side (``|z|^40 < 1e-22``) on the mirror-extended samples, then the four cubic B-spline weights. So they
differ by rounding only (the tests compare with scipy to 1e-9). scipy is not a runtime dependency. As in
ActFormer, axis-angle vectors are interpolated component-wise, not as rotations.

**Prepared files** (:func:`load_babel120`; ActFormer's ``datasets/babel`` folder)::

    <data_root>/{train,val}120.h5    (and {train,val}60.h5: the categories of id <= 60)
    <data_root>/action_label_2_idx.json    optional: class names (else :data:`CATEGORIES`)

Each key (``<seg_id>_l<NN>_A<id>``) is float32 ``(6, 25, T)``: joints 0..23 the rot6d rows of the SMPL
rotations (first two rows of each matrix), joint 24 the translation, de-meaned, zero-padded to 6. Label = the
3 digits after the last ``A``, minus 1. Rotations by Gram-Schmidt
(:func:`~jaxmotion.geometry.representations.split_rotation_features`).

**Both**: the raw loader's axis-angle goes through the same rot6d rows (:func:`smpl_features`) and conversion
as the prepared files, so the two loaders agree to float32 rounding. Joints by forward kinematics of the
project SMPL template (``SMPL24.offsets``) rooted at the translation (SMPL's ``trans``, taken as joint 0's
position; no SMPL body model ships with the library).
Frame: AMASS is z-up (ActFormer's ``visualize/visualize_skt_smpl.py`` plots it with z vertical);
:data:`AMASS_TO_LIBRARY`, ``R_x(-90 degrees)`` ``(x, y, z) -> (x, z, -y)``, turns the global orientation and the
translation so that +Z up becomes +Y up. 30 fps; subjects unknown (-1). Reading ``.h5`` needs h5py
(``pip install -e ".[h5]"``); the raw loader does not.
"""

from __future__ import annotations

import json
import zipfile
import zlib
from collections.abc import Iterator
from pathlib import Path
from typing import Literal

import numpy as np

from jaxmotion.data.formats._common import check_array, check_split, check_unique, require_file
from jaxmotion.data.formats.ntu120_files import actformer_label, read_h5_clips, require_h5py
from jaxmotion.data.formats.ntu_recon import SMPL_FEATURE_SHAPE, check_rot6d, smpl_motions
from jaxmotion.data.motion import MotionDataset, pack
from jaxmotion.geometry.skeletons import SMPL24

#: AMASS's z-up frame -> library frame (y up): R_x(-90 degrees), on column vectors.
AMASS_TO_LIBRARY = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])
FPS = 30.0
NUM_CLASSES = 120
LABEL_MAP_FILE = "action_label_2_idx.json"
#: The 120 categories ActFormer keeps, by index (BABEL's action_label_2_idx.json, most frequent first; the
#: list as public BABEL-120 code reproduces it). A user's own label-map file takes precedence.
CATEGORIES = ("walk", "stand", "hand movements", "turn", "interact with/use object", "arm movements", "t pose",
    "step", "backwards movement", "raising body part", "look", "touch object", "leg movements", "forward movement",
    "circular movement", "stretch", "jump", "touching body part", "sit", "place something",
    "take/pick something up", "run", "bend", "throw", "foot movements", "a pose", "stand up", "lowering body part",
    "sideways movement", "move up/down incline", "action with ball", "kick", "gesture", "head movements", "jog",
    "grasp object", "waist movements", "lift something", "knee movement", "wave", "move something",
    "swing body part", "catch", "dance", "lean", "greet", "poses", "touching face", "sports move",
    "exercise/training", "clean something", "punch", "squat", "scratch", "hop", "play sport", "stumble",
    "crossing limbs", "perform", "martial art", "balance", "kneel", "shake", "grab body part", "clap", "crouch",
    "spin", "upper body movements", "knock", "adjust", "crawl", "twist", "move back to original position", "bow",
    "hit", "touch ground", "shoulder movements", "telephone call", "grab person", "play instrument", "tap",
    "spread", "skip", "rolling movement", "jump rope", "play catch", "drink", "evade", "support", "point",
    "side to side movement", "stop", "protect", "wrist movements", "stances", "wait", "shuffle", "lunge",
    "communicate (vocalise)", "jumping jacks", "rub", "dribble", "swim", "sneak", "to lower a body part",
    "misc. abstract action", "mix", "limp", "sway", "slide", "cartwheel", "press something", "shrug",
    "open something", "leap", "trip", "golf", "move misc. body part", "get injured", "sudden movement",
)
AMASS_DIR = Path("amass") / "rawdata"
BABEL_DIR = "babel_v1.0_release"
#: SMPL-H pose values ActFormer keeps (root + 21 body joints), then 6 zeros for SMPL's hands.
BODY_POSE_VALUES = 66
Overlap = Literal["code", "independent"]

_POLE = np.sqrt(3.0) - 2.0
_TAPS = 40


# --- resampling ----------------------------------------------------------------------------------------------


def zoomed_frames(frames: int, scale: float) -> int:
    """The frame count ``scipy.ndimage.zoom`` gives ``frames`` samples scaled by ``scale``: ``round(frames * scale)``
    (Python's rounding)."""
    return int(round(frames * scale))


def _mirror(index: np.ndarray, n: int) -> np.ndarray:
    """Whole-sample mirror of indices into ``[0, n)`` (``-1 -> 1``, ``n -> n - 2``), any distance out."""
    period = 2 * (n - 1)
    index = np.mod(index, period)
    return np.where(index > n - 1, period - index, index)


def resample_cubic(x: np.ndarray, frames: int) -> np.ndarray:
    """``x [n, C]`` -> ``[frames, C]`` float64: the cubic B-spline through the n samples (mirror boundary) at
    ``frames`` evenly spaced positions from the first sample to the last, as ``scipy.ndimage.zoom`` (order 3)
    resamples along axis 0 (module docstring)."""
    x = np.asarray(x, np.float64)
    n = x.shape[0]
    if frames < 0:
        raise ValueError(f"frames: expected >= 0, got {frames}")
    if frames == 0 or n == 0:
        return np.zeros((frames if n else 0, *x.shape[1:]))
    if n == 1:
        return np.repeat(x, frames, axis=0)
    samples = np.arange(n)
    coefficients = sum(np.sqrt(3.0) * _POLE ** abs(k) * x[_mirror(samples + k, n)] for k in range(-_TAPS, _TAPS + 1))
    positions = np.arange(frames) * ((n - 1) / (frames - 1)) if frames > 1 else np.zeros(1)
    positions = np.clip(positions, 0.0, n - 1)
    base = np.floor(positions).astype(np.int64)
    f = (positions - base).reshape(-1, *([1] * (x.ndim - 1)))
    weights = ((1 - f) ** 3 / 6, (4 - 6 * f**2 + 3 * f**3) / 6, (1 + 3 * f + 3 * f**2 - 3 * f**3) / 6, f**3 / 6)
    return sum(w * coefficients[_mirror(base + k - 1, n)] for k, w in enumerate(weights))


def smpl_features(rotations: np.ndarray, translation: np.ndarray) -> np.ndarray:
    """``rotations [T, 24, 3]`` axis-angle, ``translation [T, 3]`` -> ActFormer's ``[T, 25, 6]``: each rotation's
    first two matrix rows (Rodrigues' formula, in numpy), then the translation zero-padded to 6."""
    angle = np.linalg.norm(rotations, axis=-1, keepdims=True)
    axis = rotations / np.where(angle > 0, angle, 1.0)
    x, y, z = axis[..., 0], axis[..., 1], axis[..., 2]
    zero = np.zeros_like(x)
    cross = np.stack([zero, -z, y, z, zero, -x, -y, x, zero], axis=-1).reshape(*x.shape, 3, 3)
    s, c = np.sin(angle)[..., None], np.cos(angle)[..., None]
    matrices = np.eye(3) + s * cross + (1 - c) * (cross @ cross)
    row = np.concatenate([translation, np.zeros_like(translation)], axis=-1)[:, None]
    return np.concatenate([matrices[..., :2, :].reshape(*rotations.shape[:-1], 6), row], axis=1)


# --- the category index ------------------------------------------------------------------------------------------


def _read_json(path: Path, what: str) -> object:
    require_file(path, what)
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (ValueError, UnicodeDecodeError) as err:
        raise ValueError(f"{path}: cannot read {what} as JSON (truncated or corrupt?): {err}") from None


def read_label_map(path: str | Path) -> tuple[dict[str, int], tuple[str, ...]]:
    """BABEL's ``action_label_2_idx.json`` -> ``(category -> index, the names of indices 0..119)``; it must map
    names to distinct integer indices covering 0..119."""
    path = Path(path)
    mapping = _read_json(path, "BABEL category index (action_label_2_idx.json)")
    if not isinstance(mapping, dict):
        raise ValueError(f"{path}: expected a JSON object from category name to index, got {type(mapping).__name__}")
    by_index: dict[int, str] = {}
    for name, index in mapping.items():
        if not isinstance(index, int) or isinstance(index, bool) or index < 0:
            raise ValueError(f"{path}: {name!r}: expected a category index (an integer >= 0), got {index!r}")
        if index in by_index:
            raise ValueError(f"{path}: index {index} is given to both {by_index[index]!r} and {name!r}")
        by_index[index] = name
    missing = [i for i in range(NUM_CLASSES) if i not in by_index]
    if missing:
        raise ValueError(f"{path}: expected the category indices 0..{NUM_CLASSES - 1} (ActFormer keeps those), "
                         f"missing {len(missing)}: {missing[:5]}")
    return dict(mapping), tuple(by_index[i] for i in range(NUM_CLASSES))


def _class_names(root: Path, classes: int) -> tuple[str, ...]:
    path = root / LABEL_MAP_FILE
    names = read_label_map(path)[1] if path.is_file() else CATEGORIES
    return names[:classes]


def _babel_split(split: str, dataset: str) -> str:
    check_split(split, ("train", "val", "test"), dataset, "'test' reads BABEL's val split (its test labels are "
                                                          "not public)")
    return "train" if split == "train" else "val"


# --- prepared h5 -------------------------------------------------------------------------------------------------


def load_babel120(root: str | Path, split: str = "train", *, classes: int = 120) -> MotionDataset:
    """``babel120``: ActFormer's prepared BABEL (``{train,val}120.h5`` under ``root``, ActFormer's
    ``datasets/babel``). ``split``: ``"train"``, ``"val"`` or ``"test"`` (= val); ``classes``: 120, or 60 for
    ActFormer's ``{train,val}60.h5``."""
    if classes not in (120, 60):
        raise ValueError(f"classes: expected 120 or 60 (ActFormer's two BABEL files), got {classes!r}")
    name = f"babel{classes}"
    root = Path(root)
    require_h5py()  # first: without it, say so before anything else
    path = root / f"{_babel_split(split, name)}{classes}.h5"
    class_names = _class_names(root, classes)
    stored = read_h5_clips(path, f"ActFormer's prepared BABEL-{classes} segments", SMPL_FEATURE_SHAPE)
    check_rot6d(stored, file=path)
    keys = [key for key, _ in stored]
    labels = [actformer_label(key, classes, file=path) for key in keys]
    motions = smpl_motions(keys, [np.transpose(a, (2, 1, 0)) for _, a in stored], AMASS_TO_LIBRARY, labels,
                           [-1] * len(keys))
    return pack(motions, name=name, split=split, class_names=class_names, skeleton=SMPL24, fps=FPS)


# --- AMASS + BABEL json ------------------------------------------------------------------------------------------


def _get(container: object, key: str, *, file: Path, where: str) -> object:
    if not isinstance(container, dict) or key not in container:
        found = sorted(container) if isinstance(container, dict) else type(container).__name__
        raise ValueError(f"{file}: {where}: missing key {key!r} (found: {found})")
    return container[key]


def _read_amass(path: Path) -> tuple[np.ndarray, np.ndarray, float]:
    """``(poses [T, 72] SMPL axis-angle, trans [T, 3], mocap_framerate)`` of one AMASS ``.npz``."""
    what = "AMASS motion file (a BABEL sequence's feat_p)"
    require_file(path, what)
    unreadable = (OSError, EOFError, ValueError, zipfile.BadZipFile, zlib.error)
    try:
        data = np.load(path, allow_pickle=False)
    except unreadable as err:
        raise ValueError(f"{path}: cannot read {what} as .npz (truncated or corrupt?): {err}") from err
    if not isinstance(data, np.lib.npyio.NpzFile):
        raise ValueError(f"{path}: expected {what} as an .npz archive of arrays, got a single array")
    with data:
        for key in ("poses", "trans", "mocap_framerate"):
            if key not in data.files:
                raise ValueError(f"{path}: missing key {key!r} (found: {sorted(data.files)})")
        try:
            arrays = {key: data[key] for key in ("poses", "trans", "mocap_framerate")}
        except unreadable as err:
            raise ValueError(f"{path}: cannot read {what} (truncated or corrupt?): {err}") from err
    poses = check_array(arrays["poses"], ("T", "D"), file=path, key="'poses'")
    if poses.shape[1] < BODY_POSE_VALUES:
        raise ValueError(f"{path}: 'poses': expected at least {BODY_POSE_VALUES} values per frame (SMPL-H axis-angle), "
                         f"got {poses.shape[1]}")
    trans = check_array(arrays["trans"], (len(poses), 3), file=path, key="'trans'")
    rate = np.asarray(arrays["mocap_framerate"])
    if rate.size != 1 or not np.issubdtype(rate.dtype, np.number) or not np.isfinite(rate).all() or rate.item() <= 0:
        raise ValueError(f"{path}: 'mocap_framerate': expected one frame rate > 0, got {rate!r}")
    body = np.concatenate([poses[:, :BODY_POSE_VALUES], np.zeros((len(poses), 72 - BODY_POSE_VALUES))], axis=1)
    return body, trans, float(rate.item())


def babel_sequences(json_path: Path, root: Path) -> Iterator[tuple[str, dict, np.ndarray, np.ndarray]]:
    """Each sequence of the BABEL annotations ``json_path`` with its AMASS motion (under ``root``) at 30 fps, in the
    file's order: ``(sid, annotation, poses [T, 24, 3] axis-angle, trans [T, 3])`` in AMASS's frame (module
    docstring)."""
    annotations = _read_json(json_path, "BABEL annotations")
    if not isinstance(annotations, dict):
        raise ValueError(f"{json_path}: expected a JSON object of sequences, got {type(annotations).__name__}")
    for sid, sequence in annotations.items():
        feat_p = _get(sequence, "feat_p", file=json_path, where=f"[{sid!r}]")
        if not isinstance(feat_p, str) or "/" not in feat_p:
            raise ValueError(f"{json_path}: [{sid!r}]['feat_p']: expected a path '<dataset>/...npz', got {feat_p!r}")
        poses, trans, rate = _read_amass(root / AMASS_DIR / feat_p.split("/", 1)[1])
        resampled = resample_cubic(np.concatenate([poses, trans], axis=1), zoomed_frames(len(poses), FPS / rate))
        yield str(sid), sequence, resampled[:, :72].reshape(-1, 24, 3), resampled[:, 72:]


def annotation_labels(annotation: object, *, file: Path, where: str) -> Iterator[tuple[int, str, dict]]:
    """``(index, where, label)`` for each label of a BABEL ``frame_ann`` or ``seq_ann`` (at ``where`` in ``file``)."""
    labels = _get(annotation, "labels", file=file, where=where)
    if not isinstance(labels, list):
        raise ValueError(f"{file}: {where}['labels']: expected a list, got {type(labels).__name__}")
    for index, label in enumerate(labels):
        yield index, f"{where}['labels'][{index}]", label


def label_categories(label: object, *, file: Path, where: str) -> list[str] | None:
    """A label's ``act_cat``: its category names, or None where BABEL gives none."""
    categories = _get(label, "act_cat", file=file, where=where)
    if categories is not None and (not isinstance(categories, list) or not all(isinstance(c, str)
                                                                                  for c in categories)):
        raise ValueError(f"{file}: {where}['act_cat']: expected a list of category names, got {categories!r}")
    return categories


def babel_segments(sequence: dict, frames: int, label_map: dict[str, int], *, file: Path,
                   sid: str) -> list[tuple[str, int, int, int]]:
    """ActFormer's segments of one BABEL sequence of ``frames`` frames at 30 fps: ``(key, label, start, end)``
    in the order ActFormer writes them (module docstring)."""
    frame_ann = _get(sequence, "frame_ann", file=file, where=f"[{sid!r}]")
    level, annotation = ("frame_ann", frame_ann) if frame_ann is not None else (
        "seq_ann", _get(sequence, "seq_ann", file=file, where=f"[{sid!r}]"))
    segments = []
    for index, where, label in annotation_labels(annotation, file=file, where=f"[{sid!r}][{level!r}]"):
        categories = label_categories(label, file=file, where=where)
        if categories is None:
            continue
        for category in sorted(set(categories)):
            if category not in label_map or label_map[category] >= NUM_CLASSES:
                continue
            seg_id = _get(label, "seg_id", file=file, where=where)
            if not isinstance(seg_id, str):
                raise ValueError(f"{file}: {where}['seg_id']: expected a segment id (text), got {seg_id!r}")
            key = f"{seg_id}_l{index:02d}_A{label_map[category] + 1:03d}"
            start, end = 0, frames
            if level == "frame_ann":
                times = [_get(label, k, file=file, where=where) for k in ("start_t", "end_t")]
                if not all(isinstance(t, (int, float)) and not isinstance(t, bool) for t in times):
                    raise ValueError(f"{file}: {where}: expected numbers start_t and end_t (seconds), got {times}")
                start, end = max(0, int(times[0] * FPS)), min(frames, int(times[1] * FPS))
            if end - start >= 1:
                segments.append((key, label_map[category], start, end))
    return segments


def load_babel120_amass(root: str | Path, split: str = "train", *, label_map: str | Path | None = None,
                        overlap: Overlap = "code") -> MotionDataset:
    """``babel120-amass``: BABEL-120 from the AMASS ``.npz`` files and BABEL's annotations, prepared as
    ActFormer does (module docstring).

    Args:
      root: the folder holding ``amass/rawdata/`` and ``babel_v1.0_release/``.
      split: ``"train"``, ``"val"`` or ``"test"`` (= val).
      label_map: BABEL's ``action_label_2_idx.json``; default ``root / "action_label_2_idx.json"`` if there,
        else :data:`CATEGORIES`.
      overlap: ``"code"`` (ActFormer's in-place de-meaning) or ``"independent"``.
    """
    if overlap not in ("code", "independent"):
        raise ValueError(f"overlap: expected 'code' or 'independent', got {overlap!r}")
    root = Path(root)
    json_path = root / BABEL_DIR / f"{_babel_split(split, 'babel120-amass')}.json"
    map_file = root / LABEL_MAP_FILE if label_map is None else Path(label_map)
    if label_map is None and not map_file.is_file():
        mapping, class_names = {c: i for i, c in enumerate(CATEGORIES)}, CATEGORIES
    else:
        mapping, class_names = read_label_map(map_file)
    keys, labels, clips = [], [], []
    for sid, sequence, poses, trans in babel_sequences(json_path, root):
        working = trans.copy()  # "code": de-meaned in place, segment by segment
        for key, label, start, end in babel_segments(sequence, len(poses), mapping, file=json_path, sid=sid):
            source = working if overlap == "code" else trans.copy()
            source[start:end] -= source[start:end].mean(axis=0)
            keys.append(key)
            labels.append(label)
            clips.append((poses[start:end], source[start:end].copy()))
    check_unique(keys, [f"segment {i}" for i in range(len(keys))], file=json_path, what="segment key")
    order = sorted(range(len(keys)), key=keys.__getitem__)
    motions = smpl_motions([keys[i] for i in order], [smpl_features(*clips[i]) for i in order], AMASS_TO_LIBRARY,
                           [labels[i] for i in order], [-1] * len(order))
    return pack(motions, name="babel120-amass", split=split, class_names=class_names, skeleton=SMPL24, fps=FPS)
