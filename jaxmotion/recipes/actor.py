"""ACTOR's table rows and sizes: :class:`ActorRecipe` (an :class:`~jaxmotion.train.actor.ActorTraining` as a row:
trained by :func:`~jaxmotion.train.actor.train_actor`, generating through
:class:`~jaxmotion.pipelines.actor.ActorGenerator`) and the trainings of the smoke, cpu and paper profiles."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import jax

from jaxmotion.data.datasets import paper_dataset
from jaxmotion.data.motion import MotionDataset
from jaxmotion.evaluation.tables import TableDataset
from jaxmotion.losses.actor import ActorLossWeights
from jaxmotion.models.actor import ActorConfig, AnyActorParams
from jaxmotion.pipelines.actor import ActorGenerator
from jaxmotion.pipelines.artefacts import DataFacts
from jaxmotion.train.actor import ActorTraining, train_actor
from jaxmotion.train.loop import LoopConfig


@dataclasses.dataclass(frozen=True)
class ActorRecipe:
    """ACTOR as a table row."""

    training: ActorTraining

    def fit(self, data: MotionDataset, key: jax.Array, workdir: str | Path | None = None, **loop_options
            ) -> AnyActorParams:
        return train_actor(data, self.training, key, workdir, **loop_options)

    def generator(self, params: AnyActorParams, facts: DataFacts) -> ActorGenerator:
        return ActorGenerator(self.training.model, params, facts, self.training.window)


@dataclasses.dataclass(frozen=True)
class ActorTable:
    """One dataset of an ACTOR table whose rows are variants of one training (Tables 1 and 2): where it is scored
    and the training every row changes."""

    table: TableDataset
    training: ActorTraining


UESTC_EPOCH = paper_dataset("UESTC").clips // 20  # steps per epoch at batch 20
#: The paper's epochs of its main runs per dataset (ACTOR's README; its ablations' shorter runs are not attributed).
PAPER_EPOCHS = {"NTU-13": 2000, "UESTC": 1000, "HumanAct12": 5000}


def smoke_training(num_classes: int, steps: int = 2, checkpoint_every: int = 0) -> ActorTraining:
    """A 1-layer ACTOR without dropout for the smoke profiles (dropout's random bits triple a step's compile
    time on CPU; unit tests cover dropout), L_P only, batch 8."""
    model = ActorConfig(num_classes=num_classes, width=16, ff=32, layers=1, heads=2, dropout=0.0)
    return ActorTraining(model, LoopConfig(steps, log_every=2, checkpoint_every=checkpoint_every), batch_size=8)


def uestc_training(profile: str) -> ActorTraining:
    """The headline UESTC run in ``profile``. cpu: sized for a CPU, where learning speed is what limits quality
    (the paper trains 530 000 steps): d 128, 2 + 2 layers, FF 256, no dropout, AdamW 1e-3, 14 000 steps. Tuning
    here (generation accuracy, 600 windows): 1e-3 beat 5e-4 and 2e-3; 3e-3 collapsed the posterior; λ_KL 3e-6
    reconstructed better but generated worse than 1e-5; a cosine decay learned slower. L_J stands in for L_V,
    which needs an SMPL model. paper: the paper's model, 1 000 epochs at batch 20."""
    classes = paper_dataset("UESTC").num_classes
    if profile == "smoke":
        return smoke_training(classes, steps=4, checkpoint_every=2)
    if profile == "cpu":
        model = ActorConfig(num_classes=classes, width=128, ff=256, layers=2, heads=4, dropout=0.0)
        return ActorTraining(model, LoopConfig(14_000, log_every=100, checkpoint_every=1000),
                             losses=ActorLossWeights(joints=1.0), learning_rate=1e-3)
    if profile == "paper":
        return ActorTraining(ActorConfig(num_classes=classes),
                             LoopConfig(PAPER_EPOCHS["UESTC"] * UESTC_EPOCH, log_every=100, checkpoint_every=10_000))
    raise ValueError(f"profile: expected smoke, cpu or paper, got {profile!r}")


#: ACTOR's cpu recipe where it is a baseline (ACTOR's Table 3, ODMO's Tables 1 and 3): d 64, 2 layers, FF 256,
#: L_P + L_J, a larger learning rate for the short budget (the paper: 390 000 / 300 000 steps at 1e-4).
CPU_BASELINE = ActorTraining(ActorConfig(num_classes=1, width=64, ff=256, layers=2, heads=4),
                             LoopConfig(3000, log_every=100, checkpoint_every=1000), losses=ActorLossWeights(joints=1.0),
                             learning_rate=3e-4)


def table_training(label: str, profile: str, cpu: ActorTraining = CPU_BASELINE) -> ActorTraining:
    """ACTOR on the paper dataset ``label`` (``"NTU-13"``, ``"UESTC"``, ``"HumanAct12"``, ``"MoCap"``) in a
    table: smoke :func:`smoke_training`; cpu the experiment's ``cpu`` training; paper the paper's model,
    batch 20 and epochs with L_P + L_J (L_J stands in for L_V, which needs an SMPL model). The number of
    classes is the dataset's in every profile. MoCap (ODMO's Table 2, where ACTOR is a baseline ODMO's
    authors trained): 100-frame windows, and HumanAct12's 5 000 epochs (ODMO does not say how long)."""
    dataset = paper_dataset(label)
    if dataset.clips is None:
        raise ValueError(f"label: ACTOR's tables use NTU-13, UESTC, HumanAct12 or MoCap, got {label!r}")
    classes = dataset.num_classes
    window = 100 if label == "MoCap" else 60
    if profile == "smoke":
        return dataclasses.replace(smoke_training(classes), window=window)
    if profile == "cpu":
        return dataclasses.replace(cpu, model=dataclasses.replace(cpu.model, num_classes=classes), window=window)
    if profile == "paper":
        steps = PAPER_EPOCHS.get(label, PAPER_EPOCHS["HumanAct12"]) * (dataset.clips // 20)
        return ActorTraining(ActorConfig(num_classes=classes), LoopConfig(steps, log_every=100, checkpoint_every=10_000),
                             losses=ActorLossWeights(joints=1.0), window=window)
    raise ValueError(f"profile: expected smoke, cpu or paper, got {profile!r}")
