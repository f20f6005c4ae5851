"""Action2Motion's table rows and sizes (a baseline of ACTOR's, ODMO's and ActFormer's tables):
:class:`A2MRecipe` (an :class:`~jaxmotion.train.a2m.A2MTraining` as a row, generating through
:class:`~jaxmotion.pipelines.a2m.A2MGenerator`) and the profiles' trainings."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import jax

from jaxmotion.data.datasets import paper_dataset
from jaxmotion.data.motion import MotionDataset
from jaxmotion.models.a2m import A2MVAEConfig, A2MVAEParams
from jaxmotion.pipelines.a2m import A2MGenerator
from jaxmotion.pipelines.artefacts import DataFacts
from jaxmotion.train.a2m import A2MTraining, train_a2m
from jaxmotion.train.loop import LoopConfig


@dataclasses.dataclass(frozen=True)
class A2MRecipe:
    """Action2Motion as a table row."""

    training: A2MTraining

    def fit(self, data: MotionDataset, key: jax.Array, workdir: str | Path | None = None, **loop_options
            ) -> A2MVAEParams:
        return train_a2m(data, self.training, key, workdir, **loop_options)

    def generator(self, params: A2MVAEParams, facts: DataFacts) -> A2MGenerator:
        return A2MGenerator(self.training.model, params, facts, self.training.window)


def a2m_table_training(label: str, profile: str) -> A2MTraining:
    """Action2Motion as a table row on the embedded stand-in of the paper dataset ``label`` (24 joints; ACTOR's
    Table 3, ODMO's Table 1) in ``profile``: the released xyz configuration (paper), the same sizes for 900
    iterations at batch 64 (cpu), a tiny model (smoke)."""
    classes = paper_dataset(label).num_classes
    window = 100 if label == "MoCap" else 60
    if profile == "smoke":
        model = A2MVAEConfig(pose_dim=72, num_classes=classes, kl_weight=1e-4, hidden=8, latent=4, decoder_layers=1,
                             time_counter=False)
        return A2MTraining(model, LoopConfig(2, log_every=2, checkpoint_every=0), batch_size=8, window=window)
    model = A2MVAEConfig(pose_dim=72, num_classes=classes, kl_weight=1e-4, time_counter=False)
    if profile == "cpu":
        return A2MTraining(model, LoopConfig(900, log_every=100, checkpoint_every=300), batch_size=64, window=window)
    if profile == "paper":
        return A2MTraining(model, LoopConfig(50_000, log_every=100, checkpoint_every=5000), window=window)
    raise ValueError(f"profile: expected smoke, cpu or paper, got {profile!r}")
