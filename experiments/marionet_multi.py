"""Neural Marionette Table 3 and Figure 8: multi-action synthesis by the pure generative pipeline, MANN, A2M and
MARIONET on the overall and sufficient test sets.

Paper: Wang et al., "Neural Marionette: A Transformer-based Multi-action Human Motion Synthesis System" (2022),
§5.2 and Table 3, Figure 8. Each model is chained (S-Alg. 1: every action continues the last 6 frames of the one
before, normalised at its last pose; no blending) over programs of 20 actions whose conditions come from the test
actions the evaluator recognises with confidence >= 50%; next tags follow the training transitions ("overall") or
the most frequent ones ("sufficient"). The test sets, scores and the choices where the paper is silent are
:mod:`jaxmotion.evaluation.multi_action`'s.

    python -m experiments.marionet_multi                   # cpu profile on the embedded synth-mag
    python -m experiments.marionet_multi --profile paper --data-root BABEL   # BABEL-MAG (loader "mag")

Table: rows MANN, A2M, MARIONET, each followed by the paper's numbers ("(reported)"). Columns per set, "(O)" overall
and "(S)" sufficient: Acc (a fraction) and FID averaged over actions 2..20, Δpose (cm) and Δvel (cm/frame) over
the transitions, as the paper; then, beyond it, Motion QR over actions 2..20 (the paper plots it only; the
action QR over the same actions is the accuracy), and FlowMDM's Peak Jerk, Area Under the Jerk and transition FID
(30-frame windows). Picture:
``figure8.png`` (Acc, FID, Action QR, Motion QR against the action index, both sets); the curves are also in
``curves.json``.

What differs from the paper, and why: the data (synth-mag and its evaluator; absolute numbers are not comparable
with the paper's); the cpu profile draws 200 programs per set (the paper one per candidate, 764) and repeats the
generation 3 times (mean ± 95% CI; the paper generates once). The rows train exactly as in Table 1
(``marionet_single``: same recipes, data and key): run after it with the same ``--out``, this table resumes Table 1's
finished rows instead of training them again (``recipes.marionette.EXPERIMENTS``).
Claims the table's layout cannot express (a set against the other for one method: S above O on Acc, and so on)
are left to the reader of the table.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

from jaxmotion import experiment
from jaxmotion.config import FrozenMap
from jaxmotion.evaluation.claims import Claim
from jaxmotion.evaluation.tables import interleave_reported
from jaxmotion.recipes.marionette import (EXPERIMENTS, A2MContextRecipe, ChainRow, MannRecipe, MarionetRecipe,
                                          ProgramTable, a2m_training, mann_training, marionet_training, program_table,
                                          run_program_table, save_index_curves)

_PAPER_COLUMNS = ("Acc", "FID", "Δpose", "Δvel")
# Table 3: overall, then sufficient
REPORTED = {name: {f"{column} ({label})": value for label, part in zip("OS", (values[:4], values[4:]))
                   for column, value in zip(_PAPER_COLUMNS, part)} for name, values in {
    "MANN": (0.723, 12.785, 1.47, 0.42, 0.746, 14.744, 1.56, 0.37),
    "A2M": (0.775, 15.796, 3.41, 1.92, 0.830, 7.933, 4.12, 1.73),
    "MARIONET": (0.786, 7.854, 2.03, 0.40, 0.862, 4.624, 2.53, 0.35),
}.items()}
ROWS = ("MANN", "A2M", "MARIONET")

# §5.2.3 (MARIONETTE.md §6, Tab. 3)
CLAIMS = tuple(claim for s in "OS" for claim in (
    Claim("MARIONET", ">", "A2M", f"Acc ({s})", "Table 3: highest accuracy"),
    Claim("A2M", ">", "MANN", f"Acc ({s})", "Table 3"),
    Claim("MARIONET", "<", "MANN", f"FID ({s})", "Table 3: lowest FID"),
    Claim("MARIONET", "<", "A2M", f"FID ({s})", "Table 3: lowest FID"),
    Claim("MANN", "<", "MARIONET", f"Δpose ({s})", "Table 3: MANN's transitions closest"),
    Claim("MARIONET", "<", "A2M", f"Δpose ({s})", "Table 3"),
    Claim("MARIONET", "<", "MANN", f"Δvel ({s})", "Table 3: smoothest velocities"),
    Claim("MANN", "<", "A2M", f"Δvel ({s})", "Table 3"),
)) + (Claim("MANN", "<", "A2M", "FID (O)", "Table 3"), Claim("A2M", "<", "MANN", "FID (S)", "Table 3"))


@dataclasses.dataclass(frozen=True)
class MarionetMultiConfig(experiment.ProfileConfig):
    table: ProgramTable
    rows: Mapping[str, ChainRow]

    @classmethod
    def for_profile(cls, profile: str) -> MarionetMultiConfig:
        return cls(program_table(profile), FrozenMap({
            "MANN": ChainRow(MannRecipe(mann_training(profile))),
            "A2M": ChainRow(A2MContextRecipe(a2m_training(profile))),
            "MARIONET": ChainRow(MarionetRecipe(marionet_training(profile)))}))


def run(config: MarionetMultiConfig, ctx: experiment.RunContext):
    rows, curves = run_program_table(config.rows, config.table, workdir=ctx.workdir, train_key=ctx.key("train"),
                                     eval_key=ctx.key("eval"), data_root=ctx.data_root, mesh=ctx.mesh,
                                     writers=ctx.writers, lenders=ctx.runs(*EXPERIMENTS))
    save_index_curves(ctx.workdir, curves, "figure8")
    return interleave_reported(rows, REPORTED, ROWS)


def main(argv=None):
    return experiment.main("marionet_multi", MarionetMultiConfig, run, argv, description=__doc__, claims=CLAIMS)


if __name__ == "__main__":
    main()
