"""ACTOR Table A.3: number of Transformer layers, swept over the headline UESTC run.

Paper: Petrovich, Black, Varol, ICCV 2021, appendix A.3. Finding: 2 and 4 layers are worse, 6 and 8 nearly equal; 8 is used everywhere.
Each row is ``experiments.actor_uestc``'s run with ``model.layers`` set to one value: 2, 4, 6, 8, in the encoder and in the decoder (the paper's).
Our copy of the paper has the finding but not the table's numbers, so there is no reported column.

    python -m experiments.actor_ablation_layers                     # cpu profile, embedded synth-uestc
    python -m experiments.actor_ablation_layers --set "values=[2]"
"""

from __future__ import annotations

import dataclasses

from experiments.actor_uestc import UestcSweep, run_sweep
from jaxmotion import experiment


@dataclasses.dataclass(frozen=True)
class ActorAblationLayersConfig(UestcSweep):
    values: tuple[int, ...] = (2, 4, 6, 8)
    FIELD = "model.layers"
    SMOKE_VALUES = (1, 2)

    def label(self, value) -> str:
        return f"{value} layers"


def main(argv=None):
    return experiment.main("actor_ablation_layers", ActorAblationLayersConfig, run_sweep, argv, description=__doc__)


if __name__ == "__main__":
    main()
