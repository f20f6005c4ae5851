"""ACTOR Table A.1: weight of the KL term, swept over the headline UESTC run.

Paper: Petrovich, Black, Varol, ICCV 2021, appendix A.1. Finding: a trade-off between diversity and realism, best balanced at λ_KL = 1e-5 (used everywhere).
Each row is ``experiments.actor_uestc``'s run with ``losses.kl`` set to one value: 1e-3, 1e-4, 1e-5, 1e-6 (our choice around the paper's 1e-5; its rows are not in our copy).
Our copy of the paper has the finding but not the table's numbers, so there is no reported column.

    python -m experiments.actor_ablation_kl                     # cpu profile, embedded synth-uestc
    python -m experiments.actor_ablation_kl --set "values=[1e-3]"
"""

from __future__ import annotations

import dataclasses

from jaxmotion import experiment
from jaxmotion.evaluation.claims import Claim
from jaxmotion.evaluation.tables import TableDataset
from jaxmotion.recipes.tables import table_dataset
from jaxmotion.train.actor import ActorTraining
from jaxmotion.recipes.actor import uestc_training

# A.1: "a good trade-off between diversity and realism ... best balanced at λ_KL = 1e-5"
CLAIMS = (
    Claim("λ_KL = 1e-05", "<", "λ_KL = 0.001", "FID_tr", "A.1: a heavy KL term loses realism"),
    Claim("λ_KL = 1e-05", "<", "λ_KL = 1e-06", "FID_tr", "A.1: a light KL term samples worse from N(0, I)"),
)


@dataclasses.dataclass(frozen=True)
class ActorAblationKlConfig(experiment.Sweep):
    training: ActorTraining  # the headline UESTC run (experiments.actor_uestc)
    table: TableDataset
    values: tuple[float, ...] = (1e-3, 1e-4, 1e-5, 1e-6)
    FIELD = "losses.kl"
    SMOKE_VALUES = (1e-4, 1e-5)
    SETUP = staticmethod(lambda profile: (uestc_training(profile), table_dataset("UESTC", profile)))

    def label(self, value) -> str:
        return f"λ_KL = {value:g}"


def main(argv=None):
    return experiment.main("actor_ablation_kl", ActorAblationKlConfig, experiment.run_sweep, argv,
                           description=__doc__, claims=CLAIMS)


if __name__ == "__main__":
    main()
