"""ActFormer Table 2: multi-person generation, NTU-2P (and GTA Combat 2-5P).

Paper: Xu et al., ICCV 2023, §4.2 and Table 2. ActFormer's multi-person model (I-Formers over the persons,
T-Formers over time, one GP sequence shared by all) trained on synth-ntu2p's train split and scored under
ActFormer's protocol: the two-person ST-GCN (the pair stacked on channels, trained with the persons permuted)
for Acc, FID_m and FID_w, and the one-person NTU-25 ST-GCN max-pooled over the persons for FIDa_m and FIDa_w
(:func:`~jaxmotion.evaluation.tables.actformer_table`). GTA Combat (synth-combat-2p .. -5p, one class, the
whole set as the authors train on it): a model per person count, scored by FID_a alone, from NTU-1P's ST-GCN
trained on the 15 joints NTU-25 and GTA-22 share (:data:`~jaxmotion.geometry.skeletons.JOINTS15`; the paper's
"unified skeleton topology", whose conversion the authors did not publish) reading every fighter, max-pooled.

Baselines: Action2Motion on NTU-2P, the GRU VAE on both persons' joint positions side by side in each frame
(the paper scales the one-person baselines so), in the dataset's frame; CSGN on NTU-2P and on every combat split
(the graph-convolution generator writing every person's channels on each joint,
:func:`~jaxmotion.recipes.actformer.csgn_table_training`, against ActFormer's critic on the stacked persons).
ACTOR carries the paper's numbers only (this project's ACTOR learns joint rotations, which NTU's skeletons do
not have).

    python -m experiments.actformer_multi                    # cpu profile (NTU-2P, GTA Combat 2P)
    python -m experiments.actformer_multi --profile paper

Table: rows Real, then each method's measured row followed by its "(reported)" row; columns "NTU-2P Acc",
"NTU-2P FID_m", "NTU-2P FID_w", "NTU-2P FIDa_m", "NTU-2P FIDa_w", "Combat <k>P FIDa". Profiles:
:func:`~jaxmotion.recipes.actformer.actformer_table_training` and ``csgn_table_training``; ``combat``: the
person counts run. To keep the cpu profile within a CPU's reach, it trains the NTU-2P models for
:data:`NTU2P_CPU_STEPS` steps and GTA Combat's 2-person split only, for :data:`COMBAT_CPU_STEPS` steps (a
two-person step costs twice a one-person one, a five-person one five times); smoke and paper run all four.

Pictures (the paper's Figure 5): ``ntu-2p-generated.png``, key poses of three generated scenes for each of
``picture_actions`` (punching, hugging, handshaking), and ``combat-<k>p-generated.png``, three generated fights,
from ActFormer's models, in the run's folder.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

from jaxmotion import experiment
from jaxmotion.config import FrozenMap, check_at_least
from jaxmotion.evaluation.claims import Claim
from jaxmotion.evaluation.tables import ACTFORMER_COLUMNS, COMBAT_COLUMNS, TableDataset, interleave_reported, slug
from jaxmotion.recipes.tables import DatasetTable, actformer_table, run_tables, table_key
from jaxmotion.pipelines.pictures import generation_grid
from jaxmotion.train.actformer import ActFormerTraining
from jaxmotion.recipes.actformer import a2m_baseline, actformer_table_training, csgn_table_training

NTU2P = tuple(f"NTU-2P {column}" for column in ACTFORMER_COLUMNS.values())


def _reported(ntu2p, combat=()):
    return {**dict(zip(NTU2P, ntu2p)), **{f"Combat {k}P FIDa": v for k, v in zip(range(2, 6), combat)}}


REPORTED = {
    "Action2Motion": _reported((16.85, 15.07, 10.12, 26.25, 20.31)),
    "CSGN": _reported((55.12, 6.10, 3.88, 8.96, 3.20), (1.15, 1.73, 2.09, 4.02)),
    "ACTOR": _reported((63.04, 13.56, 6.72, 19.14, 8.16)),
    "ActFormer": _reported((69.65, 3.77, 3.27, 7.12, 2.46), (1.04, 1.13, 1.58, 2.23)),
}
ROWS = ("Real", *REPORTED)

# §4.2: "when extended to the multi-person case ... our advantages are more significant"
CLAIMS = tuple(
    Claim("ActFormer", op, other, column, "Table 2: ActFormer leads on NTU-2P")
    for other in ("Action2Motion", "CSGN", "ACTOR")
    for op, column in zip((">", "<", "<", "<", "<"), NTU2P)
) + tuple(Claim("ActFormer", "<", "CSGN", f"Combat {k}P FIDa", "Table 2: ActFormer beats CSGN on each split")
          for k in range(2, 6))


#: The cpu profile's steps for the NTU-2P models and for each GTA Combat model.
NTU2P_CPU_STEPS = 1000
COMBAT_CPU_STEPS = 600


def _recipe(recipe, dataset: str, profile: str, cpu_steps: int) -> ActFormerTraining:
    training = recipe(dataset, profile)
    if profile != "cpu":
        return training
    return dataclasses.replace(training, loop=dataclasses.replace(training.loop, steps=cpu_steps))


@dataclasses.dataclass(frozen=True)
class ActFormerMultiConfig(experiment.ProfileConfig):
    ntu2p: DatasetTable  # NTU-2P: Action2Motion, CSGN and ActFormer
    combat: Mapping[str, DatasetTable]  # GTA Combat, one table per person count (combat2p ...): CSGN and ActFormer
    picture_actions: tuple[int, ...] = (0, 5, 8)  # NTU-2P's rows in its picture: punching, hugging, handshaking
    picture_samples: int = 3  # generated scenes per row (combat: one row, its only class)

    def __post_init__(self):
        check_at_least(self, 1, "picture_samples")

    @classmethod
    def for_profile(cls, profile: str) -> ActFormerMultiConfig:
        # smoke: the five-person set only (NTU-2P's rows already run two persons through the same code)
        persons = {"cpu": (2,), "smoke": (5,)}.get(profile, range(2, 6))
        ntu2p = DatasetTable(actformer_table("NTU-2P", profile), FrozenMap({
            "Action2Motion": a2m_baseline("NTU-2P", profile, joints=25, persons=2),
            "CSGN": _recipe(csgn_table_training, "synth-ntu2p", profile, NTU2P_CPU_STEPS),
            "ActFormer": _recipe(actformer_table_training, "synth-ntu2p", profile, NTU2P_CPU_STEPS)}))
        combat = {table_key(f"Combat {p}P"): DatasetTable(actformer_table(f"Combat {p}P", profile), FrozenMap({
            "CSGN": _recipe(csgn_table_training, f"synth-combat-{p}p", profile, COMBAT_CPU_STEPS),
            "ActFormer": _recipe(actformer_table_training, f"synth-combat-{p}p", profile, COMBAT_CPU_STEPS)}))
            for p in persons}
        return cls(ntu2p, FrozenMap(combat))


def _pictures(config: ActFormerMultiConfig, ctx: experiment.RunContext):
    """Figure 5's pictures: key poses of ActFormer's generated scenes, ``<workdir>/<dataset>-generated.png`` (with
    ``--video`` also ``.mp4``)."""

    frames = {d.table.label: d.rows["ActFormer"].generator.frames for d in (config.ntu2p, *config.combat.values())}

    def draw(table: TableDataset, samplers, train) -> None:
        actions = config.picture_actions if train.num_classes > 1 else (0,)
        path = ctx.workdir / f"{slug(table.label)}-generated.png"
        generation_grid(samplers["ActFormer"], ctx.key(f"pictures {table.label}"), train.skeleton,
                        train.class_names, train.fps, actions, path, per_action=config.picture_samples,
                        duration=frames[table.label], still=True, video=ctx.video)

    return draw


def run(config: ActFormerMultiConfig, ctx: experiment.RunContext):
    common = dict(workdir=ctx.workdir, key=ctx.key, data_root=ctx.data_root, mesh=ctx.mesh,
                  writers=ctx.writers, pictures=_pictures(config, ctx))
    rows = run_tables([config.ntu2p], columns=ACTFORMER_COLUMNS, **common)
    combat = run_tables(list(config.combat.values()), columns=COMBAT_COLUMNS, **common)
    for name, cells in combat.items():
        rows.setdefault(name, {}).update(cells)
    return interleave_reported(rows, REPORTED, ROWS)


def main(argv=None):
    return experiment.main("actformer_multi", ActFormerMultiConfig, run, argv, description=__doc__, claims=CLAIMS,
                           videos=True)


if __name__ == "__main__":
    main()
