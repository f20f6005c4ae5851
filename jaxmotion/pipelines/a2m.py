"""Action2Motion's GRU VAE (:mod:`jaxmotion.models.a2m`) put to use: its sampler for the evaluation protocol, and
:class:`A2MGenerator`, a trained model as an artefact (:mod:`jaxmotion.pipelines.artefacts`).

Axes: N motions, T frames, J joints, F = J·3.
"""

from __future__ import annotations

import dataclasses
import functools

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.data.pipeline import window_frames
from jaxmotion.geometry.skeletons import Skeleton
from jaxmotion.data.labels import check_actions, check_durations
from jaxmotion.models.a2m import A2MVAEConfig, A2MVAEParams, a2m_generate, init_a2m_vae
from jaxmotion.pipelines.artefacts import DataFacts, ParamsGenerator


@functools.partial(jax.jit, static_argnames=("frames", "config"))
def _generate_rows(params: A2MVAEParams, key_data: jax.Array, actions: jax.Array, *, frames: int,
                   config: A2MVAEConfig) -> jax.Array:
    """One motion per row, row n drawn from its own key: ``[N]`` keys and actions -> ``poses [N, frames, F]``."""
    def one(k, action):
        return a2m_generate(config, params, action[None], frames, key=jax.random.wrap_key_data(k))[0]

    return jax.vmap(one)(key_data, actions)


def a2m_sampler(params: A2MVAEParams, config: A2MVAEConfig, skeleton: Skeleton):
    """The evaluation protocol's sampler ``(key, actions [N], durations [N]) -> motions``: ``joints [N, T, J, 3]``
    (``T = max(durations)``), ``translation [N, T, 3]`` (the root joint's path: A2M models joints only),
    ``mask [N, T]``, ``lengths [N]`` and ``actions [N]``. A model whose ``pose_dim`` is P times the skeleton's
    J·3 writes P persons per frame, person-major: ``joints [N, P, T, J, 3]``, ``translation [N, P, T, 3]``.

    Row n is generated for its own duration (A2M's time counter runs over it) from ``fold_in(key, n)``, so
    a row does not depend on the others; frames past its duration repeat its last frame, as real windows do.
    """
    persons, rest = divmod(config.pose_dim, 3 * skeleton.num_joints)
    if rest or not persons:
        raise ValueError(f"skeleton: the model's pose_dim {config.pose_dim} is not a multiple of 3 × the "
                         f"{skeleton.num_joints} joints of {skeleton.name}")

    def sampler(key, actions, durations):
        check_actions(actions, config.num_classes)
        check_durations(durations, len(actions))
        actions, durations = np.asarray(actions, np.int32), np.asarray(durations, np.int32)
        if actions.size == 0:
            raise ValueError("actions: expected a non-empty [N] array of class ids, got none")
        keys = np.asarray(jax.vmap(lambda n: jax.random.key_data(jax.random.fold_in(key, n)))(
            jnp.arange(len(actions))))
        frames = int(durations.max())
        joints = np.empty((len(actions), frames, persons, skeleton.num_joints, 3), np.float32)
        for duration in np.unique(durations):  # one generation per distinct duration (the protocol has one)
            rows = np.flatnonzero(durations == duration)
            poses = _generate_rows(params, keys[rows], jnp.asarray(actions[rows]), frames=int(duration), config=config)
            index, _ = window_frames(jnp.zeros(1, jnp.int32), jnp.array([duration]), frames)  # repeat the last frame
            joints[rows] = np.asarray(poses).reshape(len(rows), int(duration), persons, -1, 3)[:, np.asarray(index[0])]
        joints = joints[:, :, 0] if persons == 1 else np.ascontiguousarray(np.moveaxis(joints, 2, 1))
        mask = np.arange(frames)[None] < durations[:, None]
        return {"joints": joints, "translation": joints[..., 0, :].copy(), "mask": mask, "lengths": durations,
                "actions": actions}

    return sampler


@dataclasses.dataclass(frozen=True, eq=False)
class A2MGenerator(ParamsGenerator):
    """A trained Action2Motion GRU VAE: its model, parameters, the data facts and ``frames`` (the window it
    trained on, the default duration)."""

    model: A2MVAEConfig
    params: A2MVAEParams
    facts: DataFacts
    frames: int = 60
    method = "a2m"
    init = staticmethod(init_a2m_vae)

    def sampler(self):
        return a2m_sampler(self.params, self.model, self.skeleton)
