"""ACTOR Table A.2: batch size, swept over the headline UESTC run.

Paper: Petrovich, Black, Varol, ICCV 2021, appendix A.2. Finding: training is sensitive to the batch size at a fixed learning rate; 20 is best (used everywhere).
Each row is ``experiments.actor_uestc``'s run with ``batch_size`` set to one value: 10, 20, 30, 40 (the paper's).
Our copy of the paper has the finding but not the table's numbers, so there is no reported column.

    python -m experiments.actor_ablation_batch                     # cpu profile, embedded synth-uestc
    python -m experiments.actor_ablation_batch --set "values=[10]"
"""

from __future__ import annotations

import dataclasses

from jaxmotion import experiment
from jaxmotion.evaluation.claims import Claim
from jaxmotion.evaluation.tables import TableDataset
from jaxmotion.recipes.tables import table_dataset
from jaxmotion.train.actor import ActorTraining
from jaxmotion.recipes.actor import uestc_training

# A.2: "sensitivity ... to different batch sizes"; 20 is the value used
CLAIMS = (
    Claim("batch 20", "<", "batch 10", "FID_tr", "A.2: 20 is best"),
    Claim("batch 20", "<", "batch 40", "FID_tr", "A.2: 20 is best"),
)


@dataclasses.dataclass(frozen=True)
class ActorAblationBatchConfig(experiment.Sweep):
    training: ActorTraining  # the headline UESTC run (experiments.actor_uestc)
    table: TableDataset
    values: tuple[int, ...] = (10, 20, 30, 40)
    FIELD = "batch_size"
    SMOKE_VALUES = (4, 8)
    SETUP = staticmethod(lambda profile: (uestc_training(profile), table_dataset("UESTC", profile)))

    def label(self, value) -> str:
        return f"batch {value}"


def main(argv=None):
    return experiment.main("actor_ablation_batch", ActorAblationBatchConfig, experiment.run_sweep, argv,
                           description=__doc__, claims=CLAIMS)


if __name__ == "__main__":
    main()
