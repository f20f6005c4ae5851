"""ACTOR Table A.4: the rotation representation of the pose parameters, swept over the headline UESTC run.

Paper: Petrovich, Black, Varol, ICCV 2021, appendix A.4. Finding: axis-angle is hard to train
(discontinuities); quaternions, matrices and 6D are similar on NTU-13, and 6D is best on UESTC (used
everywhere). The paper keeps L_V in every row; here the headline run's losses are kept (L_P + L_J, L_V
needs an SMPL model). Each generation is converted to the evaluator's input (6D rotations on UESTC)
before scoring, as in the paper. Our copy of the paper has the finding but not the table's numbers, so
there is no reported column.

    python -m experiments.actor_ablation_rotation                   # cpu profile, embedded synth-uestc
    python -m experiments.actor_ablation_rotation --set 'values=["quaternion","rot6d"]'
"""

from __future__ import annotations

import dataclasses
from typing import Literal

from jaxmotion import experiment
from jaxmotion.evaluation.claims import Claim
from jaxmotion.evaluation.tables import TableDataset
from jaxmotion.recipes.tables import table_dataset
from jaxmotion.train.actor import ActorTraining
from jaxmotion.recipes.actor import uestc_training

# A.4: axis-angle is hard to train (discontinuities); on UESTC the 6D representation is best
CLAIMS = (
    Claim("6D", "<", "axis-angle", "FID_tr", "A.4: axis-angle is difficult to train"),
    Claim("6D", ">", "axis-angle", "Acc. (%)", "A.4: axis-angle is difficult to train"),
    Claim("6D", "<", "quaternion", "FID_tr", "A.4: 6D is best on UESTC"),
    Claim("6D", "<", "rotation matrix", "FID_tr", "A.4: 6D is best on UESTC"),
)

NAMES = {"axis_angle": "axis-angle", "quaternion": "quaternion", "matrix": "rotation matrix", "rot6d": "6D"}


@dataclasses.dataclass(frozen=True)
class ActorAblationRotationConfig(experiment.Sweep):
    training: ActorTraining  # the headline UESTC run (experiments.actor_uestc)
    table: TableDataset
    values: tuple[Literal["axis_angle", "quaternion", "matrix", "rot6d"], ...] = (
        "axis_angle", "quaternion", "matrix", "rot6d")
    FIELD = "model.rep"  # the model's channels per joint follow the representation
    SMOKE_VALUES = ("quaternion", "rot6d")
    SETUP = staticmethod(lambda profile: (uestc_training(profile), table_dataset("UESTC", profile)))

    def label(self, value) -> str:
        return NAMES[value]


def main(argv=None):
    return experiment.main("actor_ablation_rotation", ActorAblationRotationConfig, experiment.run_sweep, argv,
                           description=__doc__, claims=CLAIMS)


if __name__ == "__main__":
    main()
