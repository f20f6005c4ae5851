"""ACTOR Table A.3: number of Transformer layers, swept over the headline UESTC run.

Paper: Petrovich, Black, Varol, ICCV 2021, appendix A.3. Finding: 2 and 4 layers are worse, 6 and 8 nearly equal; 8 is used everywhere.
Each row is ``experiments.actor_uestc``'s run with ``model.layers`` set to one value: 2, 4, 6, 8, in the encoder and in the decoder (the paper's).
Our copy of the paper has the finding but not the table's numbers, so there is no reported column.

    python -m experiments.actor_ablation_layers                     # cpu profile, embedded synth-uestc
    python -m experiments.actor_ablation_layers --set "values=[2]"
"""

from __future__ import annotations

import dataclasses

from jaxmotion import experiment
from jaxmotion.evaluation.claims import Claim
from jaxmotion.evaluation.tables import TableDataset
from jaxmotion.recipes.tables import table_dataset
from jaxmotion.train.actor import ActorTraining
from jaxmotion.recipes.actor import uestc_training

# A.3: "the performance degrades at 2 or 4 layers, we see marginal gains after 6 layers"
CLAIMS = (
    Claim("8 layers", "<", "2 layers", "FID_tr", "A.3: 2 layers are suboptimal"),
    Claim("8 layers", "<", "4 layers", "FID_tr", "A.3: 4 layers are suboptimal"),
    Claim("8 layers", ">", "2 layers", "Acc. (%)", "A.3: 2 layers are suboptimal"),
)


@dataclasses.dataclass(frozen=True)
class ActorAblationLayersConfig(experiment.Sweep):
    training: ActorTraining  # the headline UESTC run (experiments.actor_uestc)
    table: TableDataset
    values: tuple[int, ...] = (2, 4, 6, 8)
    FIELD = "model.layers"
    SMOKE_VALUES = (1, 2)
    SETUP = staticmethod(lambda profile: (uestc_training(profile), table_dataset("UESTC", profile)))

    def label(self, value) -> str:
        return f"{value} layers"


def main(argv=None):
    return experiment.main("actor_ablation_layers", ActorAblationLayersConfig, experiment.run_sweep, argv,
                           description=__doc__, claims=CLAIMS)


if __name__ == "__main__":
    main()
