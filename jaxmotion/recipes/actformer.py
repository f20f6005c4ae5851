"""ActFormer's table rows and sizes: :class:`ActFormerRecipe` (an :class:`~jaxmotion.train.actformer.ActFormerTraining`
as a row, generating through :class:`~jaxmotion.pipelines.actformer.ActFormerGenerator`), ActFormer's data per
embedded stand-in and the trainings of the smoke, cpu and paper profiles (ActFormer's and the CSGN baseline's)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import jax

from jaxmotion.data import synthetic
from jaxmotion.data.datasets import paper_dataset
from jaxmotion.data.motion import MotionDataset
from jaxmotion.geometry.skeletons import SMPL24
from jaxmotion.models.actformer import GeneratorConfig
from jaxmotion.models.csgn import CSGNConfig
from jaxmotion.pipelines.actformer import ActFormerGenerator
from jaxmotion.recipes.a2m import a2m_table_training
from jaxmotion.recipes.actor import table_training
from jaxmotion.train.a2m import A2MTraining
from jaxmotion.train.actor import ActorTraining
from jaxmotion.pipelines.artefacts import DataFacts
from jaxmotion.train.actformer import ActFormerTraining, train_actformer
from jaxmotion.train.loop import LoopConfig
from jaxmotion.train.state import MultiState


@dataclasses.dataclass(frozen=True)
class ActFormerRecipe:
    """ActFormer (or CSGN, trained by ActFormer's recipe) as a table row. ``fit`` returns the trained generator
    (its weights with the training data's bone lengths and root height); the critic stays in the checkpoints."""

    training: ActFormerTraining

    def fit(self, data: MotionDataset, key: jax.Array, workdir: str | Path | None = None, **loop_options
            ) -> ActFormerGenerator:
        state: MultiState = train_actformer(data, self.training, key, workdir, **loop_options)
        return ActFormerGenerator.trained_on(self.training.model, state.params["generator"],
                                             state.buffers["generator"], data)

    def generator(self, trained: ActFormerGenerator, facts: DataFacts) -> ActFormerGenerator:
        return trained


#: ActFormer's data per embedded stand-in: (generator joints, output, class sampling); persons and classes
#: come from the data. NTU-13's stand-in holds SMPL-24 joints, trained as limbs like NTU's skeletons; the SMPL
#: sets add the translation as a 25th node; BABEL resamples classes by the square root of their counts; GTA
#: Combat's 22 joints are limbs too (width 8 · 22 = 176, as the authors' GTA configs).
ACTFORMER_DATA = {"synth-ntu13": (24, "skeleton", "epoch"), "synth-ntu1p": (25, "skeleton", "epoch"),
                  "synth-ntu1p-smpl": (25, "smpl", "epoch"), "synth-babel120": (25, "smpl", "sqrt"),
                  "synth-ntu2p": (25, "skeleton", "epoch"),
                  **{f"synth-combat-{p}p": (22, "skeleton", "epoch") for p in range(2, 6)}}
#: The code's length: 500 epochs of the train split, an epoch being one pass of 64-clip batches through the
#: critic (4 per generator step).
PAPER_EPOCHS = 500


def actformer_table_training(dataset: str, profile: str) -> ActFormerTraining:
    """ActFormer as a table row on the embedded ``dataset`` (a key of :data:`ACTFORMER_DATA`) in ``profile``.

    paper: the authors' configs (``config/generator/*``: width 8 per joint, depth 2, 8 heads, critic base 32,
    batch 64, :data:`PAPER_EPOCHS` epochs of the stand-in's train split; for real data set ``loop.steps`` to
    500 epochs of it). cpu: the same generator, a critic of base 8 and batches of 16, 2 000 generator steps (at
    the paper's critic and batch a step takes about 3 s on 2 cores, 1.7 h for 2 000; ``benchmarks/RESULTS.md``).
    smoke: a few steps of a tiny model."""
    if dataset not in ACTFORMER_DATA:
        raise ValueError(f"dataset: expected one of {sorted(ACTFORMER_DATA)}, got {dataset!r}")
    variant = synthetic.VARIANTS[dataset]
    joints, output, sampling = ACTFORMER_DATA[dataset]
    generator = GeneratorConfig(num_classes=len(variant.classes), joints=joints, channels=6 if output == "smpl" else 3,
                                persons=variant.persons, output=output)
    common = dict(generator=generator, sampling=sampling)
    if profile == "smoke":
        tiny = dataclasses.replace(generator, width_per_joint=4, depth=1, heads=4)
        return ActFormerTraining(**{**common, "generator": tiny}, loop=LoopConfig(2, log_every=1, checkpoint_every=2),
                                 critic_base_channels=8, batch_size=4)
    if profile == "cpu":
        return ActFormerTraining(**common, loop=LoopConfig(2000, log_every=100, checkpoint_every=500),
                                 critic_base_channels=8, batch_size=16)
    if profile == "paper":
        clips = variant.splits["train"].num_sequences
        steps = PAPER_EPOCHS * clips // (4 * 64)
        return ActFormerTraining(**common, loop=LoopConfig(steps, log_every=100, checkpoint_every=1000))
    raise ValueError(f"profile: expected smoke, cpu or paper, got {profile!r}")



def csgn_table_training(dataset: str, profile: str, temporal: str = "conv") -> ActFormerTraining:
    """The graph-convolution generator (:class:`~jaxmotion.models.csgn.CSGNConfig`) in ActFormer's recipe on
    ``dataset`` in ``profile`` (:func:`actformer_table_training`'s critic, batch, steps and GP prior):
    ``temporal="conv"`` is the CSGN baseline of Tables 1-2 (conditional BatchNorm in the generator, the
    projection critic), ``"transformer"`` Table 3's row (2), graph convolutions with T-Formers over time."""
    training = actformer_table_training(dataset, profile)
    g = training.generator
    variant = synthetic.VARIANTS[dataset]
    skeleton = SMPL24 if variant.markers is None else variant.markers.skeleton
    parents = skeleton.parents + ((0,) if g.output == "smpl" else ())  # SMPL-25: the translation node
    generator = CSGNConfig(num_classes=g.num_classes, joints=g.joints, channels=g.channels, persons=g.persons,
                           frames=g.frames, output=g.output, parents=parents, temporal=temporal)
    if profile == "smoke":
        generator = dataclasses.replace(generator, widths=(8, 8, 8, 8), heads=2)
    return dataclasses.replace(training, generator=generator)


# --- the baselines of ActFormer's tables, on ActFormer's data in the dataset's frame ------------------


def actor_baseline(label: str, profile: str) -> ActorTraining:
    """ACTOR on ``label``'s rotations in the dataset's frame (the table recipe of its class count)."""
    base = table_training("NTU-13", profile)
    classes = paper_dataset(label).num_classes
    return dataclasses.replace(base, model=dataclasses.replace(base.model, num_classes=classes), canonical=False)


def a2m_baseline(label: str, profile: str, joints: int, persons: int = 1) -> A2MTraining:
    """Action2Motion on ``label``'s ``joints`` positions in the dataset's frame (several persons: all their
    joints side by side in each frame, as the paper scales the baselines to NTU-2P)."""
    base = a2m_table_training("NTU-13", profile)
    model = dataclasses.replace(base.model, pose_dim=3 * joints * persons, num_classes=paper_dataset(label).num_classes)
    return dataclasses.replace(base, model=model, canonical=False)
