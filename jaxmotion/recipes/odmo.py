"""ODMO's table rows and sizes: :class:`ODMORecipe` (a trainer config, :class:`~jaxmotion.train.odmo.ODMOTraining`,
plus what its row does after training: the code bank of real windows, how it finds modes and how it samples)
and the trainings of the smoke, cpu and paper profiles; :func:`benchmark_variants` are Tables 1-2's ODMO rows."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import NamedTuple

import jax

from jaxmotion.data.datasets import paper_dataset
from jaxmotion.data.motion import MotionDataset
from jaxmotion.losses.odmo import ODMOLossConfig
from jaxmotion.models.odmo import ODMOConfig, ODMOParams, ODMOStats
from jaxmotion.pipelines.artefacts import DataFacts
from jaxmotion.pipelines.odmo import (
    CodeBank,
    CodeBankConfig,
    ModeDiscovery,
    ODMOGenerator,
    Sampling,
    code_bank,
    fit_mixtures,
)
from jaxmotion.train.loop import LoopConfig
from jaxmotion.train.odmo import ODMOTraining, TeacherForcing, train_odmo, validation_split


class ODMOFit(NamedTuple):
    """A trained ODMO before its row's mixtures: parameters, the encoder's running statistics and the code bank of
    its real training windows."""

    params: ODMOParams
    buffers: ODMOStats
    bank: CodeBank


@dataclasses.dataclass(frozen=True)
class ODMORecipe:
    """ODMO as a table row: ``training`` (the trainer), ``bank`` (the real windows encoded after training),
    ``modes`` (how each class's modes are found) and ``sampling`` (``"modes"``: mode-preserving, ODMO's row;
    ``"conventional"``: ODMO_conv). Rows that differ only in ``modes`` or ``sampling`` train once."""

    training: ODMOTraining
    bank: CodeBankConfig = CodeBankConfig()
    modes: ModeDiscovery = ModeDiscovery()
    sampling: Sampling = "modes"

    def __post_init__(self):
        if self.sampling not in ("modes", "conventional"):
            raise ValueError(f"ODMORecipe.sampling: expected 'modes' or 'conventional', got {self.sampling!r}")

    @property
    def fit_key(self) -> tuple[ODMOTraining, CodeBankConfig]:
        """What determines the fit (the mixtures and the sampler do not)."""
        return self.training, self.bank

    def fit(self, data: MotionDataset, key: jax.Array, workdir: str | Path | None = None, **loop_options) -> ODMOFit:
        """Train on ``data`` less its held-out clips, then encode the code bank. ``key`` splits into the held-out
        split, the training and the bank's draws."""
        k_split, k_fit, k_bank = jax.random.split(key, 3)
        train_ids, _ = validation_split(data, k_split, self.training.validation_fraction)
        train_data = data.subset(train_ids)
        state = train_odmo(train_data, self.training, k_fit, workdir, **loop_options)
        bank = code_bank(state.params, state.buffers, self.training.model, train_data, k_bank, bank=self.bank,
                         canonical=self.training.canonical)
        return ODMOFit(state.params, state.buffers, bank)

    def generator(self, trained: ODMOFit, facts: DataFacts) -> ODMOGenerator:
        mixtures = fit_mixtures(trained.bank, self.training.model.num_classes, self.sampling, self.modes)
        return ODMOGenerator(self.training.model, trained.params, trained.buffers, trained.bank, mixtures, facts)


#: The code's per-dataset settings (``param_*.py``): frames, y weight, validation share, partner draw, bank passes.
DATASET_SETTINGS = {
    "HumanAct12": dict(num_frames=60, y_weight=5.0, validation_fraction=0.1, partners="uniform", passes=15),
    "UESTC": dict(num_frames=60, y_weight=5.0, validation_fraction=0.01, partners="uniform", passes=8),
    "MoCap": dict(num_frames=100, y_weight=1.0, validation_fraction=0.1, partners="balanced", passes=5),
}


