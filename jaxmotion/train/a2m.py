"""Training Action2Motion's GRU VAE (:mod:`jaxmotion.models.a2m`) on a dataset's joint coordinates: the
recurrent baseline of ACTOR's Table 3.

:class:`A2MTraining` holds the model, the authors' optimiser (:class:`~jaxmotion.models.a2m.A2MOptimizer`),
batch size, clip length (``window``) and the loop (steps, logging, checkpoints); :func:`train_a2m` fits the
model with :func:`~jaxmotion.train.fit.fit` (jitted step, ``fold_in(key, step)`` randomness, orbax
checkpoints, resume). Its generator is :class:`jaxmotion.pipelines.a2m.A2MGenerator`; its table rows and
profile sizes are in :mod:`jaxmotion.recipes.a2m`.

Data as Action2Motion reads it: ``window``-frame windows of joint positions, flattened joint-major to
``F = J·3`` per frame; clips shorter than the window are padded by repeating their last frame and the loss
covers the padding, as A2M's loaders pad and its trainer has no mask. Motions of P persons are read as one
body of P·J joints per frame, person-major (ActFormer's way of scaling the one-person baselines to NTU-2P:
``pose_dim`` = P·J·3). The windows are in the canonical frame
(root of frame 0 at the origin, facing +Z; ``canonical=False``: only moved to the origin, A2M's own
normalisation) because A2M's HumanAct12 joints come in a canonical frame and ACTOR, which Table 3 compares
with, trains on canonical windows too.

Axes: B batch, N motions, T frames, J joints, F = J·3.
"""

from __future__ import annotations

import dataclasses

import jax
import jax.numpy as jnp

from jaxmotion.config import check_at_least
from jaxmotion.data.motion import MotionDataset
from jaxmotion.data.pipeline import BatchSpec
from jaxmotion.models.a2m import (
    A2MOptimizer,
    A2MVAEConfig,
    A2MVAEParams,
    a2m_optimizer,
    a2m_vae_loss,
    init_a2m_vae,
)
from jaxmotion.train.fit import fit
from jaxmotion.train.loop import LoopConfig
from jaxmotion.train.state import TrainState


@dataclasses.dataclass(frozen=True)
class A2MTraining:
    """How Action2Motion is trained: ``model`` (its ``pose_dim`` is the dataset's J·3), the authors' Adam
    (``optimizer``), ``batch_size`` (128), ``window`` (the clip length, A2M's ``motion_length``: 60, CMU mocap
    100), the window's frame (``canonical``) and ``loop`` (FACTS / paper: 50k steps; the released xyz
    ``opt.txt`` files record 300k for NTU-13 and mocap, 500k for HumanAct12)."""

    model: A2MVAEConfig
    loop: LoopConfig = LoopConfig(steps=50_000, log_every=100, checkpoint_every=1000)
    optimizer: A2MOptimizer = A2MOptimizer()
    batch_size: int = 128
    window: int = 60
    canonical: bool = True

    def __post_init__(self):
        check_at_least(self, 1, "batch_size", "window")

    @property
    def batch(self) -> BatchSpec:
        return BatchSpec(batch_size=self.batch_size, window=self.window, canonical=self.canonical)


def _check_data(training: A2MTraining, data: MotionDataset) -> None:
    model, joints = training.model, data.persons * data.skeleton.num_joints
    if model.pose_dim != 3 * joints or model.num_classes != data.num_classes:
        raise ValueError(f"A2MTraining.model: expects pose_dim {model.pose_dim} and {model.num_classes} classes; "
                         f"{data.name} has {joints} joints in all persons (pose_dim {3 * joints}) and "
                         f"{data.num_classes} classes")


def train_a2m(data: MotionDataset, training: A2MTraining, key: jax.Array, workdir: str | None = None, *,
              progress: bool = True, **loop_options) -> A2MVAEParams:
    """Fit the GRU VAE on ``data``'s joints (resuming from ``workdir``'s checkpoints when present); returns the
    parameters. ``key`` splits into initialisation, data order and the loop's per-step keys (:func:`fit`);
    ``loop_options`` go to the loop (``mesh``, ``init_from``, ``eval_fn``)."""
    _check_data(training, data)
    state = fit(data, key, init_state=lambda k: a2m_state(training, k), step_fn=a2m_step(training.model),
                batch=training.batch, loop=training.loop, workdir=workdir, progress=progress, **loop_options)
    return state.params


def a2m_state(training: A2MTraining, key: jax.Array) -> TrainState:
    """Fresh parameters and the authors' Adam state for ``training``."""
    return TrainState.create(init_a2m_vae(key, training.model), a2m_optimizer(training.optimizer))


def a2m_step(config: A2MVAEConfig):
    """The training step ``(state, batch, key) -> (state, loss terms)`` (the loop jits it): the VAE loss on a
    pipeline batch's joints (flattened joint-major, ``[B, T, J·3]``; several persons ``[B, P, T, J, 3]`` person-major,
    ``[B, T, P·J·3]``), the feedback draw and the reparameterisation from ``key``, one Adam update."""

    def step_fn(state, batch, key):
        joints = batch["joints"]
        if joints.ndim == 5:  # [B, P, T, J, 3] -> [B, T, P, J, 3]: every person's joints in each frame
            joints = jnp.moveaxis(joints, 1, 2)
        poses = joints.reshape(*joints.shape[:2], -1)
        grads, metrics = jax.grad(a2m_vae_loss, argnums=1, has_aux=True)(config, state.params, poses, batch["actions"],
                                                                        key=key)
        return state.apply_gradients(grads), metrics

    return step_fn
