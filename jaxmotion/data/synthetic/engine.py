"""Turning variant specs into packed datasets: per-sequence generators, posing, FK, grounding.

Per sequence (numpy, vectorised over frames): its own generator from ``SeedSequence([seed, variant,
split, index])`` picks the subject and length; the class's ``perform`` builds anatomical angles and the
foot support; :func:`take.finish` adds secondary motion and applies the joint limits. Per chunk of
sequences (jax, all frames at once): rotations -> float32 axis-angle (what is stored), FK about the
origin, then per sequence the root path (:mod:`grounding`), then FK again from exactly the stored
float32 rotations and translation, so ``joints == forward_kinematics(rotations)``.
"""

from __future__ import annotations

import dataclasses
import zlib
from collections.abc import Callable, Mapping

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

_PARENTS = SMPL24.parents
_ANKLES = (SMPL24.index("left_ankle"), SMPL24.index("right_ankle"))
_TOES = (SMPL24.index("left_foot"), SMPL24.index("right_foot"))
_SUBJECT_STREAM = 1_000_003  # keeps subject generators apart from the per-split sequence generators
_CHUNK_SEQUENCES = 512
_FRAME_BUCKET = 8192  # pad frame batches to a multiple of this, so jit compiles only a few shapes


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
      noise: optional ``(angles [T, J, 3], translation [T, 3], rng) -> (angles, translation)`` capture-noise
        model applied to the finished motion (before the final FK), or None for clean motion.
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
    rotmats: np.ndarray  # [T, J, 3, 3]
    contact: np.ndarray  # [T, 2]
    heading: np.ndarray  # [T] radians
    flight_speed: float
    flight_carry: float
    subject: Subject
    rng: np.random.Generator


def _perform(variant: Variant, split: str, seed: int, index: int, action: int, mode: int) -> _Posed:
    rng = np.random.default_rng(np.random.SeedSequence([seed, _key(variant.name), _key(split), index]))
    who = subject(variant, int(rng.choice(variant.splits[split].subjects)), seed)
    num_frames = int(rng.integers(variant.lengths[0], variant.lengths[1] + 1))
    cls = variant.classes[action]
    take = Take(num_frames, variant.fps, rng, who, cls.modes[mode])
    cls.perform(take)
    angles = finish(take)
    return _Posed(anatomy.angles_to_rotmats(angles), take.contact, np.radians(angles[:, 0, 0]),
                  take.flight_speed, take.flight_carry, who, rng)


@jax.jit
def _pose_about_origin(rotmats, offsets):
    """``[F, J, 3, 3]`` f32, ``[F, J, 3]`` -> stored axis-angle, its FK about the origin, ankle rotations."""
    axis_angle = rotations.matrix_to_axis_angle(rotmats)
    global_rot, joints = forward_kinematics_transforms(
        rotations.axis_angle_to_matrix(axis_angle), jnp.zeros(rotmats.shape[:1] + (3,)), offsets, _PARENTS)
    return axis_angle, joints, global_rot[:, list(_ANKLES)]


@jax.jit
def _pose_in_world(axis_angle, translation, offsets):
    return forward_kinematics(rotations.axis_angle_to_matrix(axis_angle), translation, offsets, _PARENTS)


def _padded(array: np.ndarray) -> np.ndarray:
    pad = -len(array) % _FRAME_BUCKET
    return np.concatenate([array, np.zeros((pad,) + array.shape[1:], array.dtype)]) if pad else array


def _chunk(variant: Variant, posed: list[_Posed]):
    """FK, grounding and (optional) capture noise for a list of posed sequences."""
    lengths = [len(p.rotmats) for p in posed]
    starts = np.concatenate([[0], np.cumsum(lengths)])
    rotmats = np.concatenate([p.rotmats for p in posed]).astype(np.float32)
    offsets = np.concatenate([np.broadcast_to(p.subject.offsets, (n, 24, 3)) for p, n in zip(posed, lengths)])
    axis_angle, about_origin, ankle_rot = (np.asarray(a)[: starts[-1]] for a in _pose_about_origin(
        _padded(rotmats), _padded(offsets)))
    translation = np.zeros((starts[-1], 3), np.float32)
    for i, p in enumerate(posed):
        frames = slice(starts[i], starts[i + 1])
        joints = about_origin[frames]
        soles = np.stack([
            grounding.sole_points(joints[:, a], ankle_rot[frames, k], joints[:, toe],
                                  p.subject.offsets[toe], p.subject.height / 1.70)
            for k, (a, toe) in enumerate(zip(_ANKLES, _TOES))], axis=1)
        root = grounding.root_translation(soles, p.contact, p.heading, variant.fps, p.flight_speed,
                                            p.flight_carry)
        if variant.noise is not None:
            axis_angle[frames], root = variant.noise(axis_angle[frames], root, p.rng)
        translation[frames] = root
    joints = np.asarray(_pose_in_world(_padded(axis_angle), _padded(translation), _padded(offsets)))[: starts[-1]]
    return axis_angle, translation, joints, starts


def generate_split(variant: Variant, split: str, seed: int, count: int | None = None) -> MotionDataset:
    """The first ``count`` (default: all) sequences of one split, packed."""
    actions, modes = schedule(variant, split)
    if count is not None:
        actions, modes = actions[:count], modes[:count]
    parts, subjects = [], []
    for lo in range(0, len(actions), _CHUNK_SEQUENCES):
        idx = range(lo, min(lo + _CHUNK_SEQUENCES, len(actions)))
        posed = [_perform(variant, split, seed, i, int(actions[i]), int(modes[i])) for i in idx]
        subjects += [p.subject.index for p in posed]
        parts.append(_chunk(variant, posed))
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
