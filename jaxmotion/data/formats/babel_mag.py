"""``mag``: BABEL-MAG (Neural Marionette's data) rebuilt from BABEL's own files, as takes of tagged actions.

Neural Marionette relabelled BABEL's frame labels of 40 categories into 31 tags ("intention first": an action with a
clear goal gets one intention tag; otherwise a body state and the body parts that move) and resolved the overlaps
by hand; neither the 40 categories, the relabelling nor the data were released. This loader applies a documented
map instead (:data:`TAG_MAP`: every BABEL category with a tag, and why; a user's JSON ``{category: tag or null}``
replaces it) and a fixed rule for overlapping labels, so its actions are a reconstruction, not the paper's set.

**Files** (as ``babel120-amass`` reads them)::

    <data_root>/amass/rawdata/<feat_p without its first folder>    AMASS .npz: poses, trans, mocap_framerate
    <data_root>/babel_v1.0_release/{train,val}.json               BABEL annotations (frame_ann)

``"train"`` reads ``train.json``, ``"test"`` ``val.json`` (BABEL's test labels are not public; the paper draws 20%
of each tag, at most 100, from its own set, which cannot be reproduced without it).

**Per sequence** (one take): the SMPL-H body pose (root + 21 joints, SMPL's hands at rest) and translation,
resampled to 30 fps as for BABEL-120 (:func:`~jaxmotion.data.formats.babel.resample_cubic`), turned into the library
frame (y up), joints by the template's forward kinematics; translation absolute (a take is one continuous motion).
Then its actions from ``frame_ann`` (sequences with only ``seq_ann`` have no frame labels and are skipped):

1. each label's categories get their tags (:data:`TAG_MAP`; "sit" is "Sit Down" when the root ends the label at
   least :data:`SIT_DESCENT` m lower than it starts it, else the state "Sit"); categories without a tag are
   dropped and counted;
2. each frame gets the tags of every label covering it: one intention tag wins over states and body parts; two
   different intention tags are ambiguous (the frame gets none, counted); otherwise one state with the body parts
   (body parts with no state are taken as standing: "Stand"; two states are ambiguous);
3. each run of frames with the same tags is an action; runs shorter than :data:`MIN_FRAMES` are dropped (counted).
   An action's next tags are those of the action right after it (within :data:`MAX_GAP` frames), else its own.

A label starting after its end, or ending past the sequence's end by more than a frame, is an error naming the file
and the label; so are missing keys and non-finite poses. What was dropped is returned by :func:`read_babel_mag` and
printed by the loader.
"""

from __future__ import annotations

import dataclasses
import sys
from collections import Counter
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from jaxmotion.data.formats._common import check_split
from jaxmotion.data.formats.babel import (AMASS_TO_LIBRARY, BABEL_DIR, FPS, _get, _read_json, annotation_labels,
                                          babel_sequences, label_categories, smpl_features)
from jaxmotion.data.formats.ntu_recon import smpl_motions
from jaxmotion.data.motion import MotionDataset, pack
from jaxmotion.data.segments import Segments
from jaxmotion.data.mag_tags import KINDS, TAG_NAMES
from jaxmotion.geometry.skeletons import SMPL24

#: Root descent (m) over a "sit" label that makes it "Sit Down" rather than the state "Sit".
SIT_DESCENT = 0.15
#: Shortest action kept (frames at 30 fps).
MIN_FRAMES = 10
#: Frames between two actions for the second still to be the first's next action.
MAX_GAP = 15

