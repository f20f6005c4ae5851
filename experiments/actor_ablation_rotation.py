"""ACTOR Table A.4: the rotation representation of the pose parameters, swept over the headline UESTC run.

Paper: Petrovich, Black, Varol, ICCV 2021, appendix A.4. Finding: axis-angle is hard to train
(discontinuities); quaternions, matrices and 6D are similar on NTU-13, and 6D is best on UESTC (used
everywhere). The paper keeps L_V in every row; here the headline run's losses are kept (L_P + L_J, L_V
needs an SMPL model). Each generation is converted to the evaluator's input (6D rotations on UESTC)
before scoring, as in the paper. Our copy of the paper has the finding but not the table's numbers, so
there is no reported column.

    python -m experiments.actor_ablation_rotation                   # cpu profile, embedded synth-uestc
    python -m experiments.actor_ablation_rotation --set "values=[quaternion,rot6d]"
"""

from __future__ import annotations

import dataclasses
from typing import Literal

import numpy as np

from experiments.actor_uestc import UestcSweep, run_sweep
from jaxmotion import experiment
from jaxmotion.geometry.rotations import REPRESENTATIONS
from jaxmotion.train.actor import ActorTraining

NAMES = {"axis_angle": "axis-angle", "quaternion": "quaternion", "matrix": "rotation matrix", "rot6d": "6D"}


@dataclasses.dataclass(frozen=True)
class ActorAblationRotationConfig(UestcSweep):
    values: tuple[Literal["axis_angle", "quaternion", "matrix", "rot6d"], ...] = (
        "axis_angle", "quaternion", "matrix", "rot6d")
    FIELD = "rep"
    SMOKE_VALUES = ("quaternion", "rot6d")

    def label(self, value) -> str:
        return NAMES[value]

    def variants(self) -> dict[str, ActorTraining]:
        # the model's channels per joint follow the representation
        base = self.setup.training
        return {self.label(rep): dataclasses.replace(
                    base, rep=rep, model=dataclasses.replace(base.model, channels=int(np.prod(REPRESENTATIONS[rep]))))
                for rep in self.values}


def main(argv=None):
    return experiment.main("actor_ablation_rotation", ActorAblationRotationConfig, run_sweep, argv,
                           description=__doc__)


if __name__ == "__main__":
    main()
