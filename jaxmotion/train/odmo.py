"""Training ODMO (:mod:`jaxmotion.models.odmo`) as the authors' ``Trainer`` does (OD ``src/modules/trainer.py``,
``train_odmo.py``, ``dataloader_samplestart_rotate2xz_pairwise.py``).

:class:`ODMOTraining` is the trainer's config: model, loss (:class:`~jaxmotion.losses.odmo.ODMOLossConfig`), Adam
1e-3 with the gradient norm clipped at 1, batches of 512 **pairs** (:class:`~jaxmotion.data.pipeline.PairSpec`:
first windows drawn class-balanced, ODMO's class weights 10/count; the partner of the same class with
probability ½), the teacher-forcing schedule (:class:`TeacherForcing`), a held-out validation split, and
the loop (:class:`~jaxmotion.train.loop.LoopConfig`; deterministic, resumable, data-parallel on a mesh).
:func:`train_odmo` fits it with :func:`~jaxmotion.train.fit.fit` on the clips :func:`validation_split` leaves;
the code bank every sampler reads, and the table rows, are :mod:`jaxmotion.recipes.odmo`'s.

The code's units, and this recipe's:

* **epochs.** An epoch of the code is 2 048 class-balanced draws, 4 steps of 512 pairs; it trains 100 000
  epochs (400 000 steps). The teacher-forcing rate is set per epoch,
  ``max(1 − e · 0.7 / 4000, 0.3)`` (:class:`TeacherForcing` in steps: a staircase of ``steps_per_epoch``).
* **teacher forcing.** At every decoder step of every forward pass, one Bernoulli draw with that rate,
  shared by the batch (the code's ``random.random() < tf_rate`` inside the decoder loop); the two halves
  of a pair draw independently, as the code calls the model twice.
* **BatchNorm.** The two halves of a pair pass through the encoder one after the other in train mode:
  each normalises with its own batch statistics and the running statistics move twice per step, first
  towards the first half's, as in the code.
* **validation split.** ``validation_fraction`` of the training clips (the code's ``p_val``: 10%, 1% on
  UESTC) are held out by a seeded permutation and never trained on. The code still draws contrastive
  partners from them (its pair table covers every clip); here partners come from the training clips only.
* **windows.** Random 60-frame crops (CMU MoCap 100), clips shorter than the window padded with their last
  frame, the root of frame 0 moved to the origin; ``canonical`` (default) also turns the window to face
  +Z at frame 0, as the embedded data's recognisers and ACTOR's windows are (ODMO's HumanAct12 clips come in
  a fixed frame); ``canonical=False``: only moved, the code's normalisation.

Axes: B pairs, T frames, J joints, F = J·3.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Literal

import jax
import jax.numpy as jnp
import numpy as np
import optax

from jaxmotion.config import check_at_least
from jaxmotion.data.motion import MotionDataset
from jaxmotion.data.pipeline import BatchSpec, PairSpec
from jaxmotion.losses.odmo import ODMOLossConfig, pair_loss
from jaxmotion.models.odmo import ODMOConfig, flatten_poses, forward, init_odmo
from jaxmotion.train.fit import fit
from jaxmotion.train.loop import LoopConfig
from jaxmotion.train.state import TrainState


@dataclasses.dataclass(frozen=True)
class TeacherForcing:
    """The probability of teacher forcing at step ``s``: ``max(start − e · (start − end) / decay_epochs, end)``
    with ``e = s // steps_per_epoch`` (the code: 1 → 0.3 over 4 000 epochs of 4 steps)."""

    start: float = 1.0
    end: float = 0.3
    decay_epochs: int = 4000
    steps_per_epoch: int = 4

    def __post_init__(self):
        if not (0.0 <= self.end <= 1.0 and 0.0 <= self.start <= 1.0):
            raise ValueError(f"TeacherForcing: start and end must be probabilities, got {self.start}, {self.end}")
        if self.decay_epochs < 1 or self.steps_per_epoch < 1:
            raise ValueError(f"TeacherForcing: decay_epochs and steps_per_epoch must be >= 1, got "
                             f"{self.decay_epochs}, {self.steps_per_epoch}")

    def rate(self, step: jax.Array) -> jax.Array:
        epoch = (jnp.asarray(step) // self.steps_per_epoch).astype(jnp.float32)
        return jnp.maximum(self.start - epoch * (self.start - self.end) / self.decay_epochs, self.end)


@dataclasses.dataclass(frozen=True)
class ODMOTraining:
    """How ODMO is trained (defaults: the code on HumanAct12)."""

    model: ODMOConfig
    losses: ODMOLossConfig = ODMOLossConfig()
    loop: LoopConfig = LoopConfig(steps=400_000, log_every=200, checkpoint_every=4000)
    learning_rate: float = 1e-3
    clip_norm: float = 1.0
    batch_size: int = 512  # pairs
    teacher_forcing: TeacherForcing = TeacherForcing()
    validation_fraction: float = 0.1  # UESTC 0.01
    partners: Literal["uniform", "balanced"] = "uniform"  # MoCap: "balanced"
    canonical: bool = True

    def __post_init__(self):
        check_at_least(self, 1, "batch_size")
        if not 0.0 <= self.validation_fraction < 1.0:
            raise ValueError(f"ODMOTraining.validation_fraction: expected in [0, 1), got {self.validation_fraction}")
        if not self.learning_rate > 0 or not self.clip_norm > 0:
            raise ValueError(f"ODMOTraining: learning_rate and clip_norm must be > 0, got {self.learning_rate}, "
                             f"{self.clip_norm}")

    @property
    def batch(self) -> PairSpec:
        return PairSpec(BatchSpec(batch_size=self.batch_size, window=self.model.num_frames, sampling="balanced",
                                  canonical=self.canonical), other=self.partners)


def odmo_optimizer(training: ODMOTraining) -> optax.GradientTransformation:
    """Adam with the gradient's global norm clipped first (``clip_grad_norm_`` then ``Adam.step``)."""
    return optax.chain(optax.clip_by_global_norm(training.clip_norm), optax.adam(training.learning_rate))


def odmo_state(training: ODMOTraining, key: jax.Array) -> TrainState:
    """Fresh parameters, the encoder's running statistics as ``buffers`` and the optimiser's state."""
    params, stats = init_odmo(key, training.model)
    return TrainState.create(params, odmo_optimizer(training), stats)


def odmo_step(training: ODMOTraining):
    """The training step ``(state, pair batch, key) -> (state, loss terms)`` (the loop jits it): both halves
    of each pair through the autoencoder in train mode, :func:`~jaxmotion.losses.odmo.pair_loss`, one
    clipped Adam update; also logs the teacher-forcing rate."""
    model, losses, schedule = training.model, training.losses, training.teacher_forcing

    def step_fn(state, batch, key):
        k_tf, k_z = jax.random.split(key)
        rate = schedule.rate(state.step)
        first, second = batch["first"], batch["second"]
        b = first["actions"].shape[0]
        # both halves in one pass (the encoder's BatchNorm still sees them apart, see encode's groups)
        poses = flatten_poses(jnp.concatenate([first["joints"], second["joints"]]))
        actions = jnp.concatenate([first["actions"], second["actions"]])
        draws = jax.random.bernoulli(k_tf, rate, (2, model.num_frames))  # one per decoder step and half
        teacher_mask = jnp.repeat(draws.T, b, axis=1)  # [T, 2B]

        def loss_fn(params):
            out = forward(model, params, state.buffers, poses, actions, key=k_z, train=True,
                          teacher_mask=teacher_mask, groups=2)
            halves = [{k: v[i * b:(i + 1) * b] for k, v in out.items() if k != "buffers"} for i in (0, 1)]
            loss, metrics = pair_loss(*halves, poses[:b], poses[b:], batch["same"], losses)
            return loss, (metrics, out["buffers"])

        (_, (metrics, buffers)), grads = jax.value_and_grad(loss_fn, has_aux=True)(state.params)
        state = state.apply_gradients(grads).replace(buffers=buffers)
        return state, {**metrics, "teacher_forcing": rate}

    return step_fn


def validation_split(data: MotionDataset, key: jax.Array, fraction: float) -> tuple[np.ndarray, np.ndarray]:
    """``(train ids, validation ids)``: the first ``⌊fraction · N⌋`` clips of a permutation drawn with ``key``
    are held out (at least one clip when ``fraction`` > 0), as the code's ``create_weighted_loaders``."""
    order = np.asarray(jax.random.permutation(key, len(data)))
    held = int(np.floor(fraction * len(data)))
    held = max(held, 1) if fraction > 0 else 0
    return np.sort(order[held:]), np.sort(order[:held])


def _check_data(training: ODMOTraining, data: MotionDataset) -> None:
    model = training.model
    if model.num_joints != data.skeleton.num_joints or model.num_classes != data.num_classes:
        raise ValueError(f"ODMOTraining.model: sized for {model.num_joints} joints and {model.num_classes} classes; "
                         f"{data.name} has {data.skeleton.num_joints} joints and {data.num_classes} classes")


def train_odmo(data: MotionDataset, training: ODMOTraining, key: jax.Array, workdir: str | Path | None = None, *,
               progress: bool = True, **loop_options) -> TrainState:
    """Fit ODMO on ``data`` (the clips left after :func:`validation_split`; resuming from ``workdir``'s
    checkpoints when present); returns the final state (``buffers``: the encoder's running statistics).
    ``key``: :func:`~jaxmotion.train.fit.fit`'s (initialisation, data order, per-step keys); ``loop_options`` go
    to the loop (``mesh``, ``init_from``, ``eval_fn``)."""
    _check_data(training, data)
    return fit(data, key, init_state=lambda k: odmo_state(training, k), step_fn=odmo_step(training),
               batch=training.batch, loop=training.loop, workdir=workdir, progress=progress, **loop_options)
