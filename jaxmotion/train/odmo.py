"""Training ODMO (:mod:`jaxmotion.models.odmo`) as the authors' ``Trainer`` does (OD ``src/modules/trainer.py``,
``train_odmo.py``, ``dataloader_samplestart_rotate2xz_pairwise.py``).

:class:`ODMOTraining` is the recipe: model, loss (:class:`~jaxmotion.losses.odmo.ODMOLossConfig`), Adam
1e-3 with the gradient norm clipped at 1, batches of 512 **pairs** (:class:`~jaxmotion.data.pipeline.PairSpec`:
first windows drawn class-balanced, ODMO's class weights 10/count; the partner of the same class with
probability ½), the teacher-forcing schedule (:class:`TeacherForcing`), a held-out validation split, and
the loop (:class:`~jaxmotion.train.loop.LoopConfig`; deterministic, resumable, data-parallel on a mesh).
:func:`train_odmo` fits it with :func:`~jaxmotion.train.fit.fit` and returns an :class:`ODMOFit`: the
parameters, the encoder's running statistics and the **code bank** (codes of real training windows,
:func:`jaxmotion.pipelines.odmo.code_bank`) every sampler and customisation reads.

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
from typing import Any, Literal, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np
import optax
from flax.training.train_state import TrainState

from jaxmotion.data.datasets import PAPER_SIZES
from jaxmotion.data.motion import MotionDataset
from jaxmotion.data.pipeline import BatchSpec, PairSpec
from jaxmotion.geometry.skeletons import Skeleton
from jaxmotion.losses.odmo import ODMOLossConfig, pair_loss
from jaxmotion.models.odmo import ODMOConfig, ODMOParams, ODMOStats, flatten_poses, forward, init_odmo
from jaxmotion.train.fit import fit
from jaxmotion.train.loop import LoopConfig


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
class CodeBankConfig:
    """How many real windows the samplers' code bank encodes: ``passes`` × ``draws`` class-balanced draws
    (the code: passes over its training loader of 2 048 draws; MoCap 5, HumanAct12 15, UESTC 8), exact
    duplicates dropped (a clip no longer than the window always gives the same window)."""

    passes: int = 15
    draws: int = 2048

    def __post_init__(self):
        if self.passes < 1 or self.draws < 1:
            raise ValueError(f"CodeBankConfig: passes and draws must be >= 1, got {self.passes}, {self.draws}")


@dataclasses.dataclass(frozen=True)
class ModeDiscovery:
    """How the samplers find each class's modes (:func:`jaxmotion.mixtures.discover_modes_batched`): the
    silhouette ``rule`` (``"code"``: k 3..9, the authors' code; ``"paper"``: k 3..11) and the GMM restarts."""

    rule: Literal["code", "paper"] = "code"
    n_init: int = 5

    def __post_init__(self):
        if self.rule not in ("code", "paper"):
            raise ValueError(f"ModeDiscovery.rule: expected 'code' or 'paper', got {self.rule!r}")
        if self.n_init < 1:
            raise ValueError(f"ModeDiscovery.n_init: expected >= 1, got {self.n_init}")


class ODMOState(TrainState):
    batch_stats: Any = None  # ODMOStats


class ODMOFit(NamedTuple):
    """A trained ODMO: parameters, the encoder's running statistics, and the code bank of its real
    training windows (:class:`jaxmotion.pipelines.odmo.CodeBank`)."""

    params: ODMOParams
    stats: ODMOStats
    bank: Any


@dataclasses.dataclass(frozen=True)
class ODMOTraining:
    """How ODMO is trained (defaults: the code on HumanAct12) and which sampler its table row uses (``sampling``: ``"modes"``,
    mode-preserving, ODMO's row; ``"conventional"``, ODMO_conv)."""

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
    bank: CodeBankConfig = CodeBankConfig()
    modes: ModeDiscovery = ModeDiscovery()
    sampling: Literal["modes", "conventional"] = "modes"

    def __post_init__(self):
        if self.batch_size < 1:
            raise ValueError(f"ODMOTraining.batch_size: expected >= 1, got {self.batch_size}")
        if not 0.0 <= self.validation_fraction < 1.0:
            raise ValueError(f"ODMOTraining.validation_fraction: expected in [0, 1), got {self.validation_fraction}")
        if self.sampling not in ("modes", "conventional"):
            raise ValueError(f"ODMOTraining.sampling: expected 'modes' or 'conventional', got {self.sampling!r}")
        if not self.learning_rate > 0 or not self.clip_norm > 0:
            raise ValueError(f"ODMOTraining: learning_rate and clip_norm must be > 0, got {self.learning_rate}, "
                             f"{self.clip_norm}")

    @property
    def batch(self) -> PairSpec:
        return PairSpec(BatchSpec(batch_size=self.batch_size, window=self.model.num_frames, sampling="balanced",
                                  canonical=self.canonical), other=self.partners)

    @property
    def training(self) -> ODMOTraining:
        """What determines the fit (the sampler does not): rows differing only in how they sample train once."""
        return dataclasses.replace(self, sampling="modes", modes=ModeDiscovery())

    # as a table row (jaxmotion.evaluation.tables.Recipe)
    def fit(self, data: MotionDataset, key: jax.Array, workdir: str | Path | None = None, **loop_options) -> ODMOFit:
        return train_odmo(data, self, key, workdir, **loop_options)

    def sampler(self, trained: ODMOFit, skeleton: Skeleton):
        from jaxmotion.pipelines.odmo import odmo_sampler  # pipelines build on this module

        return odmo_sampler(trained, self, skeleton)


def odmo_optimizer(training: ODMOTraining) -> optax.GradientTransformation:
    """Adam with the gradient's global norm clipped first (``clip_grad_norm_`` then ``Adam.step``)."""
    return optax.chain(optax.clip_by_global_norm(training.clip_norm), optax.adam(training.learning_rate))


def odmo_state(training: ODMOTraining, key: jax.Array) -> ODMOState:
    params, stats = init_odmo(key, training.model)
    return ODMOState.create(apply_fn=None, params=params, tx=odmo_optimizer(training), batch_stats=stats)


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
            out = forward(params, state.batch_stats, k_z, poses, actions, model, train=True,
                          teacher_mask=teacher_mask, groups=2)
            halves = [{k: v[i * b:(i + 1) * b] for k, v in out.items() if k != "stats"} for i in (0, 1)]
            loss, metrics = pair_loss(*halves, poses[:b], poses[b:], batch["same"], losses)
            return loss, (metrics, out["stats"])

        (_, (metrics, stats)), grads = jax.value_and_grad(loss_fn, has_aux=True)(state.params)
        state = state.apply_gradients(grads=grads).replace(batch_stats=stats)
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
               progress: bool = True, **loop_options) -> ODMOFit:
    """Fit ODMO on ``data`` (resuming from ``workdir``'s checkpoints when present) and encode its code bank.

    ``key`` splits into the validation split, the fit (:func:`~jaxmotion.train.fit.fit`: initialisation,
    data order, per-step keys) and the code bank's draws. ``loop_options`` go to the loop (``mesh``,
    ``init_from``, ``eval_fn``)."""
    from jaxmotion.pipelines.odmo import code_bank  # pipelines build on this module

    _check_data(training, data)
    k_split, k_fit, k_bank = jax.random.split(key, 3)
    train_ids, _ = validation_split(data, k_split, training.validation_fraction)
    train_data = data.subset(train_ids)
    state = fit(train_data, k_fit, init_state=lambda k: odmo_state(training, k), step_fn=odmo_step(training),
                batch=training.batch, loop=training.loop, workdir=workdir, progress=progress, **loop_options)
    bank = code_bank(state.params, state.batch_stats, training, train_data, k_bank)
    return ODMOFit(state.params, state.batch_stats, bank)


