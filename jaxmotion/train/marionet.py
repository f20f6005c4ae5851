"""Training MARIONET (Neural Marionette §4.2.2 and the supplement's §3): action items in, Adam, scheduled sampling.

**Batches** are whole action items (:meth:`~jaxmotion.data.motion.MotionDataset.action_items`: 6 context frames,
then the action, padded to the batch's longest), normalised at their last context frame
(:func:`~jaxmotion.geometry.kinematics.heading_transform`: facing +Z over the origin, the height kept) and turned
into the 135-number pose. The ground path is the normalised root's (x, z) over the action for actions with a
root-motion tag, zeros for the others (as the paper feeds in-place actions).

**Scheduled sampling for a Transformer** (Fig. 4): a teacher-forced pass gives P'; a second pass of the same
decoder (the same Z and controls) reads, at each frame after the first, the predicted pose of P' with probability
xi and the true one otherwise; xi rises linearly from 0 to 1 between the ``activate`` and ``accomplish`` fractions
of training (the paper's epochs 250 and 750 of 1,000). While it is on, the passes weigh lambda_1 = 0.1 and
lambda_2 = 0.9, else 1 and 0, and a second pass that would weigh 0 is not run (``jax.lax.cond``: before
``activate`` and while the gate is shut, the step costs what teacher forcing alone does;
``scheduled_sampling=False``, Table 2's ablation, never runs it). Where the paper is silent: frames are mixed
independently (one Bernoulli draw each); the predicted poses enter the second pass without gradient; the "close
enough" gate turns the second pass on for a batch only while the first pass's squared error (over real frames
and numbers, as the loss's rotation term) is below ``gate`` (:class:`MarionetTraining`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
import optax

from jaxmotion.config import check_at_least
from jaxmotion.data.mag_tags import root_tag_mask
from jaxmotion.data.motion import MotionDataset
from jaxmotion.data.pipeline import action_item_batches
from jaxmotion.geometry.representations import POSE135_SIZE
from jaxmotion.geometry.skeletons import SMPL24
from jaxmotion.losses.core import masked_mse
from jaxmotion.losses.marionet import MarionetLossWeights, marionet_loss, reconstruction
from jaxmotion.models.marionet import (CONTEXT, MarionetConfig, MarionetParams, decode, forward, init_marionet,
                                       normalised_poses)
from jaxmotion.train.fit import fit
from jaxmotion.train.loop import LoopConfig
from jaxmotion.train.state import TrainState


@dataclasses.dataclass(frozen=True)
class MarionetTraining:
    """How MARIONET is trained. Paper: Adam 1e-4, batch 30, scheduled sampling from 25% to 75% of training.

    ``gate``: the first pass's mean squared error below which the second pass counts ([U]: the paper says only
    "close enough"); 0.02 is about what holding the last context pose still scores on synth-mag, so the second pass
    counts once the first beats standing still (an untrained model scores some thirty times more). ``max_frames``:
    actions longer than this are left out of training (the model's longest; the paper's is unstated).
    ``length_buckets``: how many groups of similar durations batches are drawn from, each padded to its group's
    longest (:class:`~jaxmotion.data.pipeline.BatchSpec` ``buckets``; [U]: the paper does not say how batches are
    formed); 1 (the profiles' choice for MARIONET, :data:`~jaxmotion.recipes.marionette.LENGTH_BUCKETS` says why)
    pads every batch to the longest action item. With 4 on synth-mag's durations (30-120 frames) a step costs two
    thirds of a padded one, at one compilation per bucket.
    """

    model: MarionetConfig
    loop: LoopConfig
    losses: MarionetLossWeights = MarionetLossWeights()
    batch_size: int = 30
    learning_rate: float = 1e-4
    scheduled_sampling: bool = True
    activate: float = 0.25
    accomplish: float = 0.75
    gate: float = 0.02
    max_frames: int = 120
    length_buckets: int = 1

    def __post_init__(self):
        check_at_least(self, 1, "batch_size", "max_frames", "length_buckets")
        if not 0.0 <= self.activate < self.accomplish <= 1.0:
            raise ValueError(f"MarionetTraining.activate, accomplish: expected 0 <= activate < accomplish <= 1 "
                             f"(fractions of training), got {self.activate}, {self.accomplish}")
        if not self.learning_rate > 0 or not self.gate > 0:
            raise ValueError(f"MarionetTraining.learning_rate, gate: expected positive values, got "
                             f"{self.learning_rate}, {self.gate}")


def marionet_inputs(batch: dict[str, jax.Array], root_tags: jax.Array) -> dict[str, jax.Array]:
    """A batch of action items -> MARIONET's inputs in the normalised frame of each last context pose: ``context
    [B, K, 135]``, ``target [B, T, 135]``, ``mask [B, T]``, ``path [B, T, 2]``, ``tags``, ``next_tags [B, C]``."""
    poses, _, _ = normalised_poses(batch["rotations"], batch["translation"], CONTEXT - 1)  # [B, K + T, 135]
    moves = jnp.any(batch["tags"] & root_tags, axis=-1)  # [B]
    mask = batch["mask"][:, CONTEXT:]
    ground = poses[:, CONTEXT:, POSE135_SIZE - 3:][..., jnp.array([0, 2])]  # the normalised root's (x, z)
    path = jnp.where((moves[:, None] & mask)[..., None], ground, 0.0)
    return {"context": poses[:, :CONTEXT], "target": poses[:, CONTEXT:], "mask": mask, "path": path,
            "tags": batch["tags"], "next_tags": batch["next_tags"]}


def sampling_share(training: MarionetTraining, step: jax.Array) -> jax.Array:
    """xi at ``step``: 0 before ``activate``, 1 after ``accomplish``, linear between (fractions of the steps)."""
    progress = step / max(training.loop.steps, 1)
    return jnp.clip((progress - training.activate) / (training.accomplish - training.activate), 0.0, 1.0)


def marionet_state(training: MarionetTraining, key: jax.Array) -> TrainState:
    return TrainState.create(init_marionet(key, training.model), optax.adam(training.learning_rate))


def marionet_step(training: MarionetTraining, root_tags: np.ndarray):
    """The training step ``(state, batch, key) -> (state, loss terms)`` (the loop jits it)."""
    config, root_tags = training.model, jnp.asarray(root_tags)

    def step_fn(state, batch, key):
        x = marionet_inputs(batch, root_tags)
        k_first, k_mix, k_second = jax.random.split(key, 3)
        share = sampling_share(training, state.step)
        on = state.step >= training.activate * training.loop.steps

        def loss_fn(params: MarionetParams):
            first = forward(params, config, x["context"], x["tags"], x["next_tags"], x["path"], x["target"],
                            x["mask"], k_first)
            if not training.scheduled_sampling:  # teacher forcing alone: no second pass to run
                return marionet_loss(first.poses, None, x["target"], x["mask"], first.mu, first.log_variance,
                                     weights=training.losses, skeleton=SMPL24)
            close = jax.lax.stop_gradient(masked_mse(first.poses, x["target"], x["mask"])) < training.gate
            use = on & close

            def second_pass(params: MarionetParams):
                predicted = jax.lax.stop_gradient(first.poses[:, :-1])
                mixed = jnp.where(jax.random.bernoulli(k_mix, share, predicted.shape[:2])[..., None], predicted,
                                  x["target"][:, :-1])
                previous = jnp.concatenate([x["context"][:, -1:], mixed], axis=1)
                second = decode(params, config, first.controls, previous, x["mask"], k_second)
                return reconstruction(second, x["target"], x["mask"], training.losses, SMPL24)

            # a pass that weighs nothing is not run (a quarter of training and more, before the gate opens); its
            # terms then log as zeros, and "second pass" as the share of logged steps that ran it
            second = jax.lax.cond(use, second_pass, lambda p: jax.tree.map(
                jnp.zeros_like, jax.eval_shape(second_pass, p)), params)
            loss, terms = marionet_loss(first.poses, second, x["target"], x["mask"], first.mu, first.log_variance,
                                        weights=training.losses, skeleton=SMPL24,
                                        first_weight=jnp.where(use, 0.1, 1.0), second_weight=0.9)
            return loss, {**terms, "second pass": use.astype(loss.dtype), "sampled share": share * use}

        (_, terms), grads = jax.value_and_grad(loss_fn, has_aux=True)(state.params)
        return state.apply_gradients(grads), terms

    return step_fn


def fit_action_items(data: MotionDataset, key: jax.Array, *, num_tags: int, batch_size: int, max_frames: int,
                     length_buckets: int, init_state: Callable[[jax.Array], TrainState], step_fn: Callable,
                     loop: LoopConfig, workdir: str | Path | None = None, progress: bool = True,
                     **loop_options) -> TrainState:
    """The shared loop (:func:`~jaxmotion.train.fit.fit`) on the action items of ``data`` (a multi-action dataset:
    synth-mag, mag) of at most ``max_frames`` frames, batched whole (:func:`~jaxmotion.data.pipeline.
    action_item_batches`, in ``length_buckets`` groups of similar durations): what every trainer of Neural
    Marionette's tables (MARIONET and the baselines it is compared with) runs, ``step_fn`` reading each batch
    through :func:`marionet_inputs`."""
    if data.num_classes != num_tags:
        raise ValueError(f"model.num_tags: {num_tags}, but {data.name} has {data.num_classes} tags")
    if data.rotations is None:
        raise ValueError(f"data: {data.name} has joint positions only; Neural Marionette's pose is joint rotations")
    items = data.action_items(CONTEXT)
    keep = np.flatnonzero(items.durations <= max_frames)
    if not len(keep):
        raise ValueError(f"data: no action of {data.name}/{data.split} has context frames and at most "
                         f"{max_frames} frames")
    items = items.subset(keep)
    spec, labels = action_item_batches(items, batch_size, buckets=length_buckets)
    return fit(items.data, key, init_state=init_state, step_fn=step_fn, batch=spec, labels=labels, loop=loop,
               workdir=workdir, progress=progress, **loop_options)


def train_marionet(data: MotionDataset, training: MarionetTraining, key: jax.Array,
                   workdir: str | Path | None = None, *, progress: bool = True, **loop_options) -> MarionetParams:
    """Fit MARIONET on the action items of ``data`` (:func:`fit_action_items`), resuming from ``workdir``'s
    checkpoints; returns the parameters. ``loop_options``: the loop's ``mesh``, ``init_from``, ``eval_fn``."""
    state = fit_action_items(data, key, num_tags=training.model.num_tags, batch_size=training.batch_size,
                             max_frames=training.max_frames, length_buckets=training.length_buckets,
                             init_state=lambda k: marionet_state(training, k),
                             step_fn=marionet_step(training, root_tag_mask(data.class_names)), loop=training.loop,
                             workdir=workdir, progress=progress, **loop_options)
    return state.params
