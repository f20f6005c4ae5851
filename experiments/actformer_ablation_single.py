"""ActFormer Table 3: design choices on single-person generation (NTU-1P): the latent prior, the positional
encoding, and a graph-convolution generator.

Paper: Xu et al., ICCV 2023, §4.3 and Table 3. Rows, each the full model with one thing changed
(:class:`~jaxmotion.train.actformer.ActFormerTraining`), trained on synth-ntu1p's train split and scored under
ActFormer's protocol by its NTU-25 ST-GCN evaluator (:func:`~jaxmotion.evaluation.tables.actformer_table`):

* **(1) Gaussian latent prior**: white noise per frame instead of the GP sequence (``prior="gaussian"``);
* **(2) GraphConv. in Gen.**: a graph-convolution generator with graph upsampling as CSGN's, T-Formers over
  time (:class:`~jaxmotion.models.csgn.CSGNConfig` with ``temporal="transformer"``, conditional BatchNorm);
* **(3) Fixed PE**: sinusoidal positional codes, not learnt (``generator.positions="fixed"``);
* **(4) Full model**.

    python -m experiments.actformer_ablation_single                 # cpu profile
    python -m experiments.actformer_ablation_single --seeds 0,1,2   # intervals over training seeds

Table: rows (1)-(4), each measured row followed by its "(reported)" row, then Real; columns Acc, FID_m, FID_w.
Profiles: the recipes of :func:`~jaxmotion.recipes.actformer.actformer_table_training` (cpu: a small critic,
2 000 steps a row; scoring the 120 classes is a large part of the run).
"""

from __future__ import annotations

import dataclasses

from jaxmotion import experiment
from jaxmotion.evaluation.claims import Claim
from jaxmotion.evaluation.tables import ACTFORMER_COLUMNS, TableDataset, interleave_reported
from jaxmotion.recipes.tables import actformer_table
from jaxmotion.train.actformer import ActFormerTraining
from jaxmotion.recipes.actformer import actformer_table_training, csgn_table_training

FULL = "(4) Full model"
COLUMNS = {metric: ACTFORMER_COLUMNS[metric] for metric in ("accuracy", "FIDm_train", "FID_train")}
REPORTED = {
    "(1) Gaussian latent prior": {"Acc": 37.55, "FID_m": 17.25, "FID_w": 6.01},
    "(2) GraphConv. in Gen.": {"Acc": 32.97, "FID_m": 18.68, "FID_w": 6.09},
    "(3) Fixed PE": {"Acc": 37.57, "FID_m": 18.38, "FID_w": 5.55},
    FULL: {"Acc": 42.01, "FID_m": 12.53, "FID_w": 3.57},
}
ROWS = ("Real", *REPORTED)

# §4.3: the GP prior and learnable PE matter; "no need to explicitly model skeleton topology"
CLAIMS = tuple(
    Claim(FULL, op, other, column, f"Table 3: the full model beats {other[4:]}")
    for other in REPORTED if other != FULL
    for op, column in ((">", "Acc"), ("<", "FID_m"), ("<", "FID_w"))
)


@dataclasses.dataclass(frozen=True)
class ActFormerAblationSingleConfig(experiment.Variants):
    training: ActFormerTraining  # the full model; each row changes it as VARIANTS says
    table: TableDataset
    graph_generator: ActFormerTraining  # row (2): the same recipe with the graph-convolution generator
    VARIANTS = {"(1) Gaussian latent prior": {"prior": "gaussian"}, "(3) Fixed PE": {"generator.positions": "fixed"},
                FULL: {}}
    COLUMNS = COLUMNS
    SETUP = staticmethod(lambda profile: (actformer_table_training("synth-ntu1p", profile),
                                          actformer_table("NTU-1P", profile),
                                          csgn_table_training("synth-ntu1p", profile, temporal="transformer")))

    def rows(self) -> dict:
        rows = super().rows()
        return {**dict(list(rows.items())[:1]), "(2) GraphConv. in Gen.": self.graph_generator,
                **dict(list(rows.items())[1:])}


def run(config: ActFormerAblationSingleConfig, ctx: experiment.RunContext):
    return interleave_reported(experiment.run_sweep(config, ctx), REPORTED, ROWS)


def main(argv=None):
    return experiment.main("actformer_ablation_single", ActFormerAblationSingleConfig, run, argv,
                           description=__doc__, claims=CLAIMS)


if __name__ == "__main__":
    main()