#: The code's per-dataset settings (``param_*.py``): frames, y weight, validation share, partner draw, bank passes.
DATASET_SETTINGS = {
    "HumanAct12": dict(num_frames=60, y_weight=5.0, validation_fraction=0.1, partners="uniform", passes=15),
    "UESTC": dict(num_frames=60, y_weight=5.0, validation_fraction=0.01, partners="uniform", passes=8),
    "MoCap": dict(num_frames=100, y_weight=1.0, validation_fraction=0.1, partners="balanced", passes=5),
}


def dataset_training(label: str, num_joints: int, num_classes: int, **model_overrides) -> ODMOTraining:
    """The authors' recipe on the paper dataset ``label`` (``"HumanAct12"``, ``"UESTC"``, ``"MoCap"``): their
    model, loss, optimiser, 512 pairs, 100 000 epochs (400 000 steps), with ``num_joints`` and
    ``num_classes`` of the data (the embedded stand-ins have 24 joints; the real sets 24, 18 and 20)."""
    if label not in DATASET_SETTINGS:
        raise ValueError(f"label: expected one of {sorted(DATASET_SETTINGS)}, got {label!r}")
    settings = DATASET_SETTINGS[label]
    model = ODMOConfig(num_joints=num_joints, num_classes=num_classes, num_frames=settings["num_frames"],
                       **model_overrides)
    return ODMOTraining(model, losses=ODMOLossConfig(y_weight=settings["y_weight"]),
                        validation_fraction=settings["validation_fraction"], partners=settings["partners"],
                        bank=CodeBankConfig(passes=settings["passes"]))


