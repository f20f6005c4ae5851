"""Turning variant specs into packed datasets: per-sequence generators, posing, FK, grounding, noise.

Per sequence (numpy, vectorised over frames): its own generator from ``SeedSequence([seed, variant,
split, index])`` picks the subject and length; the class's ``perform`` builds anatomical angles and the
foot support; :func:`take.finish` adds secondary motion and applies the joint limits. Per chunk of
sequences (jax, all frames at once, always ``_CHUNK_FRAMES`` of them so each pass compiles once): angles
-> rotations -> FK about the origin; then per sequence the root path (:mod:`grounding`), which a
variant's capture-noise model may perturb along with the angles (whose rotations are then recomputed);
finally rotations -> float32 axis-angle (what is stored) -> FK along the root path from exactly those,
so ``joints == forward_kinematics(rotations, translation)``. A variant on another skeleton (NTU-25,
GTA-22) reads its joints off that body through a marker set (:mod:`jaxmotion.geometry.markers`), applies
its capture model to them and stores joints only.

Speed, measured on a 2-core CPU: synth-uestc's 24 000 sequences (2.3 M frames) take ~87 s, ~3.4 ms per
sequence, most of it numpy posing; the one-off compilation of the three jax passes takes ~5 s per
process (the engine before fixed-size chunks and the jax angle conversion: ~157 s).
"""

from __future__ import annotations

