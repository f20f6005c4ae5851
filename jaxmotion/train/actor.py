"""Training ACTOR: what every ACTOR experiment shares.

:class:`ActorTraining` holds the data window, the optimiser (AdamW, fixed learning rate, batch 20 in the
paper), the loss weights and the loop (length of training, logging, checkpoints); :func:`train_actor`
fits the model on a dataset with :func:`~jaxmotion.train.fit.fit` (jitted step, ``fold_in(key, step)``
randomness, orbax checkpoints, resume); :func:`motions_from_features` turns the model's tensor into the library's motions (generation, denoising
and the protocol's sampler are in :mod:`jaxmotion.pipelines.actor`).

Axes: B batch, T frames, J joints, C channels.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import jax
import optax
from flax.training.train_state import TrainState

from jaxmotion.data.datasets import PAPER_SIZES
from jaxmotion.data.motion import MotionDataset
from jaxmotion.data.pipeline import BatchSpec
from jaxmotion.geometry.body import BodyModel
from jaxmotion.geometry.skeletons import Skeleton
from jaxmotion.losses.actor import ActorLossWeights, actor_loss
from jaxmotion.models.actor import ActorConfig, AnyActorParams, autoencode, init_actor, to_features
from jaxmotion.pipelines.actor import actor_sampler
from jaxmotion.train.fit import fit
from jaxmotion.train.loop import LoopConfig


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

    @property
    def batch(self) -> BatchSpec:
        return BatchSpec(batch_size=self.batch_size, window=self.window, min_length=self.min_length,
                         canonical=self.canonical)

    # as a table row (jaxmotion.evaluation.tables.Recipe)
    def fit(self, data: MotionDataset, key: jax.Array, workdir: str | Path | None = None, **loop_options):
        return train_actor(data, self, key, workdir, **loop_options)

    def sampler(self, params: AnyActorParams, skeleton: Skeleton):
        return actor_sampler(params, self.model, skeleton)


def actor_inputs(batch: dict[str, jax.Array], rep: str) -> tuple[jax.Array, jax.Array, jax.Array]:
    """A pipeline batch -> ACTOR's ``(x [B, T, J + 1, C], actions [B], mask [B, T])``."""
    if "rotations" not in batch:
        raise ValueError("batch: ACTOR trains on joint rotations; this dataset has joint positions only")
    return to_features(batch["rotations"], batch["translation"], rep), batch["actions"], batch["mask"]


def actor_state(training: ActorTraining, key: jax.Array) -> TrainState:
    """Fresh parameters and AdamW state for ``training``."""
    optimizer = optax.adamw(training.learning_rate, weight_decay=training.weight_decay)
    return TrainState.create(apply_fn=None, params=init_actor(key, training.model), tx=optimizer)


def actor_step(training: ActorTraining, skeleton: Skeleton, body: BodyModel | None = None):
    """The training step ``(state, batch, key) -> (state, loss terms)`` (the loop jits it): ACTOR's losses on
    a pipeline batch, dropout from ``key``, one AdamW update."""
    config = training.model

    def step_fn(state, batch, key):
        x, actions, mask = actor_inputs(batch, config.rep)

        def loss_fn(params):
            out = autoencode(params, config, key, x, actions, mask, train=True)
            return actor_loss(out["output"], x, mask, out["mu"], out["logvar"], rep=config.rep,
                              weights=training.losses, skeleton=skeleton, body=body)

        (_, terms), grads = jax.value_and_grad(loss_fn, has_aux=True)(state.params)
        return state.apply_gradients(grads=grads), terms

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


# --- the profiles' trainings -----------------------------------------------------------------------

UESTC_CLASSES, _UESTC_CLIPS = PAPER_SIZES["UESTC"]
UESTC_EPOCH = _UESTC_CLIPS // 20  # steps per epoch at batch 20
#: The paper's epochs of its main runs per dataset (ACTOR's README; its ablations' shorter runs are not attributed)
PAPER_EPOCHS = {"NTU-13": 2000, "UESTC": 1000, "HumanAct12": 5000}