#: BABEL category -> (MAG tag, or None for no tag; why). Written from the paper's tag definitions (its supplement's
#: Table 1 and §2.1: intention first, then body state and body parts); the paper's own 40 categories are unpublished.
TAG_MAP: Mapping[str, tuple[str | None, str]] = {
    "walk": ("Walk", "the tag's own name"),
    "forward movement": ("Walk", "moving forward on foot, the common case walking"),
    "backwards movement": ("Walk Backward", "moving backward on foot"),
    "sideways movement": ("Walk Sideway", "moving sideways on foot"),
    "move up/down incline": ("Walk Upward/Downward", "walking up or down stairs or a slope"),
    "step": ("Step", "the tag's own name"),
    "run": ("Run", "the tag's own name"),
    "jog": ("Run", "a slow run: the root moves as in running"),
    "jump": ("Jump", "the tag's own name"),
    "hop": ("Jump", "a jump on one leg"),
    "turn": ("Turn", "the tag's own name"),
    "sit": ("Sit", "the state; 'Sit Down' when the root descends (SIT_DESCENT)"),
    "stand up": ("Stand Up", "the tag's own name"),
    "interact with/use object": ("Using Object", "the tag's own meaning"),
    "take/pick something up": ("Take Something Up", "the tag's own meaning"),
    "lift something": ("Take Something Up", "taking something up from where it lies"),
    "grasp object": ("Take Something Up", "taking hold of something"),
    "place something": ("Place Something Down", "the tag's own meaning"),
    "move something": ("Move Something", "the tag's own name"),
    "throw": ("Throw", "the tag's own name"),
    "touch object": ("Touch Something", "the tag's own meaning"),
    "kick": ("Kick", "the tag's own name"),
    "punch": ("Punch", "the tag's own name"),
    "wave": ("Wave Hand", "the tag's own meaning"),
    "stretch": ("Stretch", "the tag's own name"),
    "crossing limbs": ("Crossing Limbs", "the tag's own name"),
    "touching body part": ("Touch Body Part", "the tag's own meaning"),
    "touching face": ("Touch Body Part", "the face is a body part"),
    "scratch": ("Touch Body Part", "a hand touching the body"),
    "stand": ("Stand", "the state's own name"),
    "t pose": ("Stand", "standing, arms out: a standing state"),
    "a pose": ("Stand", "standing, arms down at an angle: a standing state"),
    "bend": ("Bend", "the state's own name"),
    "head movements": ("Head Movement", "the body part's own name"),
    "look": ("Head Movement", "the head turns to look"),
    "arm movements": ("Arm Movement", "the body part's own name"),
    "hand movements": ("Arm Movement", "hands move with the arms (the tags have no hand)"),
    "gesture": ("Arm Movement", "a gesture is made with the arms and hands, no intention tag fits"),
    "waist movements": ("Waist Movement", "the body part's own name"),
    "leg movements": ("Leg Movement", "the body part's own name"),
    "knee movement": ("Leg Movement", "the knee is part of the leg"),
    "foot movements": ("Leg Movement", "the foot moves with the leg"),
    "raising body part": (None, "which part (arm, leg) is not said: ambiguous"),
    "lowering body part": (None, "which part is not said: ambiguous"),
    "swing body part": (None, "which part is not said: ambiguous"),
    "circular movement": (None, "walking a circle or circling the arms: ambiguous"),
}


@dataclasses.dataclass(frozen=True)
class MagReport:
    """What :func:`read_babel_mag` kept and left out, and why."""

    takes: int
    actions: int
    no_tag: Counter  # category -> labels whose category has no tag
    ambiguous_frames: int  # frames under labels of two intentions or two states
    short_actions: int  # runs under MIN_FRAMES
    skipped_sequences: int  # sequences without frame labels

    def __str__(self) -> str:
        untagged = ", ".join(f"{c} ({n})" for c, n in self.no_tag.most_common(8))
        return (f"{self.takes} takes, {self.actions} actions; left out: {sum(self.no_tag.values())} labels of "
                f"categories without a tag ({untagged or 'none'}), {self.ambiguous_frames} frames of ambiguous "
                f"overlaps, {self.short_actions} runs under {MIN_FRAMES} frames, {self.skipped_sequences} sequences "
                f"without frame labels")


def read_tag_map(path: str | Path) -> dict[str, str | None]:
    """A user's ``{category: tag or null}`` JSON; every tag must be one of the 31."""
    path = Path(path)
    mapping = _read_json(path, "BABEL-MAG tag map")
    if not isinstance(mapping, dict):
        raise ValueError(f"{path}: expected a JSON object from BABEL category to tag, got {type(mapping).__name__}")
    for category, tag in mapping.items():
        if tag is not None and tag not in TAG_NAMES:
            raise ValueError(f"{path}: {category!r}: expected one of the 31 tags or null, got {tag!r}")
    return dict(mapping)


_KIND = np.array([KINDS[name] for name in TAG_NAMES])
_INTENTION = np.isin(_KIND, ("root", "in place"))
_STAND = TAG_NAMES.index("Stand")


def resolve_actions(labels: list[tuple[int, int, tuple[str, ...]]], frames: int
                    ) -> tuple[list[tuple[int, int, tuple[int, ...]]], int, int]:
    """``labels``: ``(start, end, tags)`` per label of a sequence of ``frames`` frames -> ``(actions as (start, end,
    tag ids), ambiguous frames, short runs dropped)``, by the rules of the module docstring (steps 2-3), all frames
    at once."""
    if frames < 1:
        return [], 0, 0
    present = np.zeros((frames, len(TAG_NAMES)), bool)  # [T, C] the tags of every label covering each frame
    for start, end, tags in labels:
        present[start:end, [TAG_NAMES.index(t) for t in tags]] = True
    intentions = (present & _INTENTION).sum(axis=1)
    states = (present & (_KIND == "state")).sum(axis=1)
    ambiguous = (intentions > 1) | ((intentions == 0) & (states > 1))
    chosen = np.where((intentions == 1)[:, None], present & _INTENTION, present)  # an intention wins alone
    chosen[(intentions == 0) & (states == 0) & present.any(axis=1), _STAND] = True  # body parts alone: standing
    chosen[ambiguous] = False
    # runs of frames with the same tags; rows without any are no action
    change = np.flatnonzero(np.any(chosen[1:] != chosen[:-1], axis=1)) + 1
    bounds = np.concatenate([[0], change, [frames]])
    actions, short = [], 0
    for start, end in zip(bounds[:-1], bounds[1:]):
        if chosen[start].any():
            if end - start >= MIN_FRAMES:
                actions.append((int(start), int(end), tuple(int(t) for t in np.flatnonzero(chosen[start]))))
            else:
                short += 1
    return actions, int(ambiguous.sum()), short


