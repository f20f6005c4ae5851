"""Neural Marionette Table 4: what the next tag is worth, MARIONET trained with and without it, scored on single
actions and on the two multi-action test sets.

Paper: Wang et al., "Neural Marionette: A Transformer-based Multi-action Human Motion Synthesis System" (2022),
§5.2.4 and Table 4. "W/O next tag" feeds zeros as the next tag, in training and in generation (the paper's
ablation; ``MarionetConfig.next_tag=False``). Single-action accuracy is Table 1's protocol
(:mod:`jaxmotion.evaluation.actions`), multi-action accuracy Table 3's (the pure pipeline,
:mod:`jaxmotion.evaluation.multi_action`), both over actions 2..20 for the multi-action sets.

    python -m experiments.marionet_next_tag                 # cpu profile on the embedded synth-mag

Table: rows "W/ next tag" and "W/O next tag", each followed by the paper's numbers; columns "Single Acc", "Multi Acc
(O)", "Multi Acc (S)" (fractions, as the paper prints them).

What differs from the paper, and why: the data and evaluator (synth-mag). "W/ next tag" trains as Table 1's MARIONET
(same recipe and key); "W/O next tag" is a training of its own (in the cpu profile, as long as Table 1's).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

from jaxmotion import experiment
from jaxmotion.config import FrozenMap
from jaxmotion.evaluation.claims import Claim
from jaxmotion.evaluation.tables import interleave_reported
from jaxmotion.recipes.marionette import (EXPERIMENTS, ChainRow, MarionetRecipe, ProgramTable, marionet_training,
                                          program_table, run_action_table, run_program_table)

COLUMNS = ("Single Acc", "Multi Acc (O)", "Multi Acc (S)")
REPORTED = {"W/ next tag": dict(zip(COLUMNS, (0.874, 0.786, 0.862))),
            "W/O next tag": dict(zip(COLUMNS, (0.875, 0.770, 0.823)))}
ROWS = ("W/ next tag", "W/O next tag")

# §5.2.4 (MARIONETTE.md §6, Tab. 4); single-action accuracy "about the same" is no ordering to check
CLAIMS = tuple(Claim("W/ next tag", ">", "W/O next tag", column, "Table 4: the next tag helps multi-action synthesis")
               for column in ("Multi Acc (O)", "Multi Acc (S)"))


@dataclasses.dataclass(frozen=True)
class MarionetNextTagConfig(experiment.ProfileConfig):
    table: ProgramTable
    rows: Mapping[str, ChainRow]

    @classmethod
    def for_profile(cls, profile: str) -> MarionetNextTagConfig:
        return cls(program_table(profile), FrozenMap({
            "W/ next tag": ChainRow(MarionetRecipe(marionet_training(profile))),
            "W/O next tag": ChainRow(MarionetRecipe(marionet_training(profile, next_tag=False)))}))


def run(config: MarionetNextTagConfig, ctx: experiment.RunContext):
    recipes = {name: row.recipe for name, row in config.rows.items()}
    single = run_action_table(recipes, config.table.single, workdir=ctx.workdir, train_key=ctx.key("train"),
                              eval_key=ctx.key("eval"), data_root=ctx.data_root, mesh=ctx.mesh,
                              writers=ctx.writers, lenders=ctx.runs(*EXPERIMENTS))
    multi, _ = run_program_table(config.rows, config.table, workdir=ctx.workdir, train_key=ctx.key("train"),
                                 eval_key=ctx.key("eval"), data_root=ctx.data_root, mesh=ctx.mesh,
                                 writers=ctx.writers, lenders=ctx.runs(*EXPERIMENTS))
    rows = {name: {"Single Acc": single[name]["Acc"], "Multi Acc (O)": multi[name]["Acc (O)"],
                   "Multi Acc (S)": multi[name]["Acc (S)"]} for name in config.rows}
    return interleave_reported(rows, REPORTED, ROWS)


def main(argv=None):
    return experiment.main("marionet_next_tag", MarionetNextTagConfig, run, argv, description=__doc__, claims=CLAIMS)


if __name__ == "__main__":
    main()
