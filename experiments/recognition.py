"""The evaluators every table is measured with: action recognisers trained on the embedded data.

ACTOR, ODMO and Neural Marionette score generated motions with a recogniser trained on the real data
(Action2Motion's GRU for HumanAct12, NTU-13 and CMU; ACTOR's ST-GCN and ODMO's GRU for UESTC). The
released Action2Motion weights (the authors' checkpoints, not in this repository) only read the real
datasets, so the embedded datasets get their own evaluators, trained here with the same architectures and
cached for every later evaluation (``jaxmotion.evaluation.recognizers``). This experiment trains all of
them (or ``--set only=[...]``) and reports held-out accuracy.

    python -m experiments.recognition                    # cpu profile, all nine evaluators
    python -m experiments.recognition --set only='["synth-uestc/stgcn"]'
    python -m experiments.recognition --profile paper    # the papers' network sizes

Rows: one per evaluator; columns: held-out accuracy (the test split, or a fresh draw of the generator
with new subjects for datasets that have no test split), training-set accuracy, and the clips scored.
"""

from __future__ import annotations

import dataclasses
import sys

import jax

from jaxmotion import experiment
from jaxmotion.evaluation.recognizers import RecognizerTraining, evaluate_recognizer, trained_recognizer, training_data
from jaxmotion.recipes.evaluators import EVALUATORS, evaluator_spec


@dataclasses.dataclass(frozen=True)
class RecognitionConfig(experiment.ProfileConfig):
    evaluators: tuple[RecognizerTraining, ...]
    only: tuple[str, ...] = ()

    def __post_init__(self):
        names = [spec.name for spec in self.evaluators]
        unknown = sorted(set(self.only) - set(names))
        if unknown:
            raise ValueError(f"only: unknown evaluators {unknown}; this config has {names}")

    @classmethod
    def for_profile(cls, profile: str) -> RecognitionConfig:
        return cls(evaluators=tuple(evaluator_spec(name, profile) for name in EVALUATORS))


def run(config: RecognitionConfig, ctx: experiment.RunContext):
    rows = {}
    for spec in config.evaluators:
        if config.only and spec.name not in config.only:
            continue
        spec = dataclasses.replace(spec, seed=ctx.seed)
        recognizer, record = trained_recognizer(spec, data_root=ctx.data_root)
        train_scores = evaluate_recognizer(recognizer, training_data(spec, ctx.data_root),
                                           jax.random.key(spec.seed + 2), window=spec.window,
                                           count=spec.test_count)
        held_out = record["held_out"]
        print(f"[recognition] {spec.name}: held-out accuracy {100 * held_out['accuracy']:.1f}% "
              f"on {held_out['clips']} clips", file=sys.stderr)
        rows[spec.name] = {
            "held-out accuracy (%)": 100 * held_out["accuracy"],
            "train accuracy (%)": 100 * train_scores["accuracy"],
            "held-out clips": held_out["clips"],
        }
    return rows


def main(argv=None):
    return experiment.main("recognition", RecognitionConfig, run, argv, description=__doc__)


if __name__ == "__main__":
    main()
