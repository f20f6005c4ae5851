"""ActFormer put to use: generated motions as the library's batch dict, and the evaluation protocol's sampler.

The generator writes ActFormer's representations (:mod:`jaxmotion.geometry.representations`); the library's
motions are joint positions (plus rotations and translation for SMPL data), so :func:`to_motions` turns them
back:

* ``skeleton`` output (root + unit limb vectors): joints rebuilt from the generated root along the unit
  vectors with the training data's mean bone lengths (ActFormer's ``avglength``, kept in :class:`ActFormerFit`);
  ``translation`` is the rebuilt root. A recogniser reading ``limbs`` recovers the unit vectors to 1e-4.
  ActFormer's root is the clip's mean root removed, so the body's height is lost: the motions are lifted by
  the training data's mean root height (:class:`ActFormerFit`), standing on the floor on average (the
  evaluators remove it again).
* ``smpl`` output (rot6d + translation row): the rotations as axis-angle, the translation (de-meaned over the
  clip, as generated), joints by forward kinematics on the skeleton's rest offsets.

:func:`generate_motions` draws row n's latent sequence from ``fold_in(key, n)``, so a motion does not depend on
how many are drawn with it or on the chunk size; :func:`actformer_sampler` is the protocol's sampler.

Axes: N motions, P persons, T frames, J joints (V = J + 1 generator joints for SMPL), C channels.
"""

from __future__ import annotations

import functools
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.data.labels import check_actions, check_durations
from jaxmotion.data.motion import MotionDataset
from jaxmotion.data.pipeline import map_in_chunks
from jaxmotion.geometry.kinematics import forward_kinematics
from jaxmotion.geometry.representations import joints_from_limb_vectors, mean_bone_lengths, split_rotation_features
from jaxmotion.geometry.rotations import axis_angle_to_matrix
from jaxmotion.geometry.skeletons import Skeleton
from jaxmotion.train.state import MultiState


class ActFormerFit(NamedTuple):
    """A trained ActFormer: the train state (generator and critic, their spectral-norm vectors), the training
    data's mean bone lengths ``[J]`` that skeleton output is rebuilt with and its mean root height (metres, up
    the library's +Y) that generated motions are lifted by (:func:`fit_of`)."""

    state: MultiState
    bone_lengths: np.ndarray
    root_height: float


def fit_of(state: MultiState, data: MotionDataset) -> ActFormerFit:
    """``state`` trained on ``data`` with ``data``'s mean bone lengths (over all frames and persons) and mean
    root height."""
    lengths = np.asarray(mean_bone_lengths(jnp.asarray(data.joints), data.skeleton.parents))
    return ActFormerFit(state, lengths, float(np.mean(data.joints[..., 0, 1])))


def _check_skeleton(training, skeleton: Skeleton) -> None:
    g = training.generator
    joints = g.joints - (1 if g.output == "smpl" else 0)
    if skeleton.num_joints != joints:
        raise ValueError(f"skeleton: the generator writes {joints} joints, {skeleton.name} has {skeleton.num_joints}")
    if g.output == "smpl" and skeleton.offsets is None:
        raise ValueError(f"skeleton: SMPL output needs rest offsets for forward kinematics; {skeleton.name} has none")
    if g.output == "raw":
        raise ValueError("training.generator.output: 'raw' output has no motion to rebuild; use 'skeleton' or 'smpl'")


def to_motions(motion: jax.Array, output: str, skeleton: Skeleton, bone_lengths: jax.Array,
               root_height: float | jax.Array = 0.0) -> dict[str, jax.Array]:
    """The generator's ``motion [N, (P,) T, V, C]`` -> ``joints [N, (P,) T, J, 3]`` and ``translation
    [N, (P,) T, 3]`` (plus axis-angle ``rotations [N, (P,) T, J, 3]`` for ``output="smpl"``), lifted by
    ``root_height`` along +Y."""
    lift = jnp.asarray([0.0, 1.0, 0.0], motion.dtype) * root_height
    if output == "skeleton":
        joints = joints_from_limb_vectors(motion, skeleton.parents, bone_lengths) + lift
        return {"joints": joints, "translation": joints[..., 0, :]}
    if output == "smpl":
        rotations, translation = split_rotation_features(motion, "rot6d")
        translation = translation + lift
        joints = forward_kinematics(axis_angle_to_matrix(rotations), translation, jnp.asarray(skeleton.offsets),
                                    skeleton.parents)
        return {"joints": joints, "translation": translation, "rotations": rotations}
    raise ValueError(f"output: expected 'skeleton' or 'smpl', got {output!r}")


@functools.partial(jax.jit, static_argnames=("training", "skeleton"))
def _generate(training, state: MultiState, bone_lengths: jax.Array, root_height: jax.Array, keys: jax.Array,
              actions: jax.Array, skeleton: Skeleton) -> dict[str, jax.Array]:
    from jaxmotion.train.actformer import generator_network, latent_factors, sample_latents  # it imports this module

    factors = latent_factors(training)
    z = jax.vmap(lambda k: sample_latents(training, factors, jax.random.wrap_key_data(k), 1)[0])(keys)
    generate = generator_network(training.generator).generate
    motion, _ = generate(training.generator, state.params["generator"], state.buffers["generator"], z, actions)
    return to_motions(motion, training.generator.output, skeleton, bone_lengths, root_height)


def generate_motions(trained: ActFormerFit, training, key: jax.Array, actions, skeleton: Skeleton, *,
                     chunk: int = 256) -> dict[str, np.ndarray]:
    """Motions for ``actions [N]`` (evaluation mode: the stored power-iteration vectors), as a host batch dict:
    :func:`to_motions`' arrays plus ``lengths [N]`` and ``actions [N]``; all ``training.generator.frames`` long.
    Row n's latent comes from ``fold_in(key, n)``."""
    _check_skeleton(training, skeleton)
    g = training.generator
    actions = np.asarray(actions)
    check_actions(actions, g.num_classes)
    keys = jax.vmap(jax.random.fold_in, in_axes=(None, 0))(key, jnp.arange(len(actions)))
    lengths = jnp.asarray(trained.bone_lengths, jnp.float32)

    def run(_, part):
        row_keys, labels = part
        return _generate(training, trained.state, lengths, jnp.float32(trained.root_height), row_keys, labels,
                         skeleton)

    out = map_in_chunks(run, (np.asarray(jax.random.key_data(keys)), actions.astype(np.int32)), chunk)
    return {**out, "lengths": np.full(len(actions), g.frames, np.int32), "actions": actions.astype(np.int32)}


def actformer_sampler(trained: ActFormerFit, training, skeleton: Skeleton):
    """The evaluation protocol's sampler ``(key, actions [N], durations [N]) -> motions``. ActFormer generates
    ``training.generator.frames`` frames: other durations are refused."""
    _check_skeleton(training, skeleton)
    frames = training.generator.frames

    def sampler(key, actions, durations):
        check_durations(durations, len(actions))
        durations = np.asarray(durations)
        if np.any(durations != frames):
            raise ValueError(f"durations: ActFormer generates {frames} frames; got {sorted(set(durations.tolist()))}")
        return generate_motions(trained, training, key, actions, skeleton, chunk=max(len(actions), 1))

    return sampler
