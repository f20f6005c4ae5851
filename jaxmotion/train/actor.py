"""Training ACTOR: what every ACTOR experiment shares.

:class:`ActorTraining` holds the data window, the optimiser (AdamW, fixed learning rate, batch 20 in the
paper), the loss weights and the length of training; :func:`train_actor` fits the model on a dataset
with the minimal loop (jitted step, ``fold_in(key, step)`` randomness, orbax checkpoints, resume);
:func:`motions_from_features` turns the model's tensor into the library's motions (generation, denoising
and the protocol's sampler are in :mod:`jaxmotion.pipelines.actor`).

Axes: B batch, T frames, J joints, C channels.
"""

from __future__ import annotations

import dataclasses

import jax
import numpy as np
import optax
from flax.training.train_state import TrainState

from jaxmotion.data.motion import MotionDataset
from jaxmotion.data.pipeline import BatchSpec, from_actor_features, make_batch_fn, to_actor_features
from jaxmotion.geometry.body import BodyModel
from jaxmotion.geometry.kinematics import forward_kinematics
from jaxmotion.geometry.rotations import REPRESENTATIONS, axis_angle_to_matrix
from jaxmotion.geometry.skeletons import Skeleton
from jaxmotion.losses.actor import ActorLossWeights, actor_loss
from jaxmotion.models.actor import ActorConfig, AnyActorParams, autoencode, init_actor
from jaxmotion.train.loop import LoopConfig, train


@dataclasses.dataclass(frozen=True)
class ActorTraining:
    """How ACTOR is trained. Paper: AdamW 1e-4 (weight decay 0.01, PyTorch's default), batch 20, 60-frame
    crops; ``min_length`` set gives the variable-length fine-tuning (60-100 frames, ``window`` 100)."""

    model: ActorConfig
    steps: int
    rep: str = "rot6d"
    losses: ActorLossWeights = ActorLossWeights()
    batch_size: int = 20
    window: int = 60
    min_length: int | None = None
    learning_rate: float = 1e-4
    weight_decay: float = 0.01
    log_every: int = 100
    checkpoint_every: int = 1000

    def __post_init__(self):
        if self.rep not in REPRESENTATIONS:
            raise ValueError(f"ActorTraining.rep: expected one of {sorted(REPRESENTATIONS)}, got {self.rep!r}")
        channels = int(np.prod(REPRESENTATIONS[self.rep]))
        if self.model.channels != channels:
            raise ValueError(f"ActorTraining: rep {self.rep!r} has {channels} channels per joint but "
                             f"model.channels is {self.model.channels}")


def actor_inputs(batch: dict[str, jax.Array], rep: str) -> tuple[jax.Array, jax.Array, jax.Array]:
    """A pipeline batch -> ACTOR's ``(x [B, T, J + 1, C], actions [B], mask [B, T])``."""
    if "rotations" not in batch:
        raise ValueError("batch: ACTOR trains on joint rotations; this dataset has joint positions only")
    return to_actor_features(batch["rotations"], batch["translation"], rep), batch["actions"], batch["mask"]


def actor_state(training: ActorTraining, key: jax.Array) -> TrainState:
    """Fresh parameters and AdamW state for ``training``."""
    optimizer = optax.adamw(training.learning_rate, weight_decay=training.weight_decay)
    return TrainState.create(apply_fn=None, params=init_actor(key, training.model), tx=optimizer)


def actor_step(training: ActorTraining, skeleton: Skeleton, body: BodyModel | None = None):
    """The training step ``(state, batch, key) -> (state, loss terms)`` (the loop jits it): ACTOR's losses on
    a pipeline batch, dropout from ``key``, one AdamW update."""
    config = training.model

    def step_fn(state, batch, key):
        x, actions, mask = actor_inputs(batch, training.rep)

        def loss_fn(params):
            out = autoencode(params, config, key, x, actions, mask, train=True)
            return actor_loss(out["output"], x, mask, out["mu"], out["logvar"], rep=training.rep,
                              weights=training.losses, skeleton=skeleton, body=body)

        (_, terms), grads = jax.value_and_grad(loss_fn, has_aux=True)(state.params)
        return state.apply_gradients(grads=grads), terms

    return step_fn


def train_actor(data: MotionDataset, training: ActorTraining, key: jax.Array, workdir: str | None = None, *,
                body: BodyModel | None = None, progress: bool = True) -> AnyActorParams:
    """Fit ACTOR on ``data`` (resuming from ``workdir``'s checkpoints when present); returns the parameters."""
    if training.model.num_classes != data.num_classes or training.model.num_joints != data.skeleton.num_joints + 1:
        raise ValueError(f"ActorTraining.model: expects {training.model.num_classes} classes and "
                         f"{training.model.num_joints - 1} joints, {data.name} has {data.num_classes} and "
                         f"{data.skeleton.num_joints}")
    k_init, k_data, k_train = jax.random.split(key, 3)
    spec = BatchSpec(batch_size=training.batch_size, window=training.window, min_length=training.min_length)
    loop = LoopConfig(steps=training.steps, log_every=training.log_every, checkpoint_every=training.checkpoint_every)
    state = train(actor_state(training, k_init), actor_step(training, data.skeleton, body),
                  make_batch_fn(data, k_data, spec), key=k_train, config=loop, workdir=workdir, progress=progress)
    return state.params


def motions_from_features(x: jax.Array, mask: jax.Array, rep: str, skeleton: Skeleton) -> dict[str, jax.Array]:
    """ACTOR's tensor ``x [B, T, J + 1, C]`` -> the library's batch form: ``rotations [B, T, J, 3]``,
    ``translation [B, T, 3]`` (relative to frame 0), ``joints [B, T, J, 3]`` (forward kinematics on
    ``skeleton``'s rest offsets), ``mask [B, T]`` and ``lengths [B]``."""
    rotations, translation = from_actor_features(x, rep)
    joints = forward_kinematics(axis_angle_to_matrix(rotations), translation, skeleton.offsets, skeleton.parents)
    return {"joints": joints, "rotations": rotations, "translation": translation, "mask": mask,
            "lengths": mask.sum(axis=1)}