def dataset_recipe(label: str, num_joints: int, num_classes: int, **model_overrides) -> ODMORecipe:
    """The authors' recipe on the paper dataset ``label`` (``"HumanAct12"``, ``"UESTC"``, ``"MoCap"``): their
    model, loss, optimiser, 512 pairs, 100 000 epochs (400 000 steps), with ``num_joints`` and
    ``num_classes`` of the data (the embedded stand-ins have 24 joints; the real sets 24, 18 and 20)."""
    if label not in DATASET_SETTINGS:
        raise ValueError(f"label: expected one of {sorted(DATASET_SETTINGS)}, got {label!r}")
    settings = DATASET_SETTINGS[label]
    model = ODMOConfig(num_joints=num_joints, num_classes=num_classes, num_frames=settings["num_frames"],
                       **model_overrides)
    training = ODMOTraining(model, losses=ODMOLossConfig(y_weight=settings["y_weight"]),
                            validation_fraction=settings["validation_fraction"], partners=settings["partners"])
    return ODMORecipe(training, bank=CodeBankConfig(passes=settings["passes"]))


#: The cpu profile's ODMO (every ODMO table): LSTMs of 64 units (the paper's 128), 32 pairs a step, 1 200
#: steps; teacher forcing decays over the first 60% of them (the code: over 4 000 of 100 000 epochs).
CPU_STEPS = 1200
CPU_RECIPE = ODMORecipe(ODMOTraining(ODMOConfig(num_joints=24, num_classes=12, trajectory_hidden=64, motion_hidden=64),
                                     loop=LoopConfig(CPU_STEPS, log_every=50, checkpoint_every=300), batch_size=32,
                                     teacher_forcing=TeacherForcing(decay_epochs=int(0.6 * CPU_STEPS / 4))),
                        bank=CodeBankConfig(passes=4))


def odmo_table_recipe(label: str, profile: str, cpu: ODMORecipe = CPU_RECIPE, num_joints: int = 24) -> ODMORecipe:
    """ODMO in a table on the paper dataset ``label`` in ``profile``: paper, :func:`dataset_recipe`; cpu, the
    dataset's settings with ``cpu``'s model widths, loop, batch, schedule and bank; smoke, a tiny model for a
    few steps. The classes are the dataset's; ``num_joints`` the data's (24 on the embedded stand-ins)."""
    classes = paper_dataset(label).num_classes
    paper = dataset_recipe(label, num_joints, classes)
    frames = paper.training.model.num_frames
    if profile == "paper":
        return paper
    if profile == "cpu":
        model = dataclasses.replace(cpu.training.model, num_joints=num_joints, num_classes=classes, num_frames=frames)
        training = dataclasses.replace(paper.training, model=model, loop=cpu.training.loop,
                                       batch_size=cpu.training.batch_size, teacher_forcing=cpu.training.teacher_forcing)
        return dataclasses.replace(paper, training=training, bank=cpu.bank)
    if profile == "smoke":
        model = ODMOConfig(num_joints=num_joints, num_classes=classes, num_frames=frames, encoder_hidden=8,
                           encoder_width=16, trajectory_hidden=8, trajectory_layers=1, motion_hidden=8, motion_layers=1)
        training = dataclasses.replace(paper.training, model=model, loop=LoopConfig(4, log_every=2, checkpoint_every=0),
                                       batch_size=8, teacher_forcing=TeacherForcing(decay_epochs=1))
        return ODMORecipe(training, bank=CodeBankConfig(passes=1, draws=1024), modes=ModeDiscovery(n_init=1))
    raise ValueError(f"profile: expected smoke, cpu or paper, got {profile!r}")


def benchmark_variants(odmo: ODMORecipe) -> dict[str, ODMORecipe]:
    """The ODMO rows of the paper's Tables 1 and 2 from the full recipe: ODMO, ODMO_conv (its sampler only:
    trained once with ODMO), -r_e (no end location into the trajectory generator), -L_es (no contrastive term)."""
    training = odmo.training
    return {
        "ODMO": odmo,
        "ODMO_conv": dataclasses.replace(odmo, sampling="conventional"),
        "-r_e": dataclasses.replace(odmo, training=dataclasses.replace(
            training, model=dataclasses.replace(training.model, use_end=False))),
        "-L_es": dataclasses.replace(odmo, training=dataclasses.replace(
            training, losses=dataclasses.replace(training.losses, contrastive=False))),
    }
