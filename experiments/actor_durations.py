"""ACTOR generating variable durations on UESTC (Figure 4, §4.2): fixed-size vs variable-size training.

Paper: Petrovich, Black, Varol, ICCV 2021. Two models: one trained on fixed 60-frame clips, and the same
model fine-tuned on clips of random length U[60, min(n, 100)] (training from scratch on variable lengths
freezes the motions; FACTS.md §3: +100 epochs). Each generates at durations 40 to 120 frames (step 5) and
is scored with the ACTOR protocol at that duration (real windows of the same length), the evaluator being
the 60-frame UESTC recogniser: accuracy and FID per duration.

    python -m experiments.actor_durations                    # cpu profile on the embedded synth-uestc
    python -m experiments.actor_durations --profile paper --data-root data/uestc --set data.name=uestc evaluator.dataset=uestc

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

Cost of the cpu profile (here: 2 shared cores; measured under load 0.46 s per 60-frame ACTOR step and
1.8 s per 100-frame step, about twice as fast unloaded): about 20 minutes unloaded (fixed model 7,
fine-tune 3, evaluation at 5 durations 6, the evaluator 4 unless cached by another ACTOR experiment).

Outputs in ``results/actor_durations/<profile>/seed-<n>/``: the table, ``durations.png`` and the
checkpoints of both models (``fixed-size/``, ``variable-size/``).
"""

from __future__ import annotations

import dataclasses
import shutil
from collections.abc import Mapping, Sequence
from pathlib import Path

import jax
import numpy as np
from matplotlib.figure import Figure

from experiments.actor_uestc import UESTC_EPOCH, ActorUestcConfig
from jaxmotion import experiment
from jaxmotion.data.motion import MotionDataset
from jaxmotion.evaluation.actor_tables import (
    ActorData,
    evaluate_variants,
    load_actor_data,
    samplers_of,
    slug,
    train_variants,
)
from jaxmotion.evaluation.protocol import ProtocolConfig
from jaxmotion.evaluation.recognizers import RecognizerTraining
from jaxmotion.models.actor import AnyActorParams
from jaxmotion.train.actor import ActorTraining, train_actor

FIXED, VARIABLE = "Fixed-size", "Variable-size"


@dataclasses.dataclass(frozen=True)
class ActorDurationsConfig:
    training: ActorTraining  # the fixed-size model
    finetune_steps: int  # variable-length steps after the fixed run
    evaluator: RecognizerTraining
    protocol: ProtocolConfig  # its duration is set per column
    data: ActorData = ActorData()
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
        base = ActorUestcConfig.smoke()
        return cls(base.training, 2, base.evaluator, base.protocol, base.data, durations=(40, 80))

    @classmethod
    def cpu(cls) -> ActorDurationsConfig:
        base = ActorUestcConfig.cpu()
        return cls(dataclasses.replace(base.training, steps=2000, checkpoint_every=500), 200, base.evaluator,
                   dataclasses.replace(base.protocol, repetitions=3), base.data, durations=(40, 60, 80, 100, 120))

    @classmethod
    def paper(cls) -> ActorDurationsConfig:
        base = ActorUestcConfig.paper()
        return cls(base.training, 100 * UESTC_EPOCH, base.evaluator, base.protocol, base.data)

    def variable(self) -> ActorTraining:
        """The fine-tune: the fixed training, on variable lengths, for ``finetune_steps`` more steps."""
        return dataclasses.replace(self.training, min_length=self.min_length, window=self.max_length,
                                   steps=self.training.steps + self.finetune_steps)


def finetune_actor(data: MotionDataset, training: ActorTraining, key: jax.Array, workdir: Path,
                   pretrained: Path) -> AnyActorParams:
    """Continue the finished run in ``pretrained`` with ``training`` in ``workdir`` (same ``key``, so the
    data order goes on); returns the parameters. The fine-tune starts from a copy of that run's checkpoints,
    so ``train_actor`` resumes it as its own (and an interrupted fine-tune resumes from its own)."""
    checkpoints = workdir / "checkpoints"
    if not checkpoints.exists():
        partial = workdir / "checkpoints.copying"
        shutil.rmtree(partial, ignore_errors=True)
        shutil.copytree(pretrained / "checkpoints", partial)
        partial.rename(checkpoints)  # whole or absent: an interrupted copy is made again
    return train_actor(data, training, key, str(workdir))


def save_curves(path: Path, x: Sequence[float], panels: Mapping[str, Mapping[str, Sequence[float]]], *,
                xlabel: str, marks: Sequence[float] = ()) -> None:
    """One panel per ``{y label: {curve label: values over x}}``, dashed vertical lines at ``marks``."""
    fig = Figure(figsize=(4.5 * len(panels), 3.4))
    for ax, (ylabel, curves) in zip(fig.subplots(1, len(panels), squeeze=False)[0], panels.items(), strict=True):
        for label, values in curves.items():
            ax.plot(x, values, marker="o", label=label)
        for mark in marks:
            ax.axvline(mark, color="grey", linestyle="--", linewidth=1)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=100)


def run(config: ActorDurationsConfig, ctx: experiment.RunContext):
    real = load_actor_data(config.data, ctx.data_root)
    train = real["tr"]
    variants = {FIXED: config.training, VARIABLE: config.variable()}
    params = train_variants({FIXED: config.training}, train, ctx.key("train"), ctx.workdir)
    params[VARIABLE] = finetune_actor(train, variants[VARIABLE], ctx.key("train"), ctx.workdir / slug(VARIABLE),
                                      ctx.workdir / slug(FIXED))
    samplers = samplers_of(params, variants, train)
    rows: dict[str, dict[str, np.ndarray]] = {}
    for duration in config.durations:
        protocol = dataclasses.replace(config.protocol, duration=duration)
        scores = evaluate_variants(ctx.key("eval"), samplers, real, config.evaluator, protocol,
                                   data_root=ctx.data_root)
        for row, cells in scores.items():
            rows.setdefault(row, {}).update({f"Acc. (%) @{duration}": cells["Acc. (%)"],
                                             f"FID_tr @{duration}": cells["FID_tr"]})
    panels = {metric: {row: [np.mean(cells[f"{metric} @{d}"]) for d in config.durations] for row, cells in rows.items()}
              for metric in ("Acc. (%)", "FID_tr")}
    save_curves(ctx.workdir / "durations.png", config.durations, panels, xlabel="generated duration (frames)",
                marks=(config.min_length, config.max_length))
    return rows


def main(argv=None):
    return experiment.main("actor_durations", ActorDurationsConfig, run, argv, description=__doc__)


if __name__ == "__main__":
    main()
