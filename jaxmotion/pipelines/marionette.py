"""Neural Marionette put to use: one action per call of MARIONET, in the world frame of the motion it continues.

:func:`generate_actions` takes each action's context (its 6 preceding frames, as the library's records hold them:
axis-angle SMPL-24 rotations and root translation, in any placement), tags, next tags, duration and optional ground
path (world x, z per frame), normalises every context at its last pose (Eqs. 3-5:
:func:`~jaxmotion.geometry.kinematics.heading_transform`), turns the paths into that frame, generates frame by
frame (:func:`jaxmotion.models.marionet.generate`) and brings the actions back into the world: a context turned and
moved gives the same action turned and moved (``tests/test_marionette_pipeline.py``). Joints come from forward
kinematics on the template skeleton (the mean shape, as the loss's).

Axes: B actions, K context frames, T frames (the longest duration), C tags.
"""

from __future__ import annotations

import functools

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.geometry.kinematics import apply_transform, forward_kinematics, inverse_transform, transform_motion
from jaxmotion.geometry.representations import from_pose135
from jaxmotion.geometry.rotations import axis_angle_to_matrix
from jaxmotion.geometry.skeletons import SMPL24
from jaxmotion.models.marionet import CONTEXT, MarionetConfig, MarionetParams, generate, normalised_poses


@functools.partial(jax.jit, static_argnames="config")
def _generate(params: MarionetParams, config: MarionetConfig, rotations: jax.Array, translation: jax.Array,
              tags: jax.Array, next_tags: jax.Array, paths: jax.Array, follow: jax.Array, mask: jax.Array,
              key: jax.Array | None) -> dict[str, jax.Array]:
    context, turn, shift = normalised_poses(rotations, translation, -1)
    ground = jnp.stack([paths[..., 0], jnp.zeros_like(paths[..., 0]), paths[..., 1]], axis=-1)  # [B, T, 3]
    local_paths = apply_transform(turn, shift, ground)[..., jnp.array([0, 2])]
    local_paths = jnp.where((mask & follow[:, None])[..., None], local_paths, 0.0)  # no path: zeros, as in training
    poses = generate(params, config, context, tags, next_tags, local_paths, mask, key)
    out_rotations, out_translation = transform_motion(*inverse_transform(turn, shift), *from_pose135(poses))
    joints = forward_kinematics(axis_angle_to_matrix(out_rotations), out_translation, SMPL24.offsets, SMPL24.parents,
                                check=False)
    keep = mask[..., None]
    return {"rotations": jnp.where(keep[..., None], out_rotations, 0.0), "translation": jnp.where(keep, out_translation,
            0.0), "joints": jnp.where(keep[..., None], joints, 0.0)}


def generate_actions(params: MarionetParams, config: MarionetConfig, context_rotations: np.ndarray,
                     context_translation: np.ndarray, tags: np.ndarray, next_tags: np.ndarray,
                     durations: np.ndarray, paths: np.ndarray | None = None, follow: np.ndarray | None = None,
                     key: jax.Array | None = None) -> dict[str, np.ndarray]:
    """B actions at once, each continuing its context.

    Args:
      context_rotations: ``[B, K, 24, 3]`` axis-angle (K = 6), ``context_translation [B, K, 3]``, world frame.
      tags, next_tags: ``[B, C]`` multi-hot (bool or 0/1).
      durations: ``[B]`` frames of each action, 1 to ``config.max_frames``.
      paths: ``[B, T, 2]`` world ground points (x, z) of the root per frame (T = the longest duration); None: none.
      follow: ``[B]`` bool, which actions follow their path (the others get zeros, as in-place actions do in
        training); None: all of them when ``paths`` is given.
      key: samples Z (None: Z = mu, the paper's setting for its controllability figure).

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
    if tags.shape != (batch, config.num_tags) or next_tags.shape != tags.shape:
        raise ValueError(f"tags, next_tags: expected [B, C] = ({batch}, {config.num_tags}), got {tags.shape} and "
                         f"{next_tags.shape}")
    durations = np.asarray(durations)
    if (durations.shape != (batch,) or not np.issubdtype(durations.dtype, np.integer)
            or durations.min() < 1 or durations.max() > config.max_frames):
        raise ValueError(f"durations: expected [B] = ({batch},) frame counts in [1, {config.max_frames}], got "
                         f"{durations.dtype} {durations.shape}")
    frames = int(durations.max())
    follow = np.full(batch, paths is not None) if follow is None else np.asarray(follow, bool)
    if paths is None:
        paths = np.zeros((batch, frames, 2), np.float32)
    paths = np.asarray(paths, np.float32)
    if paths.shape != (batch, frames, 2) or not np.isfinite(paths).all():
        raise ValueError(f"paths: expected [B, T, 2] = ({batch}, {frames}, 2) finite ground points (T the longest "
                         f"duration), got {paths.shape}")
    if follow.shape != (batch,):
        raise ValueError(f"follow: expected [B] = ({batch},) bool, got shape {follow.shape}")
    mask = np.arange(frames)[None] < durations[:, None]
    out = _generate(params, config, jnp.asarray(context_rotations), jnp.asarray(context_translation),
                    jnp.asarray(tags, jnp.float32), jnp.asarray(next_tags, jnp.float32), jnp.asarray(paths),
                    jnp.asarray(follow), jnp.asarray(mask), key)
    return {**{k: np.asarray(v) for k, v in out.items()}, "mask": mask, "lengths": durations.astype(np.int64)}
