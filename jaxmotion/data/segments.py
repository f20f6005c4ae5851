"""Segment tables: the actions of multi-action sequences, each with its tags and the tags of the action after it.

A take of several actions (a person stands up, walks, turns, picks something up) is one sequence of a
:class:`~jaxmotion.data.motion.MotionDataset`; its :class:`Segments` say which frames each action spans and what
it is. Tags are multi-hot over the dataset's classes: an action carries one tag, or (BABEL-MAG's non-intention
actions) a body state and the body parts that move. ``next_tags`` are the tags of the following action of the same
sequence, and the action's own tags for the last one (Neural Marionette's convention for the end of a take).

Rows are ordered by sequence and, within a sequence, by time, and do not overlap; frames no action covers are
allowed (a take's lead-in, a label gap). Axes: S actions, C classes (tags), N sequences.

:meth:`~jaxmotion.data.motion.MotionDataset.action_items` cuts the actions out with the frames before each (their
context), as Neural Marionette trains on them; :class:`Program` is what multi-action generation takes as input,
checked action by action.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np

#: Frames of motion before an action that Neural Marionette conditions on (S§3 of the paper).
CONTEXT_FRAMES = 6


@dataclasses.dataclass(frozen=True, eq=False)
class Segments:
    """One row per action.

    Attributes:
      sequence: ``[S]`` int32 index of the sequence the action belongs to (0 in a single ``Motion``).
      start, end: ``[S]`` int32 first frame and one past the last, within the sequence.
      tags: ``[S, C]`` bool, the action's tags (at least one).
      next_tags: ``[S, C]`` bool, the next action's tags (the action's own for the last of its sequence).
      modes: ``[S]`` int32 style mode of the action's first tag (-1 where unknown).
    """

    sequence: np.ndarray
    start: np.ndarray
    end: np.ndarray
    tags: np.ndarray
    next_tags: np.ndarray
    modes: np.ndarray

    def __post_init__(self):
        s = len(self.start)
        for field in ("sequence", "start", "end", "modes"):
            value = getattr(self, field)
            if not isinstance(value, np.ndarray) or value.shape != (s,) or not np.issubdtype(value.dtype, np.integer):
                raise ValueError(f"segments.{field}: expected [S] = ({s},) integers, got "
                                 f"{getattr(value, 'dtype', type(value).__name__)} {np.shape(value)}")
        for field in ("tags", "next_tags"):
            value = getattr(self, field)
            if not isinstance(value, np.ndarray) or value.ndim != 2 or len(value) != s or value.dtype != bool:
                raise ValueError(f"segments.{field}: expected [S, C] bool with S = {s}, got "
                                 f"{getattr(value, 'dtype', type(value).__name__)} {np.shape(value)}")
        if self.tags.shape != self.next_tags.shape:
            raise ValueError(f"segments.next_tags: expected the shape of tags {self.tags.shape}, got "
                             f"{self.next_tags.shape}")
        _first_bad(np.flatnonzero(self.start < 0), "start", "a frame >= 0", self.start)
        _first_bad(np.flatnonzero(self.end <= self.start), "end", "after its start", self.end)
        _first_bad(np.flatnonzero(~self.tags.any(axis=1)), "tags", "at least one tag", self.tags.sum(axis=1))
        _first_bad(np.flatnonzero(~self.next_tags.any(axis=1)), "next_tags", "at least one tag",
                   self.next_tags.sum(axis=1))
        same = self.sequence[1:] == self.sequence[:-1]
        _first_bad(1 + np.flatnonzero(self.sequence[1:] < self.sequence[:-1]), "sequence",
                   "rows ordered by sequence", self.sequence)
        _first_bad(1 + np.flatnonzero(same & (self.start[1:] < self.end[:-1])), "start",
                   "a start at or after the previous action's end (in time order, no overlap)", self.start)

    def __len__(self) -> int:
        return len(self.start)

    @property
    def num_classes(self) -> int:
        return self.tags.shape[1]

    @property
    def durations(self) -> np.ndarray:
        """``[S]`` frames of each action."""
        return (self.end - self.start).astype(np.int64)

    @property
    def primary(self) -> np.ndarray:
        """``[S]`` int32 the first tag of each action (the lowest index: an intention tag, else the body state)."""
        return np.argmax(self.tags, axis=1).astype(np.int32)

    def check_within(self, lengths: np.ndarray, num_classes: int) -> None:
        """A ``ValueError`` unless every row lies in a sequence of ``lengths [N]`` and tags ``num_classes``."""
        if self.num_classes != num_classes:
            raise ValueError(f"segments.tags: expected one column per class ({num_classes}), got {self.num_classes}")
        outside = np.flatnonzero((self.sequence < 0) | (self.sequence >= len(lengths)))
        _first_bad(outside, "sequence", f"a sequence index in [0, {len(lengths)})", self.sequence)
        past = np.flatnonzero(self.end > np.asarray(lengths)[self.sequence])
        _first_bad(past, "end", "at most its sequence's length", self.end)

    def select(self, sequences: Sequence[int] | np.ndarray) -> Segments:
        """The rows of ``sequences``, in that order, renumbered 0, 1, ... as those sequences are in a subset."""
        sequences = np.asarray(sequences, np.int64)
        first = np.searchsorted(self.sequence, sequences, "left")  # rows are ordered by sequence
        counts = np.searchsorted(self.sequence, sequences, "right") - first
        index = np.repeat(first, counts) + np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
        renumbered = np.repeat(np.arange(len(sequences), dtype=np.int32), counts)
        return dataclasses.replace(self, sequence=renumbered, start=self.start[index], end=self.end[index],
                                   tags=self.tags[index], next_tags=self.next_tags[index], modes=self.modes[index])

    def to_arrays(self) -> dict[str, np.ndarray]:
        """The table as ``segments_<field>`` arrays (how a dataset file stores it)."""
        return {f"segments_{f.name}": getattr(self, f.name) for f in dataclasses.fields(self)}

    @classmethod
    def from_arrays(cls, arrays: dict[str, np.ndarray]) -> Segments | None:
        """What :meth:`to_arrays` wrote, or None when the arrays hold no table."""
        if "segments_start" not in arrays:
            return None
        return cls(**{f.name: arrays[f"segments_{f.name}"] for f in dataclasses.fields(cls)})

    @classmethod
    def from_rows(cls, rows: Sequence[tuple[int, int, int, Sequence[int], Sequence[int], int]],
                  num_classes: int) -> Segments:
        """A table from ``(sequence, start, end, tag ids, next tag ids, mode)`` rows."""
        flags = np.zeros((len(rows), 2, num_classes), bool)
        for r, (*_, tags, after, _) in enumerate(rows):
            flags[r, 0, list(tags)] = True
            flags[r, 1, list(after)] = True
        column = (lambda k: np.array([row[k] for row in rows], np.int32).reshape(len(rows)))
        return cls(column(0), column(1), column(2), flags[:, 0], flags[:, 1], column(5))

    @classmethod
    def empty(cls, num_classes: int) -> Segments:
        none = np.zeros(0, np.int32)
        flags = np.zeros((0, num_classes), bool)
        return cls(none, none, none, flags, flags, none)


def concatenate_segments(parts: Sequence[Segments], counts: Sequence[int]) -> Segments:
    """The tables of consecutive groups of ``counts`` sequences as one table (sequence indices shifted)."""
    offsets = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int32)
    return Segments(
        sequence=np.concatenate([p.sequence + o for p, o in zip(parts, offsets, strict=True)]).astype(np.int32),
        **{f: np.concatenate([getattr(p, f) for p in parts]) for f in ("start", "end", "tags", "next_tags", "modes")})


def transition_counts(segments: Segments) -> np.ndarray:
    """``[C, C]`` int64: how often an action tagged ``a`` is followed, in the same sequence, by one tagged ``b``
    (every pair of their tags counts; BABEL-MAG's "transition adjacent matrix", S-Fig. 1)."""
    follows = np.flatnonzero(segments.sequence[1:] == segments.sequence[:-1])
    before = segments.tags[follows].astype(np.int64)
    after = segments.tags[follows + 1].astype(np.int64)
    return before.T @ after


def label_transitions(segments: Segments) -> np.ndarray:
    """``[C, C]`` int64: how often an action whose first tag is ``a`` is followed in its take by one whose first
    tag is ``b`` (test programs step from label to label; :func:`transition_counts` counts every pair of
    tags)."""
    follows = np.flatnonzero(segments.sequence[1:] == segments.sequence[:-1])
    counts = np.zeros((segments.tags.shape[1],) * 2, np.int64)
    np.add.at(counts, (segments.primary[follows], segments.primary[follows + 1]), 1)
    return counts


def _first_bad(rows: np.ndarray, field: str, expected: str, values: np.ndarray) -> None:
    if len(rows):
        raise ValueError(f"segments.{field}: row {int(rows[0])}: expected {expected}, got {values[rows[0]]} "
                         f"({len(rows)} rows like it)")


# --- programs: the input of multi-action generation ---------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class ProgramAction:
    """One action to generate.

    Attributes:
      tags: its tag names (one, or a body state with body parts).
      duration: frames.
      path: optional ``duration`` ground points ``(x, z)`` in metres, the root's path over the action, for the tags
        that move the root; None lets the model choose.
    """

    tags: tuple[str, ...]
    duration: int
    path: tuple[tuple[float, float], ...] | None = None


@dataclasses.dataclass(frozen=True)
class Program:
    """A multi-action motion to generate: its actions in order, and optionally the motion to start from
    (``context``: :data:`CONTEXT_FRAMES` frames of ``rotations [K, J, 3]`` axis-angle and ``translation [K, 3]``;
    None starts from the model's own rest)."""

    actions: tuple[ProgramAction, ...]
    context: dict[str, np.ndarray] | None = None

    def check(self, tag_names: Sequence[str], max_duration: int, *, num_joints: int,
              context_frames: int = CONTEXT_FRAMES) -> None:
        """A ``ValueError`` naming the action index and the field of the first thing a model could not take: an
        unknown tag, a duration outside ``[1, max_duration]``, a path of the wrong length or with non-finite
        points, a context of the wrong shape or not finite."""
        if not self.actions:
            raise ValueError("program: expected at least one action, got none")
        known = set(tag_names)
        for i, action in enumerate(self.actions):
            where = f"program: action {i}"
            if not action.tags or not all(isinstance(t, str) for t in action.tags):
                raise ValueError(f"{where}: tags: expected one or more tag names, got {action.tags!r}")
            unknown = [t for t in action.tags if t not in known]
            if unknown:
                raise ValueError(f"{where}: tags: unknown tag {unknown[0]!r}; known tags: {', '.join(tag_names)}")
            if len(set(action.tags)) != len(action.tags):
                raise ValueError(f"{where}: tags: each tag once, got {action.tags!r}")
            if isinstance(action.duration, bool) or not isinstance(action.duration, int) or not (
                    1 <= action.duration <= max_duration):
                raise ValueError(f"{where}: duration: expected 1 to {max_duration} frames (the model's longest), got "
                                 f"{action.duration!r}")
            if action.path is not None:
                path = np.asarray(action.path, dtype=float) if _numeric(action.path) else None
                if path is None or path.shape != (action.duration, 2) or not np.isfinite(path).all():
                    raise ValueError(f"{where}: path: expected [duration, 2] = ({action.duration}, 2) finite ground "
                                     f"points (x, z), got {_describe(action.path)}")
        if self.context is not None:
            expected = {"rotations": (context_frames, num_joints, 3), "translation": (context_frames, 3)}
            for name, shape in expected.items():
                value = self.context.get(name) if isinstance(self.context, dict) else None
                array = np.asarray(value, dtype=float) if value is not None and _numeric(value) else None
                if array is None or array.shape != shape or not np.isfinite(array).all():
                    raise ValueError(f"program: context: {name}: expected {list(shape)} finite values, got "
                                     f"{_describe(value)}")

    def tag_matrix(self, tag_names: Sequence[str]) -> np.ndarray:
        """``[A, C]`` bool: each action's tags, multi-hot over ``tag_names``."""
        index = {t: i for i, t in enumerate(tag_names)}
        out = np.zeros((len(self.actions), len(tag_names)), bool)
        for row, action in enumerate(self.actions):
            out[row, [index[t] for t in action.tags]] = True
        return out

    @property
    def num_frames(self) -> int:
        return sum(a.duration for a in self.actions)


def _numeric(value) -> bool:
    try:
        np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return False
    return True


def _describe(value) -> str:
    if value is None:
        return "nothing"
    if not _numeric(value):
        return f"{type(value).__name__} {value!r:.60}"
    array = np.asarray(value, dtype=float)
    finite = "" if np.isfinite(array).all() else f", {int((~np.isfinite(array)).sum())} not finite"
    return f"shape {array.shape}{finite}"
