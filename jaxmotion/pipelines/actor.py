"""ACTOR put to use (Petrovich et al. 2021, §4.2, §4.4): generation, denoising, interpolation (Figure 5's
picture: :func:`jaxmotion.pipelines.pictures.generation_grid` on :func:`actor_sampler`).

* :class:`ActorGenerator`: a trained ACTOR as an artefact (:mod:`jaxmotion.pipelines.artefacts`): saved beside a
  run's checkpoints, loaded by :func:`jaxmotion.load_generator`, generating motions placed on the floor.
* :func:`generate_motions`: z ~ N(0, I) decoded with an action for a duration of its own (variable-length
  generation), returned as a packed :class:`~jaxmotion.data.motion.MotionDataset` without padding.
* :func:`denoise`: use case I, encode a motion with its true action and decode the posterior mean
  (or, with a key, a posterior sample): the encoded-decoded ("Real_denoised") motion.
* :func:`interpolate`: use case II's "Real_interpolated" data, decoded linear interpolants between the
  posterior means of two real motions.
* :func:`noisy`: Gaussian perturbation of the joint rotations, so a denoising experiment can measure the
  jitter (:func:`jaxmotion.metrics.smoothness.mean_acceleration`) before and after.

Motions in and out are the library's batch dict (as :func:`jaxmotion.data.pipeline.gather_windows`
returns): ``joints [B, T, J, 3]`` (forward kinematics of ``rotations`` on the skeleton's rest offsets,
plus ``translation``), ``rotations [B, T, J, 3]`` axis-angle, ``translation [B, T, 3]``, ``mask [B, T]``,
``lengths [B]``, ``actions [B]``; frames past a length repeat the last real one (``padding="last"``, the
pipeline's :func:`~jaxmotion.data.pipeline.window_frames`). :func:`~jaxmotion.data.motion.to_dataset` packs such a dict into a
``MotionDataset`` (padding dropped). Host functions work ``chunk`` rows at a time
(:func:`~jaxmotion.data.pipeline.map_in_chunks`, one compilation per call) and draw each row's
randomness from its own key, so results do not depend on ``chunk``. The jitted cores take the parameters
as arguments, never as closure constants.

Axes: N or B motions, T frames, J joints (the model has J + 1 rows: the translation row), C channels,
d model width (the size of z), S interpolation steps, K classes.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Sequence

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.data.motion import Motion, MotionDataset, concatenate, to_dataset
from jaxmotion.data.pipeline import (
    BatchSpec,
    Padding,
    canonicalize_motion,
    gather_windows,
    map_in_chunks,
    window_frames,
)
from jaxmotion.geometry.kinematics import forward_kinematics
from jaxmotion.geometry.rotations import axis_angle_to_matrix, matrix_to_axis_angle
from jaxmotion.geometry.skeletons import Skeleton
from jaxmotion.data.labels import check_actions, check_durations
from jaxmotion.models.actor import (
    ActorConfig,
    AnyActorParams,
    decode,
    encode,
    init_actor,
    length_mask,
    motions_from_features,
    to_features,
)
from jaxmotion.pipelines.artefacts import DataFacts, ParamsGenerator

_FIELDS = ("joints", "rotations", "translation")


# --- jittable cores --------------------------------------------------------------------------------


def _repad(motions: dict[str, jax.Array], padding: Padding) -> dict[str, jax.Array]:
    """Frames past each length replaced as the pipeline pads windows (``window_frames``, per row)."""
    lengths = motions["lengths"]
    frames = motions["mask"].shape[1]
    local, _ = window_frames(jnp.zeros_like(lengths), jnp.maximum(lengths, 1), frames, padding)  # [B, T]
    out = dict(motions)
    for name in _FIELDS:
        index = local.reshape(*local.shape, *([1] * (motions[name].ndim - 2)))
        out[name] = jnp.take_along_axis(motions[name], index, axis=1)
    return out


@functools.partial(jax.jit, static_argnames=("config", "skeleton", "padding"))
def decode_motions(params: AnyActorParams, z: jax.Array, actions: jax.Array, mask: jax.Array, *, config: ActorConfig,
                   skeleton: Skeleton, padding: Padding = "last") -> dict[str, jax.Array]:
    """Decode ``z [B, d]`` with ``actions [B]`` over ``mask [B, T]`` (True on each row's first frames) into
    the batch dict (joints by forward kinematics on ``skeleton``, translation relative to frame 0), padded
    past each length by ``padding``. Jitted; ``skeleton`` is static (hashed by identity)."""
    x = decode(config, params, z, actions, mask)
    motions = motions_from_features(x, mask, config.rep, skeleton)
    return {**_repad(motions, padding), "actions": actions}


@functools.partial(jax.jit, static_argnames=("config",))
def posterior(params: AnyActorParams, rotations: jax.Array, translation: jax.Array, actions: jax.Array, mask: jax.Array,
              *, config: ActorConfig) -> tuple[jax.Array, jax.Array]:
    """The encoder's ``(mu [B, d], logvar [B, d])`` of ``rotations [B, T, J, 3]`` (axis-angle),
    ``translation [B, T, 3]`` with ``actions [B]`` over ``mask [B, T]``; no dropout. Jitted."""
    return encode(config, params, to_features(rotations, translation, config.rep), actions, mask)


def _row_normals(key_data: jax.Array, width: int) -> jax.Array:
    return jax.vmap(lambda k: jax.random.normal(jax.random.wrap_key_data(k), (width,)))(key_data)


@functools.partial(jax.jit, static_argnames=("frames", "config", "skeleton"))
def _generate(params: AnyActorParams, key_data: jax.Array, actions: jax.Array, durations: jax.Array, *, frames: int,
              config: ActorConfig, skeleton: Skeleton) -> dict[str, jax.Array]:
    z = _row_normals(key_data, config.width)
    return decode_motions(params, z, actions, length_mask(durations, frames), config=config,
                          skeleton=skeleton)


@functools.partial(jax.jit, static_argnames=("config", "skeleton", "padding"))
def _denoise(params: AnyActorParams, rotations: jax.Array, translation: jax.Array, lengths: jax.Array,
             actions: jax.Array, key_data: jax.Array | None, *, config: ActorConfig, skeleton: Skeleton,
             padding: Padding) -> dict[str, jax.Array]:
    mask = length_mask(lengths, rotations.shape[1])
    mu, logvar = posterior(params, rotations, translation, actions, mask, config=config)
    z = mu if key_data is None else mu + jnp.exp(0.5 * logvar) * _row_normals(key_data, config.width)
    out = decode_motions(params, z, actions, mask, config=config, skeleton=skeleton, padding=padding)
    origin = translation[:, :1]  # the model's translation is relative to frame 0
    return {**out, "translation": out["translation"] + origin, "joints": out["joints"] + origin[:, :, None]}


@functools.partial(jax.jit, static_argnames=("config", "skeleton", "hips", "padding"))
def _interpolate(params: AnyActorParams, joints: jax.Array, translation: jax.Array, rotations: jax.Array,
                 lengths: jax.Array, actions: jax.Array, weights: jax.Array, *, config: ActorConfig,
                 skeleton: Skeleton, hips: tuple[int, int] | None, padding: Padding) -> dict[str, jax.Array]:
    """Two padded motions ``[2, T, ...]`` -> their S decoded interpolants (``weights [S]``), decoded with
    ``actions[0]``."""
    if hips is not None:
        joints, translation, rotations = canonicalize_motion(joints, translation, rotations, *hips)
    frames = rotations.shape[1]
    mu, _ = encode(config, params, to_features(rotations, translation, config.rep), actions, length_mask(lengths, frames))
    z = (1.0 - weights)[:, None] * mu[0] + weights[:, None] * mu[1]
    durations = jnp.round((1.0 - weights) * lengths[0] + weights * lengths[1]).astype(jnp.int32)
    return decode_motions(params, z, jnp.full(weights.shape, actions[0]), length_mask(durations, frames),
                          config=config, skeleton=skeleton, padding=padding)


@functools.partial(jax.jit, static_argnames=("skeleton", "padding"))
def _perturb(key: jax.Array, rotations: jax.Array, translation: jax.Array, lengths: jax.Array, sigma: jax.Array,
             translation_sigma: jax.Array, *, skeleton: Skeleton, padding: Padding) -> dict[str, jax.Array]:
    k_rot, k_trans = jax.random.split(key)
    # R' = R · exp(sigma ε): a rotation of isotropic random axis and ~sigma·χ₃ angle in the joint's own frame
    eps = sigma * jax.random.normal(k_rot, rotations.shape, rotations.dtype)
    mats = axis_angle_to_matrix(rotations) @ axis_angle_to_matrix(eps)
    translation = translation + translation_sigma * jax.random.normal(k_trans, translation.shape, translation.dtype)
    joints = forward_kinematics(mats, translation, skeleton.offsets, skeleton.parents)
    mask = length_mask(lengths, rotations.shape[1])
    motions = {"joints": joints, "rotations": matrix_to_axis_angle(mats), "translation": translation,
               "mask": mask, "lengths": lengths}
    return _repad(motions, padding)


# --- checks ----------------------------------------------------------------------------------------


def _check_model(config: ActorConfig, skeleton: Skeleton) -> None:
    if skeleton.offsets is None:
        raise ValueError(f"skeleton: {skeleton.name} has no rest offsets; forward kinematics needs them")
    if config.num_joints != skeleton.num_joints + 1:
        raise ValueError(f"skeleton: the model expects {config.num_joints - 1} joints (plus the translation "
                         f"row), {skeleton.name} has {skeleton.num_joints}")


def _check_labels(actions, durations, num_classes: int) -> tuple[np.ndarray, np.ndarray]:
    actions, durations = np.asarray(actions), np.asarray(durations)
    if actions.size == 0:
        raise ValueError(f"actions: expected a non-empty [N] integer array, got {actions.dtype} {actions.shape}")
    check_actions(actions, num_classes)
    check_durations(durations, len(actions))
    return actions.astype(np.int32), durations.astype(np.int32)


def _check_batch(motions: dict, num_joints: int, *, need_actions: bool) -> tuple[int, int]:
    for name in ("rotations", "translation", "lengths") + (("actions",) if need_actions else ()):
        if name not in motions:
            raise ValueError(f"motions: expected a batch dict with {name!r} (keys: rotations [B, T, J, 3], "
                             f"translation [B, T, 3], lengths [B], actions [B]), got keys {sorted(motions)}")
    rot = np.shape(motions["rotations"])
    if len(rot) != 4 or rot[2:] != (num_joints, 3):
        raise ValueError(f"motions['rotations']: expected [B, T, {num_joints}, 3], got {rot}")
    b, t = rot[:2]
    if np.shape(motions["translation"]) != (b, t, 3):
        raise ValueError(f"motions['translation']: expected [B, T, 3] = {(b, t, 3)}, "
                         f"got {np.shape(motions['translation'])}")
    lengths = np.asarray(motions["lengths"])
    if lengths.shape != (b,) or lengths.min() < 1 or lengths.max() > t:
        raise ValueError(f"motions['lengths']: expected [B] = ({b},) values in [1, T={t}], got {lengths.shape}"
                         + (f" in [{lengths.min()}, {lengths.max()}]" if lengths.size else ""))
    if need_actions and np.shape(motions["actions"]) != (b,):
        raise ValueError(f"motions['actions']: expected [B] = ({b},), got {np.shape(motions['actions'])}")
    return b, t


def _row_keys(key: jax.Array, count: int) -> np.ndarray:
    """Row n's key ``fold_in(key, n)`` (independent of the row count and the chunk size), as raw key data
    ``[N, ...]`` (map_in_chunks pads and slices plain arrays)."""
    keys = jax.vmap(jax.random.fold_in, in_axes=(None, 0))(key, jnp.arange(count))
    return np.asarray(jax.random.key_data(keys))



# --- packing ---------------------------------------------------------------------------------------


# --- use cases -------------------------------------------------------------------------------------


def generate_motions(params: AnyActorParams, config: ActorConfig, key: jax.Array, actions, durations,
                     skeleton: Skeleton, *, class_names: Sequence[str] | None = None, fps: float = 20.0,
                     name: str = "actor", split: str = "generated", chunk: int = 256) -> MotionDataset:
    """Generate one motion per ``(actions[n], durations[n])``: ``z ~ N(0, I)`` (row n drawn with
    ``fold_in(key, n)``) decoded for ``durations[n]`` frames, packed without padding.

    Joints are forward kinematics of the generated rotations on ``skeleton``'s rest offsets, with the
    generated translation (relative to frame 0, the model's frame: the root starts near the origin,
    facing +Z). All rows are decoded at ``T = max(durations)`` frames with padded frames masked, which
    does not change a row's real frames. ``class_names``: defaults to ``"0" .. "K-1"``; ``fps``: the
    dataset's (20 for UESTC).
    """
    _check_model(config, skeleton)
    actions, durations = _check_labels(actions, durations, config.num_classes)
    if class_names is None:
        class_names = tuple(str(k) for k in range(config.num_classes))
    if len(class_names) != config.num_classes:
        raise ValueError(f"class_names: expected {config.num_classes} names (the model's classes), got "
                         f"{len(class_names)}")
    frames = int(durations.max())

    def run(_, rows):
        return _generate(params, *rows, frames=frames, config=config, skeleton=skeleton)

    motions = map_in_chunks(run, (_row_keys(key, len(actions)), actions, durations), chunk)
    return to_dataset(motions, skeleton, class_names, fps, name=name, split=split)


def actor_sampler(params: AnyActorParams, config: ActorConfig, skeleton: Skeleton):
    """The evaluation protocol's sampler ``(key, actions [N], durations [N]) -> motions`` (the batch dict,
    ``T = max(durations)``, shorter rows padded by their last frame as real windows are). Row n's noise is
    ``fold_in(key, n)``, as in :func:`generate_motions`."""
    _check_model(config, skeleton)

    def sampler(key, actions, durations):
        check_actions(actions, config.num_classes)
        check_durations(durations, len(actions))
        durations = np.asarray(durations, np.int32)
        return _generate(params, _row_keys(key, len(durations)), jnp.asarray(actions, jnp.int32),
                         jnp.asarray(durations), frames=int(durations.max()), config=config, skeleton=skeleton)

    return sampler


def denoise(params: AnyActorParams, config: ActorConfig, motions: dict, skeleton: Skeleton, *,
            key: jax.Array | None = None, padding: Padding = "last", chunk: int = 256) -> dict[str, np.ndarray]:
    """ACTOR's denoising (use case I): encode each motion with its true action, decode for the same length.

    ``motions``: a batch dict (``rotations [B, T, J, 3]``, ``translation [B, T, 3]``, ``lengths [B]``,
    ``actions [B]``; e.g. from :func:`~jaxmotion.data.pipeline.gather_windows`, which also puts frame 0 in
    the canonical pose the model was trained in). Without ``key``, z is the posterior mean μ
    (deterministic); with it, row b samples ``z = μ + σ ε`` with ``fold_in(key, b)`` (the paper's
    ``autoencode`` outside training). Returns a host batch dict of the same shapes (``joints`` by forward
    kinematics on ``skeleton``; ``translation`` shifted by the input's frame-0 translation, so the output
    stays where the input was), ``mask``, ``lengths``, ``actions``; frames past a length repeat the last
    real frame (``padding``, as the pipeline pads windows).
    """
    _check_model(config, skeleton)
    batch, _ = _check_batch(motions, skeleton.num_joints, need_actions=True)
    actions = np.asarray(motions["actions"])
    if actions.min() < 0 or actions.max() >= config.num_classes:
        raise ValueError(f"motions['actions']: expected class indices in [0, {config.num_classes}), "
                         f"got [{actions.min()}, {actions.max()}]")
    rows = {name: np.asarray(motions[name]) for name in ("rotations", "translation", "lengths", "actions")}
    if key is not None:
        rows["keys"] = _row_keys(key, batch)

    def run(_, part):
        return _denoise(params, part["rotations"], part["translation"], part["lengths"], part["actions"],
                        part.get("keys"), config=config, skeleton=skeleton, padding=padding)

    return map_in_chunks(run, rows, chunk)


def interpolate(params: AnyActorParams, config: ActorConfig, motion_a: Motion, motion_b: Motion,
                action_a: int | None = None, action_b: int | None = None, steps: int = 5, *, skeleton: Skeleton,
                window: int = 60, padding: Padding = "last") -> dict[str, np.ndarray]:
    """Decoded linear interpolants between the posterior means of two real motions (use case II,
    "Real_interpolated"; the paper interpolates motions of the same action).

    Each motion keeps its first ``window`` frames (pass the window the model was trained on; ACTOR's is 60)
    and is put in the canonical pose (root of frame 0 at the origin facing +Z, as the
    training windows) when the skeleton names ``left_hip``/``right_hip``. ``motion_a`` is encoded with
    ``action_a`` (default ``motion_a.action``), ``motion_b`` with ``action_b`` (default: ``action_a``, one
    action for both), and every interpolant is decoded with ``action_a``. For weights
    ``w = linspace(0, 1, steps)``, row s decodes ``(1 - w) μ_a + w μ_b`` for ``round((1 - w) n_a + w n_b)``
    frames. Returns a host batch dict ``[S, T = window, ...]`` (translation relative to frame 0)
    plus ``weights [S]``; row 0 is the deterministic :func:`denoise` of ``motion_a``'s canonical window,
    row S - 1 that of ``motion_b`` (decoded with ``action_a``).
    """
    _check_model(config, skeleton)
    if steps < 2:
        raise ValueError(f"steps: expected >= 2 interpolation weights (both endpoints), got {steps}")
    if window < 1:
        raise ValueError(f"window: expected >= 1 frames, got {window}")
    action_a = motion_a.action if action_a is None else int(action_a)
    action_b = action_a if action_b is None else int(action_b)
    for label, value in (("action_a", action_a), ("action_b", action_b)):
        if not 0 <= value < config.num_classes:
            raise ValueError(f"{label}: expected a class index in [0, {config.num_classes}), got {value}")
    parts = []
    for label, motion in (("motion_a", motion_a), ("motion_b", motion_b)):
        if motion.rotations is None or motion.rotations.shape[1:] != (skeleton.num_joints, 3):
            raise ValueError(f"{label}: expected rotations [T, {skeleton.num_joints}, 3], got "
                             f"{None if motion.rotations is None else motion.rotations.shape}")
        parts.append((motion.joints[:window], motion.translation[:window], motion.rotations[:window]))
    n_a, n_b = len(parts[0][0]), len(parts[1][0])
    frames = window  # one shape for every pair: one compilation
    # both windows padded to T by repeating their last frame (the pipeline's padding)
    index = np.asarray(window_frames(jnp.zeros(2, jnp.int32), jnp.array([n_a, n_b]), frames)[0])
    joints, translation, rotations = (np.stack([p[i][index[k]] for k, p in enumerate(parts)]) for i in range(3))
    names = skeleton.joint_names
    hips = (names.index("left_hip"), names.index("right_hip")) if {"left_hip", "right_hip"} <= set(names) else None
    weights = np.linspace(0.0, 1.0, steps, dtype=np.float32)
    out = _interpolate(params, joints, translation, rotations, np.array([n_a, n_b], np.int32),
                       np.array([action_a, action_b], np.int32), weights, config=config,
                       skeleton=skeleton, hips=hips, padding=padding)
    return {**jax.tree.map(np.asarray, out), "weights": np.asarray(weights)}


def noisy(key: jax.Array, motions: dict, sigma: float, skeleton: Skeleton, *, translation_sigma: float = 0.0,
          padding: Padding = "last") -> dict[str, np.ndarray]:
    """Motions with Gaussian noise on the joint rotations, for a denoising experiment.

    Every real frame's local rotation ``R`` (axis-angle in, axis-angle out) becomes ``R · exp(σ ε)`` with
    ``ε ~ N(0, I₃)`` independent per joint and frame: a perturbation in the joint's own frame, independent
    of the model's representation, of mean angle ≈ 1.6 σ (radians); the root's global orientation is
    perturbed too. ``translation_sigma`` (metres) adds iid noise to the root translation. ``joints`` are
    recomputed by forward kinematics on ``skeleton`` (so compare jitter with :func:`denoise`'s output,
    also FK on ``skeleton``; ``sigma = 0`` gives the clean reference). Frames past each length repeat the
    last real frame. Returns a host batch dict (the input's other keys, e.g. ``actions``, kept).
    """
    _check_batch(motions, skeleton.num_joints, need_actions=False)
    if skeleton.offsets is None:
        raise ValueError(f"skeleton: {skeleton.name} has no rest offsets; forward kinematics needs them")
    if sigma < 0 or translation_sigma < 0:
        raise ValueError(f"sigma, translation_sigma: expected >= 0, got {sigma}, {translation_sigma}")
    out = _perturb(key, jnp.asarray(motions["rotations"], jnp.float32), jnp.asarray(motions["translation"], jnp.float32),
                   jnp.asarray(motions["lengths"], jnp.int32), jnp.float32(sigma), jnp.float32(translation_sigma),
                   skeleton=skeleton, padding=padding)
    return {**{k: np.asarray(v) for k, v in motions.items()}, **jax.tree.map(np.asarray, out)}


# --- training sets ---------------------------------------------------------------------------------


@functools.partial(jax.jit, static_argnames=("config", "skeleton", "padding"))
def _interpolate_pairs(params: AnyActorParams, joints: jax.Array, translation: jax.Array, rotations: jax.Array,
                       lengths: jax.Array, actions: jax.Array, weights: jax.Array, *, config: ActorConfig,
                       skeleton: Skeleton, padding: Padding) -> dict[str, jax.Array]:
    """P pairs of canonical windows ``[P, 2, T, ...]`` with one weight each ``[P]`` -> P interpolants
    ``[P, T, ...]`` (:func:`_interpolate` per pair)."""
    def one(j, t, r, n, a, w):
        out = _interpolate(params, j, t, r, n, a, w[None], config=config, skeleton=skeleton, hips=None,
                           padding=padding)
        return jax.tree.map(lambda x: x[0], out)

    return jax.vmap(one)(joints, translation, rotations, lengths, actions, weights)


def interpolated_set(params: AnyActorParams, config: ActorConfig, data: MotionDataset, key: jax.Array, count: int,
                     *, window: int = 60, padding: Padding = "last", chunk: int = 256) -> MotionDataset:
    """Use case II's "Real_interpolated" training set: ``count`` decoded interpolants between the posterior
    means of two real motions of the same action (the batched form of :func:`interpolate`).

    Row n takes a clip ``a`` drawn uniformly from ``data``, a clip ``b`` drawn uniformly among the clips of
    ``a``'s action (``a`` itself included) and a weight ``w ~ U(0, 1)``; each clip keeps one random
    ``window``-frame window (the model's training window) in the canonical pose, as training windows are
    drawn, and the row decodes ``(1 - w) μ_a + w μ_b`` with that action for ``round((1 - w) n_a + w n_b)``
    frames. Returns the packed interpolants (``data``'s classes, skeleton and fps; translation relative to frame 0).
    """
    _check_model(config, data.skeleton)
    if count < 1:
        raise ValueError(f"count: expected >= 1 interpolants, got {count}")
    if data.rotations is None or len(data) == 0:
        raise ValueError(f"data: {data.name}/{data.split} needs joint rotations and at least one clip")
    if data.num_classes != config.num_classes:
        raise ValueError(f"data: {data.name} has {data.num_classes} classes, the model {config.num_classes}")
    k_a, k_b, k_w, k_windows = jax.random.split(key, 4)
    a = np.asarray(jax.random.randint(k_a, (count,), 0, len(data)))
    # b: a uniform position within a's class, read from the clips sorted by class
    by_class = np.argsort(data.actions, kind="stable")
    sizes = np.bincount(data.actions, minlength=data.num_classes)
    firsts = np.cumsum(sizes) - sizes
    actions = data.actions[a]
    within = np.floor(np.asarray(jax.random.uniform(k_b, (count,))) * sizes[actions]).astype(np.int64)
    b = by_class[firsts[actions] + np.minimum(within, sizes[actions] - 1)]
    windows = gather_windows(data, np.concatenate([a, b]), k_windows, BatchSpec(batch_size=1, window=window))
    pairs = {name: np.stack([windows[name][:count], windows[name][count:]], axis=1)
             for name in ("joints", "translation", "rotations", "lengths", "actions")}
    pairs["weights"] = np.asarray(jax.random.uniform(k_w, (count,)))

    def run(_, part):
        return _interpolate_pairs(params, part["joints"], part["translation"], part["rotations"], part["lengths"],
                                  part["actions"], part["weights"], config=config,
                                  skeleton=data.skeleton, padding=padding)

    motions = map_in_chunks(run, pairs, chunk)
    return to_dataset(motions, data.skeleton, data.class_names, data.fps, name="interpolated", split="train")


def real_plus_generated(real: MotionDataset, generated: MotionDataset) -> MotionDataset:
    """Real and generated motions, the real ones repeated so that a batch draws about as many of each."""
    copies = max(1, round(len(generated) / len(real)))
    return concatenate([real] * copies + [generated], split="train")


@dataclasses.dataclass(frozen=True, eq=False)
class ActorGenerator(ParamsGenerator):
    """A trained ACTOR: its model, parameters, the data facts, and ``frames`` (the length it trained on, the
    default duration)."""

    model: ActorConfig
    params: AnyActorParams
    facts: DataFacts
    frames: int = 60
    method = "actor"
    init = staticmethod(init_actor)

    def sampler(self):
        return actor_sampler(self.params, self.model, self.skeleton)
