"""ACTOR generating variable durations on UESTC (Figure 4, §4.2): fixed-size vs variable-size training.

Paper: Petrovich, Black, Varol, ICCV 2021. Two models: one trained on fixed 60-frame clips, and the same
model fine-tuned on clips of random length U[60, min(n, 100)] (training from scratch on variable lengths
freezes the motions; the authors fine-tune for 100 more epochs). Each generates at durations 40 to 120
frames (step 5) and is scored with the ACTOR protocol at that duration (real windows of the same length),
the evaluator being the 60-frame UESTC recogniser: accuracy and FID per duration.

    python -m experiments.actor_durations                    # cpu profile on the embedded synth-uestc
    python -m experiments.actor_durations --profile paper --data-root data/uestc --set table.data.name=uestc table.evaluator.dataset=uestc

Reported (Figure 4, read from the caption and §4.2 only; the curves are not in the text): the fixed
model is best at 60 frames and keeps over 85% accuracy from 40 to 120 frames; the fine-tuned model is
better overall and drops less outside 60-100.

Rows: ``Fixed-size``, ``Variable-size`` and the protocol's ``Real`` row; columns ``Acc. (%) @<d>`` and
``FID_tr @<d>`` for each duration d (mean ± 95% CI over the protocol's repetitions). ``durations.png``
plots both against the duration, the variable model's training range dashed.

What differs from the paper, and why:

* The fine-tune continues the fixed run's last checkpoint, AdamW moments included (the paper does not
  say whether its optimiser restarted); ``finetune_steps`` counts its steps after the fixed run's.
* The cpu profile: ACTOR of the headline cpu size for 2 000 + 200 steps (the paper's 1 000 + 100 epochs
  in proportion), durations 40-120 by 20, 3 repetitions of 1 000 clips.

Cost of the cpu profile: the fixed model's training, the fine-tune on longer clips and the evaluation at 5
durations; the evaluator is trained unless another ACTOR experiment cached it.
Measured tables, each with the run record of the machine that made it: ``docs/results/``
(``python -m jaxmotion.results``).

Outputs in ``results/actor_durations/<profile>/seed-<n>/``: the table, ``durations.png`` and the
checkpoints of both models (``fixed-size/``, ``variable-size/``).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from jaxmotion import experiment
from jaxmotion.config import replace_paths
from jaxmotion.evaluation.claims import Claim
from jaxmotion.evaluation.protocol import ProtocolConfig, check_real_sets
from jaxmotion.evaluation.tables import TableDataset, paper_columns, real_sets, score_rows, slug, table_evaluator
from jaxmotion.recipes.tables import fit_generator, table_dataset
from jaxmotion.train.actor import ActorTraining
from jaxmotion.recipes.actor import UESTC_EPOCH, uestc_training
from jaxmotion.viz import save_curves

FIXED, VARIABLE = "Fixed-size", "Variable-size"


# Figure 4: the variable-size model generates better than the fixed-size one away from 60 frames
CLAIMS = (
    Claim(VARIABLE, ">", FIXED, "Acc. (%) @100", "Figure 4: variable-length training helps long generations"),
    Claim(VARIABLE, "<", FIXED, "FID_tr @100", "Figure 4: variable-length training helps long generations"),
    Claim(VARIABLE, ">", FIXED, "Acc. (%) @120", "Figure 4: also past the 100 frames it was trained on"),
)


@dataclasses.dataclass(frozen=True)
class ActorDurationsConfig:
    training: ActorTraining  # the fixed-size model
    finetune_steps: int  # variable-length steps after the fixed run
    table: TableDataset  # the protocol's duration is set per column
    min_length: int = 60  # fine-tuning clips: U[min_length, min(n, max_length)] frames
    max_length: int = 100
    durations: tuple[int, ...] = tuple(range(40, 121, 5))

    def __post_init__(self):
        if self.finetune_steps < 1:
            raise ValueError(f"finetune_steps: expected >= 1, got {self.finetune_steps}")
        if not 1 <= self.min_length <= self.max_length:
            raise ValueError(f"min_length, max_length: expected 1 <= min_length <= max_length, got "
                             f"{self.min_length}, {self.max_length}")
        if not self.durations or min(self.durations) < 1 or len(set(self.durations)) != len(self.durations):
            raise ValueError(f"durations: expected distinct frame counts >= 1, got {self.durations}")

    @classmethod
    def smoke(cls) -> ActorDurationsConfig:
        return cls(uestc_training("smoke"), 2, table_dataset("UESTC", "smoke"), durations=(40, 80))

    @classmethod
    def cpu(cls) -> ActorDurationsConfig:
        training = replace_paths(uestc_training("cpu"), {"loop.steps": 2000, "loop.checkpoint_every": 500})
        table = table_dataset("UESTC", "cpu", cpu_protocol=ProtocolConfig(repetitions=3, max_real=1000))
        return cls(training, 200, table, durations=(40, 60, 80, 100, 120))

    @classmethod
    def paper(cls) -> ActorDurationsConfig:
        return cls(uestc_training("paper"), 100 * UESTC_EPOCH, table_dataset("UESTC", "paper"))

    def variable(self) -> ActorTraining:
        """The fine-tune: the fixed training, on variable lengths, for ``finetune_steps`` more steps."""
        return dataclasses.replace(replace_paths(self.training, {"loop.steps": self.training.loop.steps
                                                                 + self.finetune_steps}),
                                   min_length=self.min_length, window=self.max_length)


def run(config: ActorDurationsConfig, ctx: experiment.RunContext):
    real = real_sets(config.table.data, ctx.data_root)
    train = real["train"]
    fixed, variable = config.training, config.variable()
    for duration in config.durations:  # every duration's real windows, before anything trains
        check_real_sets(real, dataclasses.replace(config.table.protocol, duration=duration))
    recognizer = table_evaluator(config.table, real, ctx.data_root)
    fixed_generator = fit_generator(fixed, train, ctx.key("train"), ctx.workdir / slug(FIXED), mesh=ctx.mesh,
                                    writers=ctx.writers)
    # the fine-tune starts from the fixed run's last checkpoint (its parameters, AdamW moments and step), with
    # the same key, so the data order goes on; an interrupted fine-tune resumes from its own checkpoints
    variable_generator = fit_generator(variable, train, ctx.key("train"), ctx.workdir / slug(VARIABLE),
                                       init_from=ctx.workdir / slug(FIXED), mesh=ctx.mesh,
                                       writers=ctx.writers)
    samplers = {FIXED: fixed_generator.sampler(), VARIABLE: variable_generator.sampler()}
    rows: dict[str, dict[str, np.ndarray]] = {}
    for duration in config.durations:
        protocol = dataclasses.replace(config.table.protocol, duration=duration)
        scores = paper_columns(score_rows(ctx.key("eval"), samplers, real, recognizer, protocol, mesh=ctx.mesh))
        for row, cells in scores.items():
            rows.setdefault(row, {}).update({f"Acc. (%) @{duration}": cells["Acc. (%)"],
                                             f"FID_tr @{duration}": cells["FID_tr"]})
    panels = {metric: {row: [np.mean(cells[f"{metric} @{d}"]) for d in config.durations] for row, cells in rows.items()}
              for metric in ("Acc. (%)", "FID_tr")}
    save_curves(ctx.workdir / "durations.png", config.durations, panels, xlabel="generated duration (frames)",
                marks=(config.min_length, config.max_length))
    return rows


def main(argv=None):
    return experiment.main("actor_durations", ActorDurationsConfig, run, argv, description=__doc__, claims=CLAIMS)


if __name__ == "__main__":
    main()
