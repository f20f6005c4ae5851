"""Training ACTOR: what every ACTOR experiment shares.

:class:`ActorTraining` holds the data window, the optimiser (AdamW, fixed learning rate, batch 20 in the
paper), the loss weights and the loop (length of training, logging, checkpoints); :func:`train_actor`
fits the model on a dataset with :func:`~jaxmotion.train.fit.fit` (jitted step, ``fold_in(key, step)``
randomness, orbax checkpoints, resume). Generation, denoising and the protocol's sampler are in
:mod:`jaxmotion.pipelines.actor`; the paper's tables' rows and profile sizes in :mod:`jaxmotion.recipes.actor`.

Axes: B batch, T frames, J joints, C channels.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import jax
import optax

from jaxmotion.config import check_at_least
from jaxmotion.data.motion import MotionDataset
from jaxmotion.data.pipeline import BatchSpec
from jaxmotion.geometry.body import BodyModel
from jaxmotion.geometry.skeletons import Skeleton
from jaxmotion.losses.actor import ActorLossWeights, actor_loss
from jaxmotion.models.actor import ActorConfig, AnyActorParams, autoencode, init_actor, to_features
from jaxmotion.train.fit import fit
from jaxmotion.train.loop import LoopConfig
from jaxmotion.train.state import TrainState


@dataclasses.dataclass(frozen=True)
class ActorTraining:
    """How ACTOR is trained. Paper: AdamW 1e-4 (weight decay 0.01, PyTorch's default), batch 20, 60-frame
    crops; ``min_length`` set gives the variable-length fine-tuning (60-100 frames, ``window`` 100).
    ``loop``: the number of steps and the logging / checkpoint cadence. ``canonical``: windows turned to the
    canonical frame (ACTOR's data); False keeps the dataset's frame (ActFormer's tables, whose evaluators read
    the camera's frame)."""

    model: ActorConfig
    loop: LoopConfig
    losses: ActorLossWeights = ActorLossWeights()
    batch_size: int = 20
    window: int = 60
    min_length: int | None = None
    learning_rate: float = 1e-4
    weight_decay: float = 0.01
    canonical: bool = True

    def __post_init__(self):
        check_at_least(self, 1, "batch_size", "window", "min_length")

    @property
    def batch(self) -> BatchSpec:
        return BatchSpec(batch_size=self.batch_size, window=self.window, min_length=self.min_length,
                         canonical=self.canonical)


def actor_inputs(batch: dict[str, jax.Array], rep: str) -> tuple[jax.Array, jax.Array, jax.Array]:
    """A pipeline batch -> ACTOR's ``(x [B, T, J + 1, C], actions [B], mask [B, T])``."""
    if "rotations" not in batch:
        raise ValueError("batch: ACTOR trains on joint rotations; this dataset has joint positions only")
    return to_features(batch["rotations"], batch["translation"], rep), batch["actions"], batch["mask"]


def actor_state(training: ActorTraining, key: jax.Array) -> TrainState:
    """Fresh parameters and AdamW state for ``training``."""
    optimizer = optax.adamw(training.learning_rate, weight_decay=training.weight_decay)
    return TrainState.create(init_actor(key, training.model), optimizer)


def actor_step(training: ActorTraining, skeleton: Skeleton, body: BodyModel | None = None):
    """The training step ``(state, batch, key) -> (state, loss terms)`` (the loop jits it): ACTOR's losses on
    a pipeline batch, dropout from ``key``, one AdamW update."""
    config = training.model

    def step_fn(state, batch, key):
        x, actions, mask = actor_inputs(batch, config.rep)

        def loss_fn(params):
            out = autoencode(config, params, x, actions, mask, key=key, train=True)
            return actor_loss(out["output"], x, mask, out["mu"], out["logvar"], rep=config.rep,
                              weights=training.losses, skeleton=skeleton, body=body)

        (_, terms), grads = jax.value_and_grad(loss_fn, has_aux=True)(state.params)
        return state.apply_gradients(grads), terms

    return step_fn


def train_actor(data: MotionDataset, training: ActorTraining, key: jax.Array, workdir: str | Path | None = None, *,
                body: BodyModel | None = None, progress: bool = True, **loop_options) -> AnyActorParams:
    """Fit ACTOR on ``data`` (resuming from ``workdir``'s checkpoints when present); returns the parameters.
    ``loop_options``: the loop's ``mesh``, ``init_from``, ``eval_fn`` (:func:`jaxmotion.train.loop.train`)."""
    if training.model.num_classes != data.num_classes or training.model.num_joints != data.skeleton.num_joints + 1:
        raise ValueError(f"ActorTraining.model: expects {training.model.num_classes} classes and "
                         f"{training.model.num_joints - 1} joints, {data.name} has {data.num_classes} and "
                         f"{data.skeleton.num_joints}")
    state = fit(data, key, init_state=lambda k: actor_state(training, k),
                step_fn=actor_step(training, data.skeleton, body), batch=training.batch, loop=training.loop,
                workdir=workdir, progress=progress, **loop_options)
    return state.params
