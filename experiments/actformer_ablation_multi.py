"""ActFormer Table 4: design choices on two-person generation (NTU-2P): the critic's treatment of the persons
and the positional encoding.

Paper: Xu et al., ICCV 2023, §4.3 and Table 4. Rows, each the full two-person model with one thing changed,
trained on synth-ntu2p's train split and scored under ActFormer's protocol by the two-person ST-GCN (the pair
stacked on channels) and, for FID_a, the one-person NTU-25 ST-GCN max-pooled over the persons
(:func:`~jaxmotion.evaluation.tables.actformer_table`):

* **(5) AvgPool. / (6) MaxPool. / (7) SelfAtt. in Disc.**: the critic body on each person alone, its features
  pooled over the persons (``critic_pooling``: avg, max, one self-attention then the mean;
  :func:`~jaxmotion.models.actformer_critic.pool_persons`);
* **(8) Fixed PE**: sinusoidal codes (``generator.positions="fixed"``);
* **(9) Independent PE**: one learnt ``[T + 1, P, D]`` tensor, not temporal + person parts
  (``generator.positions="independent"``);
* **(10) Full model**.

    python -m experiments.actformer_ablation_multi                  # cpu profile
    python -m experiments.actformer_ablation_multi --seeds 0,1,2

Table: rows (5)-(10), measured rows followed by their "(reported)" rows, then Real; columns Acc, FID_m,
FID_w, FIDa_m, FIDa_w. Profiles: :func:`~jaxmotion.recipes.actformer.actformer_table_training`; cpu trains each of
the six rows 1 000 steps instead of 2 000, as many steps in all as Table 5's three rows.
"""

from __future__ import annotations

import dataclasses

from jaxmotion import experiment
from jaxmotion.evaluation.claims import Claim
from jaxmotion.evaluation.tables import ACTFORMER_COLUMNS, TableDataset, interleave_reported
from jaxmotion.recipes.tables import actformer_table
from jaxmotion.train.actformer import ActFormerTraining
from jaxmotion.recipes.actformer import actformer_table_training

FULL = "(10) Full model"


def _reported(*values):
    return dict(zip(ACTFORMER_COLUMNS.values(), values))


REPORTED = {
    "(5) AvgPool. in Disc.": _reported(53.85, 20.42, 8.33, 25.35, 10.09),
    "(6) MaxPool. in Disc.": _reported(60.19, 10.71, 4.01, 17.26, 5.42),
    "(7) SelfAtt. in Disc.": _reported(51.53, 19.96, 8.27, 24.91, 8.75),
    "(8) Fixed PE": _reported(61.42, 4.86, 3.64, 7.71, 2.78),
    "(9) Independent PE": _reported(67.19, 4.08, 3.38, 7.00, 2.62),
    FULL: _reported(69.65, 3.77, 3.27, 7.12, 2.46),
}
ROWS = ("Real", *REPORTED)

# §4.3: learnable split PE beats fixed and independent PE; concatenation + permutation beats pooled critics
CLAIMS = tuple(
    Claim(FULL, "<", other, column, "Table 4: the full model's positional codes and critic")
    for other in REPORTED if other != FULL
    for column in ("FID_m", "FID_w")
) + tuple(Claim(FULL, ">", other, "Acc", "Table 4") for other in REPORTED if other != FULL)


def _training(profile: str) -> ActFormerTraining:
    training = actformer_table_training("synth-ntu2p", profile)
    if profile == "cpu":  # six rows
        training = dataclasses.replace(training, loop=dataclasses.replace(training.loop, steps=1000))
    return training


@dataclasses.dataclass(frozen=True)
class ActFormerAblationMultiConfig(experiment.Variants):
    training: ActFormerTraining  # the full two-person model; each row changes it as VARIANTS says
    table: TableDataset
    VARIANTS = {"(5) AvgPool. in Disc.": {"critic_pooling": "avg"}, "(6) MaxPool. in Disc.": {"critic_pooling": "max"},
                "(7) SelfAtt. in Disc.": {"critic_pooling": "attention"}, "(8) Fixed PE": {"generator.positions": "fixed"},
                "(9) Independent PE": {"generator.positions": "independent"}, FULL: {}}
    COLUMNS = ACTFORMER_COLUMNS
    SETUP = staticmethod(lambda profile: (_training(profile), actformer_table("NTU-2P", profile)))


def run(config: ActFormerAblationMultiConfig, ctx: experiment.RunContext):
    return interleave_reported(experiment.run_sweep(config, ctx), REPORTED, ROWS)


def main(argv=None):
    return experiment.main("actformer_ablation_multi", ActFormerAblationMultiConfig, run, argv,
                           description=__doc__, claims=CLAIMS)


if __name__ == "__main__":
    main()
