"""Training the MANN baseline of Neural Marionette's Table 1 (:mod:`jaxmotion.models.mann`) on action items.

The same batches as MARIONET (:func:`~jaxmotion.train.marionet.fit_action_items`: whole action items with their 6
context frames, normalised at the last context pose, read through :func:`~jaxmotion.train.marionet.marionet_inputs`,
the ground path zeros for in-place actions) and the same reconstruction loss (:func:`~jaxmotion.losses.marionet.
reconstruction`: L_R, L_D and L_J, each with its velocity term, weighed by :class:`~jaxmotion.losses.marionet.
MarionetLossWeights`; the KL weight is unused, MANN has no latent) on the teacher-forced prediction of every frame
(:func:`~jaxmotion.models.mann.mann_forward`), so the two rows differ by the network alone.

Where the paper is silent: teacher forcing only (MANN trains on true inputs; no scheduled sampling), Adam at 1e-4
with batches of 30 as MARIONET (MANN's AdamWR, Adam with decoupled weight decay and warm restarts, is left out).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
import optax

from jaxmotion.config import check_at_least
from jaxmotion.data.mag_tags import root_tag_mask
from jaxmotion.data.motion import MotionDataset
from jaxmotion.geometry.skeletons import SMPL24
from jaxmotion.losses.marionet import MarionetLossWeights, reconstruction
from jaxmotion.models.mann import MannConfig, MannParams, init_mann, mann_forward
from jaxmotion.train.loop import LoopConfig
from jaxmotion.train.marionet import fit_action_items, marionet_inputs
from jaxmotion.train.state import TrainState


@dataclasses.dataclass(frozen=True)
class MannTraining:
    """How MANN is trained: Adam ``learning_rate`` (1e-4) on batches of ``batch_size`` (30) action items of at most
    ``max_frames`` (120) frames in ``length_buckets`` groups of similar durations (as MARIONET's
    :class:`~jaxmotion.train.marionet.MarionetTraining`), teacher forced, the loss weights ``losses`` (MARIONET's;
    ``kl`` unused)."""

    model: MannConfig
    loop: LoopConfig
    losses: MarionetLossWeights = MarionetLossWeights()
    batch_size: int = 30
    learning_rate: float = 1e-4
    max_frames: int = 120
    length_buckets: int = 1

    def __post_init__(self):
        check_at_least(self, 1, "batch_size", "max_frames", "length_buckets")
        if not self.learning_rate > 0:
            raise ValueError(f"MannTraining.learning_rate: expected a positive value, got {self.learning_rate}")


def mann_state(training: MannTraining, key: jax.Array) -> TrainState:
    return TrainState.create(init_mann(key, training.model), optax.adam(training.learning_rate))


def mann_step(training: MannTraining, root_tags: np.ndarray):
    """The training step ``(state, batch, key) -> (state, loss terms)`` (the loop jits it): the reconstruction
    loss of the teacher-forced poses, dropout drawn from ``key``."""
    config, root_tags = training.model, jnp.asarray(root_tags)

    def step_fn(state, batch, key):
        x = marionet_inputs(batch, root_tags)

        def loss_fn(params: MannParams):
            poses = mann_forward(params, config, x["context"], x["tags"], x["next_tags"], x["path"], x["target"],
                                 x["mask"], key)
            loss, terms = reconstruction(poses, x["target"], x["mask"], training.losses, SMPL24)
            return loss, {**terms, "loss": loss}

        (_, terms), grads = jax.value_and_grad(loss_fn, has_aux=True)(state.params)
        return state.apply_gradients(grads), terms

    return step_fn


def train_mann(data: MotionDataset, training: MannTraining, key: jax.Array, workdir: str | Path | None = None, *,
               progress: bool = True, **loop_options) -> MannParams:
    """Fit MANN on the action items of ``data`` (a multi-action dataset: synth-mag, mag;
    :func:`~jaxmotion.train.marionet.fit_action_items`), resuming from ``workdir``'s checkpoints; returns the
    parameters. ``loop_options``: the loop's ``mesh``, ``init_from``, ``eval_fn``."""
    state = fit_action_items(data, key, num_tags=training.model.num_tags, batch_size=training.batch_size,
                             max_frames=training.max_frames, length_buckets=training.length_buckets,
                             init_state=lambda k: mann_state(training, k),
                             step_fn=mann_step(training, root_tag_mask(data.class_names)), loop=training.loop,
                             workdir=workdir, progress=progress, **loop_options)
    return state.params
