"""Neural Marionette put to use: one action per call of a model that continues a context (MARIONET, and the
baselines of its tables), in the world frame of the motion it continues; trained ones as loadable generators.

:func:`generate_actions` takes each action's context (its 6 preceding frames, as the library's records hold them:
axis-angle SMPL-24 rotations and root translation, in any placement), tags, next tags, duration and optional ground
path (world x, z per frame), normalises every context at its last pose (Eqs. 3-5:
:func:`~jaxmotion.geometry.kinematics.heading_transform`), turns the paths into that frame, generates frame by
frame (the model's continuation: :data:`CONTEXT_MODELS`) and brings the actions back into the world: a context
turned and moved gives the same action turned and moved (``tests/test_marionette_pipeline.py``). Joints come from
forward kinematics on the template skeleton (the mean shape, as the loss's).

:class:`ContextGenerator` is a trained one as an artefact (:func:`jaxmotion.load_generator` opens it): its model,
parameters and a bank of training starts per tag (contexts and the paths that followed them), so it generates from
tags alone (:meth:`ContextGenerator.action`, :meth:`~ContextGenerator.generate`) as well as under given conditions
(:meth:`~ContextGenerator.action_sampler`, the single-action protocol's sampler). :func:`context_free_sampler` puts
a generator that knows no context (ACTOR, the tables' reference row) through the same protocol.

Axes: B actions, K context frames, T frames (the longest duration), C tags, M starts per tag.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from types import MappingProxyType
from typing import Any, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.data.mag_tags import root_tag_mask
from jaxmotion.data.motion import MotionDataset
from jaxmotion.data.segments import label_transitions
from jaxmotion.geometry.kinematics import (apply_transform, forward_kinematics, heading_transform, inverse_transform,
                                          transform_ground_path, transform_motion)
from jaxmotion.geometry.representations import from_pose135
from jaxmotion.geometry.rotations import axis_angle_to_matrix
from jaxmotion.geometry.skeletons import SMPL24
from jaxmotion.models import marionet
from jaxmotion.models.a2m import A2MVAEConfig, a2m_continue, init_a2m_vae
from jaxmotion.models.mann import MannConfig, init_mann, mann_continue
from jaxmotion.models.marionet import CONTEXT, MarionetConfig
from jaxmotion.pipelines.artefacts import Artefact, DataFacts, SamplingGenerator, as_key, motion_records, save_artefact


class ContextModel(NamedTuple):
    """A model that continues a context in its normalised frame: its method name, ``init(key, config) -> params``
    and ``continue_(params, config, context [B, K, 135], tags, next_tags [B, C], path [B, T, 2], mask [B, T],
    key | None) -> poses [B, T, 135]`` (``key=None``: its deterministic reading)."""

    method: str
    init: Callable[..., Any]
    continue_: Callable[..., jax.Array]


#: The models that continue a context, by config type.
CONTEXT_MODELS = MappingProxyType({
    MarionetConfig: ContextModel("marionet", marionet.init_marionet, marionet.generate),
    MannConfig: ContextModel("mann", init_mann, mann_continue),  # the tables' baselines
    A2MVAEConfig: ContextModel("a2m-context", init_a2m_vae, a2m_continue),  # Action2Motion adapted
})


def context_model(config: Any) -> ContextModel:
    if type(config) not in CONTEXT_MODELS:
        raise TypeError(f"config: expected the config of a model that continues a context "
                        f"({', '.join(t.__name__ for t in CONTEXT_MODELS)}), got {type(config).__name__}")
    return CONTEXT_MODELS[type(config)]


def num_tags(config: Any) -> int:
    """The tags a context model reads (the A2M VAE calls them classes)."""
    return config.num_tags if hasattr(config, "num_tags") else config.num_classes


def continue_in_world(params: Any, config: Any, rotations: jax.Array, translation: jax.Array, tags: jax.Array,
                      next_tags: jax.Array, paths: jax.Array, follow: jax.Array, mask: jax.Array,
                      key: jax.Array | None, *, local_paths: bool = False,
                      start: Callable[[jax.Array], jax.Array] | None = None) -> dict[str, jax.Array]:
    """:func:`generate_actions` traceable, on arrays it has checked: context ``rotations [B, K, 24, 3]``,
    ``translation [B, K, 3]`` in the world frame, ``paths [B, T, 2]`` world ground points (``local_paths``: already
    in the frame of the context's last pose, normalised) -> world ``rotations``, ``translation``, ``joints``, zero
    past each action's end. ``start``: MARIONET's first decoder input from the normalised begin pose ``[B, 135] ->
    [B, d]`` (Shadow Start: :mod:`jaxmotion.pipelines.multi_action`)."""
    context, turn, shift = marionet.normalised_poses(rotations, translation, -1)
    if not local_paths:
        paths = transform_ground_path(turn, shift, paths)
    paths = jnp.where((mask & follow[:, None])[..., None], paths, 0.0)  # no path: zeros, as in training
    if start is None:
        poses = context_model(config).continue_(params, config, context, tags, next_tags, paths, mask, key)
    else:
        poses = marionet.generate(params, config, context, tags, next_tags, paths, mask, key,
                                  start=start(context[:, -1]))
    out_rotations, out_translation = transform_motion(*inverse_transform(turn, shift), *from_pose135(poses))
    joints = forward_kinematics(axis_angle_to_matrix(out_rotations), out_translation, SMPL24.offsets, SMPL24.parents,
                                check=False)
    keep = mask[..., None]
    return {"rotations": jnp.where(keep[..., None], out_rotations, 0.0), "translation": jnp.where(keep, out_translation,
            0.0), "joints": jnp.where(keep[..., None], joints, 0.0)}


_generate = jax.jit(continue_in_world, static_argnames=("config", "local_paths", "start"))


def generate_actions(params: Any, config: Any, context_rotations: np.ndarray, context_translation: np.ndarray,
                     tags: np.ndarray, next_tags: np.ndarray, durations: np.ndarray, paths: np.ndarray | None = None,
                     follow: np.ndarray | None = None, key: jax.Array | None = None, *,
                     max_frames: int | None = None) -> dict[str, np.ndarray]:
    """B actions at once, each continuing its context, by the model of ``config`` (:data:`CONTEXT_MODELS`).

    Args:
      context_rotations: ``[B, K, 24, 3]`` axis-angle (K = 6), ``context_translation [B, K, 3]``, world frame.
      tags, next_tags: ``[B, C]`` multi-hot (bool or 0/1).
      durations: ``[B]`` frames of each action, 1 to ``max_frames`` (None: the config's ``max_frames``, if any).
      paths: ``[B, T, 2]`` world ground points (x, z) of the root per frame (T at least the longest duration: the
        frames the outputs have); None: none.
      follow: ``[B]`` bool, which actions follow their path (the others get zeros, as in-place actions do in
        training); None: all of them when ``paths`` is given.
      key: samples Z (None: Z = mu, the paper's setting for its controllability figure; the model's deterministic
        reading).

    Returns:
      ``rotations [B, T, 24, 3]``, ``translation [B, T, 3]``, ``joints [B, T, 24, 3]`` in the world frame, zero past
      each action's duration, and ``mask [B, T]``, ``lengths [B]``.
    """
    context_rotations = np.asarray(context_rotations, np.float32)
    context_translation = np.asarray(context_translation, np.float32)
    batch = len(context_rotations)
    if context_rotations.shape != (batch, CONTEXT, 24, 3) or context_translation.shape != (batch, CONTEXT, 3):
        raise ValueError(f"context: expected rotations [B, {CONTEXT}, 24, 3] and translation [B, {CONTEXT}, 3], got "
                         f"{context_rotations.shape} and {context_translation.shape}")
    if not (np.isfinite(context_rotations).all() and np.isfinite(context_translation).all()):
        raise ValueError("context: expected finite rotations and translation")
    tags, next_tags = (np.asarray(a, bool) for a in (tags, next_tags))
    context_model(config)  # a model it knows
    classes = num_tags(config)
    if tags.shape != (batch, classes) or next_tags.shape != tags.shape:
        raise ValueError(f"tags, next_tags: expected [B, C] = ({batch}, {classes}), got {tags.shape} and "
                         f"{next_tags.shape}")
    durations = np.asarray(durations)
    longest = max_frames or getattr(config, "max_frames", None) or np.iinfo(np.int32).max
    if (durations.shape != (batch,) or not np.issubdtype(durations.dtype, np.integer) or not durations.size
            or durations.min() < 1 or durations.max() > longest):
        raise ValueError(f"durations: expected [B] = ({batch},) frame counts in [1, {longest}], got "
                         f"{durations.dtype} {durations.shape}" + (f" from {durations.min()} to {durations.max()}"
                                                                   if durations.size else ""))
    frames = int(durations.max()) if paths is None else np.shape(paths)[1]
    follow = np.full(batch, paths is not None) if follow is None else np.asarray(follow, bool)
    if paths is None:
        paths = np.zeros((batch, frames, 2), np.float32)
    paths = np.asarray(paths, np.float32)
    if paths.shape != (batch, frames, 2) or frames < durations.max() or not np.isfinite(paths).all():
        raise ValueError(f"paths: expected [B, T, 2] = ({batch}, T >= {durations.max()}, 2) finite ground points (T "
                         f"at least the longest duration), got {paths.shape}")
    if follow.shape != (batch,):
        raise ValueError(f"follow: expected [B] = ({batch},) bool, got shape {follow.shape}")
    mask = np.arange(frames)[None] < durations[:, None]
    out = _generate(params, config, jnp.asarray(context_rotations), jnp.asarray(context_translation),
                    jnp.asarray(tags, jnp.float32), jnp.asarray(next_tags, jnp.float32), jnp.asarray(paths),
                    jnp.asarray(follow), jnp.asarray(mask), key)
    return {**{k: np.asarray(v) for k, v in out.items()}, "mask": mask, "lengths": durations.astype(np.int64)}


def place_after(context_rotations: jax.Array, context_translation: jax.Array, rotations: jax.Array,
                translation: jax.Array) -> tuple[jax.Array, jax.Array]:
    """A motion made in the canonical frame (``rotations [B, T, 24, 3]``, ``translation [B, T, 3]``: the root of its
    first frame over the origin, facing +Z) put where its context ends (``context_rotations [B, K, 24, 3]``,
    ``context_translation [B, K, 3]``): the first root over the last context root, at its height, facing its
    heading. How a generator that reads no context (ACTOR) is placed to continue one."""
    context_rotations, context_translation, rotations, translation = (
        jnp.asarray(a) for a in (context_rotations, context_translation, rotations, translation))
    turn, shift = heading_transform(axis_angle_to_matrix(context_rotations[:, -1, 0]), context_translation[:, -1])
    start = translation[:, :1] * jnp.array([1.0, 0.0, 1.0])  # its first root to the normalised frame's origin,
    height = apply_transform(turn, shift, context_translation[:, -1:])[..., 1:2]  # at the context's height
    normalised = translation - start + jnp.concatenate([jnp.zeros_like(height), height, jnp.zeros_like(height)], -1)
    return transform_motion(*inverse_transform(turn, shift), rotations, normalised)


@jax.jit
def _placed(context_rotations, context_translation, rotations, translation) -> dict[str, jax.Array]:
    rotations, translation = place_after(context_rotations, context_translation, rotations, translation)
    joints = forward_kinematics(axis_angle_to_matrix(rotations), translation, SMPL24.offsets, SMPL24.parents,
                                check=False)
    return {"rotations": rotations, "translation": translation, "joints": joints}


def context_free_sampler(sampler: Callable[..., Mapping[str, Any]]) -> Callable[..., dict[str, np.ndarray]]:
    """A class-conditioned protocol sampler ``(key, actions [N], durations [N]) -> motions`` (ACTOR's) as the
    single-action protocol's sampler (:mod:`jaxmotion.evaluation.actions`): each action made for its label and
    duration, placed after its context (:func:`place_after`), padded to the conditions' frames. It has no
    deterministic reading: ``key=None`` is refused."""

    def action_sampler(key, conditions):
        if key is None:
            raise ValueError("key: this generator reads no context and has no Z = mu reading; ΔJPE needs one")
        durations = np.asarray(conditions["durations"], np.int32)
        motions = sampler(key, np.asarray(conditions["actions"], np.int32), durations)
        frames = np.shape(conditions["paths"])[1]
        index = np.minimum(np.arange(frames), durations[:, None] - 1)  # each one's last frame repeats
        rotations, translation = (np.take_along_axis(np.asarray(motions[k]), index.reshape(
            *index.shape, *([1] * (np.ndim(motions[k]) - 2))), axis=1) for k in ("rotations", "translation"))
        placed = _placed(conditions["context_rotations"], conditions["context_translation"], rotations, translation)
        return {k: np.asarray(v) for k, v in placed.items()}

    return action_sampler


# --- trained generators ----------------------------------------------------------------------------------------


class StartBank(NamedTuple):
    """Training starts per tag, in the normalised frame of their last context pose: ``rotations [C, M, K, 24, 3]``,
    ``translation [C, M, K, 3]``, the ground path that followed each ``paths [C, M, T, 2]`` over its ``durations
    [C, M]`` frames, and ``counts [C]`` (starts held per tag; rows past it are zero). For Shadow Start, the begin
    pose (BOP: the last context pose, normalised) of every training action ``bops [N, 135]`` and its first tag
    ``bop_labels [N]``; ``transitions [C, C]``: how often each first tag followed another in the training takes
    (:func:`~jaxmotion.data.segments.label_transitions`: pairs never seen are the paper's failure case)."""

    rotations: np.ndarray
    translation: np.ndarray
    paths: np.ndarray
    durations: np.ndarray
    counts: np.ndarray
    bops: np.ndarray
    bop_labels: np.ndarray
    transitions: np.ndarray


def start_bank(data: MotionDataset, per_tag: int = 8) -> StartBank:
    """The first ``per_tag`` actions of each tag (their first tag) of a multi-action ``data``, as :class:`StartBank`:
    what a trained generator starts from when no context is given (paths are stretched to the duration asked), and
    every action's begin pose for Shadow Start."""
    items = data.action_items(CONTEXT)
    last_context = items.data.starts[:-1, None] + np.arange(CONTEXT)
    bops = marionet.normalised_poses(jnp.asarray(items.data.rotations[last_context]),
                                     jnp.asarray(items.data.translation[last_context]), -1)[0][:, -1]
    labels = items.data.actions
    chosen = [np.flatnonzero(labels == c)[:per_tag] for c in range(data.num_classes)]
    counts = np.array([len(rows) for rows in chosen], np.int32)
    slots = np.zeros((data.num_classes, per_tag), np.int64)  # item per (tag, slot); empty slots repeat item 0
    for c, rows in enumerate(chosen):
        slots[c, :len(rows)] = rows
    durations = np.where(np.arange(per_tag) < counts[:, None], items.durations[slots], 0).astype(np.int32)
    frames = max(int(durations.max()), 1)
    index = (items.data.starts[slots][..., None]
             + np.minimum(np.arange(CONTEXT + frames), CONTEXT + np.maximum(durations, 1)[..., None] - 1))
    rotations, translation = _normalised_at_context(jnp.asarray(items.data.rotations[index]),
                                                    jnp.asarray(items.data.translation[index]))
    used = (np.arange(per_tag) < counts[:, None])[..., None, None]
    ahead = np.arange(frames) < durations[..., None]
    return StartBank(np.where(used[..., None], rotations[:, :, :CONTEXT], 0.0).astype(np.float32),
                     np.where(used, translation[:, :, :CONTEXT], 0.0).astype(np.float32),
                     np.where(ahead[..., None], translation[:, :, CONTEXT:, [0, 2]], 0.0).astype(np.float32),
                     durations, counts, np.asarray(bops, np.float32), items.data.actions.astype(np.int32),
                     label_transitions(data.segments))


@jax.jit
def _normalised_at_context(rotations: jax.Array, translation: jax.Array) -> tuple[np.ndarray, np.ndarray]:
    """``rotations [..., K + T, 24, 3]``, ``translation [..., K + T, 3]`` in the normalised frame of frame K - 1."""
    turn, shift = heading_transform(axis_angle_to_matrix(rotations[..., CONTEXT - 1, 0, :]),
                                    translation[..., CONTEXT - 1, :])
    return transform_motion(turn, shift, rotations, translation)


def _stretched(path: np.ndarray, length: int, frames: int) -> np.ndarray:
    """The first ``length`` points of ``path [T', 2]`` resampled to ``frames`` points (linear in time)."""
    source = np.linspace(0.0, 1.0, length)
    target = np.linspace(0.0, 1.0, frames)
    return np.stack([np.interp(target, source, path[:length, axis]) for axis in (0, 1)], -1).astype(np.float32)


@dataclasses.dataclass(frozen=True, eq=False)
class ContextGenerator(SamplingGenerator):
    """A trained model that continues a context (:data:`CONTEXT_MODELS`): its config, parameters, the data facts,
    the :class:`StartBank` of its training data, ``frames`` (the default duration) and ``max_frames`` (the longest
    action it trained on)."""

    model: Any
    params: Any
    facts: DataFacts
    starts: StartBank
    frames: int = 60
    max_frames: int = 120

    @property
    def method(self) -> str:
        return context_model(self.model).method

    def _root_tags(self) -> np.ndarray:
        return root_tag_mask(self.class_names)

    def tag_vector(self, tags: str | int | Sequence[str | int], where: str = "tags") -> np.ndarray:
        """``[C]`` bool from tag names or ids (one or several); an unknown one is an error naming ``where``."""
        names = self.class_names
        vector = np.zeros(len(names), bool)
        for tag in [tags] if isinstance(tags, (str, int, np.integer)) else list(tags):
            if isinstance(tag, (int, np.integer)) and not isinstance(tag, bool) and 0 <= tag < len(names):
                vector[int(tag)] = True
            elif isinstance(tag, str) and tag in names:
                vector[names.index(tag)] = True
            else:
                raise ValueError(f"{where}: {tag!r} is not one of the model's tags: {', '.join(names)} (or their ids "
                                 f"0 to {len(names) - 1})")
        if not vector.any():
            raise ValueError(f"{where}: expected at least one tag, got none")
        return vector

    def action_sampler(self) -> Callable[..., dict[str, np.ndarray]]:
        """The single-action protocol's sampler (:mod:`jaxmotion.evaluation.actions`): each action under its own
        conditions; ``key=None``: the deterministic reading (Z = mu)."""

        def sample(key, c):
            return generate_actions(self.params, self.model, c["context_rotations"], c["context_translation"],
                                    c["tags"], c["next_tags"], c["durations"], c["paths"], c["follow"], key,
                                    max_frames=self.max_frames)

        return sample

    def sampler(self):
        """The class-conditioned protocol's sampler ``(key, actions [N], durations [N]) -> motions``: action n of
        tag ``actions[n]`` (and as the next tag: the data's convention for a take's last action), from a training
        start of that tag along the path that followed it, stretched to the duration."""

        def sample(key, actions, durations):
            tags = np.eye(len(self.class_names), dtype=bool)[np.asarray(actions, np.int32)]
            none = [None] * len(tags)
            return self._rows(key, tags, tags, np.asarray(durations, np.int32), none, none, mean=False)

        return sample

    def action(self, key: jax.Array | int, tags: str | int | Sequence[str | int], duration: int, *,
               context: tuple[np.ndarray, np.ndarray] | None = None, path: np.ndarray | None = None,
               next_tags: str | int | Sequence[str | int] | None = None, mean: bool = False) -> MotionDataset:
        """One action in one call: ``tags`` (names or ids), ``duration`` frames, optionally ``context`` (``(rotations
        [6, 24, 3] axis-angle, translation [6, 3])`` world frame; None: a training start of its first tag, over the
        origin facing +Z), ``path`` (``[duration, 2]`` world ground points the root follows; None: for a
        root-motion tag without a context, the path that followed the start, stretched; else none), ``next_tags``
        (None: its own tags, as a take's last action). ``mean``: Z = mu. Returns a one-motion
        :class:`~jaxmotion.data.motion.MotionDataset` (:meth:`actions` for several in one call)."""
        return self.actions(key, [tags], [duration], contexts=[context], paths=[path], next_tags=[next_tags],
                            mean=mean)

    def actions(self, key: jax.Array | int, tags: Sequence[str | int | Sequence[str | int]],
                durations: Sequence[int], *, contexts: Sequence[tuple[np.ndarray, np.ndarray] | None] | None = None,
                paths: Sequence[np.ndarray | None] | None = None,
                next_tags: Sequence[str | int | Sequence[str | int] | None] | None = None,
                mean: bool = False) -> MotionDataset:
        """Several actions in one generation (one compilation): row n as :meth:`action` reads ``tags[n]``,
        ``durations[n]``, ``contexts[n]``, ``paths[n]``, ``next_tags[n]`` (lists of the same length; None for a list:
        None in every row). Every row draws its own Z (``mean``: Z = mu in all)."""
        count = len(tags)
        if count == 0:
            raise ValueError("tags: expected at least one action, got none")
        contexts, paths, next_tags = ([None] * count if x is None else list(x) for x in (contexts, paths, next_tags))
        for name, values in (("durations", durations), ("contexts", contexts), ("paths", paths),
                             ("next_tags", next_tags)):
            if len(values) != count:
                raise ValueError(f"{name}: expected one per action ({count}), got {len(values)}")
        for duration in durations:
            if (not isinstance(duration, (int, np.integer)) or isinstance(duration, bool)
                    or not 1 <= duration <= self.max_frames):
                raise ValueError(f"duration: expected frames from 1 to {self.max_frames} (the longest action it "
                                 f"trained on), got {duration!r}")
        vectors = np.stack([self.tag_vector(t) for t in tags])
        following = np.stack([v if n is None else self.tag_vector(n, "next_tags") for v, n in zip(vectors, next_tags)])
        rows = self._rows(as_key(key), vectors, following, np.asarray(durations, np.int32), contexts, paths, mean=mean)
        return motion_records(rows, self.facts, self.method)

    def _rows(self, key: jax.Array, vectors: np.ndarray, following: np.ndarray, lengths: np.ndarray,
              contexts: Sequence[Any], paths: Sequence[Any], *, mean: bool) -> dict[str, np.ndarray]:
        """The batch dict of actions with tags ``vectors``, next tags ``following [B, C]`` and ``lengths [B]``, each
        from its given context and path or else a training start of its first tag and the path that followed it."""
        count, frames = len(lengths), int(lengths.max())
        labels = np.argmax(vectors, axis=1).astype(np.int32)
        k_start, k_z = jax.random.split(key)
        rotations, translation, start_paths = self.starts_for(k_start, labels, lengths, frames,
                                                               np.array([c is not None for c in contexts]))
        given = np.zeros((count, frames, 2), np.float32)
        follow = (vectors & self._root_tags()).any(axis=1)
        for n, (context, path) in enumerate(zip(contexts, paths)):
            if context is not None:
                rotations[n], translation[n] = _context(context)
                follow[n] &= path is not None  # a given context has no start path to follow
            if path is not None:
                path = np.asarray(path, np.float32)
                if path.shape != (lengths[n], 2) or not np.isfinite(path).all():
                    raise ValueError(f"path: expected [duration, 2] = ({lengths[n]}, 2) finite world ground points "
                                     f"(x, z), one per frame, got shape {path.shape}")
                given[n, :lengths[n]], follow[n] = path, True
            else:
                given[n] = start_paths[n]
        out = generate_actions(self.params, self.model, rotations, translation, vectors, following, lengths, given,
                               follow, None if mean else k_z, max_frames=self.max_frames)
        return {**out, "actions": labels}

    def starts_for(self, key: jax.Array, labels: np.ndarray, durations: np.ndarray, frames: int,
                    given: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """For each label a training start of that tag drawn with ``key``: context rotations, translation and the
        path that followed it stretched to each duration ``[B, frames, 2]``. ``given [B]``: rows whose context the
        caller gives (a tag without starts is an error elsewhere)."""
        bank = self.starts
        counts = bank.counts[labels]
        missing = (counts == 0) & (True if given is None else ~given)
        if missing.any():
            name = self.class_names[int(labels[np.argmax(missing)])]
            raise ValueError(f"tags: the training data held no action of {name!r} to start from; give a context")
        picks = np.asarray(jax.random.randint(key, labels.shape, 0, np.maximum(counts, 1)))
        paths = np.zeros((len(labels), frames, 2), np.float32)
        for b, (label, pick) in enumerate(zip(labels, picks)):
            if counts[b]:
                paths[b, :durations[b]] = _stretched(bank.paths[label, pick], bank.durations[label, pick],
                                                     durations[b])
        return bank.rotations[labels, picks].copy(), bank.translation[labels, picks].copy(), paths

    def save(self, folder: str | Path) -> Path:
        return save_artefact(folder, self.method, self.model, self.facts,
                             {"params": self.params, "starts": self.starts._asdict()},
                             {"frames": self.frames, "max_frames": self.max_frames})

    @classmethod
    def load(cls, artefact: Artefact) -> ContextGenerator:
        model = context_model(artefact.model)
        template = jax.eval_shape(lambda k: model.init(k, artefact.model), jax.random.key(0))
        starts = artefact.tree("starts", {name: 0 for name in StartBank._fields})
        return cls(artefact.model, artefact.tree("params", template), artefact.facts,
                   StartBank(**{k: np.asarray(v) for k, v in starts.items()}), artefact.settings["frames"],
                   artefact.settings["max_frames"])


def _context(context: Any) -> tuple[np.ndarray, np.ndarray]:
    """``(rotations [6, 24, 3], translation [6, 3])`` checked: the frames, the shapes, finite numbers."""
    if not isinstance(context, (tuple, list)) or len(context) != 2:
        raise ValueError(f"context: expected (rotations [{CONTEXT}, 24, 3], translation [{CONTEXT}, 3]), got "
                         f"{type(context).__name__}")
    rotations, translation = (np.asarray(a, np.float32) for a in context)
    if rotations.shape != (CONTEXT, 24, 3) or translation.shape != (CONTEXT, 3):
        raise ValueError(f"context: expected the {CONTEXT} frames before the action, rotations [{CONTEXT}, 24, 3] and "
                         f"translation [{CONTEXT}, 3], got {rotations.shape} and {translation.shape}")
    if not (np.isfinite(rotations).all() and np.isfinite(translation).all()):
        raise ValueError("context: expected finite rotations and translation")
    return rotations, translation
