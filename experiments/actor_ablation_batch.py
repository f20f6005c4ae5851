"""ACTOR Table A.2: batch size, swept over the headline UESTC run.

Paper: Petrovich, Black, Varol, ICCV 2021, appendix A.2. Finding: training is sensitive to the batch size at a fixed learning rate; 20 is best (used everywhere).
Each row is ``experiments.actor_uestc``'s run with ``batch_size`` set to one value: 10, 20, 30, 40 (the paper's).
Our copy of the paper has the finding but not the table's numbers, so there is no reported column.

    python -m experiments.actor_ablation_batch                     # cpu profile, embedded synth-uestc
    python -m experiments.actor_ablation_batch --set "values=[10]"
"""

from __future__ import annotations

import dataclasses

from experiments.actor_uestc import UestcSweep, run_sweep
from jaxmotion import experiment


@dataclasses.dataclass(frozen=True)
class ActorAblationBatchConfig(UestcSweep):
    values: tuple[int, ...] = (10, 20, 30, 40)
    FIELD = "batch_size"
    SMOKE_VALUES = (4, 8)

    def label(self, value) -> str:
        return f"batch {value}"


def main(argv=None):
    return experiment.main("actor_ablation_batch", ActorAblationBatchConfig, run_sweep, argv, description=__doc__)


if __name__ == "__main__":
    main()
