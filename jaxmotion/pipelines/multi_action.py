"""Neural Marionette's system: long motions of many actions, one model call per action (§4.3; S-Alg. 1, Alg. 1).

**The chain** (:func:`chain_actions`): action ``a`` of every program continues the last 6 frames of action ``a - 1``
(the first, a given context): the context is normalised at its last pose, the action generated with its tags, the
next action's tags, its duration and its path, and put back in the world frame
(:func:`~jaxmotion.pipelines.marionette.generate_actions`'s step, jitted once per action count and size). Actions
are joined without blending (the paper's evaluated pipelines). Any model that continues a context runs in it
(MARIONET, MANN, Action2Motion adapted: :data:`~jaxmotion.pipelines.marionette.CONTEXT_MODELS`).

**Shadow Start** (Eq. 6; MARIONET only: it acts on MARIONET's pose embedding): the begin pose's embedding
``f_0`` (the last context pose, normalised) is projected by least squares onto the embeddings of the ``neighbours``
nearest begin poses (L2, in embedding space) of training actions with the action's first tag, and the projection
``f*_0`` replaces ``f_0`` as the motion decoder's first input; the condition encoder reads the context as it is.
With ``normalise`` (the paper; without it, its NEURAL MARIONETTE*) ``f*_0`` is put on the sphere the neighbours
lie on: scaled to their mean norm. **Action Revision** (Alg. 1): each generated action is classified by the
revision classifier (its first tag is the answer expected); a wrong one is generated once more with Shadow Start
and a fresh Z, and kept without a second check.

Where the paper is silent ([U] in MARIONETTE.md §2), chosen here: ``neighbours`` 8 (a tag with fewer training
actions uses all it has; with none, ``f_0`` stays); the radius of the "L2 normalisation" (unit length would put
the decoder's first input far from every pose embedding it was trained on, whose norms are those of ReLU features
of width d; the neighbours' mean norm keeps ``f*_0`` among them); the decoder's first input replaced, not the
encoder's context; a regenerated action draws a new Z; an action is "correct" when the classifier's top class is its
first tag (the evaluator's label, so AR and Acc agree on what counts).

Axes: B programs, A actions, K = 6 context frames, T frames (the longest action), C tags, N bank entries, d width.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Callable, Mapping
from typing import Literal

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.config import check_at_least
from jaxmotion.data.segments import Program
from jaxmotion.geometry.kinematics import forward_kinematics, heading_transform, transform_ground_path, transform_motion
from jaxmotion.geometry.rotations import (axis_angle_to_matrix, axis_angle_to_quaternion, quaternion_to_axis_angle,
                                         slerp)
from jaxmotion.geometry.skeletons import SMPL24
from jaxmotion.models import marionet
from jaxmotion.models.marionet import CONTEXT, MarionetConfig
from jaxmotion.models.recognition import Recognizer
from jaxmotion.pipelines.marionette import ContextGenerator, StartBank, continue_in_world, num_tags


@dataclasses.dataclass(frozen=True)
class ChainOptions:
    """How the chain corrects itself (Table 5's rows): ``shadow_start`` ``"never"`` (the pure pipeline), ``"always"``
    (every action starts from its shadow: MARIONET+SS) or ``"revision"`` (Action Revision: actions the classifier
    rejects are generated once more with Shadow Start); ``neighbours`` (N of Eq. 6) and ``normalise`` (False: NEURAL
    MARIONETTE*); ``smoothing``: frames over which an action that started from its shadow is blended in from the
    previous action's last pose (the paper's interface, §6: every joint's rotation by slerp, the root linearly,
    weight ``(k + 1) / (smoothing + 1)`` on frame k's own pose); 0, the paper's tables: off. ``orientation``: the
    interface's start orientation check (the supplement's §5.2): an action that follows a path whose first frames head
    where no training start of its tag headed, relative to the body's facing, starts from its context turned about
    the vertical until they do (:func:`heading_ranges`; smoothed in like a shadowed start); off in the tables."""

    shadow_start: Literal["never", "always", "revision"] = "never"
    neighbours: int = 8
    normalise: bool = True
    smoothing: int = 0
    orientation: bool = False

    def __post_init__(self):
        if self.shadow_start not in ("never", "always", "revision"):
            raise ValueError(f"ChainOptions.shadow_start: expected 'never', 'always' or 'revision', got "
                             f"{self.shadow_start!r}")
        check_at_least(self, 1, "neighbours")
        check_at_least(self, 0, "smoothing")


@functools.partial(jax.jit, static_argnames=("neighbours", "normalise"))
def shadow_start(params: marionet.MarionetParams, begin: jax.Array, labels: jax.Array, embedded: jax.Array,
                 bank_labels: jax.Array, *, neighbours: int, normalise: bool) -> jax.Array:
    """Eq. 6: ``begin [B, 135]`` (normalised begin poses), ``labels [B]`` (first tags), ``embedded [N, d]`` (the
    training begin poses' embeddings, :func:`~jaxmotion.models.marionet.embed_poses`) with ``bank_labels [N]`` ->
    ``f*_0 [B, d]``; rows whose tag has no bank entry keep ``f_0``."""
    f0 = marionet.embed_poses(params, begin)  # [B, d]
    distance = jnp.sum((f0[:, None] - embedded[None]) ** 2, axis=-1)  # [B, N]
    same = bank_labels[None] == labels[:, None]
    count = min(neighbours, embedded.shape[0])
    _, nearest = jax.lax.top_k(-jnp.where(same, distance, jnp.inf), count)  # [B, n]
    valid = jnp.take_along_axis(same, nearest, axis=1)  # a tag with fewer entries than n: the others dropped
    basis = jnp.where(valid[..., None], embedded[nearest], 0.0)  # [B, n, d]
    weights = jax.vmap(lambda f, b: jnp.linalg.lstsq(b.T, f)[0])(f0, basis)  # Phi*: [B, n]
    projected = jnp.einsum("bn,bnd->bd", weights, basis)
    if normalise:
        radius = jnp.sum(jnp.linalg.norm(basis, axis=-1), axis=1) / jnp.maximum(jnp.sum(valid, axis=1), 1)
        projected = projected * (radius / jnp.maximum(jnp.linalg.norm(projected, axis=-1), 1e-12))[:, None]
    return jnp.where(valid.any(axis=1)[:, None], projected, f0)


#: The orientation check's allowance beyond the directions the training starts took ([U]: the paper's range is the
#: training data's), and the least a path must move over its first frames to have a direction (metres).
HEADING_MARGIN = np.deg2rad(15.0)
HEADING_MIN_TRAVEL = 0.05


def heading_ranges(bank: StartBank, margin: float = HEADING_MARGIN) -> np.ndarray:
    """Per tag, the directions in which the root moved over the first frames (up to :data:`CONTEXT`) of its training
    starts, relative to the body's facing (angle ``atan2(x, z)`` in the normalised frame: 0 straight ahead, +pi/2 to
    the body's left) -> ``[C, 3]``: their circular mean and the least and most offsets from it, widened by
    ``margin``; a tag none of whose starts moves :data:`HEADING_MIN_TRAVEL` gets the whole circle (no check)."""
    ranges = np.tile([0.0, -np.pi, np.pi], (len(bank.counts), 1))
    for tag, count in enumerate(bank.counts):
        ahead = bank.paths[tag, np.arange(count), np.clip(bank.durations[tag, :count] - 1, 0, CONTEXT - 1)]
        ahead = ahead[np.linalg.norm(ahead, axis=-1) >= HEADING_MIN_TRAVEL]
        if len(ahead):
            angles = np.arctan2(ahead[:, 0], ahead[:, 1])
            mean = np.arctan2(np.sin(angles).mean(), np.cos(angles).mean())
            offsets = np.angle(np.exp(1j * (angles - mean)))
            ranges[tag] = [mean, max(offsets.min() - margin, -np.pi), min(offsets.max() + margin, np.pi)]
    return ranges.astype(np.float32)


def _oriented(rotations: jax.Array, translation: jax.Array, labels: jax.Array, paths: jax.Array, follow: jax.Array,
              durations: jax.Array, ranges: jax.Array) -> tuple[jax.Array, jax.Array, jax.Array]:
    """The orientation check (:class:`ChainOptions`): contexts ``rotations [B, K, 24, 3]``, ``translation [B, K, 3]``
    (world) turned about the vertical through their last root where the followed world ``paths [B, T, 2]`` start
    outside their first tag's range (``labels [B]``, :func:`heading_ranges` ``ranges [C, 3]``) -> the contexts and
    the turn ``[B]`` (radians, about +Y; 0 where none)."""
    to_local, shift = heading_transform(axis_angle_to_matrix(rotations[:, -1, 0]), translation[:, -1])
    local = transform_ground_path(to_local, shift, paths)  # [B, T, 2], the body at the origin facing +Z
    ahead = jnp.take_along_axis(local, jnp.clip(durations - 1, 0, CONTEXT - 1)[:, None, None], axis=1)[:, 0]
    mean, low, high = ranges[labels].T
    offset = jnp.angle(jnp.exp(1j * (jnp.arctan2(ahead[:, 0], ahead[:, 1]) - mean)))
    moves = follow & (jnp.linalg.norm(ahead, axis=-1) >= HEADING_MIN_TRAVEL)
    turn = jnp.where(moves, offset - jnp.clip(offset, low, high), 0.0)
    cos, sin, zero, one = jnp.cos(turn), jnp.sin(turn), jnp.zeros_like(turn), jnp.ones_like(turn)
    about_y = jnp.stack([jnp.stack([cos, zero, sin], -1), jnp.stack([zero, one, zero], -1),
                         jnp.stack([-sin, zero, cos], -1)], -2)  # [B, 3, 3]: +Z turned by `turn` towards +X
    pivot = translation[:, -1] * jnp.array([1.0, 0.0, 1.0])
    shift = pivot - jnp.einsum("bij,bj->bi", about_y, pivot)
    turned_rotations, turned_translation = transform_motion(about_y, shift, rotations, translation)
    kept = turn == 0  # those as they were, bitwise
    return (jnp.where(kept[:, None, None, None], rotations, turned_rotations),
            jnp.where(kept[:, None, None], translation, turned_translation), turn)


@functools.partial(jax.jit, static_argnames=("config", "local_paths", "options"))
def _action_step(params, config, embedded, bank_labels, ranges, rotations, translation, tags, next_tags, paths,
                 follow, mask, key, shadowed, *, local_paths: bool, options: ChainOptions) -> dict[str, jax.Array]:
    """One action of every program (``shadowed [B]``: rows that start from their shadow; ``embedded``: the Shadow
    Start bank's embeddings; ``ranges``: :func:`heading_ranges`) and the next context."""
    last_rotations, last_translation = rotations[:, -1], translation[:, -1]
    turn = jnp.zeros(rotations.shape[0], rotations.dtype)
    if options.orientation:
        rotations, translation, turn = _oriented(rotations, translation, jnp.argmax(tags, axis=-1), paths, follow,
                                                 jnp.sum(mask, axis=1), ranges)

    def start(begin):  # the normalised begin pose exists inside the step only
        shadow = shadow_start(params, begin, jnp.argmax(tags, axis=-1), embedded, bank_labels,
                              neighbours=options.neighbours, normalise=options.normalise)
        return jnp.where(shadowed[:, None], shadow, marionet.embed_poses(params, begin))

    out = continue_in_world(params, config, rotations, translation, tags, next_tags, paths, follow, mask, key,
                            local_paths=local_paths, start=None if options.shadow_start == "never" else start)
    if options.smoothing:  # from the pose before, as it was
        out = _smoothed(out, last_rotations, last_translation, shadowed | (turn != 0), mask, options.smoothing)
    out["turned"] = turn
    durations = jnp.sum(mask, axis=1)
    index = durations[:, None] + jnp.arange(CONTEXT)  # the last K frames of context + action
    out["next_rotations"] = _take(jnp.concatenate([rotations, out["rotations"]], axis=1), index)
    out["next_translation"] = _take(jnp.concatenate([translation, out["translation"]], axis=1), index)
    return out


def _smoothed(out: dict[str, jax.Array], last_rotations: jax.Array, last_translation: jax.Array, rows: jax.Array,
              mask: jax.Array, frames: int) -> dict[str, jax.Array]:
    """The first ``frames`` frames of the actions of ``rows [B]`` blended in from the pose before them
    (``last_rotations [B, 24, 3]``, ``last_translation [B, 3]``): :class:`ChainOptions`' ``smoothing``."""
    weight = jnp.minimum((jnp.arange(mask.shape[1]) + 1.0) / (frames + 1.0), 1.0)  # [T]: 1 from frame `frames` on
    weight = jnp.where(rows[:, None], weight[None], 1.0)  # [B, T]
    before = axis_angle_to_quaternion(last_rotations)[:, None]  # [B, 1, 24, 4]
    rotations = quaternion_to_axis_angle(slerp(before, axis_angle_to_quaternion(out["rotations"]), weight[..., None]))
    translation = (1.0 - weight[..., None]) * last_translation[:, None] + weight[..., None] * out["translation"]
    joints = forward_kinematics(axis_angle_to_matrix(rotations), translation, SMPL24.offsets, SMPL24.parents,
                                check=False)
    keep = (mask & rows[:, None])[..., None]  # the other rows as they were, bitwise
    return {**out, "rotations": jnp.where(keep[..., None], rotations, out["rotations"]),
            "translation": jnp.where(keep, translation, out["translation"]),
            "joints": jnp.where(keep[..., None], joints, out["joints"])}


_embedded_bank = jax.jit(marionet.embed_poses)


def _take(frames: jax.Array, index: jax.Array) -> jax.Array:
    """``frames [B, F, ...]`` at ``index [B, K]`` -> ``[B, K, ...]``."""
    return jax.vmap(lambda f, i: f[i])(frames, index)


def chain_actions(generator: ContextGenerator, key: jax.Array | None, conditions: Mapping[str, np.ndarray], *,
                  options: ChainOptions = ChainOptions(), reviser: Recognizer | None = None,
                  local_paths: bool = False, on_action: Callable[[int, np.ndarray, np.ndarray], None] | None = None
                  ) -> dict[str, np.ndarray]:
    """B programs of A actions each, every action continuing the one before (module docstring).

    Args:
      generator: a trained context model (:class:`~jaxmotion.pipelines.marionette.ContextGenerator`).
      key: Z for every action (action ``a`` from ``fold_in(key, a)``); None: Z = mu throughout.
      conditions: ``context_rotations [B, K, 24, 3]`` axis-angle and ``context_translation [B, K, 3]`` (world frame:
        what the first action continues), ``tags``, ``next_tags [B, A, C]`` bool, ``durations [B, A]`` frames (1 to
        the model's longest), ``paths [B, A, T, 2]`` the root's ground points per frame, ``follow [B, A]`` bool
        (which actions follow their path).
      options: Shadow Start and Action Revision (:class:`ChainOptions`).
      reviser: Action Revision's classifier (required with ``shadow_start="revision"``).
      local_paths: the paths are in the frame of each action's start (its context's last pose normalised: Eqs.
        3-5), as test programs made of actions from different takes give them; False: world points.
      on_action: called with ``(a, shadowed [B], revised [B])`` once action ``a`` is generated (progress).

    Returns:
      ``rotations [B, A, T, 24, 3]``, ``translation [B, A, T, 3]``, ``joints [B, A, T, 24, 3]`` (world frame, zero past
      each action's end), ``lengths [B, A]``, ``shadowed [B, A]`` (started from the shadow) and, with Action Revision,
      ``revised [B, A]`` (it regenerated the action), and with the orientation check ``turned [B, A]`` (radians
      about +Y by which each action's context was turned; 0 where it was not).
    """
    shadowing = options.shadow_start != "never"
    if shadowing and not isinstance(generator.model, MarionetConfig):
        raise ValueError(f"options.shadow_start: Shadow Start acts on MARIONET's pose embedding; the generator is "
                         f"{generator.method}")
    if options.shadow_start == "revision" and reviser is None:
        raise ValueError("reviser: Action Revision needs a classifier (the revision classifier)")
    tags, next_tags = (np.asarray(conditions[k], bool) for k in ("tags", "next_tags"))
    durations = np.asarray(conditions["durations"])
    batch, actions, classes = tags.shape
    paths = np.asarray(conditions["paths"], np.float32)
    follow = np.asarray(conditions["follow"], bool)
    expected = {"next_tags": (next_tags.shape, (batch, actions, classes)), "durations": (durations.shape,
                (batch, actions)), "follow": (follow.shape, (batch, actions))}
    for name, (shape, want) in expected.items():
        if shape != want:
            raise ValueError(f"conditions.{name}: expected {list(want)} (from tags {list(tags.shape)}), got "
                             f"{list(shape)}")
    if classes != num_tags(generator.model):
        raise ValueError(f"conditions.tags: expected {num_tags(generator.model)} tags (the model's), got {classes}")
    if (not np.issubdtype(durations.dtype, np.integer) or durations.min() < 1
            or durations.max() > generator.max_frames):
        raise ValueError(f"conditions.durations: expected frames from 1 to {generator.max_frames}, got "
                         f"{durations.min()} to {durations.max()}")
    frames = paths.shape[2] if paths.ndim == 4 else -1
    if paths.shape[:2] != (batch, actions) or paths.shape[3:] != (2,) or frames < durations.max() or not np.isfinite(
            paths).all():
        raise ValueError(f"conditions.paths: expected [B, A, T, 2] = ({batch}, {actions}, T >= {durations.max()}, 2) "
                         f"finite ground points, got {list(paths.shape)}")
    rotations = np.asarray(conditions["context_rotations"], np.float32)
    translation = np.asarray(conditions["context_translation"], np.float32)
    if rotations.shape != (batch, CONTEXT, 24, 3) or translation.shape != (batch, CONTEXT, 3):
        raise ValueError(f"conditions.context: expected rotations [{batch}, {CONTEXT}, 24, 3] and translation "
                         f"[{batch}, {CONTEXT}, 3], got {list(rotations.shape)} and {list(translation.shape)}")
    bank = generator.starts
    # the bank's embeddings once per call, not at every action step
    # (a chain that never shadows never reads them: the poses stand in, unembedded)
    embedded = _embedded_bank(generator.params, jnp.asarray(bank.bops)) if shadowing else jnp.asarray(bank.bops)
    if options.orientation and local_paths:
        raise ValueError("options.orientation: the check turns a context towards a world path; local paths turn "
                         "with it")
    step = functools.partial(_action_step, generator.params, generator.model, embedded,
                             jnp.asarray(bank.bop_labels), jnp.asarray(heading_ranges(bank)), local_paths=local_paths,
                             options=options)
    always = np.full(batch, options.shadow_start == "always")
    keep = ("rotations", "translation", "joints")
    outputs: dict[str, list[np.ndarray]] = {name: [] for name in (*keep, "shadowed", "revised", "turned")}
    for a in range(actions):
        mask = np.arange(frames)[None] < durations[:, a, None]
        k_a = None if key is None else jax.random.fold_in(key, a)
        args = (tags[:, a], next_tags[:, a], paths[:, a], follow[:, a], mask)
        out = step(rotations, translation, *args, k_a, always)
        revised = np.zeros(batch, bool)
        if options.shadow_start == "revision":
            logits, _ = reviser({**{k: np.asarray(out[k]) for k in keep}, "lengths": durations[:, a]})
            revised = np.asarray(jnp.argmax(logits, axis=-1)) != np.argmax(tags[:, a], axis=-1)
            if revised.any():
                again = step(rotations, translation, *args, None if k_a is None else jax.random.fold_in(k_a, 1),
                             revised)
                out = jax.tree.map(lambda new, old: jnp.where(
                    jnp.asarray(revised).reshape(-1, *([1] * (old.ndim - 1))), new, old), again, out)
        for name in keep:
            outputs[name].append(np.asarray(out[name]))
        outputs["shadowed"].append(always | revised)
        outputs["revised"].append(revised)
        outputs["turned"].append(np.asarray(out["turned"]))
        if on_action is not None:
            on_action(a, always | revised, revised)
        rotations, translation = out["next_rotations"], out["next_translation"]
    if options.shadow_start != "revision":
        del outputs["revised"]
    if not options.orientation:
        del outputs["turned"]
    return {**{name: np.stack(values, axis=1) for name, values in outputs.items()},
            "lengths": durations.astype(np.int32)}


def joined(chained: Mapping[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The actions of :func:`chain_actions` laid end to end: ``rotations [B, F, 24, 3]``, ``translation [B, F, 3]``,
    ``joints [B, F, 24, 3]`` (F the longest program; a shorter one repeats its last frame), ``lengths [B]``, and
    ``boundaries [B, A - 1]`` (the first frame of every action after the first) and ``starts [B, A]`` (every
    action's first frame: the segment table)."""
    lengths = np.asarray(chained["lengths"])
    starts = np.concatenate([np.zeros_like(lengths[:, :1]), np.cumsum(lengths, axis=1)[:, :-1]], axis=1)
    totals = lengths.sum(axis=1)
    frames = np.arange(int(totals.max()))
    time = np.minimum(frames[None], totals[:, None] - 1)  # [B, F]
    action = np.sum(time[..., None] >= starts[:, None, 1:], axis=-1)  # [B, F]: which action each frame is in
    within = time - np.take_along_axis(starts, action, axis=1)
    rows = np.arange(len(lengths))[:, None]
    out = {name: np.asarray(chained[name])[rows, action, within] for name in ("rotations", "translation", "joints")}
    return {**out, "lengths": totals.astype(np.int32), "boundaries": starts[:, 1:].astype(np.int32),
            "starts": starts.astype(np.int32)}



def bezier_path(points: np.ndarray, frames: int) -> np.ndarray:
    """The Bézier curve with control points ``points [P, 2]`` (ground x, z) sampled at ``t = n / frames`` for frame
    ``n = 1 .. frames`` (the supplement's sampling; four points make its cubic, two a straight line) -> ``[frames, 2]``:
    the root's ground position at the end of each frame, the first point being where the action starts."""
    points = np.asarray(points, np.float64)
    t = np.arange(1, frames + 1) / frames
    curve = np.broadcast_to(points[:, None], (len(points), frames, 2))
    while len(curve) > 1:  # de Casteljau
        curve = (1 - t)[None, :, None] * curve[:-1] + t[None, :, None] * curve[1:]
    return curve[0].astype(np.float32)


def program_conditions(generator: ContextGenerator, program: Program, key: jax.Array, *,
                       frames: int | None = None) -> dict[str, np.ndarray]:
    """:func:`chain_actions`' conditions (world paths) of one ``program``: its actions' tags, the next action's
    (the last: its own), durations, their paths where given (world ground points, followed), and its context, or
    else a training start of the first action's first tag (over the origin, facing +Z), drawn with ``key``.
    ``frames``: the frames every action is padded to (at least the longest; None: the longest), so that programs
    of other durations reuse one compilation of the chain."""
    program.check(generator.class_names, generator.max_frames, num_joints=24)
    tags = program.tag_matrix(generator.class_names)[None]
    durations = np.array([[a.duration for a in program.actions]], np.int32)
    frames = max(int(durations.max()), frames or 0)
    paths = np.zeros((1, len(program.actions), frames, 2), np.float32)
    follow = np.zeros((1, len(program.actions)), bool)
    for a, action in enumerate(program.actions):
        if action.path is not None:
            paths[0, a, :action.duration], follow[0, a] = np.asarray(action.path, np.float32), True
    if program.context is None:
        label = np.argmax(tags[:, 0], axis=-1).astype(np.int32)
        rotations, translation, _ = generator.starts_for(key, label, durations[:, 0], frames)
    else:
        rotations = np.asarray(program.context["rotations"], np.float32)[None]
        translation = np.asarray(program.context["translation"], np.float32)[None]
    return {"context_rotations": rotations, "context_translation": translation, "tags": tags,
            "next_tags": np.concatenate([tags[:, 1:], tags[:, -1:]], axis=1), "durations": durations, "paths": paths,
            "follow": follow}
