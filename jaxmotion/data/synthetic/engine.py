"""Turning variant specs into packed datasets: per-sequence generators, posing, FK, grounding, noise.

Per sequence (numpy, vectorised over frames): its own generator from ``SeedSequence([seed, variant,
split, index])`` picks the subject and length; the class's ``perform`` builds anatomical angles and the
foot support; :func:`take.finish` adds secondary motion and applies the joint limits. Per chunk of
sequences (jax, all frames at once, always ``_CHUNK_FRAMES`` of them so each pass compiles once): angles
-> rotations -> FK about the origin; then per sequence the root path (:mod:`grounding`), which a
variant's capture-noise model may perturb along with the angles (whose rotations are then recomputed);
finally rotations -> float32 axis-angle (what is stored) -> FK along the root path from exactly those,
so ``joints == forward_kinematics(rotations, translation)``.

Speed, measured on a 2-core CPU: synth-uestc's 24 000 sequences (2.3 M frames) take ~87 s, ~3.4 ms per
sequence, most of it numpy posing; the one-off compilation of the three jax passes takes ~5 s per
process (the engine before fixed-size chunks and the jax angle conversion: ~157 s).
"""

from __future__ import annotations

import dataclasses
import zlib
from collections.abc import Callable, Iterator, Mapping

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.data.motion import MotionDataset
from jaxmotion.data.synthetic import anatomy, grounding
from jaxmotion.data.synthetic.body import Subject, sample_subject
from jaxmotion.data.synthetic.take import Take, finish
from jaxmotion.geometry import rotations
from jaxmotion.geometry.kinematics import (
    forward_kinematics,
    forward_kinematics_transforms,
)
from jaxmotion.geometry.skeletons import SMPL24
from jaxmotion.progress import Progress

_PARENTS = SMPL24.parents
_ANKLES = (SMPL24.index("left_ankle"), SMPL24.index("right_ankle"))
_TOES = (SMPL24.index("left_foot"), SMPL24.index("right_foot"))
_SUBJECT_STREAM = 1_000_003  # keeps subject generators apart from the per-split sequence generators
# Every FK batch is padded to exactly this many frames (about 340 sequences), so it compiles once.
_CHUNK_FRAMES = 32768


@dataclasses.dataclass(frozen=True)
class ActionClass:
    """An action class: its name, its style modes and the function that performs it into a take."""

    name: str
    modes: tuple[str, ...]
    perform: Callable[[Take], None]
    weight: float = 1.0  # relative share of the variant's sequences


@dataclasses.dataclass(frozen=True)
class Split:
    """A split: how many sequences and which subjects perform them."""

    num_sequences: int
    subjects: tuple[int, ...]


@dataclasses.dataclass(frozen=True)
class Variant:
    """A dataset stand-in.

    Attributes:
      name: e.g. ``synth-humanact12``.
      classes: the action classes, in label order.
      fps: frame rate.
      lengths: ``(min, max)`` sequence length in frames (inclusive), drawn uniformly per sequence.
      splits: split name -> :class:`Split`.
      noise: optional capture-noise model ``(angles [T, J, 3], translation [T, 3], joints [T, J, 3], subject,
        fps, rng) -> (angles, translation)``: from the clean anatomical angles (degrees), the grounded root
        path and the clean body posed about the origin, the noisy angles (within the joint limits) and
        root path that are stored; None for clean motion.
    """

    name: str
    classes: tuple[ActionClass, ...]
    fps: float
    lengths: tuple[int, int]
    splits: Mapping[str, Split]
    noise: Callable | None = None

    @property
    def class_names(self) -> tuple[str, ...]:
        return tuple(c.name for c in self.classes)

    @property
    def mode_names(self) -> tuple[tuple[str, ...], ...]:
        return tuple(c.modes for c in self.classes)

    @property
    def subjects(self) -> tuple[int, ...]:
        return tuple(sorted({s for split in self.splits.values() for s in split.subjects}))


def _key(text: str) -> int:
    return zlib.crc32(text.encode())


