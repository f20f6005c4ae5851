"""Neural Marionette Table 2: the ablation of MARIONET's key components (scheduled sampling, time unrolling, tag
injection) in the single-action setting, with ΔJPE.

Paper: Wang et al. 2022, §5.1.4 and Table 2. Each row is MARIONET with one component (or two) switched off, trained
from the same key on the same data, scored as Table 1 (:mod:`jaxmotion.evaluation.actions`) plus ΔJPE: each test
action generated once more with Z = mu under its own conditions, against the real one (cm; the paper names the
column and never defines it).

    python -m experiments.marionet_ablation                 # cpu profile on the embedded synth-mag
    python -m experiments.marionet_ablation --profile paper --data-root BABEL

Table: rows MARIONET, w/o Schedule Sampling, w/o TU and w/o TI, w/o TU, w/o TI, each followed by the paper's
numbers, and Real. Columns FID, Acc, Div, Multi-mod, ΔJPE.

What the switches do (``jaxmotion.models.marionet``): without time unrolling every frame's control is FC(Z) (no
unrolling decoder: what replaces it is unstated); without tag injection the unrolling queries are the reverse
position code alone; without scheduled sampling the second decoder pass never counts (teacher forcing only).

What differs from the paper: synth-mag and its evaluator stand in for BABEL-MAG and the paper's recogniser
(absolute numbers are not comparable). cpu profile: MARIONET's cpu size and schedule (:func:`jaxmotion.recipes.
marionette.marionet_training`) per row, 5 repetitions over the test actions. Measured tables: ``docs/results/``.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

from jaxmotion import experiment
from jaxmotion.config import FrozenMap
from jaxmotion.evaluation.claims import Claim
from jaxmotion.evaluation.tables import interleave_reported
from jaxmotion.recipes.marionette import (EXPERIMENTS, ActionTable, MarionetRecipe, action_table, marionet_training,
                                          run_action_table)

COLUMNS = ("FID", "Acc", "Div", "Multi-mod", "ΔJPE")
# Table 2
REPORTED = {name: dict(zip(COLUMNS, values)) for name, values in {
    "MARIONET": (1.115, 0.874, 9.904, 2.068, 4.58),
    "w/o Schedule Sampling": (1.274, 0.871, 9.846, 1.985, 6.99),
    "w/o TU and w/o TI": (11.294, 0.638, 9.706, 2.404, 9.32),
    "w/o TU": (11.522, 0.676, 9.867, 2.442, 9.42),
    "w/o TI": (5.040, 0.819, 9.458, 2.284, 7.84),
}.items()}
#: Each row's switches (MarionetConfig's fields and the trainer's scheduled_sampling).
VARIANTS = {"MARIONET": {}, "w/o Schedule Sampling": {"scheduled_sampling": False},
            "w/o TU and w/o TI": {"time_unrolling": False, "tag_injection": False},
            "w/o TU": {"time_unrolling": False}, "w/o TI": {"tag_injection": False}}
ROWS = (*VARIANTS, "Real")

# §5.1.4 (MARIONETTE.md §6, Tab. 2)
CLAIMS = (
    Claim("MARIONET", "<", "w/o Schedule Sampling", "FID", "Table 2: scheduled sampling helps"),
    Claim("MARIONET", "<", "w/o Schedule Sampling", "ΔJPE", "Table 2"),
    Claim("MARIONET", ">", "w/o Schedule Sampling", "Acc", "Table 2"),
    Claim("MARIONET", "<", "w/o TI", "FID", "Table 2: tag injection helps"),
    Claim("w/o TI", "<", "w/o TU", "FID", "Table 2: time unrolling helps more"),
    Claim("MARIONET", "<", "w/o TI", "ΔJPE", "Table 2"),
    Claim("w/o TI", "<", "w/o TU", "ΔJPE", "Table 2"),
    Claim("MARIONET", ">", "w/o TI", "Acc", "Table 2"),
    Claim("w/o TI", ">", "w/o TU", "Acc", "Table 2"),
    Claim("MARIONET", ">", "w/o TU", "Div", "Table 2"),
    Claim("MARIONET", ">", "w/o TI", "Div", "Table 2"),
    Claim("w/o TU", ">", "MARIONET", "Multi-mod", "Table 2: all metrics except multimodality"),
    Claim("w/o TI", ">", "MARIONET", "Multi-mod", "Table 2"),
)


@dataclasses.dataclass(frozen=True)
class MarionetAblationConfig(experiment.ProfileConfig):
    table: ActionTable
    rows: Mapping[str, MarionetRecipe]

    @classmethod
    def for_profile(cls, profile: str) -> MarionetAblationConfig:
        return cls(action_table(profile, joint_error=True), FrozenMap({
            name: MarionetRecipe(marionet_training(profile, **switches)) for name, switches in VARIANTS.items()}))


def run(config: MarionetAblationConfig, ctx: experiment.RunContext):
    rows = run_action_table(config.rows, config.table, workdir=ctx.workdir, train_key=ctx.key("train"),
                            eval_key=ctx.key("eval"), data_root=ctx.data_root, mesh=ctx.mesh,
                            writers=ctx.writers, lenders=ctx.runs(*EXPERIMENTS))
    return interleave_reported({name: {c: cells[c] for c in COLUMNS if c in cells} for name, cells in rows.items()},
                               REPORTED, ROWS)


def main(argv=None):
    return experiment.main("marionet_ablation", MarionetAblationConfig, run, argv, description=__doc__,
                           claims=CLAIMS)


if __name__ == "__main__":
    main()