#: The cpu profile's ODMO (every ODMO table): LSTMs of 64 units (the paper's 128), 32 pairs a step, 1 200
#: steps; teacher forcing decays over the first 60% of them (the code: over 4 000 of 100 000 epochs).
CPU_STEPS = 1200
CPU_TRAINING = ODMOTraining(ODMOConfig(num_joints=24, num_classes=12, trajectory_hidden=64, motion_hidden=64),
                            loop=LoopConfig(CPU_STEPS, log_every=50, checkpoint_every=300), batch_size=32,
                            teacher_forcing=TeacherForcing(decay_epochs=int(0.6 * CPU_STEPS / 4)),
                            bank=CodeBankConfig(passes=4))


def odmo_table_training(label: str, profile: str, cpu: ODMOTraining = CPU_TRAINING, num_joints: int = 24
                        ) -> ODMOTraining:
    """ODMO in a table on the paper dataset ``label`` in ``profile``: paper, :func:`dataset_training`; cpu, the
    dataset's settings with ``cpu``'s model widths, loop, batch, schedule and bank; smoke, a tiny model for a
    few steps. The classes are the dataset's; ``num_joints`` the data's (24 on the embedded stand-ins)."""
    classes = PAPER_SIZES[label][0]
    paper = dataset_training(label, num_joints, classes)
    if profile == "paper":
        return paper
    if profile == "cpu":
        model = dataclasses.replace(cpu.model, num_joints=num_joints, num_classes=classes,
                                    num_frames=paper.model.num_frames)
        return dataclasses.replace(paper, model=model, loop=cpu.loop, batch_size=cpu.batch_size,
                                   teacher_forcing=cpu.teacher_forcing, bank=cpu.bank)
    if profile == "smoke":
        model = ODMOConfig(num_joints=num_joints, num_classes=classes, num_frames=paper.model.num_frames,
                           encoder_hidden=8, encoder_width=16, trajectory_hidden=8, trajectory_layers=1,
                           motion_hidden=8, motion_layers=1)
        return dataclasses.replace(paper, model=model, loop=LoopConfig(4, log_every=2, checkpoint_every=0),
                                   batch_size=8, teacher_forcing=TeacherForcing(decay_epochs=1),
                                   bank=CodeBankConfig(passes=1, draws=1024), modes=ModeDiscovery(n_init=1))
    raise ValueError(f"profile: expected smoke, cpu or paper, got {profile!r}")


def benchmark_variants(odmo: ODMOTraining) -> dict[str, ODMOTraining]:
    """The ODMO rows of the paper's Tables 1 and 2 from the full recipe: ODMO, ODMO_conv (its sampler only:
    trained once with ODMO), -r_e (no end location into the trajectory generator), -L_es (no contrastive term)."""
    return {
        "ODMO": odmo,
        "ODMO_conv": dataclasses.replace(odmo, sampling="conventional"),
        "-r_e": dataclasses.replace(odmo, model=dataclasses.replace(odmo.model, use_end=False)),
        "-L_es": dataclasses.replace(odmo, losses=dataclasses.replace(odmo.losses, contrastive=False)),
    }
