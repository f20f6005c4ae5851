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

**Neural Marionette's adapted A2M** (its Table 1 baseline; :mod:`jaxmotion.models.a2m`, "Neural Marionette's
adaptation"): :class:`A2MActionTraining` and :func:`train_a2m_actions` train the same VAE on a multi-action
dataset's action items through the loop every trainer of that paper's tables runs
(:func:`jaxmotion.train.marionet.fit_action_items`), each batch read by
:func:`~jaxmotion.train.marionet.marionet_inputs` as MARIONET reads it: target poses ``[B, T, 135]`` in the
normalised frame of the last context pose, the mask of real frames, the multi-hot tags. The loss is A2M's own
(:func:`~jaxmotion.models.a2m.a2m_vae_loss`: Σ over real frames, the feedback quirk, the KL to the learned prior)
with the tags as the condition and the last context pose as frame 0's ``x_prev``; the next tag, the path and the
rest of the context are not used. Optimiser: A2M's (Adam 2e-4, coupled L2 1e-5).
"""

from __future__ import annotations

import dataclasses

import jax
import jax.numpy as jnp

from jaxmotion.config import check_at_least
from jaxmotion.data.mag_tags import TAGS, root_tag_mask
from jaxmotion.data.motion import MotionDataset
from jaxmotion.data.pipeline import BatchSpec
from jaxmotion.geometry.representations import POSE135_SIZE
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
from jaxmotion.train.marionet import fit_action_items, marionet_inputs
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


def a2m_state(training: A2MTraining | A2MActionTraining, key: jax.Array) -> TrainState:
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


# ------------------------------------------------------------------ Neural Marionette's adaptation: action items


@dataclasses.dataclass(frozen=True)
class A2MActionTraining:
    """How Neural Marionette's adapted A2M is trained on action items (the paper gives no settings for it).

    ``model``: ``pose_dim`` 135 (MARIONET's pose), ``num_classes`` 31 (the BABEL-MAG tags, multi-hot), A2M's own
    sizes (hidden 128, latent 30, 1/1/2 GRU layers) and its time counter; ``kl_weight`` 1e-3, the released Lie
    runs' HumanAct12 value (6D, like the Lie parameters, is a rotation representation of numbers about 1; the xyz
    runs' 1e-4 is for metres). ``optimizer``: A2M's Adam. ``batch_size``: A2M's own 128 (the baseline keeps its
    recipe except for the paper's two changes; MARIONET's is 30). ``max_frames``: actions longer than this are
    left out of training, as MARIONET's 120; ``length_buckets`` as MARIONET's
    (:class:`~jaxmotion.train.marionet.MarionetTraining`). ``loop``: A2M's 50k steps (the paper's), as
    :class:`A2MTraining`.
    """

    model: A2MVAEConfig = A2MVAEConfig(pose_dim=POSE135_SIZE, num_classes=len(TAGS), kl_weight=1e-3)
    loop: LoopConfig = LoopConfig(steps=50_000, log_every=100, checkpoint_every=1000)
    optimizer: A2MOptimizer = A2MOptimizer()
    batch_size: int = 128
    max_frames: int = 120
    length_buckets: int = 1

    def __post_init__(self):
        check_at_least(self, 1, "batch_size", "max_frames", "length_buckets")
        if self.model.pose_dim != POSE135_SIZE:
            raise ValueError(f"A2MActionTraining.model: expected pose_dim {POSE135_SIZE} (MARIONET's pose: 22 "
                             f"joints' 6D rotations + the root translation), got {self.model.pose_dim}")


def train_a2m_actions(data: MotionDataset, training: A2MActionTraining, key: jax.Array, workdir: str | None = None,
                      *, progress: bool = True, **loop_options) -> A2MVAEParams:
    """Fit the adapted A2M on the action items of ``data`` (a multi-action dataset: synth-mag, mag) with
    :func:`~jaxmotion.train.marionet.fit_action_items` (resuming from ``workdir``'s checkpoints when present);
    returns the parameters. ``loop_options`` go to the loop (``mesh``, ``init_from``, ``eval_fn``)."""
    if training.model.num_classes != data.num_classes:
        raise ValueError(f"A2MActionTraining.model.num_classes: {training.model.num_classes}, but {data.name} has "
                         f"{data.num_classes} tags")
    state = fit_action_items(data, key, num_tags=training.model.num_classes, batch_size=training.batch_size,
                             max_frames=training.max_frames, length_buckets=training.length_buckets,
                             init_state=lambda k: a2m_state(training, k),
                             step_fn=a2m_actions_step(training.model, root_tag_mask(data.class_names)),
                             loop=training.loop, workdir=workdir, progress=progress, **loop_options)
    return state.params


def a2m_actions_step(config: A2MVAEConfig, root_tags):
    """The training step on a batch of action items ``(state, batch, key) -> (state, loss terms)`` (the loop jits
    it): A2M's loss on the normalised target poses over real frames, conditioned on the multi-hot tags, with the
    last context pose as the first ``x_prev``; ``root_tags [C]`` only serves :func:`marionet_inputs` (whose path
    A2M does not read)."""
    root_tags = jnp.asarray(root_tags)

    def step_fn(state, batch, key):
        x = marionet_inputs(batch, root_tags)
        grads, metrics = jax.grad(a2m_vae_loss, argnums=1, has_aux=True)(
            config, state.params, x["target"], x["tags"], key=key, mask=x["mask"], first_pose=x["context"][:, -1])
        return state.apply_gradients(grads), metrics

    return step_fn