def subject(variant: Variant, index: int, seed: int) -> Subject:
    """Subject ``index`` of ``variant`` (the same body in every split and sequence)."""
    rng = np.random.default_rng(np.random.SeedSequence([seed, _key(variant.name), _SUBJECT_STREAM, index]))
    return sample_subject(index, rng)


def schedule(variant: Variant, split: str) -> tuple[np.ndarray, np.ndarray]:
    """``(actions [N], modes [N])`` of a split, interleaved so that any prefix is nearly balanced.

    Class c gets ``round(N w_c / sum w)`` sequences; its k-th sequence sits at position (k + 1/2) / n_c
    of the split and uses mode k mod (number of modes).
    """
    n = variant.splits[split].num_sequences
    weights = np.array([c.weight for c in variant.classes])
    counts = np.floor(n * weights / weights.sum()).astype(int)
    counts[np.argsort(-(n * weights / weights.sum() - counts), kind="stable")[: n - counts.sum()]] += 1
    position = np.concatenate([(np.arange(k) + 0.5) / k for k in counts])
    actions = np.repeat(np.arange(len(counts)), counts)
    modes = np.concatenate([np.arange(k) % len(c.modes) for k, c in zip(counts, variant.classes)])
    order = np.lexsort((actions, position))
    return actions[order].astype(np.int32), modes[order].astype(np.int32)


@dataclasses.dataclass(frozen=True)
class _Posed:
    angles: np.ndarray  # [T, J, 3] degrees, within the joint limits
    contact: np.ndarray  # [T, 2]
    ground: np.ndarray  # [T, 2] metres
    heading: np.ndarray  # [T] radians
    flight_speed: float
    flight_carry: float
    subject: Subject
    rng: np.random.Generator


def _perform(variant: Variant, split: str, seed: int, index: int, action: int, mode: int,
             bodies: Mapping[int, Subject]) -> _Posed:
    rng = np.random.default_rng(np.random.SeedSequence([seed, _key(variant.name), _key(split), index]))
    who = bodies[int(rng.choice(variant.splits[split].subjects))]
    num_frames = int(rng.integers(variant.lengths[0], variant.lengths[1] + 1))
    cls = variant.classes[action]
    take = Take(num_frames, variant.fps, rng, who, cls.modes[mode])
    cls.perform(take)
    angles = finish(take)
    return _Posed(angles, take.contact, take.ground, np.radians(angles[:, 0, 0]), take.flight_speed, take.flight_carry,
                  who, rng)


# --- jax passes over a chunk of frames -------------------------------------------------------------------

@jax.jit
def _pose_about_origin(rotmats, offsets):
    """``[F, J, 3, 3]`` f32, ``[F, J, 3]`` offsets -> (joints about the origin, ankles' global rotations)."""
    global_rot, joints = forward_kinematics_transforms(
        rotmats, jnp.zeros(rotmats.shape[:1] + (3,)), offsets, _PARENTS)
    return joints, global_rot[:, list(_ANKLES)]


@jax.jit
def _pose_in_world(rotmats, translation, offsets):
    """-> (stored float32 axis-angle ``[F, J, 3]``, its FK along ``translation``)."""
    axis_angle = rotations.matrix_to_axis_angle(rotmats)
    return axis_angle, forward_kinematics(rotations.axis_angle_to_matrix(axis_angle), translation, offsets,
                                          _PARENTS)


def _padded(array: np.ndarray) -> np.ndarray:
    """``array [F, ...]`` zero-padded to ``[_CHUNK_FRAMES, ...]`` float32."""
    out = np.zeros((_CHUNK_FRAMES,) + array.shape[1:], np.float32)
    out[: len(array)] = array
    return out


