"""Training Action2Motion's GRU VAE (:mod:`jaxmotion.models.a2m`) on a dataset's joint coordinates, and its
sampler for the evaluation protocol: the recurrent baseline of ACTOR's Table 3.

:class:`A2MTraining` holds the model, the authors' optimisation settings (:class:`A2MTrainConfig`: batch,
iterations, clip length, Adam) and the loop's cadence; :func:`train_a2m` fits the model with the minimal
loop (jitted step, ``fold_in(key, step)`` randomness, orbax checkpoints, resume); :func:`a2m_sampler`
generates motions in the form the protocol scores.

Data as Action2Motion reads it: ``frames``-frame windows of joint positions, flattened joint-major to
``F = J·3`` per frame; clips shorter than the window are padded by repeating their last frame and the loss
covers the padding, as A2M's loaders pad and its trainer has no mask. The windows are in the canonical frame
(root of frame 0 at the origin, facing +Z; ``canonical=False``: only moved to the origin, A2M's own
normalisation) because A2M's HumanAct12 joints come in a canonical frame and ACTOR, which Table 3 compares
with, trains on canonical windows too.

Axes: B batch, N motions, T frames, J joints, F = J·3.
"""

from __future__ import annotations

import dataclasses
import functools

import jax
import jax.numpy as jnp
import numpy as np
from flax.training.train_state import TrainState

from jaxmotion.data.motion import MotionDataset
from jaxmotion.data.pipeline import BatchSpec, make_batch_fn, window_frames
from jaxmotion.models.a2m import (
    A2MTrainConfig,
    A2MVAEConfig,
    A2MVAEParams,
    a2m_generate,
    a2m_optimizer,
    a2m_vae_loss,
    init_a2m_vae,
)
from jaxmotion.train.loop import LoopConfig, train


@dataclasses.dataclass(frozen=True)
class A2MTraining:
    """How Action2Motion is trained: ``model`` (its ``pose_dim`` is the dataset's J·3), ``train`` (Adam,
    batch, ``iterations`` = steps, ``frames`` = window), the window's frame (``canonical``) and the loop's
    logging and checkpoint cadence."""

    model: A2MVAEConfig
    train: A2MTrainConfig = A2MTrainConfig()
    canonical: bool = True
    log_every: int = 100
    checkpoint_every: int = 1000

    def __post_init__(self):
        if self.train.iterations < 0 or self.train.batch_size < 1 or self.train.frames < 1:
            raise ValueError(f"A2MTraining.train: iterations must be >= 0, batch_size and frames >= 1; got "
                             f"{self.train.iterations}, {self.train.batch_size}, {self.train.frames}")


def _check_data(training: A2MTraining, data: MotionDataset) -> None:
    model, joints = training.model, data.skeleton.num_joints
    if model.pose_dim != 3 * joints or model.num_classes != data.num_classes:
        raise ValueError(f"A2MTraining.model: expects pose_dim {model.pose_dim} and {model.num_classes} classes; "
                         f"{data.name} has {joints} joints (pose_dim {3 * joints}) and {data.num_classes} classes")


def train_a2m(data: MotionDataset, training: A2MTraining, key: jax.Array, workdir: str | None = None, *,
              progress: bool = True) -> A2MVAEParams:
    """Fit the GRU VAE on ``data``'s joints (resuming from ``workdir``'s checkpoints when present); returns the
    parameters. ``key`` splits into initialisation, data order and the loop's per-step keys."""
    _check_data(training, data)
    config = training.model
    k_init, k_data, k_train = jax.random.split(key, 3)
    state = TrainState.create(apply_fn=None, params=init_a2m_vae(k_init, config), tx=a2m_optimizer(training.train))
    spec = BatchSpec(batch_size=training.train.batch_size, window=training.train.frames, canonical=training.canonical)

    def step_fn(state, batch, key):
        poses = batch["joints"].reshape(*batch["joints"].shape[:2], -1)  # [B, T, J·3], joint-major
        grads, metrics = jax.grad(a2m_vae_loss, has_aux=True)(state.params, key, poses, batch["actions"], config)
        return state.apply_gradients(grads=grads), metrics

    loop = LoopConfig(steps=training.train.iterations, log_every=training.log_every,
                      checkpoint_every=training.checkpoint_every)
    state = train(state, step_fn, make_batch_fn(data, k_data, spec), key=k_train, config=loop, workdir=workdir,
                  progress=progress)
    return state.params


@functools.partial(jax.jit, static_argnames=("frames", "config"))
def _generate_rows(params: A2MVAEParams, key_data: jax.Array, actions: jax.Array, *, frames: int,
                   config: A2MVAEConfig) -> jax.Array:
    """One motion per row, row n drawn from its own key: ``[N]`` keys and actions -> ``poses [N, frames, F]``."""
    def one(k, action):
        return a2m_generate(params, jax.random.wrap_key_data(k), action[None], frames, config)[0]

    return jax.vmap(one)(key_data, actions)


def a2m_sampler(params: A2MVAEParams, training: A2MTraining, skeleton):
    """The evaluation protocol's sampler ``(key, actions [N], durations [N]) -> motions``: ``joints [N, T, J, 3]``
    (``T = max(durations)``), ``translation [N, T, 3]`` (the root joint's path: A2M models joints only),
    ``mask [N, T]``, ``lengths [N]`` and ``actions [N]``.

    Row n is generated for its own duration (A2M's time counter runs over it) from ``fold_in(key, n)``, so
    a row does not depend on the others; frames past its duration repeat its last frame, as real windows do.
    """
    config = training.model
    if config.pose_dim != 3 * skeleton.num_joints:
        raise ValueError(f"skeleton: the model's pose_dim {config.pose_dim} is not 3 × the {skeleton.num_joints} "
                         f"joints of {skeleton.name}")

    def sampler(key, actions, durations):
        actions, durations = np.asarray(actions, np.int32), np.asarray(durations, np.int32)
        if actions.ndim != 1 or durations.shape != actions.shape or durations.size == 0 or durations.min() < 1:
            raise ValueError(f"actions, durations: expected two non-empty [N] arrays, durations >= 1; got shapes "
                             f"{actions.shape}, {durations.shape}")
        keys = np.asarray(jax.vmap(lambda n: jax.random.key_data(jax.random.fold_in(key, n)))(
            jnp.arange(len(actions))))
        frames = int(durations.max())
        joints = np.empty((len(actions), frames, skeleton.num_joints, 3), np.float32)
        for duration in np.unique(durations):  # one generation per distinct duration (the protocol has one)
            rows = np.flatnonzero(durations == duration)
            poses = _generate_rows(params, keys[rows], jnp.asarray(actions[rows]), frames=int(duration), config=config)
            index, _ = window_frames(jnp.zeros(1, jnp.int32), jnp.array([duration]), frames)  # repeat the last frame
            joints[rows] = np.asarray(poses).reshape(len(rows), int(duration), -1, 3)[:, np.asarray(index[0])]
        mask = np.arange(frames)[None] < durations[:, None]
        return {"joints": joints, "translation": joints[:, :, 0].copy(), "mask": mask, "lengths": durations,
                "actions": actions}

    return sampler