def _labels(sequence: dict, frames: int, root_height: np.ndarray, tag_map: Mapping[str, str | None], *,
            file: Path, sid: str, no_tag: Counter) -> list[tuple[int, int, tuple[str, ...]]] | None:
    """A sequence's frame labels as ``(start, end, tags)`` at 30 fps, None without frame labels."""
    frame_ann = _get(sequence, "frame_ann", file=file, where=f"[{sid!r}]")
    if frame_ann is None:
        return None
    out = []
    for _, where, label in annotation_labels(frame_ann, file=file, where=f"[{sid!r}]['frame_ann']"):
        categories = label_categories(label, file=file, where=where) or []
        times = [_get(label, k, file=file, where=where) for k in ("start_t", "end_t")]
        if not all(isinstance(t, (int, float)) and not isinstance(t, bool) and np.isfinite(t) for t in times):
            raise ValueError(f"{file}: {where}: expected numbers start_t and end_t (seconds), got {times}")
        if times[0] > times[1]:
            raise ValueError(f"{file}: {where}: start_t {times[0]} s is after end_t {times[1]} s")
        if times[1] * FPS > frames + 1:
            raise ValueError(f"{file}: {where}['end_t']: {times[1]} s is past the sequence's end ({frames / FPS:.2f} s "
                             f"at {FPS:g} fps)")
        start, end = max(0, int(times[0] * FPS)), min(frames, int(times[1] * FPS))
        tags = []
        for category in sorted(set(categories)):
            tag = tag_map.get(category)
            if tag is None:
                no_tag[category] += 1
                continue
            if tag == "Sit" and end - start >= 2 and root_height[start] - root_height[end - 1] >= SIT_DESCENT:
                tag = "Sit Down"
            tags.append(tag)
        if tags and end > start:
            out.append((start, end, tuple(tags)))
    return out


def read_babel_mag(root: str | Path, split: str = "train", *, tag_map: str | Path | None = None
                   ) -> tuple[MotionDataset, MagReport]:
    """The takes of ``split`` with their segments, and what was left out (module docstring)."""
    check_split(split, ("train", "test"), "mag", "'test' reads BABEL's val split (its test labels are not public)")
    root = Path(root)
    mapping = {c: tag for c, (tag, _) in TAG_MAP.items()} if tag_map is None else read_tag_map(tag_map)
    json_path = root / BABEL_DIR / f"{'train' if split == 'train' else 'val'}.json"
    keys, features, labels_of, rows = [], [], [], []
    no_tag, ambiguous, short, skipped = Counter(), 0, 0, 0
    for sid, sequence, poses, trans in babel_sequences(json_path, root):
        frames = len(poses)
        height = trans @ np.asarray(AMASS_TO_LIBRARY)[1]  # the library's up component
        labels = _labels(sequence, frames, height, mapping, file=json_path, sid=sid, no_tag=no_tag)
        if labels is None:
            skipped += 1
            continue
        actions, ambiguous_frames, short_runs = resolve_actions(labels, frames)
        ambiguous, short = ambiguous + ambiguous_frames, short + short_runs
        if not actions:
            continue
        rows += _rows(len(keys), actions)
        keys.append(sid)
        features.append(smpl_features(poses, trans))
        labels_of.append(actions[0][2][0])  # the first action's first tag
    motions = smpl_motions(keys, features, AMASS_TO_LIBRARY, labels_of, [-1] * len(keys))
    data = pack(motions, name="mag", split=split, class_names=TAG_NAMES, skeleton=SMPL24, fps=FPS)
    data = dataclasses.replace(data, segments=Segments.from_rows(rows, len(TAG_NAMES)))
    report = MagReport(len(keys), len(rows), no_tag, ambiguous, short, skipped)
    return data, report


def _rows(sequence: int, actions: list[tuple[int, int, tuple[int, ...]]]) -> list[tuple]:
    """One take's actions as segment rows; the next action's tags where it follows within MAX_GAP, else its own."""
    rows = []
    for k, (start, end, tags) in enumerate(actions):
        follows = k + 1 < len(actions) and actions[k + 1][0] - end <= MAX_GAP
        rows.append((sequence, start, end, tags, actions[k + 1][2] if follows else tags, -1))
    return rows


def load_babel_mag(root: str | Path, split: str = "train") -> MotionDataset:
    """``mag``: BABEL-MAG rebuilt from AMASS and BABEL under ``root`` (module docstring); prints what it left out."""
    data, report = read_babel_mag(root, split)
    print(f"[data] mag/{split} from {root}: {report}", file=sys.stderr)
    return data