def smoke_training(num_classes: int, steps: int = 2, checkpoint_every: int = 0) -> ActorTraining:
    """A 1-layer ACTOR without dropout for the smoke profiles (dropout's random bits triple a step's compile
    time on CPU; unit tests cover dropout), L_P only, batch 8."""
    model = ActorConfig(num_classes=num_classes, width=16, ff=32, layers=1, heads=2, dropout=0.0)
    return ActorTraining(model, LoopConfig(steps, log_every=2, checkpoint_every=checkpoint_every), batch_size=8)


def uestc_training(profile: str) -> ActorTraining:
    """The headline UESTC run in ``profile``. cpu: sized for ~20 minutes on 2 CPU cores, where learning speed
    is what limits quality (the paper trains 530 000 steps): d 128, 2 + 2 layers, FF 256, no dropout
    (~70 ms a step), AdamW 1e-3, 14 000 steps. Tuning here (generation accuracy, 600 windows): 1e-3 beat
    5e-4 and 2e-3; 3e-3 collapsed the posterior; λ_KL 3e-6 reconstructed better but generated worse than
    1e-5; a cosine decay learned slower. L_J stands in for L_V, which needs an SMPL model. paper: the paper's
    model, 1 000 epochs at batch 20."""
    if profile == "smoke":
        return smoke_training(UESTC_CLASSES, steps=4, checkpoint_every=2)
    if profile == "cpu":
        model = ActorConfig(num_classes=UESTC_CLASSES, width=128, ff=256, layers=2, heads=4, dropout=0.0)
        return ActorTraining(model, LoopConfig(14_000, log_every=100, checkpoint_every=1000),
                             losses=ActorLossWeights(joints=1.0), learning_rate=1e-3)
    if profile == "paper":
        return ActorTraining(ActorConfig(num_classes=UESTC_CLASSES),
                             LoopConfig(PAPER_EPOCHS["UESTC"] * UESTC_EPOCH, log_every=100, checkpoint_every=10_000))
    raise ValueError(f"profile: expected smoke, cpu or paper, got {profile!r}")


#: ACTOR's cpu recipe where it is a baseline (ACTOR's Table 3, ODMO's Tables 1 and 3): d 64, 2 layers, FF 256,
#: L_P + L_J, a larger learning rate for the short budget (the paper: 390 000 / 300 000 steps at 1e-4). Measured
#: on the 2-core CPU: 0.1 s per step.
CPU_BASELINE = ActorTraining(ActorConfig(num_classes=1, width=64, ff=256, layers=2, heads=4),
                             LoopConfig(3000, log_every=100, checkpoint_every=1000), losses=ActorLossWeights(joints=1.0),
                             learning_rate=3e-4)


def table_training(label: str, profile: str, cpu: ActorTraining = CPU_BASELINE) -> ActorTraining:
    """ACTOR on the paper dataset ``label`` (``"NTU-13"``, ``"UESTC"``, ``"HumanAct12"``, ``"MoCap"``) in a
    table: smoke :func:`smoke_training`; cpu the experiment's ``cpu`` training; paper the paper's model,
    batch 20 and epochs with L_P + L_J (L_J stands in for L_V, which needs an SMPL model). The number of
    classes is the dataset's in every profile. MoCap (ODMO's Table 2, where ACTOR is a baseline ODMO's
    authors trained): 100-frame windows, and HumanAct12's 5 000 epochs (ODMO does not say how long)."""
    if label not in PAPER_SIZES:
        raise ValueError(f"label: expected one of {sorted(PAPER_SIZES)}, got {label!r}")
    classes, clips = PAPER_SIZES[label]
    window = 100 if label == "MoCap" else 60
    if profile == "smoke":
        return dataclasses.replace(smoke_training(classes), window=window)
    if profile == "cpu":
        return dataclasses.replace(cpu, model=dataclasses.replace(cpu.model, num_classes=classes), window=window)
    if profile == "paper":
        steps = PAPER_EPOCHS.get(label, PAPER_EPOCHS["HumanAct12"]) * (clips // 20)
        return ActorTraining(ActorConfig(num_classes=classes), LoopConfig(steps, log_every=100, checkpoint_every=10_000),
                             losses=ActorLossWeights(joints=1.0), window=window)
    raise ValueError(f"profile: expected smoke, cpu or paper, got {profile!r}")
