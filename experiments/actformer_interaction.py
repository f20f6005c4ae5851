"""ActFormer Table 5: how the persons interact: the shared latent sequence and the I-Formers, on NTU-2P (and
GTA Combat 2-5P).

Paper: Xu et al., ICCV 2023, §4.3 and Table 5. Rows, each the complete two-person model with one thing
changed, trained on synth-ntu2p's train split and scored under ActFormer's protocol (two-person ST-GCN; FID_a
from the one-person NTU-25 ST-GCN max-pooled over the persons):

* **(1) w/o shared z**: one GP sequence per person (``shared_z=False``);
* **(2) Interaction by concatenation**: the one-person network writing every person's joints per frame, no
  I-Formers (``generator.interaction="concat"``);
* **(3) Complete model**.

The GTA Combat columns (FID_a on 2-5 persons) are the paper's numbers only here: the three variants on four
person counts are twelve more trainings, past this experiment's cpu budget. The complete model's combat FID_a,
on the same 15-joint protocol, is measured by :mod:`experiments.actformer_multi`.

    python -m experiments.actformer_interaction                     # cpu profile, one seed
    python -m experiments.actformer_interaction --seeds 0,1,2       # Table 5's claims with intervals over seeds

Table: rows (1)-(3), measured rows followed by their "(reported)" rows, then Real; columns "NTU-2P Acc",
"NTU-2P FID_m", "NTU-2P FID_w", "NTU-2P FIDa_m", "NTU-2P FIDa_w", and the reported "Combat <k>P FIDa".
Profiles: :func:`~jaxmotion.recipes.actformer.actformer_table_training`.
"""

from __future__ import annotations

import dataclasses

from jaxmotion import experiment
from jaxmotion.evaluation.claims import Claim
from jaxmotion.evaluation.tables import ACTFORMER_COLUMNS, TableDataset, interleave_reported
from jaxmotion.recipes.tables import actformer_table
from jaxmotion.train.actformer import ActFormerTraining
from jaxmotion.recipes.actformer import actformer_table_training

COMPLETE = "(3) Complete model"
COLUMNS = {metric: f"NTU-2P {column}" for metric, column in ACTFORMER_COLUMNS.items()}


def _reported(ntu2p, combat):
    return {**dict(zip(COLUMNS.values(), ntu2p)), **{f"Combat {k}P FIDa": v for k, v in zip(range(2, 6), combat)}}


REPORTED = {
    "(1) w/o shared z": _reported((56.35, 14.79, 5.73, 20.69, 7.26), (1.26, 1.36, 1.84, 2.42)),
    "(2) Interaction by concatenation": _reported((56.46, 7.63, 4.33, 11.51, 3.57), (1.15, 1.37, 2.23, 7.62)),
    COMPLETE: _reported((69.65, 3.77, 3.27, 7.12, 2.46), (1.04, 1.13, 1.58, 2.23)),
}
ROWS = ("Real", *REPORTED)

# §4.3: "we find both designs indispensable to synthesize high-quality interactive actions"
CLAIMS = tuple(
    Claim(COMPLETE, op, other, f"NTU-2P {column}", "Table 5: the shared z and the I-Formers are both needed")
    for other in REPORTED if other != COMPLETE
    for op, column in (("<", "FID_m"), ("<", "FID_w"), ("<", "FIDa_m"), ("<", "FIDa_w"), (">", "Acc"))
)


@dataclasses.dataclass(frozen=True)
class ActFormerInteractionConfig(experiment.Variants):
    training: ActFormerTraining  # the complete two-person model; each row changes it as VARIANTS says
    table: TableDataset
    VARIANTS = {"(1) w/o shared z": {"shared_z": False},
                "(2) Interaction by concatenation": {"generator.interaction": "concat"}, COMPLETE: {}}
    COLUMNS = COLUMNS
    SETUP = staticmethod(lambda profile: (actformer_table_training("synth-ntu2p", profile),
                                          actformer_table("NTU-2P", profile)))


def run(config: ActFormerInteractionConfig, ctx: experiment.RunContext):
    return interleave_reported(experiment.run_sweep(config, ctx), REPORTED, ROWS)


def main(argv=None):
    return experiment.main("actformer_interaction", ActFormerInteractionConfig, run, argv, description=__doc__,
                           claims=CLAIMS)


if __name__ == "__main__":
    main()
