"""ActFormer put to use: generated motions as the library's batch dict, and the evaluation protocol's sampler.

The generator writes ActFormer's representations (:mod:`jaxmotion.geometry.representations`); the library's
motions are joint positions (plus rotations and translation for SMPL data), so :func:`to_motions` turns them
back:

* ``skeleton`` output (root + unit limb vectors): joints rebuilt from the generated root along the unit
  vectors with the training data's mean bone lengths (ActFormer's ``avglength``, kept in :class:`ActFormerGenerator`);
  ``translation`` is the rebuilt root. A recogniser reading ``limbs`` recovers the unit vectors to 1e-4.
  ActFormer's root is the clip's mean root removed, so the body's height is lost: the motions are lifted by
  the training data's mean root height (:class:`ActFormerGenerator`), standing on the floor on average (the
  evaluators remove it again).
* ``smpl`` output (rot6d + translation row): the rotations as axis-angle, the translation (de-meaned over the
  clip, as generated), joints by forward kinematics on the skeleton's rest offsets.

:class:`ActFormerGenerator` is a trained generator as an artefact (:mod:`jaxmotion.pipelines.artefacts`);
:func:`generate_motions` draws row n's latent sequence from ``fold_in(key, n)``, so a motion does not depend on
how many are drawn with it or on the chunk size; :func:`actformer_sampler` is the protocol's sampler.

Axes: N motions, P persons, T frames, J joints (V = J + 1 generator joints for SMPL), C channels.
"""

from __future__ import annotations

import dataclasses
import functools
from pathlib import Path
from typing import Any

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
from jaxmotion.models.actformer_prior import ActFormerModel, generator_network, latent_factors, sample_latents
from jaxmotion.pipelines.artefacts import Artefact, DataFacts, SamplingGenerator, save_artefact


@dataclasses.dataclass(frozen=True, eq=False)
class ActFormerGenerator(SamplingGenerator):
    """A trained ActFormer (or CSGN) generator: its model and prior, parameters and non-trained state
    (``buffers``: spectral-norm vectors or BatchNorm statistics), the training data's mean bone lengths ``[J]``
    that skeleton output is rebuilt with, its mean root height (metres, up the library's +Y) that generated
    motions are lifted by (:meth:`trained_on`), and the data facts."""

    model: ActFormerModel
    params: Any
    buffers: Any
    bone_lengths: np.ndarray
    root_height: float
    facts: DataFacts
    method = "actformer"

    def __post_init__(self):
        _check_skeleton(self.model, self.facts.skeleton)

    @classmethod
    def trained_on(cls, model: ActFormerModel, params: Any, buffers: Any, data: MotionDataset) -> ActFormerGenerator:
        """The generator trained on ``data``, with its mean bone lengths (over all frames and persons) and mean
        root height."""
        lengths = np.asarray(mean_bone_lengths(jnp.asarray(data.joints), data.skeleton.parents))
        return cls(model, params, buffers, lengths, float(np.mean(data.joints[..., 0, 1])), DataFacts.of(data))

    @property
    def frames(self) -> int:
        return self.model.generator.frames

    def sampler(self):
        return actformer_sampler(self)

    def save(self, folder: str | Path) -> Path:
        return save_artefact(folder, self.method, self.model, self.facts,
                             {"params": self.params, "buffers": self.buffers, "bone_lengths": self.bone_lengths},
                             {"root_height": self.root_height})

    @classmethod
    def load(cls, artefact: Artefact) -> ActFormerGenerator:
        g = artefact.model.generator
        params, buffers = jax.eval_shape(lambda k: generator_network(g).init_generator(k, g), jax.random.key(0))
        return cls(artefact.model, artefact.tree("params", params), artefact.tree("buffers", buffers),
                   artefact.array("bone_lengths"), float(artefact.settings["root_height"]), artefact.facts)


def _check_skeleton(model: ActFormerModel, skeleton: Skeleton) -> None:
    g = model.generator
    joints = g.joints - (1 if g.output == "smpl" else 0)
    if skeleton.num_joints != joints:
        raise ValueError(f"skeleton: the generator writes {joints} joints, {skeleton.name} has {skeleton.num_joints}")
    if g.output == "smpl" and skeleton.offsets is None:
        raise ValueError(f"skeleton: SMPL output needs rest offsets for forward kinematics; {skeleton.name} has none")
    if g.output == "raw":
        raise ValueError("generator.output: 'raw' output has no motion to rebuild; use 'skeleton' or 'smpl'")


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


@functools.partial(jax.jit, static_argnames=("model", "skeleton"))
def _generate(model: ActFormerModel, params: Any, buffers: Any, bone_lengths: jax.Array, root_height: jax.Array,
              keys: jax.Array, actions: jax.Array, skeleton: Skeleton) -> dict[str, jax.Array]:
    factors = latent_factors(model)
    z = jax.vmap(lambda k: sample_latents(model, factors, jax.random.wrap_key_data(k), 1)[0])(keys)
    motion, _ = generator_network(model.generator).generate(model.generator, params, buffers, z, actions)
    return to_motions(motion, model.generator.output, skeleton, bone_lengths, root_height)


def generate_motions(generator: ActFormerGenerator, key: jax.Array, actions, *, chunk: int = 256
                     ) -> dict[str, np.ndarray]:
    """Motions for ``actions [N]`` (evaluation mode: the stored power-iteration vectors), as a host batch dict:
    :func:`to_motions`' arrays plus ``lengths [N]`` and ``actions [N]``; all ``generator.frames`` long.
    Row n's latent comes from ``fold_in(key, n)``."""
    model = generator.model
    actions = np.asarray(actions)
    check_actions(actions, model.generator.num_classes)
    keys = jax.vmap(jax.random.fold_in, in_axes=(None, 0))(key, jnp.arange(len(actions)))
    lengths = jnp.asarray(generator.bone_lengths, jnp.float32)

    def run(_, part):
        row_keys, labels = part
        return _generate(model, generator.params, generator.buffers, lengths, jnp.float32(generator.root_height),
                         row_keys, labels, generator.skeleton)

    out = map_in_chunks(run, (np.asarray(jax.random.key_data(keys)), actions.astype(np.int32)), chunk)
    return {**out, "lengths": np.full(len(actions), generator.frames, np.int32), "actions": actions.astype(np.int32)}


def actformer_sampler(generator: ActFormerGenerator):
    """The evaluation protocol's sampler ``(key, actions [N], durations [N]) -> motions``. ActFormer generates
    ``generator.frames`` frames: other durations are refused."""
    frames = generator.frames

    def sampler(key, actions, durations):
        check_durations(durations, len(actions))
        durations = np.asarray(durations)
        if np.any(durations != frames):
            raise ValueError(f"durations: ActFormer generates {frames} frames; got {sorted(set(durations.tolist()))}")
        return generate_motions(generator, key, actions, chunk=max(len(actions), 1))

    return sampler