import dataclasses
import functools
import zlib
from collections.abc import Callable, Iterator, Mapping, Sequence

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.data.motion import MotionDataset
from jaxmotion.data.segments import Segments
from jaxmotion.data.synthetic import anatomy, grounding
from jaxmotion.data.synthetic.body import Subject, sample_subject
from jaxmotion.data.synthetic.chain import TakePlan, perform_plan
from jaxmotion.data.synthetic.scene import Scene, SceneClass, pose_scenes
from jaxmotion.data.synthetic.take import Take, finish
from jaxmotion.geometry import rotations
from jaxmotion.geometry.kinematics import (
    forward_kinematics,
    forward_kinematics_transforms,
)
from jaxmotion.geometry.markers import MarkerSet, markers_from_rotations
from jaxmotion.geometry.skeletons import SMPL24, Skeleton
from jaxmotion.progress import phase

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
      markers: the output skeleton's joints as markers on the SMPL-24 body; then only joints are stored
        (``rotations`` None, ``translation`` = joint 0). None: SMPL-24 joints and rotations.
      joint_noise: optional capture model of the output joints ``(joints [T, K, 3], skeleton, fps, rng) ->
        joints`` (with ``markers`` only), e.g. :class:`~noise.KinectNoise`.
      stream: the variant whose random streams (subjects, sequences) this one draws, to store the same
        motions another way (the same takes, another skeleton or capture model); default its own name.
      persons: P; with P >= 2 the classes are :class:`~scene.SceneClass` es performed by P distinct subjects
        of the split (the clip's subject label is the first person's).
      swapped_copies: also store each clip with its persons in reverse order, right after it, named
        ``...-flip`` (ActFormer's two-person splits hold these).
      takes: for a variant of multi-action takes, ``(split, seed) -> plans`` (:class:`~chain.TakePlan`: a lead-in
        and the actions, each with its perform function, tags, mode and length); the sequences are those takes,
        joined by :mod:`chain`, with their :class:`~jaxmotion.data.segments.Segments`; ``classes`` are then the
        tags, and a split's ``num_sequences`` is not read (the plan decides). None: one action per sequence.
    """

    name: str
    classes: tuple[ActionClass, ...]
    fps: float
    lengths: tuple[int, int]
    splits: Mapping[str, Split]
    noise: Callable | None = None
    markers: MarkerSet | None = None
    joint_noise: Callable | None = None
    stream: str | None = None
    persons: int = 1
    swapped_copies: bool = False
    takes: Callable[[str, int], Sequence[TakePlan]] | None = None

    def __post_init__(self):
        if self.joint_noise is not None and self.markers is None:
            raise ValueError(f"{self.name}: joint_noise acts on marker joints; give markers too")
        scenes = {isinstance(c, SceneClass) for c in self.classes}
        if scenes != {self.persons > 1}:
            raise ValueError(f"{self.name}: {self.persons} person(s) need "
                             f"{'SceneClass' if self.persons > 1 else 'ActionClass'} classes")
        if self.swapped_copies and self.persons < 2:
            raise ValueError(f"{self.name}: swapped_copies needs several persons")
        if self.takes is not None and (self.persons > 1 or self.noise is not None or self.markers is not None):
            raise ValueError(f"{self.name}: multi-action takes are of one person, without capture models")
        for name, split in self.splits.items():
            if len(split.subjects) < self.persons:
                raise ValueError(f"{self.name}/{name}: {len(split.subjects)} subjects for scenes of {self.persons}")

    @property
    def skeleton(self) -> Skeleton:
        return SMPL24 if self.markers is None else self.markers.skeleton

    @property
    def seed_name(self) -> str:
        return self.stream or self.name

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
    rng = np.random.default_rng(np.random.SeedSequence([seed, _key(variant.seed_name), _SUBJECT_STREAM, index]))
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
    flight_speed: float | np.ndarray  # one value, or [T] (a multi-action take)
    flight_carry: float | np.ndarray
    subject: Subject
    rng: np.random.Generator


def _sequence_rng(variant: Variant, split: str, seed: int, index: int) -> np.random.Generator:
    return np.random.default_rng(np.random.SeedSequence([seed, _key(variant.seed_name), _key(split), index]))


def _perform(variant: Variant, split: str, seed: int, index: int, action: int, mode: int,
             bodies: Mapping[int, Subject]) -> _Posed:
    rng = _sequence_rng(variant, split, seed, index)
    who = bodies[int(rng.choice(variant.splits[split].subjects))]
    num_frames = int(rng.integers(variant.lengths[0], variant.lengths[1] + 1))
    cls = variant.classes[action]
    take = Take(num_frames, variant.fps, rng, who, cls.modes[mode])
    cls.perform(take)
    angles = finish(take)
    return _Posed(angles, take.contact, take.ground, np.radians(angles[:, 0, 0]), take.flight_speed, take.flight_carry,
                  who, rng)


def _perform_take(variant: Variant, split: str, seed: int, index: int, plan: TakePlan,
                  bodies: Mapping[int, Subject]) -> _Posed:
    """Take ``index`` of a split of multi-action takes, performed and joined (:mod:`chain`)."""
    rng = _sequence_rng(variant, split, seed, index)
    who = bodies[int(rng.choice(variant.splits[split].subjects))]
    joined = perform_plan(plan, variant.fps, rng, who)
    return _Posed(joined.angles, joined.contact, joined.ground, np.radians(joined.angles[:, 0, 0]),
                  joined.flight_speed, joined.flight_carry, who, rng)


def plan_segments(plans: Sequence[TakePlan], num_tags: int) -> Segments:
    """The segment table of planned takes: each action's frames, tags, the next action's tags (its own for the
    last) and mode."""
    rows = []
    for i, plan in enumerate(plans):
        start = plan.lead_in.frames
        for k, action in enumerate(plan.actions):
            after = plan.actions[k + 1] if k + 1 < len(plan.actions) else action
            rows.append((i, start, start + action.frames, action.tags, after.tags, action.mode_index))
            start += action.frames
    return Segments.from_rows(rows, num_tags)


def _stage(variant: Variant, split: str, seed: int, index: int, action: int, mode: int,
           bodies: Mapping[int, Subject]) -> Scene:
    """Scene ``index`` of a split of several persons, performed (not yet posed)."""
    rng = _sequence_rng(variant, split, seed, index)
    pool = variant.splits[split].subjects
    who = [bodies[pool[int(i)]] for i in rng.choice(len(pool), variant.persons, replace=False)]
    num_frames = int(rng.integers(variant.lengths[0], variant.lengths[1] + 1))
    cls = variant.classes[action]
    scene = Scene(num_frames, variant.fps, rng, who, cls.modes[mode])
    cls.perform(scene)
    return scene


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


@functools.partial(jax.jit, static_argnames="markers")
def _markers(markers, axis_angle, translation, offsets):
    return markers_from_rotations(markers, axis_angle, translation, offsets)


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
    padded_translation = _padded(translation)
    axis_angle, joints = (np.asarray(a)[: starts[-1]] for a in _pose_in_world(rotmats, padded_translation, offsets))
    if variant.markers is not None:  # another skeleton: its joints off the same body, then its capture model
        joints = np.array(_markers(variant.markers, _padded(axis_angle), padded_translation, offsets))[: starts[-1]]
        axis_angle = None
        if variant.joint_noise is not None:
            for i, p in enumerate(posed):
                frames = slice(starts[i], starts[i + 1])
                joints[frames] = variant.joint_noise(joints[frames], variant.skeleton, variant.fps, p.rng)
        translation = joints[:, 0].copy()
    return axis_angle, translation, joints, starts


def _scene_chunk(variant: Variant, scenes: list[Scene]):
    """Resolve, pose and store scenes of at most ``_CHUNK_FRAMES`` frames (all persons): ``(axis-angle,
    translation, joints, starts)`` packed ``[F, P, ...]`` as :func:`_chunk` gives them for one person."""
    posed = pose_scenes(scenes, _CHUNK_FRAMES)
    people = [(scene.takes[p], angles[p], roots[p]) for scene, (angles, roots) in zip(scenes, posed)
              for p in range(scene.persons)]
    lengths = [len(a) for _, a, _ in people]
    bounds = np.concatenate([[0], np.cumsum(lengths)])
    offsets = _padded(np.concatenate([np.broadcast_to(t.subject.offsets, (n, 24, 3)) for (t, _, _), n in zip(people, lengths)]))
    rotmats = anatomy.angles_to_rotmats_f32(_padded(np.concatenate([a for _, a, _ in people])))
    translation = _padded(np.concatenate([r for _, _, r in people]))
    axis_angle, joints = (np.array(a)[: bounds[-1]] for a in _pose_in_world(rotmats, translation, offsets))
    if variant.markers is not None:
        joints = np.array(_markers(variant.markers, _padded(axis_angle), translation, offsets))[: bounds[-1]]
        for i, (take, _, _) in enumerate(people):
            if variant.joint_noise is not None:
                frames = slice(bounds[i], bounds[i + 1])
                joints[frames] = variant.joint_noise(joints[frames], variant.skeleton, variant.fps, take.rng)
        translation = joints[:, 0]
    translation = translation[: bounds[-1]]

    def per_scene(a):  # person-major frames -> [F, P, ...] scene by scene
        out, k = [], 0
        for scene in scenes:
            out.append(np.stack([a[bounds[k + p]:bounds[k + p + 1]] for p in range(scene.persons)], axis=1))
            k += scene.persons
        return np.concatenate(out)

    starts = np.concatenate([[0], np.cumsum([s.takes[0].num_frames for s in scenes])])
    return (None if variant.markers is not None else per_scene(axis_angle)), per_scene(translation), \
        per_scene(joints), starts


def _batches(items: Iterator, frames_of: Callable) -> Iterator[list]:
    """Consecutive runs of items with at most ``_CHUNK_FRAMES`` frames in all."""
    batch, frames = [], 0
    for item in items:
        if batch and frames + frames_of(item) > _CHUNK_FRAMES:
            yield batch
            batch, frames = [], 0
        batch.append(item)
        frames += frames_of(item)
    if batch:
        yield batch


def generate_split(variant: Variant, split: str, seed: int, count: int | None = None, *,
                   progress: bool = False) -> MotionDataset:
    """The first ``count`` (default: all) sequences of one split, packed; ``progress``: a progress line with an
    ETA on stderr (a full split takes minutes)."""
    segments = None
    if variant.takes is not None:
        plans = tuple(variant.takes(split, seed))[:count]
        segments = plan_segments(plans, len(variant.classes))
        firsts = np.searchsorted(segments.sequence, np.arange(len(plans)))  # each take's first action
        actions, modes = segments.primary[firsts], segments.modes[firsts]
    else:
        actions, modes = schedule(variant, split)
        if count is not None:
            actions, modes = actions[:count], modes[:count]
    bodies = {s: subject(variant, s, seed) for s in variant.splits[split].subjects}
    if variant.persons == 1:
        items = ((_perform_take(variant, split, seed, i, plan, bodies) for i, plan in enumerate(plans))
                 if variant.takes is not None else
                 (_perform(variant, split, seed, i, int(a), int(m), bodies) for i, (a, m) in enumerate(zip(actions, modes))))
        frames_of, chunk, first_subject = (lambda p: len(p.angles)), _chunk, (lambda p: p.subject.index)
    else:
        items = (_stage(variant, split, seed, i, int(a), int(m), bodies) for i, (a, m) in enumerate(zip(actions, modes)))
        frames_of, chunk = (lambda s: s.persons * s.takes[0].num_frames), _scene_chunk
        first_subject = lambda s: s.takes[0].subject.index  # noqa: E731
    parts, subjects = [], []
    bar = phase(f"[data] generating {variant.name}/{split}", len(actions), unit="sequence") if progress else None
    for batch in _batches(items, frames_of):
        subjects += [first_subject(p) for p in batch]
        parts.append(chunk(variant, batch))
        if bar is not None:
            bar.update(len(subjects), {})
    if bar is not None:
        bar.close()
    lengths = np.concatenate([np.diff(p[3]) for p in parts]) if parts else np.zeros(0, int)
    skeleton = variant.skeleton
    persons = () if variant.persons == 1 else (variant.persons,)

    def stacked(k, shape):
        return np.concatenate([p[k] for p in parts]) if parts else np.zeros((0, *persons, *shape), np.float32)

    data = MotionDataset(
        name=variant.name, split=split, class_names=variant.class_names, skeleton=skeleton, fps=variant.fps,
        joints=stacked(2, (skeleton.num_joints, 3)),
        translation=stacked(1, (3,)),
        rotations=None if variant.markers is not None else stacked(0, (24, 3)),
        starts=np.concatenate([[0], np.cumsum(lengths)]).astype(np.int64),
        actions=actions, modes=modes, subjects=np.array(subjects, np.int32),
        names=tuple(f"{variant.name}-{split}-{i:06d}" for i in range(len(actions))),
        mode_names=variant.mode_names, persons=variant.persons, segments=segments,
    )
    return with_swapped_copies(data) if variant.swapped_copies else data


def with_swapped_copies(data: MotionDataset) -> MotionDataset:
    """Each sequence followed by its copy with the persons in reverse order, named ``<name>-flip``."""
    order = np.repeat(np.arange(len(data)), 2)
    doubled = data.subset(order)
    flip = np.arange(2 * len(data)) % 2 == 1
    frames = np.repeat(flip, doubled.lengths)

    def swapped(a):
        return None if a is None else np.where(frames.reshape((-1,) + (1,) * (a.ndim - 1)), a[:, ::-1], a)

    return dataclasses.replace(
        doubled, joints=swapped(doubled.joints), translation=swapped(doubled.translation),
        rotations=swapped(doubled.rotations),
        names=tuple(n + "-flip" if f else n for n, f in zip(doubled.names, flip)))
