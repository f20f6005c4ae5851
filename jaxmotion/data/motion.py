"""Motion records and packed motion datasets: the one data model every loader and generator returns.

A ``Motion`` is one variable-length sequence. A ``MotionDataset`` stores many of them packed: each
per-frame array is the concatenation of all sequences along the frame axis, and ``starts`` marks where
each sequence begins, so a dataset is a handful of arrays (cheap to cache as ``.npz``, to move to a
device, and to gather fixed-length windows from).

Axes: N sequences, F frames in all (the sum of the lengths), T frames of one sequence, P persons, J joints.
Frame: the library frame (metres, +Y up, facing +Z at rest, +X the subject's left).

Persons: a one-person dataset (``persons == 1``, every single-action set) stores ``joints [F, J, 3]``, as it
always has; a dataset of P >= 2 persons acting together (interactions, combat scenes) stores
``joints [F, P, J, 3]``, the persons axis after the packed frame axis so that windows are gathered from
either by the same frame indices. One sequence of P >= 2 persons is a ``Motion`` with ``joints [P, T, J, 3]``;
the pipeline's batches are ``[B, P, T, J, 3]``. :func:`person_axis` gives any record's arrays with the
axis, whatever P.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from jaxmotion.data.segments import CONTEXT_FRAMES, Segments, concatenate_segments
from jaxmotion.files import atomic_file
from jaxmotion.geometry.skeletons import CMU_MOCAP20, GTA22, NTU25, SMPL24, UESTC18, Skeleton

#: Joint layouts a dataset may use, by the name stored in cache files.
SKELETONS = {s.name: s for s in (SMPL24, CMU_MOCAP20, UESTC18, NTU25, GTA22)}


@dataclasses.dataclass(frozen=True, eq=False)
class Motion:
    """One sequence.

    Attributes:
      joints: ``[T, J, 3]`` float32 joint positions, library frame, metres (translation included); ``[P, T, J, 3]``
        for P >= 2 persons.
      translation: ``[T, 3]`` float32 root (joint 0) translation (``[P, T, 3]``).
      rotations: ``[T, J, 3]`` float32 local axis-angle rotations (joint 0 global; ``[P, T, J, 3]``), or
        ``None`` for formats that store joint positions only (Action2Motion's HumanAct12 and CMU mocap joints).
      action: class index.
      mode: index of the style mode within the class (``-1`` where unknown, as in real data).
      subject: subject index (``-1`` where unknown); for several persons, the clip's performer id (NTU's P
        field, which its cross-subject split uses).
      name: the clip's name in its source (file name, key), or a generated id.
      segments: the actions of a multi-action sequence (:class:`~jaxmotion.data.segments.Segments`, ``sequence``
        all 0), or None.
    """

    joints: np.ndarray
    translation: np.ndarray
    rotations: np.ndarray | None
    action: int
    mode: int = -1
    subject: int = -1
    name: str = ""
    segments: Segments | None = None

    @property
    def persons(self) -> int:
        return 1 if self.joints.ndim == 3 else self.joints.shape[0]

    @property
    def num_frames(self) -> int:
        return self.joints.shape[-3]


def _feed(hasher, value: Any) -> None:
    """Add ``value`` to ``hasher``: arrays by dtype, shape and bytes, dataclasses field by field, sequences item by
    item, anything else by its repr."""
    if isinstance(value, np.ndarray):
        hasher.update(f"{value.dtype}{value.shape}".encode())
        hasher.update(np.ascontiguousarray(value).tobytes())
    elif dataclasses.is_dataclass(value) and not isinstance(value, type):
        hasher.update(type(value).__name__.encode())
        for field in dataclasses.fields(value):
            hasher.update(field.name.encode())
            _feed(hasher, getattr(value, field.name))
    elif isinstance(value, (tuple, list)):
        hasher.update(f"{type(value).__name__}{len(value)}".encode())
        for item in value:
            _feed(hasher, item)
    else:
        hasher.update(repr(value).encode())


@dataclasses.dataclass(frozen=True, eq=False)
class MotionDataset:
    """Packed sequences of one dataset split.

    Attributes:
      name: dataset name (e.g. ``synth-uestc``, ``uestc``).
      split: ``train`` / ``test`` / ``all``.
      class_names: one name per action class; ``actions`` index into it.
      skeleton: the joint layout of ``joints`` (and of ``rotations`` when present).
      fps: frames per second.
      joints: ``[F, J, 3]`` float32; ``[F, P, J, 3]`` when ``persons`` >= 2.
      translation: ``[F, 3]`` float32 (``[F, P, 3]``).
      rotations: ``[F, J, 3]`` float32 axis-angle (``[F, P, J, 3]``), or ``None``.
      starts: ``[N + 1]`` int64 frame offsets; sequence i is frames ``starts[i]:starts[i + 1]``.
      actions, modes, subjects: ``[N]`` int32 labels (``-1`` where unknown).
      names: ``N`` clip names.
      mode_names: per class, the names of its style modes (empty tuples where unknown).
      persons: P, the persons in every sequence (1: no persons axis in the arrays).
      segments: for multi-action sequences (takes), their actions: frames, tags over ``class_names``, next tags
        (:mod:`jaxmotion.data.segments`); a take's ``actions`` label is then its first action's first tag. None
        for datasets of one action per sequence.
    """

    name: str
    split: str
    class_names: tuple[str, ...]
    skeleton: Skeleton
    fps: float
    joints: np.ndarray
    translation: np.ndarray
    rotations: np.ndarray | None
    starts: np.ndarray
    actions: np.ndarray
    modes: np.ndarray
    subjects: np.ndarray
    names: tuple[str, ...]
    mode_names: tuple[tuple[str, ...], ...] = ()
    persons: int = 1
    segments: Segments | None = None

    def __post_init__(self):
        if not isinstance(self.persons, int) or self.persons < 1:
            raise ValueError(f"persons: expected a positive number of persons, got {self.persons!r}")
        n, j = len(self.actions), self.skeleton.num_joints
        f = self.joints.shape[0] if isinstance(self.joints, np.ndarray) and self.joints.ndim else 0
        p, named_p = ((), "") if self.persons == 1 else ((self.persons,), f"{self.persons}, ")
        _expect(self.joints, (f, *p, j, 3), "joints", f"[F, {named_p}{j}, 3]")
        _expect(self.translation, (f, *p, 3), "translation", f"[F, {named_p}3]")
        if self.rotations is not None:
            _expect(self.rotations, (f, *p, j, 3), "rotations", f"[F, {named_p}{j}, 3]")
        _expect(self.starts, (n + 1,), "starts", "[N + 1]")
        for field in ("actions", "modes", "subjects"):
            _expect(getattr(self, field), (n,), field, "[N]")
        if len(self.names) != n:
            raise ValueError(f"names: expected {n} names, got {len(self.names)}")
        if n and (self.starts[0] != 0 or self.starts[-1] != f or np.any(np.diff(self.starts) < 1)):
            raise ValueError(f"starts: expected increasing offsets from 0 to F={f}, got {self.starts[:5]}...")
        if n and (self.actions.min() < 0 or self.actions.max() >= len(self.class_names)):
            raise ValueError(f"actions: expected class indices in [0, {len(self.class_names)}), "
                             f"got [{self.actions.min()}, {self.actions.max()}]")
        if self.mode_names and len(self.mode_names) != len(self.class_names):
            raise ValueError(f"mode_names: expected one tuple per class ({len(self.class_names)}), "
                             f"got {len(self.mode_names)}")
        if self.segments is not None:
            self.segments.check_within(self.lengths, len(self.class_names))

    # --- sequence access ---------------------------------------------------------------------------

    def digest(self) -> str:
        """A SHA-256 of everything the dataset holds (arrays by dtype, shape and bytes; the rest by value), the same
        for the same data in any process: with a recipe and a key, it says whether two trainings are one."""
        hasher = hashlib.sha256()
        _feed(hasher, self)
        return hasher.hexdigest()

    def __len__(self) -> int:
        return len(self.actions)

    def __getitem__(self, index: int) -> Motion:
        if not -len(self) <= index < len(self):
            raise IndexError(f"{self.name}/{self.split}: index {index} out of range for {len(self)} sequences")
        index %= len(self)
        frames = slice(int(self.starts[index]), int(self.starts[index + 1]))
        # several persons: [T, P, ...] packed -> [P, T, ...] per record
        cut = (lambda a: a[frames]) if self.persons == 1 else (lambda a: np.moveaxis(a[frames], 1, 0))
        return Motion(
            joints=cut(self.joints),
            translation=cut(self.translation),
            rotations=None if self.rotations is None else cut(self.rotations),
            action=int(self.actions[index]),
            mode=int(self.modes[index]),
            subject=int(self.subjects[index]),
            name=self.names[index],
            segments=None if self.segments is None else self.segments.select([index]),
        )

    def __iter__(self) -> Iterator[Motion]:
        return (self[i] for i in range(len(self)))

    @property
    def lengths(self) -> np.ndarray:
        """``[N]`` int64 number of frames of each sequence."""
        return np.diff(self.starts)

    @property
    def num_classes(self) -> int:
        return len(self.class_names)

    def subset(self, indices: Sequence[int] | np.ndarray, split: str | None = None) -> "MotionDataset":
        """The sequences at ``indices``, in that order, as a new packed dataset."""
        indices = np.asarray(indices, dtype=np.int64)
        frames = np.concatenate([np.arange(self.starts[i], self.starts[i + 1]) for i in indices]) if len(
            indices) else np.zeros((0,), np.int64)
        lengths = self.lengths[indices]
        return dataclasses.replace(
            self,
            split=self.split if split is None else split,
            joints=self.joints[frames],
            translation=self.translation[frames],
            rotations=None if self.rotations is None else self.rotations[frames],
            starts=np.concatenate([[0], np.cumsum(lengths)]).astype(np.int64),
            actions=self.actions[indices],
            modes=self.modes[indices],
            subjects=self.subjects[indices],
            names=tuple(self.names[i] for i in indices),
            segments=None if self.segments is None else self.segments.select(indices),
        )

    def action_items(self, context: int = CONTEXT_FRAMES) -> ActionItems:
        """Each action of a multi-action dataset as its own sequence, its ``context`` preceding frames first
        (:class:`~jaxmotion.data.segments.ActionItems`); actions with fewer frames before them are left out and
        counted. A ``ValueError`` for a dataset without segments."""
        if self.segments is None:
            raise ValueError(f"{self.name}/{self.split}: holds one action per sequence (no segments); action items "
                             f"need a multi-action dataset such as synth-mag")
        if context < 0:
            raise ValueError(f"context: expected >= 0 frames, got {context}")
        seg = self.segments
        keep = np.flatnonzero(seg.start >= context)
        first = self.starts[seg.sequence[keep]] + seg.start[keep] - context
        last = self.starts[seg.sequence[keep]] + seg.end[keep]
        frames = np.concatenate([np.arange(a, b) for a, b in zip(first, last)]) if len(keep) else np.zeros(0, int)
        lengths = last - first
        pick = (lambda a: None if a is None else a[frames])
        items = dataclasses.replace(
            self, joints=pick(self.joints), translation=pick(self.translation), rotations=pick(self.rotations),
            starts=np.concatenate([[0], np.cumsum(lengths)]).astype(np.int64),
            actions=seg.primary[keep], modes=seg.modes[keep], subjects=self.subjects[seg.sequence[keep]],
            names=tuple(f"{self.names[seg.sequence[k]]}/{k}" for k in keep), segments=None)
        return ActionItems(items, context, seg.tags[keep], seg.next_tags[keep], seg.durations[keep],
                           dropped=len(seg) - len(keep))

    # --- persistence ---------------------------------------------------------------------------------

    def save(self, path: str | Path, *, source: Mapping[str, Any] | None = None) -> None:
        """Write the dataset to one ``.npz`` (arrays plus a JSON header), atomically; ``load`` reads it back.
        ``source``: what the data was made from (a cache's variant, seed, generator version...), kept in the
        header so that a reader can check the file holds what it expects."""
        header = {
            "name": self.name, "split": self.split, "class_names": list(self.class_names),
            "skeleton": self.skeleton.name, "fps": self.fps, "names": list(self.names),
            "mode_names": [list(m) for m in self.mode_names], "persons": self.persons,
            "source": None if source is None else dict(source),
        }
        arrays = {k: getattr(self, k) for k in ("joints", "translation", "starts", "actions", "modes", "subjects")}
        if self.rotations is not None:
            arrays["rotations"] = self.rotations
        if self.segments is not None:
            arrays.update(self.segments.to_arrays())
        with atomic_file(path) as f:  # a killed generation never leaves a half-written cache
            np.savez(f, header=np.array(json.dumps(header)), **arrays)

    @classmethod
    def load(cls, path: str | Path, *, source: Mapping[str, Any] | None = None) -> "MotionDataset":
        """Read a file ``save`` wrote. ``source``: what it must have been made from (each key compared with
        the recorded ``source``); a file made from something else is a :class:`SourceMismatchError`."""
        with np.load(path, allow_pickle=False) as data:
            header = json.loads(str(data["header"]))
            arrays = {k: data[k] for k in data.files if k != "header"}
        if source is not None:
            recorded = header.get("source") or {}
            differences = [f"{k}: {recorded.get(k, '<not recorded>')!r} (expected {v!r})"
                           for k, v in source.items() if recorded.get(k, "<not recorded>") != v]
            if differences:
                raise SourceMismatchError(f"{path} holds other data: " + "; ".join(differences))
        if header["skeleton"] not in SKELETONS:
            raise ValueError(f"{path}: unknown skeleton {header['skeleton']!r}; known: {sorted(SKELETONS)}")
        return cls(
            name=header["name"], split=header["split"], class_names=tuple(header["class_names"]),
            skeleton=SKELETONS[header["skeleton"]], fps=float(header["fps"]),
            joints=arrays["joints"], translation=arrays["translation"], rotations=arrays.get("rotations"),
            starts=arrays["starts"], actions=arrays["actions"], modes=arrays["modes"], subjects=arrays["subjects"],
            names=tuple(header["names"]), mode_names=tuple(tuple(m) for m in header["mode_names"]),
            persons=int(header.get("persons", 1)),  # files written before the persons axis hold one person
            segments=Segments.from_arrays(arrays),
        )


@dataclasses.dataclass(frozen=True, eq=False)
class ActionItems:
    """Actions cut from their sequences with the frames before them, as Neural Marionette trains on them
    (:meth:`~jaxmotion.data.motion.MotionDataset.action_items`).

    Attributes:
      data: one sequence per action: its ``context`` preceding frames, then its own; ``actions`` are each action's
        first tag, ``modes`` its mode, ``subjects`` and names those of its take (the name with ``/<row>``).
      context: the context frames at the start of every sequence of ``data``.
      tags, next_tags: ``[S, C]`` bool.
      durations: ``[S]`` int64 frames of each action (its sequence's length minus ``context``).
      dropped: actions left out because fewer than ``context`` frames precede them in their sequence.
    """

    data: MotionDataset
    context: int
    tags: np.ndarray
    next_tags: np.ndarray
    durations: np.ndarray
    dropped: int

    def __len__(self) -> int:
        return len(self.durations)

    def subset(self, indices: Sequence[int] | np.ndarray) -> ActionItems:
        """The items at ``indices``, in that order."""
        indices = np.asarray(indices)
        return dataclasses.replace(self, data=self.data.subset(indices), tags=self.tags[indices],
                                   next_tags=self.next_tags[indices], durations=self.durations[indices])

    def ground_paths(self) -> list[np.ndarray]:
        """Per action ``[T, 2]`` the root's ground-plane path (x, z) over its own frames (context excluded)."""
        data = self.data
        return [data.translation[data.starts[i] + self.context:data.starts[i + 1]][:, [0, 2]]
                for i in range(len(self))]


class SourceMismatchError(ValueError):
    """A saved dataset was made from something other than what its reader expects."""


def pack(motions: Sequence[Motion], *, name: str, split: str, class_names: Sequence[str], skeleton: Skeleton,
         fps: float, mode_names: Sequence[Sequence[str]] = (), persons: int = 1) -> MotionDataset:
    """Pack a list of ``Motion`` records (all with or all without rotations, all of ``persons`` persons)
    into a dataset."""
    has_rot = {m.rotations is not None for m in motions}
    if len(has_rot) > 1:
        raise ValueError("pack: either every motion has rotations or none has")
    has_segments = {m.segments is not None for m in motions}
    if len(has_segments) > 1:
        raise ValueError("pack: either every motion has segments or none has")
    for m in motions:
        if m.persons != persons:
            raise ValueError(f"pack: motion {m.name!r} has {m.persons} persons, expected {persons} "
                             f"(joints {m.joints.shape})")
    lengths = [m.num_frames for m in motions]
    j = skeleton.num_joints
    p = () if persons == 1 else (persons,)

    def cat(arrays, shape):
        if persons > 1:  # [P, T, ...] records -> [T, P, ...] packed frames
            arrays = [np.moveaxis(a, 0, 1) for a in arrays]
        return np.concatenate(arrays).astype(np.float32) if arrays else np.zeros((0, *p, *shape), np.float32)

    return MotionDataset(
        name=name, split=split, class_names=tuple(class_names), skeleton=skeleton, fps=float(fps),
        joints=cat([m.joints for m in motions], (j, 3)),
        translation=cat([m.translation for m in motions], (3,)),
        rotations=cat([m.rotations for m in motions], (j, 3)) if has_rot == {True} else None,
        starts=np.concatenate([[0], np.cumsum(lengths, dtype=np.int64)]).astype(np.int64),
        actions=np.array([m.action for m in motions], np.int32),
        modes=np.array([m.mode for m in motions], np.int32),
        subjects=np.array([m.subject for m in motions], np.int32),
        names=tuple(m.name for m in motions),
        mode_names=tuple(tuple(m) for m in mode_names),
        persons=persons,
        segments=concatenate_segments([m.segments for m in motions], [1] * len(motions))
        if has_segments == {True} else None,
    )


def to_dataset(motions: dict, skeleton: Skeleton, class_names: Sequence[str], fps: float, *, name: str = "actor",
               split: str = "generated", modes: np.ndarray | None = None, names: Sequence[str] | None = None,
               mode_names: Sequence[Sequence[str]] = ()) -> MotionDataset:
    """A batch dict (``joints``, ``translation``, optionally ``rotations`` ``[B, T, ...]``, or ``[B, P, T, ...]``
    for several persons, ``lengths [B]``, ``actions [B]``), as the pipeline and the generators' samplers give
    it -> the packed ``MotionDataset`` of its B motions, each cut to its length."""
    lengths = np.asarray(motions["lengths"]).astype(np.int64)
    joints = np.asarray(motions["joints"], np.float32)
    if joints.ndim not in (4, 5):
        raise ValueError(f"joints: expected [B, T, J, 3] or [B, P, T, J, 3], got shape {joints.shape}")
    persons = 1 if joints.ndim == 4 else joints.shape[1]
    frames = joints.shape[-3]
    keep = np.arange(frames)[None, :] < lengths[:, None]  # row-major order is the packed order

    def frames_first(a):  # [B, P, T, ...] -> [B, T, P, ...]
        a = np.asarray(a, np.float32)
        return a if persons == 1 else np.moveaxis(a, 1, 2)

    count = len(lengths)
    return MotionDataset(
        name=name, split=split, class_names=tuple(class_names), skeleton=skeleton, fps=float(fps),
        joints=frames_first(joints)[keep],
        translation=frames_first(motions["translation"])[keep],
        rotations=frames_first(motions["rotations"])[keep] if "rotations" in motions else None,
        starts=np.concatenate([[0], np.cumsum(lengths)]).astype(np.int64),
        actions=np.asarray(motions["actions"], np.int32),
        modes=np.full(count, -1, np.int32) if modes is None else np.asarray(modes, np.int32),
        subjects=np.full(count, -1, np.int32),
        names=tuple(f"{name}-{i}" for i in range(count)) if names is None else tuple(names),
        mode_names=tuple(tuple(m) for m in mode_names),
        persons=persons,
    )


def concatenate(parts: Sequence[MotionDataset], *, split: str) -> MotionDataset:
    """The sequences of several datasets with the same classes, skeleton, persons, frame rate and fields, one after
    another. Anything that differs is an error naming it (the result could hold only one rate, and one part
    without rotations would drop everyone's)."""
    if not parts:
        raise ValueError("concatenate: expected at least one dataset, got none")
    first = parts[0]
    for p in parts[1:]:
        differs = [what for what, same in (("classes", p.class_names == first.class_names),
                                           ("skeleton", p.skeleton is first.skeleton),
                                           ("number of persons", p.persons == first.persons),
                                           (f"frame rate (fps {p.fps:g} and {first.fps:g})", p.fps == first.fps),
                                           ("rotations (present in one, absent in the other)",
                                            (p.rotations is None) == (first.rotations is None)),
                                           ("segments (present in one, absent in the other)",
                                            (p.segments is None) == (first.segments is None))) if not same]
        if differs:
            raise ValueError(f"concatenate: {p.name}/{p.split} differs from {first.name}/{first.split} in its "
                             f"{', '.join(differs)}")
    return dataclasses.replace(
        first, split=split,
        joints=np.concatenate([p.joints for p in parts]),
        translation=np.concatenate([p.translation for p in parts]),
        rotations=None if first.rotations is None else np.concatenate([p.rotations for p in parts]),
        starts=np.concatenate([[0], np.cumsum(np.concatenate([p.lengths for p in parts]))]).astype(np.int64),
        actions=np.concatenate([p.actions for p in parts]),
        modes=np.concatenate([p.modes for p in parts]),
        subjects=np.concatenate([p.subjects for p in parts]),
        names=tuple(n for p in parts for n in p.names),
        segments=None if first.segments is None else concatenate_segments([p.segments for p in parts],
                                                                          [len(p) for p in parts]),
    )


def person_axis(array: np.ndarray | None, persons: int, *, axis: int) -> np.ndarray | None:
    """``array`` with its persons axis at ``axis``, inserted (of size 1) when ``persons`` is 1: one code path
    for one and several persons. ``axis``: where P sits (0 for a ``Motion``'s arrays, 1 for a dataset's
    packed ones and for batches)."""
    if array is None:
        return None
    return np.expand_dims(array, axis) if persons == 1 else array


def _expect(array: np.ndarray, shape: tuple[int, ...], field: str, named: str) -> None:
    if not isinstance(array, np.ndarray) or array.shape != shape:
        got = getattr(array, "shape", type(array).__name__)
        raise ValueError(f"{field}: expected shape {named} = {shape}, got {got}")


def on_the_floor(data: MotionDataset) -> MotionDataset:
    """``data`` placed as people stand: each sequence lifted along +Y so that its lowest joint at its first frame
    (over all its persons) touches the floor, y = 0. Joints and translation move; rotations do not. Generated
    motions are placed so before they are drawn or exported (a model's own frame may put the pelvis at 0)."""
    firsts = data.joints[data.starts[:-1]]  # [N, (P,) J, 3]
    lift = -firsts[..., 1].reshape(len(data), -1).min(axis=1)  # [N]
    per_frame = np.repeat(lift, np.diff(data.starts)).astype(np.float32)  # [F]
    up = np.array([0.0, 1.0, 0.0], np.float32)
    joints = data.joints + per_frame.reshape((-1,) + (1,) * (data.joints.ndim - 1)) * up
    translation = data.translation + per_frame.reshape((-1,) + (1,) * (data.translation.ndim - 1)) * up
    return dataclasses.replace(data, joints=joints, translation=translation)