def _chunk(variant: Variant, posed: list[_Posed]):
    """FK, grounding and (optional) capture noise for posed sequences of at most ``_CHUNK_FRAMES`` frames.

    The clean body is posed about the origin and grounded; a noise model then perturbs its angles and
    root path; the stored rotations are posed along that path.
    """
    lengths = [len(p.angles) for p in posed]
    starts = np.concatenate([[0], np.cumsum(lengths)])
    offsets = _padded(np.concatenate([np.broadcast_to(p.subject.offsets, (n, 24, 3))
                                      for p, n in zip(posed, lengths)]))
    angles = np.concatenate([p.angles for p in posed])
    rotmats = anatomy.angles_to_rotmats_f32(_padded(angles))
    about_origin, ankle_rot = (np.asarray(a)[: starts[-1]] for a in _pose_about_origin(rotmats, offsets))
    translation = np.zeros((starts[-1], 3), np.float32)
    for i, p in enumerate(posed):
        frames = slice(starts[i], starts[i + 1])
        joints = about_origin[frames]
        soles = np.stack([
            grounding.sole_points(joints[:, a], ankle_rot[frames, k], joints[:, toe],
                                  p.subject.offsets[toe], p.subject.height / 1.70)
            for k, (a, toe) in enumerate(zip(_ANKLES, _TOES))], axis=1)
        root = grounding.root_translation(soles, p.contact, p.ground, p.heading, variant.fps, p.flight_speed,
                                          p.flight_carry)
        if variant.noise is not None:
            angles[frames], root = variant.noise(p.angles, root, joints, p.subject, variant.fps, p.rng)
        translation[frames] = root
    if variant.noise is not None:
        rotmats = anatomy.angles_to_rotmats_f32(_padded(angles))
    axis_angle, joints = (np.asarray(a)[: starts[-1]] for a in _pose_in_world(rotmats, _padded(translation),
                                                                               offsets))
    return axis_angle, translation, joints, starts


def _batches(posed: Iterator[_Posed]) -> Iterator[list[_Posed]]:
    """Consecutive runs of posed sequences with at most ``_CHUNK_FRAMES`` frames in all."""
    batch, frames = [], 0
    for p in posed:
        if batch and frames + len(p.angles) > _CHUNK_FRAMES:
            yield batch
            batch, frames = [], 0
        batch.append(p)
        frames += len(p.angles)
    if batch:
        yield batch


def generate_split(variant: Variant, split: str, seed: int, count: int | None = None, *,
                   progress: bool = False) -> MotionDataset:
    """The first ``count`` (default: all) sequences of one split, packed; ``progress``: a progress line with an
    ETA on stderr (a full split takes minutes)."""
    actions, modes = schedule(variant, split)
    if count is not None:
        actions, modes = actions[:count], modes[:count]
    bodies = {s: subject(variant, s, seed) for s in variant.splits[split].subjects}
    posed = (_perform(variant, split, seed, i, int(a), int(m), bodies) for i, (a, m) in enumerate(zip(actions, modes)))
    parts, subjects = [], []
    bar = Progress(len(actions), unit="sequence", label=f"[data] generating {variant.name}/{split}") if progress else None
    for batch in _batches(posed):
        subjects += [p.subject.index for p in batch]
        parts.append(_chunk(variant, batch))
        if bar is not None:
            bar.update(len(subjects), {})
    if bar is not None:
        bar.close()
    lengths = np.concatenate([np.diff(p[3]) for p in parts]) if parts else np.zeros(0, int)
    empty = np.zeros((0, 24, 3), np.float32)
    return MotionDataset(
        name=variant.name, split=split, class_names=variant.class_names, skeleton=SMPL24, fps=variant.fps,
        joints=np.concatenate([p[2] for p in parts]) if parts else empty,
        translation=np.concatenate([p[1] for p in parts]) if parts else np.zeros((0, 3), np.float32),
        rotations=np.concatenate([p[0] for p in parts]) if parts else empty,
        starts=np.concatenate([[0], np.cumsum(lengths)]).astype(np.int64),
        actions=actions, modes=modes, subjects=np.array(subjects, np.int32),
        names=tuple(f"{variant.name}-{split}-{i:06d}" for i in range(len(actions))),
        mode_names=variant.mode_names,
    )
